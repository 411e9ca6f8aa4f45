"""verify()'s depth check (e): exact entries into the open core and anticore, measured once for all loops,
with the straight pieces that lie on an edge of S set aside (they cannot enter either region)."""

import numpy as np
import pytest
import shapely
from shapely.geometry import MultiPolygon

import vectortighten as vt
from vectortighten import engine

from .test_split import comb, star


def _depths(T, skip=True, monkeypatch=None):
    ctx, loops = T._exact_context()
    limit = max(engine.VERIFY_DEPTH_R * ctx.r, 8.0 * ctx.precision)
    if monkeypatch is not None:
        monkeypatch.setattr(engine, "_SKIP_ON_EDGES", skip)
    return engine._exact_depths_many(ctx, loops, limit), limit


@pytest.mark.parametrize("S", [shapely.box(0, 0, 10, 10), star(600), comb(8),
                               MultiPolygon([star(400), comb(4, x0=40.0)])])
def test_setting_aside_pieces_on_edges_changes_no_depth(S, monkeypatch):
    T = vt.tighten(S, 1.0)
    with_skip, _ = _depths(T, True, monkeypatch)
    without, _ = _depths(T, False, monkeypatch)
    assert with_skip == without
    assert T.verify() == []


def test_a_loop_moved_into_the_core_is_found_at_its_depth():
    # The 10 × 10 square at r = 1; its loop shrunk by 0.3 on every side. Each straight piece runs 0.3
    # inside S, 0.7 from the shrink [1, 9]² (0.3 deep in the open core; none lies on an edge of S, so
    # none is set aside), and each corner arc, centred 0.3·√2 from the shrink's corner, passes that much
    # nearer than r to it: the deepest entry, 0.3·√2.
    T = vt.tighten(shapely.box(0, 0, 10, 10), 1.0)
    ctx, loops = T._exact_context()
    (L,) = loops
    frame = T._cache["_frame"]
    middle = (np.array([5.0, 5.0]) - (frame.ox, frame.oy)) / frame.scale
    c = L.c + 0.3 / frame.scale * np.sign(middle - L.c)
    moved = engine._DiskLoop(L.cid, L.side, c, L.phi, L.length - 0.6 / frame.scale, L.sweep, L.r)
    limit = max(engine.VERIFY_DEPTH_R * ctx.r, 8.0 * ctx.precision)
    (core, anti), = engine._exact_depths_many(ctx, [moved], limit)
    assert core * frame.scale == pytest.approx(0.3 * np.sqrt(2), abs=1e-12)
    assert anti == 0.0
