"""Figure 8's pixel tightening (the paper's 1102 × 832 px input, r = 40) timed against one EDT.

Issue 21's target: `raster.tighten` with its defaults (flow until rest, minimum-perimeter finish)
converged in under 2 s, without losing distance to the exact tightening. Each repeat times one
`scipy.ndimage.distance_transform_edt` of the same mask and one `raster.tighten`, interleaved, after one
warm-up call of each (imports, FFT plans); the medians and their ratio are printed, with the phase times
of the median run, whether every level rested, and the boundary Hausdorff distance (px) to
`vectortighten.tighten(S, r, init="core")` with the component and hole counts of both.

    python benchmarks/bench_fig8.py [--repeats N] [--figure 8|9]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "figures"))
sys.path.insert(0, str(HERE.parent))


def main(argv=None) -> int:
    import raster
    import vectortighten as vt
    from _raster_fig import _rasterize, hausdorff
    from _shapes import coastline, turtle
    from scipy import ndimage

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--figure", choices=("8", "9"), default="8")
    args = p.parse_args(argv)
    if args.figure == "8":
        S, W, H, r = coastline(1.0), 1102, 832, 40.0
    else:
        S, W, H, r = turtle(1.0), 1050, 825, 75.0
    mask, grid = _rasterize(raster, S, (H, W))
    ndimage.distance_transform_edt(mask)
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # a level that does not rest would warn: fail loudly
        raster.tighten(mask, r)
    t_edt, t_tight, runs = [], [], []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        ndimage.distance_transform_edt(mask)
        t_edt.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        res = raster.tighten(mask, r)
        t_tight.append(time.perf_counter() - t0)
        runs.append(res)
    med_e, med_t = statistics.median(t_edt), statistics.median(t_tight)
    res = runs[sorted(range(len(runs)), key=lambda i: t_tight[i])[len(runs) // 2]]
    T = vt.tighten(S, r, init="core")
    C = raster.contours(res, grid)
    print(f"figure {args.figure}: {W} x {H} px, r = {r:g}, {args.repeats} repeats")
    print(f"raster.tighten median {med_t:.3f} s (min {min(t_tight):.3f}, max {max(t_tight):.3f})")
    print(f"one EDT median {med_e:.4f} s; ratio {med_t / med_e:.1f}")
    print("phases of the median run:", {k: round(v, 3) for k, v in res.timings.items()})
    print("steps a level:", res.iterations, "rested:", res.converged)
    print(f"Hausdorff to exact {hausdorff(C, T.geometry):.2f} px; topology pixel "
          f"({vt.n_components(C)}, {vt.n_holes(C)}), exact ({T.n_components}, {T.n_holes})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
