"""The input shapes of the figures, drawn from scratch for this project.

Each function returns a valid shapely (Multi)Polygon with counter-clockwise exteriors. Sizes are chosen
so that the stated radius makes every feature show a different behaviour.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Point, Polygon, box
from shapely.affinity import rotate, translate

__all__ = [
    "FIG1_R",
    "blob",
    "fig1_shape",
    "disk",
]

#: The radius used with `fig1_shape` (Figures 1–4).
FIG1_R = 1.0


def disk(x: float, y: float, radius: float, n: int = 96) -> Polygon:
    """A regular ``n``-gon inscribed in the circle of centre (x, y)."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return Polygon(np.column_stack([x + radius * np.cos(t), y + radius * np.sin(t)]))


def blob(x: float, y: float, radius: float, harmonics, n: int = 160, phase: float = 0.0) -> Polygon:
    """A star-shaped smooth blob: radius ``radius · (1 + Σ a·cos(k·t + p))`` for ``(k, a, p)`` in harmonics."""
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False) + phase
    rho = np.full_like(t, 1.0)
    for k, a, p in harmonics:
        rho += a * np.cos(k * t + p)
    rho *= radius
    return Polygon(np.column_stack([x + rho * np.cos(t), y + rho * np.sin(t)]))


def _clean(geom):
    geom = shapely.make_valid(geom)
    polys = [p for p in shapely.get_parts(geom) if p.geom_type == "Polygon" and p.area > 0]
    return shapely.orient_polygons(shapely.union_all(polys), exterior_cw=False)


def fig1_shape():
    """The set S of Figures 1–4 (use with r = `FIG1_R` = 1).

    A block with a sharp spike, a crack narrower than 2r, a small hole (filled by filleting) and a larger
    square hole (kept), a thin bar to a round lobe (cut by shrinking), a second block across a gap
    narrower than 2r (bridged by growing) and a small island (removed by shrinking).
    """
    body = Polygon([(0, 0), (12, 0), (12, 8), (7.2, 8), (5.6, 11.5), (4.0, 8), (0, 8)])
    body = body.difference(box(7.5, 3.6, 12.5, 4.4))            # crack, 0.8 wide
    body = body.difference(disk(2.2, 5.8, 0.6, 48))              # small hole
    body = body.difference(box(3.5, 1.4, 6.8, 4.6))              # square hole, kept
    bar = box(-3.2, 4.2, 0.1, 5.0)                               # thin bar, 0.8 wide
    lobe = disk(-5.0, 4.6, 2.2)
    block = Polygon([(13.0, 0), (17.0, 0), (17.0, 3.0), (15.0, 6.0), (13.0, 6.0)])   # gap of 1.0
    island = disk(15.6, 8.6, 0.75, 48)                           # smaller than r: vanishes
    return _clean(shapely.union_all([body, bar, lobe, block, island]))
