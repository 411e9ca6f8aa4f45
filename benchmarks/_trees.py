"""Importing `vectortighten` from a given source tree (a `git archive` of some commit), for the
before/after scripts: every module of the package already imported (from this tree, to build the inputs)
is forgotten, so that the engine measured is the one in ``src``."""

from __future__ import annotations

import sys
from pathlib import Path


def use_tree(src: str) -> None:
    """Put ``src`` first on the import path and forget every `vectortighten` module imported so far."""
    sys.path.insert(0, str(Path(src).resolve()))
    for m in [m for m in sys.modules if m == "vectortighten" or m.startswith("vectortighten.")]:
        del sys.modules[m]
