"""Measures of shapes: perimeter, topology, radius of curvature, r-regularity."""

from __future__ import annotations

import math
import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from ._validation import check_radius, check_shape, check_tolerance, quad_segs_for
from .curves import Loop

__all__ = [
    "is_r_regular",
    "min_radius_of_curvature",
    "n_components",
    "n_holes",
    "perimeter",
    "polygon_radii_of_curvature",
]


def _loops(obj) -> list[Loop] | None:
    if isinstance(obj, Loop):
        return [obj]
    if isinstance(obj, (list, tuple)) and all(isinstance(x, Loop) for x in obj):
        return list(obj)
    loops = getattr(obj, "loops", None)
    return list(loops) if loops is not None else None


def perimeter(shape) -> float:
    """Length of the boundary: exact for `Loop`s (or a result holding ``loops``), else of the polygon.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> perimeter(box(0, 0, 2, 3))
    10.0
    >>> round(perimeter(Loop.circle((0, 0), 1.0)), 12) == round(2 * math.pi, 12)
    True
    """
    loops = _loops(shape)
    if loops is not None:
        return math.fsum(loop.length for loop in loops)
    if not isinstance(shape, BaseGeometry):
        raise TypeError(f"expected a shapely geometry, a Loop or a list of Loops, got {type(shape).__name__}")
    return float(shape.length) if shape.geom_type in ("Polygon", "MultiPolygon") else float(shape.length)


def n_components(geom: BaseGeometry) -> int:
    """Number of connected polygons of a (Multi)Polygon (0 if empty).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> n_components(box(0, 0, 1, 1).union(box(2, 0, 3, 1)))
    2
    """
    if geom.is_empty:
        return 0
    return int(shapely.get_num_geometries(geom)) if geom.geom_type == "MultiPolygon" else 1


def n_holes(geom: BaseGeometry) -> int:
    """Number of holes (interior rings) over all polygons of a (Multi)Polygon.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> n_holes(box(0, 0, 3, 3).difference(box(1, 1, 2, 2)))
    1
    """
    if geom.is_empty:
        return 0
    return int(shapely.get_num_interior_rings(shapely.get_parts(geom)).sum())


def polygon_radii_of_curvature(geom: BaseGeometry) -> np.ndarray:
    """Discrete radius of curvature at every vertex of a polygon's rings.

    At a vertex, the estimate is the radius of the circle through it and its two neighbours (inf where
    they are collinear). For a polygon sampled from a curve whose vertices lie on the curve this converges
    to the curve's radius of curvature; at a genuine corner it tends to 0 as the sampling is refined.

    Returns
    -------
    (n,) float
        One value per vertex, over all rings.
    """
    out = []
    for ring in shapely.get_rings(shapely.get_parts(geom)):
        c = shapely.get_coordinates(ring)[:-1]
        if len(c) < 3:
            continue
        a, b, d = np.roll(c, 1, axis=0), c, np.roll(c, -1, axis=0)
        ab = np.hypot(*(b - a).T)
        bd = np.hypot(*(d - b).T)
        ad = np.hypot(*(d - a).T)
        cross = np.abs((b - a)[:, 0] * (d - a)[:, 1] - (b - a)[:, 1] * (d - a)[:, 0])
        with np.errstate(divide="ignore", invalid="ignore"):
            rad = np.where(cross > 1e-14 * ab.max() ** 2, ab * bd * ad / (2 * cross), np.inf)
        out.append(rad)
    return np.concatenate(out) if out else np.zeros(0)


def min_radius_of_curvature(shape) -> float:
    """Smallest radius of curvature of a boundary.

    Exact for a `Loop`, a list of loops or a result holding ``loops`` (the smallest arc radius; 0 at a
    corner; inf for no arcs and no corners). For a shapely polygon a discrete estimate (see
    `polygon_radii_of_curvature`).

    Examples
    --------
    >>> min_radius_of_curvature(Loop.from_disks([(0, 0), (3, 0)], [1, 1], 0.5))
    0.5
    >>> from shapely.geometry import Point
    >>> round(min_radius_of_curvature(Point(0, 0).buffer(2.0, quad_segs=64)), 6)
    2.0
    """
    loops = _loops(shape)
    if loops is not None:
        return min((loop.min_radius_of_curvature for loop in loops), default=math.inf)
    radii = polygon_radii_of_curvature(shape)
    return float(radii.min()) if len(radii) else math.inf


def is_r_regular(S, r: float, *, tolerance: float | None = None) -> bool:
    """True if S is r-regular: its core and fillet coincide (the mortar is empty), within ``tolerance``.

    Regular means both S and its complement are unions of disks of radius r; it implies r-smoothness.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
    r : float
        Radius, > 0.
    tolerance : float, optional
        Chord tolerance (default 1e-5·r); the core and fillet may differ by a few times it.

    Examples
    --------
    >>> from shapely.geometry import Point, box
    >>> is_r_regular(Point(0, 0).buffer(3.0, quad_segs=256), 1.0)
    True
    >>> is_r_regular(box(0, 0, 4, 4), 1.0)
    False
    """
    from .morphology import _core, _fillet

    r = check_radius(r)
    S = check_shape(S)
    tol = check_tolerance(tolerance, r)
    q = quad_segs_for(r, tol)
    R, F = _core(S, r, q), _fillet(S, r, q)
    if R.is_empty:
        return False
    # Chord errors add up: the core's arcs (tol), the closing's intermediate arcs of radius 2r (2·tol), the
    # opening and closing of the chords themselves; 8·tol bounds them with room.
    return bool(shapely.hausdorff_distance(R.boundary, F.boundary) <= 8 * tol)
