"""The ``vectortighten`` command line.

Every failure a user can cause (a missing file, malformed input, a bad radius, a missing output folder)
ends with exit code 2 and one line on stderr; a traceback means a bug in vectortighten.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

__all__ = ["main"]

_EPILOG_MAIN = """\
examples:
  vectortighten demo -o demo-out
  vectortighten tighten shape.wkt -r 2 -o tight.geojson
  python -m vectortighten tighten shape.geojson -r 0.5 --init input -o tight.wkt
"""


class UsageError(Exception):
    """A mistake in what the user asked for: reported as one line, exit code 2."""


def _positive_float(text: str) -> float:
    import math

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text}")
    return value


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="vectortighten",
        description="Exact r-tightening of planar shapes: segments and circular arcs of radius r.",
        epilog=_EPILOG_MAIN,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    demo = sub.add_parser("demo", help="tighten the embedded example and draw it (SVG and PNG)",
                          description="Tighten the embedded example shape and write demo.svg and demo.png.")
    demo.add_argument("-o", "--output", required=True, type=Path, metavar="DIR",
                      help="folder to write into (created if its parent exists)")
    demo.add_argument("-r", "--radius", type=_positive_float, default=None,
                      help="radius (default: the demo's own, 2)")

    tight = sub.add_parser(
        "tighten", help="tighten a shape read from a file",
        description="Tighten the shape in IN with radius R and write it to OUT (format by extension).",
        epilog="examples:\n  vectortighten tighten shape.wkt -r 2 -o tight.geojson\n",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    tight.add_argument("input", type=Path, metavar="IN", help="input file (.wkt, .geojson, .json)")
    tight.add_argument("-r", "--radius", type=_positive_float, required=True, metavar="R",
                       help="the tightening radius, in the input's units")
    tight.add_argument("-o", "--output", type=Path, required=True, metavar="OUT",
                       help="output file (.wkt, .geojson, .json)")
    tight.add_argument("--init", choices=("core", "input", "mason"), default="core",
                       help="initial condition of the flow (default: core, the paper's)")
    tight.add_argument("--tolerance", type=_positive_float, default=None, metavar="T",
                       help="largest distance between an arc and its chords in the output (default 1e-5·R)")
    return parser


def _cmd_demo(args) -> int:
    from .demo import DEMO_RADIUS, run_demo

    out: Path = args.output
    if not out.exists():
        if not out.parent.exists():
            raise UsageError(f"cannot create {str(out)!r}: folder {str(out.parent)!r} does not exist")
        out.mkdir()
    elif not out.is_dir():
        raise UsageError(f"{str(out)!r} exists and is not a folder")
    for path in run_demo(out, r=args.radius or DEMO_RADIUS):
        print(path)
    return 0


def _cmd_tighten(args) -> int:
    from . import io
    from .engine import tighten

    if args.output.resolve() == args.input.resolve():
        raise UsageError(f"refusing to overwrite the input {str(args.input)!r}")
    shape = io.read_shape(args.input)
    result = tighten(shape, args.radius, init=args.init, tolerance=args.tolerance)
    io.write_result(result, args.output)
    print(f"{args.output}: perimeter {result.perimeter:.6g}, area {result.area:.6g}, "
          f"{result.n_components} component(s), {result.n_holes} hole(s)")
    return 0


_COMMANDS = {"demo": _cmd_demo, "tighten": _cmd_tighten}


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 on success, 2 on a user error).

    Examples
    --------
    >>> main(["tighten", "no-such-file.wkt", "-r", "1", "-o", "out.wkt"])
    2
    """
    from .errors import TighteningError

    args = _parser().parse_args(argv)
    try:
        return _COMMANDS[args.command](args)
    except (UsageError, TighteningError, ValueError, TypeError, OSError) as exc:
        message = str(exc) or type(exc).__name__
        if isinstance(exc, OSError) and exc.filename is not None:
            message = f"{exc.strerror or exc}: {exc.filename}"
        print(f"vectortighten: error: {message}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("vectortighten: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
