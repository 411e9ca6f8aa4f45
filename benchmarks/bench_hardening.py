"""Cost of the guards around the engine: the final check of every result, and the entry checks.

For each shape the script times, in the same process and alternately (the machines are noisy),

* the baseline: the engine on checked arguments (``vectortighten.engine._tighten``), what ``tighten``
  did before issue 23;
* ``vectortighten.tighten``: the same plus the entry checks (resolution, tolerance, output size), the
  rounding-speck pass over the loops and the final check (``R ⊆ T ⊆ F`` against the engine's own core
  and fillet, and tangent joins);

and reports the medians (CPU time) and their ratio. Shapes: a 25-pointed star (the fast path when r is
small, the general engine when r is large), a square with 16 holes, and a jagged 3000-vertex blob (the
general engine on a boundary that is all mortar).

Run:  python benchmarks/bench_hardening.py [--repeats 5]
It prints a markdown table and writes it to benchmarks/results/hardening.md.
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon, box

import vectortighten as vt
from vectortighten._validation import check_shape
from vectortighten.engine import Init, _tighten


def star(k=25, inner=0.5, size=10.0):
    th = np.arange(2 * k) * math.pi / k
    rad = np.where(np.arange(2 * k) % 2 == 0, size, inner * size)
    return Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))


def holed():
    S = box(0, 0, 40, 40)
    for i in range(4):
        for j in range(4):
            S = S.difference(box(3 + 9 * i, 3 + 9 * j, 9 + 9 * i, 9 + 9 * j))
    return S


def blob(n=3000):
    rng = np.random.default_rng(1)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 10 + rng.uniform(-0.5, 0.5, n)
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


CASES = [
    ("star, r = 0.1 (fast path)", star(), 0.1, "core"),
    ("star, r = 1 (general)", star(), 1.0, "core"),
    ("star, r = 1, init input", star(), 1.0, "input"),
    ("16 holes, r = 1.5", holed(), 1.5, "core"),
    ("16 holes, r = 1.5, init mason", holed(), 1.5, "mason"),
    ("jagged blob 3000 v, r = 0.3", blob(), 0.3, "core"),
]


def cpu(fn) -> float:
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    rows = []
    for name, S, r, init in CASES:
        C = check_shape(S)
        tol = 1e-5 * r
        base, guarded = [], []
        for _ in range(args.repeats):
            base.append(cpu(lambda C=C, r=r, init=init, tol=tol: _tighten(C, r, Init(init), tol)))
            guarded.append(cpu(lambda S=S, r=r, init=init: vt.tighten(S, r, init=init)))
        b, g = statistics.median(base), statistics.median(guarded)
        path = vt.tighten(S, r, init=init)._cache["_path"]
        rows.append(f"| {name} | {shapely.get_num_coordinates(S)} | {path} | {b * 1e3:.1f} | {g * 1e3:.1f} | "
                    f"{g / b:.2f} |")
        print(rows[-1], flush=True)
    text = "\n".join([
        "# Cost of the guards (issue 23)",
        "",
        f"CPU time, medians of {args.repeats}; baseline = the engine on checked arguments "
        "(`engine._tighten`), timed alternately in the same run. Python " + platform.python_version() +
        f", shapely {shapely.__version__}. Command: `python benchmarks/bench_hardening.py "
        f"--repeats {args.repeats}`.",
        "",
        "| shape | vertices | path | engine ms | tighten ms | ratio |",
        "|---|---|---|---|---|---|",
        *rows,
        "",
    ])
    out = Path(__file__).parent / "results" / "hardening.md"
    out.write_text(text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
