"""``python -m generator [names...]``: regenerate ``generated/`` (all mechanisms by default)."""

from __future__ import annotations

import argparse

from generator.build import generate
from mechanisms import MECHANISMS


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m generator", description=__doc__)
    parser.add_argument("names", nargs="*", help=f"mechanisms to build (default: all of {MECHANISMS})")
    args = parser.parse_args()
    names = args.names or MECHANISMS
    unknown = sorted(set(names) - set(MECHANISMS))
    if unknown:
        parser.error(f"unknown mechanism(s) {unknown}; valid: {MECHANISMS}")
    report = generate(MECHANISMS if not args.names else names)
    for name, stats in report.items():
        print(f"generated {name} in {stats['seconds']:.2f} s")


if __name__ == "__main__":
    main()
