"""Far-apart parts of a MultiPolygon are tightened alone (`engine._split_fast`): the groups the fast path
takes skip the general engine, and the answer is the one the general engine gives on the whole shape."""

import math
import warnings

import numpy as np
import pytest
import shapely
from shapely import affinity
from shapely.geometry import MultiPolygon, Polygon

import vectortighten as vt

from .engines import assert_same, general

# A building footprint whose ring has steps shorter than 2r (the general engine's) and one the fast path
# takes; the coarse check of a fast result (`_guard.containment_problems`) flags the first's correct
# tightening, so each group must be checked as its own path's result.
STEPPED = Polygon([(48.80, 239.73), (46.47, 238.20), (44.22, 236.45), (42.60, 238.73), (41.06, 240.94),
                   (43.31, 242.45), (41.99, 244.35), (40.57, 246.19), (39.37, 247.93), (40.82, 249.00),
                   (42.32, 250.08), (42.88, 249.24), (44.46, 250.32), (43.89, 251.25), (44.37, 251.51),
                   (42.71, 254.02), (41.08, 256.22), (39.42, 258.66), (42.00, 260.48), (43.83, 257.81),
                   (45.85, 255.09), (47.92, 252.45), (47.43, 252.07), (48.73, 250.49), (49.83, 248.73),
                   (51.27, 249.81), (52.75, 250.83), (54.45, 248.42), (56.03, 246.06), (57.78, 243.75),
                   (55.33, 242.03), (52.88, 240.22), (51.30, 242.45), (49.81, 241.49), (48.29, 240.45)])


def star(n, rad=30.0, center=(0.0, 0.0)):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rr = rad + 3 * np.sin(5 * t) + 0.05 * np.sin(40 * t)
    return Polygon(np.column_stack([center[0] + rr * np.cos(t), center[1] + rr * np.sin(t)]))


def comb(teeth, x0=0.0, r=1.0):
    """Teeth 1.5r wide and 1.5r apart (they vanish) on a back 3.5r wide: the general engine's."""
    w, pts = 1.5 * r, []
    for i in range(teeth):
        x = x0 + 2 * i * w
        pts += [(x, 0.0), (x, 10 * r), (x + w, 10 * r), (x + w, 0.5 * r)]
    end = x0 + 2 * teeth * w
    return Polygon(pts + [(end, 0.5 * r), (end, -3 * r), (x0, -3 * r)])


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_fast_part_far_from_a_general_one_skips_the_general_engine(init):
    S = MultiPolygon([star(800), comb(6, x0=40.0)])
    assert vt.tighten(S.geoms[0], 1.0)._cache["_path"] == "fast"
    assert vt.tighten(S.geoms[1], 1.0)._cache["_path"] == "general"
    T = vt.tighten(S, 1.0, init=init)
    assert T._cache["_path"] == "split"
    assert [m._cache["_path"] for m in T._cache["_members"]] == ["fast", "general"]
    assert T.converged and T.verify() == []
    assert_same(T, general(S, 1.0, init))


def test_parts_nearer_than_3r_stay_together():
    # The comb 2.5r from the star: the fillet of the two may differ from theirs apart; 3.5r: it cannot.
    A = star(800)
    near = MultiPolygon([A, comb(3, x0=A.bounds[2] + 2.5)])
    far = MultiPolygon([A, comb(3, x0=A.bounds[2] + 3.5)])
    assert near.geoms[0].distance(near.geoms[1]) < 3.0 < far.geoms[0].distance(far.geoms[1])
    assert vt.tighten(near, 1.0)._cache["_path"] == "general"
    T = vt.tighten(far, 1.0)
    assert T._cache["_path"] == "split" and T.verify() == []
    assert_same(T, general(far, 1.0))


def test_each_group_is_checked_as_its_own_path_result():
    square = affinity.translate(shapely.box(0, 0, 10, 10), 70, 240)   # the fast path's
    S = MultiPolygon([STEPPED, square])
    with warnings.catch_warnings():
        warnings.simplefilter("error")                 # a failed final check would warn
        T = vt.tighten(S, 1.0)
    assert T._cache["_path"] == "split" and T.converged
    assert sorted(m._cache["_path"] for m in T._cache["_members"]) == ["fast", "general"]
    assert T.verify() == []
    assert_same(T, general(S, 1.0))


def test_only_general_groups_take_the_whole_shape_as_before():
    S = MultiPolygon([comb(3), comb(3, x0=30.0)])
    assert vt.tighten(S, 1.0)._cache["_path"] == "general"


def test_a_group_the_convex_path_takes_verifies_as_such():
    # A convex polygon whose short edges the fast path cannot merge (a long wedge's tip cut by a roof of
    # three edges, the two merged corners' tangents overlapping on the middle one): the fast path declines
    # it, the closed form for convex polygons takes it.
    hw, y0 = 2 * math.tan(math.radians(20)), 20 * math.tan(math.radians(20))
    octagon = Polygon([(0, -y0), (18, -hw), (18.15, -hw / 2), (18.15, hw / 2), (18, hw), (0, y0)])
    S = MultiPolygon([affinity.translate(octagon, 70, 240), STEPPED])
    T = vt.tighten(S, 1.0)
    assert sorted(m._cache["_path"] for m in T._cache["_members"]) == ["convex", "general"]
    assert T.converged and T.verify() == []
    assert_same(T, general(S, 1.0))
