"""What every reader and writer shares: atomic writes, optional dependencies, checks, layers."""

from __future__ import annotations

import importlib
import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from vectortighten.errors import GeometryTypeError, InvalidGeometryError

__all__ = ["LAYERS", "MissingDependencyError", "atomic_path", "atomic_write"]

#: Layers a writer can add to an SVG, DXF or PNG output besides the tightening.
LAYERS = ("input", "core", "mortar")


class MissingDependencyError(ImportError):
    """An optional dependency needed for a file format is not installed; the message says which extra."""


def _require(module: str, extra: str, what: str):
    try:
        return importlib.import_module(module)
    except ImportError:
        raise MissingDependencyError(
            f"{what} needs the optional package {module.split('.')[0]!r}: "
            f"pip install vectortighten[{extra}]") from None


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@contextmanager
def atomic_path(path):
    """Give a temporary path beside ``path`` to write to; rename it onto ``path`` only on success.

    The temporary name keeps the extension of ``path`` (some writers choose the format by it) and starts
    with a dot. On an exception it is removed and ``path`` is left as it was.

    Parameters
    ----------
    path : str or Path
        The final file. Its folder must exist.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "x.txt"
    ...     with atomic_path(p) as tmp:
    ...         _ = tmp.write_text("hello")
    ...     p.read_text(), [q.name for q in pathlib.Path(d).iterdir()]
    ('hello', ['x.txt'])
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(2, "output folder does not exist", str(path.parent))
    if path.is_dir():
        raise IsADirectoryError(21, "output is a folder", str(path))
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=f".tmp{path.suffix}")
    os.close(fd)
    _PENDING.add(tmp)
    try:  # mkstemp makes the file private; give it the mode of the file it replaces, or the usual one
        os.chmod(tmp, path.stat().st_mode & 0o7777 if path.exists() else 0o666 & ~_umask())
    except OSError:
        pass
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    finally:
        _PENDING.discard(tmp)
        if os.path.exists(tmp):
            os.unlink(tmp)


#: Temporary files being written by `atomic_path` in this process (removed by `discard_pending`).
_PENDING: set[str] = set()


def discard_pending() -> None:
    """Remove the temporary files this process is writing (a batch worker being terminated)."""
    import sys

    pending = list(_PENDING)
    raster_io = sys.modules.get("raster.io")
    pending += list(getattr(raster_io, "_PENDING", ()))
    for tmp in pending:
        try:
            os.unlink(tmp)
        except OSError:
            pass


@contextmanager
def atomic_write(path, mode: str = "w"):
    """Open a temporary file beside ``path`` for writing; rename it onto ``path`` only on success.

    Parameters
    ----------
    path : str or Path
        The final file. Its folder must exist.
    mode : {"w", "wb"}
        Text (UTF-8) or binary.

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
    with atomic_path(path) as tmp:
        with open(tmp, mode, **({} if "b" in mode else {"encoding": "utf-8"})) as f:
            yield f


def _polygonal(geom, source: str) -> Polygon | MultiPolygon:
    """Keep the polygons of ``geom``; refuse a geometry that has none or has non-finite coordinates."""
    if geom is None or geom.is_empty:
        raise InvalidGeometryError(f"{source}: the geometry is empty")
    if not np.isfinite(shapely.get_coordinates(geom)).all():
        raise InvalidGeometryError(f"{source}: NaN or infinite coordinates")
    if not isinstance(geom, (Polygon, MultiPolygon)):
        parts = [g for g in _leaves(geom) if isinstance(g, Polygon) and not g.is_empty]
        if not parts:
            raise GeometryTypeError(f"{source}: no polygons found (got {geom.geom_type})")
        geom = shapely.union_all(parts)
    if geom.is_empty:
        raise InvalidGeometryError(f"{source}: the geometry is empty")
    return geom


def _leaves(geom) -> list:
    """The simple geometries of ``geom``, through collections nested to any depth (without recursion)."""
    out, todo = [], [geom]
    while todo:
        g = todo.pop()
        if hasattr(g, "geoms"):
            todo.extend(reversed(list(g.geoms)))
        else:
            out.append(g)
    return out


def _read_text(path: Path, kind: str) -> str:
    try:
        return path.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InvalidGeometryError(f"{path}: malformed {kind} (not UTF-8 text)") from None


def _bounds(result, layers) -> tuple[float, float, float, float]:
    boxes = [lp.bounds for lp in result.loops]
    if not boxes or "input" in layers or "mortar" in layers:
        boxes.append(result.shape.bounds)
    b = np.array(boxes, dtype=float)
    return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())


def _check_layers(layers) -> tuple[str, ...]:
    layers = tuple(layers or ())
    bad = [name for name in layers if name not in LAYERS]
    if bad:
        raise ValueError(f"unknown layer(s) {', '.join(map(repr, bad))}; choose from {', '.join(LAYERS)}")
    return layers
