"""Figure 5 — tight curves in a set X.

X is grey; the curve C that is tight with respect to X (the shortest closed curve around the hole that can
be deformed to it inside X) is black. Both are computed with `vectortighten.relative_convex_hull`.
(left) X is the plane minus a hole: C is the convex hull of the hole.
(right) X is a crescent-shaped annulus: C follows the convex hull of the hole where it lies on the hole, and
is pushed inwards by the concave piece of X's outer loop; its pieces on ∂X are joined by tangent segments.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from shapely.geometry import box  # noqa: E402

from _shapes import blob, disk  # noqa: E402
from _style import BLACK, GREY, fill, frame, new_figure, save, vt  # noqa: E402

NAME = "fig5_tight_curves"


def shapes():
    """(window, hole) of the left panel and (outer, hole) of the right panel."""
    window = box(-5.0, -4.0, 5.0, 4.0)
    star = blob(0.0, 0.0, 2.2, [(3, 0.38, 0.0), (5, 0.10, 0.7)], n=240)
    outer = disk(0.0, 0.0, 5.4, 240).difference(disk(5.6, 0.0, 3.9, 240))
    moon = disk(0.0, 0.0, 2.6, 200).difference(disk(2.2, 0.0, 1.7, 200))
    return (window, star), (outer, moon)


def draw(outdir, *, svg: bool = False) -> list[Path]:
    """Draw Figure 5 into ``outdir``; returns the files written."""
    (window, star), (outer, moon) = shapes()
    fig, axes = new_figure(1, 2, panel=(4.2, 3.6))
    for ax, (X_out, hole), title in (
        (axes[0, 0], (window, star), "X = the plane minus a hole:\nC is the hole's convex hull"),
        (axes[0, 1], (outer, moon), "X = a crescent-shaped annulus:\nC is pushed in by X's concave outer piece"),
    ):
        C = vt.relative_convex_hull(hole, X_out)
        fill(ax, X_out.difference(hole), GREY)
        fill(ax, hole, "white", edge="0.45", lw=0.6)
        fill(ax, C, "none", edge=BLACK, lw=2.2)
        ax.set_title(title)
        frame(ax, X_out.bounds if ax is axes[0, 1] else window.bounds, 0.15)
        ax.text(0.02, 0.02, f"length of C {C.length:.2f}, of ∂hole {hole.length:.2f}",
                transform=ax.transAxes, fontsize=8, color="0.15")
    fig.suptitle("Figure 5. Curves tight with respect to X (grey)")
    return save(fig, outdir, NAME, svg=svg)


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
