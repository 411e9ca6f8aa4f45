"""Before/after identity and speed of the public morphology (`vt.core`, `vt.fillet`, `vt.shrink`, `vt.grow`).

Made for issue 26's switch of the public core and fillet to the engine's guide rule (GEOS's vertices
snapped onto the corners of S's exact offsets) from their own search. A snapshot imports
``vectortighten`` from the source tree given (a commit exported with ``git archive``, or the working
tree) and runs each operation on each case, recording the result's WKB, area and CPU time. The cases
always come from this file's own tree (``benchmarks/``, ``tests/``), so both snapshots see identical
inputs:

* ``rand``: 16 random shapes of the tests' hypothesis strategies (stars, unions of boxes and of disks,
  holed squares), derandomised, with a radius from ``radii_for``;
* ``dense``: `tests.shapes_dense` outlines (an administrative-like outline of 4000 vertices at two radii,
  a traced contour, a pixel blob) and the 30k-vertex pixel staircase of `tests.strategies.pixel_outline`;
* ``corpus``: real shapes of `benchmarks/corpus.py` (glyphs, icons, countries, a mask, CAD parts, a
  contour), each at a quarter and a half of its stroke width.

``run OLD_SRC NEW_SRC`` snapshots the two trees alternately ``--rounds`` times (each in a fresh
subprocess, old first), then compares: per operation, how many results are identical (WKB bit for bit),
the largest relative area difference and the largest Hausdorff distance between the boundaries (vertex to boundary, both ways;
in units of r), for the shrink and the grow the *corner error* (the largest distance from a convex
(reflex) vertex to the nearest corner of S's exact offsets, over r; every convex vertex of the exact
shrink is such a corner) of old and new where they differ, and the median over cases of the per-case ratio new/old of the median CPU times.

Run:  python benchmarks/identity_morphology.py run OLD_SRC NEW_SRC [--rounds 3] [--out FILE.md]
      python benchmarks/identity_morphology.py snapshot SRC OUT.pkl
"""

from __future__ import annotations

import argparse
import pickle
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import shapely

from _trees import use_tree

HERE = Path(__file__).resolve().parent
OPS = ("core", "fillet", "shrink", "grow")


def _random_cases(k: int) -> list:
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from tests.strategies import radii_for, shapes

    out = []

    @settings(max_examples=k, derandomize=True, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(shapes.flatmap(lambda S: st.tuples(st.just(S), radii_for(S))))
    def draw(case):
        out.append(case)

    draw()
    return out[:k]


def cases() -> list[tuple[str, object, float]]:
    """(name, shape, r) for every case, the same on every run."""
    sys.path.insert(0, str(HERE.parent))
    sys.path.insert(0, str(HERE))
    import corpus

    from tests import shapes_dense as sd
    from tests.strategies import pixel_outline

    out = []
    for i, (S, r) in enumerate(_random_cases(16)):
        out.append((f"rand{i}", shapely.make_valid(S) if not S.is_valid else S, float(r)))
    admin = sd.admin_outline(4000, seed=2)
    out += [("admin 4000 r=600", admin, 600.0), ("admin 4000 r=6000", admin, 6000.0),
            ("contour 160px r=4", sd.traced_contour(160, seed=3), 4.0),
            ("pixel blob 60px r=3", sd.pixel_blob(60, seed=4), 3.0),
            ("pixel staircase 30k r=0.6", pixel_outline(30_000), 0.6)]
    picks = {"glyph": (0, 5, 12), "icon": (0, 5), "country": (0, 4), "mask": (1,), "cad": (1, 2),
             "contour": (1,)}
    for fam, idx in picks.items():
        got = corpus.FAMILIES[fam]()
        for i in idx:
            c = got[i]
            for f in (0.25, 0.5):
                out.append((f"{fam}: {c.name} r={f}w", c.shape, f * c.width))
    return out


def snapshot(src: str, out: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        todo = cases()                        # inputs from this tree, before the engine is imported
    use_tree(src)
    import vectortighten as vt

    print("vectortighten from", vt.__file__, file=sys.stderr)
    rows = []
    for name, S, r in todo:
        row = {"name": name, "r": r, "n": int(shapely.get_num_coordinates(S))}
        for op in OPS:
            fn = getattr(vt, op)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                t0 = time.process_time()
                g = fn(S, r)
                row[op + "_t"] = time.process_time() - t0
            row[op] = shapely.to_wkb(g)
        rows.append(row)
    Path(out).write_bytes(pickle.dumps(rows))


def _segments(coords_list) -> np.ndarray:
    return np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in coords_list if len(c) > 1])


def _one_way(pts: np.ndarray, segs: np.ndarray) -> float:
    """Largest distance from the points to the nearest of the segments (an R-tree query each)."""
    if len(pts) == 0:
        return 0.0
    if len(segs) == 0:
        return float("inf")
    tree = shapely.STRtree(shapely.linestrings(segs))
    _, d = tree.query_nearest(shapely.points(pts), return_distance=True, all_matches=False)
    return float(d.max())


def _rings(g) -> list[np.ndarray]:
    return [shapely.get_coordinates(x) for x in shapely.get_rings(shapely.get_parts(g))] if not g.is_empty else []


def _hausdorff(a, b) -> float:
    """Largest distance from a vertex of either boundary to the other boundary (0 when equal).

    GEOS's ``hausdorff_distance`` is quadratic (minutes on the 30k-vertex staircase); the vertices'
    distances to the other boundary bound it from below and equal it wherever the largest deviation is
    at a vertex, as it is for two polygons whose vertices moved.
    """
    if a.equals_exact(b, 0.0):
        return 0.0
    if a.is_empty or b.is_empty:
        return float("inf")
    ra, rb = _rings(a), _rings(b)
    return max(_one_way(np.concatenate(ra), _segments(rb)), _one_way(np.concatenate(rb), _segments(ra)))


def _corner_error(g, S, r: float, side: int) -> float:
    """Largest distance from a convex (side +1: shrink) or reflex (−1: grow) vertex of g to the nearest
    corner of S's exact offsets of that side, over r: every such vertex of the exact set is a corner."""
    from scipy.spatial import cKDTree

    import vectortighten.centers as C
    from vectortighten.offsets import exact_offsets

    if g.is_empty:
        return 0.0
    S = shapely.orient_polygons(S)
    g = shapely.orient_polygons(g)
    pts = C._corner_vertices(g, convex=side > 0)
    if len(pts) == 0:
        return 0.0
    X = exact_offsets(S, r, side)
    if len(X.corners) == 0:
        return float("inf")
    return float(cKDTree(X.corners).query(pts)[0].max()) / r


def compare(old_runs: list[list[dict]], new_runs: list[list[dict]]) -> list[str]:
    old, new = old_runs[0], new_runs[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        shapes = {name: S for name, S, _ in cases()}
    lines = ["| operation | identical (WKB) | max rel. area diff | max Hausdorff old–new / r | worst case | "
             "old: corner error / r | new: corner error / r | new nearer / farther (> 1e-9·r) | "
             "median time ratio new/old | total old s | total new s |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    per_case = []
    for op in OPS:
        same, dA, dH, worst, ratios, t_old, t_new = 0, 0.0, 0.0, "", [], 0.0, 0.0
        ex_old = ex_new = 0.0
        nearer = farther = 0
        for k, (a, b) in enumerate(zip(old, new)):
            ga, gb = shapely.from_wkb(a[op]), shapely.from_wkb(b[op])
            same += int(a[op] == b[op])
            area = max(ga.area, gb.area, 1e-300)
            dA = max(dA, abs(ga.area - gb.area) / area)
            h = _hausdorff(ga, gb) / a["r"]
            if h > dH:
                dH, worst = h, a["name"]
            if op in ("shrink", "grow") and a[op] != b[op]:
                side = 1 if op == "shrink" else -1
                S = shapes[a["name"]]
                eo, en = _corner_error(ga, S, a["r"], side), _corner_error(gb, S, a["r"], side)
            else:
                eo = en = 0.0
                ex_old, ex_new = max(ex_old, eo), max(ex_new, en)
                nearer += int(en < eo - 1e-9)
                farther += int(en > eo + 1e-9)
            to = statistics.median(run[k][op + "_t"] for run in old_runs)
            tn = statistics.median(run[k][op + "_t"] for run in new_runs)
            t_old += to
            t_new += tn
            if to > 0:
                ratios.append(tn / to)
            per_case.append((op, a["name"], a["n"], h, to, tn,
                             f"{eo:.3g} → {en:.3g}" if op in ("shrink", "grow") and a[op] != b[op] else ""))
        lines.append(f"| {op} | {same}/{len(old)} | {dA:.3g} | {dH:.3g} | {worst} | {ex_old:.3g} | {ex_new:.3g} | "
                     f"{nearer} / {farther} | {statistics.median(ratios):.3f} | {t_old:.2f} | {t_new:.2f} |")
    lines += ["", "Per case (median CPU s over the rounds):", "",
              "| operation | case | vertices | Hausdorff old–new / r | corner error / r old → new | old s | new s |",
              "|---|---|---|---|---|---|---|"]
    lines += [f"| {op} | {name} | {n} | {h:.3g} | {ce} | {to:.3f} | {tn:.3f} |"
              for op, name, n, h, to, tn, ce in per_case]
    return lines


def run(old_src: str, new_src: str, rounds: int, out: str | None) -> None:
    old_runs, new_runs = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(rounds):
            for src, acc, tag in ((old_src, old_runs, "old"), (new_src, new_runs, "new")):
                p = Path(tmp) / f"{tag}{k}.pkl"
                subprocess.run([sys.executable, __file__, "snapshot", src, str(p)], check=True)
                acc.append(pickle.loads(p.read_bytes()))
                print(f"round {k + 1} {tag} done", file=sys.stderr, flush=True)
    lines = [f"Command: `python benchmarks/identity_morphology.py run {old_src} {new_src} --rounds {rounds}`; "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; {len(old_runs[0])} cases, old and new "
             "alternating in fresh processes.", "", *compare(old_runs, new_runs), ""]
    text = "\n".join(lines)
    print(text)
    if out:
        Path(out).write_text(text)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("snapshot")
    s.add_argument("src")
    s.add_argument("out")
    c = sub.add_parser("run")
    c.add_argument("old_src")
    c.add_argument("new_src")
    c.add_argument("--rounds", type=int, default=3)
    c.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    np.seterr(all="ignore")
    if args.cmd == "snapshot":
        snapshot(args.src, args.out)
    else:
        run(args.old_src, args.new_src, args.rounds, args.out)


if __name__ == "__main__":
    main()
