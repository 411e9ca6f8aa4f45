"""Two source trees on the general engine's small shapes: CPU time per shape, alternating processes.

What it times, in each tree: ``tighten`` of the building footprints (`bench_geo.footprints`, ``--seed``,
r = 1 m) that the AFTER tree's general engine takes (chosen in a first pass, the same list for both
trees), ``exact_offsets`` of those footprints (both sides), and ``tighten`` of `bench_families`' families
at ``--family-n`` vertices (their r, tolerance 1e-5·r; the median of three calls). Each round runs one
fresh process per tree, the trees one after the other, so that both see the same load; the table gives
the medians over the rounds of CPU milliseconds, and the ratio after / before. The total area of the
results must agree.

Run:  python benchmarks/ab_general.py BEFORE_ROOT AFTER_ROOT [--n 300] [--seed 3] [--rounds 3]
      [--family-n 1000] [--no-families]
      (a root is a checkout, e.g. ``git archive <commit> | tar -x -C /tmp/before``)
"""

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _general(root: str, n: int, seed: int) -> list[int]:
    sys.path[:0] = [root, str(HERE)]
    import bench_geo

    import vectortighten as vt

    fps = bench_geo.footprints(n, seed=seed)
    return [k for k, g in enumerate(fps) if vt.tighten(g, 1.0)._cache["_path"] == "general"]


def _child(root: str, n: int, seed: int, only: list[int], family_n: int) -> dict:
    sys.path[:0] = [root, str(HERE)]
    import warnings

    import bench_families
    import bench_geo
    import shapely

    import vectortighten as vt
    from vectortighten import morphology
    from vectortighten.offsets import exact_offsets

    warnings.simplefilter("ignore")
    fps = bench_geo.footprints(n, seed=seed)
    gen = [fps[k] for k in only]
    clock = time.process_time
    out: dict = {}
    t0 = clock()
    area = sum(vt.tighten(g, 1.0).geometry.area for g in gen)
    out["general footprint"] = (clock() - t0) / max(1, len(gen)) * 1e3
    oriented = [morphology._orient(shapely.normalize(g)) for g in gen]
    t0 = clock()
    for g in oriented:
        for side in (1, -1):
            exact_offsets(g, 1.0, side)
    out["exact_offsets (2 sides)"] = (clock() - t0) / max(1, len(gen)) * 1e3
    if family_n:
        for name, (make, r) in bench_families.FAMILIES.items():
            S = make(family_n)
            times = []
            for _ in range(3):
                t0 = clock()
                T = vt.tighten(S, r, tolerance=1e-5 * r)
                times.append(clock() - t0)
            out[f"{name} @{family_n}"] = statistics.median(times) * 1e3
            area += T.geometry.area
    out["_area"] = area
    return out


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        a = sys.argv
        print(json.dumps(_child(a[2], int(a[3]), int(a[4]), json.loads(a[5]), int(a[6]))), flush=True)
        return
    if len(sys.argv) > 1 and sys.argv[1] == "--pick":
        print(json.dumps(_general(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))), flush=True)
        return
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--family-n", type=int, default=1000)
    ap.add_argument("--no-families", action="store_true")
    args = ap.parse_args()
    fam_n = 0 if args.no_families else args.family_n
    pick = subprocess.run([sys.executable, __file__, "--pick", args.after, str(args.n), str(args.seed)],
                          capture_output=True, text=True, check=True)
    only = pick.stdout.strip().splitlines()[-1]
    print(f"{len(json.loads(only))} of {args.n} footprints (seed {args.seed}) on the general engine")
    runs: dict[str, list[dict]] = {"before": [], "after": []}
    for _ in range(args.rounds):
        for name, root in (("before", args.before), ("after", args.after)):
            cmd = [sys.executable, __file__, "--child", root, str(args.n), str(args.seed), only, str(fam_n)]
            res = subprocess.run(cmd, capture_output=True, text=True, check=True)
            runs[name].append(json.loads(res.stdout.strip().splitlines()[-1]))
    keys = [k for k in runs["before"][0] if not k.startswith("_")]
    print("| CPU ms (median of %d) | before | after | after / before |" % args.rounds)
    print("|---|---:|---:|---:|")
    for k in keys:
        b = statistics.median(r[k] for r in runs["before"])
        a = statistics.median(r[k] for r in runs["after"])
        print(f"| {k} | {b:.2f} | {a:.2f} | {a / b:.2f} |")
    ab, aa = runs["before"][0]["_area"], runs["after"][0]["_area"]
    print(f"\nsame total area: {'yes' if abs(ab - aa) <= 1e-9 * abs(ab) else 'NO'} ({ab!r} / {aa!r})")


if __name__ == "__main__":
    main()
