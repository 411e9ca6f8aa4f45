"""Reading shapes from files and writing tightenings to them, chosen by the file's extension.

Every writer goes through `atomic_write`: the output is written to a temporary file in the same folder and
renamed over the target only when complete, so a failed run leaves no partial file and an existing output
untouched.
"""

from __future__ import annotations

import json
import os
import tempfile
import warnings
from contextlib import contextmanager
from pathlib import Path

import shapely
from shapely.geometry import MultiPolygon, Polygon, mapping, shape

from .errors import GeometryTypeError, InvalidGeometryError

__all__ = ["atomic_write", "read_shape", "write_result", "READ_FORMATS", "WRITE_FORMATS"]

READ_FORMATS = (".wkt", ".geojson", ".json")
WRITE_FORMATS = (".wkt", ".geojson", ".json")


@contextmanager
def atomic_write(path, mode: str = "w"):
    """Open a temporary file beside ``path`` for writing; rename it onto ``path`` only on success.

    Parameters
    ----------
    path : str or Path
        The final file. Its folder must exist.
    mode : {"w", "wb"}
        Text or binary.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "x.txt"
    ...     with atomic_write(p) as f:
    ...         _ = f.write("hello")
    ...     p.read_text()
    'hello'
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(2, "output folder does not exist", str(path.parent))
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, mode, **({} if "b" in mode else {"encoding": "utf-8"})) as f:
            yield f
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _polygonal(geom, source: str) -> Polygon | MultiPolygon:
    """Keep the polygons of ``geom``; refuse a geometry that has none."""
    if isinstance(geom, (Polygon, MultiPolygon)):
        return geom
    parts = [g for g in shapely.get_parts(geom) if isinstance(g, (Polygon, MultiPolygon))]
    if not parts:
        raise GeometryTypeError(f"{source}: no polygons found (got {geom.geom_type})")
    return shapely.union_all(parts)


def read_shape(path) -> Polygon | MultiPolygon:
    """Read a polygonal shape from a WKT or GeoJSON file.

    GeoJSON may be a bare geometry, a Feature or a FeatureCollection; all polygons are united.

    Parameters
    ----------
    path : str or Path
        ``.wkt``, ``.geojson`` or ``.json``.

    Returns
    -------
    Polygon or MultiPolygon

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.wkt"
    ...     _ = p.write_text("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0))")
    ...     read_shape(p).area
    16.0
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in READ_FORMATS:
        raise ValueError(f"{path}: unsupported input format {ext or '(none)'!r}; "
                         f"expected one of {', '.join(READ_FORMATS)}")
    text = path.read_text(encoding="utf-8")
    if ext == ".wkt":
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # GEOS warns on NaN; check_shape names it
                geom = shapely.from_wkt(text.strip())
        except shapely.errors.ShapelyError as exc:
            raise InvalidGeometryError(f"{path}: malformed WKT ({exc})") from None
    else:
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InvalidGeometryError(f"{path}: malformed JSON ({exc.msg} at line {exc.lineno})") from None
        geoms = []
        try:
            if isinstance(data, dict) and data.get("type") == "FeatureCollection":
                geoms = [shape(f["geometry"]) for f in data.get("features", []) if f.get("geometry")]
            elif isinstance(data, dict) and data.get("type") == "Feature":
                geoms = [shape(data["geometry"])] if data.get("geometry") else []
            else:
                geoms = [shape(data)]
        except (KeyError, TypeError, ValueError, AttributeError, shapely.errors.ShapelyError) as exc:
            raise InvalidGeometryError(f"{path}: malformed GeoJSON ({exc})") from None
        if not geoms:
            raise InvalidGeometryError(f"{path}: no geometry found")
        geom = shapely.union_all(geoms) if len(geoms) > 1 else geoms[0]
    if geom is None or geom.is_empty:
        raise InvalidGeometryError(f"{path}: the geometry is empty")
    return _polygonal(geom, str(path))


def write_result(result, path) -> None:
    """Write a `Tightening` (its sampled geometry) to ``path``, format by extension, atomically.

    Parameters
    ----------
    result : Tightening
    path : str or Path
        ``.wkt``, ``.geojson`` or ``.json``.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if ext not in WRITE_FORMATS:
        raise ValueError(f"{path}: unsupported output format {ext or '(none)'!r}; "
                         f"expected one of {', '.join(WRITE_FORMATS)}")
    geom = result.geometry
    if ext == ".wkt":
        text = shapely.to_wkt(geom, rounding_precision=-1) + "\n"
    else:
        feature = {
            "type": "Feature",
            "geometry": mapping(geom),
            "properties": {"r": result.r, "init": result.init, "perimeter": result.perimeter,
                           "area": result.area, "n_components": result.n_components,
                           "n_holes": result.n_holes},
        }
        text = json.dumps({"type": "FeatureCollection", "features": [feature]})
    with atomic_write(path) as f:
        f.write(text)
