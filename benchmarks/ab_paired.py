"""Two source trees in one process, timed shape by shape in alternation: a paired A/B that load on a shared
machine disturbs much less than separate processes do.

Both trees' ``vectortighten`` are imported (each under its own set of ``sys.modules`` entries, swapped in
before each call, so that imports made inside functions resolve to the same tree); each shape is timed
with A then B, or B then A, alternately, ``--repeats`` times; the totals give B / A.

Modes: ``tighten`` (the footprints of `bench_geo.footprints(300, seed=3)` that B's general engine takes,
r = 1), ``offsets`` (`offsets.exact_offsets` of those, both sides), ``corpus`` (the real shapes of
`corpus.cases()` up to 30k vertices that B's general engine takes, at half and at the whole of their width,
tolerance 1e-5·r), ``families`` (`bench_families`' families
at ``--size`` vertices, 1000 unless told, their r, tolerance 1e-5·r; ``--families`` picks any of
``ALL_FAMILIES``), ``famoffsets`` (their exact offsets, both sides).

Run:  python benchmarks/ab_paired.py BEFORE_ROOT AFTER_ROOT [tighten|offsets|families|famoffsets|corpus]
      [--repeats 5] [--size 1000] [--families NAME ...]
"""

import argparse
import importlib
import statistics
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
_MODS: dict[str, dict] = {}


def _load(root: str):
    _drop()
    sys.path.insert(0, root)
    vt = importlib.import_module("vectortighten")
    off = importlib.import_module("vectortighten.offsets")
    morph = importlib.import_module("vectortighten.morphology")
    sys.path.remove(root)
    _MODS[root] = {k: v for k, v in sys.modules.items()
                   if k == "vectortighten" or k.startswith("vectortighten.")}
    return vt, off, morph


def _drop() -> None:
    for k in [k for k in sys.modules if k == "vectortighten" or k.startswith("vectortighten.")]:
        del sys.modules[k]


def _use(root: str) -> None:
    _drop()
    sys.modules.update(_MODS[root])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("mode", nargs="?", default="tighten",
                    choices=["tighten", "offsets", "families", "famoffsets", "corpus"])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--size", type=int, default=1000, help="vertices of each family's shape (families modes)")
    ap.add_argument("--families", nargs="+", default=None,
                    help="families to time (default: the five of bench_families.FAMILIES)")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    trees = {args.a: _load(args.a), args.b: _load(args.b)}
    sys.path.insert(0, str(HERE))
    import bench_families
    import bench_geo
    import shapely

    _use(args.b)
    vt_b = trees[args.b][0]
    if args.mode in ("families", "famoffsets"):
        names = args.families or list(bench_families.FAMILIES)
        cases = [(make(args.size), r) for make, r in (bench_families.ALL_FAMILIES[k] for k in names)]
    elif args.mode == "corpus":
        import corpus
        names, cases = [], []
        for c in corpus.cases():
            for f in (0.5, 1.0):
                if c.n_vertices <= 30000 and vt_b.tighten(c.shape, f * c.width)._cache["_path"] == "general":
                    names.append(f"{c.family}/{c.name}@{f}")
                    cases.append((c.shape, f * c.width))
    else:
        fps = bench_geo.footprints(300, seed=3)
        cases = [(g, 1.0) for g in fps if vt_b.tighten(g, 1.0)._cache["_path"] == "general"]
        names = None

    def run(root, S, r):
        vt, off, morph = trees[root]
        _use(root)
        clock = time.process_time
        if args.mode in ("offsets", "famoffsets"):
            S = morph._orient(shapely.normalize(S))
            t0 = clock()
            off.exact_offsets(S, r, 1)
            off.exact_offsets(S, r, -1)
            return clock() - t0
        tol = 1e-5 * r if args.mode in ("families", "corpus") else None
        t0 = clock()
        vt.tighten(S, r, tolerance=tol)
        return clock() - t0

    ta, tb = [0.0] * len(cases), [0.0] * len(cases)
    for rep in range(args.repeats):
        for i, (S, r) in enumerate(cases):
            if (rep + i) % 2:
                ta[i] += run(args.a, S, r)
                tb[i] += run(args.b, S, r)
            else:
                tb[i] += run(args.b, S, r)
                ta[i] += run(args.a, S, r)
    n = len(cases) * args.repeats
    print(f"{args.mode}: {len(cases)} shapes x {args.repeats}: A {sum(ta) / n * 1e3:.2f} ms, "
          f"B {sum(tb) / n * 1e3:.2f} ms a shape; B / A {sum(tb) / sum(ta):.3f} "
          f"(median over shapes {statistics.median(b / a for a, b in zip(ta, tb)):.3f})")
    if names:
        for name, a, b in zip(names, ta, tb):
            print(f"  {name}: A {a / args.repeats * 1e3:.1f} ms, B {b / args.repeats * 1e3:.1f} ms, "
                  f"B / A {b / a:.3f}")


if __name__ == "__main__":
    main()
