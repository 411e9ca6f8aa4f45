import math

import numpy as np
import pytest
import shapely
from hypothesis import given
from hypothesis import strategies as st

from vectortighten import Arc, Loop, Segment, Side, common_tangents, disk_tangent
from vectortighten.curves import arc_sweeps, tangent_directions


def square(a=2.0):
    return Loop([Segment((0, 0), (a, 0)), Segment((a, 0), (a, a)), Segment((a, a), (0, a)), Segment((0, a), (0, 0))])


def test_segment_protocol():
    s = Segment((1, 2), (4, 6))
    assert s.length == 5.0
    assert s.point_at(0.5) == (2.5, 4.0)
    assert s.tangent_at() == (0.6, 0.8)
    assert s.reversed() == Segment((4, 6), (1, 2))
    assert s.curvature == 0.0
    assert s.bounds == (1, 2, 4, 6)


def test_arc_protocol():
    a = Arc((1.0, 1.0), 2.0, 0.0, math.pi / 2)
    assert a.length == pytest.approx(math.pi)
    assert a.start == pytest.approx((3.0, 1.0))
    assert a.end == pytest.approx((1.0, 3.0))
    assert a.point_at(0.5) == pytest.approx((1 + math.sqrt(2), 1 + math.sqrt(2)))
    assert a.tangent_at(0.0) == pytest.approx((0.0, 1.0))
    assert a.curvature == 0.5 and a.side is Side.CORE
    b = a.reversed()
    assert b.start == pytest.approx(a.end) and b.end == pytest.approx(a.start) and b.side is Side.ANTICORE
    assert a.bounds == pytest.approx((1.0, 1.0, 3.0, 3.0))
    with pytest.raises(ValueError, match="radius"):
        Arc((0, 0), 0.0, 0.0, 1.0)


def test_arc_bounds_include_extremes():
    a = Arc((0.0, 0.0), 1.0, -math.pi / 4, math.pi / 2)   # passes through (1, 0)
    assert a.bounds == pytest.approx((math.cos(math.pi / 4), -math.sin(math.pi / 4), 1.0, math.sin(math.pi / 4)))


def test_square_loop_length_area_orientation():
    sq = square(3.0)
    assert sq.length == 12.0 and sq.area == 9.0 and sq.is_ccw
    rev = sq.reversed()
    assert rev.area == -9.0 and rev.length == 12.0
    assert not sq.is_g1()
    assert sq.min_radius_of_curvature == 0.0


def test_loop_must_close():
    with pytest.raises(ValueError, match="not closed"):
        Loop([Segment((0, 0), (1, 0)), Segment((1, 0), (1, 1))])


@pytest.mark.parametrize("r", [0.001, 1.0, 250.0])
def test_circle_area_and_length(r):
    c = Loop.circle((3.0, -2.0), r)
    assert c.length == pytest.approx(2 * math.pi * r, rel=1e-14)
    assert c.area == pytest.approx(math.pi * r * r, rel=1e-14)
    assert c.reversed().area == pytest.approx(-math.pi * r * r, rel=1e-14)
    assert c.total_turn == pytest.approx(2 * math.pi)


def test_rounded_rectangle_closed_forms():
    # A w×h rectangle with corners rounded by r: length 2(w+h) − 8r + 2πr, area wh − (4 − π)r².
    w, h, r = 7.0, 3.0, 0.75
    loop = Loop.from_disks([(r, r), (w - r, r), (w - r, h - r), (r, h - r)], [1, 1, 1, 1], r)
    assert loop.length == pytest.approx(2 * (w + h) - 8 * r + 2 * math.pi * r, rel=1e-14)
    assert loop.area == pytest.approx(w * h - (4 - math.pi) * r * r, rel=1e-14)
    assert loop.is_g1(1e-12)
    assert loop.min_radius_of_curvature == r
    assert loop.total_turn == pytest.approx(2 * math.pi, abs=1e-12)
    assert loop.bounds == pytest.approx((0.0, 0.0, w, h))


def test_from_disks_with_a_reflex_disk():
    # Two core disks and an anticore disk dipping into the stadium between them from above.
    r = 1.0
    loop = Loop.from_disks([(0, 0), (6, 0), (3, 1.8)], [1, 1, -1], r)
    assert loop.is_g1(1e-12)
    sweeps = [p.sweep for p in loop.arcs]
    assert sum(sweeps) == pytest.approx(2 * math.pi)
    assert min(sweeps) < 0 < max(sweeps)


def test_from_disks_rejects_overlapping_opposite_disks():
    with pytest.raises(ValueError, match="no common tangent"):
        Loop.from_disks([(0, 0), (1.5, 0)], [1, -1], 1.0)


@given(st.floats(0.1, 10), st.floats(-1e3, 1e3), st.floats(-1e3, 1e3), st.floats(1e-3, 1e3))
def test_affine_scales_length_and_area(scale, dx, dy, r):
    loop = Loop.from_disks([(0, 0), (4 * r, 0), (2 * r, 3 * r)], [1, 1, 1], r)
    moved = loop.affine(scale, dx, dy)
    assert moved.length == pytest.approx(scale * loop.length, rel=1e-12)
    assert moved.area == pytest.approx(scale * scale * loop.area, rel=1e-9)


@pytest.mark.parametrize("tol", [1e-2, 1e-5])
def test_sampling_stays_within_tolerance(tol):
    r = 2.0
    loop = Loop.from_disks([(0, 0), (10, 0), (5, 6)], [1, 1, 1], r)
    pts = loop.sample(tol)
    assert np.array_equal(pts[0], pts[-1])
    ring = shapely.LinearRing(pts)
    assert ring.is_valid
    # Every sampled point is on the curve, and no chord is farther than tol from it.
    poly = shapely.Polygon(pts)
    assert abs(poly.area - loop.area) <= loop.length * tol
    mids = 0.5 * (pts[1:] + pts[:-1])
    for p in loop.arcs:
        d = np.hypot(mids[:, 0] - p.center[0], mids[:, 1] - p.center[1])
        near = np.abs(d - r) < 2 * tol
        assert (r - d[near] <= tol * (1 + 1e-9)).all()


def test_svg_path_uses_arc_commands():
    loop = Loop.from_disks([(0, 0), (4, 0)], [1, 1], 1.0)
    path = loop.svg_path(6)
    assert path.startswith("M ") and path.endswith(" Z")
    assert path.count("A 1 1 0 0 1") == 2          # two half circles, counter-clockwise in y-up
    full = Loop.circle((0, 0), 1.0).svg_path()
    assert full.count("A ") == 2                    # a full turn is split


def test_common_tangents_closed_forms():
    # Equal circles a distance d apart: outer tangents have length d, crossing ones sqrt(d² − 4r²).
    outer = common_tangents((0, 0), 1.0, (5, 0), 1.0, "outer")
    cross = common_tangents((0, 0), 1.0, (5, 0), 1.0, "crossing")
    assert [s.length for s in outer] == pytest.approx([5.0, 5.0])
    assert [s.length for s in cross] == pytest.approx([math.sqrt(21)] * 2)
    # Unequal radii: outer length sqrt(d² − (r1 − r2)²).
    outer2 = common_tangents((0, 0), 3.0, (10, 0), 1.0, "outer")
    assert [s.length for s in outer2] == pytest.approx([math.sqrt(96)] * 2)
    for s in outer2 + cross:
        # Each end touches its circle at a right angle to the tangent.
        for c, rr, p in (((0, 0), None, s.start),):
            v = np.subtract(p, c)
            assert abs(np.dot(v, np.subtract(s.end, s.start))) < 1e-9
    assert common_tangents((0, 0), 1.0, (1.5, 0), 1.0, "crossing") == []
    assert common_tangents((0, 0), 3.0, (0.5, 0), 1.0, "outer") == []
    with pytest.raises(ValueError):
        common_tangents((0, 0), 1, (3, 0), 1, "inner")


@given(st.floats(-50, 50), st.floats(-50, 50), st.floats(0.1, 5), st.sampled_from([1, -1]), st.sampled_from([1, -1]))
def test_disk_tangent_touches_both_disks_on_the_right_sides(x, y, r, s1, s2):
    c1, c2 = np.array([0.0, 0.0]), np.array([x, y])
    seg = disk_tangent(c1, s1, c2, s2, r)
    d = math.hypot(x, y)
    if d < 1e-9:
        return
    if s1 != s2 and d < 2 * r * (1 + 1e-9):
        if d < 2 * r * (1 - 1e-9):
            assert seg is None
        return
    assert seg is not None
    u = np.subtract(seg.end, seg.start)
    L = math.hypot(*u)
    assert L == pytest.approx(math.sqrt(max(d * d - ((s2 - s1) * r) ** 2, 0)), abs=1e-9 * (1 + d))
    if L < 1e-9:
        return
    u /= L
    left = np.array([-u[1], u[0]])
    for c, s, p in ((c1, s1, seg.start), (c2, s2, seg.end)):
        # The contact point is at distance r, perpendicular, with the centre on the side's side.
        assert math.dist(p, c) == pytest.approx(r, rel=1e-9)
        assert np.dot(np.subtract(c, p), left) == pytest.approx(s * r, rel=1e-9)


def test_tangent_directions_and_sweeps_of_a_square_of_disks():
    c = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    phi, L, ok = tangent_directions(c, np.ones(4), 1.0)
    assert ok.all() and L == pytest.approx([4, 4, 4, 4])
    assert phi == pytest.approx([0, math.pi / 2, math.pi, -math.pi / 2])
    sw = arc_sweeps(phi, np.ones(4))
    assert sw == pytest.approx([math.pi / 2] * 4)
    # With a reference near −π/2 a disk that should not be touched shows a negative sweep.
    sw2 = arc_sweeps(phi, np.ones(4), reference=[-2.0, 1.5, 1.5, 1.5])
    assert sw2[0] == pytest.approx(math.pi / 2 - 2 * math.pi)


def _disk_ring(n, r, seed):
    """Disks on a wavy ring, all turned left around (a star-shaped polygon with rounded corners)."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = 10 * (1 + 0.05 * np.sin(5 * t))
    c = np.column_stack([rad * np.cos(t), rad * np.sin(t)])
    s = np.ones(n)
    phi, length, _ = tangent_directions(c, s, r)
    return c, s, phi, length, arc_sweeps(phi, s)


@pytest.mark.parametrize("seed", range(5))
def test_loop_from_disks_built_in_world_coordinates_is_the_affine_image(seed):
    # The fast path builds its loops in world coordinates at once: the same numbers, bit for bit, as
    # building them in the local frame and mapping them.
    c, s, phi, length, sweeps = _disk_ring(50 + 40 * seed, 0.3, seed)
    affine = (17.25, -3.5, 1e6 / 7)
    direct = Loop._from_disk_arrays(c, s, 0.3, phi, length, sweeps, affine)
    mapped = Loop._from_disk_arrays(c, s, 0.3, phi, length, sweeps).affine(*affine)
    assert np.array_equal(direct._arc, mapped._arc)
    assert direct._data.tobytes() == mapped._data.tobytes()
    # Zero-length tangents are left out either way.
    before = len(direct)
    length[np.flatnonzero(length > 0)[0]] = 0.0
    direct = Loop._from_disk_arrays(c, s, 0.3, phi, length, sweeps, affine)
    mapped = Loop._from_disk_arrays(c, s, 0.3, phi, length, sweeps).affine(*affine)
    assert len(direct) == len(mapped) == before - 1
    assert direct._data.tobytes() == mapped._data.tobytes()


@pytest.mark.parametrize("tol", [1e-6, 1e-2, 0.5])
def test_sampling_the_same_whatever_the_rows_order(tol):
    # Alternating arcs and segments (read as strided views) and the same pieces given one by one.
    c, s, phi, length, sweeps = _disk_ring(200, 0.4, 1)
    loop = Loop._from_disk_arrays(c, s, 0.4, phi, length, sweeps)
    same = Loop(loop.pieces)
    assert np.array_equal(loop.sample(tol), same.sample(tol))
    assert loop._area_terms().tobytes() == same._area_terms().tobytes()
    assert loop.area == same.area


def test_orientation_is_the_sign_of_the_exact_area():
    c, s, phi, length, sweeps = _disk_ring(100, 0.4, 2)
    loop = Loop._from_disk_arrays(c, s, 0.4, phi, length, sweeps)
    assert loop._orientation() == 1 and loop.reversed()._orientation() == -1
    assert loop.area > 0 and loop.reversed().area < 0
    # A closed path whose area is exactly zero (a segment there and back): the compensated sum decides.
    flat = Loop([Segment((0, 0), (1e8, 1)), Segment((1e8, 1), (0, 0))])
    assert flat._orientation() == 0 and flat.area == 0.0
