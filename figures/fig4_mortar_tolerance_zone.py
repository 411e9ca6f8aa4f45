"""Figure 4 — the mortar inside the tolerance zone.

The mortar M_r(S) (black) and the tolerance zone Z_r(S) = (∂S)↑r (black and grey) of the set S of
Figure 1: M_r(S) = Z_r(S)↓r is the small part of Z_r(S) where a tightening may differ from S. On the
right, the share of each.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _shapes import FIG1_R, fig1_shape  # noqa: E402
from _style import BLACK, COLORS, GREY, fill, frame, new_figure, save, vt  # noqa: E402

NAME = "fig4_mortar_tolerance_zone"


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 4 into ``outdir``; returns the files written."""
    S, r = fig1_shape(), FIG1_R
    Z = vt.tolerance_zone(S, r)
    M = vt.mortar(S, r)
    fig, axes = new_figure(1, 2, panel=(5.2, 3.0))
    left, right = axes[0]
    fill(left, Z, GREY)
    fill(left, M, BLACK)
    left.set_title(f"M_r(S) (black) inside Z_r(S) (black and grey), r = {r:g}")
    fill(right, Z, GREY)
    fill(right, M, BLACK)
    fill(right, S, "none", edge=COLORS["tight"], lw=0.7, linestyle="--")
    right.set_title(f"with ∂S (dashed): area of M {M.area:.1f}, of Z {Z.area:.1f} "
                    f"({100 * M.area / Z.area:.0f} %)")
    b = Z.bounds
    for ax in (left, right):
        frame(ax, b, 0.3)
    fig.suptitle("Figure 4. Mortar and tolerance zone")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
