"""Before/after identity of the fast path and of the final check (`_guard`), bit for bit.

Made for speed-ups of the fast path's small-shape costs: a snapshot imports ``vectortighten`` from the
source tree given and records, for every case, the engine's path, ``converged``, every loop's exact data
arrays (`Loop._data`, `Loop._arc`) as bytes, the WKB of the sampled geometry and the final check's
findings (`_guard.containment_problems`). ``compare`` asks for all of it to be equal bit for bit.

The final check is compared on wrong results too: each fast result of a footprint is perturbed
(its loops and geometry shifted by 0.01r to r, scaled about the shape's centre by 1 ± 0.2% to 5%, or
replaced by the tightening at 1.5r and 3r, or by S's own rings), and the check must flag exactly the
same perturbed results before and after (the areas it reports may differ by rounding: printed where
they differ by more than 1e-6 relative).

Cases (their shapes are built from this file's own tree, so that both snapshots see the same input):

* ``fp``: 300 building footprints (`bench_geo.footprints`) at seeds 0 and 1, r = 0.5 and 1 (init
  core), and the first 100 of seed 0 at r = 1 with init input and mason;
* ``tf``: the shapes of ``tests/test_fast.py`` (necks near 2r, annuli, a hole near the boundary, dense
  wavy rings at their radii and inits) and 60 draws (derandomised) of its hypothesis strategies.

Run:  python benchmarks/identity_fast.py snapshot SRC_ROOT OUT.pkl [--quick]
      python benchmarks/identity_fast.py compare BEFORE.pkl AFTER.pkl
"""

from __future__ import annotations

import pickle
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import Polygon

from _trees import use_tree

HERE = Path(__file__).resolve().parent


def _test_fast_cases():
    sys.path.insert(0, str(HERE.parent))
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from tests.strategies import box_unions, disk_unions, holed, stars
    from tests.test_fast import blobs, wavy

    out = []
    for gap in [0.5, 1e-3, 1e-7, 1e-10, 0.0, -1e-10, -1e-7, -1e-3]:
        w = 2.0 + gap
        hole = wavy(3000, amp=0.0, rad=4.0, center=(6 - w, 0), hole=True)
        out.append((f"neck{gap}", Polygon(wavy(6000, amp=0.0, rad=10.0), [hole]), 1.0, "core"))
        apart = shapely.union_all([Polygon(wavy(4000, amp=0.0, rad=3.0, center=(-3 - w / 2, 0))),
                                   Polygon(wavy(4000, amp=0.0, rad=3.0, center=(3 + w / 2, 0)))])
        out.append((f"apart{gap}", apart, 1.0, "core"))
    for width in [1.9, 1.999999, 2.0 - 1e-9, 2.0 + 1e-9, 2.1]:
        S = Polygon(wavy(3000, amp=0.0, rad=10.0), [wavy(3000, amp=0.0, rad=10.0 - width, hole=True)])
        out.append((f"annulus{width}", S, 1.0, "core"))
    out.append(("hole", Polygon(wavy(20000), [wavy(5000, amp=0.02, rad=1.5, center=(7.5, 0), hole=True)]),
                0.3, "core"))
    out.append(("hole2", Polygon(wavy(20000), [wavy(5000, amp=0.0, rad=1.5, center=(8.0, 0), hole=True)]),
                0.3, "core"))
    S = Polygon(wavy(5000), [wavy(2000, amp=0.02, rad=2.0, center=(3.0, 1.0), hole=True)])
    for r in (0.1, 0.4):
        for init in ("core", "input", "mason"):
            out.append((f"wavy{r}{init}", S, r, init))
    drawn = []

    @settings(max_examples=60, derandomize=True, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(st.one_of(stars(), box_unions(max_n=4), disk_unions(max_n=4), holed(), blobs(), blobs()),
           st.floats(0.05, 2.0), st.sampled_from(["core", "input", "mason"]))
    def draw(S, r, init):
        drawn.append((S, r, init))

    draw()
    out += [(f"draw{k}", S, r, init) for k, (S, r, init) in enumerate(drawn[:60])]
    return out


def cases(quick: bool):
    sys.path.insert(0, str(HERE))
    import bench_geo

    n = 60 if quick else 300
    for seed in (0, 1):
        fps = bench_geo.footprints(n, seed=seed)
        for r in (0.5, 1.0):
            for i, g in enumerate(fps):
                yield f"fp{seed}:{r}:{i}", g, r, "core", True
        if seed == 0:
            for init in ("input", "mason"):
                for i, g in enumerate(fps[:100]):
                    yield f"fp0:1.0:{i}:{init}", g, 1.0, init, False
    if not quick:
        for name, S, r, init in _test_fast_cases():
            yield "tf:" + name, S, r, init, False


def _perturbed(vt, T, S, r):
    """Wrong results made from a fast result T of S: (name, loops, geometry)."""
    cx, cy = S.centroid.x, S.centroid.y
    for d in (0.01, 0.03, 0.1, 0.3, 1.0):
        yield (f"shift{d}", [L.affine(1.0, d * r, 0.0) for L in T.loops],
               affinity.translate(T.geometry, d * r, 0.0))
    for s in (0.95, 0.99, 0.998, 1.002, 1.01, 1.05):
        yield (f"scale{s}", [L.affine(s, cx * (1 - s), cy * (1 - s)) for L in T.loops],
               affinity.scale(T.geometry, s, s, origin=(cx, cy)))
    for k in (1.5, 3.0):
        U = vt.tighten(S, k * r)
        if U.loops:
            yield f"r{k}", U.loops, U.geometry
    from vectortighten.curves import Loop

    yield "S", [Loop.from_polygon_ring(np.asarray(ring.coords)) for ring in shapely.get_rings(S)], S


def snapshot(src: str, out: str, quick: bool) -> None:
    todo = list(cases(quick))                   # inputs from this tree, before the engine is imported
    use_tree(src)
    import vectortighten as vt
    from vectortighten._guard import containment_problems

    print("vectortighten from", vt.__file__, file=sys.stderr)
    res = {}
    t_all = time.process_time()
    t_fast = 0.0
    for name, S, r, init, perturb in todo:
        t0 = time.process_time()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                T = vt.tighten(S, r, init=init)
            except Exception as e:              # recorded, and compared like a result
                res[name] = dict(error=f"{type(e).__name__}: {e}")
                continue
        dt = time.process_time() - t0
        path = T._cache.get("_path", "?")
        if path == "fast":
            t_fast += dt
        rec = dict(path=path, converged=T.converged, warnings=[str(w.message) for w in caught],
                   loops=[(L._data.tobytes(), L._arc.tobytes()) for L in T.loops],
                   wkb=shapely.to_wkb(T.geometry), check=containment_problems(T), t=dt)
        if perturb and path == "fast":
            flags = {}
            for what, loops, geom in _perturbed(vt, T, S, r):
                if loops is None:
                    continue
                W = vt.Tightening(loops=list(loops), geometry=geom, r=T.r, init=T.init, tolerance=T.tolerance,
                                  shape=T.shape)
                W._cache.update(T._cache)
                flags[what] = containment_problems(W)
            rec["perturbed"] = flags
        res[name] = rec
    with open(out, "wb") as f:
        pickle.dump(res, f)
    paths = {}
    for v in res.values():
        paths[v.get("path", "error")] = paths.get(v.get("path", "error"), 0) + 1
    print(f"{len(res)} cases in {time.process_time() - t_all:.1f} s CPU ({t_fast:.2f} s in fast results); "
          f"paths {paths}", file=sys.stderr)


def _areas(problems: list[str]) -> list[float]:
    return [float(p.split("·")[0].split()[-1]) if "·" in p else np.nan for p in problems]


def compare(before: str, after: str) -> int:
    with open(before, "rb") as f:
        a = pickle.load(f)
    with open(after, "rb") as f:
        b = pickle.load(f)
    same = bad = 0
    flagged = {"both": 0, "neither": 0, "differ": 0}
    for k in a:
        A, B = a[k], b.get(k)
        if B is None:
            print("MISSING", k)
            bad += 1
            continue
        keys = ("error",) if "error" in A else ("path", "converged", "warnings", "loops", "wkb", "check")
        diff = [key for key in keys if A.get(key) != B.get(key)]
        if diff:
            bad += 1
            print("DIFF", k, diff, A.get("path"), B.get("path"), A.get("check"), B.get("check"))
        else:
            same += 1
        for what, pa in A.get("perturbed", {}).items():
            pb = B.get("perturbed", {}).get(what)
            if pb is None or bool(pa) != bool(pb) or len(pa) != len(pb):
                flagged["differ"] += 1
                print("CHECK DIFFERS", k, what, pa, "|", pb)
                continue
            flagged["both" if pa else "neither"] += 1
            xa, xb = np.array(_areas(pa)), np.array(_areas(pb))
            if len(xa) and not np.allclose(xa, xb, rtol=1e-6, atol=0, equal_nan=True):
                print("  area differs", k, what, pa, "|", pb)
    ta = sum(v.get("t", 0.0) for v in a.values())
    tb = sum(v.get("t", 0.0) for v in b.values())
    print(f"{len(a)} cases: {same} identical bit for bit (path, loops, WKB, check), {bad} different; "
          f"perturbed results flagged by both {flagged['both']}, by neither {flagged['neither']}, "
          f"differently {flagged['differ']}; CPU {ta:.1f} s before, {tb:.1f} s after")
    return 1 if bad or flagged["differ"] else 0


if __name__ == "__main__":
    if sys.argv[1] == "snapshot":
        snapshot(sys.argv[2], sys.argv[3], "--quick" in sys.argv)
    elif sys.argv[1] == "compare":
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    else:
        raise SystemExit(__doc__)
