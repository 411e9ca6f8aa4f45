"""The minimum-perimeter-polygon finish of the pixel flow (`raster.mpp`)."""

import warnings

import numpy as np

import raster
from raster.mpp import mpp_finish


def _bars():
    core = np.zeros((40, 40), bool)
    core[8:32, 8:12] = True
    core[8:32, 28:32] = True
    fillet = np.zeros((40, 40), bool)
    fillet[4:36, 4:36] = True
    return core, fillet


def test_a_loose_loop_around_two_bars_becomes_their_convex_hull():
    # The taut loop around two parallel bars in an open square is their convex hull: straight across
    # the top and bottom, so every pixel between the bars' ends lies inside and the row above is out.
    core, fillet = _bars()
    out = mpp_finish(fillet, core, fillet)
    assert out[8:32, 8:32].all()
    assert not out[7, 8:32].any() and not out[32, 8:32].any()
    assert (core <= out).all() and (out <= fillet).all()


def test_a_part_around_no_core_vanishes_in_the_finish():
    # A loop around no core is contractible in the mortar: its shortest loop is a point, and the part
    # vanishes, as the level set lets it (the flow's topology rest may stop while such a part is still
    # shrinking). Dually, a hole around no anticore closes.
    core = np.zeros((30, 30), bool)
    fillet = np.zeros((30, 30), bool)
    fillet[5:25, 5:25] = True
    blob = np.zeros((30, 30), bool)
    blob[10:20, 10:20] = True
    assert not mpp_finish(blob, core, fillet).any()
    assert mpp_finish(~blob, ~fillet, ~core).all()


def test_the_finish_does_not_merge_parts_that_vanish_and_touch():
    # A free part next to a core's part: the free one vanishes, the other keeps its own shape.
    core, fillet = _bars()
    flow = np.zeros_like(core)
    flow[6:34, 6:14] = True
    free = np.zeros_like(core)
    free[15:18, 18:21] = True
    out = mpp_finish(flow | free, core, fillet)
    assert not out[free].any()
    assert (core <= out).all() and (out <= fillet).all()


def test_the_finish_keeps_the_flows_topology():
    # Two separate bars, each its own loop: wrapped one by one, they stay two parts.
    core, fillet = _bars()
    flow = np.zeros_like(core)
    flow[6:34, 6:14] = True
    flow[6:34, 26:34] = True
    out = mpp_finish(flow, core, fillet)
    from scipy import ndimage
    assert ndimage.label(out, structure=np.ones((3, 3), bool))[1] == 2
    assert (core <= out).all() and (out <= fillet).all()


def test_defaults_rest_without_a_warning():
    # Two disks joined by a bar wider than 2r: with the defaults every level rests (no warning).
    yy, xx = np.mgrid[:80, :200]
    m = ((xx - 40) ** 2 + (yy - 40) ** 2 < 25 ** 2) | ((xx - 160) ** 2 + (yy - 40) ** 2 < 25 ** 2)
    m[30:50, 40:160] = True
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        T = raster.tighten(m, 8)
    assert T.is_converged and T.finish == "mpp" and T.budget == "until rest"
    assert (T.core <= T.mask).all() and (T.mask <= T.fillet).all()


def test_the_papers_budget_says_so_and_warns_when_it_does_not_rest():
    yy, xx = np.mgrid[:80, :200]
    m = ((xx - 40) ** 2 + (yy - 40) ** 2 < 25 ** 2) | ((xx - 160) ** 2 + (yy - 40) ** 2 < 25 ** 2)
    m[36:44, 40:160] = True
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        T = raster.tighten(m, 8, iterations=100, finish="none")
    assert T.budget == "the paper's 100 steps a level"
    assert len(T.converged) == T.levels
    assert all(T.converged) or any(issubclass(x.category, raster.NotConvergedWarning) for x in w)
