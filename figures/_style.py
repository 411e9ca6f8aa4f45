"""Shared style for the figure scripts: palette, panel set-up, labels and atomic saving.

Every ``figN_*.py`` script imports this module (it sits next to them; `make_all.py` and the tests put
this folder on ``sys.path``). matplotlib is used with the Agg backend; nothing is ever shown on screen.
"""

from __future__ import annotations

import math
import os
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import shapely  # noqa: E402

HERE = Path(__file__).resolve().parent
if str(HERE.parent) not in sys.path:          # the project root, for `import vectortighten` in a checkout
    sys.path.insert(0, str(HERE.parent))

import vectortighten as vt  # noqa: E402
from vectortighten.plotting import COLORS, draw_geometry, draw_loops  # noqa: E402

__all__ = [
    "COLORS",
    "DPI",
    "caption",
    "counts",
    "HERE",
    "BLACK",
    "GREY",
    "LIGHT",
    "draw_geometry",
    "draw_loops",
    "draw_polyline",
    "fill",
    "frame",
    "new_figure",
    "polygon_min_radius",
    "save",
    "stats_label",
    "plt",
    "vt",
]

#: Resolution of the PNG files (keeps them well under 300 KB).
DPI = 110
#: The paper's palette: black for the set shown, grey for what an operation adds or removes.
BLACK = "#111111"
GREY = "#a8a8a8"
LIGHT = "#d9d9d9"

plt.rcParams.update({
    "font.size": 9,
    "axes.titlesize": 9,
    "figure.titlesize": 11,
    "svg.fonttype": "none",
})


def new_figure(nrows: int, ncols: int, *, panel: tuple[float, float] = (4.0, 3.2)):
    """A figure with ``nrows × ncols`` frameless, equal-aspect panels of size ``panel`` (inches)."""
    fig, axes = plt.subplots(nrows, ncols, figsize=(panel[0] * ncols, panel[1] * nrows), squeeze=False,
                             layout="constrained")
    for ax in axes.flat:
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        for spine in ax.spines.values():
            spine.set_visible(False)
    return fig, axes


def frame(ax, bounds, pad: float = 0.0, *, box: bool = False) -> None:
    """Fix the panel's limits to ``bounds`` grown by ``pad``; with ``box`` draw a thin frame around it."""
    x0, y0, x1, y1 = bounds
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    for spine in ax.spines.values():
        spine.set_visible(box)
        spine.set_linewidth(0.5)
        spine.set_color("0.6")


def _path(geom):
    """A matplotlib Path of a (Multi)Polygon's rings (holes included; even-odd fill), or None if empty."""
    from matplotlib.path import Path as MplPath

    verts, codes = [], []
    for poly in shapely.get_parts(geom):
        if poly.is_empty or poly.geom_type != "Polygon":
            continue
        for ring in shapely.get_rings(poly):
            c = shapely.get_coordinates(ring)
            verts.append(c)
            codes.append(np.r_[MplPath.MOVETO, np.full(len(c) - 2, MplPath.LINETO), MplPath.CLOSEPOLY])
    if not verts:
        return None
    return MplPath(np.concatenate(verts), np.concatenate(codes).astype(MplPath.code_type))


def fill(ax, geom, color, *, edge: str | None = None, lw: float = 0.8, **kwargs):
    """Fill a shapely (Multi)Polygon (holes included), optionally with an outline; empty geometry is skipped.

    The patch is added without updating the data limits (slow for large paths): set them with `frame`.
    """
    from matplotlib.patches import PathPatch

    if geom is None or geom.is_empty:
        return None
    path = _path(geom)
    if path is None:
        return None
    patch = PathPatch(path, facecolor=color, edgecolor=edge or "none", linewidth=lw, **kwargs)
    ax.add_artist(patch)
    return patch


def draw_polyline(ax, xy, *, closed: bool = True, **kwargs):
    """Draw a polyline given as ``(n, 2)`` coordinates (closed by default)."""
    xy = np.asarray(xy, dtype=float)
    if closed and len(xy) and not np.array_equal(xy[0], xy[-1]):
        xy = np.vstack([xy, xy[:1]])
    return ax.plot(xy[:, 0], xy[:, 1], **kwargs)


def caption(ax, text: str, fontsize: float = 8) -> None:
    """Put ``text`` under the panel (as its x label, which constrained layout makes room for)."""
    ax.set_xlabel(text, fontsize=fontsize, labelpad=3)


def _fmt_radius(value: float) -> str:
    if math.isinf(value):
        return "∞"
    if value == 0.0:
        return "0 (corner)"
    return f"{value:.3g}"


#: A polygon vertex turning by more than this (radians) is a corner, not a sample of a smooth curve. The
#: figures sample circles with at least 48 vertices (7.5° a vertex).
CORNER_TURN = 0.35
#: In labels, a polygon's discrete radius estimate below this share of r is reported as a corner: the
#: figures' arcs have radius r or more (or are the input's own), and smaller estimates come from mild
#: tangent discontinuities (where an arc of the core meets an arc of the fillet) sampled finely.
CORNER_RADIUS = 0.2


def polygon_min_radius(geom, r: float | None = None) -> float:
    """Smallest radius of curvature of a polygon's boundary: 0 if it has a corner, else the discrete estimate.

    Edges shorter than 1e-4·r (or 1e-6 of the size) are merged first: GEOS overlays leave steps of about
    the chord tolerance that would otherwise read as two right-angle corners. Then a vertex whose turning
    angle exceeds `CORNER_TURN` is a corner (radius 0); elsewhere the radius is
    `vectortighten.metrics.polygon_radii_of_curvature` (the circle through a vertex and its neighbours).
    """
    from vectortighten.metrics import polygon_radii_of_curvature

    if geom.is_empty:
        return math.inf
    x0, y0, x1, y1 = geom.bounds
    eps = 1e-4 * r if r is not None else 1e-6 * max(x1 - x0, y1 - y0)
    rings = []
    for ring in shapely.get_rings(shapely.get_parts(geom)):
        c = shapely.get_coordinates(ring)[:-1]
        keep = [0]
        for i in range(1, len(c)):
            if math.hypot(*(c[i] - c[keep[-1]])) >= eps:
                keep.append(i)
        c = c[keep]
        if len(c) >= 2 and math.hypot(*(c[-1] - c[0])) < eps:
            c = c[:-1]
        if len(c) < 3:
            continue
        u = c - np.roll(c, 1, axis=0)
        v = np.roll(c, -1, axis=0) - c
        turn = np.abs(np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1)))
        if (turn > CORNER_TURN).any():
            return 0.0
        rings.append(shapely.Polygon(c))
    radii = polygon_radii_of_curvature(shapely.MultiPolygon(rings)) if rings else np.zeros(0)
    return float(radii.min()) if len(radii) else math.inf


def stats_label(obj, r: float | None = None) -> str:
    """Two lines: perimeter, minimum radius of curvature, components and holes of a result or polygon.

    ``obj`` is a `vectortighten.Tightening` (exact measures: its loops are segments and arcs) or a shapely
    (Multi)Polygon (its perimeter; the radius by `polygon_min_radius`, 0 at a corner; with ``r`` given,
    estimates below `CORNER_RADIUS`·r are reported as corners too).
    """
    if isinstance(obj, vt.Tightening):
        per, rmin, nc, nh = obj.perimeter, obj.min_radius_of_curvature, obj.n_components, obj.n_holes
    else:
        per = float(obj.length) if not obj.is_empty else 0.0
        rmin = polygon_min_radius(obj, r)
        if r is not None and rmin < CORNER_RADIUS * r:
            rmin = 0.0          # a tangent discontinuity sampled finely, not an arc
        nc, nh = vt.n_components(obj), vt.n_holes(obj)
    return f"perimeter {per:.1f}, min radius {_fmt_radius(rmin)}\n{counts(nc, nh)}"


def counts(n_components: int, n_holes: int) -> str:
    """``"3 components, 1 hole"``."""
    return (f"{n_components} component{'s' if n_components != 1 else ''}, "
            f"{n_holes} hole{'s' if n_holes != 1 else ''}")


def save(fig, outdir, name: str, *, svg: bool = False) -> list[Path]:
    """Write ``name.png`` (and ``name.svg``) into ``outdir`` atomically: temporary file, then rename.

    Returns the paths written; the figure is closed.
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    try:
        for ext in (["png", "svg"] if svg else ["png"]):
            path = outdir / f"{name}.{ext}"
            fd, tmp = tempfile.mkstemp(dir=outdir, prefix=f".{path.name}.", suffix=f".{ext}")
            os.close(fd)
            try:
                fig.savefig(tmp, dpi=DPI, bbox_inches="tight", pad_inches=0.08, facecolor="white")
                os.chmod(tmp, 0o644)
                os.replace(tmp, path)
            finally:
                if os.path.exists(tmp):
                    os.unlink(tmp)
            written.append(path)
    finally:
        plt.close(fig)
    return written


def geom_union(*geoms):
    """Union of shapely geometries, made a valid (Multi)Polygon with counter-clockwise exteriors."""
    g = shapely.union_all(list(geoms))
    g = shapely.make_valid(g)
    polys = [p for p in shapely.get_parts(g) if p.geom_type == "Polygon" and not p.is_empty]
    return shapely.orient_polygons(shapely.union_all(polys), exterior_cw=False)
