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
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import morphology as _m
from .tolerances import ANGLE_ZERO, PENETRATION_R

__all__: list[str] = []

_TWO_PI = 2.0 * math.pi


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


def fast_disk_loops(S, r: float, q: int, init: str):
    """Disk loops ``[(centers, sides, phi, lengths, sweeps), ...]`` for every ring of S, or None.

    ``S`` is oriented (S on the left of every ring), in the engine's local frame; ``q`` is the
    ``quad_segs`` of the shrink and grow used to check the arcs.
    """
    rings = [_clean_ring(shapely.get_coordinates(ring)) for ring in shapely.get_rings(shapely.get_parts(S))]
    if any(len(v) < 3 for v in rings):
        return None
    loops = []
    for v in rings:
        u = np.roll(v, -1, axis=0) - v                  # edge i: v[i] -> v[i+1]
        ell = np.hypot(*u.T)
        u = u / ell[:, None]
        u_in = np.roll(u, 1, axis=0)
        cross = u_in[:, 0] * u[:, 1] - u_in[:, 1] * u[:, 0]
        dot = (u_in * u).sum(axis=1)
        theta = np.arctan2(cross, dot)                  # signed turn at each vertex, left positive
        if (np.abs(theta) > math.pi - 1e-6).any():
            return None                                 # a spike: no disk fits its corner
        side = np.where(theta > 0, 1.0, -1.0)
        n_in = np.column_stack([-u_in[:, 1], u_in[:, 0]])
        n_out = np.column_stack([-u[:, 1], u[:, 0]])
        centers = v + (side * r / (1.0 + dot))[:, None] * (n_in + n_out)
        t = r * np.tan(np.abs(theta) / 2)
        length = ell - t - np.roll(t, -1)
        if (length < -1e-12 * np.maximum(ell, r)).any():
            return None
        length = np.maximum(length, 0.0)
        phi = np.arctan2(u[:, 1], u[:, 0])
        loops.append((centers, side, phi, length, theta))
    centers = np.concatenate([x[0] for x in loops])
    side = np.concatenate([x[1] for x in loops])
    # Every disk must be one: inside S, at least r from its boundary (convex vertices), or at least r
    # from S (reflex vertices).
    pts = shapely.points(centers)
    boundary = S.boundary
    shapely.prepare(boundary)
    shapely.prepare(S)
    inner = side > 0
    inside = shapely.contains_xy(S, centers[:, 0], centers[:, 1])
    if (inner & ~inside).any() or (~inner & inside).any():
        return None
    if shapely.dwithin(boundary, pts, r * (1.0 - 1e-9)).any():
        return None
    E = _m._orient(_m._shrink(S, r, q))
    G = _m._orient(_m._grow(S, r, q))
    if not _arcs_clear(r, q, loops, centers, side, E, G):
        return None
    # (The straight pieces need no check: they lie on the boundary of S, which the open core and
    # anticore never meet.)
    if init != "input" and not _reaches_edges(S, boundary, r, loops, 1):
        return None
    if init == "mason" and not _reaches_edges(S, boundary, r, loops, -1):
        return None
    return loops


def _snap(P, centers: np.ndarray, r: float):
    """P with each vertex within 1e-6·r of a centre moved onto it (GEOS places them to rounding)."""
    if P.is_empty or len(centers) == 0:
        return P
    kd = cKDTree(centers)

    def move(c):
        d, j = kd.query(c)
        close = d <= 1e-6 * r
        out = c.copy()
        out[close] = centers[j[close]]
        return out

    return shapely.transform(P, move)


def _arcs_clear(r, q, loops, centers, side, E, G) -> bool:
    """No arc enters the core (convex vertices) or the anticore (reflex vertices) elsewhere."""
    pen = PENETRATION_R * r + 2.0 * r * (1.0 - math.cos(math.pi / (4 * q)))
    probes, probe_side, owner = [], [], []
    start = 0
    for c, s, phi, length, sweep in loops:
        a0 = np.roll(phi, 1) - s * (math.pi / 2)
        m = np.maximum(2, np.ceil(np.abs(sweep) / (math.pi / 16)).astype(np.int64))
        idx = np.repeat(np.arange(len(c)), m - 1)
        first = np.repeat(np.cumsum(m - 1) - (m - 1), m - 1)
        frac = (np.arange(len(idx)) - first + 1) / np.repeat(m, m - 1)
        th = a0[idx] + sweep[idx] * frac
        probes.append(c[idx] + r * np.column_stack([np.cos(th), np.sin(th)]))
        probe_side.append(s[idx])
        owner.append(start + idx)
        start += len(c)
    probes = np.concatenate(probes)
    probe_side = np.concatenate(probe_side)
    owner = np.concatenate(owner)
    for sgn, P in ((1, E), (-1, G)):
        sel = np.flatnonzero(probe_side == sgn)
        if len(sel) == 0:
            continue
        P = _snap(P, centers[side == sgn], r)
        if P.is_empty:
            return False
        # The probes lie at distance r from their own centre (a vertex of P); anything of P closer than
        # r - pen means the arc enters the core (anticore) there.
        edges = []
        for ring in shapely.get_rings(shapely.get_parts(P)):
            xy = shapely.get_coordinates(ring)
            edges.append(np.stack([xy[:-1], xy[1:]], axis=1))
        tree = shapely.STRtree(shapely.linestrings(np.concatenate(edges)))
        hits, _ = tree.query(shapely.points(probes[sel]), predicate="dwithin", distance=r - pen)
        if len(hits):
            return False
        same = np.flatnonzero(side == sgn)
        ctree = cKDTree(centers[same])
        near = ctree.query_ball_point(probes[sel], r * (1.0 - 1e-9))
        for k, found in zip(sel.tolist(), near):
            if any(same[j] != owner[k] for j in found):
                return False
    return True


def _reaches_edges(S, boundary, r, loops, side: int) -> bool:
    """Every straight piece lies on the boundary of the core (side +1) or of the anticore (side −1).

    The piece on edge i runs between the tangent points of the disks at its ends. The core touches all of
    it when the piece moved inwards by r stays at distance ≥ r from the boundary of S (it lies in the
    shrink); the anticore when the piece moved outwards by r stays at distance ≥ r from S. Needed for
    ``init="core"`` (the core's rings must be the rings of S) and, with both sides, for ``"mason"``.
    """
    segs = []
    for c, s, phi, length, sweep in loops:
        keep = length > 0
        n = np.column_stack([-np.sin(phi), np.cos(phi)])[keep]
        d = np.column_stack([np.cos(phi), np.sin(phi)])[keep]
        a = c[keep] - s[keep, None] * r * n + side * r * n
        b = a + length[keep, None] * d
        segs.append(np.stack([a, b], axis=1))
    segs = np.concatenate(segs)
    if len(segs) == 0:
        return True
    lines = shapely.linestrings(segs)
    target = boundary if side > 0 else S
    if shapely.dwithin(target, lines, r * (1.0 - 1e-9)).any():
        return False
    mid = 0.5 * (segs[:, 0] + segs[:, 1])
    inside = shapely.contains_xy(S, mid[:, 0], mid[:, 1])
    return bool(inside.all() if side > 0 else not inside.any())
