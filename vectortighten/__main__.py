"""``python -m vectortighten``: the same command line as ``vectortighten``."""

import sys

from .cli import main

if __name__ == "__main__":  # guarded: worker processes of a batch import this module again
    sys.exit(main())
