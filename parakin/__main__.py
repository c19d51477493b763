"""``python -m parakin``: the same command line as the ``parakin`` script."""

import sys

from parakin.interfaces.cli import main

if __name__ == "__main__":
    sys.exit(main())
