import numpy as np
import pytest
from shapely.geometry import Point, Polygon, box

from vectortighten.geodesic import closed_geodesic, sleeve, string_pull, triangulate


def test_triangulation_adjacency():
    T = triangulate(box(0, 0, 3, 3).difference(box(1, 1, 2, 2)))
    assert len(T.tri) == 8
    # Every interior edge has a triangle on each side, and both hold it.
    for (u, v), (tl, tr) in zip(T.edge_vertices, T.edge_triangles):
        assert {u, v} <= set(T.tri[tl]) and {u, v} <= set(T.tri[tr])


def test_funnel_bends_around_a_corner():
    # An L-shaped corridor: the shortest path from one arm to the other bends at the inner corner.
    left = np.array([[1.0, 1.0], [1.0, 1.0]])
    right = np.array([[2.0, 0.0], [0.0, 2.0]])
    path = string_pull((1.5, -5.0), (-5.0, 1.5), left[:1], right[:1])
    assert path == [(0, 1)]


def test_closed_geodesic_around_a_hole_is_its_hull():
    D = box(0, 0, 10, 10).difference(Polygon([(3, 3), (7, 3), (7, 4), (4, 4), (4, 6), (7, 6), (7, 7), (3, 7)]))
    T = triangulate(D)
    ring = np.array([[1, 1], [9, 1], [9, 9], [1, 9]], float)
    g = closed_geodesic(T, sleeve(T, ring))
    assert g.length == pytest.approx(16.0)
    assert (g.sides == 1).all()


def test_contractible_loop_vanishes():
    T = triangulate(box(0, 0, 10, 10).difference(box(4, 4, 6, 6)))
    ring = np.array([[1, 1], [3, 1], [3, 3], [1, 3]], float)
    assert closed_geodesic(T, sleeve(T, ring)) is None


def test_wiggly_loop_tightens_to_the_inscribed_polygon():
    hole = Point(5, 5).buffer(1.5, quad_segs=4)
    T = triangulate(box(0, 0, 10, 10).difference(hole))
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = np.c_[5 + 3 * np.cos(t) + 0.5 * np.sin(7 * t), 5 + 3 * np.sin(t)]
    g = closed_geodesic(T, sleeve(T, ring))
    assert g.length == pytest.approx(hole.length, rel=1e-12)


def test_loop_winding_twice_is_a_different_class():
    # A loop around two holes separately vs. around both: the geodesics differ.
    D = box(0, 0, 20, 10).difference(box(3, 3, 6, 6)).difference(box(12, 3, 15, 6))
    T = triangulate(D)
    both = np.array([[1, 1], [19, 1], [19, 9], [1, 9]], float)
    one = np.array([[1, 1], [9, 1], [9, 9], [1, 9]], float)
    gb = closed_geodesic(T, sleeve(T, both))
    go = closed_geodesic(T, sleeve(T, one))
    assert gb.length == pytest.approx(2 * 12 + 2 * 3)
    assert go.length == pytest.approx(12)
