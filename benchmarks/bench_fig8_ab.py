"""Figure 8 (1102 × 832 px, r = 40): this checkout's `raster.tighten` against a baseline copy of the
`raster` package, interleaved in one process, so that the load of a shared machine falls on both alike.

The baseline is a copy of another checkout's ``raster/`` directory under another package name (its
imports are relative), e.g. ``cp -r /path/to/main/raster /tmp/ab/raster_main``. Each round times one
EDT of the mask, the baseline and this checkout, in turn (after a warm-up of each); prints the medians,
the median of the per-round ratios (this / baseline), the median time of each phase on both sides, and
whether the two results are identical (the mask, Φ, the steps a level and the finish's curves, the
same vertices once normalised: their order may differ).
``--figure 9`` runs the paper's Figure 9 (1050 × 825 px, r = 75) instead.

    python benchmarks/bench_fig8_ab.py /tmp/ab raster_main [--rounds N] [--figure 8|9]
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
    p.add_argument("--figure", choices=("8", "9"), default="8")
    args = p.parse_args(argv)
    sys.path.insert(0, str(HERE.parent / "figures"))
    sys.path.insert(0, str(HERE.parent))
    sys.path.append(str(args.where))
    import numpy as np
    import shapely
    from scipy import ndimage

    import raster
    from _raster_fig import _rasterize
    from _shapes import coastline, turtle

    base = importlib.import_module(args.package)
    if args.figure == "8":
        mask, _ = _rasterize(raster, coastline(1.0), (832, 1102))
        r = 40.0
    else:
        mask, _ = _rasterize(raster, turtle(1.0), (825, 1050))
        r = 75.0
    a, b = base.tighten(mask, r), raster.tighten(mask, r)
    same = {"mask": bool(np.array_equal(a.mask, b.mask)), "phi": bool(np.array_equal(a.phi, b.phi)),
            "steps": a.iterations == b.iterations,
            "curves": (a.curves is None and b.curves is None) or (
                a.curves is not None and b.curves is not None
                and bool(shapely.normalize(a.curves).equals_exact(shapely.normalize(b.curves), 0.0)))}
    t_edt, t_base, t_new = [], [], []
    ph_base, ph_new = {}, {}
    for _ in range(args.rounds):
        t0 = time.perf_counter()
        ndimage.distance_transform_edt(mask)
        t_edt.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        ra = base.tighten(mask, r)
        t_base.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        rb = raster.tighten(mask, r)
        t_new.append(time.perf_counter() - t0)
        for res, ph in ((ra, ph_base), (rb, ph_new)):
            for k, v in res.timings.items():
                ph.setdefault(k, []).append(v)
    med = statistics.median
    print(f"figure {args.figure}, rounds {args.rounds}; identical results: {same}; steps {a.iterations} / "
          f"{b.iterations}")
    for k in ph_new:
        print(f"  {k:14s} baseline {med(ph_base.get(k, [float('nan')])):.3f} s, this {med(ph_new[k]):.3f} s")
    print(f"one EDT median {med(t_edt):.4f} s")
    print(f"baseline median {med(t_base):.3f} s ({med(t_base) / med(t_edt):.1f} EDTs)")
    print(f"this     median {med(t_new):.3f} s ({med(t_new) / med(t_edt):.1f} EDTs)")
    print(f"per-round ratio this / baseline: median {med([n / o for n, o in zip(t_new, t_base)]):.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
