"""Vector against raster on small cases: where the definition leaves no room, the two must agree."""

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

import vectortighten as vt
from vectortighten.comparison import AGREE_PX, crosscheck

CASES = {
    "L-shape": (Polygon([(0, 0), (12, 0), (12, 5), (5, 5), (5, 12), (0, 12)]), 1.5),
    "square with small hole": (box(0, 0, 10, 10).difference(Point(5, 5).buffer(0.6, quad_segs=16)), 1.0),
}


@pytest.mark.parametrize("init", ["core", "input"])
@pytest.mark.parametrize("name", sorted(CASES))
def test_vector_and_raster_agree(name, init):
    S, r = CASES[name]
    c = crosscheck(S, r, pixel_size=r / 20, init=init)
    assert c.same_topology, (c.vector_topology, c.raster_topology)
    assert c.hausdorff_px <= AGREE_PX
    assert c.agree
    # The two agree within a few pixels' width along the boundary.
    assert c.symmetric_difference_px <= 3 * c.vector.perimeter / c.pixel_size


@pytest.mark.parametrize("init", ["core", "input"])
def test_two_squares_a_gap_apart(init):
    """A 16-pixel gap is one or two pixels wide on the paper's coarsest level; each front sees only itself
    (`raster.flow._speed`), so the two are not drawn together there nor at full resolution."""
    S = shapely.union(box(0, 0, 6, 6), box(6.8, 0, 12.8, 6))
    c = crosscheck(S, 1.0, pixel_size=0.05, init=init)
    assert c.vector_topology == (2, 0)
    assert c.raster_topology == (2, 0)


@pytest.mark.parametrize("init", ["core", "input"])
def test_full_resolution_flow_keeps_two_squares_apart(init):
    """Without the coarse levels the paper's pixel flow (no finish) agrees with the exact result, well within
    the target (from the input it needs 288 steps to round the corners)."""
    S = shapely.union(box(0, 0, 6, 6), box(6.8, 0, 12.8, 6))
    c = crosscheck(S, 1.0, pixel_size=0.05, init=init, levels=1, iterations=1000, supersample=1, finish="none")
    assert c.vector_topology == c.raster_topology == (2, 0)
    assert c.hausdorff_px < 0.5                      # measured 0.34 and 0.35


def test_full_resolution_flow_meets_the_bar_within_target():
    S = shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.7, 10, 3.3)])
    c = crosscheck(S, 1.0, pixel_size=0.05, levels=1, supersample=1)
    assert c.vector_topology == c.raster_topology == (2, 0)
    assert c.hausdorff_px < 0.5                      # measured 0.34


def test_bar_between_squares_from_the_core():
    """From the core the bar (thinner than 2r) is never entered: two rounded squares in both."""
    S = shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.7, 10, 3.3)])
    c = crosscheck(S, 1.0, pixel_size=0.05, init="core")
    assert c.vector_topology == c.raster_topology == (2, 0)


def test_bar_between_squares_from_the_input():
    """From the input the bar is held between two parts of the anticore and its straight sides do not move
    under the continuous flow: the exact result keeps it, one component. The coarse levels thin the bar
    (a dozen pixels thick) to a wall a pixel thick between the two parts of the anticore, which the
    full-resolution flow broke; that wall is now left to full resolution, which keeps the bar."""
    S = shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.7, 10, 3.3)])
    for supersample in (1, 5):
        c = crosscheck(S, 1.0, pixel_size=0.05, init="input", supersample=supersample)
        assert c.vector_topology == (1, 0)
        assert c.raster_topology == (1, 0)
        assert c.hausdorff_px <= AGREE_PX            # measured 0.43 and 0.92


def test_bar_between_squares_within_target():
    """The paper's coarse levels leave the front 2.8 px too far into the bar's 12-pixel mouth; run to
    convergence (the cross-check's default), full resolution pulls it back."""
    S = shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.7, 10, 3.3)])
    assert crosscheck(S, 1.0, pixel_size=0.05, supersample=1).hausdorff_px <= AGREE_PX


def test_bar_between_squares_within_target_on_the_papers_budget():
    # With the paper's budget of 100 steps a level the flow leaves the front 2.8 px into the bar's mouth
    # (this was a strict xfail); the minimum-perimeter finish, on by default, pulls it taut.
    S = shapely.union_all([box(0, 0, 6, 6), box(10, 0, 16, 6), box(6, 2.7, 10, 3.3)])
    assert crosscheck(S, 1.0, pixel_size=0.05, iterations=100, supersample=1).hausdorff_px <= AGREE_PX


def test_topology_counts():
    S = box(0, 0, 10, 10).difference(box(3, 3, 7, 7))
    c = crosscheck(S, 1.0, pixel_size=0.1)
    assert c.vector_topology == c.raster_topology == (1, 1)
    # The square ring's tightening is its core: exact perimeter from the corner formula.
    assert c.vector.perimeter == pytest.approx(40 + 16 - 2 * (8 - 2 * math.pi), rel=1e-12)


def test_table_mentions_everything():
    c = crosscheck(box(0, 0, 4, 4), 1.0, pixel_size=0.1)
    text = c.table()
    for word in ("Hausdorff", "symmetric difference", "components", "agree"):
        assert word in text


def test_bad_pixel_size():
    with pytest.raises(ValueError, match="pixel_size"):
        crosscheck(box(0, 0, 4, 4), 1.0, pixel_size=0)
    with pytest.raises(ValueError, match="too coarse|grid"):
        crosscheck(box(0, 0, 1e-3, 1e-3), 1e-4, pixel_size=1.0)


def test_public_name_and_pixel_squares():
    import raster

    assert vt.crosscheck is crosscheck
    S = Polygon([(0, 0), (7.3, 0), (2.1, 5.2)])
    grid = raster.Grid.covering(S.bounds, 0.1, 0.3)
    mask, _ = raster.rasterize(S, grid)
    P = vt.pixel_squares(mask, grid)
    assert P.is_valid
    assert P.area == pytest.approx(mask.sum() * 0.01, rel=1e-12)
    # Every pixel centre in the mask is inside the squares, every other one outside.
    rows, cols = np.indices(mask.shape)
    cx, cy = grid.to_world(rows.ravel(), cols.ravel())
    assert (shapely.contains_xy(P, cx, cy) == mask.ravel()).all()


def test_mask_reference_separates_rasterisation_from_the_flow():
    """A gap of 0.3 pixel holds no pixel centre: S has two parts, its mask one block. The exact result of S
    keeps two rounded squares, so the pixel result (one) disagrees with it; measured against the exact
    tightening of the mask it was given, the pixel flow agrees."""
    S = shapely.union(box(0, 0, 6, 6), box(6.015, 0, 12, 6))
    c = crosscheck(S, 1.0, pixel_size=0.05, mask_reference=True, supersample=1)
    assert c.vector_topology == (2, 0)
    assert c.raster_topology == (1, 0) and c.mask_topology == (1, 0)
    assert not c.agree
    assert c.agree_on_mask and c.mask_hausdorff_px <= AGREE_PX
    assert "exact of the mask" in c.table()
    assert crosscheck(S, 1.0, pixel_size=0.05, supersample=1).agree_on_mask is None


# -- supersampled morphology --------------------------------------------------------------------------------
def _wedge(half_angle_deg: float, length: float = 6.0) -> Polygon:
    t = math.radians(half_angle_deg)
    return Polygon([(0, 0), (length * math.cos(t), length * math.sin(t)),
                    (length * math.cos(t), -length * math.sin(t))])


def test_supersampling_puts_the_disk_of_an_acute_corner_where_it_belongs():
    # In a wedge of half-angle α the disk of radius r touching both sides sits r/sin α from the apex; a
    # side off by δ moves it by δ/sin α (2.9·δ at 12°). A plain rasterisation (sides off by up to half a
    # pixel) puts the pixel result beyond the 2 px bar; the core computed three times finer, a third.
    S, r, h = _wedge(12.0), 0.5, 0.025
    plain = crosscheck(S, r, pixel_size=h, supersample=1)
    fine = crosscheck(S, r, pixel_size=h, supersample=3)
    assert fine.grid == plain.grid and fine.raster.mask.shape == plain.raster.mask.shape
    assert fine.raster.r == pytest.approx(r / h)
    assert fine.same_topology and fine.hausdorff_px <= 1.5
    assert plain.hausdorff_px > AGREE_PX and fine.hausdorff_px < 0.5 * plain.hausdorff_px


def test_supersampled_pixel_result_respects_its_constraints():
    import raster

    yy, xx = np.mgrid[:99, :120]
    M = ((xx - 40) ** 2 + (yy - 50) ** 2 < 30 ** 2) | ((abs(xx - 85) < 25) & (abs(yy - 50) < 4))
    T = raster.tighten(M, 15.0, supersample=3)
    assert T.mask.shape == (33, 40) and T.r == pytest.approx(5.0)
    assert (T.core <= T.mask).all() and (T.mask <= T.fillet).all()
    # The flow's pixels are the centres of the 3 × 3 blocks: the constraints are the fine ones sampled there.
    R, F = raster.core(M, 15.0), raster.fillet(M, 15.0)
    assert (T.core == R[1::3, 1::3][:33, :40]).all() and (T.fillet == F[1::3, 1::3][:33, :40]).all()
    # The bar (8 px wide, thinner than 2r) is gone; the disk stays one part, without a hole.
    assert not T.mask[16, 35:].any() and T.mask[16, 13]


@pytest.mark.parametrize("bad", [0, 2, -1, 1.5, True, "3"])
def test_supersample_must_be_odd_and_whole(bad):
    import raster

    M = np.zeros((30, 30), bool)
    M[5:25, 5:25] = True
    with pytest.raises(ValueError, match="supersample"):
        raster.tighten(M, 3.0, supersample=bad)
    with pytest.raises(ValueError, match="supersample"):
        crosscheck(box(0, 0, 4, 4), 1.0, pixel_size=0.1, supersample=bad)


def test_a_mask_too_large_to_supersample_falls_back_to_plain_morphology(monkeypatch):
    # The limit is lowered so that the test allocates nothing large: the 99 × 120 mask (11,880 px) is over
    # a limit of 10,000, so the morphology runs on the 3 × 3 blocks' centres, exactly as if the mask had been
    # sampled there by hand and tightened plainly, and the warning gives the limit.
    import raster
    import raster.flow

    monkeypatch.setattr(raster.flow, "MAX_SUPERSAMPLED_PIXELS", 10_000)
    yy, xx = np.mgrid[:99, :120]
    M = ((xx - 40) ** 2 + (yy - 50) ** 2 < 30 ** 2) | ((abs(xx - 85) < 25) & (abs(yy - 50) < 4))
    with pytest.warns(raster.SupersampleWarning, match="limit 10,000 pixels"):
        T = raster.tighten(M, 15.0, supersample=3)
    plain = raster.tighten(M[1::3, 1::3], 5.0)
    assert T.mask.shape == (33, 40) and T.r == pytest.approx(5.0)
    assert (T.mask == plain.mask).all() and (T.core == plain.core).all() and (T.fillet == plain.fillet).all()
    assert (T.core <= T.mask).all() and (T.mask <= T.fillet).all()


def test_crosscheck_too_fine_to_supersample_warns_and_runs_plain(monkeypatch):
    import raster
    import raster.flow

    S = box(0, 0, 10, 10)
    grid_px = crosscheck(S, 2.0, pixel_size=0.1, supersample=1).grid.shape
    limit = grid_px[0] * grid_px[1] * 9 - 1             # supersample 3 would be one pixel over
    monkeypatch.setattr(raster.flow, "MAX_SUPERSAMPLED_PIXELS", limit)
    with pytest.warns(raster.SupersampleWarning, match=f"limit of {limit:,}"):
        c = crosscheck(S, 2.0, pixel_size=0.1, supersample=3)
    assert c.supersample == 1 and c.raster.mask.shape == grid_px
    assert c.agree


def _two_disks(gap: float, angle_deg: float, radius: float = 1.5) -> shapely.Geometry:
    t = math.radians(angle_deg)
    d = 2 * radius + gap
    return shapely.union(Point(0.013, 0.007).buffer(radius, quad_segs=64),
                         Point(d * math.cos(t), d * math.sin(t)).buffer(radius, quad_segs=64))


@pytest.mark.parametrize("supersample", [3, 5])
@pytest.mark.parametrize("init", ["core", "input"])
def test_two_cores_under_two_pixels_apart_stay_apart(init, supersample):
    # Components 2 of the cross-check in small: two disks larger than r (their own cores) 1.8 px apart
    # along a line at 60°. The exact tightening is the two disks. On the coarse levels their samples
    # touch and the flow filled the neck between them as one part's; the finer levels were left with
    # two fronts a one-pixel moat apart, and with Φ rebuilt from the pixel staircase instead of the
    # supersampled distances, so a moat pixel crossed and joined the parts (19 px).
    S = _two_disks(0.09, 60.0)
    c = crosscheck(S, 1.0, pixel_size=0.05, init=init, supersample=supersample)
    assert c.vector_topology == (2, 0)
    assert c.raster_topology == (2, 0)
    assert c.hausdorff_px <= 1.0                     # measured 0.62–0.64


def test_supersampling_keeps_a_disk_whose_shrink_is_under_a_pixel():
    # A disk of radius 1.02·r: its shrink is a disk of radius 0.02·r, 0.4 px at r/20, which holds no pixel
    # centre, so the plain pixel core is empty and the part vanishes; the exact tightening keeps the disk.
    # Three times finer the shrink holds a pixel and the pixel result keeps the disk too.
    S = Point(0.3, 0.1).buffer(1.02, quad_segs=64)
    plain = crosscheck(S, 1.0, pixel_size=0.05, supersample=1)
    fine = crosscheck(S, 1.0, pixel_size=0.05, supersample=3)
    assert plain.vector_topology == (1, 0) and plain.raster_topology == (0, 0)
    assert fine.agree and fine.hausdorff_px < 1.0
    # The cross-check's default is five times finer, and keeps it too.
    default = crosscheck(S, 1.0, pixel_size=0.05)
    assert default.agree and default.hausdorff_px < 1.0
