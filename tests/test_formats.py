"""One table of formats across the families: what a reader hands to the writer, and which option goes where.

The CAD, mask and geodata paths were built side by side; these tests hold them together: every reader's
``meta`` speaks one vocabulary (a GeoPackage's CRS reaches a GeoPackage output and its unit a DXF one),
every option a format declares is refused by the others (in the API and on the command line), and a
batch of mixed inputs sends each file down its own path.
"""

import numpy as np
import pytest
import shapely
from shapely.geometry import box

gpd = pytest.importorskip("geopandas")
pyogrio = pytest.importorskip("pyogrio")
ezdxf = pytest.importorskip("ezdxf")

import raster  # noqa: E402
import vectortighten as vt  # noqa: E402
from vectortighten import io  # noqa: E402
from vectortighten.cli import main  # noqa: E402
from vectortighten.io.mask import trace_pixels  # noqa: E402


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


def plate_and_hole():
    """A 30 × 20 m plate with a 10 × 10 m hole, far from the origin (UTM coordinates)."""
    return box(500_000, 5_700_000, 500_030, 5_700_020).difference(
        box(500_010, 5_700_005, 500_020, 5_700_015))


def layer(path, crs="EPSG:25832", name="parcels"):
    shed = box(500_040, 5_700_000, 500_052, 5_700_012)
    frame = gpd.GeoDataFrame({"pid": [7, 8], "use": ["yard", "barn"]}, geometry=[plate_and_hole(), shed],
                             crs=crs)
    frame.to_file(path, layer=name)
    return path


# ---------------------------------------------------------------------------------------------------------
# The table: options declared per format, refused elsewhere
# ---------------------------------------------------------------------------------------------------------
def test_every_read_option_is_refused_by_the_formats_that_do_not_declare_it(tmp_path):
    src = tmp_path / "s.wkt"
    src.write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))")
    declared = {k for f in io.FORMATS.values() if f.kind == "vector" for k in f.read_options}
    assert {"layers", "gap", "nesting", "layer", "crs"} <= declared
    for key in sorted(declared):
        owners = [f.title for f in io.FORMATS.values() if key in f.read_options]
        with pytest.raises(ValueError, match=f"{key} is an option of {owners[0]}"):
            io.read_source(src, **{key: "x"})
    with pytest.raises(TypeError, match="unknown input option 'colour'"):
        io.read_source(src, colour="red")
    # Images declare theirs too, and the vector readers do not take them.
    assert all(f.read_options == io.mask.MASK_READ_OPTIONS for f in io.FORMATS.values() if f.kind == "mask")
    with pytest.raises(ValueError, match="threshold is an option of PNG and TIFF"):
        io.read_source(src, threshold=0.5)


def test_a_bare_geojson_geometry_takes_no_layer_options(tmp_path, capsys):
    plain = tmp_path / "plain.geojson"
    plain.write_text('{"type": "Polygon", "coordinates": [[[0, 0], [9, 0], [9, 9], [0, 9], [0, 0]]]}')
    assert io.read_source(plain).shape.area == 81
    with pytest.raises(ValueError, match="bare GeoJSON geometry, not a layer of features: layer"):
        io.read_source(plain, layer="x")
    out = tmp_path / "o.wkt"
    assert main(["tighten", str(plain), "-r", "1", "-o", str(out), "--layer", "x"]) == 2
    assert "--layer applies to DXF input and geodata layers" in one_error_line(capsys)
    assert main(["tighten", str(plain), "-r", "1", "-o", str(out), "--crs", "EPSG:25832"]) == 2
    assert "--crs applies to geodata layers" in one_error_line(capsys) and not out.exists()


# ---------------------------------------------------------------------------------------------------------
# One meta, from every reader to every writer
# ---------------------------------------------------------------------------------------------------------
def test_a_layer_read_as_one_shape_carries_its_crs_and_unit_to_every_writer(tmp_path):
    src = io.read_source(layer(tmp_path / "p.gpkg"))
    assert src.crs.to_epsg() == 25832 and src.units == "m" and src.meta["layer"] == "parcels"
    assert src.shape.area == pytest.approx(600 - 100 + 144)             # the two features, united
    T = vt.tighten(src.shape, 2.0)
    io.write_result(T, tmp_path / "t.gpkg", meta=src.meta)
    back = gpd.read_file(tmp_path / "t.gpkg")
    assert back.crs.to_epsg() == 25832 and len(back) == 1
    assert back["area"].iloc[0] == pytest.approx(T.area, rel=1e-12)
    assert [str(n) for n in pyogrio.list_layers(tmp_path / "t.gpkg")[:, 0]] == ["parcels"]
    io.write_result(T, tmp_path / "t.dxf", meta=src.meta)
    doc = ezdxf.readfile(tmp_path / "t.dxf")
    assert doc.header["$INSUNITS"] == 6                                  # metres, at the layer's coordinates
    arcs = doc.modelspace().query("ARC")
    assert arcs and all(a.dxf.radius == pytest.approx(2.0, abs=1e-12) for a in arcs)
    centres = np.array([(a.dxf.center.x, a.dxf.center.y) for a in arcs])
    x0, y0, x1, y1 = T.geometry.bounds
    assert (centres[:, 0] > x0).all() and (centres[:, 0] < x1).all() and (centres[:, 1] > y0).all()
    # A shape of no CRS (DXF, WKT) gives a geodata output of no CRS.
    io.write_result(vt.tighten(box(0, 0, 9, 9), 1.0), tmp_path / "n.gpkg", meta={"units": "mm"})
    assert gpd.read_file(tmp_path / "n.gpkg").crs is None


def test_a_layer_in_us_feet_gives_a_dxf_in_us_feet(tmp_path):
    src = io.read_source(layer(tmp_path / "ny.gpkg", crs="EPSG:2263"))
    assert src.units == "us_ft"
    io.write_result(vt.tighten(src.shape, 2.0), tmp_path / "ny.dxf", meta=src.meta)
    assert ezdxf.readfile(tmp_path / "ny.dxf").header["$INSUNITS"] == 21


def test_read_features_crs_option_replaces_the_files(tmp_path):
    path = layer(tmp_path / "p.gpkg")
    f = io.read_features(path, crs="EPSG:3857")
    assert f.crs.to_epsg() == 3857 and f.meta["units"] == "m" and len(f) == 2
    assert f.attributes["pid"].tolist() == [7, 8]
    with pytest.raises(vt.CRSError, match="crs nonsense: not a CRS that pyproj knows"):
        io.read_features(path, crs="nonsense")
    with pytest.raises(ValueError, match="layers is an option of DXF input, not GeoPackage"):
        io.read_features(path, layers=["CUT"])


# ---------------------------------------------------------------------------------------------------------
# The command line: --layer for DXF and geodata, scoped options, image outputs to geodata
# ---------------------------------------------------------------------------------------------------------
def test_layer_is_several_names_for_a_dxf_and_one_for_a_layer(tmp_path, capsys):
    dxf = tmp_path / "part.dxf"
    doc = ezdxf.new(units=4)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (30, 0), (30, 20), (0, 20)], close=True, dxfattribs={"layer": "CUT"})
    msp.add_circle((10, 10), 4, dxfattribs={"layer": "HOLES"})
    msp.add_circle((22, 10), 3, dxfattribs={"layer": "ENGRAVE"})
    doc.saveas(dxf)
    out = tmp_path / "part-t.dxf"
    assert main(["tighten", str(dxf), "-r", "1", "-o", str(out), "--layer", "CUT,HOLES", "-q"]) == 0
    shape = io.read_shape(out)
    assert len(shape.interiors) == 1 and shape.area == pytest.approx(vt.tighten(
        box(0, 0, 30, 20).difference(shapely.Point(10, 10).buffer(4, 4096)), 1.0).area, rel=1e-4)
    gpkg = layer(tmp_path / "p.gpkg")
    target = tmp_path / "t.gpkg"
    assert main(["tighten", str(gpkg), "-r", "1", "-o", str(target), "--layer", "parcels,other"]) == 2
    assert "--layer takes one name here" in one_error_line(capsys) and not target.exists()
    assert main(["tighten", str(gpkg), "-r", "1", "-o", str(target), "--layer", "parcels", "-q"]) == 0
    assert gpd.read_file(target)["pid"].tolist() == [7, 8]


@pytest.mark.parametrize("extra, output, needle", [
    (["--crs", "EPSG:25832"], "o.dxf", "--crs applies to geodata layers"),
    (["--to-crs", "EPSG:25832"], "o.dxf", "--to-crs applies to geodata layers"),
    (["--trace", "exact"], "o.dxf", "--trace applies to image inputs"),
    (["--threshold", "0.5"], "o.dxf", "--threshold applies to image inputs"),
    (["--keep-style"], "o.dxf", "--keep-style applies to SVG output only"),
])
def test_options_of_other_kinds_of_input_are_refused(tmp_path, capsys, extra, output, needle):
    src = tmp_path / "s.dxf"
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline([(0, 0), (9, 0), (9, 9), (0, 9)], close=True)
    doc.saveas(src)
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / output), *extra]) == 2
    assert needle in one_error_line(capsys) and not (tmp_path / output).exists()


def test_geodata_refuses_cad_output_options(tmp_path, capsys):
    gpkg = layer(tmp_path / "p.gpkg")
    assert main(["tighten", str(gpkg), "-r", "1", "-o", str(tmp_path / "t.gpkg"), "--dxf-entities",
                 "lwpolyline"]) == 2
    assert "--dxf-entities applies to DXF output only" in one_error_line(capsys)


def test_labels_to_a_geopackage_one_feature_a_label(tmp_path, capsys):
    img = np.zeros((40, 60), np.uint16)
    img[5:35, 5:30], img[5:35, 30:55], img[10:14, 55:59] = 300, 40000, 7      # 7 vanishes at r = 4
    src, out = tmp_path / "labels.png", tmp_path / "labels.gpkg"
    raster.write_image(src, img)
    assert main(["tighten", str(src), "-r", "4", "--labels", "-o", str(out)]) == 0
    cap = capsys.readouterr()
    assert "2 of 3 label(s) kept" in cap.out and "vanished" in cap.err
    back = gpd.read_file(out)
    assert back.crs is None and back["label"].tolist() == [300, 40000]
    with pytest.warns(raster.MaskWarning, match="1 of 3 label"):
        expected = raster.tighten_labels(img, 4)
    for row in back.itertuples():
        assert row.geometry.equals(trace_pixels(expected == row.label))
        assert row.area == row.geometry.area == (expected == row.label).sum()
        assert row.r == 4 and row.init == "core"
    assert back["area_in"].tolist() == [30 * 25, 30 * 25]
    a, b = back.geometry
    assert a.intersection(b).area == 0 and a.touches(b)


def test_a_mask_to_a_geopackage_is_its_exact_tightening(tmp_path, capsys):
    mask = np.zeros((30, 40), np.uint8)
    mask[5:25, 5:35] = 1
    mask[12:18, 15:25] = 0                                                    # a hole
    src, out = tmp_path / "m.png", tmp_path / "m.gpkg"
    raster.write_image(src, mask)
    assert main(["tighten", str(src), "-r", "2", "-o", str(out), "-q"]) == 0
    back = gpd.read_file(out)
    exact = vt.tighten(trace_pixels(mask.astype(bool)), 2.0)
    assert len(back) == 1 and back.crs is None
    assert back["area"].iloc[0] == pytest.approx(exact.area, rel=1e-12) and back["n_holes"].iloc[0] == 1
    assert back.geometry.iloc[0].symmetric_difference(exact.geometry).area < 1e-9


def test_a_batch_of_every_kind_goes_down_each_own_path(tmp_path, capsys):
    folder, out = tmp_path / "in", tmp_path / "out"
    folder.mkdir()
    doc = ezdxf.new(units=1)                                                  # inches
    doc.modelspace().add_lwpolyline([(100, 50), (103, 50), (103, 52), (100, 52)], close=True)
    doc.saveas(folder / "a.dxf")
    layer(folder / "b.gpkg")
    mask = np.zeros((30, 30), np.uint16)
    mask[5:25, 5:25] = 65535
    raster.write_image(folder / "c.tif", mask)
    (folder / "d.svg").write_text(
        '<svg xmlns="http://www.w3.org/2000/svg" width="40mm" height="20mm" viewBox="0 0 40 20">'
        '<rect width="40" height="20" fill="none" stroke="red"/>'
        '<circle cx="10" cy="10" r="4" fill="none" stroke="red"/></svg>')
    assert main(["tighten", str(folder), "-r", "0.5", "-o", str(out), "--jobs", "1", "-q"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["a.dxf", "b.gpkg", "c.tif", "d.svg"]
    a = ezdxf.readfile(out / "a.dxf")
    assert a.header["$INSUNITS"] == 1
    assert io.read_shape(out / "a.dxf").bounds == pytest.approx((100, 50, 103, 52), abs=1e-9)
    b = gpd.read_file(out / "b.gpkg")
    assert b.crs.to_epsg() == 25832 and b["use"].tolist() == ["yard", "barn"]
    shed = vt.tighten(box(500_040, 5_700_000, 500_052, 5_700_012), 0.5)
    assert b.geometry.iloc[1].equals_exact(shed.geometry, 1e-6)
    c = raster.read_image(out / "c.tif").data
    assert c.dtype == np.uint16 and set(np.unique(c)) == {0, 65535}
    assert ((c != 0) == raster.tighten_mask(mask, 0.5).astype(bool)).all()
    d = io.read_source(out / "d.svg")
    assert d.units == "mm" and d.meta["page"]["viewBox"] == "0 0 40 20" and len(d.shape.interiors) == 1
