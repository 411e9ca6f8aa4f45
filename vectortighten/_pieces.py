"""Exact distances between the pieces (segments and arcs of one radius) of tight loops.

Used to find where two tight loops, or two far-apart parts of one, touch: the places where the set they
bound has a cusp and the engine performs surgery.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["arc_contains_angle", "piece_distance", "piece_distances"]

_TWO_PI = 2.0 * math.pi


def arc_contains_angle(start: float, sweep: float, theta: float, slack: float = 0.0) -> bool:
    """True if the direction ``theta`` lies on the arc from ``start`` over the signed ``sweep``."""
    if sweep < 0:
        start, sweep = start + sweep, -sweep
    if sweep >= _TWO_PI:
        return True
    off = (theta - start) % _TWO_PI
    return off <= sweep + slack or off >= _TWO_PI - slack


def _point_segment(p, a, b):
    d = b - a
    L2 = d @ d
    t = 0.0 if L2 == 0 else min(1.0, max(0.0, ((p - a) @ d) / L2))
    f = a + t * d
    return math.hypot(*(p - f)), f


def _point_arc(p, arc):
    c, r, a0, sw = arc
    v = p - c
    d = math.hypot(*v)
    if d > 0 and arc_contains_angle(a0, sw, math.atan2(v[1], v[0])):
        f = c + r * v / d
        return abs(d - r), f
    e0 = c + r * np.array([math.cos(a0), math.sin(a0)])
    e1 = c + r * np.array([math.cos(a0 + sw), math.sin(a0 + sw)])
    d0, d1 = math.hypot(*(p - e0)), math.hypot(*(p - e1))
    return (d0, e0) if d0 <= d1 else (d1, e1)


def _arc_ends(arc):
    c, r, a0, sw = arc
    return (c + r * np.array([math.cos(a0), math.sin(a0)]),
            c + r * np.array([math.cos(a0 + sw), math.sin(a0 + sw)]))


def _seg_seg(a, b):
    (p, q), (u, v) = a, b

    def orient(x, y, z):
        return (y[0] - x[0]) * (z[1] - x[1]) - (y[1] - x[1]) * (z[0] - x[0])

    o1, o2, o3, o4 = orient(p, q, u), orient(p, q, v), orient(u, v, p), orient(u, v, q)
    if o1 * o2 < 0 and o3 * o4 < 0:
        t = o3 / (o3 - o4)
        x = p + t * (q - p)
        return 0.0, x, x
    best = None
    for pt, (s0, s1), first in ((p, (u, v), True), (q, (u, v), True), (u, (p, q), False), (v, (p, q), False)):
        d, f = _point_segment(pt, s0, s1)
        if best is None or d < best[0]:
            best = (d, pt, f) if first else (d, f, pt)
    return best


def _seg_arc(seg, arc):
    p, q = seg
    c, r, a0, sw = arc
    best = None

    def take(d, x, y):
        nonlocal best
        if best is None or d < best[0]:
            best = (d, x, y)

    for pt in (p, q):
        d, f = _point_arc(pt, arc)
        take(d, pt, f)
    for e in _arc_ends(arc):
        d, f = _point_segment(e, p, q)
        take(d, f, e)
    d = q - p
    L2 = d @ d
    if L2 > 0:
        t = ((c - p) @ d) / L2
        foot = p + t * d
        h = math.hypot(*(foot - c))
        if h >= r:
            if 0 <= t <= 1 and h > 0:
                theta = math.atan2(*(foot - c)[::-1])
                if arc_contains_angle(a0, sw, theta):
                    take(h - r, foot, c + r * (foot - c) / h)
        else:
            half = math.sqrt(r * r - h * h) / math.sqrt(L2)
            for tt in (t - half, t + half):
                if 0 <= tt <= 1:
                    x = p + tt * d
                    if arc_contains_angle(a0, sw, math.atan2(*(x - c)[::-1])):
                        take(0.0, x, x)
    return best


def _arc_arc(A, B):
    ca, r, a0, asw = A
    cb, rb, b0, bsw = B
    best = None

    def take(d, x, y):
        nonlocal best
        if best is None or d < best[0]:
            best = (d, x, y)

    for e in _arc_ends(A):
        d, f = _point_arc(e, B)
        take(d, e, f)
    for e in _arc_ends(B):
        d, f = _point_arc(e, A)
        take(d, f, e)
    D = cb - ca
    dist = math.hypot(*D)
    if dist == 0:
        return best
    u = D / dist
    # Closest approach along the line of centres.
    for sa in (1.0, -1.0):
        for sb in (1.0, -1.0):
            x = ca + sa * r * u
            y = cb - sb * rb * u
            if arc_contains_angle(a0, asw, math.atan2(sa * u[1], sa * u[0])) and \
               arc_contains_angle(b0, bsw, math.atan2(-sb * u[1], -sb * u[0])):
                take(math.hypot(*(x - y)), x, y)
    # Crossing points of the two circles.
    if abs(r - rb) <= dist <= r + rb:
        a = (r * r - rb * rb + dist * dist) / (2 * dist)
        h2 = r * r - a * a
        h = math.sqrt(max(h2, 0.0))
        m = ca + a * u
        n = np.array([-u[1], u[0]])
        for x in (m + h * n, m - h * n):
            if arc_contains_angle(a0, asw, math.atan2(*(x - ca)[::-1])) and \
               arc_contains_angle(b0, bsw, math.atan2(*(x - cb)[::-1])):
                take(0.0, x, x)
    return best


def piece_distance(P, Q):
    """Exact distance between two pieces and a nearest pair of points.

    A piece is ``("seg", (p, q))`` or ``("arc", (center, radius, start_angle, sweep))``.

    Returns
    -------
    (float, (2,) ndarray, (2,) ndarray)
        The distance and the nearest point on each piece.
    """
    kp, gp = P
    kq, gq = Q
    if kp == "seg" and kq == "seg":
        return _seg_seg(gp, gq)
    if kp == "seg" and kq == "arc":
        return _seg_arc(gp, gq)
    if kp == "arc" and kq == "seg":
        d, x, y = _seg_arc(gq, gp)
        return d, y, x
    return _arc_arc(gp, gq)


# -- the same distances, vectorised over pairs (a filter: `piece_distance` decides) ----------------------
def _contains_many(start, sweep, theta):
    """`arc_contains_angle` (slack 0) elementwise."""
    s = np.where(sweep < 0, start + sweep, start)
    w = np.abs(sweep)
    off = np.mod(theta - s, _TWO_PI)
    return (w >= _TWO_PI) | (off <= w) | (off >= _TWO_PI)


def _point_segment_many(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(L2 == 0, 0.0, np.clip(((px - ax) * dx + (py - ay) * dy) / L2, 0.0, 1.0))
    return np.hypot(px - (ax + t * dx), py - (ay + t * dy))


def _arc_ends_many(cx, cy, r, a0, sw):
    a1 = a0 + sw
    return cx + r * np.cos(a0), cy + r * np.sin(a0), cx + r * np.cos(a1), cy + r * np.sin(a1)


def _point_arc_many(px, py, cx, cy, r, a0, sw):
    vx, vy = px - cx, py - cy
    d = np.hypot(vx, vy)
    on = (d > 0) & _contains_many(a0, sw, np.arctan2(vy, vx))
    e0x, e0y, e1x, e1y = _arc_ends_many(cx, cy, r, a0, sw)
    ends = np.minimum(np.hypot(px - e0x, py - e0y), np.hypot(px - e1x, py - e1y))
    return np.where(on, np.abs(d - r), ends)


def _seg_seg_many(A, B):
    px, py, qx, qy = A[:, 0], A[:, 1], A[:, 2], A[:, 3]
    ux, uy, vx, vy = B[:, 0], B[:, 1], B[:, 2], B[:, 3]

    def orient(x0, y0, x1, y1, x2, y2):
        return (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)

    o1, o2 = orient(px, py, qx, qy, ux, uy), orient(px, py, qx, qy, vx, vy)
    o3, o4 = orient(ux, uy, vx, vy, px, py), orient(ux, uy, vx, vy, qx, qy)
    d = np.minimum.reduce([_point_segment_many(px, py, ux, uy, vx, vy),
                           _point_segment_many(qx, qy, ux, uy, vx, vy),
                           _point_segment_many(ux, uy, px, py, qx, qy),
                           _point_segment_many(vx, vy, px, py, qx, qy)])
    return np.where((o1 * o2 < 0) & (o3 * o4 < 0), 0.0, d)


def _seg_arc_many(S, C):
    px, py, qx, qy = S[:, 0], S[:, 1], S[:, 2], S[:, 3]
    cx, cy, r, a0, sw = C[:, 0], C[:, 1], C[:, 2], C[:, 3], C[:, 4]
    e0x, e0y, e1x, e1y = _arc_ends_many(cx, cy, r, a0, sw)
    best = np.minimum.reduce([_point_arc_many(px, py, cx, cy, r, a0, sw),
                              _point_arc_many(qx, qy, cx, cy, r, a0, sw),
                              _point_segment_many(e0x, e0y, px, py, qx, qy),
                              _point_segment_many(e1x, e1y, px, py, qx, qy)])
    dx, dy = qx - px, qy - py
    L2 = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((cx - px) * dx + (cy - py) * dy) / L2
        fx, fy = px + t * dx, py + t * dy
        h = np.hypot(fx - cx, fy - cy)
        far = (L2 > 0) & (h >= r) & (t >= 0) & (t <= 1) & (h > 0) & \
            _contains_many(a0, sw, np.arctan2(fy - cy, fx - cx))
        best = np.where(far, np.minimum(best, h - r), best)
        half = np.sqrt(np.maximum(r * r - h * h, 0.0)) / np.sqrt(L2)
        for tt in (t - half, t + half):
            xx, yy = px + tt * dx, py + tt * dy
            hit = (L2 > 0) & (h < r) & (tt >= 0) & (tt <= 1) & _contains_many(a0, sw, np.arctan2(yy - cy, xx - cx))
            best = np.where(hit, 0.0, best)
    return best


def _arc_arc_many(A, B):
    ax, ay, ra, a0, asw = A[:, 0], A[:, 1], A[:, 2], A[:, 3], A[:, 4]
    bx, by, rb, b0, bsw = B[:, 0], B[:, 1], B[:, 2], B[:, 3], B[:, 4]
    ea = _arc_ends_many(ax, ay, ra, a0, asw)
    eb = _arc_ends_many(bx, by, rb, b0, bsw)
    best = np.minimum.reduce([_point_arc_many(ea[0], ea[1], bx, by, rb, b0, bsw),
                              _point_arc_many(ea[2], ea[3], bx, by, rb, b0, bsw),
                              _point_arc_many(eb[0], eb[1], ax, ay, ra, a0, asw),
                              _point_arc_many(eb[2], eb[3], ax, ay, ra, a0, asw)])
    Dx, Dy = bx - ax, by - ay
    dist = np.hypot(Dx, Dy)
    ok = dist > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        ux, uy = Dx / dist, Dy / dist
        for sa in (1.0, -1.0):
            for sb in (1.0, -1.0):
                hit = ok & _contains_many(a0, asw, np.arctan2(sa * uy, sa * ux)) & \
                    _contains_many(b0, bsw, np.arctan2(-sb * uy, -sb * ux))
                d = np.hypot(ax + sa * ra * ux - (bx - sb * rb * ux), ay + sa * ra * uy - (by - sb * rb * uy))
                best = np.where(hit, np.minimum(best, d), best)
        cross = ok & (np.abs(ra - rb) <= dist) & (dist <= ra + rb)
        a = (ra * ra - rb * rb + dist * dist) / (2 * dist)
        h = np.sqrt(np.maximum(ra * ra - a * a, 0.0))
        mx, my = ax + a * ux, ay + a * uy
        for sg in (1.0, -1.0):
            xx, yy = mx - sg * h * uy, my + sg * h * ux
            hit = cross & _contains_many(a0, asw, np.arctan2(yy - ay, xx - ax)) & \
                _contains_many(b0, bsw, np.arctan2(yy - by, xx - bx))
            best = np.where(hit, 0.0, best)
    return best


def piece_distances(arc_a: np.ndarray, A: np.ndarray, arc_b: np.ndarray, B: np.ndarray) -> np.ndarray:
    """`piece_distance` for many pairs at once, to rounding: the distances only, no nearest points.

    The same closed forms, evaluated with numpy in one pass per kind of pair; the results can differ
    from `piece_distance`'s by a few units in the last place of the coordinates, so callers use them to
    set aside the pairs that are clearly far and decide the others with `piece_distance`.

    Parameters
    ----------
    arc_a, arc_b : (n,) bool ndarray
        Whether each piece of the pair is an arc (else a segment).
    A, B : (n, 5) float ndarray
        The pieces: a segment as ``(px, py, qx, qy, 0)``, an arc as ``(cx, cy, radius, start, sweep)``
        (angles in radians, lengths in the pieces' units).

    Returns
    -------
    (n,) float ndarray
        The distance between the two pieces of each pair, in the pieces' units (NaN where the closed
        form is undefined for that input).

    Examples
    --------
    A segment and the parallel one 2 above it; the upper half of the unit circle and the lower half of
    the unit circle around (0, 3):

    >>> import math
    >>> A = np.array([[0.0, 0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0, math.pi]])
    >>> B = np.array([[0.0, 2.0, 1.0, 2.0, 0.0], [0.0, 3.0, 1.0, math.pi, math.pi]])
    >>> piece_distances(np.array([False, True]), A, np.array([False, True]), B).round(12).tolist()
    [2.0, 1.0]
    """
    A = np.asarray(A, dtype=float).reshape(-1, 5)
    B = np.asarray(B, dtype=float).reshape(-1, 5)
    arc_a, arc_b = np.asarray(arc_a, dtype=bool), np.asarray(arc_b, dtype=bool)
    out = np.empty(len(A))
    # Each kind of pair that occurs (a kind with no pair is skipped: the numpy calls of its closed form
    # cost as much on no rows as on a few).
    for k, many, swap in ((~arc_a & ~arc_b, _seg_seg_many, False), (~arc_a & arc_b, _seg_arc_many, False),
                          (arc_a & ~arc_b, _seg_arc_many, True), (arc_a & arc_b, _arc_arc_many, False)):
        if k.any():
            out[k] = many(B[k], A[k]) if swap else many(A[k], B[k])
    return out
