"""WKT and GeoJSON."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import mapping, shape

from vectortighten.errors import InvalidGeometryError

from ._common import _read_text

__all__ = ["geojson_text", "read_geojson", "read_wkt", "wkt_text"]


def read_wkt(path: Path):
    """The geometry of a WKT file (not yet checked to be polygonal)."""
    text = _read_text(path, "WKT").strip()
    if not text:
        raise InvalidGeometryError(f"{path}: malformed WKT (the file is empty)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # GEOS warns on NaN; _polygonal names it
            return shapely.from_wkt(text)
    except shapely.errors.ShapelyError as exc:
        raise InvalidGeometryError(f"{path}: malformed WKT ({exc})") from None


def read_geojson(path: Path):
    """The geometries of a GeoJSON file (a geometry, a Feature or a FeatureCollection), united."""
    try:
        data = json.loads(_read_text(path, "GeoJSON"))
    except json.JSONDecodeError as exc:
        raise InvalidGeometryError(f"{path}: malformed GeoJSON ({exc.msg} at line {exc.lineno})") from None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # GEOS warns on NaN; checked below
            if isinstance(data, dict) and data.get("type") == "FeatureCollection":
                geoms = [shape(f["geometry"]) for f in data["features"] if f.get("geometry")]
            elif isinstance(data, dict) and data.get("type") == "Feature":
                geoms = [shape(data["geometry"])] if data.get("geometry") else []
            else:
                geoms = [shape(data)]
    except (KeyError, TypeError, ValueError, AttributeError, IndexError, shapely.errors.ShapelyError) as exc:
        detail = f"missing {exc}" if isinstance(exc, KeyError) else str(exc) or type(exc).__name__
        raise InvalidGeometryError(f"{path}: malformed GeoJSON ({detail})") from None
    if not geoms:
        raise InvalidGeometryError(f"{path}: no geometry found")
    for g in geoms:
        if not np.isfinite(shapely.get_coordinates(g)).all():
            raise InvalidGeometryError(f"{path}: NaN or infinite coordinates")
    return shapely.union_all(geoms) if len(geoms) > 1 else geoms[0]


def wkt_text(result) -> str:
    """The sampled geometry of a `Tightening` as WKT (full precision), one line."""
    return shapely.to_wkt(result.geometry, rounding_precision=-1) + "\n"


def geojson_text(result) -> str:
    """The sampled geometry of a `Tightening` as a GeoJSON FeatureCollection of one Feature."""
    feature = {
        "type": "Feature",
        "geometry": mapping(result.geometry),
        "properties": {"r": result.r, "init": result.init, "perimeter": result.perimeter,
                       "area": result.area, "n_components": result.n_components,
                       "n_holes": result.n_holes},
    }
    return json.dumps({"type": "FeatureCollection", "features": [feature]})
