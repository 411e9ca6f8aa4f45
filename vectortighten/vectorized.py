"""Many geometries at once, in the conventions of shapely 2 and GeoPandas.

`tighten_all` tightens every geometry of an array, a list, a GeoSeries, a GeoDataFrame or a
dask-geopandas collection, each on its own: features are never united with each other, so every input
feature gives exactly one output feature, in the same place. `core_all`, `fillet_all`, `mortar_all` and
`mason_all` do the same for the morphology.

What comes back has the shape of what went in:

* a numpy array (any shape) or a list gives a numpy array of the same shape, of shapely geometries;
* a GeoSeries gives a GeoSeries with the same index, name and CRS;
* a GeoDataFrame gives a copy with its active geometry column replaced and every other column kept;
* a dask-geopandas GeoSeries or GeoDataFrame gives one of the same kind, lazily, partition by partition;
* a single geometry gives a single geometry.

``None`` and empty geometries give an empty polygon. Points, lines and collections that are not
polygonal are passed through unchanged and counted (a `PassThroughWarning`). An invalid polygon is
repaired on its own (``shapely.make_valid``, its polygonal part kept; one `RepairWarning` counts them).
A feature whose result is empty keeps its place with an empty polygon (one `EmptyTighteningWarning`
counts them). Warnings that the engine gives for single features (`ConvergenceWarning`) are gathered
into one per kind, with the count and the first features concerned.

``processes=N`` spreads the features over N worker processes (fresh interpreters; features are sent in
chunks balanced by vertex count; one pool for the call). It pays off from a few seconds of work on idle
cores; a dask cluster scales further. On Linux with autogroup scheduling (the default on desktops) the
processes started from one terminal session share that session's fair share of the CPU, so while other
sessions keep the cores busy, more processes get no more CPU than one (``benchmarks/bench_geo.py``
measures both).
A worker that dies (the out-of-memory killer) fails the features of its own chunk only (with
``errors="warn"`` they get an empty geometry and are counted; with ``"raise"`` the first is named), and
Ctrl-C terminates every worker at once (`vectortighten._workers`).
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from . import morphology as _m
from ._progress import FeatureBar
from ._validation import check_radius, check_tolerance
from ._workers import WorkerDied, run_tasks
from .engine import Init, tighten
from .errors import (
    EmptyTighteningWarning,
    FeatureErrorWarning,
    GeometryTypeError,
    InvalidGeometryError,
    PassThroughWarning,
    RepairWarning,
    TighteningError,
)

__all__ = ["core_all", "fillet_all", "mason_all", "mortar_all", "tighten_all"]

#: Features per chunk sent to a worker process aim at this share of all vertices per process.
_CHUNKS_PER_PROCESS = 16
#: Features named in a gathered warning, at most.
_NAMED = 5


# ---------------------------------------------------------------------------------------------------------
# One feature
# ---------------------------------------------------------------------------------------------------------
def _empty() -> Polygon:
    return Polygon()


def _op_tighten(S, r, init, tolerance):
    return tighten(S, r, init=init, tolerance=tolerance).geometry


def _op_core(S, r, init, tolerance):
    return _m.core(S, r, tolerance=tolerance)


def _op_fillet(S, r, init, tolerance):
    return _m.fillet(S, r, tolerance=tolerance)


def _op_mortar(S, r, init, tolerance):
    return _m.mortar(S, r, tolerance=tolerance)


def _op_mason(S, r, init, tolerance):
    return _m.mason(S, r, tolerance=tolerance)


#: name -> (function of one valid polygonal shape, what its result is called, warn when it is empty)
_OPS: dict[str, tuple[Callable, str, bool]] = {
    "tighten": (_op_tighten, "tightening", True),
    "core": (_op_core, "core", True),
    "fillet": (_op_fillet, "fillet", False),
    "mortar": (_op_mortar, "mortar", False),
    "mason": (_op_mason, "Mason filter", True),
}


@dataclass
class _Done:
    """What one feature gave: its geometry, the warnings it raised, or the error it failed with."""

    geometry: BaseGeometry | None = None
    warnings: list[tuple[type, str]] = field(default_factory=list)
    error: BaseException | None = None


def _run_one(op: str, S, r: float, init: str, tolerance: float | None) -> _Done:
    fn = _OPS[op][0]
    done = _Done()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            geom = fn(S, r, init, tolerance)
            done.geometry = _empty() if geom is None or geom.is_empty else geom
        except MemoryError:
            raise
        except Exception as exc:  # reported with the feature's name by the caller
            done.error = exc
    done.warnings = [(w.category, str(w.message)) for w in caught]
    return done


def _run_chunk(op: str, geoms: list, r: float, init: str, tolerance: float | None) -> list[_Done]:
    """Worker-process entry point: every feature of a chunk, in order (must stay picklable)."""
    out = []
    for S in geoms:
        d = _run_one(op, S, r, init, tolerance)
        if d.error is not None:
            d.error = _picklable(d.error)
        out.append(d)
    return out


def _picklable(exc: BaseException) -> BaseException:
    """The error itself if it survives pickling (most do), else a RuntimeError that names it."""
    import pickle

    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        return RuntimeError(f"{type(exc).__name__}: {exc}")


# ---------------------------------------------------------------------------------------------------------
# Preparing the batch
# ---------------------------------------------------------------------------------------------------------
def _polygonal_part(geom) -> Polygon | MultiPolygon:
    """The polygonal part of a repaired geometry (united, as `check_shape` unites it), maybe empty."""
    if geom.geom_type in ("Polygon", "MultiPolygon"):
        return geom
    polys = [g for g in shapely.get_parts(geom) if g.geom_type in ("Polygon", "MultiPolygon")]
    return shapely.union_all(polys) if polys else _empty()


def _is_polygonal(geom) -> bool:
    kind = geom.geom_type
    if kind in ("Polygon", "MultiPolygon"):
        return True
    if kind == "GeometryCollection":
        parts = [g for g in geom.geoms if not g.is_empty]
        return bool(parts) and all(g.geom_type in ("Polygon", "MultiPolygon") for g in parts)
    return False


def _repair_each(geoms: np.ndarray, labels: Callable[[int], str] | None = None, *, total: int | None = None,
                stacklevel: int = 2) -> tuple[np.ndarray, int]:
    """Repair the invalid polygonal geometries of ``geoms`` one by one, never together.

    Each invalid Polygon or MultiPolygon is replaced by the polygonal part of ``shapely.make_valid`` of
    itself alone (possibly empty); everything else is kept as it is. One `RepairWarning` counts them and
    names the first with the reason GEOS gives.

    Parameters
    ----------
    geoms : (n,) object ndarray
        Shapely geometries or None.
    labels : callable, optional
        ``labels(i)`` names the i-th feature in the warning (default: ``"feature i"``).
    total : int, optional
        The number of features to count them against in the warning (default ``len(geoms)``).
    stacklevel : int
        As for `warnings.warn`.

    Returns
    -------
    repaired : (n,) object ndarray
        A new array (the input is not modified).
    count : int
        How many were repaired.

    Examples
    --------
    >>> import numpy as np, warnings
    >>> from shapely.geometry import Polygon, box
    >>> bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     fixed, n = _repair_each(np.array([box(0, 0, 1, 1), bowtie], dtype=object))
    >>> n, fixed[1].geom_type, round(fixed[1].area, 6)
    (1, 'MultiPolygon', 2.0)
    """
    geoms = np.array(geoms, dtype=object, copy=True)
    present = np.array([g is not None for g in geoms.flat], dtype=bool).reshape(geoms.shape)
    kinds = shapely.get_type_id(np.where(present, geoms, None))
    polygonal = present & np.isin(kinds, (3, 6))            # Polygon, MultiPolygon
    invalid = np.zeros(geoms.shape, dtype=bool)
    if polygonal.any():
        invalid[polygonal] = ~shapely.is_valid(geoms[polygonal])
    idx = np.flatnonzero(invalid.ravel())
    if len(idx) == 0:
        return geoms, 0
    flat = geoms.reshape(-1)
    first_reason = shapely.is_valid_reason(flat[idx[0]])
    fixed = shapely.make_valid(flat[idx])
    for i, g in zip(idx, fixed, strict=True):
        flat[i] = _polygonal_part(g)
    name = labels(int(idx[0])) if labels else f"feature {int(idx[0])}"
    warnings.warn(f"{len(idx)} of {total or flat.size} feature(s) were invalid ({name}: {first_reason}); "
                  "each was repaired alone with shapely.make_valid", RepairWarning, stacklevel=stacklevel)
    return geoms, int(len(idx))


@dataclass
class _Batch:
    """A flat object array of geometries, with how to name its features and rebuild the caller's type."""

    flat: np.ndarray
    label: Callable[[int], str]
    wrap: Callable[[np.ndarray], object]


def _position_label(i: int) -> str:
    return f"feature {i}"


def _as_batch(geometries) -> _Batch | None:
    """Read the caller's container; None for a dask collection (handled lazily elsewhere)."""
    if hasattr(geometries, "__dask_graph__"):
        return None
    gpd = sys.modules.get("geopandas")
    if gpd is not None and isinstance(geometries, (gpd.GeoSeries, gpd.GeoDataFrame)):
        frame = geometries if isinstance(geometries, gpd.GeoDataFrame) else None
        series = frame.geometry if frame is not None else geometries
        flat = np.asarray(series.array, dtype=object).copy()
        index = series.index
        plain = index.equals(__import__("pandas").RangeIndex(len(index)))

        def label(i: int) -> str:
            if plain:
                return f"feature {i}"
            key = index[i]
            return f"feature {i} (index {(key.item() if isinstance(key, np.generic) else key)!r})"

        def wrap(out: np.ndarray):
            s = gpd.GeoSeries(out, index=index, crs=series.crs, name=series.name)
            if frame is None:
                return s
            result = frame.copy()
            result[series.name] = s
            return result

        return _Batch(flat, label, wrap)
    if geometries is None or isinstance(geometries, BaseGeometry):
        return _Batch(np.array([geometries], dtype=object), _position_label, lambda out: out[0])
    if isinstance(geometries, (str, bytes)):
        raise GeometryTypeError(f"geometries must be shapely geometries, got a {type(geometries).__name__}")
    if isinstance(geometries, np.ndarray):
        arr = geometries
    else:
        try:
            items = list(geometries)
        except TypeError:
            raise GeometryTypeError("geometries must be a shapely geometry, an array, a list, a GeoSeries "
                                    f"or a GeoDataFrame, got {type(geometries).__name__}") from None
        arr = np.empty(len(items), dtype=object)
        arr[:] = items
    shape = arr.shape
    flat = np.asarray(arr, dtype=object).reshape(-1).copy()
    if len(shape) <= 1:
        label = _position_label
    else:
        def label(i: int) -> str:
            return f"feature {np.unravel_index(i, shape)}"
    return _Batch(flat, label, lambda out: out.reshape(shape))


# ---------------------------------------------------------------------------------------------------------
# The batch
# ---------------------------------------------------------------------------------------------------------
def _check_processes(processes) -> int:
    if processes is None:
        return 1
    if isinstance(processes, bool) or not isinstance(processes, int) or processes < 1:
        raise ValueError(f"processes must be a whole number ≥ 1 (or None for one), got {processes!r}")
    return processes


def _chunks(order: np.ndarray, weight: np.ndarray, n_chunks: int) -> list[np.ndarray]:
    """Cut the positions ``order`` into about ``n_chunks`` consecutive runs of similar total weight."""
    if len(order) == 0:
        return []
    cum = np.cumsum(weight[order], dtype=float)
    target = cum[-1] / max(1, n_chunks)
    # Each run ends with the feature that brings its total to the next multiple of the target.
    cut = np.searchsorted(cum, target * np.arange(1, n_chunks), side="left") + 1
    cut = np.unique(cut[cut < len(order)])
    return [c for c in np.split(order, cut) if len(c)]


def _map(op: str, geometries, r, *, init="core", tolerance=None, processes=None, errors="raise",
         progress=False):
    """The shared body of the ``*_all`` functions (see `tighten_all`)."""
    r = check_radius(r)
    check_tolerance(tolerance, r)
    if op == "tighten":
        try:
            init = Init(init.value if isinstance(init, Init) else init).value
        except ValueError:
            raise ValueError(f"init must be 'core', 'input' or 'mason', got {init!r}") from None
    if errors not in ("raise", "warn"):
        raise ValueError(f"errors must be 'raise' or 'warn', got {errors!r}")
    n_proc = _check_processes(processes)
    batch = _as_batch(geometries)
    if batch is None:
        return _dask_map(op, geometries, r, init, tolerance, errors)
    flat, label = batch.flat, batch.label
    n = len(flat)
    out = np.empty(n, dtype=object)

    # Sort the features out: missing or empty, not a geometry, not polygonal, polygonal.
    todo: list[int] = []
    passed: list[int] = []
    for i, g in enumerate(flat):
        if g is None:
            out[i] = _empty()
        elif not isinstance(g, BaseGeometry):
            raise GeometryTypeError(f"{label(i)} is a {type(g).__name__}, not a shapely geometry")
        elif g.is_empty:
            out[i] = _empty()
        elif _is_polygonal(g):
            todo.append(i)
        else:
            out[i] = g
            passed.append(i)
    todo_idx = np.array(todo, dtype=np.int64)
    if len(todo_idx):
        coords, which = shapely.get_coordinates(flat[todo_idx], return_index=True)
        bad = np.unique(which[~np.isfinite(coords).all(axis=1)])
        if len(bad):
            raise InvalidGeometryError(f"{label(int(todo_idx[bad[0]]))} has NaN or infinite coordinates "
                                       f"({len(bad)} feature(s) do)")
    if passed:
        kinds = sorted({flat[i].geom_type for i in passed})
        warnings.warn(f"{len(passed)} of {n} geometries are not polygonal ({', '.join(kinds)}; first "
                      f"{label(passed[0])}): passed through unchanged", PassThroughWarning, stacklevel=3)
    if len(todo_idx):
        sub, _ = _repair_each(flat[todo_idx], lambda k: label(int(todo_idx[k])), total=n, stacklevel=4)
        flat = flat.copy()
        flat[todo_idx] = sub
    # A feature repaired into nothing is empty now: it gives an empty result and is counted below.
    work = [i for i in todo if not flat[i].is_empty]
    for i in todo:
        if flat[i].is_empty:
            out[i] = _empty()

    vertices = shapely.get_num_coordinates(flat[work]) if work else np.zeros(0, dtype=np.int64)
    results: dict[int, _Done] = {}
    with FeatureBar(len(work), enabled=progress, desc=_OPS[op][1]) as bar:
        if n_proc == 1 or len(work) <= 1:
            for i, v in zip(work, vertices, strict=True):
                bar.start(label(i), v)
                results[i] = _run_one(op, flat[i], r, init, tolerance)
                bar.advance()
        else:
            order = np.array(work, dtype=np.int64)
            weight = np.zeros(n, dtype=float)
            weight[order] = vertices + 50.0      # a feature costs something however small it is
            parts = _chunks(order, weight, n_proc * _CHUNKS_PER_PROCESS)
            # Fresh interpreters (spawn), one chunk at a time each: a worker that dies (out of memory)
            # fails the features of its own chunk only, and an interrupt terminates every worker at once.
            args = [(op, list(flat[c]), r, init, tolerance) for c in parts]
            for k, ok, value in run_tasks(_run_chunk, args, min(n_proc, len(parts))):
                c = parts[k]
                if not ok and isinstance(value, WorkerDied):
                    value = [_Done(error=value) for _ in c]
                elif not ok:
                    raise value
                for i, d in zip(c.tolist(), value, strict=True):
                    results[i] = d
                bar.advance(len(c))
    _gather(op, results, out, label, n, errors, len(todo) - len(work), r)
    return batch.wrap(out)


def _gather(op, results: dict[int, _Done], out: np.ndarray, label, n: int, errors: str, vanished: int,
            r: float) -> None:
    """Put the results in place; raise the first error or count the failures; gather the warnings."""
    failed = sorted(i for i, d in results.items() if d.error is not None)
    if failed and errors == "raise":
        i = failed[0]
        exc = results[i].error
        more = f" ({len(failed)} feature(s) failed)" if len(failed) > 1 else ""
        if isinstance(exc, TighteningError):
            raise type(exc)(f"{label(i)}: {exc}{more}") from exc
        raise RuntimeError(f"{label(i)}: internal error ({type(exc).__name__}: {exc}){more}") from exc
    if failed:
        names = ", ".join(label(i) for i in failed[:_NAMED]) + (", …" if len(failed) > _NAMED else "")
        first = results[failed[0]].error
        warnings.warn(f"{len(failed)} of {n} feature(s) failed and were given an empty geometry ({names}; "
                      f"first: {type(first).__name__}: {first})", FeatureErrorWarning, stacklevel=4)
    by_kind: dict[tuple[type, str], list[int]] = {}
    empty = vanished
    for i in sorted(results):
        d = results[i]
        out[i] = d.geometry if d.error is None else _empty()
        if d.error is None and d.geometry.is_empty:
            empty += 1
        for category, message in d.warnings:
            by_kind.setdefault((category, message), []).append(i)
    for (category, message), where in by_kind.items():
        names = ", ".join(label(i) for i in where[:_NAMED]) + (", …" if len(where) > _NAMED else "")
        warnings.warn(f"{len(where)} of {n} feature(s): {message} ({names})", category, stacklevel=4)
    what, warn_empty = _OPS[op][1], _OPS[op][2]
    if empty and warn_empty:
        warnings.warn(f"{empty} of {n} feature(s) have an empty {what} (no part of them holds a disk of "
                      f"radius r = {r:g}): their rows are kept with an empty geometry",
                      EmptyTighteningWarning, stacklevel=4)


def _dask_map(op, collection, r, init, tolerance, errors):
    from .io._common import _require

    dgpd = _require("dask_geopandas", "dask", f"{op}_all on a dask collection")
    if not isinstance(collection, (dgpd.GeoSeries, dgpd.GeoDataFrame)):
        raise GeometryTypeError(f"a dask collection must be a dask-geopandas GeoSeries or GeoDataFrame, "
                                f"got {type(collection).__name__}")
    return collection.map_partitions(_partition, op, r, init, tolerance, errors, meta=collection._meta)


def _partition(part, op, r, init, tolerance, errors):
    """One partition of a dask collection (runs on a worker; its warnings stay there)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _map(op, part, r, init=init, tolerance=tolerance, errors=errors)


# ---------------------------------------------------------------------------------------------------------
# Public functions
# ---------------------------------------------------------------------------------------------------------
def tighten_all(geometries, r: float, *, init: str | Init = "core", tolerance: float | None = None,
                processes: int | None = None, errors: str = "raise", progress: bool = False):
    """The exact r-tightening of every geometry, each on its own.

    The vectorised form of `vectortighten.tighten`: each output geometry is
    ``tighten(g, r, init=init, tolerance=tolerance).geometry`` of its input ``g``. Features are never
    united, so neighbouring features are tightened independently: a border they share may open into a
    gap or close into an overlap.

    Parameters
    ----------
    geometries : array_like, list, GeoSeries, GeoDataFrame or dask-geopandas collection
        Shapely geometries (None allowed). See the module's docstring for what each gives back.
    r : float
        The radius, > 0, in the geometries' units (the CRS's units for geodata: metres for UTM).
    init : {"core", "input", "mason"}
        The flow's initial condition, as for `vectortighten.tighten`.
    tolerance : float, optional
        Largest distance between an arc and its chords in each output geometry; default 1e-5·r.
    processes : int, optional
        Worker processes to spread the features over; default one (this process). Each costs an
        interpreter's start (about 0.6 s of CPU); they gain on idle cores only (see the module's notes on
        a busy machine). Ignored for a dask collection, whose scheduler decides.
    errors : {"raise", "warn"}
        A feature the engine fails on raises its error, naming the feature (``"raise"``), or is given an
        empty geometry and counted in a `FeatureErrorWarning` (``"warn"``).
    progress : bool
        Show a progress bar over the features on stderr (tqdm).

    Returns
    -------
    ndarray, GeoSeries, GeoDataFrame, dask collection or geometry
        Of the kind and shape of ``geometries``: one result per input, in order.

    Raises
    ------
    GeometryTypeError
        An element is not a shapely geometry (or None).
    InvalidGeometryError
        A feature has NaN or infinite coordinates.
    InvalidRadiusError
        ``r`` or ``tolerance`` is not a positive finite number.

    Warns
    -----
    EmptyTighteningWarning
        Some results are empty (counted).
    RepairWarning
        Some polygons were invalid and were repaired, each alone (counted).
    PassThroughWarning
        Some geometries are not polygonal and were passed through unchanged (counted).

    Examples
    --------
    >>> import warnings
    >>> from shapely.geometry import box
    >>> out = tighten_all([box(0, 0, 4, 4), None, box(10, 0, 18, 8)], 1.0)
    >>> [round(g.area, 4) for g in out]                     # a² − (4 − π)r², nothing, a² − (4 − π)r²
    [15.1416, 0.0, 63.1416]
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     out = tighten_all([box(0, 0, 4, 4), box(0, 0, 1, 9)], 1.0)   # the second is thinner than 2r
    >>> out[1].is_empty, w[0].category.__name__
    (True, 'EmptyTighteningWarning')
    """
    return _map("tighten", geometries, r, init=init, tolerance=tolerance, processes=processes,
                errors=errors, progress=progress)


def core_all(geometries, r: float, *, tolerance: float | None = None, processes: int | None = None,
             errors: str = "raise", progress: bool = False):
    """The core ``R_r(S)`` of every geometry, each on its own (see `tighten_all` for the conventions).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> [round(g.area, 4) for g in core_all([box(0, 0, 4, 4), box(0, 0, 6, 6)], 1.0)]
    [15.1416, 35.1416]
    """
    return _map("core", geometries, r, tolerance=tolerance, processes=processes, errors=errors,
                progress=progress)


def fillet_all(geometries, r: float, *, tolerance: float | None = None, processes: int | None = None,
               errors: str = "raise", progress: bool = False):
    """The fillet ``F_r(S)`` of every geometry, each on its own (see `tighten_all` for the conventions).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> g = box(0, 0, 4, 4).difference(box(1.5, 1.5, 2.5, 2.5))      # a hole narrower than 2r
    >>> [round(f.area, 6) for f in fillet_all([g], 1.0)]
    [16.0]
    """
    return _map("fillet", geometries, r, tolerance=tolerance, processes=processes, errors=errors,
                progress=progress)


def mortar_all(geometries, r: float, *, tolerance: float | None = None, processes: int | None = None,
               errors: str = "raise", progress: bool = False):
    """The mortar ``F_r(S) − R_r(S)`` of every geometry, each on its own (see `tighten_all`).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> [round(m.area, 4) for m in mortar_all([box(0, 0, 4, 4)], 1.0)]     # the four corners, (4 − π)r²
    [0.8584]
    """
    return _map("mortar", geometries, r, tolerance=tolerance, processes=processes, errors=errors,
                progress=progress)


def mason_all(geometries, r: float, *, tolerance: float | None = None, processes: int | None = None,
              errors: str = "raise", progress: bool = False):
    """The self-dual Mason filter of every geometry, each on its own (see `tighten_all`).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> [round(m.area, 4) for m in mason_all([box(0, 0, 4, 4)], 1.0)]
    [15.1416]
    """
    return _map("mason", geometries, r, tolerance=tolerance, processes=processes, errors=errors,
                progress=progress)
