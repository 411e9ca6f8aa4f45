"""The exact r-tightening of a polygonal shape.

Pipeline (see DESIGN §4):

1. Morphology in a local frame (the shape translated and scaled to unit size): shrink ``E = S↓r``, grow
   ``G = S↑r``, core ``R``, fillet ``F``, and the exact centres of the arcs of radius r (`arc_centers`).
2. Initial loops, by ``init``: the rings of the core, of S, or of Mason(S).
3. Each loop is tightened in its homotopy class in the mortar: the free space (the mortar thickened by a
   tiny δ, so that its zero-width parts have room) is triangulated, the loop's sleeve is reduced and the
   funnel algorithm gives the shortest closed polygon in the class.
4. Exact finish: each corner of that polygon is mapped to the disk of radius r it wraps (its exact
   centre and side); the loop becomes a cyclic sequence of disks joined by common tangents. Disks whose arc
   would turn the wrong way are dropped and disks that a tangent or arc enters are added, until stable.
5. Surgery: where two tight loops (or two far-apart parts of one) touch, the set they bound has a cusp
   (the paper's Figure 7). The loops are reconnected there — two loops merge, one loop splits — and the
   new loops are tightened again. Each surgery shortens the total boundary, so this ends.
6. The result holds the exact loops (segments and arcs of radius exactly r), the shapely geometry sampled
   from them, and exact perimeter and area.

A faster path handles the common case where every corner of S is isolated: each vertex then gets its own
disk (inside at a convex vertex, outside at a reflex one), and the loop is certified with the same checks
as the exact finish, without any triangulation.

Between the two, for ``init="core"``, the general engine first looks for the tight loops without the free
space: from the exact shrink's boundary where it has no holes, part of the core by part (`_shrink_parts`;
a part not shown goes alone through steps 3–5), else round the guide core's parts that are annuli of the
mortar (`_annulus_loops`). Each loop so found is the exact finish's from a guess, kept only where it is
shown to be the one the free space would give; the rest go through steps 3–5.
"""

from __future__ import annotations

import enum
import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import MultiLineString, MultiPolygon, Polygon

from . import _convex, _fast
from . import morphology as _m
from ._pieces import piece_distance, piece_distances
from ._proximity import EdgeIndex, PointIndex, point_segment_distance
from ._guard import core_vanishes, guarded_tighten
from ._validation import check_output_size, check_radius, check_resolution, check_shape, check_tolerance, \
    quad_segs_for
from .centers import ArcCenters, boundary_edges, exact_centers, missing_lines, snap_onto, snap_window
from ._zero_radius import zero_entries
from .curves import Arc, Loop, Segment, arc_sweeps, tangent_directions
from .errors import ConvergenceWarning
from .geodesic import Triangulation, closed_geodesic, sleeve, triangulate
from .offsets import precision_of, shrink_is_empty
from .tolerances import CENTRE_ROUNDING_R, CORNER_ANGLE, DOMAIN_CHORD_R, EXACT_CHORD_R, GUIDE_MISSING_R, \
    OBSTACLE_SAG_R, THICKEN_R, TOUCH_SCALE, VERIFY_DEPTH_R, ZERO_SCALE, rounding_length

__all__ = ["Init", "Tightening", "tighten"]

_TWO_PI = 2.0 * math.pi
_ANGLE_EPS = 1e-9
_MAX_FINISH_STEPS = 200
_MAX_SURGERY_ROUNDS = 64
_OBSTACLE_BOX_PAIRS = 1 << 18    # `_Context.oindex`: up to this many pairs, candidates by boxes
# `_annulus_loops`: the anticore disks within this many r of the core's boundary start the finish, which
# gets this many rounds of exact checks (the loops it settles on took at most four on every family).
_ANNULUS_REACH = 3.0
_ANNULUS_ROUNDS = 6
#: … and is given up at once if its first round finds this fraction of its pieces entering or more (the
#: jagged star at 10k: 35 of 64 after its first drops, then 1, then none; half gave it up).
_FAR_OFF = 0.75


class Init(str, enum.Enum):
    """Initial condition of the flow (the paper's §3 and §4.2)."""

    CORE = "core"
    INPUT = "input"
    MASON = "mason"


# ---------------------------------------------------------------------------------------------------------
# Local frame
# ---------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Frame:
    """``local = (world − origin) / scale``: the shape centred at 0 with unit size."""

    ox: float
    oy: float
    scale: float

    @classmethod
    def of(cls, S) -> _Frame:
        x0, y0, x1, y1 = S.bounds
        return cls(0.5 * (x0 + x1), 0.5 * (y0 + y1), max(x1 - x0, y1 - y0))

    def to_local(self, geom):
        return shapely.transform(geom, lambda c: (c - (self.ox, self.oy)) / self.scale)

    def to_world(self, geom):
        return shapely.transform(geom, lambda c: c * self.scale + (self.ox, self.oy))

    def loop_to_world(self, loop: Loop) -> Loop:
        return loop.affine(self.scale, self.ox, self.oy)


# ---------------------------------------------------------------------------------------------------------
# Context: everything about S and r that the loops are tightened against
# ---------------------------------------------------------------------------------------------------------
class _Context:
    def __init__(self, S: Polygon | MultiPolygon, r: float, tolerance: float, precision: float | None = None,
                 radii: tuple[float, float] | None = None):
        self.S = S
        self.r = r
        # Two radii (a, b) (`two_radii`): the core disks (side +1, the centres' region S↓a) have radius a,
        # the anticore disks (side −1, (S^c)↓b) radius b; r is then the larger, the scale of every
        # tolerance. With one radius a = b = r, and every expression below is the one-radius one.
        self.ra, self.rb = (r, r) if radii is None else (float(radii[0]), float(radii[1]))
        self.two = self.ra != self.rb
        # A radius 0 on one side (`_zero_radius`): its disks are S's own vertices, its region S (side +1)
        # or S's complement (−1), which the loop may not enter; ``zero`` is that side, else 0.
        self.zero = 0 if min(self.ra, self.rb) > 0 else (1 if self.ra == 0 else -1)
        # Two precisions: the shrink and grow whose vertices give the exact centres and against which the
        # exact loops are checked are sampled finely (EXACT_CHORD_R·r); the core, fillet and thickened
        # mortar that only guide the search for the homotopy class coarsely (a tenth of the thickening).
        self.delta = THICKEN_R * ((min(self.ra, self.rb) or max(self.ra, self.rb)) if self.two else r)
        self.q_exact = quad_segs_for(r, EXACT_CHORD_R * r)
        self.sag = r * (1.0 - math.cos(math.pi / (4 * self.q_exact)))
        self.q = quad_segs_for(r, DOMAIN_CHORD_R * r)
        self.sag_dom = r * (1.0 - math.cos(math.pi / (4 * self.q)))
        self.tol_int = 0.1 * self.delta
        # A piece may come closer than r to an exact centre only by rounding; to an edge of the buffered
        # shrink or grow by their own inaccuracy (chords, and GEOS's placement of offset vertices).
        # The judge is exact: the centres are the corners of S's exact offsets (`offsets`), the obstacles
        # their pieces (arcs by chords within OBSTACLE_SAG_R·r), inside tests S's exact clearance. GEOS's
        # buffers E and G only guide the search for each loop's homotopy class (the free space).
        self.centers: ArcCenters
        self.centers, self.xE, self.xG = exact_centers(S, self.ra, precision,
                                                       r_concave=self.rb if self.two else None)
        self.precision = self.xE.precision
        self.pen_center = max(1e-10 * r, 4.0 * self.precision)
        obstacle_angle = 2.0 * math.sqrt(2.0 * OBSTACLE_SAG_R)
        # Obstacle chords lie within osag of their arcs: a query drawn osag wider finds every piece within
        # r − pen_center of an obstacle, and each find is then decided by the exact piece distance.
        self.osag = OBSTACLE_SAG_R * r
        self.pen = 2.0 * self.osag + self.pen_center
        self._EG = None                       # GEOS's shrink and grow, built on first use (`E`, `G`)
        self.cxy, self.cside = _distinct_centers(self.centers.xy, self.centers.side.astype(np.int64), r)
        self._index_centres()
        self._s_edges = None
        if self.zero:
            self._index_zero_vertices()
        edges, kinds, owners, self.opieces = [], [], [], []
        for kind, X in ((1, self.xE), (-1, self.xG)):
            if X.r == 0:
                continue          # a radius 0: no distance obstacle (`_zero_radius.zero_entries` instead)
            xy, start = X.polyline_points(obstacle_angle)  # the straight pieces first, then the arcs
            if len(start) > 1:
                # The chords of every polyline: from each point that is not its polyline's last.
                owner = np.repeat(np.arange(len(start) - 1), np.diff(start) - 1)
                first = np.arange(len(owner)) + owner      # point index of each chord's start
                edges.append(np.stack([xy[first], xy[first + 1]], axis=1))
                kinds.append(np.full(len(owner), kind, dtype=np.int8))
                owners.append(owner + len(self.opieces))
            self.opieces += [(kind, ("seg", (p, q))) for p, q in X.seg]
            self.opieces += [(kind, ("arc", (c, X.r, a0, sw))) for c, a0, sw in
                             zip(X.arc_center, X.arc_start, X.arc_sweep)]
        self.oedges = np.concatenate(edges) if edges else np.zeros((0, 2, 2))
        self.okind = np.concatenate(kinds) if kinds else np.zeros(0, dtype=np.int8)
        self.opiece = np.concatenate(owners) if owners else np.zeros(0, dtype=np.int64)   # edge → opieces
        shapely.prepare(self.S)
        self.S_boundary = self.S.boundary
        shapely.prepare(self.S_boundary)
        a, b, _ = boundary_edges(S)
        self._s_tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
        # The obstacle edges for the finish's grazing queries (see `_proximity`). The queries are a loop's
        # tangents and arc chords, few against many short chords: candidates by boxes up to more pairs
        # than the default (on footprints, 2.1 ms against the trees' 3.4 ms per context).
        self.oindex = EdgeIndex(self.oedges[:, 0], self.oedges[:, 1], r, box_pairs=_OBSTACLE_BOX_PAIRS)
        self._R = None
        self._F = None
        self._side_loops: dict = {}           # `side_loops`, by side
        self.guide_free = False               # every loop shown without the guide core and fillet
        self._domain = None
        self.violation_cache: dict = {}       # `_violations` outcomes by piece, for the exact finish

    # -- morphology, lazily ------------------------------------------------------------------------------
    # GEOS's shrink E and grow G guide the search; `verify()` on a fast-path result never needs them.
    @property
    def E(self):
        return self._guide_offsets()[0]

    @property
    def G(self):
        return self._guide_offsets()[1]

    def _guide_offsets(self):
        if self._EG is None:
            # S's exact shrink and grow sampled (`morphology._sampled`), where they can be built.
            E = _m._sampled(self.S, self.ra, self.q_exact, "shrink", self.xE, lambda: self.side_loops(1)) \
                if self.ra > 0 else self.S
            G = _m._sampled(self.S, self.rb, self.q_exact, "grow", self.xG, lambda: self.side_loops(-1)) \
                if self.rb > 0 else self.S
            if E is not None and G is not None:
                self._EG = (_m._orient(E), _m._orient(G))
                return self._EG
            if self.zero:
                E = _m._orient(self.S if self.ra == 0 else _m._offsets(self.S, self.ra, self.q_exact)[0])
                G = _m._orient(self.S if self.rb == 0 else _m._offsets(self.S, self.rb, self.q_exact)[1])
            elif self.two:
                E, G = _m._orient(_m._offsets(self.S, self.ra, self.q_exact)[0]), \
                    _m._orient(_m._offsets(self.S, self.rb, self.q_exact)[1])
            else:
                E, G = (_m._orient(P) for P in _m._offsets(self.S, self.r, self.q_exact))
            # Every convex vertex of GEOS's shrink (reflex vertex of its grow) stands for a corner of the
            # exact offsets, off by up to GEOS's simplification (about r/100, more beside near-tangent
            # necks): each is moved onto the nearest exact corner within `centers.snap_window`
            # (GUIDE_MISSING_R·r at least).
            window_a, window_b = (snap_window(self.S, x, self.q_exact) for x in (self.ra, self.rb))
            self._EG = (snap_onto(E, self.centers.xy[self.centers.side == 1], 1, window_a),
                        snap_onto(G, self.centers.xy[self.centers.side == -1], -1, window_b))
        return self._EG

    def side_loops(self, side: int):
        """The exact offsets of one side chained into loops (`exact_morphology._side_loops`: precision,
        pieces, cycles, isolated corners), once: `_shrink_loops` reads them, and the guide's sampled shrink
        and grow are built from them. Raises RuntimeError where the pieces do not close."""
        if side not in self._side_loops:
            from .exact_morphology import _side_loops

            try:
                self._side_loops[side] = _side_loops(self.S, self.ra if side > 0 else self.rb, side,
                                                     self.xE if side > 0 else self.xG)
            except RuntimeError as exc:
                self._side_loops[side] = exc
        got = self._side_loops[side]
        if isinstance(got, RuntimeError):
            raise got
        return got

    # The core and fillet here only guide the search for each loop's homotopy class: the free space is
    # the mortar thickened by δ, and every contact of a finished loop is decided by the exact centres. So
    # they need not contain or be contained in S to the last ulp, as the public `core` and `fillet` are
    # nudged to be; but they must to within δ, and GEOS's buffers simplify their input by up to r/100
    # (the shrink of the grow drops bumps of it, and then misses S by that much): the overlays with S stay.
    @property
    def R(self):
        if self._R is None and self.ra == 0:
            self._R = _m._orient(self.S)      # radius 0: the core is S
        if self._R is None:
            grown = _m._grow_raw(self.E, self.ra, self.q) if not self.E.is_empty else Polygon()
            extra = self._missing(self.xE, self.E)
            if extra is not None:
                grown = shapely.union(grown, extra.buffer(self.ra, quad_segs=self.q))
            # The exact pieces GEOS lost may reach past GEOS's fillet by GEOS's own error: the guide core
            # stays inside the guide fillet, so that the free space is a thickened mortar.
            self._R = _m._orient(_m._polygonal(shapely.intersection(shapely.intersection(grown, self.S), self.F)))
        return self._R

    @property
    def F(self):
        if self._F is None and self.rb == 0:
            self._F = _m._orient(self.S)      # radius 0: the fillet is S
        if self._F is None:
            F = shapely.union(_m._shrink_raw(self.G, self.rb, self.q), self.S)
            extra = self._missing(self.xG, None)
            if extra is not None:
                F = shapely.difference(F, shapely.difference(extra.buffer(self.rb, quad_segs=self.q), self.S))
            self._F = _m._orient(_m._polygonal(F))
        return self._F

    def _missing(self, X, P):
        """The exact offset pieces of one side that GEOS's buffer lacks (`centers.missing_lines`)."""
        if X.r == 0:
            return None
        return missing_lines(X, self.G if P is None else P, X.r, GUIDE_MISSING_R, math.pi / (2 * self.q))

    # -- free space ----------------------------------------------------------------------------------------
    def _build_domain(self):
        d = self.delta
        F_d = self.F.buffer(d, join_style="mitre", mitre_limit=10.0)
        R_d = self.R.buffer(-d, join_style="mitre", mitre_limit=10.0) if not self.R.is_empty else Polygon()
        M = _m._polygonal(shapely.difference(F_d, R_d))
        parts = list(shapely.get_parts(M))
        core_xy = shapely.get_coordinates(R_d) if not R_d.is_empty else np.zeros((0, 2))
        self._core_keys = np.sort(_point_keys(core_xy))
        self._domain = (parts, shapely.STRtree(parts), [None] * len(parts))

    def component_of(self, ring: np.ndarray) -> int:
        if self._domain is None:
            self._build_domain()
        parts, tree, _ = self._domain
        pts = shapely.points(ring[: min(len(ring), 8)])
        hits = tree.query(pts, predicate="within")
        if len(hits[1]) == 0:
            hits = tree.query(pts, predicate="intersects")
        if len(hits[1]) == 0:
            raise _EngineError("a loop lies outside the mortar")
        vals, counts = np.unique(hits[1], return_counts=True)
        return int(vals[np.argmax(counts)])

    def triangulation(self, k: int) -> tuple[Triangulation, np.ndarray]:
        parts, _, cache = self._domain
        if cache[k] is None:
            T = triangulate(parts[k])
            cache[k] = (T, self._vertex_centers(T))
        return cache[k]

    def _vertex_centers(self, T: Triangulation) -> np.ndarray:
        """Exact-centre index for each triangulation vertex that lies on an arc of the core or fillet."""
        out = np.full(len(T.xy), -1, dtype=np.int64)
        # The vertices that are the thickened core's own (equal coordinates), looked up among its sorted keys.
        keys, core = _point_keys(T.xy), self._core_keys
        at = np.minimum(np.searchsorted(core, keys), max(len(core) - 1, 0))
        is_core = (core[at] == keys) if len(core) else np.zeros(len(keys), dtype=bool)
        for side, mask in ((1, is_core), (-1, ~is_core)):
            kd, ids = self._kd[side]
            if kd is None or not mask.any():
                continue
            rad = self.ra if side > 0 else self.rb        # r itself with one radius
            want = rad - self.delta
            slack = 0.5 * self.delta + 4.0 * (rad * (1.0 - math.cos(math.pi / (4 * self.q))))
            d, j = kd.query(T.xy[mask])
            if rad == 0:
                # A radius 0: the vertex is S's own, mitred by δ (at most 10δ by the mitre limit).
                want, slack = 0.0, 12.0 * self.delta
            ok = np.abs(d - want) <= slack
            out[np.flatnonzero(mask)[ok]] = ids[j[ok]]
        return out

    # -- obstacles -----------------------------------------------------------------------------------------
    def joined(self, c1: int, c2: int, point) -> bool:
        """Whether the segment between centres ``c1`` and ``c2`` lies in the shrink (or grow) — it clears
        S's boundary by r — and ``point`` comes nearer than r to it."""
        seg = shapely.linestrings(self.cxy[[c1, c2]])
        rad = self.radius_of(int(self.cside[c1]))
        if shapely.distance(seg, point) >= rad - self.pen_center:
            return False
        x0, y0, x1, y1 = self.S.bounds
        tiny = ZERO_SCALE * max(x1 - x0, y1 - y0, self.r)
        # A nearest-neighbour search in the R-tree of S's edges, bounded by the distance: it stops at the
        # first edge found, whatever the density of edges around the segment.
        hit = self._s_tree.query_nearest(seg, max_distance=rad * (1 - 1e-9) - tiny, all_matches=False)
        return len(hit) == 0

    def clearance(self, xy: np.ndarray) -> np.ndarray:
        """Exact distance from each point to S's boundary."""
        _, d = self._s_tree.query_nearest(shapely.points(xy), return_distance=True, all_matches=False)
        return d

    def in_regions(self, xy: np.ndarray) -> np.ndarray:
        """Whether each point lies in the closed shrink of S (+1), of its complement (−1), or neither (0)."""
        if len(xy) == 0:
            return np.zeros(0, dtype=np.int8)
        inside = shapely.contains_xy(self.S, xy[:, 0], xy[:, 1])
        if self.zero:
            # A radius 0: strictly inside its region, beyond the rounding (the loop runs along S's edges).
            need = np.where(inside, self.ra, self.rb)
            clear = self.clearance(xy) >= np.where(need == 0, self.pen_center, need - self.precision)
        elif self.two:
            clear = self.clearance(xy) >= np.where(inside, self.ra, self.rb) - self.precision
        else:
            clear = self.clearance(xy) >= self.r - self.precision
        return np.where(clear, np.where(inside, 1, -1), 0).astype(np.int8)

    def _index_zero_vertices(self) -> None:
        """For a radius 0: each vertex of S (numbered as `centers.boundary_edges`) and its centre, if any."""
        a, _, _ = boundary_edges(self.S)
        self._zero_vertex = {}
        for j, key in enumerate(map(tuple, a.tolist())):
            self._zero_vertex.setdefault(key, j)
        self.zero_vertex_centre = np.full(len(a), -1, dtype=np.int64)
        for ci in np.flatnonzero(self.cside == self.zero).tolist():
            j = self._zero_vertex.get(tuple(self.cxy[ci].tolist()), -1)
            if j >= 0:
                self.zero_vertex_centre[j] = ci

    def zero_vertex_at(self, x) -> int:
        """The vertex of S at exactly ``x`` (its number), or −1."""
        return self._zero_vertex.get((float(x[0]), float(x[1])), -1)

    def radius_of(self, side):
        """The disks' radius of a side (+1: a, −1: b), or of each side in an array; r with one radius."""
        if not self.two:
            return self.r
        if np.ndim(side) == 0:
            return self.ra if side > 0 else self.rb
        return np.where(np.asarray(side) > 0, self.ra, self.rb)

    def _add_centres(self, xy: np.ndarray, side: int) -> None:
        """Append exact centres of one side, and rebuild what is indexed on the centres."""
        self.cxy = np.concatenate([self.cxy, xy])
        self.cside = np.concatenate([self.cside, np.full(len(xy), side, dtype=np.int64)])
        self._index_centres()
        self.violation_cache.clear()

    def _index_centres(self) -> None:
        """The centres indexed: an R-tree, a k-d tree a side, by coordinates, and for grazing queries."""
        self.ctree = shapely.STRtree(shapely.points(self.cxy)) if len(self.cxy) else None
        self._kd = {s: (cKDTree(self.cxy[self.cside == s]) if (self.cside == s).any() else None,
                        np.flatnonzero(self.cside == s)) for s in (1, -1)}
        self.ckd = cKDTree(self.cxy) if len(self.cxy) else None
        self.cindex = PointIndex(self.cxy)

    def _s_index(self):
        """S's edges (start, end, successor) and their proximity index, built on first use."""
        if self._s_edges is None:
            a, b, nxt = boundary_edges(self.S)
            self._s_edges = (a, b, nxt, EdgeIndex(a, b, self.r))
        return self._s_edges

    def nearest_centers(self, xy: np.ndarray, radius: float):
        """Pairs (point index, centre index) with the centre within ``radius`` of the point."""
        if self.ctree is None:
            return np.zeros(0, int), np.zeros(0, int)
        return self.ctree.query(shapely.points(xy), predicate="dwithin", distance=radius)


def _point_keys(xy: np.ndarray) -> np.ndarray:
    """One sortable 16-byte key per point, equal exactly when the coordinates are equal (−0.0 as 0.0)."""
    a = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, 2) + 0.0)
    return a.view(np.dtype((np.void, 16))).ravel()


def _distinct_centers(xy: np.ndarray, side: np.ndarray, r: float) -> tuple[np.ndarray, np.ndarray]:
    """The centres with those of one side that coincide (within 1e-10·r) kept once.

    Two vertices of a buffer can refine to one exact centre (GEOS leaves a short extra edge where offset
    segments meet, a core pinched at a vertex has that vertex twice). A loop must not hold one disk under
    two numbers: between them its tangent has no direction, and the search for missed contacts, which
    inserts one disk per place a round, can keep filling that place without ever settling.
    """
    if len(xy) < 2:
        return xy, side
    keep = np.ones(len(xy), dtype=bool)
    for s in (1, -1):
        ids = np.flatnonzero(side == s)
        if len(ids) < 2:
            continue
        pairs = cKDTree(xy[ids]).query_pairs(1e-10 * r, output_type="ndarray")
        if len(pairs):
            keep[ids[pairs.max(axis=1)]] = False
    return xy[keep], side[keep]


class _EngineError(RuntimeError):
    """An internal step failed; the engine reports it instead of returning a wrong answer."""


# ---------------------------------------------------------------------------------------------------------
# Exact loops as cyclic sequences of disks
# ---------------------------------------------------------------------------------------------------------
@dataclass
class _DiskLoop:
    cid: np.ndarray          # centre index of each disk
    side: np.ndarray         # +1 turn left around it, -1 right
    c: np.ndarray            # (n, 2) centres
    phi: np.ndarray          # direction of the tangent leaving each disk
    length: np.ndarray       # tangent lengths
    sweep: np.ndarray        # signed arc sweep at each disk
    r: float | np.ndarray    # the radius, or (two radii) each disk's: a on side +1, b on side −1
    converged: bool = True

    @property
    def n(self) -> int:
        return len(self.cid)

    @property
    def rho(self) -> np.ndarray:
        """Each disk's radius (n,)."""
        return np.broadcast_to(np.asarray(self.r, dtype=float), (self.n,))

    def _r(self, i):
        """The radius of disk ``i`` (the radius itself with one)."""
        return self.r if np.ndim(self.r) == 0 else float(self.r[i])

    def tangent_points(self):
        nrm = np.column_stack([-np.sin(self.phi), np.cos(self.phi)])
        if np.ndim(self.r) == 0:
            P = self.c - self.side[:, None] * self.r * nrm
            Q = np.roll(self.c, -1, axis=0) - np.roll(self.side, -1)[:, None] * self.r * nrm
        else:
            sr = (self.side * self.r)[:, None]
            P = self.c - sr * nrm
            Q = np.roll(self.c, -1, axis=0) - np.roll(sr, -1, axis=0) * nrm
        return P, Q

    def arc_start(self) -> np.ndarray:
        return np.roll(self.phi, 1) - self.side * (math.pi / 2)

    def pieces(self):
        """``[(kind, geometry, piece_length)]``: arc i is piece 2i, the tangent leaving disk i piece 2i+1."""
        if self.n == 1:
            r0 = self._r(0)
            return [("arc", (self.c[0], r0, 0.0, self.sweep[0]), r0 * abs(self.sweep[0]))]
        P, Q = self.tangent_points()
        a0 = self.arc_start()
        out = []
        one = np.ndim(self.r) == 0
        for i in range(self.n):
            ri = self.r if one else float(self.r[i])
            out.append(("arc", (self.c[i], ri, a0[i], self.sweep[i]), ri * abs(self.sweep[i])))
            out.append(("seg", (P[i], Q[i]), self.length[i]))
        return out

    def to_loop(self, frame: _Frame | None = None) -> Loop:
        """Build the exact loop; with ``frame``, in world coordinates (as ``frame.loop_to_world``)."""
        if self.n == 1:
            loop = Loop.circle(self.c[0], self._r(0), ccw=self.sweep[0] > 0)
            return loop if frame is None else frame.loop_to_world(loop)
        affine = None if frame is None else (frame.scale, frame.ox, frame.oy)
        if np.ndim(self.r) != 0:
            return _two_radii_loop(self, frame)
        return Loop._from_disk_arrays(self.c, self.side.astype(float), self.r, self.phi, self.length,
                                      self.sweep, affine)

    @property
    def perimeter(self) -> float:
        if np.ndim(self.r) != 0:
            return math.fsum(self.length) + math.fsum(self.rho * np.abs(self.sweep))
        return math.fsum(self.length) + self.r * math.fsum(np.abs(self.sweep))

    def polyline_from(self, piece: int, point: np.ndarray, tol: float) -> np.ndarray:
        """Points around the loop starting at ``point`` on piece ``piece`` and ending just before it."""
        pcs = self.pieces()
        m = len(pcs)
        out = [np.asarray(point, float)[None, :]]

        def arc_pts(geom, frac0, frac1):
            c, r, a0, sw = geom
            if r == 0:            # a radius 0 (two radii): the corner itself
                return np.array([c, c], dtype=float)
            span = sw * (frac1 - frac0)
            n = max(1, math.ceil(abs(span) / (2 * math.acos(max(-1.0, 1 - tol / r)))))
            th = a0 + sw * frac0 + span * np.arange(n + 1) / n
            return np.column_stack([c[0] + r * np.cos(th), c[1] + r * np.sin(th)])

        def frac_of(kind, geom, x):
            if kind == "seg":
                p, q = geom
                d = q - p
                L2 = d @ d
                return 0.0 if L2 == 0 else float(np.clip(((x - p) @ d) / L2, 0, 1))
            return _along((kind, geom, 0.0), x) / (geom[1] * abs(geom[3])) if geom[3] != 0 and geom[1] > 0 else 0.0

        kind, geom, _ = pcs[piece]
        f = frac_of(kind, geom, point)
        if kind == "arc":
            out.append(arc_pts(geom, f, 1.0)[1:])
        else:
            out.append(geom[1][None, :])
        for k in range(1, m):
            kind2, geom2, _ = pcs[(piece + k) % m]
            if kind2 == "arc":
                out.append(arc_pts(geom2, 0.0, 1.0)[1:])
            else:
                out.append(geom2[1][None, :])
        if kind == "arc":
            out.append(arc_pts(geom, 0.0, f)[1:-1])
        return np.concatenate(out)


def _two_radii_loop(L: _DiskLoop, frame: _Frame | None) -> Loop:
    """The exact loop of a disk loop with a radius per disk (`two_radii._loop_from_disks`)."""
    from .two_radii import _loop_from_disks

    return _loop_from_disks(L.c, L.side.astype(float), L.rho, L.phi, L.length, L.sweep,
                            frame if frame is not None else _Frame(0.0, 0.0, 1.0))


def _dedupe(cid, side, ref):
    """Merge cyclically consecutive entries with the same disk and side (their turns add)."""
    n = len(cid)
    if n <= 1:
        return cid, side, ref
    # Runs in the order of the array (a run at the end that continues the first one is merged into it).
    new = np.ones(n, dtype=bool)
    new[1:] = (cid[1:] != cid[:-1]) | (side[1:] != side[:-1])
    first = np.flatnonzero(new)
    if len(first) == n and (cid[0] != cid[-1] or side[0] != side[-1]):
        return np.asarray(cid, dtype=np.int64), np.asarray(side, dtype=np.int64), np.asarray(ref, dtype=float)
    sums = np.add.reduceat(np.asarray(ref, dtype=float), first)
    cid, side = np.asarray(cid, dtype=np.int64)[first], np.asarray(side, dtype=np.int64)[first]
    if len(first) > 1 and cid[0] == cid[-1] and side[0] == side[-1]:
        sums[0] += sums[-1]
        cid, side, sums = cid[:-1], side[:-1], sums[:-1]
    return cid, side, sums


def _drop_indices(values: np.ndarray) -> np.ndarray:
    """Among entries with ``values < 0``, those that are not next to a more negative one (cyclically)."""
    n = len(values)
    bad = values < -_ANGLE_EPS
    prev = np.roll(values, 1)
    nxt = np.roll(values, -1)
    pick = bad & (values <= prev) & (values < nxt) if n > 2 else bad & (values == values.min())
    if not pick.any() and bad.any():
        pick = np.zeros(n, dtype=bool)
        pick[np.argmin(values)] = True
    return np.flatnonzero(pick)


def _violations(ctx: _Context, L: _DiskLoop, cache: dict | None = None):
    """Places where the loop enters the core or the anticore: list of (piece, candidate centre, side, where).

    Two tests, both exact: a piece closer than r to another disk centre, and a piece closer than r to a
    piece of the exact shrink of S or of its complement (`offsets`; candidates from a proximity index of
    chords, each decided by the closed-form piece distance). ``where`` is 0 to insert the candidate after
    disk ``piece // 2`` for a tangent piece; for an arc −1 to insert it before the arc's disk, +1 after.

    ``cache`` (a dict kept by the caller for one context) remembers the outcome for each piece by
    everything that determines it — a tangent's end points and lengths and its two disks, an arc's centre,
    start, sweep, disk and side — so that a loop that changed only in a few places is tested only there.
    """
    r = ctx.r
    thr_c = r - ctx.pen_center
    n = L.n
    n_centres = len(ctx.cxy)
    P, Q = L.tangent_points()
    a0 = L.arc_start()
    bad: dict[int, tuple[np.ndarray, set]] = {}
    seg_ids = np.flatnonzero(L.length > 1e-14)
    arcs = np.flatnonzero(L.sweep != 0)
    keys: dict[int, tuple] = {}
    known: dict[int, tuple | None] = {}
    if cache is not None:
        cid, nxt = L.cid.tolist(), np.roll(L.cid, -1).tolist()
        PQ = np.column_stack([P, Q, L.length]).tolist()
        for i in seg_ids.tolist():
            keys[2 * i + 1] = ("seg", *PQ[i], cid[i], nxt[i])
        ARC = np.column_stack([L.c, a0, L.sweep]).tolist()
        sd = L.side.tolist()
        for i in arcs.tolist():
            keys[2 * i] = ("arc", *ARC[i], cid[i], sd[i])
        for piece, key in keys.items():
            if key in cache:
                known[piece] = cache[key]
        if known:
            seg_ids = np.array([i for i in seg_ids.tolist() if 2 * i + 1 not in known], dtype=np.int64)
            arcs = np.array([i for i in arcs.tolist() if 2 * i not in known], dtype=np.int64)

    def flag(piece, point, edges=()):
        entry = bad.setdefault(piece, (point, set()))
        entry[1].update(edges)

    if len(seg_ids):
        sp, sq = P[seg_ids], Q[seg_ids]
        mid = 0.5 * (sp + sq)
        si, cj = ctx.cindex.near_segments(sp, sq, thr_c)
        if ctx.two:       # the query took the larger radius: each centre by its own side's
            si = si[point_segment_distance(ctx.cxy[cj], sp[si], sq[si])
                    <= ctx.radius_of(ctx.cside[cj]) - ctx.pen_center]
        for i in np.unique(si):
            flag(2 * int(seg_ids[i]) + 1, mid[i])
        si, ei = ctx.oindex.near_segments(sp, sq, thr_c + ctx.osag)
        seg_arrays = (np.zeros(len(sp), dtype=bool), np.column_stack([sp, sq, np.zeros(len(sp))]))
        for i, e, _ in _exact_entries(ctx, lambda i: ("seg", (sp[i], sq[i])), si, ei, thr_c, seg_arrays):
            flag(2 * int(seg_ids[i]) + 1, mid[i], (e,))
        region = ctx.in_regions(mid)
        if ctx.zero:      # a radius 0: entries into its region are judged below (`_zero_radius`)
            region[region == ctx.zero] = 0
            zero_hits = {2 * int(seg_ids[i]) + 1: (ci, ctx.zero, 0)
                         for i, ci, depth in zero_entries(ctx, sp, sq, ctx.zero)
                         if ci >= 0 and depth > ctx.pen_center}
        for i in np.flatnonzero(region != 0):
            flag(2 * int(seg_ids[i]) + 1, mid[i])
    # Arcs: points along each, tested against the other centres and the obstacle edges.
    if len(arcs):
        m = np.maximum(2, np.ceil(np.abs(L.sweep[arcs]) / (math.pi / 32)).astype(np.int64))
        owner = np.repeat(arcs, m - 1)
        first = np.repeat(np.cumsum(m - 1) - (m - 1), m - 1)
        frac = (np.arange(len(owner)) - first + 1) / np.repeat(m, m - 1)
        th = a0[owner] + L.sweep[owner] * frac
        ro = r if not ctx.two else L.rho[owner]
        pts = np.column_stack([L.c[owner, 0] + ro * np.cos(th), L.c[owner, 1] + ro * np.sin(th)])
        pi, ci = ctx.cindex.near_points(pts, thr_c)
        keep = ci != L.cid[owner[pi]]
        if ctx.two:
            keep &= np.hypot(*(pts[pi] - ctx.cxy[ci]).T) <= ctx.radius_of(ctx.cside[ci]) - ctx.pen_center
        for k in np.unique(pi[keep]):
            flag(2 * int(owner[k]), pts[k])
        # The arc lies within its chords' sag of the chords through its samples and ends: the query on
        # the chords is drawn that much wider, and each obstacle piece found is decided by its exact
        # distance to the whole arc.
        own_c = np.repeat(arcs, m)
        first_c = np.repeat(np.cumsum(m) - m, m)
        k_c = np.arange(len(own_c)) - first_c
        t0, t1 = k_c / np.repeat(m, m), (k_c + 1) / np.repeat(m, m)
        th0 = a0[own_c] + L.sweep[own_c] * t0
        th1 = a0[own_c] + L.sweep[own_c] * t1
        rc = r if not ctx.two else L.rho[own_c]
        cp = np.column_stack([L.c[own_c, 0] + rc * np.cos(th0), L.c[own_c, 1] + rc * np.sin(th0)])
        cq = np.column_stack([L.c[own_c, 0] + rc * np.cos(th1), L.c[own_c, 1] + rc * np.sin(th1)])
        step = float((np.abs(L.sweep[arcs]) / m).max(initial=0.0))
        reach = thr_c + ctx.osag + r * (1.0 - math.cos(0.5 * step)) + 1e-12 * r
        pi, ei = ctx.oindex.near_segments(cp, cq, reach)
        arc_arrays = (np.ones(n, dtype=bool), np.column_stack([L.c, np.full(n, r) if not ctx.two else L.rho, a0,
                                                                L.sweep]))
        for k, e, x in _exact_entries(ctx, lambda i: ("arc", (L.c[i], L._r(i), a0[i], L.sweep[i])), own_c[pi],
                                      ei, thr_c, arc_arrays):
            flag(2 * int(k), x, (e,))
    found: dict[int, tuple | None] = {}
    for piece in sorted(bad):
        found[piece] = None
        where, edges = bad[piece]
        disk = piece // 2
        kind = "arc" if piece % 2 == 0 else "seg"
        own = {int(L.cid[disk])} if kind == "arc" else {int(L.cid[disk]), int(L.cid[(disk + 1) % n])}
        geom = shapely.linestrings([P[disk], Q[disk]]) if kind == "seg" else shapely.points(where)
        ci = _candidate(ctx, geom, own, edges)
        if ci is None:
            continue
        cxy = ctx.cxy[ci]
        if kind == "seg":
            d = Q[disk] - P[disk]
            side = 1 if (d[0] * (cxy[1] - P[disk][1]) - d[1] * (cxy[0] - P[disk][0])) > 0 else -1
            if ctx.two:   # two radii: a disk is wrapped from its own side only (its radius is that side's)
                side = int(ctx.cside[ci])
            found[piece] = (ci, side, 0)
        else:
            c = L.c[disk]
            s = L.side[disk]
            v = where - c
            tangent = s * np.array([-v[1], v[0]])
            side = 1 if (tangent[0] * (cxy[1] - where[1]) - tangent[1] * (cxy[0] - where[0])) > 0 else -1
            if ctx.two:
                side = int(ctx.cside[ci])
            th = math.atan2(v[1], v[0])
            frac = ((th - a0[disk]) % _TWO_PI) / abs(L.sweep[disk]) if s > 0 else \
                ((a0[disk] - th) % _TWO_PI) / abs(L.sweep[disk])
            found[piece] = (ci, side, -1 if frac < 0.5 else 1)
    if ctx.zero and len(seg_ids):
        for piece, hit in zero_hits.items():
            if found.get(piece) is None:
                found[piece] = hit
    if cache is not None and len(ctx.cxy) != n_centres:
        cache.clear()                     # centres were added on the way: outcomes before may be stale
    elif cache is not None:
        for i in seg_ids.tolist():
            cache[keys[2 * i + 1]] = found.get(2 * i + 1)
        for i in arcs.tolist():
            cache[keys[2 * i]] = found.get(2 * i)
    found.update(known)
    return [(piece, *found[piece]) for piece in sorted(found) if found[piece] is not None]


def _exact_entries(ctx: _Context, piece_of, li: np.ndarray, ei: np.ndarray, thr: float, arrays=None):
    """The (loop piece, obstacle edge, nearest point) where a loop piece truly comes nearer than ``thr`` to
    the exact offset piece behind an obstacle edge.

    ``li``/``ei`` pair loop pieces (given by ``piece_of(i)``) with obstacle edges from a proximity query;
    each (loop piece, exact piece) pair is decided once, by the closed-form distance (`piece_distance`).
    ``arrays`` (whether an arc, (n, 5) parameters: `_pieces.piece_distances`), when given, describes the
    loop pieces ``piece_of(i)`` too: the pairs clearly farther than ``thr`` are then set aside at once.
    """
    out = []
    if len(li) == 0:
        return out
    pj = ctx.opiece[ei]
    order = np.lexsort((pj, li))
    li, pj, ei = li[order], pj[order], ei[order]
    first = np.ones(len(li), dtype=bool)
    first[1:] = (li[1:] != li[:-1]) | (pj[1:] != pj[:-1])
    li, pj, ei = li[first], pj[first], ei[first]
    if ctx.two:
        # Two radii: ``thr`` is the larger radius less the allowance; each obstacle piece takes its own
        # side's radius (a for the shrink S↓a, b for (S^c)↓b) less the same allowance.
        return _exact_entries_two(ctx, piece_of, li, pj, ei, ctx.radius_of(ctx.okind[ei]) - (ctx.r - thr), arrays)
    if arrays is not None:
        # Most pairs are a loop piece resting on the obstacle (distance r, above thr by pen_center): the
        # vectorised distances set aside those clearly at or beyond thr, the rest are decided exactly.
        is_arc, params = arrays
        o_arc, o_params = _obstacle_arrays(ctx)
        d = piece_distances(is_arc[li], params[li], o_arc[pj], o_params[pj])
        size = 1.0 + ctx.r + max(float(np.abs(params[:, :2]).max()), float(np.abs(o_params[:, :2]).max()))
        margin = max(0.1 * (ctx.r - thr), 64 * np.finfo(float).eps * size)    # ≫ their rounding
        near = ~(d >= thr + margin)
        li, pj, ei = li[near], pj[near], ei[near]
    for i, j, e in zip(li.tolist(), pj.tolist(), ei.tolist()):
        d, x, _ = piece_distance(piece_of(i), ctx.opieces[j][1])
        if d < thr:
            out.append((i, e, x))
    return out


def _exact_entries_two(ctx: _Context, piece_of, li, pj, ei, thr: np.ndarray, arrays):
    """`_exact_entries` with a threshold per (loop piece, obstacle piece) pair (two radii)."""
    out = []
    if arrays is not None:
        is_arc, params = arrays
        o_arc, o_params = _obstacle_arrays(ctx)
        d = piece_distances(is_arc[li], params[li], o_arc[pj], o_params[pj])
        size = 1.0 + ctx.r + max(float(np.abs(params[:, :2]).max()), float(np.abs(o_params[:, :2]).max()))
        margin = max(0.1 * ctx.pen_center, 64 * np.finfo(float).eps * size)
        near = ~(d >= thr + margin)
        li, pj, ei, thr = li[near], pj[near], ei[near], thr[near]
    for i, j, e, t in zip(li.tolist(), pj.tolist(), ei.tolist(), thr.tolist()):
        d, x, _ = piece_distance(piece_of(i), ctx.opieces[j][1])
        if d < t:
            out.append((i, e, x))
    return out


def _obstacle_arrays(ctx: _Context) -> tuple[np.ndarray, np.ndarray]:
    """``ctx.opieces`` as arrays for `piece_distances` (whether an arc; (n, 5) parameters), built once."""
    got = getattr(ctx, "_opiece_arrays", None)
    if got is None:
        # In the order of ``ctx.opieces``: each side's straight pieces, then its arcs (a side of radius 0
        # has none).
        arcs, rows = [], []
        for X in (ctx.xE, ctx.xG):
            if X.r == 0:
                continue
            seg = np.asarray(X.seg, dtype=float).reshape(-1, 2, 2)
            rows.append(np.column_stack([seg[:, 0], seg[:, 1], np.zeros(len(seg))]))
            centre = np.asarray(X.arc_center, dtype=float).reshape(-1, 2)
            rows.append(np.column_stack([centre, np.full(len(centre), float(X.r)), X.arc_start, X.arc_sweep]))
            arcs += [np.zeros(len(seg), bool), np.ones(len(centre), bool)]
        arc = np.concatenate(arcs) if arcs else np.zeros(0, bool)
        params = np.concatenate(rows) if rows else np.zeros((0, 5))
        got = ctx._opiece_arrays = (arc, params)
    return got


def _candidate(ctx: _Context, geom, own: set[int], edges) -> int | None:
    """The disk to add where a piece enters an obstacle, or None.

    The deepest-entered other centre if there is one (the lowest index among equally deep ones). Else the
    piece came nearer than r only to straight pieces or arcs of the exact shrink or grow (``edges``): the
    deepest point of such a region towards a straight piece of the loop is one of its corners, so a piece
    that enters the region enters a corner too, unless it enters only through an arc's own side: an arc
    may sweep past the straight piece that joins its own centre to the next corner and enter the region
    between the two; that corner is the disk to add, if the segment to it truly lies in the shrink
    (grow), i.e. clears S by r. A piece flagged for its midpoint alone takes the nearest centre.

    ``geom`` is a point (on an arc) or a segment (a tangent). The entered centres are found by a ball or
    capsule query of radius r − pen_center on the centres' k-d tree, whose cost does not grow with the
    density of centres around the piece (a query 3r wide did: thousands of centres on dense outlines).
    """
    if ctx.ckd is None:
        return None
    # With two radii each centre is entered by its own side's radius: the query reaches the larger.
    thr = (max(ctx.ra, ctx.rb) if ctx.two else ctx.r) - ctx.pen_center
    if shapely.get_type_id(geom) == 0:
        xy = shapely.get_coordinates(geom)
        hit = np.asarray(ctx.ckd.query_ball_point(xy[0], thr), dtype=np.int64)
    else:
        pq = shapely.get_coordinates(geom)
        _, hit = ctx.cindex.near_segments(pq[:1], pq[1:2], thr)
    entered = np.array(sorted(c for c in hit.tolist() if c not in own), dtype=np.int64)
    if len(entered):
        d = shapely.distance(geom, shapely.points(ctx.cxy[entered]))
        if ctx.two:       # each centre by its own side's radius: the deepest entered
            depth = ctx.radius_of(ctx.cside[entered]) - d
            if depth.max() > ctx.pen_center:
                return int(entered[np.argmax(depth)])
        elif d.min() < thr:
            return int(entered[np.argmin(d)])
    if edges:
        if shapely.get_type_id(geom) == 1:
            return next(iter(_fallbacks(ctx, geom, own, edges)), None)
        (mine,) = own
        for ci in _fallbacks(ctx, geom, own, edges):
            if int(ctx.cside[ci]) == int(ctx.cside[mine]) and ctx.joined(mine, ci, geom):
                return ci
        return None
    return next(iter(_fallbacks(ctx, geom, own, edges)), None)


def _fallbacks(ctx: _Context, geom, own: set[int], edges) -> list[int]:
    """Centres to try where none is entered: those at the ends of the crossed edges, else all within 3r;
    nearest to ``geom`` first."""
    ends = []
    if edges and ctx.ckd is not None:
        d, ci = ctx.ckd.query(ctx.oedges[list(edges)].reshape(-1, 2), distance_upper_bound=4.0 * ctx.pen_center)
        ends = [int(c) for c, dd in zip(ci.tolist(), d.tolist()) if math.isfinite(dd) and int(c) not in own]
    if ends:
        pool = np.array(sorted(set(ends)), dtype=np.int64)
    else:
        near = np.atleast_1d(ctx.ctree.query(geom, predicate="dwithin", distance=3.0 * ctx.r))
        pool = np.array([c for c in near.tolist() if c not in own], dtype=np.int64)
    if len(pool) == 0:
        return []
    d = shapely.distance(geom, shapely.points(ctx.cxy[pool]))
    return pool[np.argsort(d, kind="stable")].tolist()


def _chain_length(ctx: _Context, cids, sides) -> float:
    """Length of the open chain of tangents and arcs through the interior disks of ``cids``."""
    c = ctx.cxy[np.asarray(cids)]
    s = np.asarray(sides, dtype=float)
    D = c[1:] - c[:-1]
    d = np.hypot(D[:, 0], D[:, 1])
    if ctx.two:       # signed radii: each disk its own side's
        rho = s * ctx.radius_of(ctx.cside[np.asarray(cids)])
        k = rho[1:] - rho[:-1]
    else:
        k = (s[1:] - s[:-1]) * ctx.r
    if (d * d < k * k * (1 - 1e-12)).any() or (d == 0).any():
        return math.inf
    L = np.sqrt(np.maximum(d * d - k * k, 0.0))
    phi = np.arctan2(D[:, 1], D[:, 0]) - np.arctan2(k, L)
    turn = np.diff(phi)
    sw = np.where(s[1:-1] > 0, np.mod(turn, _TWO_PI), -np.mod(-turn, _TWO_PI))
    if ctx.two:
        return float(L.sum() + (np.abs(rho[1:-1]) * np.abs(sw)).sum())
    return float(L.sum() + ctx.r * np.abs(sw).sum())


def _insert_before(ctx: _Context, cid, side, disk: int, ci: int, s: int) -> bool:
    """Whether a disk poking out of the arc at ``disk`` belongs before it (else after it) in the loop."""
    n = len(cid)
    prv, nxt = (disk - 1) % n, (disk + 1) % n
    before = _chain_length(ctx, [cid[prv], ci, cid[disk], cid[nxt]], [side[prv], s, side[disk], side[nxt]])
    after = _chain_length(ctx, [cid[prv], cid[disk], ci, cid[nxt]], [side[prv], side[disk], s, side[nxt]])
    return before < after


def _entered_chain(ctx: _Context, a: int, sa: int, b: int, sb: int, taken: set[int]) -> list[tuple[int, int]]:
    """The disks that the tangent from disk ``a`` (side ``sa``) to disk ``b`` (side ``sb``) enters, and those
    that the tangents to them enter in turn, as ``(centre, side)`` in order from ``a`` to ``b``.

    A centre of side s whose disk the tangent enters (it lies on the tangent's side s·left nearer than r,
    by more than the finish's rounding allowance, and between the tangent's ends) is what `_candidate`
    would choose there, the deepest first; the finish would insert it, and in later rounds the centres
    that the two new tangents enter. Here that refinement is done at once for the gap (quickhull on
    tangents): on dense outlines the funnel misses runs of nearly collinear corners, and one round each
    would make the finish's rounds as many as the longest run. Centres in ``taken`` (in the loop, or
    inserted this round) are left out; the chosen ones are added to it. Every other kind of entry (an arc
    past its own obstacle piece, a piece entering the exact offsets between corners) is left to the
    finish's next round.
    """
    r, pen = ctx.r, ctx.pen_center
    # Two radii: each disk at its own side's radius (signed radii ρ = s·radius, DESIGN §3.1). A radius 0 is
    # entered by crossing S's boundary, not by a distance (`_zero_radius`): left to the rounds.
    reach = max(ctx.ra, ctx.rb) if ctx.two else r

    def chain(i: int, si: int, j: int, sj: int, depth_left: int) -> list[tuple[int, int]]:
        ci, cj = ctx.cxy[i], ctx.cxy[j]
        D = cj - ci
        d = math.hypot(D[0], D[1])
        rho_i = si * ctx.radius_of(si) if ctx.two else si * r
        k = sj * ctx.radius_of(sj) - rho_i if ctx.two else (sj - si) * r
        if d <= abs(k) or depth_left == 0:
            return []
        L = math.sqrt(d * d - k * k)
        phi = math.atan2(D[1], D[0]) - math.atan2(k, L)
        u = np.array([math.cos(phi), math.sin(phi)])
        nrm = np.array([-u[1], u[0]])
        P = ci - rho_i * nrm
        near = ctx.ckd.query_ball_point(P + 0.5 * L * u, 0.5 * L + reach)
        ids = np.array([c for c in near if c not in taken], dtype=np.int64)
        if len(ids) == 0:
            return []
        w = ctx.cxy[ids] - P
        t = w @ u
        s_ids = ctx.cside[ids]
        rad = ctx.radius_of(s_ids) if ctx.two else r
        depth = rad - s_ids * (w @ nrm)
        ok = (depth > pen) & (depth < 2.0 * rad - pen) & (t > 0.0) & (t < L)
        if not ok.any():
            return []
        m = int(np.argmax(np.where(ok, depth, -np.inf)))
        c, sc = int(ids[m]), int(s_ids[m])
        taken.add(c)
        return (chain(i, si, c, sc, depth_left - 1) + [(c, sc)] + chain(c, sc, j, sj, depth_left - 1))

    if ctx.ckd is None or ctx.zero:
        return []
    return chain(a, sa, b, sb, 64)


def _finish(ctx: _Context, cid: np.ndarray, side: np.ndarray, ref: np.ndarray) -> _DiskLoop | None:
    """Exact tight loop from an approximate cyclic disk sequence: drop wrong turns, add missed contacts."""
    return _without_grazed(ctx, _finish_steps(ctx, cid, side, ref))


def _without_grazed(ctx: _Context, L: _DiskLoop | None) -> _DiskLoop | None:
    """A settled loop without the disks it only grazes (arcs of sweep at most `_ANGLE_EPS`: rounding on a
    disk it touches at one point), where leaving them out changes nothing else; else L.

    The tangents into and out of such a disk leave it at one point in one direction: they are one line,
    which is also the tangent between its neighbours, so the loop is the same curve, its straight piece
    no longer cut where it grazes the disk. Which grazed disks a finish keeps depends on the path it
    started from; without them the pieces depend only on the curve. The shorter sequence is finished
    again (its pieces' checks are cached) and taken only if it settles on exactly those disks.
    """
    if L is None or not L.converged or L.n < 3:
        return L
    grazed = np.abs(L.sweep) <= _ANGLE_EPS
    if not grazed.any() or grazed.sum() > L.n - 2:
        return L
    keep = ~grazed
    M = _finish_steps(ctx, L.cid[keep], L.side[keep], L.sweep[keep])
    if M is None or not M.converged or M.n != int(keep.sum()):
        return L
    return M


def _finish_steps(ctx: _Context, cid: np.ndarray, side: np.ndarray, ref: np.ndarray,
                  rounds: int | None = None) -> _DiskLoop | None:
    r = ctx.r
    last = None
    seen = set()
    most = 4 * len(cid) + 64            # a finish that keeps adding disks is not settling (see the loop)
    entries = None
    for _ in range(_MAX_FINISH_STEPS):
        cid, side, ref = _dedupe(cid, side, ref)
        n = len(cid)
        if n == 0:
            return None
        if n > most:
            break
        c = ctx.cxy[cid]
        if ctx.two:       # each disk its centre's side's radius
            r = ctx.radius_of(ctx.cside[cid])
        if n == 1:
            return _DiskLoop(cid, side, c, np.zeros(1), np.zeros(1), np.array([_TWO_PI * side[0]]), r)
        phi, length, ok = tangent_directions(c, side, r, ctx.precision)
        if not ok.all():
            i = int(np.flatnonzero(~ok)[0])
            j = (i + 1) % n
            drop = i if abs(ref[i]) <= abs(ref[j]) else j
            keep = np.ones(n, dtype=bool)
            keep[drop] = False
            cid, side, ref = cid[keep], side[keep], ref[keep]
            continue
        sw = arc_sweeps(phi, side, ref)
        turn = side * sw
        if (turn < -_ANGLE_EPS).any():
            drop = _drop_indices(turn)
            keep = np.ones(n, dtype=bool)
            keep[drop] = False
            cid, side, ref = cid[keep], side[keep], sw[keep]
            continue
        # A turn the wrong way by less than _ANGLE_EPS is rounding on a disk the loop only grazes: no arc.
        sw = np.where((side * sw < 0) | (np.abs(sw) < 1e-15), 0.0, sw)
        loop = _DiskLoop(cid, side, c, phi, length, sw, r)
        last = loop
        state = (tuple(cid.tolist()), tuple(side.tolist()))
        if state in seen:
            loop.converged = False
            return loop
        seen.add(state)
        if rounds is not None:
            if rounds == 0 or abs(float(sw.sum())) > _WOUND * math.pi:
                break               # the budget spent, or a guess wound round and round: it will not settle
            rounds -= 1
        viol = _violations(ctx, loop, ctx.violation_cache)
        if not viol:
            return loop
        if rounds is not None:
            # With a budget (a start that is only a guess, `_shrink_loops`, `_annulus_loops`): give up as
            # soon as the guess shows itself far off (`_FAR_OFF` of its pieces entering the core or the
            # anticore) or a round leaves as many entries as the one before.
            if len(viol) >= (_FAR_OFF * n if entries is None else entries):
                break
            entries = len(viol)
        # Insert the candidates, from the back so that earlier indices stay valid. A disk that pokes out
        # of an arc goes before or after the arc's disk, whichever makes the shorter local chain.
        # A disk that several pieces enter goes in once, where it lengthens the chain least: put in at
        # each place, the loop would run back and forth between them.
        places: dict[tuple[int, int], list[int]] = {}
        for piece, ci, s, where in viol:
            disk = piece // 2
            if piece % 2 == 1:
                pos = disk + 1
            else:
                pos = disk if _insert_before(ctx, cid, side, disk, ci, s) else disk + 1
            places.setdefault((ci, s), []).append(pos)
        ins = {}
        for (ci, s), at in places.items():
            at = sorted(set(at))
            if len(at) > 1:
                at.sort(key=lambda p: _chain_length(ctx, [cid[p - 1], ci, cid[p % n]],
                                                    [side[p - 1], s, side[p % n]]))
            ins.setdefault(at[0], (ci, s))
        # Each candidate comes with the disks that the tangents to it from its neighbours enter, as the
        # next rounds would add them one by one (`_entered_chain`).
        taken = set(cid.tolist()) | {ci for ci, _ in ins.values()}
        pos_l, cid_l, side_l = [], [], []
        for pos in sorted(ins):
            ci, s = ins[pos]
            a, sa, b, sb = int(cid[pos - 1]), int(side[pos - 1]), int(cid[pos % n]), int(side[pos % n])
            chain = _entered_chain(ctx, a, sa, ci, s, taken) + [(ci, s)] + _entered_chain(ctx, ci, s, b, sb, taken)
            pos_l += [pos] * len(chain)
            cid_l += [c for c, _ in chain]
            side_l += [sc for _, sc in chain]
        cid = np.insert(cid, pos_l, cid_l)
        side = np.insert(side, pos_l, side_l)
        ref = np.insert(sw, pos_l, 0.0)
    if last is not None:
        last.converged = False
    return last


# ---------------------------------------------------------------------------------------------------------
# Tightening one loop in its homotopy class
# ---------------------------------------------------------------------------------------------------------
def _turning(xy: np.ndarray) -> np.ndarray:
    u = xy - np.roll(xy, 1, axis=0)
    v = np.roll(xy, -1, axis=0) - xy
    return np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1))


def _tighten_ring(ctx: _Context, ring: np.ndarray) -> _DiskLoop | None:
    """The exact tight loop homotopic to a closed polyline in the mortar (None if it shrinks away)."""
    distinct = np.any(ring != np.roll(ring, -1, axis=0), axis=1)
    if distinct.sum() < 3:
        return None              # surgery at a point where a loop only grazes itself leaves a point: nothing
    k = ctx.component_of(ring)
    T, vcenter = ctx.triangulation(k)
    try:
        portals = sleeve(T, ring)
    except ValueError as exc:     # a ring built by surgery from a loop the finish could not settle
        raise _EngineError(f"a loop to tighten leaves the mortar ({exc})") from None
    geo = closed_geodesic(T, portals)
    if geo is None:
        return None
    turn = _turning(geo.xy) if len(geo.xy) > 1 else np.array([_TWO_PI * geo.sides[0]])
    cid = vcenter[geo.vertices]
    known = cid >= 0
    if not known.any():
        raise _EngineError("the tightened loop touches no arc of the core or the fillet")
    return _finish(ctx, cid[known], geo.sides[known].astype(np.int64), turn[known])


def _longest_run(k: np.ndarray, n: int) -> np.ndarray:
    """The longest run of consecutive numbers among vertex numbers ``k`` of a ring of ``n`` vertices (a run
    may go on past the last vertex to the first).

    A ring passes one circle at places far apart where a neck or a bay is about 2r wide; the longest run
    is where it runs on the circle's arc (`_annulus_start`).

    Examples
    --------
    >>> _longest_run(np.array([40, 3, 4, 5]), 100).tolist()
    [3, 4, 5]
    >>> _longest_run(np.array([0, 1, 50, 98, 99]), 100).tolist()
    [98, 99, 0, 1]
    """
    k = np.sort(k)
    if len(k) < 2:
        return k
    runs = np.split(k, np.flatnonzero(np.diff(k) > 1) + 1)
    if len(runs) > 1 and k[0] == 0 and k[-1] == n - 1:                  # a run across the first vertex
        runs = [np.concatenate([runs[-1], runs[0]])] + runs[1:-1]
    return max(runs, key=len)


def _annulus_start(ctx: _Context, ring: np.ndarray):
    """A cyclic disk sequence to start the exact finish from, without the free space: every core disk
    whose arc the ring (the guide core's boundary) runs on, at the mean place of its arc along the ring
    (the longest run of vertices on its circle, `_longest_run`), and every anticore disk within
    `_ANNULUS_REACH`·r of the ring, at the ring's vertex nearest its centre; None if the ring runs on no
    core disk."""
    r = ctx.r
    xy = ring[:-1] if len(ring) > 1 and np.array_equal(ring[0], ring[-1]) else ring
    n = len(xy)
    kd, ids = ctx._kd[1]
    if kd is None or n < 3:
        return None
    turn = _turning(xy)
    d, j = kd.query(xy)
    on = np.flatnonzero(np.abs(d - r) <= 1e-3 * r)
    if len(on) == 0:
        return None
    owner = ids[j[on]]
    order = np.argsort(owner, kind="stable")
    owner, on = owner[order], on[order]
    first = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1]])
    place, cid, side, ref = [], [], [], []
    for a, b in zip(first.tolist(), np.r_[first[1:], len(owner)].tolist()):
        k = _longest_run(on[a:b], n)
        f = k.astype(float)
        if f.max() - f.min() > 0.5 * n:          # an arc across the ring's first vertex
            f = np.where(f < 0.5 * n, f + n, f)
        place.append(float(f.mean()) % n)
        cid.append(int(owner[a]))
        side.append(1)
        ref.append(float(turn[k].sum()))
    kd2, ids2 = ctx._kd[-1]
    if kd2 is not None:
        dist, v = cKDTree(xy).query(ctx.cxy[ids2])
        near = dist <= _ANNULUS_REACH * r
        place += v[near].astype(float).tolist()
        cid += ids2[near].tolist()
        side += [-1] * int(near.sum())
        ref += [0.0] * int(near.sum())
    o = np.argsort(place, kind="stable")
    return np.array(cid, dtype=np.int64)[o], np.array(side, dtype=np.int64)[o], np.array(ref)[o]


def _annulus_loops(ctx: _Context, rings: list[np.ndarray]):
    """``(loops, rest)``: the tight loops found without the free space, each round one part of the core,
    and the initial rings left for the free space (all of them where none is taken).

    Take a part of the guide fillet and, in it, parts of the guide core without holes. The closed mortar
    between them is a planar domain whose holes are those core parts and the fillet part's own holes (the
    anticore in it), pinched where the core and the fillet share S's edges; a simple closed curve in it is
    homotopic to the boundary of the core part it encloses if it encloses that part and no other hole (two
    simple closed curves in a planar domain that part its holes alike are isotopic). A converged finish (no
    piece enters the open core or anticore, every disk turned the right way) whose turns add to +2π and that
    does not touch itself (checked with the others, below) is a simple closed curve in the mortar,
    counter-clockwise; it cannot leave its part of the fillet without entering the anticore. If it wraps a
    disk of its core part, that part, connected, lies wholly inside it; a core centre of every other core part
    and an anticore centre in every hole of the same part of the fillet are checked to lie outside (each r
    deep in its hole). Being taut, the curve is then the unique shortest one in its class: the loop the free
    space would give. Where such a loop touches itself or another, surgery would operate: every ring then goes
    to the free space.

    The start is a guess from the core's boundary (`_annulus_start`); a guess that the first exact checks
    show far off is given up after a few rounds (`_ANNULUS_ROUNDS`), and its ring goes to the free space.
    """
    if ctx.two or ctx.zero or not rings:
        return [], rings
    R_parts = [P for P in shapely.get_parts(ctx.R) if not P.is_empty]
    F_parts = [P for P in shapely.get_parts(ctx.F) if not P.is_empty]
    if sum(1 + len(P.interiors) for P in R_parts) != len(rings) or not F_parts:
        return [], rings
    # The part of the fillet each part of the core lies in (the core lies in the fillet).
    probe = shapely.points([np.asarray(P.representative_point().coords[0]) for P in R_parts])
    inner, outer = shapely.STRtree(F_parts).query(probe, predicate="intersects")
    owner = np.full(len(R_parts), -1)
    owner[inner] = outer
    first = np.cumsum([0] + [1 + len(P.interiors) for P in R_parts])     # each part's first ring
    # Where a part of the fillet holds several parts of the core: the part each core centre lies in (a
    # point-in-polygon test on the prepared part, after its box) and one centre of each part.
    shared = np.flatnonzero(np.bincount(owner[owner >= 0], minlength=len(F_parts)) > 1)
    part_of = np.full(len(ctx.cxy), -1)
    witness = np.full(len(R_parts), -1)
    if len(shared):
        core = np.flatnonzero(ctx.cside == 1)
        many = np.flatnonzero(np.isin(owner, shared))
        ci, pk = shapely.STRtree([R_parts[k] for k in many]).query(shapely.points(ctx.cxy[core]))
        for j in np.unique(pk).tolist():
            P = R_parts[many[j]]
            shapely.prepare(P)
            c = core[ci[pk == j]]
            c = c[shapely.contains_xy(P, ctx.cxy[c, 0], ctx.cxy[c, 1])]
            part_of[c] = many[j]
            if len(c):
                witness[many[j]] = c[0]
    # Each part of the fillet all or nothing: a loop of the free space may touch one found here.
    found: list[_DiskLoop | None] = [None] * len(R_parts)
    for f, F_part in enumerate(F_parts):
        held = np.flatnonzero(owner == f).tolist()
        if not held or any(len(R_parts[k].interiors) for k in held):
            continue
        lakes = _hole_witnesses(ctx, F_part)                   # an anticore centre in each hole
        if lakes is None:
            continue
        loops = []
        for k in held:
            L = _annulus_loop(ctx, rings[first[k]])
            others = np.concatenate([witness[[j for j in held if j != k]], lakes]).astype(np.int64)
            if L is not None and len(held) > 1 and not (part_of[L.cid[L.side > 0]] == k).any():
                L = None                                        # it does not wrap its own core part
            if L is not None and len(others):
                inside = Polygon(L.to_loop().sample(1e-3 * ctx.r))
                if (others < 0).any() or shapely.contains_xy(inside, *ctx.cxy[others].T).any():
                    L = None                                    # it encloses another hole too
            if L is None:
                break
            loops.append(L)
        else:
            for k, L in zip(held, loops, strict=True):
                found[k] = L
    taken, rest = [], []
    for k, P in enumerate(R_parts):
        if found[k] is not None:
            taken.append(found[k])
        else:
            rest += rings[first[k]:first[k] + 1 + len(P.interiors)]
    if taken and _contacts(ctx, taken):         # a loop touching itself or another: surgery's case
        return [], rings
    return taken, rest


#: A finish with a budget (from a guess) gives up on a loop whose turns add to more than this many π: it
#: winds round twice or more (4π: no such guess was seen to settle; the disk union's 5-loop part at 10k
#: spent 0.09 s finding that out, now 0.007 s), and each round of checks on it costs more than the free
#: space would.
_WOUND = 3.0


#: `_shrink_parts` gives up (every ring goes through the free space) once the parts of the core whose loops
#: it could not show hold more than this share of the shrink's boundary (by its sample points).
_GIVE_UP_SHARE = 0.25


def _shrink_loops(ctx: _Context) -> list[_DiskLoop] | None:
    """Every part of the core's tight loop shown from the exact shrink (`_shrink_parts`), none touching
    another; else None."""
    parts = _shrink_parts(ctx)
    if parts is None or any(Ls is None for Ls, _ in parts):
        return None
    loops = [L for Ls, _ in parts for L in Ls]
    return None if _contacts(ctx, loops) else loops


def _shrink_parts(ctx: _Context) -> list[tuple[list[_DiskLoop] | None, np.ndarray]] | None:
    """For each part of the core, its tight loops found from the exact shrink's boundary (no guide core or
    fillet, no free space): its outer loop, then the loops round the anticore in the holes of its parts
    of E (`_hole_loop`); or None where they cannot be shown to be the ones; and a point of that part's
    shrink (r deep in the core). None where the shrink's loops cannot be grouped into the core's parts.

    The argument of `_annulus_loops`, on the exact sets. Each loop of the boundary of ``E = S↓r``
    (chained from its exact pieces) bounds one part of E, or, clockwise, a hole of one (its signed area
    in closed form). The core ``R = E ⊕ D_r`` is the union of the disks on E's parts, and its parts are
    E's loops grouped by a distance under 2r (`_core_groups`), each hole's loop with the loop round it
    (`_with_holes`). A hole of R with no anticore in it has a loop that shrinks away: the tightening from
    the core is then bounded by one loop a part of R, and one a hole of R that holds anticore. Each part
    gets the exact finish from a guess made along its loops of E (`_shrink_start`, spliced where there are
    several); each loop must settle and turn by +2π (whether it touches itself or another, `_contacts`,
    is the caller's to ask). A hole of E gets a loop from a guess along its loop of E where it holds anticore
    (`_hole_loop`). A settled loop stays out of the open core and anticore, so it is r or more from every
    point of E and of ``(S^c)↓r``: such points lie on one side of it or the other beyond doubt. The region
    between a part's outer loop and its holes' loops must hold a point of each of its own loops of E and
    no point of any other loop of E, nor of any loop or isolated point of ``(S^c)↓r`` (every part of the
    anticore inside a loop holds such points: a pocket in a cavity, anticore in a hole of R; the anticore
    round S no settled loop can enclose). The outer loop then encloses one part of R and nothing else the
    mortar has holes round but what lies inside its holes' loops: the unique taut loop of that part, the
    free space's; each hole's loop is the free space's for its hole of R, and no other hole of that part
    keeps a loop. A part of E that is a single point (an isolated corner: a loop of one disk, which the
    finish does not check) is left to the caller. A part whose loop is not shown is the caller's too
    (`_core_loops`): the witnesses of the parts that are shown include its points, so those loops stand
    whatever its loop turns out to be.
    """
    if ctx.two or ctx.zero:
        return None
    kd, _ = ctx._kd[1]
    if kd is None:
        return None
    from .exact_morphology import _NODE_PRECISIONS

    r = ctx.r
    tol = _NODE_PRECISIONS * max(ctx.xE.precision, ctx.xG.precision)
    try:
        _, P, cycles, lone = ctx.side_loops(1)
        _, PG, anti_cycles, anti_lone = ctx.side_loops(-1)
    except RuntimeError:                                # the pieces do not close (`exact_morphology._chain`)
        return None
    if not cycles or len(lone):
        return None                                     # a part of the shrink that is a single point
    hole = _cycle_areas(P, cycles) < -tol * r
    points = [_cycle_points(P, np.asarray(c), r) for c in cycles]
    groups = _core_groups([xy for xy, _ in points], r,
                          exact=lambda i, j: _cycle_distance(P, cycles[i], cycles[j], 2.1 * r), tie=tol)
    if groups is None or (hole.any() and (groups := _with_holes(P, cycles, points, hole, groups)) is None):
        return None
    groups.sort(key=len, reverse=True)
    # The largest parts first: where one of them is not shown, the free space is built for it anyway,
    # and the others would save little of it (`_GIVE_UP_SHARE`).
    size = np.array([sum(len(points[k][0]) for k in group) for group in groups])
    others = np.concatenate([PG.start[[c[0] for c in anti_cycles]].reshape(-1, 2), anti_lone.reshape(-1, 2)])
    loops: list[list[_DiskLoop] | None] = [None] * len(groups)
    failed = 0
    for g in np.argsort(-size, kind="stable").tolist():
        outer = [k for k in groups[g] if not hole[k]]
        starts = [_shrink_start(ctx, P, cycles[k], points[k], tol) for k in outer]
        start = None if not starts or any(s is None for s in starts) else starts[0]
        for more in starts[1:] if start is not None else ():
            start = _spliced(ctx, start, more)
        L = None if start is None else _settled(ctx, start)
        if L is None and len(outer) == 1 and start is not None and (start[1] < 0).any() \
                and (start[1] > 0).any():
            # Along one loop of E, the anticore disks may be placed wrong (beside a deep bay, one core disk
            # early); without them the finish puts in the ones the tangents enter, where they enter. (A
            # spliced guess that does not settle is most often wrong at a splice: the part has a hole.)
            core = start[1] > 0
            L = _settled(ctx, tuple(x[core] for x in start))
        if L is not None:
            holes = [_hole_loop(ctx, P, cycles[k], points[k], tol) for k in groups[g] if hole[k]]
            loops[g] = None if any(H is False for H in holes) else [L] + [H for H in holes if H is not None]
        if loops[g] is None:
            failed += size[g]
            if failed > _GIVE_UP_SHARE * size.sum():
                return None
    own = P.start[[c[0] for c in cycles]]
    shown = [g for g, L in enumerate(loops) if L is not None]
    if shown:
        owner = np.empty(len(cycles), np.int64)
        for g, group in enumerate(groups):
            owner[group] = g
        regions = [_region(loops[g], r) for g in shown]
        for g, R in zip(shown, regions, strict=True):
            loops[g] = None if R is None else loops[g]
        keep = [k for k, R in enumerate(regions) if R is not None]
        shown, regions = [shown[k] for k in keep], [regions[k] for k in keep]
    if shown:
        point, region = shapely.STRtree(regions).query(shapely.points(np.concatenate([own, others])),
                                                       predicate="within")
        # A part's region (inside its outer loop, outside its holes' loops) must hold a point of each of its
        # own loops of E and no other point (another part's of E, or the anticore's).
        holds = np.zeros((len(shown), len(cycles)), dtype=bool)
        wrong = np.zeros(len(shown), dtype=bool)
        mine = point < len(cycles)
        holds[region[mine], point[mine]] = True
        wrong[region[~mine]] = True
        wrong[region[mine][owner[point[mine]] != np.asarray(shown)[region[mine]]]] = True
        for k, g in enumerate(shown):
            if wrong[k] or not holds[k, groups[g]].all():
                loops[g] = None
        if size[[L is None for L in loops]].sum() > _GIVE_UP_SHARE * size.sum():
            return None                         # refused by their witnesses: as if they had not settled
    return [(L, own[group[0]]) for L, group in zip(loops, groups, strict=True)]


def _polygon(xy: np.ndarray) -> Polygon:
    """The polygon of a ring of points (empty where they are too few to bound anything)."""
    return Polygon(xy) if len(xy) >= 3 else Polygon()


def _region(loops: list[_DiskLoop], r: float):
    """The region a part's loops bound (the first its outer loop, the others its holes' loops), sampled
    within 1e-3·r; None where that is not a valid polygon (a hole's loop outside the outer loop, or two
    crossing)."""
    rings = [L.to_loop().sample(1e-3 * r) for L in loops]
    region = Polygon(rings[0], rings[1:])
    return region if region.is_valid else None


def _with_holes(P, cycles, points, hole: np.ndarray, groups: list[list[int]]) -> list[list[int]] | None:
    """The groups of the shrink's loops with each clockwise loop (a hole of a part of E) joined to the group
    of the innermost counter-clockwise loop round it (that part's outer loop); None where a hole's loop
    lies in no outer loop."""
    outer = np.flatnonzero(~hole)
    polygons = [_polygon(points[k][0]) for k in outer.tolist()]
    area = np.array([p.area for p in polygons])
    inner = np.flatnonzero(hole)
    point, poly = shapely.STRtree(polygons).query(shapely.points(P.start[[cycles[k][0] for k in inner]]),
                                                  predicate="within")
    label = np.empty(len(cycles), np.int64)
    for g, group in enumerate(groups):
        label[group] = g
    merged = {g: list(group) for g, group in enumerate(groups)}
    for i, k in enumerate(inner.tolist()):
        round_it = poly[point == i]
        if not len(round_it):
            return None
        a, b = label[outer[round_it[np.argmin(area[round_it])]]], label[k]
        if a != b:
            merged[a] += merged.pop(b)
            label[merged[a]] = a
    return list(merged.values())


def _hole_loop(ctx: _Context, P, cycle: list[int], points, tol: float):
    """The tight loop round the anticore in a hole of a part of E, from a guess along that hole's loop of E
    (`_shrink_start`): None where it shrinks away, or there is no disk to start from (no anticore
    there); False where it does not settle turning by −2π inside that loop of E.

    Such a loop stays out of the open core, so r or more from E: inside the hole's loop, it lies in a hole
    of the core R (the hole of E less what R covers), round that hole's anticore. The caller's witnesses
    show that it holds all of it (no point of ``(S^c)↓r`` is left between the loops): a simple loop round
    every hole of a planar domain is homotopic to its outer boundary, the hole of R's ring, so it is that
    ring's taut loop.
    """
    start = _shrink_start(ctx, P, cycle, points, tol, hole=True)
    if start is None:
        return None             # no disk near it: no anticore in the hole (the witnesses check it)
    H = _without_grazed(ctx, _finish_steps(ctx, *start, rounds=_ANNULUS_ROUNDS))
    if H is None or (H.n == 1 and H.side[0] > 0):
        return None                                 # shrunk away: no anticore in this hole
    if not H.converged or abs(float(H.sweep.sum()) + _TWO_PI) > 1e-6:
        return False
    here = H.to_loop().sample(1e-3 * ctx.r)[0]
    return H if _polygon(points[0]).contains(shapely.Point(here)) else False


def _cycle_areas(P, cycles: list[list[int]]) -> np.ndarray:
    """The signed area each chained cycle of offset pieces encloses (counter-clockwise positive), from
    its pieces in closed form: ½∮(x dy − y dx) over each segment, and over each arc
    ½(ρ²·sweep + ρ·(cx·(sin a1 − sin a0) − cy·(cos a1 − cos a0)))."""
    d, arc = P.data, P.arc
    seg = 0.5 * (d[:, 0] * d[:, 3] - d[:, 2] * d[:, 1])
    a0, sw = d[:, 3], d[:, 4]
    a1 = a0 + sw
    rho = d[:, 2]
    arcs = 0.5 * (rho * rho * sw
                  + rho * (d[:, 0] * (np.sin(a1) - np.sin(a0)) - d[:, 1] * (np.cos(a1) - np.cos(a0))))
    each = np.where(arc, arcs, seg)
    return np.array([each[c].sum() for c in cycles])


#: `_cycle_points`: an arc is sampled every this many radians (its chords within 0.02·r of it), a straight
#: piece every r but at most this many times (r may be a millionth of the shape).
_CYCLE_ARC_STEP = math.pi / 8
_CYCLE_SEG_POINTS = 16


def _cycle_points(P, idx: np.ndarray, r: float):
    """Points along one chained cycle of offset pieces (arcs every `_CYCLE_ARC_STEP`, straight pieces
    every r up to `_CYCLE_SEG_POINTS` times, each piece from its start) and the place of each: piece number
    plus fraction along it."""
    data, arc = P.data[idx], P.arc[idx]
    seg_len = np.where(arc, 0.0, np.hypot(data[:, 2] - data[:, 0], data[:, 3] - data[:, 1]))
    m = np.where(arc, np.ceil(np.abs(data[:, 4]) / _CYCLE_ARC_STEP),
                 np.minimum(np.ceil(seg_len / r), _CYCLE_SEG_POINTS)).astype(np.int64)
    m = np.maximum(m, 1)
    row = np.repeat(np.arange(len(idx)), m)
    f = (np.arange(len(row)) - np.repeat(np.cumsum(m) - m, m)) / np.repeat(m, m)
    th = data[row, 3] + data[row, 4] * f
    on_arc = data[row, :2] + data[row, 2:3] * np.column_stack([np.cos(th), np.sin(th)])
    on_seg = data[row, :2] + f[:, None] * (data[row, 2:4] - data[row, :2])
    return np.where(arc[row][:, None], on_arc, on_seg), row + f


def _core_groups(points: list[np.ndarray], r: float, exact=None, tie: float = 0.0) -> list[list[int]] | None:
    """The loops of the shrink's boundary grouped into parts of the core: two parts of the shrink less than
    2r apart have overlapping disks. From the loops' points (`_cycle_points`, within 0.02·r of the exact
    loops); where two loops are within 0.05·r of 2r apart, too close to call from them, from
    ``exact(i, j)``, their exact distance (`_cycle_distance`), if given; None where that is within
    ``tie`` + 1e-12·r of 2r (the two parts of the core touch at a point, or nearly: the offsets' rounding
    decides) or no ``exact`` is given. Each group in an order in which every loop after the first is less
    than 2r from one before it.

    Examples
    --------
    Two unit squares' boundaries 1.5 apart are one part of the core at r = 1, 3 apart two:

    >>> sq = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)])
    >>> _core_groups([sq, sq + (2.5, 0.0)], 1.0), _core_groups([sq, sq + (4.0, 0.0)], 1.0)
    ([[0, 1]], [[0], [1]])
    """
    if len(points) == 1:
        return [[0]]
    lines = np.array([shapely.linestrings(np.vstack([xy, xy[:1]])) for xy in points])
    tree = shapely.STRtree(lines)
    i, j = tree.query(lines, predicate="dwithin", distance=2.05 * r)
    far = i != j
    i, j = i[far], j[far]
    if not len(i):
        return [[k] for k in range(len(points))]
    d = shapely.distance(lines[i], lines[j])
    band = np.flatnonzero((d > 1.95 * r) & (d <= 2.05 * r))
    if len(band):
        if exact is None:
            return None
        for k in band.tolist():
            d[k] = exact(int(i[k]), int(j[k]))
            if abs(d[k] - 2.0 * r) <= tie + 1e-12 * r:
                return None
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import breadth_first_order, connected_components

    near = d <= 1.95 * r
    graph = coo_matrix((np.ones(int(near.sum())), (i[near], j[near])), shape=(len(points),) * 2).tocsr()
    n, label = connected_components(graph, directed=False)
    groups = []
    for g in range(n):
        first = int(np.flatnonzero(label == g)[0])
        groups.append(breadth_first_order(graph, first, directed=False, return_predecessors=False).tolist())
    return groups


def _cycle_distance(P, a: list[int], b: list[int], reach: float) -> float:
    """The exact distance between two chained cycles of offset pieces (`_Context.side_loops`), or inf
    where it exceeds ``reach``: the closed forms (`_pieces`) over the pairs of pieces whose bounding boxes
    come within ``reach`` of each other (an arc's box is its whole circle's).

    Examples
    --------
    A unit square's boundary and the circle of radius 1 about (3.5, 0.5):

    >>> import math
    >>> from types import SimpleNamespace
    >>> sq = [(0, 0, 1, 0), (1, 0, 1, 1), (1, 1, 0, 1), (0, 1, 0, 0)]
    >>> data = np.array([s + (0.0,) for s in sq] + [(3.5, 0.5, 1.0, 0.0, 2 * math.pi)])
    >>> P = SimpleNamespace(data=data, arc=np.array([False] * 4 + [True]))
    >>> float(_cycle_distance(P, [0, 1, 2, 3], [4], 3.0))
    1.5
    """
    def boxes(idx):
        d, arc = P.data[idx], P.arc[idx]
        rho = np.where(arc, d[:, 2], 0.0)
        lo = np.where(arc[:, None], d[:, 0:2] - rho[:, None], np.minimum(d[:, 0:2], d[:, 2:4]))
        hi = np.where(arc[:, None], d[:, 0:2] + rho[:, None], np.maximum(d[:, 0:2], d[:, 2:4]))
        return shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1])

    a, b = np.asarray(a), np.asarray(b)
    ia, ib = shapely.STRtree(boxes(b)).query(boxes(a), predicate="dwithin", distance=reach)
    if not len(ia):
        return math.inf
    pa, pb = a[ia], b[ib]
    d = piece_distances(P.arc[pa], P.data[pa], P.arc[pb], P.data[pb])
    for k in np.flatnonzero(np.isnan(d)).tolist():
        d[k] = piece_distance(*(("arc", (P.data[p, 0:2], *P.data[p, 2:5])) if P.arc[p] else
                                ("seg", (P.data[p, 0:2], P.data[p, 2:4])) for p in (pa[k], pb[k])))[0]
    return float(d.min())


def _shrink_start(ctx: _Context, P, cycle: list[int], points, tol: float, hole: bool = False):
    """A cyclic disk sequence to start the exact finish from, made along one loop of the exact shrink's
    boundary: the core disk at each of its corners (turning by the corner's turn), and every anticore disk
    within (`_ANNULUS_REACH` + 1)·r of it, at the place along the loop nearest its centre; None if the
    loop has no corner that is a core centre (for a ``hole``'s loop, which may have none: no disk at all).
    ``points``: the loop's `_cycle_points`."""
    from .exact_morphology import _turn

    r = ctx.r
    kd, ids = ctx._kd[1]
    idx = np.asarray(cycle)
    d, j = kd.query(P.start[idx], distance_upper_bound=tol)
    at = np.flatnonzero(np.isfinite(d))
    if not len(at) and not hole:
        return None
    t_in, t_out = P.t1[np.roll(idx, 1)], P.t0[idx]
    turn = _turn(t_in, t_out)
    # Places along the core's boundary the loop runs round: piece k's points at 2k + 1 + fraction, the
    # arc about corner k (the start of piece k) from 2k to 2k + 1, its disk at the middle.
    place, cid, ref, side = [2.0 * at + 0.5], [ids[j[at]]], [turn[at]], [np.ones(len(at), np.int64)]
    kd2, ids2 = ctx._kd[-1]
    if kd2 is not None:
        xy, where = points
        reach = (_ANNULUS_REACH + 1.0) * r
        c = ctx.cxy[ids2]
        near = ids2[((c >= xy.min(axis=0) - reach) & (c <= xy.max(axis=0) + reach)).all(axis=1)]
        if len(near):
            dist, k = cKDTree(xy).query(ctx.cxy[near], distance_upper_bound=reach)
            ok = np.isfinite(dist)
            if ok.any():
                # Only the anticore on the loop's own side: inside a hole's loop, outside an outer loop (the
                # anticore inside an outer loop is in the holes of its part of E, 2r or more from E).
                ok[ok] = shapely.contains_xy(_polygon(xy), *ctx.cxy[near[ok]].T) == hole
            near, k = near[ok], k[ok]
            piece = np.floor(where[k]).astype(np.int64)
            frac = where[k] - piece
            at_corner = frac == 0.0
            # Nearest a corner: along the corner's arc, by the direction of the centre from it between the
            # outward normals of the pieces in and out (the boundary's right side: E is on its left).
            u = ctx.cxy[near] - xy[k]
            a_in = np.arctan2(-t_in[piece, 0], t_in[piece, 1])
            span = turn[piece]
            rel = np.remainder(np.arctan2(u[:, 1], u[:, 0]) - a_in + math.pi, _TWO_PI) - math.pi
            with np.errstate(invalid="ignore", divide="ignore"):
                t = np.where(np.abs(span) > 1e-12, np.clip(rel / span, 0.0, 1.0), 0.5)
            place.append(np.where(at_corner, 2.0 * piece + t, 2.0 * piece + 1.0 + frac))
            cid.append(near)
            ref.append(np.zeros(len(near)))
            side.append(-np.ones(len(near), np.int64))
    o = np.argsort(np.concatenate(place), kind="stable")
    if not len(o):
        return None
    return np.concatenate(cid).astype(np.int64)[o], np.concatenate(side)[o], np.concatenate(ref)[o]


def _spliced(ctx: _Context, a, b):
    """Two guesses round parts of the shrink that one part of the core holds, made one: ``a`` up to its core
    disk nearest one of ``b``'s, then ``b`` all round from that disk, then the rest of ``a`` (the way the
    core's boundary runs from one part across the neck to the other and back); a disk of ``b`` that ``a``
    holds already is left out."""
    ca, sa, ra = a
    cb, sb, rb = b
    fresh = ~np.isin(cb, ca)
    cb, sb, rb = cb[fresh], sb[fresh], rb[fresh]
    core_a, core_b = np.flatnonzero(sa > 0), np.flatnonzero(sb > 0)
    if not len(core_b):
        return a
    d, k = cKDTree(ctx.cxy[cb[core_b]]).query(ctx.cxy[ca[core_a]])
    i = int(core_a[np.argmin(d)])
    j = int(core_b[k[np.argmin(d)]])
    roll = np.r_[j:len(cb), 0:j]
    # The disks at the two ends of each crossing turn by what the neck leaves of their corners, which
    # is not known here: no turn to go by (else a corner turned the wrong way there would be taken the
    # long way round, and the loop would wind twice).
    ref = np.concatenate([ra[:i + 1], rb[roll], ra[i + 1:]])
    n_b = len(roll)
    ref[[i, i + 1, i + n_b, (i + n_b + 1) % len(ref)]] = 0.0
    return (np.concatenate([ca[:i + 1], cb[roll], ca[i + 1:]]),
            np.concatenate([sa[:i + 1], sb[roll], sa[i + 1:]]), ref)


def _hole_witnesses(ctx: _Context, F_part: Polygon) -> np.ndarray | None:
    """One anticore centre in each hole of a part of the guide fillet (r deep in the anticore there, so r
    or more from any loop in the mortar), or None if some hole holds none."""
    if not len(F_part.interiors):
        return np.zeros(0, dtype=np.int64)
    anti = np.flatnonzero(ctx.cside == -1)
    xy = ctx.cxy[anti]
    out = []
    for ring in F_part.interiors:
        hole = Polygon(ring)
        x0, y0, x1, y1 = hole.bounds
        c = anti[(xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)]
        shapely.prepare(hole)
        c = c[shapely.contains_xy(hole, ctx.cxy[c, 0], ctx.cxy[c, 1])]
        if not len(c):
            return None
        out.append(int(c[0]))
    return np.array(out, dtype=np.int64)


def _annulus_loop(ctx: _Context, ring: np.ndarray) -> _DiskLoop | None:
    """The tight loop from a guess on one ring of the core's boundary (`_annulus_loops`), or None where
    the finish does not settle on a loop that is certainly the one."""
    start = _annulus_start(ctx, ring)
    if start is None:
        return None
    return _settled(ctx, start)


def _settled(ctx: _Context, start) -> _DiskLoop | None:
    """The exact finish from a guess ``(cid, side, ref)`` within `_ANNULUS_ROUNDS` rounds, if it settles on
    a loop round at least one core disk that turns by +2π; else None."""
    L = _without_grazed(ctx, _finish_steps(ctx, *start, rounds=_ANNULUS_ROUNDS))
    if L is None or not L.converged or not (L.side > 0).any():
        return None
    return None if abs(float(L.sweep.sum()) - _TWO_PI) > 1e-6 else L


# ---------------------------------------------------------------------------------------------------------
# Surgery
# ---------------------------------------------------------------------------------------------------------
def _piece_arrays(loops: list[_DiskLoop]):
    """All pieces of all loops as shapely lines (arcs sampled finely) with owner, index and arclength span."""
    lines, owner, index, start, stop, totals = [], [], [], [], [], []
    for li, L in enumerate(loops):
        n = L.n
        rr = L.r if np.ndim(L.r) == 0 else L.rho           # each disk's radius with two radii
        arc_len = rr * np.abs(L.sweep)
        seg_len = L.length if n > 1 else np.zeros(1)
        lens = np.empty(2 * n)
        lens[0::2], lens[1::2] = arc_len, seg_len
        cum = np.concatenate([[0.0], np.cumsum(lens)])
        totals.append(cum[-1])
        a0 = L.arc_start() if n > 1 else np.zeros(1)
        arcs = np.flatnonzero(arc_len > 0)
        if len(arcs):
            m = np.maximum(2, np.ceil(np.abs(L.sweep[arcs]) / (math.pi / 32)).astype(np.int64) + 1)
            ow = np.repeat(np.arange(len(arcs)), m)
            first = np.repeat(np.cumsum(m) - m, m)
            f = (np.arange(len(ow)) - first) / np.repeat(m - 1, m)
            th = a0[arcs][ow] + L.sweep[arcs][ow] * f
            ra = rr if np.ndim(rr) == 0 else rr[arcs][ow][:, None]
            pts = L.c[arcs][ow] + ra * np.column_stack([np.cos(th), np.sin(th)])
            lines.append(shapely.linestrings(pts, indices=ow))
            owner.append(np.full(len(arcs), li))
            index.append(2 * arcs)
        if n > 1:
            segs = np.flatnonzero(L.length > 0)
            if len(segs):
                P, Q = L.tangent_points()
                lines.append(shapely.linestrings(np.stack([P[segs], Q[segs]], axis=1)))
                owner.append(np.full(len(segs), li))
                index.append(2 * segs + 1)
        for idx in index[len(start):]:
            start.append(cum[idx])
            stop.append(cum[idx + 1])
    if not lines:
        return None
    return (np.concatenate(lines), np.concatenate(owner), np.concatenate(index),
            np.concatenate(start), np.concatenate(stop), np.array(totals))


def _contacts(ctx: _Context, loops: list[_DiskLoop]):
    """Touching places among the loops: list of (a, piece_a, x, b, piece_b, y).

    Two loops touch where two of their pieces come within `TOUCH_SCALE` (the local frame has unit size);
    one loop touches itself where two pieces do that are far apart along it (at least 0.9·π·r: between two
    places where a loop of curvature ≤ 1/r meets itself it must turn by π).
    """
    touch = TOUCH_SCALE
    r = ctx.r
    # Between two places where a loop meets itself it turns by π: along it at least π times its smallest
    # radius of curvature (the smaller of two radii).
    r_turn = (min(ctx.ra, ctx.rb) or max(ctx.ra, ctx.rb)) if getattr(ctx, "two", False) else r
    arrays = _piece_arrays(loops)
    if arrays is None:
        return []
    lines, owner, index, start, stop, totals = arrays
    tree = shapely.STRtree(lines)
    sag = r * (1 - math.cos(math.pi / 64)) + touch
    ia, ib = tree.query(lines, predicate="dwithin", distance=sag)
    keep = ia < ib
    ia, ib = ia[keep], ib[keep]
    # Pieces of one loop that lie within 0.9·π·r of each other along it cannot touch in the surgery sense:
    # the separation along the loop of any two of their points, measured either way round, is at most the
    # span from the first one's start to the last one's end (the exact test below is then always false).
    # Measured either way round, the separation is also at most the loop's length less the narrowest
    # separation one way (pieces on either side of where the loop's numbering starts).
    same = owner[ia] == owner[ib]
    far = np.maximum(stop[ia], stop[ib]) - np.minimum(start[ia], start[ib])          # widest separation
    near = np.maximum(0.0, np.maximum(start[ia], start[ib]) - np.minimum(stop[ia], stop[ib]))
    keep = ~same | (np.minimum(far, totals[owner[ia]] - near) >= 0.9 * math.pi * r_turn)
    # A segment and the arc it leaves or enters meet only where they join: the segment lies on the arc's
    # tangent there, and a circle meets its tangent once; their nearest points are that join, no distance
    # apart along the loop (the exact test below is then false).
    step = np.abs(index[ia] - index[ib])
    pieces_of = np.array([2 * L.n for L in loops])[owner[ia]]
    keep &= ~(same & ((step == 1) | (step == pieces_of - 1)))
    out = []
    used = set()
    pieces_cache = {}
    for a, b in zip(ia[keep].tolist(), ib[keep].tolist()):
        la, lb = int(owner[a]), int(owner[b])
        if la in used or lb in used:
            continue
        for li in (la, lb):
            if li not in pieces_cache:
                pieces_cache[li] = loops[li].pieces()
        Pa = pieces_cache[la][index[a]]
        Pb = pieces_cache[lb][index[b]]
        d, x, y = piece_distance((Pa[0], Pa[1]), (Pb[0], Pb[1]))
        if d > touch:
            continue
        if la == lb:
            sa = start[a] + _along(Pa, x)
            sb = start[b] + _along(Pb, y)
            gap = abs(sa - sb)
            gap = min(gap, totals[la] - gap)
            if gap < 0.9 * math.pi * r_turn:
                continue
        out.append((la, int(index[a]), x, lb, int(index[b]), y))
        used.update((la, lb))
    return out


def _along(piece, x) -> float:
    kind, g, ln = piece
    if kind == "seg":
        p, q = g
        return float(math.hypot(*(x - p)))
    c, r, a0, sw = g
    th = math.atan2(x[1] - c[1], x[0] - c[0])
    off = (th - a0) % _TWO_PI if sw >= 0 else (a0 - th) % _TWO_PI
    if off > abs(sw):
        # Outside the arc by rounding: snap to the nearer end.
        off = 0.0 if (_TWO_PI - off) < (off - abs(sw)) else abs(sw)
    return r * off


def _reconnect(ctx: _Context, loops: list[_DiskLoop], contact) -> list[np.ndarray]:
    """New closed polylines after surgery at one contact."""
    la, pa, x, lb, pb, y = contact
    tol = ctx.tol_int
    A = loops[la].polyline_from(pa, x, tol)
    if la != lb:
        B = loops[lb].polyline_from(pb, y, tol)
        return [np.concatenate([A, B, [y]])]
    # One loop touching itself: cut it into the part from x to y and the part from y to x.
    # Where y is along the loop: the nearest polyline point to y that is not near x along the loop (x and
    # y coincide in the plane, and `_contacts` guarantees at least 0.9·π·r between them both ways).
    full = A
    step = np.hypot(*np.diff(np.vstack([full, full[:1]]), axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(step)[:-1]])
    total = along[-1] + step[-1]
    r_turn = (min(ctx.ra, ctx.rb) or max(ctx.ra, ctx.rb)) if ctx.two else ctx.r
    away = np.minimum(along, total - along) >= 0.4 * math.pi * r_turn
    d = np.where(away, np.hypot(*(full - y).T), np.inf)
    k = int(np.argmin(d))
    first = np.concatenate([full[: k + 1], [y]])
    second = np.concatenate([[y], full[k + 1:], [x]])
    return [first, second]


def _rings_not_shown(ctx: _Context, parts) -> list[np.ndarray] | None:
    """The rings of the guide core's parts whose loops `_shrink_parts` did not show (each part's outer ring
    and holes), or None where its parts do not match the exact shrink's groups one to one (each part of the
    guide core must hold the point of at most one group, and each group's point must lie in one part)."""
    R_parts = [P for P in shapely.get_parts(ctx.R) if not P.is_empty]
    marks = np.array([xy for _, xy in parts]).reshape(-1, 2)
    point, part = shapely.STRtree(R_parts).query(shapely.points(marks), predicate="within")
    if len(point) != len(parts) or len(np.unique(point)) != len(parts) or len(np.unique(part)) != len(parts):
        return None
    shown = np.zeros(len(R_parts), dtype=bool)
    shown[part] = [parts[i][0] is not None for i in point.tolist()]
    return [shapely.get_coordinates(ring) for k in np.flatnonzero(~shown).tolist()
            for ring in shapely.get_rings(R_parts[k])]


def _tighten_all(ctx: _Context, rings: list[np.ndarray], shown: list[_DiskLoop] = ()) -> list[_DiskLoop]:
    """Tighten every ring, then operate where loops touch (these and the loops ``shown`` already tight)
    until none do.

    A loop whose exact finish did not settle is left as it is (marked ``converged = False``) rather than
    operated on: its pieces are not where the tight loop's are, and a contact of it may be none. Where the
    new rings of a surgery cannot be tightened, the loops it joined or split are kept instead, marked.
    """
    loops = list(shown) + [L for L in (_tighten_ring(ctx, ring) for ring in rings) if L is not None]
    for _ in range(_MAX_SURGERY_ROUNDS):
        contacts = [c for c in _contacts(ctx, loops) if loops[c[0]].converged and loops[c[3]].converged]
        if not contacts:
            return loops
        involved = set()
        operated: list[_DiskLoop] = []
        for contact in contacts:
            if contact[0] in involved or contact[3] in involved:
                continue
            involved.update((contact[0], contact[3]))
            try:
                new = [_tighten_ring(ctx, ring) for ring in _reconnect(ctx, loops, contact)]
            except _EngineError:
                for li in {contact[0], contact[3]}:
                    loops[li].converged = False
                    operated.append(loops[li])
                continue
            operated += [L for L in new if L is not None]
        loops = [L for i, L in enumerate(loops) if i not in involved] + operated
    raise _EngineError("surgery did not settle")


# ---------------------------------------------------------------------------------------------------------
# Initial loops
# ---------------------------------------------------------------------------------------------------------
def _rings(P) -> list[np.ndarray]:
    if P.is_empty:
        return []
    return [shapely.get_coordinates(ring) for ring in shapely.get_rings(shapely.get_parts(P))]


def _initial_rings(ctx: _Context, S_local, init: Init) -> list[np.ndarray]:
    if init is Init.CORE:
        return _rings(ctx.R)
    if init is Init.INPUT:
        return _rings(S_local)
    if ctx.two:
        # Two radii: Mason between R_a and F_b (`morphology._mason` with ``r_concave``).
        q_a = quad_segs_for(ctx.ra, ctx.tol_int) if ctx.ra > 0 else 0
        M = _m._mason(S_local, ctx.ra, q_a, ctx.tol_int, exact=(ctx.xE, ctx.xG, ctx.S), r_concave=ctx.rb)
        return _rings(M)
    S_m, r_m, q_m = _m._prepare(S_local, ctx.r, ctx.tol_int)
    M = _m._mason(S_m, r_m, q_m, ctx.tol_int, exact=(ctx.xE, ctx.xG, ctx.S))   # offsets computed once
    return _rings(M)


def _exact_depths(ctx: _Context, L: _DiskLoop, limit: float = 0.0) -> tuple[float, float]:
    """How deep the loop enters the open core and the open anticore: ``r − distance`` to the exact shrink
    of S (and of its complement), by exact piece-to-piece distances (no sampling), 0 where it stays out.

    Candidates come from the obstacle index (the exact pieces, arcs by chords within ``osag``) queried with
    the loop's segments and its arcs' chords, drawn wide by both sags; each (loop piece, exact piece) pair
    is then solved in closed form (`_pieces.piece_distance`). Depths of at most ``limit`` are reported as
    0. A piece lying wholly inside a region is caught by its middle.
    """
    return _exact_depths_many(ctx, [L], limit)[0]


#: `_exact_depths_many` sets aside the straight pieces that lie on an edge of S (off: every piece measured).
_SKIP_ON_EDGES = True


def _depth_pieces(ctx: _Context, loops: list[_DiskLoop], step: float):
    """The pieces `_exact_depths_many` measures, as arrays (loop by loop, arc i then the tangent leaving
    disk i, as `_DiskLoop.pieces`; tangents of length 0 left out): whether each is an arc, its
    `_pieces` row (a segment's ends; an arc's centre, radius, start and sweep), its loop, the offset its
    disk may sit off its exact corner, a middle point, and the chords that stand for it in the index
    query (an arc's every ``step`` radians at most) with the piece each belongs to."""
    r = ctx.r
    rows, arcs, loop_of, allow = [], [], [], []
    for k, L in enumerate(loops):
        if not L.n:
            continue
        # A loop's disk may sit off the exact corner it stands for by that corner's own rounding (the
        # fast path solves corners from S's vertices; an acute corner's position is ill-conditioned):
        # that offset, up to CENTRE_ROUNDING_R·r or a thousand times the coordinates' precision, moves
        # the disk's pieces as much and is not an entry.
        off = np.zeros(L.n)
        if ctx.ckd is not None:
            d, _ = ctx.ckd.query(L.c)
            off = np.where(d <= max(CENTRE_ROUNDING_R * r, 1e3 * ctx.precision), d, 0.0)
        rad = np.broadcast_to(np.asarray(L.r, dtype=float), (L.n,))
        if L.n == 1:
            a0, P = np.zeros(1), None
        else:
            P, Q = L.tangent_points()
            a0 = L.arc_start()
        row = np.zeros((2 * L.n, 5))
        row[0::2] = np.column_stack([L.c, rad, a0, L.sweep])
        is_arc = np.zeros(2 * L.n, dtype=bool)
        is_arc[0::2] = True
        keep = is_arc.copy()
        if P is not None:
            row[1::2, 0:2], row[1::2, 2:4] = P, Q
            keep[1::2] = L.length > 0
        here = np.empty(2 * L.n)
        here[0::2] = off
        here[1::2] = np.maximum(off, np.roll(off, -1))
        rows.append(row[keep]), arcs.append(is_arc[keep]), allow.append(here[keep])
        loop_of.append(np.full(int(keep.sum()), k, dtype=np.int64))
    if not rows:
        z = np.zeros((0, 2))
        return (np.zeros(0, bool), np.zeros((0, 5)), np.zeros(0, np.int64), np.zeros(0), z, z, z,
                np.zeros(0, np.int64))
    params, is_arc = np.concatenate(rows), np.concatenate(arcs)
    loop_of, allow = np.concatenate(loop_of), np.concatenate(allow)
    # Chords: a segment is its own; an arc of sweep sw, m = ⌈|sw|/step⌉ chords between the points at
    # start + sw·j/m (j = 0 … m, as `np.linspace`), its middle the point at j = m // 2 (m > 1) or the
    # middle of its one chord.
    m = np.where(is_arc, np.maximum(1, np.ceil(np.abs(params[:, 4]) / step)), 1).astype(np.int64)
    owner = np.repeat(np.arange(len(params)), m)
    start = np.cumsum(m) - m
    j = np.arange(len(owner)) - start[owner]
    arc_o = is_arc[owner]
    mo = m[owner]

    def at(jj):
        t = jj * (1.0 / mo)
        t = np.where(jj == mo, 1.0, t)
        th = params[owner, 3] + params[owner, 4] * t
        c, rr = params[owner, 0:2], params[owner, 2]
        return np.column_stack([c[:, 0] + rr * np.cos(th), c[:, 1] + rr * np.sin(th)])

    cp = np.where(arc_o[:, None], at(j), params[owner, 0:2])
    cq = np.where(arc_o[:, None], at(j + 1), params[owner, 2:4])
    mids = 0.5 * (params[:, 0:2] + params[:, 2:4])
    k = np.flatnonzero(is_arc)
    first = start[k]
    mids[k] = np.where((m[k] > 1)[:, None], cp[first + m[k] // 2], 0.5 * (cp[first] + cq[first]))
    return is_arc, params, loop_of, allow, mids, cp, cq, owner


class _PieceRows:
    """`_pieces` rows read back as ``(kind, geometry)`` pieces, one at a time (for the closed forms)."""

    def __init__(self, is_arc: np.ndarray, params: np.ndarray):
        self.is_arc, self.params = is_arc, params

    def __len__(self) -> int:
        return len(self.params)

    def __getitem__(self, i: int):
        x = self.params[i]
        if self.is_arc[i]:
            return "arc", (x[0:2], float(x[2]), float(x[3]), float(x[4]))
        return "seg", (x[0:2], x[2:4])


def _exact_depths_many(ctx: _Context, loops: list[_DiskLoop], limit: float = 0.0) -> list[tuple[float, float]]:
    """`_exact_depths` of every loop, with one query of the obstacle index for all of them."""
    r = ctx.r
    depth = [{1: 0.0, -1: 0.0} for _ in loops]
    step = math.pi / 64
    sag = r * (1.0 - math.cos(0.5 * step))
    is_arc, params, loop_of, allow, mids, cp, cq, owner = _depth_pieces(ctx, loops, step)
    pieces = _PieceRows(is_arc, params)
    if not len(pieces):
        return [(0.0, 0.0) for _ in loops]
    where = ctx.in_regions(mids)
    for s in (1, -1):
        for k in np.unique(loop_of[where == s]).tolist():
            depth[k][s] = ctx.radius_of(s)
    if ctx.zero:
        # A radius 0: how far a straight piece enters that side's region, by its boundary chain
        # (`_zero_radius`); a piece lying inside it (its middle in the region) enters it wholly.
        for k in range(len(loops)):
            segs = ~is_arc & (loop_of == k)
            if segs.any():
                P0, Q0 = params[segs, 0:2], params[segs, 2:4]
                deepest = max((d for _, _, d in zero_entries(ctx, P0, Q0, ctx.zero)), default=0.0)
                inside = bool((where[loop_of == k] == ctx.zero).any())
                depth[k][ctx.zero] = max(depth[k][ctx.zero], r if inside else 0.0,
                                         deepest if deepest > limit else 0.0)
    if len(ctx.oedges) == 0:
        return [(dk[1], dk[-1]) for dk in depth]
    if _SKIP_ON_EDGES and not ctx.zero and limit > 0:
        # A straight piece lying on an edge of S (both its ends within limit/2 of that one edge) enters
        # neither region deeper than limit/2: every point of ∂S is at distance r or more from S↓r and
        # from (S^c)↓r, and the distance to a segment is convex along another. Such pieces (most of a
        # fast-path loop's) need no query.
        seg_rows = np.flatnonzero(~is_arc)
        if len(seg_rows):
            ends = np.concatenate([params[seg_rows, 0:2], params[seg_rows, 2:4]])
            edge, dist = ctx._s_tree.query_nearest(shapely.points(ends), return_distance=True, all_matches=False)
            near = np.zeros(len(ends), dtype=np.int64)
            near[edge[0]] = edge[1]
            close = np.zeros(len(ends), dtype=bool)
            close[edge[0]] = dist <= 0.5 * limit
            m = len(seg_rows)
            on_s = close[:m] & close[m:] & (near[:m] == near[m:])
            if on_s.any():
                drop = np.zeros(len(pieces), dtype=bool)
                drop[seg_rows[on_s]] = True
                chord = ~drop[owner]
                cp, cq, owner = cp[chord], cq[chord], owner[chord]
    reach = r - limit + ctx.osag + sag + 1e-12 * r
    ci, ei = ctx.oindex.near_segments(cp, cq, reach)
    li, pj = owner[ci], ctx.opiece[ei]
    order = np.lexsort((pj, li))
    li, pj = li[order], pj[order]
    first = np.ones(len(li), dtype=bool)
    first[1:] = (li[1:] != li[:-1]) | (pj[1:] != pj[:-1])
    li, pj = li[first], pj[first]
    if len(li):
        # Nearly every pair is a loop piece resting on an exact piece (distance r, depth 0) or farther:
        # the vectorised distances set aside those whose depth is clearly at most ``limit``; the others
        # are decided by the closed form, one by one.
        o_arc, o_params = _obstacle_arrays(ctx)
        d = piece_distances(is_arc[li], params[li], o_arc[pj], o_params[pj])
        size = 1.0 + r + max(float(np.abs(params[:, :2]).max()), float(np.abs(o_params[:, :2]).max()))
        margin = 64 * np.finfo(float).eps * size                  # ≫ their rounding
        rad = r if not ctx.two else ctx.radius_of(np.array([ctx.opieces[j][0] for j in pj.tolist()]))
        keep = ~(rad - d - allow[li] <= limit - margin)           # NaN: decide exactly
        li, pj = li[keep], pj[keep]
    for i, j in zip(li.tolist(), pj.tolist()):
        side, piece = ctx.opieces[j]
        d, _, _ = piece_distance(pieces[i], piece)
        rad = r if not ctx.two else ctx.radius_of(side)
        dk = depth[loop_of[i]]
        if rad - d - allow[i] > max(dk[side], limit):
            dk[side] = rad - d - allow[i]
    return [(dk[1], dk[-1]) for dk in depth]


# ---------------------------------------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------------------------------------
@dataclass
class Tightening:
    """The exact r-tightening of a shape.

    Attributes
    ----------
    loops : list of Loop
        The exact boundary: outer boundaries counter-clockwise, holes clockwise; straight segments and
        arcs of radius exactly ``r``, G1 at every join.
    geometry : Polygon or MultiPolygon
        Valid shapely geometry sampled from the loops within ``tolerance`` (every sampled point lies on
        the exact curve). Empty when everything vanishes.
    r : float
        The radius (for two radii, the larger: see `two_radii.TwoRadiiTightening`; ``radii`` gives both).
    init : str
        The initial condition: ``"core"``, ``"input"`` or ``"mason"``.
    tolerance : float
        Largest distance between an arc and the chords of ``geometry``.
    shape : Polygon or MultiPolygon
        The (validated) input.
    """

    loops: list[Loop]
    geometry: Polygon | MultiPolygon
    r: float
    init: str
    tolerance: float
    shape: Polygon | MultiPolygon
    converged: bool = True
    _cache: dict = field(default_factory=dict, repr=False)

    # -- exact measures -----------------------------------------------------------------------------------
    @property
    def perimeter(self) -> float:
        """Exact length of the boundary (sum over the loops' segments and arcs)."""
        return math.fsum(loop.length for loop in self.loops)

    @property
    def area(self) -> float:
        """Exact area enclosed (Green's theorem over the loops; holes count negative)."""
        return math.fsum(loop.area for loop in self.loops)

    @property
    def min_radius_of_curvature(self) -> float:
        """Exact minimum radius of curvature of the boundary (inf if empty)."""
        return min((loop.min_radius_of_curvature for loop in self.loops), default=math.inf)

    @property
    def n_components(self) -> int:
        """Number of connected components."""
        return sum(1 for loop in self.loops if loop.area > 0)

    @property
    def n_holes(self) -> int:
        """Number of holes."""
        return sum(1 for loop in self.loops if loop.area < 0)

    @property
    def is_empty(self) -> bool:
        """True when the tightening is empty."""
        return not self.loops

    @property
    def radii(self) -> tuple[float, float]:
        """``(r_convex, r_concave)``: ``(r, r)`` for one radius (two: `two_radii.TwoRadiiTightening`)."""
        return (self.r, self.r)

    @property
    def r_convex(self) -> float:
        """The radius of the arcs that turn left (about disks of the core)."""
        return self.radii[0]

    @property
    def r_concave(self) -> float:
        """The radius of the arcs that turn right (about disks of the anticore)."""
        return self.radii[1]

    # -- morphology of the input (computed on first use) ---------------------------------------------------
    def _morph(self, name):
        if name not in self._cache:
            fn = {"core": _m.core, "fillet": _m.fillet, "mortar": _m.mortar}[name]
            self._cache[name] = fn(self.shape, self.r, tolerance=self.tolerance)
        return self._cache[name]

    @property
    def core(self):
        """The core ``R_r(S)`` (shapely)."""
        return self._morph("core")

    @property
    def fillet(self):
        """The fillet ``F_r(S)`` (shapely)."""
        return self._morph("fillet")

    @property
    def mortar(self):
        """The mortar ``F_r(S) − R_r(S)`` (shapely; its zero-width parts cannot be represented)."""
        return self._morph("mortar")

    def svg_path(self, precision: int = 12) -> str:
        """SVG path data of all loops (y up, real ``A`` commands); fill it with ``fill-rule="evenodd"``."""
        return " ".join(loop.svg_path(precision) for loop in self.loops)

    # -- self-check ----------------------------------------------------------------------------------------
    def verify(self) -> list[str]:
        """Check DESIGN §7 (a)–(d) on this result; return the list of violations (empty if valid).

        (a) ``R ⊆ T ⊆ F`` within ``tolerance``; (b) the loops are simple and pairwise disjoint and the
        geometry is valid; (c) every arc has radius r and lies on the boundary of the core (turning left)
        or of the fillet (turning right), every join is G1, every straight piece stays in the mortar;
        (d) the radius of curvature is at least r.
        """
        members = self._cache.get("_members")
        if members is not None:
            # Far-apart groups of parts tightened alone (`_split_fast`): each is judged as its own path's
            # result; their fillets are disjoint, so their loops cannot touch.
            problems = [f"{p} (group {k} of far-apart parts)" for k, part in enumerate(members)
                        for p in part.verify()]
            if not self.geometry.is_valid:
                problems.append(f"(b) geometry is invalid: {shapely.is_valid_reason(self.geometry)}")
            return problems
        if self._cache.get("_path") == "empty" and not self.loops:
            S_local, r_l, _, precision = self._cache["_exact"][2]
            if shrink_is_empty(S_local, r_l, precision):
                return []       # no r-disk fits in S (exactly): the core is empty, and so is every loop
        problems: list[str] = []
        r, tol = self.r, self.tolerance
        T = self.geometry
        # Far from the origin the coordinates themselves are rounded (an ulp of 1e12 is 1.2e-4): every
        # length tolerance below includes that rounding, every tangent that of its end points.
        x0, y0, x1, y1 = self.shape.bounds
        rounding = rounding_length(max(x1 - x0, y1 - y0), max(abs(x0), abs(y0), abs(x1), abs(y1)))
        info = self._exact_context()
        if info is not None:
            # (a) exactly and without buffers, on S's exact offsets, for every path: (e) below measures
            # the loops' entry into the open core and anticore piece by piece, and then a handful of
            # point tests decide R ⊆ T ⊆ F (see `_exact_containment`). A buffered reference at a quarter
            # of the tolerance cost 3–40 times the tightening on dense outlines, and GEOS's fillet, which
            # simplifies its input, raised false alarms on exact results (a traced 10k-vertex outline).
            problems += _exact_containment(info[0], self._cache["_frame"], T, self.loops, tol, rounding)
        else:
            R = _m.core(self.shape, r, tolerance=tol / 4)
            F = _m.fillet(self.shape, r, tolerance=tol / 4)
            slack = 2 * tol + 4.0 * rounding
            tiny = 1e-9 * max(x1 - x0, y1 - y0) ** 2
            out_r = R.difference(T.buffer(slack)).area if not R.is_empty else 0.0
            if out_r > tiny:
                problems.append(f"(a) the tightening misses {out_r:.3g} of the core's area")
            out_f = T.difference(F.buffer(slack)).area if not T.is_empty else 0.0
            if out_f > tiny:
                problems.append(f"(a) the tightening extends {out_f:.3g} of area outside the fillet")
        if not T.is_valid:
            problems.append(f"(b) geometry is invalid: {shapely.is_valid_reason(T)}")
        for i, loop in enumerate(self.loops):
            radii = loop.radii
            off = np.flatnonzero(np.abs(radii - r) > 1e-9 * r)
            if len(off):
                problems.append(f"(c) loop {i} has an arc of radius {float(radii[off[0]])!r}, not r = {r!r}")
            if not loop.is_g1(CORNER_ANGLE, rounding):
                problems.append(f"(c) loop {i} has a corner (max {loop.corner_angles().max():.3g} rad)")
            if loop.min_radius_of_curvature < r * (1 - 1e-9):
                problems.append(f"(d) loop {i} has radius of curvature {loop.min_radius_of_curvature:.6g} < r")
        problems += self._check_exact()
        if not self.converged:
            problems.append("the exact finish did not converge everywhere")
        return problems

    def _exact_context(self):
        """The engine's context and exact disk loops, in the local frame (built now if the fast path ran)."""
        info = self._cache.get("_exact")
        if info is None:
            return None
        ctx, disk_loops, args = info
        if ctx is None:
            ctx = _Context(*args)
            disk_loops = _rebind(ctx, disk_loops)
            self._cache["_exact"] = (ctx, disk_loops, args)
        return ctx, disk_loops

    def _check_exact(self) -> list[str]:
        """Arcs on the right boundary, pieces inside the mortar, loops disjoint — in the local frame."""
        problems = self._check_depths()
        if self._cache.get("_path") == "fast":
            return problems + self._check_fast()
        info = self._exact_context()
        if info is None:
            return problems
        ctx, disk_loops = info
        for i, L in enumerate(disk_loops):
            if (L.cid < 0).any():
                problems.append(f"(c) loop {i} has {int((L.cid < 0).sum())} arc(s) not centred on an arc centre "
                                "of the core or the fillet")
            known = L.cid >= 0
            wrong = np.flatnonzero(known & (ctx.cside[np.where(known, L.cid, 0)] != L.side) & (L.sweep != 0))
            if len(wrong):
                problems.append(f"(c) loop {i} wraps {len(wrong)} disk(s) from the wrong side")
            if _violations(ctx, L):
                problems.append(f"(c) loop {i} enters the core or the anticore")
        if _contacts(ctx, disk_loops):
            problems.append("(b) two loops (or two parts of one) touch")
        return problems


    def _check_depths(self) -> list[str]:
        """(e) Every loop stays out of the open core and anticore, measured against S's exact offsets."""
        if self._cache.get("_exact") is None:
            return []
        ctx, disk_loops = self._exact_context()
        limit = max(VERIFY_DEPTH_R * ctx.r, 8.0 * ctx.precision)
        problems = []
        for i, (core, anti) in enumerate(_exact_depths_many(ctx, disk_loops, limit)):
            for name, d in (("core", core), ("anticore", anti)):
                if d > limit:
                    problems.append(f"(e) loop {i} enters the open {name} by {d / ctx.r:.3g}·r (exact offsets)")
        return problems

    def _check_fast(self) -> list[str]:
        """(b) and (c) for a result of the fast path, by its own exact tests.

        Its arcs are centred on S's vertices, tangent to both edges. The general engine's context cannot
        judge them on dense input: GEOS simplifies a buffer's input by up to r/100, so the buffered
        shrink and grow miss the vertices of S that such arcs are centred on. The fast path's tests work
        from the edges of S alone (`_fast`): they are run again on S, and must certify it and give these
        very disks, in the same order, on the same sides, with the same sweeps.
        """
        _, disk_loops, (S_local, r_l, _, precision) = self._cache["_exact"]
        again = _fast.fast_disk_loops(S_local, r_l, quad_segs_for(r_l, EXACT_CHORD_R * r_l), self.init,
                                      precision)
        if again is None:
            return ["(c) the corners of S are not all isolated: the fast path's exact tests reject this result"]
        problems = []
        if len(again) != len(disk_loops):
            problems.append(f"(c) the exact tests give {len(again)} loop(s), the result has {len(disk_loops)}")
        for i, (L, (c, side, _, _, sweep)) in enumerate(zip(disk_loops, again)):
            same = (len(c) == L.n and np.allclose(c, L.c, rtol=0.0, atol=ZERO_SCALE)
                    and (side == L.side).all() and np.allclose(sweep, L.sweep, rtol=0.0, atol=_ANGLE_EPS))
            if not same:
                problems.append(f"(c) loop {i} is not the one the fast path's exact tests certify")
        if _contacts(_Radius(r_l), disk_loops):
            problems.append("(b) two loops (or two parts of one) touch")
        return problems


@dataclass(frozen=True)
class _Radius:
    """All that `_contacts` reads of a context: the radius (local frame)."""

    r: float


def _rebind(ctx: _Context, disk_loops: list[_DiskLoop]) -> list[_DiskLoop]:
    """The same loops with their disks numbered as the context's centres (−1 where none coincides)."""
    if len(ctx.cxy) == 0 or not disk_loops:
        return disk_loops
    d, j = cKDTree(ctx.cxy).query(np.concatenate([L.c for L in disk_loops]))
    cid = np.where(d <= 1e-9 * ctx.r, j, -1)
    cut = np.cumsum([L.n for L in disk_loops])[:-1]
    return [_DiskLoop(k, L.side, L.c, L.phi, L.length, L.sweep, L.r, L.converged)
            for k, L in zip(np.split(cid, cut), disk_loops, strict=True)]


def _exact_containment(ctx: _Context, frame: _Frame, T, loops: list[Loop], tol: float,
                       rounding: float) -> list[str]:
    """(a) ``R ⊆ T ⊆ F`` decided on S's exact offsets, for a result whose loops (e) checks exactly.

    The loops stay out of the open core ``R° = S↓r ⊕ D°_r`` (check (e), exact piece distances), so each
    component of R° lies wholly inside T or wholly outside; each holds a piece or an isolated corner of
    ``S↓r``, at distance ≥ r from the loops. So ``R ⊆ T`` exactly when every piece's middle and every
    corner of ``S↓r`` lies in T, and ``T ∩ anticore = ∅`` exactly when every one of ``(S^c)↓r`` lies
    outside; the sampled geometry, within the tolerance of the loops, decides that as the loops do (the
    points are r away from them). The sampled geometry must be the loops' region: it differs from the
    loops sampled again by at most the chords' sag along them.
    """
    problems = []
    T_loc = frame.to_local(T) if not T.is_empty else T
    shapely.prepare(T_loc)
    for X, inside in ((ctx.xE, True), (ctx.xG, False)):
        xy = X.test_points()
        if len(xy) == 0:
            continue
        if T_loc.is_empty:
            hit = np.zeros(len(xy), dtype=bool)
        else:
            hit = shapely.intersects_xy(T_loc, xy[:, 0], xy[:, 1])
        if inside and not hit.all():
            problems.append(f"(a) the tightening misses {int((~hit).sum())} piece(s) of the core's centres "
                            "(exact offsets)")
        if not inside and hit.any():
            problems.append(f"(a) the tightening covers {int(hit.sum())} piece(s) of the anticore's centres "
                            "(exact offsets)")
    # The geometry must be the loops' own region, sampled: the symmetric difference with the loops
    # assembled again within the tolerance is at most the chords' sag along them (0 when untouched).
    length = sum(L.length for L in loops)
    again = _assemble(loops, tol) if loops else Polygon()
    if T.is_empty and again.is_empty:
        off = 0.0
    elif shapely.get_num_coordinates(T) == shapely.get_num_coordinates(again) and np.array_equal(
            shapely.get_coordinates(T), shapely.get_coordinates(again)):
        off = 0.0                 # the very samples (an overlay of two copies of a dense ring costs seconds)
    else:
        off = shapely.symmetric_difference(T, again).area
    if off > 2.0 * (tol + 4.0 * rounding) * length:
        problems.append(f"(a) the geometry differs from its loops by {off:.3g} of area")
    return problems


def _assemble(loops: list[Loop], tol: float):
    """Shapely geometry from oriented loops: counter-clockwise outer boundaries, clockwise holes."""
    return _assemble_valid(loops, tol)[0]


def _three_distinct(c: np.ndarray) -> bool:
    """Whether the points ``c`` (n, 2) hold at least three distinct ones (one pass, no sort)."""
    other = (c != c[0]).any(axis=1)
    if not other.any():
        return False
    second = c[int(np.argmax(other))]
    return bool((other & (c != second).any(axis=1)).any())


def _assemble_valid(loops: list[Loop], tol: float):
    """Make `_assemble`'s geometry, and tell whether it is known to be valid.

    True if it was found valid before its rings were oriented (which validity does not depend on), None
    if that is not known.
    """
    sign = [lp._orientation() for lp in loops]
    ring = [lp.sample(tol) if s else None for lp, s in zip(loops, sign, strict=True)]
    # A loop sampled to fewer than three points (a lens of two arcs, each within ``tol`` of its chord)
    # is narrower than 2·tol: left out, as chords within ``tol`` would.
    sign = [s if s == 0 or _three_distinct(c) else 0 for s, c in zip(sign, ring, strict=True)]
    outers = [(k, Polygon(ring[k])) for k in range(len(loops)) if sign[k] > 0]
    holes = [(k, Polygon(ring[k])) for k in range(len(loops)) if sign[k] < 0]
    if not outers:
        return Polygon(), None
    shells = [[p, []] for _, p in outers]
    if holes:
        # Each hole goes to the smallest outer boundary that holds its first point inside, or covers it
        # whole (the first on ties): the candidates from an R-tree of the outer boundaries.
        outer_polys = np.array([p for _, p in outers], dtype=object)
        areas = shapely.area(outer_polys)
        tree = shapely.STRtree(outer_polys)
        first = shapely.points(np.array([ring[k][0] for k, _ in holes]))
        hi, oi = tree.query(first, predicate="within")
        hc, oc = tree.query(np.array([h for _, h in holes], dtype=object), predicate="covered_by")
        hole_of, outer_of = np.concatenate([hi, hc]), np.concatenate([oi, oc])
        order = np.lexsort((outer_of, areas[outer_of], hole_of))
        hole_of, outer_of = hole_of[order], outer_of[order]
        pick = np.r_[True, hole_of[1:] != hole_of[:-1]] if len(hole_of) else np.zeros(0, dtype=bool)
        for n, k in zip(hole_of[pick].tolist(), outer_of[pick].tolist()):
            shells[k][1].append(n)
        for hs in shells:
            hs[1].sort()
    polys = []
    for (k, shell), (_, hs) in zip(outers, shells, strict=True):
        # The same coordinates as the loops' samples: a shell without holes is used as it is.
        polys.append(Polygon(ring[k], [ring[holes[n][0]] for n in hs]) if hs else shell)
    geom = polys[0] if len(polys) == 1 else MultiPolygon(polys)
    valid = geom.is_valid or None
    if not valid:
        # Loops that touch themselves or each other at points (parts of a shrink pinched exactly 2r wide):
        # the regions the outer boundaries bound, less the holes', as one valid set. GEOS's "structure"
        # repair is that union and difference, several times cheaper than the default's line noding.
        geom = _m._polygonal(shapely.make_valid(geom, method="structure", keep_collapsed=False))
    return shapely.orient_polygons(geom, exterior_cw=False), valid


def tighten(S, r: float | tuple[float, float], *, init: str | Init = "core",
            tolerance: float | None = None) -> Tightening:
    """The exact r-tightening of a polygonal shape.

    The result T satisfies ``R_r(S) ⊆ T ⊆ F_r(S)`` and its boundary is made of disjoint simple closed
    curves that are locally shortest inside the mortar ``M_r(S)``; every point of it has radius of
    curvature at least r. The curves are returned exactly, as straight segments and arcs of radius r.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon, list of Loop, or Tightening
        The shape, in any units. Invalid polygons are repaired with ``shapely.make_valid`` (with a
        `RepairWarning`). Given by its exact boundary (`Loop`s of segments and arcs, outer boundaries
        counter-clockwise, holes clockwise, or a `Tightening` fed back in), the shape comes back itself,
        with its own pieces, when it is exactly its own tightening, else its arcs are flattened within
        1e-5·r first (see `vectortighten.loop_input`).
    r : float or (float, float)
        The radius, > 0, in the units of S. Or two radii ``(r_convex, r_concave)`` = (a, b), each ≥ 0 and
        not both 0: the core is ``R_a(S)``, the fillet ``F_b(S)``, arcs turning left have radius a and
        arcs turning right radius b, and a radius 0 keeps those corners sharp (``(0, tool_radius)``: the
        CNC inside-corner rule). ``(r, r)`` is r itself. Two different radii return a
        `two_radii.TwoRadiiTightening` (``T.r`` is then the larger radius, ``T.radii`` the pair; see
        `vectortighten.two_radii`).
    init : {"core", "input", "mason"}
        The flow's initial condition: ``"core"`` starts from the core (the paper's implementation: thin
        parts and constrictions go), ``"input"`` from S itself (self-dual, §4.2: tight constrictions
        stay), ``"mason"`` from Mason(S).
    tolerance : float, optional
        Largest distance between an arc and the chords of the sampled ``geometry``; default 1e-5·r.

    Returns
    -------
    Tightening
        Exact loops, sampled geometry, exact ``perimeter`` and ``area``, and ``verify()``. When the core
        and fillet leave no loop (everything vanishes) the result is empty, not an error; when no disk of
        radius r fits in the bounding box of S it is empty at once, whatever the size of r.

    Raises
    ------
    GeometryTypeError
        If S is not polygonal.
    InvalidGeometryError
        If S is empty or has non-finite coordinates.
    InvalidRadiusError
        If r or tolerance is not a positive finite number, if r is below what doubles resolve for S
        (`vectortighten.limits.min_radius`: 1e-8 of its size, 1e-10 of its largest coordinate), or if
        tolerance is below `vectortighten.limits.min_tolerance`.
    ResourceLimitError
        If the sampled geometry could exceed `vectortighten.limits.MAX_OUTPUT_VERTICES` vertices.
    TighteningFailedError
        If the engine fails on this (valid) shape; the message names the cause.

    Warns
    -----
    ConvergenceWarning
        If the exact finish did not settle, or if the result fails the final check ``R ⊆ T ⊆ F``
        (made on every result); ``converged`` is then False.

    References
    ----------
    .. [1] J. Williams and J. Rossignac, "Tightening: Curvature-Limiting Morphological Simplification",
       ACM Symposium on Solid and Physical Modeling (2005).

    Examples
    --------
    >>> from math import pi, isclose
    >>> from shapely.geometry import box
    >>> T = tighten(box(0, 0, 4, 4), 1.0)
    >>> isclose(T.perimeter, 16 - 8 + 2 * pi)       # each corner loses 2r·tan(θ/2) − rθ
    True
    >>> T.min_radius_of_curvature
    1.0
    """
    if not isinstance(r, (int, float)) and _is_pair(r):
        from .two_radii import tighten_two_radii   # r = (r_convex, r_concave)

        return tighten_two_radii(S, r, init=init, tolerance=tolerance)
    if not isinstance(S, (Polygon, MultiPolygon)) and _loop_input(S):
        from .loop_input import tighten_loops   # S given by its exact boundary (segments and arcs)

        return tighten_loops(S, r, init=init, tolerance=tolerance)
    r = check_radius(r)
    S = check_shape(S)
    tol = check_tolerance(tolerance, r, S)
    check_resolution(S, r)
    try:
        init = Init(init.value if isinstance(init, Init) else init)
    except ValueError:
        raise ValueError(f"init must be 'core', 'input' or 'mason', got {init!r}") from None
    check_output_size(S, r, tol)
    return guarded_tighten(_tighten, S, r, init, tol)


def _is_pair(r) -> bool:
    from .two_radii import is_pair

    return is_pair(r)


def _loop_input(S) -> bool:
    from .loop_input import is_loop_input

    return is_loop_input(S)


def _fast_result(fast, frame: _Frame, r_l: float, tol: float):
    """The disk loops, loops and geometry of a fast-path (or convex) result, or Nones if it cannot stand.

    It cannot when its geometry is invalid or empty, or when two of its loops touch: parts of S that touch
    (a repaired self-intersection leaves two parts sharing a vertex) have touching loops too, and only the
    general engine's surgery separates or joins them.
    """
    disk_loops = [_DiskLoop(np.full(len(c), -1), s.astype(np.int64), c, phi, ln, sw, r_l)
                  for c, s, phi, ln, sw in fast]
    loops = [L.to_loop(frame) for L in disk_loops]
    geometry, valid = _assemble_valid(loops, tol)
    if not (valid or geometry.is_valid) or geometry.is_empty:
        return None, None, None
    if len(disk_loops) > 1 and _contacts(_Radius(r_l), disk_loops):
        return None, None, None
    return disk_loops, loops, geometry


#: Parts of S farther apart than this many r are tightened independently (`_split_fast`).
_APART_R = 3.0


def _split_fast(S, r: float, q: int, init: str, precision: float, frame: _Frame, tol: float):
    """Tighten the far-apart groups of S's parts that the fast path takes, each alone.

    Returns ``(groups, rest)``: for each fast group ``(G, path, disk_loops, loops, geometry)`` (G in the
    local frame, path "fast" or "convex", the loops in the world's), and the other parts (a Polygon or MultiPolygon for the
    general engine, or None); or None when S is one group or no group is fast, and the general engine
    takes S whole as before.

    Why groups farther apart than 3r are independent: the core is a union of disks inside S, each inside
    one part. A point p within r of a group A is outside the fillet of A exactly when an open disk of
    radius r outside A holds p; that disk lies within 3r of A, so it misses every other group, and p is
    outside the fillet of S as well. So the fillet, the core and the mortar of S are the unions of the
    groups' own, and the mortar's components, where the tight loops live, each belong to one group.
    """
    parts = shapely.get_parts(S)
    if len(parts) < 2:
        return None
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    # A little over 3r: a pair whose distance rounds below 3r stays together.
    i, j = shapely.STRtree(parts).query(parts, predicate="dwithin", distance=_APART_R * r * (1 + 1e-9))
    n, label = connected_components(coo_matrix((np.ones(len(i)), (i, j)), shape=(len(parts),) * 2),
                                    directed=False)
    if n < 2:
        return None
    groups = [np.flatnonzero(label == k) for k in range(n)]
    done, rest = [], []
    for g in groups:
        G = parts[g[0]] if len(g) == 1 else MultiPolygon(list(parts[g]))
        fast, path = _fast.fast_disk_loops(G, r, q, init, precision), "fast"
        if fast is None and len(g) == 1:
            loop = _convex.convex_disk_loop(G, r)
            fast, path = ([loop], "convex") if loop is not None else (None, path)
        if fast is None and init == Init.CORE.value and core_vanishes(G, r, precision):
            # No core, no loop: the group's tightening from the core is empty (an islet, a speck).
            done.append((G, "empty", [], [], Polygon()))
            continue
        got = _fast_result(fast, frame, r, tol) if fast is not None else (None,)
        if got[0] is None:
            rest.extend(parts[g])
        else:
            done.append((G, path) + got)
    if not done:
        return None
    rest = None if not rest else (rest[0] if len(rest) == 1 else MultiPolygon(rest))
    return done, rest


def _core_loops(ctx: _Context, S_local, init: Init, shortcuts: bool) -> list[_DiskLoop]:
    """The general engine's tight loops: with ``shortcuts`` and ``init="core"``, those shown from the exact
    shrink's boundary (`_shrink_parts`; the parts not shown go alone through the free space, unless they
    are too many) or, failing that, round the guide core's parts that are annuli (`_annulus_loops`); the
    rest through the free space."""
    if shortcuts and init is Init.CORE:
        parts = _shrink_parts(ctx)
        shown = [L for Ls, _ in parts or () if Ls is not None for L in Ls]
        if shown and all(Ls is not None for Ls, _ in parts) and not _contacts(ctx, shown):
            ctx.guide_free = True
            return shown
        if shown:
            rest = _rings_not_shown(ctx, parts)
            if rest is not None:
                return _tighten_all(ctx, rest, shown)
    rings = _initial_rings(ctx, S_local, init)
    taut, rings = _annulus_loops(ctx, rings) if shortcuts and init is Init.CORE else ([], rings)
    return taut + (_tighten_all(ctx, rings) if rings else [])


def _tighten(S, r: float, init: Init, tol: float, allow_fast: bool = True) -> Tightening:
    """`tighten` on checked arguments; ``allow_fast=False`` forces the general engine (for testing)."""
    frame = _Frame.of(S)
    S_local = frame.to_local(S)
    r_l, tol_l = r / frame.scale, tol / frame.scale
    # The local frame keeps the rounding of S's own coordinates: ties are decided to that precision.
    precision = precision_of(S) / frame.scale
    q_exact = quad_segs_for(r_l, EXACT_CHORD_R * r_l)
    fast = _fast.fast_disk_loops(S_local, r_l, q_exact, init.value, precision) if allow_fast else None
    path = "fast"
    if fast is None and allow_fast:
        # A convex polygon's tightening is its opening, for every init (proof in `_convex`).
        loop = _convex.convex_disk_loop(S_local, r_l)
        fast, path = ([loop], "convex") if loop is not None else (None, path)
    ctx = None
    if fast is not None:
        disk_loops, loops, geometry = _fast_result(fast, frame, r_l, tol)
        if disk_loops is None:
            fast = None
    if fast is None and allow_fast and init is Init.CORE and core_vanishes(S_local, r_l, precision):
        # No core (no r-disk fits in S): the tightening from it is empty, and the general engine need not
        # build the exact centres to find that out (`Tightening.verify` asks the exact shrink again).
        fast, path = [], "empty"
        disk_loops, loops, geometry = [], [], Polygon()
    if fast is None and allow_fast and isinstance(S_local, MultiPolygon):
        # Parts far apart are tightened alone: those the fast path takes need no general engine.
        split = _split_fast(S_local, r_l, q_exact, init.value, precision, frame, tol)
        if split is not None:
            groups, rest = split
            if rest is not None:
                sub = _Context(rest, r_l, tol_l, precision)
                more = _core_loops(sub, rest, init, True)
                more_loops = [frame.loop_to_world(L.to_loop()) for L in more]
                groups.append((rest, sub, more, more_loops, _assemble(more_loops, tol)))
            # Each group's result is checked and verified as its path's would be (`_guard.containment_problems`,
            # `Tightening.verify`); the fast groups together, as one shape (one context, not one a group).
            fast_groups = [g for g in groups if g[1] == "fast"]
            if len(fast_groups) > 1:
                parts = [P for g in fast_groups for P in shapely.get_parts(g[0])]
                together = (MultiPolygon(parts), "fast", [L for g in fast_groups for L in g[2]],
                            [L for g in fast_groups for L in g[3]],
                            MultiPolygon([P for g in fast_groups for P in shapely.get_parts(g[4])]))
                groups = [together] + [g for g in groups if g[1] != "fast"]
            members = []
            for G, how, dl, lp, geom in groups:
                part = Tightening(loops=lp, geometry=geom, r=r, init=init.value, tolerance=tol,
                                  shape=frame.to_world(G), converged=all(L.converged for L in dl))
                general = isinstance(how, _Context)
                part._cache.update(_exact=(how if general else None, dl, (G, r_l, tol_l, precision)),
                                   _frame=frame, _path="general" if general else how)
                members.append(part)
            disk_loops = [L for g in groups for L in g[2]]
            loops = [L for g in groups for L in g[3]]
            # The groups' tightenings lie in their fillets, which are disjoint: their parts side by side.
            polygons = [P for g in groups for P in shapely.get_parts(g[4]) if not P.is_empty]
            geometry = polygons[0] if len(polygons) == 1 else MultiPolygon(polygons)
            fast, path = disk_loops, "split"
    if fast is None:
        ctx = _Context(S_local, r_l, tol_l, precision)
        disk_loops = _core_loops(ctx, S_local, init, allow_fast)
        loops = [frame.loop_to_world(L.to_loop()) for L in disk_loops]
        geometry = _assemble(loops, tol)
    result = Tightening(loops=loops, geometry=geometry, r=r, init=init.value, tolerance=tol, shape=S,
                        converged=all(L.converged for L in disk_loops))
    if not result.converged:
        warnings.warn("the exact finish did not settle on every loop: the result may enter the core or the "
                      "anticore (Tightening.verify() lists where)", ConvergenceWarning, stacklevel=3)
    result._cache["_exact"] = (ctx, disk_loops, (S_local, r_l, tol_l, precision))
    result._cache["_frame"] = frame
    result._cache["_path"] = path if fast is not None else "general"
    if path == "split" and fast is not None:
        result._cache["_members"] = members
    return result
