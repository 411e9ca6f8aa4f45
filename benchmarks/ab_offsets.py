"""Two source trees, `exact_offsets` alone (both sides) on dense outlines: CPU time in alternating processes.

For each case ``FAMILY:N``, ``rounds`` times: a fresh process for the BEFORE tree, then one for the AFTER
tree, each timing `exact_offsets(S, r, +1)` and `(S, r, −1)` once (`time_offsets.py`, which also times
shapely's opening + closing in the same process); the table gives the medians over the rounds.

Run:  python benchmarks/ab_offsets.py BEFORE_ROOT AFTER_ROOT [FAMILY:N ...] [--rounds 3]
      (a root is a checkout, e.g. ``git archive <commit> | tar -x -C /tmp/before``; families as in
      `time_offsets.py`: traced, harmonic, jagged, coastline, parts, two)
"""

import argparse
import re
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def one(root: str, case: str) -> tuple[float, float, int]:
    out = subprocess.run([sys.executable, str(HERE / "time_offsets.py"), f"{case}:1", "--root", root],
                         capture_output=True, text=True, check=True).stdout
    m = re.search(r"floor ([\d.]+) s\s+exact_offsets ([\d.]+) s.*pieces (\d+)", out)
    return float(m.group(1)), float(m.group(2)), int(m.group(3))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("cases", nargs="*", default=["traced:10000", "traced:100000", "harmonic:100000"])
    p.add_argument("--rounds", type=int, default=3)
    a = p.parse_args(argv)
    print("| case | opening + closing (s) | before (s) | after (s) | after / before | after / floor | pieces |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for case in a.cases:
        floor, tb, ta, pieces = [], [], [], set()
        for _ in range(a.rounds):
            for root, acc in ((a.before, tb), (a.after, ta)):
                f, t, n = one(root, case)
                floor.append(f)
                acc.append(t)
                pieces.add(n)
        fl, b, t = statistics.median(floor), statistics.median(tb), statistics.median(ta)
        same = "same count" if len(pieces) == 1 else f"DIFFER {sorted(pieces)}"
        print(f"| {case} | {fl:.3f} | {b:.3f} | {t:.3f} | {t / b:.3f} | {t / fl:.1f} | {same} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
