"""``python -m parakin.generator [names...] [--force]``: regenerate ``generated/`` from
``mechanisms/`` (every mechanism file by default; of those only the packages that are out of
date, unless ``--force``). Progress on stderr: a bar on a terminal, else a ``parakin`` logger
line per stage (``parakin.log``: ``PARAKIN_PROGRESS``, ``PARAKIN_LOG``)."""

from __future__ import annotations

import argparse
import signal
import sys

from .build import GenerationError, generate


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m parakin.generator", description=__doc__)
    parser.add_argument("names", nargs="*", help="mechanisms to build (default: every file in mechanisms/)")
    parser.add_argument("--workers", type=int, default=None, help="parallel processes (default: one per core)")
    parser.add_argument(
        "--force", action="store_true", help="rebuild every package, also those up to date (CI's reproducibility check)"
    )
    args = parser.parse_args(argv)
    # a terminated build unwinds like an interrupted one: its staging folder is removed
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))
    try:  # what it does is shown as it happens (generator.stages): a bar, parakin logger lines
        generate(args.names or None, workers=args.workers, force=args.force)
    except GenerationError as error:
        print(f"parakin generator: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
