"""The paper's morphological operations on shapely polygons, with exact set relations.

Every function takes a shapely (Multi)Polygon ``S`` and a radius ``r > 0`` in the shape's units, and
returns a valid shapely geometry. The shrink, grow, core and fillet are S's exact boundaries
(`exact_morphology`, built from S's own edges in closed form) with their circular arcs replaced by
chords no farther than ``tolerance`` from them (default `DEFAULT_TOLERANCE_R`·r, i.e. 1e-5·r); GEOS's
buffers, at the matching number of chords per quarter circle (``quad_segs``), are used only where that
construction is not available and for Mason's second opening and closing.

Chord-approximated buffers alone break the inclusions the paper relies on (``S.buffer(-r).buffer(r)``
sticks out of an L-shape by ~1e-5 with shapely's defaults). Here they hold exactly:
``core(S) ⊆ S ⊆ fillet(S)``, because the core is intersected with S and the fillet united with it.

Notation (Williams & Rossignac, §2): grow ``S↑r``, shrink ``S↓r``, core ``R_r(S) = S↓r↑r`` (opening),
fillet ``F_r(S) = S↑r↓r`` (closing), mortar ``M_r(S) = F_r(S) − R_r(S)``, anticore ``¬F_r(S)``.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon, box
from shapely.geometry.base import BaseGeometry

from ._validation import check_radius, check_shape, check_tolerance, quad_segs_for
from .tolerances import GUIDE_MISSING_R, ZERO_SCALE

__all__ = [
    "anticore",
    "core",
    "fillet",
    "fillet_round",
    "grow",
    "mason",
    "mortar",
    "pockets",
    "round_fillet",
    "shrink",
    "tolerance_zone",
]

Polygonal = Polygon | MultiPolygon


def _side_radius(r, which: int):
    """``r`` itself, or for a pair ``(r_convex, r_concave)`` the one the core (``which=0``) or the fillet
    (``which=1``) is taken at (`two_radii`); `_ZERO` when that radius is 0 (the set is S itself)."""
    from .two_radii import is_pair, parse_radii

    if not is_pair(r):
        return r
    v = parse_radii(r)[which]
    return v if v > 0 else _ZERO


_ZERO = object()


def _ring_loops(S: Polygonal) -> list:
    """S's rings as `Loop`s of segments (S oriented: outer boundaries counter-clockwise, holes clockwise)."""
    from .curves import Loop

    return [Loop.from_polygon_ring(shapely.get_coordinates(ring)) for ring in shapely.get_rings(shapely.get_parts(S))]


def _prepare(S, r, tolerance) -> tuple[Polygonal, float, int]:
    r = check_radius(r)
    S = check_shape(S)
    tol = check_tolerance(tolerance, r)
    return S, r, quad_segs_for(r, tol)


def _polygonal(geom: BaseGeometry) -> Polygonal:
    """The polygonal part of an overlay result, as a valid Polygon or MultiPolygon."""
    if geom.is_empty:
        return Polygon()
    if geom.geom_type in ("Polygon", "MultiPolygon"):
        return geom
    parts = [g for g in shapely.get_parts(geom) if g.geom_type in ("Polygon", "MultiPolygon") and not g.is_empty]
    if not parts:
        return Polygon()
    return shapely.union_all(parts)


def _orient(geom: Polygonal) -> Polygonal:
    return shapely.orient_polygons(geom, exterior_cw=False) if not geom.is_empty else geom


# GEOS can return "ghost" pieces from a buffer: a polygon whose inradius is just below r, shrunk by r, may
# come back as a tiny polygon instead of empty (its offset edges cross over and close up again); likewise a
# hole just narrower than 2r may survive a growth. A piece of the shrink all of whose vertices are closer
# than r to the boundary of S (a hole of the grow all of whose vertices are closer than r to S) cannot be
# part of the exact result and is removed.
_GHOST_R = 1e-6


_GHOST_SAMPLES = 16


def _all_too_close(ring_coords: np.ndarray, boundary, distance: float) -> bool:
    """Whether every vertex of a ring is closer than ``distance`` to ``boundary`` (prepared).

    A genuine piece of a shrink (or hole of a grow) has every vertex at distance ≥ r from the boundary, a
    ghost has none; a sample of evenly spaced vertices tells them apart.
    """
    c = ring_coords[:-1] if len(ring_coords) > 1 else ring_coords
    if len(c) > _GHOST_SAMPLES:
        c = c[np.linspace(0, len(c) - 1, _GHOST_SAMPLES).astype(int)]
    return bool(shapely.dwithin(boundary, shapely.points(c), distance).all())


def _exact(S: Polygonal, r: float, side: int):
    """S's exact offsets of one side (`offsets.exact_offsets`): the judge of every core/anticore decision."""
    from .offsets import exact_offsets

    return exact_offsets(_orient(S), r, side)


def _sampled(S: Polygonal, r: float, q: int, operation: str, exact=None, chained=None) -> Polygonal | None:
    """``operation`` of S sampled from its exact boundary (`exact_morphology`), or None where that is not
    available; ``exact``: S's `exact_offsets` of the side the operation needs, if already computed;
    ``chained``: a callable giving their chained loops (`exact_morphology._side_loops`), if kept.

    The loops are S's own offsets in closed form (segments on or parallel to S's edges, arcs of radius
    r), each arc sampled by chords within the sagitta of GEOS's ``quad_segs = q``, so the result has the
    same resolution as a buffer's. GEOS's buffers simplify their input by up to r/100 and lose parts
    exactly 2r wide; on a traced staircase their grow reaches 0.7 % of r beyond S↑r, and at small radii
    they cost up to 60 times as much. None where the exact construction is not defined (two parts of the
    shrink touching at one point) or its sampling is not a valid polygon: the caller falls back on GEOS's,
    snapped onto the exact corners.
    """
    from .engine import _assemble_valid
    from .exact_morphology import _loops_of

    try:
        loops = _loops_of(_orient(S), r, operation, exact, None if chained is None else chained())
    except (RuntimeError, ValueError, FloatingPointError):
        return None
    if not loops:
        return Polygon()
    geom, _ = _assemble_valid(loops, r * (1.0 - math.cos(math.pi / (4 * q))))
    if operation in ("core", "fillet"):
        geom = _pinned(geom, S)
    return geom if geom.is_valid else None


def _pinned(geom: Polygonal, S: Polygonal) -> Polygonal:
    """``geom`` with its vertices that lie within S's offset precision of a vertex of S moved onto it.

    The core and the fillet pass through vertices of S (a reflex corner that survives in the core, a
    convex one in the fillet, a vertex that a disk of the anticore touches): where the exact boundary
    reaches one from an arc's end, computed from its angle, it lands a few ulps beside it, and the overlay
    with S that puts the set on the right side of it would node the difference into a spike.
    """
    from scipy.spatial import cKDTree

    from .offsets import precision_of

    own = np.unique(shapely.get_coordinates(S), axis=0)
    coords = shapely.get_coordinates(geom)
    if not len(own) or not len(coords):
        return geom
    eps = precision_of(S)
    d, i = cKDTree(own).query(coords, distance_upper_bound=eps)
    found = np.isfinite(d)
    near = found.copy()                   # (not d > 0: a difference of 1e-183 squares to 0)
    near[found] = np.any(coords[found] != own[i[found]], axis=1)
    coords[near] = own[i[near]]
    # The ends of arcs tangent to an edge of S, computed from their angles, onto the edge.
    rest = ~found
    a, b = _edges(_orient(S))
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    j, dist = tree.query_nearest(shapely.points(coords[rest]), max_distance=eps, all_matches=False,
                                 return_distance=True)
    k = np.flatnonzero(rest)[j[0]]
    on = (dist > 0) & (dist <= eps)
    k, e = k[on], j[1][on]
    if len(k):
        dd = b[e] - a[e]
        t = np.einsum("ij,ij->i", coords[k] - a[e], dd) / np.einsum("ij,ij->i", dd, dd)
        coords[k] = a[e] + t[:, None] * dd
    if not near.any() and not len(k):
        return geom
    return shapely.remove_repeated_points(shapely.set_coordinates(shapely.from_wkb(shapely.to_wkb(geom)), coords), 0.0)


def _grow(S: Polygonal, r: float, q: int, exact=None) -> Polygonal:
    """``S↑r`` sampled from its exact boundary (`_sampled`); where that is not available, GEOS's with its
    reflex vertices moved onto the exact corners of S's exact offsets (side −1).

    ``exact``: `_exact(S, r, -1)` if already computed. The rule is the engine's guide's
    (`centers.snap_onto`): each reflex vertex of GEOS's grow within `centers.snap_window` of an exact
    corner is moved onto the nearest one.
    """
    from .centers import snap_onto, snap_window

    X = _exact(S, r, -1) if exact is None else exact
    G = _sampled(S, r, q, "grow", X)
    return G if G is not None else snap_onto(_grow_raw(S, r, q), X.corners, -1, snap_window(S, r, q))


def _shrink(S: Polygonal, r: float, q: int, exact=None) -> Polygonal:
    """``S↓r`` sampled from its exact boundary (`_sampled`); where that is not available, GEOS's with its
    convex vertices moved onto the exact corners of S's exact offsets (side +1).

    GEOS simplifies a buffer's input, which can cut a corner that has a vertex within a hundredth of r
    next to it (the offset corner then lands up to ~r/100 off); the exact corners (`offsets.exact_offsets`,
    from S's own edges) put it back, by the rule of the engine's guide (`centers.snap_onto`).
    ``exact``: `_exact(S, r, 1)` if already computed.
    """
    from .centers import snap_onto, snap_window

    X = _exact(S, r, 1) if exact is None else exact
    E = _sampled(S, r, q, "shrink", X)
    return E if E is not None else snap_onto(_shrink_raw(S, r, q), X.corners, 1, snap_window(S, r, q))


# GEOS offsets a ring in one piece and nodes the raw offset curve against itself. On a jagged outline (a
# traced mask: a right-angle corner at every vertex) whose corners lie a few to a few hundred of their own
# spacings within r, each corner's offset arc crosses those of its neighbours within r and the noding
# blows up (a 30k-vertex traced coastline at r = 34 pixels: 60 s for the grow, 31 s for the shrink). There
# ``S↑r = S ∪ Z`` and ``S↓r = S − Z`` with ``Z = (∂S)↑r`` the tolerance zone, built as the union of the
# buffers of short stretches of the boundary (about r/4 long), each of which GEOS offsets quickly: 8 s for
# both there, and it simplifies the input less (only within a stretch). Elsewhere (few corners, or r
# so large that GEOS's own simplification thins them) the plain buffer is faster. Thresholds measured on
# the benchmark shapes (benchmarks/bench_tighten.py).
_JAGGED_TURNS = 100                   # total turning (in full turns) of a jagged outline, at least
_JAGGED_SPACING = (3.0, 500.0)        # r over the median edge length, between these


def _jagged(S: Polygonal, r: float) -> tuple[bool, float]:
    """Whether S's outline is jagged at the scale of r (see above), and its median edge length."""
    turn, lengths = 0.0, []
    for ring in shapely.get_rings(shapely.get_parts(S)):
        c = shapely.get_coordinates(ring)[:-1]
        u = c - np.roll(c, 1, axis=0)
        v = np.roll(c, -1, axis=0) - c
        turn += float(np.abs(np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1))).sum())
        lengths.append(np.hypot(v[:, 0], v[:, 1]))
    if not lengths:
        return False, 0.0
    h = float(np.median(np.concatenate(lengths)))
    lo, hi = _JAGGED_SPACING
    return turn >= _JAGGED_TURNS * 2 * np.pi and lo * h <= r <= hi * h, h


def _zone(S: Polygonal, r: float, q: int, h: float) -> Polygonal:
    """``(∂S)↑r`` as the union of the buffers of stretches of the boundary about r/4 long."""
    k = int(np.clip(round(0.25 * r / h), 4, 64))
    stretches = []
    for ring in shapely.get_rings(shapely.get_parts(S)):
        c = shapely.get_coordinates(ring)
        n = len(c) - 1
        starts = np.arange(0, n, k)
        stretches += [c[i:min(i + k, n) + 1] for i in starts.tolist()]
    lines = shapely.linestrings(np.concatenate(stretches), indices=np.repeat(np.arange(len(stretches)),
                                                                              [len(x) for x in stretches]))
    return _polygonal(shapely.union_all(shapely.buffer(lines, r, quad_segs=q)))


def _offsets(S: Polygonal, r: float, q: int) -> tuple[Polygonal, Polygonal]:
    """The raw shrink and grow of S (see `_shrink_raw`, `_grow_raw`), through the tolerance zone where
    S is jagged at the scale of r."""
    jagged, h = _jagged(S, r)
    if not jagged:
        return _shrink_raw(S, r, q), _grow_raw(S, r, q)
    Z = _zone(S, r, q, h)
    return (_shrink_raw(S, r, q, _polygonal(shapely.difference(S, Z))),
            _grow_raw(S, r, q, _polygonal(shapely.union(S, Z))))


def _grow_raw(S: Polygonal, r: float, q: int, G: Polygonal | None = None) -> Polygonal:
    """``S↑r`` as GEOS's buffer (or the given one), without ghost holes."""
    G = _polygonal(S.buffer(r, quad_segs=q)) if G is None else G
    if G.is_empty or not any(len(p.interiors) for p in shapely.get_parts(G)):
        return G
    boundary = S.boundary
    shapely.prepare(boundary)
    parts = []
    changed = False
    for p in shapely.get_parts(G):
        keep = []
        for hole in p.interiors:
            if _all_too_close(shapely.get_coordinates(hole), S, r * (1 - _GHOST_R)):
                changed = True
            else:
                keep.append(hole)
        parts.append(Polygon(p.exterior, keep) if len(keep) != len(p.interiors) else p)
    if not changed:
        return G
    return _polygonal(shapely.union_all(parts))


def _shrink_raw(S: Polygonal, r: float, q: int, E: Polygonal | None = None) -> Polygonal:
    """``S↓r`` as GEOS's buffer (or the given one), without ghost pieces."""
    E = _polygonal(S.buffer(-r, quad_segs=q)) if E is None else E
    if E.is_empty:
        return E
    parts = list(shapely.get_parts(E))
    boundary = S.boundary
    shapely.prepare(boundary)
    keep = [p for p in parts if not _all_too_close(shapely.get_coordinates(p.exterior), boundary,
                                                   r * (1 - _GHOST_R))]
    if len(keep) == len(parts):
        return E
    return _polygonal(shapely.union_all(keep)) if keep else Polygon()


def _boundary_segments(S: Polygonal) -> np.ndarray:
    """The boundary edges of S as an array of LineStrings."""
    segs = []
    for ring in shapely.get_rings(shapely.get_parts(S)):
        c = shapely.get_coordinates(ring)
        segs.append(np.stack([c[:-1], c[1:]], axis=1))
    return shapely.linestrings(np.concatenate(segs))


def _edges(S: Polygonal) -> tuple[np.ndarray, np.ndarray]:
    """Start and end points ``(m, 2)`` of the boundary edges of an oriented S (S lies on their left)."""
    rings = shapely.get_rings(shapely.get_parts(S))
    starts, ends = [], []
    for ring in rings:
        c = shapely.get_coordinates(ring)
        starts.append(c[:-1])
        ends.append(c[1:])
    return np.concatenate(starts), np.concatenate(ends)


def _nudge(geom: Polygonal, S: Polygonal, into: bool) -> Polygonal:
    """Move the stray vertices of an overlay result by a few ulps so that the inclusion holds exactly.

    An overlay computes new vertices (where two boundaries cross) in floating point, so a vertex that
    belongs on an edge of S lands a rounding error to one side of it. With ``into=True`` the vertices of
    ``geom`` that are not strictly inside S (other than the vertices of S itself) are pushed into S, so
    that ``S.covers(geom)``; with ``into=False`` those of ``geom`` in S are pushed out, so that
    ``geom.covers(S)``.
    """
    if geom.is_empty or S.is_empty:
        return geom                                   # (nothing covers or is covered by the empty set)
    S = _orient(S)
    shapely.prepare(S)                                # a copy of our own; covers is asked several times

    def holds(g) -> bool:
        if into:
            return S.covers(g)
        shapely.prepare(g)                            # cheaper than the unprepared relate, even counted in
        return g.covers(S)

    covered = holds(geom)
    if covered:
        return geom
    a, b = _edges(S)
    d = b - a
    normal = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
    tree = None                                       # built only if a vertex has to move
    coords = shapely.get_coordinates(geom)
    keys = np.sort(a[:, 0] + 1j * a[:, 1])
    k = coords[:, 0] + 1j * coords[:, 1]
    own = keys[np.clip(np.searchsorted(keys, k), 0, len(keys) - 1)] == k
    eps = 8.0 * np.finfo(float).eps * max(1.0, float(np.abs(coords).max()))
    # First only the vertices strictly on the wrong side; those on S's boundary too only if that is not
    # enough (moving them opens a sliver of a few ulps along S's edges, which overlays then carry on).
    strict = True
    for _ in range(9):
        x, y = coords[:, 0], coords[:, 1]
        if into:
            bad = ~(shapely.intersects_xy if strict else shapely.contains_xy)(S, x, y) & ~own
        else:
            bad = (shapely.contains_xy if strict else shapely.intersects_xy)(S, x, y) & ~own
        if not bad.any():
            if strict:
                strict = False
                continue
            break
        if tree is None:
            tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
        nearest = tree.query_nearest(shapely.points(coords[bad]), all_matches=False)[1]
        coords[bad] += (eps if into else -eps) * normal[nearest]
        eps *= 4.0
        geom = shapely.set_coordinates(shapely.from_wkb(shapely.to_wkb(geom)), coords.copy())
        covered = holds(geom)
        if covered:
            break
    if not geom.is_valid:
        geom = _polygonal(shapely.make_valid(geom))
        covered = holds(geom)
    if not covered:
        # The overlay merged a vertex of S onto another boundary (S nearly touching itself): take the
        # offending sliver out of (add it to) the result, a hair thickened.
        x0, y0, x1, y1 = S.bounds
        hair = 1e-12 * max(x1 - x0, y1 - y0)
        if into:
            geom = _polygonal(shapely.difference(geom, shapely.difference(geom, S).buffer(hair)))
        else:
            geom = _polygonal(shapely.union(geom, shapely.difference(S, geom).buffer(hair)))
    return geom


def _core(S: Polygonal, r: float, q: int, centres: bool = True, exact=None, sampled: bool = True) -> Polygonal:
    """The core sampled from its exact boundary (`_sampled`), inside S. Where that is not available, from
    GEOS's shrink, snapped onto the exact corners and given back the exact pieces GEOS loses (parts
    exactly 2r wide, whose closed shrink is a centre line: `centers.missing_lines`). With
    ``centres=False``, GEOS's opening as it is (Mason's second opening, where its vertices are kept);
    ``sampled=False``, the GEOS construction even where the exact one is available (a reference
    independent of `exact_morphology`, for the tests). ``exact``: S's exact shrink (`_exact(S, r, 1)`)
    if already computed."""
    from .centers import missing_lines, snap_onto, snap_window

    if centres:
        exact = _exact(S, r, 1) if exact is None else exact
        R = _sampled(S, r, q, "core", exact) if sampled else None
        if R is not None:
            return _orient(_nudge(_polygonal(shapely.intersection(R, S)), S, into=True)) if not R.is_empty else R
        E = snap_onto(_shrink_raw(S, r, q), exact.corners, 1, snap_window(S, r, q))
    else:
        E = _shrink_raw(S, r, q)
    R = _grow_raw(E, r, q) if not E.is_empty else Polygon()
    if centres:
        extra = missing_lines(exact, E, r, GUIDE_MISSING_R, np.pi / (2 * q))
        if extra is not None:
            R = shapely.union(R, extra.buffer(r, quad_segs=q))
    if R.is_empty:
        return Polygon()
    R = _polygonal(shapely.intersection(R, S))
    return _orient(_nudge(R, S, into=True))


def _fillet(S: Polygonal, r: float, q: int, centres: bool = True, exact=None, sampled: bool = True) -> Polygonal:
    """The fillet sampled from its exact boundary (`_sampled`), around S. Where that is not available,
    from GEOS's grow, snapped onto the exact corners, with the gaps GEOS closes that an r-disk passes
    (exactly 2r wide or wider by any margin: `centers.missing_lines`) opened again. With
    ``centres=False``, GEOS's closing as it is; ``sampled=False``, the GEOS construction even where the
    exact one is available. ``exact``: `_exact(S, r, -1)` if already computed."""
    from .centers import missing_lines, snap_onto, snap_window

    if centres:
        exact = _exact(S, r, -1) if exact is None else exact
        F = _sampled(S, r, q, "fillet", exact) if sampled else None
        if F is not None:
            return _orient(_nudge(_polygonal(shapely.union(F, S)), S, into=False))
        G = snap_onto(_grow_raw(S, r, q), exact.corners, -1, snap_window(S, r, q))
    else:
        G = _grow_raw(S, r, q)
    F = shapely.union(_shrink_raw(G, r, q), S)
    if centres:
        extra = missing_lines(exact, G, r, GUIDE_MISSING_R, np.pi / (2 * q))
        if extra is not None:
            F = shapely.difference(F, shapely.difference(extra.buffer(r, quad_segs=q), S))
    return _orient(_nudge(_polygonal(F), S, into=False))


def grow(S, r: float, *, tolerance: float | None = None, exact: bool = False) -> Polygonal | list:
    """Grow ``S`` by ``r``: ``S↑r``, the points at distance < r from S (dilation by an open disk).

    The exact boundary (segments parallel to S's edges, arcs of radius r about its convex vertices) with
    its arcs sampled by chords within ``tolerance``.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float
        Radius, > 0, in the shape's units.
    tolerance : float, optional
        Largest distance between an arc of the exact result and the chord replacing it (default 1e-5·r).
        Chords lie inside the exact set, so the result is contained in ``S↑r``.
    exact : bool, optional
        Return the exact boundary of ``S↑r`` as a list of `Loop` (segments parallel to S's edges at
        distance r, arcs of radius exactly r about its convex vertices; see `exact_morphology.exact_grow`).
        Outer boundaries counter-clockwise, holes clockwise; ``tolerance`` is then unused, and S may
        also be a list of `Loop`s (its arcs then kept exactly as features).

    Returns
    -------
    Polygon or MultiPolygon
        Valid geometry, exteriors counter-clockwise.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> round(grow(box(0, 0, 2, 2), 1.0).area, 4)    # 4 + 8 + π
    15.1416
    """
    if exact:
        from .exact_morphology import exact_boundary

        return exact_boundary(S, r, "grow")
    S, r, q = _prepare(S, r, tolerance)
    return _orient(_grow(S, r, q))


def shrink(S, r: float, *, tolerance: float | None = None, exact: bool = False) -> Polygonal | list:
    """Shrink ``S`` by ``r``: ``S↓r``, the points at distance ≥ r from ¬S (erosion); may be empty.

    Its convex vertices are the centres of the core's convex arcs (see `arc_centers`). The exact
    boundary with its (concave) arcs sampled by chords within ``tolerance``.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float
        Radius, > 0.
    tolerance : float, optional
        Chord tolerance for the concave arcs that appear around reflex vertices (default 1e-5·r).
    exact : bool, optional
        Return the exact boundary of ``S↓r`` as a list of `Loop` (segments parallel to S's edges at
        distance r, arcs of radius exactly r about its reflex vertices; zero-width parts left out; see
        `exact_morphology.exact_shrink`): the tool-centre path of a pocket.
        Outer boundaries counter-clockwise, holes clockwise; ``tolerance`` is then unused, and S may
        also be a list of `Loop`s (its arcs then kept exactly as features).

    Returns
    -------
    Polygon or MultiPolygon
        Possibly empty.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> shrink(box(0, 0, 4, 3), 1.0).bounds
    (1.0, 1.0, 3.0, 2.0)
    >>> shrink(box(0, 0, 4, 3), 1.5).is_empty
    True
    """
    if exact:
        from .exact_morphology import exact_boundary

        return exact_boundary(S, r, "shrink")
    S, r, q = _prepare(S, r, tolerance)
    return _orient(_shrink(S, r, q))


def core(S, r: float, *, tolerance: float | None = None, exact: bool = False) -> Polygonal | list:
    """The core ``R_r(S) = S↓r↑r``: the union of all disks of radius r inside S (opening).

    Its exact boundary (S's surviving edges, arcs of radius r about the shrink's corners: what
    ``exact=True`` returns) with every arc replaced by chords within ``tolerance``, which lie inside the
    disks; exactly contained in S, and valid. No buffer is involved unless that construction is not
    available (two parts of the shrink touching at one point): then GEOS's opening, snapped onto the
    exact corners.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float or (float, float)
        Radius, > 0; or a pair ``(r_convex, r_concave)`` (`vectortighten.two_radii`): the core is taken at ``r_convex`` (S itself if it is 0).
    tolerance : float, optional
        Chord tolerance of the convex arcs of radius r (default 1e-5·r); the chords lie inside the disks.
    exact : bool, optional
        Return the exact boundary of the core as a list of `Loop` (S's surviving edges and arcs of
        radius exactly r about the shrink's corners; see `exact_morphology.exact_core` for the derivation).
        Outer boundaries counter-clockwise, holes clockwise; ``tolerance`` is then unused, and S may
        also be a list of `Loop`s (its arcs then kept exactly as features).

    Returns
    -------
    Polygon or MultiPolygon
        Possibly empty (when no disk of radius r fits in S).

    Examples
    --------
    >>> from math import pi
    >>> from shapely.geometry import box
    >>> R = core(box(0, 0, 4, 4), 1.0)
    >>> abs(R.area - (16 - (4 - pi))) < 1e-4          # a² − (4 − π)r²
    True
    """
    r = _side_radius(r, 0)
    if r is _ZERO:                                    # (a pair whose convex radius is 0)
        S = _orient(check_shape(S))
        return _ring_loops(S) if exact else S
    if exact:
        from .exact_morphology import exact_boundary

        return exact_boundary(S, r, "core")
    S, r, q = _prepare(S, r, tolerance)
    return _core(S, r, q)


def fillet(S, r: float, *, tolerance: float | None = None, exact: bool = False) -> Polygonal | list:
    """The fillet ``F_r(S) = S↑r↓r``: the complement of all disks of radius r in ¬S (closing).

    Its exact boundary (what ``exact=True`` returns) with every arc replaced by chords within
    ``tolerance``; exactly contains S, and valid. GEOS's closing, snapped onto the exact corners, only
    where that construction is not available.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float or (float, float)
        Radius, > 0; or a pair ``(r_convex, r_concave)`` (`vectortighten.two_radii`): the fillet is taken at ``r_concave`` (S itself if it is 0).
    tolerance : float, optional
        Chord tolerance of the concave arcs of radius r (default 1e-5·r).
    exact : bool, optional
        Return the exact boundary of the fillet as a list of `Loop` (S's surviving edges and arcs of radius
        exactly r, turning right; see `exact_morphology.exact_fillet`).
        Outer boundaries counter-clockwise, holes clockwise; ``tolerance`` is then unused, and S may
        also be a list of `Loop`s (its arcs then kept exactly as features).

    Returns
    -------
    Polygon or MultiPolygon

    Examples
    --------
    >>> from math import pi
    >>> from shapely.geometry import Polygon
    >>> L = Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)])
    >>> abs(fillet(L, 1.0).area - (L.area + 1 - pi / 4)) < 1e-4   # (1 − π/4)r² at the reflex corner
    True
    """
    r = _side_radius(r, 1)
    if r is _ZERO:                                    # (a pair whose concave radius is 0)
        S = _orient(check_shape(S))
        return _ring_loops(S) if exact else S
    if exact:
        from .exact_morphology import exact_boundary

        return exact_boundary(S, r, "fillet")
    S, r, q = _prepare(S, r, tolerance)
    return _fillet(S, r, q)


def mortar(S, r: float, *, tolerance: float | None = None) -> Polygonal:
    """The mortar ``M_r(S) = F_r(S) − R_r(S)``: corners, gaps, thin parts and small components.

    The exact mortar also has zero-width parts (where the boundary of S is r-regular); a polygon cannot
    hold them, so the result is the closure of the mortar's interior.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float or (float, float)
        Radius, > 0; or a pair ``(r_convex, r_concave)``: then ``F_{r_concave}(S) − R_{r_convex}(S)``.
    tolerance : float, optional
        Chord tolerance (default 1e-5·r).

    Returns
    -------
    Polygon or MultiPolygon
        Possibly empty (S is r-regular).

    Examples
    --------
    >>> from math import pi
    >>> from shapely.geometry import box
    >>> abs(mortar(box(0, 0, 4, 4), 1.0).area - (4 - pi)) < 1e-4   # the four convex corners
    True
    """
    from .two_radii import is_pair

    if is_pair(r):
        R, F = core(S, r, tolerance=tolerance), fillet(S, r, tolerance=tolerance)
        return _orient(_polygonal(shapely.difference(F, R)))
    S, r, q = _prepare(S, r, tolerance)
    return _orient(_polygonal(shapely.difference(_fillet(S, r, q), _core(S, r, q))))


def _window(S: Polygonal, r: float, window) -> Polygon:
    if window is None:
        x0, y0, x1, y1 = S.bounds
        return box(x0 - 2 * r, y0 - 2 * r, x1 + 2 * r, y1 + 2 * r)
    if isinstance(window, BaseGeometry):
        return check_shape(window, "window")
    x0, y0, x1, y1 = (float(v) for v in window)
    if not (x1 > x0 and y1 > y0):
        raise ValueError(f"window must be (minx, miny, maxx, maxy) with max > min, got {window!r}")
    return box(x0, y0, x1, y1)


def anticore(S, r: float, window=None, *, tolerance: float | None = None) -> Polygonal:
    """The anticore ``¬F_r(S)`` inside a window: the union of all disks of radius r in ¬S.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float
        Radius, > 0.
    window : (minx, miny, maxx, maxy) or shapely Polygon, optional
        Where to represent the (unbounded) anticore. Default: the bounds of S grown by 2r.
    tolerance : float, optional
        Chord tolerance (default 1e-5·r).

    Returns
    -------
    Polygon or MultiPolygon
        ``window − F_r(S)``.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> A = anticore(box(0, 0, 4, 4), 1.0)
    >>> A.bounds, len(A.interiors)
    ((-2.0, -2.0, 6.0, 6.0), 1)
    """
    S, r, q = _prepare(S, r, tolerance)
    return _orient(_polygonal(shapely.difference(_window(S, r, window), _fillet(S, r, q))))


def tolerance_zone(S, r: float, *, tolerance: float | None = None) -> Polygonal:
    """The tolerance zone ``Z_r(S) = (∂S)↑r``: points within r of the boundary of S.

    The mortar is ``Z_r(S)↓r``, a subset of it.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> round(tolerance_zone(box(0, 0, 4, 4), 1.0).area, 3)      # (6² − 2²) − (4 − π)
    31.142
    """
    S, r, q = _prepare(S, r, tolerance)
    return _orient(_polygonal(S.boundary.buffer(r, quad_segs=q)))


def round_fillet(S, r: float, *, tolerance: float | None = None) -> Polygonal:
    """``R_r∘F_r(S)``: fillet, then round (closing followed by opening). Biased to add material.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> two = box(0, 0, 4, 4).union(box(4.5, 0, 8.5, 4))     # a gap of 0.5 < 2r is bridged
    >>> round_fillet(two, 1.0).geom_type
    'Polygon'
    """
    S, r, q = _prepare(S, r, tolerance)
    F = _fillet(S, r, q)
    return _core(F, r, q) if not F.is_empty else F


def fillet_round(S, r: float, *, tolerance: float | None = None) -> Polygonal:
    """``F_r∘R_r(S)``: round, then fillet (opening followed by closing). Biased to remove material.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> bar = box(0, 0, 10, 1)                                # thinner than 2r: removed
    >>> fillet_round(bar, 1.0).is_empty
    True
    """
    S, r, q = _prepare(S, r, tolerance)
    R = _core(S, r, q)
    return _fillet(R, r, q) if not R.is_empty else R


def pockets(S, r: float, *, tolerance: float | None = None) -> list[Polygon]:
    """The components of the mortar's interior (the places where a tightening may differ from S).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> len(pockets(box(0, 0, 4, 4), 1.0))                    # one per corner
    4
    """
    S, r, q = _prepare(S, r, tolerance)
    M = _polygonal(shapely.difference(_fillet(S, r, q), _core(S, r, q)))
    return _pockets(M, 2.0 * check_tolerance(tolerance, r))


def _pockets(M: Polygonal, eps: float) -> list[Polygon]:
    """The components of M's interior: parts of M joined only by slivers narrower than ``2·eps``, which
    the chord approximations of the core's and the fillet's arcs leave where two pockets meet, are
    separated (each part keeps the material within ``2·eps`` of its opened interior)."""
    parts = list(shapely.get_parts(M))
    if not parts:
        return []
    opened = [p for p in shapely.get_parts(_polygonal(M.buffer(-eps, join_style="mitre"))) if not p.is_empty]
    if len(opened) <= len(parts):
        return parts
    pieces = shapely.intersection(shapely.buffer(opened, 2 * eps, join_style="mitre"), M)
    return [g for p in pieces for g in shapely.get_parts(_polygonal(p))
            if g.geom_type == "Polygon" and g.area > 0]


def mason(S, r: float, *, tolerance: float | None = None) -> Polygonal:
    """The self-dual Mason filter (Williams & Rossignac, §4.2).

    Outside the mortar the result is S (the core, and nothing of the anticore). Inside each component P of
    the mortar's interior it is ``R_r(F_r(S)) ∩ P`` or ``F_r(R_r(S)) ∩ P``, whichever differs less from
    ``S ∩ P`` (area of the symmetric difference); a tie takes ``R_r∘F_r``.

    Returns
    -------
    Polygon or MultiPolygon
        Valid; ``core(S) ⊆ mason(S) ⊆ fillet(S)``.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> M = mason(box(0, 0, 10, 1).union(box(0, 0, 1, 10)), 1.0)   # a thin L: every pocket vanishes
    >>> M.is_empty
    True
    """
    S, r, q = _prepare(S, r, tolerance)
    return _mason(S, r, q, check_tolerance(tolerance, r))


def _mason(S: Polygonal, r: float, q: int, tol: float, exact=None, r_concave: float | None = None) -> Polygonal:
    """`mason` on a checked S; ``exact``: S's exact offsets ``(side +1, side −1)`` if already computed
    (the engine has them), used only if they are of this S (bit for bit).

    With ``r_concave = b`` (two radii, `two_radii`; r is then the convex radius a, either may be 0): the
    core is R_a(S), the fillet F_b(S), and each pocket takes ``R_a(F_b(S))`` or ``F_b(R_a(S))``, whichever
    differs less from S there (a radius 0 leaves its operation out: R_0 and F_0 are the identity).
    """
    a = r
    b = r if r_concave is None else r_concave
    qb = q if r_concave is None else (quad_segs_for(b, tol) if b > 0 else 0)
    xE = xG = None
    if exact is not None and shapely.equals_exact(_orient(S), _orient(exact[2]), tolerance=0.0):
        xE, xG = exact[0], exact[1]
    R = _core(S, a, q, exact=xE) if a > 0 else _orient(S)
    F = _fillet(S, b, qb, exact=xG) if b > 0 else _orient(S)
    M = _polygonal(shapely.difference(F, R))
    if M.is_empty:
        return R
    # The second opening and closing work on chords of arcs of radius r: the exact centres that `_core`
    # and `_fillet` refine from S's own features would be refined from those chords here (a third of
    # Mason's time on many holes, and no more exact), so their vertices stay GEOS's. They are only ever
    # overlaid with a pocket P ⊆ F − R, so the overlays that put R∘F inside F and F∘R around R (a second
    # of noding along the nearly coincident boundaries on 64 holes) are left out: P ∩ R∘F ⊆ F already,
    # and R adds nothing to P but its boundary; the result is put between R and F once, at the end.
    if a > 0:
        E_F = _shrink_raw(F, a, q)
        RF = _grow_raw(E_F, a, q) if not E_F.is_empty else Polygon()
    else:
        RF = F
    if b > 0:
        FR = _shrink_raw(_grow_raw(R, b, qb), b, qb) if not R.is_empty else R
    else:
        FR = R
    parts = _pockets(M, 2.0 * tol)
    in_s, in_rf, in_fr = (_per_part(parts, X) for X in (S, RF, FR))
    d_rf = shapely.area(shapely.symmetric_difference(in_rf, in_s))
    d_fr = shapely.area(shapely.symmetric_difference(in_fr, in_s))
    chosen = [rf if a <= b else fr for rf, fr, a, b in zip(in_rf, in_fr, d_rf, d_fr)]
    # Stitch the chosen pieces to the core; a closing by a tiny distance would not be exact, so the
    # shared boundaries are merged by the union itself (they come from the same polygons).
    # Only the pieces' polygons: an overlay's result may hold lines and points along the pocket's edges
    # (thousands on many holes), which the union would node into R's boundary only to drop them.
    pieces = [g for g in shapely.get_parts(np.asarray(chosen, dtype=object)) if g.geom_type == "Polygon"]
    out = _attach(R, pieces, F)
    if out is None:
        out = shapely.union_all([R, *pieces])
        out = _polygonal(shapely.intersection(_polygonal(out), F))
    # (After `_attach`, the union with R also takes in the slivers under an ulp wide that its overlays
    # leave along R's edges, whose vertices the nudge below would push across their other side: a
    # self-intersection, and a make_valid of the whole, 0.5 s on 64 holes.)
    out = _polygonal(shapely.union(out, R))
    out = _nudge(out, R, into=False)
    return _orient(_between(out, R, F))


def _attach(R: Polygonal, pieces: list[Polygon], F: Polygonal) -> Polygonal | None:
    """``R ∪ (⋃ pieces ∩ F)`` computed near each ring of R that the pieces touch; None where that is not
    the same set, for the caller's overlays of the whole (which cost the noding of all of R and F, ~10⁵
    vertices along nearly coincident boundaries on many holes).

    The pieces lie outside R, in the mortar, and touch it along its boundary. Pieces that intersect one
    another are grouped; a group meeting one hole H of R only shrinks it, to ``Polygon(H) − U`` (U: the
    group's union ∩ F, with F clipped to U's box); a group meeting one exterior E only grows it, to
    ``Polygon(E) ∪ U`` (whose holes become holes of that part); a group meeting no ring and farther than
    rounding from R is a part of its own. A group that an overlay left a rounding gap (under 256 ulps)
    away from one ring is welded to it: its vertices that near the ring are inserted into the ring, and
    the ring's that near it into the group, so that the two share those points. What ``Polygon(H) − U``
    encloses comes back as parts. As R ⊆ F, ``(R ∪ ⋃ pieces) ∩ F ∪ R`` is this set. None if a group
    meets two rings, if a grown exterior is not one polygon, or if the result is not valid.
    """
    polys = [g for g in pieces if not g.is_empty and g.area > 0]
    R = _orient(R)
    parts = list(shapely.get_parts(R))
    if not polys or not parts:
        return None
    rings, owner, is_hole = [], [], []
    for k, p in enumerate(parts):
        for i, ring in enumerate(shapely.get_rings(p)):
            rings.append(ring), owner.append(k), is_hole.append(i > 0)
    polys_a = np.asarray(polys, dtype=object)
    group = list(range(len(polys)))

    def find(i: int) -> int:
        while group[i] != i:
            group[i] = group[group[i]]
            i = group[i]
        return i

    a, b = shapely.STRtree(polys_a).query(polys_a, predicate="intersects")
    for i, j in zip(a.tolist(), b.tolist()):
        if i < j:
            group[find(i)] = find(j)
    members: dict[int, list[int]] = {}
    for i in range(len(polys)):
        members.setdefault(find(i), []).append(i)
    x0, y0, x1, y1 = F.bounds
    gap = 256.0 * float(np.spacing(max(map(abs, F.bounds))))
    ring_tree = shapely.STRtree(rings)
    pi, ri = ring_tree.query(polys_a, predicate="intersects")
    touched: dict[int, set[int]] = {}
    for i, j in zip(pi.tolist(), ri.tolist()):
        touched.setdefault(find(i), set()).add(j)
    by_ring: dict[int, list[int]] = {}
    weld: dict[int, list[int]] = {}
    loose: list[int] = []
    for g, idx in members.items():
        t = touched.get(g)
        if t is None:
            near = np.unique(ring_tree.query(polys_a[idx], predicate="dwithin", distance=gap)[1])
            t = set(near.tolist())
            if len(t) == 1:
                weld.setdefault(next(iter(t)), []).extend(idx)
        if len(t) > 1:
            return None
        if t:
            by_ring.setdefault(next(iter(t)), []).extend(idx)
        else:
            loose.extend(idx)
    rings = list(rings)
    for j, idx in weld.items():
        welded = _weld(rings[j], polys_a[idx], gap)
        if welded is None:
            return None
        rings[j], polys_a[idx] = welded
    pad = 1e-6 * max(x1 - x0, y1 - y0)

    def in_f(idx: list[int]) -> Polygonal:
        U = _polygonal(shapely.union_all(polys_a[idx]))
        if U.is_empty:
            return U
        u0, v0, u1, v1 = U.bounds
        return _polygonal(shapely.intersection(U, shapely.clip_by_rect(F, u0 - pad, v0 - pad, u1 + pad, v1 + pad)))

    extra: list[Polygon] = []
    shells: list = [None] * len(parts)
    holes: list[list] = [[] for _ in parts]
    added: list[list] = [[] for _ in parts]
    for j, ring in enumerate(rings):
        k, idx = owner[j], by_ring.get(j)
        if not is_hole[j]:
            shells[k] = ring
            if idx:
                grown = _polygonal(shapely.union(Polygon(ring), in_f(idx)))
                if grown.geom_type != "Polygon" and j not in weld:
                    welded = _weld(ring, polys_a[idx], gap)          # a piece an ulp off: weld, again
                    if welded is None:
                        return None
                    ring, polys_a[idx] = welded
                    grown = _polygonal(shapely.union(Polygon(ring), in_f(idx)))
                if grown.geom_type != "Polygon":
                    return None
                shells[k] = grown.exterior
                added[k] = list(grown.interiors)
            continue
        if not idx:
            holes[k].append(ring)
            continue
        U = in_f(idx)
        left = _polygonal(shapely.difference(Polygon(ring), U))
        if j not in weld and any(len(g.interiors) for g in shapely.get_parts(left)):
            welded = _weld(ring, polys_a[idx], gap)        # a piece touching H at a point, an ulp off
            if welded is None:                             # along a stretch: weld, again
                return None
            ring, polys_a[idx] = welded
            U = in_f(idx)
            left = _polygonal(shapely.difference(Polygon(ring), U))
        for g in shapely.get_parts(left):
            if g.is_empty:                                 # (the hole is filled)
                continue
            holes[k].append(g.exterior)
            for inner in g.interiors:
                extra += list(shapely.get_parts(_polygonal(shapely.intersection(Polygon(inner), U))))
    out = [Polygon(shells[k], added[k] + holes[k]) for k in range(len(parts))]
    if loose:
        out += list(shapely.get_parts(in_f(loose)))
    out = [g for g in out + extra if not g.is_empty]
    result = out[0] if len(out) == 1 else MultiPolygon(out)
    return result if result.is_valid else None


def _weld(ring, polys: np.ndarray, gap: float):
    """``ring`` and ``polys`` with the vertices of each that lie within ``gap`` of the other's edges (but
    are not already vertices of it) inserted into the other's nearest edge; None if that fails."""
    rc = shapely.get_coordinates(ring)
    pr = [[shapely.get_coordinates(x) for x in shapely.get_rings(p)] for p in polys]
    pc = np.concatenate([c for rr in pr for c in rr])
    own = _keys_in(pc, rc)
    near = ~own & shapely.dwithin(ring, shapely.points(pc), gap)
    new_ring = _insert_into_edges([rc], np.unique(pc[near], axis=0), gap) if near.any() else [rc]
    if new_ring is None:
        return None
    flat = [c for rr in pr for c in rr]
    U = shapely.multipolygons(polys) if len(polys) > 1 else polys[0]
    back = ~_keys_in(rc, pc) & shapely.dwithin(U.boundary, shapely.points(rc), gap)
    if back.any():
        flat = _insert_into_edges(flat, rc[back], gap)
        if flat is None:
            return None
    out, k = [], 0
    for rr in pr:
        out.append(Polygon(flat[k], flat[k + 1:k + len(rr)]))
        k += len(rr)
    return shapely.linearrings(new_ring[0]), np.asarray(out, dtype=object)


def _per_part(parts: list[Polygon], X: Polygonal) -> np.ndarray:
    """``P ∩ X`` for every pocket P, each overlay given only X clipped to (a hair around) P's box.

    An overlay of a small pocket with the whole of X costs the size of X every time (hundreds of pockets
    on a shape with many holes); ``clip_by_rect`` is a linear scan without noding, and leaves the overlay
    the few edges that matter. The clip is exact inside the box, which holds P.
    """
    if not parts or X.is_empty:
        return shapely.intersection(np.asarray(parts, dtype=object), X)
    x0, y0, x1, y1 = X.bounds
    pad = 1e-6 * max(x1 - x0, y1 - y0)
    local = [shapely.clip_by_rect(X, p0 - pad, q0 - pad, p1 + pad, q1 + pad)
             for p0, q0, p1, q1 in shapely.bounds(parts).tolist()]
    return shapely.intersection(np.asarray(parts, dtype=object), np.asarray(local, dtype=object))


def _between(geom: Polygonal, R: Polygonal, F: Polygonal) -> Polygonal:
    """``geom`` moved by rounding errors so that ``R ⊆ geom ⊆ F`` holds exactly, if that is enough.

    Where the mortar thins out (a pocket's tip, where ∂R meets ∂F tangentially, or along zero-width parts)
    an overlay's computed vertex lands an ulp outside F, or an edge of ``geom`` cuts an ulp across a
    vertex of F or of R. The vertices of F strictly inside ``geom`` and those of R strictly outside it are
    inserted into its nearest edge; every other vertex strictly outside F, or strictly inside R, is moved
    onto the nearest edge of F (of R) and then by the fewest ulps along its normal that put it in
    ``closure(F) − interior(R)``. Each step is a spatial-index query per vertex (O(n log n)). ``geom`` is
    returned unchanged if the result is not valid or the inclusions still fail.
    """
    if geom.is_empty or R.is_empty:
        return geom
    shapely.prepare(F)
    shapely.prepare(R)

    def holds(g) -> bool:
        shapely.prepare(g)
        return F.covers(g) and g.covers(R)

    if holds(geom):
        return geom
    x0, y0, x1, y1 = F.bounds
    # How far rounding can put a vertex: the old snap's reach, or a few hundred ulps of the coordinates.
    reach = max(ZERO_SCALE * max(x1 - x0, y1 - y0), 256.0 * float(np.spacing(max(map(abs, F.bounds)))))
    parts = [_orient(p) for p in shapely.get_parts(geom)]
    rings = [shapely.get_coordinates(ring) for p in parts for ring in shapely.get_rings(p)]
    cf, cr = shapely.get_coordinates(F), shapely.get_coordinates(R)
    extra = np.concatenate([cf[shapely.contains_xy(geom, cf[:, 0], cf[:, 1])],
                            cr[~shapely.intersects_xy(geom, cr[:, 0], cr[:, 1])]])
    if len(extra):
        rings = _insert_into_edges(rings, extra, reach)
        if rings is None:
            return geom                               # a vertex far inside (outside): a real violation
    coords = np.concatenate(rings)
    fixed = _keys_in(coords, np.concatenate([cf, cr]))
    free = np.flatnonzero(~fixed)                     # (only these are tested: F's and R's own stay)
    for target, inside in ((F, True), (R, False)):
        x, y = coords[free, 0], coords[free, 1]
        bad = free[~shapely.intersects_xy(target, x, y) if inside else shapely.contains_xy(target, x, y)]
        if len(bad):
            moved = _onto(coords[bad], target, F, R, reach)
            if moved is None:
                return geom
            coords[bad] = moved
    x, y = coords[free, 0], coords[free, 1]
    drop = np.zeros(len(coords), dtype=bool)
    drop[free] = ~shapely.intersects_xy(F, x, y) | shapely.contains_xy(R, x, y)
    out, k = [], 0
    sizes = np.cumsum([0] + [len(c) for c in rings])
    for p in parts:
        n = 1 + len(p.interiors)
        rr = []
        for i in range(n):
            c, gone = coords[sizes[k + i]:sizes[k + i + 1]], drop[sizes[k + i]:sizes[k + i + 1]]
            if gone.any():
                # No representable point lies in closure(F) − interior(R) there (∂R and ∂F less than an
                # ulp apart): the vertex is left out, its neighbours joined.
                keep = ~gone[:-1]
                c = c[:-1][keep]
                c = np.concatenate([c, c[:1]]) if len(c) >= 3 else c
            rr.append(c)
        if any(len(c) < 4 for c in rr):
            return geom
        out.append(Polygon(rr[0], rr[1:]))
        k += n
    result = out[0] if len(out) == 1 else MultiPolygon(out)
    if result.is_valid and holds(result):
        return result
    return geom


def _keys_in(coords: np.ndarray, pool: np.ndarray) -> np.ndarray:
    """Whether each point of ``coords`` is (bit for bit) one of the points of ``pool``."""
    keys = np.sort(pool[:, 0] + 1j * pool[:, 1])
    k = coords[:, 0] + 1j * coords[:, 1]
    return keys[np.clip(np.searchsorted(keys, k), 0, len(keys) - 1)] == k


def _insert_into_edges(rings: list[np.ndarray], points: np.ndarray, reach: float) -> list[np.ndarray] | None:
    """Closed rings with each point inserted into the edge nearest to it, in order along the edge; None if
    a point is farther than ``reach`` from every edge."""
    a = np.concatenate([c[:-1] for c in rings])
    b = np.concatenate([c[1:] for c in rings])
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    edge, dist = tree.query_nearest(shapely.points(points), all_matches=False, return_distance=True)
    edge = edge[1]
    if (dist > reach).any():
        return None
    d = b[edge] - a[edge]
    t = np.einsum("ij,ij->i", points - a[edge], d) / np.einsum("ij,ij->i", d, d)
    order = np.lexsort((t, edge))
    edge, points = edge[order], points[order]
    out, start = [], 0
    for c in rings:
        m = len(c) - 1
        lo, hi = np.searchsorted(edge, [start, start + m])
        if lo == hi:
            out.append(c)
        else:
            # Each inserted point goes after the start of its edge; np.insert keeps their order.
            out.append(np.insert(c, edge[lo:hi] - start + 1, points[lo:hi], axis=0))
        start += m
    return out


def _onto(points: np.ndarray, target: Polygonal, F: Polygonal, R: Polygonal, reach: float) -> np.ndarray | None:
    """Each point projected onto the nearest edge of ``target``, then moved along that edge's normal by
    the fewest ulps (0, 1, 2, 4, … either way) that put it in ``closure(F) − interior(R)``; a point for
    which 64 steps are not enough is left where it was. None if a point is farther than ``reach`` from
    ``target``'s boundary (not a rounding error)."""
    a, b = _edges(_orient(target))
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    edge = tree.query_nearest(shapely.points(points), all_matches=False)[1]
    d = b[edge] - a[edge]
    t = np.clip(np.einsum("ij,ij->i", points - a[edge], d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
    foot = a[edge] + t[:, None] * d
    if (np.hypot(*(foot - points).T) > reach).any():
        return None
    normal = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
    ulp = np.spacing(np.abs(foot).max(axis=1))[:, None]
    out = points.copy()
    todo = np.ones(len(points), dtype=bool)
    for step in [0.0] + [s * 2.0 ** k for k in range(32) for s in (1.0, -1.0)]:
        trial = foot[todo] + step * ulp[todo] * normal[todo]
        ok = (shapely.intersects_xy(F, trial[:, 0], trial[:, 1])
              & ~shapely.contains_xy(R, trial[:, 0], trial[:, 1]))
        idx = np.flatnonzero(todo)[ok]
        out[idx] = trial[ok]
        todo[idx] = False
        if not todo.any():
            break
    return out
