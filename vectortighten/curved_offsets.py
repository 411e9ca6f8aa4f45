"""Exact offsets of shapes bounded by segments and circular arcs (a list of `Loop`s).

The construction of `offsets.exact_offsets`, for features that may be arcs. At clearance r from a line lie
its two parallels at distance r; from a point, the circle of radius r about it; from a circle (centre o,
radius ρ), the circles (o, ρ + r) and (o, |ρ − r|). So the raw offset elements of a boundary made of
segments and arcs are

* each segment's parallel at distance r on the side's side, running the same way;
* each arc's concentric arc of radius ρ ∓ r (ρ − r on its concave side: an arc of S of radius ρ < r
  offset towards its centre vanishes), with the same angles;
* an arc of radius r about each vertex where the boundary turns away from the side, spanning the two
  normals there (as about a polygon's reflex vertices).

Each element is cut where it crosses the boundary of a feature's r-neighbourhood: for a segment its two
parallels and the circles of radius r about its ends; for an arc the two concentric circles and the
circles of radius r about its ends. All of these crossings are line–circle or circle–circle, in closed
form. Between two cuts an element is uniformly inside or outside each neighbourhood, so the exact
clearance at the middle of each part decides it: kept when it is at least r (to the precision) and on the
side's side of S.

The polygon path of the engine does not come here (`offsets.exact_offsets` is unchanged); this module is
the input path for arcs kept exactly, used by `exact_morphology` when it is given loops.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from .offsets import _arc_param, _circle_seg_angles, _seg_circle_params, _seg_line_params

__all__ = ["curved_offsets"]

_TWO_PI = 2.0 * math.pi
_SAMPLES = 17           # points of the polyline standing in for an arc in the reach queries
_ROUNDING = 64.0        # ulps of the coordinates within which two points are one


def _features(loops):
    """Rows (as `Loop` holds them), kinds, ends and tangents of every piece of every loop; and the index
    of each piece's successor in its loop."""
    arc, data, p0, p1, t0, t1, nxt = [], [], [], [], [], [], []
    off = 0
    for lp in loops:
        a, d = lp._arc, lp._data
        s, e = lp._ends()
        u0, u1 = lp._tangents()
        keep = a | (np.hypot(*(e - s).T) > 0)
        a, d, s, e, u0, u1 = a[keep], d[keep], s[keep], e[keep], u0[keep], u1[keep]
        n = len(a)
        if n == 0:
            continue
        arc.append(a), data.append(d), p0.append(s), p1.append(e), t0.append(u0), t1.append(u1)
        nxt.append(off + (np.arange(n) + 1) % n)
        off += n
    if not arc:
        z = np.zeros((0, 2))
        return np.zeros(0, bool), np.zeros((0, 5)), z, z, z, z, np.zeros(0, np.int64)
    return (np.concatenate(arc), np.concatenate(data), np.concatenate(p0), np.concatenate(p1),
            np.concatenate(t0), np.concatenate(t1), np.concatenate(nxt))


def _cc_angles(o, R1, c, R2):
    """Angles about ``o`` of the crossings of circle (o, R1) with circle (c, R2); NaN where none."""
    w = c - o
    d = np.hypot(w[:, 0], w[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        a = (R1 * R1 - R2 * R2 + d * d) / (2.0 * d)
        cosv = a / R1
        ok = (d > 0) & (np.abs(cosv) <= 1.0)
        half = np.arccos(np.clip(cosv, -1.0, 1.0))
    base = np.arctan2(w[:, 1], w[:, 0])
    return np.where(ok, base - half, np.nan), np.where(ok, base + half, np.nan)


def _point_feature_distance(arc, data, p0, p1, j, xy):
    """Exact distance from ``xy[k]`` to feature ``j[k]`` (segment or arc)."""
    d = data[j]
    out = np.empty(len(j))
    a = arc[j]
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
        on = _arc_param(th, a0, sw) <= 1.0
        radial = np.abs(np.hypot(w[:, 0], w[:, 1]) - rho)
        ends = np.minimum(np.hypot(*(xy[a] - p0[j[a]]).T), np.hypot(*(xy[a] - p1[j[a]]).T))
        out[a] = np.where(on, radial, ends)
    return out


def _polylines(arc, data, lo=None, hi=None):
    """Shapely lines through each piece (arcs by `_SAMPLES` points), and the largest sag of those chords."""
    n = len(arc)
    lo = np.zeros(n) if lo is None else lo
    hi = np.ones(n) if hi is None else hi
    t = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, _SAMPLES)[None, :]
    th = data[:, 3, None] + data[:, 4, None] * t
    arc_xy = data[:, None, :2] + data[:, 2, None, None] * np.stack([np.cos(th), np.sin(th)], axis=-1)
    seg_xy = data[:, None, 0:2] + t[:, :, None] * (data[:, None, 2:4] - data[:, None, 0:2])
    xy = np.where(arc[:, None, None], arc_xy, seg_xy)
    step = np.abs(data[:, 4]) * (hi - lo) / (_SAMPLES - 1)
    sag = np.where(arc, data[:, 2] * (1.0 - np.cos(0.5 * step)), 0.0)
    return shapely.linestrings(xy), float(sag.max(initial=0.0))


def curved_offsets(loops, r: float, side: int = 1):
    """The exact boundary pieces of ``S↓r`` (``side=1``) or ``(S^c)↓r`` (``side=-1``) for S bounded by loops.

    Parameters
    ----------
    loops : list of Loop
        The boundary of S: outer boundaries counter-clockwise, holes clockwise, each made of `Segment`s
        and `Arc`s, pairwise disjoint and simple.
    r : float
        The radius, > 0, in the loops' units.
    side : {1, -1}
        +1 for the shrink of S, −1 for the shrink of its complement.

    Returns
    -------
    arc : (k,) bool
        Which pieces are arcs.
    data : (k, 5) float
        Each piece as `Loop` holds it: ``(cx, cy, radius, start_angle, sweep)`` for an arc,
        ``(x0, y0, x1, y1, 0)`` for a segment; running the way S's boundary runs (S on their left).
    precision : float
        The closed rule's slack (a point is kept where its clearance is at least r − precision).

    Examples
    --------
    A plate with a hole of radius 3, shrunk by 1: the hole's boundary becomes one arc of radius 4.

    >>> from vectortighten.curves import Loop, Segment
    >>> sq = Loop([Segment((-10, -10), (10, -10)), Segment((10, -10), (10, 10)),
    ...            Segment((10, 10), (-10, 10)), Segment((-10, 10), (-10, -10))])
    >>> arc, data, _ = curved_offsets([sq, Loop.circle((0, 0), 3.0, ccw=False)], 1.0)
    >>> sorted(data[arc, 2].tolist())
    [4.0]
    """
    o = _offset_parts(loops, r, side)
    if o is None:
        return np.zeros(0, bool), np.zeros((0, 5)), 0.0
    el_arc, el_dat, pe2, lo, hi = o.el_arc, o.el_dat, o.part_e, o.lo, o.hi
    arc_out = el_arc[pe2]
    d = el_dat[pe2]
    out = np.empty((len(pe2), 5))
    a0 = _points(el_arc, el_dat, pe2, lo)
    a1 = _points(el_arc, el_dat, pe2, hi)
    out[~arc_out] = np.column_stack([a0[~arc_out], a1[~arc_out], np.zeros(int((~arc_out).sum()))])
    out[arc_out] = np.column_stack([d[arc_out, 0:3], d[arc_out, 3] + d[arc_out, 4] * lo[arc_out],
                                    d[arc_out, 4] * (hi[arc_out] - lo[arc_out])])
    return arc_out, out, o.eps


class _Parts:
    """What `_offset_parts` finds: the raw elements, the kept parts of each, and the features."""

    def __init__(self, **kw):
        self.__dict__.update(kw)


def _offset_parts(loops, r: float, side: int):
    """The raw offset elements of the loops' pieces at distance r on ``side``, and the parts of each kept.

    Returns a `_Parts` with ``el_arc``, ``el_dat`` (the raw elements as `Loop` rows), ``el_piece`` (the
    feature each element offsets, −1 for an arc about a vertex), ``part_e``, ``lo``, ``hi`` (kept parts:
    element and parameter range, consecutive kept parts of one element merged), ``eps`` (the precision),
    ``collapsed`` (features whose offset is a point: arcs of radius within ``eps`` of r offset towards
    their centre), ``too_curved`` (arcs of radius below r − eps offset towards their centre: they vanish)
    and the features (``farc``, ``fdat``, ``fp0``, ``fp1``, ``tree``, ``fsag``); None without features.
    """
    r = float(r)
    farc, fdat, fp0, fp1, ft0, ft1, fnxt = _features(loops)
    if len(farc) == 0:
        return None
    pts = np.concatenate([fp0, fp1, fdat[farc, :2]])
    x0, y0 = pts.min(axis=0)
    x1, y1 = pts.max(axis=0)
    size = max(x1 - x0, y1 - y0, r)
    big = max(abs(x0), abs(y0), abs(x1), abs(y1), size)
    eps = max(1e-13 * size, _ROUNDING * float(np.spacing(big)))
    # Raw elements.
    el_arc, el_dat, el_piece = [], [], []
    nl0 = np.column_stack([-ft0[:, 1], ft0[:, 0]])         # left normal at each feature's start
    segs = ~farc
    collapsed = too_curved = np.zeros(0, np.int64)
    if segs.any():
        sh = side * r * nl0[segs]
        el_arc.append(np.zeros(int(segs.sum()), bool))
        el_dat.append(np.column_stack([fdat[segs, 0:2] + sh, fdat[segs, 2:4] + sh, np.zeros(int(segs.sum()))]))
        el_piece.append(np.flatnonzero(segs))
    if farc.any():
        d = fdat[farc]
        rho = d[:, 2] - side * np.sign(d[:, 4]) * r         # a CCW arc's left normal points to its centre
        ok = rho > eps
        el_arc.append(np.ones(int(ok.sum()), bool))
        el_dat.append(np.column_stack([d[ok, 0:2], rho[ok], d[ok, 3], d[ok, 4]]))
        ia = np.flatnonzero(farc)
        el_piece.append(ia[ok])
        collapsed, too_curved = ia[~ok & (rho >= -eps)], ia[rho < -eps]
    # Arcs about the vertices where the boundary turns away from the side.
    tin, tout = ft1, ft0[fnxt]
    turn = np.arctan2(tin[:, 0] * tout[:, 1] - tin[:, 1] * tout[:, 0], (tin * tout).sum(axis=1))
    opens = side * turn < -1e-12
    if opens.any():
        v = fp1[opens]
        n_in = side * np.column_stack([-tin[opens, 1], tin[opens, 0]])
        el_arc.append(np.ones(int(opens.sum()), bool))
        el_dat.append(np.column_stack([v, np.full(len(v), r), np.arctan2(n_in[:, 1], n_in[:, 0]), turn[opens]]))
        el_piece.append(np.full(len(v), -1))
    el_arc = np.concatenate(el_arc)
    el_dat = np.concatenate(el_dat).reshape(-1, 5)
    el_piece = np.concatenate(el_piece).astype(np.int64)
    n_el = len(el_arc)
    # Features' r-neighbourhood boundaries: 2 lines and 4 circles each (NaN where a kind has fewer).
    nf = len(farc)
    lines = np.full((nf, 2, 2, 2), np.nan)                  # (feature, which, start/end, xy)
    circ = np.full((nf, 4, 3), np.nan)                      # (feature, which, cx/cy/R)
    nl = np.column_stack([-ft0[:, 1], ft0[:, 0]])
    for k, sgn in enumerate((1.0, -1.0)):
        lines[segs, k, 0] = fdat[segs, 0:2] + sgn * r * nl[segs]
        lines[segs, k, 1] = fdat[segs, 2:4] + sgn * r * nl[segs]
    circ[:, 0, :2], circ[:, 0, 2] = fp0, r
    circ[:, 1, :2], circ[:, 1, 2] = fp1, r
    circ[farc, 2, :2], circ[farc, 2, 2] = fdat[farc, :2], fdat[farc, 2] + r
    circ[farc, 3, :2], circ[farc, 3, 2] = fdat[farc, :2], np.abs(fdat[farc, 2] - r)
    # Which features can cut which elements.
    fgeom, fsag = _polylines(farc, fdat)
    tree = shapely.STRtree(fgeom)
    egeom, esag = _polylines(el_arc, el_dat)
    pe, pf = tree.query(egeom, predicate="dwithin", distance=r + fsag + esag + 4.0 * eps)
    cuts = np.full((len(pe), 12), np.nan)
    is_seg = ~el_arc[pe]
    if is_seg.any():
        e, f = pe[is_seg], pf[is_seg]
        P0 = el_dat[e, 0:2]
        D = el_dat[e, 2:4] - P0
        cols = []
        for k in range(2):
            Q0 = lines[f, k, 0]
            cols.append(_seg_line_params(P0, D, Q0, lines[f, k, 1] - Q0))
        for k in range(4):
            cols += list(_seg_circle_params(P0, D, circ[f, k, :2], circ[f, k, 2]))
        cuts[is_seg, :10] = np.column_stack(cols)
    if (~is_seg).any():
        e, f = pe[~is_seg], pf[~is_seg]
        o, R1, a0, sw = el_dat[e, 0:2], el_dat[e, 2], el_dat[e, 3], el_dat[e, 4]
        angles = []
        for k in range(2):
            Q0 = lines[f, k, 0]
            with np.errstate(invalid="ignore"):
                angles += list(_circle_seg_angles(o, R1, Q0, lines[f, k, 1] - Q0))
        for k in range(4):
            angles += list(_cc_angles(o, R1, circ[f, k, :2], circ[f, k, 2]))
        cuts[~is_seg] = np.column_stack([_arc_param(th, a0, sw) for th in angles])
    # Split every element at its cuts; decide each part at its middle.
    length = np.where(el_arc, el_dat[:, 2] * np.abs(el_dat[:, 4]), np.hypot(*(el_dat[:, 2:4] - el_dat[:, :2]).T))
    tiny = eps / np.maximum(length, 1e-300)
    order = np.argsort(pe, kind="stable")
    pe_s, cuts_s = pe[order], cuts[order]
    bounds = np.searchsorted(pe_s, np.arange(n_el + 1))
    part_e, part_lo, part_hi = [], [], []
    for i in range(n_el):
        if length[i] <= 2.0 * eps:
            continue
        c = cuts_s[bounds[i]:bounds[i + 1]].ravel()
        c = c[np.isfinite(c) & (c > tiny[i]) & (c < 1.0 - tiny[i])]
        b = np.unique(np.r_[0.0, c, 1.0])
        if len(b) > 2:
            gap = np.diff(b) > tiny[i]
            b = np.r_[b[:-1][gap], 1.0]
        part_e.append(np.full(len(b) - 1, i)), part_lo.append(b[:-1]), part_hi.append(b[1:])
    common = dict(el_arc=el_arc, el_dat=el_dat, el_piece=el_piece, eps=eps, collapsed=collapsed,
                  too_curved=too_curved, farc=farc, fdat=fdat, fp0=fp0, fp1=fp1, tree=tree, fsag=fsag,
                  length=length, tiny=tiny)
    if not part_e:
        z = np.zeros(0)
        return _Parts(part_e=np.zeros(0, np.int64), lo=z, hi=z, **common)
    pe2, lo, hi = np.concatenate(part_e), np.concatenate(part_lo), np.concatenate(part_hi)
    mid = _points(el_arc, el_dat, pe2, 0.5 * (lo + hi))
    qi, qf = tree.query(shapely.points(mid), predicate="dwithin", distance=r + fsag)
    dist = _point_feature_distance(farc, fdat, fp0, fp1, qf, mid[qi])
    clear = np.ones(len(mid), dtype=bool)
    np.logical_and.at(clear, qi, dist >= r - eps)
    inside = _inside(loops, mid, r)
    keep = clear & (inside if side > 0 else ~inside)
    pe2, lo, hi = pe2[keep], lo[keep], hi[keep]
    # Merge consecutive kept parts of one element.
    if len(pe2):
        start = np.ones(len(pe2), dtype=bool)
        start[1:] = ~((pe2[1:] == pe2[:-1]) & (lo[1:] <= hi[:-1] + tiny[pe2[1:]]))
        idx = np.flatnonzero(start)
        hi = np.maximum.reduceat(hi, idx)
        pe2, lo = pe2[idx], lo[idx]
    return _Parts(part_e=pe2, lo=lo, hi=hi, **common)


def _points(arc, data, e, t):
    d = data[e]
    ang = d[:, 3] + d[:, 4] * t
    on_arc = d[:, :2] + d[:, 2:3] * np.column_stack([np.cos(ang), np.sin(ang)])
    on_seg = d[:, :2] + t[:, None] * (d[:, 2:4] - d[:, :2])
    return np.where(arc[e][:, None], on_arc, on_seg)


def _inside(loops, xy: np.ndarray, r: float) -> np.ndarray:
    """Whether each point is inside S, for points at clearance ≥ r − ε from ∂S (the only ones asked).

    Each loop is sampled with chords within r/100 of it, so such a point is on the same side of the
    chords as of the curve; inside S when an odd number of loops enclose it (the loops are disjoint).
    """
    count = np.zeros(len(xy), dtype=np.int64)
    if len(xy) == 0:
        return count.astype(bool)
    for lp in loops:
        count += shapely.contains_xy(Polygon(lp.sample(0.01 * r)), xy[:, 0], xy[:, 1])
    return count % 2 == 1


def _sampled(loops, tol: float):
    """S as a shapely polygon, the loops sampled within ``tol`` (for the inside test of kept parts, which
    lie at clearance ≥ r from ∂S: far from the chords)."""
    outers = [Polygon(lp.sample(tol)) for lp in loops if lp.area > 0]
    holes = [Polygon(lp.sample(tol)) for lp in loops if lp.area < 0]
    S = shapely.union_all(outers) if outers else Polygon()
    if holes:
        S = S.difference(shapely.union_all(holes))
    return S
