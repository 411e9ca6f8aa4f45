"""Figure 8 (1102 × 832 px, r = 40): this checkout's `raster.tighten` against a baseline copy of the
`raster` package, interleaved in one process, so that the load of a shared machine falls on both alike.

The baseline is a copy of another checkout's ``raster/`` directory under another package name (its
imports are relative), e.g. ``cp -r /path/to/main/raster /tmp/ab/raster_main``. Each round times one
EDT of the mask, the baseline and this checkout, in turn (after a warm-up of each); prints the medians,
the median of the per-round ratios (this / baseline), and whether the two results are identical.

    python benchmarks/bench_fig8_ab.py /tmp/ab raster_main [--rounds N]
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("where", type=Path, help="the folder holding the baseline package")
    p.add_argument("package", help="the baseline package's name there")
    p.add_argument("--rounds", type=int, default=7)
    args = p.parse_args(argv)
    sys.path.insert(0, str(HERE.parent / "figures"))
    sys.path.insert(0, str(HERE.parent))
    sys.path.append(str(args.where))
    import numpy as np
    from scipy import ndimage

    import raster
    from _raster_fig import _rasterize
    from _shapes import coastline

    base = importlib.import_module(args.package)
    mask, _ = _rasterize(raster, coastline(1.0), (832, 1102))
    r = 40.0
    a, b = base.tighten(mask, r), raster.tighten(mask, r)
    same = bool(np.array_equal(a.mask, b.mask))
    t_edt, t_base, t_new = [], [], []
    for _ in range(args.rounds):
        t0 = time.perf_counter()
        ndimage.distance_transform_edt(mask)
        t_edt.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        base.tighten(mask, r)
        t_base.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        raster.tighten(mask, r)
        t_new.append(time.perf_counter() - t0)
    med = statistics.median
    print(f"rounds {args.rounds}; identical results: {same}")
    print(f"one EDT median {med(t_edt):.4f} s")
    print(f"baseline median {med(t_base):.3f} s ({med(t_base) / med(t_edt):.1f} EDTs)")
    print(f"this     median {med(t_new):.3f} s ({med(t_new) / med(t_edt):.1f} EDTs)")
    print(f"per-round ratio this / baseline: median {med([n / o for n, o in zip(t_new, t_base)]):.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
