"""Exact boundaries of shrink, grow, core and fillet as loops (`vectortighten.exact_morphology`)."""

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import Polygon, box

from vectortighten import morphology as m
from vectortighten._validation import check_shape, quad_segs_for
from vectortighten.curves import Arc, Loop, Segment
from vectortighten.exact_morphology import ExactBoundary, exact_core, exact_fillet, exact_grow, exact_shrink
from vectortighten.io import read_shape, write_result

from .shapes_dense import admin_outline, pixel_blob, traced_contour
from .strategies import box_unions, holed, stars

L_SHAPE = Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)])


def size_of(S):
    x0, y0, x1, y1 = S.bounds
    return max(x1 - x0, y1 - y0)


def samples(loops, per_piece=7):
    """Points inside every piece of the loops (not only their ends), at evenly spaced fractions."""
    t = (np.arange(per_piece) + 0.5) / per_piece
    out = []
    for lp in loops:
        for p in lp.pieces:
            out += [p.point_at(float(f)) for f in t]
    return np.array(out).reshape(-1, 2)


def distance_error(S, loops, d):
    """Largest |distance to ∂S − d| over sampled points of the loops, relative to S's size."""
    xy = samples(loops)
    dist = shapely.distance(S.boundary, shapely.points(xy))
    return float(np.abs(dist - d).max()) / size_of(S)


def chord_error(r, q):
    """The sagitta of a chord of shapely's buffer with ``quad_segs = q`` (π/(2q) per chord)."""
    return r * (1.0 - math.cos(math.pi / (4 * q)))


def total_area(loops):
    return math.fsum(lp.area for lp in loops)


def check_loops(loops):
    """Closed (checked by `Loop`), G1 or with convex corners only where expected, oriented as documented."""
    for lp in loops:
        assert isinstance(lp, Loop)
        assert abs(abs(lp.total_turn) - 2 * math.pi) < 1e-6, lp.total_turn
        assert (lp.total_turn > 0) == (lp.area > 0)


def check_core_and_fillet_areas(S, d, rel_area):
    """The exact core and fillet are checked loops whose areas are the buffers' (at 1e-6·d: GEOS's opening
    and closing snapped onto the exact corners, the construction the public functions fall back on) to
    the chords' sag along their arcs, plus ``rel_area`` of S's area."""
    tol = 1e-6 * d
    q = quad_segs_for(d, tol)
    for exact_fn, fn in ((exact_core, m._core), (exact_fillet, m._fillet)):
        loops = exact_fn(S, d)
        check_loops(loops)
        ref = fn(m._orient(S), d, q, sampled=False)
        arcs = math.fsum(a.length for lp in loops for a in lp.arcs)
        assert abs(total_area(loops) - ref.area) <= arcs * tol + rel_area * S.area


# -- hand-derived cases -----------------------------------------------------------------------------------
def test_square_shrink_is_a_square():
    [L] = m.shrink(box(0, 0, 4, 4), 1.0, exact=True)
    assert all(isinstance(p, Segment) for p in L.pieces) and len(L) == 4
    corners = sorted(p.start for p in L.pieces)
    assert corners == [(1.0, 1.0), (1.0, 3.0), (3.0, 1.0), (3.0, 3.0)]
    assert L.area == 4.0


def test_square_grow_is_a_rounded_square_with_arcs_of_radius_d():
    d = 0.7
    [L] = m.grow(box(0, 0, 4, 4), d, exact=True)
    arcs = L.arcs
    assert len(arcs) == 4 and len(L.segments) == 4
    assert all(a.radius == d for a in arcs)
    assert sorted(a.center for a in arcs) == [(0.0, 0.0), (0.0, 4.0), (4.0, 0.0), (4.0, 4.0)]
    assert all(math.isclose(a.sweep, math.pi / 2, rel_tol=1e-14) for a in arcs)
    assert L.is_g1(1e-12)
    assert math.isclose(L.area, 16 + 16 * d + math.pi * d * d, rel_tol=1e-14)


def test_square_core_and_fillet():
    S = box(0, 0, 4, 4)
    [R] = m.core(S, 1.0, exact=True)
    assert len(R.arcs) == 4 and all(a.radius == 1.0 and a.sweep > 0 for a in R.arcs)
    assert sorted(a.center for a in R.arcs) == [(1.0, 1.0), (1.0, 3.0), (3.0, 1.0), (3.0, 3.0)]
    assert math.isclose(R.area, 12 + math.pi, rel_tol=1e-14) and R.is_g1(1e-12)
    [F] = m.fillet(S, 1.0, exact=True)                # a convex set is its own fillet
    assert all(isinstance(p, Segment) for p in F.pieces) and math.isclose(F.area, 16.0, rel_tol=1e-14)


def test_l_shape_reflex_corner():
    r = 1.0
    [F] = m.fillet(L_SHAPE, r, exact=True)
    [arc] = F.arcs                                   # one concave arc of radius r, turning right
    assert arc.radius == r and arc.sweep < 0
    assert math.isclose(arc.center[0], 4.0) and math.isclose(arc.center[1], 4.0)
    assert math.isclose(F.area, L_SHAPE.area + (1 - math.pi / 4) * r * r, rel_tol=1e-13)
    [R] = m.core(L_SHAPE, r, exact=True)            # five convex corners lose (1 − π/4) each
    assert math.isclose(R.area, L_SHAPE.area - 5 * (1 - math.pi / 4) * r * r, rel_tol=1e-13)
    assert (3.0, 3.0) in [p.end for p in R.pieces]   # the reflex vertex survives as a corner
    [X] = m.shrink(L_SHAPE, r, exact=True)
    [a] = X.arcs
    assert a.center == (3.0, 3.0) and a.radius == r and a.sweep < 0


@pytest.mark.parametrize("angle", [0.0, 37.0])
def test_bar_exactly_2r_wide(angle):
    r = 1.0
    bar = affinity.rotate(box(0, 0, 10, 2 * r), angle, origin=(0, 0))
    assert m.shrink(bar, r, exact=True) == []        # a centre line: no area
    [R] = m.core(bar, r, exact=True)                 # … whose core is the stadium: the bar, rounded
    assert len(R.arcs) == 2 and all(math.isclose(a.sweep, math.pi, rel_tol=1e-12) for a in R.arcs)
    assert math.isclose(R.area, 16 * r * r + math.pi * r * r, rel_tol=1e-12)
    assert R.is_g1(1e-9)


def test_square_of_side_2r_has_a_disk_as_core():
    [R] = m.core(box(0, 0, 2, 2), 1.0, exact=True)
    [a] = R.arcs
    assert a.center == (1.0, 1.0) and a.radius == 1.0 and math.isclose(a.sweep, 2 * math.pi)


def test_gap_exactly_2r_wide_stays_open_in_the_fillet():
    r = 1.0
    S = check_shape(box(0, 0, 5, 5).union(box(5 + 2 * r, 0, 12, 5)))
    F = m.fillet(S, r, exact=True)
    assert len(F) == 2 and all(lp.area > 0 for lp in F)
    assert math.isclose(total_area(F), S.area, rel_tol=1e-13)
    assert m.grow(S, r, exact=True)[0].area > 0


def test_holes_are_clockwise():
    S = check_shape(box(0, 0, 10, 10).difference(box(3, 3, 7, 7)))
    for fn in (m.shrink, m.grow, m.core, m.fillet):
        loops = fn(S, 1.0, exact=True)
        assert sorted(lp.area > 0 for lp in loops) == [False, True]
        check_loops(loops)


def test_shrink_to_nothing():
    assert m.shrink(box(0, 0, 4, 3), 1.6, exact=True) == []
    assert m.core(box(0, 0, 4, 3), 1.6, exact=True) == []


def test_bad_input_is_a_clear_error():
    with pytest.raises(ValueError):
        m.shrink(box(0, 0, 1, 1), -1.0, exact=True)
    with pytest.raises(ValueError, match="operation"):
        ExactBoundary.of(box(0, 0, 1, 1), 1.0, "erode")


# -- distance to ∂S --------------------------------------------------------------------------------------
def test_every_point_of_the_shrink_at_distance_d_on_a_polygon_with_holes():
    S = check_shape(box(0, 0, 20, 12).difference(shapely.union_all([
        Polygon([(3, 3), (7, 2), (6, 7)]), box(10, 4, 15, 6), Polygon([(16, 8), (18, 9), (17, 11)])])))
    for d in (0.3, 0.8, 1.7):
        loops = m.shrink(S, d, exact=True)
        assert any(lp.area < 0 for lp in loops) == (d < 1.0)     # at 1.7 the holes reach the outside
        assert distance_error(S, loops, d) < 1e-12
        assert distance_error(S, m.grow(S, d, exact=True), d) < 1e-12


@pytest.mark.parametrize("seed", [0, 1])
def test_every_point_of_the_shrink_at_distance_d_on_a_pixel_staircase(seed):
    S = check_shape(pixel_blob(40, seed=seed))
    for d in (1.0, 2.5):
        loops = m.shrink(S, d, exact=True)
        assert loops
        assert distance_error(S, loops, d) < 1e-12
        assert distance_error(S, m.grow(S, d, exact=True), d) < 1e-12


@pytest.mark.parametrize("make, radii", [(lambda: pixel_blob(40, seed=0), (1.0, 2.5)),
                                         (lambda: traced_contour(160, seed=3), (4.0,))],
                         ids=["pixel blob", "traced contour"])
def test_public_shrink_and_grow_polygons_lie_at_distance_d(make, radii):
    """`vt.shrink` and `vt.grow` (the polygons) are the exact boundaries sampled: every vertex is at
    distance d from ∂S to 1e-12 of S's size (GEOS's buffers simplify their input: the traced contour's
    grow had vertices 1.5e-5 off at d = 4, a 30k pixel staircase's 1.2 % of d at 0.6), the core inside
    S, the fillet around it."""
    S = check_shape(make())
    for d in radii:
        for fn in (m.shrink, m.grow):
            xy = shapely.get_coordinates(fn(S, d))
            assert len(xy)
            assert np.abs(shapely.distance(S.boundary, shapely.points(xy)) - d).max() <= 1e-12 * size_of(S)
        R, F = m.core(S, d), m.fillet(S, d)
        assert S.covers(R) and F.covers(S)


@pytest.mark.parametrize("make, d", [(lambda: admin_outline(4000, seed=2), 6000.0),
                                     (lambda: admin_outline(4000, seed=2), 600.0),
                                     (lambda: traced_contour(160, seed=3), 4.0)],
                         ids=["admin outline", "admin outline, r = 600", "traced contour"])
def test_dense_outlines_with_nearly_collinear_edges(make, d):
    """Regression: two offsets of nearly collinear edges meet where two lines at an angle α cross, known
    only to about precision/α along them; their ends missed each other by up to 6e-3 (r = 6000, an admin
    outline) and the chaining raised "exact offsets do not close"; a corner arc of a 1e-12 rad turn then
    made a loop of its own; at r = 600 a small loop's closing check (1e-9 of its own size, below the
    shape's precision) raised "loop is not closed". Every piece of the shrink and grow is at distance d
    from ∂S, the core and fillet are closed, G1 loops whose areas are the buffers' to the chords' sag."""
    S = check_shape(make())
    for loops in (m.shrink(S, d, exact=True), m.grow(S, d, exact=True)):
        assert loops
        assert distance_error(S, loops, d) < 1e-12
    check_core_and_fillet_areas(S, d, 1e-6)


@settings(max_examples=25, deadline=None)
@given(st.one_of(stars(), box_unions(), holed()), st.floats(0.05, 0.25))
def test_random_polygons_shrink_and_grow_at_distance_d(S, rel):
    S = check_shape(S)
    d = rel * math.sqrt(S.area)
    for fn in (m.shrink, m.grow):
        loops = fn(S, d, exact=True)
        check_loops(loops)
        if loops:
            assert distance_error(S, loops, d) < 1e-12


# -- areas against shapely's buffers ----------------------------------------------------------------------
def zone(S, d, q):
    """The tolerance zone (∂S)↑d as the union of each edge's buffer (GEOS does not simplify a single
    segment, as it simplifies a polygon's outline before offsetting it, by up to d/100)."""
    c = shapely.get_coordinates(S.boundary)
    edges = []
    for ring in shapely.get_rings(shapely.get_parts(S)):
        xy = shapely.get_coordinates(ring)
        edges += [shapely.linestrings([a, b]) for a, b in zip(xy[:-1], xy[1:]) if (a != b).any()]
    assert len(c) >= 3
    return shapely.union_all(shapely.buffer(edges, d, quad_segs=q))


def area_bound(loops, r, q):
    """Area between the exact loops and the buffers, whose arcs are chords of sagitta s: at most s per unit
    of arc length of the loops' arcs (doubled: the buffer of a buffer), and rounding."""
    arcs = math.fsum(a.length for lp in loops for a in lp.arcs)
    return 2.0 * arcs * chord_error(r, q) + 1e-12 * max(1.0, abs(total_area(loops)))


@settings(max_examples=20, deadline=None)
@given(st.one_of(stars(), box_unions(), holed()), st.floats(0.05, 0.25))
def test_random_polygons_areas_against_buffers(S, rel):
    S = check_shape(S)
    d = rel * math.sqrt(S.area)
    q = 64
    X = m.shrink(S, d, exact=True)
    G = m.grow(S, d, exact=True)
    Z = zone(S, d, q)
    # The zone's chords lie inside its arcs: S − Z is a little larger than S↓d, S ∪ Z a little smaller.
    assert abs(total_area(X) - S.difference(Z).area) <= area_bound(X, d, q) + area_bound(G, d, q)
    assert abs(total_area(G) - S.union(Z).area) <= area_bound(G, d, q)
    R = m.core(S, d, exact=True)
    F = m.fillet(S, d, exact=True)
    tol = chord_error(d, q)
    for loops, ref in ((R, m.core(S, d, tolerance=tol)), (F, m.fillet(S, d, tolerance=tol))):
        check_loops(loops)
        assert abs(total_area(loops) - ref.area) <= area_bound(loops, d, q)


@pytest.mark.parametrize("seed", [0, 2])
def test_pixel_staircase_core_and_fillet_areas(seed):
    S = check_shape(pixel_blob(40, seed=seed))
    for d in (1.0, 2.5):
        check_core_and_fillet_areas(S, d, 1e-9)


def test_core_loops_lie_in_s_and_fillet_loops_outside():
    S = check_shape(pixel_blob(40, seed=3))
    d = 1.5
    xy = samples(exact_core(S, d))
    assert shapely.distance(S, shapely.points(xy)).max() < 1e-12 * size_of(S)
    xy = samples(exact_fillet(S, d))
    inside = shapely.contains_xy(S, xy[:, 0], xy[:, 1])
    assert (~inside | (shapely.distance(S.boundary, shapely.points(xy)) < 1e-12 * size_of(S))).all()


# -- writers ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("op", ["shrink", "grow", "core", "fillet"])
@pytest.mark.parametrize("ext", ["svg", "dxf", "wkt"])
def test_written_like_a_tightening(tmp_path, op, ext):
    pytest.importorskip("ezdxf") if ext == "dxf" else None
    S = L_SHAPE.difference(box(5, 1, 7, 2))
    B = ExactBoundary.of(S, 0.6, op)
    path = tmp_path / f"out.{ext}"
    write_result(B, path)
    back = read_shape(path, flatten=1e-6)
    assert math.isclose(back.area, B.area, rel_tol=1e-5)
    assert back.symmetric_difference(B.geometry).area < 1e-5 * B.area
    if ext == "svg":
        text = path.read_text()
        assert (" A 0.6 0.6 " in text) == any(lp.arcs for lp in B.loops)
    if ext == "dxf":
        import ezdxf

        radii = {e.dxf.radius for e in ezdxf.readfile(path).modelspace().query("ARC")}
        assert radii == ({0.6} if any(lp.arcs for lp in B.loops) else set())


def test_exact_boundary_measures():
    B = ExactBoundary.of(box(0, 0, 4, 4), 1.0, "core")
    assert math.isclose(B.area, 12 + math.pi, rel_tol=1e-14)
    assert math.isclose(B.perimeter, 8 + 2 * math.pi, rel_tol=1e-14)
    assert (B.n_components, B.n_holes, B.is_empty) == (1, 0, False)
    assert abs(B.geometry.area - B.area) < 1e-4
    assert isinstance(B.loops[0].pieces[1], Arc | Segment)


# -- shapes bounded by segments and arcs (loops as input) ------------------------------------------------
def square_loop(a, c=(0.0, 0.0)):
    x, y = c
    pts = [(x - a, y - a), (x + a, y - a), (x + a, y + a), (x - a, y + a)]
    return Loop([Segment(pts[i], pts[(i + 1) % 4]) for i in range(4)])


def slot_loop(length, half, c=(0.0, 0.0), ccw=True):
    """A stadium: two segments and two half circles of radius ``half``."""
    x, y = c
    L = Loop([Segment((x, y - half), (x + length, y - half)), Arc((x + length, y), half, -math.pi / 2, math.pi),
              Segment((x + length, y + half), (x, y + half)), Arc((x, y), half, math.pi / 2, math.pi)])
    return L if ccw else Loop([p.reversed() for p in reversed(L.pieces)])


@pytest.mark.parametrize("rho, r", [(4.0, 2.0), (2.5, 1.0), (1.0, 0.4)])
def test_plate_with_a_circular_hole(rho, r):
    plate = [square_loop(10.0), Loop.circle((0.5, -0.5), rho, ccw=False)]
    X = m.shrink(plate, r, exact=True)
    [hole] = [lp for lp in X if lp.area < 0]
    [a] = hole.pieces                                  # one arc of radius ρ + r about the same centre
    assert isinstance(a, Arc) and math.isclose(a.radius, rho + r, rel_tol=1e-15) and a.center == (0.5, -0.5)
    assert math.isclose(abs(a.sweep), 2 * math.pi, rel_tol=1e-14)
    for fn in (m.core, m.fillet):                      # the hole is r-regular (ρ > r): kept exactly
        holes = [lp for lp in fn(plate, r, exact=True) if lp.area < 0]
        [[a]] = [lp.pieces for lp in holes]
        assert math.isclose(a.radius, rho, rel_tol=1e-14) and a.center == (0.5, -0.5)
    [G] = [lp for lp in m.grow(plate, r, exact=True) if lp.area < 0]
    assert math.isclose(G.pieces[0].radius, rho - r, rel_tol=1e-14)
    [R] = [lp for lp in m.core(plate, r, exact=True) if lp.area > 0]
    assert math.isclose(R.area, 400 - 4 * (1 - math.pi / 4) * r * r, rel_tol=1e-13)


def test_a_disk_smaller_than_r_vanishes_and_a_larger_one_is_kept():
    assert m.shrink([Loop.circle((3.0, 4.0), 2.0)], 3.0, exact=True) == []
    assert m.core([Loop.circle((3.0, 4.0), 2.0)], 3.0, exact=True) == []
    [R] = m.core([Loop.circle((3.0, 4.0), 5.0)], 3.0, exact=True)
    assert [(p.radius, p.center) for p in R.pieces] == [(5.0, (3.0, 4.0))]
    [G] = m.grow([Loop.circle((3.0, 4.0), 2.0)], 3.0, exact=True)
    assert [p.radius for p in G.pieces] == [5.0]


def test_slot_with_round_ends():
    slot = slot_loop(10.0, 2.0)
    [X] = m.shrink([slot], 1.5, exact=True)            # a thinner stadium: radius 0.5
    assert sorted(set(X.radii.tolist())) == [0.5] and math.isclose(X.area, 10 + math.pi / 4, rel_tol=1e-13)
    for fn in (m.core, m.fillet):                      # r-regular for r ≤ 2: unchanged
        [L] = fn([slot], 1.5, exact=True)
        assert math.isclose(L.area, slot.area, rel_tol=1e-13) and sorted(set(L.radii.tolist())) == [2.0]
    assert m.core([slot], 2.5, exact=True) == []       # thinner than 2r: no disk fits


def test_arc_input_distance_to_the_boundary():
    S = [square_loop(10.0), slot_loop(6.0, 1.5, c=(-5.0, 4.0), ccw=False), Loop.circle((4.0, -4.0), 2.0, ccw=False)]
    h = 1e-5                                           # the sampled boundary's chord error
    poly = shapely.Polygon(S[0].sample(h), [lp.sample(h) for lp in S[1:]])
    s_arcs = math.fsum(a.length for lp in S for a in lp.arcs)
    for d in (0.5, 1.2, 2.0):
        for fn in (m.shrink, m.grow):
            loops = fn(S, d, exact=True)
            check_loops(loops)
            # Against the boundary sampled within h (distances off by at most h).
            dist = shapely.distance(poly.boundary, shapely.points(samples(loops)))
            assert np.abs(dist - d).max() <= h * (1 + 1e-6)
        for fn in (m.core, m.fillet):
            loops = fn(S, d, exact=True)
            check_loops(loops)
            flat = fn(poly, d, tolerance=h)
            arcs = math.fsum(a.length for lp in loops for a in lp.arcs)
            assert abs(total_area(loops) - flat.area) <= 2 * (arcs + s_arcs) * h


def test_arc_input_is_checked():
    with pytest.raises(TypeError, match="Loops"):
        m.shrink([box(0, 0, 1, 1)], 1.0, exact=True)
    with pytest.raises(ValueError):
        m.core([Loop.circle((0, 0), 1.0)], 0.0, exact=True)
