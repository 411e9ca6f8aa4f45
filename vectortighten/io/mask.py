"""Mask and label images for the command line: read as stored, tightened, written back or traced to vectors.

An image input (PNG, TIFF, BMP, GIF, JPEG) is read by `raster.read_image` exactly as stored and then:

* to an image output (PNG, TIFF, BMP): tightened by the pixel method, a binary mask with
  `raster.tighten_mask` or a label image with `raster.tighten_labels` (``labels=True``), and written
  back in the input's size, dtype and values (0/1 in, 0/1 out; 16-bit in, 16-bit out; labels in, the
  same labels out);
* to a vector output (SVG, WKT, DXF, the geodata formats, whatever `vectortighten.io.write_result`
  writes): traced (`trace_tighten`). A label image (``labels=True``) goes to a geodata format only
  (GeoJSON, GeoPackage, …), one feature a label (`labels_features`). ``trace="exact"`` (the default)
  tightens the union of the mask's pixel squares
  with the exact engine, so the output has true arcs of radius r; ``trace="contours"`` runs the pixel
  method and writes its sub-pixel contour (straight segments between pixel edges). Coordinates are pixels:
  x is the column, y = −row (the image the right way up; SVG flips y back, so an SVG output overlays the
  image with pixel (row, col) at x ∈ [col, col + 1], y ∈ [row, row + 1]).

A stack (a multi-page TIFF, an animated GIF) is refused unless ``stack=True``, which tightens each slice
on its own (2-D, not 3-D) and writes a stack of the same shape (TIFF only).
"""

from __future__ import annotations

import importlib
import math
import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from vectortighten.errors import InvalidGeometryError

from ._common import MissingDependencyError, atomic_path

__all__ = [
    "MASK_READ_EXTENSIONS",
    "MASK_WRITE_EXTENSIONS",
    "TRACES",
    "MASK_READ_OPTIONS",
    "TracedTightening",
    "labels_features",
    "read_mask",
    "tighten_image_file",
    "trace_pixels",
    "trace_tighten",
    "write_mask",
]

#: Image extensions read as masks (the raster package's list).
MASK_READ_EXTENSIONS = (".png", ".tif", ".tiff", ".bmp", ".gif", ".jpg", ".jpeg")
#: Image extensions a tightened mask is written to.
MASK_WRITE_EXTENSIONS = (".png", ".tif", ".tiff", ".bmp")
#: How a mask becomes vectors: the exact tightening of its pixel squares, or the pixel method's contours.
TRACES = ("exact", "contours")
#: The options of reading an image (its formats' `vectortighten.io.Format.read_options`): ``threshold``
#: and ``invert`` (how a pixel is inside, `read_mask`), ``labels`` (a label image), ``stack`` (a stack of
#: slices), as `tighten_image_file` takes them.
MASK_READ_OPTIONS = ("threshold", "invert", "labels", "stack")


def _raster(*names: str):
    """The ``raster`` package, checked to offer ``names``."""
    try:
        raster = importlib.import_module("raster")
    except ImportError:
        raise MissingDependencyError("image masks need the 'raster' package (part of vectortighten)") \
            from None
    missing = [n for n in names if not hasattr(raster, n)]
    if missing:
        raise MissingDependencyError(f"this version of the raster package has no {', '.join(missing)}")
    return raster


def read_mask(path, *, threshold: float | None = None, invert: bool = False) -> np.ndarray:
    """Read an image as a boolean mask with ``raster.load_mask``: every non-zero pixel, or a threshold.

    Raises
    ------
    InvalidGeometryError
        The image cannot be decoded, is a stack, is colour without a threshold, has NaN pixels.
    """
    raster = _raster("load_mask")
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(2, "No such file or directory", str(path))
    try:
        return np.asarray(raster.load_mask(path, threshold=threshold, invert=invert), dtype=bool)
    except ValueError as exc:
        raise InvalidGeometryError(str(exc)) from None


def write_mask(mask, path) -> None:
    """Write a boolean mask as a black-and-white image (0 and 255, 8-bit) with ``raster.save_mask``."""
    path = Path(path)
    if path.suffix.lower() not in MASK_WRITE_EXTENSIONS:
        raise ValueError(f"{path}: a mask is written as {', '.join(MASK_WRITE_EXTENSIONS)}")
    raster = _raster("save_mask")
    with atomic_path(path) as tmp:
        raster.save_mask(tmp, mask)


# ---------------------------------------------------------------------------------------------------------
# Tracing a mask to vectors
# ---------------------------------------------------------------------------------------------------------
def _grid(shape):
    raster = _raster("Grid")
    return raster.Grid(x0=0.0, y_top=0.0, pixel_size=1.0, shape=tuple(shape))


def trace_pixels(mask):
    """The union of a mask's pixel squares, in pixel coordinates (x = column, y = −row).

    Built from each row's runs of True pixels (one box a run, not one a pixel, which is what makes it
    fast: 0.1 s for a 1000 × 1000 disk, against 23 s for `vectortighten.pixel_squares`, the same
    polygon), and without collinear vertices.

    Parameters
    ----------
    mask : (H, W) array of bool

    Returns
    -------
    Polygon or MultiPolygon (empty when the mask is)

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((4, 4), bool); m[1:3, 1:4] = True; m[3, 1] = True
    >>> P = trace_pixels(m)
    >>> P.area, P.bounds, len(P.exterior.coords)
    (7.0, (1.0, -4.0, 4.0, -1.0), 7)
    """
    import shapely

    m = np.asarray(mask, dtype=bool)
    d = np.diff(np.pad(m, ((0, 0), (1, 1))).astype(np.int8), axis=1)
    r0, c0 = np.nonzero(d == 1)
    _, c1 = np.nonzero(d == -1)
    if len(r0) == 0:
        return shapely.Polygon()
    union = shapely.union_all(shapely.box(c0, -r0 - 1.0, c1, -r0.astype(float)))
    return shapely.simplify(union, 0.0)


@dataclass
class TracedTightening:
    """The pixel method's tightening of a mask, traced: what the vector writers need, like a `Tightening`.

    The boundary is the sub-pixel zero level of the flow's Φ (`raster.contours`): straight segments, no
    exact arcs. ``shape``, ``core`` and ``mortar`` (for ``--layers``) are unions of pixel squares.

    Attributes
    ----------
    loops : list of Loop
        The contour's rings as loops of segments (outer boundaries counter-clockwise, holes clockwise).
    geometry : Polygon or MultiPolygon
    r : float
    init : str
    tolerance : float
        0: the geometry is the contour itself.
    result : RasterTightening
    """

    loops: list
    geometry: object
    r: float
    init: str
    result: object
    tolerance: float = 0.0
    mask: np.ndarray = field(default=None, repr=False)

    @cached_property
    def shape(self):
        """The input: the union of the mask's pixel squares."""
        return trace_pixels(self.mask)

    @cached_property
    def core(self):
        """The pixel method's core, as pixel squares."""
        return trace_pixels(self.result.core)

    @cached_property
    def mortar(self):
        """The pixel method's mortar, as pixel squares."""
        return trace_pixels(self.result.mortar)

    @property
    def perimeter(self) -> float:
        """Length of the contour, pixels."""
        return float(self.geometry.length)

    @property
    def area(self) -> float:
        """Area inside the contour, pixels²."""
        return float(self.geometry.area)

    @property
    def n_components(self) -> int:
        """Number of connected components."""
        return sum(1 for lp in self.loops if lp.area > 0)

    @property
    def n_holes(self) -> int:
        """Number of holes."""
        return sum(1 for lp in self.loops if lp.area < 0)

    @property
    def is_empty(self) -> bool:
        """True when nothing is left."""
        return not self.loops


def _loops_of(geometry) -> list:
    import shapely

    from vectortighten.curves import Loop

    loops = []
    for poly in shapely.get_parts(shapely.orient_polygons(geometry)):
        if poly.is_empty:
            continue
        for ring in (poly.exterior, *poly.interiors):
            loops.append(Loop.from_polygon_ring(np.asarray(ring.coords)))
    return loops


def trace_tighten(mask, r: float, *, trace: str = "exact", init: str = "core",
                  tolerance: float | None = None):
    """Tighten a binary mask into vectors, in pixel coordinates (x = column, y = −row).

    Parameters
    ----------
    mask : (H, W) array of bool
    r : float
        Radius, pixels.
    trace : {"exact", "contours"}
        ``"exact"``: the exact tightening (`vectortighten.tighten`) of the union of the pixel squares
        (`trace_pixels`): segments and arcs of radius exactly r. ``"contours"``: the pixel method
        (`raster.tighten`) and its sub-pixel contour (`raster.contours`).
    init : {"core", "input", "mason"}
    tolerance : float, optional
        ``"exact"`` only: the sampled geometry's tolerance (default 1e-5·r).

    Returns
    -------
    Tightening or TracedTightening
        Either one goes to `vectortighten.io.write_result`.

    Raises
    ------
    ValueError
        Unknown ``trace``; the mask is empty.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((30, 30), bool); m[5:25, 5:25] = True
    >>> T = trace_tighten(m, 4)
    >>> round(T.area, 6) == round(400 - 4 * 4 ** 2 * (1 - np.pi / 4), 6)   # the corner formula, r = 4
    True
    >>> abs(trace_tighten(m, 4, trace="contours").area - T.area) < 8      # the pixel method: within a pixel
    True
    """
    if trace not in TRACES:
        raise ValueError(f"trace must be one of {', '.join(TRACES)}, got {trace!r}")
    m = np.asarray(mask, dtype=bool)
    if not m.any():
        raise ValueError("the mask is empty: there is nothing to trace")
    if trace == "exact":
        from vectortighten.engine import tighten

        return tighten(trace_pixels(m), r, init=init, tolerance=tolerance)
    raster = _raster("tighten", "contours")
    if m.all():
        raise ValueError("the mask is set everywhere: it has no boundary to trace")
    res = raster.tighten(m, r, init=init)
    geometry = raster.contours(res, _grid(m.shape))
    return TracedTightening(_loops_of(geometry), geometry, float(r), init, res, mask=m)


def labels_features(out, res=None):
    """A tightened label image as `Features`: one feature a label, the union of its pixels' squares.

    Each label's region is traced exactly (`trace_pixels`: the union of its pixels' squares, in pixel
    coordinates x = column, y = −row), so neighbouring labels share their edges exactly and the features
    tile the labelled area with no gap and no overlap. Attributes: ``label``, ``area`` (pixels), and with
    ``res`` (a `raster.LabelTightening`) ``area_in``, ``r`` and ``init``. Labels with no pixel left have no
    feature. No CRS: the coordinates are pixels. `vectortighten.io.write_features` writes them to any
    geodata format (GeoJSON, GeoPackage, …); needs pandas (the ``geo`` extra).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((4, 6), np.uint8); img[1:3, 1:3] = 5; img[1:3, 3:5] = 9
    >>> f = labels_features(img)
    >>> f.attributes["label"].tolist(), f.attributes["area"].tolist(), [g.area for g in f.geometry]
    ([5, 9], [4, 4], [4.0, 4.0])
    """
    from ._common import _require
    from ._source import Features

    pd = _require("pandas", "geo", "label features")
    out = np.asarray(out)
    values, counts = np.unique(out[out != 0], return_counts=True)
    columns = {"label": [v.item() for v in values], "area": [int(n) for n in counts]}
    if res is not None:
        area_in = {v.item(): int(a) for v, a in zip(res.values, res.area_in, strict=True)}
        columns.update(area_in=[area_in.get(v.item()) for v in values], r=[float(res.r)] * len(values),
                       init=[str(res.init)] * len(values))
    geometry = np.array([trace_pixels(out == v) for v in values], dtype=object)
    return Features(geometry, pd.DataFrame(columns), {"crs": None, "units": None, "layer": "labels"})


# ---------------------------------------------------------------------------------------------------------
# One image file in, one file out (the command line's mask path)
# ---------------------------------------------------------------------------------------------------------
def _palette_colours(img) -> np.ndarray:
    """A palette image's colours, (…, 3) uint8, for reading it with a threshold."""
    pal = np.zeros((256, 3), dtype=np.uint8)
    p = np.asarray(img.palette, dtype=np.uint8).reshape(-1, 3)[:256]
    pal[: len(p)] = p
    return pal[img.data]


def tighten_image_file(source, target, *, r: float, init: str = "core", threshold: float | None = None,
                       invert: bool = False, labels: bool = False, stack: bool = False, trace: str = "exact",
                       tolerance: float | None = None, layers=(), max_pixels: int | None = None) -> str:
    """Tighten the mask or label image ``source`` into ``target`` (an image, or vectors); a summary line.

    Parameters
    ----------
    source : path
        An image: ``.png``, ``.tif``/``.tiff``, ``.bmp``, ``.gif``, ``.jpg``/``.jpeg``.
    target : path
        ``.png``, ``.tif``/``.tiff``, ``.bmp`` (the tightened image, in the input's values), or a vector
        format of `vectortighten.io.write_result` (``.svg``, ``.wkt``, ``.geojson``, ``.gpkg``, ``.dxf``, …).
    r : float
        Radius, pixels.
    init : {"core", "input", "mason"}
    threshold : float in (0, 1], optional
        Read a greyscale or colour image by its level (`raster.binarize`); default: non-zero is inside.
    invert : bool
        Swap inside and outside.
    labels : bool
        Tighten every label of a label image (`raster.tighten_labels`); to an image, or to a geodata
        format, one feature a label (`labels_features`).
    stack : bool
        Tighten each slice of a stack (multi-page TIFF, animated GIF); TIFF output only.
    trace : {"exact", "contours"}
        Vector output only: see `trace_tighten`.
    tolerance : float, optional
        Vector output, ``trace="exact"``: the sampled geometry's tolerance.
    layers : iterable of {"input", "core", "mortar"}
        Vector output: layers for SVG, DXF and PNG pictures.
    max_pixels : int, optional
        The largest image read (default `raster.MAX_PIXELS`).

    Returns
    -------
    str
        What was written, for the user.

    Raises
    ------
    ValueError
        Every user error (malformed image, a stack without ``stack``, colour without a threshold, NaN
        pixels, a format that cannot hold the values, options that do not go together); nothing is
        written then.
    """
    raster = _raster("read_image", "write_image", "tighten_mask", "tighten_labels")
    source, target = Path(source), Path(target)
    if labels and threshold is not None:
        raise ValueError("--labels reads label values as they are; it takes no --threshold")
    if labels and invert:
        raise ValueError("--labels takes no --invert (0 is the background of a label image)")
    ext = target.suffix.lower()
    to_image = ext in MASK_WRITE_EXTENSIONS
    if not to_image:
        from . import FORMATS, WRITE_FORMATS, format_of

        if ext in (".jpg", ".jpeg", ".gif"):
            raise ValueError(f"{target}: {ext[1:].upper()} cannot hold a mask's values exactly (lossy or "
                             f"palette-reduced); write {', '.join(MASK_WRITE_EXTENSIONS)}")
        if ext not in WRITE_FORMATS:
            raise ValueError(f"{target}: unsupported output format {ext or '(none)'!r}; an image input is "
                             f"written as an image ({', '.join(MASK_WRITE_EXTENSIONS)}) or as vectors "
                             f"({', '.join(e for e in WRITE_FORMATS if e not in MASK_WRITE_EXTENSIONS)})")
        if labels and format_of(target).write_features is None:
            geodata = ", ".join(e for f in FORMATS.values() if f.write_features for e in f.extensions)
            raise ValueError(f"{target}: --labels writes a label image ({', '.join(MASK_WRITE_EXTENSIONS)}) "
                             f"or geodata ({geodata}; one feature a label); not {ext}")
        if labels and (trace != "exact" or tolerance is not None or layers):
            raise ValueError(f"{target}: labels are traced as the pixel squares of their tightened regions; "
                             "--trace, --tolerance and --layers do not apply")
    elif trace != "exact" or tolerance is not None or layers:
        raise ValueError(f"{target}: --trace, --tolerance and --layers are for vector outputs; "
                         "an image output is the tightened mask itself")
    options = {} if max_pixels is None else {"max_pixels": max_pixels}
    img = raster.read_image(source, **options)
    if img.stack and not stack:
        raise ValueError(f"{source}: a stack of {img.data.shape[0]} images (pages or frames); pass --stack "
                         "to tighten each slice on its own, or give one image")
    if img.stack and to_image and ext not in (".tif", ".tiff"):
        raise ValueError(f"{target}: a stack is written as .tif, not {ext}")
    if img.stack and not to_image:
        raise ValueError(f"{target}: vector output of a stack is not supported; write a .tif")
    like = img
    slices = img.slices
    if threshold is not None and img.palette:
        slices = [_palette_colours(img.with_data(s)) for s in slices]     # a palette is read by its colours
        like = replace(img, palette=None, transparency=None, photometric=None)
    names = [str(source)] if len(slices) == 1 else [f"{source} slice {i}" for i in range(len(slices))]
    if not to_image and labels:
        from . import write_features

        out, res = raster.tighten_labels(slices[0], r, init=init, return_result=True, name=names[0])
        write_features(labels_features(out, res), target)
        kept = int((res.area_out > 0).sum())
        return f"{target}: {kept} of {len(res.values)} label(s) kept, traced as {kept} feature(s)"
    if not to_image:
        mask, _ = raster.binarize(slices[0], threshold, invert=invert, name=names[0])
        if not mask.any():
            raise ValueError(f"{source}: the mask is empty: there is nothing to trace")
        from . import write_result

        result = trace_tighten(mask, r, trace=trace, init=init, tolerance=tolerance)
        if result.is_empty:
            warnings.warn(f"the tightening is empty: every part is thinner than 2r = {2 * r:g} px",
                          UserWarning, stacklevel=2)
        write_result(result, target, layers=layers)
        return (f"{target}: traced {trace}, perimeter {result.perimeter:.6g} px, area {result.area:.6g} px², "
                f"{result.n_components} component(s), {result.n_holes} hole(s)")
    outs = []
    kept = total = 0
    for data, name in zip(slices, names):
        if labels:
            out, res = raster.tighten_labels(data, r, init=init, return_result=True, name=name)
            kept += int((res.area_out > 0).sum())
            total += len(res.values)
        else:
            out = raster.tighten_mask(data, r, threshold=threshold, invert=invert, init=init, name=name)
        outs.append(out)
    out = np.stack(outs) if img.stack else outs[0]
    raster.write_image(target, out, like=like)
    where = f"{len(outs)} slices, " if img.stack else ""
    if labels:
        return (f"{target}: {where}{kept} of {total} label(s) kept, "
                f"{int(np.count_nonzero(out))} labelled pixel(s)")
    grey = [o[:, :, 0] if o.ndim == 3 else o for o in outs]
    inside = sum(int((g == 0).sum()) if invert else int((g != 0).sum()) for g in grey)
    size = sum(int(math.prod(o.shape[:2])) for o in outs)
    return f"{target}: {where}{inside} pixel(s) set of {size}"
