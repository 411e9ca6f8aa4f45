"""Every numerical tolerance of vectortighten, in one place.

Lengths are given either relative to the radius ``r`` (``*_R``) or relative to the size of the shape
(``*_SCALE``: the largest side of its bounding box). Nothing else in the package writes a bare epsilon.
"""

__all__ = [
    "ANGLE_ZERO",
    "CENTER_SEARCH_R",
    "CENTRE_ROUNDING_R",
    "DEFAULT_TOLERANCE_R",
    "DOMAIN_CHORD_R",
    "EXACT_CHORD_R",
    "GUIDE_MISSING_R",
    "MAX_QUAD_SEGS",
    "OBSTACLE_SAG_R",
    "PENETRATION_R",
    "THICKEN_R",
    "TOUCH_SCALE",
    "VERIFY_DEPTH_R",
    "ZERO_SCALE",
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

#: Half-width of the band, as a fraction of r (on top of the chord error), in which the boundary features
#: that define an arc centre are looked for around a vertex of a buffered polygon.
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
OBSTACLE_SAG_R = 1e-6

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
