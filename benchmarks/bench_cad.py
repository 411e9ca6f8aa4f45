"""Speed of the CAD and cut-file readers and writers, each against a baseline timed in the same run.

Inputs: a sheet of n plates (every plate: an outline with bulged corners, two circular holes and a slot of
four loose LINE/ARC entities, the slot inside an INSERTed block), as DXF, and the same sheet as an SVG cut
file (every outline its own unfilled element; the slot as four loose pieces).

* **DXF read**: `vectortighten.io.read_dxf` (expanding blocks, joining loose pieces with ezdxf's edgeminer,
  even-odd nesting, exact loops built) against ``ezdxf.readfile`` of the same file, the parse every DXF
  reader pays anyway.
* **SVG cut read**: `vectortighten.io.load_svg` (cut-file reading, exact loops built) against
  ``svgelements.SVG.parse`` of the same document.
* **DXF write**: `vectortighten.io.write_result` (LINE and ARC entities; LWPOLYLINE with bulges) against
  ezdxf writing the tightening's sampled rings as plain LWPOLYLINEs to the same folder.

Medians of ``--repeats`` runs, alternating candidate and baseline; wall time on whatever machine runs it.

Run:  python benchmarks/bench_cad.py [--sizes 10 100 1000] [--repeats 5]
It prints a markdown table and writes it to benchmarks/results/cad.md.
"""

from __future__ import annotations

import argparse
import io as stdio
import math
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import ezdxf  # noqa: E402
import numpy as np  # noqa: E402
import shapely  # noqa: E402
import svgelements  # noqa: E402

import vectortighten as vt  # noqa: E402
from vectortighten import io  # noqa: E402


def sheet_dxf(n: int, path: Path) -> None:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    slot = doc.blocks.new("SLOT")
    slot.add_line((-10, -4), (10, -4))
    slot.add_line((10, 4), (-10, 4))
    slot.add_arc((10, 0), 4, -90, 90)
    slot.add_arc((-10, 0), 4, 90, 270)
    b = math.tan(math.pi / 8)
    cols = max(1, int(math.sqrt(n)))
    for k in range(n):
        ox, oy = 100.0 * (k % cols), 70.0 * (k // cols)
        outline = [(6, 0, 0), (74, 0, b), (80, 6, 0), (80, 44, b), (74, 50, 0), (6, 50, b), (0, 44, 0),
                   (0, 6, b)]
        msp.add_lwpolyline([(ox + x, oy + y, bb) for x, y, bb in outline], format="xyb", close=True)
        msp.add_circle((ox + 12, oy + 12), 4)
        msp.add_circle((ox + 68, oy + 38), 4)
        msp.add_blockref("SLOT", (ox + 40, oy + 25))
    doc.saveas(path)


def sheet_svg(n: int) -> bytes:
    cols = max(1, int(math.sqrt(n)))
    parts = []
    for k in range(n):
        ox, oy = 100.0 * (k % cols), 70.0 * (k // cols)
        parts.append(f'<rect x="{ox}" y="{oy}" width="80" height="50" rx="6"/>'
                     f'<circle cx="{ox + 12}" cy="{oy + 12}" r="4"/>'
                     f'<circle cx="{ox + 68}" cy="{oy + 38}" r="4"/>'
                     f'<path d="M {ox + 30} {oy + 21} H {ox + 50}"/>'
                     f'<path d="M {ox + 50} {oy + 21} A 4 4 0 0 1 {ox + 50} {oy + 29}"/>'
                     f'<path d="M {ox + 50} {oy + 29} H {ox + 30}"/>'
                     f'<path d="M {ox + 30} {oy + 29} A 4 4 0 0 1 {ox + 30} {oy + 21}"/>')
    w, h = 100 * cols, 70 * math.ceil(n / cols)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}mm" height="{h}mm" viewBox="0 0 {w} {h}">'
            f'<g fill="none" stroke="red" stroke-width="0.1">{"".join(parts)}</g></svg>').encode()


def timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def medians(candidate, baseline, repeats: int) -> tuple[float, float]:
    a, b = [], []
    for _ in range(repeats):
        a.append(timed(candidate))
        b.append(timed(baseline))
    return statistics.median(a), statistics.median(b)


def run_size(n: int, d: Path, repeats: int) -> list[tuple]:
    """The table's rows for a sheet of ``n`` plates."""
    rows = []
    dxf_path = d / f"sheet{n}.dxf"
    sheet_dxf(n, dxf_path)
    data = sheet_svg(n)

    def read_dxf():
        src = io.read_dxf(dxf_path)
        assert len(shapely.get_parts(src.shape)) == n
        return src

    def read_dxf_loops():
        assert len(read_dxf().loops) == 4 * n

    def parse_dxf():
        list(ezdxf.readfile(dxf_path).modelspace())

    for task, fn in (("DXF read (shape)", read_dxf), ("DXF read (shape and exact loops)", read_dxf_loops)):
        t, base = medians(fn, parse_dxf, repeats)
        rows.append((task, n, 4 * n, base, t))

    def read_svg():
        src = io.load_svg(data)
        assert len(shapely.get_parts(src.shape)) == n
        return src

    def read_svg_loops():
        assert len(read_svg().loops) == 4 * n

    def parse_svg():
        list(svgelements.SVG.parse(stdio.BytesIO(data), reify=False).elements())

    for task, fn in (("SVG cut read (shape)", read_svg),
                     ("SVG cut read (shape and exact loops)", read_svg_loops)):
        t, base = medians(fn, parse_svg, repeats)
        rows.append((task, n, 4 * n, base, t))

    src = io.read_dxf(dxf_path)
    T = vt.tighten(src.shape, 2.0)
    rings = [lp.sample(T.tolerance) for lp in T.loops]

    def baseline_write():
        doc = ezdxf.new("R2010")
        msp = doc.modelspace()
        for ring in rings:
            msp.add_lwpolyline(np.asarray(ring)[:-1], close=True)
        doc.saveas(d / "base.dxf")

    for entities in ("lines-arcs", "lwpolyline"):
        def write(entities=entities):
            io.write_result(T, d / "out.dxf", meta=src.meta, dxf_entities=entities)

        t, base = medians(write, baseline_write, repeats)
        rows.append((f"DXF write ({entities})", n, len(T.loops), base, t))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 1000])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for n in args.sizes:
            rows += run_size(n, Path(d), args.repeats)
            print(f"n = {n} done", file=sys.stderr)
    lines = [
        "| task | plates | loops | baseline (s) | vectortighten (s) | ratio |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for task, n, loops, base, t in rows:
        lines.append(f"| {task} | {n} | {loops} | {base:.3g} | {t:.3g} | {t / base:.2f} |")
    header = (f"Medians of {args.repeats} alternating runs; Python {platform.python_version()}, ezdxf "
              f"{ezdxf.__version__}, svgelements {svgelements.SVGELEMENTS_VERSION}. Baselines: DXF read = "
              "ezdxf.readfile; SVG read = svgelements.SVG.parse; DXF write = ezdxf writing the sampled rings "
              "as LWPOLYLINEs.\n\n"
              f"Command: python benchmarks/bench_cad.py --sizes {' '.join(map(str, args.sizes))} "
              f"--repeats {args.repeats}\n\n")
    text = header + "\n".join(lines) + "\n"
    print(text)
    out = HERE / "results" / "cad.md"
    out.write_text("# CAD and cut files: readers and writers\n\n" + text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
