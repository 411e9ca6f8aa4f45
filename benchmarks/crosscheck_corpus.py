"""Issue 21 item 5: the cross-check (exact engine against the pixel flow) over a fresh corpus of real shapes.

The corpus was fixed before any result was seen (`CHOSEN`, committed first): 32 shapes from
`benchmarks/corpus.py` — glyphs of all five fonts matplotlib ships there, toolbar icons, traced contours,
country outlines, segmentation masks and CAD parts. Each is cross-checked at two radii, with both inits
("core", "input"), with `vectortighten.crosscheck`'s defaults only (pixel size r/20, supersample 7, the
converged flow and the minimum-perimeter finish).

Radii (also fixed in advance): r = max(f·w, D/25) for f in (0.25, 0.5), where w is the stroke width
(``2·area/perimeter``) and D the larger side of the shape's bounds. The floor D/25 keeps the grid near
500 px across at r/20 (a coastline's stroke width is tiny against its extent). The first rule, f in
(0.5, 1.0), was changed before the run: one trial case (DejaVu Sans Bold 'a') showed that r = w empties
every stroke (a disk of radius w/2 just fits one), so both sides are empty and agree trivially.

Every case is written as one JSON line to ``benchmarks/results/crosscheck_corpus.jsonl`` as soon as it is
done; with ``--explain`` each case that does not agree (equal topology, ≤ 2 px) also gets
`CrossCheck.explain` (it tightens the mask exactly and S perturbed by ±half a diagonal of a fine pixel).

    python benchmarks/crosscheck_corpus.py [--explain] [--only SUBSTRING] [--shapes A:B] [--out FILE]
    python benchmarks/crosscheck_corpus.py --summarise FILE [FILE ...]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

#: (family, name) of each shape, chosen before looking at any result.
CHOSEN = [
    ("glyph", "DejaVu Sans Bold 'a'"), ("glyph", "DejaVu Sans Bold '&'"), ("glyph", "DejaVu Sans Bold '8'"),
    ("glyph", "DejaVu Serif 'g'"), ("glyph", "DejaVu Serif 'R'"),
    ("glyph", "DejaVu Sans Mono 'B'"), ("glyph", "DejaVu Sans Mono '#'"),
    ("glyph", "STIX General Italic 'f'"), ("glyph", "STIX General Italic 'S'"),
    ("glyph", "Computer Modern Roman 'M'"), ("glyph", "Computer Modern Roman 'w'"),
    ("icon", "home"), ("icon", "help"), ("icon", "filesave"), ("icon", "move"), ("icon", "zoom_to_rect"),
    ("icon", "back"),
    ("contour", "topobathy coast, marching squares ×4"), ("contour", "jacksboro DEM, 60th-percentile contour ×3"),
    ("country", "Norway"), ("country", "Greece"), ("country", "Japan"), ("country", "Italy"),
    ("country", "Madagascar"),
    ("mask", "Grace Hopper, dark regions"), ("mask", "MRI slice, tissue"), ("mask", "matplotlib logo"),
    ("mask", "present box (alpha)"),
    ("cad", "plate with holes, slot and notch"), ("cad", "spur gear, 24 teeth"), ("cad", "angle bracket"),
    ("cad", "flange, six bolt holes"),
]
FRACTIONS = (0.25, 0.5)
FLOOR = 25.0
INITS = ("core", "input")


def radii(case) -> list[float]:
    x0, y0, x1, y1 = case.shape.bounds
    D = max(x1 - x0, y1 - y0)
    return [max(f * case.width, D / FLOOR) for f in FRACTIONS]


def summarise(rows: list[dict]) -> str:
    """The counts (runs, distinct cases, how many agree) and a Markdown table of the cases that do not."""
    runs = len(rows)
    distinct = {}
    for d in rows:
        distinct.setdefault((d["name"], round(d["r"], 9), d["init"]), d)
    cases = list(distinct.values())
    agree = sum(bool(d.get("agree")) for d in cases)
    errors = [d for d in cases if "error" in d]
    rested = sum(bool(d.get("converged")) for d in cases)
    out = [f"{runs} runs, {len(cases)} distinct cases; **{agree} of {len(cases)} "
           f"({100 * agree / max(len(cases), 1):.1f} %) within 2 px with equal topology**; "
           f"flow rested in {rested}; errors: {len(errors)}", "",
           "| shape | r | init | Hausdorff (px) | exact (comp, holes) | pixel (comp, holes) | explain() verdicts |",
           "|---|---:|---|---:|---|---|---|"]
    for d in cases:
        if d.get("agree"):
            continue
        kinds = {}
        for k in d.get("verdicts", []):
            kinds[k] = kinds.get(k, 0) + 1
        verdicts = ", ".join(f"{n}× {k}" for k, n in kinds.items()) or d.get("error", "not explained")
        out.append(f"| {d['family']} {d['name']} | {d['r']:.4g} | {d['init']} | {d.get('hausdorff_px', float('nan')):.2f} "
                   f"| {tuple(d.get('vector_topology', ()))} | {tuple(d.get('raster_topology', ()))} | {verdicts} |")
    return "\n".join(out)


def main(argv=None) -> int:
    import corpus

    import vectortighten as vt

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=HERE / "results" / "crosscheck_corpus.jsonl")
    p.add_argument("--explain", action="store_true")
    p.add_argument("--only", default=None, help="run the cases whose name contains this")
    p.add_argument("--inits", default=",".join(INITS))
    p.add_argument("--radius-index", type=int, default=None, help="only the radius of this index")
    p.add_argument("--shapes", default=None, metavar="A:B",
                   help="only the shapes CHOSEN[A:B] (to run the corpus in chunks, e.g. 0:16 and 16:32)")
    p.add_argument("--failed-in", type=Path, default=None,
                   help="run only the cases that did not agree in this JSON-lines file (with --explain)")
    p.add_argument("--summarise", type=Path, nargs="+", default=None, metavar="JSONL",
                   help="print the counts and the table of disagreements of these result files, and stop")
    args = p.parse_args(argv)
    if args.summarise:
        print(summarise([json.loads(line) for f in args.summarise for line in f.open() if line.strip()]))
        return 0
    todo = None
    if args.failed_in is not None:
        done = set()
        if args.out.exists():
            done = {(d["name"], round(d["r"], 9), d["init"]) for d in map(json.loads, args.out.open())}
        todo = {(d["name"], round(d["r"], 9), d["init"]) for d in map(json.loads, args.failed_in.open())
                if not d.get("agree", False)} - done
    by_key = {(c.family, c.name): c for c in corpus.cases(sorted({f for f, _ in CHOSEN}))}
    missing = [k for k in CHOSEN if k not in by_key]
    if missing:
        print(f"missing from the corpus: {missing}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    chosen = CHOSEN
    if args.shapes is not None:
        a, _, b = args.shapes.partition(":")
        chosen = CHOSEN[int(a) if a else 0:int(b) if b else len(CHOSEN)]
    seen = {}
    with args.out.open("a") as out:
        for key in chosen:
            case = by_key[key]
            if args.only and args.only not in case.name:
                continue
            for ri, r in enumerate(radii(case)):
                if args.radius_index is not None and ri != args.radius_index:
                    continue
                for init in args.inits.split(","):
                    if todo is not None and (case.name, round(r, 9), init) not in todo:
                        continue
                    if todo is not None:
                        todo.discard((case.name, round(r, 9), init))   # a radius repeated by the floor: once
                    key = (case.name, round(r, 9), init)
                    if key in seen:
                        # The floor made both radii equal: the same computation, written once more.
                        row = dict(seen[key], r_index=ri, repeat_of_r_index=seen[key]["r_index"], seconds=0.0)
                        out.write(json.dumps(row) + "\n")
                        out.flush()
                        continue
                    t0 = time.perf_counter()
                    row = {"family": case.family, "name": case.name, "r": r, "r_index": ri, "init": init}
                    try:
                        with warnings.catch_warnings(record=True) as caught:
                            warnings.simplefilter("always")
                            C = vt.crosscheck(case.shape, r, pixel_size=r / 20)
                            row.update(supersample=C.supersample, hausdorff_px=C.hausdorff_px, vector_topology=list(C.vector_topology),
                                       raster_topology=list(C.raster_topology), agree=C.agree,
                                       converged=bool(C.raster.is_converged), grid=list(C.grid.shape),
                                       sym_share=C.symmetric_difference_share,
                                       warnings=sorted({type(w.message).__name__ for w in caught}))
                            if args.explain and not C.agree:
                                ex = C.explain()
                                row["verdicts"] = [d.kind for d in ex]
                                row["explain"] = C.explain_text(ex)
                    except Exception as exc:  # noqa: BLE001 - a benchmark records the failure and goes on
                        row["error"] = f"{type(exc).__name__}: {exc}"
                    row["seconds"] = time.perf_counter() - t0
                    seen[key] = row
                    out.write(json.dumps(row) + "\n")
                    out.flush()
                    print(json.dumps({k: v for k, v in row.items() if k != "explain"}), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
