"""The pixel path: exact-EDT morphology, the constrained curvature flow, rasterising and contours, PNGs."""

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, box

import raster
from scipy import ndimage
import vectortighten as vt

YY, XX = np.mgrid[:160, :160]


def square(half=50, cx=80, cy=80):
    return (abs(XX - cx) < half) & (abs(YY - cy) < half)


def disk(rad, cx=80, cy=80):
    return np.hypot(XX - cx, YY - cy) < rad


@st.composite
def masks(draw):
    """Random unions of boxes and disks on a 64 × 64 image, with a blank border."""
    m = np.zeros((64, 64), bool)
    yy, xx = np.mgrid[:64, :64]
    for _ in range(draw(st.integers(1, 5))):
        x, y = draw(st.integers(6, 58)), draw(st.integers(6, 58))
        a, b = draw(st.integers(1, 16)), draw(st.integers(1, 16))
        if draw(st.booleans()):
            m |= (abs(xx - x) <= a) & (abs(yy - y) <= b)
        else:
            m |= np.hypot(xx - x, yy - y) < a
    m[:2], m[-2:], m[:, :2], m[:, -2:] = False, False, False, False
    return m


# -- morphology --------------------------------------------------------------------------------------------
@settings(max_examples=40, deadline=None)
@given(masks(), st.sampled_from([1.5, 3.0, 4.5, 8.0]))
def test_morphology_relations_exact(m, r):
    R, F = raster.core(m, r), raster.fillet(m, r)
    assert (R <= m).all() and (m <= F).all()
    assert (raster.mortar(m, r) == (F & ~R)).all()
    # Duality under complement, pixel for pixel.
    assert (raster.core(~m, r) == raster.anticore(m, r)).all()
    assert (raster.shrink(~m, r) == ~raster.grow(m, r)).all()
    # Opening the core again, and closing the fillet again, changes nothing or takes away (adds) pixels:
    # never the other way. (It is not idempotent: the core's pixels are those whose centres lie in the
    # core of M's squares, and the squares of those pixels need not hold the same disks; a bar exactly 2r
    # wide, whose disks are centred on pixel corners, loses a pixel at each end.)
    assert (raster.core(R, r) <= R).all() and (F <= raster.fillet(F, r)).all()


def test_grow_shrink_against_brute_force():
    rng = np.random.default_rng(3)
    m = rng.random((20, 24)) < 0.3
    r = 2.5
    ys, xs = np.nonzero(m)
    yy, xx = np.mgrid[:20, :24]
    d_in = np.min(np.hypot(yy[..., None] - ys, xx[..., None] - xs), axis=-1)
    assert (raster.grow(m, r) == (d_in < r + 0.5)).all()
    # Shrink: beyond the image counts as the nearest border pixel (edge replication).
    big = np.pad(m, 5, mode="edge")
    ys, xs = np.nonzero(~big)
    yy, xx = np.mgrid[:30, :34]
    d_out = np.min(np.hypot(yy[..., None] - ys, xx[..., None] - xs), axis=-1)[5:-5, 5:-5]
    assert (raster.shrink(m, r) == (d_out >= r + 0.5)).all()


def test_core_of_square_has_round_corners():
    m = square(50)                       # 99 × 99 pixels, their squares span [30.5, 129.5]²
    r = 20
    R = raster.core(m, r)
    # The continuous core of the pixel squares: its corner disk is centred r in from both sides, on the
    # pixel corner (50.5, 50.5). A pixel is core exactly when its centre lies in that open disk or in the
    # cross of the two strips between the corner disks' centres.
    c = 30.5 + r
    yy, xx = np.mgrid[25:60, 25:60]
    truth = (np.hypot(xx - c, yy - c) < r) | (xx >= c) & (yy > c - r) | (yy >= c) & (xx > c - r)
    assert (R[25:60, 25:60] == (truth & m[25:60, 25:60])).all()


# -- the flow ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_core_and_anticore_never_change(init):
    m = square(50) | (abs(XX - 140) < 15) & (abs(YY - 80) < 3)    # a square with a thin bar
    m &= ~disk(4, 60, 60)                                          # and a small hole
    T = raster.tighten(m, 12, init=init)
    assert (T.core <= T.mask).all() and (T.mask <= T.fillet).all()
    assert (T.phi[T.core] < 0).all() and (T.phi[~T.fillet] > 0).all()


def test_disk_larger_than_r_stays():
    """Within a pixel: only pixels on the disk's edge may change, and the traced circle keeps its radius."""
    m = disk(40)
    T = raster.tighten(m, 15)
    edge = raster.grow(m, 1.5) & ~raster.shrink(m, 1.5)
    assert ((T.mask ^ m) <= edge).all()
    xy = shapely.get_coordinates(raster.contours(T).exterior)
    assert np.abs(np.hypot(xy[:, 0] - 80, xy[:, 1] + 80) - 39.5).max() < 1.0


def test_square_corners_become_arcs_of_radius_r():
    """The square's tightening is its core: its traced corners are arcs of radius r within a pixel."""
    m = square(50)                           # pixels 31..129
    r = 20.0
    T = raster.tighten(m, r)
    # The core is already tight: the flow only smooths its pixel staircase, by one pixel at most.
    edge = raster.grow(T.core, 1.5) & ~raster.shrink(T.core, 1.5)
    assert ((T.mask ^ T.core) <= edge).all()
    poly = raster.contours(T)                # x = column, y = −row
    xy = shapely.get_coordinates(poly.exterior)
    # The pixels sample the square [30.5, 129.5]²: its corner disks are centred 20 in from its sides, at
    # 50.5 and 109.5, and the traced arcs keep their radius within a third of a pixel.
    for cx, cy in [(50.5, 50.5), (109.5, 50.5), (50.5, 109.5), (109.5, 109.5)]:
        sx, sy = np.sign(cx - 80), np.sign(cy - 80)
        sel = (sx * (xy[:, 0] - cx) > 0) & (sy * (-xy[:, 1] - cy) > 0)
        d = np.hypot(xy[sel, 0] - cx, -xy[sel, 1] - cy)
        assert sel.sum() > 20 and np.abs(d - r).max() < 0.35
    # Against the continuous rounded square, the same third of a pixel (measured 0.296).
    exact = vt.core(box(30.5, -129.5, 129.5, -30.5), r)
    assert poly.hausdorff_distance(exact) < 0.35


def test_small_hole_fills_and_thin_bar_follows_the_exact_tightening():
    """The hole narrower than r fills whatever the start. The bar thinner than 2r is not in the core, so
    from the core (and from Mason(M), whose R∘F and F∘R both drop it) it never appears; from the input
    it is held between two parts of the anticore, its straight sides do not move, and it stays, as in
    the exact tightening of the mask's pixel squares (the coarse levels thin it to a wall a pixel thick,
    which the full-resolution flow used to break)."""
    m = np.zeros((100, 200), bool)
    m[20:80, 20:80] = m[20:80, 120:180] = True
    m[47:53, 80:120] = True                  # a bar 6 px thick, r = 10
    m[45:50, 45:50] = False                  # a hole 5 px wide
    grid = raster.Grid(0.0, 100.0, 1.0, m.shape)
    squares = vt.pixel_squares(m, grid)
    for init in ("core", "input", "mason"):
        T = raster.tighten(m, 10, init=init)
        assert T.mask[45:50, 45:50].all(), init
        exact = vt.tighten(squares, 10.0, init=init)
        keeps_bar = init == "input"
        assert exact.n_components == (1 if keeps_bar else 2), init
        assert ndimage.label(T.mask)[1] == exact.n_components, init
        thickness = T.mask[40:60, 90:110].sum(axis=0)           # of the bar's middle, pixels
        assert (thickness >= 5).all() if keeps_bar else not thickness.any(), init
        contour = raster.contours(T, grid)
        assert contour.boundary.hausdorff_distance(exact.geometry.boundary) < 1.0, init   # measured 0.41–0.81


@pytest.mark.parametrize("init", ["input", "mason"])
def test_self_dual_pixel_for_pixel(init):
    m = square(45) | disk(25, 120, 120)
    m &= ~disk(6, 70, 70)
    m[75:85, 20:140] = False                 # a slot
    a = raster.tighten(m, 9, init=init).mask
    b = raster.tighten(~m, 9, init=init).mask
    assert (a == ~b).all()


def test_multiscale_and_single_scale_agree_within_a_pixel():
    m = square(40) | disk(22, 125, 125)
    r = 16
    multi = raster.tighten(m, r)
    single = raster.tighten(m, r, levels=1, iterations=400)
    assert multi.levels > 1 and single.levels == 1
    A, B = raster.contours(multi), raster.contours(single)
    assert A.hausdorff_distance(B) <= 1.0


def test_huge_r_gives_empty_mask():
    T = raster.tighten(disk(10), 50)
    assert not T.mask.any()


def test_timings_and_iterations_reported():
    T = raster.tighten(square(50), 20)
    assert len(T.iterations) == T.levels == raster.default_levels(20)
    assert {"morphology", "init", "total", "flow level 0"} <= set(T.timings)


@pytest.mark.parametrize("bad, message", [
    (np.zeros((3, 3, 3), bool), "2-D"),
    (np.zeros((0, 5), bool), "empty"),
    (np.zeros((5, 5), bool), "no True pixel"),
    (np.ones((5, 5), bool), "True everywhere"),
    (np.full((5, 5), 0.5), "not binary"),
])
def test_bad_masks(bad, message):
    with pytest.raises(ValueError, match=message):
        raster.tighten(bad, 2)


@pytest.mark.parametrize("r", [0, -1, float("nan"), float("inf")])
def test_bad_radius(r):
    with pytest.raises(ValueError, match="r must be"):
        raster.tighten(square(), r)


def test_input_not_modified():
    m = square(40).astype(np.uint8)
    before = m.copy()
    raster.tighten(m, 10, init="input")
    assert (m == before).all()


# -- vectors and files -------------------------------------------------------------------------------------
def test_rasterize_and_contours_round_trip():
    P = Point(0, 0).buffer(10, quad_segs=64).difference(box(-3, -3, 3, 3))
    m, grid = raster.rasterize(P, pixel_size=0.25, margin=1.0)
    ys, xs = np.nonzero(m)
    x, y = grid.to_world(ys, xs)
    assert shapely.contains_xy(P, x, y).all()
    assert m.sum() == pytest.approx(P.area / 0.25 ** 2, rel=0.01)
    back = raster.contours(m, grid)
    assert back.hausdorff_distance(P) < 0.25
    assert back.geom_type == "Polygon" and len(back.interiors) == 1


def test_rasterize_matches_contains_xy():
    P = shapely.Polygon([(0, 0), (7.3, 1.1), (3.2, 6.9), (2.0, 2.5), (-1.7, 4.4)])
    m, grid = raster.rasterize(P, pixel_size=0.1, margin=0.5)
    rows, cols = np.indices(m.shape)
    x, y = grid.to_world(rows, cols)
    ref = shapely.contains_xy(P, x, y)
    # Only centres on an edge (where contains_xy says outside) may differ.
    rows, cols = np.nonzero(m != ref)
    assert shapely.distance(P.exterior, shapely.points(x[rows, cols], y[rows, cols])).max() < 1e-12
    assert (m != ref).sum() < 10


def test_png_round_trip_and_threshold(tmp_path):
    m = square(30)
    path = tmp_path / "m.png"
    raster.save_mask(path, m)
    assert (raster.load_mask(path) == m).all()
    assert (raster.load_mask(path, invert=True) == ~m).all()
    from PIL import Image
    grey = np.full((4, 4), 100, np.uint8)
    grey[0, 0] = 200
    Image.fromarray(grey).save(tmp_path / "g.png")
    assert raster.load_mask(tmp_path / "g.png", threshold=0.5).sum() == 1      # 200/255 ≥ ½, 100/255 < ½
    with pytest.warns(raster.ManyValuesWarning, match="2 distinct values"):
        assert raster.load_mask(tmp_path / "g.png").all()                      # no threshold: non-zero


def test_png_errors(tmp_path):
    (tmp_path / "bad.png").write_bytes(b"not a png")
    with pytest.raises(ValueError, match="not an image"):
        raster.load_mask(tmp_path / "bad.png")
    with pytest.raises(FileNotFoundError):
        raster.save_mask(tmp_path / "no" / "m.png", square())


@pytest.mark.parametrize("gap", [1, 2, 5])
def test_fronts_a_gap_apart_do_not_merge(gap):
    """Two disks larger than r, `gap` pixels apart: the exact tightening is the two disks (their fronts rest
    on the core and are convex). The crease of Φ between them must not draw the fronts together, however
    long the flow runs."""
    yy, xx = np.mgrid[:120, :220]
    m = ((yy - 60) ** 2 + (xx - 60) ** 2 < 40 ** 2) | ((yy - 60) ** 2 + (xx - 140 - gap) ** 2 < 40 ** 2)
    for init in ("core", "input"):
        T = raster.tighten(m, 20, init=init, levels=1, iterations=2000)
        assert ndimage.label(T.mask)[1] == 2, init
        # Nothing of the crease is kept: the result is the two disks, up to the pixels on their rims.
        assert (T.mask ^ m).sum() <= 0.01 * m.sum(), init


def test_coarse_levels_do_not_merge_what_full_resolution_keeps_apart():
    """A 2-pixel gap vanishes on the coarse grids, where the two squares' samples touch; the result must
    still be two parts, as at full resolution."""
    m = np.zeros((120, 200), bool)
    m[20:100, 20:99] = True
    m[20:100, 101:180] = True
    T = raster.tighten(m, 16)
    assert T.levels > 1
    assert ndimage.label(T.mask)[1] == 2


def test_homotopic_transfer_keeps_the_start_topology():
    from raster.flow import _homotopic

    start = np.zeros((40, 90), bool)
    start[10:30, 5:28] = True
    start[10:30, 32:55] = True
    start[10:30, 65:80] = True
    target = np.zeros_like(start)
    target[8:32, 3:57] = True                 # the gap between the first two squares closed
    target[5:35, 62:85] = True                # the third square grown, apart from the others
    movable = np.ones_like(start)
    for c in (16, 43, 72):                     # each square held by a constraint at its centre
        movable[18:22, c - 2:c + 2] = False
    out = _homotopic(start, target, movable)
    assert ndimage.label(out)[1] == 3
    # The change that would have merged two parts is undone as a whole; the other reaches its target.
    assert (out[:, :60] == start[:, :60]).all()
    assert (out[:, 60:] == target[:, 60:]).all()
    # A small part with nowhere to go vanishes, as a one-pixel component may.
    lone = np.zeros((20, 20), bool)
    lone[8:11, 8:11] = True
    assert not _homotopic(lone, np.zeros_like(lone), np.ones_like(lone)).any()


def test_homotopic_transfer_lets_a_free_part_be_swept_over():
    """A thin bar of the initial set with no constraint in it (it lies wholly in the mortar) beside a
    part whose front the coarse level moved across it: the bar may vanish, as the flow lets it, and the
    part reaches its target. Before, the whole change was undone and the full-resolution flow had to
    redo it from the initial set (components 0 of the cross-check stalled 20 px short)."""
    from raster.flow import _homotopic

    start = np.zeros((40, 60), bool)
    start[5:35, 5:25] = True                  # a part held by its core
    start[5:35, 30:33] = True                 # a thin free bar beside it
    movable = np.ones_like(start)
    movable[10:30, 5:20] = False
    target = np.zeros_like(start)
    target[5:35, 5:31] = True                 # the part grown over the gap and half the bar
    out = _homotopic(start, target, movable)
    assert (out == target).all()
    assert ndimage.label(out)[1] == 1
    # A hole with no constraint in it is free the same way (the complement, by self-duality).
    assert (_homotopic(~start, ~target, movable) == ~target).all()



def test_homotopic_transfer_does_not_press_two_parts_together():
    """Two parts whose samples touch on the coarse grid are one part there, and the coarse flow fills the
    neck between them; reached by simple flips, that fill leaves a moat one pixel wide, a 4-connected
    staircase along a diagonal, that the full-resolution flow cannot hold open (components 2 of the
    cross-check). Each region of change beside such a moat is left to the finer level; a change that
    presses nothing reaches its target. Dually, for the complement, a wall one pixel thick."""
    from raster.flow import _homotopic, _pressed

    rows, cols = np.indices((40, 70))
    d = cols - rows
    start = (d >= 3) & (cols < 45) | (d <= -4)
    start[30:36, 55:65] = True                # a third part, apart from the others
    target = (d >= 1) & (cols < 45) | (d <= -2)
    target[28:38, 52:68] = True
    movable = np.ones_like(start)
    movable[2:6, 30:34] = movable[30:34, 2:6] = movable[32:34, 59:61] = False
    assert ndimage.label(target, np.ones((3, 3)))[1] == 3 and _pressed(target).any()
    for s0, t0 in ((start, target), (~start, ~target)):
        out = _homotopic(s0, t0, movable)
        assert not (_pressed(out) & ~_pressed(s0)).any()
        assert (out[:, :48] == s0[:, :48]).all()            # the two parts' changes are undone
        assert (out[:, 48:] == t0[:, 48:]).all()            # the third part grows to its target


def test_pressed_tells_a_moat_from_a_spike():
    """A moat one pixel wide between two parts, and a wall one pixel thick between two outside regions, are
    pressed fronts; a spike shorter than `PRESS_REACH` pixels on a front is one front folded round its
    tip (the upsampled remnant of a comb's tooth), and so is an ordinary corner. A longer one is a wall."""
    from raster.flow import PRESS_REACH, _pressed

    m = np.zeros((36, 40), bool)
    m[11:20, 5:35] = True
    m[21:31, 5:35] = True                      # a moat one pixel wide, row 20
    m[10, 10] = True                           # a spike one pixel long
    m[12 - PRESS_REACH:11, 20] = True          # one PRESS_REACH − 1 pixels long
    m[2:11, 28] = True                         # one nine pixels long
    p = _pressed(m)
    assert p[20, 6:34].all()
    assert not p[:20, :25].any() and not p[:20, 29:].any()
    assert p[3:12, 28].sum() >= 5              # the long spike, a wall between two outside parts
    assert (_pressed(~m) == p).all()           # the complement: a wall between two holes, notches


def test_reinitialise_keeps_the_levels_own_distances_where_nothing_changed():
    """A finer level's Φ keeps its own sub-pixel distances (with supersampling, to where the fine mask
    puts the front) except within reach of what the transfer changed, where it becomes the distance to
    the new front; the constraints keep theirs everywhere."""
    from raster.flow import _reinitialise

    yy, xx = np.mgrid[:60, :90]
    base = (np.hypot(yy - 30.3, xx - 25.2) - 12.4).astype(np.float32)    # sub-pixel: no pixel at ±½
    movable = np.abs(base) < 6
    inside = base < 0
    assert (_reinitialise(base, inside, movable) == base).all()
    inside[28:33, 80:85] = True               # a part far from the disk, added by the transfer
    movable[20:41, 72:90] = True
    phi = _reinitialise(base, inside, movable)
    far = np.hypot(yy - 30, xx - 82) > np.abs(base) + 6
    assert far.sum() > 1000 and (phi[far] == base[far]).all()
    assert (phi[25:36, 77:88] == raster.signed_distance(inside)[25:36, 77:88]).all()
    assert (phi[~movable] == base[~movable]).all()


def test_a_resting_front_stops_the_level_though_a_pixel_swings_in_place():
    """A square beside a disk, with a bar in the notch between them: every level rests long before the
    cap (before, a pixel swinging in place by a tenth of a pixel a step kept the two finer levels running
    to the cap, whatever the front did), and stopping there changes nothing the cap would."""
    yy, xx = np.mgrid[:120, :160]
    m = ((abs(xx - 60) < 40) & (abs(yy - 60) < 40)) | ((xx - 115) ** 2 + (yy - 45) ** 2 < 20 ** 2)
    m[70:100, 90:104] = True
    for init in ("core", "input"):
        T = raster.tighten(m, 12, init=init, iterations=3000)
        assert max(T.iterations) <= 500, T.iterations
        with pytest.warns(raster.NotConvergedWarning):        # stop=0: never rests, runs to the cap
            full = raster.tighten(m, 12, init=init, iterations=3000, stop=0.0)
        assert full.iterations == [3000] * full.levels
        assert (T.mask != full.mask).sum() <= 0.002 * T.mask.sum()


def test_edt_helpers_match_scipy():
    """`raster.morphology._edt` gives `scipy.ndimage.distance_transform_edt`'s values bit for bit."""
    from raster.morphology import _edt

    rng = np.random.default_rng(11)
    for _ in range(60):
        m = rng.random(tuple(rng.integers(1, 30, 2))) < rng.random()
        want = ndimage.distance_transform_edt(m)
        got = _edt(m)
        assert got.dtype == want.dtype and np.array_equal(got, want)


def test_nearest_fitting_corner_is_exact():
    """`_dist_to_corners` finds the nearest fitting corner of every asked pixel (brute force)."""
    from raster.morphology import _dist_to_corners

    rng = np.random.default_rng(5)
    for _ in range(20):
        fits = rng.random((15, 17)) < 0.05
        fits[rng.integers(15), rng.integers(17)] = True
        where = rng.choice(fits.size, 40, replace=False)
        fi, fj = np.nonzero(fits)
        ii, jj = np.unravel_index(where, fits.shape)
        brute = np.hypot(ii[:, None] - fi[None, :] - 0.5, jj[:, None] - fj[None, :] - 0.5).min(axis=1)
        assert np.allclose(_dist_to_corners(fits, where), brute, rtol=0, atol=1e-12)


@pytest.mark.parametrize("border", ["false", "true", "mixed"])
def test_morphology_padding_per_side_is_exact(border):
    """`_core_fillet_both` pads the mask as little as each opening needs (`_opening_pads`): the same
    core, fillet and signed distances, pixel for pixel, as with `_pad`'s full width for both."""
    from raster.morphology import _core_fillet_both, _crop, _opening, _opening_pads

    rng = np.random.default_rng({"false": 1, "true": 2, "mixed": 3}[border])
    for _ in range(12):
        h, w = rng.integers(20, 50, 2)
        yy, xx = np.mgrid[:h, :w]
        m = np.zeros((h, w), bool)
        for _ in range(4):
            m ^= (yy - rng.uniform(-5, h + 5)) ** 2 + (xx - rng.uniform(-5, w + 5)) ** 2 < rng.uniform(3, 15) ** 2
        if border == "false":
            m[[0, -1]] = False
            m[:, [0, -1]] = False
        elif border == "true":
            m[[0, -1]] = True
            m[:, [0, -1]] = True
        if not m.any() or m.all():
            continue
        r = float(rng.choice([1.5, 2.0, 3.3, 5.0, 7.5]))
        pc, pa = _opening_pads(m, r)
        if border == "false":
            assert pc == 1 and pa < 2 * math.ceil(r) + 1
        p = 2 * math.ceil(r) + 1
        P = np.pad(m, p, mode="edge")
        R, Rc, dR = (_crop(a, p) for a in _opening(P, r, parts=True))
        A, Ac, dA = (_crop(a, p) for a in _opening(~P, r, parts=True))
        got = _core_fillet_both(m, r)
        for a, b in zip(got, (R, ~A, Rc, ~Ac, dR, dA)):
            assert np.array_equal(a, b)


def test_incremental_foreign_neighbours_match_a_fresh_search(monkeypatch):
    """The flow keeps `_speed`'s foreign-neighbour mask from step to step (`_ForeignCache`); searched
    afresh at every step instead, the flow gives the same Φ bit for bit (an L and a bar two pixels
    apart, from the input: corners move with another front two pixels away; not updating the mask
    at all gives another Φ here, so the comparison has teeth)."""
    import raster.flow as fl

    m = np.zeros((40, 40), bool)
    m[5:35, 5:12] = True                        # an L, and a bar two pixels from both its arms
    m[28:35, 5:30] = True
    m[5:25, 14:20] = True
    R, F, *_ = fl._core_fillet_both(m, 3.0)
    phi = fl.signed_distance(m)                 # from the input: its corners move in
    mov = F & ~R
    want = fl._flow(phi.copy(), mov, 120, 0.0)
    calls = []

    def afresh(self, flat, pos, comp, owner):
        calls.append(pos.size)
        self.full = fl._foreign_at(flat, self.idx, self.j, comp, owner)
        self._result = None

    monkeypatch.setattr(fl._ForeignCache, "changed", afresh)
    got = fl._flow(phi.copy(), mov, 120, 0.0)
    assert calls
    assert got[1] == want[1] and np.array_equal(got[0], want[0])
    monkeypatch.setattr(fl._ForeignCache, "changed", lambda self, *a: None)
    stale = fl._flow(phi.copy(), mov, 120, 0.0)
    assert not np.array_equal(stale[0], want[0])


def test_signed_distance_at_a_few_pixels_is_the_same():
    """`_signed_distance_at` (a k-d tree of each side's edge pixels) gives `signed_distance`'s values,
    bit for bit, at the pixels asked for."""
    from raster.flow import _signed_distance_at

    rng = np.random.default_rng(9)
    for _ in range(80):
        m = rng.random(tuple(rng.integers(2, 40, 2))) < rng.random()
        if not m.any() or m.all():
            continue
        where = rng.choice(m.size, min(m.size, 30), replace=False)
        got = _signed_distance_at(m, where)
        want = raster.signed_distance(m).ravel()[where]
        assert got.dtype == want.dtype and np.array_equal(got, want)
