"""Figure 1 — growing and shrinking.

(left) The input set S in black; the material that growing by r, S↑r, adds to it in grey.
(right) S shrunk by r, S↓r, in black; the material shrinking removes from S in grey.
Growing adds a band of width r all round: it bridges the gap to the right block and fills the crack and
the small hole. Shrinking removes a band of width r: it cuts the thin bar, removes the island and shortens
the spike, and widens the holes and the crack.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _shapes import FIG1_R, fig1_shape  # noqa: E402
from _style import BLACK, GREY, fill, frame, new_figure, save, vt  # noqa: E402

NAME = "fig1_grow_shrink"


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 1 into ``outdir``; returns the files written."""
    S, r = fig1_shape(), FIG1_R
    grown = vt.grow(S, r)
    shrunk = vt.shrink(S, r)
    fig, axes = new_figure(1, 2, panel=(5.2, 3.0))
    left, right = axes[0]
    fill(left, grown, GREY)
    fill(left, S, BLACK)
    left.set_title(f"S (black) and what S↑r adds (grey), r = {r:g}")
    fill(right, S, GREY)
    fill(right, shrunk, BLACK)
    right.set_title("S↓r (black) and what it removes from S (grey)")
    b = grown.bounds
    for ax in (left, right):
        frame(ax, b, 0.3)
    fig.suptitle("Figure 1. Growing and shrinking")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
