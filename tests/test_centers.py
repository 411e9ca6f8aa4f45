import warnings

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, Polygon, box

import vectortighten as vt
from vectortighten.errors import RepairWarning

from .strategies import pixel_outline, radii_for, shapes


def test_box_centres():
    C = vt.arc_centers(box(0, 0, 4, 3), 1.0)
    inner = sorted(map(tuple, C.xy[C.side == 1].round(12).tolist()))
    assert inner == [(1.0, 1.0), (1.0, 2.0), (3.0, 1.0), (3.0, 2.0)]
    assert (C.side == -1).sum() == 0          # a convex polygon has no concave fillet arcs
    assert C.exact.all()


def test_l_shape_centres_and_features():
    L = Polygon([(0, 0), (10, 0), (10, 3), (3, 3), (3, 10), (0, 10)])
    C = vt.arc_centers(L, 1.0)
    outer = C.xy[C.side == -1]
    assert outer.tolist() == [[4.0, 4.0]]     # the fillet arc at the reflex corner (3, 3)
    k = int(np.flatnonzero(C.side == -1)[0])
    feats = [C.feature_geometry(f) for f in C.features[k]]
    assert all(g.geom_type == "LineString" for g in feats)
    assert all(g.distance(Point(4, 4)) == pytest.approx(1.0, abs=1e-15) for g in feats)


def test_line_point_and_point_point_centres():
    # An L whose arms are narrower than 2r: the arc of the shrink around the reflex corner (2.8, 2.8) is
    # cut by the offsets of the outer edges, at points a distance r from an edge and from that vertex.
    S = Polygon([(0, 0), (10, 0), (10, 2.8), (2.8, 2.8), (2.8, 10), (0, 10)])
    C = vt.arc_centers(S, 1.5)
    kinds = {tuple(sorted(int(f) % 2 for f in fs)) for fs in C.features[C.exact]}
    assert (0, 1) in kinds
    lp = C.xy[[tuple(sorted(int(f) % 2 for f in fs)) == (0, 1) for fs in C.features]]
    assert sorted(map(tuple, lp.round(12).tolist())) == [(1.5, round(2.8 - (1.5 ** 2 - 1.3 ** 2) ** 0.5, 12)),
                                                        (round(2.8 - (1.5 ** 2 - 1.3 ** 2) ** 0.5, 12), 1.5)]
    # Two reflex vertices facing each other across a gap give a point–point centre of the fillet.
    two = box(0, 0, 4, 4).union(box(4.6, 0, 8.6, 4))
    C2 = vt.arc_centers(two, 1.0)
    pp = [C2.xy[i] for i in range(len(C2)) if C2.side[i] == -1 and set(C2.features[i] % 2) == {1}]
    assert pp and all(abs(p[0] - 4.3) < 1e-12 for p in pp)


@pytest.mark.parametrize("tol", [1e-7, 1e-5, 1e-3])
def test_centre_near_a_medial_axis_junction(tol):
    # Near (-0.94, 2.55) a reflex vertex and two edge lines all lie within 1e-5·r of distance r: a buffer
    # vertex there is nearest to the solution of the wrong pair (it is closer than r to the third
    # feature). Every pair's solution must be tried, the nearest valid one kept, at any chord tolerance.
    S = Polygon([(4.607640671105351, 0.1426764541855958), (1.924168086398417, 1.615177262663519),
                 (4.84001594122839, 6.393976405900918), (0.0193415544990768, 4.234736480675397),
                 (-5.935673107164341, 4.49660187619068), (-3.6864736308001778, 2.0411382101909976),
                 (-7.697604777435771, 4.120123480917884), (-3.9059665123919327, -0.0005430322968352),
                 (-2.072448819764375, -2.1201787566941928), (-3.7085008892394677, -7.367319301492925),
                 (0.2821825479647473, -3.814298300037595), (1.3365420023489358, -3.1225001661492),
                 (5.950388929245864, -2.7797098988633997), (2.3674280207146663, -0.8024760374142055)])
    r = 2.073353492818982
    C = vt.arc_centers(S, r, tolerance=tol * r)
    assert C.exact.all()
    assert np.abs(C.feature_distances() - r).max() <= 1e-13 * r
    assert (shapely.distance(S.boundary, shapely.points(C.xy)) >= r * (1 - 1e-12)).all()


def test_centres_of_a_dense_pixel_staircase():
    # A traced mask's outline, 30k vertices, r = 1350 pixel sides: every medial-axis point of clearance r
    # has dozens of staircase corners within 1e-4·r of distance r, and GEOS's buffers (which simplify
    # their input by up to r/100) place their vertices far off where two offset arcs cross at a shallow
    # angle. Refining by the nearest few features used to leave 17 % of the centres where GEOS put them.
    S = pixel_outline(30_000)
    r = 0.6
    C = vt.arc_centers(S, r)
    assert len(C) > 3000 and C.exact.mean() >= 0.999
    assert np.abs(C.feature_distances()[C.exact] - r).max() <= 1e-12 * 20
    dist = shapely.distance(S.boundary, shapely.points(C.xy[C.exact]))
    assert (dist >= r * (1 - 1e-9)).all()


@settings(max_examples=40, deadline=None)
@given(shapes.flatmap(lambda S: st.tuples(st.just(S), radii_for(S))))
def test_centres_are_exact_and_valid(case):
    S, r = case
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RepairWarning)
        S = vt._validation.check_shape(S)
    C = vt.arc_centers(S, r)
    if not C.exact.any():
        return
    x0, y0, x1, y1 = S.bounds
    size = max(x1 - x0, y1 - y0)
    d = C.feature_distances()[C.exact]
    assert np.abs(d - r).max() <= 1e-12 * size
    # A centre keeps distance r from the whole boundary, inside S (core) or outside it (fillet).
    pts = shapely.points(C.xy[C.exact])
    dist = shapely.distance(S.boundary, pts)
    assert (dist >= r * (1 - 1e-9)).all()
    inside = shapely.contains(S, pts)
    assert (inside == (C.side[C.exact] == 1)).all()


@pytest.mark.parametrize("q, r", [(64, 2.9), (157, 2.9), (157, 3.1034920465)])
def test_public_shrink_corners_are_the_exact_corners(q, r):
    # A bracket whose arms are pierced by holes: beside each hole the shrink is a strip cut by the hole's
    # offset, at corners where a chord's offset crosses an arm's offset at a shallow angle. GEOS misplaces
    # them (it simplifies its input), and a search of the vertex's own among nearby features picked a
    # point of clearance r that is not a corner (1e-4·r off at q = 157). Every convex vertex of the public
    # shrink is a corner of the exact S↓r: an end of a piece of the independent oracle's offsets.
    from shapely.geometry import Point

    from vectortighten.centers import _corner_vertices

    from . import oracle

    S = Polygon([(0, 0), (60, 0), (60, 8), (8, 8), (8, 50), (0, 50)]).buffer(2, quad_segs=q).buffer(-2, quad_segs=q)
    S = S.difference(Point(30, 4).buffer(2.5, quad_segs=q)).difference(Point(4, 30).buffer(2.5, quad_segs=q))
    E = vt.shrink(S, r)
    pts = _corner_vertices(shapely.orient_polygons(E), convex=True)
    K = oracle.shrink_pieces(S, r)
    ends = np.concatenate(oracle._ends(K.kind, K.rows))
    assert len(pts) >= 8
    d = np.array([np.hypot(*(ends - p).T).min() for p in pts])
    assert d.max() <= 1e-12 * r


def test_bad_input():
    with pytest.raises(vt.InvalidRadiusError):
        vt.arc_centers(box(0, 0, 1, 1), 0)


def test_mason_of_a_fillet_with_a_vertex_far_from_every_feature():
    # The Mason of this shape shrinks a fillet with a vertex that no feature lies within r + w of: the
    # search that once refined such vertices failed there with an IndexError (an empty array indexed by
    # a mask); the exact corners need no search.
    S = shapely.from_wkt(
        "POLYGON ((0 10, 10 10, 10 0, 0 0, 0 1.6548652302681501, 0.0682437609975624 1.223991080902669, "
        "0.2995505263448734 0.770025993237622, 0.6598192597329997 0.4097572598494958, "
        "1.1137843473980467 0.178450494502185, 1.6170085235986074 0.0987476149968833, "
        "2.120232699799168 0.178450494502185, 2.574197787464215 0.4097572598494958, "
        "2.9344665208523413 0.7700259932376222, 3.165773286199652 1.2239910809026693, "
        "3.245476165704954 1.72721525710323, 3.165773286199652 2.230439433303791, "
        "2.9344665208523413 2.684404520968838, 2.5741977874642146 3.0446732543569643, "
        "2.1202326997991676 3.275980019704275, 1.6170085235986074 3.355682899209577, "
        "1.1137843473980462 3.275980019704275, 0.6598192597329994 3.044673254356964, "
        "0.299550526344873 2.6844045209688376, 0.0682437609975624 2.2304394333037907, "
        "0 1.7995652839383096, 0 10), (4.391534819013868 6.861615772905922, "
        "4.303083700811651 7.306289572566621, 4.051196227139903 7.68326581720701, "
        "3.674219982499515 7.935153290878757, 3.229546182838816 8.023604409080974, "
        "2.784872383178117 7.935153290878757, 2.407896138537728 7.68326581720701, "
        "2.156008664865981 7.30628957256662, 2.0675575466637635 6.861615772905922, "
        "2.156008664865981 6.4169419732452235, 2.4078961385377284 6.039965728604834, "
        "2.7848723831781177 5.788078254933087, 3.229546182838816 5.69962713673087, "
        "3.674219982499515 5.788078254933087, 4.051196227139904 6.039965728604834, "
        "4.303083700811651 6.4169419732452235, 4.391534819013868 6.861615772905922))")
    for init in ("core", "input", "mason"):
        T = vt.tighten(S, 2.5, init=init)
        assert T.verify() == []
        assert T.perimeter == pytest.approx(28.669214, abs=1e-6)


def _spikes_by_the_rule(c):
    """The spike rule applied literally: a whole-array pass per removal (the reference for the heap)."""
    while len(c) >= 3:
        nxt = np.roll(c, -1, axis=0)
        dup = (c == nxt).all(axis=1)
        if dup.any():
            c = c[~dup]
            continue
        spike = (np.roll(c, 1, axis=0) == nxt).all(axis=1)
        if not spike.any():
            break
        i = int(np.flatnonzero(spike)[0])
        c = np.delete(c, [i, (i + 1) % len(c)], axis=0)
    return c


def test_without_spikes_matches_the_rule():
    from vectortighten.centers import _without_spikes

    rng = np.random.default_rng(7)
    for _ in range(3000):          # few distinct points: nested spikes, repeats and wrap-around joins
        c = rng.integers(0, int(rng.integers(1, 5)), size=(int(rng.integers(0, 13)), 2)).astype(float)
        assert np.array_equal(_without_spikes(c.copy()), _spikes_by_the_rule(c.copy()))
    # a ring with a spike of depth two nested in it keeps its square
    sq = np.array([[0, 0], [4, 0], [5, 0], [6, 0], [5, 0], [4, 0], [4, 4], [0, 4]], dtype=float)
    assert _without_spikes(sq).tolist() == [[0, 0], [4, 0], [4, 4], [0, 4]]
