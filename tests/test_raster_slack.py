"""The pixel result keeps no hole that holds no anticore and no component that holds no core (issue 21)."""

import warnings

import numpy as np

import vectortighten as vt
from raster.flow import _drop_slack_parts
from tests import shapes_dense as sd


def test_a_hole_around_mortar_only_is_filled_and_a_part_without_core_dropped():
    inside = np.zeros((20, 20), bool)
    inside[2:12, 2:12] = True
    inside[6, 6] = False                        # a hole of mortar only: its loop can shrink away
    inside[15:18, 15:18] = True                 # a part holding no core
    R = np.zeros_like(inside)
    R[4:10, 4:6] = True
    F = np.ones_like(inside)
    F[0, :] = False
    out = _drop_slack_parts(inside, R, F)
    assert out[6, 6] and not out[15:18, 15:18].any()
    assert (out[2:12, 2:12]).all() and out.sum() == 100


def test_a_hole_holding_anticore_is_kept():
    inside = np.zeros((20, 20), bool)
    inside[2:18, 2:18] = True
    inside[8:12, 8:12] = False
    R = inside.copy()
    R[7:13, 7:13] = False
    F = np.ones_like(inside)
    F[9:11, 9:11] = False
    assert (_drop_slack_parts(inside, R, F) == inside).all()


def test_blob_seed_0_at_r_3_from_the_input_has_the_exact_topology():
    # The flow cut off a 1-px hole with a diagonal chain of single pixels and kept swinging it.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c = vt.crosscheck(sd.pixel_blob(60, 0), 3.0, pixel_size=1.0, init="input", mask_reference=True)
    assert c.mask_topology == c.raster_topology == (1, 1)
    assert c.agree_on_mask
