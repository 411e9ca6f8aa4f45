"""Speed of the pixel path (`raster.tighten`) at the paper's image sizes, against one EDT of the same image.

Two synthetic inputs of the paper's sizes, with thin parts, gaps, holes, combs and small islands:
1102×832 px with r = 40 and 1050×825 px with r = 75 (the paper's Figures 8 and 9). For each, the script
reports per-phase timings beside the paper's (59 s + 86 s and 55 s + 91 s on an 800 MHz G4), and the
whole run as a ratio to one `scipy.ndimage.distance_transform_edt` of the same image, measured in the
same run (medians, alternating). Then how time grows with image size (¼, ½, 1, 2× the area at r = 40)
and with r (10, 20, 40, 80 on the 1102×832 image).

Run:  python benchmarks/bench_raster.py [--repeats 5]
It prints markdown tables and writes them to benchmarks/results/raster.md.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import scipy
from scipy import ndimage

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import raster  # noqa: E402

PAPER = {"fig8": (1102, 832, 40, 59.0, 86.0), "fig9": (1050, 825, 75, 55.0, 91.0)}


def test_image(width: int, height: int, seed: int = 1) -> np.ndarray:
    """A binary image with the details a tightening treats, scaled to the image size.

    Blobs with holes big and small, bars thinner and thicker than 2r at r = 40, a comb with narrow teeth
    and gaps, a ring, and islands of several sizes.
    """
    rng = np.random.default_rng(seed)
    s = min(width, height) / 832.0
    yy, xx = np.mgrid[:height, :width].astype(np.float32)
    m = np.zeros((height, width), bool)

    def disk(cx, cy, rad):
        return (xx - cx * s) ** 2 + (yy - cy * s) ** 2 < (rad * s) ** 2

    def rect(x0, y0, x1, y1):
        return (xx >= x0 * s) & (xx < x1 * s) & (yy >= y0 * s) & (yy < y1 * s)

    # A wobbly body with holes.
    th = np.arctan2(yy - 300 * s, xx - 320 * s)
    rad = 220 + 25 * np.sin(5 * th) + 10 * np.cos(13 * th)
    m |= np.hypot(xx - 320 * s, yy - 300 * s) < rad * s
    m &= ~disk(300, 280, 60)          # a hole larger than r: kept
    m &= ~disk(420, 220, 18)          # smaller than r: filled
    m &= ~rect(150, 380, 400, 396)    # a crack narrower than 2r
    # A bar thinner than 2r to a second body, and a thick one.
    m |= rect(530, 250, 760, 300)
    m |= rect(540, 420, 760, 520)
    m |= disk(850, 320, 140)
    # A comb: teeth 24 wide, gaps 20.
    for k in range(9):
        m |= rect(620 + 44 * k, 620, 644 + 44 * k, 780)
    m |= rect(600, 600, 1010, 640)
    # A ring thinner than 2r, and islands.
    ring = np.hypot(xx - 180 * s, yy - 680 * s)
    m |= (ring < 110 * s) & (ring > 80 * s)
    for cx, cy, rr in rng.uniform([420, 560, 6], [560, 800, 50], size=(7, 3)):
        m |= disk(cx, cy, rr)
    m[:3, :] = m[-3:, :] = False
    m[:, :3] = m[:, -3:] = False
    return m


def _median_pair(fn_a, fn_b, repeats: int):
    ta, tb, last = [], [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn_a()
        ta.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        last = fn_b()
        tb.append(time.perf_counter() - t0)
    return statistics.median(ta), statistics.median(tb), last


def run_case(m: np.ndarray, r: float, repeats: int) -> dict:
    edt, tight, T = _median_pair(lambda: ndimage.distance_transform_edt(m),
                                 lambda: raster.tighten(m, r), repeats)
    flow = sum(v for k, v in T.timings.items() if k.startswith("flow"))
    return {"edt": edt, "total": tight, "morph": T.timings["morphology"] + T.timings["init"], "flow": flow,
            "levels": T.levels, "iterations": T.iterations, "ratio": tight / edt}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--out", type=Path, default=HERE / "results" / "raster.md")
    args = parser.parse_args(argv)
    lines = [
        "# Pixel path speed (`raster.tighten`)",
        "",
        f"Machine: {platform.machine()}, {platform.python_version()}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}. Medians of {args.repeats} runs alternating with one EDT of the same "
        f"image. Command: `python benchmarks/bench_raster.py --repeats {args.repeats}`.",
        "",
        "| image | r | levels | iterations per level (coarse → fine) | morphology (s) | flow (s) | total (s) "
        "| paper morphology + flow (s) | total / one EDT |",
        "|---|---:|---:|---|---:|---:|---:|---:|---:|",
    ]
    for name, (w, h, r, pm, pf) in PAPER.items():
        m = test_image(w, h)
        res = run_case(m, r, args.repeats)
        lines.append(f"| {name}: {w}×{h} | {r} | {res['levels']} | {res['iterations']} | {res['morph']:.3f} "
                     f"| {res['flow']:.3f} | {res['total']:.3f} | {pm:.0f} + {pf:.0f} | {res['ratio']:.1f} |")
        print(lines[-1], flush=True)
    lines += ["", "Growth with image size (r = 40 scaled with the image, so the shapes are the same):", "",
              "| scale of area | pixels | total (s) | one EDT (s) | total / EDT | s per megapixel |",
              "|---:|---:|---:|---:|---:|---:|"]
    for area in (0.25, 0.5, 1.0, 2.0):
        f = area ** 0.5
        m = test_image(int(1102 * f), int(832 * f))
        res = run_case(m, 40 * f, args.repeats)
        lines.append(f"| {area:g} | {m.size} | {res['total']:.3f} | {res['edt']:.3f} | {res['ratio']:.1f} "
                     f"| {res['total'] / m.size * 1e6:.3f} |")
        print(lines[-1], flush=True)
    lines += ["", "Growth with r (the 1102×832 image):", "",
              "| r | levels | total (s) | total / EDT |", "|---:|---:|---:|---:|"]
    m = test_image(1102, 832)
    for r in (10, 20, 40, 80):
        res = run_case(m, r, args.repeats)
        lines.append(f"| {r} | {res['levels']} | {res['total']:.3f} | {res['ratio']:.1f} |")
        print(lines[-1], flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
