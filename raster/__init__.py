"""raster: the paper's r-tightening on pixels (Williams & Rossignac, §3), faithful and fast.

Binary masks (True inside, r in pixels): exact-EDT morphology (`grow`, `shrink`, `core`, `fillet`,
`mortar`, `anticore`, `round_fillet`, `fillet_round`, `mason`), the constrained level-set curvature flow
(`tighten`), and the bridges to vectors and files (`rasterize`, `contours`, `Grid`, `load_mask`,
`save_mask`). It is the independent cross-check of the exact vector engine in `vectortighten`.

Masks as image people have them (`raster.masks`, `raster.labels`, `raster.io`): `tighten_mask` takes a
0/1, 0/255, bool or 16-bit image (or a photo with a threshold) and returns an array of its shape, dtype
and values; `tighten_labels` tightens every label of a label image into one label image;
`read_image` and `write_image` keep a file's values, dtype and layout (PNG, TIFF, BMP).
"""

from .flow import (
    MAX_SUPERSAMPLED_PIXELS,
    NotConvergedWarning,
    RasterTightening,
    SupersampleWarning,
    default_levels,
    signed_distance,
    tighten,
)
from .grid import Grid, contours, rasterize
from .io import MAX_PIXELS, MaskImage, load_mask, read_image, save_mask, write_image
from .labels import LabelTightening, tighten_labels
from .masks import (
    EmptyMaskWarning,
    LostLabelWarning,
    ManyValuesWarning,
    MaskValues,
    MaskWarning,
    binarize,
    tighten_mask,
)
from .morphology import anticore, core, fillet, fillet_round, grow, mason, mortar, round_fillet, shrink

__all__ = [
    "MAX_PIXELS",
    "MAX_SUPERSAMPLED_PIXELS",
    "EmptyMaskWarning",
    "Grid",
    "LabelTightening",
    "LostLabelWarning",
    "ManyValuesWarning",
    "MaskImage",
    "MaskValues",
    "MaskWarning",
    "NotConvergedWarning",
    "RasterTightening",
    "SupersampleWarning",
    "anticore",
    "binarize",
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
    "read_image",
    "round_fillet",
    "save_mask",
    "shrink",
    "signed_distance",
    "tighten",
    "tighten_labels",
    "tighten_mask",
    "write_image",
]
