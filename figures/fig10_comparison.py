"""Figure 10 — tightening compared with the morphological filters the paper discusses (§4.2).

One input S and, at the same r: R∘F (fillet then round: biased to add material), F∘R (round then
fillet: biased to remove it), Mason (each mortar pocket takes whichever of the two differs less from S),
and the exact r-tightenings started from the core (the paper's implementation) and from S itself (the
self-dual variant, which keeps tight constrictions). Each panel gives the perimeter, the minimum radius of
curvature (exact for the tightenings, which are segments and arcs of radius r; for the polygonal filters
the discrete estimate at their vertices, 0 where a vertex is a corner), and the components and holes.
Only the tightenings reach radius r everywhere; the filters leave corners where arcs of the core meet
arcs of the fillet.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import shapely  # noqa: E402
from shapely.geometry import Polygon, box  # noqa: E402

from _shapes import disk  # noqa: E402
from _style import (BLACK, COLORS, LIGHT, caption, draw_loops, fill, frame, new_figure, save,  # noqa: E402
                    stats_label, vt)

NAME = "fig10_comparison"
R = 1.0


def shape():
    """A plate with a slot, a small hole, a notch, a thin bar to a lobe, and two thin slivers across gaps.

    The left sliver is thicker than its gap (Mason takes R∘F there), the top one thinner than its gap
    (Mason takes F∘R), so Mason differs from both.
    """
    body = Polygon([(0, 0), (18, 0), (18, 9), (10.0, 9), (8.6, 7.0), (7.2, 9), (0, 9)])  # notch on top
    body = body.difference(box(3.0, 4.5, 4.2, 9.5))                       # slot 1.2 wide
    body = body.difference(disk(13.0, 3.5, 0.8, 64))                      # hole smaller than r
    bar = box(17.9, 3.8, 21.5, 5.1)                                        # bar 1.3 thick
    lobe = Polygon([(21.4, 2.1), (25.0, 1.7), (25.6, 5.5), (22.2, 7.3), (21.4, 6.7)])
    sliver = Polygon([(-1.0, 1.5), (-2.2, 1.2), (-2.6, 7.6), (-1.0, 7.2)])  # 1.2–1.6 thick, gap 1.0
    lath = box(11.5, 10.6, 15.5, 11.5)                                     # 0.9 thick, gap 1.6
    return shapely.orient_polygons(shapely.union_all([body, bar, lobe, sliver, lath]), exterior_cw=False)


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 10 into ``outdir``; returns the files written."""
    S, r = shape(), R
    mortar = vt.mortar(S, r)
    results = [
        ("input S", S),
        ("R∘F(S): fillet, then round", vt.round_fillet(S, r)),
        ("F∘R(S): round, then fillet", vt.fillet_round(S, r)),
        ("Mason(S)", vt.mason(S, r)),
        ("tightening, init='core'", vt.tighten(S, r, init="core")),
        ("tightening, init='input'", vt.tighten(S, r, init="input")),
    ]
    fig, axes = new_figure(2, 3, panel=(4.4, 2.9))
    win = vt.grow(S, r).bounds
    for ax, (title, res) in zip(axes.flat, results):
        fill(ax, mortar, LIGHT)
        if isinstance(res, vt.Tightening):
            fill(ax, res.geometry, "#3a3a3a")
            draw_loops(ax, res.loops, tolerance=res.tolerance, color=COLORS["tight"], linewidth=1.3)
        else:
            fill(ax, res, BLACK if res is S else "#3a3a3a")
        if res is not S:
            fill(ax, S, "none", edge=COLORS["input"], lw=0.6, linestyle=(0, (3, 2)))
        ax.set_title(title)
        caption(ax, stats_label(res, r))
        frame(ax, win, 0.0)
    fig.suptitle(f"Figure 10. Tightening and morphological filters, r = {r:g} "
                 "(mortar light grey, ∂S dashed, exact tight loops red)")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
