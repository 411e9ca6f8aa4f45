"""Speed of the exact tightening against shapely's opening + closing at the same tolerance.

For each shape and size the script times, in the same process and alternately (the machines are noisy),

* the baseline: ``S.buffer(-r).buffer(r)`` and ``S.buffer(r).buffer(-r)`` with the ``quad_segs`` that the
  tolerance (1e-5·r) gives, i.e. the plain opening and closing;
* ``vectortighten.tighten(S, r)`` with the same tolerance (init="core");

and reports the medians and their ratio. Shapes:

* ``wavy star``: a star whose radius oscillates gently; r is below its smallest radius of curvature, so
  every corner is isolated (the engine's fast path);
* ``rough star``: the same star with r well above the waves' radius of curvature: the whole boundary is in
  the mortar and the general engine (triangulated mortar, funnel, surgery) does the work;
* ``traced contour``: the pixel-staircase outline of a noisy blob, like a segmentation mask's traced
  boundary (many tiny corners, every one in the mortar).
* ``coastline``: a real one, traced: the land of matplotlib's sample elevation grid ``topobathy.npz``
  (the coast of Vancouver Island and the Puget Sound, 120 × 91 cells), interpolated (cubic) to the
  resolution that gives about n vertices, thresholded at sea level and outlined pixel by pixel: some
  200 islands, fjords and channels; r = 1.5 cells of the original grid.

Run:  python benchmarks/bench_tighten.py [--sizes 1000 10000 100000 1000000] [--repeats 3]
It prints a markdown table and writes it to benchmarks/results/tighten.md.
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import shapely
import shapely.affinity
from shapely.geometry import MultiPolygon, Polygon

import vectortighten as vt
from vectortighten._validation import quad_segs_for

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from tests.strategies import pixel_outline  # noqa: E402  (the same shapes the tests use)


def wavy_star(n: int, waves: int = 12, amp: float = 0.04) -> Polygon:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 10 * (1 + amp * np.sin(waves * t))
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


def traced_contour(n: int, seed: int = 7) -> Polygon:
    """The pixel-staircase outline of a noisy blob with about n vertices (see `tests.strategies`)."""
    return pixel_outline(n, seed)


def coastline(n: int) -> MultiPolygon:
    """The traced land of matplotlib's ``topobathy.npz`` (coordinates in cells of its grid), ~n vertices."""
    import matplotlib
    from scipy import ndimage

    topo = np.load(Path(matplotlib.get_data_path()) / "sample_data" / "topobathy.npz")["topo"]
    f = max(1.0, n / 1350.0)
    land = ndimage.zoom(topo.astype(float), f, order=3) > 0 if f > 1 else topo > 0
    boxes = []
    for i, row in enumerate(land):                  # one box per run of land pixels in a row
        d = np.diff(np.r_[0, row.astype(np.int8), 0])
        start, stop = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
        boxes.append(shapely.box(start, -i - 1, stop, -i))
    P = shapely.simplify(shapely.union_all(np.concatenate(boxes)), 0.0)   # drop collinear vertices exactly
    k = land.shape[0] / topo.shape[0]
    return shapely.affinity.scale(P, 1 / k, 1 / k, origin=(0, 0))


_CLOCKS = {"cpu": time.process_time, "wall": time.perf_counter}


def _time(fn, clock) -> float:
    t0 = clock()
    fn()
    return clock() - t0


def measure(S: Polygon, r: float, repeats: int, clock=time.process_time) -> dict:
    tol = 1e-5 * r
    q = quad_segs_for(r, tol)

    def baseline():
        S.buffer(-r, quad_segs=q).buffer(r, quad_segs=q)
        S.buffer(r, quad_segs=q).buffer(-r, quad_segs=q)

    result = {}

    def ours():
        result["T"] = vt.tighten(S, r, tolerance=tol)

    base, mine = [], []
    error = None
    for _ in range(repeats):           # alternate, so that both see the same machine load
        base.append(_time(baseline, clock))
        try:
            mine.append(_time(ours, clock))
        except Exception as exc:       # an engine failure is a result too: report it, do not hide the row
            error = f"{type(exc).__name__}: {exc}"
            break
    T = result.get("T")
    ok = "error" if error else ("yes" if T.verify() == [] else "no")
    return {
        "vertices": len(shapely.get_coordinates(S)) - shapely.get_num_geometries(S),
        "baseline": statistics.median(base),
        "tighten": statistics.median(mine) if mine and not error else math.nan,
        "path": T._cache.get("_path", "?") if T is not None else "?",
        "pieces": sum(len(loop) for loop in T.loops) if T is not None and not error else 0,
        "verified": ok,
        "error": error,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000, 1_000_000])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--shapes", nargs="+", default=["wavy star", "rough star", "traced contour", "coastline"])
    parser.add_argument("--out", type=Path, default=HERE / "results" / "tighten.md")
    parser.add_argument("--clock", choices=sorted(_CLOCKS), default="cpu",
                        help="process CPU time (default: other work on the machine barely moves it) or wall time")
    args = parser.parse_args(argv)
    makers = {
        "wavy star": (lambda n: wavy_star(n), 0.5),
        "rough star": (lambda n: wavy_star(n, waves=60, amp=0.02), 1.0),
        "traced contour": (traced_contour, 0.6),
        "coastline": (coastline, 1.5),
    }
    rows = []
    for name in args.shapes:
        make, r = makers[name]
        for n in args.sizes:
            S = make(n)
            repeats = args.repeats if n <= 100_000 else 1
            m = measure(S, r, repeats, _CLOCKS[args.clock])
            m.update(shape=name, r=r, ratio=m["tighten"] / m["baseline"])
            rows.append(m)
            print(f"{name:15s} n={m['vertices']:>8d} r={r:<4g} baseline {m['baseline']:.3f}s  "
                  f"tighten {m['tighten']:.3f}s  ratio {m['ratio']:.1f}  ({m['path']} path, verified "
                  f"{m['verified']}){'  ' + m['error'] if m['error'] else ''}", flush=True)
    lines = [
        "# Tightening speed vs. shapely opening + closing",
        "",
        f"Machine: {platform.machine()}, Python {platform.python_version()}, shapely {shapely.__version__} "
        f"(GEOS {'.'.join(map(str, shapely.geos_version))}). Tolerance 1e-5·r for both; {args.clock} time, "
        f"medians of {args.repeats} alternating runs (1 for a million vertices). Command: "
        f"`python benchmarks/bench_tighten.py --shapes {' '.join(repr(x) for x in args.shapes)} "
        f"--sizes {' '.join(map(str, args.sizes))} --repeats {args.repeats}`. *verified*: `T.verify()` "
        "found nothing.",
        "",
        "| shape | vertices | r | opening + closing (s) | tighten (s) | ratio | engine path | output pieces | verified |",
        "|---|---:|---:|---:|---:|---:|---|---:|---|",
    ]
    for m in rows:
        lines.append(f"| {m['shape']} | {m['vertices']} | {m['r']:g} | {m['baseline']:.3f} | {m['tighten']:.3f} "
                     f"| {m['ratio']:.1f} | {m['path']} | {m['pieces']} | {m['verified']} |")
    for m in rows:
        if m["error"]:
            lines.append(f"\n{m['shape']}, {m['vertices']} vertices: {m['error']}")
    # Growth: time per vertex from the smallest to the largest size of each shape.
    lines += ["", "Growth of the tightening's time (exponent of n between consecutive sizes):", ""]
    for name in args.shapes:
        sub = [m for m in rows if m["shape"] == name and not m["error"]]
        exps = [math.log(b["tighten"] / a["tighten"]) / math.log(b["vertices"] / a["vertices"])
                for a, b in zip(sub, sub[1:])]
        lines.append(f"- {name}: " + ", ".join(f"{e:.2f}" for e in exps))
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
