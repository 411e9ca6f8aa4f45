"""Exact centres of the arcs of radius r on the boundaries of the core and of the fillet.

The convex arcs of ``∂R_r(S)`` are centred at the convex vertices of ``S↓r``; the concave arcs of
``∂F_r(S)`` at the reflex vertices of ``S↑r``. Each such centre is a medial-axis point of clearance exactly
r: at distance r from two boundary features of S (an edge's line or a vertex). Shapely's buffers place
these vertices only approximately (chords replace arcs, and GEOS simplifies its input by up to about
r/100); the exact centres are the corners of S's exact offsets (`offsets.exact_offsets`, from S's edges
alone), and every buffered shrink or grow used here, the public ones and the engine's guide alike, has
its corner vertices moved onto them by one rule (`snap_onto` within `snap_window`).
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import LineString, MultiPolygon, Point, Polygon

from ._validation import check_radius, check_shape, check_tolerance
from .curves import Side
from .tolerances import ANGLE_ZERO, CENTER_SEARCH_R, GUIDE_MISSING_R, ZERO_SCALE

__all__ = ["ArcCenters", "arc_centers", "boundary_edges", "missing_lines", "snap_onto", "snap_window"]


def boundary_edges(S: Polygon | MultiPolygon) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The edges of an oriented S: start points, end points ``(m, 2)`` and the index of each edge's successor.

    Edge ``i`` runs from vertex ``i`` to vertex ``next[i]``; S lies on the left of every edge when S is
    oriented (exteriors counter-clockwise, holes clockwise).
    """
    starts, ends, nexts = [], [], []
    offset = 0
    for ring in shapely.get_rings(shapely.get_parts(S)):
        c = shapely.get_coordinates(ring)
        n = len(c) - 1
        starts.append(c[:-1])
        ends.append(c[1:])
        nexts.append(offset + (np.arange(n) + 1) % n)
        offset += n
    if not starts:
        empty = np.zeros((0, 2))
        return empty, empty, np.zeros(0, dtype=np.int64)
    return np.concatenate(starts), np.concatenate(ends), np.concatenate(nexts)


@dataclass(frozen=True)
class ArcCenters:
    """Centres of the arcs of radius r of the core (side +1) and of the fillet (side −1).

    Attributes
    ----------
    xy : (n, 2) float
        Exact centres.
    side : (n,) int8
        `Side.CORE` (+1) for a centre inside S (a convex vertex of ``S↓r``), `Side.ANTICORE` (−1) for one
        outside (a reflex vertex of ``S↑r``).
    features : (n, 2) int64
        The two boundary features of S at distance exactly r: ``2·i`` is the line of edge ``i``,
        ``2·i + 1`` is vertex ``i`` (the start of edge ``i``); −1 where the centre could not be refined.
    exact : (n,) bool
        True where the centre was solved exactly from its two features.
    source : (n, 2) float
        The vertex of a buffered polygon each centre was refined from; NaN for the centres of
        `exact_centers`, which come from S's exact offsets and no buffer.
    edge_start, edge_end : (m, 2) float
        The edges of S that the feature numbers refer to.
    r : float
        The radius.
    """

    xy: np.ndarray
    side: np.ndarray
    features: np.ndarray
    exact: np.ndarray
    source: np.ndarray
    edge_start: np.ndarray
    edge_end: np.ndarray
    r: float

    def __len__(self) -> int:
        return len(self.xy)

    def feature_geometry(self, key: int) -> LineString | Point:
        """The feature numbered ``key``: the edge (a LineString) or the vertex (a Point)."""
        i, kind = divmod(int(key), 2)
        if kind == 0:
            return LineString([self.edge_start[i], self.edge_end[i]])
        return Point(self.edge_start[i])

    def feature_distances(self) -> np.ndarray:
        """``(n, 2)`` distance from each centre to each of its two features (edge segment or vertex)."""
        out = np.full(self.features.shape, np.nan)
        for j in range(2):
            key = self.features[:, j]
            ok = key >= 0
            idx, kind = np.divmod(key[ok], 2)
            out[ok, j] = _distance_to_feature(self.xy[ok], self.edge_start[idx], self.edge_end[idx], kind)
        return out

    def of_side(self, side: Side | int) -> np.ndarray:
        """Indices of the centres of one side."""
        return np.flatnonzero(self.side == int(side))


def _distance_to_feature(p, a, b, kind):
    """Distance from points p to segments ab (kind 0) or to points a (kind 1)."""
    d = b - a
    L2 = np.einsum("ij,ij->i", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(np.einsum("ij,ij->i", p - a, d) / L2, 0.0, 1.0)
    t = np.where(L2 > 0, t, 0.0)
    t = np.where(kind == 1, 0.0, t)
    foot = a + t[:, None] * d
    return np.hypot(*(p - foot).T)


def _turns(ring_coords: np.ndarray) -> np.ndarray:
    """Sine of the turning angle at each vertex of a closed ring (first point repeated at the end)."""
    c = ring_coords[:-1]
    u = c - np.roll(c, 1, axis=0)
    v = np.roll(c, -1, axis=0) - c
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    norm = np.hypot(*u.T) * np.hypot(*v.T)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, cross / norm, 0.0)


def _corner_vertices(P, convex: bool) -> np.ndarray:
    """Vertices of an oriented polygon where it turns left (convex) or right (reflex), ``(k, 2)``."""
    out = []
    for ring in shapely.get_rings(shapely.get_parts(P)):
        c = shapely.get_coordinates(ring)
        if len(c) < 4:
            continue
        s = _turns(c)
        pick = s > ANGLE_ZERO if convex else s < -ANGLE_ZERO
        out.append(c[:-1][pick])
    return np.concatenate(out) if out else np.zeros((0, 2))


def arc_centers(S, r: float, *, tolerance: float | None = None) -> ArcCenters:
    """Exact centres of the convex arcs of the core and of the concave arcs of the fillet.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        The shape.
    r : float
        Radius, > 0.
    tolerance : float, optional
        Chord tolerance of the buffers used to find the centres approximately (default 1e-5·r).

    Returns
    -------
    ArcCenters
        The centres (side +1: convex vertices of ``S↓r``, inside S; side −1: reflex vertices of ``S↑r``,
        outside S), each with the two features of S at distance exactly r from it.

    Notes
    -----
    Each vertex of the buffered polygon is matched with the boundary features of S whose distance from it
    is within a narrow band around r, and the exact point at distance r from two of them is solved for.
    Vertices that cannot be matched (degenerate input) keep their approximate position, with
    ``exact = False``.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> C = arc_centers(box(0, 0, 4, 3), 1.0)
    >>> sorted(map(tuple, C.xy[C.side == 1].round(12).tolist()))
    [(1.0, 1.0), (1.0, 2.0), (3.0, 1.0), (3.0, 2.0)]
    >>> float(abs(C.feature_distances() - 1.0).max()) < 1e-12
    True
    """
    r = check_radius(r)
    S = check_shape(S)
    check_tolerance(tolerance, r)
    return exact_centers(S, r)[0]


def exact_centers(S, r: float, precision: float | None = None, r_concave: float | None = None):
    """The exact arc centres of both sides from S's exact offsets, and those offsets (side +1, side −1).

    S must be valid (it is oriented here). Every centre is a corner of ``S↓r`` or of ``(S^c)↓r``
    (`vectortighten.offsets`), found from S's edges alone; each is given the two features of S nearest
    to it (at distance r to rounding). ``precision``: as in `offsets.exact_offsets`. ``r_concave``: the
    radius of side −1 when it differs from r (two radii: side +1 at r, side −1 at ``r_concave``).
    """
    from .morphology import _orient
    from .offsets import exact_offsets

    S = _orient(S)
    rb = r if r_concave is None else r_concave
    if r == 0 or rb == 0:
        # Two radii, one of them 0: that side's "shrink" is S itself (its own closure), its corners S's
        # convex (side +1) or reflex (−1) vertices (`_zero_radius`).
        from ._zero_radius import zero_offsets
        from .offsets import precision_of

        prec = precision_of(S) if precision is None else precision
        E = zero_offsets(S, 1, prec) if r == 0 else exact_offsets(S, r, 1, precision=precision)
        G = zero_offsets(S, -1, prec) if rb == 0 else exact_offsets(S, rb, -1, precision=precision)
    else:
        E = exact_offsets(S, r, 1, precision=precision)
        G = exact_offsets(S, rb, -1, precision=precision)
    xy = np.concatenate([E.corners, G.corners])
    side = np.concatenate([np.ones(len(E.corners), np.int8), -np.ones(len(G.corners), np.int8)])
    a, b, nxt = boundary_edges(S)
    if r_concave is None:
        features = _nearest_features(xy, a, b, nxt, r)
    else:
        features = np.concatenate([_nearest_features(E.corners, a, b, nxt, r),
                                   _nearest_features(G.corners, a, b, nxt, rb)]).reshape(-1, 2)
    C = ArcCenters(xy=xy, side=side, features=features, exact=np.ones(len(xy), dtype=bool),
                   source=np.full((len(xy), 2), np.nan), edge_start=a, edge_end=b, r=r)
    return C, E, G


def _nearest_features(xy, a, b, nxt, r):
    """For each point, the two distinct features of S (edge lines ``2i``, vertices ``2i+1``) nearest it."""
    out = np.full((len(xy), 2), -1, dtype=np.int64)
    if len(xy) == 0 or len(a) == 0:
        return out
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    pi, ei = tree.query(shapely.points(xy), predicate="dwithin", distance=r * (1 + 1e-6))
    d = b[ei] - a[ei]
    L2 = np.einsum("ij,ij->i", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.einsum("ij,ij->i", xy[pi] - a[ei], d) / L2
    t = np.where(L2 > 0, t, 0.0)
    key = np.where(t <= 0, 2 * ei + 1, np.where(t >= 1, 2 * nxt[ei] + 1, 2 * ei))
    dist = _distance_to_feature(xy[pi], a[ei], b[ei], np.zeros(len(ei), dtype=np.int64))
    order = np.lexsort((dist, pi))
    pi, key, dist = pi[order], key[order], dist[order]
    for p, k in zip(pi.tolist(), key.tolist()):
        row = out[p]
        if row[0] < 0:
            row[0] = k
        elif row[1] < 0 and k != row[0]:
            row[1] = k
    return out


def snap_onto(P, cxy: np.ndarray, side: int, window: float):
    """``P`` with each convex (side +1) or reflex (−1) vertex within ``window`` of a centre moved onto it."""
    if P.is_empty or len(cxy) == 0:
        return P
    from .morphology import _orient

    P = _orient(P)
    pts = _corner_vertices(P, convex=side > 0)
    if len(pts) == 0:
        return P
    d, j = cKDTree(cxy).query(pts, distance_upper_bound=window)
    ok = np.isfinite(d)
    return _move_vertices(P, pts[ok], cxy[j[ok]])


def missing_lines(X, P, r: float, far_r: float, max_angle: float):
    """The pieces and corners of the exact offsets ``X`` of one side that GEOS's buffer ``P`` lacks, as lines
    and points, or None.

    ``P`` is GEOS's shrink of S (side +1) or its grow (side −1). The closed shrink keeps the parts of S
    exactly 2r wide (their shrink is a centre line) and the grow's complement the gaps exactly 2r wide;
    GEOS's buffers lose them, and gaps or necks within GEOS's simplification (up to about r/100) of 2r
    wide are decided there by its vertices, not by the clearance. A piece whose middle lies farther than
    ``far_r``·r from the shrink (for the grow's complement: inside the grow, that far from its boundary)
    is one GEOS lacks. Arcs are drawn through points at most ``max_angle`` apart (their chords' sag is
    the error of a buffer of the lines).
    """
    lines = X.polylines(max_angle)
    # The corners too: an isolated point of the closed shrink (a square exactly 2r wide: its centre) is
    # a corner on no piece, and GEOS's shrink is empty there. A corner on a piece is found with it.
    corners = np.asarray(X.corners, dtype=float).reshape(-1, 2)
    if not lines and not len(corners):
        return None
    mids = np.array([0.5 * (pl[0] + pl[-1]) if len(pl) == 2 else pl[len(pl) // 2] for pl in lines]
                    ).reshape(-1, 2)
    pts = shapely.points(np.concatenate([mids, corners]))
    far = far_r * r
    if P.is_empty:
        keep = np.full(len(pts), X.side > 0)
    elif X.side > 0:
        shapely.prepare(P)                  # one predicate a point: indexed, not a scan of P per point
        keep = ~shapely.dwithin(P, pts, far)
    else:
        B = P.boundary
        shapely.prepare(B)
        keep = ~shapely.dwithin(B, pts, far)
        # Inside the grow only where it matters: nearly every piece lies on the grow's boundary, and a
        # point-in-polygon test costs O(n) a point where many edges span one height (a comb's teeth).
        if keep.sum() > 16:
            shapely.prepare(P)                  # indexed, for many points
        if keep.any():
            keep[keep] = shapely.contains(P, pts[keep])
    if not keep.any():
        return None
    geoms = [shapely.linestrings(pl) for pl, k in zip(lines, keep[:len(lines)]) if k]
    geoms += list(shapely.points(corners[keep[len(lines):]]))
    return shapely.union_all(np.array(geoms))


def snap_window(S, r: float, q: int) -> float:
    """How far a vertex of GEOS's shrink or grow of S may be moved onto an exact corner, in S's units.

    GEOS places an offset corner off by its chords' sag (``q`` segments a quarter circle), by rounding,
    and where it simplifies its input by up to about r/100 (more beside near-tangent necks); a vertex
    within this window of a corner of S's exact offsets stands for that corner (`snap_onto`).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> snap_window(box(0, 0, 4, 3), 1.0, 64)
    0.02
    """
    x0, y0, x1, y1 = S.bounds
    scale = max(x1 - x0, y1 - y0, r)
    sag = r * (1.0 - math.cos(math.pi / (4 * q)))
    return max(4.0 * sag + CENTER_SEARCH_R * r + ZERO_SCALE * scale, GUIDE_MISSING_R * r)


def _move_vertices(P, src: np.ndarray, dst: np.ndarray):
    """P with every vertex equal to a row of ``src`` moved to the matching row of ``dst``.

    Two vertices can move onto one point (GEOS places two crossings where S has one medial-axis vertex,
    and both refine to it): the repeated point is kept once, and a vertex between two copies of one
    point (a spike of zero area) is removed, so that the result stays a valid polygon.
    """
    if len(src) == 0:
        return P
    key = src[:, 0] + 1j * src[:, 1]
    order = np.argsort(key)
    key, dst = key[order], dst[order]

    def move(c):
        k = c[:, 0] + 1j * c[:, 1]
        j = np.clip(np.searchsorted(key, k), 0, len(key) - 1)
        hit = key[j] == k
        out = c.copy()
        out[hit] = dst[j[hit]]
        return out

    moved = shapely.transform(P, move)
    if moved.is_valid:
        return moved
    polys = []
    for part in shapely.get_parts(moved):
        rings = [_without_spikes(shapely.get_coordinates(ring)[:-1]) for ring in shapely.get_rings(part)]
        if len(rings[0]) >= 3:
            polys.append(Polygon(rings[0], [h for h in rings[1:] if len(h) >= 3]))
    out = polys[0] if len(polys) == 1 else MultiPolygon(polys) if polys else Polygon()
    if not out.is_valid:
        from .morphology import _polygonal

        out = _polygonal(shapely.make_valid(out))
    return out


def _without_spikes(c: np.ndarray) -> np.ndarray:
    """A ring's vertices (open) without repeated points and without vertices between two copies of one.

    The rule, applied until nothing changes or fewer than three vertices are left: drop every vertex
    equal to its successor; else take the first spike (a vertex whose neighbours are equal) and drop it
    and its successor (the second copy). Each removal changes only the neighbours of the join it makes,
    so the vertices are linked in a cycle and the spikes kept in a heap by position: O(n log n), the
    same vertices as applying the rule to the whole array each time.
    """
    if len(c) < 3:
        return c
    nxt0 = np.roll(c, -1, axis=0)
    dup = (c == nxt0).all(axis=1)
    if dup.any():
        c = c[~dup]
        if len(c) < 3:
            return c
    prv0, nxt0 = np.roll(c, 1, axis=0), np.roll(c, -1, axis=0)
    spikes = np.flatnonzero((prv0 == nxt0).all(axis=1))
    if len(spikes) == 0:
        return c
    xs, ys = c[:, 0].tolist(), c[:, 1].tolist()
    n = len(c)
    nxt = list(range(1, n)) + [0]
    prv = [n - 1] + list(range(n - 1))
    alive = [True] * n
    left = n

    def same(i, j):
        return xs[i] == xs[j] and ys[i] == ys[j]

    def drop(i):
        nonlocal left
        p, q = prv[i], nxt[i]
        nxt[p], prv[q] = q, p
        alive[i] = False
        left -= 1

    heap = spikes.tolist()              # ascending: already a heap
    while heap and left >= 3:
        i = heapq.heappop(heap)
        if not alive[i] or not same(prv[i], nxt[i]):
            continue
        j = nxt[i]
        drop(i)
        drop(j)
        if left < 3:
            break
        p, q = prv[j], nxt[j]           # the join the removal made
        if same(p, q):                  # a repeated point: the first copy goes
            pp = prv[p]
            drop(p)
            if left < 3:
                break
            p = pp
        for k in (p, q):
            if same(prv[k], nxt[k]):
                heapq.heappush(heap, k)
    return c[np.asarray(alive)]




