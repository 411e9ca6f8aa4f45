"""Random fuzzing of ``tighten`` through the API, counted (issue 23's target): silent wrong results,
undocumented exceptions, unbounded runs.

Shapes are drawn from the Hypothesis strategies of the test suite (``tests/strategies.py``: spikes,
near-degenerate rings, stars / box unions / holed squares offset and scaled), with a radius relative to
the shape's size (tiny, ordinary, huge) and a random ``init``; no shrinking, every case is new. One case
is bad if

* ``tighten`` or ``verify`` raises anything but a `TighteningError` (undocumented exception);
* the result says ``converged=True`` and ``verify()`` lists a problem, or ``converged=False`` comes
  without a `ConvergenceWarning` (silent wrong result);
* the case takes longer than ``--timeout`` seconds (unbounded run; stopped by SIGALRM).

Run (from the repository root):  python benchmarks/fuzz_api.py SEED SECONDS [--timeout 60] [--log FILE]
Bad cases are printed and, with ``--log``, appended as JSON lines (WKT, r, init) for regression tests.
Shapes come from ``.example()`` (fresh draws each batch), so a run is not reproducible from its seed;
the log is. Results: the fuzz campaign tables of ``results/hardening.md`` (calls, bad cases by kind,
what each found and its fix, the commit fuzzed).
"""

import argparse
import json
import random
import signal
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("seed", type=int)
    parser.add_argument("seconds", type=float)
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--log", type=Path)
    args = parser.parse_args()

    from hypothesis import strategies as st
    from hypothesis.errors import NonInteractiveExampleWarning

    import vectortighten as vt
    from tests import strategies as vst

    warnings.simplefilter("ignore", NonInteractiveExampleWarning)
    families = {
        "spiked": vst.spiked(),
        "near_degenerate": vst.near_degenerate(),
        "placed": vst.placed(st.one_of(vst.stars(), vst.box_unions(), vst.holed())),
    }
    rel = vst.relative_radius()
    rng = random.Random(args.seed)
    signal.signal(signal.SIGALRM, _alarm)
    counts = {"calls": 0, "documented_error": 0, "not_converged": 0, "clean": 0,
              "silent_wrong": 0, "undocumented": 0, "unbounded": 0}
    slowest = (0.0, None)
    t_end = time.time() + args.seconds
    while time.time() < t_end:
        family = rng.choice(sorted(families))
        S = families[family].example()
        x0, y0, x1, y1 = S.bounds
        size = max(x1 - x0, y1 - y0)
        r = rel.example() * size
        init = rng.choice(["core", "input", "mason"])
        verdict, detail = "clean", ""
        t0 = time.time()
        signal.setitimer(signal.ITIMER_REAL, args.timeout)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    T = vt.tighten(S, r, init=init)
                except vt.TighteningError:
                    verdict = "documented_error"
                else:
                    warned = any(issubclass(w.category, vt.ConvergenceWarning) for w in caught)
                    if T.converged:
                        problems = T.verify()
                        if problems:
                            verdict, detail = "silent_wrong", "; ".join(problems)[:300]
                    elif not warned:
                        verdict, detail = "silent_wrong", "converged=False without a ConvergenceWarning"
                    else:
                        verdict = "not_converged"
        except _Timeout:
            verdict, detail = "unbounded", f"over {args.timeout:g} s"
        except Exception as exc:                                   # noqa: BLE001 — that is the point
            verdict, detail = "undocumented", f"{type(exc).__name__}: {str(exc)[:200]}"
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        dt = time.time() - t0
        if dt > slowest[0]:
            slowest = (dt, (family, r / size, init))
        counts["calls"] += 1
        counts[verdict] += 1
        if verdict in ("silent_wrong", "undocumented", "unbounded"):
            case = {"verdict": verdict, "detail": detail, "family": family, "r": r, "rel": r / size,
                    "init": init, "wkt": S.wkt}
            print("BAD", json.dumps(case)[:600], flush=True)
            if args.log:
                with args.log.open("a") as f:
                    f.write(json.dumps(case) + "\n")
    print(json.dumps(counts), "slowest %.1f s" % slowest[0], slowest[1], flush=True)


if __name__ == "__main__":
    main()
