"""Between masks and the rest of the world: shapely polygons, sub-pixel contours and PNG files.

Grid convention: a `Grid` with origin ``(x0, y0)``, pixel size ``s`` and shape ``(rows, cols)`` puts the centre
of pixel ``(i, j)`` (row i, column j) at ``(x0 + (j + 1/2)·s, y0 + (i + 1/2)·s)``. Rows run along +y, so a
mask drawn as an image (row 0 at the top) shows the shape mirrored top to bottom; `save_mask` does not flip.
"""

from __future__ import annotations

import math
import numbers
import os
import tempfile
from dataclasses import dataclass

import contourpy
import numpy as np
import shapely
from PIL import Image
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from ._validation import check_mask
from .morphology import _edt
from .tighten import RasterTightening

__all__ = ["Grid", "contours", "load_mask", "rasterize", "save_mask"]


@dataclass(frozen=True)
class Grid:
    """Where the pixels of a mask lie in the plane.

    Attributes
    ----------
    origin : (float, float)
        ``(x0, y0)``: the lower-left corner of pixel ``(0, 0)``.
    pixel_size : float
        Side of a pixel, in the geometry's units.
    shape : (int, int)
        ``(rows, cols)`` of the mask.
    """

    origin: tuple[float, float]
    pixel_size: float
    shape: tuple[int, int]

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(minx, miny, maxx, maxy)`` of the whole grid (pixel edges, not centres)."""
        x0, y0 = self.origin
        s = self.pixel_size
        return (x0, y0, x0 + self.shape[1] * s, y0 + self.shape[0] * s)

    def centres(self) -> tuple[np.ndarray, np.ndarray]:
        """Pixel centres as two ``(rows, cols)`` arrays ``X, Y``."""
        x0, y0 = self.origin
        s = self.pixel_size
        xs = x0 + (np.arange(self.shape[1]) + 0.5) * s
        ys = y0 + (np.arange(self.shape[0]) + 0.5) * s
        return np.meshgrid(xs, ys)


def _check_pixel_size(pixel_size) -> float:
    if isinstance(pixel_size, bool) or not isinstance(pixel_size, numbers.Real):
        raise ValueError(f"pixel_size must be a positive finite number, got {pixel_size!r}")
    s = float(pixel_size)
    if not math.isfinite(s) or s <= 0:
        raise ValueError(f"pixel_size must be a positive finite number, got {pixel_size!r}")
    return s


def _make_grid(shape_or_bounds, pixel_size, origin, margin) -> Grid:
    if isinstance(shape_or_bounds, Grid):
        return shape_or_bounds
    vals = tuple(shape_or_bounds)
    s = _check_pixel_size(pixel_size)
    if len(vals) == 2:
        rows, cols = vals
        if not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) and v > 0 for v in vals):
            raise ValueError(f"shape must be two positive integers (rows, cols), got {shape_or_bounds!r}")
        ox, oy = (float(v) for v in origin)
        if not (math.isfinite(ox) and math.isfinite(oy)):
            raise ValueError(f"origin must be finite, got {origin!r}")
        return Grid((ox, oy), s, (int(rows), int(cols)))
    if len(vals) == 4:
        minx, miny, maxx, maxy = (float(v) for v in vals)
        if not all(math.isfinite(v) for v in (minx, miny, maxx, maxy)) or maxx < minx or maxy < miny:
            raise ValueError(f"bounds must be finite (minx, miny, maxx, maxy), got {shape_or_bounds!r}")
        if isinstance(margin, bool) or not isinstance(margin, numbers.Integral) or margin < 0:
            raise ValueError(f"margin must be a non-negative number of pixels, got {margin!r}")
        cols = max(1, math.ceil((maxx - minx) / s - 1e-9)) + 2 * int(margin)
        rows = max(1, math.ceil((maxy - miny) / s - 1e-9)) + 2 * int(margin)
        return Grid((minx - margin * s, miny - margin * s), s, (rows, cols))
    raise ValueError(
        "shape_or_bounds must be a Grid, (rows, cols) or (minx, miny, maxx, maxy), " f"got {shape_or_bounds!r}"
    )


def _polygonal(geometry) -> BaseGeometry:
    if not isinstance(geometry, BaseGeometry):
        raise ValueError(f"geometry must be a shapely Polygon or MultiPolygon, got {type(geometry).__name__}")
    if geometry.is_empty:
        raise ValueError("geometry is empty: there is nothing to rasterize")
    kinds = {g.geom_type for g in shapely.get_parts(geometry)}
    if not kinds <= {"Polygon", "MultiPolygon"}:
        raise ValueError(f"geometry must be polygonal, got {', '.join(sorted(kinds))}")
    if not np.isfinite(shapely.get_coordinates(geometry)).all():
        raise ValueError("geometry has non-finite (NaN or infinite) coordinates")
    if not geometry.is_valid:
        raise ValueError(f"geometry is invalid ({shapely.is_valid_reason(geometry)}); repair it first, "
                         "e.g. with shapely.make_valid")
    if geometry.geom_type == "GeometryCollection":
        geometry = shapely.union_all(shapely.get_parts(geometry))
    return geometry


def rasterize(
    geometry,
    shape_or_bounds,
    pixel_size: float = 1.0,
    *,
    origin: tuple[float, float] = (0.0, 0.0),
    margin: int = 0,
) -> tuple[np.ndarray, Grid]:
    """Rasterize shapely polygons: a pixel is True when its centre lies in the geometry.

    Parameters
    ----------
    geometry : shapely Polygon, MultiPolygon or collection of them
        A valid polygonal geometry (holes allowed). Invalid or empty geometry raises ValueError.
    shape_or_bounds : Grid, (rows, cols) or (minx, miny, maxx, maxy)
        The grid: given whole, by its shape (with ``origin``), or by bounds to cover (the grid's origin is
        ``(minx, miny)`` minus ``margin`` pixels and its shape is rounded up to whole pixels).
    pixel_size : float, default 1.0
        Side of a pixel in the geometry's units (ignored for a `Grid`).
    origin : (float, float), default (0, 0)
        Lower-left corner of pixel ``(0, 0)``, used with ``(rows, cols)``.
    margin : int, default 0
        Extra background pixels on every side, used with bounds.

    Returns
    -------
    mask : (rows, cols) ndarray of bool
        True where the pixel centre ``(x0 + (j + 1/2)·s, y0 + (i + 1/2)·s)`` is inside the geometry.
    grid : Grid
        The grid used.

    Notes
    -----
    Scanline even-odd fill, vectorised over all (edge, row) crossings: linear in pixels plus crossings.
    Centres exactly on a boundary follow a half-open rule (left and bottom edges in, right and top edges
    out), so two polygons sharing an edge never both claim a pixel.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> mask, grid = rasterize(box(0, 0, 3, 2), (4, 5))
    >>> mask.astype(int)
    array([[1, 1, 1, 0, 0],
           [1, 1, 1, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    >>> grid.origin, grid.pixel_size
    ((0.0, 0.0), 1.0)
    """
    geom = _polygonal(geometry)
    grid = _make_grid(shape_or_bounds, pixel_size, origin, margin)
    rows, cols = grid.shape
    x0, y0 = grid.origin
    s = grid.pixel_size
    # Every ring as a sequence of edges, in pixel-centre coordinates (u = column, v = row).
    rings = shapely.get_rings(geom)
    coords, ring_index = shapely.get_coordinates(rings, return_index=True)
    u = (coords[:, 0] - x0) / s - 0.5
    v = (coords[:, 1] - y0) / s - 0.5
    same = ring_index[1:] == ring_index[:-1]
    u1, v1, u2, v2 = u[:-1][same], v[:-1][same], u[1:][same], v[1:][same]
    moving = v1 != v2
    u1, v1, u2, v2 = u1[moving], v1[moving], u2[moving], v2[moving]
    vmin = np.minimum(v1, v2)
    vmax = np.maximum(v1, v2)
    # Rows i with vmin <= i < vmax (half-open: a vertex on a row centre counts once).
    lo = np.clip(np.ceil(vmin), 0, rows).astype(np.int64)
    hi = np.clip(np.ceil(vmax), 0, rows).astype(np.int64)
    n = np.maximum(hi - lo, 0)
    total = int(n.sum())
    acc = np.zeros(rows * (cols + 1), dtype=np.int64)
    if total:
        edge = np.repeat(np.arange(n.size), n)
        start = np.cumsum(n) - n
        i = lo[edge] + (np.arange(total) - start[edge])
        t = (i - v1[edge]) / (v2[edge] - v1[edge])
        ux = u1[edge] + t * (u2[edge] - u1[edge])
        # The first pixel centre at or right of the crossing toggles parity.
        k = np.clip(np.ceil(ux), 0, cols).astype(np.int64)
        acc = np.bincount(i * (cols + 1) + k, minlength=rows * (cols + 1))
    parity = np.cumsum(acc.reshape(rows, cols + 1)[:, :cols], axis=1) & 1
    return parity.astype(bool), grid


def _mask_phi(mask: np.ndarray) -> np.ndarray:
    """Signed distance of a mask, half a pixel off the centres (negative inside)."""
    mp = np.pad(mask, 1)
    phi = np.where(mp, 0.5 - _edt(mp), _edt(~mp) - 0.5)[1:-1, 1:-1]
    return phi


def contours(result_or_mask, grid: Grid | None = None) -> Polygon | MultiPolygon:
    """Sub-pixel boundary of a tightening (or of a mask) as shapely polygons with holes.

    Parameters
    ----------
    result_or_mask : RasterTightening or (h, w) array_like of bool
        A result of `raster.tighten` (its ``phi`` is contoured at level 0), or a mask (its signed distance
        function, ``±1/2`` pixel on either side of the boundary, is contoured at level 0).
    grid : Grid, optional
        Where the pixels lie; default: unit pixels with pixel ``(i, j)`` centred at ``(j + 1/2, i + 1/2)``.

    Returns
    -------
    Polygon or MultiPolygon
        The region ``phi < 0`` by marching squares (contourpy) between pixel centres, in grid coordinates.
        Pixels along the image border are closed off half a pixel beyond their centres (at the image edge).
        Empty Polygon if nothing is inside.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((6, 6), bool); m[1:5, 1:5] = True
    >>> round(contours(m).area, 6)
    15.5
    """
    if isinstance(result_or_mask, RasterTightening):
        phi = np.asarray(result_or_mask.phi, dtype=np.float64)
    else:
        phi = _mask_phi(check_mask(result_or_mask))
    if grid is None:
        grid = Grid((0.0, 0.0), 1.0, phi.shape)
    elif tuple(grid.shape) != phi.shape:
        raise ValueError(f"grid shape {grid.shape} does not match the mask's shape {phi.shape}")
    if not (phi < 0).any():
        return Polygon()
    z = np.pad(phi, 1, mode="constant", constant_values=0.5)
    lower = float(z.min()) - 1.0
    gen = contourpy.contour_generator(z=z, fill_type=contourpy.FillType.OuterOffset)
    points_list, offsets_list = gen.filled(lower, 0.0)
    x0, y0 = grid.origin
    s = grid.pixel_size
    polys = []
    for pts, offs in zip(points_list, offsets_list, strict=True):
        xy = np.empty_like(pts)
        xy[:, 0] = x0 + (pts[:, 0] - 0.5) * s  # padded column c is pixel c - 1, centred at c - 1/2
        xy[:, 1] = y0 + (pts[:, 1] - 0.5) * s
        rings = [xy[a:b] for a, b in zip(offs[:-1], offs[1:], strict=True)]
        rings = [r for r in rings if len(r) >= 4]
        if rings:
            polys.append(Polygon(rings[0], rings[1:]))
    if not polys:
        return Polygon()
    out = MultiPolygon(polys) if len(polys) > 1 else polys[0]
    if not out.is_valid:
        out = shapely.make_valid(out)
        parts = [g for g in shapely.get_parts(out) if g.geom_type in ("Polygon", "MultiPolygon")]
        out = shapely.union_all(parts) if parts else Polygon()
    return out


def load_mask(path, threshold: float = 0.5, *, invert: bool = False) -> np.ndarray:
    """Read a PNG (or any image pillow reads) as a mask.

    Parameters
    ----------
    path : str or os.PathLike
        Image file.
    threshold : float, default 0.5
        In [0, 1]. A pixel is inside where its value, scaled to [0, 1], is **greater** than ``threshold``.
        The value is the alpha channel if the image has one that is not fully opaque everywhere (a shape on
        a transparent background), otherwise the luminance (so white = inside, as `save_mask` writes).
    invert : bool, default False
        Swap inside and outside (for dark shapes on a light background).

    Returns
    -------
    mask : (h, w) ndarray of bool
        Row 0 is the top row of the image.

    Raises
    ------
    ValueError
        If the file cannot be read as an image, or ``threshold`` is not in [0, 1].

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> m = np.eye(3, dtype=bool)
    >>> path = os.path.join(tempfile.mkdtemp(), "m.png")
    >>> save_mask(path, m)
    >>> bool((load_mask(path) == m).all())
    True
    """
    if isinstance(threshold, bool) or not isinstance(threshold, numbers.Real) or not 0 <= threshold <= 1:
        raise ValueError(f"threshold must be a number in [0, 1], got {threshold!r}")
    try:
        with Image.open(path) as img:
            img.load()
            mode = img.mode
            if mode == "1":
                value = np.asarray(img, dtype=np.float64)
            elif mode in ("I;16", "I;16B", "I;16L", "I", "F"):
                arr = np.asarray(img, dtype=np.float64)
                top = 65535.0 if mode.startswith("I;16") or arr.max(initial=0) > 255 else 255.0
                value = arr / top
            else:
                has_alpha = mode in ("RGBA", "LA", "PA") or (mode == "P" and "transparency" in img.info)
                rgba = img.convert("RGBA") if has_alpha else None
                alpha = np.asarray(rgba)[..., 3] if rgba is not None else None
                if alpha is not None and (alpha < 255).any():
                    value = alpha / 255.0
                else:
                    value = np.asarray(img.convert("L"), dtype=np.float64) / 255.0
    except (OSError, SyntaxError, ValueError) as exc:
        raise ValueError(f"cannot read {os.fspath(path)!r} as an image: {exc}") from exc
    if value.ndim != 2 or value.size == 0:
        raise ValueError(f"{os.fspath(path)!r} holds no 2-D image (shape {value.shape})")
    mask = value > threshold
    return ~mask if invert else mask


def save_mask(path, mask) -> None:
    """Write a mask as an 8-bit greyscale PNG (True = 255, white), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; written to a temporary file in the same folder, then renamed over it, so a failure
        never leaves a half-written file.
    mask : (h, w) array_like of bool
        Bool, or numbers that are all 0 or 1. Row 0 becomes the top row of the image.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> path = os.path.join(tempfile.mkdtemp(), "m.png")
    >>> save_mask(path, np.ones((2, 3), bool))
    >>> load_mask(path).shape
    (2, 3)
    """
    m = check_mask(mask)
    img = Image.fromarray(np.where(m, 255, 0).astype(np.uint8))
    folder = os.path.dirname(os.path.abspath(os.fspath(path)))
    fd, tmp = tempfile.mkstemp(suffix=".png.tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as fh:
            img.save(fh, format="PNG")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
