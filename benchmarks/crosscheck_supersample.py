"""Issue 21: is supersampled morphology worth its cost? Distance to the exact tightening and time, with and
without it, on a few shapes of the cross-check corpus.

For each shape (``PICKED``, fixed before the run: one of each family but the contours, at the corpus's
first radius r = max(w/4, D/25), init "core") the cross-check runs with ``supersample`` 1 (the paper's
morphology on the flow's own grid), 3 and 5 (`vectortighten.crosscheck`'s default), pixel size r/20. The
row gives the Hausdorff distance to the exact tightening (px), both topologies, whether they agree, and
the pixel side's time: rasterising S on the fine grid plus `raster.tighten` (morphology on the fine mask,
flow and finish on the coarse grid), with that time's ratio to the plain run's, same shape, same run.

    python benchmarks/crosscheck_supersample.py [--out FILE] [--factors 1,3,5]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

#: (family, name), chosen before any result: a glyph, an icon, a country, a mask, a CAD part.
PICKED = [("glyph", "DejaVu Sans Bold 'a'"), ("icon", "help"), ("country", "Greece"),
          ("mask", "matplotlib logo"), ("cad", "angle bracket")]


def main(argv=None) -> int:
    import corpus
    from crosscheck_corpus import radii

    import raster
    import vectortighten as vt

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=None, help="also write the markdown table here")
    p.add_argument("--factors", default="1,3,5")
    args = p.parse_args(argv)
    factors = [int(f) for f in args.factors.split(",")]
    by_key = {(c.family, c.name): c for c in corpus.cases(sorted({f for f, _ in PICKED}))}
    lines = ["| shape | r | supersample | Hausdorff (px) | exact (comp, holes) | pixel (comp, holes) | agree "
             "| pixel side (s) | / supersample 1 |", "|---|---:|---:|---:|---|---|---|---:|---:|"]
    print("\n".join(lines), flush=True)
    for key in PICKED:
        case = by_key[key]
        r = radii(case)[0]
        base = None
        for k in factors:
            C = vt.crosscheck(case.shape, r, pixel_size=r / 20, supersample=k)
            fine = raster.Grid(C.grid.x0, C.grid.y_top, C.grid.pixel_size / k,
                               (C.grid.shape[0] * k, C.grid.shape[1] * k))
            t0 = time.perf_counter()
            raster.rasterize(case.shape, fine)
            t_pixel = time.perf_counter() - t0 + C.raster.timings["total"]
            base = t_pixel if base is None else base
            row = (f"| {case.family} {case.name} | {r:.4g} | {k} | {C.hausdorff_px:.2f} | "
                   f"{tuple(C.vector_topology)} | {tuple(C.raster_topology)} | {'yes' if C.agree else 'no'} | "
                   f"{t_pixel:.2f} | {t_pixel / base:.1f} |")
            lines.append(row)
            print(row, flush=True)
    if args.out is not None:
        args.out.write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
