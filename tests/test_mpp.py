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


def test_loops_that_touch_merge_as_the_level_set_merges_them():
    # An arch (a bar with two legs, concave from below) over a block that reaches up between its legs,
    # the gaps between them all mortar. The flow from the core leaves the two parts apart; the arch's
    # shortest loop straightens its concave side onto the block's top, where the block's own loop runs:
    # the loops touch, and the level set merges the fronts there. The merged part is wrapped again, so
    # the gaps between the arch and the block fill.
    core = np.zeros((60, 60), bool)
    core[10:14, 10:50] = True
    core[10:40, 10:14] = True
    core[10:40, 46:50] = True
    block = np.zeros_like(core)
    block[30:50, 20:40] = True
    core |= block
    fillet = np.zeros_like(core)
    fillet[5:55, 5:55] = True
    out = mpp_finish(core, core, fillet)
    from scipy import ndimage
    assert ndimage.label(out, structure=np.ones((3, 3), bool))[1] == 1
    assert out[20, 30] and out[35, 16] and out[35, 43]          # above the block, beside it
    assert (core <= out).all() and (out <= fillet).all()
    # Self-dual: the complement's finish gives the complement.
    assert (mpp_finish(~core, ~fillet, ~core) == ~out).all()


def test_loops_that_come_within_a_pixel_but_do_not_touch_stay_apart():
    # Two bars whose straight loops run a fraction of a pixel apart (their samples diagonally adjacent,
    # say) do not touch: the parts stay two.
    core = np.zeros((40, 40), bool)
    core[8:32, 8:19] = True
    core[8:32, 21:32] = True
    fillet = np.zeros_like(core)
    fillet[4:36, 4:36] = True
    out = mpp_finish(core, core, fillet)
    from scipy import ndimage
    assert ndimage.label(out, structure=np.ones((3, 3), bool))[1] == 2


def test_squares_is_the_union_of_the_pixel_squares():
    """`_squares` (a coverage union of row boxes) is the union of the True pixels' unit squares: the same
    polygons as a general union, parts that touch at a corner kept apart, holes kept."""
    import shapely

    from raster.mpp import _squares

    rng = np.random.default_rng(7)
    masks = [rng.random(tuple(rng.integers(1, 12, 2))) < rng.random() for _ in range(80)]
    masks.append(np.array([[1, 0, 1], [0, 1, 0], [1, 0, 1]], bool))         # corners only
    ring = np.ones((5, 5), bool)
    ring[2, 2] = False
    masks.append(ring)                                                       # one hole
    for m in masks:
        if not m.any():
            assert _squares(m).is_empty
            continue
        ii, jj = np.nonzero(m)
        want = shapely.union_all(shapely.box(jj, -ii - 1, jj + 1, -ii))
        got = _squares(m)
        assert got.is_valid and got.equals(want)
        assert len(shapely.get_parts(got)) == len(shapely.get_parts(want))
        assert got.area == m.sum()
    assert len(shapely.get_parts(_squares(masks[-2]))) == 5
    assert len(_squares(ring).interiors) == 1
