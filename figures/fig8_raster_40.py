"""Figure 8 — the paper's first raster example: a 1102 × 832 px input tightened with r = 40 px.

(a) The input: a map-like landmass with a fjord, lakes of several sizes, a thin peninsula to a headland,
an island across a narrow channel and islets. (b) Its exact vector r-tightening from the core (the
paper's method), over the mortar. (c) The paper's pixel method (constrained level-set curvature flow,
`raster` package) on the rasterised input, and (d) where the two differ.

Both start from the core. The vector engine tightens each core loop in its homotopy class and merges
loops only where the tight loops touch; the pixel flow runs multiscale as in the paper, each front seeing
only itself and each finer level keeping its own topology, until its fronts rest (raster.tighten's default),
then the minimum-perimeter finish.
Panel (d) reports both topologies (the same here) and where the boundaries differ: mostly the long,
nearly straight tight segments, which the curvature flow approaches slowly.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _raster_fig import draw_raster_figure  # noqa: E402
from _shapes import coastline  # noqa: E402

NAME = "fig8_raster_40"
SIZE = (1102, 832)
R = 40.0


def draw(outdir, *, scale: float = 1.0, svg: bool = False) -> list[Path]:
    """Draw Figure 8 into ``outdir`` (``scale`` < 1 shrinks the image and r alike, for quick tests)."""
    return draw_raster_figure(outdir, name=NAME, shape=coastline, size=SIZE, r=R, scale=scale, svg=svg,
                              title=f"Figure 8. A {SIZE[0]} × {SIZE[1]} px input tightened with r = {R:g} px")


if __name__ == "__main__":
    for p in draw(Path(__file__).resolve().parent):
        print(p)
