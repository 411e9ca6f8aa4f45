"""Speed of `tighten` on arc-bounded shapes (a list of `Loop`s) against the same shapes flattened.

Issue 22 asks that an arc-bounded shape run no slower than its polygon flattened at 1e-5·r. Each case is
timed as loops (`tighten(loops, r)`, the `loop_input` path) and as the polygon those loops make with
chords within 1e-5·r (`tighten(polygon, r)`, the baseline), in the same run, alternating.

Cases:

* **plate**: a 20 × 20 plate with corners of radius 3 and a hole of radius 4, r = 3 (its own tightening:
  the identity path);
* **plates n**: n such plates side by side, each with k holes of radius 1.5 (identity);
* **tightening**: a tightening fed back in (a star, r = 1, init core; identity);
* **sharp plate**: the plate with sharp corners (not its own tightening; its corners are isolated: the
  `arc_fillets` path);
* **thin wall (fallback)**: the sharp plate with the hole 1 from its edge at r = 1: no exact path
  applies, the loops are flattened and the polygon engine runs after the exact tests fail (their
  overhead).

Medians of ``--repeats`` runs; wall time on whatever machine runs it.

Run:  python benchmarks/bench_loop_input.py [--repeats 5]
It prints a markdown table and writes it to benchmarks/results/loop_input.md.
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402
from shapely.geometry import Polygon  # noqa: E402

from vectortighten import tighten  # noqa: E402
from vectortighten.curves import Arc, Loop, Segment  # noqa: E402
from vectortighten.loop_input import FLATTEN_R, region  # noqa: E402


def rounded_rect(x0, y0, x1, y1, rho):
    h = math.pi / 2
    return Loop([Segment((x0 + rho, y0), (x1 - rho, y0)), Arc((x1 - rho, y0 + rho), rho, -h, h),
                 Segment((x1, y0 + rho), (x1, y1 - rho)), Arc((x1 - rho, y1 - rho), rho, 0.0, h),
                 Segment((x1 - rho, y1), (x0 + rho, y1)), Arc((x0 + rho, y1 - rho), rho, h, h),
                 Segment((x0, y1 - rho), (x0, y0 + rho)), Arc((x0 + rho, y0 + rho), rho, math.pi, h)])


def plates(n, k):
    loops = []
    for i in range(n):
        x = 25.0 * i
        loops.append(rounded_rect(x, 0, x + 20, 20, 3.0))
        for j in range(k):
            a = 2 * math.pi * j / max(k, 1)
            loops.append(Loop.circle((x + 10 + 5 * math.cos(a), 10 + 5 * math.sin(a)), 1.5, ccw=False))
    return loops


def cases():
    yield "plate", [rounded_rect(-10, -10, 10, 10, 3.0), Loop.circle((0.0, 0.0), 4.0, ccw=False)], 3.0
    yield "plates 10 × 6 holes", plates(10, 6), 1.0
    th = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    star = Polygon(np.column_stack([(8 + 3 * np.cos(5 * th)) * np.cos(th), (8 + 3 * np.cos(5 * th)) * np.sin(th)]))
    yield "tightening of a star", tighten(star, 1.0).loops, 1.0
    sq = Loop([Segment((-10, -10), (10, -10)), Segment((10, -10), (10, 10)), Segment((10, 10), (-10, 10)),
               Segment((-10, 10), (-10, -10))])
    yield "sharp plate", [sq, Loop.circle((0.0, 0.0), 4.0, ccw=False)], 3.0
    yield "thin wall (fallback)", [sq, Loop.circle((5.0, 0.0), 4.0, ccw=False)], 1.0


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    rows = []
    for name, loops, r in cases():
        flat = region(loops, FLATTEN_R * r)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tighten(loops, r), tighten(flat, r)                   # warm up
            a, b = [], []
            for _ in range(args.repeats):
                ta, A = timed(lambda: tighten(loops, r))
                tb, B = timed(lambda: tighten(flat, r))
                a.append(ta)
                b.append(tb)
        path = A._cache.get("_path", "")
        ma, mb = statistics.median(a), statistics.median(b)
        rows.append(f"| {name} | {path} | {ma * 1e3:.1f} | {mb * 1e3:.1f} | {mb / ma:.2f}× | "
                    f"{sum(len(lp.arcs) for lp in A.loops)} / {sum(len(lp.arcs) for lp in B.loops)} |")
    head = ["| case | path | loops (ms) | flattened polygon (ms) | speed-up | arcs out (loops / polygon) |",
            "|---|---|---|---|---|---|"]
    text = "\n".join([f"# tighten on loops vs the flattened polygon (1e-5·r)\n",
                      f"Medians of {args.repeats} runs, {platform.processor() or platform.machine()}, "
                      f"Python {platform.python_version()}.\n", *head, *rows]) + "\n"
    print(text)
    (HERE / "results" / "loop_input.md").write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
