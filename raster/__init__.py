"""raster: the paper's r-tightening on pixels (Williams & Rossignac, §3), faithful and fast.

Binary masks (True inside, r in pixels): exact-EDT morphology (`grow`, `shrink`, `core`, `fillet`,
`mortar`, `anticore`, `round_fillet`, `fillet_round`, `mason`), the constrained level-set curvature flow
(`tighten`), and the bridges to vectors and files (`rasterize`, `contours`, `Grid`, `load_mask`,
`save_mask`). It is the independent cross-check of the exact vector engine in `vectortighten`.
"""

from .flow import RasterTightening, default_levels, signed_distance, tighten
from .grid import Grid, contours, rasterize
from .io import load_mask, save_mask
from .morphology import anticore, core, fillet, fillet_round, grow, mason, mortar, round_fillet, shrink

__all__ = [
    "Grid",
    "RasterTightening",
    "anticore",
    "contours",
    "core",
    "default_levels",
    "fillet",
    "fillet_round",
    "grow",
    "load_mask",
    "mason",
    "mortar",
    "rasterize",
    "round_fillet",
    "save_mask",
    "shrink",
    "signed_distance",
    "tighten",
]
