"""Every numerical tolerance of vectortighten, in one place.

Lengths are given either relative to the radius ``r`` (``*_R``) or relative to the size of the shape
(``*_SCALE``: the largest side of its bounding box). Nothing else in the package writes a bare epsilon.

Far from the origin the size alone is not enough: a shape of size 10 at 1e12 has coordinates that are
multiples of 1.2e-4, and every length measured on it carries that rounding. `resolution_scale` is the
scale that the checks of a result (`Tightening.verify`, the final check of `tighten`) are relative to.
"""

import math

__all__ = [
    "ANGLE_ZERO",
    "CENTER_SEARCH_R",
    "CENTRE_ROUNDING_R",
    "CORNER_ANGLE",
    "DEFAULT_TOLERANCE_R",
    "DOMAIN_CHORD_R",
    "EXACT_CHORD_R",
    "GUIDE_MISSING_R",
    "MAX_QUAD_SEGS",
    "OBSTACLE_SAG_R",
    "PENETRATION_R",
    "ROUNDING_ULPS",
    "SPECK_SCALE",
    "THICKEN_R",
    "TOUCH_SCALE",
    "VERIFY_DEPTH_R",
    "ZERO_SCALE",
    "resolution_scale",
    "rounding_length",
]

#: Default ``tolerance`` of every function that samples circular arcs: the largest distance between an arc
#: of radius r and the chords that replace it, as a fraction of r.  1e-5·r gives 176 segments a quarter
#: circle (shapely's own default of 8 is a chord error of about 0.005·r).
DEFAULT_TOLERANCE_R = 1e-5

#: Chord error, as a fraction of r, of the shrunk and grown polygons that the exact engine checks its loops
#: against. Their vertices only lead to the exact arc centres, which are solved for from S's own features;
#: their flat parts are exact offset lines; only their arcs around S's vertices are chords, and the
#: penetration allowance (`PENETRATION_R`) is widened by twice this. A finer value costs GEOS dearly on
#: outlines with many corners (a 1000-vertex pixel staircase: 6.4 s at 1e-7, 0.4 s at 1e-5).
EXACT_CHORD_R = 1e-5

#: Upper bound on the ``quad_segs`` derived from a tolerance (a chord error of about 4.6e-8·r).
MAX_QUAD_SEGS = 4096

#: Two lengths that differ by less than this fraction of the shape's size are equal (rounding only).
ZERO_SCALE = 1e-12

#: Exact tight loops closer than this fraction of the shape's size touch; the engine performs surgery there.
TOUCH_SCALE = 1e-9

#: A sine of a turning angle below this marks a straight (collinear) vertex, not a corner.
ANGLE_ZERO = 1e-12

#: A straight piece or arc that comes closer than r to a flat part of the core or of the anticore by more
#: than this fraction of r (in addition to the chord error of the polygons that stand for them) is not
#: tight; the engine repairs it. GEOS places offset vertices to a few 1e-7·r, hence the margin.
PENETRATION_R = 4e-6

#: The mortar is thickened by this fraction of r (at least 20 chord errors) before it is triangulated, so
#: that its zero-width parts, where the boundary of the shape is left unchanged, have room for a path.
THICKEN_R = 2e-4

#: A vertex of a buffered shrink or grow within this fraction of r (on top of four chord sags) of a corner
#: of S's exact offsets is moved onto it (`centers.snap_window`, which also takes GUIDE_MISSING_R·r at
#: least: GEOS simplifies its input by up to about r/100).
CENTER_SEARCH_R = 1e-4

#: Chord error, as a fraction of r, of the core and fillet from which the free space (the mortar thickened
#: by `THICKEN_R`) is built. They only guide the search for each loop's homotopy class, and every contact
#: is then decided by the exact centres; the chords must stay well inside the thickening (here half of it)
#: so that the free space still holds the exact mortar. The free space's size, and so the cost of
#: triangulating it and of the sleeves and funnels on it, grows as the inverse square root of this.
DOMAIN_CHORD_R = 0.5 * THICKEN_R

# The exact offsets' arcs stand in the finish's proximity index as chords with at most this sag (relative
# to r); the queries are drawn this much wider and every find is decided by the exact distance to the arc,
# so the sag costs only candidates, never exactness.
OBSTACLE_SAG_R = 1e-4

# The search's guide (GEOS's core and fillet) is given back the exact offset pieces that lie farther than
# this (relative to r) from GEOS's buffers: parts exactly 2r wide, and gaps exactly 2r wide. Nearer ones
# are GEOS's simplification (up to about r/100), which the exact finish corrects on its own.
GUIDE_MISSING_R = 0.02

# `verify()` allows a loop's disk to sit this far (relative to r) from the exact corner it stands for, and
# discounts that offset from the loop's depth: an acute corner's position is ill-conditioned (the offset
# lines meet at the corner's angle), so two exact solvers agree only to rounding over that angle.
CENTRE_ROUNDING_R = 1e-6

# `verify()` reports a loop that comes nearer than r to the exact shrink of S or of its complement by more
# than this (relative to r; at least a few units in the last place of the coordinates).
VERIFY_DEPTH_R = 1e-9
#: A join of a loop whose tangents differ by more than this (radians), beyond what the rounding of the
#: segments' end points explains (see `rounding_length`), is a corner.
CORNER_ANGLE = 1e-7

#: Units in the last place of the largest coordinate by which a point computed from the coordinates (a
#: tangent point, a transformed vertex: a few operations each within half an ulp) may be off.
ROUNDING_ULPS = 16.0


def resolution_scale(size: float, largest: float) -> float:
    """The scale a result is judged at: ``max(size, ROUNDING_ULPS·ulp(largest) / ZERO_SCALE)``.

    A length below ``ZERO_SCALE`` of it is rounding. Near the origin this is the size of the shape; far
    from it (``largest`` is the largest absolute coordinate), the scale at which `ZERO_SCALE` of it is
    `ROUNDING_ULPS` units in the last place of the coordinates.

    Parameters
    ----------
    size : float
        The largest side of the shape's bounding box, in the shape's units.
    largest : float
        The largest absolute coordinate, in the shape's units.

    Returns
    -------
    float
        A length in the shape's units, ``>= size``.

    Examples
    --------
    >>> resolution_scale(10.0, 5.0)                  # near the origin: the size
    10.0
    >>> resolution_scale(10.0, 1e12) > 1e9           # at 1e12 an ulp is 1.2e-4
    True
    """
    ulp = math.ulp(abs(float(largest))) if math.isfinite(largest) else math.inf
    return max(float(size), ROUNDING_ULPS * ulp / ZERO_SCALE)


def rounding_length(size: float, largest: float) -> float:
    """Lengths measured on a result below this are rounding: ``ZERO_SCALE·resolution_scale(size, largest)``.

    A segment of length L has a direction known to about ``rounding_length / L`` radians, so that is what
    a join between it and its neighbour may miss tangency by (`Loop.is_g1` with ``rounding``).

    Examples
    --------
    >>> rounding_length(10.0, 5.0)
    1e-11
    >>> round(rounding_length(10.0, 1e12) / math.ulp(1e12))   # ROUNDING_ULPS ulps of the coordinates
    16
    """
    return ZERO_SCALE * resolution_scale(size, largest)

#: A tangent of a tight loop shorter than this fraction of the loop's extent is a speck of rounding (the
#: tangents between nearly coincident disks, 1e-16–1e-10 long: their directions are noise). Between two
#: disks of one side the disks are merged into one arc; between opposite sides the tangent is dropped.
#: Either way the loop stays G1 and moves by less than the speck (the loop's closing tolerance is 1e-9).
SPECK_SCALE = 1e-10
