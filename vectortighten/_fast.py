"""The fast path of the engine: shapes whose corners are all isolated.

When every vertex of S has room for its own disk of radius r — inside S at a convex vertex, outside at a
reflex one, tangent to both edges at points that fit on them — and those arcs meet neither the core nor
the anticore elsewhere, the tight loop of each ring of S is that ring with every corner replaced by the
arc of its disk. This is checked, vectorised, in a few passes over the vertices; no triangulation is built.
When any check fails the caller falls back to the general engine.

Why the checks suffice: the straight pieces lie on the boundary of S, which never meets the (open) core or
anticore; a valid disk at a convex vertex lies in S, so its arc cannot enter the anticore, and an arc that
does not enter the core lies on its boundary (and symmetrically at reflex vertices). The region between
a ring and its tightened loop is a union of corner cusps, none of which can hold a disk of radius r, so
the loop is homotopic to the ring in the mortar.

How it is checked: from the edges of S alone, never from GEOS's buffers (which simplify dense input by up
to r/100, more than any slack could allow). Disk centres and straight pieces must keep distance r from
every edge (`_closer_than`: a k-d tree over the vertices, exact distances for the few candidates); points
along each arc must keep distance r from the shrink's boundary (convex vertices) or the grow's (reflex
ones), which the offset edges and the arcs around the other kind of vertex contain (`_arcs_clear`). The
arcs are sampled every π/16: a violation between two samples and shallower than the sampling's sagitta
can go unseen.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .tolerances import ANGLE_ZERO

__all__: list[str] = []

_TWO_PI = 2.0 * math.pi
_EXACT = 1e-9         # relative slack of the exact distance tests (rounding only)


def _clean_ring(c: np.ndarray) -> np.ndarray:
    """Ring vertices without the closing point, repeated points or straight (collinear) vertices."""
    pts = c[:-1]
    keep = np.any(pts != np.roll(pts, -1, axis=0), axis=1)
    pts = pts[keep]
    for _ in range(3):
        if len(pts) < 3:
            return pts
        u = pts - np.roll(pts, 1, axis=0)
        v = np.roll(pts, -1, axis=0) - pts
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        dot = (u * v).sum(axis=1)
        sine = cross / (np.hypot(*u.T) * np.hypot(*v.T))
        straight = (np.abs(sine) < ANGLE_ZERO) & (dot > 0)
        if not straight.any():
            return pts
        pts = pts[~straight]
    return pts


class _Rings:
    """Per-vertex data of all rings of S, concatenated (vertex i, edge i from vertex i to next[i])."""

    def __init__(self, S, r: float):
        rings = [_clean_ring(shapely.get_coordinates(ring)) for ring in shapely.get_rings(shapely.get_parts(S))]
        self.ok = all(len(v) >= 3 for v in rings)
        if not self.ok:
            return
        self.r = r
        sizes = [len(v) for v in rings]
        start = np.cumsum([0] + sizes[:-1])
        self.slices = [slice(a, a + n) for a, n in zip(start, sizes)]
        self.v = np.concatenate(rings)
        self.next = np.concatenate([a + (np.arange(n) + 1) % n for a, n in zip(start, sizes)])
        self.prev = np.concatenate([a + (np.arange(n) - 1) % n for a, n in zip(start, sizes)])
        u = self.v[self.next] - self.v
        self.ell = np.hypot(*u.T)
        self.u = u / self.ell[:, None]                                 # direction of edge i
        self.n = np.column_stack([-self.u[:, 1], self.u[:, 0]])         # its left normal (into S)
        u_in = self.u[self.prev]
        cross = u_in[:, 0] * self.u[:, 1] - u_in[:, 1] * self.u[:, 0]
        dot = (u_in * self.u).sum(axis=1)
        self.theta = np.arctan2(cross, dot)                             # turn at vertex i, left positive
        self.side = np.where(self.theta > 0, 1.0, -1.0)
        n_in = self.n[self.prev]
        self.c = self.v + (self.side * r / (1.0 + dot))[:, None] * (n_in + self.n)
        self.t = r * np.tan(np.abs(self.theta) / 2)
        self.length = self.ell - self.t - self.t[self.next]             # straight piece on edge i
        self.phi = np.arctan2(self.u[:, 1], self.u[:, 0])

    @property
    def vertex_tree(self) -> cKDTree:
        """A k-d tree over the vertices, built once for every exact proximity test."""
        if getattr(self, "_vertex_tree", None) is None:
            self._vertex_tree = _tree(self.v)
        return self._vertex_tree

    def offsets(self, side: int) -> np.ndarray:
        """Edges moved by r into S (side +1) or out of it (−1), cut at the disks' centres on that side.

        At an end whose disk is on the other side, the offset runs to the end of the edge (where the arc
        of radius r around that vertex starts).
        """
        i, j = np.arange(len(self.v)), self.next
        a = np.where((self.side[i] == side)[:, None], self.c[i], self.v[i] + side * self.r * self.n)
        b = np.where((self.side[j] == side)[:, None], self.c[j], self.v[j] + side * self.r * self.n)
        return np.stack([a, b], axis=1)

    def arcs(self, side: int):
        """Arcs of radius r around the vertices whose disk is on the other side: centres, start, sweep.

        For side +1 these are the concave arcs of the shrink around the reflex vertices (directions from
        the incoming edge's inward normal to the outgoing one's); for −1 the convex arcs of the grow
        around the convex vertices.
        """
        k = np.flatnonzero(self.side != side)
        n_in, n_out = self.n[self.prev[k]], self.n[k]
        if side < 0:
            n_in, n_out = -n_in, -n_out
        start = np.arctan2(n_in[:, 1], n_in[:, 0])
        return self.v[k], start, self.theta[k]


def fast_disk_loops(S, r: float, q: int, init: str):
    """Disk loops ``[(centers, sides, phi, lengths, sweeps), ...]`` for every ring of S, or None.

    ``S`` is oriented (S on the left of every ring), in the engine's local frame.
    """
    D = _Rings(S, r)
    if not D.ok or (np.abs(D.theta) > math.pi - 1e-6).any():
        return None                                     # a spike: no disk fits its corner
    if (D.length < -1e-12 * np.maximum(D.ell, r)).any():
        return None                                     # two disks do not fit on one edge
    length = np.maximum(D.length, 0.0)
    shapely.prepare(S)
    if not _centers_valid(D, S):
        return None
    if not _arcs_clear(D):
        return None
    if init != "input" and not _reaches_edges(D, S, 1):
        return None
    if init == "mason" and not _reaches_edges(D, S, -1):
        return None
    return [(D.c[sl], D.side[sl], D.phi[sl], length[sl], D.theta[sl]) for sl in D.slices]


def _segment_distances(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances between segments p→q and a→b, row by row (0 where they cross)."""

    def point_seg(x, s0, s1):
        d = s1 - s0
        L2 = (d * d).sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.clip(((x - s0) * d).sum(axis=1) / L2, 0.0, 1.0)
        t = np.where(L2 > 0, t, 0.0)
        return np.hypot(*(x - s0 - t[:, None] * d).T)

    def orient(o, u, v):
        return (u[:, 0] - o[:, 0]) * (v[:, 1] - o[:, 1]) - (u[:, 1] - o[:, 1]) * (v[:, 0] - o[:, 0])

    dist = np.minimum.reduce([point_seg(p, a, b), point_seg(q, a, b), point_seg(a, p, q), point_seg(b, p, q)])
    cross = (orient(p, q, a) * orient(p, q, b) < 0) & (orient(a, b, p) * orient(a, b, q) < 0)
    return np.where(cross, 0.0, dist)


def _tree(points: np.ndarray) -> cKDTree:
    """A k-d tree split at sliding midpoints rather than medians: on points strung along curves, and with
    queries at a fixed distance from them, its boxes hug the curve and searches visit several times fewer
    of them (about 6× faster on a 100k-vertex ring)."""
    return cKDTree(points, balanced_tree=False, compact_nodes=False)


def _closer_than(D: _Rings, p: np.ndarray, q: np.ndarray, limit: float, known=None) -> bool:
    """Whether any edge of S comes closer than ``limit`` to any of the segments p→q (points when p = q).

    Exact, and fast on dense rings, in two passes:

    1. the end points. An edge shorter than h that comes within ``limit`` of a point x has an end within
       sqrt(limit² + h²/4) of x (at the edge's point nearest x the edge is perpendicular to the way to x);
       a k-d tree over the vertices finds the few candidates in that thin shell;
    2. the interiors, once no edge comes near an end. An edge point y within ``limit`` of the segment
       whose nearest segment point is interior lies within sqrt(limit² + half²) of the midpoint (half =
       half the segment's length), so by the same argument the edge has an end within
       sqrt(limit² + half² + h²/4) of the midpoint. This ball hugs the segment's neighbourhood minus the
       end disks: its shell is (half² + h²/4)/(2·limit) thick, not half + h²/(8·limit), which keeps the
       candidates few even where the ring runs at nearly distance ``limit`` for a long way (a ring whose
       curvature radius is close to r).

    The rare edges longer than h are tested with an STRtree. ``known``, a pair of boolean arrays, marks
    ends already found at least ``limit`` from every edge (disk centres); pass 1 skips them.
    """
    edge_a, edge_b = D.v, D.v[D.next]
    # The shell sqrt(limit² + h²/4) − limit ≈ h²/(8·limit) is thin when h is near the typical edge length.
    h = float(np.clip(2.0 * np.percentile(D.ell, 95), limit / 1024, limit / 8))
    short = D.ell <= h
    if short.any():
        tree = D.vertex_tree
        segment = (p != q).any(axis=1)
        p_known, q_known = known if known is not None else (np.zeros(len(p), bool), np.zeros(len(q), bool))
        ends = np.concatenate([p[~p_known], q[segment & ~q_known]])
        if _near_short_edges(D, tree, ends, ends, np.zeros(len(ends)), limit, h, short):
            return True
        if segment.any():
            a, b = p[segment], q[segment]
            half = 0.5 * np.hypot(*(b - a).T)
            if _near_short_edges(D, tree, a, b, half, limit, h, short):
                return True
    if (~short).any():
        long_edges = shapely.linestrings(np.stack([edge_a[~short], edge_b[~short]], axis=1))
        probes = shapely.linestrings(np.stack([p, q + (p == q).all(axis=1)[:, None] * 1e-300], axis=1))
        hits = shapely.STRtree(long_edges).query(probes, predicate="dwithin", distance=limit)
        if hits.shape[1]:
            i, j = hits
            e = np.flatnonzero(~short)[j]
            if (_segment_distances(p[i], q[i], edge_a[e], edge_b[e]) < limit).any():
                return True
    return False


def _near_short_edges(D: _Rings, tree: cKDTree, p: np.ndarray, q: np.ndarray, half: np.ndarray,
                      limit: float, h: float, short: np.ndarray) -> bool:
    """Whether an edge of length ≤ h comes closer than ``limit`` to a segment p→q, testing the edges at
    the vertices within sqrt(limit² + half² + h²/4) of each midpoint (see `_closer_than`)."""
    mid = 0.5 * (p + q)
    edge_a, edge_b = D.v, D.v[D.next]
    # Group the segments by length (within a factor of two) so that each ball query has a tight radius.
    level = np.floor(np.log2(np.maximum(half, 1e-300))).astype(np.int64)
    order = np.lexsort((np.arange(len(half)), level))
    cuts = np.flatnonzero(np.diff(level[order])) + 1
    groups = np.split(order, cuts)
    for chunk in groups:
        if len(chunk) == 0:
            continue
        radius = math.sqrt(limit * limit + float(half[chunk].max()) ** 2 + 0.25 * h * h)
        hits = _tree(mid[chunk]).sparse_distance_matrix(tree, radius, output_type="ndarray")
        if len(hits) == 0:
            continue
        seg, vert = chunk[hits["i"]], hits["j"]
        # The two edges at each candidate vertex: the one leaving it and the one arriving.
        for e in (vert, D.prev[vert]):
            s, e = seg[short[e]], e[short[e]]
            # Most candidates are settled by the edge's line: a segment with both ends on one side of
            # it, at least ``limit`` away, is that far from the edge too. The rest get the exact distance.
            ea, d = edge_a[e], edge_b[e] - edge_a[e]
            sp = (d[:, 0] * (p[s, 1] - ea[:, 1]) - d[:, 1] * (p[s, 0] - ea[:, 0]))
            sq = (d[:, 0] * (q[s, 1] - ea[:, 1]) - d[:, 1] * (q[s, 0] - ea[:, 0]))
            reach = limit * np.hypot(d[:, 0], d[:, 1])
            far = ((sp >= reach) & (sq >= reach)) | ((sp <= -reach) & (sq <= -reach))
            s, e = s[~far], e[~far]
            if len(s) and (_segment_distances(p[s], q[s], edge_a[e], edge_b[e]) < limit).any():
                return True
    return False


def _centers_valid(D: _Rings, S) -> bool:
    """Every disk lies in S at distance ≥ r from its boundary (convex vertices) or outside, at distance
    ≥ r from S (reflex vertices).

    Decided exactly (up to rounding, `_EXACT`) from the edges of S, not from the buffered shrink and grow:
    GEOS simplifies a buffer's input by up to r/100, which on dense rings moves them further than any
    slack could allow.
    """
    r = D.r
    inner = D.side > 0
    inside = shapely.contains_xy(S, D.c[:, 0], D.c[:, 1])
    if (inner != inside).any():
        return False
    return not _closer_than(D, D.c, D.c, r * (1 - _EXACT))


def _arcs_clear(D: _Rings) -> bool:
    """No arc enters the core (convex vertices) or the anticore (reflex vertices) elsewhere.

    Decided from the edges of S, not from GEOS's opening and closing (which simplify dense input by up to
    r/100). A point x of a convex vertex's arc lies within r of that vertex, so not in the shrink; it is
    in the (open) core exactly when it is closer than r to the shrink, that is to the shrink's boundary.
    That boundary is made of points at distance exactly r from the boundary of S: on the edges moved
    inwards by r or on circles of radius r around vertices, and of those only the edges cut at the disks'
    centres and the arcs around the reflex vertices (`_Rings.offsets`, `_Rings.arcs`) can be in the
    shrink; the rest is closer than r to a neighbouring edge. So an arc point at distance ≥ r from all of
    them is outside the core. Reflex vertices likewise, outside S, against the grow. The arcs are tested
    at points every π/16 at most (slightly outside their own disk, which the pieces at its centre touch).
    """
    r = D.r
    m = np.maximum(2, np.ceil(np.abs(D.theta) / (math.pi / 16)).astype(np.int64))
    owner = np.repeat(np.arange(len(D.v)), m - 1)
    first = np.repeat(np.cumsum(m - 1) - (m - 1), m - 1)
    frac = (np.arange(len(owner)) - first + 1) / np.repeat(m, m - 1)
    a0 = D.phi[D.prev] - D.side * (math.pi / 2)
    th = a0[owner] + D.theta[owner] * frac
    # Just outside its own disk (by rounding-proof 1e-8·r): the pieces that meet at the disk's centre are
    # then no nearer than r, and only another part of the shrink's (grow's) boundary can come nearer.
    probes = D.c[owner] + (r * (1 + 1e-8)) * np.column_stack([np.cos(th), np.sin(th)])
    limit = r * (1 - _EXACT)
    for side in (1, -1):
        x = probes[D.side[owner] == side]
        if len(x) == 0:
            continue
        pieces = D.offsets(side)
        if _points_near_segments(x, pieces[:, 0], pieces[:, 1], limit):
            return False
        centres, start, sweep = D.arcs(side)
        if len(centres) and _points_near_arcs(x, centres, start, sweep, r, limit):
            return False
    return True


def _point_segment_distances(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = b - a
    L2 = (d * d).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(((x - a) * d).sum(axis=1) / L2, 0.0, 1.0)
    t = np.where(L2 > 0, t, 0.0)
    return np.hypot(*(x - a - t[:, None] * d).T)


def _points_near_segments(x: np.ndarray, a: np.ndarray, b: np.ndarray, limit: float) -> bool:
    """Whether any point x comes closer than ``limit`` to any segment a→b (exact).

    A segment of length ≤ h within ``limit`` of x has its midpoint within sqrt(limit² + h²/4) of x (at
    the segment's point nearest x, the segment is perpendicular to the way to x, or that point is an end);
    a k-d tree over the midpoints gives the candidates. Longer segments go to an STRtree.
    """
    L = np.hypot(*(b - a).T)
    h = float(np.clip(2.0 * np.percentile(L, 95), limit / 1024, limit / 8))
    short = L <= h
    if short.any():
        idx = np.flatnonzero(short)
        mid = 0.5 * (a[idx] + b[idx])
        radius = math.sqrt(limit * limit + 0.25 * h * h)
        hits = _tree(x).sparse_distance_matrix(_tree(mid), radius, output_type="ndarray")
        if len(hits):
            i, k = hits["i"], idx[hits["j"]]
            if (_point_segment_distances(x[i], a[k], b[k]) < limit).any():
                return True
    if (~short).any():
        idx = np.flatnonzero(~short)
        hits = shapely.STRtree(shapely.linestrings(np.stack([a[idx], b[idx]], axis=1))).query(
            shapely.points(x), predicate="dwithin", distance=limit)
        if hits.shape[1]:
            i, k = hits[0], idx[hits[1]]
            if (_point_segment_distances(x[i], a[k], b[k]) < limit).any():
                return True
    return False


def _points_near_arcs(x: np.ndarray, centres: np.ndarray, start: np.ndarray, sweep: np.ndarray, r: float,
                      limit: float) -> bool:
    """Whether any point x comes closer than ``limit`` to any arc of radius r (centre, start angle, signed
    sweep), exactly: the distance to the circle where x's direction from the centre falls within the arc,
    to the nearer end otherwise. Candidates: arcs whose midpoint is within limit + the half-arc's chord."""
    half = 0.5 * sweep
    mid = centres + r * np.column_stack([np.cos(start + half), np.sin(start + half)])
    reach = limit + float((2.0 * r * np.abs(np.sin(0.5 * half))).max())
    hits = _tree(x).sparse_distance_matrix(_tree(mid), reach, output_type="ndarray")
    if len(hits) == 0:
        return False
    i, k = hits["i"], hits["j"]
    p, c = x[i], centres[k]
    rel = p - c
    # Angle of x from the centre, measured from the arc's start in the sweep's direction.
    ang = np.arctan2(rel[:, 1], rel[:, 0]) - start[k]
    ang = np.where(sweep[k] >= 0, ang, -ang) % (2.0 * math.pi)
    inside = ang <= np.abs(sweep[k])
    d_circle = np.abs(np.hypot(*rel.T) - r)
    e0 = c + r * np.column_stack([np.cos(start[k]), np.sin(start[k])])
    e1 = c + r * np.column_stack([np.cos(start[k] + sweep[k]), np.sin(start[k] + sweep[k])])
    d_ends = np.minimum(np.hypot(*(p - e0).T), np.hypot(*(p - e1).T))
    return bool((np.where(inside, d_circle, d_ends) < limit).any())


def _reaches_edges(D: _Rings, S, side: int) -> bool:
    """Every straight piece lies on the boundary of the core (side +1) or of the anticore (side −1).

    The piece on edge i runs between the tangent points of the disks at its ends. The core touches all of
    it when the piece moved inwards by r is a segment of centres of disks inside S: it lies in S and no
    edge of S comes closer to it than r (its own edge is exactly r away). The anticore likewise, moved
    outwards and outside S. Decided exactly from the edges of S. Needed for ``init="core"`` (the core's
    rings must be the rings of S) and, with both sides, for ``"mason"``.
    """
    r = D.r
    keep = D.length > 0
    if not keep.any():
        return True
    a = D.c[keep] - (D.side[keep] * r)[:, None] * D.n[keep] + side * r * D.n[keep]
    b = a + np.maximum(D.length[keep], 0)[:, None] * D.u[keep]
    mid = 0.5 * (a + b)
    if (shapely.contains_xy(S, mid[:, 0], mid[:, 1]) != (side > 0)).any():
        return False
    # Ends at a disk's centre were found r from every edge by `_centers_valid`.
    known = (D.side[keep] == side, D.side[D.next[keep]] == side)
    return not _closer_than(D, a, b, r * (1 - _EXACT), known)
