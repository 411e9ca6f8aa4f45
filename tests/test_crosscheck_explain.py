"""`CrossCheck.explain`: one honestly constructed case of each kind of disagreement (issue 21, item 4)."""

import dataclasses
import warnings

import numpy as np
import shapely
from shapely.geometry import Point, box

from raster import NotConvergedWarning
from vectortighten.comparison import KINDS, crosscheck


def test_agreeing_check_has_nothing_to_explain():
    c = crosscheck(box(0, 0, 10, 10), 2.0, pixel_size=0.1)
    assert c.agree and c.explain() == []
    assert "agree" in c.explain_text()


def test_a_bar_just_under_2r_is_a_rasterisation_no_grid_resolves():
    # 1.97 wide at r = 1: exactly it vanishes; its mask is 20 pixels of 0.1 wide, 2r, which the pixel
    # method keeps (as the exact engine does with the mask's own squares, and with S grown by ½ diagonal).
    c = crosscheck(box(0, 0.013, 12, 1.983), 1.0, pixel_size=0.1, supersample=1)
    assert c.vector_topology == (0, 0) and c.raster_topology == (1, 0)
    found = c.explain()
    assert [d.kind for d in found] == ["rasterisation (not resolvable)"]
    assert found[0].topology and found[0].pixels > 1000
    assert any("pixel input agrees" in e and "100%" in e for e in found[0].evidence)


def test_a_slanted_bar_2r_wide_is_a_rasterisation_where_the_mask_decides_otherwise():
    # 2.004 wide at r = 1, slanted 7°: exactly the whole bar is core. Its mask's staircase holds a disk of
    # radius r only here and there, and the pixel morphology (disk centres on pixel centres and corners)
    # finds fewer of them than the exact engine on the mask's squares, so the pixel input's own exact
    # tightening is no witness. S shrunk by ½ pixel diagonal, 1.86 wide, loses the bar as the pixel
    # result does: the rasterisation decides, and the evidence gives the width against 2r.
    from shapely import affinity

    S = affinity.rotate(box(0, -1.002, 12, 1.002), 7, origin=(0, 0))
    c = crosscheck(S, 1.0, pixel_size=0.1, supersample=1)
    assert c.vector_topology == (1, 0) and not c.agree
    found = c.explain()
    assert found and {d.kind for d in found} == {"rasterisation (not resolvable)"}
    witness = [d for d in found if any("decides it otherwise" in e for e in d.evidence)]
    assert witness, c.explain_text(found)
    for d in witness:
        assert any("agrees with the pixel result on 100%" in e for e in d.evidence)
        width = [e for e in d.evidence if e.startswith("width:")]
        assert width and "a stroke of S 2.00" in width[0] and "2r = 2;" in width[0] and "pixel 0.1" in width[0]


def test_a_flow_stopped_after_two_steps_is_unconverged():
    # From the input, a square at r = 3 must cut its corners by 1.2 (12 px); two steps move the front
    # two pixels at most.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotConvergedWarning)
        c = crosscheck(box(0, 0, 10, 10), 3.0, pixel_size=0.1, init="input", iterations=2,
                       finish="none", supersample=5)
    assert not c.agree and not c.raster.is_converged
    found = c.explain()
    assert found and {d.kind for d in found} == {"unconverged flow"}
    assert all(d.depth_px > 2 for d in found)


def test_two_inits_of_a_dumbbell_are_two_valid_tightenings():
    # Two disks joined by a bar thinner than 2r: the core has two parts. From the core the tightening is
    # the two disks; from the input it keeps the bar. Both are valid; the check pairs the exact result of
    # one with the pixel result of the other, and explain must say so and name the shorter.
    S = shapely.union_all([Point(0, 0).buffer(3, quad_segs=32), Point(9, 0).buffer(3, quad_segs=32),
                           box(0, -0.75, 9, 0.75)])
    # supersample 5 (not the default 7): what is tested is the verdict, and the exact tightening of
    # the finer mask's staircase that explain() computes costs twice as much.
    from_core = crosscheck(S, 1.0, pixel_size=0.1, init="core", supersample=5)
    from_input = crosscheck(S, 1.0, pixel_size=0.1, init="input", supersample=5)
    assert from_core.vector_topology == (2, 0) and from_input.raster_topology == (1, 0)
    mixed = dataclasses.replace(from_core, raster=from_input.raster)
    found = mixed.explain()
    assert [d.kind for d in found] == ["two valid tightenings"]
    p = found[0].perimeters
    assert p["exact"] < p["pixel"] and p["shorter"] == "exact"
    assert abs(p["exact"] - from_core.vector.perimeter) < 1e-9
    assert "shorter: exact" in mixed.explain_text()


def test_a_hole_punched_into_the_pixel_core_is_a_pixel_defect():
    c = crosscheck(box(0, 0, 10, 10), 2.0, pixel_size=0.1)
    rt = c.raster
    mask = rt.mask.copy()
    rows, cols = np.nonzero(rt.core)
    r0, c0 = rows.mean().astype(int), cols.mean().astype(int)
    mask[r0 - 5:r0 + 5, c0 - 5:c0 + 5] = False
    broken = dataclasses.replace(c, raster=dataclasses.replace(rt, mask=mask, curves=None))
    found = broken.explain()
    assert [d.kind for d in found] == ["defect of the pixel side"]
    assert any("core ⊆ T ⊆ F fails" in e and "100 core pixels" in e for e in found[0].evidence)


def test_an_exact_result_cut_into_its_core_is_an_exact_defect():
    c = crosscheck(box(0, 0, 10, 10), 2.0, pixel_size=0.1)
    T = c.vector
    cut = T.geometry.difference(box(4, 4, 6, 6))
    wrong = dataclasses.replace(T, geometry=cut)
    import raster

    vmask, _ = raster.rasterize(cut, c.grid)
    broken = dataclasses.replace(c, vector=wrong, vector_mask=vmask, hausdorff_px=20.0)
    found = broken.explain()
    assert [d.kind for d in found] == ["defect of the exact side"]
    # verify() names the defect: the hole is in the core and off the loops ("(a) the geometry differs").
    assert any("verify(): (a)" in e for e in found[0].evidence)


def test_kinds_are_the_documented_ones():
    assert len(KINDS) == len(set(KINDS)) == 7
