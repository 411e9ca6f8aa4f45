"""WKT with circular arcs (``CURVEPOLYGON``, ``CIRCULARSTRING``, ``COMPOUNDCURVE``, ``MULTISURFACE``).

GEOS (and so shapely) does not read these types. Here they are parsed and their arcs sampled into chords
within a flattening tolerance, as the SVG and DXF readers flatten theirs; plain types met on the way
(``POLYGON``, ``MULTIPOLYGON``, ``LINESTRING`` rings, ``GEOMETRYCOLLECTION``) are read too. Z and M
ordinates are ignored. `read_curved_wkt` samples the arcs (the polygon the engine takes);
`read_curved_wkt_loops` keeps them: the boundary as `Loop`s with one exact `Arc` a three-point arc.

A ``CIRCULARSTRING`` is a chain of arcs, each through three consecutive points (start, a point on the
arc, end; consecutive arcs share their end points); three collinear points are a straight piece, and a
closed three-point string is a full circle whose middle point is diametrically opposite the start.
"""

from __future__ import annotations

import math
import re

import numpy as np
from shapely.geometry import MultiPolygon, Polygon

from vectortighten.errors import InvalidGeometryError

__all__ = ["has_curves", "read_curved_wkt", "read_curved_wkt_loops"]

_CURVED = re.compile(r"\b(CURVEPOLYGON|CIRCULARSTRING|COMPOUNDCURVE|MULTISURFACE|MULTICURVE)\b", re.I)
_TOKEN = re.compile(r"\s*(?:([A-Za-z]+)|([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|nan|inf)|(\()|(\))|(,))")
_MAX_DEPTH = 64
_MAX_CHORDS = 100_000
#: Default flattening: this fraction of the diagonal of the control points' bounding box (as for SVG).
DEFAULT_FLATTEN = 1e-4


def has_curves(text: str) -> bool:
    """Whether WKT text uses a curved geometry type (which GEOS cannot read)."""
    return _CURVED.search(text) is not None


class _Parser:
    def __init__(self, text: str, source: str):
        self.source = source
        self.tokens: list[tuple[str, str]] = []
        pos = 0
        while pos < len(text):
            if text[pos:].strip() == "":
                break
            m = _TOKEN.match(text, pos)
            if m is None or m.end() == pos:
                raise self.error(f"unexpected text {text[pos:pos + 20].strip()!r}")
            word, num, lp, rp, comma = m.groups()
            self.tokens.append(("word", word.upper()) if word else ("num", num) if num else
                               ("(", "(") if lp else (")", ")") if rp else (",", ","))
            pos = m.end()
        self.i = 0

    def error(self, what: str) -> InvalidGeometryError:
        return InvalidGeometryError(f"{self.source}: malformed WKT ({what})")

    def peek(self) -> tuple[str, str]:
        return self.tokens[self.i] if self.i < len(self.tokens) else ("end", "")

    def take(self, kind: str) -> str:
        k, v = self.peek()
        if k != kind:
            raise self.error(f"expected {kind!r}, got {v or 'the end'!r}")
        self.i += 1
        return v

    def word(self) -> str:
        w = self.take("word")
        while self.peek()[0] == "word" and self.peek()[1] in ("Z", "M", "ZM"):
            self.i += 1
        return w

    def empty(self) -> bool:
        if self.peek() == ("word", "EMPTY"):
            self.i += 1
            return True
        return False

    def points(self) -> np.ndarray:
        """A parenthesised list of points, ``( x y [z [m]], ... )``."""
        self.take("(")
        rows = []
        while True:
            row = []
            while self.peek()[0] == "num":
                row.append(float(self.take("num")))
            if len(row) < 2:
                raise self.error("a point needs two coordinates")
            rows.append(row[:2])
            if self.peek()[0] == ",":
                self.i += 1
                continue
            self.take(")")
            return np.array(rows, dtype=float)


def _arc_through(p0, p1, p2):
    """``(center, radius, start_angle, sweep)`` of the arc from p0 through p1 to p2, or None if the three
    points are collinear (a straight piece) or p0 = p1 = p2. A closed string (p0 = p2) is the full circle
    whose diameter is p0 p1, swept counter-clockwise."""
    if np.array_equal(p0, p2):
        center = 0.5 * (p0 + p1)
        radius = 0.5 * float(np.hypot(*(p1 - p0)))
        if not (math.isfinite(radius) and radius > 0):
            return None
        return center, radius, math.atan2(p0[1] - center[1], p0[0] - center[0]), 2.0 * math.pi
    (ax, ay), (bx, by), (cx, cy) = p0, p1, p2
    d = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    chord = max(float(np.hypot(*(p2 - p0))), float(np.hypot(*(p1 - p0))), 1e-300)
    if not math.isfinite(d) or abs(d) <= 1e-14 * chord * chord:
        return None
    a2_, b2_, c2_ = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    ux = (a2_ * (by - cy) + b2_ * (cy - ay) + c2_ * (ay - by)) / d
    uy = (a2_ * (cx - bx) + b2_ * (ax - cx) + c2_ * (bx - ax)) / d
    radius = float(np.hypot(ax - ux, ay - uy))
    if not (math.isfinite(radius) and radius > 0):
        return None
    a0 = math.atan2(ay - uy, ax - ux)
    a2 = math.atan2(cy - uy, cx - ux)
    sweep = (a2 - a0) % (2.0 * math.pi) if d > 0 else -((a0 - a2) % (2.0 * math.pi))
    return np.array([ux, uy]), radius, a0, sweep


def _arc_points(p0, p1, p2, tol: float) -> np.ndarray:
    """Points after p0 up to p2 along the circle through p0, p1, p2, chords within ``tol``."""
    full = np.array_equal(p0, p2)
    if full:
        center = 0.5 * (p0 + p1)
        radius = 0.5 * float(np.hypot(*(p1 - p0)))
        if radius == 0:
            return p2[None, :]
        a0 = math.atan2(p0[1] - center[1], p0[0] - center[0])
        sweep = 2.0 * math.pi
    else:
        (ax, ay), (bx, by), (cx, cy) = p0, p1, p2
        d = 2.0 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
        chord = max(float(np.hypot(*(p2 - p0))), float(np.hypot(*(p1 - p0))), 1e-300)
        if not math.isfinite(d) or abs(d) <= 1e-14 * chord * chord:
            return np.array([p1, p2]) if not np.array_equal(p1, p2) else p2[None, :]   # collinear: a line
        a2_, b2_, c2_ = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
        ux = (a2_ * (by - cy) + b2_ * (cy - ay) + c2_ * (ay - by)) / d
        uy = (a2_ * (cx - bx) + b2_ * (ax - cx) + c2_ * (bx - ax)) / d
        center = np.array([ux, uy])
        radius = float(np.hypot(ax - ux, ay - uy))
        a0 = math.atan2(ay - uy, ax - ux)
        a1 = math.atan2(by - uy, bx - ux)
        a2 = math.atan2(cy - uy, cx - ux)
        ccw = d > 0
        sweep = (a2 - a0) % (2.0 * math.pi) if ccw else -((a0 - a2) % (2.0 * math.pi))
        del a1
    if not (math.isfinite(radius) and radius > 0):
        return p2[None, :]
    step = 2.0 * math.acos(max(-1.0, 1.0 - tol / radius)) if tol < 2 * radius else math.pi
    n = min(_MAX_CHORDS, max(2, math.ceil(abs(sweep) / step) if step > 0 else _MAX_CHORDS))
    t = a0 + sweep * np.arange(1, n + 1) / n
    pts = center + radius * np.column_stack([np.cos(t), np.sin(t)])
    pts[-1] = p2
    return pts


def _circular(pts: np.ndarray, tol: float, source: str) -> np.ndarray:
    if len(pts) < 3 or len(pts) % 2 == 0:
        raise InvalidGeometryError(f"{source}: malformed WKT (a CIRCULARSTRING needs an odd number of "
                                   f"points, at least 3; got {len(pts)})")
    out = [pts[:1]]
    for k in range(0, len(pts) - 2, 2):
        out.append(_arc_points(pts[k], pts[k + 1], pts[k + 2], tol))
    return np.concatenate(out)


class _Reader:
    """Builds polygons from the parse, given the flattening tolerance."""

    def __init__(self, p: _Parser, tol: float):
        self.p, self.tol = p, tol

    def curve(self) -> np.ndarray:
        """A ring's or a compound piece's points: ``(…)``, LINESTRING, CIRCULARSTRING or COMPOUNDCURVE."""
        p = self.p
        if p.peek()[0] == "(":
            return p.points()
        w = p.word()
        if p.empty():
            return np.zeros((0, 2))
        if w == "LINESTRING":
            return p.points()
        if w == "CIRCULARSTRING":
            return _circular(p.points(), self.tol, p.source)
        if w == "COMPOUNDCURVE":
            p.take("(")
            chain: list[np.ndarray] = []
            while True:
                piece = self.curve()
                if chain and len(piece) and not np.allclose(chain[-1][-1], piece[0], rtol=0,
                                                            atol=1e-9 * (1 + np.abs(piece[0]).max())):
                    raise p.error("the pieces of a COMPOUNDCURVE do not join end to start")
                chain.append(piece[1:] if chain and len(piece) else piece)
                if p.peek()[0] == ",":
                    p.i += 1
                    continue
                p.take(")")
                return np.concatenate(chain) if chain else np.zeros((0, 2))
        raise p.error(f"{w} is not a ring")

    def rings(self) -> list[np.ndarray]:
        p = self.p
        p.take("(")
        out = []
        while True:
            ring = self.curve()
            if len(ring):
                if not np.array_equal(ring[0], ring[-1]):
                    raise p.error("a ring is not closed")
                out.append(ring)
            if p.peek()[0] == ",":
                p.i += 1
                continue
            p.take(")")
            return out

    def polygon(self, rings: list[np.ndarray]) -> list[Polygon]:
        if not rings:
            return []
        if len(rings[0]) < 4:
            raise self.p.error("a ring needs at least 3 distinct points")
        return [Polygon(rings[0], [r for r in rings[1:] if len(r) >= 4])]

    def geometry(self, depth: int = 0) -> list[Polygon]:
        p = self.p
        if depth > _MAX_DEPTH:
            raise p.error("collections nested too deeply")
        w = p.word()
        if p.empty():
            return []
        if w in ("POLYGON", "CURVEPOLYGON"):
            return self.polygon(self.rings())
        if w in ("MULTIPOLYGON", "MULTISURFACE"):
            p.take("(")
            out: list[Polygon] = []
            while True:
                out += self.polygon(self.rings()) if p.peek()[0] == "(" else self.geometry(depth + 1)
                if p.peek()[0] == ",":
                    p.i += 1
                    continue
                p.take(")")
                return out
        if w == "GEOMETRYCOLLECTION":
            p.take("(")
            out = []
            while True:
                out += self.geometry(depth + 1)
                if p.peek()[0] == ",":
                    p.i += 1
                    continue
                p.take(")")
                return out
        # Points, lines and curves on their own bound no region: skip them (balanced parentheses).
        p.take("(")
        level = 1
        while level:
            k, _ = p.peek()
            if k == "end":
                raise p.error(f"unbalanced parentheses in {w}")
            p.i += 1
            level += 1 if k == "(" else -1 if k == ")" else 0
        return []


def read_curved_wkt(text: str, source: str, flatten: float | None = None) -> Polygon | MultiPolygon:
    """The polygonal part of curved WKT ``text``, its arcs sampled within ``flatten``.

    Parameters
    ----------
    text : str
        WKT, possibly with ``CURVEPOLYGON``, ``CIRCULARSTRING``, ``COMPOUNDCURVE``, ``MULTISURFACE``.
    source : str
        Names the file in messages.
    flatten : float, optional
        Largest distance between an arc and its chords, in the file's units; default `DEFAULT_FLATTEN`
        times the diagonal of the bounding box of all points.

    Returns
    -------
    Polygon or MultiPolygon
        Possibly invalid (the caller repairs it); empty when the text holds no polygon.

    Examples
    --------
    >>> g = read_curved_wkt("CURVEPOLYGON(CIRCULARSTRING(0 0, 2 0, 0 0))", "x.wkt", 1e-6)
    >>> abs(g.area - 3.141592653589793) < 1e-5
    True
    """
    probe = _Parser(text, source)
    nums = np.array([float(v) for k, v in probe.tokens if k == "num"], dtype=float)
    if len(nums) and not np.isfinite(nums).all():
        raise InvalidGeometryError(f"{source}: NaN or infinite coordinates")
    if flatten is None:
        xy = nums[: len(nums) // 2 * 2].reshape(-1, 2) if len(nums) >= 2 else np.zeros((1, 2))
        diag = float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))
        flatten = DEFAULT_FLATTEN * diag if diag > 0 else 1.0
    reader = _Reader(probe, flatten)
    polys = reader.geometry()
    if probe.peek()[0] != "end":
        raise probe.error(f"unexpected {probe.peek()[1]!r} after the geometry")
    if not polys:
        return Polygon()
    return polys[0] if len(polys) == 1 else MultiPolygon(polys)


def _segments(pts: np.ndarray) -> list:
    from vectortighten.curves import Segment

    return [Segment(pts[k], pts[k + 1]) for k in range(len(pts) - 1) if not np.array_equal(pts[k], pts[k + 1])]


class _PieceReader(_Reader):
    """Like `_Reader`, but a ring is a list of exact pieces (`Segment`, `Arc`) instead of points."""

    def curve(self):
        from vectortighten.curves import Arc

        p = self.p
        if p.peek()[0] == "(":
            return _segments(p.points())
        w = p.word()
        if p.empty():
            return []
        if w == "LINESTRING":
            return _segments(p.points())
        if w == "CIRCULARSTRING":
            pts = p.points()
            _circular(pts, 1.0, p.source)                       # the same checks as when sampling
            out = []
            for k in range(0, len(pts) - 2, 2):
                arc = _arc_through(pts[k], pts[k + 1], pts[k + 2])
                if arc is None:
                    out += _segments(pts[k:k + 3])
                else:
                    out.append(Arc(*arc))
            return out
        if w == "COMPOUNDCURVE":
            p.take("(")
            chain: list = []
            while True:
                piece = self.curve()
                if chain and piece and not np.allclose(chain[-1].end, piece[0].start, rtol=0,
                                                       atol=1e-9 * (1 + np.abs(piece[0].start).max())):
                    raise p.error("the pieces of a COMPOUNDCURVE do not join end to start")
                chain += piece
                if p.peek()[0] == ",":
                    p.i += 1
                    continue
                p.take(")")
                return chain
        raise p.error(f"{w} is not a ring")

    def rings(self):
        p = self.p
        p.take("(")
        out = []
        while True:
            ring = self.curve()
            if ring:
                a, b = np.asarray(ring[0].start), np.asarray(ring[-1].end)
                if not np.allclose(a, b, rtol=0, atol=1e-9 * (1 + np.abs(a).max())):
                    raise p.error("a ring is not closed")
                out.append(ring)
            if p.peek()[0] == ",":
                p.i += 1
                continue
            p.take(")")
            return out

    def polygon(self, rings):
        return [rings] if rings else []


def read_curved_wkt_loops(text: str, source: str) -> list:
    """The boundary of curved WKT ``text`` as exact loops: each three-point arc one `Arc`.

    Parameters
    ----------
    text : str
        WKT, possibly with ``CURVEPOLYGON``, ``CIRCULARSTRING``, ``COMPOUNDCURVE``, ``MULTISURFACE``.
    source : str
        Names the file in messages.

    Returns
    -------
    list of Loop
        Every polygon's first ring counter-clockwise, its other rings clockwise (reversed where the file
        runs them the other way), in the file's units. Whether they bound a valid shape is the caller's
        to check (`read_curved_wkt` gives the same region sampled).

    Examples
    --------
    A square plate with a hole of radius 2: the hole is one arc, clockwise.

    >>> wkt = ("CURVEPOLYGON((0 0, 10 0, 10 10, 0 10, 0 0), "
    ...        "CIRCULARSTRING(3 5, 7 5, 3 5))")
    >>> plate, hole = read_curved_wkt_loops(wkt, "x.wkt")
    >>> [(a.center, a.radius, round(a.sweep, 9)) for a in hole.arcs]
    [((5.0, 5.0), 2.0, -6.283185307)]
    """
    from vectortighten.curves import Loop

    probe = _Parser(text, source)
    nums = np.array([float(v) for k, v in probe.tokens if k == "num"], dtype=float)
    if len(nums) and not np.isfinite(nums).all():
        raise InvalidGeometryError(f"{source}: NaN or infinite coordinates")
    polys = _PieceReader(probe, 1.0).geometry()
    if probe.peek()[0] != "end":
        raise probe.error(f"unexpected {probe.peek()[1]!r} after the geometry")
    loops = []
    for rings in polys:
        for k, ring in enumerate(rings):
            try:
                lp = Loop(ring)
            except ValueError as exc:
                raise probe.error(str(exc)) from None
            if (lp.area > 0) != (k == 0) and lp.area != 0:
                lp = lp.reversed()
            loops.append(lp)
    return loops
