"""Two radii on the general engine: shapes whose corners interact, timed against one radius, interleaved.

Each round times ``tighten(S, (a, b))`` and ``tighten(S, b)`` (one radius, the larger of the pair here)
on each shape, one after the other, so that the load of a shared machine falls on both alike; prints the
medians and the median of the per-round ratios, the path taken, ``verify()``, the independent oracle
(`tests/oracle.py`: ``R_a ⊆ T`` judged at a, ``T ⊆ F_b`` at b; for a radius 0, S ⊆ T or T ⊆ S by area)
and, for the CNC plate, the perimeter against its closed form.

The CNC plate: 100 × 60 with a 20 × 15 corner notch and a slot 4 wide and 30 deep, at (0.5, 3) and at
(0, 3) (a 6 mm end mill: the slot is too narrow for it, so the closing fills it but for a dip of radius 3
at its mouth).

    python benchmarks/bench_two_radii_general.py [--rounds N]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def plate_perimeter(a: float, b: float, w: float = 4.0) -> float:
    """The plate's tightening at (a, b) with 2b > w, by elementary geometry: five convex corners lose
    a(2 − π/2), the notch's reflex corner b(2 − π/2), and the slot's mouth (w + 2a of the top edge) is
    replaced by the chain a-arc, crossing tangent, b-arc under the dip, crossing tangent, a-arc (for
    a = 0: the b-arc alone, between the mouth's corners)."""
    h = math.sqrt(b * b - (w / 2) ** 2)
    dx, dy = w / 2 + a, h + a
    d = math.hypot(dx, dy)
    theta = math.atan2(dx, dy) - math.acos((a + b) / d)
    chain = 2 * a * theta + 2 * math.sqrt(d * d - (a + b) ** 2) + 2 * b * theta
    return 320 - 5 * a * (2 - math.pi / 2) - b * (2 - math.pi / 2) - (w + 2 * a) + chain


def shapes():
    import numpy as np
    import shapely
    from shapely.geometry import box

    sys.path.insert(0, str(HERE))
    import bench_geo

    plate = box(0, 0, 100, 60).difference(box(0, 0, 20, 15)).difference(box(48, 30, 52, 60))
    rng = np.random.default_rng(5)
    n = 200
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = np.maximum(10 + 2.0 * np.sin(9 * t) + 0.4 * rng.standard_normal(n), 2)
    star = shapely.make_valid(shapely.Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)])))
    star = max(shapely.get_parts(star), key=lambda p: p.area if p.geom_type == "Polygon" else 0)
    fps = shapely.union_all(bench_geo.footprints(16, seed=3))
    return {"CNC plate, slot 4 wide": (plate, (0.5, 3.0)),
            "CNC plate, slot 4 wide, sharp outside": (plate, (0.0, 3.0)),
            "rippled star, 200 vertices": (star, (0.4, 1.2)),
            "16 building footprints": (fps, (1.0, 2.0))}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=7)
    args = p.parse_args(argv)
    sys.path.insert(0, str(HERE.parent))
    sys.path.insert(0, str(HERE.parent / "tests"))
    import vectortighten as vt
    from oracle import judge

    med = statistics.median
    for name, (S, (a, b)) in shapes().items():
        T = vt.tighten(S, (a, b))
        if a > 0:
            ja = judge(S, a, T.loops, T.geometry)
            exact = ja.core_penetration <= 1e-9 * a and not ja.core_missing
        else:                                         # R_0 is S itself
            exact = S.difference(T.geometry).area <= 1e-9 * S.area
        if b > 0:
            jb = judge(S, b, T.loops, T.geometry)
            exact &= jb.anticore_penetration <= 1e-9 * b and not jb.anticore_covered
        else:
            exact &= T.geometry.difference(S).area <= 1e-9 * S.area
        times = {"tighten (a, b)": [], "tighten b": []}
        for _ in range(args.rounds):
            for key, run in (("tighten (a, b)", lambda: vt.tighten(S, (a, b))), ("tighten b", lambda: vt.tighten(S, b))):
                t0 = time.perf_counter()
                run()
                times[key].append(time.perf_counter() - t0)
        ratio = med([y / x for x, y in zip(times["tighten b"], times["tighten (a, b)"])])
        print(f"{name} at (a, b) = ({a:g}, {b:g}): path {T._cache['_path']}, {len(T.loops)} loop(s), "
              f"converged {T.converged}, verify {T.verify() or 'ok'}, oracle exact {exact}")
        print(f"  perimeter {T.perimeter!r}, area {T.area!r}")
        if name.startswith("CNC"):
            want = plate_perimeter(a, b)
            print(f"  closed form {want!r} (relative difference {abs(T.perimeter - want) / want:.1e})")
        for k, v in times.items():
            print(f"  {k:15s} median {med(v) * 1e3:.1f} ms ({args.rounds} rounds)")
        print(f"  (a, b) / b: median ratio {ratio:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
