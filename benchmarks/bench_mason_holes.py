"""init="mason" against init="core" on a square with many holes (issue 23, item 4): CPU time, medians.

Holes: random 9-gons (angles, radii 1.5–4 from ``numpy.random.default_rng(3)``) on a 12-unit grid; r = 1.
Run:  python benchmarks/bench_mason_holes.py [--sizes 4 8] [--repeats 3]   (n × n holes; the two inits are
timed alternately, the median of the repeats reported). Results: results/hardening.md.
"""

import argparse
import statistics
import time
import warnings

import numpy as np
import shapely
from shapely.geometry import Polygon, box

import vectortighten as vt


def holes(n: int):
    rng = np.random.default_rng(3)
    G = box(0, 0, 12 * n + 5, 12 * n + 5)
    hs = []
    for i in range(n):
        for j in range(n):
            th = np.sort(rng.uniform(0, 2 * np.pi, 9))
            rad = rng.uniform(1.5, 4.0, 9)
            cx, cy = 8.5 + 12 * i, 8.5 + 12 * j
            hs.append(Polygon(np.column_stack([cx + rad * np.cos(th), cy + rad * np.sin(th)])))
    return G.difference(shapely.union_all(hs))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[4, 8])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print("| holes | init=\"core\" | init=\"mason\" | ratio |\n|---|---|---|---|")
    for n in args.sizes:
        G = holes(n)
        samples = {"core": [], "mason": []}
        for _ in range(args.repeats):
            for init in ("core", "mason"):
                t = time.process_time()
                vt.tighten(G, 1.0, init=init)
                samples[init].append(time.process_time() - t)
        times = {init: statistics.median(v) for init, v in samples.items()}
        ratio = times["mason"] / times["core"]
        print(f"| {n * n} | {times['core']:.2f} s | {times['mason']:.2f} s | {ratio:.1f} |")


if __name__ == "__main__":
    main()
