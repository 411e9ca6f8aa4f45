"""Figure 3 — core, mortar and anticore.

The core R_r(S) (black), the mortar M_r(S) = F_r(S) − R_r(S) (grey) and the anticore ¬F_r(S) (white) of the
set S of Figure 1, which decompose the plane. On the right the same with the outline of S: away from the
details the mortar has no width and coincides with ∂S.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _shapes import FIG1_R, fig1_shape  # noqa: E402
from _style import BLACK, COLORS, GREY, fill, frame, new_figure, save, vt  # noqa: E402

NAME = "fig3_core_mortar_anticore"


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 3 into ``outdir``; returns the files written."""
    S, r = fig1_shape(), FIG1_R
    b = vt.grow(S, r).bounds
    window = (b[0] - 0.3, b[1] - 0.3, b[2] + 0.3, b[3] + 0.3)
    R, M = vt.core(S, r), vt.mortar(S, r)
    A = vt.anticore(S, r, window=window)
    fig, axes = new_figure(1, 2, panel=(5.2, 3.0))
    for ax in axes[0]:
        fill(ax, A, "white", edge="0.75", lw=0.4)
        fill(ax, M, GREY)
        fill(ax, R, BLACK)
        frame(ax, window, 0.0, box=True)
    axes[0, 0].set_title(f"core (black), mortar (grey), anticore (white), r = {r:g}")
    fill(axes[0, 1], S, "none", edge=COLORS["tight"], lw=0.9, linestyle="--")
    axes[0, 1].set_title("the same with ∂S (dashed)")
    fig.suptitle("Figure 3. Core, mortar and anticore")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
