"""Which edges lie within a distance close to r of given points or segments, on dense outlines.

Every question the engine asks of S's boundary, of the shrink and of the grow has the form "which edges
come within D of this point (or piece)", with D close to r, asked at places that are themselves about r
from the boundary: a medial-axis point, a tangent of a tight loop. Such queries graze the boundary. A
search by bounding boxes (shapely's R-tree) examines every edge in the box around the query, a whole arc
of boundary; a ball search among the edges' midpoints (a k-d tree) examines only the edges in a shell
around the ball as wide as the edges are long. So edges are grouped by length (half-lengths within a
factor of two), one k-d tree a group, and the few edges longer than a fiftieth of r go to an R-tree.
Every pair a search returns is then measured exactly.

Small questions (a footprint of thirty edges, a few dozen queries) cost more in building and walking
trees than in measuring: below `_EDGE_ALL_PAIRS` pairs every pair is measured, and below `_BOX_PAIRS`
the candidates are the pairs whose bounding boxes overlap, found by one broadcast comparison; the trees
are built only when a question needs them. All three ways give the same pairs.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

__all__: list[str] = []

#: Edges with half-length above this fraction of r are searched with an R-tree, not a k-d tree.
_LONG_HALF_R = 1.0

#: Below this many (query, item) pairs every pair is measured: cheaper than building and walking trees
#: (a small polygon's loop against its offsets), and the same pairs come out.
_ALL_PAIRS = 1 << 12

#: Below this many (segment, edge) pairs, the pairs whose bounding boxes overlap are found by one
#: broadcast comparison rather than by walking trees (the same pairs come out, and more, all measured).
#: Above it, on dense outlines (1000 short edges, grazing queries), the trees are faster; an index whose
#: queries are long pieces across few long edges may set its own (`EdgeIndex`'s ``box_pairs``).
_BOX_PAIRS = 1 << 14

#: Below this many (query, edge) pairs, `EdgeIndex` measures every pair; above (up to `_BOX_PAIRS`) it
#: measures those whose boxes overlap: on footprints' offsets, 2x faster per query from 256 pairs on.
_EDGE_ALL_PAIRS = 1 << 8


def _all_pairs(m: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Every pair ``(i, j)``, ``i < m``, ``j < n``, sorted."""
    return np.repeat(np.arange(m, dtype=np.int64), n), np.tile(np.arange(n, dtype=np.int64), m)


def _tree(points: np.ndarray) -> cKDTree:
    """A k-d tree split at sliding midpoints: on points strung along curves its boxes hug the curve."""
    return cKDTree(points, balanced_tree=False, compact_nodes=False)


def point_segment_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from each point ``x[i]`` to the segment ``a[i]b[i]``, ``(n,)``."""
    dx, dy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    wx, wy = x[:, 0] - a[:, 0], x[:, 1] - a[:, 1]
    L2 = dx * dx + dy * dy
    t = np.zeros(len(L2))
    np.divide(wx * dx + wy * dy, L2, out=t, where=L2 > 0)
    np.clip(t, 0.0, 1.0, out=t)
    return np.hypot(wx - t * dx, wy - t * dy)


def segment_segment_distance(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance between the segments ``p[i]q[i]`` and ``a[i]b[i]``, ``(n,)`` (0 where they cross)."""

    def orient(o, u, v):
        return (u[:, 0] - o[:, 0]) * (v[:, 1] - o[:, 1]) - (u[:, 1] - o[:, 1]) * (v[:, 0] - o[:, 0])

    dist = np.minimum.reduce([point_segment_distance(p, a, b), point_segment_distance(q, a, b),
                              point_segment_distance(a, p, q), point_segment_distance(b, p, q)])
    cross = (orient(p, q, a) * orient(p, q, b) < 0) & (orient(a, b, p) * orient(a, b, q) < 0)
    return np.where(cross, 0.0, dist)


def _beyond_line(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray, dist: float) -> np.ndarray:
    """Rows where the segment ``p[i]q[i]`` lies beyond ``dist`` on one side of the line ``a[i]b[i]``.

    Such a segment is farther than ``dist`` from that edge too: a cheap first test, since in a grazing
    query most edges face the query from about r away.
    """
    d = b - a
    L = np.hypot(d[:, 0], d[:, 1])
    sp = d[:, 0] * (p[:, 1] - a[:, 1]) - d[:, 1] * (p[:, 0] - a[:, 0])
    sq = d[:, 0] * (q[:, 1] - a[:, 1]) - d[:, 1] * (q[:, 0] - a[:, 0])
    reach = dist * L
    return ((sp > reach) & (sq > reach)) | ((sp < -reach) & (sq < -reach))


def _length_classes(half: np.ndarray, pick: np.ndarray) -> list[np.ndarray]:
    """Indices of ``pick`` grouped by half-length within a factor of two."""
    level = np.floor(np.log2(np.maximum(half[pick], 1e-300))).astype(np.int64)
    order = np.argsort(level, kind="stable")
    cuts = np.flatnonzero(np.diff(level[order])) + 1
    return [pick[g] for g in np.split(order, cuts) if len(g)]


class EdgeIndex:
    """Segments ``a[i]b[i]`` indexed for grazing distance queries (see the module's notes).

    Parameters
    ----------
    a, b : (m, 2) float
        The segments' ends.
    r : float
        The scale of the queries' distances; edges with half-length above ``0.01·r`` go to an R-tree.
    box_pairs : int, optional
        Up to this many (query, edge) pairs, candidates by one broadcast comparison of bounding boxes
        rather than by the trees (default `_BOX_PAIRS`).

    Examples
    --------
    >>> a = np.array([[0.0, 0.0], [4.0, 0.0]]); b = np.array([[4.0, 0.0], [4.0, 4.0]])
    >>> si, ei = EdgeIndex(a, b, 1.0).near_segments(np.array([[1.0, 0.5]]), np.array([[3.0, 0.5]]), 1.0)
    >>> ei.tolist()
    [0, 1]
    """

    def __init__(self, a: np.ndarray, b: np.ndarray, r: float, box_pairs: int | None = None):
        self.a, self.b, self.r = a, b, r
        self.box_pairs = box_pairs
        self._boxes = None
        self._trees = None

    def _build(self):
        """The k-d trees of the length classes and the R-tree of the long edges, built on first use (a
        small outline's queries may all go by `_all_pairs` or `_box_pairs`)."""
        a, b = self.a, self.b
        half = 0.5 * np.hypot(*(b - a).T) if len(a) else np.zeros(0)
        short = half <= _LONG_HALF_R * self.r
        classes = [(ids, float(half[ids].max()), _tree(0.5 * (a[ids] + b[ids])))
                   for ids in _length_classes(half, np.flatnonzero(short))]
        long_ = np.flatnonzero(~short)
        rtree = shapely.STRtree(shapely.linestrings(np.stack([a[long_], b[long_]], axis=1))) \
            if len(long_) else None
        self._trees = (classes, long_, rtree)
        return self._trees

    @property
    def classes(self) -> list:
        """``(edge ids, largest half-length, k-d tree of their middles)`` per length class."""
        return (self._trees or self._build())[0]

    @property
    def long(self) -> np.ndarray:
        """The edges searched with the R-tree."""
        return (self._trees or self._build())[1]

    @property
    def rtree(self):
        """The R-tree of the long edges (None if there are none)."""
        return (self._trees or self._build())[2]

    def __len__(self) -> int:
        return len(self.a)

    def _box_limit(self) -> int:
        return _BOX_PAIRS if self.box_pairs is None else self.box_pairs

    def near_points(self, x: np.ndarray, dist: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pairs ``(point, edge, distance)`` with the edge within ``dist`` of the point.

        Sorted by point, then by distance.
        """
        if 0 < len(x) * len(self) <= _EDGE_ALL_PAIRS:
            return self._measured(x, *_all_pairs(len(x), len(self)), dist)
        if 0 < len(x) * len(self) <= self._box_limit():
            return self._measured(x, *self._box_pairs(x, x, dist), dist)
        P, E = [], []
        if len(x) and self.classes:
            tree = _tree(x)
            for ids, half, kd in self.classes:
                hits = tree.sparse_distance_matrix(kd, dist + half, output_type="ndarray")
                P.append(hits["i"].astype(np.int64))
                E.append(ids[hits["j"]])
        if len(x) and self.rtree is not None:
            pi, ei = self.rtree.query(shapely.points(x), predicate="dwithin", distance=dist)
            P.append(pi)
            E.append(self.long[ei])
        if not P:
            return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
        return self._measured(x, np.concatenate(P), np.concatenate(E), dist)

    def _measured(self, x: np.ndarray, pi: np.ndarray, ei: np.ndarray, dist: float):
        """Of candidate pairs ``(point, edge)``, those within ``dist``, with their distance, sorted."""
        far = _beyond_line(x[pi], x[pi], self.a[ei], self.b[ei], dist)
        pi, ei = pi[~far], ei[~far]
        d = point_segment_distance(x[pi], self.a[ei], self.b[ei])
        keep = d <= dist
        pi, ei, d = pi[keep], ei[keep], d[keep]
        order = np.lexsort((d, pi))
        return pi[order], ei[order], d[order]

    def nearest(self, x: np.ndarray, exact: bool = True) -> tuple[np.ndarray, np.ndarray]:
        """The nearest edge to each point and its distance: ``(edge, distance)``.

        Each length class offers the edges of its eight nearest midpoints; with ``exact``, a point for
        which some class could still hide a nearer edge (its eighth midpoint is not far enough) is
        settled by a ball search. Without, each class offers two, and the answer is the nearest of those
        (on a boundary that grazes the point, one of the edges at about the nearest distance).
        """
        best = np.full(len(x), np.inf)
        edge = np.full(len(x), -1, dtype=np.int64)
        doubt = np.zeros(len(x), dtype=bool)
        for ids, half, kd in self.classes:
            k = min(8 if exact else 2, len(ids))
            dm, j = kd.query(x, k=k)
            dm, j = dm.reshape(len(x), k), j.reshape(len(x), k)
            e = ids[j]
            d = point_segment_distance(np.repeat(x, k, axis=0), self.a[e.ravel()], self.b[e.ravel()])
            d = d.reshape(len(x), k)
            col = np.argmin(d, axis=1)
            dmin = d[np.arange(len(x)), col]
            better = dmin < best
            best[better] = dmin[better]
            edge[better] = e[np.arange(len(x)), col][better]
            if k < len(ids):
                doubt |= dm[:, -1] - half < best
        if self.rtree is not None and len(x):
            pi, ei = self.rtree.query_nearest(shapely.points(x), all_matches=False)
            e = self.long[ei]
            d = point_segment_distance(x[pi], self.a[e], self.b[e])
            better = d < best[pi]
            best[pi[better]] = d[better]
            edge[pi[better]] = e[better]
        doubt = np.flatnonzero(doubt) if exact else np.zeros(0, dtype=np.int64)
        if len(doubt):
            pi, ei, d = self.near_points(x[doubt], float(best[doubt].max()))
            first = np.r_[True, pi[1:] != pi[:-1]] if len(pi) else np.zeros(0, bool)
            pi, ei, d = pi[first], ei[first], d[first]          # sorted by point, then by distance
            better = d < best[doubt[pi]]
            best[doubt[pi[better]]] = d[better]
            edge[doubt[pi[better]]] = ei[better]
        return edge, best

    def nearby_distance(self, x: np.ndarray) -> np.ndarray:
        """For each point, the distance to some edge near it: a cheap upper bound on the nearest.

        It is the distance to the edge of the nearest midpoint of each length class, at most twice the
        class's half-length more than the distance to the nearest edge; for sizing a search.
        """
        out = np.full(len(x), np.inf)
        for ids, _, kd in self.classes:
            _, j = kd.query(x, k=1)
            out = np.minimum(out, point_segment_distance(x, self.a[ids[j]], self.b[ids[j]]))
        if self.rtree is not None and len(x):
            pi, ei = self.rtree.query_nearest(shapely.points(x), all_matches=False)
            e = self.long[ei]
            np.minimum.at(out, pi, point_segment_distance(x[pi], self.a[e], self.b[e]))
        return out

    def clear_of(self, x: np.ndarray, dist: float) -> np.ndarray:
        """Whether each point of ``x`` is at distance ≥ ``dist`` from every edge.

        A point with an edge nearer than ``dist`` among the edges of its few nearest midpoints is settled
        at once; only the others need the full search.
        """
        ok = np.ones(len(x), dtype=bool)
        open_ = np.arange(len(x))
        for ids, half, kd in self.classes:
            if len(open_) == 0:
                break
            k = min(4, len(ids))
            _, j = kd.query(x[open_], k=k, distance_upper_bound=dist + half)
            j = j.reshape(len(open_), k)
            found = j < len(ids)
            rows, cols = np.nonzero(found)
            e = ids[j[rows, cols]]
            near = point_segment_distance(x[open_[rows]], self.a[e], self.b[e]) < dist
            hit = np.zeros(len(open_), dtype=bool)
            hit[rows[near]] = True
            ok[open_[hit]] = False
            open_ = open_[~hit]
        if len(open_):
            pi, _, d = self.near_points(x[open_], dist)
            ok[open_[pi[d < dist]]] = False
        return ok

    def near_segments(self, p: np.ndarray, q: np.ndarray, dist) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(segment, edge)`` with the edge within ``dist`` of the segment ``p[i]q[i]``, sorted.

        ``dist`` is one distance, or one for each segment (``(len(p),)``).
        """
        if len(p) == 0 or len(self) == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        each = np.ndim(dist) > 0
        if each:
            dist = np.asarray(dist, dtype=float)
        if len(p) * len(self) <= _EDGE_ALL_PAIRS:
            si, ei = _all_pairs(len(p), len(self))
        elif len(p) * len(self) <= self._box_limit():
            si, ei = self._box_pairs(p, q, dist)
        else:
            si, ei = self._candidates(p, q, float(np.max(dist)))
            # A segment is no nearer to an edge than its middle is, less its half-length: this one
            # distance drops most candidates of short segments that graze the outline (and none that the
            # exact test below keeps: the margin is far above rounding).
            mid = 0.5 * (p + q)
            shalf = 0.5 * np.hypot(*(q - p).T)
            bound = point_segment_distance(mid[si], self.a[ei], self.b[ei]) - shalf[si]
            ds = dist[si] if each else dist
            near = bound <= ds + 1e-9 * (ds + shalf[si])
            si, ei = si[near], ei[near]
        ds = dist[si] if each else dist
        far = _beyond_line(p[si], q[si], self.a[ei], self.b[ei], ds)
        si, ei = si[~far], ei[~far]
        ds = dist[si] if each else dist
        keep = segment_segment_distance(p[si], q[si], self.a[ei], self.b[ei]) <= ds
        si, ei = si[keep], ei[keep]
        order = np.lexsort((ei, si))
        return si[order], ei[order]

    def _box_pairs(self, p: np.ndarray, q: np.ndarray, dist) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(segment, edge)`` whose bounding boxes, the segment's grown by ``dist`` (and a margin
        far above rounding), overlap: every pair within ``dist`` and others, sorted by segment, then edge;
        one broadcast comparison of all pairs (few segments or few edges)."""
        if self._boxes is None:
            lo, hi = np.minimum(self.a, self.b), np.maximum(self.a, self.b)
            self._boxes = (lo, hi, float(np.abs(np.concatenate([lo, hi])).max()))
        lo, hi, scale = self._boxes
        pad = np.reshape(dist + 1e-9 * (dist + scale), (-1, 1))
        slo, shi = np.minimum(p, q) - pad, np.maximum(p, q) + pad
        hit = ((slo[:, None, 0] <= hi[None, :, 0]) & (shi[:, None, 0] >= lo[None, :, 0])
               & (slo[:, None, 1] <= hi[None, :, 1]) & (shi[:, None, 1] >= lo[None, :, 1]))
        si, ei = np.nonzero(hit)
        return si.astype(np.int64), ei.astype(np.int64)

    def _candidates(self, p: np.ndarray, q: np.ndarray, dist: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(segment, edge)`` that may lie within ``dist``: every pair that does, and others."""
        mid = 0.5 * (p + q)
        shalf = 0.5 * np.hypot(*(q - p).T)
        S, E = [], []
        for group in _length_classes(shalf, np.arange(len(p))):
            tree = _tree(mid[group])
            reach = dist + float(shalf[group].max())
            for ids, half, kd in self.classes:
                hits = tree.sparse_distance_matrix(kd, reach + half, output_type="ndarray")
                S.append(group[hits["i"]])
                E.append(ids[hits["j"]])
        if self.rtree is not None:
            # Boxes grown by ``dist`` (and a margin far above rounding): the tree's own box test, with no
            # exact distance from GEOS (which cost more than all the rest); the caller's exact test follows.
            pad = dist + 1e-9 * (dist + float(np.abs(p).max(initial=0.0)) + float(np.abs(q).max(initial=0.0)))
            lo, hi = np.minimum(p, q) - pad, np.maximum(p, q) + pad
            si, ei = self.rtree.query(shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]))
            S.append(si)
            E.append(self.long[ei])
        return np.concatenate(S), np.concatenate(E)


class PointIndex:
    """Points indexed for "which points lie within a distance of these points or segments".

    Parameters
    ----------
    xy : (m, 2) float
    """

    def __init__(self, xy: np.ndarray):
        self.xy = xy
        self.kd = _tree(xy) if len(xy) else None

    def near_points(self, x: np.ndarray, dist: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(query point, indexed point)`` at most ``dist`` apart, sorted."""
        if self.kd is None or len(x) == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        hits = _tree(x).sparse_distance_matrix(self.kd, dist, output_type="ndarray")
        i, j = hits["i"].astype(np.int64), hits["j"].astype(np.int64)
        order = np.lexsort((j, i))
        return i[order], j[order]

    def near_segments(self, p: np.ndarray, q: np.ndarray, dist: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(segment, indexed point)`` with the point within ``dist`` of the segment ``p[i]q[i]``."""
        if self.kd is None or len(p) == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
        if len(p) * len(self.xy) <= _ALL_PAIRS:
            si, j = _all_pairs(len(p), len(self.xy))
        else:
            mid = 0.5 * (p + q)
            shalf = 0.5 * np.hypot(*(q - p).T)
            S, J = [], []
            for group in _length_classes(shalf, np.arange(len(p))):
                hits = _tree(mid[group]).sparse_distance_matrix(self.kd, dist + float(shalf[group].max()),
                                                                output_type="ndarray")
                S.append(group[hits["i"]])
                J.append(hits["j"].astype(np.int64))
            si, j = np.concatenate(S), np.concatenate(J)
        keep = point_segment_distance(self.xy[j], p[si], q[si]) <= dist
        si, j = si[keep], j[keep]
        order = np.lexsort((j, si))
        return si[order], j[order]
