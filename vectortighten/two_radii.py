"""Tightening with two radii: a convex radius a and a concave radius b.

With ``r = (a, b)`` the core is ``R_a(S)`` (the opening by a), the fillet ``F_b(S)`` (the closing by b),
and the tight boundary is made of the shortest loops in ``F_b(S) − R_a(S)``: arcs of radius a that turn
left (about disks inside S), arcs of radius b that turn right (about disks outside S), and segments
tangent to both. Either radius may be 0: ``a = 0`` keeps convex corners sharp (the "disk" is the vertex),
``b = 0`` keeps reflex corners sharp; ``(0, tool_radius)`` is the CNC rule for inside corners.

Three paths, tried in this order:

* shapes whose every corner is isolated (the polygon fast path, `vectortighten._fast`): each convex corner
  gets its radius-a disk, each reflex corner its radius-b disk, certified by exact distance tests against
  the shrink by a and the grow by b;
* convex polygons with ``a > 0`` (the tightening is then the opening ``R_a(S)``, whatever b);
* everything else (corners whose disks interact, gaps or thin parts the disks cannot pass, parts that
  vanish or join) goes to the general engine (`vectortighten.engine`) with a radius per disk: the centres
  and obstacles of side +1 are the corners and pieces of ``S↓a``, those of side −1 of ``(S^c)↓b``, the
  free space lies between ``R_a`` and ``F_b``, tangents join disks of signed radii (DESIGN §3.1), every
  violation test, contact and depth is measured at the radius of the side it concerns, and `verify` runs
  the engine's exact tests on the result. A radius 0 there (`_zero_radius`): that side's disks are S's
  own convex (a = 0) or reflex (b = 0) vertices, the guide core (fillet) is S, and a straight piece that
  enters S's interior (a = 0) or leaves S (b = 0) — GEOS's exact DE-9IM relation — gets the farthest
  corner of the boundary chain it cuts off as the disk to add; the depth of such an entry is what
  `verify` bounds.

``init="mason"`` starts from Mason(S) between R_a and F_b: each pocket of the mortar takes
``R_a(F_b(S))`` or ``F_b(R_a(S))``, whichever differs less from S there (`morphology._mason`). A shape
given by its loops (segments and arcs) is tightened as the polygon it makes with its arcs flattened, with a
`FlattenWarning`. A pair ``(r, r)`` is the one-radius tightening itself (the same code path, the same
numbers).
"""

from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from . import _convex, _fast
from . import morphology as _m
from .curves import Loop
from .engine import Tightening
from .errors import ConvergenceWarning, InvalidRadiusError, TighteningError, TighteningFailedError
from .tolerances import CORNER_ANGLE, EXACT_CHORD_R, THICKEN_R, TOUCH_SCALE, rounding_length

__all__ = ["TwoRadiiNotSupportedError", "TwoRadiiTightening", "is_pair", "parse_radii", "two_radii_morphology"]


class TwoRadiiNotSupportedError(TighteningError, NotImplementedError):
    """Two different radii where no two-radii path applies.

    Every pair and every init is computed today; the class stays for code that catches it (it was raised
    for ``init="mason"`` on the general engine, and for shapes given by their loops).
    """


def is_pair(r) -> bool:
    """Whether ``r`` is given as a sequence (a pair of radii) rather than one number."""
    if isinstance(r, (str, bytes)) or isinstance(r, numbers.Real):
        return False
    return isinstance(r, (tuple, list, np.ndarray))


def parse_radii(r) -> tuple[float, float]:
    """Check a pair of radii ``(r_convex, r_concave)`` and return it as two floats.

    Parameters
    ----------
    r : sequence of two numbers
        ``(a, b)``: the convex radius a (the core is the opening ``R_a(S)``) and the concave radius b (the
        fillet is the closing ``F_b(S)``), both finite and ≥ 0, not both 0, in the shape's units.

    Returns
    -------
    (float, float)

    Raises
    ------
    InvalidRadiusError
        (a `ValueError`) if r does not have two entries, if one is not a real number, negative or not
        finite, or if both are 0.

    Examples
    --------
    >>> parse_radii((0, 3))
    (0.0, 3.0)
    >>> parse_radii([2, -1])
    Traceback (most recent call last):
    ...
    vectortighten.errors.InvalidRadiusError: r_concave must be a finite number ≥ 0, got -1
    """
    try:
        values = list(r)
    except TypeError:
        raise InvalidRadiusError(f"r must be a number or a pair (r_convex, r_concave), got {r!r}") from None
    if len(values) != 2:
        raise InvalidRadiusError(
            f"r must be a number or a pair (r_convex, r_concave), got {len(values)} value(s): {r!r}")
    out = []
    for name, x in zip(("r_convex", "r_concave"), values, strict=True):
        if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real):
            raise InvalidRadiusError(f"{name} must be a finite number ≥ 0, got {x!r}")
        v = float(x)
        if not math.isfinite(v) or v < 0:
            raise InvalidRadiusError(f"{name} must be a finite number ≥ 0, got {x!r}")
        out.append(v)
    if out[0] == 0 and out[1] == 0:
        raise InvalidRadiusError("r = (0, 0): at least one of r_convex, r_concave must be positive")
    return out[0], out[1]


def two_radii_morphology(S, radii, tolerance: float | None = None):
    """The core ``R_a(S)``, fillet ``F_b(S)`` and mortar ``F_b(S) − R_a(S)`` of a shape for two radii.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
    radii : (float, float)
        ``(a, b)``, both ≥ 0, in S's units; a radius of 0 leaves S itself (``R_0(S) = F_0(S) = S``).
    tolerance : float, optional
        Passed to `vectortighten.core` and `vectortighten.fillet`.

    Returns
    -------
    core, fillet, mortar : shapely geometry

    Examples
    --------
    >>> from shapely.geometry import box
    >>> R, F, M = two_radii_morphology(box(0, 0, 4, 4), (1.0, 0.0))
    >>> F.equals(box(0, 0, 4, 4)), round(M.area, 3)      # four corners of 1 − π/4 each
    (True, 0.858)
    """
    a, b = parse_radii(radii)
    R = _m.core(S, a, tolerance=tolerance) if a > 0 else S
    F = _m.fillet(S, b, tolerance=tolerance) if b > 0 else S
    return R, F, _m._polygonal(F.difference(R))


@dataclass
class TwoRadiiTightening(Tightening):
    """The exact tightening of a shape for two radii ``(r_convex, r_concave)`` = (a, b).

    A `Tightening` whose arcs turning left have radius a and those turning right radius b (a radius of
    0: sharp corners there), from the fast, the convex or the general path (``_cache["_path"]``). ``r`` is the larger of the two (it sets the default ``tolerance``, 1e-5·r);
    ``radii`` is the pair, also as ``r_convex`` and ``r_concave``; ``core``, ``fillet`` and ``mortar``
    are ``R_a(S)``, ``F_b(S)`` and their difference.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> from vectortighten import tighten
    >>> T = tighten(box(0, 0, 4, 4), (0.0, 1.0))        # no reflex corner: the square itself
    >>> T.radii, T.r, T.perimeter, T.min_radius_of_curvature
    ((0.0, 1.0), 1.0, 16.0, 0.0)
    """

    radii: tuple[float, float] = (0.0, 0.0)

    def _morph(self, name):
        if name not in self._cache:
            R, F, M = two_radii_morphology(self.shape, self.radii, tolerance=self.tolerance)
            self._cache.update(core=R, fillet=F, mortar=M)
        return self._cache[name]

    def verify(self) -> list[str]:
        """Check DESIGN §7 for two radii; return the list of violations (empty if valid).

        (a) ``R_a(S) ⊆ T ⊆ F_b(S)``, decided on S's exact offsets by a and b (as for one radius); (b)
        valid geometry, loops pairwise apart; (c) every arc turning left has radius a and every arc turning
        right radius b, every join is G1 except corners kept sharp by a radius 0 (left turns for a = 0,
        right turns for b = 0), and the loops are the ones the fast path's (or the convex path's) exact
        tests, run again on S, certify; for the general engine, its exact tests at each side's radius:
        the loops stay out of the open ``R_a`` and out of the complement of ``F_b`` (exact piece
        distances to ``S↓a`` and ``(S^c)↓b``), every arc is centred on an exact corner of its side, and
        no two loops touch.
        """
        return _verify(self)


def _loop_from_disks(c, s, rho, phi, length, sweep, frame) -> Loop:
    """An exact loop from disks with per-disk radii (0: a sharp corner at the centre), in world units.

    Disk i's arc (left for side +1, right for −1) is followed by the tangent leaving it, from
    ``c[i] − s[i]·ρ[i]·n(φ[i])`` to ``c[i+1] − s[i+1]·ρ[i+1]·n(φ[i])``, n the left normal. Arcs of radius
    0 and tangents of length 0 are left out.
    """
    scale, ox, oy = frame.scale, frame.ox, frame.oy
    c = np.asarray(c, float) * scale + (ox, oy)
    rho = np.asarray(rho, float) * scale
    length = np.asarray(length, float) * scale
    n = len(c)
    nrm = np.column_stack([-np.sin(phi), np.cos(phi)])
    sr = (s * rho)[:, None]
    P = c - sr * nrm
    Q = np.roll(c, -1, axis=0) - np.roll(sr, -1, axis=0) * nrm
    start = np.roll(phi, 1) - s * (math.pi / 2)
    data = np.zeros((2 * n, 5))
    data[0::2] = np.column_stack([c, rho, start, sweep])
    data[1::2, :4] = np.column_stack([P, Q])
    arc = np.zeros(2 * n, bool)
    arc[0::2] = True
    eps = 1e-13 * (float(np.ptp(c, axis=0).max()) + 2.0 * float(rho.max()))
    keep = np.empty(2 * n, bool)
    keep[0::2] = (rho > 0) & (sweep != 0)
    keep[1::2] = length > eps
    return Loop._from_arrays(arc[keep], data[keep])


def tighten_two_radii(S, radii, *, init="core", tolerance: float | None = None):
    """`vectortighten.tighten` with ``r = (r_convex, r_concave)``; see the module notes for what is supported.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
    radii : (float, float)
        ``(a, b)``, finite, ≥ 0, not both 0.
    init : {"core", "input", "mason"}
    tolerance : float, optional
        Default 1e-5·max(a, b).

    Returns
    -------
    Tightening
        For ``a == b`` the one-radius tightening itself; else a `TwoRadiiTightening`.

    Raises
    ------
    InvalidRadiusError
        For a bad pair (see `parse_radii`) or a positive radius below what doubles resolve for S.

    Examples
    --------
    A 10 × 6 rectangle with its corners rounded by 2 and no reflex corner to fill:

    >>> from math import isclose, pi
    >>> from shapely.geometry import box
    >>> T = tighten_two_radii(box(0, 0, 10, 6), (2.0, 5.0))
    >>> isclose(T.perimeter, 32 - 4 * (2 * 2.0 - 2.0 * pi / 2))
    True
    """
    from ._guard import vanishes
    from ._validation import check_output_size, check_resolution, check_shape, check_tolerance
    from .engine import Init, _loop_input, tighten

    a, b = parse_radii(radii)
    if a == b:
        return tighten(S, a, init=init, tolerance=tolerance)
    if not isinstance(S, (Polygon, MultiPolygon)) and _loop_input(S):
        S = _flattened(S, a, b)
    r = max(a, b)
    S = check_shape(S)
    tol = check_tolerance(tolerance, r, S)
    for name, x in (("r_convex", a), ("r_concave", b)):
        if x > 0:
            try:
                check_resolution(S, x)
            except InvalidRadiusError as exc:
                raise InvalidRadiusError(f"{name}: {exc}") from None
    try:
        init = Init(init.value if isinstance(init, Init) else init)
    except ValueError:
        raise ValueError(f"init must be 'core', 'input' or 'mason', got {init!r}") from None
    check_output_size(S, r, tol)
    if min(a, b) > 0 and vanishes(S, min(a, b)):
        # Neither a core disk (radius a) nor an enclosed anticore disk (radius b) fits in S's box.
        from .engine import _Frame

        empty = TwoRadiiTightening(loops=[], geometry=Polygon(), r=r, init=init.value, tolerance=tol, shape=S,
                                   radii=(a, b))
        empty._cache.update(_frame=_Frame.of(S), _path="empty")
        return empty
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            result = _tighten_pair(S, a, b, init, tol)
            problems = _final_check(result) if result._cache.get("_path") != "general" else _general_check(result)
    except (MemoryError, TighteningError):
        raise
    except Exception as exc:
        text = str(exc).splitlines()[0] if str(exc) else ""
        raise TighteningFailedError(
            f"the engine could not tighten this shape at r = ({a:g}, {b:g}) ({type(exc).__name__}"
            f"{': ' + text if text else ''}); please report it with the shape") from exc
    if problems:
        result.converged = False
        warnings.warn(f"the result fails its final check ({'; '.join(problems)}): returned with "
                      "converged=False (Tightening.verify() lists where)", ConvergenceWarning, stacklevel=3)
    return result


def _flattened(S, a: float, b: float):
    """The polygon a shape given by its loops makes with its arcs flattened within `FLATTEN_R` times the
    smaller positive radius, with a `FlattenWarning` where there were arcs.

    The exact paths for loops (a shape that is its own tightening, isolated corners filleted in closed form,
    `loop_input`) are certified at one radius; with two, the polygon engine takes the flattened shape, as
    the one-radius path does wherever those certificates fail.
    """
    from .loop_input import FLATTEN_R, FlattenWarning, as_loops, merge_arcs, region

    loops = [merge_arcs(lp) for lp in as_loops(S)]
    step = FLATTEN_R * min(x for x in (a, b) if x > 0)
    arcs = sum(len(lp.arcs) for lp in loops)
    if arcs:
        warnings.warn(f"the shape's {arcs} arc{'s are' if arcs != 1 else ' is'} flattened to chords within "
                      f"{step:.3g} before tightening with two radii: the result's arcs have radius a or b, the "
                      "input's own radii are not kept (the exact paths for arcs take one radius)", FlattenWarning,
                      stacklevel=4)
    return region(loops, step)


def _final_check(T) -> list[str]:
    """The cheap check made on every result, as `_guard.containment_problems` makes it for one radius:
    ``R_a ⊆ T ⊆ F_b`` against coarse buffers (4 chords a quarter circle) in the local frame. The loops
    are certified by the fast path's exact tests; this only catches a gross failure."""
    from ._guard import _AREA_R2, _COARSE_QUAD_SEGS, _coarse

    frame = T._cache["_frame"]
    S = frame.to_local(T.shape)
    a, b = (x / frame.scale for x in T.radii)
    r, q = max(a, b), _COARSE_QUAD_SEGS
    R = shapely.intersection(S.buffer(-a, quad_segs=q).buffer(a, quad_segs=q), S) if a > 0 else S
    F = shapely.union(S.buffer(b, quad_segs=q).buffer(-b, quad_segs=q), S) if b > 0 else S
    slack = T.tolerance / frame.scale + 2.0 * r * (1.0 - math.cos(math.pi / (4 * q))) + 2.0 * THICKEN_R * r
    tiny = _AREA_R2 * r * r
    G = frame.to_local(_coarse(T.loops, 0.25 * slack * frame.scale)) if T.loops else Polygon()
    problems = []
    if not R.is_empty:
        missed = shapely.difference(R.buffer(-0.75 * slack, quad_segs=2), G).area if not G.is_empty else R.area
        if missed > tiny:
            problems.append(f"it misses {missed / (r * r):.3g}·r² of the core R_a")
    if not G.is_empty:
        outside = shapely.difference(G, F.buffer(0.75 * slack, quad_segs=2)).area
        if outside > tiny:
            problems.append(f"{outside / (r * r):.3g}·r² of it lies outside the fillet F_b")
    return problems


def _general_check(T) -> list[str]:
    """The final check of a result of the general engine, as `guarded_tighten` makes it for one radius:
    ``R_a ⊆ T ⊆ F_b`` against the guide core and fillet the engine built, and every join tangent (both
    radii are positive there)."""
    from ._guard import _corner_problems, containment_problems

    x0, y0, x1, y1 = T.shape.bounds
    rounding = rounding_length(max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1)))
    if min(T.radii) > 0:
        return containment_problems(T) + _corner_problems(T, rounding)
    # A radius 0 keeps sharp corners turning its way: only corners turning the other way are wrong.
    bad = sum(_bad_corners(loop, *T.radii, rounding) for loop in T.loops)
    return containment_problems(T) + ([f"{bad} corner(s) turn the way whose radius is positive"] if bad else [])


def _tighten_pair(S, a: float, b: float, init, tol: float):
    from ._validation import quad_segs_for
    from .engine import _assemble_valid, _Frame
    from .offsets import precision_of

    frame = _Frame.of(S)
    S_local = frame.to_local(S)
    a_l, b_l = a / frame.scale, b / frame.scale
    r_l = max(a_l, b_l)
    precision = precision_of(S) / frame.scale
    q = quad_segs_for(r_l, EXACT_CHORD_R * r_l)
    fast = _fast.fast_disk_loops(S_local, r_l, q, init.value, precision, radii=(a_l, b_l))
    path = "fast"
    if fast is None and a_l > 0:
        # A convex polygon is its own fillet for every b: its tightening is its opening by a (`_convex`).
        loop = _convex.convex_disk_loop(S_local, a_l)
        if loop is not None:
            fast, path = [loop + (np.full(len(loop[0]), a_l),)], "convex"
    if fast is None:
        return _tighten_pair_general(S, S_local, frame, a, b, init, tol, precision)
    loops = [_loop_from_disks(c, s.astype(float), rho, phi, ln, sw, frame) for c, s, phi, ln, sw, rho in fast]
    geometry, valid = _assemble_valid(loops, tol)
    # Rounded rings that do not bound a valid region, a ring that touches itself, two rings that touch
    # (parts of the shape that meet): only the general engine's surgery separates or joins them.
    if (not (valid or geometry.is_valid) or geometry.is_empty
            or not all(shapely.is_valid(Polygon(loop.sample(tol))) for loop in loops)
            or (len(loops) > 1 and _loops_touch(loops, tol, frame.scale))):
        return _tighten_pair_general(S, S_local, frame, a, b, init, tol, precision)
    result = TwoRadiiTightening(loops=loops, geometry=geometry, r=max(a, b), init=init.value, tolerance=tol,
                                shape=S, converged=True, radii=(a, b))
    result._cache["_frame"] = frame
    result._cache["_path"] = path
    result._cache["_pair"] = (S_local, r_l, (a_l, b_l), precision, q, fast)
    return result


def _tighten_pair_general(S, S_local, frame, a: float, b: float, init, tol: float, precision: float):
    """The general engine (`engine`) with a radius per disk: side +1 disks of radius a about the corners of
    S↓a, side −1 disks of radius b about those of (S^c)↓b, the free space between R_a and F_b."""
    from ._guard import drop_specks
    from .engine import Init, _assemble, _Context, _initial_rings, _tighten_all

    a_l, b_l = a / frame.scale, b / frame.scale
    r_l, tol_l = max(a_l, b_l), tol / frame.scale
    ctx = _Context(S_local, r_l, tol_l, precision, radii=(a_l, b_l))
    rings = _initial_rings(ctx, S_local, init)
    disk_loops = _tighten_all(ctx, rings) if rings else []
    x0, y0, x1, y1 = S.bounds
    rounding = rounding_length(max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1)))
    loops = [drop_specks(L.to_loop(frame), rounding) for L in disk_loops]
    geometry = _assemble(loops, tol)
    result = TwoRadiiTightening(loops=loops, geometry=geometry, r=max(a, b), init=init.value, tolerance=tol,
                                shape=S, converged=all(L.converged for L in disk_loops), radii=(a, b))
    if not result.converged:
        warnings.warn("the exact finish did not settle on every loop: the result may enter the core or the "
                      "anticore (Tightening.verify() lists where)", ConvergenceWarning, stacklevel=4)
    result._cache["_exact"] = (ctx, disk_loops, (S_local, r_l, tol_l, precision))
    result._cache["_frame"] = frame
    result._cache["_path"] = "general"
    return result


def _loops_touch(loops, tol: float, size: float) -> bool:
    """Whether two loops come within their sampling tolerance (and the touching scale) of each other."""
    lines = [shapely.LineString(loop.sample(tol)) for loop in loops]
    tree = shapely.STRtree(lines)
    i, j = tree.query(lines, predicate="dwithin", distance=2.0 * tol + TOUCH_SCALE * size)
    return bool((i < j).any())


def _verify(T) -> list[str]:
    problems: list[str] = []
    a, b = T.radii
    tol = T.tolerance
    G = T.geometry
    x0, y0, x1, y1 = T.shape.bounds
    rounding = rounding_length(max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1)))
    # (a) ``R_a ⊆ T ⊆ F_b``, decided as for one radius on S's exact offsets (`_exact_containment`): the
    # loops are the certified ones (checked below), which stay out of the open core and anticore, so each
    # component of the open core lies wholly inside T or outside it, and it suffices that every corner
    # and piece of S↓a lies in T and every one of (S^c)↓b outside. Buffered references would not do:
    # GEOS simplifies a buffer's input (false alarms of 1e-15 of area on parts 1e-5 wide far out).
    # A radius 0 is S itself: S ⊆ T (a = 0) or T ⊆ S (b = 0), against T or S widened by the slack.
    slack = 2 * tol + 4.0 * rounding
    tiny = 1e-9 * max(x1 - x0, y1 - y0) ** 2
    info = T._cache.get("_pair")
    frame = T._cache.get("_frame")
    general = T._cache.get("_path") == "general"
    if general:
        ctx, _ = T._exact_context()
        problems += _exact_a(T, None, frame, slack, tiny, offsets=(ctx.xE, ctx.xG))
    elif T._cache.get("_path") == "empty" or info is None:
        R, _, _ = two_radii_morphology(T.shape, T.radii, tolerance=tol / 4)
        if not R.is_empty and R.difference(G.buffer(slack)).area > tiny:
            problems.append("(a) the tightening misses part of the core R_a")
    else:
        problems += _exact_a(T, info, frame, slack, tiny)
    # (b)
    if not G.is_valid:
        problems.append(f"(b) geometry is invalid: {shapely.is_valid_reason(G)}")
    if len(T.loops) > 1 and _loops_touch(T.loops, tol, frame.scale if frame else 1.0):
        problems.append("(b) two loops touch")
    # (c), (d): arcs of the right radius on the right side; corners only where a radius is 0.
    for i, loop in enumerate(T.loops):
        d = loop._data[loop._arc]
        left = d[:, 4] > 0
        if (np.abs(d[left, 2] - a) > 1e-9 * max(a, b)).any():
            problems.append(f"(c) loop {i} has an arc turning left whose radius is not r_convex = {a!r}")
        if (np.abs(d[~left, 2] - b) > 1e-9 * max(a, b)).any():
            problems.append(f"(c) loop {i} has an arc turning right whose radius is not r_concave = {b!r}")
        bad = _bad_corners(loop, a, b, rounding)
        if bad:
            problems.append(f"(c) loop {i} has {bad} corner(s) where its radius is not 0")
    if general:
        # The engine's own exact tests, each disk at its side's radius: (e) the loops stay out of the open
        # R_a and the open complement of F_b (exact piece distances to S↓a and (S^c)↓b), every arc centred on
        # an exact corner from its side, no piece entering a disk or offset piece, no two loops touching.
        from .engine import Tightening

        problems += Tightening._check_exact(T)
        if not T.converged:
            problems.append("the exact finish did not converge everywhere")
    elif T._cache.get("_path") != "empty":
        problems += _check_pair_fast(T)
    return problems


def _exact_a(T, info, frame, slack: float, tiny: float, offsets=None) -> list[str]:
    """(a) for a result of the fast or the convex path, on S's exact offsets (see `_verify`); for the
    general engine's, on the offsets its context holds (``offsets``: side +1's and side −1's)."""
    from .offsets import exact_offsets

    if offsets is not None:
        xE, xG = offsets
        a_l, b_l = xE.r, xG.r
    else:
        S_local, _, (a_l, b_l), precision, _, _ = info
    G = T.geometry
    G_local = frame.to_local(G) if not G.is_empty else G
    shapely.prepare(G_local)
    problems = []
    for radius, side, inside in ((a_l, 1, True), (b_l, -1, False)):
        if radius == 0:
            if inside and T.shape.difference(G.buffer(slack)).area > tiny:
                problems.append("(a) the tightening misses part of S, its core for r_convex = 0")
            if not inside and G.difference(T.shape.buffer(slack)).area > tiny:
                problems.append("(a) the tightening extends outside S, its fillet for r_concave = 0")
            continue
        X = exact_offsets(S_local, radius, side, precision=precision) if offsets is None else offsets[side < 0]
        xy = X.test_points()
        if len(xy) == 0:
            continue
        hit = shapely.intersects_xy(G_local, xy[:, 0], xy[:, 1]) if not G_local.is_empty else np.zeros(len(xy), bool)
        if inside and not hit.all():
            problems.append(f"(a) the tightening misses {int((~hit).sum())} piece(s) of the centres of the core "
                            "R_a (exact offsets)")
        if not inside and hit.any():
            problems.append(f"(a) the tightening covers {int(hit.sum())} piece(s) of the centres of the "
                            "anticore of F_b (exact offsets)")
    return problems


def _bad_corners(loop: Loop, a: float, b: float, rounding: float) -> int:
    """Joins that are not G1 and turn the way whose radius is positive (left for a > 0, right for b > 0)."""
    t0, t1 = loop._tangents()
    u, v = t1, np.roll(t0, -1, axis=0)
    turn = np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1))
    turn = np.where(np.isfinite(turn), turn, 0.0)
    corner = np.abs(turn) > loop._join_bounds(CORNER_ANGLE, rounding)
    allowed = np.where(turn > 0, a == 0, b == 0)
    return int((corner & ~allowed).sum())


def _check_pair_fast(T) -> list[str]:
    """The fast path's (or the convex path's) exact tests, run again on S, give these very disks."""
    info = T._cache.get("_pair")
    if info is None:
        return ["(c) the result carries no record of the exact tests that certify it"]
    S_local, r_l, (a_l, b_l), precision, q, fast = info
    if T._cache.get("_path") == "convex":
        loop = _convex.convex_disk_loop(S_local, a_l)
        again = None if loop is None else [loop + (np.full(len(loop[0]), a_l),)]
    else:
        again = _fast.fast_disk_loops(S_local, r_l, q, T.init, precision, radii=(a_l, b_l))
    if again is None:
        return ["(c) the exact tests reject this result: its corners are not all isolated"]
    problems = []
    if len(again) != len(T.loops):
        problems.append(f"(c) the exact tests give {len(again)} loop(s), the result has {len(T.loops)}")
    frame = T._cache["_frame"]
    atol = 1e-9 * frame.scale
    for i, (x, loop) in enumerate(zip(again, T.loops)):
        c, s, phi, ln, sw, rho = x
        want = _loop_from_disks(c, s.astype(float), rho, phi, ln, sw, frame)
        same = (len(want._arc) == len(loop._arc) and np.array_equal(want._arc, loop._arc)
                and np.allclose(want._data, loop._data, rtol=0.0, atol=atol))
        if not same:
            problems.append(f"(c) loop {i} is not the one the exact tests certify")
    return problems
