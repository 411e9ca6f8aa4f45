"""Random fuzzing of the public morphology (`vt.core`, `fillet`, `shrink`, `grow`, `mortar`, `pockets`,
`mason`), counted.

Shapes and radii come from the test suite's Hypothesis strategies (``tests/strategies.py``: stars, box
and disk unions, holed squares, spikes, near-degenerate rings, offsets and scales; ``radii_for``), drawn
fresh with ``.example()`` until the time is up. A case is bad if a function raises, a result is not
valid, ``core ⊆ S ⊆ fillet`` fails (by overlay, or by ``covers`` where S's rings are apart by more than
1e-9 of its size), ``core ⊆ mason ⊆ fillet`` fails by ``covers``, or a vertex of the shrink or the grow
is not at distance r from ∂S to 1e-9 of S's size. Also counted: the calls where the exact construction
was not available and GEOS's buffers were used (`morphology._sampled` returning None).

Run (from the repository root):  python benchmarks/fuzz_morphology.py SECONDS [--src TREE] [--show 4]
``--src`` imports ``vectortighten`` from another source tree (a commit exported with ``git archive``),
for the same campaign on an older version. Results: the closing notes and ``results/hardening.md``.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("seconds", type=float)
    ap.add_argument("--src", default=str(ROOT), help="source tree to import vectortighten from")
    ap.add_argument("--show", type=int, default=4, help="bad cases to print (reason, r, WKT head)")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))                      # the strategies always come from this tree
    sys.path.insert(0, a.src)
    warnings.simplefilter("ignore")

    import numpy as np
    import shapely
    from hypothesis import strategies as st

    import vectortighten as vt
    from vectortighten import morphology as m
    from tests import strategies as T
    from tests.test_morphology import rings_apart

    fallbacks = 0
    sampled = getattr(m, "_sampled", None)
    if sampled is not None:
        def counted(*args, **kwargs):
            nonlocal fallbacks
            g = sampled(*args, **kwargs)
            fallbacks += g is None
            return g
        m._sampled = counted

    draw = T.shapes.flatmap(lambda S: st.tuples(st.just(S), T.radii_for(S)))
    t0, n, bad = time.time(), 0, []
    while time.time() - t0 < a.seconds:
        S, r = draw.example()
        n += 1
        why = []
        try:
            Sc = vt._validation.check_shape(S)
            R, F, E, G = vt.core(S, r), vt.fillet(S, r), vt.shrink(S, r), vt.grow(S, r)
            M, Ma = vt.mortar(S, r), vt.mason(S, r)
            vt.pockets(S, r)
            why += [f"{k} invalid" for k, g in (("core", R), ("fillet", F), ("shrink", E), ("grow", G),
                                                 ("mortar", M), ("mason", Ma)) if not g.is_valid]
            if not (R.difference(Sc).is_empty and Sc.difference(F).is_empty):
                why.append("core ⊆ S ⊆ fillet (overlay)")
            size = max(Sc.bounds[2] - Sc.bounds[0], Sc.bounds[3] - Sc.bounds[1])
            if rings_apart(Sc, 1e-9 * size):
                if not ((R.is_empty or Sc.covers(R)) and F.covers(Sc)):
                    why.append("core ⊆ S ⊆ fillet (covers)")
                if not (Ma.is_empty or (F.covers(Ma) and (R.is_empty or Ma.covers(R)))):
                    why.append("core ⊆ mason ⊆ fillet (covers)")
            for k, g in (("shrink", E), ("grow", G)):
                xy = shapely.get_coordinates(g)
                if len(xy) and np.abs(shapely.distance(Sc.boundary, shapely.points(xy)) - r).max() > 1e-9 * size:
                    why.append(f"{k} vertex off distance r")
        except Exception as ex:                        # noqa: BLE001 (counted, not hidden)
            why.append(f"raised {type(ex).__name__}")
        if why:
            bad.append((why, r, S.wkt))
    print(f"vectortighten from {vt.__file__}")
    print(f"cases {n}, GEOS fallbacks {fallbacks}, bad {len(bad)}")
    for reason, k in Counter(w for b in bad for w in b[0]).most_common():
        print(f"  {k:5d}  {reason}")
    for why, r, wkt in bad[:a.show]:
        print(why, r, wkt[:300])


if __name__ == "__main__":
    main()
