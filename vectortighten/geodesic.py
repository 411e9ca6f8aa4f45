"""Shortest paths and shortest closed curves in a polygonal domain, in a given homotopy class.

The free space (a polygon with holes) is triangulated by CDT (a constrained Delaunay triangulation in
C++, pythoncdt; O(n log n), robust predicates), or, where CDT refuses the domain, by ear clipping
(earcut) and shapely's constrained Delaunay triangulation where earcut's triangles do not conform to the
boundary. (Measured on the free space of a 10k-vertex rippled star, 32k vertices: CDT 0.05 s, Shewchuk's
Triangle 0.05 s, earcut 0.4 s and not conforming, GEOS many seconds.) A closed curve
in it is described by the sequence of triangle edges it crosses; cancelling immediate back-and-forth
crossings (cyclically) leaves its *sleeve*, which determines its free homotopy class. The shortest curve in
the class is found by the funnel algorithm (string pulling through the sleeve's portals) on the sleeve
unrolled periodically: a closed geodesic must wrap at least one obstacle vertex; one is found on a
multiply unrolled sleeve, then the funnel is run from that vertex to its next copy.

Implementation notes (speed; the results are those of the plain sequential algorithms, bit for bit):

* The triangulation's vertices are numbered by sorting the domain's ring vertices (not every triangle
  corner), and its adjacency comes from one sort of packed undirected edge keys.
* The walk along a polyline goes in chunks: every ``_CHUNK``-th point is located (the triangle of a nearby
  boundary edge, found along a Z-order curve, then a short walk to the point), and the chunks between
  located points are walked side by side in numpy, one step of every chunk per round, with the same
  floating-point predicates in the same order as the one-walker walk. A chunk that does not start where
  the previous one ended (a wrong guess) is walked again from there, so the crossings are exactly the
  single walk's.
* The funnel is a tight loop over flat lists of events (a new left or right portal end point); its first,
  three-period pass stops as soon as the corner it is looking for is known.

References
----------
.. [1] D.T. Lee and F.P. Preparata, "Euclidean shortest paths in the presence of rectilinear barriers",
   Networks 14 (1984) — the funnel algorithm.
.. [2] J. Hershberger and J. Snoeyink, "Computing minimum length paths of a given homotopy class",
   Computational Geometry 4 (1994).
.. [3] J. Sklansky, R. Chazin and B. Hansen, "Minimum-perimeter polygons of digitized silhouettes",
   IEEE Trans. Computers 21 (1972) — the relative convex hull.
.. [4] O. Devillers, S. Pion and M. Teillaud, "Walking in a triangulation", Int. J. Found. Comput. Sci.
   13 (2002) — point location by walking.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

__all__ = ["ClosedGeodesic", "ShortestLoops", "Triangulation", "closed_geodesic", "sleeve", "triangulate"]

#: Slot k of a triangle is its edge from corner k to corner ``_NEXT[k]``.
_NEXT = np.array([1, 2, 0])
#: `crossings` walks a polyline in chunks that start at every _CHUNK-th point (where it is located).
#: Short chunks mean few lockstep rounds (each a fixed numpy overhead), which dominates on the few hundred
#: points of a small shape's ring; measured 1.3–2.7× faster than 16 on rings of 240–2600 points and the
#: same on 30k (`benchmarks/bench_geodesic.py --baseline`, identical crossings).
_CHUNK = 4
#: Lockstep walks (many chunks at once) hand the last few walkers to the one-walker walk.
_LOCKSTEP_MIN_ACTIVE = 16
_LOCKSTEP_MAX_ROUNDS = 4096
#: Point-location walks from a guess give up (the point starts no chunk) after this many steps.
_LOCATE_MAX_STEPS = 24


@dataclass
class Triangulation:
    """A constrained triangulation of a polygonal domain.

    Attributes
    ----------
    xy : (nv, 2) float
        Vertex coordinates (every vertex lies on the domain's boundary), sorted lexicographically.
    tri : (nt, 3) int
        Vertex indices of each triangle, counter-clockwise.
    edge_vertices : (ne, 2) int
        The interior edges ``(u, v)``.
    edge_triangles : (ne, 2) int
        For each interior edge, the triangle on its left (of u→v) and the one on its right.
    neighbors : (nt, 3) int
        The triangle across slot k (the edge from ``tri[t, k]`` to ``tri[t, (k + 1) % 3]``), −1 on the
        boundary.
    slot_edge : (nt, 3) int
        The interior edge of each slot, −1 on the boundary.
    """

    xy: np.ndarray
    tri: np.ndarray
    edge_vertices: np.ndarray
    edge_triangles: np.ndarray
    neighbors: np.ndarray | None = None
    slot_edge: np.ndarray | None = None
    _tree: shapely.STRtree | None = None
    _tri_tree: shapely.STRtree | None = None
    _entry: np.ndarray | None = field(default=None, repr=False)
    _walk: _WalkData | None = field(default=None, repr=False)

    @property
    def edge_tree(self) -> shapely.STRtree:
        """Spatial index over the interior edges."""
        if self._tree is None:
            segs = self.xy[self.edge_vertices]
            self._tree = shapely.STRtree(shapely.linestrings(segs))
        return self._tree


# ---------------------------------------------------------------------------------------------------------
# Triangulating the domain
# ---------------------------------------------------------------------------------------------------------
def _rings_of(poly) -> tuple[np.ndarray, np.ndarray]:
    """Ring vertices of one polygon without the closing points, and the end offset of each ring."""
    rings = shapely.get_rings(poly)
    coords = shapely.get_coordinates(rings)
    nc = shapely.get_num_coordinates(rings)
    keep = np.ones(len(coords), dtype=bool)
    keep[np.cumsum(nc) - 1] = False
    return coords[keep], np.cumsum(nc - 1)


def _earcut_mesh(domain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Earcut's triangles of every part, as indices into the parts' ring vertices.

    Returns
    -------
    verts : (n, 2) float
        The ring vertices of all parts, ring by ring, without closing points.
    idx : (m, 3) int
        Triangles, indices into ``verts`` (ring vertices that earcut skipped put back, see
        `_restore_collinear`).
    ends : (nr,) int
        End offset of each ring in ``verts``.
    """
    import mapbox_earcut

    all_verts, all_idx, all_ends = [], [], []
    base = 0
    for poly in shapely.get_parts(domain):
        if poly.is_empty:
            continue
        verts, ends = _rings_of(poly)
        idx = np.asarray(mapbox_earcut.triangulate_float64(verts, ends.astype(np.uint32)))
        idx = _restore_collinear(idx.astype(np.int64).reshape(-1, 3), verts, ends)
        all_verts.append(verts)
        all_idx.append(idx + base)
        all_ends.append(ends + base)
        base += len(verts)
    if not all_verts:
        return np.zeros((0, 2)), np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(all_verts), np.concatenate(all_idx), np.concatenate(all_ends)


def _triangles(domain, use_earcut: bool = True) -> np.ndarray:
    """Triangles ``(m, 3, 2)`` covering a polygonal domain, with no new vertices.

    Uses earcut (mapbox_earcut, ear clipping in C++) when installed, else shapely's constrained Delaunay
    triangulation (GEOS; many times slower). The funnel algorithm needs a triangulation, not a Delaunay
    one, but it must be edge-to-edge: `triangulate` checks that and falls back to GEOS otherwise (earcut
    can leave T-junctions where vertices of different rings are collinear).
    """
    if use_earcut:
        try:
            import mapbox_earcut  # noqa: F401
        except ImportError:  # pragma: no cover - the dependency is declared
            use_earcut = False
    if not use_earcut:
        tris = shapely.get_parts(shapely.constrained_delaunay_triangles(domain))
        if len(tris) == 0:
            return np.zeros((0, 3, 2))
        return shapely.get_coordinates(tris).reshape(len(tris), 4, 2)[:, :3]
    verts, idx, _ = _earcut_mesh(domain)
    return verts[idx] if len(idx) else np.zeros((0, 3, 2))


def _restore_collinear(idx: np.ndarray, verts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Earcut's triangles with the ring vertices it skipped put back.

    Earcut drops a vertex exactly collinear with its neighbours; the triangle then has an edge (u, w) along
    the ring that passes over the skipped vertices, a T-junction for the funnel. Each such triangle is
    split into a fan from its third vertex over u, the skipped vertices, w. Only runs of skipped vertices
    that lie exactly on the segment u→w, in order, are restored; anything else is left as it is (and
    `triangulate` then falls back to GEOS, as for any triangulation that does not conform).

    The gaps are found per ring with array operations; only the (few) gaps are visited one by one, and
    the triangle holding a gap's edge (u, w) is looked up among the triangles at u.
    """
    n = len(verts)
    used = np.zeros(n, dtype=bool)
    used[idx.reshape(-1)] = True
    if used.all() or len(idx) == 0:
        return idx
    gaps = []                                  # (ring start, ring size, u, w, gap), in ring order
    starts = np.r_[0, ends[:-1]].astype(np.int64)
    for s0, s1 in zip(starts.tolist(), np.asarray(ends).tolist(), strict=True):
        ring_used = used[s0:s1]
        if ring_used.all() or not ring_used.any():
            continue
        kept = s0 + np.flatnonzero(ring_used)
        m = s1 - s0
        nxt = np.roll(kept, -1)
        gap = np.where(nxt != kept, (nxt - kept) % m, m)
        for j in np.flatnonzero(gap > 1).tolist():
            gaps.append((s0, m, int(kept[j]), int(nxt[j]), int(gap[j])))
    if not gaps:
        return idx
    # The directed triangle edges, in the order (a→b, b→c, c→a, b→a, c→b, a→c) block by block; a gap's
    # edge is the first directed edge u→w in that order.
    nt = len(idx)
    a, b, c = idx[:, 0], idx[:, 1], idx[:, 2]
    blocks = ((a, b, c), (b, c, a), (c, a, b), (b, a, c), (c, b, a), (a, c, b))
    at_u = np.zeros(n, dtype=bool)
    at_u[[g[2] for g in gaps]] = True
    slot: dict[tuple[int, int], tuple[int, int]] = {}
    for bi, (eu, ew, eo) in enumerate(blocks):
        for t in np.flatnonzero(at_u[eu]).tolist():
            key = (int(eu[t]), int(ew[t]))
            pos = bi * nt + t
            if key not in slot or pos < slot[key][0]:
                slot[key] = (pos, int(eo[t]))
    drop = np.zeros(nt, dtype=bool)
    extra = []
    for s0, m, u, w, gap in gaps:
        run = [s0 + (u - s0 + j) % m for j in range(1, gap)]
        hit = slot.get((u, w))
        if hit is None:
            continue
        t, o = hit[0] % nt, hit[1]
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


def _dense_rank(a: np.ndarray) -> np.ndarray:
    """Rank of each value among the distinct values of ``a`` (equal values share a rank)."""
    order = np.argsort(a)
    s = a[order]
    new = np.empty(len(a), dtype=bool)
    new[:1] = True
    np.not_equal(s[1:], s[:-1], out=new[1:])
    rank = np.empty(len(a), dtype=np.int64)
    rank[order] = np.cumsum(new) - 1
    return rank


def _unique_rows(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows of ``P`` (n, 2), sorted lexicographically, and the row of each input point.

    The same as ``np.unique(P, axis=0, return_inverse=True)``, by three sorts of integers and floats
    instead of a sort of structured records.
    """
    if len(P) == 0:
        return P.reshape(0, 2), np.zeros(0, dtype=np.int64)
    rx = _dense_rank(P[:, 0])
    ry = _dense_rank(P[:, 1])
    key = rx * (int(ry.max()) + 1) + ry
    order = np.argsort(key)
    ks = key[order]
    first = np.empty(len(P), dtype=bool)
    first[0] = True
    np.not_equal(ks[1:], ks[:-1], out=first[1:])
    inverse = np.empty(len(P), dtype=np.int64)
    inverse[order] = np.cumsum(first) - 1
    return P[order[first]], inverse


def _twins(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """For each directed slot edge u→v, the slot holding v→u (−1 if none), by one sort of packed keys.

    An undirected edge held by exactly two slots in opposite directions pairs them; an edge held by more
    slots (not a triangulation) pairs none of them, so they count as boundary and `triangulate` falls
    back to GEOS.
    """
    m = len(u)
    twin = np.full(m, -1, dtype=np.int64)
    if m < 2:
        return twin
    nv = int(max(u.max(), v.max())) + 1
    ukey = np.minimum(u, v) * nv + np.maximum(u, v)
    bits = max(int(m - 1).bit_length(), 1)
    if nv * nv < 2 ** (62 - bits):
        packed = (ukey << bits) | np.arange(m)
        packed.sort()
        keys = packed >> bits
        slots = packed & ((1 << bits) - 1)
    else:  # pragma: no cover - beyond about a million vertices
        slots = np.argsort(ukey, kind="stable")
        keys = ukey[slots]
    same = keys[1:] == keys[:-1]
    pair = same.copy()
    pair[1:] &= ~same[:-1]
    pair[:-1] &= ~same[1:]
    sa = slots[:-1][pair]
    sb = slots[1:][pair]
    opposite = u[sa] == v[sb]
    sa, sb = sa[opposite], sb[opposite]
    twin[sa] = sb
    twin[sb] = sa
    return twin


def _build_indexed(verts: np.ndarray, idx: np.ndarray, distinct: bool = False) -> tuple[Triangulation, np.ndarray]:
    """Vertices, triangles (counter-clockwise) and edge adjacency of triangles given by vertex indices.

    Returns the triangulation and, for each input vertex, its vertex id (−1 if no triangle uses it).
    Equal points are merged, and the vertices are numbered in lexicographic order of their coordinates.
    With ``distinct`` the vertices are already distinct and sorted so (and all used).
    """
    if len(idx) == 0:
        return (Triangulation(np.zeros((0, 2)), np.zeros((0, 3), int), np.zeros((0, 2), int),
                              np.zeros((0, 2), int)), np.full(len(verts), -1, dtype=np.int64))
    used = np.zeros(len(verts), dtype=bool)
    used[idx.reshape(-1)] = True
    vid = np.full(len(verts), -1, dtype=np.int64)
    if distinct:
        xy, vid = verts, np.arange(len(verts))
    elif used.all():
        xy, vid = _unique_rows(verts)
    else:
        sel = np.flatnonzero(used)
        xy, vid[sel] = _unique_rows(verts[sel])
    tri = vid[idx]
    X, Y = xy[:, 0], xy[:, 1]
    x0, x1, x2 = X[tri[:, 0]], X[tri[:, 1]], X[tri[:, 2]]
    y0, y1, y2 = Y[tri[:, 0]], Y[tri[:, 1]], Y[tri[:, 2]]
    area2 = (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0)
    if not area2.all():
        keep = area2 != 0
        tri, area2 = tri[keep], area2[keep]
    cw = area2 < 0
    if cw.any():
        tri[cw] = tri[cw][:, ::-1]
    # Directed edges (u, v) of every triangle; the triangle lies on the left of its own directed edges.
    nt = len(tri)
    u = tri.reshape(-1)
    v = np.empty_like(u)
    v[0::3], v[1::3], v[2::3] = tri[:, 1], tri[:, 2], tri[:, 0]
    twin = _twins(u, v)
    interior = (twin >= 0) & (u < v)
    slots = np.flatnonzero(interior)
    ev = np.empty((len(slots), 2), dtype=np.int64)
    ev[:, 0], ev[:, 1] = u[slots], v[slots]
    et = np.empty((len(slots), 2), dtype=np.int64)
    et[:, 0], et[:, 1] = slots // 3, twin[slots] // 3
    # Per triangle slot k (its edge from tri[t, k] to tri[t, k+1]): the neighbour across it (-1 on the
    # boundary), the interior edge's number and the neighbour's slot of the same edge.
    has = twin >= 0
    neighbors = np.where(has, twin // 3, -1).reshape(nt, 3)
    eid = np.full(3 * nt, -1, dtype=np.int64)
    eid[slots] = np.arange(len(slots))
    eid[twin[slots]] = np.arange(len(slots))
    entry = np.where(has, twin % 3, -1).reshape(nt, 3)
    T = Triangulation(xy=xy, tri=tri, edge_vertices=ev, edge_triangles=et, neighbors=neighbors,
                      slot_edge=eid.reshape(nt, 3), _entry=entry)
    return T, vid


def _build(coords: np.ndarray) -> Triangulation:
    """Vertices, triangles (counter-clockwise) and edge adjacency of a list of triangles ``(m, 3, 2)``."""
    coords = np.asarray(coords, dtype=float)
    return _build_indexed(coords.reshape(-1, 2), np.arange(3 * len(coords)).reshape(-1, 3))[0]


def _conforms(T: Triangulation, vid: np.ndarray, ends: np.ndarray) -> bool:
    """Whether the triangles' unmatched edges are exactly the domain's boundary edges (no T-junction).

    ``vid`` maps the domain's ring vertices (ring by ring, ending at ``ends``) to vertex ids of T.
    """
    if (vid < 0).any():
        return False
    starts = np.r_[0, ends[:-1]]
    nxt = np.arange(len(vid)) + 1
    nxt[ends - 1] = starts               # each ring's last vertex is followed by its first
    slots = np.flatnonzero(T.neighbors.reshape(-1) < 0)
    if len(slots) != len(vid):
        return False
    u = T.tri.reshape(-1)[slots]
    v = T.tri[:, _NEXT].reshape(-1)[slots]
    n = len(T.xy)
    have = np.minimum(u, v) * n + np.maximum(u, v)
    w = vid[nxt]
    want = np.minimum(vid, w) * n + np.maximum(vid, w)
    return bool(np.array_equal(np.sort(have), np.sort(want)))


def _cdt_mesh(domain) -> tuple[np.ndarray, np.ndarray] | None:
    """The constrained Delaunay triangulation of a polygonal domain by CDT (pythoncdt), or None.

    The ring vertices are merged where they coincide (rings of a valid polygon may touch at points), the
    ring edges are the constraints, and the triangles outside the domain and in its holes are erased by
    CDT's depth parity. No vertex is added: if CDT finds constraint edges that cross (an invalid domain)
    or cannot erase cleanly, None is returned and the caller falls back to GEOS.

    Returns
    -------
    xy : (nv, 2) float
        The distinct ring vertices, sorted lexicographically.
    tri : (nt, 3) int
        Counter-clockwise triangles, indices into ``xy``.
    """
    try:
        import pythoncdt
    except ImportError:  # pragma: no cover - the dependency is declared
        return None
    parts = [p for p in shapely.get_parts(domain) if not p.is_empty]
    if not parts:
        return None
    rings = [_rings_of(p) for p in parts]
    verts = np.concatenate([v for v, _ in rings])
    starts, stops, base = [], [], 0
    for v, ends in rings:
        starts.append(base + np.r_[0, ends[:-1]])
        stops.append(base + ends)
        base += len(v)
    starts, stops = np.concatenate(starts), np.concatenate(stops)
    nxt = np.arange(1, len(verts) + 1)
    nxt[stops - 1] = starts                       # each ring's last vertex is followed by its first
    xy, vid = _unique_rows(verts)
    u, v = vid, vid[nxt]
    keep = u != v
    u, v = u[keep], v[keep]
    e = np.stack([u, v], axis=1).astype(np.uint32)
    if len(xy) < len(verts):                     # rings touch: a constraint may be given twice
        e = np.unique(np.sort(e, axis=1), axis=0)
    cdt = pythoncdt.Triangulation(pythoncdt.VertexInsertionOrder.AUTO,
                                  pythoncdt.IntersectingConstraintEdges.NOT_ALLOWED, 0.0)
    try:
        cdt.insert_vertices(np.ascontiguousarray(xy, dtype=np.float64))
        cdt.insert_edges(np.ascontiguousarray(e))
        cdt.erase_super_triangle()
    except Exception:  # noqa: BLE001 - any failure of the library means: use the fallback
        return None
    if cdt.vertices_count() != len(xy):          # CDT split an edge (a vertex on another ring's edge)
        return None
    arr = cdt.triangles_array()
    tri = np.asarray(arr["vertices"], dtype=np.int64)
    nb = np.asarray(arr["neighbors"], dtype=np.int64)
    inside = _inside_triangles(tri, nb, xy, u, v, domain)
    return (xy, tri[inside]) if inside is not None else None


def _inside_triangles(tri, nb, xy, u, v, domain) -> np.ndarray | None:
    """Which triangles of a triangulation of the convex hull lie in the domain, or None if that fails.

    ``nb[t, k]`` is the triangle across the edge from ``tri[t, k]`` to ``tri[t, (k + 1) % 3]`` (out of
    range on the hull), and ``(u, v)`` are the domain's edges. The triangles are grouped into regions
    across the edges that are not the domain's (connected components of the dual graph with the domain's
    edges removed); every region lies wholly inside or wholly outside, and one point-in-polygon test a
    region decides it. (CDT's own depth-parity erasure does the same, several times slower.)
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    nt, nv = len(tri), len(xy)
    if nt == 0:
        return None
    a = np.repeat(np.arange(nt), 3)
    b = nb.reshape(-1)
    p = tri.reshape(-1)
    q = tri[:, _NEXT].reshape(-1)
    use = (b >= 0) & (b < nt) & (a < b)          # each interior edge once
    a, b, p, q = a[use], b[use], p[use], q[use]
    # A domain edge is a constraint: with distinct vertices each has two ring neighbours, else sort keys.
    deg = np.bincount(np.r_[u, v], minlength=nv)
    if (deg == 2).all():
        n1 = np.empty(nv, dtype=np.int64)
        n2 = np.empty(nv, dtype=np.int64)
        n1[u] = v
        n2[v] = u
        fixed = (n1[p] == q) | (n2[p] == q)
    else:
        keys = np.sort(np.minimum(u, v) * nv + np.maximum(u, v))
        k = np.minimum(p, q) * nv + np.maximum(p, q)
        at = np.minimum(np.searchsorted(keys, k), len(keys) - 1)
        fixed = keys[at] == k
    a, b = a[~fixed], b[~fixed]
    graph = coo_matrix((np.ones(len(a), dtype=np.int8), (a, b)), shape=(nt, nt))
    nc, label = connected_components(graph, directed=False)
    first = np.full(nc, nt, dtype=np.int64)
    np.minimum.at(first, label, np.arange(nt))
    c = xy[tri[first]].mean(axis=1)
    inside = shapely.contains_xy(domain, c[:, 0], c[:, 1])
    return inside[label]


def triangulate(domain: Polygon | MultiPolygon) -> Triangulation:
    """A triangulation of a polygonal domain (no new vertices), with its interior-edge adjacency.

    The constrained Delaunay triangulation by CDT [5]_ (pythoncdt; O(n log n) expected, with robust
    predicates), which conforms to the domain's boundary by construction. Where CDT refuses the domain,
    earcut's triangulation (with the collinear ring vertices it skips put back), or GEOS's constrained
    Delaunay triangulation where earcut's does not conform to the domain's boundary.

    Parameters
    ----------
    domain : Polygon or MultiPolygon
        A valid polygonal domain.

    Returns
    -------
    Triangulation
        Its vertices are the domain's ring vertices, sorted lexicographically.

    References
    ----------
    .. [5] A. Ogre (Artem Amirkhanov), "CDT: constrained Delaunay triangulation", C++ library
       (github.com/artem-ogre/CDT), after V. Domiter and B. Zalik, "Sweep-line algorithm for constrained
       Delaunay triangulation", Int. J. Geogr. Inf. Sci. 22 (2008).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> T = triangulate(box(0, 0, 3, 3).difference(box(1, 1, 2, 2)))
    >>> len(T.tri), len(T.edge_vertices)
    (8, 8)
    """
    mesh = _cdt_mesh(domain)
    if mesh is not None:
        xy, tri = mesh
        used = np.zeros(len(xy), dtype=bool)
        used[tri.reshape(-1)] = True
        if len(tri) and used.all():              # every ring vertex is a corner of a triangle
            return _build_indexed(xy, tri, distinct=True)[0]
    try:
        verts, idx, ends = _earcut_mesh(domain)
    except ImportError:  # pragma: no cover - the dependency is declared
        return _build(_triangles(domain, use_earcut=False))
    T, vid = _build_indexed(verts, idx)
    if len(T.tri) and not _conforms(T, vid, ends):
        T = _build(_triangles(domain, use_earcut=False))
    return T


# ---------------------------------------------------------------------------------------------------------
# Walking along a polyline
# ---------------------------------------------------------------------------------------------------------
def _orient(a, b, c):
    """Twice the signed area of (a, b, c), vectorised over the leading axis."""
    return ((b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
            - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0]))


@dataclass
class _WalkData:
    """Per-triangulation arrays of the walks, computed once and kept on the `Triangulation`."""

    X: np.ndarray           # (nv,) vertex x
    Y: np.ndarray           # (nv,) vertex y
    tri: np.ndarray         # (nt, 3)
    nbr: np.ndarray         # (nt, 3) neighbour across each slot, -1 on the boundary
    sedge: np.ndarray       # (nt, 3) interior edge of each slot
    entry: np.ndarray       # (nt, 3) the slot of the neighbour that is the same edge
    rule: np.ndarray        # (nt, 3) bool: a point on the slot's edge belongs to this triangle
    ev0: np.ndarray         # (ne,) first vertex of each interior edge
    cx: np.ndarray          # (3, nt) corner x of each triangle
    cy: np.ndarray          # (3, nt) corner y
    rule3: np.ndarray       # (3, nt) rule, slot by slot
    flip: np.ndarray        # (nt, 3) bool: the slot runs from the higher vertex id to the lower
    flip3: np.ndarray       # (3, nt) flip, slot by slot
    bbox: np.ndarray | None = None     # (4, nt): xmin, xmax, ymin, ymax, for exact point location
    guess: tuple | None = None         # boundary edges in Z-order, for `_boundary_guess`


def _walk_data(T: Triangulation) -> _WalkData:
    """The walks' arrays of a triangulation (made on first use, then kept on it)."""
    if T._walk is None:
        tri = np.asarray(T.tri, dtype=np.int64)
        nbr = np.asarray(T.neighbors, dtype=np.int64)
        sedge = np.asarray(T.slot_edge, dtype=np.int64)
        entry = T._entry
        if entry is None:
            nb = np.maximum(nbr, 0)
            entry = np.where(nbr >= 0, np.argmax(sedge[nb] == sedge[:, :, None], axis=2), -1)
        rule = (tri < tri[:, _NEXT]) | (nbr < 0)
        flip = tri > tri[:, _NEXT]
        T._walk = _WalkData(X=np.ascontiguousarray(T.xy[:, 0]), Y=np.ascontiguousarray(T.xy[:, 1]), tri=tri,
                            nbr=nbr, sedge=sedge, entry=np.asarray(entry, dtype=np.int64), rule=rule,
                            ev0=np.asarray(T.edge_vertices[:, 0], dtype=np.int64),
                            cx=np.ascontiguousarray(T.xy[:, 0][tri.T]),
                            cy=np.ascontiguousarray(T.xy[:, 1][tri.T]),
                            rule3=np.ascontiguousarray(rule.T), flip=flip,
                            flip3=np.ascontiguousarray(flip.T))
    return T._walk


def _inside(W: _WalkData, cand: np.ndarray, p) -> np.ndarray:
    """Which candidate triangles hold p, by the on-edge convention of `_locate`."""
    V = W.tri[cand]
    q = np.stack([W.X[V], W.Y[V]], axis=-1)
    o = np.stack([_edge_orient(q[:, k], q[:, (k + 1) % 3], np.asarray(p)[None, :], W.flip[cand, k])
                  for k in range(3)], axis=1)
    return ((o > 0) | ((o == 0) & W.rule[cand])).all(axis=1)


def _edge_orient(a, b, p, flip) -> np.ndarray:
    """`_orient` (a, b, p) evaluated from the edge's lower vertex id (``flip``: b is that one), negated.

    Floating-point orientation is not exactly antisymmetric: ``orient(a, b, p)`` and ``−orient(b, a, p)``
    may differ in their last bits, so a point on an edge shared by two triangles could be claimed by
    neither. Evaluating every edge in one direction makes the two triangles' tests exact negatives.
    """
    o = np.where(flip, -_orient(b, a, p), _orient(a, b, p))
    return o


def _locate(T: Triangulation, p) -> int:
    """The triangle containing point p, or -1.

    A point on an interior edge (u, v), u < v, belongs to the triangle on the left of u→v — the same
    convention the walk in `crossings` uses, so a walk that returns to its start ends where it began.
    Where several triangles qualify (p on a vertex), the first one in the order of an STRtree query over
    the triangles is taken.
    """
    W = _walk_data(T)
    if W.bbox is None:
        xs, ys = W.cx, W.cy
        W.bbox = np.stack([np.minimum(np.minimum(xs[0], xs[1]), xs[2]),
                           np.maximum(np.maximum(xs[0], xs[1]), xs[2]),
                           np.minimum(np.minimum(ys[0], ys[1]), ys[2]),
                           np.maximum(np.maximum(ys[0], ys[1]), ys[2])])
    x, y = float(p[0]), float(p[1])
    b = W.bbox
    cand = np.flatnonzero((b[0] <= x) & (x <= b[1]) & (b[2] <= y) & (y <= b[3]))
    inside = cand[_inside(W, cand, np.array([x, y]))]
    if len(inside) <= 1:
        return int(inside[0]) if len(inside) else -1
    # Several: keep the first in the STRtree's order, as a tree query would.
    if T._tri_tree is None:
        T._tri_tree = shapely.STRtree(shapely.polygons(T.xy[T.tri]))
    cand = T._tri_tree.query(shapely.points(p))
    hit = np.flatnonzero(_inside(W, cand, np.array([x, y])))
    return int(cand[hit[0]]) if len(hit) else -1


def _spread_bits(v: np.ndarray) -> np.ndarray:
    """Interleave zeros between the low 31 bits of each integer (for Morton keys)."""
    v = v & 0x7FFFFFFF
    v = (v | (v << 16)) & 0x0000FFFF0000FFFF
    v = (v | (v << 8)) & 0x00FF00FF00FF00FF
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0F
    v = (v | (v << 2)) & 0x3333333333333333
    return (v | (v << 1)) & 0x5555555555555555


def _morton(x: np.ndarray, y: np.ndarray, frame: tuple[float, float, float]) -> np.ndarray:
    """Morton (Z-order) keys of points, quantised to 2³⁰ steps across ``frame = (x0, y0, scale)``."""
    x0, y0, s = frame
    ix = np.clip((x - x0) * s, 0, 2**30).astype(np.int64)
    iy = np.clip((y - y0) * s, 0, 2**30).astype(np.int64)
    return _spread_bits(ix) | (_spread_bits(iy) << 1)


def _boundary_guess(W: _WalkData, px: np.ndarray, py: np.ndarray):
    """For each point, the triangle of a nearby boundary edge and a point inside it near that edge.

    The boundary edges' midpoints are sorted along a Z-order curve; each point takes the nearest of the
    four midpoints around its own place in that order. The free space is a thickened mortar, so the loops
    to tighten run close to its boundary, where this is usually the triangle holding the point or one a
    few steps from it. A guess only: `crossings` checks it.
    """
    if W.guess is None:
        slots = np.flatnonzero(W.nbr.reshape(-1) < 0)
        bt, bk = slots // 3, slots % 3
        a, b, c = W.tri[bt, bk], W.tri[bt, _NEXT[bk]], W.tri[bt, _NEXT[_NEXT[bk]]]
        mx = 0.5 * (W.X[a] + W.X[b])
        my = 0.5 * (W.Y[a] + W.Y[b])
        sx = 0.98 * mx + 0.02 * W.X[c]
        sy = 0.98 * my + 0.02 * W.Y[c]
        x0, y0 = float(W.X.min()), float(W.Y.min())
        ext = max(float(W.X.max()) - x0, float(W.Y.max()) - y0, 1e-300)
        frame = (x0, y0, 2.0**30 / ext)
        key = _morton(mx, my, frame)
        order = np.argsort(key)
        W.guess = (frame, key[order], order, mx, my, sx, sy, bt)
    frame, keys, order, mx, my, sx, sy, bt = W.guess
    if len(keys) == 0:
        return np.full(len(px), -1, dtype=np.int64), px.copy(), py.copy()
    pos = np.searchsorted(keys, _morton(px, py, frame))
    best = bd = None
    for off in (-2, -1, 0, 1):
        j = order[np.clip(pos + off, 0, len(keys) - 1)]
        d = (mx[j] - px) ** 2 + (my[j] - py) ** 2
        if best is None:
            best, bd = j, d
        else:
            closer = d < bd
            best = np.where(closer, j, best)
            bd = np.where(closer, d, bd)
    return bt[best], sx[best], sy[best]


def _locate_many(W: _WalkData, px: np.ndarray, py: np.ndarray, max_steps: int) -> np.ndarray:
    """A likely triangle for each point (where a walk to it from a nearby guess ends), −1 if not found.

    A guess, not a certainty: `crossings` checks every one against the walk that reaches the point.
    """
    guess, sx, sy = _boundary_guess(W, px, py)
    n = len(px)
    end, state, _, _ = _lockstep(W, guess, np.arange(n), np.arange(n) + 1, sx, sy, px, py,
                                 max_rounds=max_steps)
    return np.where(state == 1, end, -1)


def _lockstep(W: _WalkData, start: np.ndarray, first: np.ndarray, stop: np.ndarray, px, py, qx, qy,
              max_rounds: int, min_active: int = 0, record: bool = False):
    """The walk of `crossings` for many chunks of segments at once.

    Walker c starts in triangle ``start[c]`` (skipped if −1) and walks the segments
    ``p[i] → q[i]`` for i from ``first[c]`` to ``stop[c] − 1``, one after the other, as the one-walker
    walk does. Every walker takes one step per round — a step crosses an edge or ends a segment — and a
    round evaluates, for all of them, exactly the tests the one-walker walk makes at that step (the same
    formulas in the same order, so the same floating-point values). Rounds stop after ``max_rounds`` or
    when fewer than ``min_active`` walkers are left.

    Returns
    -------
    end : (n,) int
        The triangle where each walker ended (−1 if it did not finish).
    state : (n,) int8
        1 finished, 2 left the domain, 0 not started or not finished.
    resume : tuple of arrays
        ``(walker, triangle, entry slot, segment, steps in that segment)`` of the walkers not finished.
    rec : tuple of arrays or None
        With ``record``: ``(walker, rank, edge, leftward)`` of every crossing, rank counting the walker's
        crossings from 0.
    """
    n = len(start)
    cap = len(W.tri) + 3
    end = np.full(n, -1, dtype=np.int64)
    state = np.zeros(n, dtype=np.int8)
    act = np.flatnonzero(start >= 0)
    ct = start[act]
    ce = np.full(len(act), -1, dtype=np.int64)
    si = np.asarray(first, dtype=np.int64)[act]
    se = np.asarray(stop, dtype=np.int64)[act]
    ns = np.zeros(len(act), dtype=np.int64)
    count = np.zeros(n, dtype=np.int64)
    slot = np.arange(3)[:, None]
    recs: list[tuple] = []
    for _ in range(max_rounds):
        if len(act) == 0 or len(act) < min_active:
            break
        # Rows are the triangles' corners (or slots) 0, 1, 2; columns the walkers.
        apx, apy, aqx, aqy = px[si], py[si], qx[si], qy[si]
        vx = W.cx[:, ct]
        vy = W.cy[:, ct]
        # Which side of the line p→q each corner lies on (a corner on the line counts as left).
        sp = ((aqx - apx) * (vy - apy) - (aqy - apy) * (vx - apx)) >= 0
        # Slot j may be the exit if q lies beyond its edge (on it: by the convention of `_locate`), the
        # edge straddles the line p→q, and it is not the slot the walker came in through.
        vx1 = vx[_NEXT]
        vy1 = vy[_NEXT]
        # Evaluated from each edge's lower vertex id (see `_edge_orient`).
        fl = W.flip3[:, ct]
        ax, ay = np.where(fl, vx1, vx), np.where(fl, vy1, vy)
        bx, by = np.where(fl, vx, vx1), np.where(fl, vy, vy1)
        oq = (bx - ax) * (aqy - ay) - (by - ay) * (aqx - ax)
        oq = np.where(fl, -oq, oq)
        stay = (oq > 0) | ((oq == 0) & W.rule3[:, ct])
        cand = ~stay & (sp != sp[_NEXT]) & (slot != ce)
        moves = cand[0] | cand[1] | cand[2]
        k = np.where(cand[0], 0, np.where(cand[1], 1, 2))
        mv = np.flatnonzero(moves)
        # Walkers that cross an edge: into the neighbour (or out of the domain).
        tm, km = ct[mv], k[mv]
        nb = W.nbr[tm, km]
        out = nb < 0
        if out.any():
            state[act[mv[out]]] = 2
            inn = mv[~out]
            tm, km, nb = tm[~out], km[~out], nb[~out]
        else:
            inn = mv
        if record and len(inn):
            e = W.sedge[tm, km]
            w = act[inn]
            recs.append((w, count[w], e, W.tri[tm, km] != W.ev0[e]))
            count[w] += 1
        ct[inn] = nb
        ce[inn] = W.entry[tm, km]
        ns[inn] += 1
        # Walkers whose segment ends here (or that hit the step cap of the one-walker walk) go on with
        # the next segment; a walker past its last segment is done.
        nxt = ~moves
        if len(inn) and ns[inn].max() >= cap:
            nxt[inn[ns[inn] >= cap]] = True
        si[nxt] += 1
        ce[nxt] = -1
        ns[nxt] = 0
        done = nxt & (si >= se)
        if done.any() or out.any():
            end[act[done]] = ct[done]
            state[act[done]] = 1
            keep = ~done
            keep[mv[out]] = False
            act, ct, ce, si, se, ns = act[keep], ct[keep], ce[keep], si[keep], se[keep], ns[keep]
    rec = None
    if record:
        if recs:
            rec = tuple(np.concatenate(col) for col in zip(*recs, strict=True))
        else:
            z = np.zeros(0, dtype=np.int64)
            rec = (z, z, z, np.zeros(0, dtype=bool))
    return end, state, (act, ct, ce, si, ns), rec


def _walk_py(W: _WalkData, t: int, entry: int, steps: int, i: int, stop: int, px, py, qx, qy):
    """The one-walker walk: crossed edges, their directions and the final triangle.

    Walks segments i … stop − 1 from triangle t, given the slot it entered t through and the steps already
    taken in segment i (−1 and 0 at the start of a segment).

    Raises
    ------
    ValueError
        If the polyline leaves the triangulated domain.
    """
    cap = len(W.tri) + 3
    out_e: list[int] = []
    out_l: list[bool] = []
    for s in range(i, stop):
        p_x, p_y, q_x, q_y = float(px[s]), float(py[s]), float(qx[s]), float(qy[s])
        for _ in range(steps, cap):
            tv = W.tri[t].tolist()
            vx = W.X[tv].tolist()
            vy = W.Y[tv].tolist()
            rule = W.rule[t].tolist()
            flip = W.flip[t].tolist()
            exit_k = -1
            for k in range(3):
                if k == entry:
                    continue
                k1 = (k + 1) % 3
                # q right of the edge (outside the triangle) and the edge straddles p→q. On the edge
                # itself, q belongs to the triangle on the left of (u, v) with u < v.
                # (Evaluated from the edge's lower vertex id, see `_edge_orient`.)
                if flip[k]:
                    oq = -((vx[k] - vx[k1]) * (q_y - vy[k1]) - (vy[k] - vy[k1]) * (q_x - vx[k1]))
                else:
                    oq = (vx[k1] - vx[k]) * (q_y - vy[k]) - (vy[k1] - vy[k]) * (q_x - vx[k])
                if oq > 0 or (oq == 0 and rule[k]):
                    continue
                o1 = (q_x - p_x) * (vy[k] - p_y) - (q_y - p_y) * (vx[k] - p_x)
                o2 = (q_x - p_x) * (vy[k1] - p_y) - (q_y - p_y) * (vx[k1] - p_x)
                if (o1 >= 0) != (o2 >= 0):
                    exit_k = k
                    break
            if exit_k < 0:
                break
            nt = int(W.nbr[t, exit_k])
            if nt < 0:
                raise ValueError("the polyline leaves the triangulated domain")
            e = int(W.sedge[t, exit_k])
            # Leaving through slot (u -> v) of t, t on its left: rightward iff u is the edge's first vertex.
            out_e.append(e)
            out_l.append(tv[exit_k] != int(W.ev0[e]))
            entry = int(W.entry[t, exit_k])
            t = nt
        entry, steps = -1, 0
    return out_e, out_l, t


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

    Raises
    ------
    ValueError
        If the polyline starts outside the domain or leaves it.

    Notes
    -----
    Points exactly on an edge count as on its left (a consistent symbolic perturbation), so a polyline
    through a vertex or along an edge still gets a well-defined sequence.

    The result is that of one walk from the triangle of the first point along the segments in turn,
    each segment's walk starting where the previous one ended. It is computed in chunks: every
    ``_CHUNK``-th point is located by a short walk from a guess (`_locate_many`); the chunks between
    located points are walked side by side (`_lockstep`), the last few alone (`_walk_py`). A chunk
    stands if it starts where the previous chunk (standing or walked again) ended; one that does not is
    walked again from there, in order along the polyline, so the result is exactly the single walk's.
    """
    pts = np.asarray(ring, dtype=float)
    if len(pts) > 1 and np.array_equal(pts[0], pts[-1]):
        pts = pts[:-1]
    nxt = np.roll(pts, -1, axis=0)
    pts = pts[(pts[:, 0] != nxt[:, 0]) | (pts[:, 1] != nxt[:, 1])]
    t0 = _locate(T, pts[0])
    if t0 < 0:
        raise ValueError("the polyline starts outside the triangulated domain")
    W = _walk_data(T)
    n = len(pts)
    px, py = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
    qx, qy = np.roll(px, -1), np.roll(py, -1)
    # Chunks start at the first point and at every located _CHUNK-th point.
    cand = np.arange(_CHUNK, n, _CHUNK)
    where = _locate_many(W, px[cand], py[cand], _LOCATE_MAX_STEPS)
    first = np.r_[0, cand[where >= 0]]
    start = np.r_[t0, where[where >= 0]]
    stop = np.r_[first[1:], n]
    nc = len(first)
    end, state, resume, (rw, rrank, redge, rleft) = _lockstep(
        W, start, first, stop, px, py, qx, qy, max_rounds=_LOCKSTEP_MAX_ROUNDS,
        min_active=_LOCKSTEP_MIN_ACTIVE, record=True)
    count = np.bincount(rw, minlength=nc)
    extra: dict[int, tuple[list[int], list[bool]]] = {}
    for c, t, e, s, ns in zip(*(a.tolist() for a in resume), strict=True):
        try:
            es, ls, end[c] = _walk_py(W, t, e, ns, s, int(stop[c]), px, py, qx, qy)
        except ValueError:
            state[c] = 2
            continue
        state[c] = 1
        extra[c] = (es, ls)
    # A chunk stands if it finished and started where the previous chunk ended.
    ok = state == 1
    ok[1:] &= start[1:] == end[:-1]
    redone: dict[int, tuple[list[int], list[bool]]] = {}
    for c0 in np.flatnonzero(~ok).tolist():
        c = c0
        while c not in redone:
            t = t0 if c == 0 else int(end[c - 1])
            es, ls, t_end = _walk_py(W, t, -1, 0, int(first[c]), int(stop[c]), px, py, qx, qy)
            redone[c] = (es, ls)
            end[c] = t_end
            c += 1
            if c == nc or not ok[c] or start[c] == t_end:
                break            # the next chunk is walked again anyway, or it stands
            ok[c] = False
    good = np.ones(nc, dtype=bool)
    good[list(redone)] = False
    keep_rec = good[rw]
    rw, rrank, redge, rleft = rw[keep_rec], rrank[keep_rec], redge[keep_rec], rleft[keep_rec]
    size = np.where(good, count, 0)
    for c, (es, _) in extra.items():
        if good[c]:
            size[c] += len(es)
    for c, (es, _) in redone.items():
        size[c] = len(es)
    offset = np.cumsum(size) - size
    out_e = np.empty(int(size.sum()), dtype=np.int64)
    out_l = np.empty(len(out_e), dtype=bool)
    pos = offset[rw] + rrank
    out_e[pos] = redge
    out_l[pos] = rleft
    for c, (es, ls) in extra.items():
        if good[c]:
            o = offset[c] + count[c]
            out_e[o:o + len(es)] = es
            out_l[o:o + len(ls)] = ls
    for c, (es, ls) in redone.items():
        out_e[offset[c]:offset[c] + len(es)] = es
        out_l[offset[c]:offset[c] + len(ls)] = ls
    return out_e, out_l


def _reduce_codes(codes: np.ndarray) -> np.ndarray:
    """Free, then cyclic, reduction of a word of letters ``code`` (the inverse of c is ``c ^ 1``)."""
    stack: list[int] = []
    push, pop = stack.append, stack.pop
    for c in codes.tolist():
        if stack and stack[-1] == c ^ 1:
            pop()
        else:
            push(c)
    i, j = 0, len(stack) - 1
    while i < j and stack[i] == stack[j] ^ 1:
        i += 1
        j -= 1
    return np.array(stack[i:j + 1], dtype=np.int64)


def reduce_cyclic(edges: np.ndarray, leftward: np.ndarray) -> list[tuple[int, bool]]:
    """Cancel consecutive crossings of the same edge in opposite directions, cyclically.

    Parameters
    ----------
    edges : (k,) int
        Crossed edges, as returned by `crossings`.
    leftward : (k,) bool
        Direction of each crossing.

    Returns
    -------
    list of (int, bool)
        The cyclically reduced sequence of crossings (the reduced word is unique, whatever the order
        of the cancellations).
    """
    codes = 2 * np.asarray(edges, dtype=np.int64) + np.asarray(leftward, dtype=bool)
    red = _reduce_codes(codes)
    return [(e, bool(lw)) for e, lw in zip((red >> 1).tolist(), (red & 1).tolist(), strict=True)]


def sleeve(T: Triangulation, ring: np.ndarray) -> np.ndarray:
    """Portals of the reduced sleeve of a closed polyline: ``(k, 2)`` vertex ids (left, right) of each.

    Left and right are relative to the direction of travel. An empty result means the polyline is
    contractible in the domain.

    Parameters
    ----------
    T : Triangulation
    ring : (n, 2) float
        A closed polyline in the interior of the domain.

    Returns
    -------
    (k, 2) int
        Vertex ids of each portal's left and right end point.
    """
    e, lw = crossings(T, ring)
    red = _reduce_codes(2 * e + lw)
    if len(red) == 0:
        return np.zeros((0, 2), dtype=int)
    ev = T.edge_vertices[red >> 1]
    lw = (red & 1).astype(bool)
    # Crossing u→v from its right to its left: u is on the traveller's left.
    return np.where(lw[:, None], ev, ev[:, ::-1])


# ---------------------------------------------------------------------------------------------------------
# The funnel algorithm
# ---------------------------------------------------------------------------------------------------------
@dataclass
class _Events:
    """The funnel's input: one event per new portal end point, then the end point, then the start point.

    ``X, Y, ID, LEFT`` are lists (for the funnel's loop) of length ``m + 2``: the m events, the end (a
    right event of id −2) and the start (id ``start_id``). ``portal`` is the portal index of each event.
    """

    X: list
    Y: list
    ID: list
    LEFT: list
    m: int
    portal: np.ndarray


def _event_flags(left_id: np.ndarray, right_id: np.ndarray, cyclic: bool) -> np.ndarray:
    """``(k, 2)`` bool: whether portal i's left / right end point differs from portal i−1's.

    Portal 0 is compared with portal k − 1 if ``cyclic``, else both its end points are new.
    """
    new = np.empty((len(left_id), 2), dtype=bool)
    if len(left_id) == 0:
        return new
    new[1:, 0] = left_id[1:] != left_id[:-1]
    new[1:, 1] = right_id[1:] != right_id[:-1]
    if cyclic:
        new[0, 0], new[0, 1] = left_id[0] != left_id[-1], right_id[0] != right_id[-1]
    else:
        new[0] = True
    return new


def _funnel_events(left: np.ndarray, right: np.ndarray, left_id, right_id, start, start_id: int,
                   end) -> _Events:
    """The events of a portal sequence.

    Portal i's left end point is an event if its id differs from portal i−1's (always for portal 0), and
    likewise on the right; a portal's left event comes before its right one.
    """
    k = len(left)
    lid = np.asarray(left_id, dtype=np.int64)
    rid = np.asarray(right_id, dtype=np.int64)
    mask = _event_flags(lid, rid, cyclic=False).reshape(-1)
    xs = np.column_stack([left[:, 0], right[:, 0]]).reshape(-1)[mask]
    ys = np.column_stack([left[:, 1], right[:, 1]]).reshape(-1)[mask]
    ids = np.column_stack([lid, rid]).reshape(-1)[mask]
    is_left = np.tile(np.array([True, False]), k)[mask]
    return _Events(X=xs.tolist() + [float(end[0]), float(start[0])],
                   Y=ys.tolist() + [float(end[1]), float(start[1])],
                   ID=ids.tolist() + [-2, int(start_id)], LEFT=is_left.tolist() + [False, False],
                   m=len(xs), portal=np.repeat(np.arange(k), 2)[mask])


class _CyclicEvents:
    """The events of a cyclic portal sequence, made once.

    The events of any run of portals (from any portal, over several periods) are then cut from them as
    list slices, without making new Python objects.
    """

    def __init__(self, xy: np.ndarray, portals: np.ndarray):
        self.k = k = len(portals)
        self.portals = portals
        self.xy = xy
        lid, rid = portals[:, 0].astype(np.int64), portals[:, 1].astype(np.int64)
        mask = _event_flags(lid, rid, cyclic=True).reshape(-1)
        ends = np.column_stack([lid, rid]).reshape(-1)[mask]
        self.X = xy[ends, 0].tolist()
        self.Y = xy[ends, 1].tolist()
        self.ID = ends.tolist()
        self.LEFT = np.tile(np.array([True, False]), k)[mask].tolist()
        self.portal = np.repeat(np.arange(k), 2)[mask]
        self.first = np.searchsorted(self.portal, np.arange(k + 1))     # first event of each portal

    def run(self, s: int, count: int, start, start_id: int, end) -> _Events:
        """The events of portals s, s + 1, …, s + count − 1 (mod k), as `_funnel_events` makes them."""
        X: list = []
        Y: list = []
        ID: list = []
        LEFT: list = []
        parts = []
        if count > 0:
            lv, rv = int(self.portals[s, 0]), int(self.portals[s, 1])
            X += [float(self.xy[lv, 0]), float(self.xy[rv, 0])]    # portal s: both end points are new
            Y += [float(self.xy[lv, 1]), float(self.xy[rv, 1])]
            ID += [lv, rv]
            LEFT += [True, False]
            parts.append(np.zeros(2, dtype=np.int64))
        cur, done = (s + 1) % self.k, 1            # the next portal, and its index in the run
        while done < count:                        # the rest, period by period
            stop = min(self.k, cur + count - done)
            a, b = int(self.first[cur]), int(self.first[stop])
            X += self.X[a:b]
            Y += self.Y[a:b]
            ID += self.ID[a:b]
            LEFT += self.LEFT[a:b]
            parts.append(self.portal[a:b] + (done - cur))
            done += stop - cur
            cur = stop % self.k
        portal = np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)
        return _Events(X=X + [float(end[0]), float(start[0])], Y=Y + [float(end[1]), float(start[1])],
                       ID=ID + [-2, int(start_id)], LEFT=LEFT + [False, False], m=len(X), portal=portal)


def _funnel(ev: _Events, stop: float | None = None) -> list[int]:
    """Funnel algorithm over `_Events`: the events that are corners of the path, in order.

    The funnel is the apex and two chains (lists read from a head index outward); each event is added to
    its side's chain after popping the chain's end while it does not turn the right way, and when that
    empties the chain, the apex advances along the other chain while the new point is beyond it. With
    ``stop``, returns as soon as a corner of portal index ≥ ``stop`` is emitted (corners come out in
    order of portal index).
    """
    X, Y, ID, LEFT, m = ev.X, ev.Y, ev.ID, ev.LEFT, ev.m
    # Event indices increase with portal indices: a corner's portal is ≥ stop iff its index is ≥ cut.
    cut = m + 2 if stop is None else int(np.searchsorted(ev.portal, stop))
    apex = m + 1
    L: list[int] = []
    R: list[int] = []
    lh = rh = 0           # heads of the chains (items before them have become the apex)
    nl = nr = 0           # live lengths of the chains
    out: list[int] = []
    for j in range(m + 1):
        tx = X[j]
        ty = Y[j]
        tid = ID[j]
        if LEFT[j]:
            if tid >= 0 and ID[L[-1] if nl else apex] == tid:
                continue
            while nl:
                b = L[-1]
                a = L[-2] if nl > 1 else apex
                xa = X[a]
                ya = Y[a]
                if (X[b] - xa) * (ty - ya) - (Y[b] - ya) * (tx - xa) <= 0:
                    L.pop()
                    nl -= 1
                else:
                    break
            if not nl:
                L = []
                lh = 0
                xa = X[apex]
                ya = Y[apex]
                while nr:
                    c = R[rh]
                    if (X[c] - xa) * (ty - ya) - (Y[c] - ya) * (tx - xa) <= 0:
                        out.append(c)
                        apex = c
                        rh += 1
                        nr -= 1
                        xa = X[c]
                        ya = Y[c]
                        if c >= cut:
                            return out
                    else:
                        break
            L.append(j)
            nl += 1
        else:
            if tid >= 0 and ID[R[-1] if nr else apex] == tid:
                continue
            while nr:
                b = R[-1]
                a = R[-2] if nr > 1 else apex
                xa = X[a]
                ya = Y[a]
                if (X[b] - xa) * (ty - ya) - (Y[b] - ya) * (tx - xa) >= 0:
                    R.pop()
                    nr -= 1
                else:
                    break
            if not nr:
                R = []
                rh = 0
                xa = X[apex]
                ya = Y[apex]
                while nl:
                    c = L[lh]
                    if (X[c] - xa) * (ty - ya) - (Y[c] - ya) * (tx - xa) >= 0:
                        out.append(c)
                        apex = c
                        lh += 1
                        nl -= 1
                        xa = X[c]
                        ya = Y[c]
                        if c >= cut:
                            return out
                    else:
                        break
            R.append(j)
            nr += 1
    out.extend(R[rh:-1])
    return out


def _corners(ev: _Events, out: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Portal indices and sides (+1 left, −1 right) of the corner events ``out`` (the start excluded)."""
    o = np.array(out, dtype=np.int64)
    o = o[o < ev.m]
    side = np.where(np.array(ev.LEFT, dtype=bool)[o], 1, -1) if len(o) else np.zeros(0, dtype=np.int64)
    return ev.portal[o], side


def string_pull(start, end, left, right, left_id=None, right_id=None, start_id=-1):
    """Funnel algorithm: shortest path from ``start`` to ``end`` through portals ``(left[i], right[i])``.

    Consecutive portals must share one end point (they are edges of one triangle). The funnel is kept as
    (left chain, apex, right chain); each portal adds one vertex, so the run is linear.

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

    Examples
    --------
    >>> string_pull((1.5, -5.0), (-5.0, 1.5), [[1.0, 1.0]], [[2.0, 0.0]])
    [(0, 1)]
    """
    left = np.asarray(left, dtype=float).reshape(-1, 2)
    right = np.asarray(right, dtype=float).reshape(-1, 2)
    k = len(left)
    if left_id is None:
        _, inv = _unique_rows(np.vstack([left, right]))
        left_id, right_id = inv[:k], inv[k:]
    ev = _funnel_events(left, right, left_id, right_id, start, start_id, end)
    portal, side = _corners(ev, _funnel(ev))
    return list(zip(portal.tolist(), side.tolist(), strict=True))


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
    max_restarts : int
        How many start vertices to try before giving up.

    Returns
    -------
    ClosedGeodesic or None
        None for an empty sleeve (a contractible curve: it shrinks to nothing).

    Raises
    ------
    RuntimeError
        If no start vertex gives a consistently closed curve.

    Notes
    -----
    A vertex of the closed geodesic is looked for among the corners of the path through three copies of
    the sleeve, from the midpoint of portal 0 to its third copy: the corner whose portal is nearest the
    middle (1.5 k). Corners come out of the funnel in order of portal index, so the funnel stops at the
    first corner past the middle. The funnel is then run from that vertex through one period to its next
    copy; if the curve does not turn the right way at the start, another of its corners is tried.
    """
    k = len(portals)
    if k == 0:
        return None
    portals = np.asarray(portals)
    events = _CyclicEvents(T.xy, portals)
    periods = 3
    mid = 0.5 * (T.xy[portals[0, 0]] + T.xy[portals[0, 1]])
    # Portals 1..(3k−1) between the midpoint of portal 0 and its copy three periods on.
    ev = events.run(1 % k, periods * k - 1, mid, -1, mid)
    first, first_side = _corners(ev, _funnel(ev, stop=1.5 * k - 1))
    if len(first) == 0:
        raise RuntimeError("closed geodesic wraps no vertex")
    # Start from the corner nearest the middle period (the first such), and run the funnel from it to its
    # next copy.
    c = int(np.argmin(np.abs((first + 1) - 1.5 * k)))
    start = (int(first[c]) + 1, int(first_side[c]))
    tried = set()
    for _ in range(max_restarts):
        j, side = start
        j %= k
        tried.add((j, side))
        vid = int(portals[j, 0 if side > 0 else 1])
        apex = T.xy[vid]
        idx = (np.arange(j + 1, j + k) % k)
        ev = events.run((j + 1) % k, k - 1, apex, vid, apex)
        pi, sd = _corners(ev, _funnel(ev))
        corner = np.where(sd > 0, portals[idx[pi], 0], portals[idx[pi], 1])
        other = corner != vid
        pi, sd, corner = pi[other], sd[other], corner[other]
        ids = np.r_[vid, corner].astype(np.int64)
        sides = np.r_[side, sd].astype(np.int64)
        xy = T.xy[ids]
        if len(ids) == 1:
            # A single corner: the curve would be a point; only possible for degenerate input.
            return ClosedGeodesic(ids, sides, xy)
        if _corner_ok(xy[-1], xy[0], xy[1], side):
            return ClosedGeodesic(ids, sides, xy)
        # The start vertex is not on the closed geodesic; restart from a corner of this curve.
        nxt = [(int(idx[i]) % k, int(s)) for i, s in zip(pi.tolist(), sd.tolist(), strict=True)
               if (int(idx[i]) % k, int(s)) not in tried]
        if not nxt:
            break
        start = nxt[len(nxt) // 2]
    raise RuntimeError("closed geodesic did not close consistently")


class ShortestLoops:
    """Shortest closed curves homotopic to given rings, each in the part of ``domain`` that holds it.

    The parts are indexed once and each is triangulated on first use. Calling the object with a ring
    returns its `ClosedGeodesic`, or None where the ring lies in no part or shrinks to nothing.
    ``probe`` vertices of the ring decide which part holds it (the part most of them touch).
    """

    def __init__(self, domain: Polygon | MultiPolygon, probe: int):
        self.parts = list(shapely.get_parts(domain))
        self.tree = shapely.STRtree(self.parts)
        self.probe = probe
        self._tris: dict[int, Triangulation] = {}

    def __call__(self, ring: np.ndarray) -> ClosedGeodesic | None:
        hits = self.tree.query(shapely.points(ring[: min(len(ring), self.probe)]), predicate="intersects")[1]
        if len(hits) == 0:
            return None
        k = int(np.bincount(hits).argmax())
        if k not in self._tris:
            self._tris[k] = triangulate(self.parts[k])
        T = self._tris[k]
        return closed_geodesic(T, sleeve(T, ring))
