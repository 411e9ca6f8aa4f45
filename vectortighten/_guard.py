"""What `tighten` does around the engine: answers known without it, documented errors, a final check.

* A radius so large that no disk of radius r fits in the shape's bounding box leaves an empty core and no
  enclosed anticore (the fillet lies in the convex hull), so every tightening is empty: it is returned at
  once, without buffering by an r that may overflow.
* A shape in which no disk of radius r fits has an empty tightening from the core (`core_vanishes`: S's
  exact shrink is empty, where no cheaper test finds a disk that fits; the engine then skips the general
  path).
* Any exception of the engine on checked input becomes a `TighteningFailedError` naming what failed
  (a `MemoryError` and a `KeyboardInterrupt` pass through).
* Pieces of a loop shorter than the rounding of the shape's numbers (`rounding_length`: `ZERO_SCALE` of
  its size, or 16 ulps of its largest coordinate far from the origin; tangents of length 1e-16 between two
  arcs, left by rounding) are dropped: their direction is noise, and they read as corners.
* Every result is checked before it is returned: its joins must be tangent (G1), and
  ``R_r(S) ⊆ T ⊆ F_r(S)`` must hold against the engine's own core
  and fillet (already built, so the check costs two overlays) within the engine's own slack; a fast-path
  result, which has none, against a coarse opening and closing of S (four buffers and two overlays). A result
  that fails it is not returned as converged: ``converged`` becomes False and a `ConvergenceWarning`
  says by how much it fails. An empty result of a shape in which no r-disk fits (`core_vanishes`) has
  nothing to check: its proof is that check.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import shapely
from shapely.geometry import Polygon

from .errors import ConvergenceWarning, TighteningError, TighteningFailedError
from .offsets import precision_of, shrink_is_empty
from .tolerances import CORNER_ANGLE, THICKEN_R, rounding_length

__all__ = ["containment_problems", "core_vanishes", "drop_specks", "guarded_tighten", "vanishes"]

#: An arc that turns by less than this (radians) and is shorter than a speck is a speck.
_SPECK_TURN = 1e-9

#: Chords a quarter circle of the coarse buffers that check a result of the fast path; where they flag
#: one, the check is made again with the finer ones before it counts. A corner of the coarse shrink where an
#: offset line meets a chord of a concave arc at a grazing angle α lies off the exact corner by the chord's
#: sagitta over sin α (a step's slid disk, tangent to an edge and through a vertex, is such a corner): the
#: area that misplaces falls with the square of the sagitta.
_COARSE_QUAD_SEGS = 4
_FINER_QUAD_SEGS = 32

#: A violation of the containment smaller than this share of r² is within rounding of the overlays.
_AREA_R2 = 1e-3


def vanishes(S, r: float) -> bool:
    """Whether no disk of radius r fits in the bounding box of S (then every tightening of S is empty).

    A disk inside S lies in its bounding box; an enclosed component of the anticore is a union of r-disks
    inside the convex hull of S. Both need ``2r`` at most the smaller side of the box, to the precision
    the exact offsets decide ties with (`offsets.precision_of`): a bar drawn 2r wide whose width rounds a
    few ulps below 2r keeps its centre line, as the engine's exact shrink does.
    """
    x0, y0, x1, y1 = S.bounds
    return 2.0 * r > min(x1 - x0, y1 - y0) + 4.0 * precision_of(S)


def core_vanishes(S, r: float, precision: float | None = None) -> bool:
    """Whether no disk of radius r fits in S: then its core is empty, and so is the tightening from it.

    A point at least r from S's complement proves a disk fits, and is looked for first, cheaply: among the
    points r + 1e-6·r inside the middles of 256 of S's edges, then at the centre of GEOS's maximum inscribed
    circle of each part (found to r/4). Where neither turns one up, S's exact shrink decides
    (`offsets.shrink_is_empty`: no piece and no corner). GEOS's circle alone cannot prove that none fits:
    its search stops after 2000 + 2000·ln(size / tolerance) cells, and on a strip 5·10⁴·r long it
    returned 0.7·r beside a disk of 1.4·r.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
        Valid, in any units.
    r : float
        The radius, > 0, in S's units.
    precision : float, optional
        The tie slack of the exact shrink (`offsets.exact_offsets`).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> core_vanishes(box(0, 0, 100, 1.8), 1.0), core_vanishes(box(0, 0, 100, 2.2), 1.0)
    (True, False)
    """
    if _wide_somewhere(S, r):
        return False
    radius = shapely.length(shapely.maximum_inscribed_circle(shapely.get_parts(S), 0.25 * r))
    if (radius >= r).any():
        return False                        # the circle's centre is r or more inside S
    return shrink_is_empty(S, r, precision)


def _wide_somewhere(S, r: float, samples: int = 256) -> bool:
    """Whether one of ``samples`` points, each r + 1e-6·r from the middle of an edge of S along its normal
    (on the side of S), lies farther than r from S's boundary."""
    ends = [shapely.get_coordinates(ring) for ring in shapely.get_rings(shapely.get_parts(S))]
    a = np.concatenate([xy[:-1] for xy in ends])
    b = np.concatenate([xy[1:] for xy in ends])
    if len(a) > samples:
        pick = np.linspace(0, len(a) - 1, samples).astype(np.int64)
        a, b = a[pick], b[pick]
    d = b - a
    length = np.hypot(d[:, 0], d[:, 1])
    ok = length > 0
    normal = np.column_stack([-d[ok, 1], d[ok, 0]]) / length[ok, None]
    middle = 0.5 * (a[ok] + b[ok])
    x = np.concatenate([middle + (1 + 1e-6) * r * normal, middle - (1 + 1e-6) * r * normal])
    x = x[shapely.contains_xy(S, x[:, 0], x[:, 1])]
    if not len(x):
        return False
    boundary = shapely.boundary(S)
    shapely.prepare(boundary)                # indexed distances
    return bool((~shapely.dwithin(boundary, shapely.points(x), r)).any())


def _empty_result(S, r: float, init, tol: float):
    from .engine import _Frame

    cls = _vanished_class()
    result = cls(loops=[], geometry=Polygon(), r=r, init=init.value, tolerance=tol, shape=S)
    result._cache["core"] = Polygon()
    result._cache["_frame"] = _Frame.of(S)
    result._cache["_path"] = "empty"
    return result


_VANISHED = None


def _vanished_class():
    """`Tightening` for a radius no disk of which fits in the shape's box (defined on first use)."""
    global _VANISHED
    if _VANISHED is None:
        from .engine import Tightening

        class VanishedTightening(Tightening):
            """An empty tightening: no disk of radius r fits in the shape's bounding box.

            Its core is empty; its fillet is computed as usual while r is within 1e8 of the shape's
            size, and is the convex hull of the shape beyond (the fillet tends to the hull as r grows;
            buffering by such an r would overflow).
            """

            def _morph(self, name):
                if name not in self._cache:
                    x0, y0, x1, y1 = self.shape.bounds
                    if self.r > 1e8 * max(x1 - x0, y1 - y0):
                        F = shapely.convex_hull(self.shape)
                        self._cache["fillet"] = F
                        self._cache["mortar"] = F
                return super()._morph(name)

            def verify(self) -> list[str]:
                """DESIGN §7 on an empty result: the core must be empty (it is, by the box)."""
                return [] if self.core.is_empty else ["(a) the tightening misses the core"]

        VanishedTightening.__module__ = __name__
        VanishedTightening.__qualname__ = "VanishedTightening"
        _VANISHED = VanishedTightening
        globals()["VanishedTightening"] = VanishedTightening
    return _VANISHED


def guarded_tighten(run, S, r: float, init, tol: float):
    """``run(S, r, init, tol)`` (the engine on checked arguments) with the guards of this module."""
    if vanishes(S, r):
        return _empty_result(S, r, init, tol)
    try:
        with warnings.catch_warnings():
            # numpy's overflow and invalid-value warnings inside the engine are not the user's concern;
            # what they lead to is judged by the final check.
            warnings.simplefilter("ignore", RuntimeWarning)
            result = run(S, r, init, tol)
    except (MemoryError, TighteningError):
        raise
    except Exception as exc:
        text = str(exc).splitlines()[0] if str(exc) else ""
        raise TighteningFailedError(
            f"the engine could not tighten this shape at r = {r:g} ({type(exc).__name__}"
            f"{': ' + text if text else ''}); please report it with the shape") from exc
    x0, y0, x1, y1 = S.bounds
    rounding = rounding_length(max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1)))
    result.loops = [drop_specks(loop, rounding) for loop in result.loops]
    problems = containment_problems(result) + _corner_problems(result, rounding)
    if problems and result.converged:
        result.converged = False
        warnings.warn(f"the result fails its final check ({'; '.join(problems)}): returned with "
                      "converged=False (Tightening.verify() lists where)", ConvergenceWarning, stacklevel=4)
    return result


def drop_specks(loop, eps: float):
    """``loop`` without its pieces of length ``eps`` or less (rounding specks), if any; else ``loop``.

    A segment that short has a direction of rounding noise; an arc that short is dropped only if it turns
    by less than 1e-9 rad.

    The gap a dropped piece leaves is its own length, far below the loop's closing tolerance (1e-9 of its
    size). A loop made only of specks is kept as it is.

    Examples
    --------
    >>> from vectortighten.curves import Arc, Loop, Segment
    >>> L = Loop([Arc((0, 0), 1, 0, 3.141592653589793), Segment((-1, 0), (-1, 1e-17)),
    ...           Arc((0, 1e-17), 1, 3.141592653589793, 3.141592653589793)], atol=1e-12)
    >>> len(drop_specks(L, 1e-12)._data), drop_specks(L, 1e-12).is_g1()
    (2, True)
    """
    data, arc = loop._data, loop._arc
    length = np.where(arc, np.abs(data[:, 2] * data[:, 4]), np.hypot(data[:, 2] - data[:, 0],
                                                                      data[:, 3] - data[:, 1]))
    # An arc is a speck only if it hardly turns: a short arc of a small radius can turn by a visible angle,
    # and without it its neighbours would meet at a corner.
    keep = (length > eps) | (arc & (np.abs(data[:, 4]) > _SPECK_TURN))
    if keep.all() or not keep.any():
        return loop
    return type(loop)._from_arrays(arc[keep], data[keep])


def _corner_problems(result, rounding: float) -> list[str]:
    """Joins that are not tangent (the radius of curvature would be 0 there), as `verify` judges them:
    by more than `CORNER_ANGLE` beyond what the rounding of the segments' end points explains."""
    bad = [loop for loop in result.loops if not loop.is_g1(CORNER_ANGLE, rounding)]
    worst = max((float(loop.corner_angles().max()) for loop in bad), default=0.0)
    return [f"a loop has a corner of {worst:.3g} rad"] if bad else []


def _coarse(loops, tol: float):
    """The region the loops bound (even-odd: they are disjoint), each sampled within ``tol``."""
    rings = [Polygon(loop.sample(tol)) for loop in loops]
    rings = [shapely.make_valid(p) if not p.is_valid else p for p in rings]
    while len(rings) > 1:         # pairwise, in a balanced tree
        pairs = shapely.symmetric_difference(rings[0:len(rings) - 1:2], rings[1::2])
        rings = list(pairs) + ([rings[-1]] if len(rings) % 2 else [])
    return rings[0]


def _pair(a, b) -> np.ndarray:
    """Two geometries as an array (for one vectorised shapely call)."""
    out = np.empty(2, dtype=object)
    out[0], out[1] = a, b
    return out


def _clipped(part, tiny: float, clip, d: float) -> float:
    """The area of ``part`` (a difference made without ``clip``), or, when that exceeds ``tiny``, the
    area of what the difference would have been with ``clip``: ``part ∩ clip.buffer(d)`` for d < 0 (the
    part of a shrunk core ``(R ∩ S)↓δ = R↓δ ∩ S↓δ`` that T misses), ``part − clip.buffer(d)`` for d > 0
    (the part of T outside a grown fillet ``(F ∪ S)↑δ = F↑δ ∪ S↑δ``).

    Shrinking distributes over intersection and growing over union, so this is the area of the same
    set as the clipped difference; it is at most ``part``'s area, so when that is negligible the clip,
    an overlay of S with edges along its own, is not needed to know the answer.
    """
    area = part.area
    if clip is None or area <= tiny or part.is_empty:
        return area
    grown = clip.buffer(d, quad_segs=2)
    return (shapely.intersection(part, grown) if d < 0 else shapely.difference(part, grown)).area


def containment_problems(result) -> list[str]:
    """``R ⊆ T ⊆ F`` on a result, against the core and fillet the engine built (the cheap final check).

    Returns a list of one-line problems (empty when the result passes). Works in the engine's local frame
    (unit size) where its context exists; otherwise (the fast path, whose loops its own exact tests
    certify) against the public core and fillet at a coarse tolerance.
    """
    cache = result._cache
    if "_members" in cache:
        # Far-apart groups of parts tightened alone (`engine._split_fast`): each checked as its path's.
        return [p for part in cache["_members"] for p in containment_problems(part)]
    if cache.get("_path") == "empty" and not result.loops:
        # No r-disk fits in S (`core_vanishes` proved it from S's exact shrink): the core and T are
        # empty, and T lies in the fillet. Buffering S to see that again costs as much as an opening and a
        # closing (4.8 s on a 100k-vertex spiral strip); `Tightening.verify` asks the exact shrink again.
        return []
    exact = cache.get("_exact")
    ctx = exact[0] if exact is not None else None
    if getattr(ctx, "guide_free", False):
        return _exact_point_problems(result, ctx)
    problems = _containment_problems(result, _COARSE_QUAD_SEGS)
    if problems and cache.get("_path") in ("fast", "convex"):
        problems = _containment_problems(result, _FINER_QUAD_SEGS)
    return problems


def _exact_point_problems(result, ctx) -> list[str]:
    """`containment_problems` on loops shown from the exact shrink (`engine._shrink_loops`), which built no
    guide core or fillet: every test point of S's exact shrink in T, none of its complement's.

    Such loops stay out of the open core and anticore, so each of those points is r or more from them and
    T's sampled geometry places it beyond doubt; each part of the open core and of the open anticore holds
    such points (as `Tightening.verify` reads them). GEOS's coarse buffers, the fast path's check, can
    go wrong where parts of S touch at a point (the negative buffer of two touching octagons, one too thin
    for any disk, kept a ghost of the thin one).
    """
    frame = result._cache["_frame"]
    T = frame.to_local(result.geometry) if not result.geometry.is_empty else result.geometry
    shapely.prepare(T)
    problems = []
    for X, inside, what in ((ctx.xE, True, "misses {} of the core's exact points"),
                            (ctx.xG, False, "covers {} of the anticore's exact points")):
        xy = X.test_points()
        if not len(xy):
            continue
        hit = shapely.intersects_xy(T, xy[:, 0], xy[:, 1]) if not T.is_empty else np.zeros(len(xy), bool)
        wrong = int((~hit).sum()) if inside else int(hit.sum())
        if wrong:
            problems.append("it " + what.format(wrong))
    return problems


def _containment_problems(result, q: int) -> list[str]:
    """`containment_problems` with q chords a quarter circle in the fast path's coarse buffers."""
    cache = result._cache
    frame = cache.get("_frame")
    exact = cache.get("_exact")
    ctx = exact[0] if exact is not None else None
    T = result.geometry
    if ctx is not None and frame is not None and hasattr(ctx, "R") and hasattr(ctx, "F"):
        R, F = ctx.R, ctx.F
        r = ctx.r
        slack = result.tolerance / frame.scale + 2.0 * getattr(ctx, "delta", THICKEN_R * r)
        clip = None
    else:
        # The fast path: coarse buffers (4 chords a quarter circle, each within 0.02·r of its arc; two of
        # them in a row) in the local frame. Its loops are certified by its own exact tests; this only
        # catches a gross failure, at a fraction of the cost of the engine's own buffers.
        S = result.shape
        if frame is not None:
            S = frame.to_local(S)
            r = result.r / frame.scale
            tol = result.tolerance / frame.scale
        else:
            r, tol = result.r, result.tolerance
        # The opening is not intersected with S, nor the closing united with it, here: the differences
        # below are, and only when they are not negligible anyway (see `_clipped`). Overlaying S with its
        # own opening or closing, whose edges lie on S's up to rounding, costs several times the buffers.
        # The shrink and the grow in one call, then the opening and the closing (the same buffers).
        K, G = shapely.buffer(_pair(S, S), [-r, r], quad_segs=q)
        R, F = shapely.buffer(_pair(K, G), [r, -r], quad_segs=q)
        clip = S
        slack = tol + 2.0 * r * (1.0 - math.cos(math.pi / (4 * q))) + 2.0 * THICKEN_R * r
    tiny = _AREA_R2 * r * r
    problems = []
    try:
        # T's geometry is sampled finely (hundreds of chords a turn); its loops sampled again within a
        # quarter of the slack are cheap to overlay; the core and fillet, coarse already, take the rest.
        if result.loops:
            T = _coarse(result.loops, 0.25 * slack * (frame.scale if frame is not None else 1.0))
        if frame is not None and not T.is_empty:
            T = frame.to_local(T)
        d = 0.75 * slack
        if T.is_empty:
            missed = 0.0 if R.is_empty else (R if clip is None else shapely.intersection(R, clip)).area
            outside = 0.0
        else:
            # The core shrunk and the fillet grown by d, then what T misses of the one and what of it lies
            # outside the other: two vectorised calls (an empty core misses nothing).
            inner, outer = shapely.buffer(_pair(R, F), [-d, d], quad_segs=2)
            lost, out = shapely.difference(_pair(inner, T), _pair(T, outer))
            missed = 0.0 if R.is_empty else _clipped(lost, tiny, clip, -d)
            outside = _clipped(out, tiny, clip, d)
        if missed > tiny:
            problems.append(f"it misses {missed / (r * r):.3g}·r² of the core")
        if outside > tiny:
            problems.append(f"{outside / (r * r):.3g}·r² of it lies outside the fillet")
    except shapely.errors.GEOSException as exc:
        problems.append(f"the check itself failed ({exc})")
    return problems


def __getattr__(name: str):
    # Unpickling a vanished result in a process that has not made one yet (a batch's parent).
    if name == "VanishedTightening":
        return _vanished_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
