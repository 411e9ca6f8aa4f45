"""The pixel core and anticore against the exact closed shrink of the mask's pixel squares (issue 24).

For random pixel blobs (unions of boxes and disks, as the raster tests draw them) and traced-mask-like
staircases, at the whole radii r = 3 and r = 8 where parts exactly 2r wide are the usual case: the exact
core at a pixel centre is ``dist(p, S↓r) < r`` with S↓r the closed shrink of the pixel squares, from the
GEOS-free clearance oracle of the tests (`tests/oracle.py`); likewise the anticore. Counts the pixels where
`raster.core` / `raster.anticore` disagree with it, for this checkout and for main's morphology
(pixel-centred disks only), whose file is passed as the first argument.

Usage: python benchmarks/raster_2r_exactness.py OLD_MORPHOLOGY.py [N_BLOBS]   (from the repository root)
"""
import importlib.util
import sys

import numpy as np
import shapely

sys.path.insert(0, ".")
import raster  # noqa: E402
import vectortighten as vt  # noqa: E402
from tests.oracle import piece_distances, shrink_pieces  # noqa: E402

spec = importlib.util.spec_from_file_location("old_morphology", sys.argv[1])
old = importlib.util.module_from_spec(spec)
spec.loader.exec_module(old)
N = int(sys.argv[2]) if len(sys.argv) > 2 else 40


def blob(rng, size=48):
    m = np.zeros((size, size), bool)
    yy, xx = np.mgrid[:size, :size]
    for _ in range(rng.integers(1, 6)):
        x, y = rng.integers(8, size - 8, 2)
        a, b = rng.integers(1, 12, 2)
        if rng.random() < 0.5:
            m |= (abs(xx - x) <= a) & (abs(yy - y) <= b)
        else:
            m |= np.hypot(xx - x, yy - y) < a
    m[:3], m[-3:], m[:, :3], m[:, -3:] = False, False, False, False
    return m


def exact(m, r, complement):
    H, W = m.shape
    grid = raster.Grid(0.0, float(H), 1.0, m.shape)
    S = vt.pixel_squares(m, grid)
    K = shrink_pieces(S, r, complement=complement)
    ii, jj = np.mgrid[:H, :W]
    xy = np.column_stack([(jj + 0.5).ravel(), (H - ii - 0.5).ravel()])
    inside = K.contains_xy(xy)
    near = np.full(len(xy), np.inf)
    if len(K):
        boxes = shapely.box(xy[:, 0] - r, xy[:, 1] - r, xy[:, 0] + r, xy[:, 1] + r)
        pi, kj = K.tree.query(boxes)
        rows_p = np.column_stack([xy[pi], xy[pi], np.zeros(len(pi))])
        d = piece_distances(np.zeros(len(pi), bool), rows_p, K.kind[kj], K.rows[kj])
        np.minimum.at(near, pi, d)
    out = inside | (near < r - K.delta)
    return out.reshape(m.shape)


rng = np.random.default_rng(24)
masks = [blob(rng) for _ in range(N)]
print(f"{N} random pixel blobs 48 × 48; per radius: pixels where the pixel core (anticore) differs from the "
      "exact one at pixel centres — spurious (pixel has it, exact not) / missed — and masks with any difference")
print("| r | version | core spurious | core missed | anticore spurious | anticore missed | masks differing |")
print("|---|---|---|---|---|---|---|")
for r in (3.0, 8.0):
    for name, mod in (("main", old), ("this branch", raster)):
        tot = np.zeros(4, int)
        bad = 0
        for m in masks:
            R, A = mod.core(m, r), mod.anticore(m, r)
            ER, EA = exact(m, r, False), exact(m, r, True)
            c = [(R & ~ER).sum(), (ER & ~R).sum(), (A & ~EA).sum(), (EA & ~A).sum()]
            tot += c
            bad += any(c)
        print(f"| {r:g} | {name} | {tot[0]} | {tot[1]} | {tot[2]} | {tot[3]} | {bad}/{N} |")
