import math

import pytest
from shapely.geometry import Point, box

import vectortighten as vt
from vectortighten import Loop


def test_perimeter_of_polygons_and_loops():
    assert vt.perimeter(box(0, 0, 2, 3)) == 10.0
    assert vt.perimeter(Loop.circle((0, 0), 2.0)) == pytest.approx(4 * math.pi)
    T = vt.tighten(box(0, 0, 4, 4), 1.0)
    assert vt.perimeter(T) == T.perimeter == pytest.approx(8 + 2 * math.pi)
    assert vt.perimeter(T.loops) == T.perimeter
    with pytest.raises(TypeError):
        vt.perimeter(3.0)


def test_components_and_holes():
    frame = box(0, 0, 10, 10).difference(box(2, 2, 4, 4)).difference(box(6, 6, 8, 8))
    assert vt.n_components(frame) == 1 and vt.n_holes(frame) == 2
    two = frame.union(box(20, 0, 21, 1))
    assert vt.n_components(two) == 2 and vt.n_holes(two) == 2
    assert vt.n_components(box(0, 0, 1, 1).difference(box(0, 0, 1, 1))) == 0


def test_min_radius_of_curvature_exact_and_discrete():
    loop = Loop.from_disks([(0, 0), (5, 0), (2, 4)], [1, 1, 1], 0.75)
    assert vt.min_radius_of_curvature(loop) == 0.75
    assert vt.min_radius_of_curvature(Loop.from_polygon_ring([(0, 0), (1, 0), (1, 1)])) == 0.0
    disk = Point(0, 0).buffer(2.0, quad_segs=64)
    assert vt.min_radius_of_curvature(disk) == pytest.approx(2.0, rel=1e-9)
    # A polygon's corners have small discrete radii: the circle through a corner and its neighbours.
    assert vt.min_radius_of_curvature(box(0, 0, 1, 1)) == pytest.approx(math.sqrt(2) / 2)


def test_is_r_regular():
    assert vt.is_r_regular(Point(0, 0).buffer(3.0, quad_segs=256), 1.0)
    assert not vt.is_r_regular(box(0, 0, 4, 4), 1.0)
    T = vt.tighten(box(0, 0, 4, 4), 1.0, tolerance=1e-6)
    assert vt.is_r_regular(T.geometry, 1.0)                # a rounded square is 1-regular
    assert not vt.is_r_regular(Point(0, 0).buffer(0.5, quad_segs=64), 1.0)
