"""SVG as cut files and as paintings (issue 18): nesting across elements, background erasing, the page,
styles and outlines kept on output, and the map to DXF."""

import math
import re

import pytest
import shapely
from shapely.geometry import Point, box

import vectortighten as vt
from vectortighten import io
from vectortighten.cli import main
from vectortighten.curves import Arc
from vectortighten.errors import InvalidGeometryError

NS = 'xmlns="http://www.w3.org/2000/svg"'
PAGE = 'width="100mm" height="80mm" viewBox="0 0 100 80"'


def svg(body, attrs=PAGE):
    return f'<svg {NS} {attrs}>{body}</svg>'.encode()


def yflip(geom):
    return shapely.transform(geom, lambda xy: xy * (1, -1))


CUT = svg('<g fill="none" stroke="#ff0000" stroke-width="0.1">'
          '<rect x="10" y="10" width="60" height="40"/>'
          '<circle cx="25" cy="25" r="5"/>'
          '<circle cx="25" cy="25" r="2"/>'                       # an island inside the hole
          '<path d="M 50 20 H 60 V 40 H 50 Z" stroke="#0000ff"/>'  # a hole of another colour
          '</g>')


def test_cut_file_holes_drawn_as_separate_elements():
    src = io.load_svg(CUT, flatten=1e-6)
    assert src.meta["nesting"] == "evenodd"
    want = yflip(box(10, 10, 70, 50).difference(Point(25, 25).buffer(5, quad_segs=4096))
                 .difference(box(50, 20, 60, 40)).union(Point(25, 25).buffer(2, quad_segs=4096)))
    assert src.shape.symmetric_difference(want).area < 2e-4      # chords within 1e-6 of the circles
    parts = sorted(shapely.get_parts(src.shape), key=lambda p: p.area)
    assert [len(p.interiors) for p in parts] == [0, 2]
    # The exact boundary: the circles are exact arcs, oriented by their nesting.
    loops = src.loops
    assert sorted(round(lp.area, 9) for lp in loops) == sorted(
        [2400.0, round(-25 * math.pi, 9), round(4 * math.pi, 9), -200.0])
    assert {a.radius for lp in loops for a in lp.arcs} == {5.0, 2.0}


def test_filled_drawing_is_read_as_painted_unless_forced():
    filled = svg('<rect x="10" y="10" width="60" height="40"/><circle cx="25" cy="25" r="5"/>')
    assert io.load_svg(filled).meta["nesting"] == "paint"
    assert io.read_svg(filled).area == pytest.approx(2400)                    # the circle paints over
    forced = io.load_svg(filled, nesting="evenodd", flatten=1e-6)
    assert forced.shape.area == pytest.approx(2400 - 25 * math.pi, abs=1e-4)  # a hole, as a cut file


def test_background_coloured_shapes_erase_in_painting_order():
    doc = svg('<rect x="10" y="10" width="60" height="40" fill="#336699"/>'
              '<circle cx="25" cy="25" r="5" fill="white"/>'            # erases
              '<circle cx="25" cy="25" r="2" fill="#336699"/>'          # painted again on top
              '<rect x="80" y="10" width="10" height="10" fill="#ffffff"/>'   # erases nothing
              '<circle cx="55" cy="35" r="6" style="fill:#fff"/>')
    src = io.load_svg(doc, flatten=1e-6)
    assert src.meta["nesting"] == "paint"
    want = yflip(box(10, 10, 70, 50).difference(Point(25, 25).buffer(5, quad_segs=4096))
                 .union(Point(25, 25).buffer(2, quad_segs=4096))
                 .difference(Point(55, 35).buffer(6, quad_segs=4096)))
    assert src.shape.symmetric_difference(want).area < 2e-4      # chords within 1e-6 of the circles
    assert sum(len(p.interiors) for p in shapely.get_parts(src.shape)) == 2
    assert src.loops is not None and sorted(a.radius for lp in src.loops for a in lp.arcs[:1]) == [2, 5, 6]
    T = vt.tighten(src.shape, 1.0)
    assert (T.n_components, T.n_holes) == (2, 2)


def test_the_documents_background_is_the_erasing_colour():
    inkscape = ('xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd" ' + PAGE)
    doc = svg('<sodipodi:namedview pagecolor="#ffff00"/>'
              '<rect x="10" y="10" width="60" height="40" fill="black"/>'
              '<rect x="20" y="20" width="10" height="10" fill="yellow"/>'   # the page's colour: erases
              '<rect x="40" y="20" width="10" height="10" fill="white"/>', inkscape)    # paints
    assert io.read_svg(doc).area == pytest.approx(2400 - 100)
    root_style = svg('<rect width="10" height="10"/><rect x="2" y="2" width="2" height="2" fill="#123456"/>',
                     f'{PAGE} style="background-color:#123456"')
    assert io.read_svg(root_style).area == pytest.approx(96)


def test_mixed_drawing_skips_unfilled_outlines_with_a_warning():
    doc = svg('<rect x="10" y="10" width="60" height="40"/>'
              '<circle cx="25" cy="25" r="5" fill="none" stroke="red"/>')
    with pytest.warns(UserWarning, match="1 unfilled outline\\(s\\) skipped.*--nesting evenodd"):
        assert io.read_svg(doc).area == pytest.approx(2400)
    cut = io.read_svg(doc, nesting="evenodd", flatten=1e-6)
    assert cut.area == pytest.approx(2400 - 25 * math.pi, abs=1e-4)


def test_loose_lines_and_arcs_of_a_cut_file_join():
    doc = svg('<g fill="none" stroke="black"><line x1="0" y1="0" x2="30" y2="0"/>'
              '<path d="M 30 10 L 0 10"/><path d="M 30 0 A 5 5 0 0 1 30 10"/>'
              '<polyline points="0,10 -5,5 0,0"/></g>')
    src = io.load_svg(doc, flatten=1e-6)
    assert len(src.loops) == 1 and src.loops[0].area == pytest.approx(300 + 12.5 * math.pi + 25, rel=1e-12)
    broken = doc.replace(b'x2="30" y2="0"', b'x2="29.9" y2="0"')
    with pytest.raises(InvalidGeometryError,
                       match=r"open outline: <line> #\d+ ends at \(29\.9, -?0\).*0\.1 away"):
        io.load_svg(broken)
    assert io.load_svg(broken, gap=0.2).shape.area == pytest.approx(300 + 12.5 * math.pi + 25, rel=1e-2)


@pytest.mark.parametrize("transform, exact", [
    ("rotate(30 40 40) scale(1.5)", True),
    ("matrix(0 1 1 0 3 4)", True),                 # a reflection: the arc turns the other way
    ("scale(2 1)", False),                         # an ellipse: flattened
    ("skewX(10)", False),
])
def test_circular_arcs_stay_exact_under_similarities(transform, exact):
    import svgelements as se

    path = "M 40 30 A 10 10 0 0 1 50 40 L 40 40 Z"
    doc = svg(f'<g transform="{transform}"><path d="{path}" fill="none" stroke="black"/></g>',
              'viewBox="0 0 100 100"')
    src = io.load_svg(doc, flatten=1e-6)
    arcs = [p for lp in src.loops for p in lp.pieces if isinstance(p, Arc)]
    assert bool(arcs) == exact
    m = se.Matrix(transform)
    seg = [s for s in se.Path(path) if isinstance(s, se.Arc)][0]
    mid = m.point_in_matrix_space(seg.point(0.5))
    if exact:
        assert arcs[0].point_at(0.5) == pytest.approx((mid.x, -mid.y), abs=1e-9)
        assert arcs[0].radius == pytest.approx(10 * math.sqrt(abs(m.a * m.d - m.b * m.c)), rel=1e-12)
    assert src.shape.exterior.distance(Point(mid.x, -mid.y)) < 1e-5


def test_svg_round_trip_keeps_the_page_and_the_position(tmp_path):
    page = 'width="210mm" height="148mm" viewBox="-10 -5 210 148" preserveAspectRatio="xMinYMin meet"'
    inp = tmp_path / "cut.svg"
    inp.write_bytes(CUT.replace(PAGE.encode(), page.encode()))
    out = tmp_path / "cut.out.svg"
    assert main(["tighten", str(inp), "-r", "1", "-o", str(out)]) == 0
    text = out.read_text()
    root = re.search(r"<svg [^>]*>", text).group(0)
    for attr in page.split():
        assert attr in root
    assert io.svg_unit(out) == "mm"
    T = vt.tighten(io.read_shape(inp), 1.0)
    back = io.read_svg(out, flatten=1e-6)
    assert back.bounds == pytest.approx(T.geometry.bounds, abs=1e-5)      # where the input was
    assert back.area == pytest.approx(T.area, rel=1e-6)


def test_keep_style_carries_each_elements_style(tmp_path):
    doc = svg('<g fill="none" stroke="#ff0000" stroke-width="0.1">'
              '<rect x="10" y="10" width="60" height="40"/>'
              '<g transform="scale(2)">'
              '<circle cx="20" cy="15" r="5" stroke="#0000ff" stroke-width="0.1"/></g>'
              '</g>')
    inp = tmp_path / "c.svg"
    inp.write_bytes(doc)
    out = tmp_path / "o.svg"
    assert main(["tighten", str(inp), "-r", "1", "-o", str(out), "--keep-style"]) == 0
    text = out.read_text()
    elements = re.findall(r'<(path|circle) id="tightening-\d+" [^>]*>', text)
    assert len(elements) == 2
    strokes = sorted(re.findall(r'stroke="(#[0-9a-f]+)"', text))
    assert strokes == ["#0000ff", "#ff0000"]
    assert 'stroke="#0000ff" stroke-width="0.2"' in text          # the width in the page's units
    assert text.count('fill="none"') == 2
    back = io.load_svg(out, flatten=1e-6)
    assert back.meta["nesting"] == "evenodd"
    assert back.shape.area == pytest.approx(vt.tighten(io.read_shape(inp), 1.0).area, rel=1e-6)


def test_keep_style_on_a_painting(tmp_path):
    doc = svg('<rect x="10" y="10" width="30" height="30" style="fill:#336699;stroke:none"/>'
              '<circle cx="25" cy="25" r="5" fill="white"/>'
              '<rect x="50" y="10" width="20" height="20" fill="#aa0000" opacity="0.5"/>')
    inp = tmp_path / "a.svg"
    inp.write_bytes(doc)
    out = tmp_path / "o.svg"
    assert main(["tighten", str(inp), "-r", "1", "-o", str(out), "--keep-style"]) == 0
    text = out.read_text()
    paths = re.findall(r'<path id="tightening-\d+" d="([^"]+)" ([^>]*)/>', text)
    assert len(paths) == 2
    by_fill = {re.search(r'fill="([^"]+)"', style).group(1): d for d, style in paths}
    assert set(by_fill) == {"#336699", "#aa0000"}
    assert by_fill["#336699"].count("M ") == 2                  # the blue square keeps its hole
    assert 'opacity="0.5"' in text
    T = vt.tighten(io.read_shape(inp), 1.0)
    assert io.read_svg(out, flatten=1e-6).area == pytest.approx(T.area, rel=1e-6)


def test_stroke_only_for_lasers(tmp_path):
    inp = tmp_path / "a.svg"
    inp.write_bytes(svg('<rect x="10" y="10" width="30" height="30"/>'
                        '<circle cx="25" cy="25" r="5" fill="white"/>'))
    out = tmp_path / "o.svg"
    assert main(["tighten", str(inp), "-r", "1", "-o", str(out), "--stroke-only"]) == 0
    text = out.read_text()
    assert "#d1495b" not in text and text.count('fill="none"') == 2
    assert text.count('stroke="#ff0000" stroke-width="0.0254"') == 2     # a hairline: 0.0254 mm
    back = io.load_svg(out, flatten=1e-6)                                 # an outline drawing: a cut file
    assert back.meta["nesting"] == "evenodd"
    T = vt.tighten(io.read_shape(inp), 1.0)
    assert back.shape.area == pytest.approx(T.area, rel=1e-6)
    assert sum(len(p.interiors) for p in shapely.get_parts(back.shape)) == T.n_holes == 1


@pytest.mark.parametrize("attrs, units, insunits, scale", [
    (PAGE, "mm", 4, 1.0),                                              # mm page: mm DXF, same numbers
    ('width="4in" height="3in" viewBox="0 0 4 3"', "in", 1, 1.0),
    ('width="400" height="300"', None, 4, 25.4 / 96),                   # px: mm, as Inkscape's default
    ('width="200mm" height="160mm" viewBox="0 0 100 80"', None, 4, 2.0),   # a user unit of 2 mm
    ('viewBox="0 0 100 80"', None, 0, 1.0),                             # no size: unitless
])
def test_svg_to_dxf_as_inkscape_exports_it(attrs, units, insunits, scale, tmp_path):
    # Inkscape's DXF export: y up, the page's bottom-left corner at the origin, in mm unless the drawing
    # is in mm, cm or in already.
    ezdxf = pytest.importorskip("ezdxf")
    inp = tmp_path / "p.svg"
    inp.write_bytes(svg('<rect x="10" y="20" width="30" height="10"/>', attrs))
    out = tmp_path / "p.dxf"
    assert main(["tighten", str(inp), "-r", "0.5", "-o", str(out)]) == 0
    src = io.load_svg(inp)
    assert src.units == units
    doc = ezdxf.readfile(out)
    assert doc.header["$INSUNITS"] == insunits
    height = 80 if "80" in attrs else (3 if "3in" in attrs else 300)
    x0, y0 = tuple(doc.header["$EXTMIN"])[:2]
    x1, y1 = tuple(doc.header["$EXTMAX"])[:2]
    want = (10 * scale, (height - 30) * scale, 40 * scale, (height - 20) * scale)
    assert (x0, y0, x1, y1) == pytest.approx(want, abs=1e-9)
    radii = [e.dxf.radius for e in doc.modelspace() if e.dxftype() == "ARC"]
    assert len(radii) == 4 and radii == pytest.approx([0.5 * scale] * 4, rel=1e-12)


def test_svg_unit_and_page_helpers():
    page = io.svg._page(io.svg._safe_svg_tree(svg("", 'width="200mm" height="100mm" viewBox="0 0 100 100"'),
                                              "x"))
    sx, sy, tx, ty = page["view"]                     # meet, centred: the viewBox sits mid-page
    assert sx == sy == pytest.approx(100 / 25.4 * 96 / 100)
    assert page["box"] == pytest.approx((-50, 0, 150, 100))
    with pytest.raises(ValueError, match="nesting must be one of"):
        io.load_svg(CUT, nesting="odd")
