"""DXF: cut files read into a shape (with its exact boundary), tightenings written in the input's frame.

Reading (`read_dxf`): the model space's LINE, ARC, CIRCLE, LWPOLYLINE and POLYLINE (bulges are exact
arcs), ELLIPSE and SPLINE (flattened within ``flatten``; an ELLIPSE whose axes are equal is a circular
arc, exact), also inside INSERTed blocks (nested, arrays included; entities of a block on layer ``0`` take
the layer of the INSERT). Loose entities are joined end to end into closed outlines within ``gap``; the
closed outlines are nested by the even-odd rule: inside one outline is material, inside two a hole,
inside three material again (the usual meaning of a cut file). Curves lie in planes parallel to XY
(extrusion ±Z; any constant elevation) and are projected onto it. Units come from ``$INSUNITS``.

Writing (`write_dxf`): LINE and ARC entities (or closed LWPOLYLINEs with bulges), a loop that is one full
circle as a CIRCLE, every arc of radius exactly r, in the input's units and at its position.

ezdxf (``pip install vectortighten[dxf]``) is imported only when a DXF file is met.
"""

from __future__ import annotations

import math
import warnings
from collections import Counter
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from vectortighten.curves import Arc, Segment
from vectortighten.errors import InvalidGeometryError

from ._common import _require
from ._outline import DEFAULT_GAP, Chain, assemble, drop_duplicates, join
from ._source import INSUNITS, MM_PER_UNIT, Source

__all__ = ["DXF_ENTITIES", "MAX_ENTITIES", "full_circle", "read_dxf", "write_dxf"]

#: What ``entities=`` (``--dxf-entities``) may ask `write_dxf` for.
DXF_ENTITIES = ("lines-arcs", "lwpolyline")
#: Most entities a drawing may expand to (block arrays multiply): beyond, the file is refused.
MAX_ENTITIES = 1_000_000
# Deepest nesting of blocks followed.
_MAX_DEPTH = 64
# Default chord tolerance of ellipses and splines, as a fraction of the drawing's diagonal (as SVG's).
_DEFAULT_FLATTEN = 1e-4
_BINARY_SENTINEL = b"AutoCAD Binary DXF\r\n\x1a\x00"
# Entities that only a 3D reading can use.
_SOLID_3D = {"3DFACE", "3DSOLID", "MESH", "SURFACE", "BODY", "PLANESURFACE", "EXTRUDEDSURFACE",
             "LOFTEDSURFACE", "REVOLVEDSURFACE", "SWEPTSURFACE", "POLYFACE", "POLYMESH"}
_CURVES = {"LINE", "ARC", "CIRCLE", "LWPOLYLINE", "POLYLINE", "ELLIPSE", "SPLINE"}
_FLATTENED = {"ELLIPSE", "SPLINE"}          # read within the flatten tolerance (all others are exact)
_UNIT_CODE = {name: code for code, name in INSUNITS.items() if name is not None}


# ---------------------------------------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------------------------------------
def read_dxf(path, *, layers=None, flatten: float | None = None, gap: float | None = None) -> Source:
    """Read the region a DXF cut file outlines (see the module's notes), with its exact boundary.

    Parameters
    ----------
    path : str or Path
        An ASCII or binary DXF file.
    layers : iterable of str, optional
        Read only entities on these layers (case-insensitive). Default: every layer that is on and
        thawed.
    flatten : float, optional
        Largest distance between an ellipse or spline and its chords, and between an arc and the chords
        of ``shape``, in drawing units. Default 1e-4 of the drawing's diagonal.
    gap : float, optional
        Two ends of outlines nearer than this join, in drawing units. Default `DEFAULT_GAP` (1e-6) of the
        drawing's diagonal.

    Returns
    -------
    Source
        ``shape`` (the even-odd region, arcs by chords within ``flatten``), ``loops`` (the exact boundary:
        arcs and circles as `Arc`s of their own radius; None if outlines cross or touch) and ``meta``:
        ``units`` (from ``$INSUNITS``; None when unitless), ``insunits``, ``mm_per_unit``, ``layers``.

    Raises
    ------
    InvalidGeometryError
        Not a DXF (or a DWG), a corrupt file, an empty model space, no closed outline, an open outline or
        branch (located), entities off the XY plane, a block that inserts itself, unknown layers.
    MissingDependencyError
        ezdxf is not installed.

    Examples
    --------
    >>> import ezdxf, tempfile, pathlib
    >>> doc = ezdxf.new("R2010"); doc.header["$INSUNITS"] = 4                  # mm
    >>> msp = doc.modelspace()
    >>> _ = msp.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    >>> _ = msp.add_circle((10, 10), 4)                                         # a hole
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "plate.dxf"; doc.saveas(p)
    ...     src = read_dxf(p)
    >>> src.units, len(src.loops), [round(lp.area, 6) for lp in src.loops]
    ('mm', 2, [800.0, -50.265482])
    """
    ezdxf = _require("ezdxf", "dxf", "reading DXF")
    path = Path(path)
    name = str(path)
    if flatten is not None and not (math.isfinite(flatten) and flatten > 0):
        raise ValueError(f"flatten must be a positive finite number, got {flatten!r}")
    if gap is not None and not (math.isfinite(gap) and gap >= 0):
        raise ValueError(f"gap must be a finite number >= 0, got {gap!r}")
    doc = _open(ezdxf, path, name)
    try:
        msp = doc.modelspace()
    except (KeyError, ezdxf.DXFError):      # a corrupt file whose block records lack the model space
        raise InvalidGeometryError(f"{name}: malformed DXF (it has no model space)") from None
    if len(msp) == 0:
        raise InvalidGeometryError(f"{name}: the model space is empty (nothing to read)")
    wanted = None if layers is None else {str(n).casefold() for n in layers}
    if wanted is not None and not wanted:
        raise ValueError("layers must name at least one layer")
    walk = _Walk(doc, name, wanted)
    try:
        walk.run(msp)
    except ezdxf.DXFError as exc:      # an entity of a corrupt file lacks what its type must have
        detail = str(exc).split("\n")[0][:120] or type(exc).__name__
        raise InvalidGeometryError(f"{name}: malformed DXF ({detail})") from None
    if wanted is not None:
        missing = sorted(wanted - walk.matched)
        if missing:
            known = sorted(walk.seen_layers, key=str.casefold)
            raise InvalidGeometryError(f"{name}: no entities on layer(s) {', '.join(map(repr, missing))}; "
                                       f"the drawing's layers are {', '.join(map(repr, known)) or '(none)'}")
    if not walk.curves:
        found = ", ".join(f"{n} {k}" for k, n in sorted(walk.skipped.items())) or "nothing readable"
        raise InvalidGeometryError(f"{name}: no outlines in the model space (found {found})")
    if walk.hidden:
        warnings.warn(f"{name}: entities on hidden (off or frozen) layer(s) "
                      f"{', '.join(map(repr, sorted(walk.hidden)))} skipped; name them with --layer to read "
                      "them", UserWarning, stacklevel=2)
    if walk.skipped:
        kinds = ", ".join(f"{n} {k}" for k, n in sorted(walk.skipped.items()))
        warnings.warn(f"{name}: {kinds} ignored (only LINE, ARC, CIRCLE, LWPOLYLINE, POLYLINE, ELLIPSE and "
                      "SPLINE outline a cut)", UserWarning, stacklevel=2)
    # Exact outlines first; their extent (with that of the curves to flatten) sets the default tolerances.
    chains, curved = [], []
    for e, layer, where in walk.curves:
        if e.dxftype() in _FLATTENED:
            curved.append((e, layer, where))
        else:
            chains += _chains_of(e, layer, where, math.inf, name)
    boxes = [c.box() for c in chains]
    if curved:
        ebbox = _require("ezdxf.bbox", "dxf", "reading DXF")
        box = ebbox.extents([e for e, _, _ in curved], fast=True)
        if box.has_data:
            boxes.append((*box.extmin.vec2, *box.extmax.vec2))
    b = np.array(boxes, dtype=float).reshape(-1, 4)
    diag = math.hypot(b[:, 2].max() - b[:, 0].min(), b[:, 3].max() - b[:, 1].min()) if len(b) else 0.0
    if not (math.isfinite(diag) and diag > 0):
        raise InvalidGeometryError(f"{name}: the outlines have no extent (zero length, or NaN or infinite "
                                   "coordinates)")
    tol = flatten if flatten is not None else _DEFAULT_FLATTEN * diag
    gap_tol = gap if gap is not None else DEFAULT_GAP * diag
    for e, layer, where in curved:
        chains += _chains_of(e, layer, where, tol, name)
    if not chains:
        raise InvalidGeometryError(f"{name}: every outline has zero length")
    closed, open_ = [], []
    for c in chains:
        (closed if np.hypot(*(c.end - c.start)) <= gap_tol else open_).append(c)
    closed, dup_closed = drop_duplicates(closed, gap_tol, closed=True)
    open_, dup_open = drop_duplicates(open_, gap_tol, closed=False)
    dropped = dup_closed + dup_open
    if dropped:
        warnings.warn(f"{name}: {len(dropped)} outline(s) drawn twice read once (e.g. {dropped[0].label})",
                      UserWarning, stacklevel=2)
    loops = join(closed + open_, gap_tol, diag, name)
    shape, exact = assemble(loops, tol)
    if shape.is_empty:
        raise InvalidGeometryError(f"{name}: the closed outlines enclose no area")
    insunits = int(doc.header.get("$INSUNITS", 0) or 0)
    unit = INSUNITS.get(insunits)
    meta = {"format": "dxf", "units": unit, "insunits": insunits,
            "mm_per_unit": MM_PER_UNIT[unit] if unit else None,
            "layers": tuple(sorted(walk.read_layers, key=str.casefold)), "dxf_transform": (1.0, 0.0, 0.0)}
    return Source(shape, meta, exact)


def _open(ezdxf, path: Path, name: str):
    """The ezdxf document of ``path``; a file that is not a readable DXF is refused in one line."""
    with open(path, "rb") as f:
        head = f.read(64)
    if head[:4] == b"AC10" or head[:2] == b"AC" and head[2:6].isdigit():
        raise InvalidGeometryError(f"{name}: this is a DWG file ({head[:6].decode('ascii', 'replace')}), "
                                   "not DXF; save it as DXF from the CAD program")
    binary = head.startswith(_BINARY_SENTINEL)
    kind = "binary DXF" if binary else "DXF"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ezdxf.readfile(path)
    except ezdxf.DXFStructureError as exc:
        raise InvalidGeometryError(f"{name}: malformed {kind} ({exc})") from None
    except OSError as exc:
        if "not a DXF file" in str(exc):
            raise InvalidGeometryError(f"{name}: not a DXF file") from None
        raise
    except Exception as exc:  # ezdxf's parsers raise what they meet on corrupt data (struct, value errors)
        detail = str(exc).split("\n")[0][:120] or type(exc).__name__
        raise InvalidGeometryError(f"{name}: malformed {kind}, truncated or corrupt ({detail})") from None


class _Walk:
    """The model space's entities, blocks expanded, filtered by layer; what was skipped, by type."""

    def __init__(self, doc, name: str, wanted):
        self.doc, self.name, self.wanted = doc, name, wanted
        self.curves: list = []                 # (entity, layer, where)
        self.skipped: Counter = Counter()
        self.hidden: set[str] = set()
        self.matched: set[str] = set()
        self.seen_layers: set[str] = set()
        self.read_layers: set[str] = set()
        self.count = 0
        self._hidden_cache: dict[str, bool] = {}

    def _is_hidden(self, layer: str) -> bool:
        if layer not in self._hidden_cache:
            rec = self.doc.layers.get(layer) if self.doc.layers.has_entry(layer) else None
            self._hidden_cache[layer] = bool(rec is not None and (rec.is_off() or rec.is_frozen()))
        return self._hidden_cache[layer]

    def _take(self, layer: str) -> bool:
        self.seen_layers.add(layer)
        key = layer.casefold()
        if self.wanted is not None:
            if key not in self.wanted:
                return False
            self.matched.add(key)
            return True
        if self._is_hidden(layer):
            self.hidden.add(layer)
            return False
        return True

    def run(self, entities, stack: tuple[str, ...] = (), layer0: str | None = None, where: str = "") -> None:
        for e in entities:
            self.count += 1
            if self.count > MAX_ENTITIES:
                raise InvalidGeometryError(f"{self.name}: the drawing expands to more than {MAX_ENTITIES:,} "
                                           "entities (nested block arrays); refused")
            kind = e.dxftype()
            layer = e.dxf.get("layer", "0")
            if layer == "0" and layer0 is not None:
                layer = layer0
            if e.dxf.get("invisible", 0):
                continue
            if kind == "INSERT":
                self._insert(e, stack, layer, where)
                continue
            if kind in _SOLID_3D or (kind == "POLYLINE" and (e.is_poly_face_mesh or e.is_polygon_mesh)):
                raise InvalidGeometryError(f"{self.name}: {_label(e, layer, where)} is a 3D entity; a "
                                           "cut file is a 2D drawing in the XY plane (export a 2D view or "
                                           "section)")
            if not self._take(layer):
                continue
            if kind in _CURVES:
                self.curves.append((e, layer, where))
                self.read_layers.add(layer)
            else:
                self.skipped[kind] += 1

    def _insert(self, e, stack, layer, where) -> None:
        block = e.dxf.name
        if block in stack:
            cycle = " → ".join((*stack[stack.index(block):], block))
            raise InvalidGeometryError(f"{self.name}: block {block!r} inserts itself ({cycle}); refused")
        if len(stack) >= _MAX_DEPTH:
            raise InvalidGeometryError(f"{self.name}: blocks nested deeper than {_MAX_DEPTH} "
                                       f"({' → '.join(stack[:3])} → …); refused")
        if self.doc.blocks.get(block) is None:
            raise InvalidGeometryError(f"{self.name}: INSERT #{e.dxf.get('handle', '?')} refers to the "
                                       f"undefined block {block!r}")
        self.seen_layers.add(layer)
        if self.wanted is None and self._is_hidden(layer):
            self.hidden.add(layer)
            return
        here = f"block {block!r} (INSERT #{e.dxf.get('handle', '?')})" if not where else where
        try:
            inserts = list(e.multi_insert()) if e.mcount > 1 else [e]
            for ins in inserts:
                self.run(list(ins.virtual_entities()), (*stack, block), layer, here)
        except InvalidGeometryError:
            raise
        except Exception as exc:  # ezdxf cannot transform some entity (e.g. a non-uniform scale of text)
            raise InvalidGeometryError(f"{self.name}: cannot expand block {block!r} "
                                       f"({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"
                                       ) from None


def _label(e, layer: str, where: str) -> str:
    handle = e.dxf.get("handle")
    what = f"{e.dxftype()} #{handle}" if handle else e.dxftype()
    return f"{what} on layer {layer!r}" + (f" in {where}" if where else "")


def _flat_error(name, e, layer, where) -> InvalidGeometryError:
    return InvalidGeometryError(f"{name}: {_label(e, layer, where)} is off the XY plane (3D); a cut file is "
                                "a 2D drawing (flatten it in the CAD program)")


def _check_plane(name, e, layer, where, zs, size) -> None:
    """Every z of an entity the same (to rounding): it lies in a plane parallel to XY."""
    zs = np.asarray(zs, dtype=float)
    if not np.isfinite(zs).all():
        raise InvalidGeometryError(f"{name}: NaN or infinite coordinates in {_label(e, layer, where)}")
    if len(zs) and zs.max() - zs.min() > 1e-9 * max(size, abs(zs).max(), 1e-300):
        raise _flat_error(name, e, layer, where)


def _extrusion_sign(name, e, layer, where) -> float:
    """+1 or −1 for an entity whose plane is parallel to XY (extrusion ±Z), else an error."""
    ex = e.dxf.get("extrusion", (0.0, 0.0, 1.0))
    x, y, z = float(ex[0]), float(ex[1]), float(ex[2])
    n = math.sqrt(x * x + y * y + z * z)
    if not n or math.hypot(x, y) > 1e-9 * n:
        raise _flat_error(name, e, layer, where)
    return 1.0 if z > 0 else -1.0


def _bulge_arc(p: np.ndarray, q: np.ndarray, bulge: float) -> Arc | None:
    """The arc from p to q of a polyline vertex's bulge (tan of a quarter of the signed sweep)."""
    chord = q - p
    length = math.hypot(*chord)
    if length == 0:
        return None
    sweep = 4.0 * math.atan(bulge)
    # The centre lies on the chord's perpendicular bisector, at (L/2)·cot(sweep/2) to the left.
    left = np.array([-chord[1], chord[0]]) / length
    c = 0.5 * (p + q) + left * (0.5 * length / math.tan(0.5 * sweep))
    radius = 0.5 * length / abs(math.sin(0.5 * sweep))
    return Arc(c, radius, math.atan2(p[1] - c[1], p[0] - c[0]), sweep)


def _polyline_runs(points: np.ndarray, bulges: np.ndarray, closed: bool) -> list:
    """Runs of a polyline whose vertex i has bulge i (towards vertex i + 1)."""
    n = len(points)
    count = n if closed else n - 1
    runs: list = []
    current = [points[0]]
    for i in range(count):
        p, q = points[i], points[(i + 1) % n]
        arc = _bulge_arc(p, q, float(bulges[i])) if bulges[i] else None
        if arc is None:
            current.append(q)
            continue
        if len(current) > 1:
            runs.append(np.array(current))
        runs.append(arc)
        current = [q]
    if len(current) > 1:
        runs.append(np.array(current))
    return runs


def _chains_of(e, layer: str, where: str, tol: float, name: str) -> list[Chain]:
    """The outline of one curve entity (WCS, projected on XY); empty for a zero-length one."""
    kind = e.dxftype()
    label = _label(e, layer, where)
    if kind == "LINE":
        s, t = e.dxf.start, e.dxf.end
        if not all(map(math.isfinite, (s.x, s.y, t.x, t.y))):
            raise InvalidGeometryError(f"{name}: NaN or infinite coordinates in {label}")
        _check_plane(name, e, layer, where, [s.z, t.z], math.hypot(t.x - s.x, t.y - s.y))
        if (s.x, s.y) == (t.x, t.y):
            return []
        return [Chain([np.array([[s.x, s.y], [t.x, t.y]])], label)]
    if kind in ("ARC", "CIRCLE"):
        sign = _extrusion_sign(name, e, layer, where)
        c = e.ocs().to_wcs(e.dxf.center)
        r = float(e.dxf.radius)
        if not (math.isfinite(r) and math.isfinite(c.x) and math.isfinite(c.y)):
            raise InvalidGeometryError(f"{name}: NaN or infinite coordinates in {label}")
        if r <= 0:
            return []
        if kind == "CIRCLE":
            return [Chain([Arc((c.x, c.y), r, 0.0, 2 * math.pi)], label)]
        span = (float(e.dxf.end_angle) - float(e.dxf.start_angle)) % 360.0
        span = 360.0 if span == 0 else span
        sp = e.start_point
        a0 = math.atan2(sp.y - c.y, sp.x - c.x)
        return [Chain([Arc((c.x, c.y), r, a0, sign * math.radians(span))], label)]
    if kind == "LWPOLYLINE":
        sign = _extrusion_sign(name, e, layer, where)
        pts = np.array([(v.x, v.y) for v in e.vertices_in_wcs()], dtype=float).reshape(-1, 2)
        bulges = sign * np.array([b for *_, b in e.get_points("xyb")], dtype=float).reshape(-1)
        return _polyline_chain(pts, bulges, bool(e.closed), label, name)
    if kind == "POLYLINE":
        verts = [v for v in e.vertices if not v.dxf.flags & 16]     # not the spline frame's control points
        if e.is_3d_polyline:
            xyz = np.array([tuple(v.dxf.location) for v in verts], dtype=float).reshape(-1, 3)
            _check_plane(name, e, layer, where, xyz[:, 2], float(np.ptp(xyz[:, :2], axis=0).max(initial=0)))
            return _polyline_chain(xyz[:, :2], np.zeros(len(xyz)), bool(e.is_closed), label, name)
        sign = _extrusion_sign(name, e, layer, where)
        ocs = e.ocs()
        z = float(e.dxf.get("elevation", (0, 0, 0))[2])
        pts = np.array([tuple(ocs.to_wcs((v.dxf.location[0], v.dxf.location[1], z)))[:2] for v in verts],
                       dtype=float).reshape(-1, 2)
        bulges = sign * np.array([float(v.dxf.get("bulge", 0.0)) for v in verts], dtype=float)
        return _polyline_chain(pts, bulges, bool(e.is_closed), label, name)
    if kind == "ELLIPSE":
        sign = _extrusion_sign(name, e, layer, where)
        major = e.dxf.major_axis
        ratio = float(e.dxf.ratio)
        if abs(ratio - 1.0) <= 1e-12 and abs(major.z) <= 1e-12 * major.magnitude:
            c, r = e.dxf.center, float(major.magnitude)
            span = (float(e.dxf.end_param) - float(e.dxf.start_param)) % (2 * math.pi)
            span = 2 * math.pi if span <= 1e-12 else span
            sp = e.start_point
            return [Chain([Arc((c.x, c.y), r, math.atan2(sp.y - c.y, sp.x - c.x), sign * span)], label)]
        xyz = np.array([tuple(v) for v in e.flattening(tol)], dtype=float).reshape(-1, 3)
        _check_plane(name, e, layer, where, xyz[:, 2], float(major.magnitude))
        return _points_chain(xyz[:, :2], label, name)
    # SPLINE
    try:
        xyz = np.array([tuple(v) for v in e.flattening(tol)], dtype=float).reshape(-1, 3)
    except Exception as exc:  # ezdxf refuses a spline without enough control points, a bad knot vector…
        raise InvalidGeometryError(f"{name}: {label} is malformed ({exc})") from None
    if not len(xyz):
        return []
    _check_plane(name, e, layer, where, xyz[:, 2], float(np.ptp(xyz[:, :2], axis=0).max()))
    return _points_chain(xyz[:, :2], label, name)


def _points_chain(pts: np.ndarray, label: str, name: str) -> list[Chain]:
    if not np.isfinite(pts).all():
        raise InvalidGeometryError(f"{name}: NaN or infinite coordinates in {label}")
    keep = np.ones(len(pts), dtype=bool)
    keep[1:] = np.any(pts[1:] != pts[:-1], axis=1)
    pts = pts[keep]
    return [Chain([pts], label)] if len(pts) >= 2 else []


def _polyline_chain(pts, bulges, closed, label, name) -> list[Chain]:
    if not np.isfinite(pts).all() or not np.isfinite(bulges).all():
        raise InvalidGeometryError(f"{name}: NaN or infinite coordinates in {label}")
    if len(pts) < 2:
        return []
    if closed and np.array_equal(pts[0], pts[-1]) and not bulges[-1]:
        pts, bulges = pts[:-1], bulges[:-1]              # a closed polyline that repeats its first vertex
    keep = np.ones(len(pts), dtype=bool)                 # repeated vertices carry no piece
    keep[1:] = np.any(pts[1:] != pts[:-1], axis=1)
    pts, bulges = pts[keep], bulges[keep]
    if len(pts) < 2:
        return []
    runs = _polyline_runs(pts, bulges, closed and len(pts) > 1)
    return [Chain(runs, label)] if runs else []


# ---------------------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------------------
def full_circle(loop, atol: float | None = None) -> tuple[float, float, float] | None:
    """``(cx, cy, radius)`` if ``loop`` is one full circle (arcs of one circle, nothing else), else None.

    Straight pieces shorter than ``atol`` (default 1e-9 of the loop's size) are ignored.

    Examples
    --------
    >>> from vectortighten.curves import Loop
    >>> full_circle(Loop.circle((1.0, 2.0), 3.0))
    (1.0, 2.0, 3.0)
    """
    x0, y0, x1, y1 = loop.bounds
    size = max(x1 - x0, y1 - y0)
    atol = 1e-9 * size if atol is None else atol
    arcs = []
    for p in loop.pieces:
        if isinstance(p, Segment):
            if p.length > atol:
                return None
        else:
            arcs.append(p)
    if not arcs:
        return None
    c = np.array([a.center for a in arcs])
    r = np.array([a.radius for a in arcs])
    if np.ptp(c[:, 0]) > atol or np.ptp(c[:, 1]) > atol or np.ptp(r) > atol:
        return None
    turn = sum(a.sweep for a in arcs)
    if abs(abs(turn) - 2 * math.pi) > 1e-9:
        return None
    return float(c[0, 0]), float(c[0, 1]), float(r[0])


def dxf_frame(meta=None, unit: str | None = None) -> tuple[float, float, float, int]:
    """``(scale, dx, dy, insunits)``: how coordinates map to a DXF output, and the ``$INSUNITS`` it declares.

    From ``meta`` (a reader's: a DXF input keeps its units and position, an SVG input maps as Inkscape's
    DXF export does) when given; else from ``unit``: mm, cm and in as they are, px, pt and pc (which DXF
    lacks) converted to mm; unitless (``$INSUNITS = 0``) when neither says.

    Examples
    --------
    >>> dxf_frame(unit="mm"), dxf_frame()
    ((1.0, 0.0, 0.0, 4), (1.0, 0.0, 0.0, 0))
    >>> dxf_frame(unit="px")[0] == 25.4 / 96
    True
    """
    if unit is None and meta:
        if "insunits" in meta:
            scale, dx, dy = meta.get("dxf_transform", (1.0, 0.0, 0.0))
            return float(scale), float(dx), float(dy), int(meta["insunits"])
        unit = meta.get("units")
    if unit is None:
        return 1.0, 0.0, 0.0, 0
    if unit in _UNIT_CODE:
        return 1.0, 0.0, 0.0, _UNIT_CODE[unit]
    if unit in MM_PER_UNIT:
        return MM_PER_UNIT[unit], 0.0, 0.0, _UNIT_CODE["mm"]
    raise ValueError(f"unknown unit {unit!r}")


def _bulge_points(loop, atol: float) -> list[tuple[float, float, float]]:
    """``(x, y, bulge)`` of a closed LWPOLYLINE tracing ``loop`` (arcs over half a turn split in two)."""
    out = []
    for p in loop.pieces:
        if isinstance(p, Segment):
            if p.length > atol or not out:
                out.append((p.start[0], p.start[1], 0.0))
            continue
        parts = max(1, math.ceil(abs(p.sweep) / math.pi - 1e-12))
        for i in range(parts):
            x, y = p.point_at(i / parts) if i else p.start
            out.append((x, y, math.tan(p.sweep / parts / 4.0)))
    return out


def write_dxf(result, tmp: Path, layers, unit=None, meta=None, entities: str = "lines-arcs") -> None:
    """Write ``result`` to the file ``tmp`` as DXF R2010, in the input's frame.

    Parameters
    ----------
    result : Tightening
    tmp : Path
        The file to write (`write_result` gives a temporary one and renames it).
    layers : iterable of {"input", "core", "mortar"}
        Also drawn, as closed LWPOLYLINEs on layers INPUT, CORE, MORTAR.
    unit : str, optional
        The unit of the coordinates (see `dxf_frame`), when ``meta`` does not say.
    meta : dict, optional
        A reader's `Source.meta`: units, ``$INSUNITS`` and the map to DXF coordinates.
    entities : {"lines-arcs", "lwpolyline"}
        The tightening as LINE and ARC entities, or one closed LWPOLYLINE with bulges a loop. Either way a
        loop that is one full circle is a CIRCLE, and every arc has radius exactly r (in the output's
        units). Layer TIGHTENING.

    Examples
    --------
    >>> import tempfile, pathlib, ezdxf
    >>> from shapely.geometry import box
    >>> from vectortighten import tighten
    >>> T = tighten(box(0, 0, 40, 20), 3.0)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "t.dxf"
    ...     write_dxf(T, p, (), meta={"units": "mm"}, entities="lwpolyline")
    ...     doc = ezdxf.readfile(p)
    >>> doc.header["$INSUNITS"], [e.dxftype() for e in doc.modelspace()]
    (4, ['LWPOLYLINE'])
    """
    ezdxf = _require("ezdxf", "dxf", "writing DXF")
    if entities not in DXF_ENTITIES:
        raise ValueError(f"dxf entities must be one of {', '.join(DXF_ENTITIES)}, got {entities!r}")
    scale, dx, dy, insunits = dxf_frame(meta, unit)
    doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = insunits
    name = INSUNITS.get(insunits)
    doc.header["$MEASUREMENT"] = 0 if name in ("in", "ft", "mi", "uin", "mil", "yd", "us_ft") else 1
    msp = doc.modelspace()
    doc.layers.add("TIGHTENING", color=1)
    attribs = {"layer": "TIGHTENING"}
    for loop in result.loops:
        if (scale, dx, dy) != (1.0, 0.0, 0.0):
            loop = loop.affine(scale, dx, dy)
        x0, y0, x1, y1 = loop.bounds
        atol = 1e-12 * max(x1 - x0, y1 - y0)
        circle = full_circle(loop)
        if circle is not None:
            msp.add_circle(circle[:2], circle[2], dxfattribs=attribs)
        elif entities == "lwpolyline":
            msp.add_lwpolyline(_bulge_points(loop, atol), format="xyb", close=True, dxfattribs=attribs)
        else:
            for p in loop.pieces:
                if isinstance(p, Segment):
                    if p.length > 0:
                        msp.add_line(p.start, p.end, dxfattribs=attribs)
                    continue
                # DXF arcs always run counter-clockwise from start_angle to end_angle: a clockwise piece
                # (negative sweep) is written from its end to its start.
                a0, a1 = (p.start_angle, p.end_angle) if p.sweep > 0 else (p.end_angle, p.start_angle)
                msp.add_arc(p.center, p.radius, math.degrees(a0) % 360.0, math.degrees(a1) % 360.0,
                            dxfattribs=attribs)
    for layer in layers:
        geom = result.shape if layer == "input" else getattr(result, layer)
        doc.layers.add(layer.upper(), color={"input": 5, "core": 7, "mortar": 8}[layer])
        if (scale, dx, dy) != (1.0, 0.0, 0.0):
            geom = shapely.transform(geom, lambda xy: xy * scale + (dx, dy))
        for poly in shapely.get_parts(geom):
            if not isinstance(poly, Polygon) or poly.is_empty:
                continue
            for ring in (poly.exterior, *poly.interiors):
                msp.add_lwpolyline(np.asarray(ring.coords)[:-1], close=True,
                                   dxfattribs={"layer": layer.upper()})
    ebbox = _require("ezdxf.bbox", "dxf", "writing DXF")
    box = ebbox.extents(msp)
    if box.has_data:                      # $EXTMIN/$EXTMAX, and the view a CAD program opens on
        msp.dxf.extmin, msp.dxf.extmax = box.extmin, box.extmax
        doc.header["$EXTMIN"], doc.header["$EXTMAX"] = box.extmin, box.extmax   # kept if they are (0, 0, 0)
        _require("ezdxf.zoom", "dxf", "writing DXF").center(msp, box.center, box.size * 1.1)
    doc.saveas(tmp)
