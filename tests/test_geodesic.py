import mapbox_earcut
import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

from vectortighten import geodesic as G
from vectortighten.geodesic import closed_geodesic, sleeve, string_pull, triangulate


def test_triangulation_adjacency():
    T = triangulate(box(0, 0, 3, 3).difference(box(1, 1, 2, 2)))
    assert len(T.tri) == 8
    # Every interior edge has a triangle on each side, and both hold it.
    for (u, v), (tl, tr) in zip(T.edge_vertices, T.edge_triangles):
        assert {u, v} <= set(T.tri[tl]) and {u, v} <= set(T.tri[tr])


def test_funnel_bends_around_a_corner():
    # An L-shaped corridor: the shortest path from one arm to the other bends at the inner corner.
    left = np.array([[1.0, 1.0], [1.0, 1.0]])
    right = np.array([[2.0, 0.0], [0.0, 2.0]])
    path = string_pull((1.5, -5.0), (-5.0, 1.5), left[:1], right[:1])
    assert path == [(0, 1)]


def test_closed_geodesic_around_a_hole_is_its_hull():
    D = box(0, 0, 10, 10).difference(Polygon([(3, 3), (7, 3), (7, 4), (4, 4), (4, 6), (7, 6), (7, 7), (3, 7)]))
    T = triangulate(D)
    ring = np.array([[1, 1], [9, 1], [9, 9], [1, 9]], float)
    g = closed_geodesic(T, sleeve(T, ring))
    assert g.length == pytest.approx(16.0)
    assert (g.sides == 1).all()


def test_contractible_loop_vanishes():
    T = triangulate(box(0, 0, 10, 10).difference(box(4, 4, 6, 6)))
    ring = np.array([[1, 1], [3, 1], [3, 3], [1, 3]], float)
    assert closed_geodesic(T, sleeve(T, ring)) is None


def test_wiggly_loop_tightens_to_the_inscribed_polygon():
    hole = Point(5, 5).buffer(1.5, quad_segs=4)
    T = triangulate(box(0, 0, 10, 10).difference(hole))
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = np.c_[5 + 3 * np.cos(t) + 0.5 * np.sin(7 * t), 5 + 3 * np.sin(t)]
    g = closed_geodesic(T, sleeve(T, ring))
    assert g.length == pytest.approx(hole.length, rel=1e-12)


def test_loop_winding_twice_is_a_different_class():
    # A loop around two holes separately vs. around both: the geodesics differ.
    D = box(0, 0, 20, 10).difference(box(3, 3, 6, 6)).difference(box(12, 3, 15, 6))
    T = triangulate(D)
    both = np.array([[1, 1], [19, 1], [19, 9], [1, 9]], float)
    one = np.array([[1, 1], [9, 1], [9, 9], [1, 9]], float)
    gb = closed_geodesic(T, sleeve(T, both))
    go = closed_geodesic(T, sleeve(T, one))
    assert gb.length == pytest.approx(2 * 12 + 2 * 3)
    assert go.length == pytest.approx(12)


# --- helpers of the fast implementation ----------------------------------------------------------------


def _square_annulus():
    return box(0, 0, 10, 10).difference(box(4, 4, 6, 6))


def _random_domain(seed):
    rng = np.random.default_rng(seed)
    holes = shapely.union_all([Point(*rng.uniform(2, 8, 2)).buffer(rng.uniform(0.4, 1.2),
                                                                    quad_segs=int(rng.integers(1, 6)))
                               for _ in range(3)])
    return box(0, 0, 10, 10).difference(holes)


def test_unique_rows_is_numpy_unique():
    rng = np.random.default_rng(1)
    P = rng.integers(0, 6, (500, 2)).astype(float) / 3     # many ties in x and in y, many duplicates
    xy, inv = G._unique_rows(P)
    want, want_inv = np.unique(P, axis=0, return_inverse=True)
    assert np.array_equal(xy, want)
    assert np.array_equal(inv, want_inv.reshape(-1))
    assert np.array_equal(xy[inv], P)


def test_twins_pair_each_interior_edge_with_its_reverse():
    T = triangulate(_random_domain(2))
    u = T.tri.reshape(-1)
    v = T.tri[:, [1, 2, 0]].reshape(-1)
    twin = G._twins(u, v)
    inner = np.flatnonzero(twin >= 0)
    assert np.array_equal(twin[twin[inner]], inner)
    assert np.array_equal(u[twin[inner]], v[inner]) and np.array_equal(v[twin[inner]], u[inner])
    # Unpaired slots are the domain's boundary: as many as its ring edges.
    assert (twin < 0).sum() == sum(len(r.coords) - 1 for r in shapely.get_rings(_random_domain(2)))


def test_triangulation_is_consistent():
    D = _random_domain(3)
    T = triangulate(D)
    assert np.all(np.diff(T.xy[:, 0]) >= 0)                       # vertices sorted lexicographically
    ties = np.diff(T.xy[:, 0]) == 0
    assert np.all(np.diff(T.xy[:, 1])[ties] > 0)
    p = T.xy[T.tri]
    assert (G._orient(p[:, 0], p[:, 1], p[:, 2]) > 0).all()        # counter-clockwise
    assert np.isclose(np.abs(G._orient(p[:, 0], p[:, 1], p[:, 2])).sum() / 2, D.area)
    nt = len(T.tri)
    t, k = np.nonzero(T.neighbors >= 0)
    nb = T.neighbors[t, k]
    entry = T._entry[t, k]
    assert np.array_equal(T.neighbors[nb, entry], t)               # the neighbour's slot points back
    assert np.array_equal(T.slot_edge[nb, entry], T.slot_edge[t, k])
    assert np.array_equal(T.tri[t, k], T.tri[nb, (entry + 1) % 3])  # the same edge, reversed
    e = T.slot_edge[t, k]
    u = T.edge_vertices[e, 0]
    left = np.where(T.tri[t, k] == u, t, nb)                       # the triangle holding u→v
    assert np.array_equal(T.edge_triangles[e, 0], left)
    assert len(np.unique(e)) == len(T.edge_vertices) == (3 * nt - (T.neighbors < 0).sum()) // 2


def test_collinear_ring_vertices_are_kept_without_the_geos_fallback(monkeypatch):
    # The hole's edges are split by collinear vertices, which earcut skips; they are put back.
    D = box(0, 0, 6, 6).difference(shapely.segmentize(box(2, 2, 4, 3), 0.5))
    verts, idx, ends = G._earcut_mesh(D)
    raw = np.asarray(mapbox_earcut.triangulate_float64(verts, ends.astype(np.uint32)))
    assert len(np.unique(raw)) < len(verts)                         # earcut skips some ...
    assert len(np.unique(idx)) == len(verts)                        # ... and they are put back
    monkeypatch.setattr(G, "_triangles", lambda *a, **k: pytest.fail("fell back to GEOS"))
    T = triangulate(D)
    assert len(T.xy) == len(shapely.get_coordinates(D)) - 2        # every ring vertex, once
    assert len(T.tri) == len(T.xy)                                 # n + 2·holes − 2 triangles
    slots = np.flatnonzero(T.neighbors.reshape(-1) < 0)
    assert len(slots) == len(T.xy)                                 # boundary slots = ring edges


def test_locate_follows_the_on_edge_convention():
    T = triangulate(_square_annulus())
    rng = np.random.default_rng(4)
    pts = rng.uniform(0, 10, (300, 2))
    pts = pts[~shapely.contains_xy(box(4, 4, 6, 6), pts[:, 0], pts[:, 1])]
    W = G._walk_data(T)
    for p in pts:
        t = G._locate(T, p)
        assert t >= 0 and G._inside(W, np.array([t]), p)[0]
        assert G._inside(W, np.arange(len(T.tri)), p).sum() == 1   # no other triangle holds it
    # A point on an interior edge (u, v) belongs to the triangle on the left of u→v, u < v.
    (u, v), (tl, _) = T.edge_vertices[0], T.edge_triangles[0]
    assert G._locate(T, 0.5 * (T.xy[u] + T.xy[v])) == tl
    assert G._locate(T, (5.0, 5.0)) == -1                          # in the hole
    assert G._locate(T, (11.0, 5.0)) == -1                         # outside


def test_located_guesses_hold_their_points():
    T = triangulate(_random_domain(5))
    W = G._walk_data(T)
    ring = shapely.get_coordinates(shapely.segmentize(_random_domain(5).buffer(-0.05).exterior, 0.05))
    where = G._locate_many(W, ring[:, 0], ring[:, 1], 64)
    assert (where >= 0).mean() > 0.5
    for p, t in zip(ring, where, strict=True):
        if t >= 0:
            assert G._inside(W, np.array([t]), p)[0]


def _one_walk(T, ring):
    """The reference: one walker along all segments, from the triangle of the first point."""
    pts = np.asarray(ring, float)[:-1]
    W = G._walk_data(T)
    q = np.roll(pts, -1, axis=0)
    e, lw, _ = G._walk_py(W, G._locate(T, pts[0]), -1, 0, 0, len(pts),
                          pts[:, 0], pts[:, 1], q[:, 0], q[:, 1])
    return np.array(e, dtype=np.int64), np.array(lw, dtype=bool)


@pytest.mark.parametrize("chunk, locate, min_active", [(4, 24, 16), (16, 24, 16), (2, 1, 0), (3, 0, 1), (1, 8, 1000)])
def test_crossings_are_the_single_walk(monkeypatch, chunk, locate, min_active):
    # Chunks that start at badly located points, long Python tails, chunks walked again: the result is
    # always the one-walker walk's.
    monkeypatch.setattr(G, "_CHUNK", chunk)
    monkeypatch.setattr(G, "_LOCATE_MAX_STEPS", locate)
    monkeypatch.setattr(G, "_LOCKSTEP_MIN_ACTIVE", min_active)
    for seed in range(3):
        D = _random_domain(seed)
        T = triangulate(D)
        rng = np.random.default_rng(seed)
        inner = D.buffer(-0.1)
        rings = [shapely.segmentize(D.buffer(-0.03).exterior, rng.uniform(0.01, 0.3)),
                 D.buffer(-0.2).exterior]
        rings += [shapely.segmentize(h, 0.02) for h in inner.interiors]        # around the holes
        for ring in rings:
            c = shapely.get_coordinates(ring)
            e, lw = G.crossings(T, c)
            e0, lw0 = _one_walk(T, c)
            assert np.array_equal(e, e0) and np.array_equal(lw, lw0)
            # Each crossing leads into a triangle that has the next crossed edge.
            tri_after = np.where(lw, T.edge_triangles[e, 0], T.edge_triangles[e, 1])
            nxt_edges = T.slot_edge[tri_after[:-1]]
            assert (nxt_edges == e[1:, None]).any(axis=1).all()


def test_crossings_of_a_ring_that_leaves_the_domain():
    T = triangulate(_square_annulus())
    with pytest.raises(ValueError, match="leaves"):
        G.crossings(T, np.array([[1, 1], [9, 1], [5, 5], [1, 9], [1, 1]], float))
    with pytest.raises(ValueError, match="starts outside"):
        G.crossings(T, np.array([[5, 5], [9, 1], [9, 9], [5, 5]], float))


def test_reduce_codes_is_the_free_cyclic_reduction():
    rng = np.random.default_rng(6)
    for _ in range(200):
        word = rng.integers(0, 8, int(rng.integers(0, 40)))
        # Naive: cancel any adjacent x, x⁻¹ until none is left, then strip inverse pairs from the ends.
        w = word.tolist()
        changed = True
        while changed:
            changed = False
            for i in range(len(w) - 1):
                if w[i] == w[i + 1] ^ 1:
                    del w[i:i + 2]
                    changed = True
                    break
        while len(w) > 1 and w[0] == w[-1] ^ 1:
            w = w[1:-1]
        assert G._reduce_codes(word).tolist() == w


def test_sleeve_of_a_ring_around_a_hole():
    D = _square_annulus()
    T = triangulate(D)
    hole = {tuple(p) for p in [(4, 4), (6, 4), (6, 6), (4, 6)]}
    outer = {tuple(p) for p in [(0, 0), (10, 0), (10, 10), (0, 10)]}
    ring = np.array([[2, 2], [8, 2], [8, 8], [2, 8], [2, 2]], float)
    for direction, (lset, rset) in ((1, (hole, outer)), (-1, (outer, hole))):
        P = sleeve(T, ring[::direction])
        assert len(P) > 0
        # Counter-clockwise around the hole, the hole is on the left of every portal.
        assert {tuple(T.xy[i]) for i in P[:, 0]} <= lset and {tuple(T.xy[i]) for i in P[:, 1]} <= rset
        # Consecutive portals (cyclically) are two edges of one triangle: they share one end point.
        nxt = np.roll(P, -1, axis=0)
        shared = (P[:, :1] == nxt).any(axis=1) | (P[:, 1:] == nxt).any(axis=1)
        assert shared.all()
    # Winding once around the hole goes once around its four sides.
    g = closed_geodesic(T, sleeve(T, ring))
    assert g.length == pytest.approx(8.0)
    assert sorted(map(tuple, g.xy.tolist())) == sorted(hole)


def test_funnel_stop_returns_a_prefix_up_to_the_first_corner_past_stop():
    hole = Point(5, 5).buffer(2.0, quad_segs=8)
    T = triangulate(box(0, 0, 10, 10).difference(hole))
    P = sleeve(T, np.array([[1, 1], [9, 1], [9, 9], [1, 9], [1, 1]], float))
    k = len(P)
    seq = np.arange(1, 3 * k) % k
    left, right = T.xy[P[seq, 0]], T.xy[P[seq, 1]]
    mid = 0.5 * (T.xy[P[0, 0]] + T.xy[P[0, 1]])
    ev = G._funnel_events(left, right, P[seq, 0], P[seq, 1], mid, -1, mid)
    full, full_side = G._corners(ev, G._funnel(ev))
    part, part_side = G._corners(ev, G._funnel(ev, stop=1.5 * k - 1))
    assert np.array_equal(full[:len(part)], part) and np.array_equal(full_side[:len(part)], part_side)
    assert part[-1] >= 1.5 * k - 1 and (part[:-1] < 1.5 * k - 1).all()
    assert np.all(np.diff(full) >= 0)                               # corners come in portal order


@pytest.mark.parametrize("s, count", [(1, 0), (1, 1), (0, 5), (3, 17), (7, 40), (2, 8)])
def test_cyclic_events_are_the_events_of_the_rotated_sequence(s, count):
    T = triangulate(box(0, 0, 10, 10).difference(Point(5, 5).buffer(2.0, quad_segs=2)))
    P = sleeve(T, np.array([[1, 1], [9, 1], [9, 9], [1, 9], [1, 1]], float))
    k = len(P)
    assert k >= 8                                                   # some cases wrap around
    idx = np.arange(s, s + count) % k
    want = G._funnel_events(T.xy[P[idx, 0]], T.xy[P[idx, 1]], P[idx, 0], P[idx, 1], (0.5, 0.5), 3, (1.0, 2.0))
    got = G._CyclicEvents(T.xy, P).run(s % k, count, (0.5, 0.5), 3, (1.0, 2.0))
    assert (got.X, got.Y, got.ID, got.LEFT, got.m) == (want.X, want.Y, want.ID, want.LEFT, want.m)
    assert np.array_equal(got.portal, want.portal)


def test_closed_geodesic_around_a_triangle_is_its_perimeter_either_way():
    tri = Polygon([(3, 3), (7, 4), (4, 7)])
    T = triangulate(box(0, 0, 10, 10).difference(tri))
    t = np.linspace(0, 2 * np.pi, 97)
    ring = np.c_[5 + 3.5 * np.cos(t), 5 + 3.5 * np.sin(t)]
    ccw = closed_geodesic(T, sleeve(T, ring))
    cw = closed_geodesic(T, sleeve(T, ring[::-1]))
    assert ccw.length == pytest.approx(tri.length) and cw.length == pytest.approx(tri.length)
    assert (ccw.sides == 1).all() and (cw.sides == -1).all()
    corners = np.asarray(tri.exterior.coords)[:-1]
    assert sorted(map(tuple, ccw.xy.tolist())) == sorted(map(tuple, corners.tolist()))


def test_morton_keys_interleave_bits():
    assert G._spread_bits(np.array([0b1011])).tolist() == [0b1000101]
    frame = (0.0, 0.0, 2.0**30)
    k = G._morton(np.array([0.0, 0.75, 0.25]), np.array([0.0, 0.25, 0.75]), frame)
    assert k[0] == 0 and k[1] < k[2]                                # (x, y) quadrant order: x bit low


def test_walk_data_of_a_triangulation_made_elsewhere():
    # A Triangulation built without the private entry slots gets them from its slot edges.
    T = triangulate(_random_domain(7))
    U = G.Triangulation(T.xy, T.tri, T.edge_vertices, T.edge_triangles, T.neighbors, T.slot_edge)
    assert np.array_equal(G._walk_data(U).entry, G._walk_data(T).entry)
    ring = shapely.get_coordinates(_random_domain(7).buffer(-0.05).exterior)
    assert np.array_equal(sleeve(U, ring), sleeve(T, ring))
