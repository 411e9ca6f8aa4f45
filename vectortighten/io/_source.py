"""What a reader hands to the writer: the geometry, and what must travel with it to the output.

Two records, one vocabulary. A reader of a file that holds *one shape* (SVG, DXF, WKT, a bare GeoJSON
geometry, or a geodata layer read as one shape) returns a `Source`: the flattened shape the engine takes,
the exact boundary as `Loop`s where the file has one, and ``meta``. A reader of a file that holds
*features* (a geodata layer: GeoPackage, Shapefile, GeoJSON, FlatGeobuf, GeoParquet) returns `Features`:
one geometry a feature, their attributes, and ``meta``. ``meta`` is the same plain dict in both: what a
writer needs to put the result back where the input was. Every key is optional; a writer uses the ones it
knows and ignores the rest, so a `Source.meta` of a GeoPackage carries its CRS to a GeoPackage output and
its units to a DXF one, and an SVG's page travels to an SVG output and nowhere else.

Keys every family may set:

``"format"`` : str
    The name of the format read (a key of `vectortighten.io.FORMATS`: ``"svg"``, ``"dxf"``, ``"gpkg"``…).
``"units"`` : str or None
    The physical length of one coordinate unit (``"mm"``, ``"in"``, ``"px"``, ``"m"``, ``"us_ft"``…; a key
    of `MM_PER_UNIT`), None when the file does not say (unitless). Geodata: the unit of the CRS's axes
    when it is a length (None for degrees).

Keys of the CAD and SVG readers and writers:

``"mm_per_unit"`` : float or None
    The same as a number: millimetres per coordinate unit, when known (also for an SVG whose user unit is
    not a whole unit, e.g. ``width="210mm" viewBox="0 0 1000 1414"``).
``"insunits"`` : int
    The DXF ``$INSUNITS`` code a DXF output declares (a DXF input's own; derived for an SVG).
``"dxf_transform"`` : (scale, dx, dy)
    ``p -> scale·p + (dx, dy)`` from the read coordinates to those a DXF output is written in (the
    identity when absent).
``"page"`` : dict
    SVG: the root's ``width``, ``height``, ``viewBox`` and ``preserveAspectRatio`` as written, which an
    SVG output keeps.
``"styles"`` : object
    SVG: what `svg_document` needs to give each output path the style of the element it comes from.
``"layers"`` : tuple of str
    DXF: the layers whose entities were read.
``"nesting"`` : str
    SVG: the reading used, ``"evenodd"`` (cut file) or ``"paint"``.

Keys of the geodata readers and writers:

``"crs"`` : pyproj.CRS or None
    The layer's coordinate reference system, written to a geodata output exactly as read.
``"layer"`` : str
    The layer's name, which a geodata output keeps.
``"geometry_name"`` : str or None
    The geometry column's name in the file (a GeoPackage output keeps it).
``"crs_unreadable"`` : bool
    A Shapefile whose ``.prj`` GDAL cannot read (``"crs"`` is None then).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from shapely.geometry import MultiPolygon, Polygon

__all__ = ["INSUNITS", "MM_PER_UNIT", "Features", "Source", "crs_units"]

#: Millimetres per unit, for every unit a reader may report (SVG's CSS units and DXF's ``$INSUNITS``).
MM_PER_UNIT: dict[str, float] = {
    "mm": 1.0, "cm": 10.0, "in": 25.4, "pt": 25.4 / 72.0, "pc": 25.4 / 6.0, "px": 25.4 / 96.0,
    "ft": 304.8, "mi": 1_609_344.0, "m": 1000.0, "km": 1e6, "uin": 25.4e-6, "mil": 0.0254, "yd": 914.4,
    "angstrom": 1e-7, "nm": 1e-6, "um": 1e-3, "dm": 100.0, "dam": 1e4, "hm": 1e5, "Gm": 1e12,
    "au": 1.495978707e14, "ly": 9.4607304725808e18, "parsec": 3.0856775814913673e19,
    "us_ft": 1200.0 / 3937.0 * 1000.0,
}

#: DXF ``$INSUNITS`` codes and the unit each stands for (0: unitless).
INSUNITS: dict[int, str | None] = {
    0: None, 1: "in", 2: "ft", 3: "mi", 4: "mm", 5: "cm", 6: "m", 7: "km", 8: "uin", 9: "mil", 10: "yd",
    11: "angstrom", 12: "nm", 13: "um", 14: "dm", 15: "dam", 16: "hm", 17: "Gm", 18: "au", 19: "ly",
    20: "parsec", 21: "us_ft",
}


@dataclass
class Source:
    """A shape read from a file, with its exact boundary and what must travel to the writer.

    Attributes
    ----------
    shape : Polygon or MultiPolygon
        The region read, curves flattened within the reader's tolerance: what `vectortighten.tighten`
        takes.
    meta : dict
        What a writer needs to put a result back in the input's frame (see the module's notes).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> src = Source(box(0, 0, 2, 1), {"units": "mm"})
    >>> src.units, src.loops is None
    ('mm', True)
    """

    shape: Polygon | MultiPolygon
    meta: dict[str, Any] = field(default_factory=dict)
    _loops: Callable[[], list | None] | None = field(default=None, repr=False)
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def loops(self):
        """The exact boundary as `Loop`s (outer boundaries counter-clockwise, holes clockwise), or None.

        Arcs and circles are exact `Arc`s; ellipses, splines and Bézier curves are chains of `Segment`s
        (flattened, like ``shape``). None when the boundary of ``shape`` is not made of whole outlines of
        the file (outlines that cross or touch, shapes painted over each other) or when the reader keeps
        no exact boundary. Built on first use.
        """
        if "loops" not in self._cache:
            self._cache["loops"] = self._loops() if self._loops is not None else None
        return self._cache["loops"]

    @property
    def units(self) -> str | None:
        """The physical unit of one coordinate unit, or None (unitless)."""
        return self.meta.get("units")

    @property
    def layers(self) -> tuple[str, ...]:
        """The layers read (DXF), else ``()``."""
        return tuple(self.meta.get("layers", ()))

    @property
    def crs(self):
        """The coordinate reference system (geodata; a ``pyproj.CRS``), or None."""
        return self.meta.get("crs")


@dataclass
class Features:
    """Features read from a file: one geometry each, their attributes, and what travels to the writer.

    A reader of a format that holds features (GeoPackage, Shapefile, GeoJSON, FlatGeobuf, GeoParquet)
    returns this; the writer of such a format takes it back and puts everything in ``meta`` and
    ``attributes`` into the output unchanged, so only the geometry changes between input and output.

    Attributes
    ----------
    geometry : (n,) object ndarray
        One shapely geometry (or None) per feature, in the file's order.
    attributes : pandas.DataFrame or None
        One row per feature (same order), every column but the geometry; None when there are none.
    meta : dict
        What the writer needs to reproduce the source, with the keys of `Source.meta` (see the module's
        notes): geodata readers set ``"crs"``, ``"layer"``, ``"geometry_name"``, ``"format"`` and
        ``"units"``.

    Examples
    --------
    >>> import numpy as np
    >>> from shapely.geometry import box
    >>> f = Features(np.array([box(0, 0, 1, 1)], dtype=object), meta={"layer": "parcels"})
    >>> len(f), f.with_geometry(np.array([None], dtype=object)).meta["layer"]
    (1, 'parcels')
    """

    geometry: Any
    attributes: Any = None
    meta: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.geometry)

    def with_geometry(self, geometry, **meta) -> Features:
        """The same features with new geometries (and ``meta`` updated by the keywords)."""
        geometry = np.asarray(geometry, dtype=object)
        if len(geometry) != len(self.geometry):
            raise ValueError(f"{len(geometry)} geometries for {len(self.geometry)} features")
        return Features(geometry, self.attributes, {**self.meta, **meta})

    @property
    def crs(self):
        """The coordinate reference system (a ``pyproj.CRS``), or None."""
        return self.meta.get("crs")


#: pyproj's names of length units, and the key of `MM_PER_UNIT` each is.
_CRS_UNITS = {"metre": "m", "meter": "m", "kilometre": "km", "foot": "ft", "US survey foot": "us_ft",
              "international foot": "ft", "yard": "yd", "mile": "mi", "centimetre": "cm", "millimetre": "mm"}


def crs_units(crs) -> str | None:
    """The unit of a projected CRS's coordinates as a key of `MM_PER_UNIT`, or None (degrees, unknown).

    Examples
    --------
    >>> import pyproj
    >>> crs_units(pyproj.CRS("EPSG:32631")), crs_units(pyproj.CRS("EPSG:2263")), crs_units(pyproj.CRS(4326))
    ('m', 'us_ft', None)
    """
    if crs is None or getattr(crs, "is_geographic", False):
        return None
    axes = getattr(crs, "axis_info", None) or []
    return _CRS_UNITS.get(axes[0].unit_name) if axes else None
