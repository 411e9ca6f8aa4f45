"""Masks as image people have them: values read the way image libraries do, files round-tripped exactly."""

import os
import warnings
import zlib

import numpy as np
import pytest

import raster
from raster import io as rio

# A shape with a thin bar (r = 3 removes it) and a sharp corner, in pixels.
_SHAPE = np.zeros((40, 60), bool)
_SHAPE[5:35, 5:45] = True
_SHAPE[18:21, 45:57] = True


def _kind(name):
    """A mask of each kind people have, with the value(s) it holds inside."""
    m = _SHAPE
    if name == "bool":
        return m.copy()
    if name == "0/1 uint8":
        return m.astype(np.uint8)
    if name == "0/255 uint8":
        return m.astype(np.uint8) * 255
    if name == "0/65535 uint16":
        return m.astype(np.uint16) * 65535
    if name == "0/1 float32":
        return m.astype(np.float32)
    if name == "0/7 int32":
        return m.astype(np.int32) * 7
    raise KeyError(name)


KINDS = ["bool", "0/1 uint8", "0/255 uint8", "0/65535 uint16", "0/1 float32", "0/7 int32"]
# Which formats hold which kinds (PNG: bool, 8 and 16 bits; BMP: bool and 8 bits; TIFF: all).
HOLDS = {".png": {"bool", "0/1 uint8", "0/255 uint8", "0/65535 uint16"},
         ".bmp": {"bool", "0/1 uint8", "0/255 uint8"},
         ".tif": set(KINDS)}
CASES = [(k, ext) for ext in HOLDS for k in KINDS if k in HOLDS[ext]]


# ---------------------------------------------------------------------------------------------------------
# binarize: non-zero is inside, thresholds as a share of the full scale
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", KINDS)
def test_nonzero_is_inside_and_values_come_back(kind):
    img = _kind(kind)
    mask, values = raster.binarize(img)
    assert (mask == _SHAPE).all()
    back = values.encode(mask)
    assert back.dtype == img.dtype and back.shape == img.shape and (back == img).all()
    assert values.inside == img.max()


def test_threshold_is_a_share_of_the_full_scale():
    grey16 = np.array([[0, 30000, 40000, 65535]], np.uint16)
    m, v = raster.binarize(grey16, threshold=0.5)
    assert m.tolist() == [[False, False, True, True]] and v.inside == 65535 and v.dtype == np.uint16
    grey8 = np.array([[0, 127, 128, 255]], np.uint8)
    assert raster.binarize(grey8, threshold=0.5)[0].tolist() == [[False, False, True, True]]
    probs = np.array([[0.1, 0.5, 0.9]], np.float32)
    m, v = raster.binarize(probs, threshold=0.5)
    assert m.tolist() == [[False, True, True]] and v.inside == 1.0 and v.dtype == np.float32
    for bad in (0, -0.1, 1.5, float("nan")):
        with pytest.raises(ValueError, match="threshold must be in"):
            raster.binarize(grey8, threshold=bad)


def test_invert_keeps_the_files_own_two_values():
    img = np.where(_SHAPE, 0, 255).astype(np.uint8)       # a dark shape on white
    mask, values = raster.binarize(img, invert=True)
    assert (mask == _SHAPE).all()
    assert (values.encode(mask) == img).all()


def test_more_than_two_integer_values_are_read_as_binary_with_a_warning():
    classes = np.zeros((10, 10), np.uint8)
    classes[2:5, 2:5], classes[6:9, 6:9] = 1, 2               # a 3-class 0/1/2 image
    with pytest.warns(raster.ManyValuesWarning, match="3 distinct values.*--labels"):
        mask, values = raster.binarize(classes)
    assert mask.sum() == 18 and values.inside == 2
    with pytest.raises(ValueError, match="float image with 2 non-zero values"):
        raster.binarize(classes.astype(np.float32))


def test_colour_needs_a_threshold_unless_its_channels_are_equal():
    rgb = np.zeros((8, 8, 3), np.uint8)
    rgb[2:6, 2:6] = (200, 30, 30)
    with pytest.raises(ValueError, match=r"colour \(RGB\) image.*threshold"):
        raster.binarize(rgb)
    m, _ = raster.binarize(rgb, threshold=0.2)                 # luminance 0.299·200 + … = 80.8 / 255 ≥ 0.2
    assert m.sum() == 16
    grey_as_rgb = np.repeat((_SHAPE * 255).astype(np.uint8)[:, :, None], 3, axis=2)
    m, values = raster.binarize(grey_as_rgb)
    assert (m == _SHAPE).all() and (values.encode(m) == grey_as_rgb).all()
    rgba = np.concatenate([grey_as_rgb, np.full(_SHAPE.shape + (1,), 255, np.uint8)], axis=2)
    m, values = raster.binarize(rgba)
    assert (values.encode(m) == rgba).all()


def test_transparency_is_laid_on_white():
    rgba = np.zeros((6, 6, 4), np.uint8)                       # black ink, opaque in the middle
    rgba[2:4, 2:4, 3] = 255
    m, _ = raster.binarize(rgba, threshold=0.5, invert=True)
    assert m.sum() == 4 and m[2:4, 2:4].all()


def test_bad_values_are_refused_naming_the_problem():
    nan = _SHAPE.astype(np.float32)
    nan[3, 3] = np.nan
    with pytest.raises(ValueError, match="NaN pixels"):
        raster.binarize(nan)
    with pytest.raises(ValueError, match="3-D stack"):
        raster.binarize(np.zeros((5, 10, 10), np.uint8))
    with pytest.raises(ValueError, match="numbers or booleans"):
        raster.binarize(np.zeros((4, 4), complex))


# ---------------------------------------------------------------------------------------------------------
# tighten_mask: scikit-image conventions
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", KINDS)
def test_tighten_mask_returns_the_images_shape_dtype_and_values(kind):
    img = _kind(kind)
    before = img.copy()
    out, res = raster.tighten_mask(img, 3, return_result=True)
    assert (img == before).all()                              # the input is not modified
    assert out.shape == img.shape and out.dtype == img.dtype
    assert set(np.unique(out).tolist()) <= set(np.unique(img).tolist())
    assert ((out != 0) == res.mask).all()
    assert ((out != 0) == raster.tighten(_SHAPE, 3).mask).all()
    assert not res.mask[19, 52] and res.mask[20, 20]           # the bar is gone, the body stays


def test_tighten_mask_warns_on_empty_input_and_empty_result():
    with pytest.warns(raster.EmptyMaskWarning, match="the mask is empty"):
        out = raster.tighten_mask(np.zeros((10, 10), np.uint8), 3)
    assert not out.any() and out.dtype == np.uint8
    with pytest.warns(raster.EmptyMaskWarning, match="tightening is empty"):
        out = raster.tighten_mask(_SHAPE, 40)
    assert not out.any()
    with pytest.warns(raster.EmptyMaskWarning, match="no pixel reaches the threshold 0.9"):
        raster.tighten_mask(np.full((5, 5), 100, np.uint8), 3, threshold=0.9)


# ---------------------------------------------------------------------------------------------------------
# Files: same size, dtype and values back
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("kind, ext", CASES)
def test_files_round_trip_exactly(tmp_path, kind, ext):
    img = _kind(kind)
    path = tmp_path / f"m{ext}"
    raster.write_image(path, img)
    back = raster.read_image(path)
    assert back.data.dtype == img.dtype and back.data.shape == img.shape and (back.data == img).all()
    assert not back.stack
    mask = raster.load_mask(path)
    assert (mask == _SHAPE).all()


def test_sixteen_bit_labels_round_trip_in_png_and_tiff(tmp_path):
    labels = np.zeros((30, 40), np.uint16)
    for i, v in enumerate((1, 300, 40000, 65535)):
        labels[5:25, 2 + 9 * i: 9 + 9 * i] = v
    for ext in (".png", ".tif"):
        raster.write_image(tmp_path / f"l{ext}", labels)
        back = raster.read_image(tmp_path / f"l{ext}").data
        assert back.dtype == np.uint16 and (back == labels).all()
    big = labels.astype(np.int32) * 3
    with pytest.raises(ValueError, match="write it as .tif"):
        raster.write_image(tmp_path / "l.png", big)
    assert not (tmp_path / "l.png").read_bytes() == b""        # the earlier PNG is untouched
    raster.write_image(tmp_path / "big.tif", big)
    assert (raster.read_image(tmp_path / "big.tif").data == big).all()


def test_palette_png_keeps_indices_and_palette(tmp_path):
    from PIL import Image

    idx = np.zeros((10, 12), np.uint8)
    idx[2:8, 2:6], idx[2:8, 6:10] = 1, 15                      # PASCAL VOC style class indices
    im = Image.fromarray(idx, mode="P")
    palette = [0, 0, 0, 128, 0, 0] + [7] * (3 * 13) + [0, 128, 128] + [0] * (768 - 48)
    im.putpalette(palette)
    im.save(tmp_path / "voc.png")
    img = raster.read_image(tmp_path / "voc.png")
    assert (img.data == idx).all() and img.palette[:6] == (0, 0, 0, 128, 0, 0)
    raster.write_image(tmp_path / "out.png", img.data, like=img)
    with Image.open(tmp_path / "out.png") as out:
        assert out.mode == "P" and out.getpalette()[:6] == [0, 0, 0, 128, 0, 0]
        assert out.getpalette()[45:48] == [0, 128, 128] and (np.asarray(out) == idx).all()


def test_tiff_keeps_photometric_compression_and_resolution(tmp_path):
    import tifffile

    scan = np.zeros((20, 30), bool)
    scan[4:16, 5:25] = True
    src = tmp_path / "fax.tif"
    tifffile.imwrite(src, scan, photometric="miniswhite", compression="zlib", resolution=(300, 300),
                     resolutionunit="INCH")
    img = raster.read_image(src)
    assert img.photometric == "miniswhite" and img.compressed and img.resolution == (300.0, 300.0, "inch")
    raster.write_image(tmp_path / "out.tif", ~scan, like=img)
    with tifffile.TiffFile(tmp_path / "out.tif") as t:
        page = t.pages[0]
        assert page.photometric.name == "MINISWHITE" and int(page.compression) != 1
        assert page.resolution == (300.0, 300.0) and page.dtype == bool
        assert (page.asarray() == ~scan).all()


def test_lzw_tiff_is_read_through_pillow_without_imagecodecs(tmp_path):
    from PIL import Image

    labels = (np.arange(40 * 50).reshape(40, 50) % 5).astype(np.uint16) * 1000
    Image.fromarray(labels).save(tmp_path / "lzw.tif", compression="tiff_lzw")
    img = raster.read_image(tmp_path / "lzw.tif")
    assert img.data.dtype == np.uint16 and (img.data == labels).all()


def test_stacks_are_read_as_stacks(tmp_path):
    import tifffile

    pages = np.stack([_SHAPE, np.zeros_like(_SHAPE), _SHAPE[::-1]]).astype(np.uint8)
    tifffile.imwrite(tmp_path / "s.tif", pages, photometric="minisblack")
    img = raster.read_image(tmp_path / "s.tif")
    assert img.stack and img.data.shape == (3, 40, 60) and len(img.slices) == 3
    with pytest.raises(ValueError, match="stack of 3 images"):
        raster.load_mask(tmp_path / "s.tif")
    raster.write_image(tmp_path / "s2.tif", img.data, like=img)
    assert (tifffile.imread(tmp_path / "s2.tif") == pages).all()
    with pytest.raises(ValueError, match="written as .tif"):
        raster.write_image(tmp_path / "s.png", img.data, like=img)


def test_real_masks_shipped_by_scikit_image():
    """scikit-image ships a binary silhouette (horse.png, RGBA) and a two-page TIFF; read as it reads them."""
    skdata = pytest.importorskip("skimage.data")
    folder = os.path.dirname(skdata.__file__)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # scikit-image's own deprecations, not ours
        horse = skdata.horse()
    assert (raster.load_mask(os.path.join(folder, "horse.png"), threshold=0.5) == horse).all()
    with pytest.raises(ValueError, match="colour with transparency"):
        raster.load_mask(os.path.join(folder, "horse.png"))
    img = raster.read_image(os.path.join(folder, "multipage.tif"))
    assert img.stack and img.data.shape == (2, 15, 10) and img.data.dtype == np.uint8


# ---------------------------------------------------------------------------------------------------------
# Bad files: one clear ValueError, nothing written
# ---------------------------------------------------------------------------------------------------------
def _png_declaring(width, height):
    """A tiny valid PNG whose header is then made to declare another size (with a correct CRC)."""
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.zeros((2, 2), np.uint8)).save(buf, format="PNG")
    data = bytearray(buf.getvalue())
    data[16:24] = width.to_bytes(4, "big") + height.to_bytes(4, "big")
    data[29:33] = zlib.crc32(bytes(data[12:29])).to_bytes(4, "big")
    return bytes(data)


def test_declared_size_above_the_limit_is_refused_before_decoding(tmp_path):
    (tmp_path / "huge.png").write_bytes(_png_declaring(100_000, 100_000))
    with pytest.raises(ValueError, match=r"declares 100000 × 100000 = 10,000,000,000 pixels.*limit"):
        raster.read_image(tmp_path / "huge.png")
    with pytest.raises(ValueError, match="limit of 3"):
        raster.read_image(tmp_path / "huge.png", max_pixels=3)
    import tifffile

    tifffile.imwrite(tmp_path / "s.tif", np.zeros((4, 5, 6), np.uint8), photometric="minisblack")
    with pytest.raises(ValueError, match=r"declares 4 × 5 × 6 = 120 pixels, more than the limit of 100"):
        raster.read_image(tmp_path / "s.tif", max_pixels=100)


def test_truncated_and_malformed_files(tmp_path):
    import tifffile

    tifffile.imwrite(tmp_path / "t.tif", (np.arange(200 * 200).reshape(200, 200) % 251).astype(np.uint8))
    whole = (tmp_path / "t.tif").read_bytes()
    for cut in (len(whole) - 100, len(whole) // 2, 20, 7):
        (tmp_path / "cut.tif").write_bytes(whole[:cut])
        with pytest.raises(ValueError, match="cut.tif: malformed TIFF"):
            raster.read_image(tmp_path / "cut.tif")
    raster.write_image(tmp_path / "m.png", _SHAPE.astype(np.uint8))
    png = (tmp_path / "m.png").read_bytes()
    (tmp_path / "cut.png").write_bytes(png[: len(png) - 30])
    with pytest.raises(ValueError, match="cut.png: malformed PNG"):
        raster.read_image(tmp_path / "cut.png")
    (tmp_path / "junk.bmp").write_bytes(b"BM not a bitmap")
    with pytest.raises(ValueError, match="junk.bmp"):
        raster.read_image(tmp_path / "junk.bmp")
    with pytest.raises(ValueError, match="unsupported image format"):
        raster.read_image(tmp_path / "m.webp")


def test_a_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(ValueError, match="BMP holds"):
        raster.write_image(tmp_path / "x.bmp", np.zeros((4, 4), np.uint16))
    with pytest.raises(FileNotFoundError):
        raster.write_image(tmp_path / "no" / "x.png", np.zeros((4, 4), np.uint8))
    assert list(tmp_path.iterdir()) == []
    assert rio.IMAGE_WRITE_EXTENSIONS == (".png", ".tif", ".tiff", ".bmp")


@pytest.mark.parametrize("ext", [".png", ".tif", ".bmp"])
def test_written_images_are_not_private(tmp_path, ext):
    """The atomic writer's temporary file is private; the image it becomes has the usual mode."""
    out = tmp_path / f"m{ext}"
    rio.write_image(out, _kind("0/255 uint8"))
    umask = os.umask(0o022)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask
    os.chmod(out, 0o640)
    rio.write_image(out, _kind("0/1 uint8"))                  # an existing file keeps its own mode
    assert out.stat().st_mode & 0o777 == 0o640
