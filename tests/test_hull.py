import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from shapely.geometry import Polygon, box

import vectortighten as vt

from .strategies import stars

C_SHAPE = Polygon([(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (4, 3), (4, 4), (0, 4)])


def test_unconstrained_hull_is_the_convex_hull():
    H = vt.relative_convex_hull(C_SHAPE, box(-1, -1, 5, 5))
    assert H.equals(C_SHAPE.convex_hull)


def test_an_obstacle_pushes_the_hull_in():
    wall = box(-1, -1, 5, 5).difference(box(2, 1.5, 5, 2.5))
    H = vt.relative_convex_hull(C_SHAPE, wall)
    assert H.area == pytest.approx(13.0, abs=1e-12)
    assert wall.covers(H)
    # Exact: every vertex of the hull is a vertex of one of the two polygons.
    verts = {tuple(p) for p in shapely.get_coordinates(C_SHAPE)} | {tuple(p) for p in shapely.get_coordinates(wall)}
    assert all(tuple(p) in verts for p in shapely.get_coordinates(H))


def test_hull_when_outer_touches_inner():
    # The outer set hugs the C's back: the hull may run along the shared boundary.
    outer = box(0, -1, 5, 5)
    H = vt.relative_convex_hull(C_SHAPE, outer)
    assert H.equals(C_SHAPE.convex_hull)


def test_two_components_merge_when_their_hulls_meet():
    inner = box(0, 0, 1, 1).union(box(2, 0, 3, 1))
    H = vt.relative_convex_hull(inner, box(-1, -1, 4, 2))
    assert H.geom_type == "Polygon" and H.area == pytest.approx(3.0)
    # A wall between them keeps them apart.
    H2 = vt.relative_convex_hull(inner, box(-1, -1, 4, 2).difference(box(1.4, -2, 1.6, 3)))
    assert shapely.get_num_geometries(H2) == 2


@settings(max_examples=30, deadline=None)
@given(stars())
def test_hull_of_a_star_in_a_box_is_its_convex_hull(S):
    x0, y0, x1, y1 = S.bounds
    H = vt.relative_convex_hull(S, box(x0 - 1, y0 - 1, x1 + 1, y1 + 1))
    assert H.symmetric_difference(S.convex_hull).area <= 1e-9 * S.area


def test_outer_must_cover_inner():
    with pytest.raises(vt.InvalidGeometryError, match="cover"):
        vt.relative_convex_hull(box(0, 0, 2, 2), box(1, 1, 3, 3))
