"""Tight loops shown from the exact shrink's boundary (`engine._shrink_parts`): where no part of S↓r has a
hole, each part of the core gets the exact finish from a guess made along its loops of ``S↓r``, and a loop is
kept only if it settles, turns once and holds exactly its own part's points of the shrink and no point of
the complement's shrink; loops that touch are the surgery's. No guide core, fillet or free space is built
where every part is shown; a part that is not goes alone through the free space. It must give the free
space's loops exactly and decline whatever it cannot show."""

import warnings

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull
from shapely.geometry import Point, Polygon, box

import vectortighten as vt
from vectortighten import engine

from .engines import assert_exact, assert_same, counted_checks, general, with_and_without_shortcuts
from .strategies import pixel_outline, radii_for, shapes
from .test_annulus import harmonic
from .test_split import STEPPED, comb

#: Two squares whose shrinks are 1.41r apart at their corners: two loops of the shrink, one part of the core.
CORNERS = shapely.union_all([box(0, 0, 6, 6), box(5, 5, 11, 11)])
#: Two squares joined by a neck thinner than 2r: two parts of the core, one loop each.
DUMBBELL = shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.5, 10, 3.5)])
#: A C round a cavity whose mouth (1 wide) no r-disk passes at r = 2: a pocket of anticore inside.
POCKET = box(0, 0, 20, 20).difference(box(5, 5, 15, 15)).difference(box(9.5, 15, 10.5, 20))
#: A square with a lake whose right wall (1.5 wide) holds no core at r = 1: S has a hole, its shrink none.
LAKE = box(0, 0, 20, 20).difference(box(5, 5, 18.5, 15))

SHAPES = {
    "stepped footprint": (STEPPED, 1.0),
    "comb": (comb(12), 1.0),
    "harmonic star": (harmonic(1000), 1.0),
    "pixel outline": (pixel_outline(600), 0.6),
    "corners": (CORNERS, 1.0),
    "dumbbell": (DUMBBELL, 1.0),
    "pocket": (POCKET, 2.0),
    "lake": (LAKE, 1.0),
    "star with a pond": (harmonic(1000).difference(Point(0, 0).buffer(8, quad_segs=16)), 1.0),
    "star with a pinhole": (harmonic(1000).difference(box(-0.75, -0.75, 0.75, 0.75)), 1.0),
}


@pytest.fixture
def shown(monkeypatch):
    """The loops `_shrink_parts` showed on each call during a test (None: declined, or not all shown)."""
    seen = []
    inner = engine._shrink_parts

    def spy(ctx):
        out = inner(ctx)
        loops = None if out is None or any(Ls is None for Ls, _ in out) else [L for Ls, _ in out for L in Ls]
        seen.append((ctx, loops))
        return out

    monkeypatch.setattr(engine, "_shrink_parts", spy)
    return seen


def context(S, r):
    """The general engine's context for S at r (local frame), as `tighten` builds it."""
    return general(S, r)._cache["_exact"][0]


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_the_loops_shown_from_the_shrink_are_the_free_space_loops(name, shown):
    S, r = SHAPES[name]
    T = vt.tighten(S, r)
    assert T._cache["_path"] == "general"
    (ctx, loops), = shown
    assert loops is not None                            # shown, without the guide core and fillet
    assert ctx._R is None and ctx._F is None and ctx._domain is None
    G = general(S, r)
    assert_same(T, G)
    mine, theirs = T._cache["_exact"][1], G._cache["_exact"][1]
    assert sorted(sorted(L.cid.tolist()) for L in mine) == sorted(sorted(L.cid.tolist()) for L in theirs)
    assert_exact(S, r, T)
    assert T.converged and T.verify() == []


def test_two_parts_of_the_shrink_nearer_than_2r_are_one_part_of_the_core(shown):
    T = vt.tighten(CORNERS, 1.0)
    (ctx, loops), = shown
    _, P, cycles, lone = ctx.side_loops(1)
    points = [engine._cycle_points(P, np.asarray(c), ctx.r)[0] for c in cycles]
    assert len(cycles) == 2 and len(lone) == 0
    assert engine._core_groups(points, ctx.r) in ([[0, 1]], [[1, 0]])
    assert loops is not None and len(loops) == 1 and len(T.loops) == 1       # one loop round both


def test_parts_of_the_shrink_farther_than_2r_apart_get_a_loop_each(shown):
    T = vt.tighten(DUMBBELL, 1.0)
    (_, loops), = shown
    assert loops is not None and len(loops) == 2 and len(T.loops) == 2


@pytest.mark.parametrize("gap, groups", [(1.5, [[0, 1]]), (2.0, None), (1.97, None), (2.04, None),
                                         (3.0, [[0], [1]])])
def test_parts_of_the_shrink_are_grouped_by_2r_and_not_at_all_too_near_it(gap, groups):
    # Two unit squares' boundaries `gap` apart (r = 1): nearer than 2r, one part of the core; farther,
    # two; within 0.05r of 2r, too near to call from points within 0.02r of the exact loops.
    square = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
    got = engine._core_groups([square, square + (1.0 + gap, 0.0)], 1.0)
    if groups is None:
        assert got is None
    else:
        assert sorted(sorted(g) for g in got) == groups


def test_a_hole_of_the_shrink_gets_the_loop_round_its_anticore():
    ring = box(0, 0, 20, 20).difference(box(6, 6, 14, 14))          # the shrink is an annulus
    ctx = context(ring, 1.0)
    _, P, cycles, _ = ctx.side_loops(1)
    areas = engine._cycle_areas(P, cycles)
    assert sorted(np.sign(areas)) == [-1, 1]
    # in the local frame (size 1): the outer loop bounds the 18 × 18 square, the hole the 10 × 10 one
    # with its corners rounded by r, all over 20²
    assert sorted(areas) == pytest.approx([-(100 - (4 - np.pi)) / 400, 324 / 400], rel=1e-12)
    loops = engine._shrink_loops(ctx)
    assert loops is not None and len(loops) == 2
    outer, hole = loops
    assert outer.sweep.sum() == pytest.approx(2 * np.pi) and hole.sweep.sum() == pytest.approx(-2 * np.pi)
    # round the hole's anticore (the 8 × 8 hole with its corners rounded by r): its four corner disks
    assert hole.n == 4 and (hole.side < 0).all()
    assert hole.to_loop().area == pytest.approx(-(64 - (4 - np.pi)) / 400, rel=1e-12)
    G = general(ring, 1.0)
    assert sorted(sorted(L.cid.tolist()) for L in loops) == \
        sorted(sorted(L.cid.tolist()) for L in G._cache["_exact"][1])


def test_a_guess_wound_round_twice_is_given_up_before_any_check(monkeypatch):
    ctx = context(box(0, 0, 20, 20).difference(box(6, 6, 14, 14)), 1.0)
    outer = engine._shrink_loops(ctx)[0]
    assert outer.n == 4                             # the core disks at the outer corners of the shrink
    checks = counted_checks(monkeypatch)
    twice = np.tile(outer.cid, 2)                   # round the square twice: 4π
    L = engine._finish_steps(ctx, twice, np.ones(8, np.int64), np.full(8, np.pi / 2), rounds=6)
    assert L is not None and not L.converged and L.sweep.sum() == pytest.approx(4 * np.pi)
    assert checks == []
    L = engine._finish_steps(ctx, outer.cid, outer.side, outer.sweep, rounds=6)       # once round: settled
    assert L.converged and checks == [4]


def test_a_loop_round_a_pocket_of_the_anticore_is_refused(monkeypatch):
    # The pocket's witness (a point of the complement's shrink in the cavity) refuses a loop that
    # settles round the outside of the C: a taut loop, in the wrong class.
    ctx = context(POCKET, 2.0)
    core = np.flatnonzero(ctx.cside == 1)
    hull = core[ConvexHull(ctx.cxy[core]).vertices]             # counter-clockwise
    settled = []
    finish = engine._finish_steps

    def spy(ctx_, cid, side, ref, rounds=None):
        out = finish(ctx_, cid, side, ref, rounds=rounds)
        settled.append(out is not None and out.converged)
        return out

    monkeypatch.setattr(engine, "_shrink_start", lambda *a: (hull, np.ones(len(hull), np.int64),
                                                             np.zeros(len(hull))))
    monkeypatch.setattr(engine, "_finish_steps", spy)
    assert engine._shrink_loops(ctx) is None
    assert settled and settled[0]                               # it settled: only the witness refused it
    monkeypatch.undo()
    assert engine._shrink_loops(context(POCKET, 2.0)) is not None     # the guess along the C is right


#: Two 128-gons of radius 3, centres 6.05 apart, joined by a bar 0.5 wide: at r = 1 their shrinks are about
#: 2.008r apart, too near 2r to call from sample points; their exact distance parts the core in two.
TWINS = shapely.union_all([Point(0, 0).buffer(3, quad_segs=32), Point(6.05, 0).buffer(3, quad_segs=32),
                          box(2.5, -0.25, 3.55, 0.25)])
#: A square frame round a lake, its top right corner cut so that no r-disk fits there (r = 0.8) although
#: the disks on either side of it overlap: a part of the core with a hole round the lake's anticore, which
#: no loop of the shrink's guess can show. A bar thinner than 2r joins it to a harmonic star.
FRAME = Polygon([(0, 0), (10, 0), (10, 7.8), (7.8, 10), (0, 10)], [[(2, 2), (8, 2), (8, 8), (2, 8)]])
FRAMED_STAR = shapely.union_all([FRAME, box(9, 4.8, 14.5, 5.2),
                                 shapely.affinity.translate(harmonic(600), 35, 5)])


def test_two_loops_of_the_shrink_about_2r_apart_are_told_apart_exactly(shown, monkeypatch):
    measured = []
    exact = engine._cycle_distance
    monkeypatch.setattr(engine, "_cycle_distance", lambda *a: measured.append(exact(*a)) or measured[-1])
    T = vt.tighten(TWINS, 1.0)
    (ctx, loops), = shown
    assert measured and all(2.0 < d / ctx.r < 2.02 for d in measured)
    assert loops is not None and len(loops) == 2 and ctx._R is None        # two parts, shown
    assert_same(T, general(TWINS, 1.0))
    assert_exact(TWINS, 1.0, T)
    assert T.verify() == []


@pytest.mark.parametrize("d, groups", [(1.9, [[0, 1]]), (2.1, [[0], [1]]), (2.0, None),
                                       (2.0 + 1e-9, [[0], [1]]), (2.0 + 1e-13, None)])
def test_a_distance_in_the_band_is_decided_by_the_exact_one(d, groups):
    square = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
    got = engine._core_groups([square, square + (3.0, 0.0)], 1.0, exact=lambda i, j: d, tie=1e-12)
    if groups is None:
        assert got is None                                          # a tie: the core parts touch
    else:
        assert sorted(sorted(g) for g in got) == groups


def test_a_part_not_shown_goes_alone_through_the_free_space(monkeypatch):
    parts, rings = [], []
    inner, free = engine._shrink_parts, engine._tighten_all
    monkeypatch.setattr(engine, "_shrink_parts", lambda ctx: parts.append(inner(ctx)) or parts[-1])

    def counted(ctx, rest, shown=()):
        rings.append((len(rest), len(shown)))
        return free(ctx, rest, shown)

    monkeypatch.setattr(engine, "_tighten_all", counted)
    T = vt.tighten(FRAMED_STAR, 0.8)
    (got,) = parts
    assert sorted(L is None for L, _ in got) == [False, True]          # the star shown, the frame not
    assert rings == [(2, 1)]              # the frame's part of the core: its outer ring and its hole
    G = general(FRAMED_STAR, 0.8)
    assert_same(T, G)
    assert len(T.loops) == 3 and T.n_holes == 1                        # the lake keeps its loop
    assert_exact(FRAMED_STAR, 0.8, T)
    assert T.converged and T.verify() == []


def test_a_large_part_not_shown_sends_every_part_to_the_free_space(monkeypatch):
    # The frame alone with a small square: the frame holds far more than a quarter of the shrink's
    # boundary, so the square's loop would save little of the free space built for it.
    S = shapely.union_all([FRAME, box(9, 4.8, 14.5, 5.2), box(14, 2, 20, 8)])
    ctx = context(S, 0.8)
    assert engine._shrink_parts(ctx) is None
    assert_same(vt.tighten(S, 0.8), general(S, 0.8))


#: A random 12-gon (found by the property tests) whose guess along its loop of E places anticore disks
#: where the finish does not settle from them at r = 3.33…; without them it settles.
MISPLACED = shapely.from_wkt(
    "POLYGON ((9.832786363079075 9.832786363079075e-12, 3.0003314533757117 2.6453754308007755, "
    "4.561598380323562 5.68490431491447, 0.2291741362479616 3.2316807362628555, "
    "-0.6850895400952997 4.896098776194685, -2.0473535103985827 0.7223572341694705, "
    "-1.9981843499753458 0.0854359620628536, -4.054328901398842 -1.368334969093841, "
    "-3.288569209585922 -9.378125940803276, 4.376574903615468 -6.816111562421533, "
    "6.481470180536084 -6.8992489170647575, 4.08124232526637 -2.0926435772621494, "
    "9.832786363079075 9.832786363079075e-12))")


def test_a_guess_that_does_not_settle_is_tried_again_without_its_anticore_disks(shown, monkeypatch):
    r = 3.3347602227169775
    tries = []
    settled = engine._settled

    def spy(ctx, start):
        out = settled(ctx, start)
        tries.append((bool((start[1] < 0).any()), out is not None))
        return out

    monkeypatch.setattr(engine, "_settled", spy)
    T = vt.tighten(MISPLACED, r)
    assert tries == [(True, False), (False, True)]
    (ctx, loops), = shown
    assert loops is not None and ctx._R is None                        # shown, without the guide
    assert_same(T, general(MISPLACED, r))
    assert_exact(MISPLACED, r, T)
    assert T.verify() == []


def test_touching_loops_are_left_to_the_surgery(monkeypatch):
    ctx = context(DUMBBELL, 1.0)
    assert engine._shrink_loops(ctx) is not None
    monkeypatch.setattr(engine, "_contacts", lambda ctx, loops: [(0, 0, None, 1, 0, None)])
    assert engine._shrink_loops(ctx) is None


def test_the_final_check_does_not_build_the_guide(monkeypatch):
    # The final check of a result shown from the shrink uses coarse buffers, as the fast path's does:
    # building the guide core and fillet only for it would cost more than the loops did.
    T = vt.tighten(STEPPED, 1.0)
    ctx = T._cache["_exact"][0]
    assert ctx.guide_free and ctx._R is None and ctx._F is None
    from vectortighten import _guard

    assert _guard.containment_problems(T) == [] and ctx._R is None


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_shapes_tighten_the_same_with_and_without_the_shortcuts(data):
    S = data.draw(shapes)
    T, G = with_and_without_shortcuts(S, data.draw(radii_for(S)))
    assert T.converged == G.converged
    assert_same(T, G, rel=1e-9)


def test_a_bar_drawn_2r_wide_keeps_its_centre_line():
    # 2.3 − 2 rounds to 0.2999999999999998: the box's width is 2r to the precision of its coordinates,
    # which is how the exact shrink decides the tie (the closed shrink is the centre line). The bounding
    # box test before the engine (`_guard.vanishes`) called it empty.
    S = Polygon([(1, 2), (1, 2.3), (0, 2.3), (0, 2)])
    T = vt.tighten(S, 0.15)
    assert T.area == pytest.approx(0.7 * 0.3 + np.pi * 0.15 ** 2, rel=1e-12)
    assert_same(T, general(S, 0.15))


def test_the_final_check_reads_the_exact_points_where_coarse_buffers_go_wrong():
    # Found by the random shapes: two octagons touching at a point, the small one too thin for a disk at
    # r = 1. GEOS's negative buffer of the pair keeps a ghost of the small one, and the coarse check said
    # the loop missed 2.8·r² of the core; the exact points of the shrinks say what is so.
    big = shapely.Point(0, 0).buffer(2.0, quad_segs=2)
    small = shapely.Point(0, 3).buffer(1.0, quad_segs=2)
    S = shapely.MultiPolygon([big, small])
    assert shapely.intersection(big, small).geom_type == "Point"
    from vectortighten import _guard

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        T = vt.tighten(S, 1.0)
    assert T.converged and T.verify() == [] and _guard.containment_problems(T) == []
    assert_same(T, general(S, 1.0))
    T.geometry = Polygon()                                # a result that misses the core is caught
    assert any("misses" in p for p in _guard.containment_problems(T))
