"""Which edges lie within a distance close to r of given points or segments, on dense outlines.

Every question the engine asks of S's boundary, of the shrink and of the grow has the form "which edges
come within D of this point (or piece)", with D close to r, asked at places that are themselves about r
from the boundary: a medial-axis point, a tangent of a tight loop. Such queries graze the boundary. A
search by bounding boxes (shapely's R-tree) examines every edge in the box around the query, a whole arc
of boundary; a ball search among the edges' midpoints (a k-d tree) examines only the edges in a shell
around the ball as wide as the edges are long. So edges are grouped by length (half-lengths within a
factor of two), one k-d tree a group, and the few edges longer than a fiftieth of r go to an R-tree.
Every pair a search returns is then measured exactly.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import cKDTree

__all__: list[str] = []

#: Edges with half-length above this fraction of r are searched with an R-tree, not a k-d tree.
_LONG_HALF_R = 0.01


def _tree(points: np.ndarray) -> cKDTree:
    """A k-d tree split at sliding midpoints: on points strung along curves its boxes hug the curve."""
    return cKDTree(points, balanced_tree=False, compact_nodes=False)


def point_segment_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from each point ``x[i]`` to the segment ``a[i]b[i]``, ``(n,)``."""
    d = b - a
    L2 = np.einsum("ij,ij->i", d, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.clip(np.einsum("ij,ij->i", x - a, d) / L2, 0.0, 1.0)
    t = np.where(L2 > 0, t, 0.0)
    return np.hypot(x[:, 0] - a[:, 0] - t * d[:, 0], x[:, 1] - a[:, 1] - t * d[:, 1])


def segment_segment_distance(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance between the segments ``p[i]q[i]`` and ``a[i]b[i]``, ``(n,)`` (0 where they cross)."""

    def orient(o, u, v):
        return (u[:, 0] - o[:, 0]) * (v[:, 1] - o[:, 1]) - (u[:, 1] - o[:, 1]) * (v[:, 0] - o[:, 0])

    dist = np.minimum.reduce([point_segment_distance(p, a, b), point_segment_distance(q, a, b),
                              point_segment_distance(a, p, q), point_segment_distance(b, p, q)])
    cross = (orient(p, q, a) * orient(p, q, b) < 0) & (orient(a, b, p) * orient(a, b, q) < 0)
    return np.where(cross, 0.0, dist)


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
    """

    def __init__(self, a: np.ndarray, b: np.ndarray, r: float):
        self.a, self.b = a, b
        half = 0.5 * np.hypot(*(b - a).T) if len(a) else np.zeros(0)
        short = half <= _LONG_HALF_R * r
        self.classes = [(ids, float(half[ids].max()), _tree(0.5 * (a[ids] + b[ids])))
                        for ids in _length_classes(half, np.flatnonzero(short))]
        self.long = np.flatnonzero(~short)
        self.rtree = shapely.STRtree(shapely.linestrings(np.stack([a[self.long], b[self.long]], axis=1))) \
            if len(self.long) else None

    def __len__(self) -> int:
        return len(self.a)

    def near_points(self, x: np.ndarray, dist: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pairs ``(point, edge, distance)`` with the edge within ``dist`` of the point, sorted by point
        and then by distance."""
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
        pi, ei = np.concatenate(P), np.concatenate(E)
        d = point_segment_distance(x[pi], self.a[ei], self.b[ei])
        keep = d <= dist
        pi, ei, d = pi[keep], ei[keep], d[keep]
        order = np.lexsort((d, pi))
        return pi[order], ei[order], d[order]

    def clear_of(self, x: np.ndarray, dist: float) -> np.ndarray:
        """Whether each point of ``x`` is at distance ≥ ``dist`` from every edge."""
        pi, _, d = self.near_points(x, dist)
        ok = np.ones(len(x), dtype=bool)
        ok[pi[d < dist]] = False
        return ok

    def near_segments(self, p: np.ndarray, q: np.ndarray, dist: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs ``(segment, edge)`` with the edge within ``dist`` of the segment ``p[i]q[i]``, sorted."""
        if len(p) == 0 or len(self) == 0:
            return np.zeros(0, np.int64), np.zeros(0, np.int64)
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
            si, ei = self.rtree.query(shapely.linestrings(np.stack([p, q], axis=1)), predicate="dwithin",
                                      distance=dist)
            S.append(si)
            E.append(self.long[ei])
        si, ei = np.concatenate(S), np.concatenate(E)
        keep = segment_segment_distance(p[si], q[si], self.a[ei], self.b[ei]) <= dist
        si, ei = si[keep], ei[keep]
        order = np.lexsort((ei, si))
        return si[order], ei[order]


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
