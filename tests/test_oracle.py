"""The exact clearance oracle (tests/oracle.py) checked on hand-derived cases and against brute force.

The oracle must be right before it may judge the engine: its pieces are exactly the points at clearance
r (hand-derived positions on squares, an L, slots, a 2r bar, a ring), and its distances agree with a
dense brute-force sampling on random polygons.
"""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from tests import oracle as o
from tests import shapes_dense as sd
from vectortighten import Arc, Loop, Segment


def _clearance(S, xy):
    return shapely.distance(shapely.points(xy), S.boundary)


def _piece_samples(K, n=9):
    t = np.linspace(0, 1, n)
    out = []
    for is_arc, row in zip(K.kind, K.rows):
        if is_arc:
            th = row[3] + t * row[4]
            out.append(np.column_stack([row[0] + row[2] * np.cos(th), row[1] + row[2] * np.sin(th)]))
        else:
            out.append(row[None, :2] + t[:, None] * (row[None, 2:4] - row[None, :2]))
    return np.concatenate(out) if out else np.zeros((0, 2))


def _sorted_rows(K):
    return sorted(tuple(np.round(r, 12).tolist()) for r in K.rows)


def _pen(piece, K):
    kind, rows = o.loop_arrays([Loop([piece, piece.reversed()])])
    return o.penetration(kind[:1], rows[:1], K)[0]


def test_square_shrink_and_anticore_centres_are_hand_derived():
    K = o.shrink_pieces(box(0, 0, 4, 4), 1.0)
    assert not K.kind.any()
    assert _sorted_rows(K) == sorted([(1.0, 1.0, 3.0, 1.0, 0.0), (3.0, 1.0, 3.0, 3.0, 0.0),
                                      (3.0, 3.0, 1.0, 3.0, 0.0), (1.0, 3.0, 1.0, 1.0, 0.0)])
    A = o.shrink_pieces(box(0, 0, 4, 4), 1.0, complement=True)
    assert A.kind.sum() == 4                              # quarter arcs about the four corners
    arcs = A.rows[A.kind]
    assert sorted(map(tuple, arcs[:, :2].tolist())) == [(0, 0), (0, 4), (4, 0), (4, 4)]
    np.testing.assert_allclose(arcs[:, 2], 1.0)
    np.testing.assert_allclose(np.abs(arcs[:, 4]), math.pi / 2, atol=1e-15)
    segs = A.rows[~A.kind]
    assert sorted(np.round(np.abs(segs[:, 2] - segs[:, 0]) + np.abs(segs[:, 3] - segs[:, 1]), 12)) == [4] * 4


def test_square_penetration_is_exact():
    K = o.shrink_pieces(box(0, 0, 4, 4), 1.0)
    # K's pieces reach ``delta`` (the tie precision, 5e-14 here) into the capsules: depths are to ±delta
    assert K.delta == pytest.approx(5e-14)
    assert _pen(Segment((0, 0), (4, 0)), K) == pytest.approx(0.0, abs=2 * K.delta)   # ∂S: distance r
    assert _pen(Segment((0, 0.5), (4, 0.5)), K) == pytest.approx(0.5, abs=2 * K.delta)
    assert _pen(Segment((-1, 0.25), (0.5, 0.25)), K) == pytest.approx(1 - math.hypot(0.5, 0.75), abs=2 * K.delta)
    assert _pen(Segment((2, 2), (2.5, 2)), K) == 1.0                  # inside the shrink
    # an arc of radius 1 about (0, 0) passes 1 − (√2 − 1)... its nearest point to (1, 1) is at 45°
    assert _pen(Arc((0, 0), 1.0, 0.0, math.pi / 2), K) == pytest.approx(1 - (math.sqrt(2) - 1), abs=2 * K.delta)
    # an arc of radius 1 concentric with the corner of K, outside: distance 1 exactly
    assert _pen(Arc((3, 3), 1.0, 0.0, math.pi / 2), K) == pytest.approx(0.0, abs=2 * K.delta)
    assert _pen(Arc((3, 3), 0.5, 0.0, math.pi / 2), K) == pytest.approx(0.5, abs=2 * K.delta)


def test_l_shape_has_the_reflex_arc():
    L = Polygon([(0, 0), (4, 0), (4, 2), (2, 2), (2, 4), (0, 4)])
    K = o.shrink_pieces(L, 0.5)
    arcs = K.rows[K.kind]
    assert len(arcs) == 1
    np.testing.assert_allclose(arcs[0, :3], [2, 2, 0.5])
    assert arcs[0, 4] == pytest.approx(-math.pi / 2)
    lengths = np.hypot(K.rows[~K.kind, 2] - K.rows[~K.kind, 0], K.rows[~K.kind, 3] - K.rows[~K.kind, 1])
    np.testing.assert_allclose(np.sort(lengths), [1.0, 1.0, 1.5, 1.5, 3.0, 3.0], atol=4 * K.delta)
    np.testing.assert_allclose(_clearance(L, _piece_samples(K)), 0.5, atol=2 * K.delta)


@pytest.mark.parametrize("eps", [1e-9, 1e-3, -1e-9, -1e-3])
@pytest.mark.parametrize("angle", [0.0, 30.0])
def test_slot_anticore_centres_exist_exactly_when_wider_than_2r(eps, angle):
    r = 1.0
    S = sd.slot(r, eps, angle=angle, offset=(123.0, -45.0))
    A = o.shrink_pieces(S, r, complement=True)
    # anticore centres deep in the slot (below the square's top edge by 2r)
    mid = o._midpoints(A.kind, A.rows)
    c, s_ = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    v = mid - np.array([123.0, -45.0])
    x, y = c * v[:, 0] + s_ * v[:, 1], -s_ * v[:, 0] + c * v[:, 1]
    deep = (y < 5.0 - 2 * r) & (y > -5.0) & (np.abs(x) < 5.0)
    assert deep.any() == (eps > 0)
    if eps > 0:
        assert np.abs(x[deep]).max() <= r * eps * (1 + 1e-6) + 2 * A.delta   # the strip |x| ≤ r·eps


@pytest.mark.parametrize("angle", [0.0, 17.0, 45.0])
def test_bar_exactly_2r_wide_has_its_centre_line_as_shrink(angle):
    r = 3.0
    S = sd.bar(r, 0.0, angle=angle, offset=(1e3, 2e3), length=10)
    K = o.shrink_pieces(S, r)
    assert len(K) >= 2
    samples = _piece_samples(K)
    np.testing.assert_allclose(_clearance(S, samples), r, atol=2 * K.delta)   # pieces reach delta in
    total = np.hypot(K.rows[~K.kind, 2] - K.rows[~K.kind, 0], K.rows[~K.kind, 3] - K.rows[~K.kind, 1]).max()
    assert total == pytest.approx(8 * r, rel=1e-9)                   # from r to 10r − r along the bar
    thin = o.shrink_pieces(sd.bar(r, -1e-9, angle=angle, offset=(1e3, 2e3)), r)
    assert len(thin) == 0


def test_ring_shrink_has_arcs_about_the_hole_corners():
    S = box(0, 0, 10, 10).difference(box(4, 4, 6, 6))
    K = o.shrink_pieces(S, 1.0)
    arcs = K.rows[K.kind]
    assert sorted(map(tuple, arcs[:, :2].tolist())) == [(4, 4), (4, 6), (6, 4), (6, 6)]
    np.testing.assert_allclose(np.abs(arcs[:, 4]), math.pi / 2)
    assert (~K.kind).sum() == 8
    np.testing.assert_allclose(_clearance(S, _piece_samples(K)), 1.0, atol=2 * K.delta)
    assert K.contains_xy(np.array([[2.0, 2.0], [5.0, 5.0], [0.5, 5.0], [3.0, 5.0]])).tolist() == \
        [True, False, False, True]


def _random_polygon(rng, k=14):
    th = np.sort(rng.uniform(0, 2 * math.pi, k))
    rad = rng.uniform(2.0, 10.0, k)
    return Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("complement", [False, True])
def test_against_brute_force_sampling(seed, complement):
    """Pieces at clearance exactly r; distances from random probes agree with a dense sampling of K."""
    rng = np.random.default_rng(seed)
    S = _random_polygon(rng)
    if not S.is_valid:
        S = shapely.make_valid(S)
    S = shapely.orient_polygons(S)
    r = float(rng.uniform(0.4, 1.5))
    K = o.shrink_pieces(S, r, complement=complement)
    samples = _piece_samples(K)
    if len(samples):
        np.testing.assert_allclose(_clearance(S, samples), r, atol=2 * K.delta)
        inside = shapely.contains_xy(S, samples[:, 0], samples[:, 1])
        assert (inside != complement).all()
        assert K.contains_xy(samples).all()
    # brute-force K: a fine grid of points with clearance ≥ r on the right side of ∂S
    h = 0.05
    xs = np.arange(-13, 13, h)
    gx, gy = np.meshgrid(xs, xs)
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    clear = _clearance(S, grid)
    inS = shapely.contains_xy(S, grid[:, 0], grid[:, 1])
    member = (clear >= r) & (inS != complement)
    np.testing.assert_array_equal(K.contains_xy(grid[::7]), member[::7])
    # K's parts narrower than the grid are seen through its pieces' own points, each checked above
    dense = _piece_samples(K, n=200)
    brute = np.concatenate([grid[member], dense]) if len(dense) else grid[member]
    tree = shapely.STRtree(shapely.points(brute))
    # random probe segments: exact distance to K (through the penetration) against the sampled one
    for _ in range(40):
        p, q = rng.uniform(-11, 11, 2), rng.uniform(-11, 11, 2)
        q = p + (q - p) * rng.uniform(0.02, 0.3)
        seg = Segment(tuple(p), tuple(q))
        pen = _pen(seg, K)
        line = shapely.linestrings([p, q])
        if len(brute):
            d_brute = shapely.distance(line, shapely.multipoints(brute[tree.query(line, predicate="dwithin",
                                                                                    distance=r)]))
            d_brute = min(d_brute, r) if np.isfinite(d_brute) else r
        else:
            d_brute = r
        assert r - pen <= d_brute + 1e-12                 # the sampled K lies in the exact one
        assert r - pen >= d_brute - 1.5 * h               # and fills it to the grid's spacing
