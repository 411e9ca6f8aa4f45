"""Tightening a geodata file feature by feature: what the command line does with a layer.

Read one layer (`vectortighten.io.read_features`, with the reader's options: ``layer``, ``crs``), check
its CRS (``r`` is a length in the CRS's units,
so degrees are refused unless the features are reprojected), tighten every feature on its own
(`vectortighten.tighten_all`, or a dask cluster), and write one output feature per input feature, in
order, with every attribute and the CRS unchanged.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from . import io
from ._progress import FeatureBar
from .errors import CRSError, EmptyTighteningWarning, GeometryTypeError, InvalidGeometryError
from .io._common import _require
from .vectorized import _is_polygonal, _repair_each, tighten_all

__all__ = ["GeoOptions", "crs_unit", "holds_features", "tighten_features_file"]


@dataclass(frozen=True)
class GeoOptions:
    """How the command line tightens a geodata layer (all optional).

    The reader's own options, ``layer`` and ``crs``, travel apart (`vectortighten.io.Format.read_options`).
    """

    to_crs: str | None = None
    input_format: str | None = None
    output_format: str | None = None
    processes: int | None = None
    dask: str | None = None
    skip_failed: bool = False
    progress: bool = False


def holds_features(path: Path, format: str | None = None) -> bool:
    """Whether ``path`` is a geodata layer (and not a shape: SVG, WKT, a bare-geometry GeoJSON)."""
    try:
        fmt = io.format_of(path, format)
    except ValueError:
        return False         # the shape reader names the unsupported format
    if not fmt.holds_features:
        return False
    if fmt.name == "geojson" and path.exists():
        return not io.geo.geojson_is_plain(path)
    return True


def crs_unit(crs) -> str:
    """The unit of a CRS's first axis, as pyproj names it ("metre", "US survey foot").

    Examples
    --------
    >>> import pyproj
    >>> crs_unit(pyproj.CRS("EPSG:32631")), crs_unit(pyproj.CRS("EPSG:2263"))
    ('metre', 'US survey foot')
    """
    axes = getattr(crs, "axis_info", None) or []
    return axes[0].unit_name if axes else "unit"


def _crs_label(crs) -> str:
    code = crs.to_authority() if crs is not None else None
    return f"{crs.name} ({code[0]}:{code[1]})" if code else (crs.name if crs is not None else "no CRS")


def _parse_crs(text: str, option: str):
    return io.geo.parse_crs(text, option)


def _suggestion(geoms, crs) -> str:
    """A projected CRS to suggest for data in degrees: its UTM zone if it is narrow, else Equal Earth."""
    parts = [g for g in geoms if g is not None and not g.is_empty]
    if parts:
        x0, y0, x1, y1 = shapely.total_bounds(np.array(parts, dtype=object))
        if math.isfinite(x0) and -180 <= x0 and x1 <= 180 and -80 <= y0 and y1 <= 84 and x1 - x0 <= 6:
            zone = int((0.5 * (x0 + x1) + 180) // 6) % 60 + 1
            epsg = (32600 if 0.5 * (y0 + y1) >= 0 else 32700) + zone
            return f"e.g. --to-crs EPSG:{epsg} (UTM zone {zone}, metres)"
    return "e.g. --to-crs EPSG:8857 (Equal Earth, metres) or your national grid"


def _check_crs(features, source: Path, options: GeoOptions, r: float):
    """The CRS to tighten in, and whether the features must be reprojected into it first."""
    crs = features.meta.get("crs")
    layer = features.meta.get("layer")
    if crs is None:
        if features.meta.get("crs_unreadable"):
            raise CRSError(f"{source}: its .prj cannot be read as a CRS, so the unit of r is unknown; say "
                           "what the coordinates are with --crs CRS (e.g. --crs EPSG:25832)")
        raise CRSError(f"{source}: layer {layer!r} has no CRS, so the unit of r is unknown; say what its "
                       "coordinates are with --crs CRS (e.g. --crs EPSG:25832)")
    source_crs = crs
    if options.to_crs is not None:
        target = _parse_crs(options.to_crs, "--to-crs")
        if target.is_geographic or target.is_geocentric or not (target.is_projected or target.is_engineering):
            raise CRSError(f"--to-crs {options.to_crs}: {_crs_label(target)} is not a projected CRS "
                           f"(its unit is {crs_unit(target)}); name one in metres or feet, "
                           f"{_suggestion(features.geometry, crs).removeprefix('e.g. ')}")
        return source_crs, target
    if crs.is_geographic or crs.is_geocentric:
        hint = (' (a GeoJSON without a "crs" member is WGS 84 by RFC 7946)'
                if features.meta.get("format") == "geojson" else "")
        raise CRSError(f"{source}: {_crs_label(crs)} is a geographic CRS{hint}: its coordinates are degrees "
                       f"and r = {r:g} would be read in {crs_unit(crs)}s; reproject to a projected CRS, "
                       f"{_suggestion(features.geometry, crs)}")
    return source_crs, crs


def _n_emptied(geoms, out) -> int:
    """How many polygonal features came out empty."""
    return sum(1 for g, h in zip(geoms, out, strict=True)
               if g is not None and not g.is_empty and _is_polygonal(g) and h.is_empty)


def _kinds(geoms) -> tuple[int, dict[str, int]]:
    """How many features are polygonal, and the others by geometry type."""
    polygonal, other = 0, {}
    for g in geoms:
        if g is None or g.is_empty:
            continue
        if _is_polygonal(g):
            polygonal += 1
        else:
            other[g.geom_type] = other.get(g.geom_type, 0) + 1
    return polygonal, other


def tighten_features_file(source: Path, target: Path, *, r: float, init: str, tolerance: float | None,
                          options: GeoOptions, read_options: dict | None = None) -> str:
    """Tighten every feature of a geodata layer and write them, one output feature per input feature.

    ``read_options`` are the reader's (``layer``, and ``crs`` given as text, as ``--crs`` has it).

    Returns
    -------
    str
        The summary line for stdout.

    Raises
    ------
    CRSError
        No CRS, an unreadable one, or a geographic one without ``to_crs``.
    GeometryTypeError
        The layer holds no polygon.
    ValueError
        The output is not a geodata format, or cannot hold the layer's geometry types.
    """
    fmt_in = io.format_of(source, options.input_format)
    fmt_out = io.format_of(target, options.output_format)

    def check_output():
        if not fmt_out.holds_features:
            formats = ", ".join(e for f in io.FORMATS.values() if f.write_features for e in f.extensions)
            raise ValueError(f"{source} is a layer of features ({fmt_in.title}): write it to a geodata "
                             f"format ({formats}), not {target.suffix or '(no extension)'}")

    if fmt_in.name != "geojson":      # a malformed GeoJSON is reported as such, whatever the output
        check_output()
    read_options = dict(read_options or {})
    if read_options.get("crs") is not None:
        read_options["crs"] = _parse_crs(read_options["crs"], "--crs")
    features = io.read_features(source, format=options.input_format, **read_options)
    check_output()
    layer = features.meta.get("layer")
    n = len(features)
    if n == 0:
        raise InvalidGeometryError(f"{source}: layer {layer!r} has no features")
    polygonal, other = _kinds(features.geometry)
    if polygonal == 0:
        found = ", ".join(f"{k} {t}" for t, k in sorted(other.items())) or "only empty geometries"
        raise GeometryTypeError(f"{source}: layer {layer!r} holds no polygons ({found}); nothing to tighten")
    if other and fmt_out.name == "shp":
        found = ", ".join(f"{k} {t}" for t, k in sorted(other.items()))
        raise ValueError(f"{target}: a Shapefile holds one kind of geometry, but {found} feature(s) of "
                         f"{source} are not polygons and would be passed through unchanged; write "
                         "GeoPackage, GeoJSON or FlatGeobuf instead")
    source_crs, crs = _check_crs(features, source, options, r)
    geoms = features.geometry
    if crs is not source_crs:
        gpd = _require("geopandas", "geo", "--to-crs")
        geoms = np.asarray(gpd.GeoSeries(geoms, crs=source_crs).to_crs(crs).array, dtype=object)
    errors = "warn" if options.skip_failed else "raise"
    if options.dask:
        out = _tighten_on_dask(geoms, crs, options, r=r, init=init, tolerance=tolerance, errors=errors)
    else:
        out = tighten_all(geoms, r, init=init, tolerance=tolerance, processes=options.processes,
                          errors=errors, progress=options.progress)
    fmt_out.write_features(features.with_geometry(out, crs=crs, format=fmt_out.name), target)
    empty = _n_emptied(geoms, out)
    parts = [f"{n} feature(s)", f"r = {r:g} {crs_unit(crs)} in {_crs_label(crs)}"]
    if crs is not source_crs:
        parts.append(f"reprojected from {_crs_label(source_crs)}")
    if empty:
        parts.append(f"{empty} empty")
    if other:
        parts.append(f"{sum(other.values())} not polygonal, passed through")
    return f"{target}: " + ", ".join(parts)


def _client(scheduler: str, processes: int | None):
    """A dask.distributed client: ``local`` or ``local:N`` starts a cluster here, else an address."""
    distributed = _require("distributed", "dask", "--dask")
    if scheduler == "local" or scheduler.startswith("local:"):
        text = scheduler.partition(":")[2]
        try:
            workers = int(text) if text else (processes or None)
        except ValueError:
            raise ValueError(f"--dask {scheduler}: expected local or local:N (N workers)") from None
        cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                           dashboard_address=None)
        return distributed.Client(cluster), cluster
    try:
        return distributed.Client(scheduler), None       # dask's connect timeout applies
    except (OSError, TimeoutError, ValueError) as exc:
        raise OSError(f"--dask {scheduler}: cannot reach the scheduler ({exc})") from None


def _tighten_on_dask(geoms, crs, options: GeoOptions, *, r, init, tolerance, errors):
    """`tighten_all` of the features through a dask.distributed cluster, partition by partition."""
    distributed = _require("distributed", "dask", "--dask")
    dgpd = _require("dask_geopandas", "dask", "--dask")
    gpd = _require("geopandas", "geo", "--dask")
    # Repairs are counted here: warnings raised on the workers stay there.
    geoms, _ = _repair_each(np.asarray(geoms, dtype=object), stacklevel=3)
    client, cluster = _client(options.dask, options.processes)
    try:
        workers = max(1, len(client.scheduler_info().get("workers", {})) or 1)
        series = gpd.GeoSeries(geoms, crs=crs)
        lazy = tighten_all(dgpd.from_geopandas(series, npartitions=max(1, min(len(series), 4 * workers))), r,
                           init=init, tolerance=tolerance, errors=errors)
        futures = client.compute(lazy.to_delayed())
        done = {}
        with FeatureBar(len(series), enabled=options.progress) as bar:
            for fut in distributed.as_completed(futures):
                done[fut.key] = fut.result()
                bar.advance(len(done[fut.key]))
        out = np.concatenate([np.asarray(done[f.key].array, dtype=object) for f in futures])
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    empty = _n_emptied(geoms, out)
    if empty:
        warnings.warn(f"{empty} of {len(out)} feature(s) have an empty tightening (no part of them holds a "
                      f"disk of radius r = {r:g}): their rows are kept with an empty geometry",
                      EmptyTighteningWarning, stacklevel=3)
    return out
