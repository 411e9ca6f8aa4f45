"""tighten_all and the *_all morphology: one result per feature, in the caller's container, and scale-out."""

import warnings

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, MultiPolygon, Point, Polygon, box

import vectortighten as vt
from vectortighten import vectorized

SHAPES = [
    box(0, 0, 10, 10),
    Polygon([(20, 0), (32, 0), (32, 5), (25, 5), (25, 12), (20, 12)]),
    box(50, 0, 62, 12).difference(box(54, 4, 58, 8)),
    MultiPolygon([box(70, 0, 76, 6), box(80, 0, 86, 8)]),
]


def wkb(geoms):
    return [shapely.to_wkb(g) for g in geoms]


def expected(geoms, r=1.0, **kw):
    return [vt.tighten(g, r, **kw).geometry for g in geoms]


def test_list_gives_array_each_equal_to_tighten():
    out = vt.tighten_all(SHAPES, 1.0)
    assert isinstance(out, np.ndarray) and out.shape == (4,) and out.dtype == object
    assert wkb(out) == wkb(expected(SHAPES))


def test_ndarray_keeps_shape_none_and_empty_give_empty():
    arr = np.array([[SHAPES[0], None], [Polygon(), SHAPES[1]]], dtype=object)
    out = vt.tighten_all(arr, 1.0, init="input")
    assert out.shape == (2, 2)
    assert out[0, 1].is_empty and out[1, 0].is_empty and out[0, 1].geom_type == "Polygon"
    assert wkb([out[0, 0], out[1, 1]]) == wkb(expected([SHAPES[0], SHAPES[1]], init="input"))
    assert arr[0, 1] is None                                   # the input is not modified


def test_scalar_gives_scalar():
    assert vt.tighten_all(SHAPES[1], 1.0).equals_exact(vt.tighten(SHAPES[1], 1.0).geometry, 0)


def test_geoseries_keeps_index_name_crs():
    gpd = pytest.importorskip("geopandas")
    s = gpd.GeoSeries(SHAPES, index=["a", "b", "c", "d"], crs="EPSG:32631", name="parcels")
    out = vt.tighten_all(s, 1.0)
    assert isinstance(out, gpd.GeoSeries)
    assert out.index.tolist() == ["a", "b", "c", "d"] and out.crs == s.crs and out.name == "parcels"
    assert wkb(out) == wkb(expected(SHAPES))


def test_geodataframe_keeps_columns():
    gpd = pytest.importorskip("geopandas")
    df = gpd.GeoDataFrame({"id": [4, 3, 2, 1], "kind": list("wxyz")}, geometry=SHAPES, crs=32631)
    out = vt.tighten_all(df, 1.0)
    assert isinstance(out, gpd.GeoDataFrame) and out.columns.tolist() == df.columns.tolist()
    assert out["id"].tolist() == [4, 3, 2, 1] and out.crs == df.crs
    assert wkb(out.geometry) == wkb(expected(SHAPES))
    assert wkb(df.geometry) == wkb(SHAPES)                     # the input frame is not modified


def test_tighten_of_a_series_points_to_tighten_all():
    gpd = pytest.importorskip("geopandas")
    with pytest.raises(vt.GeometryTypeError, match="GeoSeries of 4; for many geometries use "
                                                   "vectortighten.tighten_all"):
        vt.tighten(gpd.GeoSeries(SHAPES), 1.0)
    with pytest.raises(vt.GeometryTypeError, match="tighten_all"):
        vt.tighten(SHAPES, 1.0)


def test_empty_results_kept_and_counted():
    shapes = [SHAPES[0], box(0, 0, 1.5, 30), box(5, 5, 6, 6)]        # two thinner than 2r
    with pytest.warns(vt.EmptyTighteningWarning, match=r"2 of 3 feature\(s\) have an empty tightening"):
        out = vt.tighten_all(shapes, 1.0)
    assert [g.is_empty for g in out] == [False, True, True]


def test_non_polygonal_passed_through_and_counted():
    pt, line = Point(1, 1), LineString([(0, 0), (3, 3)])
    with pytest.warns(vt.PassThroughWarning,
                      match=r"2 of 3 geometries are not polygonal \(LineString, Point"):
        out = vt.tighten_all([pt, SHAPES[0], line], 1.0)
    assert out[0] is pt and out[2] is line
    assert wkb([out[1]]) == wkb(expected([SHAPES[0]]))


def test_invalid_features_repaired_each_alone():
    bowtie = Polygon([(0, 0), (10, 10), (10, 0), (0, 10)])
    with pytest.warns(vt.RepairWarning,
                      match=r"1 of 2 feature\(s\) were invalid \(feature 1: Self-intersection"):
        out = vt.tighten_all([SHAPES[0], bowtie], 1.0)
    assert wkb([out[1]]) == wkb(expected([shapely.make_valid(bowtie)]))


def test_bad_elements_named():
    with pytest.raises(vt.GeometryTypeError, match="feature 1 is a str"):
        vt.tighten_all([SHAPES[0], "POLYGON ((0 0, 1 0, 0 1, 0 0))"], 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)            # shapely's own note on the NaN
        nan = Polygon([(0, 0), (1, np.nan), (1, 1)])
    with pytest.raises(vt.InvalidGeometryError, match="feature 1 has NaN"):
        vt.tighten_all([SHAPES[0], nan], 1.0)
    with pytest.raises(vt.InvalidRadiusError):
        vt.tighten_all(SHAPES, -1.0)
    with pytest.raises(ValueError, match="processes must be"):
        vt.tighten_all(SHAPES, 1.0, processes=0)
    with pytest.raises(ValueError, match="init must be"):
        vt.tighten_all(SHAPES, 1.0, init="nope")


def test_a_failing_feature_is_named_or_counted(monkeypatch):
    gpd = pytest.importorskip("geopandas")
    fn, what, warn = vectorized._OPS["tighten"]

    def flaky(S, r, init, tolerance):
        if S.area == 100:
            raise shapely.errors.GEOSException("TopologyException: side location conflict")
        return fn(S, r, init, tolerance)

    monkeypatch.setitem(vectorized._OPS, "tighten", (flaky, what, warn))
    s = gpd.GeoSeries(SHAPES, index=[10, 11, 12, 13])
    with pytest.raises(RuntimeError, match=r"feature 0 \(index 10\): internal error \(GEOSException: "
                                           "TopologyException"):
        vt.tighten_all(s, 1.0)
    with pytest.warns(vt.FeatureErrorWarning, match=r"1 of 4 feature\(s\) failed .*feature 0 \(index 10\)"):
        out = vt.tighten_all(s, 1.0, errors="warn")
    assert out.iloc[0].is_empty and wkb(out.iloc[1:]) == wkb(expected(SHAPES[1:]))


def test_engine_warnings_gathered(monkeypatch):
    fn, what, warn = vectorized._OPS["tighten"]

    def unsettled(S, r, init, tolerance):
        warnings.warn("the exact finish did not settle on every loop", vt.ConvergenceWarning, stacklevel=2)
        return fn(S, r, init, tolerance)

    monkeypatch.setitem(vectorized._OPS, "tighten", (unsettled, what, warn))
    with pytest.warns(vt.ConvergenceWarning) as caught:
        vt.tighten_all(SHAPES, 1.0)
    assert len(caught) == 1
    assert "4 of 4 feature(s): the exact finish did not settle" in str(caught[0].message)


@pytest.mark.parametrize("name", ["core", "fillet", "mortar", "mason"])
def test_morphology_all(name):
    fn_all = getattr(vt, f"{name}_all")
    fn = getattr(vt, name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", vt.EmptyTighteningWarning)
        out = fn_all(SHAPES + [None], 1.0)
    assert wkb(out[:-1]) == wkb([fn(g, 1.0) for g in SHAPES]) and out[-1].is_empty


def test_processes_give_the_serial_result():
    rng = np.random.default_rng(1)
    shapes = [shapely.affinity.rotate(box(0, 0, rng.uniform(3, 12), rng.uniform(3, 12)), rng.uniform(0, 90))
              for _ in range(24)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", vt.EmptyTighteningWarning)
        serial = vt.tighten_all(shapes, 1.0)
        spread = vt.tighten_all(shapes, 1.0, processes=2)
    assert wkb(spread) == wkb(serial)


def test_chunks_balance_vertices():
    order = np.arange(10)
    weight = np.array([100, 1, 1, 1, 1, 1, 1, 1, 1, 100], dtype=float)
    parts = vectorized._chunks(order, weight, 3)
    assert np.concatenate(parts).tolist() == order.tolist()
    assert [p.tolist() for p in parts] == [[0], list(range(1, 10))]    # the heavy first feature alone


def test_progress_on_stderr(capsys):
    vt.tighten_all(SHAPES, 1.0, progress=True)
    err = capsys.readouterr().err
    assert "tightening" in err and "4/4" in err


def test_dask_geoseries_on_a_local_cluster():
    """Two worker processes, partition by partition, against the serial result (identical geometries)."""
    gpd = pytest.importorskip("geopandas")
    dgpd = pytest.importorskip("dask_geopandas")
    distributed = pytest.importorskip("distributed")
    rng = np.random.default_rng(7)
    shapes = [shapely.affinity.translate(s, 100 * k, 50 * (k % 3))
              for k, s in enumerate(SHAPES * 3)] + [None, box(0, 0, 1, 1)]
    rng.shuffle(shapes)
    series = gpd.GeoSeries(shapes, index=np.arange(100, 100 + len(shapes)), crs=32631)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", vt.EmptyTighteningWarning)
        serial = vt.tighten_all(series, 1.0)
    lazy_in = dgpd.from_geopandas(series, npartitions=4)
    lazy = vt.tighten_all(lazy_in, 1.0)
    assert isinstance(lazy, dgpd.GeoSeries) and lazy.npartitions == 4        # lazy until computed
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # distributed's notes on ports and its own deprecations
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster, distributed.Client(cluster):
            result = lazy.compute()
    assert result.index.tolist() == series.index.tolist() and result.crs == series.crs
    assert wkb(result) == wkb(serial)
