"""``python -m parakin.generator [names...]``: regenerate ``generated/`` from ``mechanisms/``
(every mechanism file by default)."""

from __future__ import annotations

import argparse
import signal
import sys

from .build import GenerationError, generate


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m parakin.generator", description=__doc__)
    parser.add_argument("names", nargs="*", help="mechanisms to build (default: every file in mechanisms/)")
    parser.add_argument("--workers", type=int, default=None, help="parallel processes (default: one per core)")
    args = parser.parse_args(argv)
    # a terminated build unwinds like an interrupted one: its staging folder is removed
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))
    try:
        report = generate(args.names or None, workers=args.workers)
    except GenerationError as error:
        print(f"parakin generator: {error}", file=sys.stderr)
        return 2
    for name, stats in report.items():
        print(f"generated {name} in {stats['seconds']:.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
