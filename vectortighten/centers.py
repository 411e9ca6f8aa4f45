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
from shapely.geometry import LineString, MultiPolygon, Point, Polygon

from ._validation import check_radius, check_shape, check_tolerance, quad_segs_for
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
        The vertex of the buffered polygon each centre was refined from.
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


# -- the three exact constructions ----------------------------------------------------------------------
def _solve_pair(p, fa, fb, a, b, r, side):
    """Points at distance r from features fa and fb (keys), on the side of S given by ``side``.

    Returns candidate solutions (list of (2,) arrays). A line feature is the line of the edge, offset by r
    toward the side of S (left of the edge for side +1, right for −1).
    """
    kinds = (fa % 2, fb % 2)
    ia, ib = fa // 2, fb // 2
    if kinds == (0, 0):
        return _line_line(a[ia], b[ia], a[ib], b[ib], r, side, p)
    if kinds == (1, 1):
        return _point_point(a[ia], a[ib], r)
    if kinds[0] == 1:
        ia, ib = ib, ia
    return _line_point(a[ia], b[ia], a[ib], r, side)


def _offset_line(a, b, r, side):
    d = b - a
    n = np.array([-d[1], d[0]]) / math.hypot(*d)
    return a + side * r * n, d / math.hypot(*d), n


def _line_line(a1, b1, a2, b2, r, side, p):
    o1, u1, n1 = _offset_line(a1, b1, r, side)
    o2, u2, n2 = _offset_line(a2, b2, r, side)
    M = np.array([n1, n2])
    rhs = np.array([n1 @ o1, n2 @ o2])
    det = np.linalg.det(M)
    if abs(det) < 1e-12:
        # Parallel offset lines: the solutions form a line; keep the projection of p onto it.
        return [p - ((p - o1) @ n1) * n1]
    return [np.linalg.solve(M, rhs)]


def _line_point(a, b, q, r, side):
    o, u, n = _offset_line(a, b, r, side)
    w = o - q
    beta = u @ w
    disc = beta * beta - (w @ w - r * r)
    if disc < -1e-9 * r * r:
        return []
    root = math.sqrt(max(disc, 0.0))
    return [o + (-beta - root) * u, o + (-beta + root) * u]


def _point_point(q1, q2, r):
    m = 0.5 * (q1 + q2)
    h = 0.5 * math.hypot(*(q2 - q1))
    if h == 0 or h > r * (1 + 1e-12):
        return []
    off = math.sqrt(max(r * r - h * h, 0.0))
    d = (q2 - q1) / (2 * h)
    n = np.array([-d[1], d[0]])
    return [m + off * n, m - off * n]


def _solve_many(p, fa, fb, a, b, r, side):
    """Vectorised solve of "distance r from feature fa and from feature fb", nearest solution to p.

    Returns ``(m, 2)`` solutions (NaN where there is none or the case is degenerate).
    """
    fa, fb = fa.copy(), fb.copy()
    swap = (fa % 2 == 1) & (fb % 2 == 0)
    fa[swap], fb[swap] = fb[swap], fa[swap]
    ia, ib = fa // 2, fb // 2
    out = np.full((len(p), 2), np.nan)

    def offset(i):
        d = b[i] - a[i]
        L = np.hypot(d[:, 0], d[:, 1])[:, None]
        u = d / L
        n = np.column_stack([-u[:, 1], u[:, 0]])
        return a[i] + side * r * n, u, n

    ll = (fa % 2 == 0) & (fb % 2 == 0)
    if ll.any():
        o1, u1, n1 = offset(ia[ll])
        o2, u2, n2 = offset(ib[ll])
        det = n1[:, 0] * n2[:, 1] - n1[:, 1] * n2[:, 0]
        r1 = (n1 * o1).sum(axis=1)
        r2 = (n2 * o2).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = (r1 * n2[:, 1] - r2 * n1[:, 1]) / det
            y = (n1[:, 0] * r2 - n2[:, 0] * r1) / det
        sol = np.column_stack([x, y])
        sol[np.abs(det) < 1e-12] = np.nan
        out[ll] = sol
    lp = (fa % 2 == 0) & (fb % 2 == 1)
    if lp.any():
        o, u, _ = offset(ia[lp])
        q = a[ib[lp]]
        w = o - q
        beta = (u * w).sum(axis=1)
        disc = beta * beta - ((w * w).sum(axis=1) - r * r)
        root = np.sqrt(np.maximum(disc, 0.0))
        c1 = o + (-beta - root)[:, None] * u
        c2 = o + (-beta + root)[:, None] * u
        pick = np.hypot(*(c1 - p[lp]).T) <= np.hypot(*(c2 - p[lp]).T)
        sol = np.where(pick[:, None], c1, c2)
        sol[disc < -1e-9 * r * r] = np.nan
        out[lp] = sol
    pp = (fa % 2 == 1) & (fb % 2 == 1)
    if pp.any():
        q1, q2 = a[ia[pp]], a[ib[pp]]
        m = 0.5 * (q1 + q2)
        h = 0.5 * np.hypot(*(q2 - q1).T)
        off = np.sqrt(np.maximum(r * r - h * h, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            d = (q2 - q1) / (2 * h)[:, None]
        n = np.column_stack([-d[:, 1], d[:, 0]])
        c1, c2 = m + off[:, None] * n, m - off[:, None] * n
        pick = np.hypot(*(c1 - p[pp]).T) <= np.hypot(*(c2 - p[pp]).T)
        sol = np.where(pick[:, None], c1, c2)
        sol[(h == 0) | (h > r * (1 + 1e-12))] = np.nan
        out[pp] = sol
    return out


# Pairs of candidates among m features, in `itertools.combinations` order.
_COMBOS = {m: np.array(list(itertools.combinations(range(m), 2)), dtype=np.int64).reshape(-1, 2)
           for m in range(2, 7)}


def _hypot_rows(v: np.ndarray) -> np.ndarray:
    """``math.hypot`` of each row (as the one-point solvers compute it, to the last bit)."""
    if len(v) == 0:
        return np.zeros(0)
    return _HYPOT(v[:, 0], v[:, 1]).astype(float)


_HYPOT = np.frompyfunc(math.hypot, 2, 1)


def _solve_pairs(p, fa, fb, a, b, r, side):
    """`_solve_pair` for many (point, feature, feature) rows at once, with the same arithmetic.

    Returns ``(row, k, xy)``: solution ``k`` (0 or 1, in `_solve_pair`'s order) of row ``row``.
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


def _refine_all_pairs(points, pairs, starts, counts, exact, xy, feats, a, b, r, side, w, tiny, tree):
    """For each point not yet solved with two or more features in the band: the solution over all pairs
    of its features (the six nearest to r when there are more) nearest to the point, that lies within the
    window, at distance r from both features and no nearer than r to any feature of S. Updates ``xy``,
    ``feats`` and ``exact`` in place.

    Same as trying every pair of every point one at a time, first solution kept among equally near ones.
    Near a junction of the medial axis three or more features lie at about r from the point; the pair
    whose solution is nearest may then give a point closer than r to a third feature, which is no centre
    (a coarse buffer places its vertex nearer to that wrong solution than to the right one).
    """
    owner = pairs[starts, 0]
    grp = np.flatnonzero((counts >= 2) & ~exact[owner])
    if len(grp) == 0:
        return
    # The candidate features of each group: all, or the six nearest to r.
    cands: dict[int, list] = {}
    many = grp[counts[grp] > 6]
    if len(many):
        lens = counts[many]
        rows = np.repeat(starts[many], lens) + (np.arange(lens.sum()) - np.repeat(np.cumsum(lens) - lens, lens))
        keys = pairs[rows, 1]
        dd_all = _distance_to_feature(points[pairs[rows, 0]], a[keys // 2], b[keys // 2], keys % 2)
        off = 0
        for g, c in zip(many.tolist(), lens.tolist()):
            dd = dd_all[off:off + c]
            cand = pairs[starts[g]:starts[g] + c, 1][np.argsort(np.abs(dd - r))[:6]]
            cands.setdefault(6, []).append((g, cand))
            off += c
    few = grp[counts[grp] <= 6]
    for c in np.unique(counts[few]).tolist():
        g = few[counts[few] == c]
        block = pairs[starts[g][:, None] + np.arange(c)[None, :], 1]
        cands.setdefault(c, []).extend(zip(g.tolist(), block))
    G, FA, FB, ORD = [], [], [], []
    for m, items in cands.items():
        gs = np.array([g for g, _ in items], dtype=np.int64)
        C = np.stack([cand for _, cand in items])
        I, J = _COMBOS[m][:, 0], _COMBOS[m][:, 1]
        G.append(np.repeat(gs, len(I)))
        FA.append(C[:, I].ravel())
        FB.append(C[:, J].ravel())
        ORD.append(np.tile(np.arange(len(I)), len(gs)))
    G, FA, FB, ORD = map(np.concatenate, (G, FA, FB, ORD))
    ok = ~((FA // 2 == FB // 2) & (FA % 2 != FB % 2))
    G, FA, FB, ORD = G[ok], FA[ok], FB[ok], ORD[ok]
    P = points[owner[G]]
    row, k, sol = _solve_pairs(P, FA, FB, a, b, r, side)
    dev = _hypot_rows(sol - P[row])
    good = dev <= w + tiny
    row, k, sol, dev = row[good], k[good], sol[good], dev[good]
    for F in (FA, FB):
        f = F[row]
        dd = _distance_to_feature(sol, a[f // 2], b[f // 2], f % 2)
        keep = np.abs(dd - r) <= 10 * tiny
        row, k, sol, dev = row[keep], k[keep], sol[keep], dev[keep]
    if len(row) == 0:
        return
    hit, _ = tree.query(shapely.points(sol), predicate="dwithin", distance=r * (1 - 1e-9) - tiny)
    clear = np.ones(len(row), dtype=bool)
    clear[hit] = False
    row, k, sol, dev = row[clear], k[clear], sol[clear], dev[clear]
    if len(row) == 0:
        return
    # Nearest solution of each group; among equally near ones the first tried (pair order, then solution).
    order = np.lexsort((k, ORD[row], dev, G[row]))
    gs = G[row][order]
    first = order[np.r_[True, gs[1:] != gs[:-1]]]
    kk = owner[G[row[first]]]
    xy[kk] = sol[first]
    feats[kk] = np.column_stack([FA[row[first]], FB[row[first]]])
    exact[kk] = True


def _refine(points, side, a, b, nxt, tree, r, window, scale):
    """Exact centres near the approximate ``points`` (one side); returns xy, features, exact flags.

    Each point is matched with the features of S (edge lines, vertices) whose distance from it lies in a
    band of half-width ``w`` around r; the common case of exactly two is solved vectorised, the rest one by
    one over all pairs. The band widens (×10, ×100, ×300) for points still unmatched: GEOS's buffers may
    misplace a vertex by up to a hundredth of r where it simplifies its input.
    """
    n = len(points)
    xy = points.copy()
    feats = np.full((n, 2), -1, dtype=np.int64)
    exact = np.zeros(n, dtype=bool)
    if n == 0:
        return xy, feats, exact
    tiny = ZERO_SCALE * scale
    for w in (window, 10 * window, 100 * window, 300 * window):
        todo = np.flatnonzero(~exact)
        if len(todo) == 0:
            break
        pi, ei = tree.query(shapely.points(points[todo]), predicate="dwithin", distance=r + w)
        pi = todo[pi]
        p = points[pi]
        d = b[ei] - a[ei]
        L2 = np.einsum("ij,ij->i", d, d)
        t = np.einsum("ij,ij->i", p - a[ei], d) / L2
        tc = np.clip(t, 0.0, 1.0)
        dist = np.hypot(*(p - (a[ei] + tc[:, None] * d)).T)
        near = np.abs(dist - r) <= w
        pi, ei, t = pi[near], ei[near], t[near]
        # An edge whose nearest point is (close to) an end contributes that vertex; one whose nearest point
        # is inside contributes its line; near an end it contributes both and the solve decides.
        slack = w / np.sqrt(L2[near])
        line = (t > -slack) & (t < 1 + slack)
        at0 = t < slack
        at1 = t > 1 - slack
        keys = np.concatenate([2 * ei[line], 2 * ei[at0] + 1, 2 * nxt[ei[at1]] + 1])
        owners = np.concatenate([pi[line], pi[at0], pi[at1]])
        # Distinct (owner, key) pairs in lexicographic order, through one integer key (fast to sort).
        base = 2 * len(a) + 2
        code = np.unique(owners.astype(np.int64) * base + keys)
        pairs = np.column_stack([code // base, code % base])
        if len(pairs) == 0:
            continue
        starts = np.flatnonzero(np.r_[True, pairs[1:, 0] != pairs[:-1, 0]])
        counts = np.diff(np.r_[starts, len(pairs)])
        # Two features, not an edge's line with its own end: solve all at once.
        two = starts[counts == 2]
        fa, fb = pairs[two, 1], pairs[two + 1, 1]
        ok = ~((fa // 2 == fb // 2) & (fa % 2 != fb % 2))
        two, fa, fb = two[ok], fa[ok], fb[ok]
        k = pairs[two, 0]
        sol = _solve_many(points[k], fa, fb, a, b, r, side)
        good = np.isfinite(sol).all(axis=1) & (np.hypot(*(sol - points[k]).T) <= w + tiny)
        fk = np.column_stack([fa, fb])
        for j in range(2):
            dd = _distance_to_feature(sol, a[fk[:, j] // 2], b[fk[:, j] // 2], fk[:, j] % 2)
            good &= np.abs(dd - r) <= 10 * tiny
        xy[k[good]] = sol[good]
        feats[k[good]] = fk[good]
        exact[k[good]] = True
        # Three or more features (or a failed pair): every pair, nearest solution (all points at once).
        _refine_all_pairs(points, pairs, starts, counts, exact, xy, feats, a, b, r, side, w, tiny, tree)
    # A centre must keep distance r from every feature, not just its two.
    if exact.any():
        idx = np.flatnonzero(exact)
        hit, _ = tree.query(shapely.points(xy[idx]), predicate="dwithin", distance=r * (1 - 1e-9) - tiny)
        bad = idx[np.unique(hit)]
        exact[bad] = False
        xy[bad] = points[bad]
        feats[bad] = -1
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
    tol = check_tolerance(tolerance, r)
    q = quad_segs_for(r, tol)
    from .morphology import _grow_raw, _orient, _shrink_raw

    return _arc_centers(S, r, _orient(_shrink_raw(S, r, q)), _orient(_grow_raw(S, r, q)), q)


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
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    window, scale = _search_window(S, r, q)
    xy, _, exact = _refine(pts, side, a, b, nxt, tree, r, window, scale)
    return _move_vertices(P, pts[exact], xy[exact])


def _move_vertices(P, src: np.ndarray, dst: np.ndarray):
    """P with every vertex equal to a row of ``src`` moved to the matching row of ``dst``."""
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

    return shapely.transform(P, move)


def _snap_vertices(P, centers: ArcCenters, side: int):
    """``P`` with each vertex that a centre of ``side`` was refined from moved onto that exact centre."""
    pick = (centers.side == side) & centers.exact
    return _move_vertices(P, centers.source[pick], centers.xy[pick]) if not P.is_empty else P


def _arc_centers(S, r, E, G, q) -> ArcCenters:
    a, b, nxt = boundary_edges(S)
    tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
    window, scale = _search_window(S, r, q)
    out_xy, out_side, out_feat, out_exact, out_src = [], [], [], [], []
    for side, P, convex in ((1, E, True), (-1, G, False)):
        pts = _corner_vertices(P, convex) if not P.is_empty else np.zeros((0, 2))
        xy, feats, exact = _refine(pts, side, a, b, nxt, tree, r, window, scale)
        out_src.append(pts)
        out_xy.append(xy)
        out_side.append(np.full(len(xy), side, dtype=np.int8))
        out_feat.append(feats)
        out_exact.append(exact)
    return ArcCenters(
        xy=np.concatenate(out_xy),
        side=np.concatenate(out_side),
        features=np.concatenate(out_feat),
        exact=np.concatenate(out_exact),
        source=np.concatenate(out_src),
        edge_start=a,
        edge_end=b,
        r=r,
    )
