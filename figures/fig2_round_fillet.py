"""Figure 2 — rounding and filleting.

(left) R_r(S) = S↓r↑r, the union of all r-disks inside S, in black; the material rounding removes from S
(convex corners, the thin bar, the island) in grey.
(right) S in black; the material F_r(S) = S↑r↓r adds (concave corners, the crack, the small hole, the gap)
in grey.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _shapes import FIG1_R, fig1_shape  # noqa: E402
from _style import BLACK, GREY, fill, frame, new_figure, save, vt  # noqa: E402

NAME = "fig2_round_fillet"


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 2 into ``outdir``; returns the files written."""
    S, r = fig1_shape(), FIG1_R
    R = vt.core(S, r)
    F = vt.fillet(S, r)
    fig, axes = new_figure(1, 2, panel=(5.2, 3.0))
    left, right = axes[0]
    fill(left, S, GREY)
    fill(left, R, BLACK)
    left.set_title(f"R_r(S) (black) and what rounding removes (grey), r = {r:g}")
    fill(right, F, GREY)
    fill(right, S, BLACK)
    right.set_title("S (black) and what filleting F_r(S) adds (grey)")
    b = vt.grow(S, r).bounds
    for ax in (left, right):
        frame(ax, b, 0.3)
    fig.suptitle("Figure 2. Rounding and filleting")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
