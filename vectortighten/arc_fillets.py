"""The tightening of an arc-bounded shape whose corners are isolated: each corner filleted, S kept elsewhere.

The polygon fast path (`_fast`) fillets the isolated corners of a polygon with disks tangent to its two
edges. This module does the same for shapes bounded by segments and circular arcs (a list of `Loop`s), so
that an arc of S that survives keeps its own radius: a plate with a circular hole of radius ρ > r and sharp
corners comes back with the hole as it was and each corner rounded to r.

Construction
------------
At a join of S's boundary where the pieces p (in) and q (out) meet with a turn τ ≠ 0 (a corner), let
σ = sign τ (+1 convex, −1 reflex) and take the disk of radius r on σ's side tangent to both pieces. Its
centre c is at distance r from p and from q on that side: on the locus of p (a segment's parallel at
distance r; for an arc of centre o and radius ρ turning by κ = ±1, the circle (o, ρ − σκr)) and on that of
q — a line–line, line–circle or circle–circle crossing, in closed form; the crossing nearest the corner is
taken. Its feet on p and q are the tangent points; the corner is replaced by the arc of radius r about c
between them (turning left at a convex corner, right at a reflex one), p is trimmed to end and q to start
at them.

Certificate
-----------
The result T is returned only if (1) every piece of S is pinned on both sides: its offset element on
each side (see `loop_input`) is kept by `curved_offsets` whole, except that on a fillet's side it may
be cut where the fillet's centre is (the element beyond the foot is then not asked for); (2) every arc about a corner in those offsets (the vertex
elements, on the side a corner turns away from) is kept whole; (3) every fillet centre has clearance
≥ r − ε from all of S's features and lies inside S (convex corner) or outside it (reflex); (4) T's
loops bound a valid shape. Then, with the lemma of `loop_input`: by (1) every kept point of ∂S lies on
∂R_r(S) and on ∂F_r(S) (the mortar has no width there), and the trimmed-away parts at a corner lie
on the boundary of the other set (∂F_r(S) at a convex corner, ∂R_r(S) at a reflex one); by (3) each convex fillet disk lies in S, so its
arc lies on ∂R_r(S), and each reflex one in S^c, its arc on ∂F_r(S); by (2) the corner itself lies on
∂F_r(S) (convex) or ∂R_r(S) (reflex). So the mortar is ∂S plus one pocket at each corner, bounded by
the corner's two pieces and the fillet arc; T's boundary lies in the mortar, its straight pieces are
straight, its left turns hug the core and its right turns the anticore: it is tight. Every init starts
from a boundary in the same pockets (∂R_r(S), ∂S or Mason(S), each differing from ∂T only inside the
pockets, which are simply connected), so the tightening is T for every init.

When a check fails (corners closer than the fillets need, a part thinner than 2r, an arc tighter than
r), `corner_fillets` returns None and `loop_input` flattens the shape instead.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from .curves import Arc, Loop, Segment
from .errors import InvalidGeometryError

__all__ = ["corner_fillets"]

_TWO_PI = 2.0 * math.pi
#: A join whose tangents turn by less than this (radians) is smooth: no fillet.
_CORNER = 1e-9
#: Feet this far (as a fraction of the piece) outside a piece are on it (rounding of the crossing).
_ON = 1e-9


def _locus(piece, sigma: int, r: float):
    """Points at distance r from ``piece`` on side σ (left +1): ("line", p, u) or ("circle", o, R)."""
    if isinstance(piece, Segment):
        u = np.array(piece.tangent_at())
        n = np.array([-u[1], u[0]])
        return "line", np.array(piece.start) + sigma * r * n, u
    kappa = 1.0 if piece.sweep > 0 else -1.0
    R = piece.radius - sigma * kappa * r
    return ("circle", np.array(piece.center), R) if R > 0 else None


def _crossings(A, B) -> list[np.ndarray]:
    """The crossing points of two loci."""
    if A[0] == "circle" and B[0] == "line":
        A, B = B, A
    if A[0] == "line" and B[0] == "line":
        (_, p, u), (_, q, v) = A, B
        det = u[0] * v[1] - u[1] * v[0]
        if abs(det) < 1e-15:
            return []
        w = q - p
        s = (w[0] * v[1] - w[1] * v[0]) / det
        return [p + s * u]
    if A[0] == "line":
        (_, p, u), (_, o, R) = A, B
        w = p - o
        b = float(w @ u)
        disc = b * b - (float(w @ w) - R * R)
        if disc < 0:
            return []
        h = math.sqrt(disc)
        return [p + (-b - h) * u, p + (-b + h) * u]
    (_, o1, R1), (_, o2, R2) = A, B
    w = o2 - o1
    d = math.hypot(*w)
    if d == 0:
        return []
    a = (R1 * R1 - R2 * R2 + d * d) / (2.0 * d)
    h2 = R1 * R1 - a * a
    if h2 < 0:
        return []
    h = math.sqrt(h2)
    e = w / d
    m = o1 + a * e
    n = np.array([-e[1], e[0]])
    return [m - h * n, m + h * n]


def _foot(piece, c: np.ndarray) -> tuple[float, np.ndarray]:
    """The parameter (0..1) and point of ``piece`` nearest to c along its normal (c's tangent point)."""
    if isinstance(piece, Segment):
        p0, p1 = np.array(piece.start), np.array(piece.end)
        v = p1 - p0
        t = float((c - p0) @ v / (v @ v))
        return t, p0 + t * v
    o = np.array(piece.center)
    w = c - o
    theta = math.atan2(w[1], w[0])
    sw = piece.sweep
    turn = (theta - piece.start_angle) % _TWO_PI if sw > 0 else (piece.start_angle - theta) % _TWO_PI
    t = turn / abs(sw)
    if t > 1.0 and (_TWO_PI - turn) / abs(sw) <= _ON:       # just before the start
        t = -(_TWO_PI - turn) / abs(sw)
    return t, o + piece.radius * w / math.hypot(*w)


def _part(piece, a: float, b: float):
    """The part of ``piece`` between parameters a < b."""
    if isinstance(piece, Segment):
        return Segment(piece.point_at(a), piece.point_at(b))
    return Arc(piece.center, piece.radius, piece.start_angle + piece.sweep * a, piece.sweep * (b - a))


def _turn(piece_in, piece_out) -> float:
    t0, t1 = piece_in.tangent_at(1.0), piece_out.tangent_at(0.0)
    return math.atan2(t0[0] * t1[1] - t0[1] * t1[0], t0[0] * t1[0] + t0[1] * t1[1])


def corner_fillets(loops, r: float):
    """The tightening of the shape bounded by ``loops`` when its corners are isolated, else None.

    Parameters
    ----------
    loops : list of Loop
        Outer boundaries counter-clockwise, holes clockwise; segments and arcs.
    r : float
        The radius, > 0.

    Returns
    -------
    list of Loop or None
        S's pieces, trimmed where the fillets meet them, and an arc of radius r at every corner
        (see the module notes for when this is the tightening, for every init); None when a check fails
        or S has no corner.

    Examples
    --------
    A square plate with sharp corners and a hole of radius 4, at r = 3: the hole is kept, the corners
    are rounded.

    >>> from vectortighten.curves import Segment
    >>> sq = Loop([Segment((-10, -10), (10, -10)), Segment((10, -10), (10, 10)),
    ...            Segment((10, 10), (-10, 10)), Segment((-10, 10), (-10, -10))])
    >>> outer, hole = corner_fillets([sq, Loop.circle((0.0, 0.0), 4.0, ccw=False)], 3.0)
    >>> sorted(a.radius for a in outer.arcs), [a.radius for a in hole.arcs]
    ([3.0, 3.0, 3.0, 3.0], [4.0])
    """
    from .curved_offsets import _inside, _offset_parts, _point_feature_distance
    from .loop_input import _pinned, region

    clean = []
    for lp in loops:
        pieces = [p for p in lp.pieces if isinstance(p, Arc) or p.length > 0]
        clean.append(pieces)
    trims, centres, sides, out = [], [], [], []
    corners = 0
    for pieces in clean:
        n = len(pieces)
        lo, hi = np.zeros(n), np.ones(n)
        start_side, end_side = np.zeros(n, np.int64), np.zeros(n, np.int64)    # the fillets' sides
        fillet = [None] * n                         # fillet[k]: the arc after piece k
        for k in range(n):
            p, q = pieces[k], pieces[(k + 1) % n]
            tau = _turn(p, q)
            if abs(tau) <= _CORNER:
                continue
            sigma = 1 if tau > 0 else -1
            A, B = _locus(p, sigma, r), _locus(q, sigma, r)
            if A is None or B is None:
                return None
            v = np.array(p.end)
            cs = _crossings(A, B)
            if not cs:
                return None
            c = min(cs, key=lambda x: math.hypot(*(x - v)))
            tp, fp = _foot(p, c)
            tq, fq = _foot(q, c)
            if not (-_ON <= tp <= 1 + _ON and -_ON <= tq <= 1 + _ON):
                return None
            hi[k] = min(hi[k], max(tp, 0.0))
            lo[(k + 1) % n] = max(lo[(k + 1) % n], min(tq, 1.0))
            end_side[k], start_side[(k + 1) % n] = sigma, sigma
            th_p = math.atan2(fp[1] - c[1], fp[0] - c[0])
            th_q = math.atan2(fq[1] - c[1], fq[0] - c[0])
            sweep = sigma * ((sigma * (th_q - th_p)) % _TWO_PI)
            if not 0 < abs(sweep) <= math.pi:
                return None
            fillet[k] = Arc(c, r, th_p, sweep)
            centres.append(c)
            sides.append(sigma)
            corners += 1
        if (hi - lo <= 1e-12).any():
            return None                             # two fillets overlap on one piece
        trims.append(np.column_stack([lo, hi, start_side, end_side]))
        new = []
        for k in range(n):
            new.append(_part(pieces[k], lo[k], hi[k]) if (lo[k], hi[k]) != (0.0, 1.0) else pieces[k])
            if fillet[k] is not None:
                new.append(fillet[k])
        out.append(new)
    if corners == 0:
        return None
    S = [Loop(p) for p in clean]
    trims = np.concatenate(trims)
    # (1), (2): the pieces pinned on both sides — on a fillet's side up to its foot, on the other side
    # whole (the corner's pieces bound its pocket) — and the vertex elements whole.
    for side in (1, -1):
        o = _offset_parts(S, r, side)
        if len(o.farc) != len(trims):
            return None
        rng = np.column_stack([np.where(trims[:, 2] == side, trims[:, 0], 0.0),
                               np.where(trims[:, 3] == side, trims[:, 1], 1.0)])
        pinned, joins = _pinned(S, r, side, rng, o)
        if not (pinned.all() and joins):
            return None
    # (3): every fillet centre clear of S's features, on its side.
    c = np.array(centres)
    sides = np.array(sides)
    qi, qf = o.tree.query(shapely.points(c), predicate="dwithin", distance=r + o.fsag)
    dist = _point_feature_distance(o.farc, o.fdat, o.fp0, o.fp1, qf, c[qi])
    clear = np.ones(len(c), dtype=bool)
    np.logical_and.at(clear, qi, dist >= r - o.eps)
    inside = _inside(S, c, r)
    if not (clear & (inside == (sides > 0))).all():
        return None
    # (4): the result bounds a valid shape.
    try:
        T = [Loop(p, atol=None) for p in out]
        region(T, 1e-3 * r)
    except (InvalidGeometryError, ValueError):
        return None
    return T
