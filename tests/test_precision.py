"""Checks of a result far from the origin (issue 23): tolerances relative to the coordinates' rounding.

At 1e12 an ulp is 1.2e-4, at 1e15 it is 0.125: a tangent whose end points are rounded that much turns by
ulp/length, which a fixed 1e-7 rad read as a corner (and ``min_radius_of_curvature`` as 0). `verify` and
the final check of `tighten` now judge lengths and joins at `tolerances.resolution_scale`; a real defect
must still be reported there.
"""

import math

import numpy as np
import pytest
from shapely import affinity
from shapely.geometry import Polygon, box

import vectortighten as vt
from vectortighten.curves import Loop
from vectortighten.tolerances import ZERO_SCALE, resolution_scale, rounding_length

OFFSETS = [1e6, 1e9, 1e12, 1e15]


def star(k=25, inner=0.5):
    th = np.arange(2 * k) * math.pi / k
    rad = np.where(np.arange(2 * k) % 2 == 0, 1.0, inner)
    return Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))


def ngon(n):
    return Polygon([(math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)) for k in range(n)])


def holed():
    return box(0, 0, 10, 10).difference(box(3, 3, 7, 7)).difference(box(1, 1, 2, 8.5))


# (shape, r): the general engine (stars, holes) and the fast path (L, a 64-gon).
SHAPES = {
    "star-fine": (star(), 0.1),
    "star": (star(), 0.3),
    "L": (Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)]), 1.0),
    "holes": (holed(), 0.6),
    "64-gon": (ngon(64), 0.5),
}


def placed(S, r, offset):
    """S scaled so that r stays twice the smallest radius doubles resolve there, then moved to offset."""
    s = max(1.0, 2e-9 * offset)
    return affinity.translate(affinity.scale(S, s, s, origin=(0, 0)), offset, offset), r * s, s


@pytest.mark.parametrize("offset", OFFSETS)
@pytest.mark.parametrize("name", sorted(SHAPES))
def test_far_from_origin_results_verify_clean(name, offset):
    S0, r0 = SHAPES[name]
    S, r, s = placed(S0, r0, offset)
    T = vt.tighten(S, r)                      # a ConvergenceWarning would fail the test (warnings are errors)
    assert T.converged
    assert T.verify() == []
    assert T.min_radius_of_curvature >= r * (1 - 1e-9)
    near = vt.tighten(S0, r0)
    # the same tightening, up to the rounding of the coordinates there
    assert T.area / s ** 2 == pytest.approx(near.area, rel=1e-6)
    assert T.perimeter / s == pytest.approx(near.perimeter, rel=1e-6)


@pytest.mark.parametrize("init", ["input", "mason"])
@pytest.mark.parametrize("offset", [1e9, 1e15])
def test_far_from_origin_other_inits_verify_clean(init, offset):
    S, r, _ = placed(star(), 0.3, offset)
    T = vt.tighten(S, r, init=init)
    assert T.converged and T.verify() == []


@pytest.mark.parametrize("offset", OFFSETS)
def test_a_vertex_moved_into_the_core_is_still_reported(offset):
    S, r, s = placed(star(), 0.3, offset)
    T = vt.tighten(S, r)
    assert T.verify() == []
    ring = np.asarray(T.geometry.exterior.coords)[:-1]
    centre = np.array([offset, offset])
    k = int(np.argmax(np.hypot(*(ring - centre).T)))   # a vertex on an outer arc: move it to the centre's
    ring[k] = centre + 0.3 * (ring[k] - centre)        # side, deep into the core (by about 0.7 of the radius)
    T.geometry = Polygon(ring)
    problems = T.verify()
    # (a) is decided on the exact offsets: the notch holds no piece of S↓r, and the geometry is no
    # longer the loops' region, which verify() reports whatever the offset.
    assert any(p.startswith("(a) the geometry differs from its loops") for p in problems), problems


@pytest.mark.parametrize("offset", OFFSETS)
def test_a_real_corner_is_still_reported(offset):
    """A tangent's end point moved by 1e-3·r (a kink of about 1e-3 rad): a corner at every offset."""
    S, r, _ = placed(star(), 0.3, offset)
    T = vt.tighten(S, r)
    loop = T.loops[0]
    data = loop._data.copy()
    seg = np.flatnonzero(~loop._arc)
    i = seg[np.argmax(np.hypot(data[seg, 2] - data[seg, 0], data[seg, 3] - data[seg, 1]))]
    data[i, 2:4] += 1e-3 * r * np.array([0.6, 0.8])
    T.loops = [Loop._from_arrays(loop._arc.copy(), data)] + T.loops[1:]
    problems = T.verify()
    assert any(p.startswith("(c)") and "corner" in p for p in problems), problems
    assert T.loops[0].min_radius_of_curvature == 0.0


def test_resolution_scale_is_the_size_near_the_origin_and_the_ulps_far_from_it():
    assert resolution_scale(10.0, 10.0) == 10.0
    assert rounding_length(10.0, 10.0) == ZERO_SCALE * 10.0
    for big in (1e9, 1e12, 1e15):
        assert rounding_length(10.0, big) == pytest.approx(16 * math.ulp(big))
        assert resolution_scale(10.0, big) > 10.0


# ---------------------------------------------------------------------------------------------------------
# Tiny pieces (1e-16–1e-10 long) are merged or dropped where loops are assembled, exactly
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", [64, 256, 1024])
def test_polygon_at_its_inradius_is_one_circle(n):
    """The shrink is a point: n nearly coincident disks (tangents of 0–1e-15) merge into one full arc."""
    r = math.cos(math.pi / n)
    T = vt.tighten(ngon(n), r)
    assert T.verify() == []
    assert len(T.loops) == 1 and len(T.loops[0].pieces) == 1
    arc = T.loops[0].pieces[0]
    assert arc.radius == r and arc.sweep == pytest.approx(2 * math.pi, abs=1e-12)
    assert T.area == pytest.approx(math.pi * r * r, rel=1e-12)
    assert T.min_radius_of_curvature == r


def disk_loop(c, s, r):
    from vectortighten.curves import arc_sweeps, tangent_directions

    c, s = np.asarray(c, float), np.asarray(s, float)
    phi, length, ok = tangent_directions(c, s, r)
    assert ok.all()
    return c, s, phi, length, arc_sweeps(phi, s, None)


@pytest.mark.parametrize("gap", [1e-16, 1e-13, 1e-11])
def test_speck_between_disks_of_one_side_merges_them_g1(gap):
    """A stadium with a third disk ``gap`` from one end: the two end disks become one arc."""
    c, s, phi, length, sweeps = disk_loop([(0, 0), (gap, 0), (4, 0)], [1, 1, 1], 1.0)
    loop = Loop._from_disk_arrays(c, s, 1.0, phi, length, sweeps)
    kinds = [type(p).__name__ for p in loop.pieces]
    assert kinds.count("Arc") == 2 and kinds.count("Segment") == 2
    assert loop.is_g1(1e-12)
    assert loop.length == pytest.approx(2 * math.pi + 8, abs=1e-9)
    assert abs(loop.area) == pytest.approx(math.pi + 8, abs=1e-9)
    start, end = loop._ends()
    assert np.hypot(*(end - np.roll(start, -1, axis=0)).T).max() <= max(gap, 1e-15)

