import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

import raster


def _star():
    ang = np.linspace(0, 2 * np.pi, 19)[:-1]
    rad = np.where(np.arange(18) % 2 == 0, 9.0, 3.0)
    return Polygon(np.c_[rad * np.cos(ang), rad * np.sin(ang)])


def test_quickcheck_star():
    xs = np.arange(-12, 12, 0.1) + 0.05
    X, Y = np.meshgrid(xs, xs)
    m = shapely.contains_xy(_star(), X, Y)
    res = raster.tighten(m, 6.0)
    core = raster.core(m, 6.0)
    fil = raster.fillet(m, 6.0)
    assert not (core & ~res.mask).any() and not (res.mask & ~fil).any()


def test_core_inside_mask_inside_fillet():
    rng = np.random.default_rng(1)
    m = rng.random((60, 70)) < 0.5
    for r in (1.0, 2.5, 4.0):
        c, f = raster.core(m, r), raster.fillet(m, r)
        assert not (c & ~m).any() and not (m & ~f).any()
