"""Near-tangent passages at random placements, judged by the independent oracle (issue 25).

The test suite checks gaps, necks, slots and corner passages 2r·(1 ± eps) wide at a few fixed
placements (`tests.exactness_cases`). Rounding depends on where a shape lies, so this script draws
random ones: an angle in [0°, 90°), an offset of magnitude 10^U(0, 5), each kind of `tests.shapes_dense`
(`gap_pair`, `neck`, `slot`, `corner_gap` against a corner, a wall and a 2r bar, `bar`), each eps of
``--eps`` that is resolvable there (`exactness_cases._resolvable`), both inits, default settings. A case
is bad when `tighten` raises, says ``converged=False``, enters the open core or anticore by more than
1e-9·r (`tests/oracle.py`), misses a piece of the shrink or covers one of the anticore's centres, gets
the case's exact decision wrong (gap open or closed, neck kept or cut, ...), or when `verify()` is not
clean exactly when the oracle finds the result exact.

    python benchmarks/passages_scan.py --seed 0 --placements 40
    python benchmarks/passages_scan.py --seed 3 --placements 100 --eps 1e-6,-1e-6,1e-4,-1e-4

Prints each bad case (kind, eps, init, angle, offset: enough to rebuild it) and a count; exits 1 if any.
A placement it finds goes into `tests.exactness_cases` as a regression case.
"""

from __future__ import annotations

import argparse
import math
import random
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def _cases(kind: str, eps: float, angle: float, off, r: float = 1.0):
    """The `Case` of one passage (the exact decision as `tests.exactness_cases._tie_cases` states it)."""
    from tests import exactness_cases as ec
    from tests import shapes_dense as sd

    tag = f"{kind} 2r(1{eps:+g}) a{angle:.6g}@{off[0]:.17g},{off[1]:.17g}"
    centre = ec._rot((0.0, 0.0), angle, off)
    if kind == "gap":
        mk = lambda: sd.gap_pair(r, eps, angle, off)                        # noqa: E731
        return ec.Case(tag, mk, r, outside=(centre,) if eps >= 0 else (), kind="gap")
    if kind == "neck":
        mk = lambda: sd.neck(r, eps, angle, off)                            # noqa: E731
        if eps >= 0:
            return ec.Case(tag, mk, r, inside=(centre,), kind="neck")
        return ec.Case(tag, mk, r, outside=(centre,), inits=("core",), kind="neck")
    if kind == "slot":
        mk = lambda: sd.slot(r, eps, angle, off)                            # noqa: E731
        deep = ec._rot((0.0, 2.0), angle, off)
        # exactly 2r (eps = 0) an r-disk passes, as for a gap: the closed shrink of ¬S reaches in
        return ec.Case(tag, mk, r, **({"outside": (deep,)} if eps >= 0 else {"inside": (deep,)}), kind="slot")
    if kind == "bar":
        mk = lambda: sd.bar(3.0, eps, angle, off)                           # noqa: E731
        if eps >= 0:
            return ec.Case(tag, mk, 3.0, inside=(centre,), kind="bar")
        return ec.Case(tag, mk, 3.0, empty=True, kind="bar")
    against = kind.split()[0]
    mk = lambda: sd.corner_gap(r, eps, against, angle, off)                 # noqa: E731
    return ec.Case(tag, mk, r, outside=(centre,), kind="corner gap")


KINDS = ("gap", "neck", "slot", "bar", "corner gap", "wall gap", "bar gap")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--placements", type=int, default=40)
    ap.add_argument("--eps", default="1e-6,-1e-6,1e-3,-1e-3,1e-9,-1e-9")
    ap.add_argument("--kinds", default=",".join(KINDS))
    args = ap.parse_args(argv)

    from tests import exactness_cases as ec

    rng = random.Random(args.seed)
    eps_list = [float(e) for e in args.eps.split(",")]
    kinds = args.kinds.split(",")
    n = bad = 0
    for _ in range(args.placements):
        angle = rng.uniform(0.0, 90.0)
        mag = 10.0 ** rng.uniform(0.0, 5.0)
        off = (rng.choice((-1.0, 1.0)) * mag * rng.random(), rng.choice((-1.0, 1.0)) * mag)
        for kind in kinds:
            for eps in eps_list:
                case = _cases(kind, eps, angle, off)
                if not ec._resolvable(eps, case.r, off):
                    continue
                for init in ("core", "input"):
                    n += 1
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        T, J, problems, _ = ec.evaluate(case, init)
                    why = []
                    if T is None:
                        why.append(f"raised {type(J).__name__}: {str(J)[:120]}")
                    else:
                        if not T.converged:
                            why.append("converged=False")
                        if J.worst > 1e-9:
                            why.append(f"enters by {J.worst:.3g}·r")
                        if J.core_missing or J.anticore_covered:
                            why.append(f"missing {J.core_missing}, covered {J.anticore_covered}")
                        why += ec.decision_errors(case, init, T)
                        if bool(problems) != (J.worst > 1e-9):
                            why.append(f"verify: {problems[:2] if problems else 'clean'}")
                    if why:
                        bad += 1
                        print(f"BAD {case.id} init={init}: {'; '.join(why)}", flush=True)
    print(f"seed {args.seed}: {n} cases, {bad} bad")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
