"""An exact clearance oracle for tightenings, independent of the engine and of GEOS's buffers.

The paper's closed shrink ``S↓r = {p ∈ S : dist(p, ∂S) ≥ r}`` has a boundary made of two kinds of raw
offset elements of S's own features:

* each edge's inward parallel segment at distance r;
* an arc of radius r about each reflex vertex, spanning the inward normals of its two edges.

Each raw element is clipped, in closed form, against the *open* r-capsule ``{p : dist(p, e) < r}`` of
every edge e of S within reach (an STRtree query): the capsule is bounded by two lines and two circles,
so the places where an element crosses it are roots of a line–line, line–circle or circle–circle
equation; between consecutive roots one mid-parameter point decides inside or out. What remains are the
pieces of ∂(S↓r), plus isolated points where the shrink has zero width (a bar exactly 2r wide keeps its
centre line). No chaining into loops is needed: the oracle only measures distances to these pieces and
tests points for membership.

The anticore's centres ``{p ∉ S : dist(p, S) ≥ r}`` are the same construction on the complement (every
ring reversed, the outward parallels and arcs about convex vertices); its unbounded outer part needs no
frame, because only its boundary pieces and a membership test are used.

A result T (loops of `Segment` and `Arc` pieces) is then judged by the penetration of its boundary into
the open core ``R = {p : dist(p, S↓r) < r}`` and the open anticore: for each piece, ``r − dist(piece, K)``
where the distance is exact (closed-form segment–segment, segment–arc and arc–arc distances) and is 0
when the piece lies in K. ``R ⊆ T ⊆ F`` holds exactly when no piece penetrates and every component of
the shrink lies in T (every component of the anticore's centres outside T): `judge` reports both.

Ties are decided to rounding: a stretch between two crossings of a capsule is removed only when its
middle lies nearer than ``r − delta`` to the edge, ``delta = TIE_REL·M`` (M the largest coordinate
magnitude plus r), so a part whose width is 2r to within a few ulps of its coordinates counts as 2r wide,
as issue 24 asks. The crossings themselves are those of the radius-r capsule, so near-tangent cusps stay
where they are exactly. Nothing here calls ``buffer``, ``offset_curve`` or anything of `vectortighten` except
the piece types, whose public attributes it reads.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

__all__ = ["TIE_REL", "Judgement", "OffsetPieces", "judge", "loop_arrays", "penetration", "shrink_pieces"]

TIE_REL = 1e-14
"""Relative precision of the tie "width exactly 2r": the capsules are open by ``TIE_REL·M``."""

_TWO_PI = 2.0 * math.pi


# ---------------------------------------------------------------------------------------------------
# S's rings and edges
# ---------------------------------------------------------------------------------------------------
def _polygons(S):
    if isinstance(S, Polygon):
        return [S] if not S.is_empty else []
    if isinstance(S, MultiPolygon):
        return [p for p in S.geoms if not p.is_empty]
    raise TypeError(f"S must be a Polygon or MultiPolygon, got {type(S).__name__}")


def _ring_xy(coords, ccw: bool) -> np.ndarray:
    xy = np.asarray(coords, dtype=float)[:, :2]
    if len(xy) > 1 and np.array_equal(xy[0], xy[-1]):
        xy = xy[:-1]
    keep = np.any(xy != np.roll(xy, 1, axis=0), axis=1)     # drop repeated vertices
    xy = xy[keep] if keep.any() else xy[:1]
    x, y = xy[:, 0], xy[:, 1]
    area2 = np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)
    if (area2 > 0) != ccw:
        xy = xy[::-1]
    return xy


def _rings(S, complement: bool) -> list[np.ndarray]:
    """Rings of S with the region on their left: exteriors CCW, holes CW (all reversed for ¬S)."""
    out = []
    for P in _polygons(S):
        out.append(_ring_xy(P.exterior.coords, ccw=not complement))
        out += [_ring_xy(h.coords, ccw=complement) for h in P.interiors]
    return [r for r in out if len(r) >= 3]


# ---------------------------------------------------------------------------------------------------
# Pieces as arrays: kind (True = arc) and rows (x0, y0, x1, y1, 0) or (cx, cy, R, start_angle, sweep)
# ---------------------------------------------------------------------------------------------------
def loop_arrays(loops) -> tuple[np.ndarray, np.ndarray]:
    """The pieces of ``loops`` (`vectortighten.Loop`) as ``(is_arc (n,), rows (n, 5))`` arrays."""
    kind, rows = [], []
    for loop in loops:
        for p in loop.pieces:
            if hasattr(p, "radius"):
                kind.append(True)
                rows.append((p.center[0], p.center[1], p.radius, p.start_angle, p.sweep))
            else:
                kind.append(False)
                rows.append((p.start[0], p.start[1], p.end[0], p.end[1], 0.0))
    return np.array(kind, dtype=bool), np.array(rows, dtype=float).reshape(-1, 5)


def _bounds(kind, rows) -> np.ndarray:
    """Boxes ``(n, 4)`` holding each piece (an arc's whole circle: conservative)."""
    seg = np.column_stack([np.minimum(rows[:, 0], rows[:, 2]), np.minimum(rows[:, 1], rows[:, 3]),
                           np.maximum(rows[:, 0], rows[:, 2]), np.maximum(rows[:, 1], rows[:, 3])])
    arc = np.column_stack([rows[:, 0] - rows[:, 2], rows[:, 1] - rows[:, 2],
                           rows[:, 0] + rows[:, 2], rows[:, 1] + rows[:, 2]])
    return np.where(kind[:, None], arc, seg)


def _ends(kind, rows):
    a0, a1 = rows[:, 3], rows[:, 3] + rows[:, 4]
    start = np.where(kind[:, None], rows[:, :2] + rows[:, 2:3] * np.column_stack([np.cos(a0), np.sin(a0)]),
                     rows[:, :2])
    end = np.where(kind[:, None], rows[:, :2] + rows[:, 2:3] * np.column_stack([np.cos(a1), np.sin(a1)]),
                   rows[:, 2:4])
    return start, end


def _midpoints(kind, rows) -> np.ndarray:
    am = rows[:, 3] + 0.5 * rows[:, 4]
    arc = rows[:, :2] + rows[:, 2:3] * np.column_stack([np.cos(am), np.sin(am)])
    seg = 0.5 * (rows[:, :2] + rows[:, 2:4])
    return np.where(kind[:, None], arc, seg)


# ---------------------------------------------------------------------------------------------------
# Closed-form distances (vectorised over pairs)
# ---------------------------------------------------------------------------------------------------
def _pt_seg(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    ll = dx * dx + dy * dy
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(ll > 0, ((px - ax) * dx + (py - ay) * dy) / ll, 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.hypot(px - (ax + t * dx), py - (ay + t * dy))


def _in_arc(theta, a0, sweep):
    """Whether angle ``theta`` lies on the arc from ``a0`` over the signed ``sweep`` (closed)."""
    t = np.where(sweep >= 0, theta - a0, a0 - theta) % _TWO_PI
    return (t <= np.abs(sweep)) | (np.abs(sweep) >= _TWO_PI)


def _arc_point(c_x, c_y, R, theta):
    return c_x + R * np.cos(theta), c_y + R * np.sin(theta)


def _pt_arc(px, py, cx, cy, R, a0, sw):
    vx, vy = px - cx, py - cy
    rho = np.hypot(vx, vy)
    inside = _in_arc(np.arctan2(vy, vx), a0, sw) | (rho == 0)
    sx, sy = _arc_point(cx, cy, R, a0)
    ex, ey = _arc_point(cx, cy, R, a0 + sw)
    ends = np.minimum(np.hypot(px - sx, py - sy), np.hypot(px - ex, py - ey))
    return np.where(inside, np.abs(rho - R), ends)


def _orient(ax, ay, bx, by, cx, cy):
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


def _seg_seg(a, b):
    """Distance between segments ``a`` and ``b`` (rows ``x0, y0, x1, y1``), exact up to rounding."""
    ax0, ay0, ax1, ay1 = a[:, 0], a[:, 1], a[:, 2], a[:, 3]
    bx0, by0, bx1, by1 = b[:, 0], b[:, 1], b[:, 2], b[:, 3]
    d = np.minimum.reduce([_pt_seg(ax0, ay0, bx0, by0, bx1, by1), _pt_seg(ax1, ay1, bx0, by0, bx1, by1),
                           _pt_seg(bx0, by0, ax0, ay0, ax1, ay1), _pt_seg(bx1, by1, ax0, ay0, ax1, ay1)])
    o1, o2 = _orient(ax0, ay0, ax1, ay1, bx0, by0), _orient(ax0, ay0, ax1, ay1, bx1, by1)
    o3, o4 = _orient(bx0, by0, bx1, by1, ax0, ay0), _orient(bx0, by0, bx1, by1, ax1, ay1)
    cross = (o1 * o2 < 0) & (o3 * o4 < 0)
    return np.where(cross, 0.0, d)


def _seg_arc(s, a):
    """Distance between segments ``s`` (x0, y0, x1, y1) and arcs ``a`` (cx, cy, R, a0, sweep)."""
    x0, y0, x1, y1 = s[:, 0], s[:, 1], s[:, 2], s[:, 3]
    cx, cy, R, a0, sw = a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4]
    sx, sy = _arc_point(cx, cy, R, a0)
    ex, ey = _arc_point(cx, cy, R, a0 + sw)
    d = np.minimum.reduce([_pt_arc(x0, y0, cx, cy, R, a0, sw), _pt_arc(x1, y1, cx, cy, R, a0, sw),
                           _pt_seg(sx, sy, x0, y0, x1, y1), _pt_seg(ex, ey, x0, y0, x1, y1)])
    dx, dy = x1 - x0, y1 - y0
    ll = dx * dx + dy * dy
    ok = ll > 0
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(ok, ((cx - x0) * dx + (cy - y0) * dy) / ll, 0.0)
        fx, fy = x0 + t * dx, y0 + t * dy                     # foot of the centre on the line
        h = np.hypot(fx - cx, fy - cy)
        # interior–interior critical point: the radial through the foot
        crit = ok & (t > 0) & (t < 1) & (h > 0) & _in_arc(np.arctan2(fy - cy, fx - cx), a0, sw)
        d = np.where(crit, np.minimum(d, np.abs(h - R)), d)
        # crossings: the line meets the circle at foot ± w along the segment
        L = np.sqrt(ll)
        w = np.sqrt(np.maximum(R * R - h * h, 0.0)) / np.where(ok, L, 1.0)
        for sgn in (-1.0, 1.0):
            tt = t + sgn * w
            px, py = x0 + tt * dx, y0 + tt * dy
            hit = ok & (h <= R) & (tt >= 0) & (tt <= 1) & _in_arc(np.arctan2(py - cy, px - cx), a0, sw)
            d = np.where(hit, 0.0, d)
    return d


def _arc_arc(p, q):
    """Distance between arcs ``p`` and ``q`` (rows cx, cy, R, a0, sweep)."""
    c1x, c1y, R1, a1, s1 = p[:, 0], p[:, 1], p[:, 2], p[:, 3], p[:, 4]
    c2x, c2y, R2, a2, s2 = q[:, 0], q[:, 1], q[:, 2], q[:, 3], q[:, 4]
    p0 = _arc_point(c1x, c1y, R1, a1)
    p1 = _arc_point(c1x, c1y, R1, a1 + s1)
    q0 = _arc_point(c2x, c2y, R2, a2)
    q1 = _arc_point(c2x, c2y, R2, a2 + s2)
    d = np.minimum.reduce([_pt_arc(*p0, c2x, c2y, R2, a2, s2), _pt_arc(*p1, c2x, c2y, R2, a2, s2),
                           _pt_arc(*q0, c1x, c1y, R1, a1, s1), _pt_arc(*q1, c1x, c1y, R1, a1, s1)])
    vx, vy = c2x - c1x, c2y - c1y
    dc = np.hypot(vx, vy)
    conc = dc == 0
    with np.errstate(invalid="ignore", divide="ignore"):
        ux, uy = np.where(conc, 1.0, vx / dc), np.where(conc, 0.0, vy / dc)
        th = np.arctan2(uy, ux)
        for g1 in (0.0, math.pi):
            for g2 in (0.0, math.pi):
                ok = ~conc & _in_arc(th + g1, a1, s1) & _in_arc(th + g2, a2, s2)
                xa, ya = _arc_point(c1x, c1y, R1, th + g1)
                xb, yb = _arc_point(c2x, c2y, R2, th + g2)
                d = np.where(ok, np.minimum(d, np.hypot(xa - xb, ya - yb)), d)
        overlap = conc & (_in_arc(a1, a2, s2) | _in_arc(a2, a1, s1))
        d = np.where(overlap, np.minimum(d, np.abs(R1 - R2)), d)
        meet = ~conc & (dc <= R1 + R2) & (dc >= np.abs(R1 - R2))
        aa = (dc * dc + R1 * R1 - R2 * R2) / (2 * dc)
        hh = np.sqrt(np.maximum(R1 * R1 - aa * aa, 0.0))
        for sgn in (-1.0, 1.0):
            xi = c1x + aa * ux - sgn * hh * uy
            yi = c1y + aa * uy + sgn * hh * ux
            hit = meet & _in_arc(np.arctan2(yi - c1y, xi - c1x), a1, s1) \
                & _in_arc(np.arctan2(yi - c2y, xi - c2x), a2, s2)
            d = np.where(hit, 0.0, d)
    return d


def piece_distances(kind_a, rows_a, kind_b, rows_b) -> np.ndarray:
    """Exact distances between pieces ``a[i]`` and ``b[i]`` (same length arrays)."""
    out = np.empty(len(kind_a))
    ss = ~kind_a & ~kind_b
    out[ss] = _seg_seg(rows_a[ss], rows_b[ss])
    sa = ~kind_a & kind_b
    out[sa] = _seg_arc(rows_a[sa], rows_b[sa])
    as_ = kind_a & ~kind_b
    out[as_] = _seg_arc(rows_b[as_], rows_a[as_])
    aa = kind_a & kind_b
    out[aa] = _arc_arc(rows_a[aa], rows_b[aa])
    return out


# ---------------------------------------------------------------------------------------------------
# The shrink's pieces
# ---------------------------------------------------------------------------------------------------
@dataclass
class OffsetPieces:
    """Boundary pieces of ``K = {p ∈ S : dist(p, ∂S) ≥ r}`` (or of the complement's version).

    Attributes
    ----------
    kind, rows : arrays
        ``kind[i]`` True for an arc; ``rows[i]`` as in `loop_arrays`.
    r : float
        The radius.
    delta : float
        Tie precision: capsules are open with radius ``r − delta``.
    complement : bool
        False for the shrink of S (core centres), True for the anticore's centres.
    """

    kind: np.ndarray
    rows: np.ndarray
    r: float
    delta: float
    complement: bool
    S: object
    edges: np.ndarray
    edge_tree: shapely.STRtree
    tree: shapely.STRtree | None = None

    def __len__(self) -> int:
        return len(self.kind)

    def contains_xy(self, xy: np.ndarray) -> np.ndarray:
        """Whether points ``(n, 2)`` lie in K (closed, to the tie precision: clearance ≥ r − 2·delta)."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        if len(xy) == 0:
            return np.zeros(0, dtype=bool)
        inS = shapely.contains_xy(self.S, xy[:, 0], xy[:, 1])
        pts = shapely.points(xy)
        _, dist = self.edge_tree.query_nearest(pts, return_distance=True, all_matches=False)
        return (inS != self.complement) & (dist >= self.r - 2 * self.delta)


def _tie_delta(S, r: float) -> float:
    x0, y0, x1, y1 = S.bounds
    return TIE_REL * (max(abs(x0), abs(y0), abs(x1), abs(y1)) + r)


def _param_points(kind, rows, t) -> np.ndarray:
    """Points at parameter t: length along a segment, angle offset (in the sweep's sense) on an arc."""
    d = rows[:, 2:4] - rows[:, :2]
    L = np.hypot(d[:, 0], d[:, 1])
    u = d / np.where(L > 0, L, 1.0)[:, None]
    seg = rows[:, :2] + t[:, None] * u
    th = rows[:, 3] + np.where(rows[:, 4] >= 0, 1.0, -1.0) * t
    arc = rows[:, :2] + rows[:, 2:3] * np.column_stack([np.cos(th), np.sin(th)])
    return np.where(kind[:, None], arc, seg)


def _raw_elements(rings, r):
    """Inward parallels of every edge and arcs about reflex vertices, with the edges each must ignore."""
    A, B, prev_edge = [], [], []
    base = 0
    for xy in rings:
        n = len(xy)
        A.append(xy)
        B.append(np.roll(xy, -1, axis=0))
        prev_edge.append(base + (np.arange(n) - 1) % n)
        base += n
    A, B, prev_edge = np.concatenate(A), np.concatenate(B), np.concatenate(prev_edge)
    d = B - A
    L = np.hypot(d[:, 0], d[:, 1])
    u = d / L[:, None]
    nrm = np.column_stack([-u[:, 1], u[:, 0]])
    m = len(A)
    seg_rows = np.column_stack([A + r * nrm, B + r * nrm, np.zeros(m)])
    # vertex i joins edge prev_edge[i] (in) and edge i (out)
    d1, d2 = u[prev_edge], u
    cr = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    dt = d1[:, 0] * d2[:, 0] + d1[:, 1] * d2[:, 1]
    reflex = (cr < 0) | ((cr == 0) & (dt < 0))
    sweep = np.arctan2(cr, dt)
    sweep = np.where((cr == 0) & (dt < 0), -math.pi, sweep)
    n1 = nrm[prev_edge]
    idx = np.flatnonzero(reflex)
    arc_rows = np.column_stack([A[idx], np.full(len(idx), r), np.arctan2(n1[idx, 1], n1[idx, 0]), sweep[idx]])
    kind = np.concatenate([np.zeros(m, dtype=bool), np.ones(len(idx), dtype=bool)])
    rows = np.concatenate([seg_rows, arc_rows])
    own1 = np.concatenate([np.arange(m), prev_edge[idx]])
    own2 = np.concatenate([np.arange(m), idx])
    return kind, rows, own1, own2, np.column_stack([A, B])


def _capsule_roots_seg(p0, uu, a, b, rho):
    """Parameters along lines ``p0 + t·uu`` (unit uu) where they cross the boundary of the rho-capsule."""
    e = b - a
    le = np.hypot(e[:, 0], e[:, 1])
    en = np.column_stack([-e[:, 1], e[:, 0]]) / le[:, None]
    h0 = np.einsum("ij,ij->i", p0 - a, en)
    hu = np.einsum("ij,ij->i", uu, en)
    cols = []
    with np.errstate(invalid="ignore", divide="ignore"):
        for sgn in (-1.0, 1.0):
            cols.append(np.where(hu != 0, (sgn * rho - h0) / hu, np.nan))
        for q in (a, b):
            w = p0 - q
            Bq = np.einsum("ij,ij->i", w, uu)
            disc = Bq * Bq - (np.einsum("ij,ij->i", w, w) - rho * rho)
            sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
            cols += [-Bq - sq, -Bq + sq]
    return np.column_stack(cols)


def _capsule_roots_arc(c, R, a0, sig, a, b, rho):
    """Angle offsets ``t`` (θ = a0 + sig·t) where circles cross the boundary of the rho-capsule."""
    e = b - a
    le = np.hypot(e[:, 0], e[:, 1])
    en = np.column_stack([-e[:, 1], e[:, 0]]) / le[:, None]
    al = np.arctan2(en[:, 1], en[:, 0])
    hc = np.einsum("ij,ij->i", c - a, en)
    thetas = []
    with np.errstate(invalid="ignore", divide="ignore"):
        for sgn in (-1.0, 1.0):
            k = (sgn * rho - hc) / R
            ac = np.arccos(np.where(np.abs(k) <= 1, k, np.nan))
            thetas += [al + ac, al - ac]
        for q in (a, b):
            D = q - c
            dd = np.hypot(D[:, 0], D[:, 1])
            k = (dd * dd + R * R - rho * rho) / (2 * R * dd)
            ac = np.arccos(np.where(np.abs(k) <= 1, k, np.nan))
            be = np.arctan2(D[:, 1], D[:, 0])
            thetas += [be + ac, be - ac]
    th = np.column_stack(thetas)
    return (sig[:, None] * (th - a0[:, None])) % _TWO_PI


def _removed_intervals(kind, rows, pairs_e, pairs_k, edges, rho, r):
    """Open parameter intervals of each raw element inside the r-capsule of each paired edge.

    The cuts are the crossings of the capsule of radius r itself; an interval between cuts is removed
    when its middle is nearer than ``rho = r − delta`` to the edge. So a tie (an element at distance r
    from the edge to within delta) keeps the element, but a cut stays where the exact geometry puts it:
    at a near-tangent cusp of half-angle α a cut made at rho would move by delta/α along the element.
    """
    a, b = edges[pairs_k, :2], edges[pairs_k, 2:]
    r_e = rows[pairs_e]
    is_arc = kind[pairs_e]
    out_e, out_t0, out_t1 = [], [], []
    for arcs in (False, True):
        sel = is_arc == arcs
        if not sel.any():
            continue
        re_, aa, bb, el = r_e[sel], a[sel], b[sel], pairs_e[sel]
        if not arcs:
            p0, p1 = re_[:, :2], re_[:, 2:4]
            d = p1 - p0
            Lp = np.hypot(d[:, 0], d[:, 1])
            uu = d / np.where(Lp > 0, Lp, 1.0)[:, None]
            roots = _capsule_roots_seg(p0, uu, aa, bb, r)
            span = Lp
        else:
            c, R, a0, sw = re_[:, :2], re_[:, 2], re_[:, 3], re_[:, 4]
            sig = np.where(sw >= 0, 1.0, -1.0)
            roots = _capsule_roots_arc(c, R, a0, sig, aa, bb, r)
            span = np.abs(sw)
        roots = np.where((roots > 0) & (roots < span[:, None]), roots, np.nan)
        t = np.sort(np.column_stack([np.zeros(len(span)), roots, span]), axis=1)   # NaN sort last
        t = np.where(np.isnan(t), span[:, None], t)                                 # pad with the end
        lo, hi = t[:, :-1], t[:, 1:]
        mid = 0.5 * (lo + hi)
        if not arcs:
            mx = p0[:, 0:1] + mid * uu[:, 0:1]
            my = p0[:, 1:2] + mid * uu[:, 1:2]
        else:
            th = a0[:, None] + sig[:, None] * mid
            mx = c[:, 0:1] + R[:, None] * np.cos(th)
            my = c[:, 1:2] + R[:, None] * np.sin(th)
        dist = _pt_seg(mx, my, aa[:, 0:1], aa[:, 1:2], bb[:, 0:1], bb[:, 1:2])
        inside = (dist < rho) & (hi > lo)
        ii, jj = np.nonzero(inside)
        out_e.append(el[ii])
        out_t0.append(lo[ii, jj])
        out_t1.append(hi[ii, jj])
    if not out_e:
        return np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0)
    return np.concatenate(out_e), np.concatenate(out_t0), np.concatenate(out_t1)


def _kept_intervals(n_elem, span, e, t0, t1):
    """Complement, in ``[0, span]`` of each element, of the union of its removed intervals."""
    untouched = np.setdiff1d(np.arange(n_elem), e)
    ke, k0, k1 = [untouched], [np.zeros(len(untouched))], [span[untouched]]
    if len(e):
        order = np.lexsort((t0, e))
        e, t0, t1 = e[order], t0[order], t1[order]
        # running maximum of t1 within each element, exactly: by ranks, offset per element
        rank = np.empty(len(t1), dtype=np.int64)
        srt = np.argsort(t1, kind="stable")
        rank[srt] = np.arange(len(t1))
        n = np.int64(len(t1))
        key = e.astype(np.int64) * n + rank
        run = t1[srt][np.maximum.accumulate(key) - e.astype(np.int64) * n]
        first = np.ones(len(e), dtype=bool)
        first[1:] = e[1:] != e[:-1]
        last = np.ones(len(e), dtype=bool)
        last[:-1] = e[1:] != e[:-1]
        g = first & (t0 > 0)                                    # before the first removed interval
        ke.append(e[g]); k0.append(np.zeros(g.sum())); k1.append(t0[g])
        inner = ~first
        prev_run = np.roll(run, 1)
        g = inner & (t0 > prev_run)
        ke.append(e[g]); k0.append(prev_run[g]); k1.append(t0[g])
        g = last & (run < span[e])
        ke.append(e[g]); k0.append(run[g]); k1.append(span[e][g])
    return np.concatenate(ke), np.concatenate(k0), np.concatenate(k1)


def shrink_pieces(S, r: float, *, complement: bool = False) -> OffsetPieces:
    """Boundary pieces of the closed shrink ``S↓r`` (or, with ``complement``, of ``(¬S)↓r``).

    Parameters
    ----------
    S : Polygon or MultiPolygon
        The shape (valid).
    r : float
        Radius, > 0, in S's units.
    complement : bool
        False: ``{p ∈ S : dist(p, ∂S) ≥ r}`` (the core's centres). True: ``{p ∉ S : dist(p, S) ≥ r}`` (the
        anticore's centres).

    Returns
    -------
    OffsetPieces
        Segments and arcs of radius r (unordered), with a membership test.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> K = shrink_pieces(box(0, 0, 4, 4), 1.0)
    >>> len(K), sorted(map(tuple, K.rows[:, :4].round(12).tolist()))[0]
    (4, (1.0, 1.0, 3.0, 1.0))
    """
    if not (r > 0 and math.isfinite(r)):
        raise ValueError(f"r must be a positive finite number, got {r!r}")
    rings = _rings(S, complement)
    delta = _tie_delta(S, r)
    rho = r - delta
    kind, rows, own1, own2, edges = _raw_elements(rings, r)
    edge_geoms = shapely.linestrings(edges.reshape(-1, 2, 2))
    edge_tree = shapely.STRtree(edge_geoms)
    span = np.where(kind, np.abs(rows[:, 4]), np.hypot(rows[:, 2] - rows[:, 0], rows[:, 3] - rows[:, 1]))
    # Lipschitz tests, by bisection. A sub-range of an element (h its half length, m its midpoint) goes
    # when dist(m, ∂S) < ρ − h: a capsule holds all of it. Otherwise the edges within ρ + h of m (other
    # than the element's own, at distance exactly r) are the only ones that can clip it: with none it
    # stays whole; with few it is clipped against them exactly; with many it is halved and tried again.
    el = np.arange(len(kind))
    lo, hi = np.zeros(len(kind)), span.copy()
    gone_e, gone_lo, gone_hi = [], [], []
    pe_all, pk_all = [], []
    for level in range(24):
        if len(el) == 0:
            break
        pts = shapely.points(_param_points(kind[el], rows[el], 0.5 * (lo + hi)))
        half = 0.5 * (hi - lo) * np.where(kind[el], rows[el, 2], 1.0)
        _, dm = edge_tree.query_nearest(pts, return_distance=True, all_matches=False)
        gone = dm + half < rho
        gone_e.append(el[gone]); gone_lo.append(lo[gone]); gone_hi.append(hi[gone])
        live = np.flatnonzero(~gone)
        qi, qk = edge_tree.query(pts[live], predicate="dwithin", distance=rho + half[live] + 2 * delta)
        qi = live[qi]
        own = (qk == own1[el[qi]]) | (qk == own2[el[qi]])
        qi, qk = qi[~own], qk[~own]
        count = np.bincount(qi, minlength=len(el))
        final = ~gone & (count > 0) & ((count <= 16) | (half <= r / 1024) | (level == 23))
        take = final[qi]
        pe_all.append(el[qi[take]]); pk_all.append(qk[take])
        split = ~gone & (count > 0) & ~final
        m = 0.5 * (lo + hi)
        el, lo, hi = el[split].repeat(2), np.column_stack([lo[split], m[split]]).ravel(), \
            np.column_stack([m[split], hi[split]]).ravel()
    pe = np.concatenate(pe_all) if pe_all else np.zeros(0, dtype=np.int64)
    pk = np.concatenate(pk_all) if pk_all else np.zeros(0, dtype=np.int64)
    if len(pe):
        uniq = np.unique(pe.astype(np.int64) * len(edges) + pk)
        pe, pk = uniq // len(edges), uniq % len(edges)
    keep = (pk != own1[pe]) & (pk != own2[pe])
    pe, pk = pe[keep], pk[keep]
    es, t0s, t1s = gone_e, gone_lo, gone_hi
    for s in range(0, len(pe), 1_000_000):
        e_, a_, b_ = _removed_intervals(kind, rows, pe[s:s + 1_000_000], pk[s:s + 1_000_000], edges, rho, r)
        es.append(e_); t0s.append(a_); t1s.append(b_)
    e, t0, t1 = np.concatenate(es), np.concatenate(t0s), np.concatenate(t1s)
    ke, k0, k1 = _kept_intervals(len(kind), span, e, t0, t1)
    src = rows[ke]
    is_arc = kind[ke]
    out = np.zeros((len(ke), 5))
    # segments: sub-segment [k0, k1] along the parallel
    d = src[:, 2:4] - src[:, :2]
    Ls = np.where(is_arc, 1.0, np.hypot(d[:, 0], d[:, 1]))
    Ls = np.where(Ls > 0, Ls, 1.0)
    u = d / Ls[:, None]
    seg = np.column_stack([src[:, :2] + k0[:, None] * u, src[:, :2] + k1[:, None] * u, np.zeros(len(ke))])
    sig = np.where(src[:, 4] >= 0, 1.0, -1.0)
    arc = np.column_stack([src[:, 0], src[:, 1], src[:, 2], src[:, 3] + sig * k0, sig * (k1 - k0)])
    out[:] = np.where(is_arc[:, None], arc, seg)
    if complement:
        geom = S
    else:
        geom = S
    shapely.prepare(geom)
    K = OffsetPieces(is_arc, out, float(r), delta, complement, geom, edges, edge_tree)
    if len(K):
        b = _bounds(K.kind, K.rows)
        K.tree = shapely.STRtree(shapely.box(b[:, 0], b[:, 1], b[:, 2], b[:, 3]))
    return K


# ---------------------------------------------------------------------------------------------------
# Judging a result
# ---------------------------------------------------------------------------------------------------
def penetration(kind, rows, K: OffsetPieces) -> np.ndarray:
    """Per piece, how far it enters the open r-neighbourhood of K: ``max(0, r − dist(piece, K))``.

    A piece that lies in K (or crosses its boundary) enters by r.
    """
    n = len(kind)
    pen = np.zeros(n)
    if n == 0 or len(K) == 0:
        return pen
    r = K.r
    bx = _bounds(kind, rows)
    boxes = shapely.box(bx[:, 0] - r, bx[:, 1] - r, bx[:, 2] + r, bx[:, 3] + r)
    pi, kj = K.tree.query(boxes)
    if len(pi):
        # in chunks, to bound the memory of the pairwise arrays
        dmin = np.full(n, np.inf)
        for s in range(0, len(pi), 2_000_000):
            a, b = pi[s:s + 2_000_000], kj[s:s + 2_000_000]
            dd = piece_distances(kind[a], rows[a], K.kind[b], K.rows[b])
            np.minimum.at(dmin, a, dd)
        pen = np.maximum(0.0, r - dmin)
    start, _ = _ends(kind, rows)
    inside = K.contains_xy(start)
    pen[inside] = r
    return pen


@dataclass
class Judgement:
    """The oracle's verdict on one result, lengths in S's units.

    Attributes
    ----------
    core_penetration, anticore_penetration : float
        Largest depth of the loops into the open core and the open anticore (0 when exact).
    core_missing : int
        Pieces of ``S↓r`` whose midpoint T does not contain (a core component left out).
    anticore_covered : int
        Pieces of the anticore's centres whose midpoint T contains.
    n_core_pieces, n_anticore_pieces : int
        Sizes of the two offsets.
    seconds : float
        Time the oracle took.
    """

    r: float
    core_penetration: float
    anticore_penetration: float
    core_missing: int
    anticore_covered: int
    n_core_pieces: int
    n_anticore_pieces: int
    seconds: float

    @property
    def worst(self) -> float:
        """Largest penetration in units of r (1.0 for a missing or covered component)."""
        w = max(self.core_penetration, self.anticore_penetration) / self.r
        return max(w, 1.0 if (self.core_missing or self.anticore_covered) else 0.0)

    def exact(self, rel: float = 1e-9) -> bool:
        """Whether ``R ⊆ T ⊆ F`` holds to ``rel·r``."""
        return self.worst <= rel


def judge(S, r: float, loops, geometry=None) -> Judgement:
    """Judge a tightening's loops against the exact core and anticore of S at radius r.

    Parameters
    ----------
    S : Polygon or MultiPolygon
        The input shape.
    r : float
        The radius.
    loops : list of vectortighten.Loop
        The result's boundary (``Tightening.loops``).
    geometry : Polygon or MultiPolygon, optional
        The result's region, for the containment test of K's components (skipped without it).

    Returns
    -------
    Judgement
    """
    t0 = time.perf_counter()
    kind, rows = loop_arrays(loops)
    Kc = shrink_pieces(S, r)
    Ka = shrink_pieces(S, r, complement=True)
    pc = penetration(kind, rows, Kc)
    pa = penetration(kind, rows, Ka)
    missing = covered = 0
    if geometry is not None:
        shapely.prepare(geometry)
        for K, flag in ((Kc, "core"), (Ka, "anti")):
            if len(K) == 0:
                continue
            mid = _midpoints(K.kind, K.rows)
            inT = shapely.intersects_xy(geometry, mid[:, 0], mid[:, 1]) if not geometry.is_empty \
                else np.zeros(len(mid), dtype=bool)
            if flag == "core":
                missing = int((~inT).sum())
            else:
                covered = int(inT.sum())
    return Judgement(float(r), float(pc.max(initial=0.0)), float(pa.max(initial=0.0)), missing, covered,
                     len(Kc), len(Ka), time.perf_counter() - t0)
