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

How the arcs are checked: points along each arc are tested against GEOS's opening and closing of S at
the chosen tolerance. Their chords lie inside the exact arcs, so the opening is (up to GEOS's rounding)
inside the exact core and the closing contains the exact fillet: a point found inside the opening (outside
the closing) is a real violation, and a violation shallower than the chord error can go unseen — the
result is then exact in structure within the tolerance. Centres and coverage are checked against the
shrink and grow, with the vertices of the other kind (the only features those approximate) tested
exactly.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import morphology as _m
from .tolerances import ANGLE_ZERO

__all__: list[str] = []

_TWO_PI = 2.0 * math.pi
_EXACT = 1e-9         # relative slack of the exact distance tests (rounding only)
_GEOS = 1e-6          # relative slack for GEOS's placement of offset vertices


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
    E = _m._shrink_raw(S, r, q)
    G = _m._grow_raw(S, r, q)
    for P in (E, G):
        shapely.prepare(P)
    if not _centers_valid(D, S, E, G):
        return None
    R = _m._polygonal(E.buffer(r, quad_segs=q)) if not E.is_empty else E
    F = _m._polygonal(G.buffer(-r, quad_segs=q))
    if not _arcs_clear(D, R, F):
        return None
    if init != "input" and not _reaches_edges(D, E, 1):
        return None
    if init == "mason" and not _reaches_edges(D, G, -1):
        return None
    return [(D.c[sl], D.side[sl], D.phi[sl], length[sl], D.theta[sl]) for sl in D.slices]


def _boundary(P):
    """The boundary of P, prepared for repeated distance queries."""
    b = P.boundary
    shapely.prepare(b)
    return b


def _centers_valid(D: _Rings, S, E, G) -> bool:
    """Every disk lies in S at distance ≥ r from its boundary (convex vertices) or outside, at distance
    ≥ r from S (reflex vertices)."""
    r = D.r
    inner = D.side > 0
    inside = shapely.contains_xy(S, D.c[:, 0], D.c[:, 1])
    if (inner != inside).any():
        return False
    # The shrink (grow) decides, for each centre moved a hair (1e-6·r) further from S's boundary so that it
    # lies strictly inside the shrink (outside the grow) unless it is not a valid centre. The shrink's
    # chords err only near arcs, i.e. near the vertices of the other kind, which are tested exactly below.
    bis = D.n[D.prev] + D.n
    bis /= np.hypot(*bis.T)[:, None]
    moved = D.c + (D.side * _GEOS * r)[:, None] * bis
    if E.is_empty and inner.any():
        return False
    if inner.any() and not shapely.contains_xy(E, moved[inner, 0], moved[inner, 1]).all():
        return False
    if (~inner).any() and shapely.intersects_xy(G, moved[~inner, 0], moved[~inner, 1]).any():
        return False
    for side in (1, -1):
        mine = np.flatnonzero(D.side == side)
        other = np.flatnonzero(D.side != side)
        if len(mine) and len(other):
            near = cKDTree(D.v[other]).query_ball_point(D.c[mine], r * (1 - _EXACT), return_length=True)
            if (near > 0).any():
                return False
    return True


def _arcs_clear(D: _Rings, R, F) -> bool:
    """No arc enters the core (convex vertices) or the anticore (reflex vertices) elsewhere.

    ``R`` and ``F`` are the chord-approximated opening and closing of S: points along each arc must lie
    outside the opening (convex vertices) and inside the closing (reflex vertices).
    """
    r = D.r
    m = np.maximum(2, np.ceil(np.abs(D.theta) / (math.pi / 16)).astype(np.int64))
    owner = np.repeat(np.arange(len(D.v)), m - 1)
    first = np.repeat(np.cumsum(m - 1) - (m - 1), m - 1)
    frac = (np.arange(len(owner)) - first + 1) / np.repeat(m, m - 1)
    a0 = D.phi[D.prev] - D.side * (math.pi / 2)
    th = a0[owner] + D.theta[owner] * frac
    # Just outside its own disk (by rounding-proof 1e-8·r), so that only another disk can cover a point.
    probes = D.c[owner] + (r * (1 + 1e-8)) * np.column_stack([np.cos(th), np.sin(th)])
    inner = D.side[owner] > 0
    for P in (R, F):
        shapely.prepare(P)
    in_core = shapely.contains_xy(R, probes[inner, 0], probes[inner, 1]) if not R.is_empty else False
    in_fillet = shapely.intersects_xy(F, probes[~inner, 0], probes[~inner, 1])
    return not np.any(in_core) and bool(np.all(in_fillet))


def _reaches_edges(D: _Rings, P, side: int) -> bool:
    """Every straight piece lies on the boundary of the core (side +1) or of the anticore (side −1).

    The piece on edge i runs between the tangent points of the disks at its ends. The core touches all of
    it when the piece moved inwards by r lies in the shrink, the anticore when moved outwards it lies
    outside the grow. Needed for ``init="core"`` (the core's rings must be the rings of S) and, with both
    sides, for ``"mason"``.
    """
    r = D.r
    keep = D.length > 0
    if not keep.any():
        return True
    a = D.c[keep] - (D.side[keep] * r)[:, None] * D.n[keep] + side * r * D.n[keep]
    b = a + np.maximum(D.length[keep], 0)[:, None] * D.u[keep]
    # Sample each moved piece (its ends, and every r/4) pushed a hair (1e-6·r) further from S's boundary:
    # strictly inside the shrink (outside the grow) when the core (anticore) reaches the piece.
    count = np.maximum(1, np.ceil(D.length[keep] / (0.25 * r)).astype(np.int64))
    owner = np.repeat(np.arange(len(a)), count + 1)
    first = np.repeat(np.cumsum(count + 1) - (count + 1), count + 1)
    f = (np.arange(len(owner)) - first) / np.repeat(count, count + 1)
    # At an end where the disk is on this side, the moved piece ends at that disk's centre, a corner of
    # the shrink (grow): push along the corner's bisector there, along the edge's normal elsewhere.
    idx = np.flatnonzero(keep)
    bis = D.n[D.prev] + D.n
    bis /= np.hypot(*bis.T)[:, None]
    push = np.repeat(D.n[idx], count + 1, axis=0)
    at_start, at_end = f == 0, f == 1
    i0, i1 = idx[owner], D.next[idx[owner]]
    corner0 = at_start & (D.side[i0] == side)
    corner1 = at_end & (D.side[i1] == side)
    push[corner0] = bis[i0[corner0]]
    push[corner1] = bis[i1[corner1]]
    pts = a[owner] + f[:, None] * (b - a)[owner] + (side * _GEOS * r) * push
    if side > 0:
        if P.is_empty or not shapely.contains_xy(P, pts[:, 0], pts[:, 1]).all():
            return False
    elif shapely.intersects_xy(P, pts[:, 0], pts[:, 1]).any():
        return False
    # Exactly: the moved pieces keep distance r from the vertices of the other kind (the only features
    # the coarse buffer approximates).
    other = D.v[D.side != side]
    if len(other):
        mid = 0.5 * (a + b)
        reach = 0.5 * float(np.hypot(*(b - a).T).max()) + r
        pairs = cKDTree(mid).sparse_distance_matrix(cKDTree(other), reach, output_type="ndarray")
        if len(pairs):
            k, j = pairs["i"], pairs["j"]
            d = b[k] - a[k]
            L2 = (d * d).sum(axis=1)
            with np.errstate(invalid="ignore", divide="ignore"):
                t = np.clip(((other[j] - a[k]) * d).sum(axis=1) / L2, 0, 1)
            t = np.where(L2 > 0, t, 0.0)
            if (np.hypot(*(other[j] - a[k] - t[:, None] * d).T) < r * (1 - _EXACT)).any():
                return False
    return True
