"""Shortest paths and shortest closed curves in a polygonal domain, in a given homotopy class.

The free space (a polygon with holes) is triangulated with shapely's constrained Delaunay triangulation.
A closed curve in it is described by the sequence of triangle edges it crosses; cancelling immediate
back-and-forth crossings (cyclically) leaves its *sleeve*, which determines its free homotopy class. The
shortest curve in the class is found by the funnel algorithm (string pulling through the sleeve's portals)
on the sleeve unrolled periodically: a closed geodesic must wrap at least one obstacle vertex; one is found
on a multiply unrolled sleeve, then the funnel is run from that vertex to its next copy.

References
----------
.. [1] D.T. Lee and F.P. Preparata, "Euclidean shortest paths in the presence of rectilinear barriers",
   Networks 14 (1984) — the funnel algorithm.
.. [2] J. Hershberger and J. Snoeyink, "Computing minimum length paths of a given homotopy class",
   Computational Geometry 4 (1994).
.. [3] J. Sklansky, R. Chazin and B. Hansen, "Minimum-perimeter polygons of digitized silhouettes",
   IEEE Trans. Computers 21 (1972) — the relative convex hull.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

__all__ = ["ClosedGeodesic", "Triangulation", "closed_geodesic", "sleeve", "triangulate"]


@dataclass
class Triangulation:
    """A constrained triangulation of a polygonal domain.

    Attributes
    ----------
    xy : (nv, 2) float
        Vertex coordinates (every vertex lies on the domain's boundary).
    tri : (nt, 3) int
        Vertex indices of each triangle, counter-clockwise.
    edge_vertices : (ne, 2) int
        The interior edges ``(u, v)``.
    edge_triangles : (ne, 2) int
        For each interior edge, the triangle on its left (of u→v) and the one on its right.
    """

    xy: np.ndarray
    tri: np.ndarray
    edge_vertices: np.ndarray
    edge_triangles: np.ndarray
    neighbors: np.ndarray | None = None
    slot_edge: np.ndarray | None = None
    _tree: shapely.STRtree | None = None
    _tri_tree: shapely.STRtree | None = None

    @property
    def edge_tree(self) -> shapely.STRtree:
        """Spatial index over the interior edges."""
        if self._tree is None:
            segs = self.xy[self.edge_vertices]
            self._tree = shapely.STRtree(shapely.linestrings(segs))
        return self._tree


def _triangles(domain, use_earcut: bool = True) -> np.ndarray:
    """Triangles ``(m, 3, 2)`` covering a polygonal domain, with no new vertices.

    Uses earcut (mapbox_earcut, ear clipping in C++) when installed, else shapely's constrained Delaunay
    triangulation (GEOS; many times slower). The funnel algorithm needs a triangulation, not a Delaunay
    one, but it must be edge-to-edge: `triangulate` checks that and falls back to GEOS otherwise (earcut
    can leave T-junctions where vertices of different rings are collinear).
    """
    if use_earcut:
        try:
            import mapbox_earcut
        except ImportError:  # pragma: no cover - the dependency is declared
            use_earcut = False
    if not use_earcut:
        tris = shapely.get_parts(shapely.constrained_delaunay_triangles(domain))
        if len(tris) == 0:
            return np.zeros((0, 3, 2))
        return shapely.get_coordinates(tris).reshape(len(tris), 4, 2)[:, :3]
    out = []
    for poly in shapely.get_parts(domain):
        rings = [np.asarray(poly.exterior.coords)[:-1]] + [np.asarray(h.coords)[:-1] for h in poly.interiors]
        verts = np.concatenate(rings)
        ends = np.cumsum([len(x) for x in rings]).astype(np.uint32)
        idx = np.asarray(mapbox_earcut.triangulate_float64(verts, ends)).reshape(-1, 3)
        out.append(verts[_restore_collinear(idx, verts, ends)])
    return np.concatenate(out) if out else np.zeros((0, 3, 2))


def _restore_collinear(idx: np.ndarray, verts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Earcut's triangles with the ring vertices it skipped put back.

    Earcut drops a vertex exactly collinear with its neighbours; the triangle then has an edge (u, w) along
    the ring that passes over the skipped vertices, a T-junction for the funnel. Each such triangle is
    split into a fan from its third vertex over u, the skipped vertices, w. Only runs of skipped vertices
    that lie exactly on the segment u→w, in order, are restored; anything else is left as it is (and
    `triangulate` then falls back to GEOS, as for any triangulation that does not conform).
    """
    used = np.zeros(len(verts), dtype=bool)
    used[idx.reshape(-1)] = True
    if used.all() or len(idx) == 0:
        return idx
    # Directed triangle edges (a, b) -> (triangle, opposite vertex), in both directions.
    a, b, c = idx[:, 0], idx[:, 1], idx[:, 2]
    n = len(verts)
    eu = np.concatenate([a, b, c, b, c, a]).astype(np.int64)
    ew = np.concatenate([b, c, a, a, b, c]).astype(np.int64)
    eo = np.concatenate([c, a, b, c, a, b])
    et = np.tile(np.arange(len(idx)), 6)
    keys = eu * n + ew
    order = np.argsort(keys, kind="stable")
    keys = keys[order]

    def slot_of(u, w):
        j = int(np.searchsorted(keys, u * n + w))
        if j == len(keys) or keys[j] != u * n + w:
            return None
        return int(et[order[j]]), int(eo[order[j]])

    drop = np.zeros(len(idx), dtype=bool)
    extra = []
    starts = np.r_[0, ends[:-1]].astype(np.int64)
    for s0, s1 in zip(starts.tolist(), ends.tolist()):
        ring_used = used[s0:s1]
        if ring_used.all() or not ring_used.any():
            continue
        kept = s0 + np.flatnonzero(ring_used)
        m = s1 - s0
        for k in range(len(kept)):
            u = int(kept[k])
            w = int(kept[(k + 1) % len(kept)])
            gap = (w - u) % m if w != u else m
            if gap <= 1:
                continue
            run = [s0 + (u - s0 + j) % m for j in range(1, gap)]
            hit = slot_of(u, w)
            if hit is None:
                continue
            t, o = hit
            P, Q = verts[u], verts[w]
            D = Q - P
            R = verts[run]
            cross = D[0] * (R[:, 1] - P[1]) - D[1] * (R[:, 0] - P[0])
            along = (R - P) @ D / (D @ D)
            if (cross != 0).any() or not (np.all(np.diff(along) > 0) and along[0] > 0 and along[-1] < 1):
                continue
            chain = [u] + run + [w]
            drop[t] = True
            extra.extend((chain[j], chain[j + 1], o) for j in range(len(chain) - 1))
    if not extra:
        return idx
    return np.concatenate([idx[~drop], np.array(extra, dtype=idx.dtype).reshape(-1, 3)])


def triangulate(domain: Polygon | MultiPolygon) -> Triangulation:
    """A triangulation of a polygonal domain (no new vertices), with its interior-edge adjacency.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> T = triangulate(box(0, 0, 3, 3).difference(box(1, 1, 2, 2)))
    >>> len(T.tri), len(T.edge_vertices)
    (8, 8)
    """
    T = _build(_triangles(domain))
    if len(T.tri) and not _conforms(T, domain):
        T = _build(_triangles(domain, use_earcut=False))
    return T


def _conforms(T: Triangulation, domain) -> bool:
    """Whether the triangles' unmatched edges are exactly the domain's boundary edges (no T-junction)."""
    key = T.xy[:, 0] + 1j * T.xy[:, 1]          # T.xy is sorted, so are these keys
    want = []
    for ring in shapely.get_rings(shapely.get_parts(domain)):
        c = shapely.get_coordinates(ring)
        k = np.searchsorted(key, c[:, 0] + 1j * c[:, 1])
        if (k >= len(key)).any() or (key[np.minimum(k, len(key) - 1)] != c[:, 0] + 1j * c[:, 1]).any():
            return False
        want.append(np.sort(np.column_stack([k[:-1], k[1:]]), axis=1))
    want = np.concatenate(want)
    slots = np.flatnonzero(T.neighbors.reshape(-1) < 0)
    u = T.tri.reshape(-1)[slots]
    v = np.roll(T.tri, -1, axis=1).reshape(-1)[slots]
    have = np.sort(np.column_stack([u, v]), axis=1)
    if len(have) != len(want):
        return False
    n = len(T.xy)
    return bool(np.array_equal(np.sort(have[:, 0] * n + have[:, 1]), np.sort(want[:, 0] * n + want[:, 1])))


def _build(coords: np.ndarray) -> Triangulation:
    """Vertices, triangles (counter-clockwise) and edge adjacency of a list of triangles."""
    if len(coords) == 0:
        return Triangulation(np.zeros((0, 2)), np.zeros((0, 3), int), np.zeros((0, 2), int),
                             np.zeros((0, 2), int))
    xy, inverse = np.unique(coords.reshape(-1, 2), axis=0, return_inverse=True)
    tri = inverse.reshape(-1, 3)
    p = xy[tri]
    area2 = ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
             - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    keep = area2 != 0
    tri, area2 = tri[keep], area2[keep]
    cw = area2 < 0
    tri[cw] = tri[cw][:, ::-1]
    # Directed edges (u, v) of every triangle; the triangle lies on the left of its own directed edges.
    nt = len(tri)
    u = tri.reshape(-1)
    v = np.roll(tri, -1, axis=1).reshape(-1)
    owner = np.repeat(np.arange(nt), 3)
    key_fwd = u.astype(np.int64) * len(xy) + v
    key_rev = v.astype(np.int64) * len(xy) + u
    order = np.argsort(key_fwd)
    pos = np.searchsorted(key_fwd[order], key_rev)
    pos = np.minimum(pos, len(order) - 1)
    twin = np.where(key_fwd[order][pos] == key_rev, order[pos], -1)
    interior = (twin >= 0) & (u < v)
    ev = np.column_stack([u[interior], v[interior]])
    et = np.column_stack([owner[interior], owner[twin[interior]]])
    # Per triangle slot k (its edge from tri[t, k] to tri[t, k+1]): the neighbour across it (-1 on the
    # boundary) and the interior edge's number.
    neighbors = np.where(twin >= 0, owner[np.maximum(twin, 0)], -1).reshape(nt, 3)
    eid = np.full(3 * nt, -1, dtype=np.int64)
    slots = np.flatnonzero(interior)
    eid[slots] = np.arange(len(slots))
    eid[twin[slots]] = np.arange(len(slots))
    return Triangulation(xy=xy, tri=tri, edge_vertices=ev, edge_triangles=et, neighbors=neighbors,
                         slot_edge=eid.reshape(nt, 3))


def _orient(a, b, c):
    """Twice the signed area of (a, b, c), vectorised over the leading axis."""
    return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])


def _locate(T: Triangulation, p) -> int:
    """The triangle containing point p, or -1.

    A point on an interior edge (u, v), u < v, belongs to the triangle on the left of u→v — the same
    convention the walk in `crossings` uses, so a walk that returns to its start ends where it began.
    """
    if T._tri_tree is None:
        T._tri_tree = shapely.STRtree(shapely.polygons(T.xy[T.tri]))
    cand = T._tri_tree.query(shapely.points(p))
    if len(cand) == 0:
        return -1
    q = T.xy[T.tri[cand]]
    o = np.stack([_orient(q[:, k], q[:, (k + 1) % 3], np.asarray(p)[None, :]) for k in range(3)], axis=1)
    u = T.tri[cand]
    v = np.roll(T.tri[cand], -1, axis=1)
    on_left_by_rule = (u < v) | (T.neighbors[cand] < 0)
    inside = np.flatnonzero(((o > 0) | ((o == 0) & on_left_by_rule)).all(axis=1))
    return int(cand[inside[0]]) if len(inside) else -1


def crossings(T: Triangulation, ring: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Interior edges crossed by a closed polyline, in order along it (a walk through the triangles).

    Parameters
    ----------
    T : Triangulation
    ring : (n, 2) float
        Closed polyline (the first point may or may not be repeated at the end); it must lie in the
        interior of the triangulated domain.

    Returns
    -------
    edges : (k,) int
        Interior edge crossed at each crossing.
    leftward : (k,) bool
        True where the polyline crosses edge (u, v) from its right to its left.

    Notes
    -----
    Points exactly on an edge count as on its left (a consistent symbolic perturbation), so a polyline
    through a vertex or along an edge still gets a well-defined sequence.
    """
    pts = np.asarray(ring, dtype=float)
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]
    keep = np.any(pts != np.roll(pts, -1, axis=0), axis=1)
    pts = pts[keep]
    t = _locate(T, pts[0])
    if t < 0:
        raise ValueError("the polyline starts outside the triangulated domain")
    X = T.xy[:, 0].tolist()
    Y = T.xy[:, 1].tolist()
    tri = T.tri.tolist()
    nbr = T.neighbors.tolist()
    sedge = T.slot_edge.tolist()
    ev0 = T.edge_vertices[:, 0].tolist()
    out_e: list[int] = []
    out_l: list[bool] = []
    P = pts.tolist()
    n = len(P)
    for i in range(n):
        px, py = P[i]
        qx, qy = P[(i + 1) % n]
        entry = -1
        for _ in range(len(tri) + 3):
            a, b, c = tri[t]
            vx = (X[a], X[b], X[c])
            vy = (Y[a], Y[b], Y[c])
            exit_k = -1
            for k in range(3):
                if k == entry:
                    continue
                k1 = (k + 1) % 3
                # q right of the edge (outside the triangle) and the edge straddles p→q. On the edge
                # itself, q belongs to the triangle on the left of (u, v) with u < v.
                oq = (vx[k1] - vx[k]) * (qy - vy[k]) - (vy[k1] - vy[k]) * (qx - vx[k])
                if oq > 0 or (oq == 0 and (tri[t][k] < tri[t][k1] or nbr[t][k] < 0)):
                    continue
                o1 = (qx - px) * (vy[k] - py) - (qy - py) * (vx[k] - px)
                o2 = (qx - px) * (vy[k1] - py) - (qy - py) * (vx[k1] - px)
                if (o1 >= 0) != (o2 >= 0):
                    exit_k = k
                    break
            if exit_k < 0:
                break
            nt = nbr[t][exit_k]
            if nt < 0:
                raise ValueError("the polyline leaves the triangulated domain")
            e = sedge[t][exit_k]
            # Leaving through slot (u -> v) of t, t on its left: rightward iff u is the edge's first vertex.
            out_e.append(e)
            out_l.append(tri[t][exit_k] != ev0[e])
            # Entry slot of the neighbour: the one whose edge is this edge.
            row = sedge[nt]
            entry = row.index(e)
            t = nt
    return np.array(out_e, dtype=np.int64), np.array(out_l, dtype=bool)


def reduce_cyclic(edges: np.ndarray, leftward: np.ndarray) -> list[tuple[int, bool]]:
    """Cancel consecutive crossings of the same edge in opposite directions, cyclically."""
    stack: list[tuple[int, bool]] = []
    for e, lw in zip(edges.tolist(), leftward.tolist()):
        if stack and stack[-1][0] == e and stack[-1][1] != lw:
            stack.pop()
        else:
            stack.append((e, lw))
    i, j = 0, len(stack) - 1
    while i < j and stack[i][0] == stack[j][0] and stack[i][1] != stack[j][1]:
        i += 1
        j -= 1
    return stack[i:j + 1]


def sleeve(T: Triangulation, ring: np.ndarray) -> np.ndarray:
    """Portals of the reduced sleeve of a closed polyline: ``(k, 2)`` vertex ids (left, right) of each.

    Left and right are relative to the direction of travel. An empty result means the polyline is
    contractible in the domain.
    """
    e, lw = crossings(T, ring)
    red = reduce_cyclic(e, lw)
    if not red:
        return np.zeros((0, 2), dtype=int)
    ev = T.edge_vertices[np.array([x[0] for x in red])]
    lw = np.array([x[1] for x in red])
    # Crossing u→v from its right to its left: u is on the traveller's left.
    return np.where(lw[:, None], ev, ev[:, ::-1])


def string_pull(start, end, left, right, left_id=None, right_id=None, start_id=-1):
    """Funnel algorithm: shortest path from ``start`` to ``end`` through portals ``(left[i], right[i])``.

    Consecutive portals must share one end point (they are edges of one triangle). The funnel is kept as
    a deque (left chain, apex, right chain); each portal adds one vertex, so the run is linear.

    Parameters
    ----------
    start, end : (2,) float
    left, right : (k, 2) float
        Portal end points, left and right relative to the direction of travel.
    left_id, right_id : (k,) int, optional
        Identities of the end points (default: the coordinates decide).
    start_id : int, optional
        Identity of ``start`` when it is itself a portal end point (a vertex the path starts from).

    Returns
    -------
    list of (int, int)
        The path's corners as ``(portal index, side)``: side +1 when the path turns left around the left
        end point of that portal, −1 when it turns right around the right end point. The portal index is
        the first portal of the run in which the vertex was the current end point.
    """
    k = len(left)
    left = np.asarray(left, dtype=float)
    right = np.asarray(right, dtype=float)
    if left_id is None:
        _, inv = np.unique(np.vstack([left, right]), axis=0, return_inverse=True)
        inv = inv.reshape(-1)
        left_id, right_id = inv[:k], inv[k:]
    # The funnel: apex, left chain and right chain (deques from the apex outward).
    # Items are (x, y, id, portal index, side).
    apex = (float(start[0]), float(start[1]), int(start_id), -1, 0)
    Lc: deque = deque()
    Rc: deque = deque()
    out: list[tuple[int, int]] = []

    def cross(p, q, t):
        return (q[0] - p[0]) * (t[1] - p[1]) - (q[1] - p[1]) * (t[0] - p[0])

    def add_right(item):
        nonlocal apex
        if (Rc[-1] if Rc else apex)[2] == item[2] and item[2] >= 0:
            return
        while Rc and cross(Rc[-2] if len(Rc) > 1 else apex, Rc[-1], item) >= 0:
            Rc.pop()
        if not Rc:
            while Lc and cross(apex, Lc[0], item) >= 0:
                out.append((Lc[0][3], 1))
                apex = Lc.popleft()
        Rc.append(item)

    def add_left(item):
        nonlocal apex
        if (Lc[-1] if Lc else apex)[2] == item[2] and item[2] >= 0:
            return
        while Lc and cross(Lc[-2] if len(Lc) > 1 else apex, Lc[-1], item) <= 0:
            Lc.pop()
        if not Lc:
            while Rc and cross(apex, Rc[0], item) <= 0:
                out.append((Rc[0][3], -1))
                apex = Rc.popleft()
        Lc.append(item)

    prev_l = prev_r = None
    for i in range(k):
        li, ri = int(left_id[i]), int(right_id[i])
        if li != prev_l:
            add_left((left[i, 0], left[i, 1], li, i, 1))
        if ri != prev_r:
            add_right((right[i, 0], right[i, 1], ri, i, -1))
        prev_l, prev_r = li, ri
    add_right((float(end[0]), float(end[1]), -2, k, 0))
    out.extend((item[3], item[4]) for item in list(Rc)[:-1])
    return [c for c in out if c[0] >= 0]


@dataclass
class ClosedGeodesic:
    """The shortest closed curve in a homotopy class: its corners (vertex ids) and turn directions."""

    vertices: np.ndarray
    sides: np.ndarray
    xy: np.ndarray

    @property
    def length(self) -> float:
        """Length of the polygonal curve."""
        d = np.roll(self.xy, -1, axis=0) - self.xy
        return float(np.hypot(*d.T).sum())


def _corner_ok(prev_xy, v_xy, next_xy, side) -> bool:
    c = (v_xy[0] - prev_xy[0]) * (next_xy[1] - v_xy[1]) - (v_xy[1] - prev_xy[1]) * (next_xy[0] - v_xy[0])
    return c * side >= 0


def closed_geodesic(T: Triangulation, portals: np.ndarray, max_restarts: int = 8) -> ClosedGeodesic | None:
    """Shortest closed curve through a cyclic sequence of portals (a reduced sleeve).

    Parameters
    ----------
    T : Triangulation
    portals : (k, 2) int
        Left and right vertex ids of each portal, as returned by `sleeve`.

    Returns
    -------
    ClosedGeodesic or None
        None for an empty sleeve (a contractible curve: it shrinks to nothing).
    """
    k = len(portals)
    if k == 0:
        return None
    left = T.xy[portals[:, 0]]
    right = T.xy[portals[:, 1]]
    periods = 3
    Lp = np.tile(left, (periods, 1))
    Rp = np.tile(right, (periods, 1))
    mid = 0.5 * (left[0] + right[0])
    # Portals 1..(3k−1) between the midpoint of portal 0 and its copy three periods on.
    lid = np.tile(portals[:, 0], periods)
    rid = np.tile(portals[:, 1], periods)
    corners = string_pull(mid, mid, Lp[1:periods * k], Rp[1:periods * k], lid[1:periods * k], rid[1:periods * k])
    corners = [(i + 1, s) for i, s in corners]
    if not corners:
        raise RuntimeError("closed geodesic wraps no vertex")
    # Start from a corner in the middle period, and run the funnel from it to its next copy.
    start = min(corners, key=lambda c: abs(c[0] - 1.5 * k))
    tried = set()
    for _ in range(max_restarts):
        j, side = start
        j %= k
        tried.add((j, side))
        vid = portals[j, 0 if side > 0 else 1]
        apex = T.xy[vid]
        idx = (np.arange(j + 1, j + k) % k)
        path = string_pull(apex, apex, left[idx], right[idx], portals[idx, 0], portals[idx, 1], start_id=vid)
        path = [(i, sd) for i, sd in path if portals[idx[i], 0 if sd > 0 else 1] != vid]
        ids = [vid] + [portals[idx[i], 0 if s > 0 else 1] for i, s in path]
        sides = [side] + [s for _, s in path]
        xy = T.xy[np.array(ids)]
        if len(ids) == 1:
            # A single corner: the curve would be a point; only possible for degenerate input.
            return ClosedGeodesic(np.array(ids), np.array(sides), xy)
        if _corner_ok(xy[-1], xy[0], xy[1], side):
            return ClosedGeodesic(np.array(ids), np.array(sides), xy)
        # The start vertex is not on the closed geodesic; restart from a corner of this curve.
        nxt = [((idx[i] % k), s) for i, s in path if ((idx[i] % k), s) not in tried]
        if not nxt:
            break
        start = nxt[len(nxt) // 2]
    raise RuntimeError("closed geodesic did not close consistently")
