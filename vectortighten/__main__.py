"""``python -m vectortighten``: the same command line as ``vectortighten``."""

import sys

from .cli import main

sys.exit(main())
