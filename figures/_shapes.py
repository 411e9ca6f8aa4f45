"""The input shapes of the figures, drawn from scratch for this project.

Each function returns a valid shapely (Multi)Polygon with counter-clockwise exteriors. Sizes are chosen
so that the stated radius makes every feature show a different behaviour.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon, box
import shapely.affinity

__all__ = [
    "FIG1_R",
    "blob",
    "coastline",
    "disk",
    "fig1_shape",
    "turtle",
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


def coastline(scale: float = 1.0):
    """A map-like input for the paper's first raster example: 1102 × 832 px, use r = 40 px.

    A wavy landmass with a fjord, a narrow lake, small and large lakes, a thin peninsula ending in a
    headland, an island across a narrow channel and islets of several sizes. Coordinates are pixels
    (y up) times ``scale``.
    """
    land = blob(440, 430, 300, [(3, 0.10, 0.3), (5, 0.06, 1.1), (9, 0.035, 0.2), (17, 0.02, 2.0),
                                (29, 0.012, 0.5)], n=900)
    fjord = Polygon([(700, 455), (700, 495), (540, 505), (380, 470), (380, 450), (540, 480)])  # ~25–45 wide
    land = land.difference(fjord)
    land = land.difference(disk(300, 300, 28, 64))                 # lake smaller than r: filled
    land = land.difference(blob(330, 560, 85, [(2, 0.15, 0.0), (3, 0.08, 1.0)], n=200))   # lake, kept
    land = land.difference(Polygon([(480, 250), (640, 300), (630, 330), (470, 280)]))     # narrow lake
    peninsula = Polygon([(600, 650), (760, 760), (740, 790), (580, 680)])                 # ~36 wide
    headland = blob(790, 760, 62, [(3, 0.12, 0.4)], n=160)
    island = blob(930, 420, 120, [(2, 0.12, 0.8), (5, 0.06, 0.0), (11, 0.03, 1.0)], n=400)
    islets = [disk(1000, 700, 24, 48), disk(1010, 150, 58, 96), disk(180, 90, 18, 48),
              blob(160, 760, 45, [(3, 0.3, 0.0)], n=120)]
    S = _clean(shapely.union_all([land, peninsula, headland, island, *islets]))
    S = S.intersection(box(5, 5, 1097, 827))
    return shapely.affinity.scale(S, scale, scale, origin=(0, 0)) if scale != 1.0 else S


def _ellipse(x: float, y: float, a: float, b: float, angle: float = 0.0, n: int = 160) -> Polygon:
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    e = Polygon(np.column_stack([x + a * np.cos(t), y + b * np.sin(t)]))
    return shapely.affinity.rotate(e, angle, origin=(x, y)) if angle else e


def turtle(scale: float = 1.0):
    """An input for the paper's second raster example: 1050 × 825 px, use r = 75 px.

    A turtle: a wavy shell with one lake larger than r (kept) and two smaller (filled), four thick legs,
    a head on a neck narrower than 2r, a thin pointed tail and a small eye. Coordinates are pixels (y up)
    times ``scale``.
    """
    t = np.linspace(0.0, 2.0 * np.pi, 720, endpoint=False)
    wobble = 1.0 + 0.025 * np.cos(14 * t) + 0.015 * np.cos(23 * t + 0.4)
    shell = Polygon(np.column_stack([470 + 320 * wobble * np.cos(t), 415 + 270 * wobble * np.sin(t)]))
    legs = [_ellipse(250, 160, 105, 85, -35), _ellipse(690, 160, 105, 85, 35),
            _ellipse(250, 670, 105, 85, 35), _ellipse(690, 670, 105, 85, -35)]
    neck = box(770, 380, 850, 470)                                           # 90 wide
    head = disk(935, 430, 105, 200)
    tail = Polygon([(160, 395), (40, 440), (160, 445)])
    S = shapely.union_all([shell, *legs, neck, head, tail])
    S = S.difference(blob(420, 415, 95, [(3, 0.07, 0.5)], n=200))            # lake, kept
    S = S.difference(disk(640, 320, 38, 64)).difference(disk(640, 510, 30, 64))   # small lakes, filled
    S = S.difference(disk(1005, 470, 14, 48))                                # eye, filled
    S = _clean(S)
    return shapely.affinity.scale(S, scale, scale, origin=(0, 0)) if scale != 1.0 else S
