"""SVG: reading a drawing's filled region, and writing a tightening with real arc commands.

Reading (`read_svg`): every filled shape of the drawing (paths with lines, Bézier curves and elliptical
arcs; rect, circle, ellipse, polygon, polyline; transforms of nested groups and ``<use>``), each filled by
its own ``fill-rule`` (``nonzero`` by default, or ``evenodd``), all united. Curves are flattened to
``flatten`` (default `DEFAULT_FLATTEN` times the drawing's diagonal). Coordinates are the drawing's user
units (those of the root ``viewBox``) with y pointing up, so that a shape written by `svg_document` reads
back where it was. The XML is checked with defusedxml first: entity declarations (billion laughs, XXE)
and references to external DTDs other than the W3C's own SVG DTDs are refused, never followed.

svgelements and defusedxml (``pip install vectortighten[svg]``) are imported only when an SVG is met.
"""

from __future__ import annotations

import io as _stdio
import math
import re
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from vectortighten.curves import Segment
from vectortighten.errors import InvalidGeometryError

from ._common import _bounds, _check_layers, _polygonal, _require
from ._fill import fill_rings

__all__ = ["DEFAULT_FLATTEN", "read_svg", "svg_document", "svg_unit"]

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


def _describe(el) -> str:
    ident = el.get("id")
    return f"<{_local(el.tag)} id={ident!r}>" if ident else f"<{_local(el.tag)}>"


def _matrix(m) -> np.ndarray:
    """A 3×3 numpy matrix from an svgelements Matrix (x' = a x + c y + e, y' = b x + d y + f)."""
    return np.array([[m.a, m.c, m.e], [m.b, m.d, m.f], [0.0, 0.0, 1.0]], dtype=float)


def _curve_chords(seg, se, tol: float) -> np.ndarray:
    """Points after ``seg.start`` up to ``seg.end`` on a curve, chords within ``tol`` (local units)."""
    if isinstance(seg, se.CubicBezier):
        p = np.array([[seg.start.x, seg.start.y], [seg.control1.x, seg.control1.y],
                      [seg.control2.x, seg.control2.y], [seg.end.x, seg.end.y]])
        bend = max(np.hypot(*(p[0] - 2 * p[1] + p[2])), np.hypot(*(p[1] - 2 * p[2] + p[3])))
        # |B''| ≤ 6·bend, and a chord of a parameter step h is within |B''|·h²/8 of the curve.
        n = math.ceil(math.sqrt(6.0 * bend / (8.0 * tol)))
    elif isinstance(seg, se.QuadraticBezier):
        p = np.array([[seg.start.x, seg.start.y], [seg.control.x, seg.control.y], [seg.end.x, seg.end.y]])
        bend = np.hypot(*(p[0] - 2 * p[1] + p[2]))
        n = math.ceil(math.sqrt(2.0 * bend / (8.0 * tol)))
    elif isinstance(seg, se.Arc):
        big = max(abs(seg.rx), abs(seg.ry))                     # |point''| ≤ max radius per radian²
        n = math.ceil(abs(seg.sweep) * math.sqrt(big / (8.0 * tol)))
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


def _subpath_rings(path, se, tol: float) -> list[np.ndarray]:
    """The subpaths of an svgelements Path as open point arrays (each closed implicitly, as fill does)."""
    rings: list[np.ndarray] = []
    current: list[np.ndarray] | None = None

    def finish():
        if current:
            rings.append(np.concatenate(current))

    for seg in path:
        if isinstance(seg, se.Move):
            finish()
            current = [np.array([[seg.end.x, seg.end.y]], dtype=float)]
        elif isinstance(seg, se.Close):
            finish()
            current = None
        else:
            if current is None:
                current = [np.array([[seg.start.x, seg.start.y]], dtype=float)]
            if isinstance(seg, se.Line):
                current.append(np.array([[seg.end.x, seg.end.y]], dtype=float))
            else:
                current.append(_curve_chords(seg, se, tol))
    finish()
    return rings


def read_svg(source, *, flatten: float | None = None) -> Polygon | MultiPolygon:
    """Read the filled region of an SVG drawing (see the module's notes), y up, in user units.

    Parameters
    ----------
    source : str, Path or bytes
        A file name, or the document itself.
    flatten : float, optional
        Largest distance between a curve (Bézier, arc, circle, rounded corner) and the chords that replace
        it, in user units. Default `DEFAULT_FLATTEN` times the diagonal of the drawing's bounding box.

    Returns
    -------
    Polygon or MultiPolygon
        Every shape filled by its own fill rule, all united. Shapes are read whatever their paint (cutting
        files often draw outlines only); ``display="none"``, unrendered containers (defs, symbol, mask,
        marker, pattern, clipPath) and the extra layers `svg_document` adds are skipped; text and images
        are skipped with a warning.

    Examples
    --------
    >>> svg = b'''<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">
    ...   <path d="M 0 0 H 10 V 10 H 0 Z M 2 2 H 8 V 8 H 2 Z" fill-rule="evenodd"/></svg>'''
    >>> read_svg(svg).area
    64.0
    """
    if isinstance(source, (bytes, bytearray)):
        data, name = bytes(source), "<svg>"
    else:
        name = str(source)
        data = Path(source).read_bytes()
    if flatten is not None and not (math.isfinite(flatten) and flatten > 0):
        raise ValueError(f"flatten must be a positive finite number, got {flatten!r}")
    try:
        return _read_svg(data, name, flatten)
    except RecursionError:
        raise InvalidGeometryError(f"{name}: malformed SVG (elements nested too deeply)") from None


def _read_svg(data: bytes, name: str, flatten: float | None) -> Polygon | MultiPolygon:
    root = _safe_svg_tree(data, name)
    se = _require("svgelements", "svg", "reading SVG")
    clean, ignored = _prepare_svg(root, name)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            svg = se.SVG.parse(_stdio.BytesIO(clean), reify=False, on_error="raise")
    except (ValueError, TypeError, IndexError, AttributeError, KeyError, ZeroDivisionError) as exc:
        for el in root.iter():            # name the culprit when it is path data (the usual one)
            if _local(el.tag) == "path" and el.get("d"):
                try:
                    se.Path(el.get("d"))
                except (ValueError, IndexError, TypeError):
                    raise InvalidGeometryError(f"{name}: malformed SVG (bad path data in {_describe(el)})") \
                        from None
        detail = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
        raise InvalidGeometryError(f"{name}: malformed SVG ({detail})") from None
    # The root viewport maps user units to px; undo it so coordinates are the drawing's user units.
    view = _matrix(se.Matrix(svg.viewbox_transform)) if getattr(svg, "viewbox_transform", "") else np.eye(3)
    try:
        to_user = np.linalg.inv(view)
    except np.linalg.LinAlgError:
        raise InvalidGeometryError(f"{name}: malformed SVG (degenerate viewBox)") from None
    shapes = []
    for el in svg.elements():
        if not isinstance(el, se.Shape) or isinstance(el, se.SimpleLine):
            continue
        path = se.Path(el)
        if len(path) == 0:
            continue
        m = to_user @ _matrix(path.transform)
        m[1] *= -1.0                                     # y up
        smax = np.linalg.svd(m[:2, :2], compute_uv=False)[0]
        if not (math.isfinite(smax) and smax > 0) or abs(np.linalg.det(m[:2, :2])) == 0:
            continue
        rule = str(el.values.get("fill-rule") or "nonzero").strip().lower()
        shapes.append((path, m, smax, "evenodd" if rule == "evenodd" else "nonzero"))
    for tag, count in ignored.items():
        warnings.warn(f"{name}: {count} <{tag}> element(s) ignored (convert text and images to paths)",
                      UserWarning, stacklevel=3)
    if not shapes:
        raise InvalidGeometryError(f"{name}: no shapes found in the SVG")
    if flatten is None:
        corners = []
        for path, m, _, _ in shapes:
            pts = np.array([[s.end.x, s.end.y] for s in path if s.end is not None] or [[0.0, 0.0]])
            with np.errstate(all="ignore"):
                corners.append(pts @ m[:2, :2].T + m[:2, 2])
        allpts = np.concatenate(corners)
        allpts = allpts[np.isfinite(allpts).all(axis=1)]
        diag = float(np.hypot(*(allpts.max(axis=0) - allpts.min(axis=0)))) if len(allpts) else 0.0
        flatten = DEFAULT_FLATTEN * diag if diag > 0 else 1e-6
    regions = []
    for path, m, smax, rule in shapes:
        rings = []
        for ring in _subpath_rings(path, se, flatten / smax):
            with np.errstate(all="ignore"):
                user = ring @ m[:2, :2].T + m[:2, 2]
            if not np.isfinite(user).all():
                raise InvalidGeometryError(f"{name}: NaN or infinite coordinates (after transforms)")
            rings.append(user)
        region = fill_rings(rings, rule)
        if not region.is_empty:
            regions.append(region)
    if not regions:
        raise InvalidGeometryError(f"{name}: the SVG has no closed shape with an area")
    return _polygonal(shapely.union_all(regions) if len(regions) > 1 else regions[0], name)


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
    root = _safe_svg_tree(data, name)
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
def _num(value: float) -> str:
    """Shortest decimal that reads back as the same float (``2.0`` → ``"2"``)."""
    text = repr(float(value))
    if text.endswith(".0"):
        text = text[:-2]
    return "0" if text == "-0" else text


def _loop_path_flipped(loop) -> str:
    """SVG path data of an exact loop with y flipped (SVG's y points down): ``M``, ``L`` and ``A``."""
    pieces = loop.pieces
    if not pieces:
        return ""
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


def svg_document(result, *, layers=(), unit: str | None = None) -> str:
    """The SVG document `write_result` writes for a `Tightening`.

    The tightening is one ``<path id="tightening">`` with ``fill-rule="evenodd"``, straight ``L`` and
    ``A`` commands whose radius is exactly ``r``. The y axis is flipped (SVG's points down) and the
    ``viewBox`` frames the shapes with a margin, so the picture looks as the shape does in a y-up plot and
    `read_svg` gives back the same coordinates. ``layers`` adds groups (Inkscape layers) under it.

    Parameters
    ----------
    result : Tightening
    layers : iterable of {"input", "core", "mortar"}
    unit : {"mm", "cm", "in", "pt", "pc", "px"}, optional
        The physical length of one unit of the shape: sets ``width`` and ``height`` so that the drawing
        has its true size (see `svg_unit`). Without it the document has no ``width`` and ``height``.
    """
    layers = _check_layers(layers)
    _check_unit(unit)
    x0, y0, x1, y1 = _bounds(result, layers)
    size = max(x1 - x0, y1 - y0)
    if not (math.isfinite(size) and size > 0):
        size = 1.0
    margin = 0.05 * size
    vb = (x0 - margin, -(y1 + margin), (x1 - x0) + 2 * margin, (y1 - y0) + 2 * margin)
    stroke = _num(0.002 * size)
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<svg xmlns="http://www.w3.org/2000/svg" '
        'xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" version="1.1" '
        f'viewBox="{" ".join(_num(v) for v in vb)}"'
        + (f' width="{_num(vb[2])}{unit}" height="{_num(vb[3])}{unit}">' if unit else ">"),
        f"<!-- vectortighten: r={_num(result.r)} init={result.init} perimeter={_num(result.perimeter)} "
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
    fill = 'fill="#d1495b" fill-opacity="0.6"' if layers else 'fill="#d1495b"'
    d = " ".join(_loop_path_flipped(lp) for lp in result.loops)
    lines.append('<g id="tightening-layer" inkscape:label="tightening" inkscape:groupmode="layer">'
                 + (f'<path id="tightening" d="{d}" fill-rule="evenodd" {fill} stroke="#d1495b" '
                    f'stroke-width="{stroke}"/>' if d else "") + "</g>")
    if "input" in layers:
        d = _polygon_path_flipped(result.shape)
        lines.append(f'<g id="input" {_LAYER_ATTR}="input" inkscape:label="input" inkscape:groupmode="layer">'
                     + (f'<path d="{d}" fill="none" stroke="#1f3b73" stroke-width="{stroke}" '
                        f'stroke-dasharray="{_num(0.01 * size)}"/>' if d else "") + "</g>")
    lines.append("</svg>")
    return "\n".join(lines) + "\n"
