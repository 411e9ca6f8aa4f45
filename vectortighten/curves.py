"""Exact curves made of straight segments and circular arcs.

`Segment` and `Arc` share one small protocol (``start``, ``end``, ``length``, ``point_at``,
``tangent_at``, ``curvature``, ``reversed``, ``area_term``, ``sample``, ``bounds``, ``svg``), so that a
`Loop` never asks which kind of piece it holds. A `Loop` is a closed G1 curve: the boundary of a
tightening is a list of them, every arc of radius exactly r.

Angles are in radians, counter-clockwise from the +x axis; a positive sweep turns left. Coordinates are in
the units of the input shape.

The last part of the module builds loops from disks. A tight loop is a cyclic sequence of disks of radius
r, each with a `Side`: `Side.CORE` when the loop turns left around it (the disk lies inside the set the
loop bounds) and `Side.ANTICORE` when it turns right (the disk lies outside). Consecutive disks are joined
by their common tangent: the outer tangent for equal sides, the crossing tangent for opposite sides.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Iterable, Sequence

import numpy as np
import shapely
from shapely.geometry import LinearRing, Polygon

from .tolerances import CORNER_ANGLE, SPECK_SCALE, rounding_length

__all__ = [
    "Arc",
    "Loop",
    "Segment",
    "Side",
    "common_tangents",
    "disk_tangent",
    "tangent_directions",
]

_TWO_PI = 2.0 * math.pi


class Side(enum.IntEnum):
    """Which way a loop turns around a disk it touches.

    ``CORE`` (+1): the loop turns left, the disk is on the side of the set it bounds (a disk of the core).
    ``ANTICORE`` (-1): the loop turns right, the disk is outside the set (a disk of the anticore).
    """

    CORE = 1
    ANTICORE = -1


def _fmt(value: float, precision: int) -> str:
    text = f"{value:.{precision}g}"
    return "0" if text == "-0" else text


def _arc_steps(radius: float, sweep: float, tolerance: float) -> int:
    """Number of chords for an arc so that no chord is farther than ``tolerance`` from it."""
    if tolerance >= radius:
        step = math.pi / 2
    else:
        step = 2.0 * math.acos(1.0 - tolerance / radius)
    return max(1, math.ceil(abs(sweep) / step - 1e-9))


@dataclass(frozen=True, slots=True)
class Segment:
    """A straight segment from ``start`` to ``end``.

    Parameters
    ----------
    start, end : (2,) float
        End points, in the units of the shape.

    Examples
    --------
    >>> s = Segment((0.0, 0.0), (3.0, 4.0))
    >>> s.length
    5.0
    >>> s.point_at(0.5)
    (1.5, 2.0)
    """

    start: tuple[float, float]
    end: tuple[float, float]

    def __post_init__(self):
        object.__setattr__(self, "start", (float(self.start[0]), float(self.start[1])))
        object.__setattr__(self, "end", (float(self.end[0]), float(self.end[1])))

    @property
    def length(self) -> float:
        """Length of the segment."""
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def curvature(self) -> float:
        """Signed curvature, 0 for a segment."""
        return 0.0

    def point_at(self, t: float) -> tuple[float, float]:
        """Point at the fraction ``t`` of the length (0 is ``start``, 1 is ``end``)."""
        (x0, y0), (x1, y1) = self.start, self.end
        return (x0 + t * (x1 - x0), y0 + t * (y1 - y0))

    def tangent_at(self, t: float = 0.0) -> tuple[float, float]:
        """Unit tangent (the same everywhere on a segment)."""
        dx, dy = self.end[0] - self.start[0], self.end[1] - self.start[1]
        n = math.hypot(dx, dy)
        if n == 0:
            return (float("nan"), float("nan"))
        return (dx / n, dy / n)

    def reversed(self) -> Segment:
        """The same segment run the other way."""
        return Segment(self.end, self.start)

    def area_term(self, origin: tuple[float, float] = (0.0, 0.0)) -> float:
        """Contribution ½∮(x dy − y dx) of this piece to the signed area of a closed curve.

        Coordinates are taken relative to ``origin``; the total over a closed curve does not depend on it.
        """
        x0, y0 = self.start[0] - origin[0], self.start[1] - origin[1]
        x1, y1 = self.end[0] - origin[0], self.end[1] - origin[1]
        return 0.5 * (x0 * y1 - x1 * y0)

    def sample(self, tolerance: float) -> np.ndarray:
        """Points ``(n, 2)`` from ``start`` up to, but excluding, ``end`` (a segment needs only its start)."""
        return np.array([self.start])

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(minx, miny, maxx, maxy)``."""
        (x0, y0), (x1, y1) = self.start, self.end
        return (min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1))

    def svg(self, precision: int = 12) -> str:
        """SVG path command drawing this piece from the current point (``L x y``)."""
        return f"L {_fmt(self.end[0], precision)} {_fmt(self.end[1], precision)}"

    def affine(self, scale: float, dx: float, dy: float) -> Segment:
        """The segment under ``p -> scale·p + (dx, dy)``."""
        return Segment((scale * self.start[0] + dx, scale * self.start[1] + dy),
                       (scale * self.end[0] + dx, scale * self.end[1] + dy))


@dataclass(frozen=True, slots=True)
class Arc:
    """A circular arc: ``center + radius·(cos θ, sin θ)`` for θ from ``start_angle`` over ``sweep``.

    Parameters
    ----------
    center : (2,) float
        Centre of the circle.
    radius : float
        Radius, > 0.
    start_angle : float
        Angle of the start point, radians.
    sweep : float
        Signed angle swept, radians: positive counter-clockwise (the curve turns left), negative clockwise.

    Examples
    --------
    >>> a = Arc((0.0, 0.0), 2.0, 0.0, math.pi / 2)
    >>> round(a.length, 12) == round(math.pi, 12)
    True
    >>> [round(v, 12) for v in a.end]
    [0.0, 2.0]
    """

    center: tuple[float, float]
    radius: float
    start_angle: float
    sweep: float

    def __post_init__(self):
        object.__setattr__(self, "center", (float(self.center[0]), float(self.center[1])))
        object.__setattr__(self, "radius", float(self.radius))
        object.__setattr__(self, "start_angle", float(self.start_angle))
        object.__setattr__(self, "sweep", float(self.sweep))
        if not self.radius > 0:
            raise ValueError(f"arc radius must be positive, got {self.radius!r}")

    @property
    def end_angle(self) -> float:
        """Angle of the end point, ``start_angle + sweep``."""
        return self.start_angle + self.sweep

    @property
    def side(self) -> Side:
        """`Side.CORE` if the arc turns left (counter-clockwise), else `Side.ANTICORE`."""
        return Side.CORE if self.sweep >= 0 else Side.ANTICORE

    def _at_angle(self, theta: float) -> tuple[float, float]:
        return (self.center[0] + self.radius * math.cos(theta), self.center[1] + self.radius * math.sin(theta))

    @property
    def start(self) -> tuple[float, float]:
        """Start point."""
        return self._at_angle(self.start_angle)

    @property
    def end(self) -> tuple[float, float]:
        """End point."""
        return self._at_angle(self.end_angle)

    @property
    def length(self) -> float:
        """Arc length, ``radius·|sweep|``."""
        return self.radius * abs(self.sweep)

    @property
    def curvature(self) -> float:
        """Signed curvature: ``+1/radius`` turning left, ``-1/radius`` turning right."""
        return math.copysign(1.0 / self.radius, self.sweep)

    def point_at(self, t: float) -> tuple[float, float]:
        """Point at the fraction ``t`` of the sweep."""
        return self._at_angle(self.start_angle + t * self.sweep)

    def tangent_at(self, t: float = 0.0) -> tuple[float, float]:
        """Unit tangent in the direction of travel at the fraction ``t`` of the sweep."""
        theta = self.start_angle + t * self.sweep
        sign = 1.0 if self.sweep >= 0 else -1.0
        return (-sign * math.sin(theta), sign * math.cos(theta))

    def reversed(self) -> Arc:
        """The same arc run the other way."""
        return Arc(self.center, self.radius, self.end_angle, -self.sweep)

    def area_term(self, origin: tuple[float, float] = (0.0, 0.0)) -> float:
        """Contribution ½∮(x dy − y dx) of this arc to the signed area of a closed curve (exact)."""
        cx, cy = self.center[0] - origin[0], self.center[1] - origin[1]
        r, a0, a1 = self.radius, self.start_angle, self.end_angle
        return 0.5 * (r * r * self.sweep + r * cx * (math.sin(a1) - math.sin(a0))
                      - r * cy * (math.cos(a1) - math.cos(a0)))

    def sample(self, tolerance: float) -> np.ndarray:
        """Points ``(n, 2)`` on the arc from ``start`` up to, excluding, ``end``; chords within ``tolerance``.

        Every sampled point lies on the circle, so the chords lie on the centre's side of the arc.
        """
        n = _arc_steps(self.radius, self.sweep, tolerance)
        theta = self.start_angle + self.sweep * np.arange(n) / n
        return np.column_stack([self.center[0] + self.radius * np.cos(theta),
                                self.center[1] + self.radius * np.sin(theta)])

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(minx, miny, maxx, maxy)`` of the arc (exact: includes the extreme points it passes)."""
        xs = [self.start[0], self.end[0]]
        ys = [self.start[1], self.end[1]]
        lo, hi = sorted((self.start_angle, self.end_angle))
        k = math.ceil(lo / (math.pi / 2))
        while k * math.pi / 2 <= hi:
            x, y = self._at_angle(k * math.pi / 2)
            xs.append(x)
            ys.append(y)
            k += 1
        return (min(xs), min(ys), max(xs), max(ys))

    def svg(self, precision: int = 12) -> str:
        """SVG path commands (``A``) drawing this arc from the current point.

        The coordinates are the shape's own (y up): the sweep flag is 1 for a counter-clockwise arc in
        that frame. An arc of more than half a turn is written as several ``A`` commands.
        """
        parts = max(1, math.ceil(abs(self.sweep) / math.pi - 1e-12))
        r = _fmt(self.radius, precision)
        flag = 1 if self.sweep > 0 else 0
        out = []
        for i in range(1, parts + 1):
            x, y = self._at_angle(self.start_angle + self.sweep * i / parts)
            out.append(f"A {r} {r} 0 0 {flag} {_fmt(x, precision)} {_fmt(y, precision)}")
        return " ".join(out)

    def affine(self, scale: float, dx: float, dy: float) -> Arc:
        """The arc under ``p -> scale·p + (dx, dy)`` (``scale > 0``)."""
        return Arc((scale * self.center[0] + dx, scale * self.center[1] + dy), scale * self.radius,
                   self.start_angle, self.sweep)


Piece = Segment | Arc


def _ahead(x: np.ndarray) -> np.ndarray:
    """``np.roll(x, -1, axis=0)`` (item i + 1 at i, the last at the first's), without np.roll's overhead
    (several times the copy on arrays of a few dozen items)."""
    return np.concatenate([x[1:], x[:1]])


def _behind(x: np.ndarray) -> np.ndarray:
    """``np.roll(x, 1, axis=0)``: item i − 1 at i, the first's at the last."""
    return np.concatenate([x[-1:], x[:-1]])


def _speck_length(c: np.ndarray, r: float) -> float:
    """`SPECK_SCALE` of the extent of a loop of disks of radius r centred at ``c`` (its own units)."""
    extent = float(np.ptp(c, axis=0).max()) + 2.0 * abs(float(r)) if len(c) else 0.0
    return SPECK_SCALE * extent


def _merge_specks(c, s, r, phi, length, sweeps):
    """Disks joined by a speck tangent (shorter than `_speck_length`) on the same side, merged into one.

    A run of disks ``i, i + 1, …, j`` whose tangents are all specks and whose sides agree becomes disk i
    with the run's total sweep, leaving along disk j's outgoing tangent. The merged arc ends where disk
    j's arc ended, moved by ``c_i − c_j`` (shorter than the specks), and its end tangent is that
    tangent's direction exactly: the join stays G1, the gap is within the loop's closing tolerance.
    A speck between disks of opposite sides (an inflection) is left to be dropped: both arcs are already
    tangent to its direction.

    Returns the arrays ``(c, s, phi, length, sweeps)``, unchanged if nothing merges.
    """
    n = len(c)
    if n < 2:
        return c, s, phi, length, sweeps
    # For one side the tangent's length is the distance between the centres: judged on the centres.
    gap = np.hypot(*(_ahead(c) - c).T)
    merge_next = (gap <= _speck_length(c, r)) & (s == _ahead(s))
    merged = _behind(merge_next)                      # disk k is merged into the one before it
    if not merged.any():
        return c, s, phi, length, sweeps
    if merged.all():
        # One disk all round (the shrink is a point): a full circle.
        k = 0
        return c[k:k + 1], s[k:k + 1], phi[-1:], length[-1:], np.array([sweeps.sum()])
    first = int(np.flatnonzero(~merged)[0])
    order = np.roll(np.arange(n), -first)
    lead = ~merged[order]
    group = np.cumsum(lead) - 1
    starts = np.flatnonzero(lead)
    ends = np.r_[starts[1:] - 1, n - 1]
    total = np.bincount(group, weights=sweeps[order])
    return (c[order[starts]], s[order[starts]], phi[order[ends]], length[order[ends]], total)


class Loop:
    """A closed curve of `Segment` and `Arc` pieces, each starting where the previous one ends.

    Parameters
    ----------
    pieces : sequence of Segment or Arc
        The pieces in order; the last ends where the first starts.
    atol : float, optional
        Largest gap allowed between consecutive pieces. Default: 1e-9 of the loop's size.

    Notes
    -----
    The pieces are held as arrays (one row per piece), so that loops of hundreds of thousands of pieces
    measure and sample quickly; ``pieces`` builds the `Segment` and `Arc` objects on first use.
    ``length`` and ``area`` are exact sums over the pieces (Green's theorem for the area); the area is
    positive for a counter-clockwise loop. ``sample`` gives polygon coordinates for shapely.

    Examples
    --------
    >>> sq = Loop([Segment((0, 0), (1, 0)), Segment((1, 0), (1, 1)),
    ...            Segment((1, 1), (0, 1)), Segment((0, 1), (0, 0))])
    >>> sq.length, sq.area
    (4.0, 1.0)
    >>> disk = Loop.circle((0, 0), 1.0)
    >>> round(disk.area, 12) == round(math.pi, 12)
    True
    """

    # A loop never changes after construction, so its exact (compensated) sums are computed once.
    __slots__ = ("_arc", "_data", "_pieces", "_area", "_length", "_terms", "_start_cs")

    def __init__(self, pieces: Iterable[Piece], atol: float | None = None):
        pieces = tuple(pieces)
        if not pieces:
            raise ValueError("a loop needs at least one piece")
        arc = np.array([isinstance(p, Arc) for p in pieces], dtype=bool)
        data = np.array([(p.center[0], p.center[1], p.radius, p.start_angle, p.sweep) if isinstance(p, Arc)
                         else (p.start[0], p.start[1], p.end[0], p.end[1], 0.0) for p in pieces], dtype=float)
        self._arc, self._data, self._pieces = arc, data, pieces
        self._area = self._length = self._terms = self._start_cs = None
        self._check_closed(atol)

    @classmethod
    def _from_arrays(cls, arc: np.ndarray, data: np.ndarray, atol: float | None = math.inf) -> Loop:
        """A loop from its array form: ``arc[i]`` tells the kind of piece i; ``data[i]`` is
        ``(cx, cy, radius, start_angle, sweep)`` for an arc, ``(x0, y0, x1, y1, 0)`` for a segment."""
        if len(arc) == 0:
            raise ValueError("a loop needs at least one piece")
        self = object.__new__(cls)
        self._arc = np.asarray(arc, dtype=bool)
        self._data = np.asarray(data, dtype=float)
        self._pieces = self._area = self._length = self._terms = self._start_cs = None
        self._check_closed(atol)
        return self

    def _check_closed(self, atol):
        if atol == math.inf:
            return
        start, end = self._ends()
        if atol is None:
            x0, y0, x1, y1 = self.bounds
            atol = 1e-9 * max(x1 - x0, y1 - y0, 1e-300)
        gap = np.hypot(*(end - _ahead(start)).T)
        if (gap > atol).any():
            i = int(np.argmax(gap))
            raise ValueError(f"loop is not closed: piece {i} ends {gap[i]:.3g} away from where the next starts")

    def _ends(self) -> tuple[np.ndarray, np.ndarray]:
        """Start and end points of every piece, ``(n, 2)`` each."""
        d, arc = self._data, self._arc
        a0, a1 = d[:, 3], d[:, 3] + d[:, 4]
        start = np.where(arc[:, None], d[:, :2] + d[:, 2:3] * np.column_stack([np.cos(a0), np.sin(a0)]), d[:, :2])
        end = np.where(arc[:, None], d[:, :2] + d[:, 2:3] * np.column_stack([np.cos(a1), np.sin(a1)]), d[:, 2:4])
        return start, end

    def _tangents(self) -> tuple[np.ndarray, np.ndarray]:
        """Unit tangent at the start and at the end of every piece."""
        d, arc = self._data, self._arc
        seg_dir = d[:, 2:4] - d[:, :2]
        norm = np.hypot(*seg_dir.T)
        with np.errstate(invalid="ignore", divide="ignore"):
            seg_dir = seg_dir / norm[:, None]
        sign = np.where(d[:, 4] >= 0, 1.0, -1.0)
        a0, a1 = d[:, 3], d[:, 3] + d[:, 4]
        t0 = np.column_stack([-sign * np.sin(a0), sign * np.cos(a0)])
        t1 = np.column_stack([-sign * np.sin(a1), sign * np.cos(a1)])
        return np.where(arc[:, None], t0, seg_dir), np.where(arc[:, None], t1, seg_dir)

    # -- construction -------------------------------------------------------------------------------
    @classmethod
    def circle(cls, center: Sequence[float], radius: float, ccw: bool = True) -> Loop:
        """A full circle as one arc, counter-clockwise by default."""
        return cls([Arc(center, radius, 0.0, _TWO_PI if ccw else -_TWO_PI)])

    @classmethod
    def from_polygon_ring(cls, coords) -> Loop:
        """A loop of segments through the vertices ``coords`` ((n, 2), closed or not)."""
        pts = np.asarray(coords, dtype=float)
        if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
            pts = pts[:-1]
        if len(pts) < 2:
            raise ValueError("a ring needs at least two distinct vertices")
        data = np.column_stack([pts, np.roll(pts, -1, axis=0), np.zeros(len(pts))])
        return cls._from_arrays(np.zeros(len(pts), dtype=bool), data)

    @classmethod
    def from_disks(cls, centers, sides, r: float, reference_sweeps=None) -> Loop:
        """The loop that wraps the disks of radius ``r`` in order, joined by their common tangents.

        Parameters
        ----------
        centers : (n, 2) float
            Disk centres in the order the loop visits them.
        sides : (n,) int
            `Side` of each disk (+1 the loop turns left around it, -1 right).
        r : float
            Radius of every disk.
        reference_sweeps : (n,) float, optional
            Approximate signed sweep of each arc; the exact sweep is taken within π of it. Without it each
            arc turns the way its side says by less than a full turn.

        Returns
        -------
        Loop
            Arcs of radius exactly ``r`` joined G1 by tangent segments (zero-length ones are left out).

        Raises
        ------
        ValueError
            If two consecutive disks of opposite sides overlap (no crossing tangent) or coincide.

        Examples
        --------
        >>> loop = Loop.from_disks([(0, 0), (4, 0)], [1, 1], 1.0)   # a stadium
        >>> round(loop.length, 12) == round(8 + 2 * math.pi, 12)
        True
        """
        c = np.asarray(centers, dtype=float).reshape(-1, 2)
        s = np.asarray(sides, dtype=float).reshape(-1)
        n = len(c)
        if n == 0:
            raise ValueError("a loop needs at least one disk")
        if n == 1:
            return cls.circle(c[0], r, ccw=s[0] > 0)
        phi, length, ok = tangent_directions(c, s, r)
        if not ok.all():
            i = int(np.flatnonzero(~ok)[0])
            raise ValueError(f"disks {i} and {(i + 1) % n} have no common tangent of the required kind")
        sweeps = arc_sweeps(phi, s, reference_sweeps)
        return cls._from_disk_arrays(c, s, r, phi, length, sweeps)

    @classmethod
    def _from_disk_arrays(cls, c, s, r, phi, length, sweeps, affine=None) -> Loop:
        """Loop from disks with their tangent directions, tangent lengths and arc sweeps (all exact).

        With ``affine = (scale, dx, dy)`` the loop comes out under ``p -> scale·p + (dx, dy)`` at once: the
        same numbers as ``_from_disk_arrays(c, s, r, phi, length, sweeps).affine(scale, dx, dy)``.

        Tangents shorter than `SPECK_SCALE` of the loop's extent are specks (`_merge_specks`): between
        two disks of one side (a run of nearly coincident disks, as when the shrink is a point) the disks
        are merged into one arc; between disks of opposite sides the tangent is dropped.
        """
        c, s, phi, length, sweeps = _merge_specks(np.asarray(c, float), np.asarray(s, float), r,
                                                  np.asarray(phi, float), np.asarray(length, float),
                                                  np.asarray(sweeps, float))
        n = len(c)
        eps = _speck_length(c, r)
        nx, ny = -np.sin(phi), np.cos(phi)              # left normal of each tangent
        sr, sr_next = s * r, _ahead(s) * r
        cx, cy = c[:, 0], c[:, 1]
        cx_next, cy_next = _ahead(cx), _ahead(cy)
        # Arc i is row 2i: (cx, cy, r, start, sweep); the tangent leaving disk i row 2i + 1: (P, Q, 0). The
        # rows are stored a column at a time (Fortran order): every measure reads the array by columns.
        buf = np.empty((5, n, 2))
        arcs, segs = buf[:, :, 0], buf[:, :, 1]
        arcs[0], arcs[1], arcs[2] = cx, cy, r
        np.subtract(_behind(phi), s * (math.pi / 2), out=arcs[3])
        arcs[4] = sweeps
        for k, (x, sx) in enumerate(((cx, nx), (cy, ny), (cx_next, nx), (cy_next, ny))):
            np.multiply(sr if k < 2 else sr_next, sx, out=segs[k])
            np.subtract(x, segs[k], out=segs[k])
        segs[4] = 0.0
        if affine is not None:
            scale, dx, dy = affine
            for rows, cols in ((arcs, (0, 1)), (segs, (0, 1, 2, 3))):
                for k in cols:
                    rows[k] *= scale
                    rows[k] += dy if k % 2 else dx
            arcs[2] *= scale
        data = buf.reshape(5, 2 * n).T
        arc = np.zeros(2 * n, dtype=bool)
        arc[0::2] = True
        keep = np.empty(2 * n, dtype=bool)
        keep[0::2], keep[1::2] = arcs[4] != 0.0, length > eps
        if keep.all():
            return cls._from_arrays(arc, data)
        if not keep.any():
            keep[0] = True
        return cls._from_arrays(arc[keep], data[keep])

    # -- pieces -------------------------------------------------------------------------------------
    @property
    def pieces(self) -> tuple[Piece, ...]:
        """The pieces as `Segment` and `Arc` objects."""
        if self._pieces is None:
            self._pieces = tuple(Arc((row[0], row[1]), row[2], row[3], row[4]) if is_arc
                                 else Segment((row[0], row[1]), (row[2], row[3]))
                                 for is_arc, row in zip(self._arc.tolist(), self._data.tolist()))
        return self._pieces

    # -- measures -----------------------------------------------------------------------------------
    @property
    def length(self) -> float:
        """Exact length."""
        if self._length is None:
            d = self._data
            seg = np.hypot(d[:, 2] - d[:, 0], d[:, 3] - d[:, 1])
            self._length = math.fsum(np.where(self._arc, d[:, 2] * np.abs(d[:, 4]), seg).tolist())
        return self._length

    @property
    def area(self) -> float:
        """Exact signed area enclosed (positive for a counter-clockwise loop)."""
        if self._area is None:
            self._area = self._signed_area()
        return self._area

    def _signed_area(self) -> float:
        terms = self._area_terms()
        self._terms = None
        return math.fsum(terms.tolist())

    def _area_terms(self) -> np.ndarray:
        """Each piece's contribution ½∮(x dy − y dx) to the area, relative to the first piece's start."""
        if self._terms is not None:
            return self._terms
        d = self._data
        # Origin: the first piece's start (the same arithmetic as `_ends`, on that piece alone).
        first = Loop.__new__(Loop)
        first._arc, first._data = self._arc[:1], d[:1]
        o = first._ends()[0][0]
        terms = np.empty(len(d))
        arc, seg = self._rows()
        e = d[seg]
        if len(e):
            x0, y0, x1, y1 = e[:, 0] - o[0], e[:, 1] - o[1], e[:, 2] - o[0], e[:, 3] - o[1]
            terms[seg] = 0.5 * (x0 * y1 - x1 * y0)
        e = d[arc]
        if len(e):
            x0, y0 = e[:, 0] - o[0], e[:, 1] - o[1]
            r, a0, sw = e[:, 2], e[:, 3], e[:, 4]
            a1 = a0 + sw
            cos0, sin0 = self._arc_start_cs()
            terms[arc] = 0.5 * (r * r * sw + r * x0 * (np.sin(a1) - sin0)
                                - r * y0 * (np.cos(a1) - cos0))
        return terms

    def _arc_start_cs(self) -> tuple[np.ndarray, np.ndarray]:
        """Cosine and sine of every arc's start angle (the arcs' rows of `_rows`), computed once: the area
        and the samples both need them."""
        if self._start_cs is None:
            a0 = self._data[self._rows()[0], 3]
            self._start_cs = (np.cos(a0), np.sin(a0))
        return self._start_cs

    def _rows(self):
        """Find the rows of the arcs and of the segments.

        Slices when they alternate, arc first (as `_from_disk_arrays` makes them), else index arrays.
        """
        arc = self._arc
        if len(arc) % 2 == 0 and arc[0::2].all() and not arc[1::2].any():
            return slice(0, None, 2), slice(1, None, 2)
        return np.flatnonzero(arc), np.flatnonzero(~arc)

    def _orientation(self) -> int:
        """Give the sign of `area` (+1, −1 or 0), exactly.

        The compensated sum is left for `area` where rounding cannot change the sign of a plain one.
        """
        if self._area is None:
            terms = self._terms = self._area_terms()
            total = float(terms.sum())
            # Any order of summation errs by less than (n − 1)·u·Σ|terms|, u = 2⁻⁵³; doubled for safety.
            if abs(total) > 2.0 * len(terms) * 2.0 ** -53 * float(np.abs(terms).sum()):
                return 1 if total > 0 else -1
        area = self.area
        return 1 if area > 0 else (-1 if area < 0 else 0)

    @property
    def is_ccw(self) -> bool:
        """True if the loop runs counter-clockwise (positive area)."""
        return self.area > 0

    @property
    def arcs(self) -> list[Arc]:
        """The arc pieces."""
        return [p for p in self.pieces if isinstance(p, Arc)]

    @property
    def segments(self) -> list[Segment]:
        """The straight pieces."""
        return [p for p in self.pieces if isinstance(p, Segment)]

    @property
    def radii(self) -> np.ndarray:
        """Radius of every arc."""
        return self._data[self._arc, 2].copy()

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(minx, miny, maxx, maxy)``, exact (arcs count with the extreme points they pass)."""
        start, end = self._ends()
        pts = [start, end]
        d = self._data[self._arc]
        if len(d):
            lo = np.minimum(d[:, 3], d[:, 3] + d[:, 4])
            hi = np.maximum(d[:, 3], d[:, 3] + d[:, 4])
            for k in range(4):
                ang = k * math.pi / 2
                # The axis direction ang + 2πm inside [lo, hi] for some integer m.
                m = np.ceil((lo - ang) / _TWO_PI)
                hit = ang + _TWO_PI * m <= hi
                if hit.any():
                    e = d[hit]
                    pts.append(e[:, :2] + e[:, 2:3] * np.array([[math.cos(ang), math.sin(ang)]]))
        allp = np.concatenate(pts)
        return (float(allp[:, 0].min()), float(allp[:, 1].min()), float(allp[:, 0].max()), float(allp[:, 1].max()))

    def corner_angles(self) -> np.ndarray:
        """Absolute angle between the end tangent of each piece and the start tangent of the next."""
        t0, t1 = self._tangents()
        a, b = t1, _ahead(t0)
        ang = np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(axis=1)))
        return np.where(np.isfinite(ang), ang, 0.0)

    @property
    def total_turn(self) -> float:
        """Sum of the signed turning of the loop (arcs and corners): ±2π for a simple G1 loop."""
        t0, t1 = self._tangents()
        a, b = t1, _ahead(t0)
        corner = np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(axis=1))
        corner = np.where(np.isfinite(corner), corner, 0.0)
        return math.fsum((self._data[self._arc, 4]).tolist()) + math.fsum(corner.tolist())

    def is_g1(self, atol: float = 1e-9, rounding: float = 0.0) -> bool:
        """True if every join between pieces is tangent-continuous within ``atol`` radians.

        Parameters
        ----------
        atol : float
            Largest angle between the tangents at a join, radians.
        rounding : float, optional
            A length (the loop's units) by which the end points of its segments may be off by rounding
            (see `tolerances.rounding_length`); a segment of length L then has a direction known to
            ``rounding / L`` radians only, and a join may miss tangency by that much more on either side.

        Examples
        --------
        A stadium at 1e12, where an ulp is 1.2e-4: one end of a tangent rounded by an ulp turns it by
        1.2e-4 rad, a corner unless the rounding of the coordinates is allowed for.

        >>> far, ulp = 1e12, math.ulp(1e12)
        >>> L = Loop([Arc((far, 1.0), 1.0, 0.0, math.pi), Segment((far - 1.0, 1.0), (far - 1.0 + ulp, 0.0)),
        ...           Arc((far, 0.0), 1.0, math.pi, math.pi), Segment((far + 1.0, 0.0), (far + 1.0, 1.0))],
        ...          atol=1e-3)
        >>> L.is_g1(1e-7), L.is_g1(1e-7, rounding=L.rounding())
        (False, True)
        """
        angles = self.corner_angles()
        if rounding <= 0.0:
            return bool((angles <= atol).all())
        return bool((angles <= self._join_bounds(atol, rounding)).all())

    def _join_bounds(self, atol: float, rounding: float) -> np.ndarray:
        """Per join (piece i to piece i + 1): ``atol`` plus ``rounding / L`` for each segment of length L
        beside it (an arc's tangents come from its angles, not from rounded points)."""
        d = self._data
        length = np.hypot(d[:, 2] - d[:, 0], d[:, 3] - d[:, 1])
        with np.errstate(divide="ignore"):
            slack = np.where(self._arc, 0.0, rounding / length)
        return atol + slack + _ahead(slack)

    def rounding(self) -> float:
        """The length below which this loop's own numbers are rounding (`tolerances.rounding_length` of its
        size and its largest coordinate)."""
        x0, y0, x1, y1 = self.bounds
        return rounding_length(max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1)))

    @property
    def min_radius_of_curvature(self) -> float:
        """Exact minimum radius of curvature: the smallest arc radius, 0 if a join has a corner, else inf.

        A join is a corner if its tangents differ by more than `tolerances.CORNER_ANGLE` beyond what the
        rounding of the loop's coordinates explains (`is_g1` with ``rounding``).
        """
        if not self.is_g1(CORNER_ANGLE, self.rounding()):
            return 0.0
        radii = self.radii
        return float(radii.min()) if len(radii) else math.inf

    # -- transformations ----------------------------------------------------------------------------
    def reversed(self) -> Loop:
        """The same loop run the other way."""
        d = self._data[::-1].copy()
        arc = self._arc[::-1].copy()
        seg = ~arc
        d[seg] = d[seg][:, [2, 3, 0, 1, 4]]
        d[arc, 3] = d[arc, 3] + d[arc, 4]
        d[arc, 4] = -d[arc, 4]
        return Loop._from_arrays(arc, d)

    def affine(self, scale: float, dx: float, dy: float) -> Loop:
        """The loop under ``p -> scale·p + (dx, dy)`` with ``scale > 0``."""
        d = self._data.copy()
        d[:, :2] = d[:, :2] * scale + (dx, dy)
        seg = ~self._arc
        d[seg, 2:4] = d[seg, 2:4] * scale + (dx, dy)
        d[self._arc, 2] *= scale
        return Loop._from_arrays(self._arc.copy(), d)

    # -- output -------------------------------------------------------------------------------------
    def sample(self, tolerance: float) -> np.ndarray:
        """Closed polygon coordinates ``(n + 1, 2)``: arcs by chords within ``tolerance``, first point repeated.

        Every point lies on the exact curve (the chords of an arc lie on its centre's side).
        """
        d, arc = self._data, self._arc
        ia = self._rows()[0]
        e = d[ia]
        r = e[:, 2]
        step = np.where(tolerance >= r, math.pi / 2, 2.0 * np.arccos(np.clip(1.0 - tolerance / r, -1.0, 1.0)))
        count = np.maximum(1, np.ceil(np.abs(e[:, 4]) / step - 1e-9)).astype(np.int64)
        if (count == 1).all():
            # One point a piece, its start (arcs at their start angle).
            out = np.empty((len(d) + 1, 2))
            out[:-1] = d[:, :2]
            cos0, sin0 = self._arc_start_cs()
            pts = out[:-1][ia]
            np.multiply(r, cos0, out=pts[:, 0])
            pts[:, 0] += e[:, 0]
            np.multiply(r, sin0, out=pts[:, 1])
            pts[:, 1] += e[:, 1]
            out[:-1][ia] = pts
            out[-1] = out[0]
            return out
        ia = np.flatnonzero(arc)
        counts = np.ones(len(d), np.int64)
        counts[ia] = count
        owner = np.repeat(np.arange(len(d)), counts)
        first = np.repeat(np.cumsum(counts) - counts, counts)
        frac = (np.arange(len(owner)) - first) / counts[owner]
        row = d[owner]
        th = row[:, 3] + row[:, 4] * frac
        pts = np.where(arc[owner][:, None],
                       row[:, :2] + row[:, 2:3] * np.column_stack([np.cos(th), np.sin(th)]), row[:, :2])
        return np.concatenate([pts, pts[:1]])

    def to_ring(self, tolerance: float) -> LinearRing:
        """Shapely ring sampled within ``tolerance``."""
        return LinearRing(self.sample(tolerance))

    def to_polygon(self, tolerance: float) -> Polygon:
        """Shapely polygon bounded by this loop (orientation dropped)."""
        return shapely.orient_polygons(Polygon(self.sample(tolerance)))

    def svg_path(self, precision: int = 12) -> str:
        """SVG path data with real ``A`` commands, in the loop's own coordinates, closed with ``Z``."""
        start, _ = self._ends()
        cmds = [f"M {_fmt(start[0, 0], precision)} {_fmt(start[0, 1], precision)}"]
        cmds += [p.svg(precision) for p in self.pieces]
        return " ".join(cmds) + " Z"

    def __len__(self) -> int:
        return len(self._arc)

    def __iter__(self):
        return iter(self.pieces)

    def __repr__(self) -> str:
        return (f"<Loop {len(self)} pieces ({int(self._arc.sum())} arcs), length {self.length:.6g}, "
                f"area {self.area:.6g}>")


# -- disks and their tangents ---------------------------------------------------------------------------
def tangent_directions(centers, sides, r: float, precision: float = 0.0):
    """Directions of the tangents joining each disk to the next, for a loop that visits them in order.

    Parameters
    ----------
    centers : (n, 2) float
        Disk centres.
    sides : (n,) float or int
        `Side` of each disk: +1 the loop keeps it on its left, -1 on its right.
    r : float or (n,) float
        Radius of every disk, or of each (two radii: core disks a, anticore disks b; 0 is a point, where
        the loop turns with a corner).
    precision : float, optional
        How far (same units) each centre may be from where exact arithmetic puts it, e.g. the rounding of
        the coordinates it was solved from. Two disks on opposite sides that overlap by no more than twice
        that are a tie: they touch, and the tangent between them has length 0.

    Returns
    -------
    phi : (n,) float
        Direction (radians) of the tangent from disk ``i`` to disk ``i + 1`` (cyclic).
    length : (n,) float
        Its length ``sqrt(d² − k²)`` with ``k = (s[i+1] − s[i])·r``, or with per-disk radii
        ``k = s[i+1]·r[i+1] − s[i]·r[i]`` (the signed radii's difference).
    ok : (n,) bool
        False where the tangent does not exist (``d < |k|`` beyond rounding and ``precision``, or
        coincident centres).

    Notes
    -----
    The tangent leaves disk ``i`` at ``c[i] − s[i]·r·n(phi)`` and reaches disk ``i+1`` at
    ``c[i+1] − s[i+1]·r·n(phi)``, where ``n(phi) = (−sin phi, cos phi)`` is the left normal (``r[i]``
    and ``r[i+1]`` with per-disk radii).

    Examples
    --------
    A core disk and an anticore disk of radius 1 whose centres are 2 − 1e-10 apart overlap; they touch
    (a tie) when their centres are known only to 1e-10:

    >>> c = [(0.0, 0.0), (2.0 - 1e-10, 0.0)]
    >>> bool(tangent_directions(c, [1, -1], 1.0)[2][0])
    False
    >>> phi, length, ok = tangent_directions(c, [1, -1], 1.0, precision=1e-10)
    >>> bool(ok[0]), float(length[0])
    (True, 0.0)

    Per-disk radii: from a point (radius 0) to an anticore disk of radius 3 whose centre is 5 away, the
    tangent is 4 long.

    >>> phi, length, ok = tangent_directions([(0.0, 0.0), (5.0, 0.0)], [1, -1], [0.0, 3.0])
    >>> float(length[0]), bool(ok.all())
    (4.0, True)
    """
    c = np.asarray(centers, dtype=float)
    s = np.asarray(sides, dtype=float)
    D = np.roll(c, -1, axis=0) - c
    d = np.hypot(D[:, 0], D[:, 1])
    if np.ndim(r) == 0:
        k = (np.roll(s, -1) - s) * r
        r2 = r * r
    else:
        rho = s * np.asarray(r, dtype=float)               # signed radii
        k = np.roll(rho, -1) - rho
        r2 = np.maximum(np.abs(rho), np.abs(np.roll(rho, -1))) ** 2
    gap = d * d - k * k
    # d is known to 2·precision, so d² − k² to about 4·d·precision (plus the rounding of the squares).
    slack = np.maximum(1e-12 * (d * d + r2), 4.0 * d * precision)
    ok = (gap >= -slack) & (d > 0)
    length = np.sqrt(np.maximum(gap, 0.0))
    phi = np.arctan2(D[:, 1], D[:, 0]) - np.arctan2(k, length)
    return phi, length, ok


def arc_sweeps(phi, sides, reference=None) -> np.ndarray:
    """Signed sweep of the arc at each disk, between the incoming tangent ``phi[i-1]`` and ``phi[i]``.

    Without ``reference`` a `Side.CORE` disk turns left by ``(phi_out − phi_in) mod 2π`` and an
    `Side.ANTICORE` disk right by ``(phi_in − phi_out) mod 2π``. With ``reference`` the representative
    within π of it is taken, so a disk the loop should not touch shows up with the wrong sign.
    """
    phi = np.asarray(phi, dtype=float)
    s = np.asarray(sides, dtype=float)
    delta = phi - np.roll(phi, 1)
    if reference is None:
        left = np.mod(delta, _TWO_PI)
        right = -np.mod(-delta, _TWO_PI)
        return np.where(s > 0, left, right)
    ref = np.asarray(reference, dtype=float)
    return delta + _TWO_PI * np.round((ref - delta) / _TWO_PI)


def disk_tangent(c1, side1: int, c2, side2: int, r: float) -> Segment | None:
    """The tangent that leaves disk ``(c1, side1)`` for disk ``(c2, side2)``, both of radius ``r``.

    The loop keeps a `Side.CORE` disk on its left and an `Side.ANTICORE` disk on its right; equal sides
    give an outer tangent, opposite sides a crossing one.

    Returns
    -------
    Segment or None
        ``None`` when the tangent does not exist (opposite sides with ``|c2 − c1| < 2r``).

    Examples
    --------
    >>> disk_tangent((0, 0), 1, (5, 0), 1, 1.0)
    Segment(start=(0.0, -1.0), end=(5.0, -1.0))
    """
    c = np.array([c1, c2], dtype=float)
    phi, length, ok = tangent_directions(c, [side1, side2], r)
    if not ok[0]:
        return None
    n = np.array([-math.sin(phi[0]), math.cos(phi[0])])
    return Segment(c[0] - side1 * r * n, c[1] - side2 * r * n)


def common_tangents(c1, r1: float, c2, r2: float, kind: str = "outer") -> list[Segment]:
    """The common tangent segments of two circles, between their points of contact.

    Parameters
    ----------
    c1, c2 : (2,) float
        Centres.
    r1, r2 : float
        Radii (> 0).
    kind : {"outer", "crossing"}
        Outer tangents keep both circles on the same side; crossing tangents pass between them.

    Returns
    -------
    list of Segment
        Two segments from circle 1 to circle 2 (one if they coincide in the limit case, none if they do
        not exist: a circle inside the other for outer tangents, overlapping circles for crossing ones).

    Examples
    --------
    >>> [s.length for s in common_tangents((0, 0), 1.0, (0, 4), 1.0, "crossing")]
    [3.4641016151377544, 3.4641016151377544]
    """
    if kind not in ("outer", "crossing"):
        raise ValueError(f"kind must be 'outer' or 'crossing', got {kind!r}")
    c1 = np.asarray(c1, dtype=float)
    c2 = np.asarray(c2, dtype=float)
    sign = 1.0 if kind == "outer" else -1.0
    out: list[Segment] = []
    for s1 in (1.0, -1.0):
        rho1, rho2 = s1 * r1, sign * s1 * r2          # signed radii: centre = contact + rho·n
        D = c2 - c1
        d = math.hypot(*D)
        k = rho2 - rho1
        if d == 0 or d * d < k * k * (1 - 1e-12):
            continue
        length = math.sqrt(max(d * d - k * k, 0.0))
        phi = math.atan2(D[1], D[0]) - math.atan2(k, length)
        n = np.array([-math.sin(phi), math.cos(phi)])
        seg = Segment(c1 - rho1 * n, c2 - rho2 * n)
        if not any(np.allclose(seg.start, o.start) and np.allclose(seg.end, o.end) for o in out):
            out.append(seg)
    return out
