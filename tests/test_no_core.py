"""Shapes (and far-apart groups of parts) with no core: their tightening from the core is empty, found by
GEOS's maximum inscribed circles (`_guard.core_vanishes`) instead of the general engine, and
`Tightening.verify` proves the empty core again from S's exact shrink (no piece, no corner:
`offsets.shrink_is_empty`)."""

import numpy as np
import pytest
import shapely
from shapely.geometry import MultiPolygon, Point, Polygon, box

import vectortighten as vt
from vectortighten import engine
from vectortighten._guard import core_vanishes
from vectortighten.offsets import shrink_is_empty

from .engines import assert_exact, assert_same, general
from .test_split import comb, star


def local(T):
    """The shape, radius and precision of a result in the engine's local frame (`shrink_is_empty`'s)."""
    S_local, r_l, _, precision = T._cache["_exact"][2]
    return S_local, r_l, precision


def spiral(width, turns=3.0, n=2000, x0=0.0):
    """A strip ``width`` wide wound ``turns`` times (the benchmark's spiral strip)."""
    t = np.linspace(0, 2 * np.pi * turns, n // 2)
    a = 2 + 1.2 * t
    outer = np.column_stack([x0 + (a + width) * np.cos(t), (a + width) * np.sin(t)])
    inner = np.column_stack([x0 + a * np.cos(t), a * np.sin(t)])
    return Polygon(np.vstack([outer, inner[::-1]]))


def annulus(width, rad=10.0, centre=(0.0, 0.0)):
    c = Point(centre)
    return c.buffer(rad + width, quad_segs=64).difference(c.buffer(rad, quad_segs=64))


@pytest.mark.parametrize("S", [spiral(1.6), annulus(1.8), box(0, 0, 30, 1.5).union(box(0, 0, 1.2, 30))],
                         ids=["spiral", "annulus", "thin L"])
def test_a_shape_without_core_tightens_to_nothing_without_the_general_engine(S):
    assert core_vanishes(S, 1.0)
    T = vt.tighten(S, 1.0)
    assert T._cache["_path"] == "empty" and T.geometry.is_empty and T.loops == []
    assert T.converged and T.verify() == []
    G = general(S, 1.0)                       # the general engine finds no loop either
    assert G.geometry.is_empty and G.loops == []
    assert shrink_is_empty(*local(T))
    assert_exact(S, 1.0, T)                   # the independent oracle finds no core to miss


def test_a_core_just_wider_than_nothing_is_not_taken_for_empty():
    # The thin L's junction holds r-disks when its arms are 1.8r wide (centres (c, c), 1 ≤ c ≤ 1.8 − 1/√2).
    S = box(0, 0, 30, 1.8).union(box(0, 0, 1.8, 30))
    assert not core_vanishes(S, 1.0)
    T = vt.tighten(S, 1.0)
    assert T._cache["_path"] != "empty" and T.area > 0
    assert_same(T, general(S, 1.0))
    # A strip just under 2r wide has no core (the exact shrink says so, as the general engine does); one
    # exactly 2r wide has its centre line.
    assert core_vanishes(annulus(1.995), 1.0) and general(annulus(1.995), 1.0).geometry.is_empty
    T = vt.tighten(annulus(1.995), 1.0)
    assert T.geometry.is_empty and T._cache["_path"] == "empty" and T.verify() == []
    assert not core_vanishes(box(0, 0, 30, 2.0).union(box(0, 0, 2.0, 30)), 1.0)


@pytest.mark.parametrize("init", ["input", "mason"])
def test_other_initial_conditions_still_go_to_the_engine(init):
    S = annulus(1.8)
    T = vt.tighten(S, 1.0, init=init)
    assert T._cache["_path"] != "empty"
    assert_same(T, general(S, 1.0, init))


def test_far_apart_islets_drop_out_of_a_split_and_are_verified():
    islets = [Point(60 + 5 * k, 40).buffer(0.8, quad_segs=16) for k in range(3)]
    S = MultiPolygon([star(800), comb(6, x0=40.0), *islets, spiral(1.6, x0=120.0)])
    T = vt.tighten(S, 1.0)
    assert T._cache["_path"] == "split"
    paths = sorted(m._cache["_path"] for m in T._cache["_members"])
    assert paths == ["empty"] * 4 + ["fast", "general"]
    assert T.converged and T.verify() == []
    assert_same(T, general(S, 1.0))
    assert_exact(S, 1.0, T)


def test_verify_of_an_empty_result_falls_back_to_the_exact_check(monkeypatch):
    S = spiral(1.6)
    T = vt.tighten(S, 1.0)
    monkeypatch.setattr(engine, "shrink_is_empty", lambda *args: False)
    assert T.verify() == []                   # the full exact check finds no core either


def test_verify_finds_a_core_that_an_empty_result_misses():
    # An empty result claimed for a shape that has a core: verify's proof of emptiness fails, and the full
    # exact check names the missed core.
    S = shapely.orient_polygons(box(0, 0, 10, 10).union(box(10, 0, 40, 1.5)), exterior_cw=False)  # as checked
    frame = engine._Frame.of(S)
    S_local = frame.to_local(S)
    T = engine.Tightening(loops=[], geometry=Polygon(), r=1.0, init="core", tolerance=1e-5, shape=S)
    T._cache.update(_exact=(None, [], (S_local, 1.0 / frame.scale, 1e-5 / frame.scale,
                                       engine.precision_of(S) / frame.scale)),
                    _frame=frame, _path="empty")
    assert not shrink_is_empty(*local(T))
    problems = T.verify()
    assert any(p.startswith("(a) the tightening misses") for p in problems), problems


def test_core_vanishes_errs_only_towards_not_empty():
    # Random thin and thick polygons: whenever the inscribed circles claim no core, the general engine
    # finds none and no r-disk fits (the maximum inscribed circle, to 1e-4·r, is below r).
    rng = np.random.default_rng(7)
    claimed = 0
    for _ in range(40):
        n = int(rng.integers(5, 12))
        t = np.sort(rng.uniform(0, 2 * np.pi, n))
        rad = rng.uniform(0.5, 3.0, n)
        P = shapely.make_valid(Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)])))
        P = max(shapely.get_parts(P), key=lambda g: g.area) if P.geom_type != "Polygon" else P
        if P.geom_type != "Polygon" or P.area == 0:
            continue
        if core_vanishes(P, 1.0):
            claimed += 1
            assert shapely.maximum_inscribed_circle(P, 1e-4).length < 1.0
            assert general(P, 1.0).geometry.is_empty
    assert claimed >= 5


def test_a_disk_that_geos_inscribed_circle_misses_on_a_long_strip_is_still_found():
    # A strip 1.4r wide and 5·10⁴·r long, drawn with 2.5·10⁴ vertices, with one blob 1.4r in radius: no
    # sampled edge middle lies in the blob, and GEOS's maximum inscribed circle stops its search (2000 +
    # 2000·ln of size over tolerance cells) at the strip's 0.7r. The exact shrink finds the blob's core.
    L = 50_000.0
    S = shapely.segmentize(box(0, 0, L, 1.4), 4.0).union(Point(0.37 * L + 0.3, 0.7).buffer(1.4, quad_segs=8))
    assert shapely.maximum_inscribed_circle(S, 0.25).length < 0.75       # GEOS's search, cut short
    assert not shrink_is_empty(S, 1.0)
    assert not core_vanishes(S, 1.0)
