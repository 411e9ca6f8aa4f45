"""raster.tighten_labels: every label tightened, conflicts resolved symmetrically, none dropped silently."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import raster

R = 5


def _touching(dtype=np.uint16):
    """A big square, a smaller one against its right side, a bar across the bottom of both, and a small
    square that the radius removes: labels of different sizes with straight and jagged shared borders."""
    img = np.zeros((90, 120), dtype)
    img[8:60, 8:60] = 40
    img[18:46, 60:88] = 2                      # touches 40 along a vertical border
    img[60:75, 8:100] = 7                      # touches 40 along a horizontal border, reaches past 2
    img[61:64, 30:40] = 40                     # a tooth of 40 into 7 (a jagged shared border)
    img[20:26, 95:101] = 99                    # 6 × 6 < 2r: vanishes
    return img


def _guarantees(img, out, r):
    """The issue's guarantees, checked against each label's own core and fillet on the whole image."""
    union = img != 0
    union_core = raster.core(union, r)
    for v in np.unique(img[img != 0]):
        M = img == v
        R_, F = raster.core(M, r), raster.fillet(M, r)
        mine = out == v
        assert (mine[R_]).all(), f"label {v} lost part of its own core"
        assert not (mine & ~F).any(), f"label {v} left its own fillet"
    # Background only where no label's tightening holds a pixel and the union's core does not cover it:
    # in particular every pixel of the union's core is labelled (no gap where the input had none).
    assert (out[union_core] != 0).all()
    assert set(np.unique(out).tolist()) <= set(np.unique(img).tolist()) | {0}


def test_touching_labels_of_different_sizes():
    img = _touching()
    with pytest.warns(raster.LostLabelWarning, match=r"1 of 4 label\(s\) vanished.*: 99"):
        out, res = raster.tighten_labels(img, R, return_result=True)
    assert out.dtype == img.dtype and out.shape == img.shape
    _guarantees(img, out, R)
    assert res.lost == [99] and res.vanished == [99] and not (out == 99).any()
    # The shared borders stay where they were, away from the corners where labels meet the background.
    assert (out[20:40, 59] == 40).all() and (out[20:40, 60] == 2).all()
    assert (out[59, 15:25] == 40).all() and (out[60, 15:25] == 7).all()
    # No gap opens between touching labels: both pixels of every horizontal contact stay labelled.
    rows, cols = np.nonzero((img[:, :-1] != 0) & (img[:, 1:] != 0) & (img[:, :-1] != img[:, 1:]))
    assert (out[rows, cols] != 0).all() and (out[rows, cols + 1] != 0).all()
    # Convex outer corners are rounded as a binary tightening rounds them.
    assert out[8, 8] == 0 and out[74, 99] == 0
    assert res.conflicts + res.filled > 0            # the rule had work to do


def test_relabelling_only_renames_the_output():
    img = _touching(np.int32)
    rng = np.random.default_rng(7)
    with pytest.warns(raster.LostLabelWarning):
        out = raster.tighten_labels(img, R)
    for _ in range(3):
        values = np.unique(img[img != 0])
        new = rng.permutation(np.arange(-50, 1000))[: len(values)]
        new[new == 0] = 1001
        lut = np.zeros(img.max() + 1, np.int32)
        lut[values] = new
        relabelled = lut[img]
        with pytest.warns(raster.LostLabelWarning):
            out2 = raster.tighten_labels(relabelled, R)
        expected = lut[out]
        assert (out2 == expected).all()


def test_mirror_twins_swap_exactly():
    """Two equal squares side by side: every tie between them is broken by the input or by position, so
    swapping their values swaps the output and changes nothing else."""
    img = np.zeros((40, 61), np.uint8)
    img[8:32, 6:30], img[8:32, 30:54] = 1, 2
    out, res = raster.tighten_labels(img, R, return_result=True)
    def swap(a):
        return np.where(a == 1, 2, np.where(a == 2, 1, a)).astype(a.dtype)

    out_sw = raster.tighten_labels(swap(img), R)
    assert (swap(out_sw) == out).all()
    assert (out[8:32, 29] == 1).all() and (out[8:32, 30] == 2).all()     # the notches at the ends are filled
    assert res.filled > 0
    _guarantees(img, out, R)


def test_a_thin_label_between_thick_ones_keeps_its_pixels():
    """A one-pixel label between two squares: no neighbour's fillet reaches it, and the union's core covers
    it, so it keeps its input pixels (documented: the union has no gap there) instead of vanishing."""
    img = np.zeros((40, 61), np.uint8)
    img[8:32, 6:30], img[8:32, 31:55], img[8:32, 30] = 1, 2, 3
    out, res = raster.tighten_labels(img, R, return_result=True)
    assert res.vanished == [3] and res.lost == []
    assert (out[8:32, 30] == 3).all()
    _guarantees(img, out, R)


def test_crops_give_the_whole_images_flow():
    img = np.zeros((100, 140), np.uint8)
    yy, xx = np.mgrid[:100, :140]
    img[np.hypot(yy - 50, xx - 70) < 30] = 5
    img[45:55, 95:125] = 5                      # a bar that goes
    out = raster.tighten_labels(img, 6)
    full = raster.tighten(img == 5, 6).mask
    assert ((out == 5) == full).all()


def test_a_label_that_fills_the_image_and_an_empty_one():
    full = np.full((12, 12), 3, np.uint8)
    assert (raster.tighten_labels(full, 2) == full).all()
    with pytest.warns(raster.EmptyMaskWarning, match="no label"):
        assert not raster.tighten_labels(np.zeros((5, 5), np.int16), 2).any()
    with pytest.warns(raster.LostLabelWarning), pytest.warns(raster.EmptyMaskWarning, match="empty"):
        raster.tighten_labels(_touching(), 60)


def test_dtypes_and_bad_input():
    img = _touching(np.int64) - 20 * (_touching() == 2)      # a negative label, -18, in an int64 image
    img = np.where(img == 99, 0, img)
    out = raster.tighten_labels(img, R)
    assert out.dtype == np.int64 and (out == -18).any()
    as_float = _touching(np.float32)
    with pytest.warns(raster.LostLabelWarning):
        assert (raster.tighten_labels(as_float, R) == raster.tighten_labels(_touching(), R)).all()
    with pytest.raises(ValueError, match="fractional"):
        raster.tighten_labels(as_float + 0.5, R)
    with pytest.raises(ValueError, match="2-D label image.*--stack"):
        raster.tighten_labels(np.zeros((3, 9, 9), np.uint8), R)
    with pytest.raises(ValueError, match="r must be"):
        raster.tighten_labels(_touching(), -1)


@st.composite
def _label_images(draw):
    """A few rectangles and disks, painted in order (later over earlier), with random labels."""
    h, w = 48, 64
    img = np.zeros((h, w), np.int32)
    yy, xx = np.mgrid[:h, :w]
    for _ in range(draw(st.integers(2, 5))):
        v = draw(st.integers(1, 9))
        y, x = draw(st.integers(0, h - 1)), draw(st.integers(0, w - 1))
        if draw(st.booleans()):
            img[max(0, y - draw(st.integers(3, 14))):y + draw(st.integers(3, 14)),
                max(0, x - draw(st.integers(3, 14))):x + draw(st.integers(3, 14))] = v
        else:
            img[np.hypot(yy - y, xx - x) < draw(st.integers(4, 16))] = v
    return img


@settings(max_examples=15)
@given(_label_images(), st.sampled_from([2.5, 4.0]))
def test_guarantees_on_random_label_images(img, r):
    with np.errstate(all="ignore"):
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", raster.MaskWarning)
            out, res = raster.tighten_labels(img, r, return_result=True)
    _guarantees(img, out, r)
    assert sorted(res.lost) == sorted(v for v in np.unique(img[img != 0]) if not (out == v).any())
