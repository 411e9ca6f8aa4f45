"""Two source trees on the same building footprints: CPU time of ``tighten`` per footprint, alternating.

Each round runs one fresh process per tree, the trees one after the other, so that both see the same load;
a process builds ``--n`` footprints (`bench_geo.footprints`, ``--seed``), tightens each at r = 1 m, times
shapely's vectorised opening + closing of the same array at quad_segs 176, and prints CPU milliseconds per
footprint, the ratio, and the total area (which must agree between the trees). With ``--fast-only`` only
the footprints that the AFTER tree's fast path takes are timed (chosen in a first pass, the same list for
both trees): the fast path's cost a footprint, against the opening + closing of those footprints.

Run:  python benchmarks/ab_footprints.py BEFORE_ROOT AFTER_ROOT [--n 300] [--seed 3] [--rounds 2]
      [--fast-only]
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


def child(root: str, n: int, seed: int, only: list[int] | None = None) -> dict:
    sys.path[:0] = [root, str(HERE)]
    import numpy as np

    import bench_geo
    import vectortighten as vt

    if not vt.__file__.startswith(root):
        raise SystemExit(f"imported {vt.__file__}, not from {root}")
    fps = list(bench_geo.footprints(n, seed=seed))
    if only is not None:
        fps = [fps[k] for k in only]
        n = len(fps)
    t0 = time.process_time()
    area = sum(vt.tighten(g, 1.0).area for g in fps)
    engine = time.process_time() - t0
    t0 = time.process_time()
    bench_geo.opening_closing(np.array(fps, dtype=object), 1.0, 176)
    base = time.process_time() - t0
    return {"ms": engine / n * 1e3, "base_ms": base / n * 1e3, "area": area}


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--child":
        only = json.loads(argv[4]) if len(argv) > 4 else None
        print(json.dumps(child(argv[1], int(argv[2]), int(argv[3]), only)), flush=True)
        return 0
    if argv and argv[0] == "--fast-list":
        sys.path[:0] = [argv[1], str(HERE)]
        import bench_geo
        import vectortighten as vt

        fps = bench_geo.footprints(int(argv[2]), seed=int(argv[3]))
        print(json.dumps([k for k, g in enumerate(fps) if vt.tighten(g, 1.0)._cache["_path"] == "fast"]))
        return 0
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--fast-only", action="store_true", help="time only the footprints the fast path takes")
    args = ap.parse_args(argv)
    extra = []
    if args.fast_only:
        extra = [subprocess.run([sys.executable, __file__, "--fast-list", str(Path(args.after).resolve()),
                                 str(args.n), str(args.seed)], capture_output=True, text=True,
                                check=True).stdout.strip()]
        print(f"{len(json.loads(extra[0]))} of {args.n} footprints on the fast path")
    got = {args.before: [], args.after: []}
    for _ in range(args.rounds):
        for root in (args.before, args.after):
            out = subprocess.run([sys.executable, __file__, "--child", str(Path(root).resolve()), str(args.n),
                                  str(args.seed)] + extra, capture_output=True, text=True, check=True)
            got[root].append(json.loads(out.stdout))
    b, a = got[args.before], got[args.after]
    mb, ma = statistics.median(m["ms"] for m in b), statistics.median(m["ms"] for m in a)
    print("| tree | tighten (ms a footprint) | opening + closing (ms) | ratio |")
    print("|---|---:|---:|---:|")
    for name, ms, rows in (("before", mb, b), ("after", ma, a)):
        base = statistics.median(m["base_ms"] for m in rows)
        print(f"| {name} | {ms:.1f} | {base:.3f} | {ms / base:.0f} |")
    same = len({round(m["area"], 6) for m in b + a}) == 1
    print(f"\nafter / before: {ma / mb:.2f}; same total area: {'yes' if same else 'NO'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
