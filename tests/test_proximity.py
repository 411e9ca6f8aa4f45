"""The proximity indexes find exactly the pairs within the distance, by trees or by measuring every pair."""

import numpy as np
import pytest

from vectortighten import _proximity
from vectortighten._proximity import EdgeIndex, PointIndex, point_segment_distance, segment_segment_distance


def _outline(n, rng):
    """A dense wavy ring's edges (grazing queries at distance ~r are the indexes' hard case) and a few
    long edges (the R-tree's share)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 10 + 0.8 * np.sin(7 * t) + 0.05 * rng.normal(size=n)
    xy = np.column_stack([rad * np.cos(t), rad * np.sin(t)])
    a, b = xy, np.roll(xy, -1, axis=0)
    long_a = rng.uniform(-12, 12, (5, 2))
    long_b = long_a + rng.uniform(-8, 8, (5, 2))
    return np.concatenate([a, long_a]), np.concatenate([b, long_b])


#: ``(_EDGE_ALL_PAIRS, _BOX_PAIRS)``: trees, one broadcast box comparison, every pair measured.
_MODES = [(0, 0), (0, 1 << 30), (1 << 30, 1 << 30)]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_near_segments_trees_and_all_pairs_agree(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    a, b = _outline(900, rng)
    r = 1.0
    index = EdgeIndex(a, b, r)
    p = rng.uniform(-11, 11, (120, 2))
    q = p + rng.normal(0, 0.6, (120, 2))
    dist = r * 0.97
    # Every pair measured, the reference: the pairs within dist, sorted by segment then edge.
    d = segment_segment_distance(np.repeat(p, len(a), axis=0), np.repeat(q, len(a), axis=0),
                                 np.tile(a, (len(p), 1)), np.tile(b, (len(p), 1))).reshape(len(p), len(a))
    want = np.argwhere(d <= dist)
    assert len(want) > 100                              # the queries graze the ring
    for every, boxes in _MODES:
        monkeypatch.setattr(_proximity, "_EDGE_ALL_PAIRS", every)
        monkeypatch.setattr(_proximity, "_BOX_PAIRS", boxes)
        si, ei = index.near_segments(p, q, dist)
        np.testing.assert_array_equal(np.column_stack([si, ei]), want)


@pytest.mark.parametrize("seed", [0, 1])
def test_near_points_trees_boxes_and_all_pairs_agree(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    a, b = _outline(700, rng)
    x = rng.uniform(-11, 11, (150, 2))
    dist = 0.9
    d = point_segment_distance(np.repeat(x, len(a), axis=0), np.tile(a, (len(x), 1)),
                               np.tile(b, (len(x), 1))).reshape(len(x), len(a))
    want = np.argwhere(d <= dist)
    assert len(want) > 100
    index = EdgeIndex(a, b, 1.0)
    for every, boxes in _MODES:
        monkeypatch.setattr(_proximity, "_EDGE_ALL_PAIRS", every)
        monkeypatch.setattr(_proximity, "_BOX_PAIRS", boxes)
        pi, ei, di = index.near_points(x, dist)
        # Sorted by point, then by distance; the distances are the exact ones of the pairs.
        assert np.all(np.diff(pi) >= 0) and np.all((np.diff(pi) > 0) | (np.diff(di) >= 0))
        np.testing.assert_array_equal(di, d[pi, ei])
        got = np.column_stack([pi, ei])
        np.testing.assert_array_equal(got[np.lexsort((ei, pi))], want)


@pytest.mark.parametrize("seed", [0, 1])
def test_point_index_near_segments_trees_and_all_pairs_agree(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-5, 5, (700, 2))
    p = rng.uniform(-5, 5, (90, 2))
    q = p + rng.normal(0, 1.0, (90, 2))
    dist = 0.4
    d = point_segment_distance(np.tile(xy, (len(p), 1)), np.repeat(p, len(xy), axis=0),
                               np.repeat(q, len(xy), axis=0)).reshape(len(p), len(xy))
    want = np.argwhere(d <= dist)
    assert len(want) > 50
    index = PointIndex(xy)
    for limit in (0, 1 << 30):
        monkeypatch.setattr(_proximity, "_ALL_PAIRS", limit)
        si, j = index.near_segments(p, q, dist)
        np.testing.assert_array_equal(np.column_stack([si, j]), want)


@pytest.mark.parametrize("seed", [0, 1])
def test_near_segments_distance_per_segment(seed, monkeypatch):
    """A distance for each segment gives, in every mode, the pairs of each segment at its own distance."""
    rng = np.random.default_rng(seed)
    a, b = _outline(600, rng)
    index = EdgeIndex(a, b, 1.0)
    p = rng.uniform(-11, 11, (80, 2))
    q = p + rng.normal(0, 0.3, (80, 2))
    dist = rng.uniform(0.5, 1.2, len(p))
    d = segment_segment_distance(np.repeat(p, len(a), axis=0), np.repeat(q, len(a), axis=0),
                                 np.tile(a, (len(p), 1)), np.tile(b, (len(p), 1))).reshape(len(p), len(a))
    want = np.argwhere(d <= dist[:, None])
    assert len(want) > 50 and len(want) != len(np.argwhere(d <= dist.max()))
    for every, boxes in _MODES:
        monkeypatch.setattr(_proximity, "_EDGE_ALL_PAIRS", every)
        monkeypatch.setattr(_proximity, "_BOX_PAIRS", boxes)
        si, ei = index.near_segments(p, q, dist)
        np.testing.assert_array_equal(np.column_stack([si, ei]), want)
