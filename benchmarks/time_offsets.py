"""CPU time of `exact_offsets` alone (both sides) on dense outlines, against shapely's opening + closing.

Each shape is built once; `exact_offsets(S, r, +1)` and `(S, r, −1)` are timed ``repeats`` times in this
process (CPU time, median), beside ``S.buffer(-r).buffer(r)`` plus ``S.buffer(r).buffer(-r)`` at shapely's
default quad_segs, measured in the same process.

Run:  python benchmarks/time_offsets.py [FAMILY:N:REPEATS ...] [--root TREE] [--profile]
      e.g. ``traced:100000:3 harmonic:100000:3 traced:10000:3``; ``--root`` imports vectortighten from
      another checkout (A/B against a tree unpacked with ``git archive``).
"""

import argparse
import cProfile
import pstats
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

SHORT = {"traced": "traced outline", "harmonic": "harmonic star", "jagged": "jagged star",
         "coastline": "coastline", "parts": "many parts", "two": "two-harmonic star"}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("cases", nargs="*", default=["traced:10000:3"])
    p.add_argument("--root", default=str(HERE.parent))
    p.add_argument("--profile", action="store_true")
    a = p.parse_args(argv)
    sys.path[:0] = [a.root, str(Path(a.root) / "benchmarks")]      # that tree's bench_families puts its root first
    import shapely

    import bench_families
    import vectortighten
    from vectortighten import morphology
    from vectortighten.offsets import exact_offsets

    if not vectortighten.__file__.startswith(str(Path(a.root).resolve())):
        raise SystemExit(f"imported {vectortighten.__file__}, not from {a.root}")

    for case in a.cases:
        fam, n, reps = case.split(":")
        make, r = bench_families.ALL_FAMILIES[SHORT.get(fam, fam)]
        S = morphology._orient(shapely.normalize(make(int(n))))
        floor, times = [], []
        for _ in range(int(reps)):
            t0 = time.process_time()
            S.buffer(-r).buffer(r), S.buffer(r).buffer(-r)
            floor.append(time.process_time() - t0)
            t0 = time.process_time()
            if a.profile:
                pr = cProfile.Profile(time.process_time)
                pr.enable()
            E = [exact_offsets(S, r, s) for s in (1, -1)]
            if a.profile:
                pr.disable()
            times.append(time.process_time() - t0)
        pieces = sum(len(e.seg) + len(e.arc_center) for e in E)
        fl, t = statistics.median(floor), statistics.median(times)
        print(f"{fam}:{n} r={r} floor {fl:.3f} s  exact_offsets {t:.3f} s  ratio {t / fl:.1f}  "
              f"pieces {pieces}  times {[round(x, 3) for x in times]}", flush=True)
        if a.profile:
            pstats.Stats(pr).sort_stats("cumulative").print_stats(30)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
