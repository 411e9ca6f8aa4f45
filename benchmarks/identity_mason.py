"""Before/after identity of the Mason filter: snapshot one source tree, compare two snapshots (issue 23).

A snapshot computes, with the source tree given (its ``vectortighten`` imported first), for 15 fixed
cases (square plates with 1, 4, 16, 64 random holes from `bench_mason_holes.holes` at r = 1 and 1.5, a
25-point star at r = 0.1 and 0.3, two boxes meeting at a corner with a 1e-6 notch, three bars, a comb of
seven teeth, an L and a notched box): ``mason(S, r)`` and ``tighten(S, r, init="mason")``, recording the
WKB, area, number of parts (Mason) and area, perimeter, ``converged``, number of loops, WKB (tightening),
with their CPU times.

Comparing two snapshots: areas and perimeters to 1e-12 relative, the same numbers of parts, loops and
``converged``; the geometries are also compared vertex for vertex after ``shapely.normalize`` (reported,
not required: an overlay computed in another order may move a vertex by an ulp) and by the area of their
symmetric difference.

Run:  python benchmarks/identity_mason.py snapshot SRC_ROOT OUT.pkl
      python benchmarks/identity_mason.py compare BEFORE.pkl AFTER.pkl
"""

import math
import os
import pickle
import sys
import time
import warnings

import numpy as np


def cases():
    from shapely.geometry import Polygon, box

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from bench_mason_holes import holes

    out = []
    for n in (1, 2, 4, 8):
        for r in (1.0, 1.5):
            out.append((f"holes {n * n}, r = {r}", holes(n), r))
    k = 25
    th = np.arange(2 * k) * math.pi / k
    rad = np.where(np.arange(2 * k) % 2 == 0, 1.0, 0.5)
    star = Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))
    out += [("star, r = 0.1", star, 0.1), ("star, r = 0.3", star, 0.3)]
    notched = Polygon([(1.001, 1.001), (2, 1.001), (2, 2), (1.6, 2), (1.6, 1.999999), (1.599999, 1.999999),
                       (1.599999, 2), (1.001, 2)])
    out.append(("two boxes at a corner, notch", box(0, 0, 1, 1).union(notched), 0.1))
    bars = box(0, 0, 10, 1.5).union(box(0, 2.5, 10, 4)).union(box(0, 5, 10, 6.5))
    out.append(("three bars", bars, 1.0))
    comb = box(0, 0, 14, 1)
    for i in range(7):
        comb = comb.union(box(i * 2 + 0.5, 1, i * 2 + 1.5, 5))
    out.append(("comb", comb, 0.5))
    out.append(("L", box(0, 0, 10, 1).union(box(0, 0, 1, 10)), 1.0))
    out.append(("notched box", box(0, 0, 4, 4).difference(box(1.9, 3, 2.1, 4)), 0.5))
    return out


def snapshot(src: str, path: str) -> None:
    sys.path.insert(0, os.path.abspath(src))
    import shapely

    import vectortighten as vt

    assert vt.__file__.startswith(os.path.abspath(src)), vt.__file__
    warnings.simplefilter("ignore")
    rows = []
    for name, S, r in cases():
        t = time.process_time()
        M = vt.mason(S, r)
        tm = time.process_time() - t
        t = time.process_time()
        T = vt.tighten(S, r, init="mason")
        tt = time.process_time() - t
        rows.append(dict(name=name, m_wkb=shapely.to_wkb(M), m_area=M.area, m_parts=len(shapely.get_parts(M)),
                         t_wkb=shapely.to_wkb(T.geometry), t_area=T.area, t_perimeter=T.perimeter,
                         converged=T.converged, loops=len(T.loops), t_mason=tm, t_tighten=tt))
        print(f"{name}: mason {tm:.2f} s, tighten {tt:.2f} s", flush=True)
    with open(path, "wb") as f:
        pickle.dump(rows, f)


def compare(a_path: str, b_path: str) -> int:
    import shapely

    with open(a_path, "rb") as f:
        A = pickle.load(f)
    with open(b_path, "rb") as f:
        B = pickle.load(f)
    bad = 0

    def rel(x, y):
        return abs(x - y) / max(abs(x), abs(y), 1e-300)

    for a, b in zip(A, B, strict=True):
        assert a["name"] == b["name"]
        verdict = []
        for key, what in (("m_wkb", "mason"), ("t_wkb", "tightening")):
            ga, gb = shapely.from_wkb(a[key]), shapely.from_wkb(b[key])
            same = shapely.equals_exact(shapely.normalize(ga), shapely.normalize(gb), tolerance=0.0)
            sd = ga.symmetric_difference(gb).area if not same else 0.0
            verdict.append(f"{what} {'same vertices' if same else f'sym. diff. {sd:.1e}'}")
        checks = [rel(a["m_area"], b["m_area"]) <= 1e-12 or a["m_area"] == b["m_area"],
                  a["m_parts"] == b["m_parts"],
                  rel(a["t_area"], b["t_area"]) <= 1e-12 or a["t_area"] == b["t_area"],
                  rel(a["t_perimeter"], b["t_perimeter"]) <= 1e-12 or a["t_perimeter"] == b["t_perimeter"],
                  a["converged"] == b["converged"], a["loops"] == b["loops"]]
        ok = all(checks)
        bad += not ok
        print(f"{'ok ' if ok else 'BAD'} {a['name']}: mason area {rel(a['m_area'], b['m_area']):.1e} rel, "
              f"tightening area {rel(a['t_area'], b['t_area']):.1e} rel; {', '.join(verdict)}; "
              f"mason {a['t_mason']:.2f} → {b['t_mason']:.2f} s, tighten {a['t_tighten']:.2f} → "
              f"{b['t_tighten']:.2f} s")
    print(f"{len(A) - bad} of {len(A)} identical (areas, perimeters to 1e-12, parts, loops, converged)")
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "snapshot":
        snapshot(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        sys.exit(__doc__)
