"""Geodata: GeoPackage, Shapefile, GeoJSON, FlatGeobuf and GeoParquet through pyogrio and GeoPandas; WKT.

Every geodata format holds *features*: a geometry each, with attributes, in a layer with a coordinate
reference system. `read_features` gives them as `Features` (geometry array, attribute table, and the
CRS, layer name and geometry column name in ``meta``); `write_features` writes them back with every
attribute and the CRS unchanged. Reading and writing go through pyogrio (GDAL), GeoParquet through
GeoPandas and pyarrow; all of them are the ``geo`` extra (``pip install "vectortighten[geo]"``).

A GeoJSON file that is a bare geometry (its top-level ``"type"`` is ``"Polygon"``, ``"MultiPolygon"``,
…) is not a layer: it is read as one plain shape, in its own units and with no CRS, like WKT.

Invalid polygons are repaired as they are read, each on its own (``shapely.make_valid``), with one
`RepairWarning` that counts them: features are never united with each other.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import shape

from vectortighten.errors import InvalidGeometryError

from ._common import _polygonal, _read_text, _require, atomic_path
from ._source import Features, Source, crs_units
from ._wkt_curves import has_curves, read_curved_wkt, read_curved_wkt_loops

__all__ = ["GEODATA", "geojson_is_plain", "parse_crs", "read_features", "read_source", "read_wkt",
           "result_features", "wkt_text", "write_features"]

#: Geodata formats: name -> (GDAL driver or None for GeoParquet, what to call it in messages).
GEODATA: dict[str, tuple[str | None, str]] = {
    "gpkg": ("GPKG", "GeoPackage"),
    "shp": ("ESRI Shapefile", "Shapefile"),
    "geojson": ("GeoJSON", "GeoJSON"),
    "fgb": ("FlatGeobuf", "FlatGeobuf"),
    "parquet": (None, "GeoParquet"),
}

_GEOMETRY_TYPES = {"Point", "MultiPoint", "LineString", "MultiLineString", "Polygon", "MultiPolygon",
                   "GeometryCollection"}
#: Sidecar files of a Shapefile that a new output may lack; an old one left beside it would mislead.
_SHAPEFILE_OPTIONAL = (".prj", ".cpg", ".qix", ".sbn", ".sbx", ".qmd")


# ---------------------------------------------------------------------------------------------------------
# WKT and plain GeoJSON geometries
# ---------------------------------------------------------------------------------------------------------
def read_wkt(path: Path, flatten: float | None = None):
    """The geometry of a WKT file (not yet checked to be polygonal).

    Curved types (``CURVEPOLYGON``, ``CIRCULARSTRING``, ``COMPOUNDCURVE``, ``MULTISURFACE``), which GEOS
    does not read, are read by `_wkt_curves.read_curved_wkt`: arcs sampled within ``flatten`` (default
    1e-4 of the diagonal).
    """
    text = _read_text(path, "WKT").strip()
    if not text:
        raise InvalidGeometryError(f"{path}: malformed WKT (the file is empty)")
    if has_curves(text):
        return read_curved_wkt(text, str(path), flatten)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # GEOS warns on NaN; _polygonal names it
            return shapely.from_wkt(text)
    except shapely.errors.ShapelyError as exc:
        raise InvalidGeometryError(f"{path}: malformed WKT ({exc})") from None


def read_wkt_source(path: Path, flatten: float | None = None) -> Source:
    """A WKT file as a `Source`: the polygonal shape (arcs sampled within ``flatten``) and, for curved WKT
    whose sampled shape is valid, the exact boundary as `Loop`s (`_wkt_curves.read_curved_wkt_loops`).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.wkt"
    ...     _ = p.write_text("CURVEPOLYGON(CIRCULARSTRING(0 0, 4 0, 0 0))")
    ...     src = read_wkt_source(p)
    >>> [(a.center, a.radius) for lp in src.loops for a in lp.arcs]
    [((2.0, 0.0), 2.0)]
    """
    text = _read_text(path, "WKT").strip()
    region = _polygonal(read_wkt(path, flatten), str(path))
    if not has_curves(text):
        return Source(region, {"format": "wkt"})

    def exact(text=text, region=region):
        return read_curved_wkt_loops(text, str(path)) if region.is_valid else None

    return Source(region, {"format": "wkt"}, exact)


def wkt_text(result) -> str:
    """The sampled geometry of a `Tightening` as WKT (full precision), one line."""
    return shapely.to_wkt(result.geometry, rounding_precision=-1) + "\n"


def _top_level_type(text: str) -> str | None:
    """The value of the top-level ``"type"`` member of a JSON object, read from its first characters.

    Enough of a scanner to skip strings and nested values; None if the text does not show it (yet).

    Examples
    --------
    >>> _top_level_type('{"crs": {"type": "name"}, "type": "FeatureCollection", "features": []}')
    'FeatureCollection'
    """
    depth, i, n = 0, 0, len(text)
    key = None
    while i < n:
        c = text[i]
        if c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            word, i = text[i + 1:j], j + 1
            if depth == 1:
                if key == "type":
                    return word
                k = i
                while k < n and text[k] in " \t\r\n":
                    k += 1
                if k < n and text[k] == ":":
                    key, i = word, k + 1
                    continue
            key = None
            continue
        if c in "{[":
            depth += 1
            key = None
        elif c in "}]":
            depth -= 1
        elif c == ",":
            key = None
        i += 1
    return None


def geojson_is_plain(path) -> bool:
    """Whether a GeoJSON file is a bare geometry (not a Feature or a FeatureCollection).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.geojson"
    ...     _ = p.write_text('{"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [0, 1], [0, 0]]]}')
    ...     geojson_is_plain(p)
    True
    """
    with open(path, "rb") as f:
        head = f.read(1 << 20)
    return _top_level_type(head.decode("utf-8-sig", errors="replace")) in _GEOMETRY_TYPES


def _read_plain_geojson(path: Path):
    """The geometry of a bare-geometry GeoJSON file."""
    try:
        # Integers are read as floats: a 400-digit coordinate becomes inf (refused below by name), not an
        # OverflowError in shapely or Python's limit on converting long digit strings.
        data = json.loads(_read_text(path, "GeoJSON"), parse_int=float)
    except json.JSONDecodeError as exc:
        raise InvalidGeometryError(f"{path}: malformed GeoJSON ({exc.msg} at line {exc.lineno})") from None
    except RecursionError:
        raise InvalidGeometryError(f"{path}: malformed GeoJSON (arrays or objects nested too deeply)") \
            from None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # GEOS warns on NaN; checked below
            geom = shape(data)
    except RecursionError:
        raise InvalidGeometryError(f"{path}: malformed GeoJSON (geometries nested too deeply)") from None
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, ArithmeticError,
            shapely.errors.ShapelyError) as exc:
        detail = f"missing {exc}" if isinstance(exc, KeyError) else str(exc) or type(exc).__name__
        raise InvalidGeometryError(f"{path}: malformed GeoJSON ({detail})") from None
    if not np.isfinite(shapely.get_coordinates(geom)).all():
        raise InvalidGeometryError(f"{path}: NaN or infinite coordinates")
    return geom


def read_source(path, name: str, *, layer: str | None = None, crs=None) -> Source:
    """A geodata file as one shape: a bare GeoJSON geometry, or the union of a layer's features.

    The features are repaired one by one before the union (see `read_features`), so that two features
    that a reprojection made invalid cannot make the union fail. ``meta`` is that of `read_features`
    (CRS, layer, units), so `vectortighten.io.write_result` writes the result back in the layer's CRS.

    Parameters
    ----------
    path : str or Path
    name : {"gpkg", "shp", "geojson", "fgb", "parquet"}
    layer : str, optional
        See `read_features`.
    crs : pyproj.CRS or str, optional
        See `read_features`.

    Returns
    -------
    Source
        ``loops`` is None (the file's boundary is sampled).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.geojson"
    ...     _ = p.write_text('{"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]]]}')
    ...     src = read_source(p, "geojson")
    >>> src.shape.area, src.crs, src.units
    (16.0, None, None)
    """
    path = Path(path)
    if name == "geojson" and geojson_is_plain(path):
        if layer is not None or crs is not None:
            given = "layer" if layer is not None else "crs"
            raise ValueError(f"{path} is a bare GeoJSON geometry, not a layer of features: {given} does not "
                             "apply")
        return Source(_read_plain_geojson(path), {"format": "geojson", "crs": None, "units": None})
    features = read_features(path, name, layer=layer, crs=crs)
    return Source(_union(features, path), dict(features.meta))


def _union(features: Features, path: Path):
    geoms = [g for g in features.geometry if g is not None and not g.is_empty]
    if not geoms:
        raise InvalidGeometryError(f"{path}: no geometry found")
    return shapely.union_all(geoms) if len(geoms) > 1 else geoms[0]


# ---------------------------------------------------------------------------------------------------------
# Features
# ---------------------------------------------------------------------------------------------------------
def _libraries(what: str, parquet: bool = False):
    gpd = _require("geopandas", "geo", what)
    pyogrio = _require("pyogrio", "geo", what)
    if parquet:
        _require("pyarrow", "geo", what)
    return gpd, pyogrio


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return text.split("; It might help")[0].rstrip(".;")


def read_features(path, name: str, *, layer: str | None = None, crs=None, repair: bool = True) -> Features:
    """Read the features of one layer of a geodata file.

    Parameters
    ----------
    path : str or Path
        A GeoPackage, Shapefile, GeoJSON (a Feature or a FeatureCollection), FlatGeobuf or GeoParquet file.
    name : {"gpkg", "shp", "geojson", "fgb", "parquet"}
        Its format (see `GEODATA`).
    layer : str, optional
        The layer to read; needed when the file has several (a GeoPackage may).
    crs : pyproj.CRS or str, optional
        The CRS of the coordinates, for a layer that has none (or a wrong one): it replaces the file's.
        Anything ``pyproj.CRS.from_user_input`` takes ("EPSG:25832", a WKT, a PROJ string).
    repair : bool
        Repair invalid polygons, each alone (``shapely.make_valid``, with a counted `RepairWarning`).

    Returns
    -------
    Features
        ``meta`` has ``crs`` (``pyproj.CRS`` or None), ``units`` (`crs_units` of it: ``"m"``, ``"us_ft"``…,
        None for degrees), ``layer``, ``geometry_name``, ``format``, and for a Shapefile whose ``.prj`` GDAL
        cannot read, ``crs_unreadable=True``.

    Raises
    ------
    InvalidGeometryError
        The file cannot be read as that format (corrupt, truncated), or has no geometry column.
    ValueError
        The file has several layers and ``layer`` is None, or has no layer ``layer``.
    CRSError
        The file's CRS cannot be read, or ``crs`` is not a CRS.
    MissingDependencyError
        The ``geo`` extra is not installed.

    Examples
    --------
    >>> import tempfile, pathlib, json
    >>> fc = {"type": "FeatureCollection", "features": [
    ...     {"type": "Feature", "properties": {"id": 7},
    ...      "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 4], [0, 0]]]}}]}
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "f.geojson"
    ...     _ = p.write_text(json.dumps(fc))
    ...     f = read_features(p, "geojson")
    >>> len(f), f.attributes["id"].tolist(), f.meta["crs"].to_epsg()      # GeoJSON is WGS 84 (RFC 7946)
    (1, [7], 4326)
    """
    path = Path(path)
    driver, label = GEODATA[name]
    gpd, pyogrio = _libraries(f"reading {label}", parquet=driver is None)
    given_crs = parse_crs(crs, "crs") if crs is not None else None
    if not path.exists():
        raise FileNotFoundError(2, "No such file or directory", str(path))
    geometry_name = None
    try:
        if driver is None:
            if layer is not None:
                raise ValueError(f"{path}: a GeoParquet file has one table; --layer does not apply")
            frame = gpd.read_parquet(path)
            layer_name = path.stem
            geometry_name = frame.geometry.name
        else:
            layers = pyogrio.list_layers(path)
            names = [str(x) for x in layers[:, 0]]
            if not names:
                raise InvalidGeometryError(f"{path}: malformed {label} (no layer found)")
            if layer is None:
                if len(names) > 1:
                    raise ValueError(f"{path} has {len(names)} layers ({', '.join(names)}); choose one "
                                     "with --layer")
                layer_name = names[0]
            elif layer not in names:
                raise ValueError(f"{path} has no layer {layer!r}; its layers: {', '.join(names)}")
            else:
                layer_name = layer
            info = pyogrio.read_info(path, layer=layer_name)
            geometry_name = info.get("geometry_name") or None
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # GDAL's notes on field types
                frame = pyogrio.read_dataframe(path, layer=layer_name)
    except (ValueError, InvalidGeometryError) as exc:
        if type(exc).__module__.startswith(("pyogrio", "pyarrow")):
            raise InvalidGeometryError(f"{path}: malformed {label} ({_first_line(exc)})") from None
        raise
    except pyogrio.errors.CRSError as exc:
        from vectortighten.errors import CRSError

        hint = "fix or remove its .prj" if name == "shp" else "fix it"
        raise CRSError(f"{path}: its CRS cannot be read ({_first_line(exc)}); {hint}, then give the CRS "
                       "with --crs") from None
    except (pyogrio.errors.DataSourceError, pyogrio.errors.DataLayerError, pyogrio.errors.FieldError,
            pyogrio.errors.GeometryError, OSError, RuntimeError) as exc:
        if isinstance(exc, FileNotFoundError):
            raise
        raise InvalidGeometryError(f"{path}: malformed {label} ({_first_line(exc)})") from None
    if not isinstance(frame, gpd.GeoDataFrame) or frame.geometry is None:
        raise InvalidGeometryError(f"{path}: layer {layer_name!r} has no geometry column")
    geometry = np.asarray(frame.geometry.array, dtype=object)
    attributes = frame.drop(columns=[frame.geometry.name])
    crs = frame.crs if given_crs is None else given_crs
    meta = {"crs": crs, "units": crs_units(crs), "layer": layer_name, "geometry_name": geometry_name,
            "format": name}
    if crs is None and name == "shp" and any(path.with_suffix(e).exists() for e in (".prj", ".PRJ")):
        meta["crs_unreadable"] = True
    if repair and len(geometry):
        from vectortighten.vectorized import _repair_each

        geometry, _ = _repair_each(geometry, stacklevel=3)
    return Features(geometry, attributes, meta)


def result_features(result, meta: dict | None = None) -> Features:
    """One feature: the sampled geometry of a `Tightening` with its measures as attributes.

    ``meta`` is the input's (`vectortighten.io.read_source`): its CRS and layer name are kept; an input
    that is not geodata (SVG, DXF, WKT) gives a feature with no CRS.
    """
    pd = _require("pandas", "geo", "writing geodata")
    meta = meta or {}
    attributes = pd.DataFrame({"r": [result.r], "init": [result.init], "perimeter": [result.perimeter],
                               "area": [result.area], "n_components": [result.n_components],
                               "n_holes": [result.n_holes]})
    keep = {k: meta[k] for k in ("crs", "layer") if meta.get(k) is not None}
    return Features(np.array([result.geometry], dtype=object), attributes, {"crs": None, **keep})


def parse_crs(text, what: str = "crs"):
    """A ``pyproj.CRS`` from anything ``pyproj.CRS.from_user_input`` takes; `CRSError` naming ``what``.

    Examples
    --------
    >>> parse_crs("EPSG:32631").to_epsg()
    32631
    """
    pyproj = _require("pyproj", "geo", what)
    if isinstance(text, pyproj.CRS):
        return text
    try:
        return pyproj.CRS.from_user_input(text)
    except pyproj.exceptions.CRSError as exc:
        from vectortighten.errors import CRSError

        detail = str(exc).splitlines()[0] if str(exc) else "not understood"
        raise CRSError(f"{what} {text}: not a CRS that pyproj knows ({detail})") from None


def _frame(features: Features, gpd):
    import pandas as pd

    attributes = features.attributes if features.attributes is not None else pd.DataFrame(
        index=pd.RangeIndex(len(features)))
    geometry = gpd.GeoSeries(features.geometry, index=attributes.index, crs=features.meta.get("crs"))
    name = features.meta.get("geometry_name") or "geometry"
    if name in attributes.columns:
        name = "geometry"
    return gpd.GeoDataFrame(attributes.copy(), geometry=geometry.rename(name), crs=features.meta.get("crs"))


def write_features(features: Features, path, name: str) -> None:
    """Write features to a geodata file, atomically, with their attributes and CRS unchanged.

    The layer keeps the name it was read with (``meta["layer"]``; else the file's stem), a GeoPackage its
    geometry column's name. A Shapefile is written into a temporary folder beside ``path`` and its files
    renamed into place only when all are complete.

    Parameters
    ----------
    features : Features
    path : str or Path
        The output file; its folder must exist.
    name : {"gpkg", "shp", "geojson", "fgb", "parquet"}
        Its format.

    Raises
    ------
    ValueError
        GDAL refuses the features (a Shapefile takes one geometry type), with nothing written.
    """
    path = Path(path)
    driver, label = GEODATA[name]
    gpd, pyogrio = _libraries(f"writing {label}", parquet=driver is None)
    frame = _frame(features, gpd)
    layer = features.meta.get("layer") or path.stem
    if driver is None:
        with atomic_path(path) as tmp:
            frame.to_parquet(tmp)
        return
    options = {}
    if name == "gpkg" and features.meta.get("geometry_name"):
        options["GEOMETRY_NAME"] = features.meta["geometry_name"]
    if name == "fgb":
        # FlatGeobuf's spatial index sorts the features along a Hilbert curve (and takes no empty
        # geometry): without it, the output keeps the input's order, one feature for one.
        options["SPATIAL_INDEX"] = "NO"
    try:
        with warnings.catch_warnings():
            # A plain shape (WKT, SVG, bare GeoJSON) has no CRS, and its output says none on purpose.
            warnings.filterwarnings("ignore", "'crs' was not provided", UserWarning)
            if name == "shp":
                _write_shapefile(frame, path, pyogrio)
            else:
                with atomic_path(path) as tmp:
                    pyogrio.write_dataframe(frame, tmp, driver=driver, layer=layer,
                                            layer_options=options or None)
    except (pyogrio.errors.FeatureError, pyogrio.errors.GeometryError, pyogrio.errors.FieldError,
            pyogrio.errors.DataLayerError) as exc:
        raise ValueError(f"{path}: cannot write it as {label} ({_first_line(exc)}); nothing was "
                         "written") from None


def _write_shapefile(frame, path: Path, pyogrio) -> None:
    """A Shapefile's several files written beside ``path`` in a temporary folder, then renamed."""
    if not path.parent.is_dir():
        raise FileNotFoundError(2, "output folder does not exist", str(path.parent))
    tmp = tempfile.mkdtemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # GDAL's notes on field names it shortens
            pyogrio.write_dataframe(frame, os.path.join(tmp, path.name), driver="ESRI Shapefile",
                                    layer=path.stem)
        made = os.listdir(tmp)
        for ext in _SHAPEFILE_OPTIONAL:
            old = path.with_suffix(ext)
            if path.stem + ext not in made and old.exists():
                old.unlink()
        # The .shp last: a reader never finds a new .shp beside the old .dbf.
        for f in sorted(made, key=lambda f: f.lower().endswith(".shp")):
            os.replace(os.path.join(tmp, f), path.parent / f)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
