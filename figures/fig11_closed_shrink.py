"""Figure 11 — the closed shrink: parts exactly 2r wide.

The paper's shrink is closed (the points at distance at least r from the complement), so a bar exactly 2r
wide has a shrink, its centre line, and lies in the core: every tightening keeps it (left). A gap exactly
2r wide is, in the same way, anticore: an r-disk passes through it, and the tightening leaves it open
(right). Core black, mortar grey, the tightening (init="core") outlined.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from shapely.geometry import box  # noqa: E402
from shapely.ops import unary_union  # noqa: E402

from _style import BLACK, COLORS, GREY, fill, frame, new_figure, save, vt  # noqa: E402

NAME = "fig11_closed_shrink"
R = 1.0


def shapes():
    """The two shapes of the figure: a bar exactly 2r wide between two squares, and two squares 2r apart."""
    bar = unary_union([box(0, 0, 4, 4), box(4, 2 - R, 10, 2 + R), box(10, 0, 14, 4)])
    gap = unary_union([box(0, 0, 6, 4), box(6 + 2 * R, 0, 14, 4)])
    return bar, gap


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 11 into ``outdir``; returns the files written."""
    fig, axes = new_figure(1, 2, panel=(5.2, 2.4))
    for ax, S, title in zip(axes[0], shapes(), ("a bar exactly 2r wide is core: kept",
                                                "a gap exactly 2r wide is anticore: open")):
        T = vt.tighten(S, R)
        fill(ax, vt.mortar(S, R), GREY)
        fill(ax, vt.core(S, R), BLACK)
        fill(ax, S, "none", edge="0.45", lw=0.6, linestyle="--")
        fill(ax, T.geometry, "none", edge=COLORS["tight"], lw=1.4)
        x0, y0, x1, y1 = S.bounds
        frame(ax, (x0 - 0.6, y0 - 0.6, x1 + 0.6, y1 + 0.6), 0.0, box=True)
        ax.set_title(f"{title} (r = {R:g})")
    fig.suptitle("Figure 11. The closed shrink: parts and gaps exactly 2r wide")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
