"""The annulus shortcut (`engine._annulus_loops`): where a part of the guide fillet without holes holds
parts of the guide core without holes, the tight loop round each is found by the exact finish from a
guess made on the core's boundary, without building and triangulating the free space. It must give the
free space's loops exactly, decline where a part has a hole, take a part of the fillet whole or not at
all, and give up a bad guess quickly.

And the finish's loops no longer keep disks they only graze (`engine._without_grazed`): a straight piece
is not cut where it touches a disk at one point, whichever way the loop was found."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon, box

import vectortighten as vt
from vectortighten import engine

from .engines import assert_exact, assert_same, counted_checks, general, with_and_without_shortcuts
from .strategies import pixel_outline, radii_for, stars
from .test_split import STEPPED, comb


def jagged(n, seed=3):
    """A star with noise of 0.05 on a radius of 10 (at r = 0.5, many anticore disks in its crevices)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 10 * (1 + 0.04 * np.sin(12 * t)) + rng.normal(0, 0.05, n)
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


def harmonic(n, seed=0):
    """A star whose ripples (amplitude about 2r and 0.15r at r = 1) are comparable to r."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 20 + 2 * np.sin(9 * t + rng.uniform(0, 6)) + 0.15 * np.sin(61 * t)
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


@pytest.fixture
def taken(monkeypatch):
    """What `_annulus_loop` returned on each call during a test (None: declined or given up), with the
    loops from the exact shrink (`engine._shrink_parts`, tested in test_shrink_loops.py) turned off: on
    these shapes they would come first, and this shortcut is what the engine falls back on."""
    monkeypatch.setattr(engine, "_shrink_parts", lambda ctx: None)
    seen = []
    inner = engine._annulus_loop

    def spy(ctx, ring):
        out = inner(ctx, ring)
        seen.append(out)
        return out

    monkeypatch.setattr(engine, "_annulus_loop", spy)
    return seen


def collinear_joins(T) -> int:
    """How many joins of two straight pieces that run on in one direction the result's loops have."""
    count = 0
    for loop in T.loops:
        data, arc = loop._data, loop._arc
        n = len(data)
        for i in range(n):
            j = (i + 1) % n
            if n < 2 or arc[i] or arc[j]:
                continue
            u, v = data[i, 2:4] - data[i, 0:2], data[j, 2:4] - data[j, 0:2]
            cross = u[0] * v[1] - u[1] * v[0]
            if abs(cross) <= 1e-9 * math.hypot(*u) * math.hypot(*v) and u @ v > 0:
                count += 1
    return count


SHAPES = {
    "stepped footprint": (STEPPED, 1.0),
    "comb": (comb(12), 1.0),
    "harmonic star": (harmonic(1000), 1.0),
    "pixel outline": (pixel_outline(600), 0.6),
}


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_the_annulus_loop_is_the_free_space_loop(name, taken):
    S, r = SHAPES[name]
    T = vt.tighten(S, r)
    assert T._cache["_path"] == "general"
    assert taken and taken[-1] is not None          # the shortcut gave the loop
    G = general(S, r)
    assert_same(T, G)
    mine, theirs = T._cache["_exact"][1], G._cache["_exact"][1]
    assert [sorted(L.cid.tolist()) for L in mine] == [sorted(L.cid.tolist()) for L in theirs]
    assert_exact(S, r, T)
    assert T.verify() == []


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_stars_tighten_the_same_with_and_without_the_shortcut(data):
    S = data.draw(stars())
    T, G = with_and_without_shortcuts(S, data.draw(radii_for(S)))
    assert T.converged == G.converged
    assert_same(T, G)


def test_each_part_of_the_fillet_that_is_an_annulus_takes_the_shortcut(taken):
    # Two stepped footprints 2.5r apart: one group of the split (nearer than 3r), two parts of the fillet
    # (the gap is wider than 2r), each holding one part of the core.
    S = shapely.MultiPolygon([STEPPED, shapely.affinity.translate(STEPPED, 18.5, 0.0)])
    assert shapely.distance(*S.geoms) == pytest.approx(2.5, abs=0.3)
    T = vt.tighten(S, 1.0)
    assert len(taken) == 2 and all(L is not None for L in taken)
    G = general(S, 1.0)
    assert_same(T, G)
    assert_exact(S, 1.0, T)


def test_no_shortcut_where_the_fillet_or_a_core_part_has_a_hole():
    ring = box(0, 0, 20, 20).difference(box(6, 6, 14, 14))           # the core and the fillet have a hole
    G = general(ring, 1.0)
    ctx = G._cache["_exact"][0]
    rings = engine._rings(ctx.R)
    taken, rest = engine._annulus_loops(ctx, rings)
    assert taken == [] and len(rest) == len(rings)


@pytest.mark.parametrize("S", [
    shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.5, 10, 3.5)]),   # a neck 1 wide
    shapely.MultiPolygon([box(0, 0, 6, 6), box(7, 0, 13, 6)]),                      # a gap 1 wide
    shapely.union_all([box(0, 0, 6, 6), box(5.5, 5.5, 11.5, 11.5)]),                # corners overlapping
])
def test_one_part_of_the_fillet_with_two_core_parts_takes_each_loop_or_none(S):
    # The fillet bridges the neck or the gap (narrower than 2r): one part of it holds both parts of the
    # core, and each loop is taken only if it encloses its own core part and not the other.
    G = general(S, 1.0)
    ctx = G._cache["_exact"][0]
    R_parts = list(shapely.get_parts(ctx.R))
    assert len(R_parts) == 2 and len(shapely.get_parts(ctx.F)) == 1
    rings = engine._rings(ctx.R)
    taken, rest = engine._annulus_loops(ctx, rings)
    assert (len(taken), len(rest)) == (2, 0)
    if taken:
        inside = [Polygon(L.to_loop().sample(1e-3 * ctx.r)) for L in taken]
        for P in R_parts:                        # each core part inside exactly one loop
            assert sum(Q.contains(P.representative_point()) for Q in inside) == 1
    assert_same(vt.tighten(S, 1.0), G)


def test_a_far_off_guess_is_given_up_within_its_rounds(monkeypatch, taken):
    checks = counted_checks(monkeypatch)
    budgeted = []
    finish = engine._finish_steps

    def spy(ctx, cid, side, ref, rounds=None):
        before = len(checks)
        out = finish(ctx, cid, side, ref, rounds=rounds)
        if rounds is not None:
            budgeted.append(len(checks) - before)
        return out

    monkeypatch.setattr(engine, "_finish_steps", spy)
    S, r = jagged(1000), 0.5
    T = vt.tighten(S, r)
    assert taken == [None]                           # the guess on this jagged outline is far off
    assert budgeted and max(budgeted) <= engine._ANNULUS_ROUNDS
    assert_same(T, general(S, r))


@pytest.mark.parametrize("name", ["pixel outline", "stepped footprint"])
def test_no_straight_piece_is_cut_where_the_loop_grazes_a_disk(name):
    S, r = SHAPES[name]
    for T in (vt.tighten(S, r), general(S, r)):
        assert collinear_joins(T) == 0
        for L in T._cache["_exact"][1]:
            assert (np.abs(L.sweep) > engine._ANGLE_EPS).all()      # no disk touched at one point only


def test_a_loop_found_here_is_not_kept_beside_a_free_space_loop_in_the_same_part_of_the_fillet():
    # Found by the identity benchmark: on this traced mask at r = 1 stroke width, one part of the fillet
    # holds several parts of the core; taking the loops of some of them here and leaving the others to
    # the free space kept two touching loops apart (no surgery) and one of them wrapped a disk from the
    # wrong side. A part of the fillet is now taken whole or not at all.
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    import corpus

    case = next(c for c in corpus.masks() if c.name == "Grace Hopper, dark regions")
    S, r = case.shape, case.width
    T = vt.tighten(S, r)
    assert T.verify() == []
    assert_same(T, general(S, r))


def test_a_part_of_the_fillet_with_a_hole_keeps_its_loops_out_of_the_hole():
    # Eight disks of radius 2 round a lake, 0.5 apart at r = 1: the fillet bridges the gaps into a ring
    # with a hole (anticore disks fit in the lake), holding the eight cores. Each loop encloses its own
    # core and neither another core nor the lake: taken, and the same disks as the free space's loops.
    centre = 4.5 / (2 * math.sin(math.pi / 8))
    S = shapely.MultiPolygon([shapely.Point(centre * math.cos(a), centre * math.sin(a)).buffer(2.0, 32)
                              for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)])
    G = general(S, 1.0)
    ctx = G._cache["_exact"][0]
    (F_part,) = shapely.get_parts(ctx.F)
    assert len(F_part.interiors) == 1 and len(shapely.get_parts(ctx.R)) == 8
    (lake,) = engine._hole_witnesses(ctx, F_part)          # an anticore centre in the lake, r from S
    assert Polygon(F_part.interiors[0]).contains(shapely.Point(ctx.cxy[lake]))
    assert shapely.distance(ctx.S, shapely.Point(ctx.cxy[lake])) >= ctx.r * (1 - 1e-9)
    taken, rest = engine._annulus_loops(ctx, engine._rings(ctx.R))
    assert len(taken) == 8 and rest == []
    theirs = sorted(sorted(L.cid.tolist()) for L in G._cache["_exact"][1])
    assert sorted(sorted(L.cid.tolist()) for L in taken) == theirs


def test_a_loop_round_a_lake_of_the_fillet_is_not_taken():
    # A C of core round a lake of the anticore whose mouth the fillet closes: a guess that encloses the
    # lake is refused by the lake's witness (the loop must leave every hole of the fillet part outside).
    S = box(0, 0, 20, 20).difference(box(5, 5, 15, 15)).difference(box(9.5, 0, 10.5, 5))
    G = general(S, 2.0)
    ctx = G._cache["_exact"][0]
    F_parts = list(shapely.get_parts(ctx.F))
    lakes = [engine._hole_witnesses(ctx, F) for F in F_parts]
    assert any(w is not None and len(w) for w in lakes)
    taken, rest = engine._annulus_loops(ctx, engine._rings(ctx.R))
    for L in taken:
        inside = Polygon(L.to_loop().sample(1e-3 * ctx.r))
        for w in lakes:
            assert w is None or not shapely.contains_xy(inside, *ctx.cxy[w].T).any()
    assert_same(vt.tighten(S, 2.0), G)
