"""Short edges between corners of the same side on the fast path (`_fast._same_side_runs`): a bevel, a round
corner digitised by a few chords and a chamfered inner corner become one corner disk; a slot (or a tab)
narrower than 2r is spanned by the disk through its mouth's two corners. Each against closed-form centres,
the general engine and the oracle."""

import math

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

import vectortighten as vt

from .engines import assert_exact, assert_same, disks, general


def _has(c, x, y):
    return np.hypot(c[:, 0] - x, c[:, 1] - y).min() < 1e-12


def _fast_and_right(S, r, init="core"):
    T = vt.tighten(S, r, init=init)
    assert T._cache["_path"] == "fast" and T.verify() == []
    assert_same(T, general(S, r, init), rel=1e-10)
    assert_exact(S, r, T)
    return T


L_SHAPE = [(0, 0), (10, 0), (10, 5), (5, 5), (5, 10), (0, 10)]


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_bevelled_corner_is_one_disk(init):
    # The corner (10, 0) of an L cut by a 45° chamfer of legs 0.3: both 45° tangents r·tan(22.5°) do not
    # fit on its 0.42 edge. The one disk tangent to the two walls, centre (10 − r, r), clears the chamfer
    # ((2 − 0.3)/√2 = 1.2 from it) and turns by 90°.
    r, c = 1.0, 0.3
    S = Polygon([(0, 0), (10 - c, 0), (10, c), (10, 5), (5, 5), (5, 10), (0, 10)])
    T = _fast_and_right(S, r, init)
    centres, _ = disks(T)
    assert len(centres) == 6                        # one disk a corner: the bevel's two merged
    assert _has(centres, 10 - r, r)


def test_a_round_corner_of_four_chords_is_one_disk():
    # A quarter circle of radius 0.5 about (9.5, 4.5), digitised by 4 chords (0.195 long; turns 11.25° at
    # the ends, 22.5° between): no chord holds its two tangents. The corner becomes the wall corner's
    # own disk, centre (10 − r, 5 − r), its arc turning 90°.
    r, R = 1.0, 0.5
    arc = [(9.5 + R * math.cos(a), 4.5 + R * math.sin(a)) for a in np.linspace(0, math.pi / 2, 5)]
    S = Polygon([(0, 0), (10, 0)] + arc + [(5, 5), (5, 10), (0, 10)])
    T = _fast_and_right(S, r)
    centres, _ = disks(T)
    assert len(centres) == 6
    assert _has(centres, 10 - r, 5 - r)
    (L,) = T.loops
    arcs = [p for p in L.pieces if hasattr(p, "sweep") and math.dist(p.center, (9, 4)) < 1e-9]
    assert len(arcs) == 1 and abs(arcs[0].sweep) == pytest.approx(math.pi / 2, abs=1e-12)


def test_a_chamfered_inner_corner_is_one_disk_outside():
    # The L's reflex corner (5, 5) chamfered by legs 0.4: the disk outside S tangent to both walls,
    # centre (5 + r, 5 + r), takes both reflex corners.
    r, c = 1.0, 0.4
    S = Polygon([(0, 0), (10, 0), (10, 5), (5 + c, 5), (5, 5 + c), (5, 10), (0, 10)])
    T = _fast_and_right(S, r)
    centres, sides = disks(T)
    assert len(centres) == 6
    assert _has(centres, 5 + r, 5 + r) and sides[np.hypot(*(centres - (5 + r, 5 + r)).T).argmin()] == -1


def _slot(w, h, x0=5.0):
    """A block with a slot w wide and h deep cut up into its lower wall at x0 (h < 0: a tab below)."""
    return Polygon([(0, 0), (x0, 0), (x0, h), (x0 + w, h), (x0 + w, 0), (12, 0), (12, 10), (0, 10)])


@pytest.mark.parametrize("init", ["core", "input", "mason"])
@pytest.mark.parametrize("w,h", [(0.5, 3.0), (1.5, 1.2)])
def test_a_deep_slot_narrower_than_2r(w, h, init):
    # The disk E through the mouth's corners (5, 0) and (5 + w, 0), outside S: centre sqrt(r² − w²/4)
    # below the mouth's middle. The corners' own disks touch both their edges: centres (5 − r, r) and
    # (5 + w + r, r).
    r = 1.0
    T = _fast_and_right(_slot(w, h), r, init)
    centres, _ = disks(T)
    assert len(centres) == 7                        # 4 block corners, 2 mouth corners, E
    assert _has(centres, 5 + w / 2, -math.sqrt(r * r - w * w / 4))
    assert _has(centres, 5 - r, r) and _has(centres, 5 + w + r, r)


@pytest.mark.parametrize("w,h", [(0.5, 0.5), (1.9, 0.9), (0.3, 0.2)])
def test_a_shallow_slot_slides_its_mouth_disks(w, h):
    # Shallower than r: each mouth corner's disk slides along its wall until it meets the slot's floor
    # corner: tangent to y = 0 and through (5, h), centre (5 − sqrt(2rh − h²), r) (and mirrored).
    r = 1.0
    T = _fast_and_right(_slot(w, h), r)
    centres, _ = disks(T)
    a = math.sqrt(2 * r * h - h * h)
    assert _has(centres, 5 - a, r) and _has(centres, 5 + w + a, r)
    assert _has(centres, 5 + w / 2, -math.sqrt(r * r - w * w / 4))


@pytest.mark.parametrize("w,h", [(0.5, 3.0), (1.2, 0.4)])
def test_a_tab_narrower_than_2r(w, h):
    # A protrusion below the wall: E lies inside S, sqrt(r² − w²/4) above the mouth's middle.
    r = 1.0
    T = _fast_and_right(_slot(w, -h), r)
    centres, sides = disks(T)
    i = np.hypot(*(centres - (5 + w / 2, math.sqrt(r * r - w * w / 4))).T).argmin()
    assert _has(centres, 5 + w / 2, math.sqrt(r * r - w * w / 4)) and sides[i] == 1


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_tab_wider_at_its_mouth_than_2r_rests_on_its_wall(init):
    # A block's right wall bends slightly at (10, 4) and runs up to a tab 1.6 wide, (10.3, 9)–(8.7, 9),
    # whose left wall comes down to (8.7, 6). The mouth (10, 4)–(8.7, 6) is √5.69 ≈ 2.39 wide: no disk of
    # radius 1 passes through both. The core's corner there is the disk tangent to the bent wall, from
    # inside, through the reflex corner (8.7, 6): centre P + s·u with P the wall's point (10, 4) moved by
    # r along its inner normal, s the first root of |P + s·u − (8.7, 6)| = r.
    r = 1.0
    S = Polygon([(0, 0), (10, 0), (10, 4), (10.3, 9), (8.7, 9), (8.7, 6), (0, 6)])
    T = _fast_and_right(S, r, init)
    u = np.array([0.3, 5.0]) / math.hypot(0.3, 5.0)
    P = np.array([10.0, 4.0]) + r * np.array([-u[1], u[0]])
    q = P - (8.7, 6.0)
    b, c = float(q @ u), float(q @ q) - r * r
    E = P + (-b - math.sqrt(b * b - c)) * u
    centres, sides = disks(T)
    i = np.hypot(*(centres - E).T).argmin()
    assert _has(centres, *E) and sides[i] == 1


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_tab_beside_a_notch_rests_on_their_shared_wall(init):
    # A crenellation on the top wall of a 12 × 8 block: a tab 1.5 wide and 1 high, (7, 8)–(5.5, 9), and at
    # once a notch 1.5 wide and 1 deep, (5.5, 7)–(4, 8), sharing the wall x = 5.5. The disk through the
    # tab's mouth, (7, 8) and (5.5, 7), would reach 0.5 into the notch (its centre (6.01, 7.86) is 0.51 from
    # the wall). The core's corner is the disk tangent to the shared wall from inside, through (7, 8):
    # centre (6.5, 8 − √0.75); the anticore's, tangent to it from outside through (4, 8): (4.5, 8 + √0.75).
    # The loop runs up the shared wall between them.
    r = 1.0
    S = Polygon([(0, 0), (12, 0), (12, 8), (7, 8), (7, 9), (5.5, 9), (5.5, 7), (4, 7), (4, 8), (0, 8)])
    T = _fast_and_right(S, r, init)
    centres, sides = disks(T)
    for (x, y), side in (((6.5, 8 - math.sqrt(0.75)), 1), ((4.5, 8 + math.sqrt(0.75)), -1)):
        i = np.hypot(centres[:, 0] - x, centres[:, 1] - y).argmin()
        assert _has(centres, x, y) and sides[i] == side


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_slot_whose_walls_bend_slightly_is_spanned_at_its_true_mouth(init):
    # A slot 1.5–1.6 wide and 3 deep whose walls bend by 3.8° half way up, both to the left as one walks
    # the ring (convex bends in a notch of reflex corners). The bends are not its mouth: the disk through
    # them, 0.66 below their middle, is 0.75 from either wall. E passes through the true mouth corners
    # (5, 0) and (6.6, 0), 1.6 apart: centre (5.8, −sqrt(r² − 0.8²)) = (5.8, −0.6). The bends' own disks
    # are passed by.
    r = 1.0
    S = Polygon([(0, 0), (5, 0), (5, 1.5), (4.9, 3), (6.5, 3), (6.5, 1.5), (6.6, 0), (12, 0), (12, 10),
                 (0, 10)])
    T = _fast_and_right(S, r, init)
    centres, sides = disks(T)
    assert len(centres) == 7                        # 4 block corners, 2 mouth corners, E
    assert _has(centres, 5.8, -0.6) and sides[np.hypot(*(centres - (5.8, -0.6)).T).argmin()] == -1


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_notch_rests_on_the_wall_beyond_its_mouth(init):
    # A channel 1.6 wide between x = 0 and x = 1.6 whose right wall ends at the convex corner A = (1.6, 2.3)
    # and whose left wall bends slightly at D = (0, 1.8) and runs on up to (−0.1, 3.5). Through A and D no
    # disk clears both walls (the channel is narrower than 2r). The anticore's corner is the disk tangent
    # to the wall beyond D, from the channel's side, through A: centre P + x·u with P = D moved by r off
    # that wall, x the larger root of |P + x·u − A| = r. D's own disk is passed by.
    r = 1.0
    S = Polygon([(10, 2.3), (1.6, 2.3), (1.6, 0), (0, 0), (0, 1.8), (-0.1, 3.5), (-0.1, 7), (-5, 7), (-5, -3),
                 (10, -3)])
    T = _fast_and_right(S, r, init)
    u = np.array([-0.1, 1.7]) / math.hypot(0.1, 1.7)
    P = np.array([0.0, 1.8]) + r * np.array([u[1], -u[0]])
    q = P - (1.6, 2.3)
    b, c = float(q @ u), float(q @ q) - r * r
    E = P + (-b + math.sqrt(b * b - c)) * u
    centres, sides = disks(T)
    assert _has(centres, *E) and sides[np.hypot(*(centres - E).T).argmin()] == -1
    assert len(centres) == 8                        # D's own disk (inside S, beside it) is not on the loop
    assert not ((np.hypot(*(centres - (0.0, 1.8)).T) < 2 * r) & (sides == 1)).any()


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_slot_with_a_flared_mouth_is_spanned_by_the_disk_tangent_to_both_flares(init):
    # A slot 1.2 wide whose walls flare out over their last 1.5 to a mouth (5, 0)–(7, 0) exactly 2r wide. The
    # disk tangent to both flares, outside S, sits on the slot's axis where its distance to the left flare
    # (through (5, 0), direction (0.4, 1.5)) is r: |1.5·1 − 0.4·y| = sqrt(0.4² + 1.5²), y = −0.1309. The loop
    # reaches it from the mouth corners' disks on inner tangents (its feet lie before their tangent points).
    r = 1.0
    S = Polygon([(0, 0), (5, 0), (5.4, 1.5), (5.4, 3), (6.6, 3), (6.6, 1.5), (7, 0), (12, 0), (12, 10), (0, 10)])
    T = _fast_and_right(S, r, init)
    y = (1.5 - math.hypot(0.4, 1.5)) / 0.4
    centres, sides = disks(T)
    assert _has(centres, 6.0, y) and sides[np.hypot(*(centres - (6.0, y)).T).argmin()] == -1
    assert len(centres) == 7


@pytest.mark.parametrize("init", ["core", "input", "mason"])
@pytest.mark.parametrize("corner", ["bevel", "round"])
def test_a_bevel_beside_a_step_is_one_disk_across_the_step(corner, init):
    # The bottom wall steps up by 0.3 at x = 8.6 and its tread runs into the corner (10, 0.3), bevelled
    # (legs 0.2) or rounded (radius 0.3, three chords). The corner's one disk is tangent to the tread and
    # the right wall: centre (10 − r, 0.3 + r) = (9, 1.3), its foot on the tread at x = 9, on the step's
    # edge. The step's lower corner's disk slides back along y = 0 until it meets the step's upper end:
    # centre (8.6 − sqrt(r² − 0.7²), r). The loop runs straight from it to the corner's disk, passing the
    # step's reflex corner by.
    r = 1.0
    if corner == "bevel":
        bend = [(9.8, 0.3), (10, 0.5)]
    else:
        bend = [(9.7, 0.3)] + [(9.7 + 0.3 * math.sin(a), 0.6 - 0.3 * math.cos(a))
                               for a in np.linspace(0, math.pi / 2, 4)[1:]]
    S = Polygon([(0, 0), (8.6, 0), (8.6, 0.3)] + bend + [(10, 6), (0, 6)])
    T = _fast_and_right(S, r, init)
    centres, sides = disks(T)
    assert _has(centres, 9.0, 1.3) and _has(centres, 8.6 - math.sqrt(r * r - 0.49), r)
    assert len(centres) == 5 and (sides == 1).all()


@pytest.mark.parametrize("init", ["core", "input", "mason"])
def test_a_dent_too_shallow_for_its_mouth_disk_is_two_steps(init):
    # 1.9 wide and 0.2 deep: the disk through the mouth would poke 1 − sqrt(1 − 0.95²) = 0.69 above it,
    # through the floor. The dent is two steps with its floor between them: each floor corner's disk, outside
    # S, slides along the floor until it meets its step's mouth corner, centre (5 + sqrt(2rh − h²), h − r) =
    # (5.6, −0.8) and mirrored (6.3, −0.8); each mouth corner's disk slides along the wall until it meets the
    # floor corner, (5 − sqrt(r² − (r − h)²), r) = (4.4, 1) and (7.5, 1). The loop runs along the floor between
    # the two floor disks (0.7 of it).
    r = 1.0
    T = _fast_and_right(_slot(1.9, 0.2), r, init)
    centres, sides = disks(T)
    for (x, y), side in (((5.6, -0.8), -1), ((6.3, -0.8), -1), ((4.4, 1.0), 1), ((7.5, 1.0), 1)):
        assert _has(centres, x, y) and sides[np.hypot(centres[:, 0] - x, centres[:, 1] - y).argmin()] == side
    assert len(centres) == 8


def test_cases_the_fast_path_declines():
    r = 1.0
    # A mouth corner whose wall is a step: the notch and the step would share a disk.
    S = Polygon([(0, 0), (4.8, 0), (4.8, 0.3), (5, 0.3), (5, 1), (5.5, 1), (5.5, 0.3), (12, 0.3), (12, 10),
                 (0, 10)])
    assert vt.tighten(S, r)._cache["_path"] == "general"


@st.composite
def featured_blocks(draw):
    """A 30 × 12 block (r = 1) whose lower wall has 1–3 features 7–9 apart — slots and tabs 0.2–1.9 wide
    and 0.1–3 deep, slightly slanted, or bevels — and whose corners may be chamfered (legs 0.05–0.5);
    turned by a random angle."""
    pts, x = [(0.0, 0.0)], 0.0
    for _ in range(draw(st.integers(1, 3))):
        x += draw(st.floats(7.0, 9.0))
        kind = draw(st.sampled_from(["slot", "tab", "bevel"]))
        if kind == "bevel":
            c = draw(st.floats(0.05, 0.5))
            pts += [(x, 0.0), (x + c, -c), (x + 3.0, -c), (x + 3.0 + c, 0.0)]
            x += 3.0 + c
            continue
        w, h = draw(st.floats(0.2, 1.9)), draw(st.floats(0.1, 3.0)) * (1 if kind == "slot" else -1)
        lean = draw(st.floats(-0.1, 0.1))
        pts += [(x, 0.0), (x + lean * h, h), (x + w + lean * h, h), (x + w, 0.0)]
        x += w
    x += draw(st.floats(7.0, 9.0))
    c1, c2 = draw(st.floats(0.05, 0.5)), draw(st.floats(0.05, 0.5))
    pts += [(x, 0.0), (x, 12.0 - c1), (x - c1, 12.0), (c2, 12.0), (0.0, 12.0 - c2)]
    S = Polygon(pts)
    return shapely.affinity.rotate(S, draw(st.floats(0, 360)), origin=(0, 0)) if S.is_valid else None


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(S=featured_blocks(), init=st.sampled_from(["core", "input", "mason"]))
def test_fast_results_with_runs_are_the_general_engines(S, init):
    if S is None:
        return
    T = vt.tighten(S, 1.0, init=init)
    if T._cache["_path"] != "fast":
        return
    assert T.verify() == []
    assert_same(T, general(S, 1.0, init), rel=1e-10)
    assert_exact(S, 1.0, T)
