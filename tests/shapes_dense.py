"""Generators of dense, real-looking shapes and of exact 2r ties, for the exactness tests and benchmark.

Each generator is deterministic in its arguments (``seed``). Kinds:

* `admin_outline` — long administrative-like outlines: a star-shaped polygon whose radius is a fractal
  (midpoint displacement at several scales), densified with many near-collinear vertices, in projected
  coordinates around 1e5–1e6 (feet or metres).
* `traced_contour` — a level of a smooth random field traced by marching squares (sub-pixel vertices).
* `pixel_blob` — the pixel-square outline of a random blob (the union of its pixels), for whole-pixel
  radii.
* `bar`, `slot`, `gap_pair`, `neck` — parts and passages of width ``2r·(1 + eps)`` (eps may be 0, < 0,
  > 0), at an angle and an offset from the origin, alone or embedded in a large outline
  (`embed_in_outline`), and a pixel-staircase variant (`staircase_stroke`).
* `corner_gap` — short passages: a corner of S ``2r·(1 + eps)`` from another corner or from a flat
  wall (a gap as long as a point, where a disk's clearance is decided by a vertex).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
import shapely.affinity
from scipy import ndimage
from shapely.geometry import MultiPolygon, Polygon, box

__all__ = ["admin_outline", "bar", "embed_in_outline", "gap_pair", "neck", "pixel_blob", "slot",
           "staircase_gap", "staircase_stroke", "traced_contour", "corner_gap"]


def _valid(geom):
    geom = shapely.make_valid(geom) if not geom.is_valid else geom
    polys = [g for g in getattr(geom, "geoms", [geom]) if isinstance(g, (Polygon, MultiPolygon))]
    geom = shapely.union_all(polys)
    return shapely.orient_polygons(geom)


def _fractal(n: int, rng, roughness: float = 0.55) -> np.ndarray:
    """Periodic midpoint-displacement noise of ``n = 2**k`` samples, amplitude ~1."""
    k = int(round(math.log2(n)))
    v = np.zeros(1)
    amp = 1.0
    for _ in range(k):
        nxt = np.roll(v, -1)
        mid = 0.5 * (v + nxt) + amp * rng.standard_normal(len(v))
        out = np.empty(2 * len(v))
        out[0::2], out[1::2] = v, mid
        v = out
        amp *= roughness
    return v / max(np.abs(v).max(), 1e-300)


def admin_outline(n_vertices: int = 20_000, seed: int = 0, size: float = 2e5,
                  origin: tuple[float, float] = (9.8e5, 2.1e5), roughness: float = 0.6,
                  collinear: int = 4) -> Polygon:
    """A long administrative-like outline, ``size`` across, centred at ``origin`` (feet / metres).

    The boundary is fractal over several scales; every fractal vertex is followed by ``collinear − 1``
    vertices almost on the segment to the next one (perpendicular jitter of 1e-7 of the segment), as
    digitised borders have.
    """
    rng = np.random.default_rng(seed)
    base = max(64, 2 ** int(math.floor(math.log2(max(n_vertices // collinear, 64)))))
    noise = _fractal(base, rng, roughness)
    theta = np.linspace(0, 2 * math.pi, base, endpoint=False)
    rad = 0.5 * size * (1.0 + 0.35 * noise) / 1.35
    pts = np.column_stack([rad * np.cos(theta), rad * np.sin(theta)])
    if collinear > 1:
        nxt = np.roll(pts, -1, axis=0)
        d = nxt - pts
        nrm = np.column_stack([-d[:, 1], d[:, 0]])
        ts = np.arange(collinear) / collinear
        jitter = 1e-7 * rng.standard_normal((len(pts), collinear))
        jitter[:, 0] = 0.0
        dense = pts[:, None, :] + ts[None, :, None] * d[:, None, :] + jitter[:, :, None] * nrm[:, None, :]
        pts = dense.reshape(-1, 2)
    pts = pts + np.asarray(origin)
    return _valid(Polygon(pts))


def traced_contour(size: int = 200, seed: int = 0, smooth: float = 8.0, level: float = 0.0,
                   scale: float = 1.0) -> Polygon | MultiPolygon:
    """The region ``field > level`` of a smooth random field on a ``size``² grid, traced with marching
    squares (sub-pixel vertices), in pixel units times ``scale``; only parts of at least 50 px²."""
    from skimage import measure

    rng = np.random.default_rng(seed)
    z = ndimage.gaussian_filter(rng.standard_normal((size, size)), smooth, mode="wrap")
    z = z / z.std()
    z = np.pad(z, 1, constant_values=z.min() - 1.0)
    parts = []
    for c in measure.find_contours(z, level):
        if len(c) < 4:
            continue
        p = Polygon(c[:, ::-1])
        if not p.is_valid:
            p = shapely.make_valid(p)
        parts.append(p)
    # Even-odd fill: contours of holes lie inside contours of parts.
    geom = None
    for p in sorted(parts, key=lambda g: -g.area):
        geom = p if geom is None else shapely.symmetric_difference(geom, p)
    geom = _valid(geom)
    polys = [g for g in getattr(geom, "geoms", [geom]) if g.area >= 50]
    geom = shapely.union_all(polys)
    return _valid(shapely.affinity.scale(geom, scale, scale, origin=(0, 0)))


def _pixel_outline(mask: np.ndarray, origin=(0.0, 0.0)) -> Polygon | MultiPolygon:
    ys, xs = np.nonzero(mask)
    boxes = shapely.box(xs, ys, xs + 1.0, ys + 1.0)
    geom = shapely.simplify(shapely.union_all(boxes), 0.0)
    return _valid(shapely.affinity.translate(geom, *origin))


def pixel_blob(size: int = 60, seed: int = 0, smooth: float = 4.0, fill: float = 0.5,
               origin=(0.0, 0.0)) -> Polygon | MultiPolygon:
    """The pixel-square outline (union of pixels) of a random blob on a ``size``² grid."""
    rng = np.random.default_rng(seed)
    z = ndimage.gaussian_filter(rng.standard_normal((size, size)), smooth)
    yy, xx = np.mgrid[:size, :size]
    z -= 0.02 * np.hypot(xx - size / 2, yy - size / 2) / size * z.std() * 50
    mask = z > np.quantile(z, 1 - fill)
    mask[[0, -1], :] = False
    mask[:, [0, -1]] = False
    return _pixel_outline(mask, origin)


def _place(geom, angle_deg: float, offset):
    geom = shapely.affinity.rotate(geom, angle_deg, origin=(0, 0))
    return _valid(shapely.affinity.translate(geom, *offset))


def bar(r: float, eps: float, angle: float = 0.0, offset=(0.0, 0.0), length: float = 10.0) -> Polygon:
    """A rectangle ``length·r`` long and ``2r·(1 + eps)`` wide, centred on the x axis, then rotated by
    ``angle`` degrees about the origin and moved by ``offset``."""
    w = 2 * r * (1 + eps)
    return _place(box(-0.5 * length * r, -0.5 * w, 0.5 * length * r, 0.5 * w), angle, offset)


def gap_pair(r: float, eps: float, angle: float = 0.0, offset=(0.0, 0.0), side: float = 6.0):
    """Two squares of side ``side·r`` with a straight gap ``2r·(1 + eps)`` wide between them, centred
    at the origin (the gap along the y axis), rotated and moved."""
    g = 2 * r * (1 + eps)
    s = side * r
    a = box(-0.5 * g - s, -0.5 * s, -0.5 * g, 0.5 * s)
    b = box(0.5 * g, -0.5 * s, 0.5 * g + s, 0.5 * s)
    return _place(MultiPolygon([a, b]), angle, offset)


def neck(r: float, eps: float, angle: float = 0.0, offset=(0.0, 0.0), side: float = 6.0,
         length: float = 3.0):
    """Two squares of side ``side·r`` joined by a straight neck ``2r·(1 + eps)`` wide and
    ``length·r`` long (centred at the origin, along x), rotated and moved."""
    w = 2 * r * (1 + eps)
    s, ln = side * r, length * r
    a = box(-0.5 * ln - s, -0.5 * s, -0.5 * ln, 0.5 * s)
    b = box(0.5 * ln, -0.5 * s, 0.5 * ln + s, 0.5 * s)
    n = box(-0.5 * ln - 1e-3 * r, -0.5 * w, 0.5 * ln + 1e-3 * r, 0.5 * w)
    return _place(shapely.union_all([a, b, n]), angle, offset)


def slot(r: float, eps: float, angle: float = 0.0, offset=(0.0, 0.0), side: float = 10.0,
         depth: float = 4.0):
    """A square of side ``side·r`` with a straight slot ``2r·(1 + eps)`` wide and ``depth·r`` deep cut
    into it from the top edge, centred at the origin, rotated and moved."""
    g = 2 * r * (1 + eps)
    s = side * r
    body = box(-0.5 * s, -0.5 * s, 0.5 * s, 0.5 * s)
    cut = box(-0.5 * g, 0.5 * s - depth * r, 0.5 * g, 0.5 * s + r)
    return _place(body.difference(cut), angle, offset)


def corner_gap(r: float, eps: float, against: str = "corner", angle: float = 0.0, offset=(0.0, 0.0),
               side: float = 3.0):
    """A square of side ``side·r`` standing on a corner whose lowest vertex is ``2r·(1 + eps)`` above what
    lies below: another such square's top vertex (``against="corner"``), a flat wall (``"wall"``, a
    rectangle 4r thick under y = −r(1 + eps)) or a bar exactly 2r thick there (``"bar"``: its core is its
    centre line's stadium, a tie next to the passage). The passage is centred at the origin, then rotated
    and moved.

    Whatever eps, the origin is anticore: for eps ≥ 0 the r-disk centred there clears both sides; for
    eps < 0 the r-disks that touch the corner(s) from either side (centred ``r·sqrt(1 − (1 + eps)²)``
    off the axis for two corners), whose nearest points are the vertices, still cover it. A passage as
    short as a vertex never closes the anticore: only a long one does (`gap_pair`).
    """
    g = r * (1 + eps)                                      # half the passage
    h = side * r / math.sqrt(2.0)                           # half the diagonal
    top = Polygon([(0.0, g), (h, g + h), (0.0, g + 2 * h), (-h, g + h)])
    if against == "corner":
        other = Polygon([(0.0, -g), (-h, -g - h), (0.0, -g - 2 * h), (h, -g - h)])
    else:
        other = box(-2 * h, -g - (4 * r if against == "wall" else 2 * r), 2 * h, -g)
    return _place(MultiPolygon([top, other]), angle, offset)


def embed_in_outline(part, outline: Polygon, r: float, margin: float = 3.0):
    """``part`` moved to the middle of ``outline`` and set in a rectangular window cut out of it, with
    ``margin·r`` of clearance all round: the part keeps its own passages, and the shape is as large and
    dense, and its coordinates as far from the origin, as the outline."""
    x0, y0, x1, y1 = part.bounds
    p = outline.representative_point()
    moved = shapely.affinity.translate(part, p.x - 0.5 * (x0 + x1), p.y - 0.5 * (y0 + y1))
    mx0, my0, mx1, my1 = moved.bounds
    m = margin * r
    window = box(mx0 - m, my0 - m, mx1 + m, my1 + m)
    if not outline.contains(window):
        raise ValueError("the outline is too small for the part")
    return _valid(shapely.union(outline.difference(window), moved))


def staircase_stroke(r_px: int, n_steps: int = 6, step: int = 3, origin=(0.0, 0.0)):
    """A horizontal stroke exactly ``2·r_px`` pixels tall and ``8·r_px`` long joining two pixel
    staircase blobs (diagonal runs of ``step``-pixel stairs), as a pixel-square outline."""
    h = 2 * r_px
    length = 8 * r_px
    W = length + 2 * (n_steps * step + 4 * r_px) + 4
    H = 2 * (n_steps * step + 4 * r_px) + h + 4
    mask = np.zeros((H, W), dtype=bool)
    y0 = H // 2 - r_px
    left_end = 2 + n_steps * step + 4 * r_px
    mask[y0:y0 + h, left_end:left_end + length] = True
    # staircase blobs at both ends: stacked rectangles offset by `step` per stair
    for k in range(n_steps):
        half = 2 * r_px + (n_steps - k) * step
        for x in (left_end - 4 * r_px + k * step // 2, left_end + length + k * step // 2):
            mask[max(0, H // 2 - half):H // 2 + half, x:x + 4 * r_px] = True
    return _pixel_outline(mask, origin)


def staircase_gap(r_px: int, n_steps: int = 6, step: int = 2, origin=(0.0, 0.0)):
    """Two pixel staircase blobs facing each other across a straight gap exactly ``2·r_px`` pixels
    wide (the facing sides are straight columns of ``8·r_px`` pixels), as a pixel-square outline."""
    g = 2 * r_px
    blob = 6 * r_px + n_steps * step
    W = 2 * blob + g + 4
    H = 2 * (n_steps * step) + 8 * r_px + 4
    mask = np.zeros((H, W), dtype=bool)
    cy = H // 2
    for k in range(n_steps + 1):
        half = 4 * r_px + (n_steps - k) * step
        w = blob - k * step
        mask[cy - half:cy + half, 2 + k * step:2 + blob] = True         # left blob, staircase on its left
        mask[cy - half:cy + half, 2 + blob + g:2 + blob + g + w] = True   # right blob
    mask[cy - 4 * r_px:cy + 4 * r_px, 2:2 + blob] = True
    mask[cy - 4 * r_px:cy + 4 * r_px, 2 + blob + g:2 + 2 * blob + g] = True
    return _pixel_outline(mask, origin)
