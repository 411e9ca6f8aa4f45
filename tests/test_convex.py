"""The convex closed form (`vectortighten._convex`) against the general engine and hand-derived values."""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

import vectortighten as vt
from vectortighten import _convex
from vectortighten.curves import Arc
from vectortighten.engine import Init, _tighten


def _pieces(T):
    out = []
    for L in T.loops:
        for p in L.pieces:
            if isinstance(p, Arc):
                out.append((1, *p.center, p.radius, p.sweep))
            else:
                out.append((0, *p.start, *p.end))
    return out


def _hull(seed, n):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 2)) * rng.uniform(1, 5, 2)
    return shapely.convex_hull(shapely.multipoints(pts))


def _ellipse(n, a=6.0, b=2.0):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return Polygon(np.column_stack([a * np.cos(t), b * np.sin(t)]))


CASES = [(_hull(s, n), r) for s, n in ((0, 12), (1, 40), (2, 200), (3, 7)) for r in (0.2, 0.6)]
CASES += [(_ellipse(12, 3, 1.6), 1.2), (_ellipse(20, 3, 1.6), 1.0), (_ellipse(20, 3, 1.6), 1.5),
          (_ellipse(50, 3, 3), 0.5)]


@pytest.mark.parametrize(("S", "r"), CASES)
def test_convex_closed_form_is_the_general_engines_answer(S, r):
    T = vt.tighten(S, r)
    G = _tighten(S, r, Init.CORE, 1e-5 * r, allow_fast=False)
    assert T._cache["_path"] in ("fast", "convex")
    assert G._cache["_path"] == "general"
    a, b = _pieces(T), _pieces(G)
    assert len(a) == len(b)
    assert math.isclose(T.area, G.area, rel_tol=1e-9)
    assert math.isclose(T.perimeter, G.perimeter, rel_tol=1e-9)
    # Same disks (centres and sweeps), whatever piece each loop starts at.
    ca = sorted((round(x, 7), round(y, 7), round(sw, 7)) for k, x, y, _, sw in a if k == 1)
    cb = sorted((round(x, 7), round(y, 7), round(sw, 7)) for k, x, y, _, sw in b if k == 1)
    assert ca == cb
    assert T.verify() == []
    # T is the opening: inside S, and every point of S farther than r from its boundary is in T.
    assert T.geometry.difference(S.buffer(1e-9)).area < 1e-9 * S.area
    assert S.buffer(-r * (1 + 1e-6)).difference(T.geometry).area == 0


def test_coarse_polygon_leaves_the_fast_path_for_the_closed_form():
    # A 20-gon inscribed in an ellipse of semi-axes 3 and 1.6 at r = 1.2: near the ends of the long axis
    # the tangent points of neighbouring corners' disks do not fit on the edges between them, so the fast
    # path declines; the closed form answers, for every init.
    S = _ellipse(20, 3.0, 1.6)
    T = vt.tighten(S, 1.2)
    assert T._cache["_path"] == "convex"
    assert T.verify() == []
    for init in ("input", "mason"):
        U = vt.tighten(S, 1.2, init=init)
        assert math.isclose(U.area, T.area, rel_tol=1e-9)


def test_dense_convex_input_is_left_to_the_general_engine():
    assert _convex.convex_disk_loop(_ellipse(3000), 1.5) is None


def test_square_by_the_corner_formula():
    S = box(0, 0, 10, 10)
    r = 2.0
    loop = _convex.convex_disk_loop(S, r)
    c, side, phi, length, sweep = loop
    assert len(c) == 4 and (side == 1).all()
    np.testing.assert_allclose(np.sort(sweep), [math.pi / 2] * 4)
    np.testing.assert_allclose(length, 6.0)
    T = vt.tighten(S, r)
    assert math.isclose(T.area, 100 - 4 * r * r * (1 - math.pi / 4), rel_tol=1e-12)


def test_not_convex_or_vanishing_is_declined():
    r = 1.0
    assert _convex.convex_disk_loop(Polygon([(0, 0), (4, 0), (4, 4), (2, 1), (0, 4)]), r) is None
    assert _convex.convex_disk_loop(box(0, 0, 10, 10).difference(box(4, 4, 6, 6)), r) is None
    assert _convex.convex_disk_loop(box(0, 0, 10, 1.5), r) is None       # S↓r empty
    assert _convex.convex_disk_loop(box(0, 0, 10, 2.0), r) is None       # S↓r a segment
