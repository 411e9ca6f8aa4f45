"""Figure 6 — several r-tightenings of one set.

(a) The input S: three lobes joined by bars thinner than 2r into a ring around a hole.
(b) Its core (black), mortar (grey) and anticore (white): the core has three components and the anticore
two (outside, and the hole), so the r-tightening is not unique.
(c) An r-tightening with three components: the flow started from the core (``init="core"``, the paper's
implementation) wraps each core component separately.
(d) An r-tightening with a hole: started from S itself (``init="input"``, the self-dual variant) the outer
loop and the hole's loop stay apart and the bars survive as constrictions.
Each tightening is exact (segments and arcs of radius r, red) and labelled with its measures.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402
import shapely  # noqa: E402
from shapely.affinity import rotate  # noqa: E402
from shapely.geometry import LineString, Polygon  # noqa: E402

from _shapes import blob  # noqa: E402
from _style import (BLACK, COLORS, GREY, LIGHT, caption, draw_loops, fill, frame, new_figure, save,  # noqa: E402
                    stats_label, vt)

NAME = "fig6_several_tightenings"
R = 1.0


def shape():
    """Three lobes (a square, a pentagon, a blob) joined into a ring by bars 0.9 wide (r = 1)."""
    centres = [(5.4 * np.cos(a), 5.4 * np.sin(a)) for a in np.deg2rad([90.0, 210.0, 330.0])]
    (x0, y0), (x1, y1), (x2, y2) = centres
    square = rotate(Polygon([(x0 - 2, y0 - 2), (x0 + 2, y0 - 2), (x0 + 2, y0 + 2), (x0 - 2, y0 + 2)]), 12,
                    origin=(x0, y0))
    t = np.deg2rad(90 + 72 * np.arange(5))
    pentagon = Polygon(np.column_stack([x1 + 2.5 * np.cos(t), y1 + 2.5 * np.sin(t)]))
    lobe = blob(x2, y2, 2.3, [(3, 0.14, 0.4), (2, 0.06, 0.0)], n=120)
    bars = [LineString([centres[i], centres[(i + 1) % 3]]).buffer(0.45, cap_style="flat") for i in range(3)]
    return shapely.orient_polygons(shapely.union_all([square, pentagon, lobe, *bars]), exterior_cw=False)


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 6 into ``outdir``; returns the files written."""
    S, r = shape(), R
    g = vt.grow(S, r).bounds
    window = (g[0] - 0.3, g[1] - 0.3, g[2] + 0.3, g[3] + 0.3)
    core, mortar = vt.core(S, r), vt.mortar(S, r)
    anti = vt.anticore(S, r, window=window)
    tights = {init: vt.tighten(S, r, init=init) for init in ("core", "input")}
    fig, axes = new_figure(1, 4, panel=(3.3, 3.6))
    a, b, c, d = axes[0]
    fill(a, S, BLACK)
    a.set_title(f"(a) input S, r = {r:g}")
    caption(a, stats_label(S, r))
    fill(b, anti, "white")
    fill(b, mortar, GREY)
    fill(b, core, BLACK)
    b.set_title("(b) core (black), mortar (grey), anticore (white)", fontsize=8)
    caption(b, f"core: {vt.n_components(core)} components\nanticore: {vt.n_components(anti)} components")
    for ax, init, tag in ((c, "core", "(c) three components"), (d, "input", "(d) with a hole")):
        T = tights[init]
        fill(ax, mortar, LIGHT)
        fill(ax, T.geometry, "#3a3a3a")
        draw_loops(ax, T.loops, tolerance=T.tolerance, color=COLORS["tight"], linewidth=1.4)
        fill(ax, S, "none", edge=COLORS["input"], lw=0.6, linestyle=(0, (3, 2)))
        ax.set_title(f"{tag}: init={init!r}")
        caption(ax, stats_label(T))
    for ax in axes.flat:
        frame(ax, window, 0.0, box=True)
    fig.suptitle("Figure 6. Two r-tightenings of the same set (dashed: ∂S)")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
