"""Two source trees on the same shapes: CPU time of ``tighten`` on `bench_families`' families, alternating.

Each (family, size) runs in a fresh process per tree, the trees one after the other, so that both see the
same load; each process builds the shape, tightens it ``repeats`` times (tolerance 1e-5·r, as
`bench_families`) and prints the median CPU time and the result's area (the two areas must agree to
1e-12, relative: the sum of the same pieces in another order differs in its last digits).

Run:  python benchmarks/ab_families.py BEFORE_ROOT AFTER_ROOT [FAMILY:N:REPEATS ...]
      (a root is a checkout, e.g. ``git archive <commit> | tar -x -C /tmp/before``)
"""

import json
import statistics
import subprocess
import sys
import time

DEFAULT = ["jagged star:1000:3", "harmonic star:1000:3", "traced outline:1000:3", "coastline:1000:3",
           "many parts:1000:3", "many parts:10000:1"]


def child(root: str, family: str, n: int, repeats: int) -> dict:
    sys.path[:0] = [root, root + "/benchmarks"]
    import bench_families
    import vectortighten as vt

    if not vt.__file__.startswith(root):
        raise SystemExit(f"imported {vt.__file__}, not from {root}")
    make, r = getattr(bench_families, "ALL_FAMILIES", bench_families.FAMILIES)[family]   # an older tree has only FAMILIES
    S = make(n)
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        T = vt.tighten(S, r, tolerance=1e-5 * r)
        times.append(time.process_time() - t0)
    return {"median": statistics.median(times), "times": times, "area": T.area}


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--child":
        print(json.dumps(child(argv[1], argv[2], int(argv[3]), int(argv[4]))), flush=True)
        return 0
    if len(argv) < 2:
        print(__doc__)
        return 2
    before, after, specs = argv[0], argv[1], argv[2:] or DEFAULT
    print("| family | vertices | before (s) | after (s) | after / before | same area |")
    print("|---|---:|---:|---:|---:|---|")
    for spec in specs:
        family, n, repeats = spec.rsplit(":", 2)
        got = []
        for root in (before, after):
            out = subprocess.run([sys.executable, __file__, "--child", root, family, n, repeats],
                                 capture_output=True, text=True, check=True)
            got.append(json.loads(out.stdout.strip().splitlines()[-1]))
        a, b = got
        print(f"| {family} | {n} | {a['median']:.3f} | {b['median']:.3f} | {b['median'] / a['median']:.2f} "
              f"| {'yes' if abs(a['area'] - b['area']) <= 1e-12 * abs(a['area']) else 'NO'} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
