"""Outlines of cut files: exact pieces chained into closed loops, nested even-odd into a shape.

Shared by the DXF reader and the SVG reader's cut-file reading. An outline (`Chain`) is a sequence of
*runs*, each an exact `Arc` or a polyline ``(n, 2)`` of straight pieces, running from ``start`` to ``end``.
Loose outlines (a slot drawn as two LINEs and two ARCs) are joined end to end into closed ones within a
gap tolerance (ezdxf's ``edgeminer``); the closed outlines are then nested by the even-odd rule (inside an
odd number of outlines is material); and where the boundary of that region is made of whole outlines, the
outlines themselves, oriented, are its exact boundary.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from vectortighten.curves import Arc, Loop, Segment
from vectortighten.errors import InvalidGeometryError

from ._common import _require
from ._fill import fill_rings

__all__ = ["DEFAULT_GAP", "Chain"]

#: Default gap tolerance, as a fraction of the drawing's diagonal: two ends of outlines nearer than this
#: are the same point (endpoints written by CAD programs agree to 1e-9 of the drawing or better; 1e-6 of a
#: 200 mm part is 0.2 µm).
DEFAULT_GAP = 1e-6


def _fmt_point(p) -> str:
    return f"({p[0]:.6g}, {p[1]:.6g})"


class Chain:
    """An outline: runs (exact `Arc`s and polylines) from ``start`` to ``end``, labelled for messages.

    Parameters
    ----------
    runs : list of Arc or (n, 2) float
        In order; each starts where the previous one ends (to within the gap tolerance).
    label : str
        What the outline is in the file, for error messages (``"LINE #1F on layer 'CUT'"``).
    owner : int
        The element it was read from (SVG: for styles), -1 if none.
    """

    __slots__ = ("label", "owner", "runs")

    def __init__(self, runs, label: str, owner: int = -1):
        self.runs = [r if isinstance(r, Arc) else np.asarray(r, dtype=float).reshape(-1, 2) for r in runs]
        self.label = label
        self.owner = owner

    @property
    def start(self) -> np.ndarray:
        r = self.runs[0]
        return np.array(r.start) if isinstance(r, Arc) else r[0]

    @property
    def end(self) -> np.ndarray:
        r = self.runs[-1]
        return np.array(r.end) if isinstance(r, Arc) else r[-1]

    def reversed(self) -> Chain:
        return Chain([r.reversed() if isinstance(r, Arc) else r[::-1] for r in self.runs[::-1]],
                     self.label, self.owner)

    @property
    def length(self) -> float:
        return math.fsum(r.length if isinstance(r, Arc) else float(np.hypot(*np.diff(r, axis=0).T).sum())
                         for r in self.runs)

    def midpoint(self) -> np.ndarray:
        """The point halfway along the outline."""
        half, acc = 0.5 * self.length, 0.0
        for r in self.runs:
            if isinstance(r, Arc):
                if acc + r.length >= half:
                    return np.array(r.point_at((half - acc) / r.length if r.length else 0.0))
                acc += r.length
            else:
                seg = np.hypot(*np.diff(r, axis=0).T)
                cum = acc + np.concatenate([[0.0], np.cumsum(seg)])
                if cum[-1] >= half:
                    k = min(int(np.searchsorted(cum, half)) - 1, len(seg) - 1)
                    k = max(k, 0)
                    t = (half - cum[k]) / seg[k] if seg[k] else 0.0
                    return r[k] + t * (r[k + 1] - r[k])
                acc = cum[-1]
        return self.end

    def box(self) -> tuple[float, float, float, float]:
        """A box around the outline, cheap and at most a little loose.

        An arc of at most half a turn counts with its chord's box widened by its sagitta, a larger one with
        its whole circle.
        """
        x0 = y0 = math.inf
        x1 = y1 = -math.inf
        for r in self.runs:
            if isinstance(r, Arc):
                if abs(r.sweep) <= math.pi:
                    (sx, sy), (ex, ey) = r.start, r.end
                    h = r.radius * (1.0 - math.cos(0.5 * r.sweep))
                    bx0, by0, bx1, by1 = min(sx, ex) - h, min(sy, ey) - h, max(sx, ex) + h, max(sy, ey) + h
                else:
                    (cx, cy), rad = r.center, r.radius
                    bx0, by0, bx1, by1 = cx - rad, cy - rad, cx + rad, cy + rad
            else:
                (bx0, by0), (bx1, by1) = r.min(axis=0), r.max(axis=0)
            x0, y0, x1, y1 = min(x0, bx0), min(y0, by0), max(x1, bx1), max(y1, by1)
        return float(x0), float(y0), float(x1), float(y1)

    def close(self, scale: float) -> Chain:
        """Make a closed outline of one whose ends meet within the gap: snap them (see `_snap`)."""
        self.runs = _snap(self.runs, scale, closed=True)
        return self

    def ring(self, tol: float) -> np.ndarray:
        """Points of the closed outline ``(n, 2)``, first not repeated; arcs by chords within ``tol``.

        Every point lies on the outline (the chords of an arc lie on its centre's side).
        """
        parts = [r.sample(tol) if isinstance(r, Arc) else r[:-1] for r in self.runs]
        return np.concatenate(parts) if parts else np.empty((0, 2))

    def loop(self) -> Loop:
        """The closed outline as an exact `Loop` (polylines as `Segment`s, zero-length ones left out)."""
        pieces = []
        for r in self.runs:
            if isinstance(r, Arc):
                pieces.append(r)
                continue
            keep = np.ones(len(r), dtype=bool)
            keep[1:] = np.any(r[1:] != r[:-1], axis=1)
            pts = r[keep]
            pieces += [Segment(pts[k], pts[k + 1]) for k in range(len(pts) - 1)]
        return Loop(pieces)


def _snap(runs: list, scale: float, closed: bool) -> list:
    """Make consecutive runs meet exactly.

    A polyline's end moves onto an arc's (arcs stay exact); two polylines meet halfway; two arcs apart by
    more than 1e-12 of ``scale`` get a straight bridge. Adjacent polylines are merged.
    """
    out: list = []
    for r in runs:
        r = r if isinstance(r, Arc) else np.array(r, dtype=float)
        if out and not isinstance(out[-1], Arc) and not isinstance(r, Arc):
            mid = 0.5 * (out[-1][-1] + r[0])
            out[-1] = np.vstack([out[-1][:-1], mid, r[1:]])
            continue
        out.append(r)
    if closed and len(out) > 1 and not isinstance(out[0], Arc) and not isinstance(out[-1], Arc):
        mid = 0.5 * (out[-1][-1] + out[0][0])
        out[0] = np.vstack([out[-1][:-1], mid, out[0][1:]])
        out.pop()
    n = len(out)
    joins = range(n if closed else n - 1)
    bridges = {}
    for i in joins:
        a, b = out[i], out[(i + 1) % n]
        if isinstance(a, Arc) and isinstance(b, Arc):
            p, q = np.array(a.end), np.array(b.start)
            if np.hypot(*(q - p)) > 1e-12 * scale:
                bridges[i] = np.array([p, q])
        elif isinstance(a, Arc):
            b[0] = a.end
        elif isinstance(b, Arc):
            a[-1] = b.start
        else:                                      # one closed polyline: its own ends meet halfway
            a[0] = a[-1] = 0.5 * (a[0] + a[-1])
    if not bridges:
        return out
    snapped = []
    for i, r in enumerate(out):
        snapped.append(r)
        if i in bridges:
            snapped.append(bridges[i])
    return snapped


def drop_duplicates(chains: list[Chain], gap: float, closed: bool) -> tuple[list[Chain], list[Chain]]:
    """Outlines drawn twice (within ``gap``) are kept once; returns ``(kept, dropped)``.

    Two open outlines are the same when their ends and midpoints agree within ``gap`` (either way round);
    two closed ones when their boxes (`Chain.box`) agree within ``gap`` and they are within ``gap`` of each
    other
    (Hausdorff distance of their chords).
    """
    if len(chains) < 2:
        return chains, []
    from scipy.spatial import cKDTree

    if closed:
        keys = np.array([c.box() for c in chains])
    else:
        ends = np.array([np.concatenate(sorted([tuple(c.start), tuple(c.end)])) for c in chains])
        keys = np.column_stack([ends, np.array([c.midpoint() for c in chains])])
    pairs = cKDTree(keys).query_pairs(r=gap, p=np.inf, output_type="ndarray")
    if not len(pairs):
        return chains, []
    drop = set()
    for i, j in sorted(map(tuple, pairs)):
        if i in drop or j in drop:
            continue
        if closed:
            tol = max(gap, 1e-12)
            a = shapely.LinearRing(_closed(chains[i].ring(tol)))
            b = shapely.LinearRing(_closed(chains[j].ring(tol)))
            if a.hausdorff_distance(b) > 2 * gap + tol:
                continue
        drop.add(j)
    return ([c for k, c in enumerate(chains) if k not in drop],
            [c for k, c in enumerate(chains) if k in drop])


def _closed(ring: np.ndarray) -> np.ndarray:
    return np.vstack([ring, ring[:1]]) if len(ring) else ring


def join(chains: list[Chain], gap: float, scale: float, name: str) -> list[Chain]:
    """Join open outlines end to end into closed ones; every end must meet exactly one other within ``gap``.

    Parameters
    ----------
    chains : list of Chain
        Open outlines (a closed one is passed through).
    gap : float
        Largest distance between two ends that join, in drawing units.
    scale : float
        The drawing's size (for the rounding allowance of `_snap`).
    name : str
        The file, named in errors.

    Raises
    ------
    InvalidGeometryError
        An end meets no other (a gap: its position, the nearest other end and how far it is), or three
        or more ends meet at one point (the outlines branch or overlap).
    """
    if not chains:
        return []
    closed, open_ = [], []
    for c in chains:
        (closed if np.hypot(*(c.end - c.start)) <= gap else open_).append(c)
    out = [c.close(scale) for c in closed]
    if not open_:
        return out
    from scipy.spatial import cKDTree

    ends = np.array([p for c in open_ for p in (c.start, c.end)], dtype=float)
    tree = cKDTree(ends)
    near = tree.query_ball_point(ends, r=gap)
    for k, hits in enumerate(near):
        others = [h for h in hits if h != k]
        if not others:
            d, j = tree.query(ends[k], k=2)
            c = open_[k // 2]
            if len(ends) > 1 and math.isfinite(d[1]):
                o = open_[int(j[1]) // 2]
                where = (f"the nearest end, of {o.label}, is {d[1]:.3g} away at {_fmt_point(ends[int(j[1])])}"
                         if o is not c else f"its other end is {d[1]:.3g} away")
            else:
                where = "no other outline has an end"
            raise InvalidGeometryError(
                f"{name}: open outline: {c.label} ends at {_fmt_point(ends[k])} and nothing joins it within "
                f"the gap tolerance {gap:.3g} ({where}); close it in the drawing or allow a wider gap (--gap "
                "on the command line, gap= in Python)")
        if len(others) > 1:
            labels = sorted({open_[h // 2].label for h in hits})
            raise InvalidGeometryError(
                f"{name}: outlines branch at {_fmt_point(ends[k])}: {len(hits)} ends meet there "
                f"({', '.join(labels[:4])}{', …' if len(labels) > 4 else ''}); a cut outline must not branch "
                "or be drawn twice")
    em = _require("ezdxf.edgeminer", "dxf", "joining loose outlines")
    from ezdxf.math import Vec2

    edges = [em.make_edge(Vec2(*c.start), Vec2(*c.end), max(c.length, 1e-300), payload=i)
             for i, c in enumerate(open_)]
    deposit = em.Deposit(edges, gap_tol=gap)
    found_all = []
    for found in em.find_all_simple_chains(deposit):
        if not em.is_loop(found, gap_tol=gap):     # cannot happen when every end meets one other
            raise InvalidGeometryError(f"{name}: open outline: {open_[found[0].payload].label} is part of a "
                                       "chain that does not close")
        # The same loop whatever order the search met it in: from its first outline, run as drawn.
        found = list(found)
        k = min(range(len(found)), key=lambda i: found[i].payload)
        found = found[k:] + found[:k]
        if found[0].is_reverse:
            found = [e.reversed() for e in reversed(found)]
            found = found[-1:] + found[:-1]
        found_all.append(found)
    for found in sorted(found_all, key=lambda f: f[0].payload):
        runs: list = []
        for e in found:
            c = open_[e.payload]
            runs += (c.reversed() if e.is_reverse else c).runs
        first = open_[found[0].payload]
        label = first.label if len(found) == 1 else f"the outline through {first.label}"
        out.append(Chain(_snap(runs, scale, closed=True), label, first.owner))
    return out


def assemble(closed: list[Chain], tol: float) -> tuple[Polygon | MultiPolygon, Callable]:
    """The even-odd region of closed outlines, and a function giving its exact boundary (or None).

    Parameters
    ----------
    closed : list of Chain
        Closed outlines.
    tol : float
        Chord tolerance of arcs in the region, in drawing units.

    Returns
    -------
    shape : Polygon or MultiPolygon
        Points inside an odd number of outlines (possibly empty).
    loops : callable
        ``loops()`` gives the exact `Loop`s of the region's boundary when every ring of it is one whole
        outline, else None.
    """
    rings = [c.ring(tol) for c in closed]
    shape = fill_rings(rings, "evenodd")
    return shape, lambda: exact_boundary(shape, rings, closed)


def exact_boundary(shape, rings: list[np.ndarray], chains: list[Chain]) -> list[Loop] | None:
    """The outlines whose chords are exactly the rings of ``shape``, oriented; None if some ring is not one.

    A ring of ``shape`` is an outline's when it has the same vertices as that outline's chords (in any
    order and direction): the fill rules keep the coordinates of rings that neither cross nor touch.
    Outer boundaries come out counter-clockwise and holes clockwise, as `vectortighten.tighten` writes them.
    """
    if shape.is_empty or not rings:
        return [] if shape.is_empty else None
    ids = np.repeat(np.arange(len(rings)), [len(r) for r in rings])
    pts = np.concatenate(rings)
    key = pts[:, 0] + 1j * pts[:, 1]
    order = np.argsort(key, kind="stable")
    ks, kid = key[order], ids[order]
    same = ks[1:] == ks[:-1]
    if (same & (kid[1:] != kid[:-1])).any():
        return None                                # two outlines share a vertex: they touch
    first = np.concatenate([[True], ~same])
    unique_count = np.bincount(kid[first], minlength=len(rings))
    used = set()
    out = []
    for poly in shapely.get_parts(shape):
        for k, ring in enumerate((poly.exterior, *poly.interiors)):
            xy = np.asarray(ring.coords)[:-1]
            q = xy[:, 0] + 1j * xy[:, 1]
            idx = np.minimum(np.searchsorted(ks, q), len(ks) - 1)
            if not (ks[idx] == q).all():
                return None
            owner = kid[idx]
            c = int(owner[0])
            if (owner != c).any() or c in used or len(np.unique(q)) != unique_count[c]:
                return None
            used.add(c)
            loop = chains[c].loop()
            if (loop.area > 0) != (k == 0):
                loop = loop.reversed()
            out.append(loop)
    return out
