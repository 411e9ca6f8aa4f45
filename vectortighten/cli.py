"""The ``vectortighten`` command line.

Every failure a user can cause (a missing file, malformed input, a bad radius, a missing output folder)
ends with exit code 2 and one line on stderr, never a traceback. An internal error (a bug) also prints one
line and exits with code 1; set ``VECTORTIGHTEN_DEBUG=1`` to see its traceback.

Subcommands live in `COMMANDS`: each is a pair of functions, one that adds its sub-parser and one that
runs it and returns the exit code. Adding a subcommand is adding an entry.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from ._geofile import GeoOptions

__all__ = ["COMMANDS", "main"]

_EPILOG_MAIN = """\
examples:
  vectortighten demo -o demo-out
  vectortighten tighten shape.svg -r 2 -o tight.svg
  vectortighten tighten shape.wkt -r 2 -o tight.dxf --init input
  vectortighten tighten drawings/ -r 0.5 -o out/ --format svg --jobs 4
  vectortighten tighten parcels.gpkg --layer parcels -r 2 -o tight.gpkg
  vectortighten compare shape.svg -r 2 --plot check.png
  vectortighten figures -o figs
  python -m vectortighten tighten --help
"""

_EPILOG_TIGHTEN = """\
formats (by extension):
  in:  .svg (paths, curves, arcs, basic shapes, transforms, fill-rule nonzero/evenodd),
       .dxf (LINE, ARC, CIRCLE, LWPOLYLINE/POLYLINE with bulges, ELLIPSE, SPLINE, blocks),
       .wkt (also CURVEPOLYGON, CIRCULARSTRING, COMPOUNDCURVE, MULTISURFACE: arcs
       sampled within --flatten), .geojson/.json (a bare geometry),
       .png .tif .tiff .bmp .gif .jpg (a mask or label image);
       geodata layers: .gpkg, .shp, .geojson/.json (Feature, FeatureCollection), .fgb,
       .parquet (GeoParquet)
  out: .svg (exact arcs as A commands), .wkt, .dxf (LINE and ARC, or LWPOLYLINE),
       .png (a picture; for an image input, the tightened mask), .tif .bmp (image inputs),
       and the geodata formats .gpkg, .shp, .geojson/.json, .fgb, .parquet

masks and label images (the pixel method; r in pixels):
  any non-zero pixel is inside (0/1, 0/255, 0/65535, bool); --threshold V reads a greyscale
  or colour photo (inside where value/full scale >= V). The output image keeps the input's
  size, dtype and values. --labels tightens every label of a label image (0 = background).
  A multi-page TIFF is refused unless --stack (each slice on its own). Images of more than
  8192 x 8192 pixels (all pages counted) are refused. A vector output (.svg, .dxf, ...)
  traces the mask: --trace exact (default) tightens its pixel squares exactly (true arcs),
  --trace contours writes the pixel method's sub-pixel contour. Pixel coordinates:
  x = column, y = -row (SVG: y = row). --labels to geodata (.geojson, .gpkg, ...): one
  feature a label.

cut files (CNC, laser): a DXF, or an SVG whose shapes are all unfilled outlines, is read
as a cut file: closed outlines nest even-odd (a circle inside the plate is a hole), loose
LINE/ARC pieces are joined end to end within --gap. A DXF output is written in the input's
units and at its position ($INSUNITS of a DXF input; an SVG in mm gives mm; an SVG placed
y up with its page's bottom-left corner at the origin, as Inkscape exports it; unitless
input gives $INSUNITS 0). An SVG output keeps an SVG input's page (width, height, viewBox).

SVG coordinates are the drawing's user units (R is in them too); an SVG whose root says
width="210mm" viewBox="0 0 210 297" is in mm, and SVG and DXF outputs say so again.

geodata: every feature of the layer is tightened on its own and written as one output
feature, in order, with all its attributes and the CRS unchanged (a feature whose
tightening is empty keeps its row, with an empty geometry; points and lines pass through
unchanged). Features are never united, so neighbouring features are tightened
independently: a border they share may open into a gap or close into an overlap.
R is a length in the layer's CRS units (metres for UTM, feet for a US state plane in feet).
A layer in degrees (EPSG:4326, or a GeoJSON without a "crs" member) is refused: pass
--to-crs with a projected CRS to reproject it, tighten there and write it there. A layer
with no CRS needs --crs. Needs the geo extra: pip install "vectortighten[geo]".

several inputs, or a folder, write one output per input into the folder OUT, named after
the input with the extension of --format (default: the input's own). A file that fails is
reported on one line and the others go on; the exit code is then 2. An option that
applies to none of the inputs (or outputs) is refused; in a batch, each file takes the
options that apply to it (--layer: the DXF layers to read, or the one layer of a geodata
file).

examples:
  vectortighten tighten shape.svg -r 2 -o tight.svg
  vectortighten tighten part.dxf -r 0,3 -o part-cnc.dxf     # inside corners >= 3, outside sharp
  vectortighten tighten shape.svg -r 2 -o tight.svg --layers input,core,mortar
  vectortighten tighten part.geojson -r 0.5 --init input -o part.dxf
  vectortighten tighten shape.svg -r 2 --flatten 0.001 --tolerance 0.0001 -o tight.wkt
  vectortighten tighten a.svg b.wkt c.geojson -r 1 -o out/ --format svg
  vectortighten tighten drawings/ -r 1 -o out/ --jobs 4 --progress
  vectortighten tighten mask.png -r 8 -o tight.png
  vectortighten tighten part.dxf -r 3 -o part-tight.dxf --layer CUT --dxf-entities lwpolyline
  vectortighten tighten cut.svg -r 0.5 -o cut-tight.svg --stroke-only
  vectortighten tighten art.svg -r 1 -o art-tight.svg --keep-style --nesting paint
  vectortighten tighten labels.tif -r 6 --labels -o tight.tif
  vectortighten tighten photo.jpg -r 8 --threshold 0.6 -o tight.png
  vectortighten tighten mask.png -r 8 -o tight.svg --trace exact
  vectortighten tighten buildings.shp -r 1.5 -o tight.gpkg
  vectortighten tighten countries.geojson -r 20000 --to-crs EPSG:8857 -o tight.gpkg
  vectortighten tighten parcels.parquet -r 2 -o tight.parquet --jobs 2
  vectortighten tighten parcels.parquet -r 2 -o tight.parquet --dask local:4
"""

_EPILOG_DEMO = """\
examples:
  vectortighten demo -o demo-out
  vectortighten demo -o demo-out -r 3
"""

from . import io as _io

# The extensions the command line reads and writes, from the table of formats (`vectortighten.io.FORMATS`).
_VECTOR_IN = _io.READ_FORMATS
_MASK_IN = tuple(e for f in _io.FORMATS.values() if f.kind == "mask" for e in f.extensions)
_ALL_IN = _VECTOR_IN + _MASK_IN
_VECTOR_OUT = _io.WRITE_FORMATS
_MASK_OUT = _io.mask.MASK_WRITE_EXTENSIONS


class UsageError(Exception):
    """A mistake in what the user asked for: reported as one line, exit code 2."""


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr (and exit code 2), not the usage block."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text}")
    return value


def _radius(text: str):
    """``-r``: one radius ``R`` (> 0), or two, ``A,B`` (convex, concave; each ≥ 0, not both 0)."""
    if "," not in text:
        return _positive_float(text)
    from .two_radii import parse_radii

    values = []
    for part in text.split(","):
        try:
            values.append(float(part))
        except ValueError:
            raise argparse.ArgumentTypeError(f"{part.strip()!r} is not a number (expected R or A,B)") from None
    try:
        a, b = parse_radii(values)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return a if a == b else (a, b)


def _nonnegative_radius(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {text}")
    return value


def _radius_of(args):
    """The radius of a ``tighten`` run: ``-r`` (one or two), or ``--r-convex`` and/or ``--r-concave``.

    A missing or contradictory radius is a usage error of the parser (one line, exit code 2).
    """
    pair = (args.r_convex, args.r_concave)
    error = args.tighten_parser.error
    if args.radius is not None:
        if pair != (None, None):
            error("give either -r/--radius or --r-convex/--r-concave, not both")
        return args.radius
    if pair == (None, None):
        error("the following arguments are required: -r/--radius (or --r-convex/--r-concave)")
    a, b = (0.0 if x is None else x for x in pair)
    if a == 0 and b == 0:
        error("--r-convex and --r-concave are both 0: at least one must be positive")
    return a if a == b else (a, b)


def _threshold(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0 < value <= 1:
        raise argparse.ArgumentTypeError(f"must be more than 0 and at most 1 (a share of the full scale), "
                                         f"got {text}")
    return value


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text}")
    return value


def _odd_positive_int(text: str) -> int:
    value = _positive_int(text)
    if value % 2 == 0:
        raise argparse.ArgumentTypeError(f"must be odd (the flow's pixels are the centres of K × K blocks), "
                                         f"got {text}")
    return value


def _layers(text: str) -> tuple[str, ...]:
    from .io import LAYERS

    names = tuple(n.strip() for n in text.split(",") if n.strip())
    bad = [n for n in names if n not in LAYERS]
    if bad:
        raise argparse.ArgumentTypeError(f"unknown layer {bad[0]!r}; choose from {','.join(LAYERS)}")
    return names


def _names(text: str) -> list[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise argparse.ArgumentTypeError(f"expected one or more names, got {text!r}")
    return names


def _nonnegative_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError(f"must be a finite number >= 0, got {text}")
    return value


def _format(text: str) -> str:
    ext = "." + text.lower().lstrip(".")
    known = _VECTOR_OUT + tuple(e for e in _MASK_OUT if e not in _VECTOR_OUT)
    if ext not in known:
        raise argparse.ArgumentTypeError(f"{text!r} is not one of {', '.join(e[1:] for e in known)}")
    return ext


def _input_format(text: str) -> str:
    ext = "." + text.lower().lstrip(".")
    if ext not in _VECTOR_IN:
        raise argparse.ArgumentTypeError(f"{text!r} is not one of {', '.join(e[1:] for e in _VECTOR_IN)}")
    return ext


def _geo_options(**options):
    from ._geofile import GeoOptions

    return GeoOptions(**options)


# ---------------------------------------------------------------------------------------------------------
# demo
# ---------------------------------------------------------------------------------------------------------
def _add_demo(sub) -> None:
    demo = sub.add_parser("demo", help="tighten the embedded example and draw it (SVG and PNG)",
                          description="Tighten the embedded example shape and write demo.svg and demo.png.",
                          epilog=_EPILOG_DEMO, formatter_class=argparse.RawDescriptionHelpFormatter)
    demo.add_argument("-o", "--output", required=True, type=Path, metavar="DIR",
                      help="folder to write into (created if its parent exists)")
    demo.add_argument("-r", "--radius", type=_positive_float, default=None,
                      help="radius (default: the demo's own, 2)")


def _out_folder(out: Path) -> None:
    """Make sure ``out`` is a folder: create it (one level) if its parent exists."""
    if not out.exists():
        if not out.parent.exists():
            raise UsageError(f"cannot create {str(out)!r}: folder {str(out.parent)!r} does not exist")
        out.mkdir()
    elif not out.is_dir():
        raise UsageError(f"{str(out)!r} exists and is not a folder")


def _cmd_demo(args) -> int:
    from .demo import DEMO_RADIUS, run_demo

    _out_folder(args.output)
    for path in run_demo(args.output, r=args.radius or DEMO_RADIUS):
        print(path)
    return 0


# ---------------------------------------------------------------------------------------------------------
# tighten
# ---------------------------------------------------------------------------------------------------------
def _add_tighten(sub) -> None:
    tight = sub.add_parser(
        "tighten", help="tighten shapes read from files",
        description="Tighten the shape in each IN with radius R and write it to OUT (format by extension).",
        epilog=_EPILOG_TIGHTEN, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    tight.add_argument("inputs", type=Path, nargs="+", metavar="IN",
                       help="input file(s) or a folder of them (.svg, .dxf, .wkt, .geojson, .json, .gpkg, "
                            ".shp, .fgb, .parquet; images: .png, .tif, .bmp, .gif, .jpg)")
    tight.add_argument("-r", "--radius", type=_radius, default=None, metavar="R",
                       help="the tightening radius, in the input's units (pixels for an image; the CRS's "
                            "units for geodata, after --to-crs if given); or two, A,B: convex corners "
                            "rounded by A, concave (inside) corners by B, either 0 to keep them sharp "
                            "(-r 0,3: the CNC inside-corner rule; vector shapes only)")
    tight.set_defaults(tighten_parser=tight)
    tight.add_argument("--r-convex", type=_nonnegative_radius, default=None, metavar="A",
                       help="two radii: the convex radius (the core is the opening by A; default 0, "
                            "convex corners stay sharp, when only --r-concave is given)")
    tight.add_argument("--r-concave", type=_nonnegative_radius, default=None, metavar="B",
                       help="two radii: the concave radius (the fillet is the closing by B; default 0, "
                            "concave corners stay sharp, when only --r-convex is given)")
    tight.add_argument("-o", "--output", type=Path, required=True, metavar="OUT",
                       help="output file; a folder for several inputs (created if its parent exists)")
    tight.add_argument("--init", choices=("core", "input", "mason"), default="core",
                       help="initial condition of the flow (default: core, the paper's)")
    tight.add_argument("--tolerance", type=_positive_float, default=None, metavar="T",
                       help="largest distance between an arc and its chords in sampled outputs "
                            "(WKT, GeoJSON and the other geodata formats, PNG; default 1e-5·R)")
    tight.add_argument("--flatten", type=_positive_float, default=None, metavar="F",
                       help="SVG, DXF and curved WKT (CURVEPOLYGON) input: largest distance between a "
                            "curve and its chords (default 1e-4 of the drawing's diagonal)")
    known_out = _VECTOR_OUT + tuple(e for e in _MASK_OUT if e not in _VECTOR_OUT)
    tight.add_argument("--format", type=_format, default=None, metavar="EXT",
                       help="output format for a folder OUT, or for an OUT whose extension does not tell: "
                            f"{', '.join(e[1:] for e in known_out)} (default: the input's)")
    tight.add_argument("--input-format", type=_input_format, default=None, metavar="EXT",
                       help="the input's format when its extension does not tell (vector formats)")
    tight.add_argument("--layers", type=_layers, default=(), metavar="L,L",
                       help="SVG, DXF and PNG output: also draw input, core and/or mortar, e.g. "
                            "--layers input,core,mortar")
    tight.add_argument("--layer", type=_names, action="extend", default=None, metavar="NAME[,NAME]",
                       help="DXF input: read only entities on these layers (case-insensitive; repeatable; "
                            "default: every layer that is on and thawed); geodata input: the one layer to "
                            "tighten, when the file has several (a GeoPackage may)")
    img = tight.add_argument_group("masks and label images")
    img.add_argument("--threshold", type=_threshold, default=None, metavar="V",
                     help="image input: read a greyscale or colour photo; a pixel is inside when its "
                          "level (value / full scale, colour by luminance, transparency on white) is >= V, "
                          "0 < V <= 1 (default: no threshold, every non-zero pixel is inside)")
    img.add_argument("--invert", action="store_true",
                     help="image input: swap inside and outside (dark shapes on a light background)")
    img.add_argument("--labels", action="store_true",
                     help="image input: a label image (0 = background); tighten every label and write "
                          "one label image of the same dtype (or geodata: one feature a label)")
    img.add_argument("--stack", action="store_true",
                     help="image input: tighten each slice of a multi-page TIFF (or animated GIF) on its "
                          "own and write a stack (.tif); without it a stack is refused")
    img.add_argument("--trace", choices=("exact", "contours"), default=None,
                     help="image input, vector output: exact = tighten the pixel squares exactly (arcs of "
                          "radius R; default), contours = the pixel method's sub-pixel contour")
    cad = tight.add_argument_group("CAD and cut files")
    cad.add_argument("--nesting", choices=("auto", "evenodd", "paint"), default=None,
                     help="SVG input: evenodd reads every outline as a cut line, nested across elements "
                          "(holes drawn as separate elements stay holes); paint fills shapes in painting "
                          "order, a shape in the background colour erasing; auto (default) is evenodd "
                          "when no shape is filled, else paint")
    cad.add_argument("--exact-arcs", action="store_true",
                     help="SVG, DXF and curved WKT input: read circles and circular arcs as exact arcs; a "
                          "part that is its own tightening (every corner rounded to at least R, holes of "
                          "radius at least R, no part thinner than 2R) comes back unchanged with its own "
                          "arcs, any other is flattened within 1e-5·R first (with a warning)")
    cad.add_argument("--gap", type=_nonnegative_float, default=None, metavar="G",
                     help="SVG and DXF input: loose ends nearer than G join into one outline, in the "
                          "drawing's units (default 1e-6 of its diagonal)")
    cad.add_argument("--dxf-entities", choices=("lines-arcs", "lwpolyline"), default=None,
                     help="DXF output: LINE and ARC entities (default), or one closed LWPOLYLINE with "
                          "bulges per loop (what many CAM programs prefer); full circles are CIRCLEs")
    cad.add_argument("--keep-style", action="store_true",
                     help="SVG output: give each part the style of the input element it comes from")
    cad.add_argument("--stroke-only", action="store_true",
                     help="SVG output: outlines only (fill none, one element per loop, full circles as "
                          "<circle>), a red hairline stroke unless --keep-style keeps the element's")
    geo = tight.add_argument_group("geodata (GeoPackage, Shapefile, GeoJSON, FlatGeobuf, GeoParquet)")
    geo.add_argument("--to-crs", default=None, metavar="CRS",
                     help="reproject the features to this projected CRS (EPSG:32631, a WKT, a PROJ string) "
                          "before tightening; R is then in its units, and the output is written in it")
    geo.add_argument("--crs", default=None, metavar="CRS",
                     help="the CRS of the input's coordinates, when the file has none (or a wrong one)")
    geo.add_argument("--dask", default=None, metavar="SCHEDULER",
                     help="tighten the features on a dask cluster: a scheduler address "
                          "(tcp://host:8786), or local / local:N to start N local workers "
                          "(needs the dask extra)")
    geo.add_argument("--skip-failed", action="store_true",
                     help="a feature the engine fails on gets an empty geometry and is counted, "
                          "instead of stopping the run")
    tight.add_argument("-j", "--jobs", type=_positive_int, default=None, metavar="N",
                       help="processes for several inputs (default: all cores); for one geodata input, "
                            "processes over its features (default: one)")
    shown = tight.add_mutually_exclusive_group()
    shown.add_argument("--progress", action="store_true",
                       help="show a progress bar on stderr (shown anyway when stderr is a terminal): over "
                            "files for several inputs, over features for one geodata input")
    shown.add_argument("-q", "--quiet", action="store_true",
                       help="no progress bar and no summary line (warnings and errors still go to stderr)")


@dataclass(frozen=True)
class _Task:
    """One input to tighten into one output, with the options of the run (picklable).

    ``route`` is how the input is tightened: ``"shape"`` (one shape through the exact engine: SVG, DXF,
    WKT, a bare GeoJSON geometry), ``"features"`` (a geodata layer, feature by feature) or ``"image"``
    (a mask or label image: the pixel method, or traced to vectors).
    """

    source: Path
    target: Path
    r: float | tuple[float, float]
    init: str
    tolerance: float | None
    flatten: float | None
    layers: tuple[str, ...]
    route: str = "shape"
    read_options: tuple = ()      # (name, value) pairs for the input format's reader (`Format.read_options`)
    write_options: tuple = ()     # (name, value) pairs for the output format's writer
    trace: str = "exact"
    geo: GeoOptions | None = None
    progress: bool = False
    quiet: bool = False
    exact_arcs: bool = False


@dataclass
class _Outcome:
    """What a task produced: a summary line, warnings, or an error line (``internal`` for a bug)."""

    task: _Task
    summary: str = ""
    warnings: list[str] = field(default_factory=list)
    error: str | None = None
    internal: bool = False


def _error_text(exc: BaseException) -> str:
    if isinstance(exc, OSError) and exc.filename is not None:
        return f"{exc.strerror or exc}: {exc.filename}"
    return _one_line(str(exc) or type(exc).__name__)


def _one_line(text: str) -> str:
    """A message as one line of reasonable length: long digit runs shortened, only the first line kept.

    Examples
    --------
    >>> _one_line("Unrecognized number: " + "1" * 400)
    'Unrecognized number: 111111111111… (400 digits)'
    """
    import re

    text = text.strip().splitlines()[0] if text.strip() else text
    return re.sub(r"\d{40,}", lambda m: f"{m.group()[:12]}… ({len(m.group())} digits)", text)


def _user_errors():
    from .errors import TighteningError
    from .io import MissingDependencyError

    return (UsageError, TighteningError, MissingDependencyError, ValueError, TypeError, OSError)


def _prefixed(path: Path, message: str) -> str:
    """Name the input in the message unless it already does."""
    return message if str(path) in message else f"{path}: {message}"


def _run_task(task: _Task) -> _Outcome:
    """Read, tighten and write one file; never raises (errors come back in the outcome)."""
    outcome = _Outcome(task)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            outcome.summary = _tighten_file(task)
        except _user_errors() as exc:
            outcome.error = _prefixed(task.source, _error_text(exc))
        except MemoryError:
            outcome.error = f"{task.source}: out of memory"
        except Exception as exc:  # a bug: report it on one line and let the other files go on
            if os.environ.get("VECTORTIGHTEN_DEBUG"):
                raise
            outcome.error = (f"{task.source}: internal error ({type(exc).__name__}: {exc}); "
                             "please report it with this input")
            outcome.internal = True
    seen = set()
    for w in caught:
        text = _prefixed(task.source, str(w.message))
        if text not in seen:
            seen.add(text)
            outcome.warnings.append(text)
    return outcome


def _tighten_file(task: _Task) -> str:
    from . import io

    geo = task.geo or _geo_options()
    _check_output_format(task, geo.output_format)
    if task.route == "image":
        return io.mask.tighten_image_file(task.source, task.target, r=task.r, init=task.init,
                                          trace=task.trace, tolerance=task.tolerance, layers=task.layers,
                                          **dict(task.read_options))
    if task.route == "features":
        from ._geofile import tighten_features_file

        return tighten_features_file(task.source, task.target, r=task.r, init=task.init,
                                     tolerance=task.tolerance, options=replace(geo, progress=task.progress),
                                     read_options=dict(task.read_options))
    import shapely

    from ._progress import FeatureBar
    from .engine import tighten

    source = io.read_source(task.source, flatten=task.flatten, format=geo.input_format,
                            **dict(task.read_options))
    with FeatureBar(1, enabled=task.progress, unit="shape") as bar:     # a large shape shows it is working
        bar.start(task.source.name, shapely.get_num_coordinates(source.shape))
        shape = io.loops_of(source, str(task.source)) if task.exact_arcs else source.shape
        result = tighten(shape, task.r, init=task.init, tolerance=task.tolerance)
        bar.advance()
    if result.is_empty:
        warnings.warn(f"the tightening is empty: every part is thinner than 2r = {2 * result.r:g}", UserWarning)
    # What the reader found (units, position, page, styles; a CRS) travels to the writer in the meta.
    io.write_result(result, task.target, layers=task.layers, meta=source.meta, format=geo.output_format,
                    **dict(task.write_options))
    return (f"{task.target}: perimeter {result.perimeter:.6g}, area {result.area:.6g}, "
            f"{result.n_components} component(s), {result.n_holes} hole(s)")


def _expand_inputs(inputs: list[Path]) -> tuple[list[Path], bool]:
    """The input files (a folder gives its supported files) and whether this is a batch."""
    files: list[Path] = []
    batch = len(inputs) > 1
    for p in inputs:
        if p.is_dir():
            batch = True
            found = sorted(q for q in p.iterdir()
                           if q.is_file() and not q.name.startswith(".") and q.suffix.lower() in _ALL_IN)
            if not found:
                raise UsageError(f"no input files ({', '.join(_ALL_IN)}) in folder {str(p)!r}")
            files += found
        else:
            files.append(p)
    return files, batch


def _check_output_format(task: _Task, override: str | None = None) -> None:
    if task.route != "shape":
        return      # an image goes to an image or to vectors, a layer to geodata: their paths check
    ext = task.target.suffix.lower()
    if ext in _MASK_OUT and ext not in _VECTOR_OUT:
        raise UsageError(f"{task.target}: {ext} is for image inputs (masks); a vector shape is written as "
                         f"one of {', '.join(_VECTOR_OUT)}")
    if override is None and ext not in _VECTOR_OUT:
        raise UsageError(f"{task.target}: unsupported output format {ext or '(none)'!r}; "
                         f"expected one of {', '.join(_VECTOR_OUT)}")


def _format_or_none(path: Path, format: str | None = None):
    from . import io

    try:
        return io.format_of(path, format)
    except ValueError:
        return None       # the reader or writer names the unsupported format


def _route(path: Path, input_format: str | None) -> str:
    """How ``path`` is tightened: ``"image"``, ``"features"`` (a geodata layer) or ``"shape"``."""
    fmt = _format_or_none(path, input_format)
    if fmt is None:
        return "shape"
    if fmt.kind == "mask":
        return "image"
    if fmt.holds_features:
        from ._geofile import holds_features

        return "features" if holds_features(path, input_format) else "shape"
    return "shape"


@dataclass(frozen=True)
class _Scoped:
    """A ``tighten`` option that only some inputs or outputs take.

    ``keys`` are the reader's or writer's keywords it becomes (`vectortighten.io.Format.read_options`,
    ``write_options``): a file takes the option when its format declares one of them. ``route`` instead
    names the kind of input whose tightening takes it (``"image"``, ``"features"``).
    """

    dest: str
    flag: str
    side: str = "input"
    keys: tuple[str, ...] = ()
    route: str | None = None

    def given(self, args) -> bool:
        value = getattr(args, self.dest, None)
        return value is not None and value is not False

    def key_for(self, task: _Task) -> str | None:
        """The keyword ``task`` takes this option as (``""`` for a route option), or None."""
        if self.route is not None:
            return "" if task.route == self.route else None
        geo = task.geo or _geo_options()
        if self.side == "input":
            fmt = _format_or_none(task.source, geo.input_format)
            if fmt is None or (fmt.holds_features and task.route == "shape"):
                return None       # a bare GeoJSON geometry is one shape: no layer, no CRS
            keys = fmt.read_options
        else:
            fmt = _format_or_none(task.target, geo.output_format)
            keys = fmt.write_options if fmt is not None else ()
        return next((k for k in self.keys if k in keys), None)

    def owners(self) -> str:
        """Who takes it, for the message that refuses it."""
        from . import io

        images, layers = f"image inputs ({', '.join(_MASK_IN)})", f"geodata layers ({_GEODATA_TITLES})"
        if self.route is not None:
            return images if self.route == "image" else layers
        takes = [f for f in io.FORMATS.values() if any(
            k in (f.read_options if self.side == "input" else f.write_options) for k in self.keys)]
        plain = [f.title for f in takes if f.kind != "mask" and not f.holds_features]
        parts = [f"{' and '.join(plain)} {self.side}"] if plain else []
        if any(f.holds_features for f in takes):
            parts.append(layers)
        if any(f.kind == "mask" for f in takes):
            parts.append(images)
        return " and ".join(parts)


_GEODATA_TITLES = ", ".join(f.title for f in _io.FORMATS.values() if f.holds_features)
_FEATURE_EXTS = tuple(e for f in _io.FORMATS.values() if f.holds_features for e in f.extensions)

#: The options of ``tighten`` that only some inputs or outputs take, checked by one rule: an option that
#: none of the run's files takes is refused; in a batch, each file uses the options it takes.
_SCOPED = (
    _Scoped("layer", "--layer", keys=("layers", "layer")),      # DXF: layers to read; geodata: one layer
    _Scoped("nesting", "--nesting", keys=("nesting",)),
    _Scoped("gap", "--gap", keys=("gap",)),
    _Scoped("crs", "--crs", keys=("crs",)),
    _Scoped("threshold", "--threshold", keys=("threshold",)),
    _Scoped("invert", "--invert", keys=("invert",)),
    _Scoped("labels", "--labels", keys=("labels",)),
    _Scoped("stack", "--stack", keys=("stack",)),
    _Scoped("trace", "--trace", route="image"),
    _Scoped("to_crs", "--to-crs", route="features"),
    _Scoped("dask", "--dask", route="features"),
    _Scoped("skip_failed", "--skip-failed", route="features"),
    _Scoped("dxf_entities", "--dxf-entities", side="output", keys=("dxf_entities",)),
    _Scoped("keep_style", "--keep-style", side="output", keys=("keep_style",)),
    _Scoped("stroke_only", "--stroke-only", side="output", keys=("stroke_only",)),
)


def _scoped_options(args, task: _Task) -> _Task:
    """``task`` with the reader's and writer's options it takes; refuses a value it cannot take."""
    read, write = [], []
    for opt in _SCOPED:
        if not opt.given(args) or opt.route is not None:
            continue
        key = opt.key_for(task)
        if key is None:
            continue
        value = getattr(args, opt.dest)
        if key == "layer":
            if len(value) != 1:
                raise UsageError(f"{task.source}: a geodata file's layers are tables, and one is "
                                 f"tightened at a time; --layer takes one name here, got {','.join(value)}")
            value = value[0]
        elif isinstance(value, list):
            value = tuple(value)
        (read if opt.side == "input" else write).append((key, value))
    return replace(task, read_options=tuple(read), write_options=tuple(write))


def _check_scoped(args, tasks: list[_Task]) -> None:
    """Refuse an option that applies to none of the inputs (or outputs) of the run."""
    for opt in _SCOPED:
        if opt.given(args) and not any(opt.key_for(t) is not None for t in tasks):
            what = "inputs" if opt.side == "input" else "outputs"
            raise UsageError(f"{opt.flag} applies to {opt.owners()} only, and none of the {what} is")


def _plan(args) -> tuple[list[_Task], bool]:
    """The tasks of a ``tighten`` run, every output checked against every input."""
    files, batch = _expand_inputs(args.inputs)
    out: Path = args.output
    if not batch and out.is_dir():
        batch = True
    if batch and args.dask:
        raise UsageError("--dask takes one input file")
    single = len(files) == 1 and not batch
    geo = _geo_options(to_crs=args.to_crs, input_format=args.input_format,
                       output_format=args.format if not batch else None,
                       processes=args.jobs if single else None, dask=args.dask,
                       skip_failed=args.skip_failed)
    opts = dict(r=_radius_of(args), init=args.init, tolerance=args.tolerance, flatten=args.flatten,
                layers=args.layers, trace=args.trace or "exact", geo=geo, quiet=args.quiet,
                exact_arcs=args.exact_arcs, progress=not batch and not args.quiet and (args.progress or sys.stderr.isatty()))
    if batch:
        if out.exists() and not out.is_dir():
            raise UsageError(f"{str(out)!r} exists and is not a folder")
        targets = []
        for f in files:
            own = f.suffix.lower()
            if args.format:
                ext = args.format
            elif own in _MASK_IN:
                ext = own if own in _MASK_OUT else ".png"      # GIF and JPEG masks come back as PNG
            else:
                ext = own if own in _VECTOR_OUT else ".svg"
            targets.append(out / (f.stem + ext))
    else:
        known = out.suffix.lower() in _VECTOR_OUT + _MASK_OUT
        if args.format and known and out.suffix.lower() != args.format:
            raise UsageError(f"--format {args.format[1:]} disagrees with the output {str(out)!r}")
        targets = [out]
    resolved_in = {}
    for f in files:
        try:
            resolved_in[f.resolve()] = f
        except OSError:
            pass
    seen: dict[Path, Path] = {}
    tasks = []
    for f, t in zip(files, targets, strict=True):
        rt = t.resolve()
        hit = resolved_in.get(rt) or next((g for g in files if _same_file(g, t)), None)
        if hit is not None:
            raise UsageError(f"refusing to overwrite the input {str(hit)!r}")
        if rt in seen:
            raise UsageError(f"{str(seen[rt])!r} and {str(f)!r} would both be written to {str(t)!r}")
        seen[rt] = f
        tasks.append(_Task(f, t, route=_route(f, args.input_format), **opts))
    _check_scoped(args, tasks)
    if isinstance(opts["r"], tuple):
        bad = next((t for t in tasks if t.route != "shape"), None)
        if bad is not None:
            raise UsageError(f"two radii apply to vector shapes (SVG, DXF, WKT, a GeoJSON geometry) only, "
                             f"not {str(bad.source)!r}")
    if args.exact_arcs and any(t.route != "shape" for t in tasks):
        bad = next(t for t in tasks if t.route != "shape")
        raise UsageError(f"--exact-arcs applies to SVG, DXF and WKT input only, not {str(bad.source)!r}")
    tasks = [_scoped_options(args, t) for t in tasks]
    if batch:
        _out_folder(out)
    return tasks, batch


def _same_file(a: Path, b: Path) -> bool:
    """Whether two existing paths are the same file (hard links included)."""
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


class _Progress:
    """A one-line progress bar on stderr, redrawn in place; other lines are printed above it."""

    def __init__(self, total: int, enabled: bool, stream=None):
        self.total, self.done, self.enabled = total, 0, enabled
        self.stream = stream or sys.stderr
        self._drawn = False
        self.draw()

    def draw(self) -> None:
        if not self.enabled:
            return
        width = 30
        filled = width * self.done // max(1, self.total)
        self.stream.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total}")
        self.stream.flush()
        self._drawn = True

    def clear(self) -> None:
        if self.enabled and self._drawn:
            self.stream.write("\r" + " " * 50 + "\r")
            self._drawn = False

    def line(self, text: str, stream=None) -> None:
        """Print one line (to ``stream``, stderr by default) without breaking the bar."""
        self.clear()
        print(text, file=stream or self.stream, flush=True)
        self.draw()

    def step(self) -> None:
        self.done += 1
        self.draw()

    def close(self) -> None:
        if self.enabled and self._drawn:
            self.stream.write("\n")
            self.stream.flush()


def _report(outcome: _Outcome, progress: _Progress) -> None:
    for w in outcome.warnings:
        progress.line(f"vectortighten: warning: {w}")
    if outcome.error is not None:
        progress.line(f"vectortighten: error: {outcome.error}")
    elif not outcome.task.quiet:
        progress.line(outcome.summary, stream=sys.stdout)


def _cmd_tighten(args) -> int:
    tasks, batch = _plan(args)
    if not batch:
        outcome = _run_task(tasks[0])
        for w in outcome.warnings:
            print(f"vectortighten: warning: {w}", file=sys.stderr)
        if outcome.error is not None:
            print(f"vectortighten: error: {outcome.error}", file=sys.stderr)
            return 1 if outcome.internal else 2
        if not args.quiet:
            print(outcome.summary)
        return 0
    jobs = min(args.jobs or os.cpu_count() or 1, len(tasks))
    progress = _Progress(len(tasks), enabled=not args.quiet and (args.progress or sys.stderr.isatty()))
    outcomes: list[_Outcome] = []
    try:
        if jobs == 1:
            for task in tasks:
                outcomes.append(_run_task(task))
                _report(outcomes[-1], progress)
                progress.step()
        else:
            # Fresh interpreters, not forks: safe whatever threads the parent runs, the same on every OS.
            # One task at a time per worker, so that a worker that dies fails its own file only, and
            # Ctrl-C terminates the workers before anything else is written (`_workers`).
            from ._workers import WorkerDied, run_tasks

            for k, ok, value in run_tasks(_run_task, [(t,) for t in tasks], jobs):
                if ok:
                    outcome = value
                else:   # the worker died (killed, out of memory): this file fails, the others go on
                    outcome = _Outcome(tasks[k], error=f"{tasks[k].source}: {_error_text(value)}",
                                       internal=not isinstance(value, WorkerDied))
                outcomes.append(outcome)
                _report(outcome, progress)
                progress.step()
    finally:
        progress.close()
    failed = [o for o in outcomes if o.error is not None]
    if failed:
        print(f"vectortighten: {len(failed)} of {len(tasks)} file(s) failed", file=sys.stderr)
        return 2 if any(not o.internal for o in failed) else 1
    return 0


# ---------------------------------------------------------------------------------------------------------
# compare
# ---------------------------------------------------------------------------------------------------------
_EPILOG_COMPARE = """\
examples:
  vectortighten compare shape.svg -r 2
  vectortighten compare shape.wkt -r 2 --pixel-size 0.05 --init input --plot check.png
"""


def _add_compare(sub) -> None:
    cmp_ = sub.add_parser(
        "compare", help="cross-check the exact tightening against the paper's pixel method",
        description="Tighten IN exactly and on pixels (the paper's level-set flow) on the same grid, and "
                    "print how far the two agree: Hausdorff distance, symmetric difference, topology; "
                    "where they do not, each differing region and why (rasterisation, unconverged flow, "
                    "two valid tightenings, or a defect of one side), with the evidence.",
        epilog=_EPILOG_COMPARE, formatter_class=argparse.RawDescriptionHelpFormatter)
    cmp_.add_argument("input", type=Path, metavar="IN", help="input file (.svg, .wkt, .geojson, .json)")
    cmp_.add_argument("-r", "--radius", type=_positive_float, required=True, metavar="R",
                      help="the tightening radius, in the input's units")
    cmp_.add_argument("--pixel-size", type=_positive_float, default=None, metavar="P",
                      help="pixel side, in the input's units (default R/20)")
    cmp_.add_argument("--init", choices=("core", "input", "mason"), default="core",
                      help="initial condition of both flows (default: core)")
    cmp_.add_argument("--levels", type=_positive_int, default=None, metavar="L",
                      help="resolution levels of the pixel flow (default: the paper's multiscale; 1 = full "
                           "resolution only, slower but more accurate)")
    cmp_.add_argument("--iterations", type=_positive_int, default=None, metavar="N",
                      help="most steps of the pixel flow per level (default: until its front rests, with "
                           "a safety cap; the paper's budget is 100)")
    cmp_.add_argument("--supersample", type=_odd_positive_int, default=None, metavar="K",
                      help="rasterise IN K times finer (K odd) for the pixel method's core, fillet and start, "
                           "and flow on the grid of P (default 7, which agrees best, at about twice the time "
                           "of 5 and 10 to 40 times that of 1; 1 is the paper's method on a plain rasterisation; a fine grid "
                           "over 50 million pixels falls back to 1 with a warning)")
    cmp_.add_argument("--mask-reference", action="store_true",
                      help="also tighten the rasterised input exactly and compare the pixel result with it "
                           "(the flow's own error, without that of rasterising IN)")
    cmp_.add_argument("--plot", type=Path, default=None, metavar="OUT.png",
                      help="also draw the input with its mortar, both results and their difference")


def _cmd_compare(args) -> int:
    from . import io
    from .comparison import crosscheck, plot_crosscheck

    if args.plot is not None and args.plot.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise UsageError(f"{str(args.plot)!r}: the plot must be .png, .svg or .pdf")
    shape = io.read_shape(args.input)
    pixel = args.pixel_size or args.radius / 20
    options = {} if args.supersample is None else {"supersample": args.supersample}
    check = crosscheck(shape, args.radius, pixel_size=pixel, init=args.init, levels=args.levels,
                       iterations=args.iterations, mask_reference=args.mask_reference, **options)
    print(check.table())
    if not check.agree:
        # Under the table, in its two-column form: the verdicts of `CrossCheck.explain`, indented.
        head, *lines = check.explain_text().splitlines()
        print(f"why they differ  {head}")
        for line in lines:
            print(f"  {line}")
    if args.plot is not None:
        plot_crosscheck(check, args.plot, S=shape)
        print(f"plot: {args.plot}")
    return 0


# ---------------------------------------------------------------------------------------------------------
# figures
# ---------------------------------------------------------------------------------------------------------
def _add_figures(sub) -> None:
    fig = sub.add_parser(
        "figures", help="redraw the paper's figures (1-9) and the comparison figure",
        description="Redraw every figure script of the checkout's figures/ folder into DIR.",
        epilog="examples:\n  vectortighten figures -o figs\n  vectortighten figures -o figs --only fig7_cusps",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    fig.add_argument("-o", "--output", required=True, type=Path, metavar="DIR",
                     help="folder to write into (created if its parent exists)")
    fig.add_argument("--only", nargs="+", default=None, metavar="NAME", help="only these figures")


def _cmd_figures(args) -> int:
    import importlib.util

    script = Path(__file__).resolve().parent.parent / "figures" / "make_all.py"
    if not script.is_file():
        raise UsageError("the figure scripts live in the source checkout's figures/ folder, which this "
                         "installation does not have; install from a clone with pip install -e .")
    _out_folder(args.output)
    spec = importlib.util.spec_from_file_location("_vectortighten_figures", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    if args.only:
        unknown = sorted(set(args.only) - set(module.FIGURES))
        if unknown:
            raise UsageError(f"unknown figure(s) {', '.join(unknown)}; known: {', '.join(module.FIGURES)}")
    for path in module.run_all(args.output, names=args.only):
        print(path)
    return 0


# ---------------------------------------------------------------------------------------------------------
# Dispatch
# ---------------------------------------------------------------------------------------------------------
#: Subcommands: name -> (add its sub-parser to the ``add_subparsers`` object, run it and return the code).
COMMANDS = {
    "demo": (_add_demo, _cmd_demo),
    "tighten": (_add_tighten, _cmd_tighten),
    "compare": (_add_compare, _cmd_compare),
    "figures": (_add_figures, _cmd_figures),
}


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="vectortighten",
        description="Exact r-tightening of planar shapes: segments and circular arcs of radius r.",
        epilog=_EPILOG_MAIN,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    from . import __version__

    parser.add_argument("--version", action="version", version=f"vectortighten {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)
    for add, _ in COMMANDS.values():
        add(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 on success, 2 on a user error, 1 on a bug).

    Examples
    --------
    >>> main(["tighten", "no-such-file.wkt", "-r", "1", "-o", "out.wkt"])
    2
    """
    args = _parser().parse_args(argv)
    try:
        return COMMANDS[args.command][1](args)
    except _user_errors() as exc:
        print(f"vectortighten: error: {_error_text(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("vectortighten: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:
        if os.environ.get("VECTORTIGHTEN_DEBUG"):
            raise
        print(f"vectortighten: internal error ({type(exc).__name__}: {exc}); please report it",
              file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
