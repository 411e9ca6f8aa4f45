import math
import warnings

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, MultiPolygon, Point, Polygon, box

import vectortighten as vt
from vectortighten._validation import quad_segs_for
from vectortighten.errors import GeometryTypeError, InvalidGeometryError, InvalidRadiusError, RepairWarning

from .strategies import radii_for, shapes, stars

L_SHAPE = Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)])


@pytest.mark.parametrize("a,r", [(4.0, 1.0), (10.0, 0.3), (1e-3, 2e-4), (5e5, 1e4)])
def test_square_core_is_the_rounded_square(a, r):
    R = vt.core(box(0, 0, a, a), r)
    exact = a * a - (4 - math.pi) * r * r
    # Chords replace the corner arcs: the area falls short by at most the tolerance times the arc length.
    assert exact - 2 * math.pi * r * 1e-5 * r <= R.area <= exact


def test_l_shape_fillet_adds_the_reflex_corner():
    F = vt.fillet(L_SHAPE, 1.0)
    extra = F.area - L_SHAPE.area
    assert 1 - math.pi / 4 <= extra + 1e-12 <= 1 - math.pi / 4 + 2 * math.pi * 1e-5


def test_l_shape_core_loses_five_convex_corners():
    R = vt.core(L_SHAPE, 1.0)
    assert L_SHAPE.area - R.area == pytest.approx(5 * (1 - math.pi / 4), abs=1e-4)


def test_plain_buffers_break_containment_but_ours_do_not():
    naive = L_SHAPE.buffer(-1).buffer(1)
    assert naive.difference(L_SHAPE).area > 0          # the problem the package fixes
    R, F = vt.core(L_SHAPE, 1.0), vt.fillet(L_SHAPE, 1.0)
    assert L_SHAPE.covers(R) and F.covers(L_SHAPE)
    assert R.difference(L_SHAPE).is_empty and L_SHAPE.difference(F).is_empty


def rings_apart(S, gap):
    """Whether every two rings of S are farther apart than ``gap`` (no boundary pinched to rounding)."""
    rings = list(shapely.get_rings(shapely.get_parts(S)))
    return all(a.distance(b) > gap for i, a in enumerate(rings) for b in rings[i + 1:])


@settings(max_examples=60)
@given(shapes.flatmap(lambda S: st.tuples(st.just(S), radii_for(S))))
def test_containment_holds_exactly_on_random_shapes(case):
    S, r = case
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RepairWarning)
        R, F = vt.core(S, r), vt.fillet(S, r)
        S = vt._validation.check_shape(S)
    assert R.is_valid and F.is_valid
    assert R.difference(S).is_empty and S.difference(F).is_empty
    # The predicates too, unless S's own rings touch within rounding (a hole 1e-16 from the outline):
    # there GEOS's overlays snap them together and no representation can be exact.
    if rings_apart(S, 1e-9 * max(S.bounds[2] - S.bounds[0], S.bounds[3] - S.bounds[1])):
        assert R.is_empty or S.covers(R)
        assert F.covers(S)


def test_grow_shrink_areas():
    assert vt.grow(box(0, 0, 2, 2), 1.0).area == pytest.approx(4 + 8 + math.pi, abs=1e-4)
    assert vt.shrink(box(0, 0, 4, 3), 1.0).equals(box(1, 1, 3, 2))
    assert vt.shrink(box(0, 0, 4, 3), 1.6).is_empty


def test_shrink_drops_geos_ghosts():
    # An octagon whose inradius is just below r: GEOS's buffer(-r) returns a tiny octagon, not empty.
    octagon = Point(0, 0).buffer(1.767, quad_segs=2)
    inradius = 1.767 * math.cos(math.pi / 8)
    r = inradius + 0.05
    assert not octagon.buffer(-r, quad_segs=8).is_empty
    assert vt.shrink(octagon, r).is_empty and vt.core(octagon, r).is_empty
    assert not vt.shrink(octagon, inradius - 0.05).is_empty


def test_grow_drops_ghost_holes():
    ring = box(-5, -5, 5, 5).difference(Point(0, 0).buffer(1.767, quad_segs=2))
    r = 1.767 * math.cos(math.pi / 8) + 0.05
    assert sum(len(p.interiors) for p in shapely.get_parts(vt.grow(ring, r))) == 0


def test_mortar_anticore_and_tolerance_zone():
    S = box(0, 0, 4, 4)
    assert vt.mortar(S, 1.0).area == pytest.approx(4 - math.pi, abs=1e-4)
    A = vt.anticore(S, 1.0)
    assert A.bounds == (-2.0, -2.0, 6.0, 6.0)
    assert A.area == pytest.approx(64 - 16, abs=1e-6)          # the fillet of a square is the square
    A2 = vt.anticore(S, 1.0, window=(-1, -1, 5, 5))
    assert A2.area == pytest.approx(36 - 16, abs=1e-6)
    Z = vt.tolerance_zone(S, 1.0)
    assert Z.area == pytest.approx(36 - 4 - (4 - math.pi), abs=1e-4)
    with pytest.raises(ValueError):
        vt.anticore(S, 1.0, window=(1, 1, 0, 0))


def test_round_fillet_bridges_and_fillet_round_removes():
    two = box(0, 0, 4, 4).union(box(4.5, 0, 8.5, 4))
    assert vt.round_fillet(two, 1.0).geom_type == "Polygon"
    bar = box(0, 0, 10, 1)
    assert vt.fillet_round(bar, 1.0).is_empty
    assert not vt.round_fillet(bar, 1.0).is_empty or vt.round_fillet(bar, 1.0).is_empty  # RF of a bar: F then R
    assert vt.round_fillet(bar, 1.0).is_empty                # F(bar) = bar, then R removes it


def test_mason_lies_between_core_and_fillet_and_picks_per_pocket():
    S = box(0, 0, 4, 4).union(box(4, 1.6, 8, 2.4)).union(box(8, 0, 12, 4))   # squares joined by a thin bar
    M = vt.mason(S, 1.0)
    R, F = vt.core(S, 1.0), vt.fillet(S, 1.0)
    assert M.covers(R.buffer(-1e-9)) and F.buffer(1e-9).covers(M)
    assert shapely.get_num_geometries(M) == 2                  # the bar's pocket: both filters drop it


def test_quad_segs_from_tolerance():
    assert quad_segs_for(1.0, 1e-5) == 176
    for q_tol in (1e-2, 1e-4, 1e-6):
        q = quad_segs_for(2.0, q_tol * 2)
        assert 2.0 * (1 - math.cos(math.pi / (4 * q))) <= q_tol * 2


@pytest.mark.parametrize("fn", [vt.grow, vt.shrink, vt.core, vt.fillet, vt.mortar, vt.anticore, vt.mason,
                                vt.tolerance_zone, vt.round_fillet, vt.fillet_round])
def test_bad_inputs_are_named(fn):
    with pytest.raises(GeometryTypeError, match="Polygon"):
        fn(LineString([(0, 0), (1, 1)]), 1.0)
    with pytest.raises(GeometryTypeError):
        fn("POLYGON ((0 0, 1 0, 1 1, 0 0))", 1.0)
    with pytest.raises(InvalidGeometryError, match="empty"):
        fn(Polygon(), 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)      # shapely warns when building it
        nan_poly = Polygon([(0, 0), (1, 0), (float("nan"), 1)])
    with pytest.raises(InvalidGeometryError, match="NaN"):
        fn(nan_poly, 1.0)
    for bad_r in (0, -1, float("nan"), float("inf"), "1", True, None):
        with pytest.raises(InvalidRadiusError, match="r must be"):
            fn(box(0, 0, 1, 1), bad_r)
    with pytest.raises(InvalidRadiusError, match="tolerance"):
        fn(box(0, 0, 1, 1), 1.0, tolerance=-1)


def test_bowtie_is_repaired_with_a_warning():
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    with pytest.warns(RepairWarning, match="Self-intersection"):
        R = vt.core(bowtie, 0.1)
    assert R.is_valid and not R.is_empty


def test_inputs_are_not_modified():
    S = MultiPolygon([box(0, 0, 4, 4), box(6, 0, 9, 3)])
    before = S.wkb
    vt.core(S, 1.0), vt.fillet(S, 1.0), vt.mason(S, 1.0)
    assert S.wkb == before


@given(stars())
@settings(max_examples=30)
def test_opening_and_closing_are_idempotent_up_to_chords(S):
    r = 1.0
    R = vt.core(S, r)
    if R.is_empty:
        return
    RR = vt.core(R, r)
    assert R.symmetric_difference(RR).area <= 1e-3 * R.area


def test_pockets_joined_by_slivers_are_separate():
    """Two notches' pockets meet where the chords of the core's and fillet's arcs leave a sliver; they are
    still two components of the mortar's interior, and Mason chooses for each on its own."""
    S = Polygon([(0, 0), (18, 0), (18, 9), (10, 9), (8.6, 7), (7.2, 9), (0, 9)])
    P = vt.pockets(S, 1.0)
    assert len(P) == 7                     # four outer corners, the notch's tip and its two shoulders
    M = vt.mason(S, 1.0)
    assert M.is_valid and M.covers(vt.core(S, 1.0)) and vt.fillet(S, 1.0).covers(M)


def test_rounding_cracks_between_parts_are_closed_with_a_warning():
    """Two unit squares whose shared edge was computed twice miss each other by an ulp: one part, area 2."""
    right = 1.0 + 2.0 ** -52
    S = MultiPolygon([box(0, 0, 1, 1), box(right, 0, 2, 1)])
    assert S.geom_type == "MultiPolygon" and S.distance(box(0, 0, 1, 1)) == 0
    with pytest.warns(RepairWarning, match="rounding crack"):
        F = vt.fillet(S, 0.25)
    assert F.geom_type == "Polygon"
    with pytest.warns(RepairWarning, match="rounding crack"):
        R = vt.core(S, 0.25)
    # One 2×1 rectangle: its core (opening) loses (4 − π)·r² at its four corners, and nothing else.
    assert R.geom_type == "Polygon"
    assert R.area == pytest.approx(2.0 - (4 - math.pi) * 0.25 ** 2, rel=1e-3)


@pytest.mark.parametrize("S", [
    MultiPolygon([box(0, 0, 1, 1), box(1, 1, 2, 2)]),                   # touching at a corner only
    MultiPolygon([box(0, 0, 1, 1), box(1 + 1e-6, 0, 2, 1)]),            # a real gap, 5e-7 of the size
    # A hole touching the shell at two points cuts off a corner: two parts meeting at sharp corners, whose
    # mitres overlap more than a point touch's but join nothing (found by hypothesis).
    box(0, 0, 10, 10).difference(Point(1, 1).buffer(1, quad_segs=2)),
    # The complement of a hole (a 16-gon) touching its shell at one vertex: the wedge's overlap is
    # 20·eps², and closing it joined the parts and broke self-duality (found by hypothesis).
    box(-20, -20, 30, 30).difference(
        Polygon(box(0, 0, 10, 10).exterior, [Point(1, 3).buffer(1, quad_segs=4).exterior])),
])
def test_parts_touching_at_a_point_or_a_real_gap_apart_are_left_alone(S):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RepairWarning)
        F = vt.fillet(S, 0.25)
    assert not F.is_empty
