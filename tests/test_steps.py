"""Steps in a wall (a convex and a reflex corner closer than their disks' tangents) on the fast path
(`_fast._bridge_steps`): the loop crosses the step on the inner tangent of the two corner disks, a disk
whose tangent is longer than the step slides to the step's far end, and the answer is the general
engine's."""

import math
import warnings

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

import vectortighten as vt

from .engines import assert_exact, assert_same, disks, general


@pytest.mark.parametrize("h", [0.3, 0.05, 1.2])
@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_right_angled_step_lower_than_r(h, init):
    # A wall along y = 0 that steps up by h at x = 0. Below r, the core's corner disk, tangent to y = 0
    # and through the step's top (0, h), has its centre at (−√(2rh − h²), r); the anticore's, tangent to
    # y = h from below and through (0, 0), at (√(2rh − h²), h − r). From r to 2r each corner keeps the disk
    # touching both its edges, centred r from the step. The loop crosses the step between them.
    r = 1.0
    S = Polygon([(-10, 0), (0, 0), (0, h), (10, h), (10, 10), (-10, 10)])
    T = vt.tighten(S, r, init=init)
    assert T._cache["_path"] == "fast" and T.verify() == []
    a = math.sqrt(2 * r * h - h * h) if h < r else r
    c = disks(T)[0]
    for x, y in ((-a, r), (a, h - r)):
        assert np.hypot(c[:, 0] - x, c[:, 1] - y).min() < 1e-12
    assert_same(T, general(S, r, init), rel=1e-10)
    assert_exact(S, r, T)


def test_a_gentle_step_keeps_its_corner_disks():
    # 30° turns: each tangent r·tan(15°) fits on the 0.4-long step, but not both; the disks stay where
    # they touch both edges, and only the piece between them changes (an inner tangent).
    r, L = 1.0, 0.4
    x, y = L * math.cos(math.pi / 6), L * math.sin(math.pi / 6)
    S = Polygon([(-10, 0), (0, 0), (x, y), (10, y), (10, 10), (-10, 10)])
    assert r * math.tan(math.pi / 12) < L < 2 * r * math.tan(math.pi / 12)
    T = vt.tighten(S, r)
    assert T._cache["_path"] == "fast" and T.verify() == []
    c = disks(T)[0]
    t = r * math.tan(math.pi / 12)
    for cx, cy in ((-t, r), (x + t, y - r)):
        assert np.hypot(c[:, 0] - cx, c[:, 1] - cy).min() < 1e-12
    assert_same(T, general(S, r), rel=1e-10)
    assert_exact(S, r, T)


def test_a_step_beside_another_short_edge_goes_to_the_general_engine():
    # A notch 0.5 wide and 0.7 deep (taken by `_same_side_runs`) whose left mouth corner's wall is a step
    # 0.3 high: the step's disk and the notch's mouth disk would be the same.
    S = Polygon([(0, 0), (4.8, 0), (4.8, 0.3), (5, 0.3), (5, 1), (5.5, 1), (5.5, 0.3), (10, 0.3), (10, 10),
                 (0, 10)])
    assert vt.tighten(S, 1.0)._cache["_path"] == "general"


@st.composite
def stepped_walls(draw):
    """A block whose lower wall has 1–5 steps up or down (heights 0.05r–1.8r, slanted forward or back by up
    to 0.4 of their height: turns of 68°–112°, tangents up to 1.5r), 4r–7r apart so that each is isolated,
    turned by a random angle; r = 1."""
    k = draw(st.integers(1, 5))
    pts, x, y = [(0.0, 0.0)], 0.0, 0.0
    for _ in range(k):
        x += draw(st.floats(4.0, 7.0))
        pts.append((x, y))
        h = draw(st.floats(0.05, 1.8))
        x += h * draw(st.floats(-0.4, 0.4))
        y += h * draw(st.sampled_from([-1.0, 1.0]))
        pts.append((x, y))
    x += draw(st.floats(4.0, 7.0))
    pts += [(x, y), (x, 12.0), (0.0, 12.0)]
    S = Polygon(pts)
    return shapely.affinity.rotate(S, draw(st.floats(0, 360)), origin=(0, 0)) if S.is_valid else None


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(S=stepped_walls(), init=st.sampled_from(["core", "input", "mason"]))
def test_bridged_results_are_the_general_engines(S, init):
    if S is None:
        return
    T = vt.tighten(S, 1.0, init=init)
    assert T._cache["_path"] == "fast" and T.verify() == []
    assert_same(T, general(S, 1.0, init), rel=1e-10)
    assert_exact(S, 1.0, T)


def test_a_slid_disk_at_a_grazing_angle_passes_the_final_check():
    # A star whose step has a convex corner with a tangent longer than the step: its disk slides until it
    # meets the reflex end, where the edge's offset meets that vertex's circle at a grazing angle. The
    # final check's coarse shrink misplaces that corner by its chord's sagitta / sin(angle); the finer
    # check it falls back on passes the exact answer.
    S = Polygon([(9.593353847388743, 2.8051239193500965), (2.477544273894597, -6.502111992421594),
                 (2.1525955523651894, -5.978719546634362), (-9.023389714627127, -0.8715879061864402),
                 (-7.8763066249148945, 5.105097678900334), (-7.3178190548564865, 6.586034935054179),
                 (-1.4743194611653663, 6.443160875529573), (5.099590617529096, 1.7973554079537892),
                 (7.545725370548143, 2.3868017235700805)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        T = vt.tighten(S, 0.6)
    assert T._cache["_path"] == "fast" and T.converged and T.verify() == []
    assert_same(T, general(S, 0.6), rel=1e-10)
    assert_exact(S, 0.6, T)


def test_two_steps_in_a_row_before_a_corner():
    # Turns of +30° and −30° on edges of 0.5 and 0.7, then the block's right-angled corner: both edges
    # are steps (their tangents overlap); the middle corner's disk touches both, the corner's slides back
    # along the wall above it until it meets the middle vertex.
    r = 1.0
    a = (0.5 * math.cos(math.pi / 6), 0.5 * math.sin(math.pi / 6))
    b = (a[0] + 0.7, a[1])
    S = Polygon([(-10, 0), (0, 0), a, b, (b[0], 10), (-10, 10)])
    T = vt.tighten(S, r)
    assert T._cache["_path"] == "fast" and T.verify() == []
    x = b[0] - r                                    # the slid disk: r left of the wall x = b[0] ...
    y = a[1] + math.sqrt(r * r - (x - a[0]) ** 2)  # ... and r from the middle vertex
    c = disks(T)[0]
    assert np.hypot(c[:, 0] - x, c[:, 1] - y).min() < 1e-12
    assert_same(T, general(S, r), rel=1e-10)
    assert_exact(S, r, T)


def test_a_jog_whose_middle_corner_the_loop_passes_by():
    # Up 0.3, right 0.4, up again (r = 1). The reflex corner (0, 0.3) between the two steps has a tangent r
    # longer than both: its (outside) disk touches neither of its edges but rests on (0, 0) and
    # (0.4, 0.3), sqrt(r² − 0.25²) from the middle of the line between them. The convex corners' disks
    # slide until they meet the middle vertex: to (−√(2·0.3 − 0.09), 1) along y = 0 and to (−0.6, 1.1)
    # along x = 0.4. The middle disk lies beyond their common tangent, which the loop runs along: the
    # middle corner is not on the loop, but its disk cuts the offset curves the checks measure against.
    r = 1.0
    S = Polygon([(-10, 0), (0, 0), (0, 0.3), (0.4, 0.3), (0.4, 10), (-10, 10)])
    T = vt.tighten(S, r)
    assert T._cache["_path"] == "fast" and T.verify() == []
    a, b = (-math.sqrt(0.6 - 0.09), 1.0), (-0.6, 1.1)
    c = disks(T)[0]
    assert len(c) == 5                              # the two slid disks and the block's three corners
    for x, y in (a, b):
        assert np.hypot(c[:, 0] - x, c[:, 1] - y).min() < 1e-12
    pieces = [p for L in T.loops for p in L.pieces]
    tangent = math.hypot(b[0] - a[0], b[1] - a[1])
    assert min(abs(p.length - tangent) for p in pieces) < 1e-12
    for init in ("core", "input", "mason"):
        T = vt.tighten(S, r, init=init)
        assert_same(T, general(S, r, init), rel=1e-10)
        assert_exact(S, r, T)


def test_a_neck_narrower_than_2r_parts_the_core():
    # Squares of 10 and 10.5 overlapping in a 0.5 × 0.5 corner: the neck, 0.5·√2 wide, lets no disk of radius 1
    # through, so the core has two rings and init="core" gives two loops (the general engine's); the
    # offset arcs about the neck's two reflex corners cross nearer than r to S, which the fast path now
    # sees. init="input" keeps one loop through the neck.
    S = shapely.box(0, 0, 10, 10).union(shapely.box(9.5, 9.5, 20, 20))
    T = vt.tighten(S, 1.0)
    assert len(T.loops) == 2 and T._cache["_path"] == "general"
    assert abs(T.perimeter - (40 - 8 + 2 * math.pi) - (42 - 8 + 2 * math.pi)) < 1e-9
    T = vt.tighten(S, 1.0, init="input")
    assert len(T.loops) == 1 and T._cache["_path"] == "fast"
    assert_same(T, general(S, 1.0, "input"), rel=1e-10)


def test_a_cut_away_piece_must_be_nearer_than_r_to_s():
    # `_covered` on a wall along y = 0 (r = 1): a segment at height 0.5 is covered; one at height 1 is
    # not, but for an end kept (exactly r away there is the moved centre); an arc about (0, 0) is covered
    # where it dips below y = 1 only; a piece of the wall's own offset is not covered by the wall itself.
    from vectortighten import _fast
    from vectortighten import morphology as M

    D = _fast._Rings(M._orient(shapely.box(-10, -10, 10, 0)), 1.0)
    p, q = np.array([-2.0, 0.5]), np.array([2.0, 0.5])
    assert _fast._covered(D, [("seg", (p, q), False, False, ())])
    high = (np.array([-2.0, 1.0]), np.array([2.0, 1.0]))
    assert not _fast._covered(D, [("seg", high, False, False, ())])
    rising = (np.array([-2.0, 0.5]), np.array([-2.0, 1.0]))
    assert _fast._covered(D, [("seg", rising, False, True, ())])
    assert not _fast._covered(D, [("seg", rising, True, False, ())])
    centre = np.array([0.0, 0.0])
    assert _fast._covered(D, [("arc", (centre, 0.1, 1.2), False, False, ())])
    assert not _fast._covered(D, [("arc", (centre, 0.1, 1.5), False, False, ())])
    assert _fast._covered(D, [("arc", (centre, 0.1, math.pi / 2 - 0.1), False, True, ())])
    wall = int(np.flatnonzero((D.v[:, 1] == 0) & (D.v[D.next, 1] == 0))[0])
    assert not _fast._covered(D, [("seg", (p, q), False, False, (wall,))])


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(overlap=st.floats(0.05, 2.5), size=st.floats(4.0, 12.0), turn=st.floats(0, 90),
       init=st.sampled_from(["core", "input", "mason"]))
def test_necks_of_every_width_match_the_general_engine(overlap, size, turn, init):
    # Two squares overlapping at a corner by `overlap` (a neck overlap·√2 wide, below and above 2r = 2): the
    # answer of whichever path takes it is the general engine's, loop for loop.
    S = shapely.box(0, 0, size, size).union(shapely.box(size - overlap, size - overlap, 2 * size, 2 * size))
    S = shapely.affinity.rotate(S, turn, origin=(0, 0))
    T = vt.tighten(S, 1.0, init=init)
    assert_same(T, general(S, 1.0, init), rel=1e-10)
