"""Reading shapes from files and writing tightenings to them, through one table of formats.

Each family of files has its module — `svg`, `dxf`, `geo` (WKT and GeoJSON), `mask` (mask and label
images: PNG, TIFF, BMP, GIF, JPEG, for the pixel method or traced to vectors), `picture` (a rendering) — and registers what it reads and writes in `FORMATS`, keyed by
the format's name with the extensions it owns. `read_shape` and `write_result` look the extension up
there (``format=`` overrides it); the command line reads the same table for ``--format`` and its help.

Every writer goes through `atomic_write` or `atomic_path`: the output is written to a temporary file in
the same folder and renamed over the target only when complete, so a failed run leaves no partial file
and an existing output untouched.

Optional packages (svgelements and defusedxml for SVG, ezdxf for DXF) are imported only when a file of
theirs is met; without them a `MissingDependencyError` names the extra to install.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from shapely.geometry import MultiPolygon, Polygon

from . import dxf, geo, picture, svg
from ._common import LAYERS, MissingDependencyError, _check_layers, _polygonal, atomic_path, atomic_write
from ._fill import fill_rings
from .mask import read_mask, tighten_image_file, trace_tighten, write_mask
from .svg import DEFAULT_FLATTEN, read_svg, svg_document, svg_unit

__all__ = [
    "DEFAULT_FLATTEN",
    "FORMATS",
    "LAYERS",
    "READ_FORMATS",
    "WRITE_FORMATS",
    "Format",
    "MissingDependencyError",
    "atomic_path",
    "atomic_write",
    "fill_rings",
    "format_of",
    "read_mask",
    "read_shape",
    "read_svg",
    "svg_document",
    "svg_unit",
    "tighten_image_file",
    "trace_tighten",
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
        ``read(path, **options) -> Polygon | MultiPolygon`` for a vector format; None if not readable.
    write : callable or None
        ``write(result, path, *, layers, unit)``, atomic; None if not writable.
    kind : {"vector", "mask"}
        A vector format holds shapes for the exact engine; a mask format holds images for the pixel method.
    """

    name: str
    extensions: tuple[str, ...]
    read: Callable | None
    write: Callable | None
    kind: str = "vector"


def _write_text(text_of: Callable) -> Callable:
    def write(result, path, *, layers=(), unit=None):
        with atomic_write(path) as f:
            f.write(text_of(result, layers=layers, unit=unit))
    return write


def _write_dxf(result, path, *, layers=(), unit=None):
    dxf._require("ezdxf", "dxf", "writing DXF")
    with atomic_path(path) as tmp:
        dxf.write_dxf(result, tmp, layers, unit)          # looked up when called (tests replace it)


def _write_picture(result, path, *, layers=(), unit=None):
    with atomic_write(path, "wb") as f:
        picture.write_picture(result, f, layers)


def _read_geometry(reader: Callable) -> Callable:
    def read(path, **_options):
        return _polygonal(reader(path), str(path))
    return read


#: Every format, by name. A mask format (PNG, TIFF, BMP, GIF, JPEG) is read by `read_mask` or
#: `tighten_image_file`; a vector result is drawn into a PNG.
FORMATS: dict[str, Format] = {
    "svg": Format("svg", (".svg",), lambda path, flatten=None, **_: read_svg(path, flatten=flatten),
                  _write_text(lambda result, **kw: svg.svg_document(result, **kw))),
    "wkt": Format("wkt", (".wkt",), _read_geometry(geo.read_wkt),
                  _write_text(lambda result, **_: geo.wkt_text(result))),
    "geojson": Format("geojson", (".geojson", ".json"), _read_geometry(geo.read_geojson),
                      _write_text(lambda result, **_: geo.geojson_text(result))),
    "dxf": Format("dxf", (".dxf",), None, _write_dxf),
    "png": Format("png", (".png",), None, _write_picture, kind="mask"),
    "tiff": Format("tiff", (".tif", ".tiff"), None, None, kind="mask"),
    "bmp": Format("bmp", (".bmp",), None, None, kind="mask"),
    "gif": Format("gif", (".gif",), None, None, kind="mask"),
    "jpeg": Format("jpeg", (".jpg", ".jpeg"), None, None, kind="mask"),
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


def read_shape(path, *, flatten: float | None = None, format: str | None = None) -> Polygon | MultiPolygon:
    """Read a polygonal shape from a vector file (SVG, WKT, GeoJSON).

    Parameters
    ----------
    path : str or Path
        ``.svg``, ``.wkt``, ``.geojson`` or ``.json``. GeoJSON may be a bare geometry, a Feature or a
        FeatureCollection; all polygons are united.
    flatten : float, optional
        SVG only: largest distance between a curve and its chords, in the drawing's user units. Default
        `DEFAULT_FLATTEN` times the diagonal of the drawing.
    format : str, optional
        The format's name (see `FORMATS`), when the extension does not tell.

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
        raise ValueError(f"{path}: {fmt.name.upper()} files cannot be read yet; "
                         f"expected one of {', '.join(READ_FORMATS + _MASK_IN)}")
    return fmt.read(path, flatten=flatten)


def write_result(result, path, *, layers=(), unit: str | None = None, format: str | None = None) -> None:
    """Write a `Tightening` to ``path``, format by extension (or ``format``), atomically.

    Parameters
    ----------
    result : Tightening
    path : str or Path
        ``.svg`` (exact arcs, see `svg_document`), ``.wkt`` and ``.geojson`` / ``.json`` (the sampled
        geometry, within the result's tolerance), ``.dxf`` (LINE and ARC entities on layer
        ``TIGHTENING``; each ARC has radius exactly r and runs counter-clockwise, as DXF requires) or
        ``.png`` (a picture).
    layers : iterable of {"input", "core", "mortar"}
        SVG, DXF and PNG: also draw these, each in its own layer.
    unit : {"mm", "cm", "in", "pt", "pc", "px"}, optional
        SVG: the document's ``width`` and ``height`` in this unit (true size); DXF: ``$INSUNITS`` (mm, cm
        and in only). Typically `svg_unit` of the input.
    format : str, optional
        The format's name (see `FORMATS`), when the extension does not tell.

    Raises
    ------
    ValueError
        Unsupported extension or unknown layer.
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
    fmt.write(result, path, layers=layers, unit=unit)
