"""Exact offsets: the boundary of the closed shrink ``S↓r`` and of the grow's complement, from S's features.

The shrink ``S↓r = {p ∈ S : d(p, ∂S) ≥ r}`` (closed, as in the paper) is bounded by pieces of the *raw
offset elements* of S's boundary: each edge's parallel segment at distance r on the side of S, and an arc
of radius r about each reflex vertex, spanning the normals of its two edges. A point of a raw element
belongs to ``∂S↓r`` exactly when no edge of S comes nearer to it than r, that is when it lies outside the
open r-capsule of every edge. The complement of the grow, ``(S^c)↓r``, is the same construction on the
other side (normals pointing out of S, arcs about convex vertices, points outside S).

Each raw element is cut, in closed form, where it crosses the boundary of a capsule within its reach (the
capsule boundary is two offset segments and two circles of radius r); between two cuts an element is
entirely inside or entirely outside every capsule, so one exact clearance test at the middle of each
sub-piece decides it. Nothing here calls a buffer: GEOS's buffers simplify their input by up to r/100,
and the decisions made here are the ones every other part of the engine takes as ground truth:

* the **corners** of ``S↓r`` (where two kept pieces meet at an angle, or an isolated point of it) are
  exactly the centres of the convex arcs of the core; those of ``(S^c)↓r`` the centres of the concave
  arcs of the fillet;
* a curve enters the open core exactly when it comes nearer than r to a kept piece of ``∂S↓r`` (or
  crosses into ``S↓r``), and likewise for the anticore.

The rule is closed: a part of S exactly 2r wide has a shrink of zero width (its centre line), which is
kept, to the precision `precision_of` gives (a few units in the last place of the coordinates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import _proximity
from ._proximity import EdgeIndex, _length_classes, _tree

__all__ = ["OffsetPieces", "exact_offsets", "precision_of"]

_TWO_PI = 2.0 * math.pi
_ARC_SAMPLES = 9            # points of the polyline that stands in for an arc in the reach query
_SHORT_ARC = 0.125          # arcs of at most this sweep (radians) are reached through their chords


def precision_of(S) -> float:
    """The length below which two points of S's offsets cannot be told apart, in S's units.

    Sixty-four units in the last place of S's largest coordinate, and at least 1e-13 of S's size: the
    offsets are computed from the coordinates with a few operations each, and the clearance of a point
    (a GEOS point-segment distance) is correct to a few ulps of the coordinates.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> precision_of(box(0, 0, 1, 1)) < 1e-12
    True
    """
    x0, y0, x1, y1 = S.bounds
    size = max(x1 - x0, y1 - y0)
    big = max(abs(x0), abs(y0), abs(x1), abs(y1), size)
    return max(1e-13 * size, 64.0 * np.spacing(big))


@dataclass(frozen=True)
class OffsetPieces:
    """The kept pieces of ``∂S↓r`` (``side=+1``) or ``∂(S^c)↓r`` (``side=-1``), and their corners.

    Attributes
    ----------
    side : int
        +1: the shrink of S (centres of the core's arcs); −1: the shrink of the complement (the fillet's).
    r : float
        The radius, in S's units.
    seg : (k, 2, 2) float
        Straight pieces, each parallel to an edge of S at distance r from it.
    seg_edge : (k,) int
        The edge of S each straight piece is the offset of.
    arc_center, arc_start, arc_sweep : (j, 2), (j,), (j,) float
        Arcs of radius r about vertices of S: start angle and signed sweep (radians).
    corners : (m, 2) float
        Corners of the region: the exact arc centres of its side.
    precision : float
        The closed rule's slack (`precision_of`): a point is kept if its clearance is ≥ r − precision.
    """

    side: int
    r: float
    seg: np.ndarray
    seg_edge: np.ndarray
    arc_center: np.ndarray
    arc_start: np.ndarray
    arc_sweep: np.ndarray
    corners: np.ndarray
    precision: float

    def test_points(self) -> np.ndarray:
        """``(k, 2)``: every corner and the middle of every piece, the points at which a region holding (or
        missing) the whole closed set is told apart exactly by point-in-polygon tests."""
        pts = [self.corners]
        if len(self.seg):
            pts.append(0.5 * (self.seg[:, 0] + self.seg[:, 1]))
        if len(self.arc_center):
            th = self.arc_start + 0.5 * self.arc_sweep
            pts.append(self.arc_center + self.r * np.column_stack([np.cos(th), np.sin(th)]))
        return np.concatenate(pts).reshape(-1, 2)

    def polylines(self, max_angle: float = math.pi / 64) -> list[np.ndarray]:
        """Each piece as a polyline (arcs through points on them, at most ``max_angle`` apart)."""
        xy, start = self.polyline_points(max_angle)
        return np.split(xy, start[1:-1]) if len(start) > 1 else []

    def polyline_points(self, max_angle: float = math.pi / 64) -> tuple[np.ndarray, np.ndarray]:
        """The pieces' polylines (`polylines`) in one array: their points, and where each starts.

        Returns ``(xy, start)``: polyline ``i`` is ``xy[start[i]:start[i + 1]]``; the straight pieces first
        (two points each), then the arcs, each through ``max(1, ⌈|sweep| / max_angle⌉) + 1`` points evenly
        spaced in angle (the ends exact), in S's units.

        Examples
        --------
        >>> from shapely.geometry import box
        >>> xy, start = exact_offsets(box(0, 0, 4, 3), 1.0, side=-1).polyline_points(math.pi / 4)
        >>> start.tolist()
        [0, 2, 4, 6, 8, 11, 14, 17, 20]
        """
        k = len(self.seg)
        sw = np.asarray(self.arc_sweep, dtype=float)
        m = np.maximum(1, np.ceil(np.abs(sw) / max_angle)).astype(np.int64)
        sizes = np.concatenate([np.full(k, 2, dtype=np.int64), m + 1])
        start = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        arc_xy = np.zeros((0, 2))
        if len(m):
            # As `np.linspace(0, 1, m + 1)` does it: i · (1/m), the last exactly 1.
            row = np.repeat(np.arange(len(m)), m + 1)
            i = np.arange(len(row)) - np.repeat(start[k:-1] - start[k], m + 1)
            t = i.astype(float) * (1.0 / m)[row]
            t[start[k + 1:] - start[k] - 1] = 1.0
            th = self.arc_start[row] + sw[row] * t
            c = self.arc_center[row]
            arc_xy = np.column_stack([c[:, 0] + self.r * np.cos(th), c[:, 1] + self.r * np.sin(th)])
        xy = np.concatenate([np.asarray(self.seg, dtype=float).reshape(-1, 2), arc_xy])
        return xy, start


def _edges(S):
    """Edges of an oriented S (interior on the left), with each edge's predecessor and successor.

    Each ring loses its repeated consecutive points and its closing point; rings of fewer than three
    points are dropped. Many rings at once (no loop over rings: a shape of many small parts); a few one
    at a time (`_ring_edges`, fewer numpy calls).
    """
    rings = shapely.get_rings(shapely.get_parts(S))
    if len(rings) < _FEW_RINGS:
        return _ring_edges(rings)
    c, rid = shapely.get_coordinates(rings, return_index=True)
    c = c[:, :2]
    if len(c):
        keep = np.ones(len(c), dtype=bool)
        keep[1:] = (rid[1:] != rid[:-1]) | np.any(c[1:] != c[:-1], axis=1)
        c, rid = c[keep], rid[keep]
    first = np.flatnonzero(np.r_[True, rid[1:] != rid[:-1]]) if len(c) else np.zeros(0, np.int64)
    end = np.r_[first[1:], len(c)].astype(np.int64)
    # A closing point (equal to its ring's first) goes.
    closed = (end - first > 1) & np.all(c[np.maximum(end - 1, 0)] == c[first], axis=1) if len(c) \
        else np.zeros(0, dtype=bool)
    drop = np.zeros(len(c), dtype=bool)
    drop[end[closed] - 1] = True
    size = end - first - closed
    ok = size >= 3
    keep = np.repeat(ok, end - first) & ~drop
    if not keep.any():
        z = np.zeros((0, 2))
        return z, z, np.zeros(0, np.int64), np.zeros(0, np.int64)
    a = c[keep]
    n = size[ok]
    start = np.r_[0, np.cumsum(n)[:-1]].astype(np.int64)
    ring = np.repeat(np.arange(len(n)), n)
    pos = np.arange(len(a)) - start[ring]
    nxt = start[ring] + (pos + 1) % n[ring]
    prv = start[ring] + (pos - 1) % n[ring]
    return a, a[nxt], prv, nxt


_FEW_RINGS = 8      # `_edges` takes fewer rings than this one at a time


def _ring_edges(rings):
    """`_edges` of a few rings, one ring at a time."""
    a, b, prv, nxt = [], [], [], []
    off = 0
    for ring in rings:
        c = shapely.get_coordinates(ring)[:, :2]
        keep = np.ones(len(c), dtype=bool)
        keep[1:] = np.any(c[1:] != c[:-1], axis=1)
        c = c[keep]
        if len(c) > 1 and np.all(c[0] == c[-1]):
            c = c[:-1]
        n = len(c)
        if n < 3:
            continue
        a.append(c)
        b.append(np.roll(c, -1, axis=0))
        idx = np.arange(n)
        prv.append(off + (idx - 1) % n)
        nxt.append(off + (idx + 1) % n)
        off += n
    if not a:
        z = np.zeros((0, 2))
        return z, z, np.zeros(0, np.int64), np.zeros(0, np.int64)
    return np.concatenate(a), np.concatenate(b), np.concatenate(prv), np.concatenate(nxt)


def _cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _seg_line_params(P0, D, Q0, E, lo=-1e-9, hi=1 + 1e-9):
    """Parameters t on P0 + tD where it crosses the segments Q0 + uE (u in [lo, hi]); NaN where none."""
    den = _cross(D, E)
    w = Q0 - P0
    with np.errstate(divide="ignore", invalid="ignore"):
        t = _cross(w, E) / den
        u = _cross(w, D) / den
    ok = (np.abs(den) > 0) & (u >= lo) & (u <= hi)
    return np.where(ok, t, np.nan)


def _seg_circle_params(P0, D, c, r):
    """The two parameters t on P0 + tD at distance r from c (NaN where the line misses the circle)."""
    L = np.hypot(D[:, 0], D[:, 1])
    w = c - P0
    with np.errstate(divide="ignore", invalid="ignore"):
        along = (w * D).sum(axis=1) / L            # foot of c along the line, in length units
        off = _cross(D, w) / L                     # signed distance of c from the line
        h2 = (r - off) * (r + off)
        h = np.sqrt(np.where(h2 >= 0, h2, np.nan))
        return (along - h) / L, (along + h) / L


def _arc_param(theta, a0, sw):
    """Where angle ``theta`` falls along an arc starting at ``a0`` with signed sweep ``sw`` (0..1)."""
    turn = np.where(sw > 0, (theta - a0) % _TWO_PI, (a0 - theta) % _TWO_PI)
    return turn / np.abs(sw)


def _circle_circle_angles(v, c, r):
    """Angles (about v) of the two points at distance r from both v and c; NaN where there are none."""
    d = c - v
    L = np.hypot(d[:, 0], d[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        h2 = (r - 0.5 * L) * (r + 0.5 * L)
        ok = (h2 >= 0) & (L > 0)
        base = np.arctan2(d[:, 1], d[:, 0])
        half = np.arccos(np.clip(0.5 * L / r, -1.0, 1.0))
    return np.where(ok, base - half, np.nan), np.where(ok, base + half, np.nan)


def _circle_seg_angles(v, r, Q0, E, lo=-1e-9, hi=1 + 1e-9):
    """Angles (about v) where the circle of radius r about v crosses the segments Q0 + uE."""
    L = np.hypot(E[:, 0], E[:, 1])
    w = v - Q0
    with np.errstate(divide="ignore", invalid="ignore"):
        along = (w * E).sum(axis=1) / L
        off = _cross(E, w) / L
        h2 = (r - off) * (r + off)
        h = np.sqrt(np.where(h2 >= 0, h2, np.nan))
        out = []
        for s in (-1.0, 1.0):
            u = (along + s * h) / L
            p = Q0 + u[:, None] * E
            th = np.arctan2(p[:, 1] - v[:, 1], p[:, 0] - v[:, 0])
            out.append(np.where((u >= lo) & (u <= hi), th, np.nan))
    return out


def _elements(a, b, prv, nxt, r, side):
    """The raw offset elements: segments (one per edge) and arcs (at the vertices where offsets open)."""
    d = b - a
    L = np.hypot(d[:, 0], d[:, 1])
    u = d / L[:, None]
    N = side * np.column_stack([-u[:, 1], u[:, 0]])        # unit normal towards the side's region
    seg = np.stack([a + r * N, b + r * N], axis=1)
    # Vertex b[i] = a[nxt[i]]: the offsets open (an arc) where the boundary turns away from the side.
    j = nxt
    turn = np.arctan2(_cross(u, u[j]), (u * u[j]).sum(axis=1))
    opens = side * turn < 0
    ai = np.flatnonzero(opens)
    arc_v = b[ai]
    arc_a0 = np.arctan2(N[ai, 1], N[ai, 0])
    arc_sw = turn[ai]                                     # the normal turns as the edge does
    return seg, N, turn, ai, arc_v, arc_a0, arc_sw


class _Elements:
    """The raw offset elements of one side, and exact cuts of them against edges' capsules."""

    def __init__(self, S, r: float, side: int, precision: float | None = None):
        self.S, self.r, self.side = S, r, side
        a, b, prv, nxt = _edges(S)
        self.a, self.b, self.prv, self.nxt = a, b, prv, nxt
        self.eps = max(precision_of(S), precision or 0.0)
        seg, N, turn, ai, arc_v, arc_a0, arc_sw = _elements(a, b, prv, nxt, r, side)
        self.seg, self.N, self.turn = seg, N, turn
        self.ai, self.arc_v, self.arc_a0, self.arc_sw = ai, arc_v, arc_a0, arc_sw
        self.n_seg, self.n_arc = len(a), len(ai)
        self.length = np.concatenate([np.hypot(*(seg[:, 1] - seg[:, 0]).T), r * np.abs(arc_sw)])
        self.tiny = np.where(self.length > 0, self.eps / np.maximum(self.length, 1e-300), 1.0)
        self._tree = None
        self._middles = None
        self._index = None
        # The edges that cannot cut an element: a segment's own edge, an arc's two edges.
        self.own = np.concatenate([np.stack([np.arange(len(a)), np.arange(len(a))], axis=1),
                                   np.stack([ai, nxt[ai]], axis=1)]) if len(a) else np.zeros((0, 2), np.int64)

    @property
    def tree(self):
        """The edges in shapely's R-tree, built on first use (None if S has no edge)."""
        if self._tree is None and len(self.a):
            self._tree = shapely.STRtree(shapely.linestrings(np.stack([self.a, self.b], axis=1)))
        return self._tree

    @property
    def middles(self) -> cKDTree:
        """The edges' middles, in a k-d tree whose boxes hug the outline (`_proximity._tree`)."""
        if self._middles is None:
            self._middles = _tree(0.5 * (self.a + self.b))
        return self._middles

    def points(self, e, t) -> np.ndarray:
        """Points at parameters ``t`` of elements ``e``."""
        e = np.asarray(e, dtype=np.int64)
        t = np.asarray(t, dtype=float)
        s = e < self.n_seg
        n_s = int(np.count_nonzero(s))
        if n_s == len(e):                                   # straight pieces only
            p0 = self.seg[e, 0]
            return p0 + t[:, None] * (self.seg[e, 1] - p0)
        if n_s == 0:                                        # arcs only
            return self._arc_points(e - self.n_seg, t)
        out = np.empty((len(e), 2))
        out[s] = self.seg[e[s], 0] + t[s, None] * (self.seg[e[s], 1] - self.seg[e[s], 0])
        out[~s] = self._arc_points(e[~s] - self.n_seg, t[~s])
        return out

    def _arc_points(self, k, t) -> np.ndarray:
        """Points at parameters ``t`` of arcs ``k``."""
        ang = self.arc_a0[k] + self.arc_sw[k] * t
        out = np.empty((len(k), 2))
        out[:, 0] = np.cos(ang)
        out[:, 1] = np.sin(ang)
        out *= self.r
        out += self.arc_v[k]
        return out

    def geoms(self, e, lo, hi):
        """The sub-pieces as shapely lines (an arc by a polyline), for reach queries; and their sag.

        A straight sub-piece is the segment between its ends; an arc goes through ``_ARC_SAMPLES`` points.
        """
        m = _ARC_SAMPLES
        is_seg = e < self.n_seg
        # Points a piece: 2 on a straight one (its ends, at lo and (hi − lo) + lo), m on an arc.
        count = np.where(is_seg, 2, m)
        row = np.repeat(np.arange(len(e)), count)
        j = np.arange(len(row)) - np.repeat(np.cumsum(count) - count, count)
        frac = np.where(is_seg[row], j.astype(float), np.linspace(0.0, 1.0, m)[np.minimum(j, m - 1)])
        span = (hi - lo)[row]
        t = np.where(is_seg[row], frac * span + lo[row], lo[row] + span * frac)
        lines = shapely.linestrings(self.points(e[row], t), indices=row)
        step = np.where(is_seg, 0.0, np.abs(self.arc_sw[np.clip(e - self.n_seg, 0, None)] if self.n_arc
                                             else 0.0) * (hi - lo) / (m - 1))
        return lines, float(self.r * (1.0 - np.cos(0.5 * step)).max(initial=0.0))

    def reach(self, e, lo, hi, slack: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(sub-piece, edge)`` with the edge nearer than r + slack to the sub-piece (an arc: to its
        polyline, within the polyline's sag more), other than the sub-piece's own edges.

        Straight sub-pieces go to the grazing index (`_proximity.EdgeIndex`): one near ∂S↓r lies about r
        from many edges of a dense outline, and the index measures only a shell around it as wide as the
        edges are long, where the R-tree measures every edge in a box 2r wide (3x faster on a 100k-vertex
        rippled star). Arcs, fewer and longer, go to the R-tree.
        """
        pis, pjs = [], []
        seg = np.flatnonzero(e < self.n_seg)
        if len(seg):
            if self._index is None:
                self._index = EdgeIndex(self.a, self.b, self.r)
            si, ej = self._index.near_segments(self.points(e[seg], lo[seg]), self.points(e[seg], hi[seg]),
                                               self.r + slack)
            pis.append(seg[si]), pjs.append(ej)
        arc = np.flatnonzero(e >= self.n_seg)
        if len(arc):
            # Short arcs by their chords: every edge within r + slack of such an arc lies within that
            # plus the arc's sag of its chord; grouped by sag within a factor of two, one grazing query
            # a group. Longer arcs (fewer) by their polylines in the R-tree.
            sweep = np.abs(self.arc_sw[e[arc] - self.n_seg]) * (hi[arc] - lo[arc])
            short = sweep <= _SHORT_ARC
            if short.any():
                if self._index is None:
                    self._index = EdgeIndex(self.a, self.b, self.r)
                sa = arc[short]
                sag = self.r * (1.0 - np.cos(0.5 * sweep[short]))
                p, q = self.points(e[sa], lo[sa]), self.points(e[sa], hi[sa])
                groups = _length_classes(sag, np.arange(len(sa)))
                dist = [self.r + slack + float(sag[group].max()) * (1.0 + 1e-9) for group in groups]
                if len(sa) * len(self._index) <= _proximity._BOX_PAIRS:
                    # Few pairs: one query, each chord at its group's distance (the same pairs).
                    each = np.empty(len(sa))
                    for group, d in zip(groups, dist):
                        each[group] = d
                    si, ej = self._index.near_segments(p, q, each)
                    pis.append(sa[si]), pjs.append(ej)
                else:
                    for group, d in zip(groups, dist):
                        si, ej = self._index.near_segments(p[group], q[group], d)
                        pis.append(sa[group[si]]), pjs.append(ej)
                arc = arc[~short]
        if len(arc) and len(arc) * len(self.a) <= _proximity._BOX_PAIRS:
            # Few pairs: every edge whose box comes within r + slack of the arc's circle's box (more
            # than the R-tree finds; the capsules of the others do not reach the arc: `_uncovered` takes
            # nothing of it for them).
            v = self.arc_v[e[arc] - self.n_seg]
            pad = 2.0 * self.r + slack + 1e-9 * (self.r + float(np.abs(v).max()))
            lo_e, hi_e = np.minimum(self.a, self.b), np.maximum(self.a, self.b)
            hit = ((v[:, None, 0] - pad <= hi_e[None, :, 0]) & (v[:, None, 0] + pad >= lo_e[None, :, 0])
                   & (v[:, None, 1] - pad <= hi_e[None, :, 1]) & (v[:, None, 1] + pad >= lo_e[None, :, 1]))
            ai, ej = np.nonzero(hit)
            pis.append(arc[ai]), pjs.append(ej.astype(np.int64))
        elif len(arc):
            g, sag = self.geoms(e[arc], lo[arc], hi[arc])
            ai, ej = self.tree.query(g, predicate="dwithin", distance=self.r + sag + slack)
            pis.append(arc[ai]), pjs.append(ej)
        pi = np.concatenate(pis) if pis else np.zeros(0, np.int64)
        pj = np.concatenate(pjs) if pjs else np.zeros(0, np.int64)
        own = (self.own[e[pi], 0] == pj) | (self.own[e[pi], 1] == pj)
        return pi[~own], pj[~own]

    def clearance(self, xy):
        """Distance of each point to S's boundary, and the nearest edge, as far as the rounds need them.

        The edge whose middle is nearest (if that middle is nearer than r − precision) gives an upper
        bound; where it is nearer than r − precision the point is in that edge's capsule, and that is all
        the rounds need to know (the clearance returned there is that bound). Elsewhere the R-tree finds
        the nearest edge exactly where some edge lies within r − precision; a point farther than that
        from every edge gets +inf and edge −1 (the rounds only compare the clearance with r − precision).
        """
        d = np.empty(len(xy))
        e = np.empty(len(xy), dtype=np.int64)
        if len(xy) == 0:
            return d, e
        # An edge is no farther than its middle: a middle nearer than r − precision proves the point deep
        # (and the bounded query stays cheap where every edge is far, as around a wide arc of a staircase).
        dm, j = self.middles.query(xy, distance_upper_bound=self.r - self.eps)
        found = np.flatnonzero(np.isfinite(dm))
        deep = np.zeros(len(xy), dtype=bool)
        dj = self._edge_distance(xy[found], j[found])
        hit = dj < self.r - self.eps
        deep[found[hit]] = True
        d[found[hit]], e[found[hit]] = dj[hit], j[found[hit]]
        rest = np.flatnonzero(~deep)
        if len(rest):
            # Most of the rest are clear (an offset piece lies at r from its own edge): a grazing query
            # (`_proximity.EdgeIndex`: edges by length class, a ball on their middles only as much wider
            # than r − precision as they are long) finds the few with an edge that near, nearest first;
            # the others are farther than r − precision from every edge (+inf, edge −1).
            if self._index is None:
                self._index = EdgeIndex(self.a, self.b, self.r)
            pi, ei, di = self._index.near_points(xy[rest], self.r - self.eps)
            first = np.r_[True, pi[1:] != pi[:-1]] if len(pi) else np.zeros(0, dtype=bool)
            d[rest], e[rest] = np.inf, -1
            d[rest[pi[first]]], e[rest[pi[first]]] = di[first], ei[first]
        return d, e

    def _edge_distance(self, xy, j):
        p, q = self.a[j], self.b[j]
        px, py = p[:, 0], p[:, 1]
        vx, vy = q[:, 0] - px, q[:, 1] - py
        L2 = vx * vx + vy * vy
        u = np.zeros(len(L2))
        np.divide((xy[:, 0] - px) * vx + (xy[:, 1] - py) * vy, L2, out=u, where=L2 > 0)
        np.clip(u, 0.0, 1.0, out=u)
        return np.hypot(xy[:, 0] - (px + u * vx), xy[:, 1] - (py + u * vy))

    def crowded(self, xy, reach) -> np.ndarray:
        """Whether more than `_FEW_EDGES` edges have their middle within ``reach`` of each point."""
        k = _FEW_EDGES + 1
        if len(self.a) < k:
            return np.zeros(len(xy), dtype=bool)
        d, _ = self.middles.query(xy, k=[k], distance_upper_bound=float(np.max(reach)))
        return d[:, 0] <= reach

    def kept(self, xy) -> np.ndarray:
        """The closed rule at points: on the side's side of S and clearance ≥ r − precision.

        Only whether some edge lies nearer than r − precision matters here, not which: an approximate
        nearest middle (within twice the nearest's distance, much cheaper on dense outlines) settles most
        points, whose edge is that near; the exact search decides the rest.
        """
        if len(xy) == 0:
            return np.zeros(0, dtype=bool)
        out = np.zeros(len(xy), dtype=bool)
        dm, j = self.middles.query(xy, distance_upper_bound=self.r - self.eps, eps=1.0)
        found = np.flatnonzero(np.isfinite(dm))
        deep = np.zeros(len(xy), dtype=bool)
        deep[found] = self._edge_distance(xy[found], j[found]) < self.r - self.eps
        rest = np.flatnonzero(~deep)
        if len(rest):
            d, _ = self.clearance(xy[rest])
            clear = d >= self.r - self.eps
            clear[clear] = self.on_side(xy[rest][clear])      # only the clear ones: a point-in-polygon
            out[rest] = clear                                   # test costs O(n) a point on a comb
        return out

    def on_side(self, xy) -> np.ndarray:
        """Whether points lie in S (side +1) or outside it (side −1)."""
        inside = shapely.contains_xy(self.S, xy[:, 0], xy[:, 1])
        return inside if self.side > 0 else ~inside

    def cuts(self, e, j) -> np.ndarray:
        """(K, 8) parameters where elements ``e`` cross the boundary of edge ``j``'s capsule (NaN: none)."""
        r, a, b = self.r, self.a, self.b
        out = np.full((len(e), 8), np.nan)
        if len(e) == 0:
            return out
        Ej = b[j] - a[j]
        Lj = np.hypot(Ej[:, 0], Ej[:, 1])
        nrm = np.column_stack([-Ej[:, 1], Ej[:, 0]]) / Lj[:, None]
        s = e < self.n_seg
        if s.any():
            es, js = e[s], j[s]
            P0 = self.seg[es, 0]
            D = self.seg[es, 1] - P0
            cols = [_seg_line_params(P0, D, a[js] + r * nrm[s], Ej[s]),
                    _seg_line_params(P0, D, a[js] - r * nrm[s], Ej[s]),
                    *_seg_circle_params(P0, D, a[js], r), *_seg_circle_params(P0, D, b[js], r)]
            out[s, :6] = np.column_stack(cols)
        if (~s).any():
            k, js = e[~s] - self.n_seg, j[~s]
            v, a0, sw = self.arc_v[k], self.arc_a0[k], self.arc_sw[k]
            angles = [*_circle_seg_angles(v, r, a[js] + r * nrm[~s], Ej[~s]),
                      *_circle_seg_angles(v, r, a[js] - r * nrm[~s], Ej[~s]),
                      *_circle_circle_angles(v, a[js], r), *_circle_circle_angles(v, b[js], r)]
            out[~s] = np.column_stack([_arc_param(th, a0, sw) for th in angles])
        return out

    def inside_edge(self, xy, j) -> np.ndarray:
        """Whether points lie in the open capsule of edge ``j`` (closed rule: nearer than r − precision)."""
        return self._edge_distance(xy, j) < self.r - self.eps


def _split(el, lo, hi, cut, tiny):
    """Sub-intervals of [lo, hi] of each element between the cuts that fall strictly inside it.

    Returns (owner row, lo, hi) of the sub-intervals, in order along each element.
    """
    k = len(el)
    inner = np.where((cut > lo[:, None] + tiny[el][:, None]) & (cut < hi[:, None] - tiny[el][:, None]),
                     cut, np.nan)
    breaks = np.concatenate([lo[:, None], inner, hi[:, None]], axis=1)
    breaks = np.sort(breaks, axis=1)                       # NaN last
    row = np.repeat(np.arange(k), breaks.shape[1] - 1)
    b0, b1 = breaks[:, :-1].ravel(), breaks[:, 1:].ravel()
    ok = np.isfinite(b0) & np.isfinite(b1) & (b1 - b0 > tiny[el][row])
    return row[ok], b0[ok], b1[ok]


def _uncovered(X, el, lo, hi, pi, pj):
    """The parts of pieces ``(el, lo, hi)`` outside the open capsules of edges ``pj`` (paired with ``pi``).

    Each pair's cuts split the piece into parts uniform for that capsule; those whose middle lies inside
    it are taken. The taken intervals of each piece are merged (sorted by start, with a running maximum of
    their ends), and the gaps between them are returned as ``(row, lo, hi)``; gaps no longer than the
    precision are returned as points (``touch``: where two capsules just meet, or a capsule is tangent):
    the closed rule may keep them as isolated points of the region.
    """
    k = len(el)
    if len(pi):
        row, b0, b1 = _split(el[pi], lo[pi], hi[pi], X.cuts(el[pi], pj), X.tiny)
        pe, pr = el[pi][row], pi[row]
        taken = X.inside_edge(X.points(pe, 0.5 * (b0 + b1)), pj[row])
        pr, b0, b1 = pr[taken], b0[taken], b1[taken]
    else:
        pr, b0, b1 = np.zeros(0, np.int64), np.zeros(0), np.zeros(0)
    # Every piece gets a sentinel interval at each end, so that the gaps are the spaces between
    # consecutive intervals of the merged, sorted list.
    idx = np.arange(k)
    pr = np.concatenate([pr, idx, idx])
    b0 = np.concatenate([b0, lo, hi])
    b1 = np.concatenate([b1, lo, hi])
    order = np.lexsort((b0, pr))
    pr, b0, b1 = pr[order], b0[order], b1[order]
    # Running maximum of the ends within each piece (a segmented scan by doubling: exact, O(n log n)).
    reach = b1.copy()
    shift = 1
    while shift < len(reach):
        same = pr[shift:] == pr[:-shift]
        reach[shift:] = np.where(same, np.maximum(reach[shift:], reach[:-shift]), reach[shift:])
        shift *= 2
    same = pr[1:] == pr[:-1]
    g0, g1, gr = reach[:-1][same], b0[1:][same], pr[1:][same]
    tiny = X.tiny[el[gr]]
    wide = g1 - g0 > tiny
    near = ~wide & (g1 - g0 > -tiny)
    inner = near & (g0 > lo[gr] + tiny) & (g1 < hi[gr] - tiny)
    touch = X.points(el[gr[inner]], 0.5 * (g0[inner] + g1[inner]))
    return (gr[wide], g0[wide], g1[wide]), touch


_MAX_ROUNDS = 400
_PRUNE = True                   # drop the raw elements `_dominated` proves covered before the rounds
_PRUNE_STEPS = 2                # neighbours on each side along the ring that `_dominated` tries at a time
_PRUNE_SLACK = 4.0              # the margin of `_dominated`'s radius, in units of the precision


def _dominated(X) -> np.ndarray:
    """Raw elements that lie wholly inside the union of a few other edges' capsules, shrunk by a margin.

    Such an element is at clearance below ``r − precision`` everywhere, by more than rounding can move it:
    the rounds would cut all of it away, and none of the ends of its removed parts could pass the closed
    rule. Dropping it first changes nothing else; on a dense outline (a pixel staircase, where r is many
    pixels) nearly every element is such, and the rounds are left with the few near ``∂S↓r``.

    The tests are sufficient, not necessary (an element they miss goes through the rounds as before), and
    local along the ring, with a radius ``ρ = r − m``, ``m`` a few times the precision:

    * a straight piece is covered when both its ends lie within ρ of one of the two edges before or after
      its own (a capsule is convex);
    * an arc about vertex v is covered by the ρ-disks about other arc vertices w: points of the arc at
      angle θ within ``arccos((r² + |w − v|² − ρ²) / (2r|w − v|))`` of the direction of ``w − v`` lie
      within ρ of w. Of each candidate's interval only what holds one end of the arc is used: the arc is
      covered when what holds its start reaches what holds its end. The candidates are the nearest arc
      vertices along the ring still undecided (`_PRUNE_STEPS` each side); a covered arc leaves the list,
      its neighbours close up, and the test is repeated until nothing more goes. On a staircase this peels
      the vertices off as a convex hull does, down to those whose arcs the offset keeps.

    An arc that stays is trimmed to what its last test left uncovered: its parts from its start to the
    reach of the intervals holding its start, and from the intervals holding its end, are covered too.

    Returns ``(covered, lo, hi)`` over the elements (straight pieces, then arcs): the mask, and the part
    of each element (parameters from 0 to 1) that may still hold points of ``∂S↓r``.
    """
    n_el = X.n_seg + X.n_arc
    out = np.zeros(n_el, dtype=bool)
    lo, hi = np.zeros(n_el), np.ones(n_el)
    r = X.r
    rho = r - _PRUNE_SLACK * X.eps
    if X.n_seg == 0 or not rho > 0.5 * r:
        return out, lo, hi
    # Straight pieces: both ends in one capsule of a nearby edge.
    p0, p1 = X.seg[:, 0], X.seg[:, 1]
    fw = bw = np.arange(X.n_seg)
    near = []
    for _ in range(2):
        fw, bw = X.nxt[fw], X.prv[bw]
        near += [fw, bw]
    # The four neighbours' capsules in one call: both ends against each.
    j = np.concatenate(near)
    d = X._edge_distance(np.concatenate([np.tile(p0, (4, 1)), np.tile(p1, (4, 1))]), np.tile(j, 2)) < rho
    d = d.reshape(2, 4, X.n_seg)
    out[:X.n_seg] = (d[0] & d[1]).any(axis=0)
    if X.n_arc < 3:
        return out, lo, hi
    # Arcs: ρ-disks about the nearest undecided arc vertices along the ring.
    ring = np.cumsum(X.prv != np.arange(-1, X.n_seg - 1)) - 1     # rings are runs of consecutive edges
    rid = ring[X.ai]
    alive = np.arange(X.n_arc)
    test = np.ones(X.n_arc, dtype=bool)          # the arcs whose neighbours changed (all, at first)
    k = _PRUNE_STEPS
    step = np.repeat(np.arange(1, k + 1), 2) * np.tile([1, -1], k)
    while len(alive) > 2 and test.any():
        g = rid[alive]
        first = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])
        size = np.diff(np.r_[first, len(alive)])
        grp = np.repeat(np.arange(len(first)), size)
        pos = np.arange(len(alive)) - first[grp]

        def around(i):
            """Positions in ``alive`` of the k nearest on each side along the ring of positions i."""
            return first[grp[i]][:, None] + (pos[i][:, None] + step) % size[grp[i]][:, None]

        t = np.flatnonzero(test)
        at = alive[t]
        cov_t, head, tail = _arcs_covered(X.arc_v[at], X.arc_a0[at], X.arc_sw[at], X.arc_v[alive[around(t)]],
                                          r, rho)
        span = np.abs(X.arc_sw[at])
        lo[X.n_seg + at] = np.clip(head / span, 0.0, 1.0)
        hi[X.n_seg + at] = np.clip(tail / span, 0.0, 1.0)
        if not cov_t.any():
            break
        cov = np.zeros(len(alive), dtype=bool)
        cov[t[cov_t]] = True
        out[X.n_seg + alive[cov]] = True
        # Only the arcs that had a covered one among their neighbours get new neighbours: test those.
        dirty = np.zeros(len(alive), dtype=bool)
        dirty[around(np.flatnonzero(cov)).ravel()] = True
        test = dirty[~cov]
        alive = alive[~cov]
    return out, lo, hi


def _arcs_covered(v, a0, sw, w, r, rho) -> np.ndarray:
    """Whether the arcs (centre v, radius r, start a0, signed sweep sw) lie in the union of the ρ-disks
    about the points ``w[i, :]`` (only intervals that hold an end of the arc count; see `_dominated`).

    Returns ``(covered, head, tail)``: the arc (turns from its start, 0 to ``|sw|``) is covered on
    ``[0, head]`` and on ``[tail, |sw|]``.
    """
    d = np.hypot(w[..., 0] - v[:, None, 0], w[..., 1] - v[:, None, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        c = (r * r + d * d - rho * rho) / (2.0 * r * d)
        half = np.arccos(np.clip(c, -1.0, 1.0))
        phi = np.arctan2(w[..., 1] - v[:, None, 1], w[..., 0] - v[:, None, 0])
    ok = (c < 1.0) & (d > 0)
    # Each interval in turns from the arc's start, along its sweep: [s, s + 2·half].
    s = np.where((sw > 0)[:, None], (phi - half - a0[:, None]) % _TWO_PI, (a0[:, None] - phi - half) % _TWO_PI)
    e = s + 2.0 * half
    span = np.abs(sw)[:, None]
    head = np.where(ok & (e > _TWO_PI), e - _TWO_PI, -np.inf).max(axis=1)      # covers [0, head]
    tail = np.where(ok & (s < span) & (e > span), s, np.inf).min(axis=1)      # covers [tail, span]
    span = span[:, 0]
    return (head >= span) | (tail <= 0.0) | (head > tail), head, tail
_CLEAR_PIECE_R = 1.0 / 16.0     # longest piece (relative to r) cut against every capsule in reach …
_SPLIT_MAX_R = 4.0              # … unless it is longer than this (relative to r), then it stays whole
_FEW_EDGES = 16                 # … or no more edges than this lie near it (then it is cut at once)


def shrink_is_empty(S, r: float, precision: float | None = None) -> bool:
    """Whether no disk of radius r fits in S: its exact shrink ``S↓r`` has no piece and no corner.

    Exact (`exact_offsets`, side +1), O(n log n) in S's vertices.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        Valid, in any units (oriented here).
    r : float
        The radius, > 0, in S's units.
    precision : float, optional
        As `exact_offsets`'s.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> shrink_is_empty(box(0, 0, 100, 1.99), 1.0), shrink_is_empty(box(0, 0, 100, 2.0), 1.0)
    (True, False)
    """
    S = shapely.orient_polygons(S, exterior_cw=False)
    return len(exact_offsets(S, r, 1, precision=precision).test_points()) == 0


def exact_offsets(S, r: float, side: int = 1, _brute: bool = False, *,
                  precision: float | None = None) -> OffsetPieces:
    """The exact boundary pieces and corners of ``S↓r`` (``side=1``) or of ``(S^c)↓r`` (``side=-1``).

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        A valid, oriented shape (exteriors counter-clockwise, holes clockwise), in any units.
    r : float
        The radius, > 0, in S's units.
    side : {1, -1}
        +1 for the shrink of S (its corners are the centres of the core's convex arcs), −1 for the shrink
        of S's complement (the centres of the fillet's concave arcs).
    precision : float, optional
        A larger tie slack than `precision_of(S)`, in S's units: for a shape moved and scaled from
        coordinates whose rounding S still carries (the engine's local frame), that of the original.

    Returns
    -------
    OffsetPieces
        Straight pieces and arcs of radius r, each at clearance exactly r from S's boundary, and the
        corners where they meet.

    Notes
    -----
    Each raw element is clipped in rounds. A piece whose middle lies in the capsule of its nearest edge
    loses, in closed form, the part inside that capsule (a convex set: at most two parts remain), and
    what remains goes on. A piece whose middle is clear is cut against every capsule within its reach;
    between those cuts it is uniform, and its parts are kept or sent back by one test each. On dense
    boundaries almost every element lies inside one capsule and goes in the first round, so the work is
    O(n log n) with the reach queries confined to the few pieces near ``∂S↓r``.

    Before the rounds, `_dominated` drops the elements that a few ring neighbours' capsules (disks, for
    arcs) cover with a margin, and trims the arcs it keeps to what those left uncovered: on a pixel
    staircase much finer than r most arcs lie under their neighbours' disks (an arc about a vertex that
    no r-disk in S can touch), and only the arcs of the staircase's outermost vertices reach the rounds.

    Examples
    --------
    A 4 × 3 box at r = 1: the shrink is the rectangle [1, 3] × [1, 2], its corners the core's arc centres.

    >>> from shapely.geometry import box
    >>> E = exact_offsets(box(0, 0, 4, 3), 1.0)
    >>> sorted(map(tuple, E.corners.round(12).tolist()))
    [(1.0, 1.0), (1.0, 2.0), (3.0, 1.0), (3.0, 2.0)]

    A bar exactly 2r wide keeps its centre line (the closed shrink):

    >>> E = exact_offsets(box(0, 0, 10, 2), 1.0)
    >>> sorted(map(tuple, E.corners.round(12).tolist()))
    [(1.0, 1.0), (9.0, 1.0)]
    """
    r = float(r)
    X = _Elements(S, r, side, precision)
    eps = X.eps
    n_el = X.n_seg + X.n_arc
    if n_el == 0:
        z = np.zeros((0, 2))
        return OffsetPieces(side, r, np.zeros((0, 2, 2)), np.zeros(0, np.int64), z, np.zeros(0), np.zeros(0),
                            z, eps)
    el = np.arange(n_el)
    lo, hi = np.zeros(n_el), np.ones(n_el)
    if _PRUNE:
        covered, lo, hi = _dominated(X)
        keep = (X.tiny < 0.5) & ~covered & (hi - lo > X.tiny)
    else:
        keep = X.tiny < 0.5
    el, lo, hi = el[keep], lo[keep], hi[keep]
    final_el, final_lo, final_hi, lonely = [], [], [], []
    for _ in range(_MAX_ROUNDS):
        if len(el) == 0:
            break
        mid = X.points(el, 0.5 * (lo + hi))
        d, near = X.clearance(mid)
        inside = d < r - eps
        if _brute and _ == 0:
            inside[:] = False            # every element cut against all capsules in reach (for tests)
        # Pieces whose middle lies in the nearest edge's capsule: cut that capsule away.
        i = np.flatnonzero(inside)
        nxt_el, nxt_lo, nxt_hi = [], [], []
        if len(i):
            row, b0, b1 = _split(el[i], lo[i], hi[i], X.cuts(el[i], near[i]), X.tiny)
            e2 = el[i][row]
            tm = 0.5 * (lo[i] + hi[i])[row]
            # The part holding the piece's middle is inside that capsule by construction (the capsule is
            # convex and crossed only at the cuts): it goes even where rounding puts its own middle near
            # the capsule's boundary, so that every round makes progress.
            gone = X.inside_edge(X.points(e2, 0.5 * (b0 + b1)), near[i][row]) | ((b0 <= tm) & (b1 >= tm))
            lonely += [X.points(e2[gone], b0[gone]), X.points(e2[gone], b1[gone])]
            nxt_el.append(e2[~gone]), nxt_lo.append(b0[~gone]), nxt_hi.append(b1[~gone])
        # Pieces whose middle is clear: each capsule within reach takes the parts of the piece inside it
        # (between two of its cuts, decided at the middle); what no capsule takes is the kept set.
        c = np.flatnonzero(~inside)
        # A long clear piece that many capsules reach is split and goes round again: a capsule reaches
        # it only within r of the piece, so the parts are cut against few capsules each, and most of
        # them then lie in their nearest capsule and go cheaply (a dense outline). A piece that few
        # edges lie near is cut against their capsules now, whatever its length (a sparse polygon:
        # splitting it would only multiply the pieces). Pieces much longer than r are never split.
        size = X.length[el[c]] * (hi[c] - lo[c])
        parts = np.ceil(size / (_CLEAR_PIECE_R * r)).astype(np.int64)
        long_ = (parts > 1) & (size <= _SPLIT_MAX_R * r)
        if long_.any():
            long_[long_] = X.crowded(X.points(el[c][long_], 0.5 * (lo[c] + hi[c])[long_]), r + 0.5 * size[long_])
        if long_.any():
            lc, k = c[long_], parts[long_]
            row = np.repeat(np.arange(len(lc)), k)
            step = np.arange(len(row)) - np.repeat(np.cumsum(k) - k, k)
            w = (hi[lc] - lo[lc]) / k
            s0 = lo[lc][row] + w[row] * step
            s1 = np.where(step == k[row] - 1, hi[lc][row], s0 + w[row])        # the last part ends exactly
            nxt_el.append(el[lc][row]), nxt_lo.append(s0), nxt_hi.append(s1)
            c = c[~long_]
        if len(c):
            pi, pj = X.reach(el[c], lo[c], hi[c], 4.0 * eps)
        if len(c):
            gaps, touch = _uncovered(X, el[c], lo[c], hi[c], pi, pj)
            lonely.append(touch)
            row, b0, b1 = gaps
            e2 = el[c][row]
            # Each gap lies outside every capsule in reach: clear parts are decided (kept on the side's
            # side of S, else dropped: offsets of a part thinner than 2r that left it); a part that
            # rounding leaves undecided goes round again.
            xy = X.points(e2, 0.5 * (b0 + b1))
            # A gap that is its whole piece has the piece's middle, whose clearance this round measured.
            whole = (b0 == lo[c][row]) & (b1 == hi[c][row])
            d2 = np.empty(len(row))
            d2[whole] = d[c][row[whole]]
            d2[~whole] = X.clearance(xy[~whole])[0]
            clear = d2 >= r - eps
            ok = clear.copy()
            ok[clear] = X.on_side(xy[clear])
            final_el.append(e2[ok]), final_lo.append(b0[ok]), final_hi.append(b1[ok])
            nxt_el.append(e2[~clear]), nxt_lo.append(b0[~clear]), nxt_hi.append(b1[~clear])
        el = np.concatenate(nxt_el) if nxt_el else np.zeros(0, np.int64)
        lo = np.concatenate(nxt_lo) if nxt_lo else np.zeros(0)
        hi = np.concatenate(nxt_hi) if nxt_hi else np.zeros(0)
    else:
        raise RuntimeError(f"exact offsets: {len(el)} pieces still undecided after {_MAX_ROUNDS} rounds")
    sub_el = np.concatenate(final_el) if final_el else np.zeros(0, np.int64)
    lo_t = np.concatenate(final_lo) if final_lo else np.zeros(0)
    hi_t = np.concatenate(final_hi) if final_hi else np.zeros(0)
    order = np.lexsort((lo_t, sub_el))
    sub_el, lo_t, hi_t = sub_el[order], lo_t[order], hi_t[order]
    tiny = X.tiny
    # Merge touching kept sub-pieces of one element.
    if len(sub_el):
        start = np.ones(len(sub_el), dtype=bool)
        start[1:] = ~((sub_el[1:] == sub_el[:-1]) & (np.abs(lo_t[1:] - hi_t[:-1]) <= tiny[sub_el[1:]]))
        lo_t = lo_t[start]
        hi_t = np.maximum.reduceat(hi_t, np.flatnonzero(start))
        sub_el = sub_el[start]
    # Corners: ends of kept pieces at a cut (not at an element's own end); isolated points of the region
    # (an end of a removed part that is itself kept and lies on no kept piece: the centre of a square of
    # side 2r, or where two capsules just touch); …
    lonely = np.unique(np.concatenate(lonely), axis=0) if lonely else np.zeros((0, 2))
    lonely = lonely[X.kept(lonely)]
    lonely = lonely[~_on_pieces(X, sub_el, lo_t, hi_t, lonely, 4.0 * eps)]
    corner_pts = [X.points(sub_el[lo_t > 0], lo_t[lo_t > 0]), X.points(sub_el[hi_t < 1], hi_t[hi_t < 1]),
                  lonely]
    # … and the vertices where the offsets of two edges meet at an angle at an element's end (a convex
    # corner so nearly straight that the crossing falls within the precision of the ends).
    at_end = sub_el[(sub_el < X.n_seg) & (hi_t >= 1)]
    j = X.nxt[at_end]
    convex = side * X.turn[at_end] > 1e-12
    i, j = at_end[convex], j[convex]
    cosine = (X.N[i] * X.N[j]).sum(axis=1)
    good = 1.0 + cosine > 1e-12
    i, j = i[good], j[good]
    corner_pts.append(X.b[i] + r * (X.N[i] + X.N[j]) / (1.0 + cosine[good])[:, None])
    corners = _distinct(np.concatenate(corner_pts), max(1e-10 * r, 4.0 * eps))
    s = sub_el < X.n_seg
    se = sub_el[s]
    seg_out = np.stack([X.points(se, lo_t[s]), X.points(se, hi_t[s])], axis=1) if len(se) \
        else np.zeros((0, 2, 2))
    ka = sub_el[~s] - X.n_seg
    return OffsetPieces(
        side=side, r=r, seg=seg_out, seg_edge=se.astype(np.int64),
        arc_center=X.arc_v[ka], arc_start=X.arc_a0[ka] + X.arc_sw[ka] * lo_t[~s],
        arc_sweep=X.arc_sw[ka] * (hi_t[~s] - lo_t[~s]), corners=corners, precision=eps)


def _on_pieces(X, el, lo, hi, xy, tol) -> np.ndarray:
    """Whether each point lies within ``tol`` of the inside of one of the kept pieces ``(el, lo, hi)``
    (farther than ``tol`` from its ends), exactly."""
    if len(xy) == 0 or len(el) == 0:
        return np.zeros(len(xy), dtype=bool)
    if len(xy) * len(el) <= _proximity._ALL_PAIRS:
        # Few pairs: every point against every piece (each pair is measured exactly below).
        pi, pj = _proximity._all_pairs(len(xy), len(el))
    else:
        g, sag = X.geoms(el, lo, hi)
        pi, pj = shapely.STRtree(g).query(shapely.points(xy), predicate="dwithin", distance=tol + sag)
    if len(pi) == 0:
        return np.zeros(len(xy), dtype=bool)
    e, a, b = el[pj], lo[pj], hi[pj]
    s = e < X.n_seg
    d = np.empty(len(pi))
    if s.any():
        p, q = X.points(e[s], a[s]), X.points(e[s], b[s])
        v = q - p
        L2 = (v * v).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.clip(((xy[pi[s]] - p) * v).sum(axis=1) / L2, 0.0, 1.0)
        f = p + np.where(L2 > 0, u, 0.0)[:, None] * v
        d[s] = np.hypot(*(xy[pi[s]] - f).T)
    if (~s).any():
        k = e[~s] - X.n_seg
        w = xy[pi[~s]] - X.arc_v[k]
        t = _arc_param(np.arctan2(w[:, 1], w[:, 0]), X.arc_a0[k], X.arc_sw[k])
        t = np.clip(t, a[~s], b[~s])
        d[~s] = np.hypot(*(xy[pi[~s]] - X.points(e[~s], t)).T)
    # At a piece's end the point may be a corner the cut did not mark (the cut fell on an element's own
    # end, as on a pixel staircase): only points inside a piece are on it.
    p0, p1 = X.points(e, a), X.points(e, b)
    inner = (np.hypot(*(xy[pi] - p0).T) > tol) & (np.hypot(*(xy[pi] - p1).T) > tol)
    out = np.zeros(len(xy), dtype=bool)
    out[pi[(d <= tol) & inner]] = True
    return out


def _distinct(xy: np.ndarray, tol: float) -> np.ndarray:
    """The points with those within ``tol`` of an earlier one dropped."""
    if len(xy) < 2:
        return xy
    pairs = cKDTree(xy).query_pairs(tol, output_type="ndarray")
    if len(pairs) == 0:
        return xy
    keep = np.ones(len(xy), dtype=bool)
    # Drop the later of each pair, unless the earlier was dropped already (chains keep one representative).
    for i, j in sorted(map(tuple, np.sort(pairs, axis=1).tolist())):
        if keep[i]:
            keep[j] = False
    return xy[keep]
