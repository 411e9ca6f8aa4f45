"""Figure 7 — cusps of a topology-preserving tightening, and the surgery that removes them.

(a) An input S: a thick ring cut by a slit on the left and thin (narrower than 2r) on the right; ∂S is one
loop. (b) Its core (dark grey) and mortar (light grey), and ∂S tightened while keeping its topology: the
shortest loop homotopic to ∂S in the mortar (black). Along the thin part the loop runs twice over the
hole's boundary — it overlaps itself — so the set it bounds has two cusps (red circles; the doubled stretch
in red). (c) Our r-tightening: the loop is cut where it touches itself and each part is tightened again
(the level set's split), giving two components with no cusp.
(d)–(f) The same with a ring that is only thin on the right: its two loops (outer and hole) overlap along
the hole's boundary; surgery merges them into one loop (the level set's merge).

How (b) and (e) are computed: the mortar, thickened by 1e-4·r so that its zero-width parts have room, is
triangulated; each input ring gives a sleeve of triangles, and the funnel algorithm on the sleeve unrolled
periodically gives the shortest closed polygon in its homotopy class (`vectortighten.geodesic`). Its
corners lie on the core's and anticore's boundaries sampled within 1e-5·r, so it is the exact tight loop to
drawing precision. Nothing splits or merges there; overlaps are detected afterwards (pieces of loops that
run within 1e-3·r of each other).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
import shapely  # noqa: E402
from shapely.geometry import Polygon, box  # noqa: E402

from _shapes import disk  # noqa: E402
from _style import (BLACK, COLORS, GREY, LIGHT, caption, draw_loops, draw_polyline, fill, frame,  # noqa: E402
                    new_figure, save, stats_label, vt)
from vectortighten.geodesic import closed_geodesic, sleeve, triangulate  # noqa: E402

NAME = "fig7_cusps"
R = 1.0
CUSP = "#d1495b"


def shapes():
    """(one loop overlapping itself, two loops overlapping): a slit thin ring and a thin ring (r = 1)."""
    ring = disk(0.0, 0.0, 5.0, 240).difference(disk(1.2, 0.0, 3.0, 240))     # 0.8 thick on the right
    slit = ring.difference(box(-6.0, -0.35, -1.5, 0.35))
    return shapely.orient_polygons(slit, exterior_cw=False), shapely.orient_polygons(ring, exterior_cw=False)


def homotopic_loops(S, r: float):
    """Each ring of S tightened in its homotopy class inside the mortar, without surgery: list of (n, 2)."""
    core, fil = vt.core(S, r), vt.fillet(S, r)
    eps = 1e-4 * r
    inner = core.buffer(-eps, join_style="mitre") if not core.is_empty else Polygon()
    domain = fil.buffer(eps, join_style="mitre").difference(inner)
    T = triangulate(domain)
    loops = []
    for ring in shapely.get_rings(shapely.get_parts(S)):
        geo = closed_geodesic(T, sleeve(T, shapely.get_coordinates(ring)))
        if geo is not None:
            loops.append(geo.xy)
    return core, fil, loops


def overlaps(loops, r: float):
    """Sample points of the loops that lie on another loop or on a distant part of the same loop.

    Returns ``(samples, masks)``: per loop, ``(m, 2)`` points sampled every r/40 and a boolean mask of
    those doubled by another piece.
    """
    h, tol = r / 40.0, 1e-3 * r
    segs, seg_loop, seg_s = [], [], []
    samples, sample_s = [], []
    for k, xy in enumerate(loops):
        closed = np.vstack([xy, xy[:1]])
        d = np.hypot(*np.diff(closed, axis=0).T)
        s0 = np.concatenate([[0.0], np.cumsum(d)])
        segs.append(np.stack([closed[:-1], closed[1:]], axis=1))
        seg_loop.append(np.full(len(d), k))
        seg_s.append(np.column_stack([s0[:-1], s0[1:]]))
        line = shapely.LineString(closed)
        s = np.arange(0.0, s0[-1], h)
        samples.append(shapely.get_coordinates(shapely.line_interpolate_point(line, s)))
        sample_s.append(s)
    segs = np.concatenate(segs)
    seg_loop = np.concatenate(seg_loop)
    seg_s = np.concatenate(seg_s)
    tree = shapely.STRtree(shapely.linestrings(segs))
    masks = []
    for k, (pts, s) in enumerate(zip(samples, sample_s)):
        total = s[-1] + h
        ip, iseg = tree.query(shapely.points(pts), predicate="dwithin", distance=tol)
        other = seg_loop[iseg] != k
        # The same loop counts only far away along it (a loop of curvature ≤ 1/r turns by π in between).
        gap = np.minimum(np.abs(seg_s[iseg, 0] - s[ip]), np.abs(seg_s[iseg, 1] - s[ip]))
        gap = np.minimum(gap, total - gap)
        far = gap > np.pi * r
        mask = np.zeros(len(pts), dtype=bool)
        mask[ip[other | far]] = True
        masks.append(mask)
    return samples, masks


def cusps(samples, masks, r: float) -> np.ndarray:
    """The ends of the doubled stretches (where the bounded set has a cusp), deduplicated."""
    ends = []
    for pts, m in zip(samples, masks):
        if not m.any() or m.all():
            continue
        change = np.flatnonzero(m != np.roll(m, 1))
        for i in change:
            ends.append(pts[i] if m[i] else pts[i - 1])
    out = []
    for p in ends:
        if all(np.hypot(*(p - q)) > 0.2 * r for q in out):
            out.append(p)
    return np.array(out).reshape(-1, 2)


def _ours(S, r: float):
    """Our tightening from the input loops (the level set's initial condition); the core if that fails."""
    try:
        return vt.tighten(S, r, init="input"), None
    except Exception as exc:  # noqa: BLE001 - shown in the figure instead of hiding the panel
        return vt.tighten(S, r, init="core"), f"init='input' failed ({type(exc).__name__}); shown: init='core'"


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 7 into ``outdir``; returns the files written."""
    r = R
    fig, axes = new_figure(2, 3, panel=(3.5, 3.5))
    rows = (("(a)", "(b)", "(c)", "one loop overlaps itself", "the loop splits"),
            ("(d)", "(e)", "(f)", "two loops overlap", "the loops merge"))
    for (ta, tb, tc, what, surgery), S, ax_row in zip(rows, shapes(), axes):
        a, b, c = ax_row
        core, fil, loops = homotopic_loops(S, r)
        mortar = fil.difference(core)
        samples, masks = overlaps(loops, r)
        cs = cusps(samples, masks, r)
        fill(a, S, BLACK)
        a.set_title(f"{ta} input S, r = {r:g}")
        caption(a, stats_label(S, r))
        fill(b, mortar, LIGHT)
        fill(b, core, GREY)
        for xy in loops:
            draw_polyline(b, xy, color=BLACK, lw=1.3)
        for pts, m in zip(samples, masks):
            if m.any():
                b.plot(np.where(m, pts[:, 0], np.nan), np.where(m, pts[:, 1], np.nan), color=CUSP, lw=2.6)
        b.plot(cs[:, 0], cs[:, 1], "o", ms=9, mfc="none", mec=CUSP, mew=1.6)
        b.set_title(f"{tb} topology kept: {what}")
        length = sum(float(shapely.LinearRing(xy).length) for xy in loops)
        caption(b, f"{len(loops)} loop{'s' if len(loops) != 1 else ''}, length {length:.1f}\n"
                   f"{len(cs)} cusps of the bounded set")
        T, note = _ours(S, r)
        fill(c, mortar, LIGHT)
        fill(c, T.geometry, "#3a3a3a")
        draw_loops(c, T.loops, tolerance=T.tolerance, color=COLORS["tight"], linewidth=1.6)
        c.set_title(f"{tc} our tightening: {surgery}, no cusp")
        caption(c, stats_label(T) + (f"\n{note}" if note else ""))
        win = fil.buffer(0.4 * r).bounds
        for ax in ax_row:
            frame(ax, win, 0.0)
    fig.suptitle("Figure 7. Cusps of a topology-preserving tightening, removed by splitting and merging loops")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
