"""Before/after identity of the exact engine's results: snapshot one source tree, compare two snapshots.

A snapshot tightens, with the source tree given (its ``vectortighten`` imported first), a fixed set of
shapes and records for each: the pieces of every loop (segments' ends, arcs' centre, radius, start
angle and sweep), area, perimeter, the geometry's WKB, ``verify()``'s findings and the CPU times. Sets:

* ``random``: 120 random stars with ripples near r, 60 unions of boxes (some with a round hole), 60 unions
  of disks (numpy seed 12345, radii drawn per shape);
* ``fp``: 150 building footprints (`bench_geo.footprints`, seed 3), r = 1;
* ``corpus``: `benchmarks/corpus.py`'s real shapes up to 30 000 vertices at r = 0.5 and 1.0 stroke width;
* ``families``: `benchmarks/bench_families.py`'s families at 1000 vertices, at their r and tolerance 1e-5·r.

Comparing two snapshots matches each loop as a cyclic sequence (the piece a loop starts at may differ
when the triangulation does: the loops are the same curves), pieces equal to 1e-11 of the shape's size,
area and perimeter to 1e-12 relative; the WKB is compared as bytes and, where it differs, after
``shapely.normalize`` (which fixes each ring's start).

Run:  python benchmarks/identity.py snapshot SRC_ROOT OUT.pkl [random fp corpus]
      python benchmarks/identity.py compare BEFORE.pkl AFTER.pkl
"""

import os
import pickle
import signal
import sys
import time

import numpy as np
import shapely


def split(p):
    out, cur = [], []
    for row in p:
        if row[0] == 9:
            out.append(np.array(cur))
            cur = []
        else:
            cur.append(row)
    return out


def canon(L):
    # rotate so that the lexicographically smallest start point comes first; arcs: start angle wraps
    key = [(round(r[0]), round(r[1], 9), round(r[2], 9)) for r in L]
    i = min(range(len(L)), key=lambda j: key[j])
    return np.roll(L, -i, axis=0)


def loops_equal(pa, pb, tol):
    A = sorted((canon(L) for L in split(pa)), key=lambda L: tuple(np.round(L[0], 9)))
    B = sorted((canon(L) for L in split(pb)), key=lambda L: tuple(np.round(L[0], 9)))
    if len(A) != len(B):
        return False
    for x, y in zip(A, B, strict=True):
        if x.shape != y.shape or not np.array_equal(x[:, 0], y[:, 0]):
            return False
        d = np.abs(x - y)
        arc = x[:, 0] == 1
        d[arc, 4] = np.abs(np.angle(np.exp(1j * (x[arc, 4] - y[arc, 4]))))
        if d.max() > tol:
            print("  maxdiff", d.max())
            return False
    return True


def compare(before: str, after: str) -> None:
    a = pickle.load(open(before, "rb"))
    b = pickle.load(open(after, "rb"))
    same = diff = 0
    rot = {True: 0, False: 0, "bytes": 0}
    ta = tb = 0.0
    va = vb = 0
    for k in a:
        if k not in b:
            continue
        A, B = a[k], b[k]
        if "error" in A or "error" in B:
            if A.get("error") != B.get("error"):
                print("ERR", k, A.get("error"), "|", B.get("error"))
            continue
        ta += A["t"]
        tb += B["t"]
        va += bool(A["verify"])
        vb += bool(B["verify"])
        pa, pb = A["pieces"], B["pieces"]
        scale = max(1.0, np.abs(pa[:, 1:3]).max()) if len(pa) else 1.0
        ok = pa.shape == pb.shape and (pa.shape[0] == 0 or loops_equal(pa, pb, 1e-12 * scale * 10))
        ok_a = abs(A["area"] - B["area"]) <= 1e-12 * max(1, abs(A["area"])) and abs(
            A["perimeter"] - B["perimeter"]
        ) <= 1e-12 * max(1, A["perimeter"])
        wkb = A["wkb"] == B["wkb"]
        if ok and ok_a:
            same += 1
        else:
            diff += 1
            md = np.abs(pa - pb).max() if pa.shape == pb.shape and len(pa) else None
            print(
                "DIFF",
                k,
                pa.shape,
                pb.shape,
                "maxdiff",
                md,
                "area",
                A["area"],
                B["area"],
                "per",
                A["perimeter"],
                B["perimeter"],
                "verify",
                A["verify"][:1],
                B["verify"][:1],
            )
        if bool(A["verify"]) != bool(B["verify"]):
            print("VERIFY", k, A["verify"][:2], B["verify"][:2])
        if ok and ok_a and not wkb:
            nw = shapely.normalize(shapely.from_wkb(A["wkb"])).equals_exact(
                shapely.normalize(shapely.from_wkb(B["wkb"])), 1e-12 * scale * 10
            )
            rot[nw] += 1
            if not nw:
                print("WKB differs even normalized", k)
        elif wkb:
            rot["bytes"] += 1
    print(
        "WKB: identical bytes",
        rot["bytes"],
        "equal after normalize (ring start differs)",
        rot[True],
        "differ",
        rot[False],
    )
    print(
        f"same {same} diff {diff}; time before {ta:.1f}s after {tb:.1f}s; verify-unclean before {va} "
        f"after {vb}; only-before {len(set(a) - set(b))}"
    )


def snapshot(src: str, out: str, sets: list[str]) -> None:
    sys.path.insert(0, src)
    sys.path.insert(0, src + "/benchmarks")
    import vectortighten as vt
    from vectortighten.curves import Arc

    def shapes():
        rng = np.random.default_rng(12345)
        if "random" in sets:
            for i in range(120):  # random stars with ripples near r
                n = int(rng.integers(20, 300))
                k = rng.uniform(0.5, 3.0)
                t = np.sort(rng.uniform(0, 2 * np.pi, n))
                rad = (
                    10
                    + k * rng.uniform(-1, 1) * np.sin(rng.integers(3, 15) * t)
                    + rng.uniform(0, 1.5) * rng.standard_normal(n) * 0.5
                )
                rad = np.maximum(rad, 2)
                P = shapely.make_valid(shapely.Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)])))
                P = max(shapely.get_parts(P), key=lambda p: p.area if p.geom_type == "Polygon" else 0)
                yield f"star{i}", P, float(rng.uniform(0.3, 2.0))
            for i in range(60):  # unions of boxes, with holes sometimes
                bs = [
                    shapely.box(
                        *(lambda x, y: (x, y, x + rng.uniform(1, 6), y + rng.uniform(1, 6)))(
                            *rng.uniform(0, 8, 2)
                        )
                    )
                    for _ in range(int(rng.integers(2, 7)))
                ]
                P = shapely.union_all(bs)
                if rng.random() < 0.4:
                    c = rng.uniform(2, 8, 2)
                    P = P.difference(shapely.Point(c).buffer(rng.uniform(0.3, 1.5), 4))
                yield f"boxes{i}", P, float(rng.uniform(0.2, 1.5))
            for i in range(60):  # disk unions
                P = shapely.union_all(
                    [
                        shapely.Point(rng.uniform(0, 10, 2)).buffer(rng.uniform(0.5, 3), 8)
                        for _ in range(int(rng.integers(2, 6)))
                    ]
                )
                yield f"disks{i}", P, float(rng.uniform(0.2, 1.5))
        if "fp" in sets:
            import bench_geo

            for i, g in enumerate(bench_geo.footprints(150, seed=3)):
                yield f"fp{i}", g, 1.0
        if "corpus" in sets:
            import corpus

            for c in corpus.cases():
                if c.n_vertices > 30000:
                    continue
                for f in (0.5, 1.0):
                    yield f"{c.family}/{c.name}@{f}", c.shape, f * c.width
        if "families" in sets:
            import bench_families

            for fam, (make, r) in bench_families.FAMILIES.items():
                yield f"family/{fam}@1000", make(1000), (r, 1e-5 * r)

    class TO(Exception):
        pass

    def alarm(*a):
        raise TO()

    signal.signal(signal.SIGALRM, alarm)
    res = {}
    limit = int(os.environ.get("SNAP_LIMIT", "120"))
    for name, S, r in shapes():
        r, kw = (r[0], {"tolerance": r[1]}) if isinstance(r, tuple) else (r, {})
        signal.alarm(limit)
        t0 = time.process_time()
        try:
            T = vt.tighten(S, r, **kw)
            dt = time.process_time() - t0
            signal.alarm(0)
            pcs = []
            for L in T.loops:
                for p in L.pieces:
                    if isinstance(p, Arc):
                        pcs.append((1, p.center[0], p.center[1], p.radius, p.start_angle, p.sweep))
                    else:
                        pcs.append((0, p.start[0], p.start[1], p.end[0], p.end[1], 0.0))
                pcs.append((9, 0, 0, 0, 0, 0))
            signal.alarm(limit)
            t1 = time.process_time()
            v = T.verify()
            dv = time.process_time() - t1
            signal.alarm(0)
            res[name] = dict(
                pieces=np.array(pcs),
                area=T.area,
                perimeter=T.perimeter,
                wkb=shapely.to_wkb(T.geometry),
                verify=v,
                t=dt,
                tv=dv,
                path=T._cache.get("_path", "?"),
                n=int(shapely.get_num_coordinates(S)),
            )
        except TO:
            res[name] = dict(error="timeout", t=limit)
        except Exception as e:
            signal.alarm(0)
            res[name] = dict(error=f"{type(e).__name__}: {e}", t=time.process_time() - t0)
        print(
            name, res[name].get("error", ""), f"{res[name]['t']:.2f}", res[name].get("path", ""), flush=True
        )
        pickle.dump(res, open(out, "wb"))


if __name__ == "__main__":
    if sys.argv[1] == "snapshot":
        snapshot(sys.argv[2], sys.argv[3], sys.argv[4:] or ["random", "fp", "corpus"])
    else:
        compare(sys.argv[2], sys.argv[3])
