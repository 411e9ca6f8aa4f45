"""The documented limits of vectortighten: what doubles can resolve, and the caps on resources.

Two kinds of limit live here, each a named constant that messages quote:

* **Resolution.** The engine works in doubles, in a frame where the shape has unit size. A radius much
  smaller than the shape (``r < MIN_R_SIZE · size``) or than the magnitude of its coordinates
  (``r < MIN_R_MAGNITUDE · max|x|, |y|``) cannot be told apart from rounding: the engine's own
  tolerances (1e-12 of the size for equal lengths, 1e-9 for touching loops) would exceed the arcs it
  places, and results go silently empty or wrong. `tighten` refuses such a radius with an
  `InvalidRadiusError` that names `min_radius`. Likewise a chord tolerance finer than the coordinates'
  rounding or than ``MIN_TOLERANCE_R · r`` is refused (`min_tolerance`). Coordinates beyond
  ``MAX_COORDINATE`` are refused (areas would overflow).
* **Resources.** ``MAX_SVG_ELEMENTS`` drawn elements after ``<use>`` references are expanded,
  ``MAX_PIXELS`` decoded pixels of an image (all pages), and ``MAX_OUTPUT_VERTICES`` vertices of a
  sampled output (an arc of radius r sampled to tolerance t has about ``π/√(2t/r)`` chords a full turn).
  An input beyond a cap raises `ResourceLimitError` before the memory is spent.

Measured (shapely 2.2): a 25-pointed star is tightened right at r = 10^-8.5 of its size and fails from
10^-9 (a loop leaves the mortar; at 10^-10.5 an allocation of 50 GiB); a square is still right at 1e-11.
``MIN_R_SIZE`` keeps a margin of 10^0.5 below the star's failure.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

__all__ = [
    "MAX_COORDINATE",
    "MAX_OUTPUT_VERTICES",
    "MAX_PIXELS",
    "MAX_SVG_ELEMENTS",
    "MIN_R_MAGNITUDE",
    "MIN_R_SIZE",
    "MIN_TOLERANCE_R",
    "chords_per_turn",
    "min_radius",
    "min_tolerance",
]

#: Smallest radius, as a fraction of the shape's size (the largest side of its bounding box).
MIN_R_SIZE = 1e-8

#: Smallest radius, as a fraction of the largest absolute coordinate: the default tolerance (1e-5·r) is
#: then at least 1e-15 of it, about 4.5 units in the last place.
MIN_R_MAGNITUDE = 1e-10

#: Smallest chord tolerance as a fraction of r: about 7·10^5 chords a full turn.
MIN_TOLERANCE_R = 1e-11

#: Smallest chord tolerance as a fraction of the largest absolute coordinate (4.5 units in the last place).
MIN_TOLERANCE_MAGNITUDE = 1e-15

#: Largest absolute coordinate accepted (the square of a size must stay finite with a wide margin).
MAX_COORDINATE = 1e100

#: Largest number of drawn SVG elements once every ``<use>`` is expanded (nested uses multiply).
MAX_SVG_ELEMENTS = 1_000_000

#: Largest number of decoded pixels of an image, all pages counted (8192 × 8192); the same as
#: ``raster.io.MAX_PIXELS``, which the image readers apply to the size an image declares before decoding.
MAX_PIXELS = 8192 * 8192

#: Largest number of vertices of a sampled output geometry.
MAX_OUTPUT_VERTICES = 20_000_000


def _extent(S) -> tuple[float, float]:
    """The size of ``S`` (largest side of its bounding box) and its largest absolute coordinate."""
    x0, y0, x1, y1 = S.bounds
    return max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1))


def min_radius(S) -> float:
    """The smallest radius `tighten` accepts for the shape ``S``, in its units.

    ``max(MIN_R_SIZE · size, MIN_R_MAGNITUDE · magnitude)`` where size is the largest side of the bounding
    box and magnitude the largest absolute coordinate.

    Parameters
    ----------
    S : shapely geometry
        The shape (non-empty).

    Returns
    -------
    float
        The limit, in the units of S.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> min_radius(box(0, 0, 10, 10))
    1e-07
    >>> round(min_radius(box(1e6, 1e6, 1e6 + 10, 1e6 + 10)), 12)   # far from the origin: 1e6 counts
    0.000100001
    """
    size, magnitude = _extent(S)
    return max(MIN_R_SIZE * size, MIN_R_MAGNITUDE * magnitude)


def min_tolerance(S, r: float) -> float:
    """The smallest chord tolerance `tighten` accepts for ``S`` at radius ``r``, in the units of S.

    ``max(MIN_TOLERANCE_R · r, MIN_TOLERANCE_MAGNITUDE · magnitude)``: finer chords than about 7·10^5 a
    full turn, or than a few units in the last place of the coordinates, cannot be written.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> min_tolerance(box(0, 0, 1, 1), 0.1)
    1e-12
    """
    _, magnitude = _extent(S)
    return max(MIN_TOLERANCE_R * r, MIN_TOLERANCE_MAGNITUDE * magnitude)


def chords_per_turn(r: float, tolerance: float) -> int:
    """Number of chords a full circle of radius ``r`` is sampled with at chord error ``tolerance``.

    A chord spanning the angle a lies ``r·(1 − cos(a/2))`` from its arc at most.

    Examples
    --------
    >>> chords_per_turn(1.0, 1e-5)
    703
    """
    step = 2.0 * math.acos(max(-1.0, 1.0 - tolerance / r))
    return max(1, math.ceil(2.0 * math.pi / step)) if step > 0 else 2**62


def coordinate_magnitude(S) -> float:
    """The largest absolute coordinate of ``S`` (0 for an empty geometry)."""
    c = shapely.get_coordinates(S)
    return float(np.abs(c).max()) if len(c) else 0.0
