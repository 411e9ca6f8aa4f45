"""SVG: reading a drawing's region (painted artwork or a cut file), writing a tightening on its page.

Reading (`load_svg`, `read_svg`): every shape of the drawing (paths with lines, Bézier curves and
elliptical arcs; rect, circle, ellipse, polygon, polyline, line; transforms of nested groups and
``<use>``). Two readings, chosen by ``nesting``:

* **cut file** (``"evenodd"``): every outline is a cut line, whatever its paint. The closed outlines of
  all elements are nested by the even-odd rule (inside one is material, inside two a hole…), so holes
  drawn as separate ``<circle>``/``<path>`` elements stay holes; loose open outlines (``<line>``, open
  paths) are joined end to end within ``gap`` (a subpath of a *filled* element closes implicitly, as its
  fill does).
* **painting** (``"paint"``): the drawing as it is seen. Each filled element fills its region by its own
  ``fill-rule``, in painting (document) order; a shape filled with the document's background colour
  (``pagecolor`` of Inkscape's ``sodipodi:namedview``, the root's ``background-color`` or
  ``viewport-fill``; white when none is given) erases what lies under it. Strokes paint nothing;
  unfilled elements are skipped (with a warning naming how many).
* ``"auto"`` (the default) reads a drawing in which no element is filled (``fill="none"``, or a fill of
  zero opacity) as a cut file, and any other as a painting. ``--nesting`` on the command line forces
  either.

Curves are flattened to ``flatten`` (default `DEFAULT_FLATTEN` times the drawing's diagonal); circular
arcs (a ``<circle>``, an ``A`` command with equal radii) under a transform that keeps circles circular
are exact `Arc`s in `Source.loops`. Coordinates are the drawing's user units (those of the root
``viewBox``) with y pointing up, so that a shape written by `svg_document` reads back where it was. The
XML is checked with defusedxml first: entity declarations (billion laughs, XXE) and references to
external DTDs other than the W3C's own SVG DTDs are refused, never followed.

Writing (`svg_document`): the tightening with real arc commands, on the input's page (its ``width``,
``height`` and ``viewBox``) when the input was an SVG, optionally with each element's style
(``keep_style``) or as outlines only (``stroke_only``).

svgelements and defusedxml (``pip install vectortighten[svg]``) are imported only when an SVG is met.
"""

from __future__ import annotations

import io as _stdio
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Point, Polygon

from vectortighten.curves import Arc, Segment
from vectortighten.errors import InvalidGeometryError, ResourceLimitError
from vectortighten.limits import MAX_SVG_ELEMENTS

from ._common import _bounds, _check_layers, _polygonal, _require
from ._fill import fill_rings
from ._outline import DEFAULT_GAP, Chain, _snap, assemble, drop_duplicates, exact_boundary, join
from ._source import Source

__all__ = ["DEFAULT_FLATTEN", "NESTINGS", "load_svg", "read_svg", "svg_document", "svg_unit"]

#: Readings of `load_svg` (``nesting=``): ``"auto"``, ``"evenodd"`` (cut file), ``"paint"``.
NESTINGS = ("auto", "evenodd", "paint")
DEFAULT_FLATTEN = 1e-4

# Largest number of chords one SVG curve is cut into, whatever the tolerance.
_MAX_CHORDS = 100_000
# Public identifiers and system ids of the W3C's SVG DTDs: a DOCTYPE naming one of them is accepted (the
# DTD is never loaded); any other external DTD is refused.
_W3C_DTD = re.compile(r"^(-//W3C//DTD SVG [0-9.]+( Tiny| Basic)?//EN|https?://www\.w3\.org/Graphics/SVG/.*)$")
# Attributes that hold coordinates, checked for NaN and infinities before svgelements sees them (it would
# skip or mangle them silently).
_GEOMETRY_ATTRS = ("d", "points", "transform", "x", "y", "cx", "cy", "r", "rx", "ry", "width", "height",
                   "x1", "y1", "x2", "y2", "viewBox")
_NONFINITE = re.compile(r"(?<![a-z])(nan|inf(inity)?)(?![a-z])", re.IGNORECASE)
_SVG_URI = "http://www.w3.org/2000/svg"
# Marks the layers `svg_document` adds besides the tightening; `read_svg` skips them.
_LAYER_ATTR = "data-vectortighten-layer"
# Containers whose shapes are not drawn where they stand (only through <use>, or not at all).
_NOT_RENDERED = ("defs", "symbol", "mask", "marker", "pattern", "clipPath")


def _local(tag) -> str:
    return tag.rsplit("}", 1)[-1] if isinstance(tag, str) else ""


def _safe_svg_tree(data: bytes, source: str):
    """Parse ``data`` with defusedxml; refuse entities and external DTDs; return the root element."""
    _require("svgelements", "svg", "reading SVG")
    dx = _require("defusedxml", "svg", "reading SVG")
    DET = _require("defusedxml.ElementTree", "svg", "reading SVG")
    from xml.etree.ElementTree import ParseError

    def parse(forbid_dtd: bool):
        return DET.fromstring(data, forbid_dtd=forbid_dtd, forbid_entities=True, forbid_external=True)

    try:
        try:
            return parse(forbid_dtd=True)
        except dx.DTDForbidden as exc:
            ids = [i for i in (exc.pubid, exc.sysid) if i]
            if ids and not all(_W3C_DTD.match(i) for i in ids):
                raise InvalidGeometryError(
                    f"{source}: refused: the SVG references an external DTD "
                    f"({exc.sysid or exc.pubid!r}); external references are not followed") from None
            # No external DTD, or the W3C's own SVG DTD (never loaded): parse again, refusing entities.
            return parse(forbid_dtd=False)
    except dx.EntitiesForbidden as exc:
        kind = "an external entity" if exc.sysid else "an entity"
        raise InvalidGeometryError(
            f"{source}: refused: the SVG declares {kind} ({exc.name!r}); entity expansion "
            "(billion laughs) and external entities (XXE) are not allowed; save it as plain SVG without a "
            "DOCTYPE") from None
    except dx.DefusedXmlException as exc:
        raise InvalidGeometryError(f"{source}: refused: {exc}") from None
    except ParseError as exc:
        raise InvalidGeometryError(f"{source}: malformed SVG (XML: {exc})") from None


def _prepare_svg(root, source: str) -> tuple[bytes, dict[str, int]]:
    """Check the tree's coordinates, move never-drawn containers into ``<defs>``; return it serialised."""
    from xml.etree import ElementTree as ET

    if _local(root.tag) != "svg":
        raise InvalidGeometryError(f"{source}: malformed SVG (the root element is <{_local(root.tag)}>, "
                                   "not <svg>)")
    ignored: dict[str, int] = {}
    parent = {child: node for node in root.iter() for child in node}
    for el in root.iter():
        tag = _local(el.tag)
        for attr in _GEOMETRY_ATTRS:
            value = el.get(attr)
            if value is not None and _NONFINITE.search(value):
                raise InvalidGeometryError(f"{source}: NaN or infinite coordinates in the {attr!r} of "
                                           f"{_describe(el)}")
        if tag in ("text", "image", "foreignObject"):
            ignored[tag] = ignored.get(tag, 0) + 1
    for el in list(root.iter()):
        if el.get(_LAYER_ATTR) is not None and el in parent:      # input/core/mortar drawn by svg_document
            parent[el].remove(el)
    box = root.get("viewBox")
    if box is not None:
        try:
            values = [float(v) for v in re.split(r"[\s,]+", box.strip())]
        except ValueError:
            values = []
        if len(values) != 4:
            raise InvalidGeometryError(f"{source}: malformed SVG (viewBox={box!r} is not four numbers)")
        if not (values[2] > 0 and values[3] > 0):
            raise InvalidGeometryError(f"{source}: the root viewBox={box!r} has a width or height that is "
                                       "not positive; such an SVG draws nothing")
    expanded = _expanded_count(root)
    if expanded > MAX_SVG_ELEMENTS:
        raise ResourceLimitError(f"{source}: refused: its <use> references expand to {expanded:.3g} drawn "
                                 f"elements, more than the limit of {MAX_SVG_ELEMENTS:,} "
                                 "(vectortighten.limits.MAX_SVG_ELEMENTS)")
    # <symbol>, <mask>, <marker>, <pattern> and <clipPath> are not drawn where they stand; svgelements
    # lists their shapes as if they were. Inside <defs> they are drawn only through <use>, as they should.
    # A symbol becomes a group (its viewBox is not honoured).
    defs = ET.Element(f"{{{_SVG_URI}}}defs")
    for el in list(root.iter()):
        tag = _local(el.tag)
        if tag == "symbol":
            el.tag = f"{{{_SVG_URI}}}g"
            for attr in ("viewBox", "preserveAspectRatio", "x", "y", "width", "height", "refX", "refY"):
                el.attrib.pop(attr, None)
        if tag in _NOT_RENDERED[1:] and el in parent and _local(parent[el].tag) != "defs":
            parent[el].remove(el)
            defs.append(el)
    # svgelements passes a nested <svg>'s x and y on to the shapes inside as theirs: move them into a
    # translating group.
    for el in list(root.iter()):
        if _local(el.tag) != "svg" or el is root or el not in parent:
            continue
        try:
            x, y = float(el.get("x", "0")), float(el.get("y", "0"))   # plain user units only
        except ValueError:
            continue
        if x or y:
            el.attrib.pop("x", None)
            el.attrib.pop("y", None)
            holder = parent[el]
            wrap = ET.Element(f"{{{_SVG_URI}}}g", {"transform": f"translate({x} {y})"})
            holder.insert(list(holder).index(el), wrap)
            holder.remove(el)
            wrap.append(el)
    if len(defs):
        root.insert(0, defs)
    return ET.tostring(root), ignored


def _href(el) -> str | None:
    """The local target id of a ``<use>`` (``href`` or ``xlink:href`` of the form ``#id``), or None."""
    for key in ("href", "{http://www.w3.org/1999/xlink}href"):
        value = el.get(key)
        if value is not None:
            value = value.strip()
            return value[1:] if value.startswith("#") else None
    return None


def _expanded_count(root) -> float:
    """How many elements the tree has once every ``<use>`` is replaced by a copy of what it references.

    Nested uses multiply (ten uses of a group of ten uses of ...), so this is computed per element and
    memoised, without recursion (a deep tree would exhaust Python's stack), in floating point (the count
    of a bomb overflows nothing). Elements inside never-rendered containers count only where used; a
    reference cycle counts as one element (svgelements refuses it later).
    """
    by_id = {el.get("id"): el for el in root.iter() if el.get("id") is not None}
    memo: dict[int, float] = {}
    active: set[int] = set()
    stack = [(root, False)]
    while stack:
        el, done = stack.pop()
        key = id(el)
        if key in memo:
            continue
        target = by_id.get(_href(el)) if _local(el.tag) == "use" else None
        kids = list(el) + ([target] if target is not None else [])
        if not done:
            active.add(key)
            stack.append((el, True))
            stack.extend((k, False) for k in kids if id(k) not in memo and id(k) not in active)
            continue
        active.discard(key)
        memo[key] = 1.0 + math.fsum(memo.get(id(k), 1.0) for k in kids)
    # Count what is drawn where it stands (not the contents of <defs> and the like), with what each
    # <use> among them brings in whole.
    rendered, todo = 0.0, [root]
    while todo:
        el = todo.pop()
        rendered += 1.0
        if _local(el.tag) in _NOT_RENDERED:
            continue
        if _local(el.tag) == "use":
            target = by_id.get(_href(el))
            rendered += memo.get(id(target), 1.0) if target is not None else 0.0
        todo.extend(el)
    return rendered


def _describe(el) -> str:
    ident = el.get("id")
    return f"<{_local(el.tag)} id={ident!r}>" if ident else f"<{_local(el.tag)}>"


def _matrix(m) -> np.ndarray:
    """A 3×3 numpy matrix from an svgelements Matrix (x' = a x + c y + e, y' = b x + d y + f)."""
    return np.array([[m.a, m.c, m.e], [m.b, m.d, m.f], [0.0, 0.0, 1.0]], dtype=float)


def _curve_chords(seg, se, tol: float) -> np.ndarray:
    """Points after ``seg.start`` up to ``seg.end`` on a curve, chords within ``tol`` (local units)."""
    if isinstance(seg, (se.CubicBezier, se.QuadraticBezier)):
        if isinstance(seg, se.CubicBezier):
            p = np.array([[seg.start.x, seg.start.y], [seg.control1.x, seg.control1.y],
                          [seg.control2.x, seg.control2.y], [seg.end.x, seg.end.y]])
        else:
            p = np.array([[seg.start.x, seg.start.y], [seg.control.x, seg.control.y], [seg.end.x, seg.end.y]])
        if not np.isfinite(p).all():
            raise InvalidGeometryError("NaN or infinite control point of a Bézier curve")
        with np.errstate(over="ignore", invalid="ignore"):
            d2 = p[:-2] - 2 * p[1:-1] + p[2:]
            bend = float(np.hypot(d2[:, 0], d2[:, 1]).max())
            # |B''| ≤ 2·bend (quadratic) or 6·bend (cubic), and a chord of a parameter step h is within
            # |B''|·h²/8 of the curve.
            n = math.sqrt((6.0 if len(p) == 4 else 2.0) * bend / (8.0 * tol))
        # A bend that overflows (control points near 1e308) takes the most chords; the coordinates'
        # own limit refuses such a shape later by name.
        n = math.ceil(n) if math.isfinite(n) else _MAX_CHORDS
    elif isinstance(seg, se.Arc):
        big = max(abs(seg.rx), abs(seg.ry))                     # |point''| ≤ max radius per radian²
        # An arc whose radius or sweep overflows (radii of 1e308 between nearby points) is a straight
        # line to within rounding: one chord.
        n = abs(seg.sweep) * math.sqrt(big / (8.0 * tol)) if math.isfinite(big) else math.nan
        n = math.ceil(n) if math.isfinite(n) else 1
    else:
        n = 1
    if not math.isfinite(n):
        n = 1
    n = min(_MAX_CHORDS, max(1, n))
    if n == 1:
        return np.array([[seg.end.x, seg.end.y]], dtype=float)
    pts = np.asarray(seg.npoint(np.arange(1, n + 1) / n), dtype=float).reshape(-1, 2)
    pts[-1] = (seg.end.x, seg.end.y)
    return pts


_SHAPE_TAGS = {"Path": "path", "Circle": "circle", "Ellipse": "ellipse", "Rect": "rect", "Polygon": "polygon",
               "Polyline": "polyline", "SimpleLine": "line"}
# Presentation properties `keep_style` carries to the output (as svgelements has cascaded them).
_STYLE_PROPS = ("fill", "fill-opacity", "fill-rule", "stroke", "stroke-width", "stroke-opacity",
                "stroke-linecap", "stroke-linejoin", "stroke-miterlimit", "stroke-dasharray",
                "stroke-dashoffset", "opacity")
_NUMBER = re.compile(r"^\s*[0-9.eE+-]+\s*$")
_URL = re.compile(r"url\([^)]*\)\s*")


@dataclass
class _Shape:
    """One drawn element: its path, the map from its coordinates to user units (y up), how it paints."""

    path: object
    m: np.ndarray
    smax: float
    rule: str
    filled: bool
    rgb: tuple | None
    style: dict
    label: str
    is_line: bool


def _describe_shape(el, index: int) -> str:
    tag = _SHAPE_TAGS.get(type(el).__name__, type(el).__name__.lower())
    ident = el.id if getattr(el, "id", None) else None
    return f"<{tag} id={ident!r}>" if ident else f"<{tag}> #{index + 1}"


def _opacity(value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        return 1.0


def _style_of(el, m: np.ndarray) -> dict:
    """The element's cascaded presentation properties, lengths scaled from its coordinates to user units."""
    scale = math.sqrt(abs(np.linalg.det(m[:2, :2])))
    out = {}
    for prop in _STYLE_PROPS:
        value = el.values.get(prop)
        if value is None or str(value).strip() == "":
            continue
        value = str(value).strip()
        if prop in ("fill", "stroke") and "url(" in value:
            value = _URL.sub("", value).strip() or ("#000000" if prop == "fill" else "none")
        if prop in ("stroke-width", "stroke-dashoffset") and _NUMBER.match(value):
            value = _num(float(value) * scale)
        elif prop == "stroke-dasharray" and value != "none":
            parts = [p for p in re.split(r"[\s,]+", value) if p]
            if all(_NUMBER.match(p) for p in parts):
                value = " ".join(_num(float(p) * scale) for p in parts)
        out[prop] = value
    return out


def _background(root, se) -> tuple[int, int, int]:
    """The document's background colour: Inkscape's page colour, the root's, or white."""
    candidates = []
    for el in root.iter():
        if _local(el.tag) == "namedview" and el.get("pagecolor"):
            candidates.append(el.get("pagecolor"))
    style = root.get("style") or ""
    m = re.search(r"background(?:-color)?\s*:\s*([^;]+)", style)
    if m:
        candidates.insert(0, m.group(1))
    if root.get("viewport-fill"):
        candidates.insert(0, root.get("viewport-fill"))
    for text in candidates:
        try:
            c = se.Color(text.strip())
        except (ValueError, TypeError):
            continue
        if c.value is not None and c.alpha > 0:
            return (c.red, c.green, c.blue)
    return (255, 255, 255)


def _similarity(M: np.ndarray) -> tuple[float, float] | None:
    """``(scale, sign of det)`` if ``M`` maps circles to circles (a rotation, reflection and scale)."""
    a, c, b, d = float(M[0, 0]), float(M[0, 1]), float(M[1, 0]), float(M[1, 1])
    det = a * d - b * c
    s2 = abs(det)
    # Mᵀ M = s² I: columns of equal length s, orthogonal.
    if not s2 or max(abs(a * a + b * b - s2), abs(c * c + d * d - s2), abs(a * c + b * d)) > 1e-12 * s2:
        return None
    return math.sqrt(s2), 1.0 if det > 0 else -1.0


def _subpaths(shape: _Shape, se, tol_user: float) -> list[tuple[list, bool]]:
    """Each subpath of ``shape`` as runs in user units (y up), and whether it is closed.

    A subpath is closed by ``Z`` (or by coming back to its start). Circular arcs under a similarity are
    exact `Arc`s; other curves are chords within ``tol_user``.
    """
    M, t = shape.m[:2, :2], shape.m[:2, 2]
    sim = _similarity(M)
    tol_local = tol_user / shape.smax
    out: list[tuple[list, bool]] = []
    runs: list = []
    poly: list = []
    start = None

    def user(pts) -> np.ndarray:      # the caller ignores floating-point errors; NaNs are checked below
        return np.asarray(pts, dtype=float).reshape(-1, 2) @ M.T + t

    def flush_poly():
        nonlocal poly
        if len(poly) > 1:
            runs.append(user(np.concatenate(poly)))
        poly = poly[-1:] if poly else []

    def finish(closed: bool):
        nonlocal runs, poly, start
        if start is not None:
            if poly:
                flush_poly()
            if runs:
                out.append((runs, closed))
        runs, poly, start = [], [], None

    for seg in shape.path:
        if isinstance(seg, se.Move):
            finish(False)
            start = np.array([[seg.end.x, seg.end.y]], dtype=float)
            poly = [start]
            continue
        if isinstance(seg, se.Close):
            if start is not None and poly:
                # back at the start (to rounding, as after a circle's last arc): nothing to add
                step = np.abs(poly[-1][-1] - start[0]).max()
                if step > 1e-12 * max(1.0, float(np.abs(start).max())):
                    poly.append(start)
            finish(True)
            continue
        if start is None:
            start = np.array([[seg.start.x, seg.start.y]], dtype=float)
            poly = [start]
        if isinstance(seg, se.Line):
            poly.append(np.array([[seg.end.x, seg.end.y]], dtype=float))
        elif (isinstance(seg, se.Arc) and sim is not None and seg.rx > 0 and seg.ry > 0 and seg.sweep
              and abs(seg.rx - seg.ry) <= 1e-12 * max(seg.rx, seg.ry)):
            s, sign = sim
            if not poly:
                poly = [np.array([[seg.start.x, seg.start.y]], dtype=float)]
            flush_poly()
            c = user([[seg.center.x, seg.center.y]])[0]
            p0 = user([[seg.start.x, seg.start.y]])[0]
            runs.append(Arc(c, s * 0.5 * (seg.rx + seg.ry), math.atan2(p0[1] - c[1], p0[0] - c[0]),
                            sign * float(seg.sweep)))
            poly = [np.array([[seg.end.x, seg.end.y]], dtype=float)]
        else:
            poly.append(_curve_chords(seg, se, tol_local))
    finish(False)
    for runs_, _ in out:
        for r in runs_:
            pts = np.array([r.center]) if isinstance(r, Arc) else r
            if not np.isfinite(pts).all():
                raise InvalidGeometryError(f"NaN or infinite coordinates in {shape.label} (after transforms)")
    return out


def _closed_runs(runs: list, scale: float) -> list:
    """Close the runs of a subpath as a fill closes it: a straight piece back to the start.

    Nothing is added when it ends there already (to 1e-12 of ``scale``).
    """
    first = runs[0]
    start = np.array(first.start) if isinstance(first, Arc) else first[0]
    last = runs[-1]
    end = np.array(last.end) if isinstance(last, Arc) else last[-1]
    if np.hypot(*(end - start)) > 1e-12 * scale:
        return [*runs, np.array([end, start])]
    return runs


class _Styles:
    """What `svg_document` needs to give each output loop the style of the element it comes from."""

    def __init__(self, styles: list[dict], mode: str, outlines=None, owners=None, regions=None):
        self.styles, self.mode = styles, mode
        self._outlines, self._owners = outlines or [], owners or []
        self._regions = regions or []               # (region, owner, erase), in painting order
        self._tree = shapely.STRtree(self._outlines) if self._outlines else None

    def of_loop(self, loop) -> dict | None:
        """Cut file: the style of the outline nearest the loop."""
        if self._tree is None:
            return None
        x, y = loop.pieces[0].point_at(0.5)
        k = self._tree.nearest(Point(x, y))
        return self.styles[self._owners[int(k)]] if k is not None else None

    def of_region(self, poly) -> dict | None:
        """Painting: the style of the topmost painted element under the region (else the nearest)."""
        p = poly.representative_point()
        for region, owner, erase in reversed(self._regions):
            if not erase and region.covers(p):
                return self.styles[owner]
        painted = [(region.distance(p), owner) for region, owner, erase in self._regions if not erase]
        return self.styles[min(painted)[1]] if painted else None


def _page(root) -> dict:
    """The root's page attributes (as written) and the map from user units to the page, in CSS px.

    Returns a dict with ``attrs`` (``width``, ``height``, ``viewBox``, ``preserveAspectRatio``, those
    present), ``viewport`` ((W, H) in px, or None when the size is not absolute), ``view`` ((sx, sy, tx,
    ty): px = s·user + t) and ``box`` (the viewport in user units, (x0, y0, x1, y1) with y down, or None).
    """
    attrs = {k: root.get(k) for k in ("width", "height", "viewBox", "preserveAspectRatio")
             if root.get(k) is not None}

    def length(text):
        m = _LENGTH.match(text or "")
        if not m:
            return None
        try:
            v = float(m.group(1))
        except ValueError:
            return None
        return v * 96.0 / _UNITS_PER_INCH[m.group(2) or "px"] if math.isfinite(v) and v > 0 else None

    vb = None
    if "viewBox" in attrs:
        try:
            vals = [float(v) for v in re.split(r"[\s,]+", attrs["viewBox"].strip())]
            if len(vals) == 4 and all(map(math.isfinite, vals)) and vals[2] > 0 and vals[3] > 0:
                vb = vals
        except ValueError:
            vb = None
    W, H = length(attrs.get("width")), length(attrs.get("height"))
    if vb is not None:
        if W is None and H is not None and "width" not in attrs:
            W = H * vb[2] / vb[3]
        if H is None and W is not None and "height" not in attrs:
            H = W * vb[3] / vb[2]
    viewport = (W, H) if W is not None and H is not None else None
    if vb is None:
        view = (1.0, 1.0, 0.0, 0.0)
        box = (0.0, 0.0, W / 1.0, H / 1.0) if viewport else None
        return {"attrs": attrs, "viewport": viewport, "view": view, "box": box}
    if viewport is None:
        return {"attrs": attrs, "viewport": None, "view": None,
                "box": (vb[0], vb[1], vb[0] + vb[2], vb[1] + vb[3])}
    par = (attrs.get("preserveAspectRatio") or "xMidYMid meet").split()
    align = par[0] if par else "xMidYMid"
    sx, sy = W / vb[2], H / vb[3]
    if align != "none":
        s = max(sx, sy) if len(par) > 1 and par[1] == "slice" else min(sx, sy)
        sx = sy = s
    fx = {"xMin": 0.0, "xMid": 0.5, "xMax": 1.0}.get(align[:4], 0.5) if align != "none" else 0.0
    fy = {"YMin": 0.0, "YMid": 0.5, "YMax": 1.0}.get(align[4:], 0.5) if align != "none" else 0.0
    tx = -vb[0] * sx + (W - vb[2] * sx) * fx
    ty = -vb[1] * sy + (H - vb[3] * sy) * fy
    box = (-tx / sx, -ty / sy, (W - tx) / sx, (H - ty) / sy)
    return {"attrs": attrs, "viewport": viewport, "view": (sx, sy, tx, ty), "box": box}


def _dxf_meta(page: dict, unit: str | None) -> dict:
    """Units and the map to DXF coordinates of an SVG, as Inkscape's DXF export places it.

    y up, the page's bottom-left corner at the origin, in the drawing's own unit when it is mm, cm or in,
    else in mm (Inkscape's default); unitless when the page has no absolute size.
    """
    box = page["box"]
    view = page["view"]
    if view is None or page["viewport"] is None:
        # No physical size: unitless, user units, placed on the page when there is one.
        if box is None:
            return {"units": None, "mm_per_unit": None, "insunits": 0, "dxf_transform": (1.0, 0.0, 0.0)}
        return {"units": None, "mm_per_unit": None, "insunits": 0, "dxf_transform": (1.0, -box[0], box[3])}
    sx, sy = view[0], view[1]
    if abs(sx - sy) > 1e-12 * max(sx, sy):         # preserveAspectRatio="none" with another aspect
        return {"units": None, "mm_per_unit": None, "insunits": 0,
                "dxf_transform": (1.0, -box[0], box[3])}
    mm_per_user = sx * 25.4 / 96.0
    if unit in ("mm", "cm", "in"):
        scale, out_unit = 1.0, unit
    else:
        scale, out_unit = mm_per_user, "mm"
    codes = {"in": 1, "mm": 4, "cm": 5}
    return {"units": unit, "mm_per_unit": mm_per_user, "insunits": codes[out_unit],
            "dxf_transform": (scale, -scale * box[0], scale * box[3])}


def load_svg(source, *, flatten: float | None = None, nesting: str = "auto",
             gap: float | None = None) -> Source:
    """Read an SVG drawing as a cut file or as a painting (see the module's notes), y up, in user units.

    Parameters
    ----------
    source : str, Path or bytes
        A file name, or the document itself.
    flatten : float, optional
        Largest distance between a curve (Bézier, arc, circle, rounded corner) and the chords that replace
        it, in user units. Default `DEFAULT_FLATTEN` times the diagonal of the drawing's bounding box.
    nesting : {"auto", "evenodd", "paint"}
        The reading: ``"evenodd"`` nests every outline across elements (a cut file), ``"paint"`` fills
        shapes in painting order (background-coloured ones erase), ``"auto"`` takes ``"evenodd"`` when no
        element is filled and ``"paint"`` otherwise.
    gap : float, optional
        Cut-file reading: loose ends nearer than this join, in user units. Default `DEFAULT_GAP` (1e-6)
        of the drawing's diagonal.

    Returns
    -------
    Source
        ``shape``; ``loops``, the exact boundary when it is made of whole outlines of the drawing (circles
        and circular arcs exact); ``meta``: ``nesting`` (the reading used), ``units`` (`svg_unit`),
        ``mm_per_unit``, ``page`` (the root's width, height, viewBox, preserveAspectRatio), ``styles``,
        and the ``insunits`` and ``dxf_transform`` a DXF output uses.

    Raises
    ------
    InvalidGeometryError
        Malformed SVG, refused constructs, no shape with an area, an open outline in a cut file.

    Examples
    --------
    >>> cut = b'''<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10" fill="none" stroke="red">
    ...   <rect width="10" height="10"/><circle cx="5" cy="5" r="2"/></svg>'''
    >>> src = load_svg(cut)
    >>> src.meta["nesting"], round(sum(lp.area for lp in src.loops), 6)       # 100 − 4π, exactly
    ('evenodd', 87.433629)
    >>> [type(p).__name__ for p in src.loops[1].pieces]                       # the circle: exact arcs
    ['Arc', 'Arc', 'Arc', 'Arc']
    """
    if isinstance(source, (bytes, bytearray)):
        data, name = bytes(source), "<svg>"
    else:
        name = str(source)
        data = Path(source).read_bytes()
    if flatten is not None and not (math.isfinite(flatten) and flatten > 0):
        raise ValueError(f"flatten must be a positive finite number, got {flatten!r}")
    if gap is not None and not (math.isfinite(gap) and gap >= 0):
        raise ValueError(f"gap must be a finite number >= 0, got {gap!r}")
    if nesting not in NESTINGS:
        raise ValueError(f"nesting must be one of {', '.join(NESTINGS)}, got {nesting!r}")
    try:
        return _load_svg(data, name, flatten, nesting, gap)
    except RecursionError:
        raise InvalidGeometryError(f"{name}: malformed SVG (elements nested too deeply)") from None


def read_svg(source, *, flatten: float | None = None, nesting: str = "auto",
             gap: float | None = None) -> Polygon | MultiPolygon:
    """Read the region of an SVG drawing: ``load_svg(...).shape`` (see `load_svg`).

    Examples
    --------
    >>> svg = b'''<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
    ...   <path d="M 0 0 H 10 V 10 H 0 Z M 2 2 H 8 V 8 H 2 Z" fill-rule="evenodd"/></svg>'''
    >>> read_svg(svg).area
    64.0
    """
    return load_svg(source, flatten=flatten, nesting=nesting, gap=gap).shape


def _parse_shapes(data: bytes, name: str):
    """The drawn elements of the document (`_Shape`), the parsed tree's root, and svgelements."""
    root = _safe_svg_tree(data, name)
    se = _require("svgelements", "svg", "reading SVG")
    clean, ignored = _prepare_svg(root, name)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            svg = se.SVG.parse(_stdio.BytesIO(clean), reify=False, on_error="raise")
    except (ValueError, TypeError, IndexError, AttributeError, KeyError, ArithmeticError) as exc:
        for el in root.iter():            # name the culprit when it is path data (the usual one)
            if _local(el.tag) == "path" and el.get("d"):
                try:
                    se.Path(el.get("d"))
                except ArithmeticError:
                    raise InvalidGeometryError(
                        f"{name}: path data in {_describe(el)} cannot be computed in doubles (an arc's "
                        "radii or a coordinate too small or too large)") from None
                except (ValueError, IndexError, TypeError):
                    raise InvalidGeometryError(f"{name}: malformed SVG (bad path data in {_describe(el)})") \
                        from None
        detail = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
        raise InvalidGeometryError(f"{name}: malformed SVG ({detail})") from None
    if not isinstance(svg, se.SVG):     # e.g. a root <svg> in another namespace than the SVG one
        ns = root.tag[1:].split("}", 1)[0] if isinstance(root.tag, str) and root.tag.startswith("{") else ""
        raise InvalidGeometryError(f"{name}: malformed SVG (the root <svg> is not in the SVG namespace "
                                   f"{_SVG_URI!r}{f'; it is in {ns!r}' if ns else ''})")
    # The root viewport maps user units to px; undo it so coordinates are the drawing's user units.
    view = _matrix(se.Matrix(svg.viewbox_transform)) if getattr(svg, "viewbox_transform", "") else np.eye(3)
    try:
        to_user = np.linalg.inv(view)
    except np.linalg.LinAlgError:
        raise InvalidGeometryError(f"{name}: malformed SVG (degenerate viewBox)") from None
    shapes = []
    for index, el in enumerate(svg.elements()):
        if not isinstance(el, se.Shape):
            continue
        path = se.Path(el)
        if len(path) == 0:
            continue
        m = to_user @ _matrix(path.transform)
        style = _style_of(el, m)
        m[1] *= -1.0                                     # y up
        smax = np.linalg.svd(m[:2, :2], compute_uv=False)[0]
        if not (math.isfinite(smax) and smax > 0) or abs(np.linalg.det(m[:2, :2])) == 0:
            continue
        rule = str(el.values.get("fill-rule") or "nonzero").strip().lower()
        is_line = isinstance(el, se.SimpleLine)
        fill = el.fill
        filled = (not is_line and fill is not None and fill.value is not None and fill.alpha > 0
                  and _opacity(el.values.get("opacity")) > 0)
        rgb = (fill.red, fill.green, fill.blue) if filled else None
        shapes.append(_Shape(path, m, smax, "evenodd" if rule == "evenodd" else "nonzero", filled, rgb,
                             style, _describe_shape(el, index), is_line))
    for tag, count in ignored.items():
        warnings.warn(f"{name}: {count} <{tag}> element(s) ignored (convert text and images to paths)",
                      UserWarning, stacklevel=4)
    return shapes, root, se


def _load_svg(data: bytes, name: str, flatten: float | None, nesting: str, gap: float | None) -> Source:
    with np.errstate(all="ignore"):      # huge transforms overflow to inf; `_subpaths` refuses them by name
        return _load_svg_checked(data, name, flatten, nesting, gap)


def _load_svg_checked(data: bytes, name: str, flatten: float | None, nesting: str,
                      gap: float | None) -> Source:
    shapes, root, se = _parse_shapes(data, name)
    if not shapes:
        raise InvalidGeometryError(f"{name}: no shapes found in the SVG")
    corners = []
    for s in shapes:
        pts = np.array([[g.end.x, g.end.y] for g in s.path if g.end is not None] or [[0.0, 0.0]])
        with np.errstate(all="ignore"):
            corners.append(pts @ s.m[:2, :2].T + s.m[:2, 2])
    allpts = np.concatenate(corners)
    allpts = allpts[np.isfinite(allpts).all(axis=1)]
    diag = float(np.hypot(*(allpts.max(axis=0) - allpts.min(axis=0)))) if len(allpts) else 0.0
    if flatten is None:
        flatten = DEFAULT_FLATTEN * diag if diag > 0 else 1e-6
    scale = diag if diag > 0 else 1.0
    mode = nesting if nesting != "auto" else ("paint" if any(s.filled for s in shapes) else "evenodd")
    styles = [s.style for s in shapes]
    if mode == "evenodd":
        closed, open_ = [], []
        for k, s in enumerate(shapes):
            for runs, is_closed in _subpaths(s, se, flatten):
                if is_closed or (s.filled and not s.is_line):
                    closed.append(Chain(_snap(_closed_runs(runs, scale), scale, closed=True), s.label, k))
                else:
                    open_.append(Chain(_snap(runs, scale, closed=False), s.label, k))
        gap_tol = gap if gap is not None else DEFAULT_GAP * scale
        closed, dup_closed = drop_duplicates(closed, gap_tol, closed=True)
        open_, dup_open = drop_duplicates(open_, gap_tol, closed=False)
        dropped = dup_closed + dup_open
        if dropped:
            warnings.warn(f"{name}: {len(dropped)} outline(s) drawn twice read once "
                          f"(e.g. {dropped[0].label})", UserWarning, stacklevel=3)
        loops = join(closed + open_, gap_tol, scale, name)
        shape, exact = assemble(loops, flatten)
        rings = [(c.ring(flatten), c.owner) for c in loops]
        style_map = _Styles(styles, mode, outlines=[shapely.LinearRing(np.vstack([r, r[:1]]))
                                                    for r, _ in rings if len(r) >= 3],
                            owners=[k for r, k in rings if len(r) >= 3])
    else:
        background = _background(root, se)
        skipped = sum(1 for s in shapes if not s.filled and not s.is_line)
        if skipped:
            warnings.warn(f"{name}: {skipped} unfilled outline(s) skipped: the drawing has filled shapes, so "
                          "it is read as painted; read it as a cut file to keep them (--nesting evenodd)",
                          UserWarning, stacklevel=3)
        all_rings, all_chains, regions = [], [], []
        for k, s in enumerate(shapes):
            if not s.filled:
                continue
            chains = [Chain(_snap(_closed_runs(runs, scale), scale, closed=True), s.label, k)
                      for runs, _ in _subpaths(s, se, flatten)]
            rings = [c.ring(flatten) for c in chains]
            all_chains += chains
            all_rings += rings
            region = fill_rings(rings, s.rule)
            if not region.is_empty:
                regions.append((region, k, s.rgb == background))
        shape = _paint(regions)
        rings_, chains_ = all_rings, all_chains

        def exact(shape=shape, rings_=rings_, chains_=chains_):
            return exact_boundary(shape, rings_, chains_)

        style_map = _Styles(styles, mode, regions=regions)
    if shape.is_empty:
        raise InvalidGeometryError(f"{name}: the SVG has no closed shape with an area")
    shape = _polygonal(shape, name)
    page = _page(root)
    unit = _unit_of(root)
    meta = {"format": "svg", "nesting": mode, "page": page["attrs"], "styles": style_map,
            **_dxf_meta(page, unit)}
    meta["units"] = unit
    return Source(shape, meta, exact)


def _paint(regions) -> Polygon | MultiPolygon:
    """Paint regions in order: each adds itself, or erases what lies under it (background colour)."""
    out = Polygon()
    batch: list = []
    for region, _, erase in regions:
        if erase:
            if batch:
                out = shapely.union_all([out, *batch]) if not out.is_empty else shapely.union_all(batch)
                batch = []
            if not out.is_empty:
                out = out.difference(region)
        else:
            batch.append(region)
    if batch:
        out = shapely.union_all([out, *batch]) if not out.is_empty else (
            shapely.union_all(batch) if len(batch) > 1 else batch[0])
    return out
_UNITS_PER_INCH = {"in": 1.0, "mm": 25.4, "cm": 2.54, "pt": 72.0, "pc": 6.0, "px": 96.0}
_LENGTH = re.compile(r"^\s*([0-9.eE+-]+)\s*(mm|cm|in|pt|pc|px)?\s*$")


def svg_unit(source) -> str | None:
    """The physical unit of one user unit of an SVG drawing, when the root says so plainly.

    ``width="210mm" viewBox="0 0 210 297"`` gives ``"mm"``: coordinates read by `read_svg` are then
    millimetres, and `write_result` can say so again (``unit=``). Returns None when the root has no
    ``width``, no ``viewBox``, or they do not make one user unit one whole unit of mm, cm, in, pt, pc
    or px.

    Examples
    --------
    >>> svg_unit(b'<svg xmlns="http://www.w3.org/2000/svg" width="10cm" viewBox="0 0 100 50"/>')
    'mm'
    """
    if isinstance(source, (bytes, bytearray)):
        data, name = bytes(source), "<svg>"
    else:
        name = str(source)
        data = Path(source).read_bytes()
    return _unit_of(_safe_svg_tree(data, name))


def _unit_of(root) -> str | None:
    """`svg_unit` of a parsed root."""
    width, box_ = root.get("width"), root.get("viewBox")
    if width is None or box_ is None:
        return None
    m = _LENGTH.match(width)
    try:
        size = float(m.group(1)) if m else math.nan
        vb_width = float(re.split(r"[\s,]+", box_.strip())[2])
    except (ValueError, IndexError):
        return None
    if not (math.isfinite(size) and size > 0 and math.isfinite(vb_width) and vb_width > 0):
        return None
    unit = m.group(2) or "px"
    for candidate in _UNITS_PER_INCH:                    # e.g. width="10cm" viewBox="0 0 100 ..." is mm
        ratio = size / _UNITS_PER_INCH[unit] * _UNITS_PER_INCH[candidate] / vb_width
        if abs(ratio - 1.0) <= 1e-6:
            return candidate
    return None


# ---------------------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------------------
def _radius_text(result) -> str:
    """``r=R``, or ``r_convex=A r_concave=B`` for a tightening with two radii."""
    a, b = getattr(result, "radii", (result.r, result.r))
    return f"r={_num(result.r)}" if a == b else f"r_convex={_num(a)} r_concave={_num(b)}"


def _num(value: float) -> str:
    """Shortest decimal that reads back as the same float (``2.0`` → ``"2"``)."""
    text = repr(float(value))
    if text.endswith(".0"):
        text = text[:-2]
    return "0" if text == "-0" else text


def _loop_path_flipped(loop) -> str:
    """SVG path data of an exact loop with y flipped (SVG's y points down): ``M``, ``L`` and ``A``.

    A loop that is one full circle is written as two ``A`` half-circles, whatever arcs it is made of.
    """
    from .dxf import full_circle

    pieces = loop.pieces
    if not pieces:
        return ""
    circle = full_circle(loop)
    if circle is not None:
        cx, cy, r = circle
        flag = 0 if loop.area > 0 else 1
        rr = _num(r)
        return (f"M {_num(cx + r)} {_num(-cy)} A {rr} {rr} 0 0 {flag} {_num(cx - r)} {_num(-cy)} "
                f"A {rr} {rr} 0 0 {flag} {_num(cx + r)} {_num(-cy)} Z")
    x, y = pieces[0].start
    out = [f"M {_num(x)} {_num(-y)}"]
    for p in pieces:
        if isinstance(p, Segment):
            out.append(f"L {_num(p.end[0])} {_num(-p.end[1])}")
        else:
            parts = max(1, math.ceil(abs(p.sweep) / math.pi - 1e-12))   # each part at most half a turn
            r = _num(p.radius)
            flag = 0 if p.sweep > 0 else 1        # counter-clockwise with y up is clockwise with y down
            for i in range(1, parts + 1):
                ex, ey = p.point_at(i / parts) if i < parts else p.end
                out.append(f"A {r} {r} 0 0 {flag} {_num(ex)} {_num(-ey)}")
    out.append("Z")
    return " ".join(out)


def _polygon_path_flipped(geom) -> str:
    parts = []
    for poly in shapely.get_parts(geom):
        if not isinstance(poly, Polygon) or poly.is_empty:
            continue
        for ring in (poly.exterior, *poly.interiors):
            c = np.asarray(ring.coords)[:-1]
            if len(c) < 3:
                continue
            parts.append("M " + " L ".join(f"{_num(x)} {_num(-y)}" for x, y in c) + " Z")
    return " ".join(parts)


def _check_unit(unit) -> None:
    if unit is not None and unit not in _UNITS_PER_INCH:
        raise ValueError(f"unknown unit {unit!r}; choose from {', '.join(_UNITS_PER_INCH)}")


def _attr(value: str) -> str:
    return (str(value).replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")
            .replace(">", "&gt;"))


def _style_attrs(style: dict) -> str:
    return " ".join(f'{k}="{_attr(v)}"' for k, v in style.items())


def _is_filled(style: dict) -> bool:
    fill = style.get("fill", "black").strip().lower()
    if fill in ("none", "transparent"):
        return False
    return _opacity(style.get("fill-opacity", 1)) > 0 and _opacity(style.get("opacity", 1)) > 0


def _components(loops, tol: float) -> list[tuple[int, list[int]]]:
    """Outer loops with the holes each holds: ``[(outer, [hole, …]), …]`` (indices into ``loops``)."""
    outer = [k for k, lp in enumerate(loops) if lp.area > 0]
    holes = [k for k, lp in enumerate(loops) if lp.area < 0]
    groups = {k: [] for k in outer}
    if holes and outer:
        polys = [Polygon(loops[k].sample(tol)) for k in outer]
        tree = shapely.STRtree(polys)
        starts = shapely.points([loops[h].pieces[0].start for h in holes])
        pairs = tree.query(starts, predicate="within")          # (hole index, outer index)
        best: dict[int, int] = {}
        for i, j in zip(*pairs, strict=True):
            if i not in best or polys[j].area < polys[best[i]].area:
                best[i] = j
        for i, h in enumerate(holes):
            if i in best:
                groups[outer[best[i]]].append(h)
            else:
                groups[h] = []
    else:
        groups.update({h: [] for h in holes})
    return list(groups.items())


def _element(loop, style_text: str, ident: str) -> str:
    """One loop as an element: a ``<circle>`` when it is one, else a ``<path>``."""
    from .dxf import full_circle

    circle = full_circle(loop)
    if circle is not None:
        cx, cy, r = circle
        return f'<circle id="{ident}" cx="{_num(cx)}" cy="{_num(-cy)}" r="{_num(r)}" {style_text}/>'
    return f'<path id="{ident}" d="{_loop_path_flipped(loop)}" {style_text}/>'


def svg_document(result, *, layers=(), unit: str | None = None, meta: dict | None = None,
                 keep_style: bool = False, stroke_only: bool = False) -> str:
    """The SVG document `write_result` writes for a `Tightening`.

    By default the tightening is one ``<path id="tightening">`` with ``fill-rule="evenodd"``, straight
    ``L`` and ``A`` commands whose radius is exactly ``r`` (a loop that is one full circle as two ``A``
    half-circles). The y axis is flipped (SVG's points down), so that `read_svg` gives back the same
    coordinates. ``layers`` adds groups (Inkscape layers) under it.

    Parameters
    ----------
    result : Tightening
    layers : iterable of {"input", "core", "mortar"}
    unit : {"mm", "cm", "in", "pt", "pc", "px"}, optional
        The physical length of one unit of the shape: sets ``width`` and ``height`` so that the drawing
        has its true size (see `svg_unit`). Without it (and without ``meta``) the document has no
        ``width`` and ``height``.
    meta : dict, optional
        The input's `Source.meta`. From an SVG, the output keeps the input's page: its ``width``,
        ``height``, ``viewBox`` and ``preserveAspectRatio`` as written, so the result lies on the page
        where the input did. Otherwise the ``viewBox`` frames the shapes with a margin, and a DXF input's
        units give ``width`` and ``height`` (true size; units SVG lacks, such as m or ft, in mm).
    keep_style : bool
        Give each part the style (fill, stroke, stroke width, opacity…) of the input element it comes
        from: for a painting, one evenodd ``<path>`` per component (outer boundary and its holes) with the
        style of the element painted there; for a cut file, or wherever that style is unfilled, one
        element per loop with the style of the outline nearest it.
    stroke_only : bool
        Outlines only, for laser cutters: ``fill="none"``, one element per loop (a full circle as a
        ``<circle>``), a red hairline stroke (0.0254 mm when the drawing's size is known; with
        ``keep_style`` the element's own stroke where it has one).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> from vectortighten import tighten
    >>> text = svg_document(tighten(box(0, 0, 10, 10).difference(box(3, 3, 7, 7)), 1.0), stroke_only=True)
    >>> text.count("<path"), 'fill="none"' in text
    (2, True)
    """
    layers = _check_layers(layers)
    _check_unit(unit)
    meta = meta or {}
    x0, y0, x1, y1 = _bounds(result, layers)
    size = max(x1 - x0, y1 - y0)
    if not (math.isfinite(size) and size > 0):
        size = 1.0
    page = meta.get("page") if unit is None else None
    if page:
        root_attrs = " ".join(f'{k}="{_attr(v)}"' for k, v in page.items())
    else:
        margin = 0.05 * size
        vb = (x0 - margin, -(y1 + margin), (x1 - x0) + 2 * margin, (y1 - y0) + 2 * margin)
        root_attrs = f'viewBox="{" ".join(_num(v) for v in vb)}"'
        size_unit, factor = unit, 1.0
        if size_unit is None and meta.get("units"):
            if meta["units"] in _UNITS_PER_INCH:
                size_unit = meta["units"]
            elif meta.get("mm_per_unit"):
                size_unit, factor = "mm", float(meta["mm_per_unit"])
        if size_unit:
            w, h = _num(vb[2] * factor), _num(vb[3] * factor)
            root_attrs += f' width="{w}{size_unit}" height="{h}{size_unit}"'
    stroke = _num(0.002 * size)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<svg xmlns="http://www.w3.org/2000/svg" '
        'xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" version="1.1" ' + root_attrs + ">",
        f"<!-- vectortighten: {_radius_text(result)} init={result.init} perimeter={_num(result.perimeter)} "
        f"area={_num(result.area)} components={result.n_components} holes={result.n_holes}; "
        "coordinates are the shape's with y negated -->",
    ]
    styles = {
        "mortar": ('fill="#c9c9c9" stroke="none"', lambda: result.mortar),
        "core": ('fill="#2b2b2b" fill-opacity="0.85" stroke="none"', lambda: result.core),
    }
    for name in ("mortar", "core"):
        if name in layers:
            style, geom = styles[name]
            d = _polygon_path_flipped(geom())
            lines.append(f'<g id="{name}" {_LAYER_ATTR}="{name}" inkscape:label="{name}" '
                         'inkscape:groupmode="layer">'
                         + (f'<path d="{d}" fill-rule="evenodd" {style}/>' if d else "") + "</g>")
    lines.append('<g id="tightening-layer" inkscape:label="tightening" inkscape:groupmode="layer">'
                 + _tightening_body(result, layers, meta, keep_style, stroke_only, stroke, size) + "</g>")
    if "input" in layers:
        d = _polygon_path_flipped(result.shape)
        lines.append(f'<g id="input" {_LAYER_ATTR}="input" inkscape:label="input" inkscape:groupmode="layer">'
                     + (f'<path d="{d}" fill="none" stroke="#1f3b73" stroke-width="{stroke}" '
                        f'stroke-dasharray="{_num(0.01 * size)}"/>' if d else "") + "</g>")
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def _tightening_body(result, layers, meta, keep_style, stroke_only, stroke, size) -> str:
    loops = result.loops
    if not loops:
        return ""
    style_map = meta.get("styles") if keep_style else None
    if keep_style and style_map is None:
        warnings.warn("keep_style: the input has no styles to keep (not an SVG); default styles written",
                      UserWarning, stacklevel=4)
    if not stroke_only and style_map is None:
        fill = 'fill="#d1495b" fill-opacity="0.6"' if layers else 'fill="#d1495b"'
        d = " ".join(_loop_path_flipped(lp) for lp in loops)
        return (f'<path id="tightening" d="{d}" fill-rule="evenodd" {fill} stroke="#d1495b" '
                f'stroke-width="{stroke}"/>')
    mm = meta.get("mm_per_unit")
    hairline = {"fill": "none", "stroke": "#ff0000",
                "stroke-width": _num(0.0254 / mm) if mm else _num(0.001 * size)}
    tol = result.tolerance
    parts = []
    n = 0
    for outer, holes in _components(loops, tol):
        if style_map is None:
            comp_style = None
        elif style_map.mode == "paint":
            region = Polygon(loops[outer].sample(tol), [loops[k].sample(tol) for k in holes])
            comp_style = style_map.of_region(region if region.is_valid else shapely.make_valid(region))
        else:
            comp_style = style_map.of_loop(loops[outer])
        if not stroke_only and comp_style is not None and _is_filled(comp_style):
            d = " ".join(_loop_path_flipped(loops[k]) for k in (outer, *holes))
            style = {**comp_style, "fill-rule": "evenodd"}
            n += 1
            parts.append(f'<path id="tightening-{n}" d="{d}" {_style_attrs(style)}/>')
            continue
        for k in (outer, *holes):
            if style_map is None:
                style = dict(hairline)
            else:
                own = style_map.of_loop(loops[k]) if style_map.mode != "paint" else comp_style
                style = dict(own or comp_style or hairline)
                if stroke_only:
                    style["fill"] = "none"
                    if style.get("stroke", "none").strip().lower() in ("none", "transparent"):
                        style.update({k2: v for k2, v in hairline.items() if k2 != "fill"})
            n += 1
            parts.append(_element(loops[k], _style_attrs(style), f"tightening-{n}"))
    return "".join(parts)
