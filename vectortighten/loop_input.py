"""Shapes given by their exact boundary (a list of `Loop`s, or a `Tightening`) as input to `tighten`.

A shape bounded by segments and circular arcs — a CAD part read with `vectortighten.io.read_loops`, or a
tightening fed back in — can be tightened without flattening its arcs when the answer is the shape
itself. This module decides that exactly (`identity`), and otherwise flattens the arcs to chords within
1e-5·r and hands the polygon to the polygon engine, with a warning naming what is lost.

When S is its own tightening
----------------------------
Write ∂S for S's boundary, made of segments and arcs, S on its left; R = R_r(S), F = F_r(S). For a side
σ (+1: inside S, −1: outside) the *offset element* of a piece is the set of points at distance r from it
along its σ-normal: a segment's parallel, an arc's concentric arc of radius ρ − σ·κ·r (κ = +1 for an arc
turning left, −1 for one turning right; a point when that radius is 0, nothing when it is negative), and
at a join where ∂S turns away from σ, the arc of radius r about the join between the two normals.
`curved_offsets._offset_parts` cuts every element where it enters or leaves a feature's r-neighbourhood
(line–line, line–circle and circle–circle crossings, in closed form) and keeps the parts whose
clearance — exact distance to every feature — is at least r − ε and which lie on σ's side of S. Between
two cuts the clearance is ≥ r or < r throughout, so "an element is kept whole" means: every point of it
is at clearance ≥ r (to the precision ε) and on σ's side. Call a piece *pinned on σ* when its element is
kept whole (a point element: the point has clearance ≥ r − ε and lies on σ's side); it needs ρ ≥ r for
an arc bending towards σ.

*Lemma.* If a piece is pinned on σ, every point p of it is on the boundary of an open r-disk D ⊆ S
(σ = +1) or D ⊆ S^c (σ = −1), tangent to ∂S at p. Proof: the centre c = p + σ·r·n(p) (n the left
normal) lies on the element, at clearance ≥ r, so the open disk D(c, r) meets no feature: it lies inside
S or inside S^c, and points of the normal just past p on σ's side are in it, so it is on σ's side. So p
is on ∂R (σ = +1: p ∈ closure of D ⊆ R ⊆ S, and p ∈ ∂S) or on ∂F (σ = −1).

*Identity (R = S = F).* If every piece and every join is pinned on both sides, then R = S = F. For
R ⊇ S: a point x ∈ S at distance δ ≥ r from ∂S is the centre of an r-disk in S. Else let p be a nearest
point of ∂S: x = p + δ·u with u in S's normal cone at p (the normal if ∂S is smooth at p; between the two
normals at a join turning away from S's side, whose arc is an element). The element point c = p + r·u
has clearance ≥ r, so x lies on the segment p c inside the closed disk D̄(c, r) ⊆ S: x ∈ R. A join
where ∂S turns towards σ (a sharp convex corner for σ = +1) makes the neighbouring parallels cross: both
are cut, so such a join is never pinned. The same on σ = −1 gives F = S. Then the mortar is ∂S itself
(zero width), every init starts from ∂S (Mason(S) = S when R = S = F), and the tightening is S, with its
own pieces.

*Tight already (init "input").* The flow starts from ∂S, a set of disjoint simple loops in the mortar
(R ⊆ S ⊆ F). If every arc turning left is pinned on +1 and every arc turning right is pinned on −1, and
∂S has no corner, then ∂S is locally shortest in the mortar: its straight pieces are straight, its left
turns lie on ∂R with R on the inside of the turn (the curve cannot move into R, and moving it outwards
lengthens it), its right turns lie on ∂F with the anticore on the inside of the turn. In a planar domain
a locally shortest closed curve is the shortest of its homotopy class, which the funnel finds: ∂S is the
tightening for init "input".

*Tight already (init "core").* The flow starts from ∂R. If moreover every piece is pinned on +1 (so
R = S, by the identity argument on that side), ∂R = ∂S, which is tight by the previous paragraph.

*Tight, other inits (not exact: matched).* When ∂S is tight (the "input" criterion) but neither of
the above holds — a tightening with a neck narrower than 2r, fed back in with init "core" or "mason" —
S is exactly *a* tightening of itself, but whether the flow from R_r(S) or Mason(S) picks it is not
decided in closed form. The shape is then flattened (chords within 1e-5·r) and tightened by the polygon
engine; if that result has S's numbers of components and holes and differs from S by less than
1e-3·r·perimeter and a quarter of an r-disk in area, S is returned with its own pieces (path
``"matched"``). The reasoning: the tight loops of one homotopy class are unique (a planar domain is
non-positively curved in its length metric), and two tightenings of different classes differ by a
whole component of the core or anticore, which holds an r-disk; so a result that close to S is in
S's class. What is not proved is that the flow on the flattened shape picks the class the flow on S
would (it may not where a part of S is within rounding of 2r wide).

Otherwise the arcs are flattened and the polygon engine's result is returned, with a `FlattenWarning`:
the engine's exact centres are solved on segments and points only (item 3 of issue 22, not done yet).

Precision: clearance is compared with r − ε, ε = max(1e-13·size, 64 ulps of the coordinates) (the closed
rule of `curved_offsets`): a tightening fed back in, whose arcs have radius r exactly and are tangent to
their neighbours to rounding, is certified.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import shapely

from .curves import Arc, Loop
from .engine import Init, Tightening, tighten
from .errors import InvalidGeometryError

__all__ = ["FlattenWarning", "LoopTightening", "as_loops", "identity", "merge_arcs", "tighten_loops"]

#: Chord tolerance, as a fraction of r, of the polygon an arc-bounded input is flattened to.
FLATTEN_R = 1e-5
#: Arcs whose centres and radii agree to this fraction of the loop's size are one circle (`merge_arcs`).
_SAME_CIRCLE = 1e-12
#: Largest angle (radians) between the tangents at a join that is still smooth (not a corner).
_SMOOTH = 1e-9


def merge_arcs(loop: Loop) -> Loop:
    """The loop with consecutive arcs of one circle merged into one arc (a whole circle into one piece).

    Parameters
    ----------
    loop : Loop

    Returns
    -------
    Loop
        The same curve; arcs merged where consecutive arcs have the same centre and radius (to 1e-12 of
        the loop's size) and turn the same way. Segments are left as they are.

    Examples
    --------
    An SVG circle is two half circles: merged, one arc of a whole turn.

    >>> import math
    >>> halves = Loop([Arc((0, 0), 2.0, 0.0, math.pi), Arc((0, 0), 2.0, math.pi, math.pi)])
    >>> [(a.radius, a.sweep / math.pi) for a in merge_arcs(halves).pieces]
    [(2.0, 2.0)]
    """
    pieces = list(loop.pieces)
    if len(pieces) < 2:
        return loop
    x0, y0, x1, y1 = loop.bounds
    tol = _SAME_CIRCLE * max(x1 - x0, y1 - y0, 1e-300)

    def same(a, b) -> bool:
        return (isinstance(a, Arc) and isinstance(b, Arc) and (a.sweep > 0) == (b.sweep > 0)
                and abs(a.radius - b.radius) <= tol
                and math.hypot(a.center[0] - b.center[0], a.center[1] - b.center[1]) <= tol)

    # Start at a piece that does not continue the one before it (if every join merges: one circle).
    start = next((k for k in range(len(pieces)) if not same(pieces[k - 1], pieces[k])), None)
    if start is None:
        a = pieces[0]
        return Loop([Arc(a.center, a.radius, a.start_angle, math.fsum(p.sweep for p in pieces))], atol=math.inf)
    pieces = pieces[start:] + pieces[:start]
    out = [pieces[0]]
    for p in pieces[1:]:
        if same(out[-1], p):
            a = out[-1]
            out[-1] = Arc(a.center, a.radius, a.start_angle, a.sweep + p.sweep)
        else:
            out.append(p)
    if len(out) == len(pieces):
        return loop
    return Loop(out, atol=math.inf)


def is_loop_input(S) -> bool:
    """Whether S is a shape given by its exact boundary: a list of `Loop`s or a result with ``loops``."""
    if isinstance(S, (list, tuple)):
        return len(S) > 0 and all(isinstance(lp, Loop) for lp in S)
    return hasattr(S, "loops") and isinstance(getattr(S, "loops"), list) and hasattr(S, "r")


def as_loops(S) -> list[Loop]:
    """The loops of S (a list of `Loop`s, or a `Tightening` / `ExactBoundary`), checked.

    Raises
    ------
    InvalidGeometryError
        Empty, non-finite coordinates, loops that cross or touch, or holes not inside an outer loop
        (outer loops run counter-clockwise, holes clockwise).

    Examples
    --------
    >>> as_loops([Loop.circle((0, 0), 1.0)])[0].is_ccw
    True
    """
    loops = list(S.loops) if not isinstance(S, (list, tuple)) else list(S)
    if not loops:
        raise InvalidGeometryError("the shape has no loop (it is empty)")
    bad = [type(lp).__name__ for lp in loops if not isinstance(lp, Loop)]
    if bad:
        raise TypeError(f"a shape given as a list must hold Loops, got {', '.join(sorted(set(bad)))}")
    for lp in loops:
        if not np.isfinite(lp._data).all():
            raise InvalidGeometryError("a loop has NaN or infinite coordinates")
    if sum(1 for lp in loops if lp.area > 0) == 0:
        raise InvalidGeometryError("no loop runs counter-clockwise: outer boundaries must, holes run clockwise")
    return loops


def region(loops, tolerance: float):
    """The shapely region bounded by the loops, arcs sampled within ``tolerance``; validity checked.

    Raises
    ------
    InvalidGeometryError
        If the loops cross, touch, or a hole lies outside every outer loop (the sampled region is then not
        valid, or its area differs from the loops' exact area by more than the sampling explains).
    """
    from .engine import _assemble_valid

    geom, valid = _assemble_valid(loops, tolerance)
    exact = math.fsum(lp.area for lp in loops)
    slack = tolerance * math.fsum(lp.length for lp in loops) + 1e-9 * abs(exact)
    if not valid or abs(geom.area - exact) > slack:
        raise InvalidGeometryError("the loops do not bound a valid shape (they cross or touch, or a hole "
                                   "is outside every outer loop: outer loops run counter-clockwise, holes "
                                   "clockwise)")
    return geom


def _apart(loops, tolerance: float) -> bool:
    """Whether the loops are pairwise more than 4·``tolerance`` apart, sampled within ``tolerance`` (so a
    pair that touches, or comes within rounding of it, is found; a pair closer than that is taken as
    touching, and the exact paths are not tried)."""
    rings = [lp.to_ring(tolerance) for lp in loops]
    if len(rings) < 2:
        return True
    tree = shapely.STRtree(rings)
    i, j = tree.query(rings, predicate="dwithin", distance=4.0 * tolerance)
    return bool((i == j).all())


def _pinned(loops, r: float, side: int, trims=None, o=None) -> tuple[np.ndarray, bool]:
    """Per feature (pieces of the loops in `curved_offsets._features` order): whether it is pinned on
    ``side`` (its offset element kept whole, see the module notes; with ``trims`` (nf, 2), kept over the
    parameter range ``trims[f]`` of feature f only); and whether every vertex element (an arc about a
    join turning away from the side) is kept whole."""
    from .curved_offsets import _inside, _offset_parts, _point_feature_distance

    o = _offset_parts(loops, r, side) if o is None else o
    nf = len(o.farc)
    own = o.el_piece >= 0
    a = np.zeros(len(o.el_arc))
    b = np.ones(len(o.el_arc))
    if trims is not None:
        a[own], b[own] = trims[o.el_piece[own], 0], trims[o.el_piece[own], 1]
    # An element is kept (over [a, b]) when one kept part covers that range (to its length's precision).
    whole = np.zeros(len(o.el_arc), dtype=bool)
    if len(o.part_e):
        e = o.part_e
        full = (o.lo <= a[e] + o.tiny[e]) & (o.hi >= b[e] - o.tiny[e])
        whole[e[full]] = True
    whole |= o.length <= 2.0 * o.eps                        # rounding-sized elements: nothing to keep
    pinned = np.zeros(nf, dtype=bool)
    pinned[o.el_piece[own]] = whole[own]
    # Point elements: the centre of an arc of radius r bending towards the side.
    if len(o.collapsed):
        c = o.fdat[o.collapsed, :2]
        qi, qf = o.tree.query(shapely.points(c), predicate="dwithin", distance=r + o.fsag)
        dist = _point_feature_distance(o.farc, o.fdat, o.fp0, o.fp1, qf, c[qi])
        clear = np.ones(len(c), dtype=bool)
        np.logical_and.at(clear, qi, dist >= r - o.eps)
        inside = _inside(loops, c, r)
        pinned[o.collapsed] = clear & (inside if side > 0 else ~inside)
    pinned[o.too_curved] = False
    return pinned, bool(whole[~own].all())


def _smooth(loops) -> bool:
    """No join of any loop is a corner (tangents agree within `_SMOOTH` beyond the loops' rounding)."""
    return all(lp.is_g1(_SMOOTH, lp.rounding()) for lp in loops)


def identity(loops, r: float, init: str) -> bool:
    """Whether the r-tightening of the shape bounded by ``loops`` (for ``init``) is the shape itself.

    Decided exactly from the offsets of the loops' segments and arcs (see the module notes for the
    criterion and its proof): True when R_r(S) = S = F_r(S); for init ``"input"`` also when every arc
    turning left is pinned by a core disk and every arc turning right by an anticore disk and ∂S has no
    corner; for ``"core"`` when in addition R_r(S) = S.

    Parameters
    ----------
    loops : list of Loop
        Outer boundaries counter-clockwise, holes clockwise, disjoint and simple.
    r : float
        The radius, > 0.
    init : {"core", "input", "mason"}

    Examples
    --------
    A plate with a hole of radius 4 and rounded corners of radius 3 is its own tightening at r = 3; with
    sharp corners it is not.

    >>> from vectortighten.curves import Segment
    >>> hole = Loop.circle((0.0, 0.0), 4.0, ccw=False)
    >>> sq = Loop([Segment((-10, -10), (10, -10)), Segment((10, -10), (10, 10)),
    ...            Segment((10, 10), (-10, 10)), Segment((-10, 10), (-10, -10))])
    >>> identity([sq, hole], 3.0, "core")
    False
    """
    if not _smooth(loops):
        return False
    features = np.concatenate([lp._arc[_kept(lp)] for lp in loops])
    sweeps = np.concatenate([lp._data[_kept(lp), 4] for lp in loops])
    plus, plus_joins = _pinned(loops, r, 1)
    minus, minus_joins = _pinned(loops, r, -1)
    if plus.all() and minus.all() and plus_joins and minus_joins:
        return True
    if init == "mason":
        return False
    left, right = features & (sweeps > 0), features & (sweeps < 0)
    tight = bool(plus[left].all() and minus[right].all())
    if init == "input":
        return tight
    return tight and bool(plus.all()) and plus_joins


def _kept(lp: Loop) -> np.ndarray:
    """The pieces `curved_offsets._features` keeps (arcs, and segments of nonzero length)."""
    s, e = lp._ends()
    return lp._arc | (np.hypot(*(e - s).T) > 0)


def tighten_loops(S, r: float, init="core", tolerance: float | None = None):
    """`tighten` for a shape given by its exact boundary: a list of `Loop`s, a `Tightening` or an
    `ExactBoundary`.

    Parameters
    ----------
    S : list of Loop, or a result with ``loops``
        Outer boundaries counter-clockwise, holes clockwise, disjoint and simple; segments and arcs of any
        radius.
    r : float
        The radius, > 0, in the loops' units.
    init : {"core", "input", "mason"}
    tolerance : float, optional
        Chord tolerance of the result's ``geometry``; default 1e-5·r.

    Returns
    -------
    Tightening
        The shape itself, with its own pieces (arcs of one circle merged, `merge_arcs`), when `identity`
        certifies that it is its own tightening, or when it is tight and the polygon engine on it
        flattened comes back to it (``"matched"``, see the module notes); else the tightening of the
        polygon the loops make with their arcs flattened within `FLATTEN_R`·r, with a `FlattenWarning`
        when there were arcs. ``T._cache["_path"]`` says which (``"identity"``, ``"matched"``).

    Examples
    --------
    A tightening fed back in comes back with the same pieces.

    >>> from shapely.geometry import box
    >>> from vectortighten import tighten
    >>> T = tighten(box(0, 0, 4, 3), 1.0)
    >>> again = tighten_loops(T, 1.0)
    >>> [lp.pieces for lp in again.loops] == [lp.pieces for lp in T.loops]
    True
    """
    from ._validation import check_radius, check_shape, check_tolerance

    r = check_radius(r)
    try:
        init = Init(init.value if isinstance(init, Init) else init).value
    except ValueError:
        raise ValueError(f"init must be 'core', 'input' or 'mason', got {init!r}") from None
    loops = [merge_arcs(lp) for lp in as_loops(S)]
    tolerance = check_tolerance(tolerance, r)
    shape = region(loops, tolerance)
    tolerance = check_tolerance(tolerance, r, shape)
    apart = _apart(loops, tolerance)
    if apart and identity(loops, r, init):
        T = LoopTightening(loops=loops, geometry=shape, r=r, init=init, tolerance=tolerance, shape=shape)
        T._cache["_path"] = "identity"
        return T
    from .arc_fillets import corner_fillets

    filleted = corner_fillets(loops, r) if apart else None
    if filleted is not None:
        T = LoopTightening(loops=filleted, geometry=region(filleted, tolerance), r=r, init=init,
                           tolerance=tolerance, shape=shape)
        T._cache["_path"] = "arc-fillets"
        return T
    flat = check_shape(region(loops, FLATTEN_R * r))
    U = tighten(flat, r, init=init, tolerance=tolerance)
    if apart and init != "input" and identity(loops, r, "input") and _matches(U, shape, loops, r):
        # S is exactly a tightening of itself, and the flow from this init picks its homotopy class.
        T = LoopTightening(loops=loops, geometry=shape, r=r, init=init, tolerance=tolerance, shape=shape)
        T._cache["_path"] = "matched"
        return T
    arcs = sum(len(lp.arcs) for lp in loops)
    if arcs:
        warnings.warn(f"the shape's {arcs} arc{'s are' if arcs != 1 else ' is'} flattened to chords within "
                      f"{FLATTEN_R:g}·r before tightening: the result's arcs all have radius r, the input's "
                      "own radii are not kept (the exact paths take shapes that are their own tightening or "
                      "whose corners are isolated)", FlattenWarning, stacklevel=3)
    return U


def _matches(U, shape, loops, r: float) -> bool:
    """Whether the tightening U of the flattened shape is the shape itself, up to the flattening.

    Same numbers of components and holes, and a symmetric difference smaller than ``1e-3·r`` times the
    perimeter (a hundred times what chords within 1e-5·r account for) and than a quarter of an r-disk:
    two tightenings of one shape in different homotopy classes differ by a whole component of the core
    or the anticore, which holds an r-disk.
    """
    if U.is_empty:
        return False
    if U.n_components != sum(1 for lp in loops if lp.area > 0) or U.n_holes != sum(1 for lp in loops if lp.area < 0):
        return False
    limit = min(1e-3 * r * math.fsum(lp.length for lp in loops), 0.25 * math.pi * r * r)
    return float(U.geometry.symmetric_difference(shape).area) <= limit


class LoopTightening(Tightening):
    """A `Tightening` that is its input, with the input's own pieces (made by `tighten_loops`).

    Its arcs are the input's: of radius r or more. `verify` checks (a), (b) and (d) as for any tightening,
    and for (c) that every arc has radius at least r (not exactly r) and every join is G1.
    """

    def verify(self) -> list[str]:
        """As `Tightening.verify`, arcs of radius ≥ r allowed (the input's own arcs)."""
        r = self.r
        out = [p for p in super().verify() if "has an arc of radius" not in p]
        for i, lp in enumerate(self.loops):
            small = [a.radius for a in lp.arcs if a.radius < r * (1 - 1e-9)]
            if small:
                out.append(f"(c) loop {i} has an arc of radius {min(small)!r} < r = {r!r}")
        return out


class FlattenWarning(UserWarning):
    """An arc-bounded input was flattened to chords before tightening: its own arc radii are lost."""

