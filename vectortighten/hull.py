"""The relative convex hull: the shortest closed curve around a set inside another.

This is Sklansky's minimum-perimeter polygon, the building block of the tightening engine, and useful on
its own (for example to simplify a digitised silhouette between its inner and outer pixel boundaries).
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import MultiPolygon, Polygon

from ._validation import check_shape
from .errors import InvalidGeometryError
from .geodesic import ShortestLoops

__all__ = ["relative_convex_hull"]

_THICKEN = 1e-7  # of the outer polygon's size: room for the curve where the two boundaries touch


def relative_convex_hull(inner, outer) -> Polygon | MultiPolygon:
    """The relative convex hull of ``inner`` in ``outer``: bounded by the shortest closed curves around it.

    Inside each part of ``outer`` that has no holes, one curve wraps all the components of ``inner`` it
    holds (Sklansky's minimum-perimeter polygon). Where ``outer`` has holes (obstacles the curve cannot
    cross) the way around them is not unique, so each component of ``inner`` is wrapped by the shortest
    curve homotopic to its own outer boundary, and curves that meet are merged and wrapped again.

    Parameters
    ----------
    inner : shapely Polygon or MultiPolygon
        The set to wrap (its holes are ignored).
    outer : shapely Polygon or MultiPolygon
        The set the curve must stay in; must cover ``inner``.

    Returns
    -------
    Polygon or MultiPolygon
        Exact on polygons: every vertex of the result is a vertex of ``inner`` or of ``outer``.

    Raises
    ------
    InvalidGeometryError
        If ``outer`` does not cover ``inner``.

    Notes
    -----
    The domain ``outer − inner`` is triangulated (constrained Delaunay); the boundary of each component
    gives a sleeve of triangles, and the funnel algorithm on the sleeve unrolled periodically gives the
    shortest closed curve. The two sets are moved apart by 1e-7 of the size of ``outer`` where they touch,
    then every corner is put back on the original vertex it came from.

    References
    ----------
    .. [1] J. Sklansky, R. Chazin and B. Hansen, "Minimum-perimeter polygons of digitized silhouettes",
       IEEE Transactions on Computers 21 (1972) 260–268.
    .. [2] G. Toussaint, "Computing geodesic properties inside a simple polygon", Revue d'Intelligence
       Artificielle 3 (1989).

    Examples
    --------
    >>> from shapely.geometry import Polygon, box
    >>> C = Polygon([(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (4, 3), (4, 4), (0, 4)])   # a "C"
    >>> relative_convex_hull(C, box(-1, -1, 5, 5)).area                                # its convex hull
    16.0
    >>> wall = box(-1, -1, 5, 5).difference(box(2, 1.5, 5, 2.5))   # a wall reaching into the C's mouth
    >>> relative_convex_hull(C, wall).area                        # 16 minus the trapezoid it keeps out
    13.0
    """
    inner = check_shape(inner, "inner")
    outer = check_shape(outer, "outer")
    x0, y0, x1, y1 = outer.bounds
    size = max(x1 - x0, y1 - y0)
    if inner.difference(outer).area > 1e-12 * size * size:
        raise InvalidGeometryError("outer must cover inner")
    eps = _THICKEN * size
    domain = shapely.difference(outer.buffer(eps, join_style="mitre", mitre_limit=50.0),
                                inner.buffer(-eps, join_style="mitre", mitre_limit=50.0))
    original = np.vstack([shapely.get_coordinates(outer), shapely.get_coordinates(inner)])
    kd = cKDTree(original)
    shortest = ShortestLoops(domain, probe=4)

    def wrap(ring: np.ndarray) -> Polygon | None:
        geo = shortest(ring)
        if geo is None:
            return None
        _, j = kd.query(geo.xy)
        pts = original[j]
        keep = np.r_[True, np.any(pts[1:] != pts[:-1], axis=1)]
        pts = pts[keep]
        if len(pts) >= 2 and np.array_equal(pts[0], pts[-1]):
            pts = pts[:-1]
        if len(pts) < 3:
            return None
        return shapely.make_valid(Polygon(pts))

    comps = list(shapely.get_parts(inner))
    rings = []
    for part in shapely.get_parts(outer):
        held = [c for c in comps if part.covers(c.representative_point())]
        if not held:
            continue
        if len(part.interiors) == 0 and len(held) > 1:
            rings.append(shapely.get_coordinates(part.exterior))       # one curve around all of them
        else:
            rings += [shapely.get_coordinates(c.exterior) for c in held]
    hull = None
    for _ in range(len(rings) + 1):
        wrapped = [w for w in (wrap(ring) for ring in rings) if w is not None]
        pieces = shapely.union_all([*wrapped, inner])
        pieces = shapely.union_all([g for g in shapely.get_parts(pieces) if g.geom_type == "Polygon"])
        n_before = len(rings)
        merged = list(shapely.get_parts(pieces))
        hull = pieces
        if len(merged) == n_before:
            break
        rings = [shapely.get_coordinates(Polygon(p.exterior)) for p in merged]
    return shapely.orient_polygons(hull, exterior_cw=False)
