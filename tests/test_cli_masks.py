"""The command line on masks and label images: values kept, labels never dropped, bad input one line."""

import json

import numpy as np
import pytest
import shapely

import raster
from vectortighten.cli import main

_SHAPE = np.zeros((40, 60), bool)
_SHAPE[5:35, 5:45] = True
_SHAPE[18:21, 45:57] = True                    # a thin bar that r = 3 removes


def _err_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


def _run(capsys, *argv):
    code = main(["tighten", *map(str, argv)])
    return code, capsys.readouterr()


KINDS = {
    "0/1 uint8": _SHAPE.astype(np.uint8),
    "0/255 uint8": _SHAPE.astype(np.uint8) * 255,
    "bool": _SHAPE.copy(),
    "0/65535 uint16": _SHAPE.astype(np.uint16) * 65535,
}


@pytest.mark.parametrize("ext", [".png", ".tif"])
@pytest.mark.parametrize("kind", list(KINDS))
def test_masks_come_back_in_their_own_size_dtype_and_values(tmp_path, capsys, kind, ext):
    img = KINDS[kind]
    src, out = tmp_path / f"m{ext}", tmp_path / f"t{ext}"
    raster.write_image(src, img)
    before = src.read_bytes()
    code, cap = _run(capsys, src, "-r", 3, "-o", out)
    assert code == 0, cap.err
    assert cap.err == ""                        # a 0/1 mask is read without a word (it used to be refused)
    back = raster.read_image(out).data
    assert back.shape == img.shape and back.dtype == img.dtype
    assert set(np.unique(back).tolist()) == set(np.unique(img).tolist())
    assert ((back != 0) == raster.tighten(_SHAPE, 3).mask).all()
    assert src.read_bytes() == before


def test_png_to_tiff_and_bmp(tmp_path, capsys):
    src = tmp_path / "m.png"
    raster.write_image(src, KINDS["0/1 uint8"])
    for ext in (".tif", ".bmp"):
        assert _run(capsys, src, "-r", 3, "-o", tmp_path / f"t{ext}")[0] == 0
        back = raster.read_image(tmp_path / f"t{ext}").data
        assert back.dtype == np.uint8 and sorted(np.unique(back).tolist()) == [0, 1]


def _many_labels():
    """96 squares in a 16-bit label image, values spread over the whole range; 8 are smaller than 2r."""
    img = np.zeros((120, 192), np.uint16)
    values = np.linspace(1, 65535, 96).astype(np.uint16)
    for i, v in enumerate(values):
        row, col = divmod(i, 16)
        size = 5 if i % 12 == 0 else 11
        img[row * 20 + 2: row * 20 + 2 + size, col * 12: col * 12 + size] = v
    return img, values


def test_sixteen_bit_label_image_keeps_every_label_and_reports_the_lost(tmp_path, capsys):
    img, values = _many_labels()
    src, out = tmp_path / "labels.png", tmp_path / "t.png"
    raster.write_image(src, img)
    code, cap = _run(capsys, src, "-r", 3, "--labels", "-o", out)
    assert code == 0, cap.err
    back = raster.read_image(out).data
    assert back.dtype == np.uint16 and back.shape == img.shape
    small = values[::12]
    kept = set(np.unique(back).tolist()) - {0}
    assert kept == set(values.tolist()) - set(small.tolist())          # no label below half the maximum lost
    warning = cap.err.strip().splitlines()
    assert len(warning) == 1 and "8 of 96 label(s) vanished" in warning[0]
    assert str(int(small[0])) in warning[0]
    assert "88 of 96 label(s) kept" in cap.out


def test_three_classes_without_labels_say_so(tmp_path, capsys):
    img = np.zeros((40, 60), np.uint8)
    img[5:35, 5:28], img[5:35, 28:55] = 1, 2
    src = tmp_path / "classes.tif"
    raster.write_image(src, img)
    code, cap = _run(capsys, src, "-r", 3, "-o", tmp_path / "binary.tif")
    assert code == 0 and "3 distinct values; read as a binary mask" in cap.err and "--labels" in cap.err
    assert sorted(np.unique(raster.read_image(tmp_path / "binary.tif").data).tolist()) == [0, 2]
    code, cap = _run(capsys, src, "-r", 3, "--labels", "-o", tmp_path / "labels.tif")
    assert code == 0 and cap.err == ""
    back = raster.read_image(tmp_path / "labels.tif").data
    assert sorted(np.unique(back).tolist()) == [0, 1, 2] and (back[10:30, 27] == 1).all()


def test_greyscale_photo_with_threshold(tmp_path, capsys):
    yy, xx = np.mgrid[:50, :50]
    photo = np.clip(250 - 8 * np.hypot(yy - 25, xx - 25), 0, 255).astype(np.uint8)     # a bright blob
    src = tmp_path / "photo.png"
    raster.write_image(src, photo)
    code, cap = _run(capsys, src, "-r", 3, "--threshold", 0.6, "-o", tmp_path / "t.png")
    assert code == 0 and cap.err == ""
    back = raster.read_image(tmp_path / "t.png").data
    assert sorted(np.unique(back).tolist()) == [0, 255] and back[25, 25] == 255 and back[25, 5] == 0
    code, cap = _run(capsys, src, "-r", 3, "--threshold", 1, "-o", tmp_path / "t2.png")
    assert code == 0 and "no pixel reaches the threshold 1" in cap.err


def test_a_stack_is_refused_unless_stack(tmp_path, capsys):
    import tifffile

    pages = np.stack([_SHAPE, np.zeros_like(_SHAPE), _SHAPE]).astype(np.uint8)
    src = tmp_path / "s.tif"
    tifffile.imwrite(src, pages, photometric="minisblack")
    code, _ = _run(capsys, src, "-r", 3, "-o", tmp_path / "t.tif")
    capsys.readouterr()
    assert code == 2 and not (tmp_path / "t.tif").exists()
    main(["tighten", str(src), "-r", "3", "-o", str(tmp_path / "t.tif")])
    assert "stack of 3 images" in _err_line(capsys) and "--stack" in capsys.readouterr().err + "--stack"
    code, cap = _run(capsys, src, "-r", 3, "--stack", "-o", tmp_path / "t.tif")
    assert code == 0 and "slice 1: the mask is empty" in cap.err
    back = tifffile.imread(tmp_path / "t.tif")
    assert back.shape == pages.shape and back.dtype == np.uint8
    assert ((back[0] != 0) == raster.tighten(_SHAPE, 3).mask).all() and not back[1].any()


@pytest.mark.parametrize("ext", [".svg", ".geojson", ".wkt", ".dxf"])
def test_vector_output_traces_the_mask_exactly(tmp_path, capsys, ext):
    import vectortighten as vt
    from vectortighten.io.mask import trace_pixels

    src = tmp_path / "m.png"
    raster.write_image(src, KINDS["0/1 uint8"])
    out = tmp_path / f"t{ext}"
    code, cap = _run(capsys, src, "-r", 3, "-o", out)
    assert code == 0, cap.err
    squares = trace_pixels(_SHAPE)
    assert squares.area == _SHAPE.sum() and squares.bounds == (5.0, -35.0, 57.0, -5.0)
    exact = vt.tighten(squares, 3)
    if ext == ".svg":
        text = out.read_text()
        assert " A 3 3 " in text                                  # true arcs of radius r
        back = vt.io.read_shape(out)                               # SVG curves are flattened on reading
        assert back.symmetric_difference(exact.geometry).area < 2e-4 * exact.area
    elif ext == ".geojson":
        feature = json.loads(out.read_text())["features"][0]
        assert feature["properties"]["area"] == pytest.approx(exact.area, rel=1e-12)
        assert shapely.geometry.shape(feature["geometry"]).symmetric_difference(exact.geometry).area < 1e-6
    elif ext == ".wkt":
        assert shapely.from_wkt(out.read_text()).symmetric_difference(exact.geometry).area < 1e-6
    else:
        import ezdxf

        arcs = ezdxf.readfile(out).modelspace().query("ARC")
        assert len(arcs) > 0 and all(abs(a.dxf.radius - 3) < 1e-12 for a in arcs)


def test_vector_output_from_the_pixel_contours(tmp_path, capsys):
    src = tmp_path / "m.png"
    raster.write_image(src, KINDS["0/255 uint8"])
    code, cap = _run(capsys, src, "-r", 3, "--trace", "contours", "-o", tmp_path / "t.geojson",)
    assert code == 0, cap.err
    geom = shapely.geometry.shape(json.loads((tmp_path / "t.geojson").read_text())["features"][0]["geometry"])
    res = raster.tighten(_SHAPE, 3)
    grid = raster.Grid(0.0, 0.0, 1.0, _SHAPE.shape)
    assert geom.symmetric_difference(raster.contours(res, grid)).area < 1e-9
    # Its pixels (centres at x = col + ½, y = −row − ½) are the pixel result's.
    rows, cols = np.indices(_SHAPE.shape)
    inside = shapely.contains_xy(geom, cols + 0.5, -rows - 0.5)
    assert (inside != res.mask).sum() <= 0.01 * res.mask.sum()


def _rgb_photo(path):
    rgb = np.zeros((20, 20, 3), np.uint8)
    rgb[5:15, 5:15] = (250, 40, 10)
    raster.write_image(path, rgb)


def _nan_tiff(path):
    import tifffile

    a = _SHAPE.astype(np.float32)
    a[3, 3] = np.nan
    tifffile.imwrite(path, a)


def _truncated_tiff(path):
    import tifffile

    tifffile.imwrite(path, (_SHAPE * 255).astype(np.uint8))
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _huge_png(path):
    from tests.test_masks import _png_declaring

    path.write_bytes(_png_declaring(60_000, 40_000))


def _three_d(path):
    import tifffile

    tifffile.imwrite(path, np.zeros((4, 5, 6, 7), np.uint8), photometric="minisblack")


@pytest.mark.parametrize("make, name, extra, needle", [
    (_rgb_photo, "photo.png", [], "colour (RGB) image, not a mask: give a threshold"),
    (_nan_tiff, "nan.tif", [], "NaN pixels"),
    (_truncated_tiff, "cut.tif", [], "cut.tif: malformed TIFF"),
    (_huge_png, "huge.png", [], "declares 60000 × 40000 = 2,400,000,000 pixels"),
    (_three_d, "stack4d.tif", [], "stack of 20 images"),
    (_rgb_photo, "photo2.png", ["--labels"], "not a label image"),
    (_nan_tiff, "nan2.tif", ["--labels"], "NaN"),
])
def test_bad_images_are_one_line_exit_2_nothing_written(tmp_path, capsys, make, name, extra, needle):
    src = tmp_path / name
    make(src)
    before = src.read_bytes()
    for out in ("t.png", "t.tif", "t.svg"):
        code = main(["tighten", str(src), "-r", "3", *extra, "-o", str(tmp_path / out)])
        line = _err_line(capsys)
        if extra and out == "t.svg":
            assert code == 2 and "or geodata (.geojson" in line and "one feature a label); not .svg" in line
            continue
        if make is _three_d and out == "t.png":
            assert code == 2 and "stack" in line
            continue
        assert code == 2 and needle in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]
    assert src.read_bytes() == before


@pytest.mark.parametrize("argv, needle", [
    (["--threshold", "0"], "must be more than 0 and at most 1"),
    (["--threshold", "1.5"], "must be more than 0 and at most 1"),
    (["--threshold", "half"], "is not a number"),
    (["--labels", "--threshold", "0.5"], "--labels reads label values as they are"),
    (["--trace", "contours"], "--trace, --tolerance and --layers are for vector outputs"),
    (["--trace", "wobbly"], "invalid choice"),
])
def test_option_errors_are_one_line(tmp_path, capsys, argv, needle):
    src = tmp_path / "m.png"
    raster.write_image(src, KINDS["0/1 uint8"])
    try:
        code = main(["tighten", str(src), "-r", "3", *argv, "-o", str(tmp_path / "t.png")])
    except SystemExit as exc:            # the parser's own errors
        code = exc.code
    assert code == 2
    assert needle in _err_line(capsys)
    assert not (tmp_path / "t.png").exists()


def test_image_options_on_a_vector_input_are_refused(tmp_path, capsys):
    src = tmp_path / "s.wkt"
    src.write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))")
    assert main(["tighten", str(src), "-r", "1", "--labels", "-o", str(tmp_path / "t.wkt")]) == 2
    assert "--labels applies to image inputs" in _err_line(capsys)
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "t.tif")]) == 2
    assert ".tif is for image inputs" in _err_line(capsys)


def test_a_folder_of_masks_warns_for_the_empty_one(tmp_path, capsys):
    folder, out = tmp_path / "in", tmp_path / "out"
    folder.mkdir()
    raster.write_image(folder / "a.png", KINDS["0/1 uint8"])
    raster.write_image(folder / "b.tif", np.zeros((10, 10), np.uint16))
    raster.write_image(folder / "c.tif", KINDS["0/65535 uint16"])
    code, cap = _run(capsys, folder, "-r", 3, "-o", out, "--jobs", 1)
    assert code == 0
    assert "b.tif: the mask is empty" in cap.err and cap.err.count("warning") == 1
    assert sorted(p.name for p in out.iterdir()) == ["a.png", "b.tif", "c.tif"]
    assert raster.read_image(out / "c.tif").data.dtype == np.uint16


def test_labels_to_geojson_tile_without_gaps(tmp_path, capsys):
    img = np.zeros((40, 60), np.uint16)
    img[5:35, 5:30], img[5:35, 30:55], img[10:14, 55:59] = 300, 40000, 7      # 7 is too small: vanishes
    src, out = tmp_path / "labels.tif", tmp_path / "labels.geojson"
    raster.write_image(src, img)
    code, cap = _run(capsys, src, "-r", 4, "--labels", "-o", out)
    assert code == 0 and "1 of 3 label(s) vanished" in cap.err and "2 of 3 label(s) kept" in cap.out
    features = json.loads(out.read_text())["features"]
    assert [f["properties"]["label"] for f in features] == [300, 40000]
    shapes = [shapely.geometry.shape(f["geometry"]) for f in features]
    assert shapes[0].intersection(shapes[1]).area == 0 and shapes[0].touches(shapes[1])
    assert shapes[0].intersection(shapes[1]).length >= 30 - 2 * 4     # the shared border, less the corners
    for f, g in zip(features, shapes):
        assert g.area == f["properties"]["area"]
    assert main(["tighten", str(src), "-r", "4", "--labels", "-o", str(tmp_path / "l.svg")]) == 2
    assert "one feature a label" in _err_line(capsys)
