"""`tighten` and `verify()` of two source trees on the same shapes, in alternating processes (CPU medians).

Shapes: many parts (MultiPolygons of building footprints) at 1k and 10k vertices, a smooth wavy star of
20k vertices (the fast path), the disk union, coastline, harmonic star, comb, spiral strip, jagged star and
traced outline of `bench_families.py` at about 10k (5k for the comb, 4k for the disk union). Each tree runs
in its own process, ``--rounds`` times, the order alternating; the table gives the medians and, for the
second tree, verify over tighten.

    python benchmarks/ab_verify.py BEFORE_TREE AFTER_TREE [--rounds 3]

(a tree: a `git archive` of a commit, unpacked; its ``vectortighten`` is imported with `_trees.use_tree`).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def cases():
    import numpy as np
    from shapely.geometry import Polygon

    import bench_families as bf

    t = np.linspace(0, 2 * np.pi, 20_000, endpoint=False)
    rad = 10 + 0.8 * np.sin(7 * t) + 0.3 * np.sin(19 * t)
    return {"many parts 1k": (bf.many_parts(1000), 1.0), "many parts 10k": (bf.many_parts(10_000), 1.0),
            "wavy star 20k": (Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)])), 0.3),
            "disk union 4k": (bf.disk_union(4337), 1.0), "coastline 10k": (bf.coastline(10_000), 1.5),
            "harmonic star 10k": (bf.harmonic_star(10_000), 1.0), "comb 5k": (bf.comb(10_000), 1.0),
            "spiral strip 10k": (bf.spiral_strip(10_000), 1.0),
            "jagged star 10k": (bf.jagged_star(10_000), 0.5),
            "traced outline 10k": (bf.traced_outline(10_000), 0.6)}


def child(tree: str) -> None:
    sys.path.insert(0, str(HERE))
    from _trees import use_tree

    todo = cases()
    use_tree(tree)
    import vectortighten as vt
    from verify_cost import tighten_and_verify

    out = {}
    for name, (S, r) in todo.items():
        tighten_s, verify_s, problems, path = tighten_and_verify(vt, S, r)
        out[name] = (tighten_s, verify_s, len(problems), path)
    print(json.dumps(out))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    trees = [args.before, args.after]
    runs = [[], []]
    for k in range(args.rounds):
        for i in (0, 1) if k % 2 == 0 else (1, 0):
            done = subprocess.run([sys.executable, __file__, "--child", trees[i]], capture_output=True,
                                  text=True, check=True)
            runs[i].append(json.loads(done.stdout.strip().splitlines()[-1]))
    print("| shape | path | tighten before (s) | after | verify before (s) | after | verify / tighten after "
          "| problems before, after |")
    print("|---|---|---:|---:|---:|---:|---:|---|")
    for name in runs[0][0]:
        med = [[statistics.median(run[name][i] for run in runs[t]) for i in (0, 1)] for t in (0, 1)]
        print(f"| {name} | {runs[1][0][name][3]} | {med[0][0]:.3f} | {med[1][0]:.3f} | {med[0][1]:.3f} | "
              f"{med[1][1]:.3f} | {med[1][1] / med[1][0]:.2f} | "
              f"{runs[0][0][name][2]}, {runs[1][0][name][2]} |")


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--child":
        child(sys.argv[2])
    else:
        main()
