"""Filling closed rings by a fill rule (SVG's nonzero and evenodd), shared by the readers."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon

__all__ = ["fill_rings"]


def _clean_ring(xy: np.ndarray) -> np.ndarray | None:
    """Closed ring without repeated points, or None when it cannot bound any area."""
    keep = np.ones(len(xy), dtype=bool)
    keep[1:] = np.any(xy[1:] != xy[:-1], axis=1)
    xy = xy[keep]
    if len(xy) > 1 and np.all(xy[0] == xy[-1]):
        xy = xy[:-1]
    if len(xy) < 3:
        return None
    return np.vstack([xy, xy[:1]])


def _winding(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Winding number of ``ring`` (closed, (n+1, 2)) around each of ``points`` ((m, 2))."""
    x0, y0 = ring[:-1, 0], ring[:-1, 1]
    x1, y1 = ring[1:, 0], ring[1:, 1]
    out = np.zeros(len(points), dtype=np.int64)
    step = max(1, 2_000_000 // max(1, len(x0)))
    for k in range(0, len(points), step):
        px = points[k:k + step, 0:1]
        py = points[k:k + step, 1:2]
        up = (y0 <= py) & (y1 > py)
        down = (y0 > py) & (y1 <= py)
        cross = (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)
        out[k:k + step] = np.sum(up & (cross > 0), axis=1) - np.sum(down & (cross < 0), axis=1)
    return out


def fill_rings(rings, rule: str = "nonzero") -> Polygon | MultiPolygon:
    """The region that rings fill under an SVG fill rule.

    The rings are noded together and cut into faces (``shapely.polygonize``); a face is filled when the
    winding number of the rings around an interior point of it is non-zero (``"nonzero"``) or odd
    (``"evenodd"``). Self-intersecting rings, rings that cross each other, holes drawn in the same or the
    opposite direction: every case follows the SVG specification.

    Parameters
    ----------
    rings : sequence of (n, 2) float
        Closed or open (closed implicitly) rings, in drawing order, each with its own direction.
    rule : {"nonzero", "evenodd"}

    Returns
    -------
    Polygon or MultiPolygon
        Valid, possibly empty.

    Examples
    --------
    >>> outer = [(0, 0), (4, 0), (4, 4), (0, 4)]
    >>> inner = [(1, 1), (3, 1), (3, 3), (1, 3)]          # same direction as outer
    >>> fill_rings([outer, inner], "nonzero").area, fill_rings([outer, inner], "evenodd").area
    (16.0, 12.0)
    >>> fill_rings([outer, inner[::-1]], "nonzero").area   # opposite direction: a hole
    12.0
    """
    if rule not in ("nonzero", "evenodd"):
        raise ValueError(f"rule must be 'nonzero' or 'evenodd', got {rule!r}")
    closed = [r for r in (_clean_ring(np.asarray(r, dtype=float).reshape(-1, 2)) for r in rings)
              if r is not None]
    if not closed:
        return Polygon()
    if len(closed) == 1:
        simple = Polygon(closed[0])
        if simple.is_valid:
            return shapely.orient_polygons(simple)
    noded = shapely.node(shapely.multilinestrings([LineString(r) for r in closed]))
    faces = [f for f in shapely.get_parts(shapely.polygonize(shapely.get_parts(noded))) if f.area > 0]
    if not faces:
        return Polygon()
    reps = shapely.get_coordinates(shapely.point_on_surface(faces))
    # Only rings whose bounding box holds a face's point can wind around it.
    tree = shapely.STRtree([shapely.box(*LineString(r).bounds) for r in closed])
    face_idx, ring_idx = tree.query(shapely.points(reps), predicate="intersects")
    winding = np.zeros(len(faces), dtype=np.int64)
    for k in np.unique(ring_idx):
        sel = face_idx[ring_idx == k]
        winding[sel] += _winding(reps[sel], closed[k])
    keep = winding != 0 if rule == "nonzero" else (winding % 2) == 1
    filled = [f for f, k in zip(faces, keep, strict=True) if k]
    if not filled:
        return Polygon()
    # The faces of a polygonization meet only along shared edges: a coverage, united without overlays.
    try:
        out = shapely.coverage_union_all(filled) if len(filled) > 1 else filled[0]
    except shapely.errors.GEOSException:
        # Faces of coordinates so large (1e50) that rounding makes them overlap: a plain union.
        out = shapely.union_all(filled)
    if not out.is_valid:
        out = shapely.make_valid(out)
    polys = [g for g in shapely.get_parts(out) if isinstance(g, Polygon) and not g.is_empty]
    out = polys[0] if len(polys) == 1 else MultiPolygon(polys) if polys else Polygon()
    return shapely.orient_polygons(out)
