"""Checks made once at the public boundary; code inside the package trusts their results."""

import math
import numbers
import warnings

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from .errors import (
    GeometryTypeError,
    InvalidGeometryError,
    InvalidRadiusError,
    RepairWarning,
    ResourceLimitError,
)
from .limits import (
    MAX_COORDINATE,
    MAX_OUTPUT_VERTICES,
    MIN_R_MAGNITUDE,
    MIN_R_SIZE,
    MIN_TOLERANCE_R,
    chords_per_turn,
    min_radius,
    min_tolerance,
)
from .tolerances import DEFAULT_TOLERANCE_R, MAX_QUAD_SEGS

__all__ = ["check_output_size", "check_radius", "check_resolution", "check_shape", "check_tolerance",
           "quad_segs_for"]


def check_radius(r, name: str = "r") -> float:
    """Return ``r`` as a float, or raise `InvalidRadiusError` unless it is a positive finite number."""
    if isinstance(r, bool) or not isinstance(r, numbers.Real):
        raise InvalidRadiusError(f"{name} must be a positive finite number, got {r!r}")
    value = float(r)
    if not math.isfinite(value) or value <= 0:
        raise InvalidRadiusError(f"{name} must be a positive finite number, got {r!r}")
    return value


def check_tolerance(tolerance, r: float, S=None) -> float:
    """Return the chord tolerance to use for radius ``r`` (``None`` means the documented default).

    With the shape ``S``, a tolerance finer than `vectortighten.limits.min_tolerance` (what doubles can
    resolve at the shape's coordinates, or about 7·10^5 chords a full turn) is refused too.
    """
    if tolerance is None:
        return DEFAULT_TOLERANCE_R * r
    tol = check_radius(tolerance, "tolerance")
    if tol >= r:
        raise InvalidRadiusError(f"tolerance must be smaller than r = {r!r}, got {tolerance!r}")
    if S is not None:
        limit = min_tolerance(S, r)
        if tol < limit:
            raise InvalidRadiusError(
                f"tolerance = {tolerance!r} is below what doubles resolve here: it must be at least "
                f"{limit:.3g} (the larger of {MIN_TOLERANCE_R:g}·r and 1e-15 of the largest coordinate)")
    return tol


def check_output_size(S, r: float, tolerance: float) -> None:
    """Refuse a tolerance whose sampled output could exceed `vectortighten.limits.MAX_OUTPUT_VERTICES`.

    Each loop of a tightening turns by a full turn in arcs of radius r at least, and each boundary ring
    of S gives at most one loop per vertex of it that a loop can wrap; the estimate is the chords of one
    full turn at ``tolerance`` for every ring of S plus the input's own vertices. A tolerance that gives
    more is refused before anything is computed.
    """
    n_rings = int(shapely.get_num_interior_rings(shapely.get_parts(S)).sum()) + shapely.get_num_geometries(S)
    estimate = chords_per_turn(r, tolerance) * n_rings + shapely.get_num_coordinates(S)
    if estimate > MAX_OUTPUT_VERTICES:
        raise ResourceLimitError(
            f"tolerance = {tolerance:g} would sample the output with about {estimate:.3g} vertices "
            f"({chords_per_turn(r, tolerance)} a full turn of radius r, for each of {n_rings} ring(s)); "
            f"the cap is {MAX_OUTPUT_VERTICES:g}: use a larger tolerance")


def check_resolution(S, r: float) -> None:
    """Refuse a radius too small for doubles to resolve against the shape (see `vectortighten.limits`).

    Raises `InvalidRadiusError` naming the limit when ``r < min_radius(S)``.
    """
    limit = min_radius(S)
    if r < limit:
        raise InvalidRadiusError(
            f"r = {r!r} is below the smallest radius doubles resolve for this shape: r must be at least "
            f"{limit:.3g} (the larger of {MIN_R_SIZE:g} of its size and {MIN_R_MAGNITUDE:g} of its largest "
            "coordinate); scale the shape up or move it nearer the origin")


def quad_segs_for(r: float, tolerance: float) -> int:
    """Number of chords a quarter circle of radius ``r`` needs so that none is farther than ``tolerance``.

    A chord spanning the angle a lies ``r·(1 − cos(a/2))`` from its arc at most.
    """
    step = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / r))
    return int(min(MAX_QUAD_SEGS, max(1, math.ceil((math.pi / 2) / step - 1e-9))))


def _repaired(S, name: str, reason: str):
    """The polygonal part of ``shapely.make_valid(S)``; part by part where
    GEOS refuses the whole ("Overlay input is mixed-dimension": a part collapsed to a point or a line at
    coordinates whose rounding is coarser than the part), leaving out the parts with fewer than three
    distinct vertices."""

    def polygonal(g):
        polys = [p for p in getattr(g, "geoms", [g]) if p.geom_type in ("Polygon", "MultiPolygon")]
        return shapely.union_all(polys) if polys else Polygon()

    try:
        return polygonal(shapely.make_valid(S))
    except shapely.errors.GEOSException:
        pass
    try:
        parts = [polygonal(shapely.make_valid(p)) for p in shapely.get_parts(S)
                 if len(np.unique(shapely.get_coordinates(p.exterior), axis=0)) >= 3]
        return shapely.union_all(parts) if parts else Polygon()
    except shapely.errors.GEOSException as exc:
        raise InvalidGeometryError(f"{name} is invalid ({reason}) and GEOS cannot repair it "
                                   f"({str(exc).splitlines()[0]})") from None


def check_shape(S, name: str = "S", *, allow_empty: bool = False) -> Polygon | MultiPolygon:
    """Return ``S`` as a valid, oriented (Multi)Polygon, or raise an error that names the problem.

    Invalid polygons (self-intersections, bow-ties) are repaired with ``shapely.make_valid``, keeping the
    polygonal part, and a `RepairWarning` is issued. Exteriors come back counter-clockwise and holes
    clockwise. The input object is never modified.
    """
    if not isinstance(S, BaseGeometry):
        if hasattr(S, "__len__") and not isinstance(S, (str, bytes)):
            # A GeoSeries, an array or a list of geometries: the vectorised call is tighten_all.
            raise GeometryTypeError(f"{name} must be one shapely Polygon or MultiPolygon, got a "
                                    f"{type(S).__name__} of {len(S)}; for many geometries use "
                                    "vectortighten.tighten_all (or core_all, fillet_all, ...)")
        raise GeometryTypeError(f"{name} must be a shapely Polygon or MultiPolygon, got {type(S).__name__}")
    if S.geom_type == "GeometryCollection":
        parts = [g for g in S.geoms if not g.is_empty]
        if any(g.geom_type not in ("Polygon", "MultiPolygon") for g in parts):
            kinds = sorted({g.geom_type for g in parts})
            raise GeometryTypeError(f"{name} must be polygonal; its collection holds {', '.join(kinds)}")
        S = shapely.union_all(parts) if parts else Polygon()
    elif S.geom_type not in ("Polygon", "MultiPolygon"):
        raise GeometryTypeError(f"{name} must be a Polygon or MultiPolygon, got a {S.geom_type}")
    if S.is_empty:
        if allow_empty:
            return S
        raise InvalidGeometryError(f"{name} is empty")
    coords = shapely.get_coordinates(S)
    if not np.isfinite(coords).all():
        raise InvalidGeometryError(f"{name} has NaN or infinite coordinates")
    if np.abs(coords).max() > MAX_COORDINATE:
        raise InvalidGeometryError(f"{name} has coordinates up to {np.abs(coords).max():.3g}; at most "
                                   f"{MAX_COORDINATE:g} in absolute value are supported "
                                   "(areas would overflow)")
    if not S.is_valid:
        reason = shapely.is_valid_reason(S)
        fixed = _repaired(S, name, reason)
        if fixed.is_empty or fixed.area == 0:
            raise InvalidGeometryError(f"{name} is invalid ({reason}) and has no area once repaired")
        warnings.warn(f"{name} was invalid ({reason}); repaired with shapely.make_valid", RepairWarning,
                      stacklevel=3)
        S = fixed
    if S.area <= 0:
        raise InvalidGeometryError(f"{name} has zero area")
    S = _close_cracks(S, name)
    # Consecutive vertices closer than 1e-12 of the shape's size carry no geometry (only rounding): drop
    # them, sparing every edge loop a zero or subnormal length.
    x0, y0, x1, y1 = S.bounds
    eps = 1e-12 * max(x1 - x0, y1 - y0)
    S = _drop_specks(S, eps)
    try:
        merged = shapely.remove_repeated_points(S, eps)
    except shapely.errors.GEOSException:       # a ring collapsed below three points: keep S as it is
        merged = S
    if shapely.get_num_coordinates(merged) != shapely.get_num_coordinates(S) and merged.is_valid \
            and not merged.is_empty:
        S = merged
    return shapely.orient_polygons(S, exterior_cw=False)


def _drop_specks(S, eps: float):
    """``S`` without the parts and holes whose bounding box is within ``1000·eps`` (rounding-sized specks).

    Such a speck is below every radius `tighten` accepts (`vectortighten.limits.MIN_R_SIZE` is 1e-8 of
    the size, ``eps`` 1e-12 of it), so no tightening depends on it; it only breaks the merging of repeated
    points.
    """
    def small(ring) -> bool:
        a, b, c, d = ring.bounds
        return max(c - a, d - b) <= 1000.0 * eps

    parts = [p for p in getattr(S, "geoms", [S]) if not small(p.exterior)]
    if len(parts) == len(getattr(S, "geoms", [S])) and not any(small(h) for p in parts for h in p.interiors):
        return S
    kept = [Polygon(p.exterior, [h for h in p.interiors if not small(h)]) for p in parts]
    if not kept:
        return S
    out = kept[0] if len(kept) == 1 else MultiPolygon(kept)
    return out if out.is_valid else S


#: Parts of a MultiPolygon closer than this share of the shape's size are one part cut by rounding.
CRACK = 1e-9


def _close_cracks(S, name: str):
    """Merge the parts of ``S`` that a crack of rounding width separates along a stretch of boundary.

    Squares unioned from pixel centres, or parcels whose shared edges were written twice, arrive as
    parts a few units in the last place apart. Mathematically such a crack is a gap: it leaves no disk
    of radius r inside S across it, so the core, and with it the tightening, falls apart. A crack of width
    ``CRACK`` times the shape's size or less is closed (a mitred grow and shrink by that width, applied to
    the cracked parts only) and a `RepairWarning` says so. Parts that merely touch at a point are left as
    they are.
    """
    if S.geom_type != "MultiPolygon" or len(S.geoms) < 2:
        return S
    x0, y0, x1, y1 = S.bounds
    eps = CRACK * max(x1 - x0, y1 - y0)
    parts = np.asarray(S.geoms)
    i, j = shapely.STRtree(parts).query(parts, predicate="dwithin", distance=eps)
    keep = i < j
    if not keep.any():
        return S
    i, j = i[keep], j[keep]
    with np.errstate(invalid="ignore", over="ignore"):      # coordinates near 1e50: judged below
        grown = shapely.buffer(parts, eps, join_style="mitre", mitre_limit=10.0)
    # A crack of length L makes the eps-grown parts overlap by about 2·eps·L. Parts touching at a point
    # overlap too, in the wedge between them: about (2·eps)² at a right angle, but 20·eps² where a 16-gon's
    # vertex meets an edge (a hole touching its shell), and closing that wedge would join the parts.
    # So a crack must be at least 1000·eps long (10⁻⁶ of the shape's size); a shared edge shorter than that
    # is not one a user draws.
    cracked = shapely.area(shapely.intersection(grown[i], grown[j])) > 2000.0 * eps * eps
    if not cracked.any():
        return S
    involved = np.unique(np.concatenate([i[cracked], j[cracked]]))
    with np.errstate(invalid="ignore", over="ignore"):
        closed = shapely.union_all(grown[involved]).buffer(-eps, join_style="mitre", mitre_limit=10.0)
    rest = np.setdiff1d(np.arange(len(parts)), involved)
    merged = shapely.union_all(np.append(parts[rest], closed))
    if not merged.is_valid or merged.is_empty or shapely.get_num_geometries(merged) >= len(parts):
        # Nothing was joined: the overlap came from sharp corners meeting at a point (their mitres reach
        # further than a crack's width), not from a crack.
        return S
    warnings.warn(f"{name}: {len(involved)} parts lay within {eps:.3g} (a rounding crack) of one another along "
                  f"an edge; closed the cracks, leaving {len(getattr(merged, 'geoms', [merged]))} part(s)",
                  RepairWarning, stacklevel=4)
    return merged
