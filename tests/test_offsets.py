"""The exact offsets (`vectortighten.offsets`): hand-derived shrinks, the closed rule, and GEOS agreement."""

import math

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree
from shapely import affinity
from shapely.geometry import Point, Polygon, box

import vectortighten as vt
from vectortighten._validation import check_shape
from vectortighten.offsets import exact_offsets

from .strategies import pixel_outline


def corners(S, r, side=1):
    return sorted(map(tuple, exact_offsets(check_shape(S), r, side).corners.round(9).tolist()))


def test_box_corners_are_the_inset_rectangle():
    assert corners(box(0, 0, 4, 3), 1.0) == [(1.0, 1.0), (1.0, 2.0), (3.0, 1.0), (3.0, 2.0)]


def test_box_has_no_anticore_corners_and_arcs_about_its_vertices():
    E = exact_offsets(check_shape(box(0, 0, 4, 3)), 1.0, -1)
    assert len(E.corners) == 0
    assert len(E.arc_sweep) == 4
    assert np.allclose(np.abs(E.arc_sweep), math.pi / 2)
    assert len(E.seg) == 4


def test_l_shape_reflex_vertex_gives_an_arc_of_the_shrink():
    L = Polygon([(0, 0), (4, 0), (4, 1.5), (1.5, 1.5), (1.5, 4), (0, 4)])   # reflex vertex at (1.5, 1.5)
    E = exact_offsets(check_shape(L), 0.5)
    assert len(E.arc_sweep) == 1
    assert np.allclose(E.arc_center, [[1.5, 1.5]])
    assert math.isclose(abs(E.arc_sweep[0]), math.pi / 2)
    # convex corners of the shrink: the inset corners of the arms
    assert set(corners(L, 0.5)) == {(0.5, 0.5), (3.5, 0.5), (3.5, 1.0), (0.5, 3.5), (1.0, 3.5)}


@pytest.mark.parametrize("angle", [0.0, 30.0, 73.1])
@pytest.mark.parametrize("origin", [(0.0, 0.0), (1e5, -3e5)])
def test_bar_exactly_2r_wide_keeps_its_centre_line(angle, origin):
    r = 0.75
    bar = affinity.translate(affinity.rotate(box(0, 0, 10, 2 * r), angle, origin=(0, 0)), *origin)
    E = exact_offsets(check_shape(bar), r)
    assert len(E.corners) == 2
    ends = np.array([[r, r], [10 - r, r]])
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    ends = ends @ np.array([[c, s], [-s, c]]) + origin
    d, _ = cKDTree(E.corners).query(ends)
    assert d.max() < 1e-9 * r
    assert len(E.seg) >= 1 and all(math.isclose(np.hypot(*(q - p)), 10 - 2 * r, rel_tol=1e-9) for p, q in E.seg)


@pytest.mark.parametrize("eps, kept", [(1e-9, True), (-1e-9, False), (1e-3, True), (-1e-3, False)])
def test_bar_near_2r_is_decided_by_its_width(eps, kept):
    r = 1.0
    E = exact_offsets(check_shape(affinity.rotate(box(0, 0, 10, 2 * r * (1 + eps)), 21.0)), r)
    assert (len(E.corners) > 0) == kept


def test_square_of_side_2r_has_its_centre_as_the_shrink():
    assert corners(box(0, 0, 2, 2), 1.0) == [(1.0, 1.0)]
    assert corners(box(0, 0, 2, 2), 1.0 + 1e-9) == []


def test_gap_exactly_2r_keeps_the_anticore_centre_line():
    r = 0.5
    two = box(0, 0, 4, 4).union(box(4 + 2 * r, 0, 9, 4))
    E = exact_offsets(check_shape(two), r, -1)
    mid = 4 + r
    on_line = E.seg[np.all(np.abs(E.seg[:, :, 0] - mid) < 1e-12, axis=1)]
    assert len(on_line) >= 1
    ys = np.sort(on_line[:, :, 1].ravel())
    assert ys[0] <= 1e-12 and ys[-1] >= 4 - 1e-12


def _stars(seed, n):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        k = int(rng.integers(5, 40))
        th = np.sort(rng.uniform(0, 2 * np.pi, k))
        rad = 1 + 0.5 * rng.uniform(-1, 1, k)
        S = Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)])).buffer(0)
        if rng.random() < 0.5:
            S = S.difference(Point(0, 0).buffer(0.2, quad_segs=3))
        yield check_shape(S), float(rng.uniform(0.02, 0.3))


@pytest.mark.parametrize("seed", [1, 2])
def test_pieces_lie_on_geos_buffers_and_corners_match_them(seed):
    """Away from GEOS's simplification (random stars with long edges) the two agree to GEOS's chords."""
    for S, r in _stars(seed, 15):
        for side in (1, -1):
            E = exact_offsets(S, r, side)
            G = S.buffer(-side * r, quad_segs=128)
            pts = np.concatenate(E.polylines(math.pi / 200)) if len(E.seg) + len(E.arc_sweep) else np.zeros((0, 2))
            # every kept piece is at clearance exactly r, on its side of S
            if len(pts):
                cl = shapely.distance(shapely.points(pts), S.boundary)
                assert np.abs(cl - r).max() < 1e-9 * r
                assert (shapely.contains_xy(S, pts[:, 0], pts[:, 1]) == (side > 0)).all()
            if G.is_empty:
                continue
            gv = shapely.get_coordinates(G.boundary)
            gv = gv[shapely.distance(shapely.points(gv), S.boundary) > r * (1 - 1e-6)]
            if len(gv):
                lines = shapely.multilinestrings([shapely.linestrings(p) for p in E.polylines(math.pi / 500)])
                assert shapely.distance(shapely.points(gv), lines).max() < 1e-4 * r


def test_many_small_edges_give_the_same_corners_as_the_all_pairs_cut():
    rng = np.random.default_rng(3)
    th = np.linspace(0, 2 * np.pi, 600, endpoint=False)
    rad = 1 + 0.05 * np.sin(7 * th) + 0.01 * rng.standard_normal(len(th))
    S = check_shape(Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)])).buffer(0))
    for r in (0.01, 0.1):
        for side in (1, -1):
            A = exact_offsets(S, r, side)
            B = exact_offsets(S, r, side, _brute=True)
            assert len(A.corners) == len(B.corners)
            if len(A.corners):
                assert cKDTree(B.corners).query(A.corners)[0].max() < 1e-12


def test_corner_at_an_element_end_is_found_on_collinear_pixel_edges():
    # A 60 × 60 square traced as pixel edges (a vertex every unit, collinear): at r = 10 every corner of
    # the shrink falls exactly on an end of a unit edge's offset, where no cut marks it. Regression: the
    # four corners (30, 30) … were lost, and the engine returned two disks.
    t = np.arange(0.0, 60.0)
    ring = np.concatenate([np.column_stack([t, 0 * t]), np.column_stack([60 + 0 * t, t]),
                           np.column_stack([60 - t, 60 + 0 * t]), np.column_stack([0 * t, 60 - t])]) + 20.0
    S = check_shape(Polygon(ring))
    E = exact_offsets(S, 10.0)
    assert sorted(map(tuple, E.corners.round(12).tolist())) == [(30.0, 30.0), (30.0, 70.0), (70.0, 30.0),
                                                                (70.0, 70.0)]
    T = vt.tighten(S, 10.0)
    assert T.converged and T.n_components == 1
    assert T.area == pytest.approx(3600 - (4 - math.pi) * 100, rel=1e-12)


@pytest.mark.parametrize("angle", [0.0, 37.0])
def test_morphology_keeps_parts_and_gaps_exactly_2r_wide(angle):
    # Issue 24: the core of a lone bar exactly 2r wide is the bar with its ends rounded (the union of the
    # r-disks on its centre line); a 2r bar between two squares is core, so every tightening and Mason
    # keep it; a gap exactly 2r wide is anticore, so the fillet and the tightenings leave it open.
    r = 1.0
    rot = lambda g: affinity.rotate(g, angle, origin=(0, 0))   # noqa: E731
    bar = rot(box(0, 0, 10, 2 * r))
    # (sampled within the default tolerance, 1e-5·r: the area is off by at most perimeter × tolerance)
    exact_area, perimeter = 8 * 2 * r + math.pi * r * r, 2 * 8 + 2 * math.pi * r
    assert abs(vt.core(bar, r).area - exact_area) <= perimeter * 1e-5 * r
    joined = rot(shapely.union_all([box(0, 0, 4, 4), box(4, 2 - r, 10, 2 + r), box(10, 0, 14, 4)]))
    middle = rot(shapely.LineString([(4.5, 2), (9.5, 2)]))
    assert vt.core(joined, r).covers(middle)
    for init in ("core", "input", "mason"):
        T = vt.tighten(joined, r, init=init)
        assert T.converged and T.n_components == 1 and T.geometry.covers(middle), init
    assert vt.mason(joined, r).covers(middle)
    gap = rot(shapely.union_all([box(0, 0, 6, 4), box(6 + 2 * r, 0, 14, 4)]))
    assert len(shapely.get_parts(vt.fillet(gap, r))) == 2
    for init in ("core", "input"):
        assert vt.tighten(gap, r, init=init).n_components == 2, init


def _fast_two_boxes():
    S = box(0, 0, 10, 6).union(box(20, 0, 28, 6))
    T = vt.tighten(S, 1.0)
    assert T._cache["_path"] == "fast"
    return T


def test_verify_on_the_fast_path_decides_a_on_the_exact_offsets():
    # verify()'s (a) on a fast-path result: every piece of S↓r inside T, every piece of the anticore's
    # centres outside, and T the loops' own region. A clean result passes; dropping a part of T (a core
    # component missing), adding a box of anticore, or moving a sampled vertex are each reported.
    T = _fast_two_boxes()
    assert T.verify() == []
    good = T.geometry
    T.geometry = max(good.geoms, key=lambda g: g.area)
    assert any(p.startswith("(a) the tightening misses") for p in T.verify())
    T.geometry = good.union(box(12, 2, 16, 4))
    assert any(p.startswith("(a) the geometry differs") for p in T.verify())
    T.geometry = good.union(box(10.5, 2, 19.5, 4))     # a bridge over the anticore's centres x = 11, 19
    assert any(p.startswith("(a) the tightening covers") for p in T.verify())
    ring = np.asarray(max(good.geoms, key=lambda g: g.area).exterior.coords)
    ring[[0, -1]] += 0.05                          # a corner vertex moved 0.07 into its part
    T.geometry = Polygon(ring).union(min(good.geoms, key=lambda g: g.area))
    assert any(p.startswith("(a) the geometry differs") for p in T.verify())


def _pieces(E):
    return E.seg, E.arc_center, E.arc_start, E.arc_sweep, E.corners


@pytest.mark.parametrize("make, r", [
    (lambda: pixel_outline(3000, 7), 0.6),
    (lambda: Polygon([(math.cos(t) * (3 + 0.4 * math.sin(7 * t) + 0.05 * ((k * 7919) % 13 - 6)),
                       math.sin(t) * (3 + 0.4 * math.sin(7 * t) + 0.05 * ((k * 7919) % 13 - 6)))
                      for k, t in enumerate(np.linspace(0, 2 * math.pi, 400, endpoint=False))]), 0.3),
])
def test_pruning_drops_covered_elements_and_keeps_the_same_pieces(make, r, monkeypatch):
    """`offsets._dominated` only takes away what the rounds would cut away whole: the pieces and corners
    come out the same with and without it (to rounding: an arc it trims is cut from a shorter start), and
    on a pixel staircase many times finer than r it settles most elements before the rounds."""
    from vectortighten import offsets

    S = check_shape(make())
    for side in (1, -1):
        X = offsets._Elements(S, r, side)
        covered, lo, hi = offsets._dominated(X)
        E = exact_offsets(S, r, side)
        monkeypatch.setattr(offsets, "_PRUNE", False)
        F = exact_offsets(S, r, side)
        monkeypatch.setattr(offsets, "_PRUNE", True)
        for a, b in zip(_pieces(E), _pieces(F)):
            assert a.shape == b.shape
            assert np.allclose(a, b, rtol=0, atol=1e-12)
        # No kept arc lies in a part the pruning took away.
        ka = np.flatnonzero((X.arc_v[:, None, :] == E.arc_center[None, :, :]).all(axis=2).any(axis=1))
        assert not covered[X.n_seg + ka].any()
        if len(E.arc_center):
            k = np.array([np.flatnonzero((X.arc_v == c).all(axis=1))[0] for c in E.arc_center])
            t0 = (E.arc_start - X.arc_a0[k]) / X.arc_sw[k]
            t0 = np.where(t0 < -1e-9, t0 + 2 * math.pi / np.abs(X.arc_sw[k]), t0)
            assert np.all(t0 >= lo[X.n_seg + k] - 1e-12)
            assert np.all(t0 + E.arc_sweep / X.arc_sw[k] <= hi[X.n_seg + k] + 1e-12)
        if r == 0.6:
            assert covered.mean() > 0.7          # 79 % at this size (r = 45 pixels)


@pytest.mark.parametrize("seed", [4, 5])
def test_small_shapes_give_the_same_pieces_by_trees_boxes_or_every_pair(seed, monkeypatch):
    """The proximity queries' three ways of finding candidates (`_proximity`: trees, one broadcast box
    comparison, every pair measured) give bit-identical pieces and corners on small polygons."""
    from vectortighten import _proximity

    shapes = list(_stars(seed, 6))
    results = []
    for every, boxes in [(0, 0), (0, 1 << 30), (1 << 30, 1 << 30)]:
        monkeypatch.setattr(_proximity, "_ALL_PAIRS", every)
        monkeypatch.setattr(_proximity, "_EDGE_ALL_PAIRS", every)
        monkeypatch.setattr(_proximity, "_BOX_PAIRS", boxes)
        results.append([_pieces(exact_offsets(S, r, side)) for S, r in shapes for side in (1, -1)])
    assert sum(len(p[0]) + len(p[3]) for p in results[0]) > 20
    for other in results[1:]:
        for want, got in zip(results[0], other, strict=True):
            for a, b in zip(want, got, strict=True):
                np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("few", [0, 8])
def test_edges_of_many_rings_drop_repeats_closing_points_and_degenerate_rings(few, monkeypatch):
    """`offsets._edges`, all rings at once or one at a time: repeated points and closing points go, rings
    of fewer than three distinct points go, and each edge's successor starts where it ends, within its
    own ring."""
    from vectortighten import offsets
    from vectortighten.offsets import _edges

    monkeypatch.setattr(offsets, "_FEW_RINGS", few)
    outer = [(0, 0), (4, 0), (4, 0), (4, 4), (0, 4), (0, 0)]
    holes = [[(1, 1), (1, 1), (2, 1), (1, 1)],                 # two distinct points: dropped
             [(1, 2), (1, 3), (2, 3), (2, 2), (1, 2)]]
    S = shapely.MultiPolygon([Polygon(outer, holes), box(10, 0, 11, 1)])
    a, b, prv, nxt = _edges(S)
    assert len(a) == 4 + 4 + 4
    np.testing.assert_array_equal(a[:4], [(0, 0), (4, 0), (4, 4), (0, 4)])
    np.testing.assert_array_equal(b, a[nxt])
    np.testing.assert_array_equal(prv[nxt], np.arange(len(a)))
    ring = np.repeat([0, 1, 2], 4)
    np.testing.assert_array_equal(ring[nxt], ring)
    assert not np.any(np.all(a == b, axis=1))
    assert [len(x) for x in _edges(Polygon())] == [0, 0, 0, 0]


def test_edges_all_rings_at_once_equal_one_at_a_time(monkeypatch):
    from vectortighten import offsets

    rng = np.random.default_rng(2)
    parts = [Point(rng.uniform(0, 50, 2)).buffer(rng.uniform(0.5, 2), quad_segs=int(rng.integers(1, 5)))
             for _ in range(40)]
    S = check_shape(shapely.union_all(parts))
    assert len(shapely.get_rings(shapely.get_parts(S))) > 8
    want = offsets._ring_edges(shapely.get_rings(shapely.get_parts(S)))
    for x, y in zip(want, offsets._edges(S), strict=True):
        assert x.dtype == y.dtype
        np.testing.assert_array_equal(x, y)
