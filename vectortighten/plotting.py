"""Drawing shapes, loops and tightenings with matplotlib (the only module of the package that imports it).

matplotlib is imported when a function here is first called, never at package import.
"""

from __future__ import annotations

import numpy as np
import shapely

__all__ = ["COLORS", "draw_geometry", "draw_loops", "draw_tightening", "new_axes"]

#: The palette shared by the demo, the figures and the comparison plots.
COLORS = {
    "input": "#1f3b73",
    "core": "#2b2b2b",
    "mortar": "#c9c9c9",
    "anticore": "#ffffff",
    "tight": "#d1495b",
    "raster": "#2e86ab",
    "fillet": "#8a8a8a",
}


def new_axes(figsize=(6.0, 6.0)):
    """A figure and axes with equal aspect and no frame."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=figsize)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return fig, ax


def _path_of(geom):
    from matplotlib.path import Path

    verts, codes = [], []
    for poly in shapely.get_parts(geom):
        if poly.is_empty or poly.geom_type != "Polygon":
            continue
        for ring in [poly.exterior, *poly.interiors]:
            c = np.asarray(ring.coords)
            verts.append(c)
            codes += [Path.MOVETO] + [Path.LINETO] * (len(c) - 2) + [Path.CLOSEPOLY]
    if not verts:
        return None
    return Path(np.concatenate(verts), codes)


def draw_geometry(ax, geom, *, facecolor="none", edgecolor="black", linewidth=1.0, **kwargs):
    """Draw a shapely (Multi)Polygon, holes included, as one patch; returns the patch (or None if empty)."""
    from matplotlib.patches import PathPatch

    path = _path_of(geom)
    if path is None:
        return None
    patch = PathPatch(path, facecolor=facecolor, edgecolor=edgecolor, linewidth=linewidth, **kwargs)
    ax.add_patch(patch)
    ax.update_datalim(path.vertices)
    ax.autoscale_view()
    return patch


def draw_loops(ax, loops, *, tolerance: float, color=COLORS["tight"], linewidth=2.0, centers=False, **kwargs):
    """Draw exact loops (sampled within ``tolerance``); with ``centers`` mark their arc centres."""
    for loop in loops:
        pts = loop.sample(tolerance)
        ax.plot(pts[:, 0], pts[:, 1], color=color, linewidth=linewidth, **kwargs)
        if centers:
            c = np.array([a.center for a in loop.arcs]) if loop.arcs else np.zeros((0, 2))
            ax.plot(c[:, 0], c[:, 1], "+", color=color, markersize=4)
    ax.autoscale_view()


def draw_tightening(ax, T, *, show_input=True, show_mortar=True):
    """The paper's picture: mortar grey, core dark, the input's outline and the tightening's boundary."""
    if show_mortar and not T.mortar.is_empty:
        draw_geometry(ax, T.mortar, facecolor=COLORS["mortar"], edgecolor="none")
    if not T.core.is_empty:
        draw_geometry(ax, T.core, facecolor=COLORS["core"], edgecolor="none", alpha=0.85)
    if show_input:
        draw_geometry(ax, T.shape, edgecolor=COLORS["input"], linewidth=0.8, linestyle="--")
    draw_loops(ax, T.loops, tolerance=T.tolerance)
