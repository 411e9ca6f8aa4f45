"""Exact distances between the pieces (segments and arcs of one radius) of tight loops.

Used to find where two tight loops, or two far-apart parts of one, touch: the places where the set they
bound has a cusp and the engine performs surgery.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["arc_contains_angle", "piece_distance"]

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
