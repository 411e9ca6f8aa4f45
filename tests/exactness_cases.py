"""The corpus of issues 24, 25 and 26: shapes, radii and the exact decision each must get.

A `Case` holds a shape S, a radius r, and what the exact answer decides there (points that T must
contain, points T must not contain, or that T is empty), derived by hand from the construction: a gap
``2r(1 + eps)`` wide with eps > 0 lets an r-disk pass, so its middle is anticore and stays out of T; a
neck ``2r(1 − eps)`` wide is not core, so ``init="core"`` cuts it; a part at least 2r wide has a shrink
(its centre line when exactly 2r) and stays in T; a lone bar narrower than 2r has an empty core and
vanishes. Used by ``tests/test_exactness.py`` and ``benchmarks/exactness.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cache

from tests import shapes_dense as sd

__all__ = ["Case", "cases"]


@dataclass(frozen=True)
class Case:
    """One shape at one radius, with its exact decisions.

    ``inside``/``outside``: points that T must / must not contain; ``inits``: the inits the decision
    holds for (the exactness checks hold for every init); ``empty``: T must be empty.
    """

    id: str
    make: object = field(repr=False, compare=False)
    r: float
    inside: tuple = ()
    outside: tuple = ()
    empty: bool = False
    inits: tuple = ("core", "input")
    kind: str = "tie"

    @property
    def shape(self):
        return _shape(self.id, self.make)


_SHAPES: dict = {}


def _shape(key, make):
    if key not in _SHAPES:
        _SHAPES[key] = make()
    return _SHAPES[key]


def _rot(p, angle, offset):
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    return (c * p[0] - s * p[1] + offset[0], s * p[0] + c * p[1] + offset[1])


def _resolvable(eps: float, r: float, off) -> bool:
    """Whether a width 2r(1 + eps) differs from 2r by more than ten times the oracle's tie precision
    (``TIE_REL·M``, M the coordinates' magnitude): finer differences are ties to rounding."""
    from tests.oracle import TIE_REL

    M = max(abs(off[0]), abs(off[1])) + 20 * r
    return eps == 0 or 2 * abs(eps) * r > 10 * TIE_REL * M


def _tie_cases() -> list[Case]:
    out = []
    placements = [(0.0, (0.0, 0.0)), (30.0, (1234.5, -678.25)), (61.0, (-3.0e4, 2.0e4))]
    for angle, off in placements:
        tag = f"a{angle:g}@{off[0]:g},{off[1]:g}"
        for eps in (0.0, 1e-9, -1e-9, 1e-3, -1e-3):
            r = 3.0
            if not _resolvable(eps, r, off):
                continue
            mk = (lambda r=r, eps=eps, angle=angle, off=off: sd.bar(r, eps, angle, off))
            centre = _rot((0.0, 0.0), angle, off)
            if eps >= 0:
                out.append(Case(f"bar 2r(1{eps:+g}) {tag}", mk, r, inside=(centre,), kind="bar"))
            else:
                out.append(Case(f"bar 2r(1{eps:+g}) {tag}", mk, r, empty=True, kind="bar"))
        for eps in (1e-10, 1e-6, 1e-2, 0.0, -1e-10, -1e-6, -1e-2):
            r = 1.0
            if not _resolvable(eps, r, off):
                continue
            mk = (lambda r=r, eps=eps, angle=angle, off=off: sd.gap_pair(r, eps, angle, off))
            centre = _rot((0.0, 0.0), angle, off)
            if eps >= 0:            # an r-disk passes (exactly, for eps = 0: the closed shrink of ¬S)
                out.append(Case(f"gap 2r(1{eps:+g}) {tag}", mk, r, outside=(centre,), kind="gap"))
            else:
                out.append(Case(f"gap 2r(1{eps:+g}) {tag}", mk, r, kind="gap"))
            mk = (lambda r=r, eps=eps, angle=angle, off=off: sd.neck(r, eps, angle, off))
            if eps >= 0:
                out.append(Case(f"neck 2r(1{eps:+g}) {tag}", mk, r, inside=(centre,), kind="neck"))
            else:
                out.append(Case(f"neck 2r(1{eps:+g}) {tag}", mk, r, outside=(centre,), inits=("core",),
                                kind="neck"))
        for eps in (1e-10, 1e-3, -1e-10, -1e-3):
            r = 1.0
            if not _resolvable(eps, r, off):
                continue
            mk = (lambda r=r, eps=eps, angle=angle, off=off: sd.slot(r, eps, angle, off))
            deep = _rot((0.0, 2.0), angle, off)        # in the slot, 2r below the mouth
            if eps > 0:
                out.append(Case(f"slot 2r(1{eps:+g}) {tag}", mk, r, outside=(deep,), kind="slot"))
            else:
                out.append(Case(f"slot 2r(1{eps:+g}) {tag}", mk, r, inside=(deep,), kind="slot"))
        for against in ("corner", "wall", "bar"):
            for eps in (1e-10, 1e-6, 1e-2, 0.0, -1e-10, -1e-6, -1e-2):
                r = 1.0
                if not _resolvable(eps, r, off):
                    continue
                mk = (lambda r=r, eps=eps, angle=angle, off=off, against=against:
                      sd.corner_gap(r, eps, against, angle, off))
                centre = _rot((0.0, 0.0), angle, off)       # anticore for every eps (see sd.corner_gap)
                out.append(Case(f"{against} gap 2r(1{eps:+g}) {tag}", mk, r, outside=(centre,),
                                kind="corner gap"))
    # Placements where a random scan (random angle, offsets up to 1e5) found the general engine wrong:
    # a neck 2r(1 + 1e-6) whose square's core corner and the fillet beside it are 2r(1 + 1e-13) apart,
    # which rounding made overlap, so the finish dropped a disk (converged=False, 0.67·r into the
    # anticore). Ties between disks are decided to the centres' precision now (`tangent_directions`).
    for angle, off in [(37.0, (-3.6e4, 2.1e4)), (21.475, (6277.288012815955, 68817.87394888674))]:
        tag = f"a{angle:g}@{off[0]:g},{off[1]:g}"
        centre = _rot((0.0, 0.0), angle, off)
        for eps in (1e-6, -1e-6):
            mk = (lambda r=1.0, eps=eps, angle=angle, off=off: sd.neck(r, eps, angle, off))
            if eps >= 0:
                out.append(Case(f"neck 2r(1{eps:+g}) {tag}", mk, 1.0, inside=(centre,), kind="neck"))
            else:
                out.append(Case(f"neck 2r(1{eps:+g}) {tag}", mk, 1.0, outside=(centre,), inits=("core",),
                                kind="neck"))
    return out


def _embedded_cases() -> list[Case]:
    out = []
    r = 100.0
    for eps in (1e-8, 1e-4, -1e-8, -1e-4):
        for what in ("gap", "neck", "corner gap", "wall gap"):
            if what.endswith(" gap") and what != "gap" and abs(eps) != 1e-8:
                continue
            def mk(eps=eps, what=what):
                outline = sd.admin_outline(4000, seed=3, size=2e5, origin=(9.8e5, 2.1e5))
                return sd.embed_in_outline(_embedded_part(r, eps, what), outline, r)
            p = _embedded_centre(eps, what)          # the part's centre, in the outline's window
            if what == "gap":
                kw = dict(outside=(p,)) if eps > 0 else {}
            elif what == "neck":
                kw = dict(inside=(p,)) if eps > 0 else dict(outside=(p,), inits=("core",))
            else:                                    # anticore for every eps (see sd.corner_gap)
                kw = dict(outside=(p,))
            out.append(Case(f"embedded {what} 2r(1{eps:+g})", mk, r, kind=f"embedded {what}", **kw))
    return out


def _embedded_part(r, eps, what):
    """The part of an embedded case, its passage centred at the origin."""
    if what in ("gap", "neck"):
        return (sd.gap_pair if what == "gap" else sd.neck)(r, eps, 23.0, (0.0, 0.0))
    return sd.corner_gap(r, eps, what.split()[0], 23.0, (0.0, 0.0))


@cache
def _embedded_centre(eps, what):
    """Where `embed_in_outline` puts the part's passage (it centres the part's bounding box)."""
    outline = sd.admin_outline(4000, seed=3, size=2e5, origin=(9.8e5, 2.1e5))
    p = outline.representative_point()
    part = _embedded_part(100.0, eps, what)
    x0, y0, x1, y1 = part.bounds
    return (p.x - 0.5 * (x0 + x1), p.y - 0.5 * (y0 + y1))


def _dense_cases(scale: str) -> list[Case]:
    out = []
    n = 4000 if scale == "ci" else 75_000
    for seed in ((0,) if scale == "ci" else (0, 1)):
        mk = (lambda seed=seed: sd.admin_outline(n, seed=seed))
        for frac in ((0.003, 0.03) if scale == "ci" else (0.001, 0.003, 0.01, 0.03, 0.1)):
            out.append(Case(f"admin {n} seed {seed} r={frac:g}·size", mk, frac * 2e5, kind="admin"))
    size = 160 if scale == "ci" else 600
    for seed in ((0, 1) if scale == "ci" else (0,)):
        mk = (lambda seed=seed: sd.traced_contour(size, seed=seed))
        for r in ((2.0, 6.5) if scale == "ci" else (1.0, 2.0, 4.0, 8.6, 16.0)):
            out.append(Case(f"contour {size}px seed {seed} r={r:g}", mk, r, kind="contour"))
    size = 60 if scale == "ci" else 200
    for seed in ((0, 1, 2) if scale == "ci" else (0, 1)):
        mk = (lambda seed=seed: sd.pixel_blob(size, seed=seed))
        for r in ((3.0, 8.0) if scale == "ci" else (1.0, 2.0, 3.0, 5.0, 8.0)):
            out.append(Case(f"pixel blob {size}px seed {seed} r={r:g}", mk, r, kind="pixel"))
    for rp in (3, 8):
        mk = (lambda rp=rp: sd.staircase_stroke(rp))
        out.append(Case(f"staircase stroke 2·{rp}px", mk, float(rp), inside=(_stroke_mid(rp),),
                        kind="staircase"))
        mk = (lambda rp=rp: sd.staircase_gap(rp))
        out.append(Case(f"staircase gap 2·{rp}px", mk, float(rp), outside=(_gap_mid(rp),), kind="staircase"))
    return out


def _stroke_mid(rp, n_steps=6, step=3):
    h, length = 2 * rp, 8 * rp
    H = 2 * (n_steps * step + 4 * rp) + h + 4
    left_end = 2 + n_steps * step + 4 * rp
    return (left_end + 0.5 * length, H // 2 - rp + 0.5 * h)


def _gap_mid(rp, n_steps=6, step=2):
    blob = 6 * rp + n_steps * step
    H = 2 * (n_steps * step) + 8 * rp + 4
    return (2 + blob + rp, H // 2)


def cases(scale: str = "ci") -> list[Case]:
    """All cases: ``"ci"`` keeps the dense ones small; ``"bench"`` uses 75k-vertex outlines and five
    radii per dense shape."""
    return _tie_cases() + _embedded_cases() + _dense_cases(scale)


def evaluate(case: Case, init: str):
    """Tighten ``case`` with defaults and ``init``; return (result, judgement, verify problems, seconds)."""
    import time

    import vectortighten as vt
    from tests import oracle

    import warnings

    t0 = time.perf_counter()
    try:
        # A ConvergenceWarning comes with a result (converged=False) that is judged like any other;
        # verify() then lists why.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", vt.ConvergenceWarning)
            T = vt.tighten(case.shape, case.r, init=init)
    except Exception as exc:        # the engine's own failure is a result to report, not a crash
        return None, exc, None, time.perf_counter() - t0
    secs = time.perf_counter() - t0
    J = oracle.judge(case.shape, case.r, T.loops, T.geometry)
    return T, J, T.verify(), secs


def decision_errors(case: Case, init: str, T) -> list[str]:
    """What the result gets wrong of the case's exact decisions."""
    import shapely

    errs = []
    if init not in case.inits:
        return errs
    G = T.geometry
    if case.empty and not G.is_empty:
        errs.append(f"T should be empty (area {G.area:.3g})")
    for p in case.inside:
        if G.is_empty or not shapely.intersects_xy(G, *p):
            errs.append(f"T should contain {p}")
    for p in case.outside:
        if not G.is_empty and shapely.intersects_xy(G, *p):
            errs.append(f"T should not contain {p}")
    return errs

