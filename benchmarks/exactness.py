"""Exactness of `vt.tighten` judged by the independent oracle (tests/oracle.py): issues 24, 25, 26.

Runs the oracle over the real shapes of `benchmarks/corpus.py` at five radii each (fractions of the
stroke width) and over the dense generators of `tests/shapes_dense.py` (`tests.exactness_cases`), both
inits, default settings. Per case: penetration into the open core and anticore in units of r, whether
T holds the shrink's components and avoids the anticore's centres, the converged flag, whether
``verify()`` is clean, and the time of the oracle against the time of `tighten` (both measured in this
run; the ratio is the figure to compare). Summary counts: exact (≤ 1e-9·r), entering, and
verify-silent-while-entering.

    python benchmarks/exactness.py                 # corpus + dense generators (bench scale), slow
    python benchmarks/exactness.py --ci            # the CI cases of tests/test_exactness.py only
    python benchmarks/exactness.py --families mask,contour --limit 3

Writes ``benchmarks/results/exactness.md`` (``exactness_ci.md`` with --ci).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

REL = 1e-9
FRACTIONS = (0.05, 0.1, 0.25, 0.5, 1.0)


def _corpus_cases(families, limit):
    import corpus

    from tests.exactness_cases import Case

    out = []
    for fam in families:
        if fam not in corpus.FAMILIES:
            continue
        try:
            got = corpus.FAMILIES[fam]()
        except Exception as exc:   # a family whose data or optional dependency is missing
            print(f"skipping family {fam}: {exc}", file=sys.stderr)
            continue
        for c in got[:limit]:
            for r in c.radii(FRACTIONS):
                out.append(Case(f"{c.family}: {c.name} r={r:.4g}", (lambda s=c.shape: s), float(r),
                                kind=c.family))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ci", action="store_true", help="only the CI cases of tests/test_exactness.py")
    ap.add_argument("--families", default="glyph,icon,contour,country,mask,cad")
    ap.add_argument("--limit", type=int, default=4, help="shapes per corpus family")
    ap.add_argument("--no-corpus", action="store_true")
    ap.add_argument("--dense", choices=("ci", "bench", "none"), default="bench",
                    help="scale of the dense generators (bench: 75k-vertex outlines, five radii)")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)

    from tests import exactness_cases as ec

    if args.ci:
        cases = ec.cases("ci")
    else:
        cases = [] if args.no_corpus else _corpus_cases(args.families.split(","), args.limit)
        if args.dense != "none":
            cases += [c for c in ec.cases(args.dense) if c.kind in ("admin", "contour", "pixel", "staircase")]
    rows, oracle_t, tighten_t = [], [], []
    counts = dict(exact=0, entering=0, silent=0, raised=0, decision=0)
    for case in cases:
        _write(args, rows, counts, oracle_t, tighten_t, partial=True)
        for init in ("core", "input"):
            T, J, problems, secs = ec.evaluate(case, init)
            if T is None:
                counts["raised"] += 1
                rows.append(f"| {case.id} | {init} | raised {type(J).__name__} | | | | | | {secs:.2f} | |")
                print(f"{case.id} | {init}: raised {J!r}", flush=True)
                continue
            dec = ec.decision_errors(case, init, T)
            entering = J.worst > REL
            counts["exact" if not entering else "entering"] += 1
            counts["silent"] += int(entering and not problems)
            counts["decision"] += int(bool(dec))
            oracle_t.append(J.seconds)
            tighten_t.append(secs)
            rows.append(f"| {case.id} | {init} | {J.core_penetration / case.r:.3g} | "
                        f"{J.anticore_penetration / case.r:.3g} | {J.core_missing}/{J.anticore_covered} | "
                        f"{T.converged} | {'clean' if not problems else 'reports'} | "
                        f"{'ok' if not dec else '; '.join(dec)} | {secs:.2f} | {J.seconds:.2f} |")
            print(f"{case.id} | {init}: core {J.core_penetration / case.r:.3g}·r anticore "
                  f"{J.anticore_penetration / case.r:.3g}·r missing/covered {J.core_missing}/"
                  f"{J.anticore_covered} verify {'clean' if not problems else problems[0][:60]} "
                  f"decision {dec or 'ok'} ({secs:.2f} s, oracle {J.seconds:.2f} s)", flush=True)
    out = _write(args, rows, counts, oracle_t, tighten_t, partial=False)
    print(next(x for x in out.read_text().splitlines() if " results: " in x))
    print(f"wrote {out}")


def _write(args, rows, counts, oracle_t, tighten_t, partial):
    n = sum(counts[k] for k in ("exact", "entering", "raised"))
    ratio = statistics.median(o / t for o, t in zip(oracle_t, tighten_t) if t > 0) if oracle_t else float("nan")
    lines = [
        "# Exactness of tighten, judged by the independent oracle (issues 24, 25, 26)",
        "",
        f"Command: `python benchmarks/exactness.py {' '.join(sys.argv[1:])}`; "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}.",
        "Penetrations are in units of r (into the open core / open anticore); *missing/covered* counts",
        "pieces of S↓r outside T / pieces of the anticore's centres inside T; times in seconds.",
        "" if not partial else "**Partial: the run was still going when this was written.**",
        "",
        f"**{n} results: {counts['exact']} exact (≤ 1e-9·r), {counts['entering']} entering, "
        f"{counts['silent']} of them with `verify()` silent; {counts['raised']} raised; "
        f"{counts['decision']} with a wrong exact decision.**",
        "",
        f"Oracle time / tighten time: median {ratio:.3g} (over {len(oracle_t)} results); "
        f"total oracle {sum(oracle_t):.1f} s, tighten {sum(tighten_t):.1f} s.",
        "",
        "| case | init | core ·r | anticore ·r | missing/covered | converged | verify | decision | tighten s | oracle s |",
        "|---|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
    ]
    out = Path(args.out) if args.out else ROOT / "benchmarks" / "results" / \
        ("exactness_ci.md" if args.ci else "exactness.md")
    out.write_text("\n".join(lines))
    return out


if __name__ == "__main__":
    main()
