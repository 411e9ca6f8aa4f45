"""Geodata in, geodata out: features, attributes and CRS through every format, on the command line.

A small projected dataset is built here (parcels in UTM zone 31N, metres, with attributes of several
types); pyogrio's wheel ships Natural Earth's 177 countries (EPSG:4326), used for the geographic refusal
as it is and, reprojected, for the happy path.
"""

import hashlib
import json
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, MultiPolygon, Point, Polygon, box

gpd = pytest.importorskip("geopandas")
pyogrio = pytest.importorskip("pyogrio")
pytest.importorskip("pyarrow")
pd = pytest.importorskip("pandas")

import vectortighten as vt  # noqa: E402
from vectortighten import io  # noqa: E402
from vectortighten.cli import main  # noqa: E402

R = 1.0
FORMATS = ["gpkg", "shp", "geojson", "fgb", "parquet"]


def parcels() -> "gpd.GeoDataFrame":
    """Six parcels in metres: plain, L-shaped, a strip thinner than 2r (vanishes), holed, in two parts."""
    geoms = [
        box(0, 0, 10, 10),
        Polygon([(20, 0), (32, 0), (32, 5), (25, 5), (25, 12), (20, 12)]),
        box(40, 0, 41.5, 20),                                        # 1.5 m wide: empty at r = 1
        box(50, 0, 62, 12).difference(box(54, 4, 58, 8)),
        MultiPolygon([box(70, 0, 76, 6), box(80, 0, 86, 8)]),
        Polygon([(0, 20), (14, 20), (14, 24), (12.5, 24), (12.5, 26), (14, 26), (14, 30), (0, 30)]),
    ]
    return gpd.GeoDataFrame(
        {"parcel_id": [101, 102, 103, 104, 105, 106],
         "owner": ["Ana", "Bo", None, "Céline", "Dai", "Eve"],
         "value": [1.5, 2.25, 0.0, 1e6, -3.5, 7.0],
         "zone": ["R1", "R1", "C2", "C2", "R3", "R3"]},
        geometry=geoms, crs="EPSG:32631")


def write(frame, path: Path) -> Path:
    if path.suffix == ".parquet":
        frame.to_parquet(path)
    else:
        frame.to_file(path, layer=path.stem) if path.suffix == ".gpkg" else frame.to_file(path)
    return path


def read(path: Path):
    return gpd.read_parquet(path) if path.suffix == ".parquet" else gpd.read_file(path)


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def one_error_line(capsys) -> str:
    err = [ln for ln in capsys.readouterr().err.strip().splitlines() if "warning:" not in ln]
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


def same_geometry(a, b, tol=1e-9) -> bool:
    """Equal up to the file's coordinate rounding (GeoJSON keeps 15 digits); empty and None alike."""
    if a is None or a.is_empty or b is None or b.is_empty:
        return (a is None or a.is_empty) and (b is None or b.is_empty)
    return shapely.hausdorff_distance(a, b) <= tol and abs(a.area - b.area) <= tol * max(1.0, a.area)


def naturalearth() -> Path:
    folder = Path(pyogrio.__file__).parent / "tests" / "fixtures" / "naturalearth_lowres"
    path = folder / "naturalearth_lowres.shp"
    if not path.exists():
        pytest.skip("pyogrio's naturalearth_lowres fixture is not installed")
    return path


# ---------------------------------------------------------------------------------------------------------
# Round trips, format by format
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("ext", FORMATS)
def test_round_trip_keeps_rows_attributes_crs(ext, tmp_path, capsys):
    src = write(parcels(), tmp_path / f"parcels.{ext}")
    before = digest(src)
    out = tmp_path / f"tight.{ext}"
    assert main(["tighten", str(src), "-r", str(R), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "6 feature(s)" in captured.out and "r = 1 metre" in captured.out and "EPSG:32631" in captured.out
    assert "1 of 6 feature(s) have an empty tightening" in captured.err          # counted on stderr
    assert digest(src) == before                                                  # the input untouched
    inp, res = read(src), read(out)
    assert len(res) == len(inp) == 6
    assert res.crs == inp.crs and res.crs.to_epsg() == 32631
    pd.testing.assert_frame_equal(res.drop(columns=res.geometry.name).reset_index(drop=True),
                                  inp.drop(columns=inp.geometry.name).reset_index(drop=True))
    for k, (g_in, g_out) in enumerate(zip(inp.geometry, res.geometry, strict=True)):
        expected = vt.tighten(g_in, R).geometry
        assert same_geometry(g_out, expected), (k, g_out, expected)
    strip = res.geometry[res["parcel_id"] == 103].iloc[0]
    assert strip is None or strip.is_empty                                        # the strip: row kept, empty
    assert not res.geometry[res["parcel_id"] == 101].iloc[0].is_empty


def test_gpkg_keeps_layer_and_geometry_column_names(tmp_path):
    src = tmp_path / "city.gpkg"
    pyogrio.write_dataframe(parcels(), src, layer="parcels_2024", layer_options={"GEOMETRY_NAME": "shape"})
    assert pyogrio.read_info(src, layer="parcels_2024")["geometry_name"] == "shape"
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), "-q"]) == 0
    assert pyogrio.list_layers(out)[:, 0].tolist() == ["parcels_2024"]
    assert pyogrio.read_info(out, layer="parcels_2024")["geometry_name"] == "shape"


@pytest.mark.parametrize("src_ext, out_ext", [("shp", "gpkg"), ("gpkg", "parquet"), ("parquet", "fgb"),
                                              ("fgb", "geojson")])
def test_between_formats(src_ext, out_ext, tmp_path, capsys):
    src = write(parcels(), tmp_path / f"in.{src_ext}")
    out = tmp_path / f"out.{out_ext}"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 0
    inp, res = read(src), read(out)       # (a FlatGeobuf written with its index is in Hilbert order)
    assert res.crs.to_epsg() == 32631 and res["parcel_id"].tolist() == inp["parcel_id"].tolist()
    assert res["owner"].tolist() == inp["owner"].tolist()
    for g_in, g_out in zip(inp.geometry, res.geometry, strict=True):
        assert same_geometry(g_out, vt.tighten(g_in, 1.0).geometry)


def test_per_feature_never_union(tmp_path):
    """Two overlapping parcels stay two features; their tightenings overlap as the inputs do."""
    frame = gpd.GeoDataFrame({"id": [1, 2]}, geometry=[box(0, 0, 10, 10), box(8, 0, 18, 10)], crs=32631)
    src = write(frame, tmp_path / "two.gpkg")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "2", "-o", str(out), "-q"]) == 0
    res = read(out)
    assert len(res) == 2
    assert res.geometry.iloc[0].intersection(res.geometry.iloc[1]).area > 15      # 2 × 10 minus corners
    assert same_geometry(res.geometry.iloc[1], vt.tighten(box(8, 0, 18, 10), 2.0).geometry)


def test_plain_geojson_and_wkt_still_shapes(tmp_path, capsys):
    plain = tmp_path / "plain.geojson"
    plain.write_text(json.dumps(shapely.geometry.mapping(box(0, 0, 10, 10))))
    out = tmp_path / "t.gpkg"
    assert main(["tighten", str(plain), "-r", "1", "-o", str(out)]) == 0
    res = read(out)
    assert len(res) == 1 and res.crs is None                                     # a plain shape has no CRS
    assert res["perimeter"].iloc[0] == pytest.approx(40 - (8 - 2 * np.pi), rel=1e-12)


# ---------------------------------------------------------------------------------------------------------
# Units and CRS
# ---------------------------------------------------------------------------------------------------------
def test_geographic_crs_refused(tmp_path, capsys):
    src = naturalearth()
    out = tmp_path / "world.gpkg"
    assert main(["tighten", str(src), "-r", "20000", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "EPSG:4326" in line and "geographic" in line and "--to-crs" in line and "degree" in line
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_to_crs_reprojects_tightens_and_writes_there(tmp_path, capsys):
    """Ten countries, among them Sudan and Mozambique, which the reprojection makes invalid."""
    world = gpd.read_file(naturalearth())
    subset = world[world.iso_a3.isin(["SDN", "MOZ", "LUX", "KWT", "QAT", "LKA", "JAM", "SWZ", "LBN",
                                      "TTO"])]
    src = tmp_path / "countries.gpkg"
    subset.to_file(src, layer="countries")
    out = tmp_path / "tight.gpkg"
    assert main(["tighten", str(src), "-r", "10000", "--to-crs", "EPSG:8857", "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "reprojected from WGS 84 (EPSG:4326)" in captured.out and "metre" in captured.out
    assert re.search(r"2 of 10 feature\(s\) were invalid .*repaired alone", captured.err)
    res = read(out)
    assert res.crs.to_epsg() == 8857 and len(res) == 10
    pd.testing.assert_frame_equal(res.drop(columns="geometry"),
                                  subset.drop(columns="geometry").reset_index(drop=True))
    projected = subset.to_crs(8857)
    for g_in, g_out in zip(projected.geometry, res.geometry, strict=True):
        with pytest.warns(vt.RepairWarning) if not g_in.is_valid else _no_warning():
            expected = vt.tighten(g_in, 10000).geometry
        assert same_geometry(g_out, expected, tol=1e-6)


class _no_warning:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def test_naturalearth_read_repairs_each_feature_alone():
    """The issue's case: two features invalid after reprojection; each is repaired, never the file."""
    from vectortighten.vectorized import _repair_each

    f = io.read_features(naturalearth())
    assert len(f) == 177 and f.meta["crs"].to_epsg() == 4326
    assert f.attributes.columns.tolist() == ["pop_est", "continent", "name", "iso_a3", "gdp_md_est"]
    projected = np.asarray(gpd.GeoSeries(f.geometry, crs=4326).to_crs(8857).array, dtype=object)
    assert (~shapely.is_valid(projected)).sum() == 2
    with pytest.warns(vt.RepairWarning, match=r"2 of 177 feature\(s\) were invalid"):
        fixed, n = _repair_each(projected)
    assert n == 2 and shapely.is_valid(fixed).all()
    changed = np.flatnonzero([a is not b for a, b in zip(projected, fixed, strict=True)])
    assert len(changed) == 2
    for i in changed:       # each one is make_valid of itself alone
        assert fixed[i].equals(shapely.make_valid(projected[i]))


def test_geojson_without_crs_is_wgs84_and_says_so(tmp_path, capsys):
    fc = {"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"id": 1},
         "geometry": shapely.geometry.mapping(box(2, 40, 5, 43))}]}
    src = tmp_path / "mm.geojson"
    src.write_text(json.dumps(fc))
    out = tmp_path / "out.geojson"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "RFC 7946" in line and "--to-crs EPSG:32631 (UTM zone 31" in line
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), "--crs", "EPSG:32631", "-q"]) == 0
    assert read(out).crs.to_epsg() == 32631


def test_missing_crs_needs_crs_option(tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.shp")
    src.with_suffix(".prj").unlink()
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "no CRS" in line and "--crs" in line and not out.exists()
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), "--crs", "EPSG:32631", "-q"]) == 0
    assert read(out).crs.to_epsg() == 32631


def test_unreadable_crs(tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.shp")
    src.with_suffix(".prj").write_text("GEOGCS[nonsense")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "its CRS cannot be read" in line and ".prj" in line and "--crs" in line and not out.exists()


@pytest.mark.parametrize("argv, needle", [
    (["--to-crs", "EPSG:4326"], "not a projected CRS"),
    (["--to-crs", "EPSG:99999999"], "not a CRS that pyproj knows"),
    (["--crs", "nonsense"], "not a CRS that pyproj knows"),
])
def test_bad_crs_options(argv, needle, tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.gpkg")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), *argv]) == 2
    assert needle in one_error_line(capsys) and not out.exists()


# ---------------------------------------------------------------------------------------------------------
# Invalid features, mixed types, layers
# ---------------------------------------------------------------------------------------------------------
def test_invalid_features_repaired_one_by_one(tmp_path, capsys):
    bowtie = Polygon([(0, 0), (10, 10), (10, 0), (0, 10)])
    figure8 = Polygon([(20, 0), (30, 0), (20, 10), (30, 10)])
    frame = gpd.GeoDataFrame({"id": [1, 2, 3]}, geometry=[bowtie, box(40, 0, 50, 10), figure8], crs=32631)
    src = write(frame, tmp_path / "bad.gpkg")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "2 of 3 feature(s) were invalid" in captured.err and "Self-intersection" in captured.err
    res = read(out)
    assert res["id"].tolist() == [1, 2, 3]
    for g_in, g_out in zip(frame.geometry, res.geometry, strict=True):
        expected = vt.tighten(shapely.make_valid(g_in), 1.0).geometry
        assert same_geometry(g_out, expected)


def test_mixed_types_pass_through(tmp_path, capsys):
    pt, line = Point(100, 100), LineString([(0, 50), (30, 50)])
    frame = gpd.GeoDataFrame({"id": [1, 2, 3]}, geometry=[box(0, 0, 10, 10), pt, line], crs=32631)
    src = write(frame, tmp_path / "mixed.gpkg")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "2 of 3 geometries are not polygonal (LineString, Point" in captured.err
    assert "2 not polygonal, passed through" in captured.out
    res = read(out)
    assert res.geometry.iloc[1].equals(pt) and res.geometry.iloc[2].equals(line)
    assert same_geometry(res.geometry.iloc[0], vt.tighten(box(0, 0, 10, 10), 1.0).geometry)
    shp = tmp_path / "out.shp"
    assert main(["tighten", str(src), "-r", "1", "-o", str(shp)]) == 2
    assert "Shapefile holds one kind of geometry" in one_error_line(capsys)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mixed.gpkg", "out.gpkg"]


def test_no_polygon_layer_refused(tmp_path, capsys):
    frame = gpd.GeoDataFrame({"id": [1, 2]},
                             geometry=[LineString([(0, 0), (5, 5)]), LineString([(1, 0), (2, 2)])],
                             crs=32631)
    src = write(frame, tmp_path / "roads.gpkg")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "holds no polygons (2 LineString)" in line and not out.exists()


def test_empty_layer_refused(tmp_path, capsys):
    src = write(parcels().iloc[:0], tmp_path / "none.gpkg")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    assert "has no features" in one_error_line(capsys) and not out.exists()


def test_layers_of_a_geopackage(tmp_path, capsys):
    src = tmp_path / "city.gpkg"
    parcels().to_file(src, layer="parcels")
    parcels().iloc[:2].to_file(src, layer="blocks", mode="a")
    out = tmp_path / "out.gpkg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "2 layers (parcels, blocks)" in line and "--layer" in line and not out.exists()
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), "--layer", "nope"]) == 2
    assert "no layer 'nope'" in one_error_line(capsys)
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), "--layer", "blocks", "-q"]) == 0
    assert len(read(out)) == 2 and pyogrio.list_layers(out)[:, 0].tolist() == ["blocks"]


@pytest.mark.parametrize("name, data, needle", [
    ("junk.gpkg", b"\x00garbage" * 100, "malformed GeoPackage"),
    ("junk.fgb", b"fgb\x03junk" * 50, "malformed FlatGeobuf"),
    ("junk.parquet", b"PAR1 nonsense" * 20, "malformed GeoParquet"),
    ("junk.shp", b"\x00" * 50, "malformed Shapefile"),
    ("junk.geojson", b'{"type": "FeatureCollection"}', "malformed GeoJSON"),
])
def test_corrupt_files(name, data, needle, tmp_path, capsys):
    src = tmp_path / name
    src.write_bytes(data)
    out = tmp_path / ("out" + src.suffix)
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert needle in line and name in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


def test_features_to_a_shape_format_refused(tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.gpkg")
    out = tmp_path / "out.svg"
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    assert "write it to a geodata format" in one_error_line(capsys) and not out.exists()


def test_geodata_options_on_a_shape_refused(tmp_path, capsys):
    src = tmp_path / "s.wkt"
    src.write_text("POLYGON ((0 0, 9 0, 9 9, 0 9, 0 0))")
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "o.wkt"), "--to-crs", "EPSG:3857"]) == 2
    assert "--to-crs applies to geodata layers" in one_error_line(capsys)


def test_shapefile_replaced_whole(tmp_path):
    """A Shapefile output replaces every file of an older one, and leaves no stale sidecar."""
    out = tmp_path / "out.shp"
    write(parcels(), tmp_path / "p.shp")
    (tmp_path / "out.prj").write_text("stale")
    (tmp_path / "out.qix").write_text("stale index")
    src = write(parcels(), tmp_path / "q.shp")
    src.with_suffix(".prj").unlink()
    assert main(["tighten", str(src), "-r", "1", "-o", str(out), "--crs", "EPSG:32631", "-q"]) == 0
    assert not (tmp_path / "out.qix").exists()
    assert read(out).crs.to_epsg() == 32631
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


def test_write_failure_leaves_nothing(tmp_path, monkeypatch, capsys):
    src = write(parcels(), tmp_path / "p.gpkg")
    out = tmp_path / "out.gpkg"
    out.write_bytes(b"old")

    def fail(*args, **kwargs):
        Path(args[1]).write_bytes(b"half")
        raise pyogrio.errors.FeatureError("disk full")

    monkeypatch.setattr(pyogrio, "write_dataframe", fail)
    assert main(["tighten", str(src), "-r", "1", "-o", str(out)]) == 2
    assert "nothing was written" in one_error_line(capsys)
    assert out.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["out.gpkg", "p.gpkg"]


# ---------------------------------------------------------------------------------------------------------
# Progress, quiet, help, extras
# ---------------------------------------------------------------------------------------------------------
def test_progress_bar_over_features(tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.gpkg")
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "a.gpkg"), "--progress"]) == 0
    err = capsys.readouterr().err
    assert "tightening" in err and "6/6" in err and "feature" in err
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "b.gpkg")]) == 0
    captured = capsys.readouterr()                    # not a terminal: no bar
    assert "6/6" not in captured.err and "6 feature(s)" in captured.out
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "c.gpkg"), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and "6/6" not in captured.err and "empty tightening" in captured.err


def test_slow_feature_shows_it_is_working(monkeypatch):
    """While one feature takes long, the bar is redrawn with its name, vertex count and time so far."""
    import io as stdio
    import time

    from vectortighten import _progress

    monkeypatch.setattr(_progress, "TICK", 0.05)
    monkeypatch.setattr(_progress, "SLOW", 0.1)
    stream = stdio.StringIO()
    with _progress.FeatureBar(2, enabled=True, stream=stream) as bar:
        bar.start(7, 75000)
        time.sleep(0.5)
        bar.advance(2)
    assert "feature 7: 75000 vertices" in stream.getvalue() and "2/2" in stream.getvalue()


def test_help_says_features_are_independent(capsys):
    with pytest.raises(SystemExit):
        main(["tighten", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "tightened independently" in text and "open into a gap or close into an overlap" in text
    assert "--to-crs" in text and "--layer" in text and "--dask" in text


def test_missing_geo_extra_names_it(monkeypatch, tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.gpkg")
    monkeypatch.setitem(sys.modules, "pyogrio", None)
    with pytest.raises(io.MissingDependencyError, match=re.escape("pip install vectortighten[geo]")):
        io.read_features(src)
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "o.gpkg")]) == 2
    assert "vectortighten[geo]" in one_error_line(capsys)


def test_missing_dask_extra_names_it(monkeypatch, tmp_path, capsys):
    src = write(parcels(), tmp_path / "p.gpkg")
    monkeypatch.setitem(sys.modules, "distributed", None)
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "o.gpkg"), "--dask", "local"]) == 2
    assert "vectortighten[dask]" in one_error_line(capsys)
    assert not (tmp_path / "o.gpkg").exists()


def test_jobs_over_features_same_result(tmp_path):
    src = write(parcels(), tmp_path / "p.gpkg")
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "one.gpkg"), "-q"]) == 0
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "two.gpkg"), "-q", "-j", "2"]) == 0
    a, b = read(tmp_path / "one.gpkg"), read(tmp_path / "two.gpkg")
    assert all(x.equals_exact(y, 0) for x, y in zip(a.geometry, b.geometry, strict=True))


def test_dask_option_runs_the_file_on_a_cluster(tmp_path, capsys):
    """--dask ADDRESS sends the features to a running scheduler; the output is the serial one."""
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("dask_geopandas")
    src = write(parcels(), tmp_path / "p.gpkg")
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "serial.gpkg"), "-q"]) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # distributed's notes on ports and its own deprecations
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                      dashboard_address=None) as cluster:
            code = main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "dask.gpkg"), "--dask",
                         cluster.scheduler_address, "--progress"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "1 of 6 feature(s) have an empty tightening" in captured.err and "6/6" in captured.err
    a, b = read(tmp_path / "serial.gpkg"), read(tmp_path / "dask.gpkg")
    pd.testing.assert_frame_equal(a.drop(columns="geometry"), b.drop(columns="geometry"))
    assert all(x.equals_exact(y, 0) for x, y in zip(a.geometry, b.geometry, strict=True))
    assert b.crs == a.crs


def test_dask_unreachable_scheduler(tmp_path, capsys):
    pytest.importorskip("distributed")
    import dask

    src = write(parcels(), tmp_path / "p.gpkg")
    out = tmp_path / "o.gpkg"
    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        assert main(["tighten", str(src), "-r", "1", "-o", str(out), "--dask", "tcp://127.0.0.1:9"]) == 2
    assert "cannot reach the scheduler" in one_error_line(capsys) and not out.exists()
