"""The small-shape queries of `offsets._Elements` (numpy over every pair) against the R-tree's answers."""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from vectortighten import offsets


def _star(seed, k=30):
    rng = np.random.default_rng(seed)
    th = np.sort(rng.uniform(0, 2 * math.pi, k))
    rad = rng.uniform(2.0, 10.0, k)
    P = Polygon(np.column_stack([rad * np.cos(th), rad * np.sin(th)]))
    P = P if P.is_valid else max(shapely.get_parts(shapely.make_valid(P)), key=lambda g: g.area)
    return shapely.orient_polygons(P)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("side", [1, -1])
def test_clearance_and_reach_equal_the_rtree(seed, side, monkeypatch):
    S = _star(seed)
    X = offsets._Elements(S, 1.0, side)
    rng = np.random.default_rng(seed)
    xy = np.concatenate([rng.uniform(-11, 11, (400, 2)),
                         shapely.get_coordinates(S)[:-1] + rng.normal(0, 1e-9, (len(S.exterior.coords) - 1, 2))])
    e = rng.integers(0, X.n_seg + X.n_arc, 200)
    lo = rng.uniform(0, 0.5, 200)
    hi = lo + rng.uniform(1e-3, 0.5, 200)
    got = {}
    for limit in (10**9, 0):                     # every pair by numpy; every query by the R-tree
        monkeypatch.setattr(offsets, "_BRUTE_PAIRS", limit)
        d, near = X.clearance(xy)
        pi, pj = X.reach(e, lo, hi, 1e-9)
        got[limit] = d, near, set(zip(pi.tolist(), pj.tolist()))
    (d0, n0, p0), (d1, n1, p1) = got[10**9], got[0]
    assert np.array_equal(d0, d1)                # GEOS's distances, bit for bit
    # Where the nearest edges differ they are equally near (a shared vertex, or a point of the medial axis).
    a, b = X.a, X.b
    dist = offsets._point_segment_geos(xy[:, 0], xy[:, 1], a[n0, 0], a[n0, 1], b[n0, 0], b[n0, 1])
    assert np.array_equal(dist, offsets._point_segment_geos(xy[:, 0], xy[:, 1], a[n1, 0], a[n1, 1],
                                                            b[n1, 0], b[n1, 1]))
    assert p0 == p1 and len(p0) > 0
