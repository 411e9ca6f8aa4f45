"""Two radii on the fast path: the one-radius fast path of this checkout against a baseline copy of
`vectortighten/_fast.py` (e.g. main's), and ``tighten(S, (a, b))`` against ``tighten(S, r)``, interleaved
in one process so that the load of a shared machine falls on all alike.

The baseline is one file: ``git -C /work/main show main:vectortighten/_fast.py > /tmp/fast_main.py``.
Each round times, on each shape, the baseline's ``fast_disk_loops(S, r)``, this checkout's, and the whole
``tighten`` with one radius and with two; prints the medians, the median of the per-round ratios, and
whether the baseline and this checkout give bit-identical disk loops for one radius.

    python benchmarks/bench_two_radii.py /tmp/fast_main.py [--rounds N]
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _shapes():
    import math

    import numpy as np
    from shapely.geometry import Polygon

    def wavy(n, size=100.0):
        t = np.linspace(0, 2 * math.pi, n, endpoint=False)
        rad = size * (1 + 0.1 * np.sin(7 * t))
        return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))

    def comb(teeth):
        from shapely import union_all
        from shapely.geometry import box

        return union_all([box(0, 0, 20 * teeth, 10)] + [box(20 * k, 9, 20 * k + 8, 30) for k in range(teeth)])

    return {"wavy star 20k (r=2, (1, 3))": (wavy(20_000), 2.0, (1.0, 3.0)),
            "comb 200 teeth (r=2, (0, 3))": (comb(200), 2.0, (0.0, 3.0))}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("baseline", type=Path, help="a copy of another checkout's vectortighten/_fast.py")
    p.add_argument("--rounds", type=int, default=7)
    args = p.parse_args(argv)
    sys.path.insert(0, str(HERE.parent))
    import numpy as np

    import vectortighten as vt
    from vectortighten import _fast
    from vectortighten.engine import _Frame
    from vectortighten.offsets import precision_of

    spec = importlib.util.spec_from_file_location("vectortighten._fast_baseline", args.baseline)
    base = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = base
    spec.loader.exec_module(base)
    med = statistics.median
    for name, (S, r, pair) in _shapes().items():
        S = vt.tighten(S, r).shape                        # validated and oriented, as the engine has it
        frame = _Frame.of(S)
        SL, rl, prec = frame.to_local(S), r / frame.scale, precision_of(S) / frame.scale
        x, y = base.fast_disk_loops(SL, rl, 8, "core", prec), _fast.fast_disk_loops(SL, rl, 8, "core", prec)
        same = x is not None and y is not None and all(
            all(np.array_equal(u, v) for u, v in zip(p_, q_)) for p_, q_ in zip(x, y))
        T2 = vt.tighten(S, pair)
        times = {k: [] for k in ("baseline fast", "this fast", "tighten r", "tighten (a, b)")}
        for _ in range(args.rounds):
            for key, run in (("baseline fast", lambda: base.fast_disk_loops(SL, rl, 8, "core", prec)),
                             ("this fast", lambda: _fast.fast_disk_loops(SL, rl, 8, "core", prec)),
                             ("tighten r", lambda: vt.tighten(S, r)),
                             ("tighten (a, b)", lambda: vt.tighten(S, pair))):
                t0 = time.perf_counter()
                run()
                times[key].append(time.perf_counter() - t0)
        ratio = lambda k1, k2: med([b_ / a_ for a_, b_ in zip(times[k1], times[k2])])  # noqa: E731
        print(f"{name}: {len(S.exterior.coords) - 1} vertices, rounds {args.rounds}; one radius bit-identical "
              f"to the baseline: {same}; two radii path {T2._cache['_path']}, verify {T2.verify() or 'ok'}")
        for k, v in times.items():
            print(f"  {k:15s} median {med(v):.4f} s")
        print(f"  this fast / baseline fast: {ratio('baseline fast', 'this fast'):.3f}; "
              f"tighten (a, b) / tighten r: {ratio('tighten r', 'tighten (a, b)'):.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
