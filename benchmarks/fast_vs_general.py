"""Every result of the fast path against the general engine, the oracle and `verify()`.

The fast path (`vectortighten/_fast.py`) answers directly where corners are isolated or form steps; it must
give the general engine's answer. For each shape of a set, at each radius and init, this tightens with the
defaults and, where the path was "fast", also with the general engine alone (`allow_fast=False`), and counts
a mismatch unless

* the loops are as many, the perimeters agree to 1e-9 and the symmetric difference of the geometries is
  at most 1e-9 of the area;
* `tests/oracle.py`'s `judge` finds nothing (no entry into the core or anticore deeper than 1e-9·r,
  nothing of the core missed, nothing of the anticore covered);
* ``verify()`` returns no problem.

Sets: ``footprints`` (`bench_geo.footprints`, seeds given), ``stairs`` (blocks whose walls climb and
descend in staircases of random treads and risers, right-angled or slanted: runs of steps, jogs, corners
between two steps), ``features`` (blocks whose corners are bevelled, rounded by a few chords or left
sharp, and whose walls carry notches and tabs, square or tapered, of widths and depths from 0.1 to 3,
slight bends, and steps out and back: the shapes of cut parts and plans, drawn without looking at which
the fast path takes), ``slots`` (the same blocks whose walls carry notches and tabs as real outlines draw
them: walls bent slightly part way, flared mouths, one wall ending at a ledge; `slot_wall`).

Run:  python benchmarks/fast_vs_general.py footprints --n 300 --seeds 0 1 --radii 0.5 1 2
      python benchmarks/fast_vs_general.py stairs --n 60 --radii 0.3 0.6 1
      python benchmarks/fast_vs_general.py features --n 200 --seeds 0 1 --radii 0.3 0.7 1.5
      python benchmarks/fast_vs_general.py slots --n 100 --seeds 0 1 --radii 0.3 0.7 1.5
(``--root`` imports ``vectortighten`` from another source tree.)
"""

from __future__ import annotations

import argparse
import collections
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

HERE = Path(__file__).resolve().parent


def staircase(rng: np.random.Generator, length: float, height: float, right_angled: bool) -> np.ndarray:
    """A wall's profile from (0, 0) to (length, 0): treads at both ends, a staircase up (treads 0.05–1.2,
    risers 0.05–``height``), a plateau, the same down."""
    n = max(1, int((length - 7) / 2 / 0.8))
    up = np.cumsum(rng.uniform(0.05, height, n))
    pts, x, y = [(0.0, 0.0)], 2.0, 0.0
    for ny in list(up) + [None] + list(up[::-1][1:]) + [0.0]:
        if ny is None:
            x += 2.5
            continue
        pts += [(x, y), (x, ny)] if right_angled else [(x + rng.uniform(-0.3, 0.3), ny)]
        y, x = ny, x + rng.uniform(0.05, 1.2)
    pts.append((max(x, length - 2) + 2, 0.0))
    p = np.array(pts)
    p[:, 0] *= length / p[-1, 0]
    return p


def stairs(n: int, seed: int = 0):
    """Blocks 12–30 on a side whose four walls are staircases, in or out, turned by a random angle."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        w, h = rng.uniform(12, 30, 2)
        right_angled, height = rng.random() < 0.7, rng.uniform(0.1, 1.5)
        sides = []
        for x0, y0, x1, y1 in ((0, 0, w, 0), (w, 0, w, h), (w, h, 0, h), (0, h, 0, 0)):
            L = math.hypot(x1 - x0, y1 - y0)
            ux, uy = (x1 - x0) / L, (y1 - y0) / L
            p = staircase(rng, L, height, right_angled)
            p[:, 1] *= rng.choice([-1.0, 1.0])
            sides.append(np.column_stack([x0 + p[:, 0] * ux - p[:, 1] * uy, y0 + p[:, 0] * uy + p[:, 1] * ux]))
        g = shapely.make_valid(Polygon(np.concatenate(sides)))
        parts = [q for q in shapely.get_parts(g) if q.geom_type == "Polygon"]
        yield shapely.affinity.rotate(Polygon(max(parts, key=lambda q: q.area).exterior), rng.uniform(0, 180))


def wall(rng: np.random.Generator, length: float) -> np.ndarray:
    """A wall's profile from (0, 0) to (length, 0), y outwards: features 2 or more from either end, each
    a notch or a tab (square or tapered), a slight bend, or a step out and back some way on."""
    pts, x = [(0.0, 0.0)], 2.0
    while True:
        kind = rng.choice(["slot", "taper", "bend", "step", "none"], p=[0.3, 0.15, 0.2, 0.15, 0.2])
        width = rng.uniform(0.1, 3.0)
        if x + width + 2.0 > length:
            break
        depth = rng.uniform(0.1, 3.0) * rng.choice([-1.0, 1.0])
        if kind == "slot":
            pts += [(x, 0.0), (x, depth), (x + width, depth), (x + width, 0.0)]
        elif kind == "taper":
            inset = rng.uniform(0.0, 0.45) * width
            pts += [(x, 0.0), (x + inset, depth), (x + width - inset, depth), (x + width, 0.0)]
        elif kind == "bend":
            pts.append((x + 0.5 * width, rng.uniform(-0.2, 0.2)))
        elif kind == "step":
            rise = rng.uniform(0.05, 1.2) * rng.choice([-1.0, 1.0])
            pts += [(x, 0.0), (x + rng.uniform(-0.2, 0.2), rise), (x + width, rise),
                    (x + width + rng.uniform(-0.2, 0.2), 0.0)]
        x += width + rng.uniform(0.3, 3.0)
    pts.append((length, 0.0))
    return np.array(pts)


def slot_wall(rng: np.random.Generator, length: float) -> np.ndarray:
    """A wall's profile as `wall`'s, whose features (2–5 apart) are notches and tabs 0.3–3 wide and 0.3–4 deep drawn
    the ways real outlines draw them: walls with a slight bend (either way, up to 12°) part way along, a
    mouth flared over its first 0.2–1.5, or one wall ending at a ledge 0.2–2 off the wall's line (the
    wall goes on from there)."""
    pts, x, base = [(0.0, 0.0)], 2.0, 0.0
    while True:
        width = rng.uniform(0.3, 3.0)
        if x + width + 3.0 > length:
            break
        depth = rng.uniform(0.3, 4.0) * rng.choice([-1.0, 1.0])
        kind = rng.choice(["bent", "flared", "ledge"])
        if kind == "bent":
            # Each wall bends at a fraction of the depth by a slight angle: a sideways offset of the rest.
            f0, f1 = rng.uniform(0.2, 0.8, 2)
            d0, d1 = (rng.uniform(-0.2, 0.2, 2) * abs(depth))
            pts += [(x, base), (x, base + f0 * depth), (x + d0, base + depth),
                    (x + width + d1, base + depth), (x + width, base + f1 * depth), (x + width, base)]
        elif kind == "flared":
            flare, wide = rng.uniform(0.2, 1.5), rng.uniform(0.05, 0.6)
            flare = min(flare, 0.9 * abs(depth))
            pts += [(x - wide, base), (x, base + math.copysign(flare, depth)), (x, base + depth),
                    (x + width, base + depth), (x + width, base + math.copysign(flare, depth)),
                    (x + width + wide * rng.uniform(0, 1.5), base)]
        else:
            ledge = rng.uniform(0.2, 2.0) * rng.choice([-1.0, 1.0])
            if abs(ledge - depth) < 0.2:
                ledge = -ledge
            pts += [(x, base), (x, base + depth), (x + width, base + depth), (x + width, base + ledge)]
            base += ledge
        x += width + rng.uniform(2.0, 5.0)
        if kind == "ledge" and rng.random() < 0.5 or abs(base) > 3.0:
            pts += [(x, base), (x, 0.0)]            # back to the wall's line
            base = 0.0
            x += rng.uniform(2.0, 5.0)
    pts += [(length - 1.0, base), (length - 1.0, 0.0)] if base else []
    pts.append((length, 0.0))
    return np.array(pts)


def corner(rng: np.random.Generator, prev: np.ndarray, at: np.ndarray, nxt: np.ndarray) -> list:
    """A corner left sharp, bevelled (legs 0.05–1.5) or rounded by 2–5 chords (radius 0.2–1.5)."""
    kind = rng.choice(["sharp", "bevel", "round"])
    u = (at - prev) / np.hypot(*(at - prev))
    v = (nxt - at) / np.hypot(*(nxt - at))
    if kind == "sharp":
        return [at]
    if kind == "bevel":
        return [at - rng.uniform(0.05, 1.5) * u, at + rng.uniform(0.05, 1.5) * v]
    rho, k = rng.uniform(0.2, 1.5), int(rng.integers(2, 6))
    turn = math.atan2(u[0] * v[1] - u[1] * v[0], u @ v)
    start = at - rho * math.tan(abs(turn) / 2) * u            # where the arc leaves the incoming edge
    centre = start + rho * math.copysign(1.0, turn) * np.array([-u[1], u[0]])
    back = math.atan2(*(start - centre)[::-1])
    return [centre + rho * np.array([math.cos(back + turn * j / k), math.sin(back + turn * j / k)])
            for j in range(k + 1)]


def featured(n: int, seed: int = 0, profile=None):
    """Blocks 10–30 on a side with featured walls and corners (`wall`, or ``profile``, and `corner`),
    turned by a random angle; the largest polygon of their repair where features cross."""
    profile = profile or wall
    rng = np.random.default_rng(seed)
    for _ in range(n):
        w, h = rng.uniform(10, 30, 2)
        box = [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]
        ring = []
        for i in range(4):
            (x0, y0), (x1, y1) = box[i], box[(i + 1) % 4]
            L = math.hypot(x1 - x0, y1 - y0)
            ux, uy = (x1 - x0) / L, (y1 - y0) / L
            p = profile(rng, L)
            # Outwards is to the right of a counter-clockwise wall.
            ring.append(np.column_stack([x0 + p[:, 0] * ux + p[:, 1] * uy, y0 + p[:, 0] * uy - p[:, 1] * ux])[:-1])
        pts = np.concatenate(ring)
        out, m = [], len(pts)
        for i in range(m):
            is_box_corner = any(np.allclose(pts[i], c) for c in box)
            out += corner(rng, pts[i - 1], pts[i], pts[(i + 1) % m]) if is_box_corner else [pts[i]]
        g = shapely.make_valid(Polygon(np.array(out)))
        parts = [q for q in shapely.get_parts(g) if q.geom_type == "Polygon"]
        if not parts:
            continue
        yield shapely.affinity.rotate(Polygon(max(parts, key=lambda q: q.area).exterior), rng.uniform(0, 180))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("set", choices=["footprints", "stairs", "features", "slots"])
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--radii", type=float, nargs="+", default=[1.0])
    ap.add_argument("--inits", nargs="+", default=["core", "input", "mason"])
    ap.add_argument("--root", default=str(HERE.parent))
    args = ap.parse_args()
    sys.path[:0] = [args.root, str(HERE), str(Path(args.root) / "tests")]
    import vectortighten as vt
    from oracle import judge
    from vectortighten import engine

    import bench_geo

    warnings.simplefilter("ignore")
    paths, bad, t0 = collections.Counter(), [], time.process_time()
    for seed in args.seeds:
        make = {"footprints": lambda: bench_geo.footprints(args.n, seed=seed), "stairs": lambda: stairs(args.n, seed),
                "features": lambda: featured(args.n, seed), "slots": lambda: featured(args.n, seed, slot_wall)}
        shapes = make[args.set]()
        for k, S in enumerate(shapes):
            for r in args.radii:
                for init in args.inits:
                    T = vt.tighten(S, r, init=init)
                    paths[T._cache["_path"]] += 1
                    if T._cache["_path"] != "fast":
                        continue
                    G = engine._tighten(vt._validation.check_shape(S), r, engine.Init(init), 1e-5 * r,
                                        allow_fast=False)
                    same = (len(T.loops) == len(G.loops) and abs(T.perimeter - G.perimeter) <= 1e-9 * G.perimeter
                            and T.geometry.symmetric_difference(G.geometry).area <= 1e-9 * max(G.area, 1.0))
                    J = judge(S, r, T.loops, T.geometry)
                    clean = (J.core_penetration < 1e-9 * r and J.anticore_penetration < 1e-9 * r
                             and J.core_missing == 0 and J.anticore_covered == 0)
                    problems = T.verify()
                    if not (same and clean and not problems):
                        bad.append((seed, k, r, init, same, clean, problems[:1], T.perimeter, G.perimeter))
    print(f"{args.set}: paths {dict(paths)}; fast results compared: {paths['fast']}; mismatches: {len(bad)} "
          f"({time.process_time() - t0:.0f} s CPU)")
    for b in bad[:20]:
        print("  seed %d shape %d r %g init %s: same %s, oracle clean %s, verify %s, perimeter %.12g vs %.12g" % b)


if __name__ == "__main__":
    main()
