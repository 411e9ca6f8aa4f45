"""Two radii: r = (r_convex, r_concave) = (a, b) (issue 22 item 3)."""

import math

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import MultiPolygon, Polygon, box

import vectortighten as vt
from vectortighten.cli import main
from vectortighten.two_radii import TwoRadiiNotSupportedError, TwoRadiiTightening, parse_radii

from .oracle import judge
from .strategies import box_unions, stars

L_SHAPE = Polygon([(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)])
STAR = Polygon([(20 * math.cos(math.pi / 2 + k * math.pi / 5) * (1 if k % 2 == 0 else 0.5),
                 20 * math.sin(math.pi / 2 + k * math.pi / 5) * (1 if k % 2 == 0 else 0.5)) for k in range(10)])
FRAME = box(0, 0, 20, 20).difference(box(6, 6, 14, 14))          # a hole: its four corners are reflex
CROSS = Polygon([(4, 0), (8, 0), (8, 4), (12, 4), (12, 8), (8, 8), (8, 12), (4, 12), (4, 8), (0, 8), (0, 4),
                 (4, 4)])
SHAPES = {"L": L_SHAPE, "star": STAR, "frame": FRAME, "cross": CROSS}


def _turns(S):
    """Turning angle (left positive) at every vertex of every ring of S, S on the left of its rings."""
    S = shapely.orient_polygons(S, exterior_cw=False)
    out = []
    for ring in shapely.get_rings(shapely.get_parts(S)):
        c = np.asarray(ring.coords)[:-1]
        u, v = c - np.roll(c, 1, axis=0), np.roll(c, -1, axis=0) - c
        out.append(np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1)))
    return np.concatenate(out)


def _corner_formula(S, a, b):
    """Perimeter and area of S with convex corners rounded by a and reflex corners by b (far apart)."""
    th = _turns(S)
    rho = np.where(th > 0, a, b)
    t = np.abs(th)
    dp = 2 * rho * np.tan(t / 2) - rho * t
    da = rho ** 2 * (np.tan(t / 2) - t / 2)
    return S.length - dp.sum(), S.area - da[th > 0].sum() + da[th < 0].sum()


# -- the pair: parsing and errors ---------------------------------------------------------------------------
@pytest.mark.parametrize("bad, words", [
    ((-1, 2), "r_convex must be a finite number ≥ 0"),
    ((1, -2), "r_concave must be a finite number ≥ 0"),
    ((math.nan, 1), "r_convex"),
    ((1, math.inf), "r_concave"),
    ((0, 0), "at least one"),
    ((1, 2, 3), "pair"),
    ((1,), "pair"),
    (("1", 2), "r_convex"),
    ((True, 2), "r_convex"),
])
def test_bad_pairs_are_refused_with_one_clear_line(bad, words):
    with pytest.raises(ValueError, match=words) as info:
        vt.tighten(L_SHAPE, bad)
    assert isinstance(info.value, vt.InvalidRadiusError) and "\n" not in str(info.value)


def test_parse_radii_accepts_sequences_of_two():
    assert parse_radii([0, 3]) == (0.0, 3.0)
    assert parse_radii(np.array([1.5, 2])) == (1.5, 2.0)


def test_equal_radii_are_the_one_radius_tightening_itself():
    for S in SHAPES.values():
        one, two = vt.tighten(S, 1.0), vt.tighten(S, (1.0, 1.0))
        assert type(two) is vt.Tightening and two.radii == (1.0, 1.0)
        assert len(one.loops) == len(two.loops)
        for p, q in zip(one.loops, two.loops):
            assert np.array_equal(p._data, q._data) and np.array_equal(p._arc, q._arc)


# -- geometry -------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(SHAPES))
@pytest.mark.parametrize("a, b", [(0.5, 1.5), (1.5, 0.5), (0.0, 1.0), (1.0, 0.0)])
def test_corner_formula_with_two_radii(name, a, b):
    S = SHAPES[name]
    T = vt.tighten(S, (a, b))
    assert isinstance(T, TwoRadiiTightening) and T.radii == (a, b) and T.r == max(a, b)
    perimeter, area = _corner_formula(S, a, b)
    assert T.perimeter == pytest.approx(perimeter, rel=1e-12)
    assert T.area == pytest.approx(area, rel=1e-12)
    assert T.verify() == []


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_arcs_have_their_side_s_radius(name):
    a, b = 0.7, 1.3
    T = vt.tighten(SHAPES[name], (a, b))
    th = _turns(SHAPES[name])
    arcs = [arc for loop in T.loops for arc in loop.arcs]
    left = [arc.radius for arc in arcs if arc.sweep > 0]
    right = [arc.radius for arc in arcs if arc.sweep < 0]
    assert len(left) == (th > 0).sum() and len(right) == (th < 0).sum()
    assert left == pytest.approx([a] * len(left), rel=1e-14)
    assert right == pytest.approx([b] * len(right), rel=1e-14)
    assert T.min_radius_of_curvature == pytest.approx(min(a, b) if len(right) else a, rel=1e-14)
    for loop in T.loops:
        assert loop.is_g1(1e-9)


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_between_core_and_fillet(name):
    S = SHAPES[name]
    a, b = 0.6, 1.4
    T = vt.tighten(S, (a, b))
    R, F = vt.core(S, a, tolerance=1e-6), vt.fillet(S, b, tolerance=1e-6)
    G = T.geometry
    slack = 2 * T.tolerance                  # the chords of T's geometry, and of R's and F's
    assert R.difference(G.buffer(slack)).area < 1e-12
    assert G.difference(F.buffer(slack)).area < 1e-12
    # T's own core and fillet are R_a and F_b, and differ from the one-radius ones.
    assert T.core.equals(vt.core(S, a, tolerance=T.tolerance))
    assert T.fillet.equals(vt.fillet(S, b, tolerance=T.tolerance))
    assert T.mortar.area == pytest.approx(T.fillet.area - T.core.area, rel=1e-9)


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_concave_radius_alone_is_the_fillet_and_convex_alone_the_core(name):
    """(0, b) is the tight loop between S and F_b(S): S with its reflex corners filleted, F_b(S) itself
    when every reflex corner is isolated; (a, 0) likewise R_a(S). Compared with the exact offsets."""
    S = SHAPES[name]
    T0b, Ta0 = vt.tighten(S, (0.0, 1.2)), vt.tighten(S, (0.9, 0.0))
    F = vt.fillet(S, 1.2, exact=True)
    R = vt.core(S, 0.9, exact=True)
    assert T0b.perimeter == pytest.approx(math.fsum(lp.length for lp in F), rel=1e-12)
    assert T0b.area == pytest.approx(math.fsum(lp.area for lp in F), rel=1e-12)
    assert Ta0.perimeter == pytest.approx(math.fsum(lp.length for lp in R), rel=1e-12)
    assert Ta0.area == pytest.approx(math.fsum(lp.area for lp in R), rel=1e-12)
    assert S.difference(T0b.geometry).area < 1e-9 and Ta0.geometry.difference(S).area < 1e-9
    # Sharp corners are kept exactly: every vertex of the other kind is a vertex of the loops.
    assert all(arc.sweep < 0 for lp in T0b.loops for arc in lp.arcs)
    assert all(arc.sweep > 0 for lp in Ta0.loops for arc in lp.arcs)
    assert T0b.min_radius_of_curvature == 0.0 and Ta0.min_radius_of_curvature == 0.0


def test_zero_concave_radius_on_a_convex_polygon_is_its_opening():
    """A convex shape is its own closing: (a, b) gives R_a(S) for any b (the convex path when the disks
    of its corners interact, the fast path otherwise)."""
    tri = Polygon([(0, 0), (4, 0), (2, 1.2)])
    T = vt.tighten(tri, (0.3, 2.0))
    one = vt.tighten(tri, 0.3)
    assert T.perimeter == pytest.approx(one.perimeter, rel=1e-12)
    assert T.area == pytest.approx(one.area, rel=1e-12)
    assert T.verify() == []


def test_zero_convex_radius_keeps_a_convex_shape():
    T = vt.tighten(box(0, 0, 4, 4), (0.0, 1.0))
    assert T.perimeter == 16.0 and T.area == 16.0 and T.geometry.equals(box(0, 0, 4, 4))
    assert T.core.equals(box(0, 0, 4, 4)) and T.verify() == []


def test_verify_reports_a_tampered_result():
    T = vt.tighten(L_SHAPE, (0.5, 1.5))
    lp = T.loops[0]
    data = lp._data.copy()
    k = int(np.flatnonzero(lp._arc)[0])
    data[k, 2] *= 1.01                                         # one arc's radius changed
    T.loops[0] = vt.Loop._from_arrays(lp._arc, data)
    problems = T.verify()
    assert any("radius is not r_convex" in p for p in problems)
    assert any("not the one the exact tests certify" in p for p in problems)


DUMBBELL = box(0, 0, 4, 4).union(box(4, 1.6, 8, 2.4)).union(box(8, 0, 12, 4))


@pytest.mark.parametrize("a, b", [(0.5, 1.5), (0.0, 1.5), (0.5, 0.0)])
def test_verify_reports_a_moved_result(a, b):
    """(a) on the exact offsets: the loops moved sideways miss the core and cover the anticore."""
    T = vt.tighten(FRAME, (a, b))
    T.loops = [lp.affine(1.0, 0.7, 0.0) for lp in T.loops]
    T.geometry = shapely.affinity.translate(T.geometry, 0.7, 0.0)
    problems = T.verify()
    assert any(p.startswith("(a)") for p in problems)
    assert any("not the one the exact tests certify" in p for p in problems)


SLOT = box(0, 0, 10, 10).difference(box(4.5, 3, 5.5, 10))          # a slot 1 wide, 7 deep, open at the top


def _slot_perimeter(a, b):
    """The slot's tightening for 2b > 1 (F_b closes the slot but for a dip of radius b at its mouth),
    by elementary geometry: the box's four corners rounded by a, and across the mouth a chain that leaves
    the top of the right mouth corner's a-disk, turns left by θ, runs on a crossing tangent of length L to
    the b-disk over the mouth, turns right by 2θ under it, and back symmetrically."""
    h = math.sqrt(b * b - 0.25)                       # the b-disk touching both mouth corners: centre (5, 10 + h)
    dx, dy = 0.5 + a, h + a                           # from the right a-disk's centre (5.5 + a, 10 − a)
    d = math.hypot(dx, dy)
    theta = math.atan2(dx, dy) - math.acos((a + b) / d)
    L = math.sqrt(d * d - (a + b) ** 2)
    chain = 2 * a * theta + 2 * L + 2 * b * theta
    return 40 - 4 * a * (2 - math.pi / 2) - (1 + 2 * a) + chain


@pytest.mark.parametrize("a, b", [(0.8, 1.0), (0.3, 0.6), (1.2, 0.7)])
def test_slot_narrower_than_2b_on_the_general_engine(a, b):
    """The slot's corners interact (their b-disks do not fit), so the general engine runs, each disk at its
    side's radius; the result is the closed-form chain across the mouth, exact to 1e-12."""
    T = vt.tighten(SLOT, (a, b))
    assert isinstance(T, TwoRadiiTightening) and T._cache["_path"] == "general" and T.converged
    assert T.perimeter == pytest.approx(_slot_perimeter(a, b), rel=1e-12)
    arcs = [arc for lp in T.loops for arc in lp.arcs]
    assert sorted(round(arc.radius, 12) for arc in arcs if arc.sweep > 0) == [a] * 6
    assert [arc.radius for arc in arcs if arc.sweep < 0] == pytest.approx([b], rel=1e-14)
    assert T.min_radius_of_curvature == pytest.approx(min(a, b), rel=1e-14)
    assert all(lp.is_g1(1e-9) for lp in T.loops)
    assert T.verify() == []
    _oracle_between(SLOT, T, a, b)


def _oracle_between(S, T, a, b):
    """R_a ⊆ T ⊆ F_b by the independent oracle: at a for the core side, at b for the fillet side."""
    ja, jb = judge(S, a, T.loops, T.geometry), judge(S, b, T.loops, T.geometry)
    assert ja.core_penetration <= 1e-9 * a and ja.core_missing == 0
    assert jb.anticore_penetration <= 1e-9 * b and jb.anticore_covered == 0


ISLAND = MultiPolygon([L_SHAPE, box(14, 0, 15, 8)])                  # the bar is thinner than 2a: it vanishes


@pytest.mark.parametrize("a, b", [(0.6, 1.5), (1.5, 0.6)])
def test_corner_formula_on_the_general_engine(a, b):
    """The bar's corners interact, so the general engine runs; the bar vanishes from the core and the L
    keeps every corner isolated: the corner formula with two radii holds for the L alone."""
    T = vt.tighten(ISLAND, (a, b))
    assert T._cache["_path"] == "general" and T.converged and len(T.loops) == 1
    perimeter, area = _corner_formula(L_SHAPE, a, b)
    assert T.perimeter == pytest.approx(perimeter, rel=1e-12)
    assert T.area == pytest.approx(area, rel=1e-12)
    assert T.verify() == []
    _oracle_between(ISLAND, T, a, b)


def test_dumbbell_neck_thinner_than_2a():
    """init='core': the neck (0.8 wide) holds no a-disk for a = 0.8 > 0.4, so the two boxes come apart.
    An a-disk still pokes into the neck's mouth: its centre reaches x = 4 − √(a² − 0.4²) between the
    neck's reflex corners (4, 1.6) and (4, 2.4). Each loop is the convex hull of five a-disks: the
    hull of their centres' perimeter plus 2πa."""
    a, b = 0.8, 1.0
    T = vt.tighten(DUMBBELL, (a, b))
    assert T._cache["_path"] == "general" and len(T.loops) == 2
    tip = 4 - math.sqrt(a * a - 0.16) - (4 - a)         # how far the tip's centre is beyond the square's
    hull = 3 * (4 - 2 * a) + 2 * math.hypot(tip, 2 - a)
    assert T.perimeter == pytest.approx(2 * (hull + 2 * math.pi * a), rel=1e-12)
    assert T.verify() == []
    _oracle_between(DUMBBELL, T, a, b)
    # init='input' keeps the neck (its sides are tight already) with its four reflex corners at radius b.
    T = vt.tighten(DUMBBELL, (a, 0.3), init="input")
    assert len(T.loops) == 1 and T.verify() == []
    assert sorted(round(arc.radius, 12) for lp in T.loops for arc in lp.arcs if arc.sweep < 0) == [0.3] * 4
    _oracle_between(DUMBBELL, T, a, 0.3)


@pytest.mark.parametrize("b", [1.0, 0.7])
@pytest.mark.parametrize("init", ["core", "input"])
def test_sharp_outside_corners_on_the_general_engine(b, init):
    """(0, b), the CNC rule, on the slot: the disks of side +1 are S's convex vertices (radius 0), and the
    loop runs along S's edges, turns sharp at the box's and the mouth's corners, and crosses the mouth on
    the b-disk that touches both mouth corners: an arc of chord 1, 2b·asin(1/2b) long."""
    T = vt.tighten(SLOT, (0.0, b), init=init)
    assert T._cache["_path"] == "general" and T.converged
    assert T.perimeter == pytest.approx(40 - 1 + 2 * b * math.asin(0.5 / b), rel=1e-12)
    assert [arc.radius for lp in T.loops for arc in lp.arcs] == pytest.approx([b], rel=1e-14)
    assert T.min_radius_of_curvature == 0.0 and T.verify() == []
    assert SLOT.difference(T.geometry).area < 1e-12                 # S ⊆ T: R_0 is S
    jb = judge(SLOT, b, T.loops, T.geometry)
    assert jb.anticore_penetration <= 1e-9 * b and jb.anticore_covered == 0


def test_sharp_inside_corners_on_the_general_engine():
    """(a, 0) on the dumbbell (init='core'): the loop may not leave S; the disks of side −1 are the neck's
    reflex vertices. Each box's loop is its square rounded by a, but where the neck meets it the loop
    turns sharp at (4, 1.6), runs over the a-disk that pokes into the neck's mouth (through both reflex
    vertices: an arc of π/3 at a = 0.8) and turns sharp again at (4, 2.4)."""
    a = 0.8
    T = vt.tighten(DUMBBELL, (a, 0.0))
    assert T._cache["_path"] == "general" and len(T.loops) == 2
    assert T.perimeter == pytest.approx(2 * (16 - 4 * a * (2 - math.pi / 2) - 0.8 + a * math.pi / 3), rel=1e-12)
    assert T.verify() == [] and T.geometry.difference(DUMBBELL).area < 1e-12    # T ⊆ S: F_0 is S
    ja = judge(DUMBBELL, a, T.loops, T.geometry)
    assert ja.core_penetration <= 1e-9 * a and ja.core_missing == 0
    left = [arc.radius for lp in T.loops for arc in lp.arcs]
    assert left == pytest.approx([a] * len(left), rel=1e-14) and all(arc.sweep > 0 for lp in T.loops for arc in lp.arcs)


@pytest.mark.parametrize("r", [(0.5, 1.0), (1.0, 0.5), (0.0, 1.0), (0.8, 0.0)])
def test_mason_with_two_radii_on_the_general_engine(r):
    """init='mason' with two radii starts from Mason between R_a and F_b: on two squares joined by a bar
    thinner than 2a the result is one of the two tightenings the other inits give (the bar kept or not),
    between R_a and F_b, verified."""
    S = box(0, 0, 4, 4).union(box(6, 0, 10, 4)).union(box(4, 1.6, 6, 2.4))
    T = vt.tighten(S, r, init="mason")
    assert T.verify() == []
    R, F = vt.core(S, r), vt.fillet(S, r)            # both sampled like T: within 2 tolerances of each other
    slack = 2.0 * T.tolerance
    assert R.difference(T.geometry.buffer(slack)).area < 1e-12 and T.geometry.difference(F.buffer(slack)).area < 1e-12
    others = [vt.tighten(S, r, init=init) for init in ("core", "input")]
    assert any(T.area == pytest.approx(U.area, rel=1e-12) and T.perimeter == pytest.approx(U.perimeter, rel=1e-12)
               for U in others)


def test_a_shape_too_thin_for_either_disk_vanishes():
    T = vt.tighten(box(0, 0, 10, 1), (0.8, 0.6))
    assert T.is_empty and T.radii == (0.8, 0.6) and T.core.is_empty and T.verify() == []


RADII = st.one_of(st.just(0.0), st.floats(0.05, 1.5))


@settings(max_examples=20, deadline=None)
@given(stars(max_k=12), RADII, RADII)
def test_random_stars_are_exact(S, a, b):
    """Every pair is computed and verified; with a radius 0, S ⊆ T (a = 0) or T ⊆ S (b = 0), and the
    other side by the independent oracle."""
    if a == b == 0:
        return
    T = vt.tighten(S, (a, b))
    assert T.converged and T.verify() == []
    if a == 0:
        assert S.difference(T.geometry).area < 1e-9
    else:
        ja = judge(S, a, T.loops, T.geometry)
        assert ja.core_penetration <= 1e-9 * a and ja.core_missing == 0
    if b == 0:
        assert T.geometry.difference(S).area < 1e-9
    else:
        jb = judge(S, b, T.loops, T.geometry)
        assert jb.anticore_penetration <= 1e-9 * b and jb.anticore_covered == 0
    if isinstance(T, TwoRadiiTightening) and T._cache["_path"] == "fast":
        perimeter, area = _corner_formula(S, a, b)
        assert T.perimeter == pytest.approx(perimeter, rel=1e-9)
        assert T.area == pytest.approx(area, rel=1e-9)


@settings(max_examples=10, deadline=None)
@given(st.one_of(stars(max_k=16), box_unions(max_n=4)), st.floats(0.2, 1.5), st.floats(0.2, 1.5),
       st.sampled_from(["core", "input"]))
def test_random_shapes_with_two_positive_radii(S, a, b, init):
    """Positive pairs with a ≠ b always give a result: exact (R_a ⊆ T ⊆ F_b by the independent oracle at
    each radius), verified, arcs turning left of radius a and right of radius b, curvature ≥ min(a, b)."""
    if a == b:
        return
    T = vt.tighten(S, (a, b), init=init)
    assert T.converged and T.verify() == []
    _oracle_between(S, T, a, b)
    for lp in T.loops:
        for arc in lp.arcs:
            assert arc.radius == pytest.approx(a if arc.sweep > 0 else b, rel=1e-12)
    assert T.min_radius_of_curvature >= min(a, b) * (1 - 1e-12)


# -- output ---------------------------------------------------------------------------------------------------
def test_writers_carry_each_arc_s_radius(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    T = vt.tighten(L_SHAPE, (2.0, 3.0))
    path = T.svg_path()
    assert path.count("A 2 2 ") == 5 and path.count("A 3 3 ") == 1
    vt.io.write_result(T, tmp_path / "t.dxf")
    radii = sorted(e.dxf.radius for e in ezdxf.readfile(tmp_path / "t.dxf").modelspace() if e.dxftype() == "ARC")
    assert radii == pytest.approx([2.0] * 5 + [3.0])
    vt.io.write_result(T, tmp_path / "t.svg")
    T = vt.tighten(SLOT, (0.8, 1.0))                       # the general engine
    vt.io.write_result(T, tmp_path / "s.dxf")
    radii = sorted(e.dxf.radius for e in ezdxf.readfile(tmp_path / "s.dxf").modelspace() if e.dxftype() == "ARC")
    assert radii == pytest.approx([0.8] * 6 + [1.0])
    assert T.svg_path().count("A 0.8 0.8 ") == 6 and T.svg_path().count("A 1 1 ") == 1
    assert "r_convex=2 r_concave=3" in (tmp_path / "t.svg").read_text()


# -- command line ---------------------------------------------------------------------------------------------
@pytest.fixture
def l_wkt(tmp_path):
    src = tmp_path / "L.wkt"
    src.write_text(L_SHAPE.wkt)
    return src


@pytest.mark.parametrize("args", [["-r", "0,3"], ["--r-concave", "3"], ["--r-convex", "0", "--r-concave", "3"]])
def test_cli_cnc_inside_corners(l_wkt, tmp_path, capsys, args):
    out = tmp_path / "out.wkt"
    assert main(["tighten", str(l_wkt), *args, "-o", str(out)]) == 0
    G = shapely.from_wkt(out.read_text())
    T = vt.tighten(L_SHAPE, (0.0, 3.0))
    assert T.area == pytest.approx(_corner_formula(L_SHAPE, 0.0, 3.0)[1], rel=1e-12)
    assert G.symmetric_difference(T.geometry).area < 1e-9         # the same result, written
    assert "perimeter 38.7124" in capsys.readouterr().out


def test_cli_two_radii_refused_for_images(tmp_path, capsys):
    png = tmp_path / "m.png"
    from PIL import Image

    Image.fromarray(np.pad(np.ones((20, 20), np.uint8) * 255, 5)).save(png)
    assert main(["tighten", str(png), "-r", "0,3", "-o", str(tmp_path / "o.png")]) == 2
    assert "vector shapes" in capsys.readouterr().err


@pytest.mark.parametrize("args, words", [
    (["-r", "0,0"], "at least one"),
    (["-r", "1,2,3"], "pair"),
    (["-r", "x,2"], "not a number"),
    (["-r", "nan,2"], "r_convex"),
    (["-r", "1", "--r-convex", "2"], "not both"),
    (["--r-concave", "-1"], ">= 0"),
    ([], "required: -r/--radius"),
    (["--r-convex", "0", "--r-concave", "0"], "both 0"),
])
def test_cli_bad_radii_exit_2_with_one_line(l_wkt, tmp_path, capsys, args, words):
    with pytest.raises(SystemExit) as info:
        main(["tighten", str(l_wkt), *args, "-o", str(tmp_path / "o.wkt")])
    assert info.value.code == 2 and not (tmp_path / "o.wkt").exists()
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "Traceback" not in err


def test_the_final_check_flags_a_gross_failure(monkeypatch):
    """Every two-radii result gets the cheap containment check that one radius gets (`_guard`)."""
    from vectortighten import two_radii

    real = two_radii._fast.fast_disk_loops

    def shifted(*args, **kwargs):
        out = real(*args, **kwargs)
        return [(x[0] + (0.05, 0.0),) + tuple(x[1:]) for x in out]         # every disk moved sideways

    monkeypatch.setattr(two_radii._fast, "fast_disk_loops", shifted)
    with pytest.warns(vt.ConvergenceWarning, match="final check"):
        T = vt.tighten(L_SHAPE, (0.5, 1.5))
    assert not T.converged


# -- tangents between disks of different radii ----------------------------------------------------------------
@settings(max_examples=40)
@given(st.lists(st.tuples(st.floats(-20, 20), st.floats(-20, 20), st.sampled_from([1, -1]),
                          st.one_of(st.just(0.0), st.floats(0.1, 3.0))), min_size=2, max_size=6))
def test_tangents_between_disks_of_different_radii(disks):
    """Each tangent touches both circles at right angles, keeps each disk on its own side, and the one
    radius case is the scalar formula, bit for bit."""
    c = np.array([(x, y) for x, y, _, _ in disks])
    s = np.array([side for _, _, side, _ in disks], float)
    rho = np.array([radius for _, _, _, radius in disks])
    phi, length, ok = vt.tangent_directions(c, s, rho)
    nrm = np.column_stack([-np.sin(phi), np.cos(phi)])
    u = np.column_stack([np.cos(phi), np.sin(phi)])
    P = c - (s * rho)[:, None] * nrm
    Q = np.roll(c, -1, axis=0) - (np.roll(s * rho, -1))[:, None] * nrm
    size = 1.0 + np.abs(c).max() + rho.max()
    for i in np.flatnonzero(ok):
        j = (i + 1) % len(c)
        assert np.allclose(Q[i] - P[i], length[i] * u[i], atol=1e-9 * size)
        for x, k in ((P[i], i), (Q[i], j)):
            assert math.hypot(*(x - c[k])) == pytest.approx(rho[k], abs=1e-9 * size)
            # The disk on the loop's left (+1) or right (−1) of the tangent's direction.
            cross = u[i, 0] * (c[k, 1] - x[1]) - u[i, 1] * (c[k, 0] - x[0])
            assert rho[k] == 0 or np.sign(cross) == s[k]
    for i in np.flatnonzero(~ok):
        j = (i + 1) % len(c)
        k = s[j] * rho[j] - s[i] * rho[i]
        assert math.hypot(*(c[j] - c[i])) ** 2 <= k * k + 1e-9 * size ** 2
    if len(set(rho.tolist())) == 1:
        one = vt.tangent_directions(c, s, float(rho[0]))
        assert all(np.array_equal(x, y) for x, y in zip(one, (phi, length, ok)))


@pytest.mark.parametrize("a, b", [(0.0, 1.0), (1.0, 0.0), (0.5, 1.5)])
def test_public_morphology_takes_the_pair(a, b):
    """``vt.core(S, (a, b))`` is the core at a, ``vt.fillet`` the fillet at b (S itself for a radius 0),
    the mortar their difference; an L-shape: five convex corners lose a²(1 − π/4) each, the reflex one
    gains b²(1 − π/4)."""
    S = L_SHAPE
    R, F, M = vt.core(S, (a, b)), vt.fillet(S, (a, b)), vt.mortar(S, (a, b))
    loss, gain = 5 * a * a * (1 - math.pi / 4), b * b * (1 - math.pi / 4)
    assert abs(R.area - (S.area - loss)) <= 1e-4 * max(a, 1e-3) and S.covers(R)
    assert abs(F.area - (S.area + gain)) <= 1e-4 * max(b, 1e-3) and F.covers(S)
    assert abs(M.area - (loss + gain)) <= 2e-4 * max(a, b)
    if a == 0:
        assert R.equals(S)
        assert sum(lp.area for lp in vt.core(S, (a, b), exact=True)) == S.area
    else:
        exact = sum(lp.area for lp in vt.core(S, (a, b), exact=True))
        assert abs(exact - (S.area - loss)) <= 1e-12 * S.area
    with pytest.raises(vt.InvalidRadiusError):
        vt.mortar(S, (0.0, 0.0))


def test_loops_with_two_radii_are_tightened_flattened_with_a_warning():
    """A plate with a round hole given by its exact loops, at (0, b): the hole (radius 5 > b) stays, the
    slot narrower than 2b is filled, the convex corners stay sharp; the same as the flattened polygon."""
    from vectortighten.loop_input import FlattenWarning, region

    plate = shapely.orient_polygons(shapely.difference(box(0, 0, 40, 20), box(26, 8, 28, 20)))  # slot 2 wide
    loops = [vt.Loop.from_polygon_ring(plate.exterior.coords), vt.Loop.circle([10.0, 10.0], 5.0, ccw=False)]
    with pytest.warns(FlattenWarning, match="two radii"):
        T = vt.tighten(loops, (0.0, 3.0))
    flat = region(loops, 1e-5 * 3.0)
    ref = vt.tighten(flat, (0.0, 3.0))
    assert T.area == pytest.approx(ref.area, rel=1e-12)
    assert T.perimeter == pytest.approx(ref.perimeter, rel=1e-12)
    # The hole survives (its radius 5 exceeds b) and the slot is filled: one component with one hole.
    assert shapely.get_num_interior_rings(T.geometry) == 1
    assert T.geometry.covers(box(26.2, 9, 27.8, 11))
    assert all(arc.sweep < 0 for lp in T.loops for arc in lp.arcs)          # a = 0: no convex arc
