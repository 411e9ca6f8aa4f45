"""Shared drawing for Figures 8 and 9: a large raster-sized input, its exact vector tightening and the
paper's pixel method (the `raster` package) side by side, with their difference.

When the `raster` package of this checkout offers ``rasterize`` and ``tighten``, the figure has four
panels: (a) the input image, (b) the exact vector tightening, (c) the pixel flow's result and (d) where the
two differ, with the symmetric difference (pixels, and as a share of the mortar), the Hausdorff distance
between the boundaries and the component and hole counts of both. Without it, the third panel shows the
vector tightening started from the input instead, and says so.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import shapely
from matplotlib.colors import ListedColormap
from scipy.spatial import cKDTree

from _style import (BLACK, COLORS, LIGHT, caption, counts, draw_loops, fill, frame, new_figure, save, stats_label,
                    vt)

__all__ = ["draw_raster_figure", "raster_module"]

#: Both sides start the flow from the core, as the paper's implementation does.
INIT = "core"
# Steps a level: None is `raster.tighten`'s default, until the fronts rest (with a safety cap). The
# paper's 100 leave the long straight tight segments tens of pixels short of where they settle.
ITERATIONS = None


def raster_module():
    """The `raster` package if it offers the paper's flow (``rasterize`` and ``tighten``), else None."""
    try:
        import raster
    except ImportError:
        return None
    return raster if all(hasattr(raster, name) for name in ("rasterize", "tighten", "contours")) else None


def _rasterize(rmod, geom, shape):
    """Mask of ``geom`` on a grid of ``shape`` (rows, cols) with unit pixels, its bottom-left corner at (0, 0)."""
    rows, cols = shape
    grid = rmod.Grid(0.0, float(rows), 1.0, (rows, cols))
    return rmod.rasterize(geom, grid)


def _boundary_points(geom, step: float) -> np.ndarray:
    if geom.is_empty:
        return np.zeros((0, 2))
    return shapely.get_coordinates(shapely.segmentize(geom.boundary, step))


def hausdorff(a, b, step: float = 0.5) -> float:
    """Hausdorff distance between the boundaries of two polygons, both sampled every ``step``."""
    pa, pb = _boundary_points(a, step), _boundary_points(b, step)
    if len(pa) == 0 or len(pb) == 0:
        return float("inf") if len(pa) or len(pb) else 0.0
    return float(max(cKDTree(pb).query(pa)[0].max(), cKDTree(pa).query(pb)[0].max()))


def draw_raster_figure(outdir, *, name: str, title: str, shape, size: tuple[int, int], r: float,
                       scale: float = 1.0, svg: bool = False) -> list[Path]:
    """Draw one raster-example figure.

    Parameters
    ----------
    shape : callable(scale) -> Polygon or MultiPolygon
        The input in pixel coordinates (y up) at ``scale``.
    size : (width, height)
        The image size in pixels at scale 1 (the paper's).
    r : float
        The radius in pixels at scale 1; both are multiplied by ``scale`` (for quick tests).
    """
    W, H = round(size[0] * scale), round(size[1] * scale)
    rs = r * scale
    S = shape(scale)
    t0 = time.perf_counter()
    T = vt.tighten(S, rs, init=INIT)
    t_vec = time.perf_counter() - t0
    mortar = vt.mortar(S, rs)
    rmod = raster_module()
    if rmod is None:
        fig, axes = new_figure(1, 3, panel=(4.6, 4.6 * H / W + 0.3))
        a, b, c = axes[0]
    else:
        fig, axes = new_figure(2, 2, panel=(5.4, 5.4 * H / W + 0.45))
        a, b, c, d = axes.flat
    fill(b, mortar, LIGHT)
    fill(b, T.geometry, "#3a3a3a")
    draw_loops(b, T.loops, tolerance=T.tolerance, color=COLORS["tight"], linewidth=1.2)
    b.set_title(f"(b) exact vector tightening, init={INIT!r} ({t_vec:.1f} s)")
    caption(b, stats_label(T))
    if rmod is None:
        fill(a, S, BLACK)
        a.set_title(f"(a) input, {W} × {H} px, r = {rs:g} px")
        caption(a, stats_label(S, rs))
        Ti = vt.tighten(S, rs, init="input")
        fill(c, mortar, LIGHT)
        fill(c, Ti.geometry, "#3a3a3a")
        draw_loops(c, Ti.loops, tolerance=Ti.tolerance, color=COLORS["tight"], linewidth=1.2)
        c.set_title("(c) vector tightening, init='input'")
        caption(c, stats_label(Ti) + "\n(raster package not available: pixel flow not drawn)")
    else:
        _raster_panels(rmod, a, c, d, S, T, rs, (W, H))
    for ax in axes.flat:
        frame(ax, (0, 0, W, H), 0.0, box=True)
    fig.suptitle(title)
    return save(fig, outdir, name, svg=svg)


def _image(ax, mask, extent, colors, **kwargs):
    ax.imshow(mask.astype(np.uint8), origin="upper", extent=extent, cmap=ListedColormap(colors),
              vmin=0, vmax=len(colors) - 1, interpolation="nearest", **kwargs)


def _raster_panels(rmod, a, c, d, S, T, r, size):
    W, H = size
    mask, grid = _rasterize(rmod, S, (H, W))
    x0, y0, x1, y1 = grid.bounds
    extent = (x0, x1, y0, y1)
    _image(a, mask, extent, ["white", BLACK])
    a.set_title(f"(a) input image, {W} × {H} px, r = {r:g} px")
    caption(a, stats_label(S, r) + f"\n{int(mask.sum())} pixels inside")
    t0 = time.perf_counter()
    res = rmod.tighten(mask, r, init=INIT, iterations=ITERATIONS)
    t_ras = time.perf_counter() - t0
    C = rmod.contours(res, grid)
    _image(c, res.mortar, extent, ["white", LIGHT])
    _image(c, res.mask, extent, [(1, 1, 1, 0), "#3a3a3a"])
    fill(c, C, "none", edge=COLORS["raster"], lw=1.2)
    levels = getattr(res, "levels", None)
    steps = sum(getattr(res, "iterations", []) or [])
    c.set_title(f"(c) pixel flow (paper §3), init={INIT!r} ({t_ras:.1f} s"
                + (f", {levels} levels, {steps} steps)" if levels else ")"))
    caption(c, f"perimeter {C.length:.1f} (sub-pixel contour)\n{counts(vt.n_components(C), vt.n_holes(C))}")
    vec_mask, _ = _rasterize(rmod, T.geometry, (H, W))
    only_vec = vec_mask & ~res.mask
    only_ras = res.mask & ~vec_mask
    diff = np.zeros(mask.shape, dtype=np.uint8)
    diff[vec_mask & res.mask] = 1
    diff[only_vec] = 2
    diff[only_ras] = 3
    _image(d, diff, extent, ["white", "#d9d9d9", COLORS["tight"], COLORS["raster"]])
    draw_loops(d, T.loops, tolerance=T.tolerance, color=COLORS["tight"], linewidth=0.7)
    fill(d, C, "none", edge=COLORS["raster"], lw=0.7)
    n_diff = int(only_vec.sum() + only_ras.sum())
    n_mortar = int(res.mortar.sum())
    h = hausdorff(T.geometry, C)
    same = (T.n_components, T.n_holes) == (vt.n_components(C), vt.n_holes(C))
    d.set_title("(d) vector only (red), pixel flow only (blue), both (grey)")
    caption(d, f"differ in {n_diff} px = {100 * n_diff / max(n_mortar, 1):.1f} % of the mortar's "
               f"{n_mortar} px; Hausdorff {h:.1f} px\n"
               f"components/holes: vector {T.n_components}/{T.n_holes}, pixel {vt.n_components(C)}/"
               f"{vt.n_holes(C)}" + (" (same)" if same else " (differ)"))
