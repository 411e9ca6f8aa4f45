"""Draw every figure: ``python figures/make_all.py [outdir]`` (default: this folder).

`FIGURES` lists the figure modules in order; `run_all` imports each from this folder (which need not be
an installed package: the folder is put on ``sys.path``) and calls its ``draw(outdir)``.
"""

from __future__ import annotations

import importlib
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

FIGURES = [
    "fig1_grow_shrink",
    "fig2_round_fillet",
    "fig3_core_mortar_anticore",
    "fig4_mortar_tolerance_zone",
    "fig5_tight_curves",
    "fig6_several_tightenings",
    "fig7_cusps",
    "fig8_raster_40",
    "fig9_raster_75",
    "fig10_comparison",
    "fig11_closed_shrink",
]


def load(name: str):
    """Import the figure module ``name`` from this folder."""
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    return importlib.import_module(name)


def run_all(outdir=HERE, *, names=None, verbose: bool = False, **kwargs) -> list[Path]:
    """Run ``draw(outdir, **kwargs)`` of each figure in ``names`` (default: all); returns the files written."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    for name in names or FIGURES:
        t0 = time.perf_counter()
        paths = load(name).draw(outdir, **kwargs)
        written += paths
        if verbose:
            print(f"{name}: {time.perf_counter() - t0:.1f} s -> {', '.join(p.name for p in paths)}")
    return written


if __name__ == "__main__":
    run_all(Path(sys.argv[1]) if len(sys.argv) > 1 else HERE, verbose=True)
