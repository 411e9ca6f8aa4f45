"""The fast path's certificates (offset curves that do not touch themselves) never accept a shape that the
exact distance tests reject, and the fast path's answers are the same either way."""

import math
import warnings

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

import vectortighten as vt
from vectortighten import _fast, _pieces
from vectortighten.engine import _Frame

from .strategies import box_unions, disk_unions, holed, stars


def wavy(n, waves=12, amp=0.04, rad=10.0, center=(0.0, 0.0), hole=False):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rr = rad * (1 + amp * np.sin(waves * t))
    ring = np.column_stack([center[0] + rr * np.cos(t), center[1] + rr * np.sin(t)])
    return ring[::-1] if hole else ring


def _rings(S, r):
    S = vt._validation.check_shape(S)
    frame = _Frame.of(S)
    S = frame.to_local(S)
    D = _fast._Rings(S, r / frame.scale)
    shapely.prepare(S)
    return S, D


def _exact(D, S, side):
    """The exact distance tests of one side: disk centres, arcs, straight pieces moved by r."""
    mine = D.side == side
    limit = D.r * (1 - _fast._EXACT)
    centres = not (mine.any() and _fast._closer_than(D, D.c[mine], D.c[mine], limit))
    return centres, _fast._arcs_clear(D, side), _fast._reaches_edges(D, S, side)


def check_certificates_sound(S, r):
    """A certified side passes every exact test of that side; returns which sides were certified."""
    S, D = _rings(S, r)
    if not D.ok or (np.abs(D.theta) > math.pi - 1e-6).any():
        return []
    if (D.length < -1e-12 * np.maximum(D.ell, D.r)).any():
        return []
    inside = shapely.contains_xy(S, D.c[:, 0], D.c[:, 1])
    certified = []
    for side in (1, -1):
        if not _fast._offset_certified(D, S, side):
            continue
        mine = D.side == side
        assert (inside[mine] == (side > 0)).all(), "certified, yet a disk centre is on the wrong side of S"
        centres, arcs, edges = _exact(D, S, side)
        assert centres, "certified, yet a disk centre is nearer than r to an edge"
        assert edges, "certified, yet a straight piece moved by r leaves S or comes nearer than r to it"
        if _fast._rounded_certified(D):
            assert arcs, "certified, yet an arc enters the core or anticore"
        certified.append(side)
    return certified


SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def blobs(draw):
    """Densely sampled smooth blobs (random low harmonics of the radius), some with a blob-shaped hole:
    the shapes the fast path takes, with necks and gaps of any width."""
    def ring(n, rad, cx, cy, hole):
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        amps = draw(st.lists(st.floats(0.0, 0.08), min_size=4, max_size=4))
        phases = draw(st.lists(st.floats(0.0, 2 * np.pi), min_size=4, max_size=4))
        waves = enumerate(zip(amps, phases, strict=True))
        rr = rad * (1 + sum(a * np.sin((k + 2) * t + p) for k, (a, p) in waves))
        pts = np.column_stack([cx + rr * np.cos(t), cy + rr * np.sin(t)])
        return pts[::-1] if hole else pts
    outer = ring(draw(st.integers(200, 3000)), 10.0, 0.0, 0.0, False)
    holes = []
    if draw(st.booleans()):
        rad = draw(st.floats(1.0, 4.0))
        holes.append(ring(draw(st.integers(100, 1000)), rad, draw(st.floats(-5.0, 5.0)), 0.0, True))
    return Polygon(outer, holes)


@SETTINGS
@given(st.one_of(stars(), box_unions(max_n=4), disk_unions(max_n=4), holed(), blobs(), blobs()),
       st.floats(0.05, 2.0))
def test_certificates_never_accept_what_the_exact_tests_reject(S, r):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", vt.RepairWarning)
        check_certificates_sound(S, r)


@pytest.mark.parametrize("gap", [0.5, 1e-3, 1e-7, 1e-10, 0.0, -1e-10, -1e-7, -1e-3])
def test_necks_near_2r(gap):
    # A disk with an off-centre hole, 2r + gap from its edge (a neck inside S), and two disks 2r + gap
    # apart (outside S): below 2r the disks on one side of the neck come nearer than r to the other side,
    # which no certificate may accept; near 2r the certificates give way to the exact tests.
    r = 1.0
    w = 2 * r + gap
    hole = wavy(3000, amp=0.0, rad=4.0, center=(6 - w, 0), hole=True)
    holed = Polygon(wavy(6000, amp=0.0, rad=10.0), [hole])
    sides = check_certificates_sound(holed, r)
    if gap < 0:
        assert 1 not in sides
    if gap == 0.5:
        assert 1 in sides
    apart = shapely.union_all([Polygon(wavy(4000, amp=0.0, rad=3.0, center=(-3 - w / 2, 0))),
                               Polygon(wavy(4000, amp=0.0, rad=3.0, center=(3 + w / 2, 0)))])
    sides = check_certificates_sound(apart, r)
    if gap < 0:
        assert -1 not in sides
    if gap == 0.5:
        assert sides == [1, -1]


@pytest.mark.parametrize("width", [1.9, 1.999999, 2.0 - 1e-9, 2.0 + 1e-9, 2.1])
def test_annulus_narrower_than_2r_is_never_certified(width):
    # A ring of width < 2r: the inward offset of each circle lies wholly in the other's r-neighbourhood
    # without crossing it, so only the exact test of one point per ring can reject it.
    r = 1.0
    outer, inner = wavy(3000, amp=0.0, rad=10.0), wavy(3000, amp=0.0, rad=10.0 - width, hole=True)
    S = Polygon(outer, [inner])
    _, D = _rings(S, r)
    S_local, _ = _rings(S, r)
    certified = _fast._offset_certified(D, S_local, 1)
    if width < 2.0 - 1e-8:
        assert not certified
        assert vt.tighten(S, r)._cache["_path"] == "general" or vt.tighten(S, r).area == 0
    check_certificates_sound(S, r)


def test_hole_near_the_boundary_and_dense_rings():
    r = 0.3
    S = Polygon(wavy(20000), [wavy(5000, amp=0.02, rad=1.5, center=(7.5, 0), hole=True)])
    assert check_certificates_sound(S, r) == [1, -1]
    assert vt.tighten(S, r)._cache["_path"] == "fast"
    # Moved to within 2r of the outer boundary: the core's offset curves cross, nothing is certified on
    # that side, and the exact tests decide as before.
    S2 = Polygon(wavy(20000), [wavy(5000, amp=0.0, rad=1.5, center=(8.0, 0), hole=True)])
    assert 1 not in check_certificates_sound(S2, r)


def test_fast_path_results_unchanged_by_the_certificates(monkeypatch):
    S = Polygon(wavy(5000), [wavy(2000, amp=0.02, rad=2.0, center=(3.0, 1.0), hole=True)])
    for r in (0.1, 0.4):
        for init in ("core", "input", "mason"):
            A = vt.tighten(S, r, init=init)
            with monkeypatch.context() as m:
                m.setattr(_fast, "_offset_certified", lambda D, S, side: False)
                B = vt.tighten(S, r, init=init)
            assert A._cache["_path"] == B._cache["_path"] == "fast"
            assert len(A.loops) == len(B.loops)
            for a, b in zip(A.loops, B.loops, strict=True):
                assert np.array_equal(a._data, b._data) and np.array_equal(a._arc, b._arc)


def _separated_brute(A, B, fat, nxt, eps):
    m = len(A)
    i, j = np.triu_indices(m, 1)
    across = np.where(fat[nxt] > 0, nxt[nxt], nxt)
    keep = (nxt[i] != j) & (nxt[j] != i) & (across[i] != j) & (across[j] != i)
    i, j = i[keep], j[keep]
    gap = _fast._segment_distances(A[i], B[i], A[j], B[j]) - fat[i] - fat[j]
    return bool((gap >= eps).all())


def _random_chains(sizes, seed, long_share):
    """Closed chains: star-shaped rings (simple, a few pieces much longer than the rest) and random walks
    closed on themselves (often crossing or nearly touching), some pieces marked as arcs."""
    rng = np.random.default_rng(seed)
    A, B, fat, nxt, first = [], [], [], [], []
    start = 0
    for n in sizes:
        if rng.random() < 0.6:
            th = np.sort(rng.uniform(0, 2 * np.pi, n))
            rad = rng.uniform(3.0, 3.3, n) * (1 + 2 * (rng.random(n) < long_share))
            pts = np.column_stack([rad * np.cos(th), rad * np.sin(th)]) + rng.normal(size=2) * 12
        else:
            steps = rng.normal(size=(n, 2)) * np.where(rng.random(n) < long_share, 8.0, 1.0)[:, None]
            steps -= steps.mean(axis=0)
            pts = np.cumsum(steps, axis=0) + rng.normal(size=2) * 5
        A.append(pts)
        B.append(np.roll(pts, -1, axis=0))
        is_arc = rng.random(n) < 0.3
        is_arc &= ~np.roll(is_arc, 1)             # arcs never follow arcs
        fat.append(np.where(is_arc, rng.uniform(1e-6, 0.2, n), 0.0))
        nxt.append(start + (np.arange(n) + 1) % n)
        first.append(np.full(n, start))
        start += n
    return map(np.concatenate, (A, B, fat, nxt, first))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(3, 60), min_size=1, max_size=4), st.integers(0, 2**32 - 1), st.floats(0.0, 0.3))
def test_separated_agrees_with_all_pairs(sizes, seed, long_share):
    # The candidate search may not miss a pair that the test of all pairs finds; chains of up to
    # `_ALL_PIECES` pieces take every pair directly, so the search is made to run on them too.
    A, B, fat, nxt, first = _random_chains(sizes, seed, long_share)
    for eps in (1e-9, 0.05, 0.5):
        want = _separated_brute(A, B, fat, nxt, eps)
        for few in (_fast._ALL_PIECES, 0):
            with pytest.MonkeyPatch.context() as m:
                m.setattr(_fast, "_ALL_PIECES", few)
                assert _fast._separated(A, B, fat, nxt, first, eps) == want


def _arc_distances(x, c, start, sweep, r):
    i, k = (a.ravel() for a in np.meshgrid(np.arange(len(x)), np.arange(len(c)), indexing="ij"))
    d = [_pieces.piece_distance(("seg", (x[a], x[a])), ("arc", (c[b], r, start[b], sweep[b])))[0]
         for a, b in zip(i.tolist(), k.tolist(), strict=True)]
    return np.array(d).reshape(len(x), len(c))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(3, 40), st.integers(1, 60), st.floats(0.05, 3.0))
def test_exact_distance_tests_of_few_pieces_agree_with_their_searches(seed, n_edges, n_points, limit):
    # Below `_ALL_PAIRS` pairs the exact distance tests compare every pair whose boxes (or, for arcs,
    # midpoint balls) come near, without trees: the same answer as with the trees, and as the distance of
    # every pair by the closed forms (shapes drawn so that no distance ties with the limit).
    rng = np.random.default_rng(seed)
    th = np.sort(rng.uniform(0, 2 * np.pi, n_edges))
    rad = rng.uniform(2.0, 6.0, n_edges)
    S = Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))
    if not S.is_valid or S.area < 1.0:
        return
    S, D = _rings(S, 1.0)
    if not D.ok:
        return
    p = rng.uniform(-7, 7, (n_points, 2))
    q = np.where(rng.random((n_points, 1)) < 0.4, p, p + rng.normal(scale=2.0, size=(n_points, 2)))
    a, b = rng.uniform(-7, 7, (n_edges, 2)), rng.uniform(-7, 7, (n_edges, 2))
    c = rng.uniform(-5, 5, (n_edges, 2))
    start, sweep = rng.uniform(-np.pi, np.pi, n_edges), rng.uniform(-3.0, 3.0, n_edges)
    r = float(rng.uniform(0.2, 2.0))
    edges_a, edges_b = D.v, D.v[D.next]
    i, e = (g.ravel() for g in np.meshgrid(np.arange(n_points), np.arange(len(edges_a)), indexing="ij"))
    to_edges = _fast._segment_distances(p[i], q[i], edges_a[e], edges_b[e])
    i, k = (g.ravel() for g in np.meshgrid(np.arange(n_points), np.arange(n_edges), indexing="ij"))
    to_segments = _fast._point_segment_distances(p[i], a[k], b[k])
    to_arcs = _arc_distances(p, c, start, sweep, r)
    for d in (to_edges, to_segments, to_arcs):
        if (np.abs(d - limit) < 1e-9).any():
            return
    got = []
    for few in (_fast._ALL_PAIRS, 0):
        with pytest.MonkeyPatch.context() as m:
            m.setattr(_fast, "_ALL_PAIRS", few)
            got.append((_fast._closer_than(D, p, q, limit), _fast._points_near_segments(p, a, b, limit),
                        _fast._points_near_arcs(p, c, start, sweep, r, limit)))
    assert got[0] == got[1] == (bool((to_edges < limit).any()), bool((to_segments < limit).any()),
                                bool((to_arcs < limit).any()))


@pytest.mark.parametrize("seed", range(4))
def test_closer_than_finds_long_edges_near_a_point(seed):
    # Points alone (p = q, as the disk centres are tested), each on its own, against the long edges of a
    # 24-gon (every edge longer than r/8, so the large-shape path sends them all to its STRtree): the
    # answer of the all-pairs path and of the distances themselves. A point was once probed as a segment
    # of length 0, which the tree matches to nothing.
    rng = np.random.default_rng(seed)
    th = np.sort(rng.uniform(0, 2 * np.pi, 24))
    S = Polygon(np.column_stack([4 * np.cos(th), 4 * np.sin(th)]) * rng.uniform(0.8, 1.2, (24, 1)))
    D = _fast._Rings(S, 1.0)                         # in S's own frame: r = 1
    p = rng.uniform(-5, 5, (60, 2))
    d = np.array([_fast._segment_distances(np.repeat(x[None], len(D.v), 0), np.repeat(x[None], len(D.v), 0),
                                           D.v, D.v[D.next]).min() for x in p])
    p, d = p[np.abs(d - 1.0) > 1e-6], d[np.abs(d - 1.0) > 1e-6]
    assert (d < 1.0).sum() > 5 and (d > 1.0).sum() > 5
    for few in (_fast._ALL_PAIRS, 0):
        with pytest.MonkeyPatch.context() as m:
            m.setattr(_fast, "_ALL_PAIRS", few)
            got = [_fast._closer_than(D, x[None], x[None], 1.0) for x in p]
        assert got == (d < 1.0).tolist()


@pytest.mark.parametrize("pieces_per_side", [5, 50, 500])
def test_separated_finds_a_far_side_of_a_thin_ring(pieces_per_side):
    # A 100 × 0.01 rectangle cut into many pieces: the two long sides are 0.01 apart and far apart along
    # the ring.
    x = np.linspace(0, 100, pieces_per_side + 1)
    pts = np.concatenate([np.column_stack([x, np.zeros_like(x)]),
                          np.column_stack([x[::-1], np.full_like(x, 0.01)])])
    m = len(pts)
    A, B = pts, np.roll(pts, -1, axis=0)
    fat, nxt, first = np.zeros(m), (np.arange(m) + 1) % m, np.zeros(m, int)
    assert _fast._separated(A, B, fat, nxt, first, 0.0099)
    assert not _fast._separated(A, B, fat, nxt, first, 0.0101)
    assert _separated_brute(A, B, fat, nxt, 0.0101) is False


def test_verify_judges_dense_fast_path_results_by_their_own_exact_tests():
    # 10k vertices, every corner isolated: GEOS's buffers simplify this ring by up to r/100 and miss
    # vertices the arcs are centred on; verify() once reported such arcs as "not centred on an arc centre".
    T = vt.tighten(Polygon(wavy(10_000)), 0.5)
    assert T._cache["_path"] == "fast"
    assert T.verify() == []


def test_verify_flags_a_fast_path_loop_that_is_not_the_certified_one():
    from vectortighten.engine import _DiskLoop

    T = vt.tighten(Polygon(wavy(400)), 0.5)
    assert T._cache["_path"] == "fast" and T.verify() == []
    ctx, loops, args = T._cache["_exact"]
    L = loops[0]
    c = L.c.copy()
    c[7] += 1e-6                                    # one disk moved by a millionth of the shape's size
    T._cache["_exact"] = (ctx, [_DiskLoop(L.cid, L.side, c, L.phi, L.length, L.sweep, L.r, L.converged)], args)
    assert any("not the one the fast path's exact tests certify" in p for p in T.verify())


def _near_pairs_all(A, B, fat, nxt, first, eps):
    mx, my = 0.5 * (A[:, 0] + B[:, 0]), 0.5 * (A[:, 1] + B[:, 1])
    found = list(_fast._near_pairs(A, B, fat, nxt, first, mx, my, eps))
    if not found:
        return set()
    i, j = (np.concatenate(x).tolist() for x in zip(*found, strict=True))
    return set(zip(i, j, strict=True))


def _meeting_pairs(A, B, fat, nxt, eps):
    """Pairs i < j, other than neighbours and pieces with an arc between them, whose disks come within eps."""
    mid = 0.5 * (A + B)
    rho = 0.5 * np.hypot(*(B - A).T) + fat
    i, j = np.triu_indices(len(A), 1)
    reach = rho[i] + rho[j] + eps
    meet = ((mid[i] - mid[j]) ** 2).sum(axis=1) <= reach * reach
    across = np.where(fat[nxt] > 0, nxt[nxt], nxt)
    meet &= (nxt[i] != j) & (nxt[j] != i) & (across[i] != j) & (across[j] != i)
    return set(zip(i[meet].tolist(), j[meet].tolist(), strict=True))


def _smooth_chains(sizes, seed):
    """Dense rings close to circles, pieces of uneven length, every other piece at random a short arc:
    most windows of blocks are straight, the search ends at the top level but for the rings' seams."""
    rng = np.random.default_rng(seed)
    A, B, fat, nxt, first = [], [], [], [], []
    start = 0
    for n in sizes:
        t = np.sort(rng.uniform(0, 2 * np.pi, n))
        rad = 5 * (1 + 0.02 * np.sin(3 * t))
        pts = np.column_stack([rad * np.cos(t), rad * np.sin(t)]) + rng.normal(size=2) * 8
        A.append(pts)
        B.append(np.roll(pts, -1, axis=0))
        is_arc = (np.arange(n) % 2 == 1) & (rng.random(n) < 0.5)
        fat.append(np.where(is_arc, rng.uniform(1e-9, 1e-4, n), 0.0))
        nxt.append(start + (np.arange(n) + 1) % n)
        first.append(np.full(n, start))
        start += n
    return map(np.concatenate, (A, B, fat, nxt, first))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(3, 400), min_size=1, max_size=3), st.integers(0, 2**32 - 1), st.floats(0.0, 0.3),
       st.booleans())
def test_near_pairs_misses_no_pair_whose_disks_meet(sizes, seed, long_share, smooth):
    # The search may prune only pairs whose disks stay apart: compared with all pairs.
    chains = _smooth_chains(sizes, seed) if smooth else _random_chains(sizes, seed, long_share)
    A, B, fat, nxt, first = chains
    for eps in (1e-9, 1e-3, 0.05):
        assert _meeting_pairs(A, B, fat, nxt, eps) <= _near_pairs_all(A, B, fat, nxt, first, eps)
        assert _fast._separated(A, B, fat, nxt, first, eps) == _separated_brute(A, B, fat, nxt, eps)


def test_window_terms_of_a_few_pieces_are_those_of_all():
    A, B, fat, nxt, first = _random_chains([5, 40, 3, 17], 11, 0.1)
    mx, my = 0.5 * (A[:, 0] + B[:, 0]), 0.5 * (A[:, 1] + B[:, 1])
    pieces = _fast._Pieces(A, B, fat, nxt, first, mx, my)
    every = {name: x.copy() for name, x in pieces.each_term()}
    idx = np.array([0, 4, 5, 6, 44, 45, 47, 64])
    some = pieces.terms_at(idx)
    for name, x in every.items():
        assert np.array_equal(x[idx], some[name]), name


def test_dense_ring_settled_at_the_top_level():
    # A 200k-piece smooth ring: the straight windows settle nearly every pair of blocks at once.
    S = Polygon(wavy(100_000))
    S_local, D = _rings(S, 0.5)
    chain = _fast._rounded_chain(D)
    A, B, fat, nxt, first = chain
    assert len(A) == 200_000
    across = np.where(fat[nxt] > 0, nxt[nxt], nxt)
    found = [(i, j) for i, j in _near_pairs_all(A, B, fat, nxt, first, _fast._CONTACT * D.r)
             if j not in (nxt[i], across[i]) and i not in (nxt[j], across[j])]
    assert len(found) < 100
    assert _fast._separated(*chain, _fast._CONTACT * D.r)


@pytest.mark.parametrize("side", [1, -1])
def test_offset_chain_is_the_offsets_and_arcs_of_its_side(side):
    # The chain is built from the points where its pieces meet: its segments must be `_Rings.offsets`
    # exactly and its arcs run between the ends of the arcs of `_Rings.arcs` (up to rounding), in ring order.
    S = Polygon(wavy(2000, amp=0.1), [wavy(500, amp=0.05, rad=3.0, center=(2.0, 1.0), hole=True)])
    _, D = _rings(S, 0.3)
    A, B, fat, nxt, first = _fast._offset_chain(D, side)
    seg, arc = fat == 0, fat > 0
    pieces = D.offsets(side)
    assert np.array_equal(A[seg], pieces[:, 0]) and np.array_equal(B[seg], pieces[:, 1])
    centres, start, sweep = D.arcs(side)
    r = D.r
    a = centres + r * np.column_stack([np.cos(start), np.sin(start)])
    b = centres + r * np.column_stack([np.cos(start + sweep), np.sin(start + sweep)])
    assert np.allclose(A[arc], a, rtol=0, atol=1e-14) and np.allclose(B[arc], b, rtol=0, atol=1e-14)
    assert np.array_equal(fat[arc], r * (1 - np.cos(0.5 * sweep)))
    assert np.array_equal(B, A[nxt])                                    # a closed chain per ring
    assert np.array_equal(np.unique(first), [0, np.flatnonzero(first)[0]])
