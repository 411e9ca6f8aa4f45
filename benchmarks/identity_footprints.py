"""Before/after identity of `vt.tighten` on the geo benchmark's footprints and on the tests' random shapes.

Made to check that a speed-up changes no result. A snapshot imports ``vectortighten`` from the source
tree given (so a commit exported with ``git archive`` can be measured against the working tree) and
tightens, in this order:

* ``fp``: the first ``--fp`` (default 300) building footprints of the geo benchmark's dataset
  (``bench_geo.footprints(1000)``, seed 0, the same features `bench_geo.py` times), r = 1 m;
* ``rand``: ``--rand`` (default 100) random shapes drawn from the tests' hypothesis strategies
  (``tests/strategies.py``: stars, unions of boxes, unions of disks, holed squares) with a radius from
  ``radii_for`` and an init from ``core`` / ``input``, derandomised (the same draw every run).

The shapes and radii always come from this file's own tree (``benchmarks/``, ``tests/``), so both
snapshots see identical inputs. Each result is recorded as its exact pieces (a segment's two ends; an
arc's centre, radius, start angle and sweep), its area, perimeter, the WKB of its sampled geometry,
and the engine's path (fast, convex, general).

``compare`` matches each loop as a cyclic sequence of pieces (a loop may start at another piece) and
accepts a difference of at most 1e-12 × max(1, largest coordinate) in any piece coordinate (arc angles
compared modulo 2π); it reports how many results are identical bit for bit and how many within that
tolerance, and lists any other one.

Run:  python benchmarks/identity_footprints.py snapshot SRC_ROOT OUT.pkl [--fp 300] [--rand 100]
      python benchmarks/identity_footprints.py compare BEFORE.pkl AFTER.pkl
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely

from _trees import use_tree

HERE = Path(__file__).resolve().parent


def random_cases(k: int) -> list:
    """k (shape, r, init) triples drawn from the tests' strategies, the same on every run."""
    sys.path.insert(0, str(HERE.parent))
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from tests.strategies import radii_for, shapes

    out = []

    @settings(max_examples=k, derandomize=True, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(shapes.flatmap(lambda S: st.tuples(st.just(S), radii_for(S), st.sampled_from(["core", "input"]))))
    def draw(case):
        out.append(case)

    draw()
    return out[:k]


def cases(n_fp: int, n_rand: int):
    sys.path.insert(0, str(HERE))
    import bench_geo

    for i, g in enumerate(bench_geo.footprints(1000)[:n_fp]):
        yield f"fp{i}", g, 1.0, "core"
    for i, (S, r, init) in enumerate(random_cases(n_rand)):
        yield f"rand{i}", S, float(r), init


def snapshot(src: str, out: str, n_fp: int, n_rand: int) -> None:
    todo = list(cases(n_fp, n_rand))            # inputs from this tree, before the engine is imported
    use_tree(src)
    import vectortighten as vt
    from vectortighten.curves import Arc

    print("vectortighten from", vt.__file__, file=sys.stderr)
    res = {}
    t_all = time.process_time()
    for name, S, r, init in todo:
        t0 = time.process_time()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                T = vt.tighten(S, r, init=init)
        except Exception as e:                  # recorded, and compared like a result
            res[name] = dict(error=f"{type(e).__name__}: {e}", t=time.process_time() - t0)
            continue
        dt = time.process_time() - t0
        pcs = []
        for L in T.loops:
            for p in L.pieces:
                if isinstance(p, Arc):
                    pcs.append((1, p.center[0], p.center[1], p.radius, p.start_angle, p.sweep))
                else:
                    pcs.append((0, p.start[0], p.start[1], p.end[0], p.end[1], 0.0))
            pcs.append((9, 0, 0, 0, 0, 0))
        res[name] = dict(pieces=np.array(pcs, dtype=float).reshape(-1, 6), area=T.area,
                         perimeter=T.perimeter, wkb=shapely.to_wkb(T.geometry), t=dt,
                         path=T._cache.get("_path", "?"), scale=float(max(1.0, *np.abs(S.bounds))))
    with open(out, "wb") as f:
        pickle.dump(res, f)
    paths = {}
    for v in res.values():
        paths[v.get("path", "error")] = paths.get(v.get("path", "error"), 0) + 1
    print(f"{len(res)} shapes in {time.process_time() - t_all:.1f} s CPU; paths {paths}", file=sys.stderr)


def _loops(p: np.ndarray) -> list[np.ndarray]:
    out, cur = [], []
    for row in p:
        if row[0] == 9:
            out.append(np.array(cur).reshape(-1, 6))
            cur = []
        else:
            cur.append(row)
    return out


def _piece_diff(x: np.ndarray, y: np.ndarray) -> float:
    d = np.abs(x - y)
    arc = x[:, 0] == 1
    d[arc, 4] = np.abs(np.angle(np.exp(1j * (x[arc, 4] - y[arc, 4]))))
    return float(d.max()) if d.size else 0.0


def _loop_diff(a: np.ndarray, b: np.ndarray) -> float:
    """Least largest piece difference of loop b against loop a over b's cyclic shifts (inf: other kinds)."""
    if a.shape != b.shape:
        return np.inf
    best = np.inf
    for s in range(len(b)):
        c = np.roll(b, -s, axis=0)
        if np.array_equal(a[:, 0], c[:, 0]):
            best = min(best, _piece_diff(a, c))
    return best


def result_diff(A: dict, B: dict) -> float:
    """Largest piece difference between two results, loops matched one to one (inf when they cannot be)."""
    la, lb = _loops(A["pieces"]), _loops(B["pieces"])
    if len(la) != len(lb):
        return np.inf
    worst, left = 0.0, list(range(len(lb)))
    for x in la:
        ds = [(_loop_diff(x, lb[j]), j) for j in left]
        if not ds:
            return np.inf
        d, j = min(ds)
        worst = max(worst, d)
        left.remove(j)
    return worst


def compare(before: str, after: str) -> int:
    with open(before, "rb") as f:
        a = pickle.load(f)
    with open(after, "rb") as f:
        b = pickle.load(f)
    bits = close = bad = 0
    ta = tb = {"fp": 0.0, "rand": 0.0}
    ta, tb = dict(ta), dict(tb)
    for k in a:
        A, B = a[k], b.get(k)
        kind = "fp" if k.startswith("fp") else "rand"
        if B is None:
            print("MISSING", k)
            bad += 1
            continue
        ta[kind] += A["t"]
        tb[kind] += B["t"]
        if "error" in A or "error" in B:
            if A.get("error") == B.get("error"):
                bits += 1
            else:
                print("ERROR", k, A.get("error"), "|", B.get("error"))
                bad += 1
            continue
        if np.array_equal(A["pieces"], B["pieces"]) and A["wkb"] == B["wkb"]:
            bits += 1
            continue
        d = result_diff(A, B)
        tol = 1e-12 * A["scale"]
        area_ok = abs(A["area"] - B["area"]) <= 1e-12 * max(1.0, abs(A["area"]))
        if d <= tol and area_ok:
            close += 1
        else:
            bad += 1
            print("DIFF", k, "pieces", A["pieces"].shape, B["pieces"].shape, "maxdiff", d, "area",
                  A["area"], B["area"], "path", A["path"], B["path"])
    print(f"{len(a)} results: {bits} identical bit for bit, {close} within 1e-12 × size "
          f"(not bit for bit), {bad} different")
    for kind in ("fp", "rand"):
        print(f"  {kind}: CPU before {ta[kind]:.2f} s, after {tb[kind]:.2f} s")
    return 1 if bad else 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("snapshot")
    s.add_argument("src")
    s.add_argument("out")
    s.add_argument("--fp", type=int, default=300)
    s.add_argument("--rand", type=int, default=100)
    c = sub.add_parser("compare")
    c.add_argument("before")
    c.add_argument("after")
    args = ap.parse_args(argv)
    if args.cmd == "snapshot":
        snapshot(args.src, args.out, args.fp, args.rand)
        return 0
    return compare(args.before, args.after)


if __name__ == "__main__":
    sys.exit(main())
