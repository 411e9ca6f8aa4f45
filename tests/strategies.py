"""Hypothesis strategies: random polygons of the kinds the engine must handle."""

import math

import numpy as np
import shapely
from hypothesis import assume
from hypothesis import strategies as st
from shapely.geometry import Point, Polygon, box


@st.composite
def stars(draw, min_k=5, max_k=24):
    """Star-shaped simple polygons (sorted angles, positive radii) around the origin, size ~20."""
    k = draw(st.integers(min_k, max_k))
    angles = draw(st.lists(st.floats(0, 2 * math.pi, exclude_max=True), min_size=k, max_size=k,
                           unique_by=lambda a: round(a, 3)))
    radii = draw(st.lists(st.floats(2.0, 10.0), min_size=len(angles), max_size=len(angles)))
    th = np.sort(np.array(angles))
    rad = np.array(radii)
    P = Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))
    assume(P.is_valid and P.area > 1.0)
    return P


@st.composite
def box_unions(draw, max_n=5):
    """Unions of axis-aligned boxes (several components, notches, gaps, thin parts)."""
    n = draw(st.integers(1, max_n))
    boxes = []
    for _ in range(n):
        x, y = draw(st.floats(0, 10)), draw(st.floats(0, 10))
        w, h = draw(st.floats(0.3, 6)), draw(st.floats(0.3, 6))
        boxes.append(box(x, y, x + w, y + h))
    return shapely.union_all(boxes)


@st.composite
def disk_unions(draw, max_n=5):
    """Unions of polygonal disks (coarse and fine), often overlapping."""
    n = draw(st.integers(1, max_n))
    parts = [Point(draw(st.floats(0, 10)), draw(st.floats(0, 10))).buffer(draw(st.floats(0.3, 3.5)),
                                                                           quad_segs=draw(st.integers(2, 16)))
             for _ in range(n)]
    return shapely.union_all(parts)


@st.composite
def holed(draw):
    """A square with polygonal holes (some cut through its boundary)."""
    n = draw(st.integers(1, 4))
    holes = [Point(draw(st.floats(0.5, 9.5)), draw(st.floats(0.5, 9.5))).buffer(draw(st.floats(0.2, 2.5)),
                                                                               quad_segs=draw(st.integers(1, 6)))
             for _ in range(n)]
    return box(0, 0, 10, 10).difference(shapely.union_all(holes))


def with_redundant_vertices(P):
    """The same shape with a collinear vertex inserted in every edge and every vertex repeated once."""
    def ring(c):
        c = np.asarray(c)[:-1]
        nxt = np.roll(c, -1, axis=0)
        out = np.empty((3 * len(c), 2))
        out[0::3], out[1::3], out[2::3] = c, c, 0.5 * (c + nxt)
        return np.vstack([out, out[:1]])
    polys = []
    for p in shapely.get_parts(P):
        polys.append(Polygon(ring(p.exterior.coords), [ring(h.coords) for h in p.interiors]))
    return polys[0] if len(polys) == 1 else shapely.MultiPolygon(polys)


shapes = st.one_of(stars(), box_unions(), disk_unions(), holed())


def radii_for(S):
    """Radii from a twentieth to a quarter of the shape's size."""
    x0, y0, x1, y1 = S.bounds
    size = max(x1 - x0, y1 - y0)
    return st.floats(size / 40, size / 4)


def pixel_outline(n: int, seed: int = 7) -> Polygon:
    """The pixel outline of a noisy blob digitised at a resolution that gives about n vertices.

    The blob (a disk of radius 10 with six octaves of smooth noise on its radius) is digitised row by row:
    each pixel row keeps the run of pixels between the curve's leftmost and rightmost points in that row,
    and the outline is the staircase around those runs, as a segmentation mask's traced boundary is. It
    is built in O(n) without an image, so a million vertices need no gigapixel raster.
    """
    rng = np.random.default_rng(seed)
    side = max(16, int(n / 2))                      # pixel rows across the blob; ~2 vertices per row
    h = 20.0 / side
    m = 16 * side
    t = np.linspace(0, 2 * np.pi, m, endpoint=False)
    rad = np.full(m, 8.0)
    for k in range(1, 7):
        rad += 0.6 / k * np.sin(3 * k * t + rng.uniform(0, 2 * np.pi))
    x, y = rad * np.cos(t), rad * np.sin(t)
    rows = np.floor(y / h).astype(np.int64)
    j0 = rows.min()
    rows -= j0
    nrow = rows.max() + 1
    lo = np.full(nrow, np.iinfo(np.int64).max)
    hi = np.full(nrow, np.iinfo(np.int64).min)
    cols = np.floor(x / h).astype(np.int64)
    np.minimum.at(lo, rows, cols)
    np.maximum.at(hi, rows, cols + 1)
    j = np.arange(nrow)
    right = np.column_stack([np.repeat(hi, 2), np.column_stack([j, j + 1]).ravel()])
    left = np.column_stack([np.repeat(lo, 2), np.column_stack([j, j + 1]).ravel()])[::-1]
    ring = np.vstack([right, left]).astype(float)
    ring[:, 1] += j0
    P = shapely.remove_repeated_points(Polygon(ring * h))
    P = shapely.simplify(P, 0.0)                    # drop collinear vertices (exactly, tolerance 0)
    return P if P.is_valid else max(shapely.make_valid(P).geoms, key=lambda g: g.area)


# ---------------------------------------------------------------------------------------------------------
# Adversarial strategies (issue 23): the kinds of input a hostile fuzzer found problems with.
# ---------------------------------------------------------------------------------------------------------
@st.composite
def spiked(draw):
    """A square with thin or zero-width spikes (outward) and slits (inward) on its sides."""
    n = draw(st.integers(1, 4))
    pts = [(0.0, 0.0)]
    xs = sorted(draw(st.lists(st.floats(0.5, 9.5), min_size=n, max_size=n, unique_by=lambda v: round(v, 2))))
    for x in xs:
        width = draw(st.sampled_from([0.0, 1e-12, 1e-6, 1e-3, 0.05]))
        length = draw(st.floats(-4.0, 6.0).filter(lambda v: abs(v) > 0.1))
        pts += [(x, 0.0), (x + width / 2, -length), (x + width, 0.0)]
    pts += [(10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]
    P = Polygon(pts)
    assume(not P.is_empty)
    return P


@st.composite
def near_degenerate(draw):
    """Rings with nearly repeated vertices, nearly collinear runs, and bumps of rounding size."""
    base = draw(st.sampled_from(["square", "star"]))
    if base == "square":
        c = np.array([(0, 0), (10, 0), (10, 10), (0, 10)], dtype=float)
    else:
        k = 11
        th = np.arange(2 * k) * math.pi / k
        rad = np.where(np.arange(2 * k) % 2 == 0, 10.0, 5.0)
        c = np.column_stack([rad * np.cos(th), rad * np.sin(th)])
    out = []
    eps = draw(st.sampled_from([1e-15, 1e-13, 1e-10, 1e-7]))
    for i, p in enumerate(c):
        out.append(tuple(p))
        q = c[(i + 1) % len(c)]
        kind = draw(st.sampled_from(["none", "repeat", "collinear", "bump"]))
        if kind == "repeat":
            out.append(tuple(p + eps))
        elif kind == "collinear":
            out.append(tuple(p + 0.5 * (q - p)))
        elif kind == "bump":
            m = p + 0.5 * (q - p)
            n = np.array([-(q - p)[1], (q - p)[0]]) / np.hypot(*(q - p))
            out += [tuple(m - 0.01 * (q - p)), tuple(m + eps * n), tuple(m + 0.01 * (q - p))]
    return Polygon(out)


@st.composite
def placed(draw, shapes):
    """A shape of ``shapes`` rotated, scaled by 10^-6…10^6 and moved by up to 10^9."""
    P = draw(shapes)
    angle = draw(st.floats(0, 360))
    scale = 10.0 ** draw(st.integers(-6, 6))
    offset = draw(st.sampled_from([0.0, 1e3, 1e6, 1e9])) * draw(st.sampled_from([1, -1]))
    P = shapely.affinity.rotate(P, angle, origin=(0, 0))
    P = shapely.affinity.scale(P, scale, scale, origin=(0, 0))
    return shapely.affinity.translate(P, offset, -offset)


def relative_radius():
    """Radii relative to the shape's size: tiny (down to 10^-14), ordinary, and huge (up to 10^200)."""
    return st.one_of(st.sampled_from([1e-14, 1e-10, 1e-9, 1e-7, 1e3, 1e30, 1e200]),
                     st.floats(0.01, 0.6))
