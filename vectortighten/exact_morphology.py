"""Exact boundaries of the shrink, grow, core and fillet, as loops of segments and arcs.

`offsets.exact_offsets` gives the boundary of the closed shrink ``X = S↓r`` (side +1) and of the closed
shrink of the complement ``X = (S^c)↓r`` (side −1) as loose pieces: segments parallel to S's edges and
arcs of radius r about its vertices. This module chains those pieces into closed `Loop`s and derives the
other three boundaries from them, in closed form.

Derivation
----------
*Orientation.* Every piece of side +1 runs with ``S↓r`` on its left (an edge's parallel runs the way the
edge does, an arc about a reflex vertex turns right). Every piece of side −1 runs with the grow ``S↑r``
on its left; reversed, it runs with ``X = (S^c)↓r`` on its left. So in both cases the pieces, taken with
X on their left, chain head to tail into the boundary of X. Where several pieces leave one point (the
centre line of a part exactly 2r wide leaving the rest of X, a T of such lines), the chain takes the one
that turns most to the right: it walks round the outside of X, into every zero-width part and back, so
that the loop is the boundary of the *closed* set X, zero-width parts included. A piece that would run
straight back is the last choice.

*Shrink and grow.* ``∂(S↓r)`` is the chained loops of side +1; ``∂(S↑r)`` those of side −1 reversed
(outer boundaries counter-clockwise, holes clockwise). A zero-width part has no area: the loops returned
for the shrink and the grow leave out the loops that enclose none (a shrink that is only a centre line or
a point comes back empty); the core and the fillet are built from all of them.

*Core.* ``R_r(S) = X ⊕ D_r`` with ``X = S↓r`` (the union of the r-disks centred in X). Its boundary is
the set of points at distance exactly r from X, that is the outward offset of ``∂X`` by r, which is
formed piece by piece:

* a segment of ``∂X`` (the parallel of an edge e at distance r) moves to the right by r onto e itself:
  the part of e that survives in the core;
* an arc of ``∂X`` of radius r about a reflex vertex v turns right (it is concave); moved outward by r
  its radius becomes r − r = 0: it collapses to v, a reflex corner that survives in the core;
* at a corner of X, where the incoming piece's tangent turns left by θ into the outgoing one, the
  offset is the arc of radius r about the corner from the right normal of the incoming tangent to that
  of the outgoing, sweeping θ counter-clockwise: the convex arcs of the core, centred at the corners of
  the shrink (a turn of exactly π, at the end of a zero-width part, gives a half circle);
* at a tangent join (a segment meeting an arc) nothing is added;
* an isolated point of X (the centre of a square of side 2r) gives a whole circle of radius r.

The pieces of ``∂X`` carry ``S``'s feet (every point of a kept piece is at distance exactly r from ∂S,
with its nearest boundary point at its right normal), which is why the offset of each lies on ∂S or on
the boundary of a disk inside S. ``∂X`` has no reflex corners (``(S^c)↑r`` is a union of open r-disks),
so consecutive offsets never cross, except where two parts of X touch at a single point: that pinch is
reported as an error rather than answered wrongly.

*Fillet.* ``F_r(S)`` is the complement of ``R_r(S^c)`` (the closing is the dual of the opening), so its
loops are the core construction applied to the loops of ``X = (S^c)↓r``, reversed.

Every piece comes from one closed-form offset, so a loop's pieces meet to the precision of the offsets
(`offsets.precision_of`), far inside `Loop`'s closing tolerance, and no buffer is sampled anywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import MultiPolygon, Polygon

from .curves import Loop
from .offsets import OffsetPieces, exact_offsets, precision_of

__all__ = ["ExactBoundary", "exact_boundary", "exact_core", "exact_fillet", "exact_grow", "exact_shrink", "offset_loops"]

_TWO_PI = 2.0 * math.pi
#: A turn (radians) below this between two chained pieces is a tangent join, not a corner.
_JOIN_ANGLE = 1e-12
#: A turn within this of ±π is a piece running straight back (taken as +π: the end of a zero-width part).
_BACK_ANGLE = 1e-9
#: Chained pieces meet within this many offset precisions.
_NODE_PRECISIONS = 64.0
#: A piece shorter than this fraction of r with a loose end is a crumb of a near-tangent cut (`_pruned`).
_SLIVER_R = 1e-6


class _Pieces:
    """Pieces of one offset as arrays, each with X on its left: kind, data rows as `Loop` holds them,
    start and end points, start and end tangents, signed curvature."""

    def __init__(self, E: OffsetPieces, reverse: bool):
        ns, na = len(E.seg), len(E.arc_center)
        self._seg_edge = E.seg_edge
        seg = E.seg[:, ::-1] if reverse else E.seg
        a0 = E.arc_start + (E.arc_sweep if reverse else 0.0)
        sw = -E.arc_sweep if reverse else E.arc_sweep
        radius = np.full(na, E.r)
        self.arc = np.r_[np.zeros(ns, bool), np.ones(na, bool)]
        self.data = np.concatenate([np.column_stack([seg[:, 0], seg[:, 1], np.zeros(ns)]),
                                    np.column_stack([E.arc_center, radius, a0, sw])]).reshape(-1, 5)
        a1 = a0 + sw
        arc_p0 = E.arc_center + radius[:, None] * np.column_stack([np.cos(a0), np.sin(a0)])
        arc_p1 = E.arc_center + radius[:, None] * np.column_stack([np.cos(a1), np.sin(a1)])
        self.start = np.concatenate([seg[:, 0], arc_p0]).reshape(-1, 2)
        self.end = np.concatenate([seg[:, 1], arc_p1]).reshape(-1, 2)
        d = seg[:, 1] - seg[:, 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            u = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        sgn = np.where(sw >= 0, 1.0, -1.0)
        self.t0 = np.concatenate([u, np.column_stack([-sgn * np.sin(a0), sgn * np.cos(a0)])]).reshape(-1, 2)
        self.t1 = np.concatenate([u, np.column_stack([-sgn * np.sin(a1), sgn * np.cos(a1)])]).reshape(-1, 2)
        self.kappa = np.r_[np.zeros(ns), sgn / E.r]
        self.edge: tuple[np.ndarray, np.ndarray] | None = None   # S's edge under each straight piece

    def with_edges(self, S) -> _Pieces:
        """Record, for each straight piece, the edge of S (oriented, as `exact_offsets` read it) it is
        the parallel of, so that the core and the fillet put their pieces on S's edges (`_offset_rows`)."""
        from .offsets import _edges

        a, b, _, _ = _edges(S)
        self.edge = (a[self._seg_edge], b[self._seg_edge])
        return self

    def __len__(self) -> int:
        return len(self.arc)


def _turn(t_in: np.ndarray, t_out: np.ndarray, back: float = math.pi) -> np.ndarray:
    """Signed turn from tangent ``t_in`` to ``t_out`` in (−π, π]; a reversal counts as ``back``."""
    tau = np.arctan2(t_in[..., 0] * t_out[..., 1] - t_in[..., 1] * t_out[..., 0], (t_in * t_out).sum(axis=-1))
    return np.where(np.abs(tau) > math.pi - _BACK_ANGLE, back, tau)


def _chain(P: _Pieces, tol: float, rightmost: bool = True) -> list[list[int]]:
    """The pieces chained head to tail into cycles (lists of piece indices).

    Where several pieces leave one point, the one turning most to the right (``rightmost``: round the
    outside of zero-width parts) or to the left (else: a set touching itself at a point is split there
    into simple loops); a piece running straight back is the last choice either way.
    """
    n = len(P)
    if n == 0:
        return []
    tree = cKDTree(P.start)
    cand = tree.query_ball_point(P.end, tol)
    used = np.zeros(n, dtype=bool)
    cycles = []
    sign = 1.0 if rightmost else -1.0
    for first in range(n):
        if used[first]:
            continue
        used[first] = True
        cycle, cur = [first], first
        while True:
            cs = [j for j in cand[cur] if not used[j] or j == first]
            if not cs:
                j = _collinear_next(P, tree, cur, used, first, tol)
                if j is None:
                    x, y = P.end[cur]
                    raise RuntimeError(f"exact offsets do not close: a piece ends at ({x:.17g}, {y:.17g}) "
                                       "where no piece starts")
                cs = [j]
            if len(cs) > 1:
                cs_a = np.array(cs)
                key = sign * _turn(P.t1[cur][None, :], P.t0[cs_a], back=sign * math.pi)
                near = cs_a[key <= key.min() + _BACK_ANGLE]
                j = int(near[np.argmin(sign * P.kappa[near])]) if len(near) > 1 else int(near[0])
            else:
                j = cs[0]
            if j == first:
                cycles.append(cycle)
                break
            used[j] = True
            cycle.append(j)
            cur = j
    return cycles


def _collinear_next(P: _Pieces, tree, cur: int, used: np.ndarray, first: int, tol: float) -> int | None:
    """The piece that continues ``cur`` across an ill-conditioned join, welded to it; None if there is none.

    Two offset segments of nearly collinear edges of S (a traced contour's staircase of tiny steps) meet
    at the crossing of two lines whose directions differ by α: each piece's end there is known only to
    about ``tol / α`` along the line, and the two ends may miss each other by far more than ``tol``. The
    continuation is a segment that starts within ``tol`` of the line of ``cur``, ahead of its end by less
    than ``tol / α`` (and less than half of either segment), turning by α < 1e-4 rad: both ends slide
    along their lines to the midpoint (within the join's own uncertainty).
    """
    if P.arc[cur]:
        return None
    t = P.t1[cur]
    ln_cur = float(np.hypot(*(P.end[cur] - P.start[cur])))
    best, best_gap = None, math.inf
    for j in tree.query_ball_point(P.end[cur], 0.5 * ln_cur):
        if (used[j] and j != first) or P.arc[j] or j == cur:
            continue
        v = P.start[j] - P.end[cur]
        gap = float(np.hypot(*v))
        alpha = abs(float(_turn(t, P.t0[j])))
        if alpha > 1e-4 or abs(t[0] * v[1] - t[1] * v[0]) > tol:
            continue
        if gap > min(tol / max(alpha, 1e-300), 0.5 * float(np.hypot(*(P.end[j] - P.start[j])))):
            continue
        if gap < best_gap:
            best, best_gap = j, gap
    if best is not None:
        # Each end slides along its own line (the directions, and so the joins at the far ends, stay) to
        # the foot of the midpoint: the two ends then meet within tol, as every other join does.
        m = 0.5 * (P.end[cur] + P.start[best])
        for k, cols, at in ((cur, slice(2, 4), P.end), (best, slice(0, 2), P.start)):
            u = P.t0[k]
            foot = P.start[k] + ((m - P.start[k]) @ u) * u
            at[k] = P.data[k, cols] = foot
    return best


def _isolated(E: OffsetPieces, P: _Pieces, tol: float) -> np.ndarray:
    """The corners of E that lie on no piece: isolated points of the shrink."""
    if len(E.corners) == 0 or len(P) == 0:
        return E.corners
    near = _Clearance(P, np.zeros((0, 2)), None, 0.0).nearer(E.corners, tol)
    return E.corners[~near]


def _loop(P: _Pieces, cycle: list[int], atol: float | None = None) -> Loop:
    """One chained cycle as a `Loop`; ``atol``: the chaining's node tolerance (pieces met within it), or
    None for `Loop`'s own relative check (too strict for a small loop of a large shape: its 1e-9 of the
    loop's size can be below the shape's precision)."""
    idx = np.asarray(cycle)
    if atol is not None:
        x0, y0, x1, y1 = np.r_[P.start[idx].min(axis=0), P.start[idx].max(axis=0)]
        atol = max(atol, 1e-9 * max(x1 - x0, y1 - y0))
    return Loop._from_arrays(P.arc[idx], P.data[idx], atol=atol)


def _enclosing(loops: list[Loop], eps: float) -> list[Loop]:
    """The loops that enclose some area (not a zero-width part run out and back)."""
    return [lp for lp in loops if abs(lp.area) > 16.0 * eps * max(lp.length, eps)]


def _reversed(loop: Loop) -> Loop:
    return Loop([p.reversed() for p in reversed(loop.pieces)], atol=math.inf)


def _offset_rows(P: _Pieces, cycle: list[int], r: float, tol: float = 0.0):
    """The outward offset by r of one chained loop of ``∂X`` (X on its left), piece by piece.

    Returns ``(rows, is_arc, is_corner)``: rows as `Loop` holds them; ``is_corner`` marks the arcs about
    corners of X (the only pieces that other parts of ``X ⊕ D`` can cover). At a right turn (two parts of
    X touching at a point) the arc about the point runs backwards there; the clipping removes what of it
    is covered. A corner arc shorter than ``tol`` (a turn of ~1e-12 rad where two nearly collinear pieces
    meet) is left out: the offsets on either side of it meet within ``tol``, as chained pieces do. The
    segments beside an arc that collapses onto a vertex of S end at that vertex exactly.
    """
    idx = np.asarray(cycle)
    nxt = np.roll(idx, -1)
    tau = _turn(P.t1[idx], P.t0[nxt])
    rows, kinds, corner, pins = [], [], [], []
    edge = getattr(P, "edge", None)
    for k, i in enumerate(idx.tolist()):
        row = P.data[i]
        if P.arc[i]:
            rho = row[2] + math.copysign(r, row[4])
            if rho > 1e-9 * r:                          # an arc of S's own: radius ρ ± r, about its centre
                rows.append((row[0], row[1], rho, row[3], row[4]))
                kinds.append(True)
                corner.append(False)
            else:                                       # a concave arc of radius r collapses onto its
                pins.append((len(rows), row[0], row[1]))  # centre, a vertex of S: pinned there below
        elif edge is not None:                          # onto S's own edge: the feet of its ends
            a, d = edge[0][i], edge[1][i] - edge[0][i]
            dd = d @ d
            f0 = a + ((row[:2] - a) @ d / dd) * d
            f1 = a + ((row[2:4] - a) @ d / dd) * d
            rows.append((f0[0], f0[1], f1[0], f1[1], 0.0))
            kinds.append(False)
            corner.append(False)
        else:
            tx, ty = P.t0[i]
            rows.append((row[0] + r * ty, row[1] - r * tx, row[2] + r * ty, row[3] - r * tx, 0.0))
            kinds.append(False)
            corner.append(False)
        t = float(tau[k])
        if abs(t) > _JOIN_ANGLE and r * abs(t) > tol:
            tx, ty = P.t1[i]
            cx, cy = P.end[i]
            rows.append((cx, cy, r, math.atan2(-tx, ty), t))
            kinds.append(True)
            corner.append(True)
    # The segments on either side of a collapsed arc end at its centre, a vertex of S, bit for bit (their
    # offsets put them there only to rounding, and an overlay with S would node the difference).
    n = len(rows)
    for at, cx, cy in pins:
        if n and not kinds[at - 1]:
            x0, y0, _, _, z = rows[at - 1]
            rows[at - 1] = (x0, y0, cx, cy, z)
        if n and not kinds[at % n]:
            _, _, x1, y1, z = rows[at % n]
            rows[at % n] = (cx, cy, x1, y1, z)
    return rows, kinds, corner


class _Clearance:
    """Exact distance from points to X, given the pieces of ``∂X`` and its isolated points."""

    _SAMPLES = 17

    def __init__(self, P: _Pieces, lone: np.ndarray, inside, eps: float):
        self.P, self.lone, self.inside, self.eps = P, lone, inside, eps
        m = self._SAMPLES
        t = np.linspace(0.0, 1.0, m)
        d = P.data
        th = d[:, 3][:, None] + d[:, 4][:, None] * t[None, :]
        arc_xy = d[:, None, :2] + d[:, 2, None, None] * np.stack([np.cos(th), np.sin(th)], axis=-1)
        seg_xy = d[:, None, 0:2] + t[None, :, None] * (d[:, None, 2:4] - d[:, None, 0:2])
        xy = np.where(P.arc[:, None, None], arc_xy, seg_xy)
        self.sag = float((d[P.arc, 2] * (1 - np.cos(0.5 * np.abs(d[P.arc, 4]) / (m - 1)))).max(initial=0.0))
        self.tree = shapely.STRtree(shapely.linestrings(xy)) if len(P) else None
        self.kd = cKDTree(lone) if len(lone) else None

    def covered(self, xy: np.ndarray, r: float) -> np.ndarray:
        """Whether each point is nearer than r to X (closed rule: by more than the precision)."""
        return self.nearer(xy, r - self.eps, r)

    def nearer(self, xy: np.ndarray, lim: float, reach: float | None = None) -> np.ndarray:
        """Whether each point is nearer than ``lim`` to X (``reach``: the farthest a piece can matter)."""
        out = np.zeros(len(xy), dtype=bool)
        if len(xy) == 0:
            return out
        r = lim if reach is None else reach
        if self.kd is not None:
            dl, _ = self.kd.query(xy)
            out |= dl < lim
        if self.tree is not None:
            pi, pj = self.tree.query(shapely.points(xy), predicate="dwithin", distance=r + self.sag)
            if len(pi):
                dist = _piece_distance(self.P, pj, xy[pi])
                hit = pi[dist < lim]
                out[hit] = True
        if self.inside is not None and not self.inside.is_empty:
            rest = np.flatnonzero(~out)
            out[rest] = shapely.contains_xy(self.inside, xy[rest, 0], xy[rest, 1])
        return out


def _piece_distance(P: _Pieces, j: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """Exact distance from points ``xy[k]`` to pieces ``j[k]``."""
    d = P.data[j]
    out = np.empty(len(j))
    a = P.arc[j]
    s = ~a
    if s.any():
        p, q = d[s, 0:2], d[s, 2:4]
        v = q - p
        L2 = (v * v).sum(axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            u = np.clip(((xy[s] - p) * v).sum(axis=1) / L2, 0.0, 1.0)
        f = p + np.where(L2 > 0, u, 0.0)[:, None] * v
        out[s] = np.hypot(*(xy[s] - f).T)
    if a.any():
        c, rho, a0, sw = d[a, 0:2], d[a, 2], d[a, 3], d[a, 4]
        w = xy[a] - c
        th = np.arctan2(w[:, 1], w[:, 0])
        turn = np.where(sw > 0, (th - a0) % _TWO_PI, (a0 - th) % _TWO_PI)
        on = turn <= np.abs(sw)
        radial = np.abs(np.hypot(w[:, 0], w[:, 1]) - rho)
        e0 = np.hypot(*(xy[a] - P.start[j[a]]).T)
        e1 = np.hypot(*(xy[a] - P.end[j[a]]).T)
        out[a] = np.where(on, radial, np.minimum(e0, e1))
    return out


class _Rows:
    """Loose pieces given as `Loop` rows, with the arrays `_chain` reads."""

    def __init__(self, arc, data):
        self.arc = np.asarray(arc, dtype=bool)
        self.data = np.asarray(data, dtype=float).reshape(-1, 5)
        d = self.data
        a0, a1 = d[:, 3], d[:, 3] + d[:, 4]
        c0 = np.column_stack([np.cos(a0), np.sin(a0)])
        c1 = np.column_stack([np.cos(a1), np.sin(a1)])
        self.start = np.where(self.arc[:, None], d[:, :2] + d[:, 2:3] * c0, d[:, :2])
        self.end = np.where(self.arc[:, None], d[:, :2] + d[:, 2:3] * c1, d[:, 2:4])
        u = d[:, 2:4] - d[:, :2]
        with np.errstate(invalid="ignore", divide="ignore"):
            u = u / np.hypot(u[:, 0], u[:, 1])[:, None]
        sgn = np.where(d[:, 4] >= 0, 1.0, -1.0)[:, None]
        self.t0 = np.where(self.arc[:, None], sgn * np.column_stack([-c0[:, 1], c0[:, 0]]), u)
        self.t1 = np.where(self.arc[:, None], sgn * np.column_stack([-c1[:, 1], c1[:, 0]]), u)
        self.kappa = np.where(self.arc, sgn[:, 0] / np.where(self.arc, d[:, 2], 1.0), 0.0)

    def __len__(self) -> int:
        return len(self.arc)


def _opened(P: _Pieces, cycles: list[list[int]], lone: np.ndarray, r: float, eps: float, tol: float) -> list[Loop]:
    """The loops of ``X ⊕ D_r`` from the chained loops of ``∂X`` (X on their left) and its isolated points.

    Each loop's outward offset (`_offset_rows`) is exact but may overlap another's, or itself, where two
    parts of X come within 2r of each other (a mouth narrower than 2r seen from both sides). Only the arcs
    about X's corners can be covered (the offsets of X's pieces lie on ∂S, at distance r from X), and only
    where they cross another corner's circle: each corner arc is cut at those crossings, and a part is
    dropped when its middle is nearer than r to X (exact distance to X's pieces). What is left is chained
    again, turning leftmost where the set touches itself.
    """
    rows, kinds, corner = [], [], []
    for c in cycles:
        a, b, k = _offset_rows(P, c, r, tol)
        rows += a
        kinds += b
        corner += k
    for c in lone:
        rows.append((c[0], c[1], r, 0.0, _TWO_PI))
        kinds.append(True)
        corner.append(True)
    if not rows:
        return []
    data = np.array(rows, dtype=float).reshape(-1, 5)
    arc = np.array(kinds, dtype=bool)
    corner = np.array(corner, dtype=bool)
    ci = np.flatnonzero(corner)
    if len(ci) > 1:
        centres = data[ci, :2]
        kd = cKDTree(centres)
        near = kd.query_ball_point(centres, 2.0 * r)
        inside = _X_polygon(P, cycles, lone, eps, r)
        clear = _Clearance(P, lone, inside, eps)
        keep_rows = []
        drop = np.zeros(len(data), dtype=bool)
        for k, nb in zip(ci.tolist(), near):
            c, a0, sw = data[k, :2], data[k, 3], data[k, 4]
            others = centres[[j for j in nb if j != np.searchsorted(ci, k)]]
            w = others - c
            dist = np.hypot(w[:, 0], w[:, 1])
            w, dist = w[dist > tol], dist[dist > tol]
            if len(w) == 0:
                continue
            base = np.arctan2(w[:, 1], w[:, 0])
            half = np.arccos(np.clip(0.5 * dist / r, -1.0, 1.0))
            th = np.concatenate([base - half, base + half])
            t = np.where(sw > 0, (th - a0) % _TWO_PI, (a0 - th) % _TWO_PI) / abs(sw)
            t = np.unique(t[(t > 1e-12) & (t < 1 - 1e-12)])
            b = np.r_[0.0, t, 1.0]
            mid = 0.5 * (b[:-1] + b[1:])
            ang = a0 + sw * mid
            gone = clear.covered(c + r * np.column_stack([np.cos(ang), np.sin(ang)]), r)
            if not gone.any():
                continue
            drop[k] = True
            # Merge the kept runs of consecutive parts.
            i = 0
            while i < len(gone):
                if gone[i]:
                    i += 1
                    continue
                j = i
                while j + 1 < len(gone) and not gone[j + 1]:
                    j += 1
                keep_rows.append((c[0], c[1], r, a0 + sw * b[i], sw * (b[j + 1] - b[i])))
                i = j + 1
        if drop.any() or keep_rows:
            kept = np.flatnonzero(~drop)
            data = np.concatenate([data[kept], np.array(keep_rows, dtype=float).reshape(-1, 5)])
            arc = np.r_[arc[kept], np.ones(len(keep_rows), dtype=bool)]
    R = _Rows(arc, data)
    return [_loop(R, c, tol) for c in _chain(R, tol, rightmost=False)]


def _X_polygon(P: _Pieces, cycles, lone, eps, r: float):
    """X sampled (its arcs by chords), for the inside test of `_Clearance`.

    That test is asked only of points at least ``r − eps`` from ``∂X`` (nearer ones are decided by the
    exact distance), and chords within r/1000 of the arcs put no such point on the wrong side; finer
    chords only cost (a traced blob at r = 3: 1.1 s of make_valid on chords within 1e-9 of its size).
    """
    from .engine import _assemble

    loops = _enclosing([_loop(P, c, _NODE_PRECISIONS * eps) for c in cycles], eps)
    if not loops:
        return None
    x = np.concatenate([P.start, P.end])
    size = float(np.ptp(x, axis=0).max()) if len(x) else 1.0
    return _assemble(loops, max(1e-3 * r, 1e-9 * max(size, eps)))


def _pruned(E: OffsetPieces, tol: float) -> OffsetPieces:
    """E without its dangling slivers: pieces shorter than `_SLIVER_R`·r with an end no other piece
    meets (where two parts of S share a vertex, a near-tangent cut can leave such a crumb of an arc)."""
    for _ in range(8):
        P = _Pieces(E, reverse=False)
        if len(P) == 0:
            return E
        tree_s, tree_e = cKDTree(P.start), cKDTree(P.end)
        d_next, _ = tree_s.query(P.end, k=2)
        d_prev, _ = tree_e.query(P.start, k=2)
        own = np.hypot(*(P.end - P.start).T) <= tol          # a closed piece (a full circle) meets itself
        nxt = np.where(own, d_next[:, 1], d_next[:, 0]) if len(P) > 1 else d_next[:, 0]
        prv = np.where(own, d_prev[:, 1], d_prev[:, 0]) if len(P) > 1 else d_prev[:, 0]
        length = np.where(P.arc, P.data[:, 2] * np.abs(P.data[:, 4]), np.hypot(*(P.end - P.start).T))
        crumb = ((nxt > tol) | (prv > tol)) & (length <= _SLIVER_R * E.r)
        if not crumb.any():
            return E
        ns = len(E.seg)
        ks, ka = ~crumb[:ns], ~crumb[ns:]
        E = replace(E, seg=E.seg[ks], seg_edge=E.seg_edge[ks], arc_center=E.arc_center[ka],
                    arc_start=E.arc_start[ka], arc_sweep=E.arc_sweep[ka])
    return E


def _reversed_rows(arc: np.ndarray, data: np.ndarray) -> np.ndarray:
    out = data.copy()
    out[~arc] = data[~arc][:, [2, 3, 0, 1, 4]]
    out[arc, 3] = data[arc, 3] + data[arc, 4]
    out[arc, 4] = -data[arc, 4]
    return out


def _side_loops(S, r: float, side: int, offsets: OffsetPieces | None = None):
    """The chained loops of ``S↓r`` (side +1) or ``(S^c)↓r`` (−1), that set on their left; S a shapely
    (Multi)Polygon or a list of `Loop`s (then arcs of S are features, see `curved_offsets`).
    ``offsets``: S's `exact_offsets` of that side, if already computed (a polygon S only).

    Returns (precision, pieces, cycles, isolated points)."""
    if isinstance(S, (list, tuple)):
        from .curved_offsets import curved_offsets

        arc, data, eps = curved_offsets(S, r, side)
        P = _Rows(arc, data if side > 0 else _reversed_rows(arc, data))
        return eps, P, _chain(P, _NODE_PRECISIONS * eps), np.zeros((0, 2))
    tol = _NODE_PRECISIONS * precision_of(S)
    E = _pruned(exact_offsets(S, r, side) if offsets is None else offsets, tol)
    P = _Pieces(E, reverse=side < 0).with_edges(S)
    return E.precision, P, _chain(P, tol), _isolated(E, P, tol)


def offset_loops(E: OffsetPieces) -> list[Loop]:
    """The pieces of an `OffsetPieces` chained into closed loops, with the shrunk set on their left.

    Parameters
    ----------
    E : OffsetPieces
        From `offsets.exact_offsets` (side +1: the loops bound ``S↓r``; side −1: ``(S^c)↓r``, so the
        outer boundary of a bounded S's grow comes out clockwise).

    Returns
    -------
    list of Loop
        Every loop, zero-width ones (a centre line run out and back) included.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> from vectortighten.offsets import exact_offsets
    >>> [round(lp.area, 12) for lp in offset_loops(exact_offsets(box(0, 0, 4, 3), 1.0))]
    [2.0]
    """
    P = _Pieces(E, reverse=E.side < 0)
    tol = _NODE_PRECISIONS * E.precision
    return [_loop(P, c, tol) for c in _chain(P, tol)]


def exact_shrink(S, r: float) -> list[Loop]:
    """The exact boundary of the shrink ``S↓r`` (points at distance ≥ r from ``S^c``), as loops.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        Valid, oriented (exteriors counter-clockwise), in any units.
    r : float
        Radius, > 0, in S's units.

    Returns
    -------
    list of Loop
        Outer boundaries counter-clockwise, holes clockwise: segments parallel to S's edges at distance r
        and arcs of radius r about its reflex vertices. Zero-width parts and isolated points are left out
        (they enclose no area); empty when the shrink is.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> [lp.area for lp in exact_shrink(box(0, 0, 4, 3), 1.0)]
    [2.0]
    """
    return _loops_of(S, r, "shrink")


def exact_grow(S, r: float) -> list[Loop]:
    """The exact boundary of the grow ``S↑r`` (points at distance < r from S), as loops.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        Valid, oriented, in any units.
    r : float
        Radius, > 0.

    Returns
    -------
    list of Loop
        Outer boundaries counter-clockwise, holes clockwise: segments parallel to S's edges at distance r
        and arcs of radius r about its convex vertices. A hole of S exactly 2r wide is closed by the open
        grow except for its centre line, which encloses no area and is left out.

    Examples
    --------
    >>> import math
    >>> from shapely.geometry import box
    >>> [abs(lp.area - (16 + 16 + math.pi)) < 1e-12 for lp in exact_grow(box(0, 0, 4, 4), 1.0)]
    [True]
    """
    return _loops_of(S, r, "grow")


def exact_core(S, r: float) -> list[Loop]:
    """The exact boundary of the core ``R_r(S) = S↓r↑r`` (union of the r-disks inside S), as loops.

    Built from the shrink's loops in closed form (see the module's derivation): S's surviving edges, its
    surviving reflex corners, and arcs of radius r about the shrink's corners.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        Valid, oriented, in any units.
    r : float
        Radius, > 0.

    Returns
    -------
    list of Loop
        Outer boundaries counter-clockwise, holes clockwise; every arc of radius exactly r, turning left.

    Raises
    ------
    RuntimeError
        Where two parts of the shrink touch at a single point (not handled yet).

    Examples
    --------
    A 4 × 4 square at r = 1: four sides and four quarter circles, area 16 − (4 − π).

    >>> import math
    >>> from shapely.geometry import box
    >>> [L] = exact_core(box(0, 0, 4, 4), 1.0)
    >>> round(L.area - (12 + math.pi), 12), sorted(set(L.radii.tolist()))
    (0.0, [1.0])
    """
    return _loops_of(S, r, "core")


def exact_fillet(S, r: float) -> list[Loop]:
    """The exact boundary of the fillet ``F_r(S) = S↑r↓r`` (outside every r-disk in ``S^c``), as loops.

    The dual of `exact_core`: the core construction on the loops of ``(S^c)↓r``, reversed.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        Valid, oriented, in any units.
    r : float
        Radius, > 0.

    Returns
    -------
    list of Loop
        Outer boundaries counter-clockwise, holes clockwise; every arc of radius exactly r, turning right.

    Examples
    --------
    An L-shape at r = 1 gains (1 − π/4) at its reflex corner.

    >>> import math
    >>> from shapely.geometry import Polygon
    >>> L = Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)])
    >>> round(sum(lp.area for lp in exact_fillet(L, 1.0)) - (L.area + 1 - math.pi / 4), 12)
    0.0
    """
    return _loops_of(S, r, "fillet")


def _loops_of(S, r: float, operation: str, offsets: OffsetPieces | None = None, chained=None) -> list[Loop]:
    """`exact_boundary` of an oriented, checked polygon S, from its `exact_offsets` of the side the
    operation needs if they are given (`morphology` passes the ones it has), or from `_side_loops` of that
    side if it was run already (``chained``: what it returned; the engine keeps it)."""
    side = 1 if operation in ("shrink", "core") else -1
    eps, P, cycles, lone = _side_loops(S, r, side, offsets) if chained is None else chained
    if operation == "shrink":
        return _enclosing([_loop(P, c, _NODE_PRECISIONS * eps) for c in cycles], eps)
    if operation == "grow":
        return [_reversed(lp) for lp in _enclosing([_loop(P, c, _NODE_PRECISIONS * eps) for c in cycles], eps)]
    loops = _opened(P, cycles, lone, r, eps, _NODE_PRECISIONS * eps)
    return loops if operation == "core" else [_reversed(lp) for lp in loops]


def _checked(S, r):
    """S as an oriented shapely shape or a list of `Loop`s, and r, checked (a one-line error if bad)."""
    from . import morphology as _m
    from ._validation import check_radius

    if isinstance(S, (list, tuple)):
        if not all(isinstance(lp, Loop) for lp in S):
            kinds = sorted({type(lp).__name__ for lp in S if not isinstance(lp, Loop)})
            raise TypeError(f"S as a list must hold Loops (outer counter-clockwise, holes clockwise), got "
                            f"{', '.join(kinds)}")
        return list(S), check_radius(r)
    S, r, _ = _m._prepare(S, r, None)
    return _m._orient(S), r


def exact_boundary(S, r: float, operation: str) -> list[Loop]:
    """The exact boundary of ``operation`` of S at radius r, S checked first.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon, or list of Loop
        The shape; as loops (outer counter-clockwise, holes clockwise) its arcs are features kept exactly
        (`curved_offsets`).
    r : float
        Radius, > 0, in S's units.
    operation : {"shrink", "grow", "core", "fillet"}

    Returns
    -------
    list of Loop

    Examples
    --------
    >>> from vectortighten.curves import Loop
    >>> [lp.radii.tolist() for lp in exact_boundary([Loop.circle((0, 0), 5.0)], 2.0, "shrink")]
    [[3.0]]
    """
    ops = {"shrink": exact_shrink, "grow": exact_grow, "core": exact_core, "fillet": exact_fillet}
    if operation not in ops:
        raise ValueError(f"operation must be one of {', '.join(ops)}, got {operation!r}")
    S, r = _checked(S, r)
    return ops[operation](S, r)


@dataclass
class ExactBoundary:
    """Exact loops of a morphological operation, in the shape the writers take (like a `Tightening`).

    Attributes
    ----------
    loops : list of Loop
        The exact boundary (outer counter-clockwise, holes clockwise).
    r : float
        The radius.
    init : str
        The operation (``"shrink"``, ``"grow"``, ``"core"`` or ``"fillet"``); the writers print it where
        they print a tightening's initial condition.
    tolerance : float
        Chord tolerance of `geometry` (and of the ``core``/``mortar`` layers).
    shape : Polygon or MultiPolygon
        The input (loops given as input are sampled within ``tolerance``).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> B = ExactBoundary.of(box(0, 0, 4, 3), 1.0, "shrink")
    >>> B.area, B.n_components, B.geometry.bounds
    (2.0, 1, (1.0, 1.0, 3.0, 2.0))
    """

    loops: list
    r: float
    init: str
    tolerance: float
    shape: Polygon | MultiPolygon
    _cache: dict = field(default_factory=dict, repr=False)

    @classmethod
    def of(cls, S, r: float, operation: str, *, tolerance: float | None = None) -> ExactBoundary:
        """The exact boundary of ``operation`` (shrink, grow, core or fillet) of S at radius r."""
        from ._validation import check_tolerance

        loops = exact_boundary(S, r, operation)
        S, r = _checked(S, r)
        if isinstance(S, list):
            from .curved_offsets import _sampled

            S = _sampled(S, check_tolerance(tolerance, r))
        return cls(loops, r, operation, check_tolerance(tolerance, r), S)

    @property
    def geometry(self) -> Polygon | MultiPolygon:
        """The loops sampled within `tolerance`, as valid shapely geometry."""
        if "geometry" not in self._cache:
            from .engine import _assemble

            self._cache["geometry"] = _assemble(self.loops, self.tolerance)
        return self._cache["geometry"]

    @property
    def perimeter(self) -> float:
        """Exact total length of the loops."""
        return math.fsum(lp.length for lp in self.loops)

    @property
    def area(self) -> float:
        """Exact area (Green's theorem over the loops; holes count negative)."""
        return math.fsum(lp.area for lp in self.loops)

    @property
    def n_components(self) -> int:
        """Number of counter-clockwise loops."""
        return sum(1 for lp in self.loops if lp.area > 0)

    @property
    def n_holes(self) -> int:
        """Number of clockwise loops."""
        return sum(1 for lp in self.loops if lp.area < 0)

    @property
    def is_empty(self) -> bool:
        """True when there is no loop."""
        return not self.loops

    def _morph(self, name):
        if name not in self._cache:
            from . import morphology as _m

            self._cache[name] = getattr(_m, name)(self.shape, self.r, tolerance=self.tolerance)
        return self._cache[name]

    @property
    def core(self):
        """The core of the input (shapely), for the writers' ``core`` layer."""
        return self._morph("core")

    @property
    def fillet(self):
        """The fillet of the input (shapely)."""
        return self._morph("fillet")

    @property
    def mortar(self):
        """The mortar of the input (shapely), for the writers' ``mortar`` layer."""
        return self._morph("mortar")
