"""Parts exactly 2r wide on pixels (issue 24): at a whole radius r a stroke of 2r pixels is core, a gap of
2r pixels is anticore, and a stroke or gap of 2r − 1 is neither; the same in `raster.tighten`."""

import numpy as np
import pytest
from scipy import ndimage

import raster

RADII = (3, 8)


def _bar(r, w, vertical=False):
    """A straight stroke w pixels wide and 12r long on a blank image, the slice of its middle, and its
    exact core sampled at the pixel centres: the centres within r (open) of the closed shrink of the
    stroke's squares, the rectangle r in from each side (a segment when w = 2r)."""
    L = 12 * r
    m = np.zeros((w + 4 * r, L + 4 * r), bool)
    m[2 * r:2 * r + w, 2 * r:2 * r + L] = True
    mid = (slice(2 * r, 2 * r + w), slice(2 * r + 3 * r, 2 * r + L - 3 * r))
    x0, x1 = 2 * r - 0.5 + r, 2 * r + L - 0.5 - r
    y0, y1 = 2 * r - 0.5 + r, 2 * r + w - 0.5 - r
    yy, xx = np.mgrid[:m.shape[0], :m.shape[1]]
    gap = np.hypot(np.maximum(np.maximum(x0 - xx, xx - x1), 0), np.maximum(np.maximum(y0 - yy, yy - y1), 0))
    exact = (gap < r) if y1 >= y0 else np.zeros_like(m)
    if vertical:
        return m.T.copy(), (mid[1], mid[0]), exact.T.copy()
    return m, mid, exact


def _staircase(r, w):
    """A stroke descending in steps: step k is w pixels tall and 6r long, each r pixels lower than the
    last. Returns the mask and the middle column of each step with the rows the step covers there."""
    s, h, n = 6 * r, r, 4
    m = np.zeros((2 * r + n * h + w + 2 * r, 2 * r + n * s + 2 * r), bool)
    cols = []
    for k in range(n):
        y, x = 2 * r + k * h, 2 * r + k * s
        m[y:y + w, x:x + s] = True
        cols.append((slice(y, y + w), x + s // 2))
    return m, cols


@pytest.mark.parametrize("r", RADII)
@pytest.mark.parametrize("vertical", [False, True])
@pytest.mark.parametrize("dw", [-1, 0, 1])
def test_a_bar_is_core_exactly_when_it_is_at_least_2r_wide(r, vertical, dw):
    m, mid, exact = _bar(r, 2 * r + dw, vertical)
    R = raster.core(m, r)
    assert (R <= m).all()
    assert R[mid].all() if dw >= 0 else not R.any()       # the whole width, along the middle
    assert (R == exact).all()                             # and the caps: the continuous core, exactly


@pytest.mark.parametrize("r", RADII)
@pytest.mark.parametrize("vertical", [False, True])
@pytest.mark.parametrize("dw", [-1, 0, 1])
def test_a_gap_is_anticore_exactly_when_it_is_at_least_2r_wide(r, vertical, dw):
    bar, mid, exact = _bar(r, 2 * r + dw, vertical)
    m = ~bar                           # a slot in a block that fills the image (and continues beyond it)
    A = raster.anticore(m, r)
    assert A[mid].all() if dw >= 0 else not A.any()
    assert (A == exact).all()
    assert (raster.fillet(m, r) == ~raster.core(~m, r)).all()


@pytest.mark.parametrize("r", RADII)
@pytest.mark.parametrize("dw", [-1, 0, 1])
def test_staircase_steps_2r_tall_are_core(r, dw):
    m, cols = _staircase(r, 2 * r + dw)
    R = raster.core(m, r)
    assert (R <= m).all()
    for rows, c in cols:
        assert R[rows, c].all() if dw >= 0 else not R[rows, c].any(), (rows, c)
    # and the same steps as gaps between two parts of a block
    A = raster.anticore(~m, r)
    for rows, c in cols:
        assert A[rows, c].all() if dw >= 0 else not A[rows, c].any(), (rows, c)


def _dumbbell(r, w):
    """Two squares 8r wide joined by a stroke w pixels wide and 6r long."""
    a = 8 * r
    m = np.zeros((a + 4 * r, 2 * a + 6 * r + 4 * r), bool)
    m[2 * r:2 * r + a, 2 * r:2 * r + a] = True
    m[2 * r:2 * r + a, 2 * r + a + 6 * r:2 * r + 2 * a + 6 * r] = True
    y = 2 * r + a // 2 - w // 2
    m[y:y + w, 2 * r + a:2 * r + a + 6 * r] = True
    return m, (slice(y, y + w), slice(2 * r + a + r, 2 * r + a + 5 * r))


@pytest.mark.parametrize("r", RADII)
@pytest.mark.parametrize("init", ["core", "input"])
def test_tighten_keeps_a_2r_stroke_and_a_2r_gap(r, init):
    m, neck = _dumbbell(r, 2 * r)
    T = raster.tighten(m, r, init=init)
    assert T.core[neck].all() and T.mask[neck].all()
    assert ndimage.label(T.mask, structure=np.ones((3, 3), bool))[1] == 1
    # The complement: the two squares are holes of a block, the stroke a 2r gap between them.
    T = raster.tighten(~m, r, init=init)
    assert not T.fillet[neck].any() and not T.mask[neck].any()
    assert (T.core <= T.mask).all() and (T.mask <= T.fillet).all()


@pytest.mark.parametrize("r", RADII)
def test_tighten_from_the_core_drops_a_stroke_2r_minus_1_wide(r):
    m, neck = _dumbbell(r, 2 * r - 1)
    T = raster.tighten(m, r, init="core")
    assert not T.core[neck].any() and not T.mask[neck].any()
    assert ndimage.label(T.mask, structure=np.ones((3, 3), bool))[1] == 2


def _thin_ring():
    """A ring 12 px wide (0.6 r at r = 20 px) around a hole 30 px in radius (its own anticore)."""
    yy, xx = np.mgrid[:140, :140]
    d = np.hypot(yy - 69.5, xx - 69.5)
    return (d >= 30) & (d < 42)


def test_a_thin_ring_vanishes_from_the_input():
    """Issue 21: no core anywhere, so every tightening is empty, and the flow from the input must get
    there. Its inner edge rests against the hole's anticore, and the outer front sweeps the ring towards
    it; the minimum-perimeter finish sees both loops wrap the same anticore, nothing between them, and
    lets the part vanish (dually, the complement's gap closes)."""
    m = _thin_ring()
    r = 20.0
    assert not raster.core(m, r).any() and raster.anticore(m, r)[69, 69]
    T = raster.tighten(m, r, init="input")
    assert T.is_converged
    assert not T.mask.any()
    T = raster.tighten(~m, r, init="input")
    assert T.mask.all()
    # Fronts that only see themselves still keep two parts apart that must stay apart (two squares with
    # their own cores, a 3-pixel gap between them).
    two = np.zeros((60, 100), bool)
    two[10:50, 10:48] = two[10:50, 51:90] = True
    T = raster.tighten(two, 8, init="input")
    assert ndimage.label(T.mask, structure=np.ones((3, 3), bool))[1] == 2
