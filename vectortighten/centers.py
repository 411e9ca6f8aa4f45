"""Exact centres of the arcs of radius r on the boundaries of the core and of the fillet.

The convex arcs of ``∂R_r(S)`` are centred at the convex vertices of ``S↓r``; the concave arcs of
``∂F_r(S)`` at the reflex vertices of ``S↑r``. Each such centre is a medial-axis point of clearance exactly
r: at distance r from two boundary features of S (an edge's line or a vertex). Shapely's buffers place
these vertices only approximately (chords replace arcs); here each is recomputed as the exact solution of
"distance r from feature A and from feature B" (line–line, line–point or point–point).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import LineString, MultiPolygon, Point, Polygon

from ._proximity import EdgeIndex, point_segment_distance
from ._validation import check_radius, check_shape, check_tolerance
from .curves import Side
from .tolerances import ANGLE_ZERO, CENTER_SEARCH_R, ZERO_SCALE

__all__ = ["ArcCenters", "arc_centers", "boundary_edges", "snap_to_centers"]


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


# Pairs of candidates among m features, in `itertools.combinations` order.
_COMBOS = {m: np.array(list(itertools.combinations(range(m), 2)), dtype=np.int64).reshape(-1, 2)
           for m in range(2, 7)}


def _hypot_rows(v: np.ndarray) -> np.ndarray:
    """``math.hypot`` of each row.

    Correctly rounded, unlike ``np.hypot`` on some platforms: the centres, and the snapped buffers built
    on them, do not change with the numpy build.
    """
    if len(v) == 0:
        return np.zeros(0)
    return _HYPOT(v[:, 0], v[:, 1]).astype(float)


_HYPOT = np.frompyfunc(math.hypot, 2, 1)


def _solve_pairs(p, fa, fb, a, b, r, side):
    """Points at distance r from feature ``fa[i]`` and from feature ``fb[i]``, for every row i at once.

    A feature is a key: ``2·e`` the line of edge e, ``2·e + 1`` vertex e (the start of edge e). A line
    feature stands for the edge's line offset by r toward ``side`` (left of the edge for +1, right for
    −1): line–line has one solution (for parallel lines, the projection of ``p`` onto the common offset),
    line–point and point–point have two (or none).

    Returns ``(row, k, xy)``: solution ``k`` (0 or 1) of row ``row``.
    """
    kinds_a, kinds_b = fa % 2, fb % 2
    swap = (kinds_a == 1) & (kinds_b == 0)
    ia = np.where(swap, fb // 2, fa // 2)
    ib = np.where(swap, fa // 2, fb // 2)
    rows, ks, sols = [], [], []

    def offset(i):
        d = b[i] - a[i]
        L = _hypot_rows(d)[:, None]
        n = np.column_stack([-d[:, 1], d[:, 0]]) / L
        return a[i] + side * r * n, n, d / L

    ll = np.flatnonzero((kinds_a == 0) & (kinds_b == 0))
    if len(ll):
        o1, n1, _ = offset(ia[ll])
        o2, n2, _ = offset(ib[ll])
        M = np.stack([n1, n2], axis=1)
        rhs = np.column_stack([np.vecdot(n1, o1), np.vecdot(n2, o2)])
        det = np.linalg.det(M)
        flat = np.abs(det) < 1e-12
        sol = np.empty((len(ll), 2))
        if flat.any():
            # Parallel offset lines: the solutions form a line; keep the projection of p onto it.
            pf, of, nf = p[ll[flat]], o1[flat], n1[flat]
            sol[flat] = pf - np.vecdot(pf - of, nf)[:, None] * nf
        if (~flat).any():
            sol[~flat] = np.linalg.solve(M[~flat], rhs[~flat][:, :, None])[:, :, 0]
        rows.append(ll)
        ks.append(np.zeros(len(ll), dtype=np.int64))
        sols.append(sol)
    pp = np.flatnonzero((kinds_a == 1) & (kinds_b == 1))
    if len(pp):
        q1, q2 = a[ia[pp]], a[ib[pp]]
        m = 0.5 * (q1 + q2)
        h = 0.5 * _hypot_rows(q2 - q1)
        ok = ~((h == 0) | (h > r * (1 + 1e-12)))
        pp, q1, q2, m, h = pp[ok], q1[ok], q2[ok], m[ok], h[ok]
        off = np.sqrt(np.maximum(r * r - h * h, 0.0))[:, None]
        d = (q2 - q1) / (2 * h)[:, None]
        n = np.column_stack([-d[:, 1], d[:, 0]])
        rows += [pp, pp]
        ks += [np.zeros(len(pp), dtype=np.int64), np.ones(len(pp), dtype=np.int64)]
        sols += [m + off * n, m - off * n]
    lp = np.flatnonzero(kinds_a != kinds_b)
    if len(lp):
        o, _, u = offset(ia[lp])
        wv = o - a[ib[lp]]
        beta = np.vecdot(u, wv)
        disc = beta * beta - (np.vecdot(wv, wv) - r * r)
        ok = ~(disc < -1e-9 * r * r)
        lp, o, u, beta, disc = lp[ok], o[ok], u[ok], beta[ok], disc[ok]
        root = np.sqrt(np.maximum(disc, 0.0))
        rows += [lp, lp]
        ks += [np.zeros(len(lp), dtype=np.int64), np.ones(len(lp), dtype=np.int64)]
        sols += [o + (-beta - root)[:, None] * u, o + (-beta + root)[:, None] * u]
    if not rows:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    return np.concatenate(rows), np.concatenate(ks), np.concatenate(sols)


def _ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The concatenation of ``arange(s, s + c)`` over the rows (vectorised)."""
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    offsets = np.cumsum(counts) - counts
    return np.repeat(starts - offsets, counts) + np.arange(total)


def _clear_of_listed(xy, owner, dev, chk_start, chk_dist, chk_edge, a, b, limit, tiny) -> np.ndarray:
    """Whether each point ``xy[i]`` is at distance ≥ ``limit`` from the edges listed for ``owner[i]``.

    An owner's edges are listed by increasing distance ``chk_dist`` from the owner (rows ``chk_start[o]``
    to ``chk_start[o + 1]``); a point ``dev[i]`` away from its owner can come nearer than ``limit`` only
    to those nearer than ``limit + dev[i]`` to the owner, a prefix found by binary search.
    """
    lo, hi = chk_start[owner], chk_start[owner + 1]
    bound = limit + dev + 2 * tiny
    left, right = lo.copy(), hi.copy()
    while True:
        active = left < right
        if not active.any():
            break
        mid = (left + right) // 2
        below = np.zeros(len(xy), dtype=bool)
        below[active] = chk_dist[mid[active]] < bound[active]
        left = np.where(active & below, mid + 1, left)
        right = np.where(active & ~below, mid, right)
    counts = left - lo
    rows = _ranges(lo, counts)
    if len(rows) == 0:
        return np.ones(len(xy), dtype=bool)
    e = chk_edge[rows]
    d = point_segment_distance(np.repeat(xy, counts, axis=0), a[e], b[e])
    low = np.full(len(xy), np.inf)
    has = counts > 0
    low[has] = np.minimum.reduceat(d, (np.cumsum(counts) - counts)[has])
    return low >= limit


_PAIR_FEATURES = 6                    # the features nearest to a point among which pairs are solved


def _candidates(points, owner, key, kd, a, b, r, side):
    """Every solution of every pair among each point's candidate features.

    ``owner``, ``key`` and ``kd`` list, sorted by owner and then by ``kd`` (the distance from the owner),
    the features (keys) near each point; the first `_PAIR_FEATURES` of each owner are paired.
    Returns ``(owner, fa, fb, order, xy)``: for each candidate its point, its two features, its rank
    among that point's pairs and solutions (``itertools.combinations`` order, then solution 0 before 1)
    and its position.
    """
    if len(owner) == 0:
        return (np.zeros(0, dtype=np.int64),) * 4 + (np.zeros((0, 2)),)
    starts = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1]])
    counts = np.minimum(np.diff(np.r_[starts, len(owner)]), _PAIR_FEATURES)
    OWN, FA, FB, ORD = [], [], [], []
    for m in np.unique(counts[counts >= 2]).tolist():
        g = starts[counts == m]
        C = key[g[:, None] + np.arange(m)[None, :]]
        I, J = _COMBOS[m][:, 0], _COMBOS[m][:, 1]
        OWN.append(np.repeat(owner[g], len(I)))
        FA.append(C[:, I].ravel())
        FB.append(C[:, J].ravel())
        ORD.append(np.tile(np.arange(len(I)), len(g)))
    if not OWN:
        return (np.zeros(0, dtype=np.int64),) * 4 + (np.zeros((0, 2)),)
    OWN, FA, FB, ORD = map(np.concatenate, (OWN, FA, FB, ORD))
    ok = ~((FA // 2 == FB // 2) & (FA % 2 != FB % 2))           # not an edge's line with its own start
    OWN, FA, FB, ORD = OWN[ok], FA[ok], FB[ok], ORD[ok]
    row, k, xy = _solve_pairs(points[OWN], FA, FB, a, b, r, side)
    return OWN[row], FA[row], FB[row], 2 * ORD[row] + k, xy


def _refine(points, side, a, b, nxt, index: EdgeIndex, r, window, scale, reach=None):
    """Exact centres near the approximate ``points`` (one side); returns xy, features, exact flags.

    Each point is matched with the features of S (edge lines, vertices) within ``r + w`` of it, and every
    pair among the nearest few is solved exactly. A solution counts when it lies at distance r from both
    its features and no nearer than r to any edge of S; the one nearest to the point is kept, provided it
    is within ``reach`` of it (default ``300·window``: GEOS's buffers may misplace a vertex by up to a
    hundredth of r where they simplify their input, and where two offset arcs cross at a shallow angle a
    chord moves the crossing far along them). The band widens (×10, ×100, ×300) for points still
    unmatched: an edge's line is offered only where the point's foot falls within ``w`` of the edge.
    """
    n = len(points)
    xy = points.copy()
    feats = np.full((n, 2), -1, dtype=np.int64)
    exact = np.zeros(n, dtype=bool)
    if n == 0:
        return xy, feats, exact
    tiny = ZERO_SCALE * scale
    limit = r * (1 - 1e-9) - tiny
    reach = 300 * window if reach is None else reach
    for w in (window, 10 * window, 100 * window, 300 * window):
        todo = np.flatnonzero(~exact)
        if len(todo) == 0:
            break
        pi, ei, dist = index.near_points(points[todo], r + w)
        pi = todo[pi]
        chk_start = np.r_[0, np.cumsum(np.bincount(pi, minlength=n))]       # pi is sorted
        # The features each edge offers: its line where the point's foot falls inside it, its ends where
        # the foot falls (close to) an end; each with its distance from the point.
        d = b[ei] - a[ei]
        L2 = np.einsum("ij,ij->i", d, d)
        t = np.einsum("ij,ij->i", points[pi] - a[ei], d) / L2
        slack = w / np.sqrt(L2)
        line, at0, at1 = (t > -slack) & (t < 1 + slack), t < slack, t > 1 - slack
        owner = np.concatenate([pi[line], pi[at0], pi[at1]])
        key = np.concatenate([2 * ei[line], 2 * ei[at0] + 1, 2 * nxt[ei[at1]] + 1])
        kd = _distance_to_feature(points[owner], a[key // 2], b[key // 2], key % 2)
        # Distinct (owner, key), sorted by owner, then distance, then key.
        if len(owner) == 0:
            continue                                  # no feature of S this near any point yet: widen
        order = np.lexsort((key, kd, owner))
        owner, key, kd = owner[order], key[order], kd[order]
        new = np.r_[True, (owner[1:] != owner[:-1]) | (key[1:] != key[:-1])]
        # (equal keys of one owner have equal distances, hence sit next to each other)
        owner, key, kd = owner[new], key[new], kd[new]
        own, fa, fb, rank, sol = _candidates(points, owner, key, kd, a, b, r, side)
        dev = np.hypot(*(sol - points[own]).T)
        good = np.isfinite(sol).all(axis=1) & (dev <= reach + tiny)
        for f in (fa, fb):
            good &= np.abs(_distance_to_feature(sol, a[f // 2], b[f // 2], f % 2) - r) <= 10 * tiny
        own, fa, fb, rank, sol, dev = own[good], fa[good], fb[good], rank[good], sol[good], dev[good]
        # Nearest first, a round at a time over each unmatched point's next candidate. Any edge nearer than
        # r to a solution within w of its point is among the point's own edges, so such a solution is
        # settled by them; a farther one that clears them is then checked against all edges, all such at
        # once, and where it fails the point's later candidates are tried.
        order = np.lexsort((rank, dev, own))
        own, fa, fb, sol, dev = own[order], fa[order], fb[order], sol[order], dev[order]
        first = np.flatnonzero(np.r_[True, own[1:] != own[:-1]]) if len(own) else np.zeros(0, np.int64)
        pos = np.arange(len(own)) - np.repeat(first, np.diff(np.r_[first, len(own)]))
        alive = np.ones(len(own), dtype=bool)
        while True:
            pick = np.full(n, -1, dtype=np.int64)         # each point's first candidate clear of its edges
            for j in range(int(pos.max()) + 1 if len(pos) else 0):
                at = np.flatnonzero((pos == j) & alive & ~exact[own])
                at = at[pick[own[at]] < 0]
                if len(at) == 0:
                    continue
                listed = _clear_of_listed(sol[at], own[at], dev[at], chk_start, dist, ei, a, b, limit, tiny)
                alive[at[~listed]] = False
                pick[own[at[listed]]] = at[listed]
            chosen = pick[pick >= 0]
            far = chosen[dev[chosen] > w]
            failed = far[~index.clear_of(sol[far], limit)]
            alive[failed] = False
            ok = np.setdiff1d(chosen, failed)
            k = own[ok]
            xy[k] = sol[ok]
            feats[k] = np.column_stack([fa[ok], fb[ok]])
            exact[k] = True
            if len(failed) == 0:
                break
    return xy, feats, exact


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


def exact_centers(S, r: float, precision: float | None = None):
    """The exact arc centres of both sides from S's exact offsets, and those offsets (side +1, side −1).

    S must be valid (it is oriented here). Every centre is a corner of ``S↓r`` or of ``(S^c)↓r``
    (`vectortighten.offsets`), found from S's edges alone; each is given the two features of S nearest
    to it (at distance r to rounding). ``precision``: as in `offsets.exact_offsets`.
    """
    from .morphology import _orient
    from .offsets import exact_offsets

    S = _orient(S)
    E = exact_offsets(S, r, 1, precision=precision)
    G = exact_offsets(S, r, -1, precision=precision)
    xy = np.concatenate([E.corners, G.corners])
    side = np.concatenate([np.ones(len(E.corners), np.int8), -np.ones(len(G.corners), np.int8)])
    a, b, nxt = boundary_edges(S)
    features = _nearest_features(xy, a, b, nxt, r)
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
    """The pieces of the exact offsets ``X`` of one side that GEOS's buffer ``P`` lacks, as lines, or None.

    ``P`` is GEOS's shrink of S (side +1) or its grow (side −1). The closed shrink keeps the parts of S
    exactly 2r wide (their shrink is a centre line) and the grow's complement the gaps exactly 2r wide;
    GEOS's buffers lose them, and gaps or necks within GEOS's simplification (up to about r/100) of 2r
    wide are decided there by its vertices, not by the clearance. A piece whose middle lies farther than
    ``far_r``·r from the shrink (for the grow's complement: inside the grow, that far from its boundary)
    is one GEOS lacks. Arcs are drawn through points at most ``max_angle`` apart (their chords' sag is
    the error of a buffer of the lines).
    """
    lines = X.polylines(max_angle)
    if not lines:
        return None
    mids = shapely.points(np.array([0.5 * (pl[0] + pl[-1]) if len(pl) == 2 else pl[len(pl) // 2]
                                    for pl in lines]))
    far = far_r * r
    if P.is_empty:
        keep = np.ones(len(lines), dtype=bool) if X.side > 0 else np.zeros(len(lines), dtype=bool)
    elif X.side > 0:
        keep = ~shapely.dwithin(P, mids, far)
    else:
        keep = shapely.contains(P, mids) & ~shapely.dwithin(P.boundary, mids, far)
    if not keep.any():
        return None
    return shapely.union_all(np.array([shapely.linestrings(pl) for pl, k in zip(lines, keep) if k]))


def _search_window(S, r: float, q: int) -> tuple[float, float]:
    x0, y0, x1, y1 = S.bounds
    scale = max(x1 - x0, y1 - y0, r)
    sag = r * (1.0 - math.cos(math.pi / (4 * q)))
    return 4.0 * sag + CENTER_SEARCH_R * r + ZERO_SCALE * scale, scale


def snap_to_centers(P, S, r: float, q: int, side: int):
    """``P`` (the shrink of S for side +1, its grow for −1) with its convex (reflex) vertices moved onto
    the exact arc centres they approximate; vertices that cannot be refined stay where they are."""
    if P.is_empty:
        return P
    from .morphology import _orient

    P = _orient(P)
    pts = _corner_vertices(P, convex=side > 0)
    if len(pts) == 0:
        return P
    a, b, nxt = boundary_edges(S)
    window, scale = _search_window(S, r, q)
    xy, _, exact = _refine(pts, side, a, b, nxt, EdgeIndex(a, b, r), r, window, scale)
    return _move_vertices(P, pts[exact], xy[exact])


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
    """A ring's vertices (open) without repeated points and without vertices between two copies of one."""
    while len(c) >= 3:
        nxt = np.roll(c, -1, axis=0)
        dup = (c == nxt).all(axis=1)
        if dup.any():
            c = c[~dup]
            continue
        prv = np.roll(c, 1, axis=0)
        spike = (prv == nxt).all(axis=1)
        if not spike.any():
            break
        i = int(np.flatnonzero(spike)[0])
        c = np.delete(c, [i, (i + 1) % len(c)], axis=0)
    return c




