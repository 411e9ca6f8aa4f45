"""Reading shapes from files and writing tightenings to them, through one table of formats.

Each family of files has its module — `svg`, `dxf`, `geo` (WKT and the geodata formats: GeoPackage,
Shapefile, GeoJSON, FlatGeobuf, GeoParquet), `mask` (mask and label images: PNG, TIFF, BMP, GIF, JPEG, for
the pixel method or traced to vectors), `picture` (a rendering) — and registers what it reads and writes
in `FORMATS`, keyed by the format's name with the extensions it owns. `read_source`, `read_shape`,
`read_features`, `write_result` and `write_features` look the extension up there (``format=`` overrides
it); the command line reads the same table for ``--format``, its help and its option checks.

A reader hands over what must travel to the writer, in one vocabulary (see `Source`): `read_source`
gives a `Source` (the shape, its exact boundary as `Loop`s where the file has one, and ``meta``: units,
page, position, styles, CRS, layer), and ``write_result(..., meta=source.meta)`` puts the result back in
the input's frame (a DXF in the input's ``$INSUNITS`` at its coordinates, an SVG on the input's page, a
GeoPackage in the input's CRS). A format that holds *features* (a geometry each, with attributes, in a
layer with a CRS) also has ``read_features`` and ``write_features``: `read_features` returns `Features`
(geometries, attributes and the same ``meta``) and `write_features` writes them back with everything but
the geometry unchanged. Options that only some formats take are declared in their `Format`
(``read_options``, ``write_options``) and refused elsewhere.

Every writer goes through `atomic_write` or `atomic_path`: the output is written to a temporary file in
the same folder and renamed over the target only when complete, so a failed run leaves no partial file
and an existing output untouched.

Optional packages (svgelements and defusedxml for SVG, ezdxf for DXF and for joining an SVG's loose
outlines, pyogrio, GeoPandas, pyproj and pyarrow for geodata) are imported only when a file of theirs is
met; without them a `MissingDependencyError` names the extra to install.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from shapely.geometry import MultiPolygon, Polygon

from . import dxf, geo, picture, svg
from ._common import LAYERS, MissingDependencyError, _check_layers, _polygonal, atomic_path, atomic_write
from ._fill import fill_rings
from ._outline import DEFAULT_GAP
from ._source import INSUNITS, MM_PER_UNIT, Features, Source
from .dxf import DXF_ENTITIES, read_dxf
from .mask import MASK_READ_OPTIONS, read_mask, tighten_image_file, trace_tighten, write_mask
from .svg import DEFAULT_FLATTEN, NESTINGS, load_svg, read_svg, svg_document, svg_unit

__all__ = [
    "DEFAULT_FLATTEN",
    "DEFAULT_GAP",
    "DXF_ENTITIES",
    "FORMATS",
    "Features",
    "INSUNITS",
    "LAYERS",
    "MM_PER_UNIT",
    "NESTINGS",
    "READ_FORMATS",
    "WRITE_FORMATS",
    "Format",
    "MissingDependencyError",
    "Source",
    "atomic_path",
    "atomic_write",
    "fill_rings",
    "format_of",
    "load_svg",
    "read_dxf",
    "read_features",
    "loops_of",
    "read_loops",
    "read_mask",
    "read_shape",
    "read_source",
    "read_svg",
    "svg_document",
    "svg_unit",
    "tighten_image_file",
    "trace_tighten",
    "write_features",
    "write_mask",
    "write_result",
]


@dataclass(frozen=True)
class Format:
    """One file format: the extensions it owns and how shapes are read from it and results written to it.

    Attributes
    ----------
    name : str
        What ``--format`` and ``format=`` call it.
    extensions : tuple of str
        Lower-case, with the dot; the first is the one an output is named with.
    read : callable or None
        ``read(path, *, flatten, **read_options) -> Source`` for a vector format (a reader may also return
        a bare Polygon or MultiPolygon, which `read_source` wraps); None if not readable as one shape.
    write : callable or None
        ``write(result, path, *, layers, unit, meta, **write_options)``, atomic; None if not writable.
    kind : {"vector", "mask"}
        A vector format holds shapes (or features) for the exact engine; a mask format holds images for
        the pixel method (read by `read_mask` and `tighten_image_file`).
    read_options, write_options : tuple of str
        The keyword options only this format's reader or writer takes (e.g. ``"layers"`` for DXF input,
        ``"layer"`` and ``"crs"`` for a geodata layer, ``"threshold"`` for an image, ``"keep_style"`` for
        SVG output); `read_source`, `read_features`, `write_result` and `write_features` refuse them for
        other formats, and so does the command line.
    read_features : callable or None
        ``read_features(path, **read_options) -> Features | None`` for a format that holds features (None
        back: this file holds one plain geometry, read it with ``read``); None if the format holds shapes.
    write_features : callable or None
        ``write_features(features, path)``, atomic, every attribute and ``meta`` entry it knows kept.
    label : str
        What messages call it ("GeoPackage"); default the upper-case name.
    """

    name: str
    extensions: tuple[str, ...]
    read: Callable | None
    write: Callable | None
    kind: str = "vector"
    read_options: tuple[str, ...] = ()
    write_options: tuple[str, ...] = ()
    read_features: Callable | None = None
    write_features: Callable | None = None
    label: str = ""

    @property
    def title(self) -> str:
        """The format's name in messages."""
        return self.label or self.name.upper()

    @property
    def holds_features(self) -> bool:
        """Whether files of this format are layers of features (geodata)."""
        return self.read_features is not None


def _write_text(text_of: Callable) -> Callable:
    def write(result, path, *, layers=(), unit=None, meta=None, **options):
        with atomic_write(path) as f:
            f.write(text_of(result, layers=layers, unit=unit, meta=meta, **options))
    return write


def _write_dxf(result, path, *, layers=(), unit=None, meta=None, dxf_entities="lines-arcs"):
    dxf._require("ezdxf", "dxf", "writing DXF")
    if dxf_entities not in DXF_ENTITIES:
        raise ValueError(f"dxf_entities must be one of {', '.join(DXF_ENTITIES)}, got {dxf_entities!r}")
    with atomic_path(path) as tmp:
        # looked up when called (tests replace it)
        dxf.write_dxf(result, tmp, layers, unit, meta, dxf_entities)


def _write_picture(result, path, *, layers=(), unit=None, meta=None):
    with atomic_write(path, "wb") as f:
        picture.write_picture(result, f, layers)


def _read_geometry(reader: Callable) -> Callable:
    def read(path, **_options):
        return _polygonal(reader(path), str(path))
    return read


def _read_svg(path, flatten=None, **options) -> Source:
    return load_svg(path, flatten=flatten, **options)


def _read_dxf(path, flatten=None, **options) -> Source:
    return dxf.read_dxf(path, flatten=flatten, **options)


#: What a geodata layer's reader takes: the layer of a file that has several, and the CRS of a layer
#: that has none (or a wrong one).
_GEODATA_READ_OPTIONS = ("layer", "crs")


def _geodata(name: str, extensions: tuple[str, ...]) -> Format:
    """A geodata format: features read and written through pyogrio (GeoParquet through GeoPandas)."""

    def read(path, flatten=None, **options) -> Source:
        source = geo.read_source(path, name, **options)
        source.shape = _polygonal(source.shape, str(path))
        return source

    def read_features(path, **options):
        if name == "geojson" and geo.geojson_is_plain(path):
            return None
        return geo.read_features(path, name, **options)

    def write_features(features, path):
        geo.write_features(features, path, name)

    def write(result, path, *, layers=(), unit=None, meta=None):
        geo.write_features(geo.result_features(result, meta), path, name)

    return Format(name, extensions, read, write, read_options=_GEODATA_READ_OPTIONS,
                  read_features=read_features, write_features=write_features, label=geo.GEODATA[name][1])


def _mask(name: str, extensions: tuple[str, ...], write: Callable | None = None) -> Format:
    return Format(name, extensions, None, write, kind="mask", read_options=MASK_READ_OPTIONS)


#: Every format, by name. A mask format (PNG, TIFF, BMP, GIF, JPEG) is read by `read_mask` or
#: `tighten_image_file`; a vector result is drawn into a PNG. The geodata formats hold features.
FORMATS: dict[str, Format] = {
    "svg": Format("svg", (".svg",), _read_svg,
                  _write_text(lambda result, meta=None, **kw: svg.svg_document(result, meta=meta, **kw)),
                  read_options=("nesting", "gap"), write_options=("keep_style", "stroke_only")),
    "wkt": Format("wkt", (".wkt",), lambda path, flatten=None, **_: geo.read_wkt_source(path, flatten),
                  _write_text(lambda result, **_: geo.wkt_text(result))),
    "geojson": _geodata("geojson", (".geojson", ".json")),
    "gpkg": _geodata("gpkg", (".gpkg",)),
    "shp": _geodata("shp", (".shp",)),
    "fgb": _geodata("fgb", (".fgb",)),
    "parquet": _geodata("parquet", (".parquet", ".geoparquet")),
    "dxf": Format("dxf", (".dxf",), _read_dxf, _write_dxf, read_options=("layers", "gap"),
                  write_options=("dxf_entities",)),
    "png": _mask("png", (".png",), _write_picture),
    "tiff": _mask("tiff", (".tif", ".tiff")),
    "bmp": _mask("bmp", (".bmp",)),
    "gif": _mask("gif", (".gif",)),
    "jpeg": _mask("jpeg", (".jpg", ".jpeg")),
}

#: Extensions `read_shape` understands (images go to `read_mask` or `tighten_image_file` instead).
READ_FORMATS = tuple(e for f in FORMATS.values() if f.read is not None for e in f.extensions)
_MASK_IN = tuple(e for f in FORMATS.values() if f.kind == "mask" for e in f.extensions)
#: Extensions `write_result` writes.
WRITE_FORMATS = tuple(e for f in FORMATS.values() if f.write is not None for e in f.extensions)


def format_of(path, format: str | None = None) -> Format:
    """The `Format` of ``path``: by ``format`` (a name or an extension) if given, else by its extension.

    Raises
    ------
    ValueError
        Neither names a known format.

    Examples
    --------
    >>> format_of("part.GeoJSON").name, format_of("x.txt", "wkt").name
    ('geojson', 'wkt')
    """
    if format is not None:
        key = format.lower().lstrip(".")
        for f in FORMATS.values():
            if key == f.name or f".{key}" in f.extensions:
                return f
        raise ValueError(f"unknown format {format!r}; expected one of {', '.join(FORMATS)}")
    ext = Path(path).suffix.lower()
    for f in FORMATS.values():
        if ext in f.extensions:
            return f
    raise ValueError(f"{path}: unsupported format {ext or '(none)'!r}; expected one of "
                     f"{', '.join(e for f in FORMATS.values() for e in f.extensions)}")


def _check_options(fmt: Format, options: dict, allowed: tuple[str, ...], what: str) -> None:
    bad = sorted(k for k in options if k not in allowed)
    if bad:
        def options_of(f):
            return f.read_options if what == "input" else f.write_options

        takes = {k for f in FORMATS.values() for k in options_of(f)}
        key = bad[0]
        if key in takes:
            owners = [f.title for f in FORMATS.values() if key in options_of(f)]
            raise ValueError(f"{key} is an option of {' and '.join(owners)} {what}, not {fmt.title}")
        raise TypeError(f"unknown {what} option {key!r}")


def read_source(path, *, flatten: float | None = None, format: str | None = None, **options) -> Source:
    """Read a vector file into a `Source`: the shape, its exact boundary and what travels to the writer.

    Parameters
    ----------
    path : str or Path
        ``.svg``, ``.dxf``, ``.wkt``, ``.geojson`` or ``.json``, ``.gpkg``, ``.shp``, ``.fgb``, ``.parquet``.
        The features of a geodata layer are repaired one by one and then united into one shape: to
        tighten them one by one, use `read_features` and `vectortighten.tighten_all` (the command line
        does).
    flatten : float, optional
        SVG and DXF: largest distance between a curve and its chords, in the drawing's units. Default
        `DEFAULT_FLATTEN` times the diagonal of the drawing.
    format : str, optional
        The format's name (see `FORMATS`), when the extension does not tell.
    **options
        Options of the format's reader (its `Format.read_options`): SVG ``nesting`` (see `load_svg`) and
        ``gap``; DXF ``layers`` and ``gap`` (see `read_dxf`); geodata ``layer`` and ``crs`` (see
        `read_features`).

    Returns
    -------
    Source
        ``shape``, ``loops`` (None where the reader keeps no exact boundary) and ``meta`` (for geodata:
        ``crs``, ``units``, ``layer``, which `write_result` takes back to a geodata output).

    Raises
    ------
    InvalidGeometryError, GeometryTypeError, OSError
        As `read_shape`.
    ValueError
        An option of another format.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.svg"
    ...     _ = p.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40mm" height="20mm" '
    ...                      'viewBox="0 0 40 20"><rect width="40" height="20" fill="none" stroke="red"/>'
    ...                      '<circle cx="10" cy="10" r="4" fill="none" stroke="red"/></svg>')
    ...     src = read_source(p)
    >>> src.units, src.meta["nesting"], len(src.loops), round(sum(lp.area for lp in src.loops), 6)
    ('mm', 'evenodd', 2, 749.734518)
    """
    path = Path(path)
    try:
        fmt = format_of(path, format)
    except ValueError:
        if format is not None:
            raise
        raise ValueError(f"{path}: unsupported input format {path.suffix.lower() or '(none)'!r}; "
                         f"expected one of {', '.join(READ_FORMATS + _MASK_IN)}") from None
    if fmt.kind == "mask":
        raise ValueError(f"{path}: a {fmt.name.upper()} is a mask for the pixel method; "
                         "read it with read_mask")
    if fmt.read is None:
        raise ValueError(f"{path}: {fmt.title} files cannot be read yet; "
                         f"expected one of {', '.join(READ_FORMATS + _MASK_IN)}")
    _check_options(fmt, options, fmt.read_options, "input")
    got = fmt.read(path, flatten=flatten, **options)
    if isinstance(got, Source):
        got.meta.setdefault("format", fmt.name)
        return got
    return Source(got, {"format": fmt.name})


def read_loops(path, *, format: str | None = None, **options) -> list:
    """Read a vector file's exact boundary as `Loop`s: circles and circular arcs as exact `Arc`s.

    The sibling of `read_shape` for the exact path (``tighten(read_loops(path), r)``): SVG ``<circle>``
    and ``A`` commands with equal radii (under a transform that keeps circles circular), DXF ARC, CIRCLE
    and polyline bulges, WKT ``CIRCULARSTRING`` arcs each become one `Arc` of their own radius, and
    consecutive arcs of one circle are merged (an SVG circle, drawn as two half circles, is one arc of a
    whole turn). Ellipses, Bézier curves and splines are chains of `Segment`s, flattened within the
    reader's tolerance as in `read_shape`. A file without curves gives its polygon's rings as segments.

    Parameters
    ----------
    path : str or Path
        A vector file (see `read_source`).
    format : str, optional
        The format's name, when the extension does not tell.
    **options
        The format's reader options (see `read_source`).

    Returns
    -------
    list of Loop
        Outer boundaries counter-clockwise, holes clockwise, in the file's units (as `read_source`).

    Raises
    ------
    InvalidGeometryError
        The file's outlines do not make a valid boundary (they cross or touch, or shapes are painted over
        each other): read it with `read_shape`, which unites them.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.svg"
    ...     _ = p.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="20">'
    ...                      '<path d="M0 0 H40 V20 H0 Z M14 10 A4 4 0 0 0 6 10 A4 4 0 0 0 14 10 Z"/></svg>')
    ...     plate, hole = read_loops(p)
    >>> [(a.center, a.radius) for a in hole.pieces]        # y flipped: SVG's y points down
    [((10.0, -10.0), 4.0)]
    """
    return loops_of(read_source(path, format=format, **options), str(path))


def loops_of(source: Source, name: str = "the input") -> list:
    """The exact boundary of a `Source` as `Loop`s, as `read_loops` gives it (``name`` for messages)."""
    import shapely

    from vectortighten.curves import Loop
    from vectortighten.errors import InvalidGeometryError
    from vectortighten.loop_input import merge_arcs

    loops = source.loops
    if loops is None:
        if source.meta.get("format") in ("svg", "dxf") or not source.shape.is_valid or source.shape.is_empty:
            raise InvalidGeometryError(f"{name}: the outlines do not make one valid boundary (they cross, "
                                       "touch or are painted over each other); read_shape unites them")
        loops = []
        for poly in getattr(source.shape, "geoms", [source.shape]):
            poly = shapely.orient_polygons(poly, exterior_cw=False)
            loops += [Loop.from_polygon_ring(ring.coords) for ring in [poly.exterior, *poly.interiors]]
    return [merge_arcs(lp) for lp in loops]


def read_shape(path, *, flatten: float | None = None, format: str | None = None,
               **options) -> Polygon | MultiPolygon:
    """Read a polygonal shape from a vector file (SVG, DXF, WKT, geodata): ``read_source(...).shape``.

    Parameters
    ----------
    path : str or Path
        ``.svg``, ``.dxf``, ``.wkt``, ``.geojson`` or ``.json`` (a bare geometry, a Feature or a
        FeatureCollection), ``.gpkg``, ``.shp``, ``.fgb``, ``.parquet``. The features of a geodata file are
        repaired one by one and then united into one shape.
    flatten : float, optional
        SVG and DXF: largest distance between a curve and its chords, in the drawing's units. Default
        `DEFAULT_FLATTEN` times the diagonal of the drawing.
    format : str, optional
        The format's name (see `FORMATS`), when the extension does not tell.
    **options
        The format's reader options (see `read_source`).

    Returns
    -------
    Polygon or MultiPolygon
        Not yet validated: `vectortighten.tighten` repairs invalid polygons (with a warning).

    Raises
    ------
    InvalidGeometryError
        Malformed or empty file, NaN or infinite coordinates, a refused SVG (entities, external DTD).
    GeometryTypeError
        The file holds no polygon (only points or lines).
    OSError
        The file is missing or unreadable.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.wkt"
    ...     _ = p.write_text("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0))")
    ...     read_shape(p).area
    16.0
    """
    return read_source(path, flatten=flatten, format=format, **options).shape


def write_result(result, path, *, layers=(), unit: str | None = None, format: str | None = None,
                 meta: dict | None = None, **options) -> None:
    """Write a `Tightening` to ``path``, format by extension (or ``format``), atomically.

    Parameters
    ----------
    result : Tightening
    path : str or Path
        ``.svg`` (exact arcs, see `svg_document`), ``.wkt`` and the geodata formats ``.geojson`` /
        ``.json``, ``.gpkg``, ``.shp``, ``.fgb``, ``.parquet`` (the sampled geometry, within the result's
        tolerance; geodata as one feature whose attributes are r, init, perimeter, area and the counts),
        ``.dxf`` (LINE and ARC entities on layer ``TIGHTENING``; each ARC has radius exactly r and runs
        counter-clockwise, as DXF requires) or ``.png`` (a picture).
    layers : iterable of {"input", "core", "mortar"}
        SVG, DXF and PNG: also draw these, each in its own layer.
    unit : {"mm", "cm", "in", "pt", "pc", "px"}, optional
        The physical unit of the coordinates, when ``meta`` does not give it. SVG: the document's
        ``width`` and ``height`` in this unit (true size); DXF: ``$INSUNITS`` (mm, cm and in as they are;
        px, pt and pc converted to mm). Without either, a DXF is unitless (``$INSUNITS = 0``).
    format : str, optional
        The format's name (see `FORMATS`), when the extension does not tell.
    meta : dict, optional
        The `Source.meta` of the input (`read_source`): a DXF is written in the input's units and at its
        position (an SVG input mapped as Inkscape's DXF export maps it: y up, the page's bottom-left corner
        at the origin); an SVG keeps the input's page (``width``, ``height``, ``viewBox``); a geodata
        output the input's CRS and layer name.
    **options
        Options of the output format's writer: DXF ``dxf_entities`` (``"lines-arcs"`` or
        ``"lwpolyline"``, see `vectortighten.io.dxf.write_dxf`); SVG ``keep_style`` and ``stroke_only``
        (see `svg_document`).

    Raises
    ------
    ValueError
        Unsupported extension, unknown layer, or an option of another format.
    FileNotFoundError
        The output folder does not exist.
    """
    path = Path(path)
    try:
        fmt = format_of(path, format)
    except ValueError:
        if format is not None:
            raise
        fmt = None
    if fmt is None or fmt.write is None:
        raise ValueError(f"{path}: unsupported output format {path.suffix.lower() or '(none)'!r}; "
                         f"expected one of {', '.join(WRITE_FORMATS)}")
    layers = _check_layers(layers)
    svg._check_unit(unit)
    _check_options(fmt, options, fmt.write_options, "output")
    fmt.write(result, path, layers=layers, unit=unit, meta=meta, **options)


def read_features(path, *, format: str | None = None, **options) -> Features:
    """Read the features of one layer of a geodata file.

    GeoPackage, Shapefile, GeoJSON, FlatGeobuf or GeoParquet (see `FORMATS`).

    Parameters
    ----------
    path : str or Path
    format : str, optional
        The format's name (see `FORMATS`), when the extension does not tell.
    **options
        The reader's options (`Format.read_options`): ``layer``, the layer when the file has several;
        ``crs``, the CRS of the coordinates, replacing the file's (see `vectortighten.io.geo.read_features`).

    Returns
    -------
    Features
        Geometries (invalid polygons repaired one by one, with a counted `RepairWarning`), attributes,
        and ``meta`` with ``crs``, ``units``, ``layer`` and ``geometry_name``. A bare-geometry GeoJSON gives
        one feature with no attributes and no CRS.

    Raises
    ------
    ValueError
        Not a geodata format; several layers and no ``layer``; no such layer; an option of another
        format.
    InvalidGeometryError
        The file is corrupt or has no geometry column.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "s.geojson"
    ...     _ = p.write_text('{"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]]]}')
    ...     f = read_features(p)
    >>> len(f), f.meta["crs"], f.geometry[0].area
    (1, None, 16.0)
    """
    path = Path(path)
    fmt = format_of(path, format)
    if not fmt.holds_features:
        raise ValueError(f"{path}: a {fmt.title} file holds one shape, not features; read it with "
                         "read_source")
    _check_options(fmt, options, fmt.read_options, "input")
    features = fmt.read_features(path, **options)
    if features is None:
        import numpy as np

        source = read_source(path, format=fmt.name, **options)
        features = Features(np.array([source.shape], dtype=object), None,
                            {**source.meta, "layer": path.stem})
    return features


def write_features(features: Features, path, *, format: str | None = None) -> None:
    """Write `Features` to a geodata file, atomically, with their attributes and CRS unchanged.

    Raises
    ------
    ValueError
        Not a geodata format, or GDAL refuses the features (nothing is written then).

    Examples
    --------
    >>> import tempfile, pathlib, numpy as np
    >>> from shapely.geometry import box
    >>> f = Features(np.array([box(0, 0, 2, 2)], dtype=object), meta={"crs": "EPSG:32631", "layer": "x"})
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_features(f, pathlib.Path(d) / "x.gpkg")
    ...     back = read_features(pathlib.Path(d) / "x.gpkg")
    >>> back.meta["crs"].to_epsg(), back.meta["units"], back.geometry[0].area
    (32631, 'm', 4.0)
    """
    path = Path(path)
    fmt = format_of(path, format)
    if fmt.write_features is None:
        exts = ", ".join(e for f in FORMATS.values() if f.write_features for e in f.extensions)
        raise ValueError(f"{path}: {fmt.title} does not hold features; write features to one of {exts}")
    fmt.write_features(features, path)
