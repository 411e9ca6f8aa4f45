"""Between vector shapes and pixels: `Grid`, `rasterize` and `contours`.

Image convention: row 0 is the top of the image. Pixel (i, j) has its centre at
``x = x0 + (j + ½)·h``, ``y = y_top − (i + ½)·h`` for the grid's left edge x0, top edge y_top and pixel
size h, so y grows upwards in world coordinates as in the vector engine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

__all__ = ["Grid", "contours", "rasterize"]


@dataclass(frozen=True)
class Grid:
    """A pixel grid in world coordinates.

    Attributes
    ----------
    x0, y_top : float
        World coordinates of the grid's left and top edges.
    pixel_size : float
        Side of a pixel, world units.
    shape : (int, int)
        Rows and columns.
    """

    x0: float
    y_top: float
    pixel_size: float
    shape: tuple

    @classmethod
    def covering(cls, bounds, pixel_size: float, margin: float = 0.0) -> Grid:
        """The grid of square pixels that covers ``bounds`` (minx, miny, maxx, maxy) grown by ``margin``.

        Examples
        --------
        >>> Grid.covering((0, 0, 10, 5), 1.0).shape
        (5, 10)
        """
        if not (math.isfinite(pixel_size) and pixel_size > 0):
            raise ValueError(f"pixel_size must be a finite number > 0, got {pixel_size!r}")
        x0, y0, x1, y1 = bounds
        x0, y0, x1, y1 = x0 - margin, y0 - margin, x1 + margin, y1 + margin
        cols = max(1, math.ceil((x1 - x0) / pixel_size - 1e-9))
        rows = max(1, math.ceil((y1 - y0) / pixel_size - 1e-9))
        return cls(float(x0), float(y0 + rows * pixel_size), float(pixel_size), (rows, cols))

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(minx, miny, maxx, maxy) of the whole grid."""
        h = self.pixel_size
        rows, cols = self.shape
        return (self.x0, self.y_top - rows * h, self.x0 + cols * h, self.y_top)

    def to_world(self, rows, cols) -> tuple[np.ndarray, np.ndarray]:
        """World (x, y) of fractional pixel positions (row, column index of pixel centres)."""
        h = self.pixel_size
        return (self.x0 + (np.asarray(cols, float) + 0.5) * h, self.y_top - (np.asarray(rows, float) + 0.5) * h)


def rasterize(geometry, grid: Grid | None = None, *, pixel_size: float | None = None,
              margin: float = 0.0) -> tuple[np.ndarray, Grid]:
    """Polygons to a mask: a pixel is True when its centre lies inside (even-odd over all rings).

    Scanline fill: each row's crossings with the boundary are found for all rows at once, sorted, and the
    runs between pairs filled, in time linear in pixels plus crossings. A centre exactly on an edge follows
    the half-open rule (inside on the left and bottom edges of a horizontal run).

    Parameters
    ----------
    geometry : shapely Polygon or MultiPolygon
    grid : Grid, optional
        The grid to use; else one covering the geometry's bounds (plus ``margin``) at ``pixel_size``.
    pixel_size : float, optional
        Required when ``grid`` is not given.
    margin : float
        World units of empty border around the bounds when the grid is made here.

    Returns
    -------
    mask : (H, W) ndarray of bool
    grid : Grid

    Examples
    --------
    >>> from shapely.geometry import box
    >>> m, g = rasterize(box(0, 0, 4, 2), pixel_size=1.0, margin=1.0)
    >>> m.shape, int(m.sum())
    ((4, 6), 8)
    """
    if not isinstance(geometry, (Polygon, MultiPolygon)):
        raise TypeError(f"geometry must be a shapely Polygon or MultiPolygon, got {type(geometry).__name__}")
    if grid is None:
        if pixel_size is None:
            raise ValueError("give either a grid or a pixel_size")
        if geometry.is_empty:
            raise ValueError("cannot choose a grid for an empty geometry; pass grid=")
        grid = Grid.covering(geometry.bounds, float(pixel_size), margin)
    rows, cols = grid.shape
    mask = np.zeros((rows, cols), dtype=bool)
    if geometry.is_empty:
        return mask, grid
    h = grid.pixel_size
    starts, ends = [], []
    for ring in shapely.get_rings(shapely.get_parts(geometry)):
        c = shapely.get_coordinates(ring)
        starts.append(c[:-1])
        ends.append(c[1:])
    a, b = np.concatenate(starts), np.concatenate(ends)
    # Continuous row coordinate v (row i has its centre at v = i) and column coordinate u.
    va, vb = (grid.y_top - a[:, 1]) / h - 0.5, (grid.y_top - b[:, 1]) / h - 0.5
    ua, ub = (a[:, 0] - grid.x0) / h - 0.5, (b[:, 0] - grid.x0) / h - 0.5
    lo, hi = np.minimum(va, vb), np.maximum(va, vb)
    first = np.clip(np.ceil(lo), 0, rows).astype(np.int64)      # rows whose centre line the edge crosses:
    last = np.clip(np.ceil(hi), 0, rows).astype(np.int64)       # lo ≤ i < hi (half-open)
    count = np.maximum(last - first, 0)
    if count.sum() == 0:
        return mask, grid
    edge = np.repeat(np.arange(len(a)), count)
    row = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count) + np.repeat(first, count)
    t = (row - va[edge]) / (vb[edge] - va[edge])
    u = ua[edge] + t * (ub[edge] - ua[edge])
    order = np.lexsort((u, row))
    row, u = row[order], u[order]
    # Pairs of consecutive crossings in a row bound the inside runs (even-odd): columns j with u0 ≤ j < u1.
    j0 = np.clip(np.ceil(u[0::2]), 0, cols).astype(np.int64)
    j1 = np.clip(np.ceil(u[1::2]), 0, cols).astype(np.int64)
    rr = row[0::2]
    delta = np.zeros((rows, cols + 1), dtype=np.int32)
    np.add.at(delta, (rr, j0), 1)
    np.add.at(delta, (rr, j1), -1)
    mask[:] = np.cumsum(delta, axis=1)[:, :cols] > 0
    return mask, grid


def _rings_to_polygons(rings: list[np.ndarray]):
    """Closed rings to polygons with holes by even-odd nesting."""
    polys = [Polygon(r) for r in rings if len(r) >= 4]
    polys = [p if p.is_valid else shapely.make_valid(p) for p in polys if p.area > 0]
    if not polys:
        return Polygon()
    out = polys[0]
    for p in polys[1:]:
        out = shapely.symmetric_difference(out, p)
    out = shapely.make_valid(out)
    parts = [g for g in shapely.get_parts(out) if isinstance(g, Polygon) and g.area > 0]
    return shapely.orient_polygons(MultiPolygon(parts) if len(parts) > 1 else (parts[0] if parts else Polygon()))


def contours(result, grid: Grid | None = None):
    """The boundary of a raster result as shapely polygons with holes, to sub-pixel accuracy.

    For a `RasterTightening` with the minimum-perimeter finish, its loops themselves (the curves the mask
    samples); otherwise the zero level of Φ is traced (linear interpolation between pixel centres); for a
    plain mask the ½ level of the mask (the pixel outline with its corners cut). Coordinates are
    world coordinates of ``grid`` if given, else pixel coordinates with x = column, y = −row (so that the
    image is the right way up).

    Parameters
    ----------
    result : RasterTightening or (H, W) array of bool
    grid : Grid, optional

    Returns
    -------
    Polygon or MultiPolygon (possibly empty)

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((10, 10), bool); m[2:8, 2:8] = True
    >>> round(contours(m).area, 6)      # a 6 × 6 pixel square with its corners cut by ½ × ½ triangles
    35.5
    """
    import contourpy

    curves = getattr(result, "curves", None)
    if curves is not None:
        # The minimum-perimeter finish's own loops: the boundary the mask samples, exactly.
        if grid is None:
            return curves
        h = grid.pixel_size
        return shapely.transform(curves, lambda xy: np.column_stack([grid.x0 + (xy[:, 0] + 0.5) * h,
                                                                     grid.y_top - (0.5 - xy[:, 1]) * h]))
    phi = getattr(result, "phi", None)
    mask = np.asarray(getattr(result, "mask", result), dtype=bool)
    if phi is not None:
        # Φ places the front where it agrees with the mask; a pixel a final step (the minimum-perimeter
        # finish) moved to the other side keeps the flow's Φ of about 0, which would put the front on
        # that pixel's centre: there the front is taken half-way to the neighbours, as for a plain mask.
        mag = np.where((phi < 0) == mask, np.abs(phi), 0.5)
        field = np.where(mask, -mag - 1e-6, mag + 1e-6).astype(float)
        field = np.clip(field, -2.0, 2.0)
        level = 0.0
        pad_value = 2.0
    else:
        field = (~mask).astype(float)
        level = 0.5
        pad_value = 1.0
    field = np.pad(field, 1, constant_values=pad_value)       # so every contour closes
    gen = contourpy.contour_generator(z=field, name="serial", line_type="Separate")
    rings = []
    for line in gen.lines(level):
        if len(line) < 4:
            continue
        cols, rows = line[:, 0] - 1.0, line[:, 1] - 1.0
        if grid is not None:
            x, y = grid.to_world(rows, cols)
        else:
            x, y = cols, -rows
        ring = np.column_stack([x, y])
        if not np.array_equal(ring[0], ring[-1]):
            ring = np.vstack([ring, ring[:1]])
        rings.append(ring)
    return _rings_to_polygons(rings)
