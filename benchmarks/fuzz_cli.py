"""Mutation fuzzing of the command line: every bad file must end in exit 2, one error line, nothing written.

Small valid SVG, WKT (plain and curved) and GeoJSON files (``--dxf``: a DXF) are mutated (characters
deleted, hostile tokens inserted: 1e308, nan, unbalanced brackets, 50-digit numbers; truncation) and
run through ``vectortighten tighten`` in-process with random r and init. A case is bad if it exits with
a code other than 0 or 2, or exits 2 with other than one error line or with an output written.

Run (in an empty scratch folder):  python benchmarks/fuzz_cli.py SEED SECONDS [--dxf]
Results: the fuzz campaign tables of ``results/hardening.md`` (cases, bad cases, what each found and its
fix, the commit fuzzed).
"""

import contextlib
import io
import os
import random
import sys
import time
import warnings


def run(seed: int, seconds: float, dxf: bool) -> None:
    from vectortighten.cli import main

    warnings.simplefilter("ignore")
    seeds = {
        "a.svg": ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">'
                  '<g transform="rotate(10) scale(2)"><rect x="10" y="10" width="30" height="20" rx="3"/>'
                  '<circle cx="50" cy="50" r="8"/>'
                  '<path d="M 5 5 L 40 5 A 10 10 0 0 1 40 25 Q 20 40 5 25 Z" fill-rule="evenodd"/>'
                  '</g></svg>'),
        "b.wkt": "MULTIPOLYGON (((0 0, 10 0, 10 10, 0 10, 0 0), (2 2, 4 2, 4 4, 2 4, 2 2)), "
                 "((20 0, 30 0, 25 8, 20 0)))",
        "c.geojson": ('{"type":"Polygon","coordinates":[[[0,0],[10,0],[10,10],[0,10],[0,0]],'
                      '[[2,2],[4,2],[4,4],[2,4],[2,2]]]}'),
        "d.wkt": "CURVEPOLYGON(COMPOUNDCURVE(CIRCULARSTRING(0 0,5 5,10 0),(10 0,0 0)))",
    }
    if dxf:
        import ezdxf

        d = ezdxf.new()
        m = d.modelspace()
        m.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
        m.add_circle((5, 5), 2)
        m.add_arc((20, 0), 3, 0, 180)
        m.add_line((17, 0), (23, 0))
        d.saveas("e.dxf")
        with open("e.dxf") as f:
            seeds = {"e.dxf": f.read()}
    rng = random.Random(seed)
    tokens = ["1e308", "-1e308", "nan", "inf", "0", "1e-300", "(", ")", ",", " ", "#", "<use/>", "9" * 50,
              "-", ".", "e", "]", "[", "{", "}", '"', "EMPTY", "Z", "A"]
    bad = n = 0
    t0 = time.time()
    while time.time() - t0 < seconds:
        name, text = rng.choice(list(seeds.items()))
        s = list(text)
        for _ in range(rng.randint(1, 4)):
            op, i = rng.random(), rng.randrange(len(s) + 1)
            if op < 0.3 and s:
                del s[min(i, len(s) - 1)]
            elif op < 0.7:
                s.insert(i, rng.choice(tokens))
            else:
                s = s[:i]
        src = "in_" + name
        with open(src, "w") as f:
            f.write("".join(s))
        out = "out.wkt" if not name.endswith("svg") else "out.svg"
        if os.path.exists(out):
            os.remove(out)
        r = rng.choice(["1", "0.5", "3", "1e-9", "1e9"])
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            try:
                code = main(["tighten", src, "-r", r, "-o", out, "--init",
                             rng.choice(["core", "input", "mason"])])
            except SystemExit as exc:
                code = exc.code
        n += 1
        errors = [line for line in err.getvalue().strip().splitlines() if "error" in line]
        if code not in (0, 2) or (code == 2 and (len(errors) != 1 or os.path.exists(out))):
            bad += 1
            print("BAD", code, name, r, repr("".join(s))[:300], err.getvalue()[:300])
    print("cases", n, "bad", bad)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    run(int(args[0]) if args else 0, float(args[1]) if len(args) > 1 else 120.0, "--dxf" in sys.argv)
