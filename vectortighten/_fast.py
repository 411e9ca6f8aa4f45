"""The fast path of the engine: shapes whose corners are all isolated.

When every vertex of S has room for its own disk of radius r — inside S at a convex vertex, outside at a
reflex one, tangent to both edges at points that fit on them — and those arcs meet neither the core nor
the anticore elsewhere, the tight loop of each ring of S is that ring with every corner replaced by the
arc of its disk. This is checked, vectorised, in a few passes over the vertices; no triangulation is built.
When any check fails the caller falls back to the general engine.

Steps in a wall — an edge between a convex and a reflex corner too short for both tangents, the commonest
shape of building footprints and CAD outlines — are taken too (`_bridge_steps`): the loop crosses such a
step on the inner tangent of its two corner disks, each disk where it touches both its edges, or, when its
own tangent is longer than the step, slid along the other edge until it meets the step's far end. The
same exact tests then run on the moved disks and the trimmed offset curves, and each bridge is measured
exactly against both offset curves (`_bridges_clear`). Steps may follow one another (a jog, a staircase
of a few treads): a disk may slide along a step, a corner between two steps too short for its tangent
rests on both far ends, and a corner whose disk lies beyond its neighbours' common tangent is passed by.

Short edges between two corners of the same side are taken too (`_same_side_runs`): a run of such corners
(a bevel, a round corner digitised by a few chords, a chamfered inner corner) becomes the one disk tangent
to the edges on either side of it; a slot or a tab narrower than 2r, whose run turns through π, is spanned
by the disk through its mouth's two corners (or, where the mouth is 2r or wider, by the disk tangent to
one wall through the other mouth corner), bridged like a step from their disks (which may slide along
their walls); a tab and a notch that share a wall are spanned as a chain. A lone notch or tab may also be
spanned by the disk tangent to two of its walls, or resting on the wall beyond one mouth corner (which it
passes by), and its mouth may lie past slight bends of its walls. Beside a step, a run (with no mouth to
span) becomes one disk that the step's bridge reaches, sliding along the run's other edge where the step
is shorter than its tangent; a notch or tab is spanned as usual, its mouth corner's disk sliding along
the wall into it as the step's own slide would. Whatever a moved disk or a span cuts from the offset
curves is proven nearer than r to S's boundary (`_covered`), so none of it was on the shrink's (grow's)
boundary.

Why the checks suffice: the straight pieces lie on the boundary of S, which never meets the (open) core or
anticore; a valid disk at a convex vertex lies in S, so its arc cannot enter the anticore, and an arc that
does not enter the core lies on its boundary (and symmetrically at reflex vertices). The region between
a ring and its tightened loop is a union of corner cusps, none of which can hold a disk of radius r, so
the loop is homotopic to the ring in the mortar. For ``init="core"`` (and ``"mason"``) it must be
homotopic to the core's boundary too, which has one ring for each ring of S only when the shrink does:
a neck narrower than 2r parts the core. The certificates show it; without them, every point of the
offset curves must be r from S (`_reaches_edges`).

How it is checked: from the edges of S alone, never from GEOS's buffers (which simplify dense input by up
to r/100, more than any slack could allow). Disk centres and straight pieces must keep distance r from
every edge; points along each arc must keep distance r from the shrink's boundary (convex vertices) or the
grow's (reflex ones), which the offset edges and the arcs around the other kind of vertex contain. First
by certificates (`_offset_certified`, `_rounded_certified`): when the offset curves, and the rings with their
corners rounded, do not touch themselves, all of that holds, and checking it costs a search among
neighbouring pieces only. Where a certificate fails, by the exact distance tests: `_closer_than` (a k-d
tree over the vertices, exact distances for the few candidates; on a small shape, exact distances for every
pair of pieces whose boxes come near) and `_arcs_clear`, whose arcs are sampled every π/16 (a violation between two samples and shallower than the sampling's sagitta can go unseen).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .offsets import precision_of
from .tolerances import ANGLE_ZERO

__all__: list[str] = []

_TWO_PI = 2.0 * math.pi
_EXACT = 1e-9         # the exact distance tests' slack, relative to r, at most (see `_Rings.tie`)


def _clean_ring(c: np.ndarray):
    """Clean a ring: its vertices, and the vectors and lengths of the edges that leave them.

    The closing point, repeated points and straight (collinear) vertices are left out; the edges are None
    if fewer than three vertices are left.
    """
    pts = c[:-1]
    if len(pts) < 3:
        return pts, None, None
    v = np.empty_like(pts)                          # edge i, from vertex i to the next
    np.subtract(pts[1:], pts[:-1], out=v[:-1])
    np.subtract(pts[0], pts[-1], out=v[-1])
    # A point equals the next one exactly when the edge between them is zero (the coordinates are finite,
    # and a difference of two doubles is 0 only if they are equal).
    keep = (v[:, 0] != 0) | (v[:, 1] != 0)
    if not keep.all():
        pts = pts[keep]
        v = None
    for _ in range(3):
        if len(pts) < 3:
            return pts, None, None
        if v is None:
            v = np.concatenate([pts[1:], pts[:1]]) - pts
        u = np.concatenate([v[-1:], v[:-1]])        # the edge arriving at vertex i
        cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        dot = u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1]
        ell = np.hypot(v[:, 0], v[:, 1])
        sine = cross / (np.concatenate([ell[-1:], ell[:-1]]) * ell)
        straight = (np.abs(sine) < ANGLE_ZERO) & (dot > 0)
        if not straight.any():
            return pts, v, ell
        pts, v = pts[~straight], None
    if len(pts) < 3:
        return pts, None, None
    v = np.concatenate([pts[1:], pts[:1]]) - pts
    return pts, v, np.hypot(v[:, 0], v[:, 1])


class _Rings:
    """Per-vertex data of all rings of S, concatenated (vertex i, edge i from vertex i to next[i])."""

    def __init__(self, S, r: float, precision: float | None = None, radii: tuple[float, float] | None = None):
        rings = [_clean_ring(shapely.get_coordinates(ring))
                 for ring in shapely.get_rings(shapely.get_parts(S))]
        self.ok = all(len(v) >= 3 for v, _, _ in rings)
        if not self.ok:
            return
        self.r = r
        # Two radii (``radii = (a, b)``, r their larger): disks at convex vertices (side +1) have radius a,
        # at reflex ones (−1) radius b, and the shrink is by a, the grow by b (`radius`). One radius: all r.
        self.pair = radii is not None
        self.ra, self.rb = radii if self.pair else (r, r)
        # The distance tests call a clearance of at least r − tie "r" (a tie, as a part exactly 2r wide):
        # the closed rule of `offsets.exact_offsets`, whose slack is `precision_of(S)`, and never more than
        # _EXACT·r. A neck narrower than 2r by more than that is cut here as it is there; one narrower by
        # less than _EXACT·r but more than the precision used to pass as a tie (and come back joined).
        r_tie = min(x for x in (self.ra, self.rb) if x > 0) if self.pair else r
        self.tie = min(_EXACT * r_tie, max(precision_of(S), precision or 0.0))
        sizes = np.array([len(v) for v, _, _ in rings])
        start = np.cumsum(sizes) - sizes
        self.slices = [slice(a, a + n) for a, n in zip(start.tolist(), sizes.tolist(), strict=True)]
        self._first, self._last = start, start + sizes - 1
        nv = int(sizes.sum())
        if len(rings) == 1:
            self.v, u, self.ell = rings[0]
        else:
            self.v, u, self.ell = (np.concatenate(part) for part in zip(*rings, strict=True))
        self.next = np.arange(1, nv + 1)
        self.next[self._last] = self._first
        self.prev = np.arange(-1, nv - 1)
        self.prev[self._first] = self._last
        self.u = u / self.ell[:, None]                                  # direction of edge i
        ux, uy = self.u[:, 0], self.u[:, 1]
        self.n = np.column_stack([-uy, ux])                             # its left normal (into S)
        u_in = self._pred(self.u)
        cross = u_in[:, 0] * uy - u_in[:, 1] * ux
        dot = u_in[:, 0] * ux + u_in[:, 1] * uy
        self.theta = np.arctan2(cross, dot)                             # turn at vertex i, left positive
        self.side = np.where(self.theta > 0, 1.0, -1.0)
        # Each vertex's own disk radius (a scalar for one radius: the very same arithmetic as before).
        self.rv = np.where(self.side > 0, self.ra, self.rb) if self.pair else r
        n_in = self._pred(self.n)
        self.c = n_in
        self.c += self.n
        self.c *= (self.side * self.rv / (1.0 + dot))[:, None]
        self.c += self.v
        self.t = self.rv * np.tan(np.abs(self.theta) / 2)
        self.length = self.ell - self.t - self._succ(self.t)            # straight piece on edge i
        self.phi = np.arctan2(uy, ux)
        self.bridged = np.zeros(0, dtype=np.int64)     # edges whose step a bridge crosses (`_bridge_steps`)
        self.keep = None                # vertices left in the loops, where runs merged (`_same_side_runs`)
        self.dropped = None             # corners the loop passes by (`_bridge_steps`)
        self.spans = []                 # (side, edges, vertex): offsets trimmed to its centre (`_trim_spans`)
        self.merged = {}                # first corner -> run, of the runs merged into one disk (`_merge_run`)
        self._fixed = []                # pieces from a span's foot: (at, edge, start, end) (`_fixed_pieces`)
        self._offsets, self._arcs = {}, {}
        self._edge_trees = {}
        self._sagitta = None

    @property
    def sagitta(self) -> np.ndarray:
        """How far the arc of radius r at each vertex strays from its chord: r·(1 − cos(θ/2))."""
        if self._sagitta is None:
            self._sagitta = self.rv * (1 - np.cos(0.5 * self.theta))
        return self._sagitta

    def radius(self, side: int) -> float:
        """The offset distance of a side: the shrink's (+1, the convex radius) or the grow's (−1)."""
        return self.ra if side > 0 else self.rb

    def arc_sagitta(self, side: int, k: np.ndarray) -> np.ndarray:
        """Sagitta of the arcs of this side's offset curve around vertices k (of the other side)."""
        if not self.pair:
            return self.sagitta[k]
        return self.radius(side) * (1 - np.cos(0.5 * self.theta[k]))

    def _succ(self, x: np.ndarray) -> np.ndarray:
        """``x[next]``, copied in one sweep but at the rings' ends."""
        y = np.empty_like(x)
        y[:-1] = x[1:]
        y[self._last] = x[self._first]
        return y

    def _pred(self, x: np.ndarray) -> np.ndarray:
        """``x[prev]``, copied in one sweep but at the rings' starts."""
        y = np.empty_like(x)
        y[1:] = x[:-1]
        y[self._first] = x[self._last]
        return y

    @property
    def vertex_tree(self) -> cKDTree:
        """A k-d tree over the vertices, built once for every exact proximity test."""
        if getattr(self, "_vertex_tree", None) is None:
            self._vertex_tree = _tree(self.v)
        return self._vertex_tree

    def edge_tree(self, edges: np.ndarray | None = None) -> tuple[np.ndarray, shapely.STRtree]:
        """An STRtree over the edges of S (all, or those marked in the boolean array ``edges``), and the
        edge numbers of its items, built once for each selection.

        On a large MultiPolygon (a layer of footprints) every exact test used to build its own, and the
        linestrings and trees cost more than the tests."""
        key = None if edges is None else edges.tobytes()
        cache = self._edge_trees
        if key not in cache:
            idx = np.arange(len(self.v)) if edges is None else np.flatnonzero(edges)
            lines = shapely.linestrings(np.stack([self.v[idx], self.v[self.next[idx]]], axis=1))
            cache[key] = idx, shapely.STRtree(lines)
        return cache[key]

    def offsets(self, side: int) -> np.ndarray:
        """Edges moved by r into S (side +1) or out of it (−1), cut at the disks' centres on that side.

        At an end whose disk is on the other side, the offset runs to the end of the edge (where the arc
        of radius r around that vertex starts).
        """
        return np.stack(self._offset_ends(side), axis=1)

    def _offset_ends(self, side: int):
        """`offsets` as the arrays of their starts and of their ends."""
        if side not in self._offsets:
            shift = side * self.radius(side) * self.n
            mine = (self.side == side)[:, None]
            a = self.v + shift
            np.copyto(a, self.c, where=mine)
            # b = v[next] + shift, but c[next] where next's disk is on this side: in one sweep, then at
            # the rings' ends.
            b = np.empty_like(a)
            np.add(self.v[1:], shift[:-1], out=b[:-1])
            np.copyto(b[:-1], self.c[1:], where=mine[1:])
            last, first = self._last, self._first
            b[last] = np.where(mine[first], self.c[first], self.v[first] + shift[last])
            self._offsets[side] = (a, b)
        return self._offsets[side]

    def arcs(self, side: int):
        """Arcs of radius r around the vertices whose disk is on the other side: centres, start, sweep.

        For side +1 these are the concave arcs of the shrink around the reflex vertices (directions from
        the incoming edge's inward normal to the outgoing one's); for −1 the convex arcs of the grow
        around the convex vertices.
        """
        if side not in self._arcs:
            k = np.flatnonzero(self.side != side)
            n_in = self.n[self.prev[k]]
            if side < 0:
                n_in = -n_in
            start = np.arctan2(n_in[:, 1], n_in[:, 0])
            self._arcs[side] = (self.v[k], start, self.theta[k])
        return self._arcs[side]


def fast_disk_loops(S, r: float, q: int, init: str, precision: float | None = None,
                    radii: tuple[float, float] | None = None):
    """Disk loops ``[(centers, sides, phi, lengths, sweeps), ...]`` for every ring of S, or None.

    ``S`` is oriented (S on the left of every ring), in the engine's local frame; ``precision`` is the
    rounding of the world coordinates in it (`offsets.exact_offsets`). With ``radii = (a, b)`` (two
    radii, r their larger, either may be 0) convex corners get disks of radius a and reflex ones of
    radius b, each side is checked against its own offset, and each loop carries a sixth array, the
    radius of every disk (0: the vertex itself, a sharp corner).
    """
    D = _Rings(S, r, precision, radii)
    if not D.ok or (np.abs(D.theta) > math.pi - 1e-6).any():
        # A spike: no disk fits its corner (kept sharp by a radius 0, its two sides would touch).
        return None
    if (D.length < -1e-12 * np.maximum(D.ell, r)).any():
        # Two disks do not fit on one edge: same-side runs (`_same_side_runs`) first, then steps.
        if D.pair:
            return None
        if not _same_side_runs(D):
            return None
        if (D.length < -1e-12 * np.maximum(D.ell, r)).any():
            runs = D.bridged
            if not _bridge_steps(D):
                return None
            D.bridged = np.concatenate([runs, D.bridged])
        if D.spans:
            _trim_spans(D)
    length = np.maximum(D.length, 0.0)
    shapely.prepare(S)
    # A side of radius 0 (two radii) keeps its corners sharp: its shrink (grow) is S itself, which the
    # straight pieces lie on and the other side's arcs stay out of; nothing to check there. The
    # certificates read the offset curves of disks at S's vertices: not where a step was bridged or a run
    # merged.
    plain = not len(D.bridged) and D.keep is None
    certified = {side: True if D.pair and D.radius(side) == 0 else
                 (plain and _offset_certified(D, S, side)) for side in (1, -1)}
    # A certified side's offset curves lie wholly in S (+1) or outside it (−1), and its centres with them.
    open_ = np.flatnonzero([not certified[s] for s in D.side.astype(int)]) if not all(certified.values()) \
        else np.zeros(0, np.int64)
    if len(open_):
        inside = shapely.contains_xy(S, D.c[open_, 0], D.c[open_, 1])
        if ((D.side[open_] > 0) != inside).any():
            return None                                 # a disk on the wrong side of S
    rounded = None
    for side in (1, -1):
        if D.pair and D.radius(side) == 0:
            continue
        limit = D.radius(side) - D.tie
        # The straight pieces must lie on the core's boundary for init="core" (side +1) and, with the
        # anticore's too, for "mason".
        edges = init != "input" if side > 0 else init == "mason"
        if certified[side]:
            # Every disk centre of this side is r from S, and so is every straight piece moved by r.
            if rounded is None:
                rounded = _rounded_certified(D)
            if not rounded and not _arcs_clear(D, side):
                return None
            continue
        # Not certified (pieces that touch or nearly do, very short edges): the exact distance tests.
        mine = D.side == side
        if mine.any() and _closer_than(D, D.c[mine], D.c[mine], limit):
            return None
        if not _arcs_clear(D, side):
            return None
        if edges and not _reaches_edges(D, S, side):
            return None
    if len(D.bridged) and not _bridges_clear(D):
        return None
    # Left out of the loops: the corners a run merged into one disk, and those a tangent passes by.
    kept = None if D.keep is None else D.keep.copy()
    if D.dropped is not None and D.dropped.any():
        kept = ~D.dropped if kept is None else kept & ~D.dropped
    fields = (D.c, D.side, D.phi, length, D.theta) + ((D.rv,) if D.pair else ())
    if kept is None:
        return [tuple(x[sl] for x in fields) for sl in D.slices]
    return [tuple(x[sl][kept[sl]] for x in fields) for sl in D.slices]


# -- steps: a convex and a reflex corner closer than their disks' tangents ---------------------------------
# An edge between a convex and a reflex corner (a step in a wall) shorter than the two tangent lengths
# r·tan(θ/2) at its ends: the tight loop does not run along it but crosses it, on the inner tangent of the
# two corner disks (a bridge, turning one way and then the other). A corner whose own tangent is longer
# than the edge has no disk touching both its edges: its disk slides along the other edge until it meets
# the far end of the step (the core's corner there is tangent to the edge before the step and passes
# through the step's reflex end; the anticore's likewise on the other side). The offset curves change with
# it: the offset of the stepped edge on that side is gone, and the arc about the far end starts (ends) at
# the moved centre; what is cut away must be nearer than r to S everywhere (`_covered`), so that none of it
# was on the shrink's (grow's) boundary.
#
# In a run of steps (a jog, a staircase) a disk may slide along an edge that is itself a step, as long as
# its foot stays on that edge. A corner between two steps whose tangent is longer than both is *wedged*:
# its disk touches neither of its edges but rests on their far ends, the two vertices next to it, on its
# own side of the line between them (they must be less than 2r apart). A corner between two bridges that
# would turn the wrong way is *passed by*: its disk lies beyond the common tangent of its neighbours'
# disks, and the loop runs along that tangent (of one side with the disks when they are of one side, a
# bridge across when the corners passed by are two or more); its disk still shapes the offset curves. A
# run of same-side corners merged into one disk (`_merge_run`) is one corner here, sliding along the run's
# outer edges. A short edge between corners of the same side, each the far end of a step (a bump or a dent
# no span's disk fits), keeps its straight piece: both disks slide along it, away from their steps. A disk
# two steps would slide, and other short edges between corners of the same side that no run took, are left
# to the general engine.

def _bridge_steps(D: _Rings) -> bool:
    """Bridge every step of S (see above) in place: centres, lengths, turns, offsets, arcs; False if some
    short edge is not a step (or a bridge does not fit), and the general engine must take S."""
    r = D.r
    short = D.length < -1e-12 * np.maximum(D.ell, r)
    bad = np.flatnonzero(short)
    nxt = D.next[bad]
    if any(short[sl].all() for sl in D.slices):
        return False
    # A short edge between two corners of one side, each the far end of a step (a bump or a dent
    # narrower than 2r, shallower than its corners' tangents): the loop runs along it, both disks sliding
    # along it away from their steps (checked below: its straight piece must not be negative).
    same = D.side[bad] == D.side[nxt]
    between = bad[same]
    if len(between):
        before, after = D.prev[between], D.next[between]
        if not (short[before] & short[after] & (D.side[before] != D.side[between])
                & (D.side[after] != D.side[D.next[after]])).all():
            return False
        bad, nxt = bad[~same], nxt[~same]
    arcs = {side: tuple(a.copy() for a in D.arcs(side)) for side in (1, -1)}  # about the original corners
    # Where each edge's straight piece starts and ends, as distances from its two vertices.
    foot_start, foot_end = D.t.copy(), D._succ(D.t)
    moved = {}                                  # corner -> the step whose far end its disk slid to
    # A corner between two steps whose tangent is longer than both (a jog's middle corner, a bump or a
    # dent narrower than 2r) is wedged: its disk touches neither of its edges but the far ends of both
    # steps, on its own side of the line between them.
    for k in np.intersect1d(bad, nxt).tolist():
        a, b = D.v[D.prev[k]], D.v[D.next[k]]
        if not (D.t[k] > D.ell[D.prev[k]] and D.t[k] > D.ell[k]):
            continue
        w = b - a
        half = 0.5 * math.hypot(w[0], w[1])
        if not half < r * (1 - 1e-9):
            return False
        depth = math.sqrt(r * r - half * half) / (2.0 * half)
        D.c[k] = 0.5 * (a + b) + D.side[k] * depth * np.array([-w[1], w[0]])
        moved[k] = _WEDGED
    # A run merged into one disk (`_merge_run`) is its corners' disk: the edges it slides along are the
    # edges before and after the run, and it moves whole.
    ending = {run[-1]: run for run in D.merged.values()}
    walls = []
    for i, j in zip(bad.tolist(), nxt.tolist()):
        run_i, run_j = ending.get(i), D.merged.get(j)
        h, at = (int(D.prev[run_i[0]]), run_i[0]) if run_i else (int(D.prev[i]), i)
        e = run_j[-1] if run_j else j
        walls += [h, e]
        if D.t[i] > D.ell[i] and moved.get(i) is not _WEDGED:
            # Corner i's disk slides forward along edge h's offset until it meets vertex j. Edge h may be
            # a step too (a jog): the disk must then still touch it, its foot no farther back than h's
            # start. A disk that two steps would slide is left to the general engine.
            base = D.v[at] + D.side[i] * r * D.n[h]
            x = _circle_hit(base, D.u[h], D.v[j], r, first=True)
            if x is None or x > 0 or i in moved or (short[h] and -x > D.ell[h]):
                return False
            D.c[run_i or i] = base + x * D.u[h]
            foot_end[h] = -x
            moved[i] = i
        if D.t[j] > D.ell[i] and moved.get(j) is not _WEDGED:
            # Corner j's disk slides back along edge j's offset (after a merged run, the run's last edge)
            # until it meets vertex i (edge j may be a step, as above).
            base = D.v[e] + D.side[j] * r * D.n[e]
            x = _circle_hit(base, D.u[e], D.v[i], r, first=False)
            if x is None or x < 0 or j in moved or (short[e] and x > D.ell[e]):
                return False
            D.c[run_j or j] = base + x * D.u[e]
            foot_start[e] = x
            moved[j] = i
    # The straight pieces next to the steps, with their moved ends; then each bridge: the inner tangent
    # of its two disks, whose normal meets the line of centres at asin(2r/d), on the side of the first.
    near = np.unique(walls)
    near = near[(~short[near] | np.isin(near, between)) & ~np.isin(near, D.bridged)]   # (not a span's bridge)
    D.length[near] = D.ell[near] - foot_start[near] - foot_end[near]
    if (D.length[near] < 0).any():
        return False
    for i, j in zip(bad.tolist(), nxt.tolist()):
        w = D.c[j] - D.c[i]
        d = math.hypot(w[0], w[1])
        if not d > 2.0 * r * (1 + 1e-9):
            return False
        D.phi[i] = math.atan2(w[1], w[0]) + D.side[i] * math.asin(2.0 * r / d)
        D.length[i] = math.sqrt(d * d - 4.0 * r * r)
    # A corner between two bridges that would turn the wrong way is not touched by the loop: its disk
    # lies beyond the common tangent of its neighbours' disks (of the other side, so of one side), and
    # the loop runs along that tangent from one to the other. Its disk still shapes the offset curves.
    dropped = np.zeros(len(D.v), bool)
    inner = np.intersect1d(bad, nxt).tolist()
    changed = True
    while changed:                      # each pass drops a corner or ends: at most len(inner) passes
        changed = False
        for k in inner:
            if dropped[k]:
                continue
            h = int(D.prev[k])
            while dropped[h]:
                h = int(D.prev[h])
            if _wrap(D.phi[k] - D.phi[h]) * D.side[k] > 0:
                continue
            b = int(D.next[k])
            while dropped[b]:
                b = int(D.next[b])
            # The tangent from h's disk to b's: along the line of centres when they are of one side (the
            # corners passed by alternate), across it otherwise (a bridge).
            w = D.c[b] - D.c[h]
            d = math.hypot(w[0], w[1])
            if D.side[h] == D.side[b]:
                phi, length = math.atan2(w[1], w[0]), d
            elif d > 2.0 * r * (1 + 1e-9):
                phi, length = math.atan2(w[1], w[0]) + D.side[h] * math.asin(2.0 * r / d), math.sqrt(d * d - 4 * r * r)
            else:
                return False
            dropped[k], D.length[k] = True, 0.0
            D.phi[h], D.length[h] = phi, length
            x = int(D.next[h])
            while x != b:                   # the corners passed by carry the tangent's direction
                D.phi[x] = phi
                x = int(D.next[x])
            changed = True
    # The turn at every corner a bridge leaves or reaches, from the directions it now joins.
    ends = np.unique(np.concatenate([bad, nxt]))
    ends = ends[~dropped[ends]]
    if D.keep is not None:
        ends = ends[D.keep[ends]]
    for v in ends.tolist():
        turn = _wrap(D.phi[v] - D.phi[D.prev[v]])
        if not turn * D.side[v] > 0:
            return False
        D.theta[v] = turn
    # A run merged into one disk beside a step: its whole turn, from the direction that arrives (a bridge,
    # or the edge before it) to the one that leaves, at its last corner.
    for first, run in D.merged.items():
        if short[D.prev[first]] or short[run[-1]]:
            arrive = D.phi[D.prev[first]]
            D.phi[run[:-1]], D.theta[run[:-1]] = arrive, 0.0
            turn = _wrap(D.phi[run[-1]] - arrive)
            if not turn * D.side[first] > 0:
                return False
            D.theta[run[-1]] = turn
    D.theta[dropped] = 0.0
    D.bridged = bad
    D.dropped = dropped if D.dropped is None else dropped | D.dropped    # with the bends a span passes by
    D._sagitta = None
    # The offset curves: the stepped edge's offset is gone on a side whose disk moved (a point at the
    # centre), and the arc about the step's other end starts or ends at the moved centre. What is cut
    # away must be nearer than r to S (`_covered`): then none of it is on the shrink's (grow's) boundary.
    cut_away = []
    for side in (1, -1):
        a, b = D._offset_ends(side)
        centres, start, sweep = arcs[side]
        k_of = {int(v): n for n, v in enumerate(np.flatnonzero(D.side != side))}
        for i in bad.tolist():
            j = int(D.next[i])
            mine, far = (i, j) if D.side[i] == side else (j, i)
            if moved.get(mine) not in (i, _WEDGED):   # not moved, or moved for its other edge's step
                continue
            # The offset of edge i runs between the moved centre (kept, a point now) and the far arc.
            cut_away.append(("seg", (a[i].copy(), b[i].copy()), mine == i, mine == j, (i,)))
            a[i] = b[i] = D.c[mine]
            n = k_of[far]
            ang = math.atan2(*(D.c[mine] - D.v[far])[::-1])
            if mine == i:                       # the arc about j begins where centre i meets it
                cut = _wrap(ang - start[n])
                if cut * sweep[n] < 0 or abs(cut) > abs(sweep[n]):
                    return False
                cut_away.append(("arc", (D.v[far], start[n], cut), False, True, (int(D.prev[far]), far)))
                start[n], sweep[n] = ang, sweep[n] - cut
            else:                               # the arc about i ends where centre j meets it
                keep = _wrap(ang - start[n])
                if keep * sweep[n] < 0 or abs(keep) > abs(sweep[n]):
                    return False
                cut_away.append(("arc", (D.v[far], ang, sweep[n] - keep), True, False, (int(D.prev[far]), far)))
                sweep[n] = keep
        D._arcs[side] = (centres, start, sweep)
    return _covered(D, cut_away)


_KEPT = 1e-9          # `_covered`: crossings this near a kept end (a fraction of the piece) are that end


def _covered(D: _Rings, pieces) -> bool:
    """Whether every point of each piece, but the ends marked kept, is nearer than r to an edge of S.

    ``pieces``: ``(kind, geometry, keep_start, keep_end, own)``, a segment ``("seg", (p, q))`` or an arc of
    radius r ``("arc", (centre, start, sweep))``, and the edges whose offset it was (an edge's offset
    segment; an arc's vertex's two edges), set aside: the piece lies on the boundary of their capsules, so
    they cover none of it, and rounding must not say otherwise. A point nearer than r to S is not on the
    boundary of the shrink or the grow (every point of which is exactly r from S), so the piece can be cut
    from the raw offset curves.

    Exact up to rounding: the points nearer than r to an edge form an open capsule, convex, so along a
    piece the set it covers changes only where the piece crosses the capsule's boundary (two circles about
    the ends and four lines). Between consecutive such crossings of all the nearby edges' capsules, the
    piece is covered throughout or nowhere: one point in each stretch, and each crossing itself, decide.
    """
    if not pieces:
        return True
    r = D.r
    ea, eb = D.v, D.v[D.next]
    # The edges that can reach each piece: within r of a segment, 2r of an arc's centre (every edge of a
    # small shape; on a large one, from an R-tree, all pieces in one query).
    near = None
    if len(ea) > _ALL_PIECES:
        ends = np.array([g if kind == "seg" else (g[0], g[0]) for kind, g, *_ in pieces], dtype=float)
        point = (ends[:, 0] == ends[:, 1]).all(axis=1)
        probes = np.empty(len(pieces), dtype=object)
        probes[point] = shapely.points(ends[point, 0])
        probes[~point] = shapely.linestrings(ends[~point])
        reach = np.array([r if kind == "seg" else 2.0 * r for kind, *_ in pieces]) * (1 + 1e-9)
        pi, pe = D.edge_tree()[1].query(probes, predicate="dwithin", distance=reach)
        order = np.lexsort((pe, pi))
        pi, pe = pi[order], pe[order]
        bounds = np.searchsorted(pi, np.arange(len(pieces) + 1))
        near = pi, pe, bounds
    whole = _in_one_capsule(D, pieces, near)
    for index, ((kind, geom, keep0, keep1, own), settled) in enumerate(zip(pieces, whole, strict=True)):
        if settled:
            continue
        if kind == "seg":
            p, q = geom
            w = q - p
        else:
            o, s0, sw = geom
            if sw == 0:
                continue
            p = q = o
        if near is None:
            m = len(ea)
            reach = (r if kind == "seg" else 2.0 * r) * (1 + 1e-9)
            e = np.flatnonzero(_segment_distances(np.tile(p, (m, 1)), np.tile(q, (m, 1)), ea, eb) <= reach)
        else:
            e = near[1][near[2][index]:near[2][index + 1]]
        e = e[~np.isin(e, own)]
        if not len(e):
            return False
        a, b = D.v[e], D.v[D.next[e]]
        d = b - a
        L = np.hypot(d[:, 0], d[:, 1])
        u = d / L[:, None]
        nrm = np.column_stack([-u[:, 1], u[:, 0]])
        # Each capsule's boundary: the circles about a and b, and the lines (x − a)·m = k.
        circles = np.concatenate([a, b])
        lines_m = np.concatenate([nrm, nrm, u, u])
        lines_k = np.concatenate([np.full(len(e), r), np.full(len(e), -r), np.zeros(len(e)), L])
        lines_a = np.concatenate([a, a, a, a])
        lines_k = lines_k + (lines_a * lines_m).sum(axis=1)       # x·m = k
        if kind == "seg":
            crit = _segment_crossings(p, w, circles, lines_m, lines_k, r)
        else:
            crit = _arc_crossings(o, s0, sw, circles, lines_m, lines_k, r)
        # A kept end is exactly r from S (a moved centre, where the far vertex's circle passes): the
        # crossing there, found again within rounding, is that end.
        lo, hi = (_KEPT if keep0 else 0.0), (1.0 - _KEPT if keep1 else 1.0)
        crit = np.unique(np.concatenate([[0.0, 1.0], crit[(crit > lo) & (crit < hi)]]))
        tau = np.concatenate([crit, 0.5 * (crit[1:] + crit[:-1])])
        tau = tau[~(((tau == 0) & keep0) | ((tau == 1) & keep1))]
        if kind == "seg":
            x = p + tau[:, None] * w
        else:
            th = s0 + tau * sw
            x = o + r * np.column_stack([np.cos(th), np.sin(th)])
        m, k = len(x), len(e)
        dist = _point_segment_distances(np.repeat(x, k, axis=0), np.tile(a, (m, 1)), np.tile(b, (m, 1)))
        if not (dist.reshape(m, k).min(axis=1) < r).all():
            return False
    return True


_MARGIN = 1e-3       # `_in_one_capsule`: beside a kept end, the piece's other points this far (× r) inside


def _in_one_capsule(D: _Rings, pieces, near=None) -> np.ndarray:
    """Which pieces (`_covered`'s) lie wholly in the open capsule of one edge (not their own): the common
    case, settled without the crossings. The points of a segment are convex combinations of its ends, those
    of an arc turning by less than π of its ends and of where its end tangents meet; the distance to an
    edge is convex, so it is below r all along where it is below r at those points. A kept end (exactly r
    from S) may be at r: the piece then leaves the capsule only within a fraction (rounding)/(_MARGIN·r) of
    that end, below `_KEPT`, if its other points are _MARGIN·r inside.

    ``near``: `_covered`'s candidate pairs ``(piece, edge, bounds)``, or None to try every edge. An edge
    whose capsule holds a piece's two ends (an arc's are r from its centre) is within r of a segment, 2r of
    an arc's centre: among the candidates."""
    r = D.r
    n = len(pieces)
    pts = np.full((n, 3, 2), np.nan)
    kept = np.zeros((n, 3), bool)
    own_piece, own_edge = [], []
    for i, (kind, geom, keep0, keep1, edges) in enumerate(pieces):
        if kind == "seg":
            pts[i, 0], pts[i, 2] = geom
        else:
            o, s0, sw = geom
            if not abs(sw) < 0.9 * math.pi:
                continue                            # its tangents meet far out: left to the crossings
            a1 = s0 + sw
            pts[i, 0] = o + r * np.array([math.cos(s0), math.sin(s0)])
            pts[i, 2] = o + r * np.array([math.cos(a1), math.sin(a1)])
            mid = s0 + 0.5 * sw
            pts[i, 1] = o + (r / math.cos(0.5 * sw)) * np.array([math.cos(mid), math.sin(mid)])
        kept[i, 0], kept[i, 2] = keep0, keep1
        own_edge.extend(edges)
        own_piece.extend([i] * len(edges))
    valid = ~np.isnan(pts[:, :, 0])
    m = len(D.v)
    if near is None:
        pi, pe = np.repeat(np.arange(n), m), np.tile(np.arange(m), n)
    else:
        pi, pe = near[0], near[1]
    x = np.where(valid[:, :, None], pts, 0.0)[pi]                       # (pairs, 3, 2)
    d = _point_segment_distances(x.reshape(-1, 2), np.repeat(D.v[pe], 3, axis=0),
                                 np.repeat(D.v[D.next[pe]], 3, axis=0)).reshape(-1, 3)
    k = kept[pi]
    inside = np.where(k, d <= r * (1 + 1e-12), d < r) | ~valid[pi]
    deep = np.where(k, True, d < r * (1 - _MARGIN)) | ~valid[pi]
    own_keys = np.asarray(own_piece, dtype=np.int64) * m + np.asarray(own_edge, dtype=np.int64)
    own = np.isin(pi * m + pe, own_keys)
    fits = inside.all(axis=1) & (~k.any(axis=1) | deep.all(axis=1)) & ~own
    whole = np.zeros(n, bool)
    whole[pi[fits]] = True
    return whole & valid[:, [0, 2]].all(axis=1) & ~(kept[:, 0] & kept[:, 2])


def _segment_crossings(p, w, circles, m, k, r) -> np.ndarray:
    """Parameters t of the points p + t·w on the circles of radius r about ``circles`` and on the lines
    x·m = k."""
    out = []
    ww = float(w @ w)
    if ww > 0:
        f = p - circles
        bh = f @ w
        disc = bh * bh - ww * ((f * f).sum(axis=1) - r * r)
        ok = disc >= 0
        root = np.sqrt(disc[ok])
        out += [(-bh[ok] - root) / ww, (-bh[ok] + root) / ww]
    wm = m @ w
    ok = wm != 0
    out.append((k[ok] - m[ok] @ p) / wm[ok])
    return np.concatenate(out) if out else np.zeros(0)


def _arc_crossings(o, s0, sw, circles, m, k, r) -> np.ndarray:
    """Fractions τ ∈ [0, 1] of the arc (centre o, radius r, from angle s0, signed sweep sw) where it meets
    the circles of radius r about ``circles`` and the lines x·m = k."""
    ang = []
    f = circles - o
    dist = np.hypot(f[:, 0], f[:, 1])
    ok = (dist > 0) & (dist <= 2 * r)
    base = np.arctan2(f[ok, 1], f[ok, 0])
    half = np.arccos(np.clip(dist[ok] / (2 * r), -1, 1))
    ang += [base - half, base + half]
    # r·cos(θ − β) = k − o·m, β the direction of m (a unit vector).
    c = (k - m @ o) / r
    ok = np.abs(c) <= 1
    beta = np.arctan2(m[ok, 1], m[ok, 0])
    half = np.arccos(c[ok])
    ang += [beta - half, beta + half]
    th = np.concatenate(ang)
    return np.mod((th - s0) * np.sign(sw), _TWO_PI) / abs(sw)


_WEDGED = -1          # `_bridge_steps`: a corner whose disk rests on the far ends of both its steps


def _wrap(a: float) -> float:
    """An angle in (−π, π]."""
    return math.remainder(a, _TWO_PI)


def _circle_hit(base: np.ndarray, u: np.ndarray, x: np.ndarray, r: float, first: bool):
    """Where the line ``base + s·u`` (u a unit vector) meets the circle of radius r about x: the smaller
    s (``first``) or the larger, or None if it misses."""
    w = base - x
    b = float(w @ u)
    disc = b * b - (float(w @ w) - r * r)
    if disc < 0:
        return None
    root = math.sqrt(disc)
    return -b - root if first else -b + root


# -- same-side runs: corners of one side closer than their disks' tangents ----------------------------------
# A short edge between two corners of the same side (a bevel, two chords of a digitised round corner, a
# notch's floor): a maximal run of corners i_1 … i_k of side s joined by short edges, between the edge h
# arriving at i_1 and the edge e leaving i_k.
#
# * Merged corner (|Θ| < π, Θ the run's total turn). Near the run the shrink (s = +1; the grow outside S
#   for s = −1) is the intersection of the half-planes bounded by the offset lines of h, the inner edges and
#   e, whose directions turn monotonically through less than π. Each surviving line bounds one edge of that
#   intersection, which lies in the segment its neighbours' lines cut from it; for an inner edge that
#   segment has negative length (the edge is short), so no inner line survives, and h and e meet at one
#   vertex C: the centre of the one disk tangent to h and e, about the intersection V of their lines as at
#   any corner. The run becomes that disk, turning by Θ; its tangent points must fall on h and e (checked),
#   and the straight pieces on h and e shrink to match (≥ 0, else the general engine). The offset curves
#   on side s pass through C (the inner edges' offsets shrink to the point C); the other side's, the arcs
#   about the run's corners, are unchanged.
# * Notch or tab (|Θ| ≥ π: a slot, or a protrusion, between corners A and D of the other side). With
#   |AD| < 2r, the disk E of radius r through A and D on side s is the corner of the grow (a notch, s = −1;
#   the shrink for a tab) where the arcs about A and D meet: the loop goes from A's own disk, on the inner
#   tangent, to E, around E, and on to D's disk. On side s the offsets of the run's edges and the parts of
#   the arcs about A and D beyond E are trimmed away: sound only where every point removed is nearer than r
#   to S's boundary, which is checked exactly (`_covered`: the run's edges' whole offsets against the open
#   capsules of the edges nearby; the arcs against the other corner's open disk).
#
#   A mouth 2r or wider (a building's end narrower than 2r whose one mouth corner is a slight bend farther
#   along the wall) has no disk through both corners: E is then tangent to that wall, on side s, through
#   the other mouth corner (where the wall's offset meets that corner's circle), the wall's offset kept up
#   to E; what goes (the rest of the run's offsets, the wall's offset beyond E, the arc about the other
#   corner up to E) is checked exactly by `_covered`.
# * Chains: a tab and a notch that share a wall (the one's far mouth corner the other's first corner) are
#   spanned one after the other, the loop running from one E straight to the next (`_span_chains`). A disk
#   through both corners of a mouth inside the chain usually reaches into the other span; the disks
#   tangent to the shared wall, from either side, through the far corners, are the corners of the shrink
#   and the grow there (`_span_chain` takes the first candidate whose centre is r from every edge).
# * A lone notch or tab none of those disks fits (real outlines: walls digitised with slight bends, mouths
#   flared or cut by a neighbouring wall), tried in turn, each exactly like the others:
#   - E tangent to two edges turning by less than π, the wall from A or the edge before A, and the wall
#     into D or the edge after D (`_span_walls`): a merged corner over the corners between them. The loop
#     runs along each edge to E or, where E's foot comes before the neighbouring disk's tangent point,
#     on the inner tangent from that disk, which must touch E between its two feet.
#   - E tangent to the wall beyond one mouth corner, through the other (`_span_beyond`): the mouth corner
#     on that wall is passed by, and the loop runs on along the wall from E's foot.
#   - The same notch with its mouth taken past slight bends (under 30°) of its walls (`_mouth`): tried
#     when the mouth as drawn does not fit, after D is put back as it was (`_Undo`).
#   A corner of the other side that a span passes by keeps its own disk, which still shapes that side's
#   offset curves (sliding along an edge where it is a step's, `_slide_passed`); its arc on side s goes,
#   checked like the rest, and stays in the arrays as the point E.
#
# The dropped corners stay in the arrays as disks of sweep 0 at the merged centre (their edges of length 0,
# leaving in the direction that arrives at the run), so every exact test reads them as points of the one
# arc; `_Rings.keep` leaves them out of the loops.
#
# Beside a step (a short edge to a corner of the other side): a run merged into one disk is its corners'
# disk for `_bridge_steps`, which bridges the step to it and, where its foot would lie beyond the step,
# slides it along the run's other edge (it is tried only where no notch's mouth spans the run); a notch's
# or tab's mouth corner keeps its disk for both the span's bridge and the step's, sliding it first along
# the wall into the span exactly as `_bridge_steps` will (both agree), which then sets its turn. A mouth
# corner whose disk two slides would move, or a notch whose mouth corner is another run's, goes to the
# general engine.

def _same_side_runs(D: _Rings) -> bool:
    """Merge every run of same-side short edges into one corner, or span it as a notch or tab (see above),
    in place; False if some run cannot be taken (the general engine must take S). Steps are left short for
    `_bridge_steps`."""
    r = D.r
    short = D.length < -1e-12 * np.maximum(D.ell, r)
    nxt, prv = D.next, D.prev
    inner = short & (D.side == D.side[nxt])
    if not inner.any():
        return True
    if any(inner[sl].all() for sl in D.slices):
        return False
    step = short & ~inner
    for side in (1, -1):
        D.arcs(side)                                # cached about the original corners, before turns change
    keep = np.ones(len(D.v), bool)
    outer, notches, passed, other = [], [], [], {}
    for first in np.flatnonzero(inner & ~inner[prv]).tolist():
        run = [first]
        while inner[run[-1]]:
            run.append(int(nxt[run[-1]]))
        last, h = run[-1], int(prv[first])
        s = float(D.side[first])
        turn = float(D.theta[run].sum())
        # One merged corner where it fits (not beside a step), else a notch or tab where one spans it, else
        # (beside a step) one merged corner the step is bridged to.
        merge = abs(turn) < math.pi - 1e-6
        if merge and not (step[h] or step[last]) and _merge_run(D, run, s, turn, step):
            outer += [h, last]
            D.merged[first] = run
        else:
            # A notch or tab: its mouth as drawn (`_mouth`), else across slight bends of its walls; a run
            # beside a step with no mouth, one disk that `_bridge_steps` then bridges to the step.
            plain, bent = _mouth(D, run, s, short, False), _mouth(D, run, s, short, True)
            if plain is None and bent is None:
                if not (merge and _merge_run(D, run, s, turn, step)):
                    return False
                outer += [x for x in (h, last) if not step[x]]
                D.merged[first] = run
                keep[run[:-1]] = False
                continue
            notches.append(plain or bent)
            if plain is not None and bent is not None and (bent[0], bent[2]) != (plain[0], plain[2]):
                other[plain[0], plain[2]] = bent
            continue
        keep[run[:-1]] = False
    if outer:
        e = np.array(outer)
        D.length[e] = D.ell[e] - D.t[e] - D.t[nxt[e]]
        if (D.length[e] < -1e-12 * np.maximum(D.ell[e], r)).any():
            return False                            # a merged disk's tangent runs past its outer edge
    chains = _span_chains(D, notches, short, step)
    if chains is None:
        return False
    used = np.zeros(len(D.v), bool)
    about = {side: np.flatnonzero(D.side != side) for side in (1, -1)}     # the vertices of each side's arcs
    for chain in chains:
        used[[x for A, run, Dv, _ in chain for x in [A, Dv] + run]] = True
    bridged = []
    for chain in chains:
        undo = _Undo(D, chain[0][0], chain[-1][2], about)
        spanned = _span_chain(D, chain)
        bent = other.get((chain[0][0], chain[0][2])) if len(chain) == 1 else None
        if spanned is None and bent is not None:
            # The mouth across the walls' slight bends instead, where it meets no other span or step.
            A, run, Dv, _ = bent
            mine = [A, Dv] + run
            if not (short[prv[A]] or short[Dv] or used[mine].sum() > len(chain[0][1]) + 2):
                undo.restore(D)
                chain = [bent]
                spanned = _span_chain(D, chain)
        if spanned is None:
            A, run, Dv, _ = chain[0]
            if not (len(chain) == 1 and len(run) == 2 and step[A] and step[run[-1]]):
                return False
            # A bump or dent between two steps that no disk spans: left to `_bridge_steps`, which takes
            # it as two steps whose disks slide along the edge between them.
            undo.restore(D)
            continue
        trims, crossed, gone = spanned
        bridged += crossed
        for _, run, _, _ in chain:
            keep[run] = False
        keep[[at for _, _, at, *_ in trims]] = True
        passed += gone
        D.spans += trims
    if D._fixed and not _fixed_pieces(D):
        return False
    if passed:
        D.dropped = np.zeros(len(D.v), bool)
        D.dropped[passed] = True
        keep[passed] = False
    D.keep = keep
    D.bridged = np.array(bridged, dtype=np.int64)
    D._sagitta = None
    return True


def _mouth(D: _Rings, run: list, s: float, short: np.ndarray, bends: bool):
    """A notch's (tab's) mouth ``(A, run, D, s)``: the nearest corners of the other side before and after
    the run, across at most a few corners whose edges fit and that are of side s or, with ``bends``, slight
    bends of the other side (a wall digitised with a slight bend before the notch, either way: passed by,
    their own disks still shaping that side's offset curves); None if a corner of side s is left there."""
    nxt, prv = D.next, D.prev
    run = list(run)
    A, Dv = int(prv[run[0]]), int(nxt[run[-1]])
    for _ in range(_WALL_BENDS):
        if not (D.side[A] == s or bends and abs(D.theta[A]) < _SLIGHT) or short[prv[A]]:
            break
        run.insert(0, A)
        A = int(prv[A])
    for _ in range(_WALL_BENDS):
        if not (D.side[Dv] == s or bends and abs(D.theta[Dv]) < _SLIGHT) or short[Dv]:
            break
        run.append(Dv)
        Dv = int(nxt[Dv])
    return None if D.side[A] == s or D.side[Dv] == s else (A, run, Dv, s)


class _Undo:
    """What spanning a chain may change of D, from a few corners before its first mouth to a few after its
    last: put back (`restore`) when the chain does not fit, before it is tried another way."""

    def __init__(self, D: _Rings, first: int, last: int, about: dict, margin: int = 3):
        idx = [first]
        for _ in range(margin):
            idx.insert(0, int(D.prev[idx[0]]))
        x = first
        while x != last and len(idx) <= len(D.v):
            x = int(D.next[x])
            idx.append(x)
        for _ in range(margin):
            idx.append(int(D.next[idx[-1]]))
        self.idx = idx = np.unique(idx)
        self.rows = [(a, a[idx].copy()) for a in (D.c, D.t, D.phi, D.length, D.theta)]
        self.arcs = []
        for side in (1, -1):
            arrays = D.arcs(side)
            k = np.searchsorted(about[side], idx[D.side[idx] != side])
            self.arcs.append((arrays, k, [a[k].copy() for a in arrays]))
        self.spans, self.fixed = len(D.spans), len(D._fixed)

    def restore(self, D: _Rings) -> None:
        for a, saved in self.rows:
            a[self.idx] = saved
        for arrays, k, saved in self.arcs:
            for a, x in zip(arrays, saved, strict=True):
                a[k] = x
        del D.spans[self.spans:], D._fixed[self.fixed:]


def _span_chains(D: _Rings, notches: list, short: np.ndarray, step: np.ndarray):
    """The notches and tabs grouped into chains, each span's far mouth corner the next one's first corner
    and its last corner the next one's near mouth (a tab beside a notch that share a wall, a crenellation);
    None if two spans share corners otherwise, a chain's outer wall is another run's inner edge, or a step
    whose mouth corner's disk fits neither its wall nor the step (it would slide two ways)."""
    prv = D.prev
    after = {}
    for k, (A, run, Dv, s) in enumerate(notches):
        after[(run[0], A)] = k                      # a span, by its first corner and its near mouth
    nxt = [after.get((Dv, run[-1])) for A, run, Dv, s in notches]
    has_prev = {k for k in nxt if k is not None}
    used = np.zeros(len(short), bool)
    chains, seen = [], 0
    for k in range(len(notches)):
        if k in has_prev:
            continue
        chain = [notches[k]]
        while nxt[k] is not None:
            k = nxt[k]
            chain.append(notches[k])
        A, Dv = chain[0][0], chain[-1][2]
        for X, wall, inside in ((A, int(prv[A]), A), (Dv, Dv, chain[-1][1][-1])):
            if step[wall] and D.t[X] > D.ell[wall] and D.t[X] > D.ell[inside]:
                return None
            if short[wall] and not step[wall]:
                return None                         # beside another run of corners
        corners = [A, Dv] + [x for _, run, _, _ in chain for x in run]
        if used[corners].any():
            return None
        used[corners] = True
        chains.append(chain)
        seen += len(chain)
    # A ring of spans (each linked to the next all round) has no first: left to the general engine.
    return chains if seen == len(notches) else None


def _trim_spans(D: _Rings) -> None:
    """The offsets on side s of a notch's (tab's) edges are gone, points at E (`_span_chain` checked that
    every point of them is nearer than r to S's boundary). After the steps have moved their disks."""
    for s, edges, at, *ends in D.spans:
        a, b = D._offset_ends(s)
        a[edges] = b[edges] = D.c[at]
        for edge, begins in ends[0] if ends else ():    # a wall's offset beyond a span: begins (ends) at E
            (a if begins else b)[edge] = D.c[at]


def _merge_run(D: _Rings, run: list, s: float, turn: float, step: np.ndarray) -> bool:
    """One disk for the run's corners, tangent to the edges h before it and e after (see above). Where h
    (e) is a step, the disk's foot must lie on it; `_bridge_steps` then crosses the step."""
    first, last = run[0], run[-1]
    h = int(D.prev[first])
    uh, ue = D.u[h], D.u[last]
    sine = uh[0] * ue[1] - uh[1] * ue[0]
    if not abs(sine) > 1e-9:
        return False
    w = D.v[last] - D.v[first]
    a = (w[0] * ue[1] - w[1] * ue[0]) / sine        # V = v[first] + a·uh = v[last] + b·ue
    b = (w[0] * uh[1] - w[1] * uh[0]) / sine
    t = D.r * math.tan(0.5 * abs(turn))
    foot_h, foot_e = t - a, t + b                   # tangent points: back from v[first], on from v[last]
    if not (foot_h >= 0 and foot_e >= 0):
        return False
    # The straight pieces on h and e, with the disks at their other ends as they are now (not on a step: a
    # bridge crosses it, the disk sliding along the run's other edge where its foot is beyond the step).
    if not ((step[h] or D.ell[h] - D.t[h] - foot_h >= -1e-12 * max(D.ell[h], D.r))
            and (step[last] or D.ell[last] - foot_e - D.t[D.next[last]] >= -1e-12 * max(D.ell[last], D.r))):
        return False
    V = D.v[first] + a * uh
    C = V + (s * D.r / (1.0 + float(uh @ ue))) * (D.n[h] + D.n[last])
    D.t[first], D.t[last] = foot_h, foot_e
    D.c[run] = C
    D.theta[run[:-1]] = 0.0
    D.theta[last] = turn
    D.phi[run[:-1]] = D.phi[h]
    D.length[run[:-1]] = 0.0
    return True


_GRAZING = 0.25       # a notch's disk E at least this × r beyond its mouth (`_span_chain`)
_WALL_BENDS = 3       # `_same_side_runs`: a notch's mouth is looked for across at most this many corners
_SLIGHT = math.pi / 6     # … of its own side or, with ``bends``, turning the other way by less than this


def _span_chain(D: _Rings, chain: list):
    """Span each notch or tab of a chain (see above) by a disk E on its side s; the loop runs from the
    first A's own disk on inner tangents through every E to the last D's own disk. In place; the offsets
    to trim (`_Rings.spans` entries), or None if some part does not fit.

    E is the first of these whose centre is r or more from every edge of S (a corner of the shrink, or of
    the grow): the disk through the mouth's corners A and D, when they are less than 2r apart; the disk
    tangent to the wall from A into the span, through D; the disk tangent to the wall into D, through A.
    A wall-tangent disk is where the wall's offset meets the other corner's circle, the wall's offset kept
    up to it. (In a chain, the wall between two spans is both the one's wall into D and the next one's
    wall from A: a crenellation's disks rest on it from either side.)
    """
    r = D.r
    limit = r - D.tie
    disks, trims = [], []
    for A, run, Dv, s in chain:
        chord = D.v[Dv] - D.v[A]
        w = math.hypot(chord[0], chord[1])
        found = None
        # The circles about A and D cross at E at an angle of about 2·depth/r: for a depth below _GRAZING·r
        # the final check's coarse buffers misplace such a corner by their chords' sagitta over that angle,
        # and would flag the exact answer: no disk through a mouth that close to 2r.
        if w < 2.0 * r * (1 - 1e-9) and math.sqrt(r * r - 0.25 * w * w) >= _GRAZING * r:
            depth = math.sqrt(r * r - 0.25 * w * w)
            nl = np.array([-chord[1], chord[0]]) / w
            E = 0.5 * (D.v[A] + D.v[Dv]) + (s * depth) * nl
            if not _closer_than(D, E[None], E[None], limit):
                found = (E, ("mouth", nl, depth), [A] + run)
        for wall, through, forward in ((A, Dv, True), (run[-1], A, False)):
            if found is not None:
                break
            base = D.v[wall] + s * r * D.n[wall]
            x = _circle_hit(base, D.u[wall], D.v[through], r, first=forward)
            if x is None or not 0.0 <= x <= D.ell[wall]:
                continue
            E = base + x * D.u[wall]
            if _closer_than(D, E[None], E[None], limit):
                continue
            # The wall's offset ends (begins) at E, where the first (last) corner's centre now is: its part
            # beyond E goes, with the offsets of the span's other edges.
            raw = D.v[D.next[wall]] + s * r * D.n[wall] if forward else D.v[wall] + s * r * D.n[wall]
            beyond = ("seg", (E, raw) if forward else (raw, E), forward, not forward, (int(wall),))
            found = (E, ("wall", wall, through, forward, beyond), run if forward else [A] + run[:-1])
        if found is None:
            if len(chain) > 1:
                return None
            spanned = _span_walls(D, A, run, Dv, s)     # False: it fitted, then failed (D changed)
            return _span_beyond(D, A, run, Dv, s) if spanned is None else spanned or None
        disks.append(found[:2])
        trims.append((int(s), found[2], [x for x in run if D.side[x] == s][-1]))   # E's corner in the loop
    # The outer mouth corners' own disks touch the edges into the chain, or slide along their walls until
    # they meet the first (last) run's end corner (`_slide_mouth`). The mouths inside a chain are corners
    # of the next (previous) span's run: their disks are not on the loop.
    A0, first_run = chain[0][0], chain[0][1]
    Dn, last_run = chain[-1][2], chain[-1][1]
    for X, wall, corner, forward in ((A0, int(D.prev[A0]), first_run[0], True), (Dn, Dn, last_run[-1], False)):
        if D.t[X] > D.ell[A0 if forward else last_run[-1]] and not _slide_mouth(D, X, wall, corner, forward):
            return None
    # A mouth corner beside a step whose tangent is longer than the step: its disk slides along its wall
    # into the chain until it meets the step's far end, as `_bridge_steps` will slide it (the very same
    # arithmetic, so that the two agree), which then bridges the step from it and cuts its offsets.
    stepped = [_is_step(D, int(D.prev[A0])), _is_step(D, Dn)]
    if stepped[0] and D.t[A0] > D.ell[D.prev[A0]]:
        base = D.v[A0] + D.side[A0] * r * D.n[A0]
        x = _circle_hit(base, D.u[A0], D.v[D.prev[A0]], r, first=False)
        if x is None or not 0 <= x <= D.ell[A0]:
            return None
        D.c[A0] = base + x * D.u[A0]
    if stepped[1] and D.t[Dn] > D.ell[Dn]:
        h = int(D.prev[Dn])
        base = D.v[Dn] + D.side[Dn] * r * D.n[h]
        x = _circle_hit(base, D.u[h], D.v[D.next[Dn]], r, first=True)
        if x is None or not -D.ell[h] <= x <= 0:
            return None
        D.c[Dn] = base + x * D.u[h]
    for e in (int(D.prev[A0]), Dn):
        D.length[e] = D.ell[e] - D.t[e] - D.t[D.next[e]]
        if D.length[e] < -1e-12 * max(D.ell[e], r) and D.side[e] == D.side[D.next[e]]:
            return None                             # (a step is left short: `_bridge_steps` crosses it)
    # What the spans trim from side s must be nearer than r to S's boundary: the edges' whole offsets, the
    # part of a wall's offset beyond E, and the arcs about the mouth corners up to E — these checked
    # exactly (`_covered`), or, for a mouth narrower than 2r, shown to lie in the other corner's open disk.
    pieces = []
    for (A, run, Dv, s), (E, how), (_, edges, _) in zip(chain, disks, trims, strict=True):
        pieces += _whole_offsets(D, edges, s)
        centres, start, sweep = D.arcs(int(s))
        k_of = np.cumsum(D.side != s) - 1           # index of a vertex's arc on side s
        bends = [x for x in run if D.side[x] != s]  # slight bends passed by: their whole arcs on side s go
        pieces += _whole_arcs(D, bends, s, E)
        if how[0] == "mouth":
            w = math.hypot(*(D.v[Dv] - D.v[A]))
            beta = math.acos(min(1.0, 0.5 * w / r))     # the arc about A inside D's open disk: ±β about A→D
            for X, Y, keep_first in ((A, Dv, True), (Dv, A, False)):
                n = int(k_of[X])
                cut = _arc_cut(float(start[n]), float(sweep[n]), math.atan2(*(E - D.v[X])[::-1]), keep_first,
                               math.atan2(*(D.v[Y] - D.v[X])[::-1]), beta)
                if cut is None:
                    return None                     # not all of it in the other corner's open disk
                start[n], sweep[n] = cut
        else:
            _, wall, through, forward, beyond = how
            pieces.append(beyond)
            # The arc about the other corner: kept from E on (after E when the wall is A's).
            n = int(k_of[through])
            a0, sw = float(start[n]), float(sweep[n])
            at = _wrap(math.atan2(*(E - D.v[through])[::-1]) - a0)
            if at * sw < 0 or abs(at) > abs(sw):
                return None
            own = (int(D.prev[through]), int(through))
            if forward:                             # the part before E goes
                pieces.append(("arc", (D.v[through], a0, at), False, True, own))
                start[n], sweep[n] = a0 + at, sw - at
            else:                                   # the part after E goes
                pieces.append(("arc", (D.v[through], a0 + at, sw - at), True, False, own))
                sweep[n] = at
    if not _covered(D, pieces):
        return None
    # The bridges: inner tangents from each disk to the next, A0's, every E, Dn's (their sides alternate).
    centres = [D.c[A0]] + [E for E, _ in disks] + [D.c[Dn]]
    sides = [float(D.side[A0])] + [s for _, _, _, s in chain] + [float(D.side[Dn])]
    phis, lengths = [], []
    for k in range(len(centres) - 1):
        u = centres[k + 1] - centres[k]
        d = math.hypot(u[0], u[1])
        if not d > 2.0 * r * (1 + 1e-9):
            return None
        phis.append(math.atan2(u[1], u[0]) + sides[k] * math.asin(2.0 * r / d))
        lengths.append(math.sqrt(d * d - 4 * r * r))
    # The turn at every disk of the chain, each the way of its side.
    turns = [_wrap(phis[0] - D.phi[D.prev[A0]])] + [_wrap(phis[k + 1] - phis[k]) for k in range(len(chain))] \
        + [_wrap(D.phi[Dn] - phis[-1])]
    # (Beside a step the mouth corner's turn is the bridge's business: `_bridge_steps` sets and checks it.)
    free = [not stepped[0]] + [True] * len(chain) + [not stepped[1]]
    if not all(t * sd > 0 or not f for t, sd, f in zip(turns, sides, free, strict=True)):
        return None
    # Each E's arc runs where E's disk touches the grow's (shrink's) corner: between its contacts.
    for k, ((E, how), (A, run, Dv, s)) in enumerate(zip(disks, chain, strict=True)):
        if how[0] == "mouth":
            _, nl, depth = how
            for phi in (phis[k], phis[k + 1]):
                if not -math.sin(phi) * nl[0] + math.cos(phi) * nl[1] > depth / r:
                    return None
            continue
        _, wall, through, forward, _ = how
        foot = math.atan2(*(-s * D.n[wall])[::-1])
        corner = math.atan2(*(D.v[through] - E)[::-1])
        lo, hi = (foot, corner) if forward else (corner, foot)
        span = (s * (hi - lo)) % _TWO_PI
        for phi in (phis[k], phis[k + 1]):
            touch = math.atan2(*(-s * np.array([-math.sin(phi), math.cos(phi)]))[::-1])
            at = (s * (touch - lo)) % _TWO_PI
            if not (at <= span + 1e-9 or at >= _TWO_PI - 1e-9):
                return None
    D.phi[A0], D.length[A0], D.theta[A0] = phis[0], lengths[0], turns[0]
    for k, ((_, run, _, s), (E, _), (_, _, at)) in enumerate(zip(chain, disks, trims, strict=True)):
        D.c[[x for x in run if D.side[x] == s]] = E
        D.phi[run], D.length[run], D.theta[run] = phis[k], 0.0, 0.0
        D.phi[run[run.index(at):]] = phis[k + 1]    # from E on (bends passed by after it), the bridge out
        D.length[at], D.theta[at] = lengths[k + 1], turns[k + 1]
    D.theta[Dn] = turns[-1]
    gone = [x for _, run, _, s in chain for x in run if D.side[x] != s]
    if not _slide_passed(D, gone):
        return None
    return trims, [A0] + [at for _, _, at in trims], gone


def _span_beyond(D: _Rings, A: int, run: list, Dv: int, s: float):
    """Span a notch (tab) whose disk E rests on a wall outside its mouth, when no disk of `_span_chain`
    fits: tangent to the edge leaving D, through A (D a slight bend the wall goes on beyond), or to the
    edge arriving at A, through D. The mouth corner on that wall is passed by: the loop runs from A's own
    disk on the inner tangent to E, around E, and on along the wall after D (or along the wall before A to
    E, around E, and on the inner tangent to D's disk). In place; ``(trims, bridged, passed)`` as
    `_span_chain`'s, or None.

    Cut from side s, and shown nearer than r to S (`_covered`): the offsets of the edges from A to D, the
    wall's offset up to E, the passed corner's whole arc and the other corner's arc beyond E.
    """
    r = D.r
    limit = r - D.tie
    mine = [x for x in run if D.side[x] == s]
    if not mine or _is_step(D, int(D.prev[A])) or _is_step(D, Dv):
        return None
    for after in (True, False):
        wall = Dv if after else int(D.prev[A])
        through, passed = (A, Dv) if after else (Dv, A)
        base = D.v[wall] + s * r * D.n[wall]
        x = _circle_hit(base, D.u[wall], D.v[through], r, first=not after)
        if x is None or not 0.0 <= x <= D.ell[wall]:
            continue
        E = base + x * D.u[wall]
        if not _closer_than(D, E[None], E[None], limit):
            break
    else:
        return None
    nxt, prv = D.next, D.prev
    # The kept mouth corner's disk touches its wall into the span, or slides along its outer wall.
    if after and D.t[A] > D.ell[A] and not _slide_mouth(D, A, int(prv[A]), run[0], True):
        return None
    if not after and D.t[Dv] > D.ell[run[-1]] and not _slide_mouth(D, Dv, Dv, run[-1], False):
        return None
    centres, start, sweep = D.arcs(int(s))
    k_of = np.cumsum(D.side != s) - 1               # index of a vertex's arc on side s
    pieces = _whole_offsets(D, [A] + run, s)
    pieces += _whole_arcs(D, [x for x in run if D.side[x] != s] + [passed], s, E)
    raw0, raw1 = base, D.v[nxt[wall]] + s * r * D.n[wall]
    pieces.append(("seg", (raw0, E), False, True, (wall,)) if after
                  else ("seg", (E, raw1), True, False, (wall,)))
    n = int(k_of[through])
    a0, sw = float(start[n]), float(sweep[n])
    at = _wrap(math.atan2(*(E - D.v[through])[::-1]) - a0)
    if at * sw < 0 or abs(at) > abs(sw):
        return None
    own = (int(prv[through]), int(through))
    if after:                                       # A's arc after E goes (toward the span)
        pieces.append(("arc", (D.v[through], a0 + at, sw - at), True, False, own))
        sweep[n] = at
    else:                                           # D's arc before E goes
        pieces.append(("arc", (D.v[through], a0, at), False, True, own))
        start[n], sweep[n] = a0 + at, sw - at
    if not _covered(D, pieces):
        return None
    # The bridge between E and the kept mouth corner's disk (of the other side: the inner tangent).
    X = A if after else Dv
    phi, span_len = _inner_tangent(D.c[X], E, float(D.side[X]), r) if after else _inner_tangent(E, D.c[X], s, r)
    if phi is None:
        return None
    along = float(D.phi[wall])
    if after:
        turn_x, turn_e = _wrap(phi - D.phi[prv[A]]), _wrap(along - phi)
    else:
        turn_e, turn_x = _wrap(phi - along), _wrap(D.phi[Dv] - phi)
    if not (turn_x * D.side[X] > 0 and turn_e * s > 0):
        return None
    # E's arc runs where E's disk touches the grow's (shrink's) corner: from the bridge's contact to the
    # foot on the wall (from the foot to the bridge's), within the directions of its two contacts.
    foot = math.atan2(*(-s * D.n[wall])[::-1])
    corner = math.atan2(*(D.v[through] - E)[::-1])
    lo, hi = (corner, foot) if after else (foot, corner)
    at = (s * (_touch(phi, s) - lo)) % _TWO_PI
    if not (at <= (s * (hi - lo)) % _TWO_PI + 1e-9 or at >= _TWO_PI - 1e-9):
        return None
    rep = mine[-1]
    D.c[mine] = E
    D.length[run] = D.theta[run] = 0.0
    D.phi[run] = phi if after else along
    D.phi[run[run.index(rep):]] = along if after else phi
    D.theta[rep] = turn_e
    D.theta[X] = turn_x
    D.theta[passed] = D.length[passed] = 0.0
    if after:
        D.phi[A], D.length[A] = phi, span_len
        D._fixed.append((rep, int(wall), float(x), None))           # on along the wall (`_fixed_pieces`)
        e = int(prv[A])
        D.length[e] = D.ell[e] - D.t[e] - D.t[A]
        bridged = [A, rep]
    else:
        D.phi[A] = along
        D.phi[rep], D.length[rep] = phi, span_len
        D._fixed.append((int(wall), int(wall), None, float(x)))
        D.length[Dv] = D.ell[Dv] - D.t[Dv] - D.t[nxt[Dv]]
        bridged = [wall, rep]
    e = int(prv[A]) if after else Dv
    gone = [x for x in run if D.side[x] != s] + [passed]
    if D.length[e] < -1e-12 * max(D.ell[e], r) or not _slide_passed(D, gone):
        return None
    return [(int(s), [A] + run, rep, [(wall, after)])], bridged, gone


def _whole_arcs(D: _Rings, corners: list, s: float, E: np.ndarray | None) -> list:
    """The arcs about ``corners`` on side s, as `_covered`'s pieces; unless E is None, each is left in
    `_Rings.arcs` as the point E (a sweep of 0 there, where the span's trimmed offsets are points too)."""
    centres, start, sweep = D.arcs(int(s))
    k_of = np.cumsum(D.side != s) - 1
    pieces = []
    for y in corners:
        n = int(k_of[y])
        own = (int(D.prev[y]), int(y))
        pieces.append(("arc", (D.v[y], float(start[n]), float(sweep[n])), False, False, own))
        if E is not None:
            centres[n] = E - D.r * np.array([math.cos(start[n]), math.sin(start[n])])
            sweep[n] = 0.0
    return pieces


def _span_walls(D: _Rings, A: int, run: list, Dv: int, s: float):
    """Span a notch (tab) by the disk E tangent to two edges on either side of it that turn by less than π:
    the wall from A or the edge before A, and the wall into D or the edge after D (a slot whose walls, past
    slight bends, close in to less than 2r; a mouth corner inside the grow's corner). As a run merged into
    one corner (`_merge_run`): the corners between the two edges are left out of the loop, those of side s
    at E, the others passed by. The loop runs from the first edge's start corner's disk along it to E,
    around E, and along the second edge to its end corner's disk; where E's foot comes before that disk's
    (a corner of the other side), on the inner tangent between the two disks instead, which must leave E
    between its two feet. In place (only once one fits); ``(trims, bridged, passed)`` as `_span_chain`'s,
    or None.

    Cut from side s, and shown nearer than r to S (`_covered`): the offsets of the edges between the two,
    their offsets beyond E, and the arcs about the corners passed by.
    """
    r = D.r
    tol = -1e-12 * r
    if _is_step(D, int(D.prev[A])) or _is_step(D, Dv):
        return None                                 # (beside a step: the main candidates only)
    for h, e in ((A, run[-1]), (A, Dv), (int(D.prev[A]), run[-1]), (int(D.prev[A]), Dv)):
        found = _tangent_disk(D, h, e, s)
        if found is None:
            continue
        E, back, on = found
        P, Q = int(h), int(D.next[e])                   # the corners whose disks the loop comes from, goes to
        # Along each edge, or on a bridge: the direction and length of the loop into E and out of it.
        phi_in, phi_out = float(D.phi[h]), float(D.phi[e])
        piece_h = D.ell[h] - D.t[P] - back
        piece_e = D.ell[e] - on - D.t[Q]
        bridge_in, bridge_out = piece_h < tol * D.ell[h], piece_e < tol * D.ell[e]
        # (A bridge only from the chain's own mouth corners: another's disk is not this span's to turn.)
        if bridge_in:
            if h != A or D.side[P] == s or D.t[P] > D.ell[h]:
                continue
            phi_in, len_in = _inner_tangent(D.c[P], E, float(D.side[P]), r)
        if bridge_out:
            if e != run[-1] or D.side[Q] == s or D.t[Q] > D.ell[e]:
                continue
            phi_out, len_out = _inner_tangent(E, D.c[Q], s, r)
        if phi_in is None or phi_out is None:
            continue
        turn = _wrap(phi_out - phi_in)
        turn_p = _wrap(phi_in - D.phi[D.prev[P]]) if bridge_in else D.theta[P]
        turn_q = _wrap(D.phi[Q] - phi_out) if bridge_out else D.theta[Q]
        if not (turn * s > 0 and turn_p * D.side[P] > 0 and turn_q * D.side[Q] > 0):
            continue
        # E's arc lies between its feet on h and e: on the boundary of the grow (shrink) there.
        foot_h = math.atan2(*(-s * D.n[h])[::-1])
        span = (s * (math.atan2(*(-s * D.n[e])[::-1]) - foot_h)) % _TWO_PI
        at = [(s * (_touch(phi, s) - foot_h)) % _TWO_PI for phi in (phi_in, phi_out)]
        if not all(x <= span + 1e-9 or x >= _TWO_PI - 1e-9 for x in at):       # at a foot: 0 or 2π
            continue
        mid = ([] if h == A else [A]) + run + ([] if e == run[-1] else [Dv])     # corners from h's end to e
        passed = [x for x in mid if D.side[x] != s]
        mine = [x for x in mid if D.side[x] == s]
        pieces = _whole_offsets(D, mid[:-1], s) + _whole_arcs(D, passed, s, None)
        pieces += [("seg", (E, D.v[D.next[h]] + s * r * D.n[h]), True, False, (int(h),)),
                   ("seg", (D.v[e] + s * r * D.n[e], E), False, True, (int(e),))]
        if not mine or not _covered(D, pieces):
            continue
        _whole_arcs(D, passed, s, E)
        rep = mine[-1]
        D.c[mine] = E
        D.length[mid] = D.theta[mid] = 0.0
        D.phi[mid] = phi_in
        D.phi[mid[mid.index(rep):]] = phi_out
        D.theta[rep] = turn
        bridged = []
        if bridge_in:
            D.phi[P], D.length[P], D.theta[P] = phi_in, len_in, turn_p
            bridged.append(P)
        else:
            D._fixed.append((P, int(h), None, float(D.ell[h] - back)))
        if bridge_out:
            D.length[rep], D.theta[Q] = len_out, turn_q
            bridged.append(rep)
        else:
            D._fixed.append((rep, int(e), float(on), None))
        if not _slide_passed(D, passed):
            return False
        return [(int(s), mid[:-1], rep, [(int(h), False), (int(e), True)])], bridged, passed
    return None


def _inner_tangent(p: np.ndarray, q: np.ndarray, side: float, r: float):
    """The inner tangent from the disk about p (of this side) to the one about q (of the other), each of
    radius r: its direction and length, or (None, None) if the disks come within 2r of each other."""
    u = q - p
    d = math.hypot(u[0], u[1])
    if not d > 2.0 * r * (1 + 1e-9):
        return None, None
    return math.atan2(u[1], u[0]) + side * math.asin(2.0 * r / d), math.sqrt(d * d - 4.0 * r * r)


def _touch(phi: float, s: float) -> float:
    """The direction from a disk of side s to where the loop, running in direction phi, touches it."""
    return math.atan2(-s * math.cos(phi), s * math.sin(phi))


def _tangent_disk(D: _Rings, h: int, e: int, s: float):
    """The disk on side s tangent to edges h and e (their directions turning the way of s by less than π),
    its centre r or more from every edge: ``(E, back, on)``, its feet ``back`` from h's end and ``on`` from
    e's start, both on their edges; or None."""
    r = D.r
    turn = _wrap(float(D.phi[e] - D.phi[h]))
    uh, ue = D.u[h], D.u[e]
    sine = uh[0] * ue[1] - uh[1] * ue[0]
    if not (turn * s > 0 and abs(sine) > 1e-9):
        return None
    w = D.v[e] - D.v[D.next[h]]
    # The lines meet at V = h's end + a·uh = e's start + b·ue.
    a = (w[0] * ue[1] - w[1] * ue[0]) / sine
    b = (w[0] * uh[1] - w[1] * uh[0]) / sine
    t = r * math.tan(0.5 * abs(turn))
    back, on = t - a, t + b
    if not (0 <= back <= D.ell[h] and 0 <= on <= D.ell[e]):
        return None
    V = D.v[D.next[h]] + a * uh
    E = V + (s * r / (1.0 + float(uh @ ue))) * (D.n[h] + D.n[e])
    if _closer_than(D, E[None], E[None], r - D.tie):
        return None
    return E, back, on


def _is_step(D: _Rings, e: int) -> bool:
    """Whether edge e joins corners of the two sides and is too short for both their tangents."""
    f = D.next[e]
    return bool(D.side[e] != D.side[f] and D.ell[e] - D.t[e] - D.t[f] < -1e-12 * max(D.ell[e], D.r))


def _slide_passed(D: _Rings, passed: list) -> bool:
    """The corners a span passes by keep their own disks, which shape the other side's offset curves: a
    disk whose tangent is longer than one of its edges (a step inside the span) slides along the other
    edge until it meets that edge's far end (`_slide_mouth`); False if it cannot."""
    for x in passed:
        nxt, prv = int(D.next[x]), int(D.prev[x])
        fwd, back = D.t[x] > D.ell[x], D.t[x] > D.ell[prv]
        if fwd and back or fwd and not _slide_mouth(D, x, prv, nxt, True) \
                or back and not _slide_mouth(D, x, x, prv, False):
            return False
    return True


def _fixed_pieces(D: _Rings) -> bool:
    """The straight pieces on the edges a span's disk E rests on (`_span_walls`, `_span_beyond`), once every
    span has moved its disks: from E's foot to the disk at the edge's other end; False if one is negative
    or an edge carries two feet."""
    edges = [edge for _, edge, _, _ in D._fixed]
    if len(set(edges)) < len(edges):
        return False
    for at, edge, start, end in D._fixed:
        lo = D.t[edge] if start is None else start
        hi = D.ell[edge] - D.t[D.next[edge]] if end is None else end
        D.length[at] = hi - lo
        if D.length[at] < -1e-12 * max(D.ell[edge], D.r):
            return False
    return True


def _arc_cut(start: float, sweep: float, at: float, keep_first: bool, toward: float, beta: float):
    """An arc (start, signed sweep) cut at angle ``at``: its part before (``keep_first``) or after, as
    ``(start, sweep)``; None unless ``at`` lies on it and the part removed lies in the open cap of
    directions within ``beta`` of ``toward``, ``at`` on the cap's edge."""
    cut = _wrap(at - start)
    if cut * sweep < 0 or abs(cut) > abs(sweep):
        return None
    edge = _wrap(at - toward)                       # ±β
    removed = sweep - cut if keep_first else -cut   # from ``at``, signed, to the far end of the part removed
    if abs(abs(edge) - beta) > 1e-9 or (removed != 0 and not abs(edge + removed) < beta):
        return None
    return (start, cut) if keep_first else (at, sweep - cut)


def _slide_mouth(D: _Rings, X: int, wall: int, corner: int, forward: bool) -> bool:
    """Slide the disk of a notch's (tab's) mouth corner X along the offset of its wall (the edge before A,
    forward; the edge after D, back) until it meets the run's end corner, as `_bridge_steps` slides a
    step's disk; in place, False if it cannot.

    On X's side the offset of the edge from X to the corner is gone, and the arc about the corner starts
    (ends) at the moved centre. Removing them is sound where every point removed is nearer than r to the
    wall: the offset is checked as in `_covered`; the arc part removed must lie where the corner's circle
    dips below the wall's offset line (directions within β of the way to the wall) and project onto the
    wall segment.
    """
    r, side = D.r, float(D.side[X])
    base = D.v[X] + side * r * D.n[wall]
    x = _circle_hit(base, D.u[wall], D.v[corner], r, first=forward)
    if x is None or (x > 0 if forward else x < 0):
        return False
    c = base + x * D.u[wall]
    edge = X if forward else corner                 # the edge between X and the corner
    if not _covered(D, _whole_offsets(D, [edge], side)):
        return False
    height = float((D.v[corner] - D.v[X]) @ (side * D.n[wall]))   # the corner above the wall, on X's side
    if not 0 < height < 2 * r:
        return False
    down = -side * D.n[wall]
    beta = math.pi - math.acos((r - height) / r)
    centres, start, sweep = D.arcs(int(side))
    n = int(np.cumsum(D.side != side)[corner] - 1)
    at = math.atan2(c[1] - D.v[corner][1], c[0] - D.v[corner][0])
    a0, sw0 = float(start[n]), float(sweep[n])
    cut = _arc_cut(a0, sw0, at, not forward, math.atan2(down[1], down[0]), beta)
    if cut is None:
        return False
    # The part removed projects onto the wall segment: extremes at its ends or where it faces ±u.
    lo_a, span = (a0, _wrap(at - a0)) if forward else (at, sw0 - _wrap(at - a0))
    angles = [lo_a, lo_a + span]
    phi_u = math.atan2(D.u[wall][1], D.u[wall][0])
    for crit in (phi_u, phi_u + math.pi):
        k = _wrap(crit - lo_a)
        if k * span > 0 and abs(k) < abs(span):
            angles.append(crit)
    base_proj = float((D.v[corner] - D.v[wall]) @ D.u[wall])
    proj = [base_proj + r * math.cos(a - phi_u) for a in angles]
    if not (min(proj) >= 0 and max(proj) <= D.ell[wall]):
        return False
    start[n], sweep[n] = cut
    D.c[X] = c
    D.t[X] = -x if forward else x                   # its tangent point on the wall, from X
    D.spans.append((int(side), [edge], X))
    return True


def _whole_offsets(D: _Rings, edges: list, s: float) -> list:
    """The offsets by r of ``edges`` to side s, end to end, as `_covered`'s pieces (no end kept)."""
    return [("seg", (D.v[e] + s * D.r * D.n[e], D.v[D.next[e]] + s * D.r * D.n[e]), False, False, (int(e),))
            for e in edges]


def _bridges_clear(D: _Rings) -> bool:
    """No bridge comes nearer than r to the shrink's boundary or the grow's, but where it is tangent to its
    own two disks: exact distances to every piece of both sides' offset curves (`_pieces`)."""
    from ._pieces import piece_distance, piece_distances

    r, i = D.r, D.bridged
    if D.dropped is not None:
        i = i[~D.dropped[i]]
    j = D.next[i]
    if D.dropped is not None:
        while D.dropped[j].any():                       # a tangent passes the dropped corners by
            j = np.where(D.dropped[j], D.next[j], j)
    nrm = np.column_stack([-np.sin(D.phi[i]), np.cos(D.phi[i])])
    P = D.c[i] - (D.side[i] * r)[:, None] * nrm
    Q = D.c[j] - (D.side[j] * r)[:, None] * nrm
    limit = r - D.tie
    rows, kinds = [], []
    for side in (1, -1):
        a, b = D._offset_ends(side)
        rows.append(np.column_stack([a, b, np.zeros(len(a))]))
        kinds.append(np.zeros(len(a), bool))
        centres, start, sweep = D.arcs(side)
        rows.append(np.column_stack([centres, np.full(len(centres), r), start, sweep]))
        kinds.append(np.ones(len(centres), bool))
    pieces, arc = np.concatenate(rows), np.concatenate(kinds)
    # Candidates: the segments themselves, each arc by its circle's box (from all pairs of boxes on a small
    # shape, else from an R-tree).
    if len(P) * len(pieces) <= _ALL_PAIRS:
        lo = np.where(arc[:, None], pieces[:, :2] - r, pieces[:, :2])
        hi = np.where(arc[:, None], pieces[:, :2] + r, pieces[:, 2:4])
        bi, m = _boxes_within(P, Q, lo, hi, limit + 1e-9 * r)
    else:
        box = shapely.box(pieces[:, 0] - r, pieces[:, 1] - r, pieces[:, 0] + r, pieces[:, 1] + r)
        point = ~arc & (pieces[:, 0] == pieces[:, 2]) & (pieces[:, 1] == pieces[:, 3])   # a trimmed offset
        geoms = np.where(arc, box, np.where(point, shapely.points(pieces[:, :2]),
                                            shapely.linestrings(pieces[:, :4].reshape(-1, 2, 2))))
        bi, m = shapely.STRtree(geoms).query(shapely.linestrings(np.stack([P, Q], axis=1)),
                                             predicate="dwithin", distance=limit + 1e-9 * r)
    if not len(bi):
        return True
    seg = np.column_stack([P[bi], Q[bi], np.zeros(len(bi))])
    d = piece_distances(np.zeros(len(bi), bool), seg, arc[m], pieces[m])
    # The vectorised distances are right to a few ulps of the coordinates: those clearly at least the
    # limit are set aside (a bridge rests on its own disks' pieces at r, a tie above r − tie), the others
    # are decided by the closed form, one by one.
    size = 1.0 + r + float(np.abs(pieces[:, :2]).max())
    doubt = ~(d >= limit + 8 * np.finfo(float).eps * size)
    for b, k in zip(bi[doubt].tolist(), m[doubt].tolist()):
        other = ("arc", (pieces[k, :2], r, pieces[k, 3], pieces[k, 4])) if arc[k] else \
            ("seg", (pieces[k, :2], pieces[k, 2:4]))
        if piece_distance(("seg", (P[b], Q[b])), other)[0] < limit:
            return False
    return True


# -- certificates: the offset curves do not touch themselves ---------------------------------------------
# Why a curve that does not touch itself settles the distance tests (exact arithmetic; `_CONTACT` covers the
# rounding). Side +1; side −1 is the same outside S.
#
# C, the raw offset curve of a ring, is the ring's edges moved by r into S and cut at the disks' centres
# (`_Rings.offsets`) joined by the arcs of radius r around the reflex vertices (`_Rings.arcs`); consecutive
# pieces meet at their common end only (at a centre the turn is below π, an arc is tangent to its
# segments), and every point of C is at distance exactly r from the edge or vertex it comes from. Let
# f = dist(·, ∂S) − r on C, so f ≤ 0. Where f < 0 next to a point q of C with f(q) = 0, some other edge
# (or reflex vertex) is at distance exactly r from q, and its nearest point y is where the disk of radius r
# around q touches ∂S, from inside S: y is inside the edge, in its part that C keeps (a point of the rest,
# within r·tan(θ/2) of a convex end, has the neighbouring edge nearer than r), or a reflex vertex whose
# normal cone holds q − y. Either way q lies on the piece of C that comes from y too: two pieces of C that
# are not consecutive meet at q. So if no two such pieces come within `_CONTACT` of each other, f is 0 all
# along each closed curve or negative all along it, and one point of each, tested exactly, tells which.
# Then every disk centre of that side is at distance r from ∂S, and so is every straight piece moved by r.
#
# Given that, C (all rings) is the boundary of the shrink K, and the core is the set of points nearer than
# r to K. L, the ring with its convex corners replaced by their arcs, is C moved back by r; let
# g = dist(·, K) − r on L, so g ≤ 0, and g = 0 on ∂S (each disk around a point of K lies in S), which L
# meets at every tangent point. A point q of an arc where g becomes negative next to it is at distance r
# from a point z of K other than the arc's centre (K near that centre is the wedge of its two pieces, which
# is no nearer), so q also lies on the piece of L that comes from z: again two pieces of L that are not
# consecutive meet. If none come within `_CONTACT`, no arc enters the core.
#
# The checks look at the pieces near each piece only (`_separated`: boxes of blocks of consecutive pieces,
# whole runs of a chain that goes one way settled at once), so they cost a few sweeps over the pieces,
# however closely a ring runs at distance r from another part of S; the exact tests' balls of radius r
# graze the ring at every vertex (~45 s for a million vertices). When a check fails (pieces that touch or
# nearly do, very short pieces) the caller runs the exact distance tests instead, which decide.

_CONTACT = 1e-7       # pieces closer than this (× r) count as touching: 100× the exact tests' slack


def _offset_certified(D: _Rings, S, side: int) -> bool:
    """Whether the raw offset curves of this side provably keep distance r from every edge of S."""
    if (D.length <= _CONTACT * D.r).any():
        return False                          # a piece too short for its direction to be sure
    chain = _offset_chain(D, side)
    if not _separated(*chain, _CONTACT * D.r):
        return False
    # One point of each ring's curve, the start of its first straight piece, decides the sign of f there.
    f = D._first
    p0 = np.where((D.side[f] == side)[:, None], D.c[f], D.v[f] + side * D.radius(side) * D.n[f])
    if (shapely.contains_xy(S, p0[:, 0], p0[:, 1]) != (side > 0)).any():
        return False
    limit = D.radius(side) - D.tie
    if len(p0) * len(D.v) > 4_000_000:
        return not _closer_than(D, p0, p0, limit)
    # Few rings: every edge against every point, without building the k-d tree. An edge whose start is
    # farther than limit + its length from the point (beyond any rounding) is farther than limit from it.
    a = D.v
    reach = (limit + D.ell) * (1 + 1e-9) + 1e-12 * (1.0 + float(np.abs(a).max()))
    reach *= reach
    for x in p0:
        dx, dy = a[:, 0] - x[0], a[:, 1] - x[1]
        near = np.flatnonzero(dx * dx + dy * dy <= reach)
        if not (_point_segment_distances(x[None, :], a[near], D.v[D.next[near]]) >= limit).all():
            return False
    return True


def _rounded_certified(D: _Rings) -> bool:
    """Whether no arc of a certified side (`_offset_certified`) can enter the core (+1) or the anticore (−1).

    One chain serves both sides (`_rounded_chain`): every corner's arc, each followed by its whole outgoing
    edge. The rings with only the convex (or only the reflex) corners rounded are made of these arcs and
    parts of these edges, with the same pieces next to each other, so if this chain does not touch itself
    neither do they.
    """
    return _separated(*_rounded_chain(D), _CONTACT * D.r)


# A chain (`_separated`) is returned as chord ends ``A``, ``B`` ((m, 2), stored a coordinate at a time, in
# Fortran order, as `_separated` reads them), how far each piece may stray from its chord (``fat``, the
# sagitta of an arc; > 0 marks the arcs), the index of the next piece of the same ring and of the first
# piece of each piece's ring. The pieces of a ring follow one another, from the arc (if any) at its first
# vertex. The ends are built a coordinate at a time: several times faster than rows.

def _rounded_chain(D: _Rings):
    """Every vertex's arc (between its tangent points) followed by the whole edge that leaves it."""
    nv, t = len(D.v), D.t
    m = 2 * nv
    A, B, fat = np.empty((m, 2), order="F"), np.empty((m, 2), order="F"), np.zeros(m)
    for col in (0, 1):
        v, u = D.v[:, col], D.u[:, col]
        np.subtract(v, t * D._pred(u), out=A[0::2, col])
        A[1::2, col] = v
        np.add(v, t * u, out=B[0::2, col])
        B[1::2, col] = D._succ(v)
    np.maximum(D.sagitta, 1e-300, out=fat[0::2])
    return (A, B, fat) + _links(2 * D._first, m)


def _offset_chain(D: _Rings, side: int):
    """The raw offset curves of this side (see the comment above `_offset_certified`): at vertex i the
    arc around it if its disk is on the other side, then edge i moved by r (`_Rings.offsets`).

    Each piece ends where the next starts: the arc around vertex k runs from where the offset of the edge
    arriving at k ends to where that of the edge leaving k starts (both r from k, along the edges'
    normals), and a segment ends at the next vertex's disk centre or where the next arc starts. So the
    chain is built from the points where its pieces meet, each piece's end being the next one's start.
    """
    mine = D.side == side
    k = np.flatnonzero(~mine)
    seg_at = np.cumsum(2 - mine) - 1                # index of edge i's segment; its arc, if any, just before
    m = int(seg_at[-1]) + 1
    arc_at = seg_at[k] - 1
    kp = D.prev[k]
    shift = side * D.radius(side) * D.n
    A, B, fat = np.empty((m, 2), order="F"), np.empty((m, 2), order="F"), np.zeros(m)
    for col in (0, 1):
        v, sh = D.v[:, col], shift[:, col]
        a = v + sh                                  # `_Rings.offsets`: the segments' starts
        np.copyto(a, D.c[:, col], where=mine)
        A[seg_at, col] = a
        A[arc_at, col] = v[k] + sh[kp]              # where the offset of edge prev[k] ends
    fat[arc_at] = np.maximum(D.arc_sagitta(side, k), 1e-300)
    starts = seg_at[D._first] - (~mine[D._first])
    nxt, first = _links(starts, m)
    B[:-1] = A[1:]
    B[np.append(starts[1:], m) - 1] = A[starts]
    return A, B, fat, nxt, first


def _links(starts: np.ndarray, m: int):
    """``nxt`` and ``first`` of a chain of m pieces whose rings start at ``starts``."""
    nxt = np.arange(1, m + 1)
    nxt[np.append(starts[1:], m) - 1] = starts        # the last piece of a ring is followed by its first
    if len(starts) == 1:
        return nxt, np.zeros(m, np.int64)
    return nxt, np.repeat(starts, np.diff(np.append(starts, m)))


def _separated(A: np.ndarray, B: np.ndarray, fat: np.ndarray, nxt: np.ndarray, first: np.ndarray,
               eps: float) -> bool:
    """Whether every two pieces that are not consecutive are at least ``eps`` apart.

    Piece i lies within ``fat[i]`` of the segment A[i]→B[i] (``fat > 0`` marks an arc); the distance
    between two pieces is bounded below by that of their segments minus both ``fat``. The two segments on
    either side of an arc are exempt too: they are tangent to its circle at its ends and run away from each
    other (its sweep is below π), so they are the arc's chord apart, however short it is. The pieces of a
    ring are stored one after another (``nxt[i] = i + 1`` but at the ring's last piece, whose ``nxt`` is
    its first, ``first[i]``).

    Each piece is bounded by the disk around its chord's midpoint of radius half the chord plus ``fat``;
    two pieces whose disks are more than ``eps`` apart pass. The pairs whose disks come nearer get the
    segment test: all of them, found by a search that only prunes pairs whose disks provably stay apart
    (`_near_pairs`).
    """
    mx, my = 0.5 * (A[:, 0] + B[:, 0]), 0.5 * (A[:, 1] + B[:, 1])
    if len(A) <= _ALL_PIECES:
        return _separated_few(A, B, fat, nxt, mx, my, eps)
    # Batch by batch: a chain that touches itself is usually found out in the first.
    for i, j in _near_pairs(A, B, fat, nxt, first, mx, my, eps):
        # Neighbours are exempt, and so are the two pieces on either side of an arc.
        ni, nj = nxt[i], nxt[j]
        across_i, across_j = np.where(fat[ni] > 0, nxt[ni], ni), np.where(fat[nj] > 0, nxt[nj], nj)
        keep = (ni != j) & (nj != i) & (across_i != j) & (across_j != i)
        i, j = i[keep], j[keep]
        rho = 0.5 * np.hypot(B[i, 0] - A[i, 0], B[i, 1] - A[i, 1]) + fat[i]
        rho_j = 0.5 * np.hypot(B[j, 0] - A[j, 0], B[j, 1] - A[j, 1]) + fat[j]
        dx, dy = mx[i] - mx[j], my[i] - my[j]
        reach = rho + rho_j + eps
        keep = dx * dx + dy * dy <= reach * reach
        i, j = i[keep], j[keep]
        if len(i):
            gap = _segment_distances(A[i], B[i], A[j], B[j]) - fat[i] - fat[j]
            if not (gap >= eps).all():
                return False
    return True


_ALL_PIECES = 128     # `_separated` pairs every two pieces of a chain of at most this many


def _separated_few(A, B, fat, nxt, mx, my, eps: float) -> bool:
    """`_separated` of a short chain (a building's footprint): every pair of pieces, no search (its blocks
    and windows would cost more than the pairs they prune). The same tests, the disks' first."""
    m = len(A)
    if m < 3:
        return True
    i, j = _upper_pairs(m)
    rho = 0.5 * np.hypot(B[:, 0] - A[:, 0], B[:, 1] - A[:, 1]) + fat
    dx, dy = mx[i] - mx[j], my[i] - my[j]
    reach = rho[i] + rho[j] + eps
    keep = dx * dx + dy * dy <= reach * reach
    i, j = i[keep], j[keep]
    ni, nj = nxt[i], nxt[j]
    across_i, across_j = np.where(fat[ni] > 0, nxt[ni], ni), np.where(fat[nj] > 0, nxt[nj], nj)
    keep = (ni != j) & (nj != i) & (across_i != j) & (across_j != i)
    i, j = i[keep], j[keep]
    if not len(i):
        return True
    gap = _segment_distances(A[i], B[i], A[j], B[j]) - fat[i] - fat[j]
    return bool((gap >= eps).all())


@functools.lru_cache(maxsize=_ALL_PIECES + 1)
def _upper_pairs(m: int):
    """``np.triu_indices(m, 1)``, made once for each m (read only)."""
    i, j = np.triu_indices(m, 1)
    i.flags.writeable = j.flags.writeable = False
    return i, j
_TOP_BLOCKS = 8192    # `_near_pairs` starts from blocks of at least 32 pieces, and about this many blocks
_EXPAND = 1 << 14     # … and pairs all their pieces at once when that makes no more pairs than this
_ROUNDING = 1e-12     # × the chain's extent: more than the rounding of every bound `_near_pairs` prunes by


def _near_pairs(A: np.ndarray, B: np.ndarray, fat: np.ndarray, nxt: np.ndarray, first: np.ndarray,
                mx: np.ndarray, my: np.ndarray, eps: float):
    """Pairs ``i < j`` of pieces of `_separated`'s chain that may be ``eps`` or less apart, in batches.

    Yields arrays ``(i, j)``: every pair whose bounding disks (midpoint ``(mx, my)``, radius half the chord
    plus ``fat``) come within ``eps`` of each other is among them, but for neighbours and pieces with an
    arc between them; pairs found to be farther apart, beyond any rounding, are left out.

    The search runs down a hierarchy of blocks of consecutive pieces (2**L of them at level L), each with
    the box of its pieces' disks. It starts from every block of the top level paired with itself and with
    the blocks whose boxes come within ``eps`` of its own (a k-d tree over the boxes' centres), and splits
    a pair of blocks into the pairs of their halves, down to pieces, unless

    * their boxes are more than ``eps`` apart, or
    * both lie in a *straight window*: two neighbouring blocks of one ring whose pieces' chain runs in one
      direction. Let m_k be the midpoints, s_k = m_{k+1} − m_k the steps between them and ρ_k the disks'
      radii. If the angles of the window's steps span 2β < π, all of them lie within β of the middle
      direction d, and for pieces i < j of the window ``|m_j − m_i| ≥ (m_j − m_i)·d ≥ cos β · Σ_{i≤k<j}
      |s_k|``. For j ≥ i + 3 the sum holds |s_i| + |s_{i+1}| + |s_{j−1}|, for j = i + 2 the first two.
      As ``cos β · x − ρ ≥ (x − ρ) − (1 − cos β)·x``, the window's minima of ``|s_i| + |s_{i+1}| − ρ_i``,
      ``|s_{j−1}| − ρ_j`` and ``|s_i| + |s_{i+1}| − ρ_i − ρ_{i+2}`` (but for pieces with an arc between
      them, which are exempt) and maxima of ``|s_i| + |s_{i+1}|`` and ``|s_{j−1}|`` bound every pair's
      ``|m_j − m_i| − ρ_i − ρ_j`` from below. If that bound exceeds ``eps``, no two pieces of the window
      other than neighbours are near.

    On pieces strung along smooth curves the top level's windows are straight, and the search ends
    there; it goes down only where the chain turns sharply or comes back near itself. Every bound is
    computed with a margin (`_ROUNDING`) above its rounding, so that no pair whose disks the caller's test
    finds to meet is pruned.
    """
    m = len(A)
    if m < 3:
        return
    pieces = _Pieces(A, B, fat, nxt, first, mx, my)
    top = min(max(5, (m // _TOP_BLOCKS).bit_length()), m.bit_length() - 2)
    full = {top: _Blocks(pieces, top)}
    # Every box holds its pieces' ends: the margin scales with the largest coordinate.
    extent = max(float(np.abs(x).max()) for x in (full[top].x0, full[top].x1, full[top].y0, full[top].y1))
    slack = eps + _ROUNDING * extent
    a_top, b_top = _top_pairs(full[top], slack)
    batch = max(4096, -(-len(a_top) // 8))
    for k in range(0, len(a_top), batch):
        a, b = a_top[k:k + batch], b_top[k:k + batch]
        for level in range(top, 0, -1):
            if len(a) * (1 << (2 * level)) <= _EXPAND:
                a, b = _pieces_of(a, b, level, m)    # few pairs left: all their pieces' pairs at once
                break
            n = -(-m >> level)
            if level in full or 8 * len(a) > n:
                if level not in full:
                    full[level] = _Blocks(pieces, level, keep=level > 1)
                blocks = full[level]
            else:                                   # few pairs left: only the blocks they need
                same = a == b
                ids = np.unique(np.concatenate([a, b, a[same] - 1, a[same] + 1]))
                blocks = _Blocks(pieces, level, ids[(ids >= 0) & (ids < n)])
            # A block with itself is settled by a straight window on either side; two neighbours by theirs.
            same = a == b
            ahead = blocks.straight(a, slack)
            keep = np.where(same, ~(blocks.straight(a - 1, slack) | ahead),
                            ~(((b == a + 1) & ahead) | blocks.apart(a, b, slack)))
            a, b = _children(a[keep], b[keep], -(-m >> (level - 1)))
        keep = (a != b) & ~pieces.apart(a, b, slack)
        a, b = a[keep], b[keep]
        dx, dy = mx[a] - mx[b], my[a] - my[b]
        reach = pieces.rho[a] + pieces.rho[b] + slack
        keep = dx * dx + dy * dy <= reach * reach
        if keep.any():
            yield a[keep], b[keep]


class _Pieces:
    """Per piece of a chain (`_near_pairs`): its disk, and the terms of the straight windows on demand.

    The terms (`_TERMS`) are made one after another and reduced to blocks as they come (`_Blocks`), so
    that few arrays as long as the chain are alive at once; those of a few pieces are made from their
    neighbours' midpoints (`terms_at`).
    """

    def __init__(self, A, B, fat, nxt, first, mx, my):
        self.m, self.first, self.mx, self.my, self.fat = len(A), first, mx, my, fat
        self._nxt, self._end = nxt, np.flatnonzero(nxt != np.arange(1, len(A) + 1))
        rho = B[:, 0] - A[:, 0]
        rho *= rho
        hy = B[:, 1] - A[:, 1]
        hy *= hy
        rho += hy
        del hy
        np.sqrt(rho, out=rho)
        rho *= 0.5
        rho += fat
        self.rho = rho
        self.terms = None                   # all pieces' terms, kept once a lower level needs them all

    def _succ(self, x: np.ndarray) -> np.ndarray:
        """``x[nxt]``, copied in one sweep but at the rings' ends."""
        y = np.empty_like(x)
        y[:-1] = x[1:]
        y[self._end] = x[self._nxt[self._end]]
        return y

    def _succ2(self, x: np.ndarray) -> np.ndarray:
        """``x[nxt[nxt]]``, copied in one sweep but at the last two pieces of each ring."""
        y = np.empty_like(x)
        y[:-2] = x[2:]
        e = self._end
        at = np.concatenate([e, e[e > 0] - 1])    # all that is two ahead of a ring's last piece, and more
        y[at] = x[self._nxt[self._nxt[at]]]
        return y

    def _pred(self, x: np.ndarray) -> np.ndarray:
        """``x[prev]``, where ``nxt[prev[i]] = i``."""
        y = np.empty_like(x)
        y[1:] = x[:-1]
        y[self._nxt[self._end]] = x[self._end]
        return y

    def each_term(self):
        """Yield ``(name, array)`` for every term of every piece, one term at a time.

        The terms: the direction ``psi`` of the step s_i = m_{i+1} − m_i, ``two`` = |s_i| + |s_{i+1}|,
        ``back`` = |s_{i−1}|, ``two_rho`` = two − ρ_i, ``back_rho`` = back − ρ_i and ``span`` =
        two − ρ_i − ρ_{i+2} (∞ with an arc between). An array is overwritten once the next is asked for.
        """
        mx, my, rho = self.mx, self.my, self.rho
        sx, sy = self._ahead(mx, np.subtract), self._ahead(my, np.subtract)
        yield "psi", np.arctan2(sy, sx)
        sx *= sx
        sy *= sy
        sx += sy
        del sy
        step = np.sqrt(sx, out=sx)
        two = self._ahead(step, np.add)
        yield "two", two
        back = self._pred(step)
        del step, sx
        yield "back", back
        back -= rho
        yield "back_rho", back
        two -= rho
        yield "two_rho", two
        span = two
        span -= self._succ2(rho)
        span[self._succ(self.fat) > 0] = np.inf
        yield "span", span

    def _ahead(self, x: np.ndarray, op) -> np.ndarray:
        """``op(x[nxt], x)`` in one sweep (but at the rings' ends)."""
        y = np.empty_like(x)
        op(x[1:], x[:-1], out=y[:-1])
        e = self._end
        y[e] = op(x[self._nxt[e]], x[e])
        return y

    def terms_at(self, idx: np.ndarray) -> dict:
        """Make the terms (see `each_term`) of the pieces ``idx`` from their neighbours' midpoints."""
        mx, my, rho = self.mx, self.my, self.rho
        # The piece before: the previous one, or at a ring's first piece the ring's last.
        p, j = idx - 1, self._nxt[idx]
        start = self.first[idx] == idx
        p[start] = self._end[np.searchsorted(self._end, idx[start])]
        jj = self._nxt[j]

        def steps(a, b):
            sx, sy = mx[b] - mx[a], my[b] - my[a]
            return sx, sy, np.sqrt(sx * sx + sy * sy)

        sx, sy, step = steps(idx, j)
        two = steps(j, jj)[2] + step
        back = steps(p, idx)[2]
        span = two - rho[idx] - rho[jj]
        span[self.fat[j] > 0] = np.inf
        return {"psi": np.arctan2(sy, sx), "two": two, "back": back, "back_rho": back - rho[idx],
                "two_rho": two - rho[idx], "span": span}

    def apart(self, a: np.ndarray, b: np.ndarray, slack: float) -> np.ndarray:
        """Whether the boxes of the disks of pieces a and b are more than ``slack`` apart, pair by pair."""
        ra, rb = self.rho[a], self.rho[b]
        out = np.zeros(len(a), bool)
        for c in (self.mx, self.my):
            ca, cb = c[a], c[b]
            out |= np.maximum(ca - ra, cb - rb) - np.minimum(ca + ra, cb + rb) > slack
        return out


# How `_Blocks` reduces each term of `_Pieces` over a block: to the least or the greatest.
_TERMS = {"psi": None, "two": np.maximum, "back": np.maximum, "back_rho": np.minimum, "two_rho": np.minimum,
          "span": np.minimum}


class _Blocks:
    """Blocks of 2**level consecutive pieces: all of them, or those numbered ``ids`` (sorted).

    Each has the box of its pieces' disks, the range of its steps' directions, the minima and maxima of
    the window terms (see `_near_pairs`) and the ring of its first and of its last piece. Looked up by
    block number.
    """

    def __init__(self, pieces: _Pieces, level: int, ids: np.ndarray | None = None, keep: bool = False):
        size, m = 1 << level, pieces.m
        self.n, self.ids, self._straight = -(-m // size), ids, None
        if ids is None:
            starts = np.arange(0, m, size)

            def reduce(op, x):
                return op.reduceat(x, starts)

            if pieces.terms is not None:
                terms = pieces.terms.items()
            elif keep:                              # a lower level will need them too
                pieces.terms = {name: x.copy() for name, x in pieces.each_term()}
                terms = pieces.terms.items()
            else:
                terms = pieces.each_term()
            mx, my, rho = pieces.mx, pieces.my, pieces.rho
        else:
            # The pieces of each block (the last of a short block repeated: minima and maxima only).
            starts = ids * size
            at = np.minimum(starts[:, None] + np.arange(size), np.minimum(starts + size, m)[:, None] - 1)
            shape, at = at.shape, at.ravel()

            def reduce(op, x):
                return op.reduce(x.reshape(shape), axis=1)

            terms = pieces.terms_at(at).items()
            mx, my, rho = pieces.mx[at], pieces.my[at], pieces.rho[at]
        lo, hi = np.minimum, np.maximum
        r = reduce(hi, rho)
        self.x0, self.x1 = reduce(lo, mx) - r, reduce(hi, mx) + r
        self.y0, self.y1 = reduce(lo, my) - r, reduce(hi, my) + r
        for name, x in terms:
            if _TERMS[name] is None:
                self.psi0, self.psi1 = reduce(lo, x), reduce(hi, x)
            else:
                setattr(self, name, reduce(_TERMS[name], x))
        self.ring0 = pieces.first[starts]
        self.ring1 = pieces.first[np.minimum(starts + size, m) - 1]

    def _at(self, k: np.ndarray) -> np.ndarray:
        return k if self.ids is None else np.searchsorted(self.ids, k)

    def straight(self, k: np.ndarray, slack: float) -> np.ndarray:
        """Whether the window of blocks k and k + 1 is straight (see `_near_pairs`); False off the ends."""
        if self.ids is None:
            if self._straight is None:
                self._straight = np.zeros(self.n + 1, bool)
                every = np.arange(self.n - 1)
                self._straight[:self.n - 1] = self._windows(every, every + 1, slack)
            return self._straight[k]            # k = −1 reads the last entry: False
        ok = (k >= 0) & (k + 1 < self.n)
        out = np.zeros(len(k), bool)
        if ok.any():
            out[ok] = self._windows(self._at(k[ok]), self._at(k[ok] + 1), slack)
        return out

    def _windows(self, p: np.ndarray, q: np.ndarray, slack: float) -> np.ndarray:
        """`straight` of the windows made of the blocks stored at p and q."""
        # Every step's direction is within β, half the range of their angles, of the range's middle
        # (padded beyond the rounding of the angles, so that cos β is below the cosine of the true β).
        beta = (np.maximum(self.psi1[p], self.psi1[q]) - np.minimum(self.psi0[p], self.psi0[q])) \
            * (0.5 * (1.0 + 1e-9)) + 1e-12
        loss = 1.0 - np.cos(np.minimum(beta, 1.5))
        two = np.maximum(self.two[p], self.two[q]) * loss
        head = np.minimum(self.two_rho[p], self.two_rho[q]) - two
        tail = np.minimum(self.back_rho[p], self.back_rho[q]) - np.maximum(self.back[p], self.back[q]) * loss
        span = np.minimum(self.span[p], self.span[q]) - two
        return (self.ring0[p] == self.ring1[q]) & (beta < 1.5) & (head + tail > slack) & (span > slack)

    def apart(self, a: np.ndarray, b: np.ndarray, slack: float) -> np.ndarray:
        """Whether the boxes of blocks a and b are more than ``slack`` apart, pair by pair."""
        a, b = self._at(a), self._at(b)
        return ((np.maximum(self.x0[a], self.x0[b]) - np.minimum(self.x1[a], self.x1[b]) > slack)
                | (np.maximum(self.y0[a], self.y0[b]) - np.minimum(self.y1[a], self.y1[b]) > slack))


def _top_pairs(lv: _Blocks, slack: float):
    """Every block paired with itself and with each block whose box comes within ``slack`` of its own."""
    n = lv.n
    if n <= 64:                                 # few blocks: every pair of them
        a, b = np.triu_indices(n)
        keep = (a == b) | ~lv.apart(a, b, slack)
        return a[keep], b[keep]
    cx, cy = 0.5 * (lv.x0 + lv.x1), 0.5 * (lv.y0 + lv.y1)
    ext = np.maximum(lv.x1 - lv.x0, lv.y1 - lv.y0) * 0.5 * (1.0 + 1e-12)
    h = max(min(float(ext.max()), 2.0 * float(np.percentile(ext, 95))), slack)
    small = np.flatnonzero(ext <= h)
    found = [np.column_stack([np.arange(n), np.arange(n)])]
    if len(small) > 1:
        # Boxes of half-extent ≤ h within ``slack``: centres within 2h + slack in both coordinates, so
        # within √2 of that (a Euclidean search is several times faster than one in the maximum norm).
        tree = _tree(np.column_stack([cx[small], cy[small]]))
        found.append(small[tree.query_pairs(1.5 * (2.0 * h + 2.0 * slack), output_type="ndarray")])
    big = np.flatnonzero(ext > h)
    if len(big):
        # The few larger boxes against all others (the box test below settles them).
        other = np.arange(n)
        for chunk in np.array_split(big, max(1, len(big) * n // 4_000_000)):
            a = np.repeat(chunk, n)
            b = np.tile(other, len(chunk))
            keep = a != b
            found.append(np.column_stack([a[keep], b[keep]]))
    a, b = np.concatenate(found).T
    a, b = np.minimum(a, b), np.maximum(a, b)
    keep = (a == b) | ~lv.apart(a, b, slack)
    return a[keep], b[keep]


def _pieces_of(a: np.ndarray, b: np.ndarray, level: int, m: int):
    """List the pairs ``i < j`` of pieces (of m) of the pairs of blocks a ≤ b of this level."""
    size = 1 << level
    i = (a[:, None] * size + np.arange(size))[:, :, None]
    j = (b[:, None] * size + np.arange(size))[:, None, :]
    i, j = np.broadcast_arrays(i, j)
    keep = (i < j) & (j < m)
    return i[keep], j[keep]


def _children(a: np.ndarray, b: np.ndarray, n: int):
    """Pairs of blocks split into the pairs of their halves (blocks 2a, 2a + 1 of the level below, of n)."""
    same = a == b
    a0, b0 = 2 * a, 2 * b
    ca = np.concatenate([a0, a0, a0 + 1, a0 + 1])
    cb = np.concatenate([b0, b0 + 1, b0, b0 + 1])
    # Of a block with itself: (2a, 2a), (2a, 2a+1), (2a+1, 2a+1); of two blocks all four.
    no = np.zeros(len(a), bool)
    keep = ~np.concatenate([no, no, same, no]) & (ca < n) & (cb < n)
    return ca[keep], cb[keep]


def _segment_distances(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances between segments p→q and a→b, row by row (0 where they cross)."""

    def orient(o, u, v):
        return (u[:, 0] - o[:, 0]) * (v[:, 1] - o[:, 1]) - (u[:, 1] - o[:, 1]) * (v[:, 0] - o[:, 0])

    dist = _point_segment_distances(p, a, b)
    if p is q:
        # Points: the distances from a and b to the point p are its distances to them (the same numbers
        # as `_point_segment_distances(a, p, p)`), and a point crosses nothing.
        np.minimum(dist, np.hypot(a[:, 0] - p[:, 0], a[:, 1] - p[:, 1]), out=dist)
        np.minimum(dist, np.hypot(b[:, 0] - p[:, 0], b[:, 1] - p[:, 1]), out=dist)
        return dist
    np.minimum(dist, _point_segment_distances(q, a, b), out=dist)
    np.minimum(dist, _point_segment_distances(a, p, q), out=dist)
    np.minimum(dist, _point_segment_distances(b, p, q), out=dist)
    cross = (orient(p, q, a) * orient(p, q, b) < 0) & (orient(a, b, p) * orient(a, b, q) < 0)
    dist[cross] = 0.0
    return dist


def _tree(points: np.ndarray) -> cKDTree:
    """A k-d tree split at sliding midpoints rather than medians: on points strung along curves, and with
    queries at a fixed distance from them, its boxes hug the curve and searches visit several times fewer
    of them (about 6× faster on a 100k-vertex ring)."""
    return cKDTree(points, balanced_tree=False, compact_nodes=False)


#: Below this many pairs the exact distance tests (`_closer_than`, `_points_near_segments`,
#: `_points_near_arcs`) compute the distance of every pair; above it they search k-d trees and R-trees for
#: the pairs that can be near enough, and compute those distances with the same formulas.
_ALL_PAIRS = 1 << 13


def _boxes_within(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray, limit: float):
    """Every pair ``(i, k)`` of a segment p→q and a segment a→b (points where the ends are equal) whose
    bounding boxes are less than ``limit`` apart in both coordinates, beyond any rounding.

    Two segments whose boxes are ``limit`` or more apart in one coordinate are at least that far apart;
    the margin (1e-9 of ``limit`` and 1e-12 of the largest coordinate) is more than the rounding of the
    distances computed for the other pairs, so no pair whose computed distance is below ``limit`` is left
    out. All pairs are formed: for few segments (see `_ALL_PAIRS`).
    """
    reach = limit * (1 + 1e-9) + 1e-12 * (1.0 + max(float(np.abs(p).max()), float(np.abs(q).max()),
                                                    float(np.abs(a).max()), float(np.abs(b).max())))
    near = None
    for col in (0, 1):
        lo, hi = np.minimum(p[:, col], q[:, col]), np.maximum(p[:, col], q[:, col])
        lo2, hi2 = np.minimum(a[:, col], b[:, col]), np.maximum(a[:, col], b[:, col])
        ok = (lo2[None, :] - hi[:, None] < reach) & (lo[:, None] - hi2[None, :] < reach)
        near = ok if near is None else near & ok
    return np.nonzero(near)


def _closer_than(D: _Rings, p: np.ndarray, q: np.ndarray, limit: float, known=None) -> bool:
    """Whether any edge of S comes closer than ``limit`` to any of the segments p→q (points when p = q).

    Exact, and fast on dense rings, in two passes:

    1. the end points. An edge shorter than h that comes within ``limit`` of a point x has an end within
       sqrt(limit² + h²/4) of x (at the edge's point nearest x the edge is perpendicular to the way to x);
       a k-d tree over the vertices finds the few candidates in that thin shell;
    2. the interiors, once no edge comes near an end. An edge point y within ``limit`` of the segment
       whose nearest segment point is interior lies within sqrt(limit² + half²) of the midpoint (half =
       half the segment's length), so by the same argument the edge has an end within
       sqrt(limit² + half² + h²/4) of the midpoint. This ball hugs the segment's neighbourhood minus the
       end disks: its shell is (half² + h²/4)/(2·limit) thick, not half + h²/(8·limit), which keeps the
       candidates few even where the ring runs at nearly distance ``limit`` for a long way (a ring whose
       curvature radius is close to r).

    The rare edges longer than h are tested with an STRtree. ``known``, a pair of boolean arrays, marks
    ends already found at least ``limit`` from every edge (disk centres); pass 1 skips them.

    With at most `_ALL_PAIRS` pairs of a segment and an edge (a small shape), neither pass is needed: every
    pair whose boxes come within ``limit`` (`_boxes_within`) gets its exact distance, the same formula.
    """
    edge_a, edge_b = D.v, D.v[D.next]
    if len(p) * len(edge_a) <= _ALL_PAIRS:
        # Few of both (a building's footprint): every segment against every edge whose box is near.
        i, e = _boxes_within(p, q, edge_a, edge_b, limit)
        if not len(i):
            return False
        x = p[i]
        y = x if p is q or np.array_equal(p, q) else q[i]        # points: `_segment_distances` knows
        return bool((_segment_distances(x, y, edge_a[e], edge_b[e]) < limit).any())
    # The shell sqrt(limit² + h²/4) − limit ≈ h²/(8·limit) is thin when h is near the typical edge length.
    h = float(np.clip(2.0 * np.percentile(D.ell, 95), limit / 1024, limit / 8))
    short = D.ell <= h
    if short.any():
        tree = D.vertex_tree
        segment = (p != q).any(axis=1)
        p_known, q_known = known if known is not None else (np.zeros(len(p), bool), np.zeros(len(q), bool))
        ends = np.concatenate([p[~p_known], q[segment & ~q_known]])
        if _near_short_edges(D, tree, ends, ends, np.zeros(len(ends)), limit, h, short):
            return True
        if segment.any():
            a, b = p[segment], q[segment]
            half = 0.5 * np.hypot(*(b - a).T)
            if _near_short_edges(D, tree, a, b, half, limit, h, short):
                return True
    if (~short).any():
        long_edges, tree = D.edge_tree(~short)
        # A point is probed as a point: a segment of length 0 (p = q) has no extent the tree can match,
        # and `STRtree.query` then finds no edge near it at all.
        point = (p == q).all(axis=1)
        probes = np.empty(len(p), dtype=object)
        probes[point] = shapely.points(p[point])
        probes[~point] = shapely.linestrings(np.stack([p[~point], q[~point]], axis=1))
        hits = tree.query(probes, predicate="dwithin", distance=limit)
        if hits.shape[1]:
            i, j = hits
            e = long_edges[j]
            if (_segment_distances(p[i], q[i], edge_a[e], edge_b[e]) < limit).any():
                return True
    return False


def _near_short_edges(D: _Rings, tree: cKDTree, p: np.ndarray, q: np.ndarray, half: np.ndarray,
                      limit: float, h: float, short: np.ndarray) -> bool:
    """Whether an edge of length ≤ h comes closer than ``limit`` to a segment p→q, testing the edges at
    the vertices within sqrt(limit² + half² + h²/4) of each midpoint (see `_closer_than`)."""
    mid = 0.5 * (p + q)
    edge_a, edge_b = D.v, D.v[D.next]
    # Group the segments by length (within a factor of two) so that each ball query has a tight radius.
    level = np.floor(np.log2(np.maximum(half, 1e-300))).astype(np.int64)
    order = np.lexsort((np.arange(len(half)), level))
    cuts = np.flatnonzero(np.diff(level[order])) + 1
    groups = np.split(order, cuts)
    for chunk in groups:
        if len(chunk) == 0:
            continue
        radius = math.sqrt(limit * limit + float(half[chunk].max()) ** 2 + 0.25 * h * h)
        hits = _tree(mid[chunk]).sparse_distance_matrix(tree, radius, output_type="ndarray")
        if len(hits) == 0:
            continue
        seg, vert = chunk[hits["i"]], hits["j"]
        # The two edges at each candidate vertex: the one leaving it and the one arriving.
        for e in (vert, D.prev[vert]):
            s, e = seg[short[e]], e[short[e]]
            # Most candidates are settled by the edge's line: a segment with both ends on one side of
            # it, at least ``limit`` away, is that far from the edge too. The rest get the exact distance.
            ea, d = edge_a[e], edge_b[e] - edge_a[e]
            sp = (d[:, 0] * (p[s, 1] - ea[:, 1]) - d[:, 1] * (p[s, 0] - ea[:, 0]))
            sq = (d[:, 0] * (q[s, 1] - ea[:, 1]) - d[:, 1] * (q[s, 0] - ea[:, 0]))
            reach = limit * np.hypot(d[:, 0], d[:, 1])
            far = ((sp >= reach) & (sq >= reach)) | ((sp <= -reach) & (sq <= -reach))
            s, e = s[~far], e[~far]
            if len(s) and (_segment_distances(p[s], q[s], edge_a[e], edge_b[e]) < limit).any():
                return True
    return False


def _arcs_clear(D: _Rings, side: int) -> bool:
    """No arc of this side enters the core (side +1, convex vertices) or the anticore (side −1, reflex
    vertices) elsewhere.

    Decided from the edges of S, not from GEOS's opening and closing (which simplify dense input by up to
    r/100). A point x of a convex vertex's arc lies within r of that vertex, so not in the shrink; it is
    in the (open) core exactly when it is closer than r to the shrink, that is to the shrink's boundary.
    That boundary is made of points at distance exactly r from the boundary of S: on the edges moved
    inwards by r or on circles of radius r around vertices, and of those only the edges cut at the disks'
    centres and the arcs around the reflex vertices (`_Rings.offsets`, `_Rings.arcs`) can be in the
    shrink; the rest is closer than r to a neighbouring edge. So an arc point at distance ≥ r from all of
    them is outside the core. Reflex vertices likewise, outside S, against the grow. The arcs are tested
    at points every π/16 at most (slightly outside their own disk, which the pieces at its centre touch).
    """
    r = D.radius(side)
    mine = D.side == side
    if D.dropped is not None:
        mine &= ~D.dropped                               # not on the loop
    mine = np.flatnonzero(mine)
    if len(mine) == 0:
        return True
    m = np.maximum(2, np.ceil(np.abs(D.theta[mine]) / (math.pi / 16)).astype(np.int64))
    owner = np.repeat(mine, m - 1)
    first = np.repeat(np.cumsum(m - 1) - (m - 1), m - 1)
    frac = (np.arange(len(owner)) - first + 1) / np.repeat(m, m - 1)
    a0 = D.phi[D.prev[owner]] - side * (math.pi / 2)
    th = a0 + D.theta[owner] * frac
    # Just outside its own disk (by rounding-proof 1e-8·r): the pieces that meet at the disk's centre are
    # then no nearer than r, and only another part of the shrink's (grow's) boundary can come nearer.
    x = D.c[owner] + (r * (1 + 1e-8)) * np.column_stack([np.cos(th), np.sin(th)])
    limit = r - D.tie
    if _points_near_segments(x, *D._offset_ends(side), limit):       # `_Rings.offsets`, start and end
        return False
    centres, start, sweep = D.arcs(side)
    return not (len(centres) and _points_near_arcs(x, centres, start, sweep, r, limit))


def _point_segment_distances(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances from points x to segments a→b, row by row (a point where a = b)."""
    ax, ay = a[:, 0], a[:, 1]
    dx, dy = b[:, 0] - ax, b[:, 1] - ay
    wx, wy = x[:, 0] - ax, x[:, 1] - ay
    L2 = dx * dx + dy * dy
    # The nearest point's parameter along the segment, clamped to it; 0 for a point (d = 0: any t would do).
    t = wx * dx
    t += wy * dy
    t /= np.where(L2 > 0, L2, 1.0)
    np.clip(t, 0.0, 1.0, out=t)
    dx *= t
    dy *= t
    wx -= dx
    wy -= dy
    return np.hypot(wx, wy)


def _points_near_segments(x: np.ndarray, a: np.ndarray, b: np.ndarray, limit: float) -> bool:
    """Whether any point x comes closer than ``limit`` to any segment a→b (exact).

    A segment of length ≤ h within ``limit`` of x has its midpoint within sqrt(limit² + h²/4) of x (at
    the segment's point nearest x, the segment is perpendicular to the way to x, or that point is an end);
    a k-d tree over the midpoints gives the candidates. Longer segments go to an STRtree. With at most
    `_ALL_PAIRS` pairs, the candidates are every pair whose boxes come within ``limit`` (`_boxes_within`).
    """
    if len(x) * len(a) <= _ALL_PAIRS:
        i, k = _boxes_within(x, x, a, b, limit)
        return bool(len(i)) and bool((_point_segment_distances(x[i], a[k], b[k]) < limit).any())
    L = np.hypot(*(b - a).T)
    h = float(np.clip(2.0 * np.percentile(L, 95), limit / 1024, limit / 8))
    short = L <= h
    if short.any():
        idx = np.flatnonzero(short)
        mid = 0.5 * (a[idx] + b[idx])
        radius = math.sqrt(limit * limit + 0.25 * h * h)
        hits = _tree(x).sparse_distance_matrix(_tree(mid), radius, output_type="ndarray")
        if len(hits):
            i, k = hits["i"], idx[hits["j"]]
            if (_point_segment_distances(x[i], a[k], b[k]) < limit).any():
                return True
    if (~short).any():
        idx = np.flatnonzero(~short)
        hits = shapely.STRtree(shapely.linestrings(np.stack([a[idx], b[idx]], axis=1))).query(
            shapely.points(x), predicate="dwithin", distance=limit)
        if hits.shape[1]:
            i, k = hits[0], idx[hits[1]]
            if (_point_segment_distances(x[i], a[k], b[k]) < limit).any():
                return True
    return False


def _points_near_arcs(x: np.ndarray, centres: np.ndarray, start: np.ndarray, sweep: np.ndarray, r: float,
                      limit: float) -> bool:
    """Whether any point x comes closer than ``limit`` to any arc of radius r (centre, start angle, signed
    sweep), exactly: the distance to the circle where x's direction from the centre falls within the arc,
    to the nearer end otherwise. Candidates: arcs whose midpoint is within limit + the half-arc's chord
    (from k-d trees, or, with at most `_ALL_PAIRS` pairs, from all of them)."""
    half = 0.5 * sweep
    mid = centres + r * np.column_stack([np.cos(start + half), np.sin(start + half)])
    reach = limit + float((2.0 * r * np.abs(np.sin(0.5 * half))).max())
    if len(x) * len(centres) <= _ALL_PAIRS:
        # Few of both: the same candidates from all pairs, without the trees.
        dx, dy = x[:, 0, None] - mid[None, :, 0], x[:, 1, None] - mid[None, :, 1]
        i, k = np.nonzero(dx * dx + dy * dy <= reach * reach)
    else:
        hits = _tree(x).sparse_distance_matrix(_tree(mid), reach, output_type="ndarray")
        i, k = hits["i"], hits["j"]
    if len(i) == 0:
        return False
    p, c = x[i], centres[k]
    rel = p - c
    # Angle of x from the centre, measured from the arc's start in the sweep's direction.
    ang = np.arctan2(rel[:, 1], rel[:, 0]) - start[k]
    ang = np.where(sweep[k] >= 0, ang, -ang) % (2.0 * math.pi)
    inside = ang <= np.abs(sweep[k])
    d_circle = np.abs(np.hypot(*rel.T) - r)
    e0 = c + r * np.column_stack([np.cos(start[k]), np.sin(start[k])])
    e1 = c + r * np.column_stack([np.cos(start[k] + sweep[k]), np.sin(start[k] + sweep[k])])
    d_ends = np.minimum(np.hypot(*(p - e0).T), np.hypot(*(p - e1).T))
    return bool((np.where(inside, d_circle, d_ends) < limit).any())


def _reaches_edges(D: _Rings, S, side: int) -> bool:
    """The offset curves of this side are the boundary of the shrink (side +1) or of the grow (−1): then
    the core's (anticore's) boundary is made of one ring for each ring of S, and every straight piece
    lies on it.

    Needed for ``init="core"`` (the core's rings must be the rings of S) and, with both sides, for
    ``"mason"``, where the certificate (`_offset_certified`) has not shown it. Every point of the
    boundary of the shrink is exactly r from S and lies on the raw offset curves (the comment above
    `_offset_certified`); if, conversely, every point of those curves (as `_bridge_steps` left them) is
    at least r from S, they are that boundary, one closed curve for each ring. Where they are not — a
    neck of S narrower than 2r, which parts the core into two, leaves arcs about its two reflex corners
    that cross each other nearer than r to S — the general engine takes S. Decided exactly from the edges
    of S: `_closer_than` for the segments, the closed forms of `_pieces` for the arcs.
    """
    r = D.radius(side)
    limit = r - D.tie
    a, b = D._offset_ends(side)
    # One point of each ring's curve on the right side of S, and each segment no nearer than r to S.
    f = D._first
    p0 = 0.5 * (a[f] + b[f])
    if (shapely.contains_xy(S, p0[:, 0], p0[:, 1]) != (side > 0)).any():
        return False
    if _closer_than(D, a, b, limit):
        return False
    centres, start, sweep = D.arcs(side)
    if not len(centres):
        return True
    k = np.flatnonzero(D.side != side)                 # the vertex each arc is about
    # The edges near each arc's box (every pair whose boxes come within the limit on a small shape).
    if len(centres) * len(D.v) <= _ALL_PAIRS:
        ai, ej = _boxes_within(centres - r, centres + r, D.v, D.v[D.next], limit)
    else:
        boxes = shapely.box(centres[:, 0] - r, centres[:, 1] - r, centres[:, 0] + r, centres[:, 1] + r)
        ai, ej = D.edge_tree()[1].query(boxes, predicate="dwithin", distance=limit)
    # An arc's own two edges end at its centre: r from all of it.
    other = (ej != k[ai]) & (ej != D.prev[k[ai]])
    ai, ej = ai[other], ej[other]
    if not len(ai):
        return True
    arc_rows = np.column_stack([centres, np.full(len(centres), r), start, sweep])[ai]
    seg_rows = np.column_stack([D.v[ej], D.v[D.next[ej]], np.zeros(len(ej))])
    return _far_enough(arc_rows, seg_rows, limit, 1.0 + r + float(np.abs(D.v).max()))


def _far_enough(arcs: np.ndarray, segs: np.ndarray, limit: float, size: float) -> bool:
    """Whether each arc row is at least ``limit`` from the segment row beside it (`_pieces` rows):
    vectorised, then the closed form one by one where the vectorised distance is within rounding."""
    from ._pieces import piece_distance, piece_distances

    d = piece_distances(np.ones(len(arcs), bool), arcs, np.zeros(len(segs), bool), segs)
    doubt = ~(d >= limit + 8 * np.finfo(float).eps * size)
    for x, y in zip(arcs[doubt], segs[doubt]):
        if piece_distance(("arc", (x[:2], x[2], x[3], x[4])), ("seg", (y[:2], y[2:4])))[0] < limit:
            return False
    return True
