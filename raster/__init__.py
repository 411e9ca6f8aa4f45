"""raster: the paper's pixel method for r-tightening (constrained level-set curvature flow).

Masks are 2-D boolean arrays (True = inside) and every radius is in pixels; see `raster.morphology` for the
pixel-centre semantics and `raster.tighten` for the flow.
"""

from .io import Grid, contours, load_mask, rasterize, save_mask
from .morphology import anticore, core, fillet, grow, mortar, shrink
from .tighten import Init, RasterTightening, tighten

__all__ = [
    "Grid",
    "Init",
    "RasterTightening",
    "anticore",
    "contours",
    "core",
    "fillet",
    "grow",
    "load_mask",
    "mortar",
    "rasterize",
    "save_mask",
    "shrink",
    "tighten",
]
