"""Speed of raster.tighten_labels on a large label image, as ratios against baselines timed in the same run.

The image: 2048 × 2048 pixels, 200 labels, like a segmentation of cells — Voronoi cells of 200 random
seeds with wavy borders (each pixel's nearest seed looked up ±3 px away), each cut to a jagged disk
around its seed (radius 45–110 px, boundary noise of a few pixels), so that neighbours touch along
jagged shared borders and the background shows between groups.

Timed (CPU time of this process, medians of ``--repeats``):

* ``tighten_labels``: every label tightened by the pixel method (the paper's flow) on its crop, then the
  symmetric rule of `raster.labels`;
* ``tighten(union)``: the binary tightening of the union of the labels, `raster.tighten` (what the same
  flow costs once on the whole image, without labels);
* ``skimage per-label opening+closing``: for each label, scikit-image's ``isotropic_opening`` then
  ``isotropic_closing`` (EDT-based, the fast ones) on the same crop, pasted back in label order (later
  labels overwrite earlier ones: the naive rule). Needs scikit-image (the ``bench`` extra); without it
  scipy.ndimage's ``binary_opening`` / ``binary_closing`` with a disk, and the table says so.

    python benchmarks/bench_labels.py --repeats 3 --out benchmarks/results/labels.md
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
from scipy import ndimage

import raster


def label_image(size: int = 2048, n: int = 200, seed: int = 1) -> np.ndarray:
    """Voronoi cells of ``n`` random seeds cut to jagged disks around them; uint16, 0 = background."""
    rng = np.random.default_rng(seed)
    seeds = rng.uniform(60, size - 60, size=(n, 2))
    marks = np.zeros((size, size), bool)
    rows, cols = seeds.astype(int).T
    marks[rows, cols] = True
    dist, (ir, ic) = ndimage.distance_transform_edt(~marks, return_indices=True)
    index = np.full((size, size), -1, np.int32)
    index[rows, cols] = np.arange(n)
    # The nearest seed of every pixel, looked up a few pixels away (a smooth random displacement), so that
    # the borders between cells are wavy and jagged as a segmentation's are, not digital straight lines.
    shift = [ndimage.gaussian_filter(rng.normal(size=(size, size)), 3.0) for _ in range(2)]
    shift = [np.rint(s * 3.0 / s.std()).astype(np.int64) for s in shift]
    yy, xx = np.indices((size, size))
    owner = index[ir, ic][np.clip(yy + shift[0], 0, size - 1), np.clip(xx + shift[1], 0, size - 1)]
    radius = rng.uniform(45, 110, n)
    noise = ndimage.gaussian_filter(rng.normal(size=(size, size)), 2.0)
    noise *= 4.0 / noise.std()
    inside = dist + noise < radius[owner]
    labels = np.where(inside, owner + 1, 0).astype(np.uint16)
    return labels


def _crops(labels: np.ndarray, r: float):
    margin = math.ceil(2 * r) + 3
    for k, sl in enumerate(ndimage.find_objects(labels), start=1):
        if sl is None:
            continue
        box = tuple(slice(max(0, s.start - margin), min(n, s.stop + margin))
                    for s, n in zip(sl, labels.shape, strict=True))
        yield k, box


def skimage_open_close(labels: np.ndarray, r: float) -> tuple[np.ndarray, str]:
    """Per label: opening then closing on the label's crop, pasted back in label order."""
    try:
        from skimage.morphology import isotropic_closing, isotropic_opening

        def op(m):
            return isotropic_closing(isotropic_opening(m, r), r)
        name = "skimage isotropic_opening + isotropic_closing, per label"
    except ImportError:
        disk = np.hypot(*np.mgrid[-math.ceil(r):math.ceil(r) + 1, -math.ceil(r):math.ceil(r) + 1]) <= r

        def op(m):
            return ndimage.binary_closing(ndimage.binary_opening(m, disk), disk)
        name = "scipy.ndimage binary_opening + binary_closing with a disk, per label (no scikit-image)"
    out = np.zeros_like(labels)
    for k, box in _crops(labels, r):
        region = op(labels[box] == k)
        out[box][region] = k
    return out, name


def _cpu(fn):
    t0 = time.process_time()
    value = fn()
    return time.process_time() - t0, value


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=int, default=2048)
    ap.add_argument("--labels", type=int, default=200)
    ap.add_argument("--radius", type=float, nargs="+", default=[8.0, 16.0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)

    labels = label_image(args.size, args.labels)
    present = len(np.unique(labels)) - 1
    union = labels > 0
    rows = []
    for r in args.radius:
        times = {"labels": [], "union": [], "baseline": []}
        for _ in range(args.repeats):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", raster.MaskWarning)
                t, (out, res) = _cpu(lambda r=r: raster.tighten_labels(labels, r, return_result=True))
            times["labels"].append(t)
            t, union_res = _cpu(lambda r=r: raster.tighten(union, r))
            times["union"].append(t)
            t, (base, base_name) = _cpu(lambda r=r: skimage_open_close(labels, r))
            times["baseline"].append(t)
        med = {k: statistics.median(v) for k, v in times.items()}
        rows.append(dict(r=r, **med, lost=len(res.lost), conflicts=res.conflicts, filled=res.filled,
                         kept=int((res.area_out > 0).sum()), base_name=base_name,
                         union_px=int(union_res.mask.sum()), labelled_px=int((out > 0).sum()),
                         base_px=int((base > 0).sum())))
        print(f"r = {r:g}: tighten_labels {med['labels']:.2f} s, tighten(union) {med['union']:.2f} s, "
              f"baseline {med['baseline']:.2f} s", flush=True)

    lines = [
        "# Label images: `raster.tighten_labels` against the binary tightening of the union and per-label "
        "opening + closing",
        "",
        f"`python benchmarks/bench_labels.py --radius {' '.join(f'{r:g}' for r in args.radius)} --repeats "
        f"{args.repeats}` — a {args.size} × {args.size} label "
        f"image with {present} labels (Voronoi cells with jagged shared borders cut to jagged disks; see "
        f"the script), CPU time of one process, medians of {args.repeats}. Machine: {platform.processor() or platform.machine()}, "
        f"Python {platform.python_version()}, numpy {np.__version__}. Baseline: {rows[0]['base_name']}.",
        "",
        "| r (px) | tighten_labels (s) | tighten(union) (s) | per-label opening+closing (s) | "
        "labels / union | labels / opening+closing | labels kept | conflicts (px) | gaps filled (px) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        lines.append(f"| {row['r']:g} | {row['labels']:.2f} | {row['union']:.2f} | {row['baseline']:.2f} | "
                     f"{row['labels'] / row['union']:.2f} | {row['labels'] / row['baseline']:.1f} | "
                     f"{row['kept']} of {present} | {row['conflicts']} | {row['filled']} |")
    lines += ["", "Pixels labelled in the output: " + ", ".join(
        f"r = {row['r']:g}: {row['labelled_px']:,} (union tightened: {row['union_px']:,}; opening+closing: "
        f"{row['base_px']:,})" for row in rows) + "."]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out is not None:
        args.out.write_text(text)


if __name__ == "__main__":
    main()
