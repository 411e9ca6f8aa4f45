"""Shapes given by their exact boundary: readers keeping arcs, `tighten` on loops, idempotence."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image
from shapely.geometry import Point, Polygon, box

from vectortighten import tighten
from vectortighten.cli import main
from vectortighten.curves import Arc, Loop, Segment
from vectortighten.errors import InvalidGeometryError, InvalidRadiusError
from vectortighten.io import read_loops, write_result
from vectortighten.loop_input import FlattenWarning, LoopTightening, identity, merge_arcs

from .strategies import box_unions, holed, stars

INITS = ("core", "input", "mason")


def rounded_rect(x0, y0, x1, y1, rho):
    """A counter-clockwise rectangle whose corners are quarter circles of radius rho."""
    h = math.pi / 2
    return Loop([Segment((x0 + rho, y0), (x1 - rho, y0)), Arc((x1 - rho, y0 + rho), rho, -h, h),
                 Segment((x1, y0 + rho), (x1, y1 - rho)), Arc((x1 - rho, y1 - rho), rho, 0.0, h),
                 Segment((x1 - rho, y1), (x0 + rho, y1)), Arc((x0 + rho, y1 - rho), rho, h, h),
                 Segment((x0, y1 - rho), (x0, y0 + rho)), Arc((x0 + rho, y0 + rho), rho, math.pi, h)])


def square(a):
    return Loop([Segment((-a, -a), (a, -a)), Segment((a, -a), (a, a)), Segment((a, a), (-a, a)),
                 Segment((-a, a), (-a, -a))])


def plate(rho_corner=3.0, rho_hole=4.0):
    """A 20 × 20 plate with corners of radius rho_corner and a centred hole of radius rho_hole."""
    return [rounded_rect(-10, -10, 10, 10, rho_corner), Loop.circle((0.0, 0.0), rho_hole, ccw=False)]


def the_hole(loops):
    [hole] = [lp for lp in loops if lp.area < 0]
    return hole


def assert_one_arc(hole, center, radius):
    assert len(hole) == 1
    [a] = hole.pieces
    assert isinstance(a, Arc)
    assert a.radius == pytest.approx(radius, abs=1e-12)
    assert a.center == pytest.approx(center, abs=1e-12)
    assert abs(a.sweep) == pytest.approx(2 * math.pi, abs=1e-12)


def same_pieces(A, B):
    return [lp.pieces for lp in A.loops] == [lp.pieces for lp in B.loops]


# -- readers ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("ext", [".svg", ".dxf"])
def test_plate_with_a_hole_round_trips_with_its_hole_one_exact_arc(tmp_path, ext):
    T = tighten(plate(), 3.0)
    assert isinstance(T, LoopTightening)
    out = tmp_path / f"plate{ext}"
    write_result(T, out)
    back = read_loops(out)
    assert_one_arc(the_hole(back), (0.0, 0.0), 4.0)
    [outer] = [lp for lp in back if lp.area > 0]
    assert sorted(a.radius for a in outer.arcs) == pytest.approx([3.0] * 4, abs=1e-12)
    assert math.fsum(lp.area for lp in back) == pytest.approx(T.area, rel=1e-12)


def test_dxf_bulges_are_exact_arcs(tmp_path):
    T = tighten(plate(), 3.0)
    out = tmp_path / "plate.dxf"
    write_result(T, out, dxf_entities="lwpolyline")
    back = read_loops(out)
    assert_one_arc(the_hole(back), (0.0, 0.0), 4.0)
    assert sum(len(lp.arcs) for lp in back) == 5


def test_svg_circle_element_is_one_arc(tmp_path):
    p = tmp_path / "c.svg"
    p.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="30" height="30">'
                 '<rect x="1" y="1" width="28" height="28" fill="none" stroke="red"/>'
                 '<circle cx="12.5" cy="10.25" r="3.75" fill="none" stroke="red"/></svg>')
    loops = read_loops(p)
    assert_one_arc(the_hole(loops), (12.5, -10.25), 3.75)        # y up: SVG's y flipped


def test_wkt_curvepolygon_gives_exact_arcs(tmp_path):
    p = tmp_path / "plate.wkt"
    # Outer: a compound curve with a quarter circle of radius 3 at one corner; hole: one circle of radius 4.
    p.write_text("CURVEPOLYGON(COMPOUNDCURVE((-10 -10, 10 -10, 10 7), CIRCULARSTRING(10 7, "
                 f"{7 + 3 * math.cos(math.pi / 4)!r} {7 + 3 * math.sin(math.pi / 4)!r}, 7 10), (7 10, -10 10, -10 -10)), "
                 "CIRCULARSTRING(4 0, -4 0, 4 0))")
    loops = read_loops(p)
    assert_one_arc(the_hole(loops), (0.0, 0.0), 4.0)
    [outer] = [lp for lp in loops if lp.area > 0]
    [corner] = outer.arcs
    assert corner.radius == pytest.approx(3.0, abs=1e-12)
    assert corner.center == pytest.approx((7.0, 7.0), abs=1e-12)
    assert corner.sweep == pytest.approx(math.pi / 2, abs=1e-12)
    assert corner.start == pytest.approx((10.0, 7.0), abs=1e-12)
    assert corner.end == pytest.approx((7.0, 10.0), abs=1e-12)


def test_read_loops_of_a_plain_polygon_is_its_rings(tmp_path):
    p = tmp_path / "sq.wkt"
    p.write_text("POLYGON ((0 0, 0 4, 4 4, 4 0, 0 0), (1 1, 3 1, 3 3, 1 3, 1 1))")
    outer, hole = read_loops(p)
    assert outer.area == 16.0 and hole.area == -4.0 and not outer.arcs


def test_merge_arcs_joins_one_circle_and_keeps_the_rest():
    halves = Loop([Arc((1, 2), 2.0, 0.5, -math.pi), Arc((1, 2), 2.0, 0.5 - math.pi, -math.pi)])
    assert_one_arc(merge_arcs(halves), (1.0, 2.0), 2.0)
    L = rounded_rect(0, 0, 10, 5, 1.0)
    assert merge_arcs(L) is L


# -- tighten on loops: the exact identity ---------------------------------------------------------------
@pytest.mark.parametrize("init", INITS)
def test_plate_with_a_round_hole_is_unchanged(init):
    S = plate()
    T = tighten(S, 3.0, init=init)
    assert isinstance(T, LoopTightening)
    assert [lp.pieces for lp in T.loops] == [lp.pieces for lp in S]
    assert_one_arc(the_hole(T.loops), (0.0, 0.0), 4.0)
    assert T.area == pytest.approx(400 - (4 - math.pi) * 9 - 16 * math.pi, rel=1e-13)
    assert T.verify() == []


@pytest.mark.parametrize("init", INITS)
def test_slot_with_round_ends_of_half_width_r_is_unchanged(init):
    # A stadium whose half-width is r: its shrink is the centre segment, its core itself.
    r = 2.0
    slot = Loop([Segment((0, -r), (10, -r)), Arc((10, 0), r, -math.pi / 2, math.pi),
                 Segment((10, r), (0, r)), Arc((0, 0), r, math.pi / 2, math.pi)])
    T = tighten([slot], r, init=init)
    assert isinstance(T, LoopTightening) and [lp.pieces for lp in T.loops] == [slot.pieces]
    assert T.perimeter == pytest.approx(20 + 2 * math.pi * r, rel=1e-14)


def test_a_disk_smaller_than_r_vanishes_with_a_warning():
    with pytest.warns(FlattenWarning, match="1 arc is flattened"):
        T = tighten([Loop.circle((5.0, 5.0), 2.0)], 3.0)
    assert T.is_empty


def test_a_disk_of_radius_at_least_r_is_its_own_tightening():
    for rho in (3.0, 7.5):
        T = tighten([Loop.circle((5.0, 5.0), rho)], 3.0)
        assert_one_arc(T.loops[0], (5.0, 5.0), rho)


# -- corners filleted, arcs of S kept (arc_fillets) -----------------------------------------------------
@pytest.mark.parametrize("init", INITS)
def test_sharp_plate_with_a_round_hole_keeps_the_hole_and_fillets_the_corners(init):
    S = [square(10.0), Loop.circle((0.0, 0.0), 4.0, ccw=False)]
    assert not identity(S, 3.0, init)
    T = tighten(S, 3.0, init=init)
    assert T._cache["_path"] == "arc-fillets"
    assert_one_arc(the_hole(T.loops), (0.0, 0.0), 4.0)
    [outer] = [lp for lp in T.loops if lp.area > 0]
    centres = np.array(sorted(a.center for a in outer.arcs))
    assert np.abs(centres - [(-7, -7), (-7, 7), (7, -7), (7, 7)]).max() <= 1e-12
    # Corner formula, θ = π/2: each corner loses 2r·tan(θ/2) − rθ of perimeter and r²(tan(θ/2) − θ/2) of area.
    assert T.perimeter == pytest.approx(80 - 4 * (6 - 1.5 * math.pi) + 8 * math.pi, rel=1e-14)
    assert T.area == pytest.approx(400 - 4 * 9 * (1 - math.pi / 4) - 16 * math.pi, rel=1e-14)
    assert outer.is_g1(1e-12)
    assert T.verify() == []


def test_fillets_between_a_segment_and_an_arc_are_solved_in_closed_form():
    # A half disk of radius 5 at r = 1: each fillet is centred on the line y = 1 and the circle of radius 4.
    D = Loop([Segment((-5, 0), (5, 0)), Arc((0, 0), 5.0, 0.0, math.pi)])
    T = tighten([D], 1.0)
    assert T._cache["_path"] == "arc-fillets"
    small = np.array(sorted(a.center for a in T.loops[0].arcs if a.radius == 1.0))
    assert np.abs(small - [(-math.sqrt(15), 1.0), (math.sqrt(15), 1.0)]).max() <= 1e-12
    a = math.atan2(1, math.sqrt(15))
    assert T.perimeter == pytest.approx(5 * (math.pi - 2 * a) + 2 * math.sqrt(15) + 2 * (a + math.pi / 2), rel=1e-14)
    assert [x.radius for x in T.loops[0].arcs].count(5.0) == 1 and T.verify() == []


def test_a_slot_with_round_ends_in_a_sharp_plate_is_kept():
    slot = Loop([Segment((-4, -2), (4, -2)), Arc((4, 0), 2.0, -math.pi / 2, math.pi),
                 Segment((4, 2), (-4, 2)), Arc((-4, 0), 2.0, math.pi / 2, math.pi)]).reversed()
    T = tighten([square(10.0), slot], 1.5)
    assert T._cache["_path"] == "arc-fillets"
    assert the_hole(T.loops).pieces == slot.pieces
    assert T.verify() == []


def test_reflex_corner_beside_a_round_hole_gains_the_corner_area():
    L = Loop.from_polygon_ring([(0, 0), (20, 0), (20, 8), (8, 8), (8, 20), (0, 20)])
    T = tighten([L, Loop.circle((4.0, 4.0), 2.0, ccw=False)], 1.0)
    assert T._cache["_path"] == "arc-fillets"
    # Five convex corners lose r²(1 − π/4) each, the reflex one gains as much; the hole stays.
    assert T.area == pytest.approx(256 - 4 * math.pi - 4 * (1 - math.pi / 4), rel=1e-14)
    assert_one_arc(the_hole(T.loops), (4.0, 4.0), 2.0)
    assert any(a.sweep < 0 and a.radius == 1.0 for lp in T.loops for a in lp.arcs)


def test_a_wall_thinner_than_2r_is_not_filleted_exactly():
    # The hole comes within 1 of the edge at r = 1: a part thinner than 2r, not isolated corners.
    S = [square(10.0), Loop.circle((5.0, 0.0), 4.0, ccw=False)]
    with pytest.warns(FlattenWarning):
        T = tighten(S, 1.0)
    assert T._cache.get("_path") not in ("identity", "arc-fillets", "matched")


def test_two_tangent_circles_are_not_taken_by_an_exact_path():
    # Loops that touch need surgery (the exact answer merges them), which only the polygon engine does.
    with pytest.warns(FlattenWarning):
        T = tighten([Loop.circle((0.0, 0.0), 4.0), Loop.circle((8.0, 0.0), 4.0)], 1.0)
    assert not isinstance(T, LoopTightening)


def test_a_hole_tighter_than_r_is_not_certified():
    # A hole of radius 2 at r = 3: no anticore disk fits in it, so F_r(S) ≠ S.
    S = [rounded_rect(-10, -10, 10, 10, 3.0), Loop.circle((0.0, 0.0), 2.0, ccw=False)]
    assert not identity(S, 3.0, "core") and not identity(S, 3.0, "input")


def test_two_parts_closer_than_2r_are_not_the_identity_for_mason():
    # Two disks of radius 4 with a gap of 1 at r = 3: each is r-regular inside, but F_r fills the gap.
    S = [Loop.circle((0.0, 0.0), 4.0), Loop.circle((9.0, 0.0), 4.0)]
    assert identity(S, 3.0, "core") and identity(S, 3.0, "input")
    assert not identity(S, 3.0, "mason")


def test_bad_loops_get_a_clear_error():
    with pytest.raises(InvalidGeometryError, match="valid shape"):
        tighten([Loop.circle((0.0, 0.0), 4.0), Loop.circle((5.0, 0.0), 4.0)], 1.0)       # overlapping
    with pytest.raises(InvalidGeometryError, match="counter-clockwise"):
        tighten([Loop.circle((0.0, 0.0), 4.0, ccw=False)], 1.0)
    with pytest.raises(ValueError, match="init"):
        tighten(plate(), 3.0, init="nope")
    with pytest.raises(InvalidRadiusError):
        tighten(plate(), 0.0)
    with pytest.raises(InvalidGeometryError, match="NaN"):
        tighten([Loop.circle((math.nan, 0.0), 4.0)], 1.0)
    with pytest.raises(InvalidGeometryError, match="valid shape"):
        tighten([Loop.circle((0.0, 0.0), 4.0), Loop.circle((20.0, 0.0), 1.0, ccw=False)], 1.0)   # hole outside


# -- idempotence ----------------------------------------------------------------------------------------
@pytest.mark.parametrize("init", INITS)
@pytest.mark.parametrize("S", [box(0, 0, 4, 3), Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)]),
                               box(0, 0, 10, 10).difference(box(3, 3, 7, 7))], ids=["box", "L", "frame"])
def test_tightening_a_tightening_gives_it_back(S, init):
    T = tighten(S, 1.0, init=init)
    U = tighten(T.loops, 1.0, init=init)
    assert same_pieces(U, T)
    assert U.perimeter == pytest.approx(T.perimeter, rel=1e-12)
    assert U.area == pytest.approx(T.area, rel=1e-12)
    assert tighten(T, 1.0, init=init).loops == U.loops or same_pieces(tighten(T, 1.0, init=init), T)


@pytest.mark.parametrize("init", ["core", "mason"])
def test_a_tight_wall_thinner_than_2r_comes_back_matched(init):
    # A square hole (a disk with quad_segs=1) 0.6 from the edge at r = 0.4: the tightening keeps the wall
    # (its sides are tight), so R_r(T) ≠ T and the identity is not exact; the flattened run matches T.
    S = box(0, 0, 10, 10).difference(Point(2.6, 5).buffer(2, quad_segs=1))
    T = tighten(S, 0.4, init=init)
    assert (T.n_components, T.n_holes) == (1, 1)
    assert not identity(T.loops, 0.4, init) and identity(T.loops, 0.4, "input")
    U = tighten(T.loops, 0.4, init=init)
    assert U._cache["_path"] == "matched"
    assert same_pieces(U, T)


@settings(max_examples=6, deadline=None, suppress_health_check=list(HealthCheck))
@given(S=st.one_of(stars(), box_unions(), holed()), f=st.floats(1 / 40, 1 / 6), init=st.sampled_from(INITS))
def test_idempotence(S, f, init):
    x0, y0, x1, y1 = S.bounds
    r = f * max(x1 - x0, y1 - y0)
    T = tighten(S, r, init=init)
    if T.is_empty:
        return
    U = tighten(T.loops, r, init=init)
    assert same_pieces(U, T)
    assert U.area == pytest.approx(T.area, rel=1e-12)
    assert U.perimeter == pytest.approx(T.perimeter, rel=1e-12)


# -- command line ---------------------------------------------------------------------------------------
def test_cli_exact_arcs_keeps_the_hole(tmp_path, capsys):
    src = tmp_path / "plate.dxf"
    write_result(tighten(plate(), 3.0), src)
    out = tmp_path / "out.svg"
    assert main(["tighten", str(src), "-r", "3", "-o", str(out), "--exact-arcs"]) == 0
    assert_one_arc(the_hole(read_loops(out)), (0.0, 0.0), 4.0)
    # Without the option the hole is flattened first: its tight loop is made of arcs of radius r.
    flat = tmp_path / "flat.svg"
    assert main(["tighten", str(src), "-r", "3", "-o", str(flat)]) == 0
    assert len(the_hole(read_loops(flat))) > 1


def test_cli_exact_arcs_refused_for_images(tmp_path, capsys):
    img = tmp_path / "m.png"
    Image.fromarray(np.pad(np.full((20, 20), 255, np.uint8), 5)).save(img)
    assert main(["tighten", str(img), "-r", "3", "-o", str(tmp_path / "o.png"), "--exact-arcs"]) == 2
    err = capsys.readouterr().err
    assert "--exact-arcs applies to SVG, DXF and WKT input only" in err and "Traceback" not in err


@pytest.mark.parametrize("seed", [11])
def test_arc_fillets_agree_with_the_polygon_engine_on_the_flattened_shape(seed):
    # Random star plates with round holes: where the exact path applies, the polygon engine on the shape
    # flattened within 1e-5·r gives the same topology and differs by chord-sized slivers only.
    from shapely.geometry import Point

    from vectortighten.arc_fillets import corner_fillets
    from vectortighten.loop_input import region

    rng = np.random.default_rng(seed)
    done = 0
    while done < 1:
        k = int(rng.integers(5, 10))
        th = np.sort(rng.uniform(0, 2 * np.pi, k))
        rad = rng.uniform(6, 10, k)
        P = Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))
        c, rho = rng.uniform(-3, 3, 2), float(rng.uniform(0.8, 2.0))
        if not (P.is_valid and P.contains(Point(c).buffer(rho + 0.5))):
            continue
        loops = [Loop.from_polygon_ring(P.exterior.coords), Loop.circle(tuple(c), rho, ccw=False)]
        r = float(rng.uniform(0.3, 0.8))
        if corner_fillets(loops, r) is None:
            continue
        done += 1
        T = tighten(loops, r)
        assert T._cache["_path"] == "arc-fillets"
        assert_one_arc(the_hole(T.loops), tuple(c), rho)
        U = tighten(region(loops, 1e-5 * r), r)
        assert (U.n_components, U.n_holes) == (T.n_components, T.n_holes)
        assert T.geometry.symmetric_difference(U.geometry).area <= 1e-4 * r * T.perimeter
        assert T.verify() == []
