"""DXF in and out (issue 18): every entity type, blocks, units, position, loose pieces, bad input.

The drawings are built here with ezdxf. The reference for each is the same part built exactly with
shapely (circles sampled far finer than the reader's chords), tightened by `vt.tighten` too.
"""

import math

import numpy as np
import pytest
import shapely
from shapely import affinity
from shapely.geometry import Point, Polygon, box

import vectortighten as vt
from vectortighten import io
from vectortighten.cli import main
from vectortighten.curves import Arc, Loop, Segment
from vectortighten.errors import InvalidGeometryError
from vectortighten.io.dxf import full_circle

from .test_io import _count_cycles

ezdxf = pytest.importorskip("ezdxf")

OX, OY = 1000.0, -500.0          # the part sits far from the origin
BULGE_90 = math.tan(math.pi / 8)  # a quarter turn


def plate_doc(s=1.0, insunits=4, ox=OX, oy=OY, as_block=False):
    """An 80 × 50 plate (×s) with every entity type: an LWPOLYLINE outline with bulged corners (radius 6),
    two CIRCLE holes, a slot of loose LINEs and ARCs inside an INSERTed block, a POLYLINE hole with bulged
    corners and an ELLIPSE hole. With ``as_block`` the whole plate is a block inserted at (ox, oy)."""
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = insunits
    msp = doc.modelspace()
    if as_block:
        doc.modelspace().add_blockref("PLATE", (ox, oy), dxfattribs={"layer": "CUT"})
        msp, ox, oy = doc.blocks.new("PLATE"), 0.0, 0.0
    b = BULGE_90
    outline = [(6, 0, 0), (74, 0, b), (80, 6, 0), (80, 44, b), (74, 50, 0), (6, 50, b), (0, 44, 0), (0, 6, b)]
    msp.add_lwpolyline([(ox + s * x, oy + s * y, bb) for x, y, bb in outline], format="xyb", close=True,
                       dxfattribs={"layer": "CUT"})
    msp.add_circle((ox + s * 12, oy + s * 12), s * 4, dxfattribs={"layer": "CUT"})
    msp.add_circle((ox + s * 68, oy + s * 38), s * 4, dxfattribs={"layer": "CUT"})
    slot = doc.blocks.new("SLOT")
    slot.add_line((-10 * s, -4 * s), (10 * s, -4 * s))
    slot.add_line((10 * s, 4 * s), (-10 * s, 4 * s))
    slot.add_arc((10 * s, 0), 4 * s, -90, 90)
    slot.add_arc((-10 * s, 0), 4 * s, 90, 270)
    msp.add_blockref("SLOT", (ox + s * 40, oy + s * 25), dxfattribs={"layer": "CUT"})
    cx, cy, h, r = 15, 38, 4, 2
    square = [(cx - h + r, cy - h, 0), (cx + h - r, cy - h, b), (cx + h, cy - h + r, 0),
              (cx + h, cy + h - r, b), (cx + h - r, cy + h, 0), (cx - h + r, cy + h, b),
              (cx - h, cy + h - r, 0), (cx - h, cy - h + r, b)]
    pl = msp.add_polyline2d([(ox + s * x, oy + s * y) for x, y, _ in square], close=True,
                            dxfattribs={"layer": "CUT"})
    for v, (_, _, bb) in zip(pl.vertices, square, strict=True):
        v.dxf.bulge = bb
    msp.add_ellipse((ox + s * 65, oy + s * 12), (s * 6, 0, 0), 0.5, dxfattribs={"layer": "CUT"})
    return doc


def plate_exact(s=1.0, ox=OX, oy=OY, q=512):
    """The same part with shapely, its arcs sampled at 4·q chords a turn."""
    outer = box(6, 0, 74, 50).union(box(0, 6, 80, 44))
    corners = [Point(c).buffer(6, quad_segs=q) for c in [(6, 6), (74, 6), (74, 44), (6, 44)]]
    outer = shapely.union_all([outer, *corners])
    holes = [Point(12, 12).buffer(4, quad_segs=q), Point(68, 38).buffer(4, quad_segs=q),
             shapely.union_all([box(30, 21, 50, 29), Point(30, 25).buffer(4, quad_segs=q),
                                Point(50, 25).buffer(4, quad_segs=q)]),
             shapely.union_all([box(11, 36, 19, 40), box(13, 34, 17, 42)]
                               + [Point(x, y).buffer(2, quad_segs=q) for x in (13, 17) for y in (36, 40)]),
             affinity.scale(Point(65, 12).buffer(6, quad_segs=q), 1, 0.5)]
    part = outer.difference(shapely.union_all(holes))
    return affinity.translate(affinity.scale(part, s, s, origin=(0, 0)), ox, oy)


@pytest.fixture(scope="module")
def plates(tmp_path_factory):
    d = tmp_path_factory.mktemp("plates")
    out = {}
    for unit, s, code in (("mm", 1.0, 4), ("in", 1 / 25.4, 1)):
        path = d / f"plate_{unit}.dxf"
        plate_doc(s, code).saveas(path)
        out[unit] = (path, s, code)
        path = d / f"plate_{unit}_block.dxf"
        plate_doc(s, code, as_block=True).saveas(path)
        out[f"{unit} block"] = (path, s, code)
    return out


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


# ---------------------------------------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("unit", ["mm", "in", "mm block", "in block"])
def test_plate_of_every_entity_type(plates, unit):
    path, s, code = plates[unit]
    unit = unit.split()[0]
    flatten = 1e-4 * s
    src = io.read_source(path, flatten=flatten)
    exact = plate_exact(s)
    size = 80 * s
    assert src.units == unit and src.meta["insunits"] == code and src.layers == ("CUT",)
    assert src.shape.bounds == pytest.approx(exact.bounds, abs=1e-9 * size)
    assert len(src.shape.interiors) == 5
    perimeter = exact.length
    assert src.shape.area == pytest.approx(exact.area, abs=perimeter * flatten)
    assert src.shape.symmetric_difference(exact).area <= perimeter * flatten
    # The exact boundary: one counter-clockwise outline, five clockwise holes, arcs of the drawn radii.
    loops = src.loops
    assert [lp.area > 0 for lp in loops] == [True] + [False] * 5
    radii = sorted({round(a.radius / s, 9) for lp in loops for a in lp.arcs})
    assert radii == [2.0, 4.0, 6.0]
    circles = sorted(c for c in map(full_circle, loops) if c)
    assert np.allclose(circles, [(OX + 12 * s, OY + 12 * s, 4 * s), (OX + 68 * s, OY + 38 * s, 4 * s)],
                       rtol=0, atol=1e-12 * OX)
    # Tightened, the DXF part and the exact part agree: holes, bounds, area.
    r = 2.5 * s
    T = vt.tighten(src.shape, r)
    T_exact = vt.tighten(exact, r)
    assert (T.n_components, T.n_holes) == (T_exact.n_components, T_exact.n_holes) == (1, 5)
    assert T.geometry.bounds == pytest.approx(T_exact.geometry.bounds, abs=2 * flatten)
    assert T.area == pytest.approx(T_exact.area, abs=T.perimeter * 2 * flatten)
    assert T.area > src.shape.area     # the POLYLINE hole's corners (radius 2 < r) were filled in


def test_exact_loops_without_ellipse_are_exact():
    # Lines, bulges, circles and arcs only: the exact loops' area is the analytic one to rounding.
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    b = BULGE_90
    outline = [(6, 0, 0), (74, 0, b), (80, 6, 0), (80, 44, b), (74, 50, 0), (6, 50, b), (0, 44, 0), (0, 6, b)]
    msp.add_lwpolyline([(x, y, bb) for x, y, bb in outline], format="xyb", close=True)
    msp.add_circle((12, 12), 4)
    for e in ([(30, 21), (50, 21)], [(50, 29), (30, 29)]):
        msp.add_line(*e)
    msp.add_arc((50, 25), 4, -90, 90)
    msp.add_arc((30, 25), 4, 90, 270)
    src = _read(doc)
    want = 80 * 50 - (4 - math.pi) * 36 - math.pi * 16 - (20 * 8 + math.pi * 16)
    assert math.fsum(lp.area for lp in src.loops) == pytest.approx(want, rel=1e-13)
    for lp in src.loops:
        assert lp.is_g1(1e-9) or any(isinstance(p, Segment) for p in lp.pieces)


def _read(doc, tmp=None, **options):
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "d.dxf"
        doc.saveas(path)
        return io.read_dxf(path, **options)


def test_bulges_both_ways_and_mirrored_extrusion():
    # A bulge of +1 is a counter-clockwise half circle, -1 a clockwise one: going round the rectangle
    # counter-clockwise, the right end bulges out and the left end is notched in. With extrusion (0, 0, -1)
    # the OCS is mirrored in x and so is every bulge.
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0, 0), (10, 0, 1), (10, 4, 0), (0, 4, -1)], format="xyb", close=True)
    src = _read(doc)
    arcs = [p for p in src.loops[0].pieces if isinstance(p, Arc)]
    assert sorted((round(a.center[0], 12), round(a.center[1], 12), a.radius) for a in arcs) == \
        [(0.0, 2.0, 2.0), (10.0, 2.0, 2.0)]
    assert src.loops[0].area == pytest.approx(40, rel=1e-14)
    assert src.shape.contains(Point(11.5, 2)) and not src.shape.contains(Point(1.5, 2))
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0, 0), (10, 0, 1), (10, 4, 0), (0, 4, -1)], format="xyb", close=True,
                       dxfattribs={"extrusion": (0, 0, -1)})
    mirrored = _read(doc)
    assert mirrored.loops[0].bounds == pytest.approx((-12, 0, 0, 4), abs=1e-12)
    assert mirrored.loops[0].area == pytest.approx(40, rel=1e-14)
    assert mirrored.shape.contains(Point(-11.5, 2)) and not mirrored.shape.contains(Point(-1.5, 2))


def test_blocks_rotated_scaled_nested_arrays_and_layer_zero():
    # A block of one 2 × 1 rectangle with a hole, inserted rotated by 90° and scaled by 3, inside another
    # block inserted as a 2 × 1 array (MINSERT) on layer PARTS. Block entities on layer 0 take the
    # INSERT's layer; an arc with extrusion −Z inside the block is mirrored as it should be.
    doc = ezdxf.new("R2010")
    inner = doc.blocks.new("RECT")
    inner.add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    inner.add_arc((-0.5, 0.5), 0.25, 0, 180, dxfattribs={"extrusion": (0, 0, -1)})
    inner.add_arc((-0.5, 0.5), 0.25, 180, 360, dxfattribs={"extrusion": (0, 0, -1)})
    outer = doc.blocks.new("PAIR")
    outer.add_blockref("RECT", (0, 0), dxfattribs={"rotation": 90, "xscale": 3, "yscale": 3})
    msp = doc.modelspace()
    ref = msp.add_blockref("PAIR", (100, 200), dxfattribs={"layer": "PARTS"})
    ref.grid(size=(1, 2), spacing=(0, 10))
    src = _read(doc, layers=["parts"], flatten=1e-7)
    assert src.layers == ("PARTS",)
    parts = sorted(shapely.get_parts(src.shape), key=lambda p: p.bounds[0])
    assert len(parts) == 2
    for k, part in enumerate(parts):
        assert part.bounds == pytest.approx((97 + 10 * k, 200, 100 + 10 * k, 206), abs=1e-9)
        assert len(part.interiors) == 1
        hole = Polygon(part.interiors[0])
        assert hole.centroid.coords[0] == pytest.approx((98.5 + 10 * k, 201.5), abs=1e-9)
        assert hole.area == pytest.approx(math.pi * 0.75 ** 2, rel=1e-6)
    assert sum(1 for lp in src.loops for a in lp.arcs if abs(a.radius - 0.75) < 1e-12) == 4


def test_ellipse_and_spline_within_the_flatten_tolerance():
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (40, 0), (40, 20), (0, 20)], close=True)
    major = (5 * math.cos(0.4), 5 * math.sin(0.4), 0)
    msp.add_ellipse((10, 10), major, 0.4)
    fit = [(30 + 4 * math.cos(a), 10 + 3 * math.sin(a)) for a in np.linspace(0, 2 * math.pi, 9)[:-1]]
    spline = msp.add_spline([*fit, fit[0]])
    flatten = 1e-3
    src = _read(doc, flatten=flatten)
    holes = sorted((Polygon(h) for h in src.shape.interiors), key=lambda p: p.centroid.x)
    ell = affinity.rotate(affinity.scale(Point(10, 10).buffer(5, quad_segs=2048), 1, 0.4), 0.4,
                          origin=(10, 10), use_radians=True)
    t = spline.construction_tool()
    ref = Polygon(np.array([tuple(v) for v in t.points(np.linspace(0, t.max_t, 40001))])[:, :2])
    for got, want in ((holes[0], ell), (holes[1], ref)):
        d = got.exterior.hausdorff_distance(want.exterior)
        assert d <= flatten * 1.01 + 1e-5
        assert got.symmetric_difference(want).area <= want.length * flatten
    assert len(src.loops) == 3 and not any(lp.arcs for lp in src.loops)        # flattened, not exact


def test_ellipse_with_equal_axes_is_an_exact_arc():
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_ellipse((3, 4), (2, 0, 0), 1.0)
    src = _read(doc)
    assert full_circle(src.loops[0]) == pytest.approx((3, 4, 2))


def test_loose_pieces_in_any_order_and_direction(tmp_path):
    # The slot's four pieces, shuffled and two of them reversed, join into one loop.
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_arc((10, 0), 4, -90, 90)
    msp.add_line((-10, 4), (10, 4))          # reversed with respect to the loop
    msp.add_line((-10, -4), (10, -4))
    msp.add_arc((-10, 0), 4, 90, 270)
    src = _read(doc)
    assert len(src.loops) == 1 and len(src.loops[0]) == 4
    assert src.loops[0].area == pytest.approx(160 + 16 * math.pi, rel=1e-14)
    assert src.loops[0].is_g1(1e-12)


def test_gap_is_located_and_gap_joins_it(tmp_path, capsys):
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_line((0, 0), (10, 0))
    msp.add_line((10, 0), (10, 10))
    msp.add_line((10, 10), (0, 10.03))       # misses its neighbour by 0.03
    msp.add_line((0, 10), (0, 0))
    path = tmp_path / "gap.dxf"
    doc.saveas(path)
    with pytest.raises(InvalidGeometryError, match=r"open outline: LINE #\w+ on layer '0' ends at "
                                                   r"\(0, 10\.03\).*0\.03 away at \(0, 10\).*--gap"):
        io.read_dxf(path)
    src = io.read_dxf(path, gap=0.05)
    assert src.shape.area == pytest.approx(100.075)        # the two ends meet halfway
    out = tmp_path / "o.dxf"
    assert main(["tighten", str(path), "-r", "1", "-o", str(out)]) == 2
    assert "ends at (0, 10.03)" in one_error_line(capsys) and not out.exists()
    assert main(["tighten", str(path), "-r", "1", "-o", str(out), "--gap", "0.05"]) == 0
    assert out.exists()


def test_branching_outlines_are_refused(tmp_path):
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    for a, b in [((0, 0), (10, 0)), ((10, 0), (10, 10)), ((10, 10), (0, 10)), ((0, 10), (0, 0)),
                 ((10, 0), (20, 0)), ((20, 0), (20, 5)), ((20, 5), (10, 0))]:
        msp.add_line(a, b)
    with pytest.raises(InvalidGeometryError, match=r"outlines branch at \(10, 0\): 4 ends meet"):
        _read(doc)


def test_outlines_drawn_twice_are_read_once():
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
    for _ in range(2):
        msp.add_circle((5, 5), 2)            # a hole drawn twice would cancel itself under even-odd
        msp.add_line((20, 0), (30, 0))
    msp.add_line((30, 0), (30, 5))
    msp.add_line((30, 5), (20, 0))
    with pytest.warns(UserWarning, match="2 outline\\(s\\) drawn twice read once"):
        src = _read(doc, flatten=1e-7)
    assert len(src.shape.geoms) == 2
    assert src.shape.area == pytest.approx(100 - 4 * math.pi + 25, rel=1e-6)


def test_layers_selected_hidden_and_unknown(tmp_path):
    doc = ezdxf.new("R2010")
    doc.layers.add("CUT")
    doc.layers.add("ENGRAVE").off()
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True, dxfattribs={"layer": "CUT"})
    msp.add_circle((5, 5), 2, dxfattribs={"layer": "ENGRAVE"})
    msp.add_circle((20, 5), 2, dxfattribs={"layer": "OTHER"})
    path = tmp_path / "l.dxf"
    doc.saveas(path)
    with pytest.warns(UserWarning, match="hidden .*'ENGRAVE'"):
        every = io.read_dxf(path, flatten=1e-7)
    assert every.shape.area == pytest.approx(100 + 4 * math.pi, rel=1e-6)
    assert io.read_dxf(path, layers=["cut"]).shape.area == pytest.approx(100)
    both = io.read_dxf(path, layers=["CUT", "engrave"], flatten=1e-7)
    assert both.shape.area == pytest.approx(100 - 4 * math.pi, rel=1e-6)
    with pytest.raises(InvalidGeometryError, match="no entities on layer\\(s\\) 'nope'.*'CUT'"):
        io.read_dxf(path, layers=["nope"])


def test_binary_dxf_reads_like_ascii(tmp_path, plates):
    path, _, _ = plates["mm"]
    doc = ezdxf.readfile(path)
    binary = tmp_path / "bin.dxf"
    doc.saveas(binary, fmt="bin")
    assert binary.read_bytes().startswith(b"AutoCAD Binary DXF")
    a, b = io.read_dxf(path), io.read_dxf(binary)
    assert a.shape.equals_exact(b.shape, 1e-12) and a.units == b.units == "mm"


def test_entities_other_than_outlines_are_ignored_with_a_warning():
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
    msp.add_text("label")
    msp.add_point((3, 3))
    with pytest.warns(UserWarning, match="1 POINT, 1 TEXT ignored"):
        src = _read(doc)
    assert src.shape.area == 100


# ---------------------------------------------------------------------------------------------------------
# Bad input: exit code 2, one line, nothing written
# ---------------------------------------------------------------------------------------------------------
def _self_insert():
    doc = ezdxf.new("R2010")
    blk = doc.blocks.new("A")
    blk.add_circle((0, 0), 1)
    blk.add_blockref("A", (5, 0))
    doc.modelspace().add_blockref("A", (0, 0))
    return doc


def _mutual_insert():
    doc = ezdxf.new("R2010")
    doc.blocks.new("A").add_blockref("B", (1, 0))
    b = doc.blocks.new("B")
    b.add_circle((0, 0), 1)
    b.add_blockref("A", (5, 0))
    doc.modelspace().add_blockref("A", (0, 0))
    return doc


def _doc_with(add):
    doc = ezdxf.new("R2010")
    add(doc.modelspace())
    return doc


def _binary_truncated(path):
    doc = _doc_with(lambda m: m.add_circle((0, 0), 1))
    doc.saveas(path, fmt="bin")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


BAD_DXF = {
    "text": (lambda p: p.write_text("hello, this is not a drawing\n"), "not a DXF file"),
    "dwg": (lambda p: p.write_bytes(b"AC1032" + bytes(range(200))), "DWG file"),
    "truncated": (lambda p: p.write_text(_ascii(_doc_with(lambda m: m.add_circle((0, 0), 1)))[:3000]),
                  "malformed DXF"),
    "binary": (_binary_truncated, "malformed binary DXF"),
    "empty": (lambda p: ezdxf.new("R2010").saveas(p), "model space is empty"),
    "open": (lambda p: _doc_with(lambda m: (m.add_lwpolyline([(0, 0), (5, 0), (5, 5)]),
                                            m.add_lwpolyline([(9, 0), (12, 0), (12, 4)]))).saveas(p),
             "open outline: LWPOLYLINE"),
    "3d line": (lambda p: _doc_with(lambda m: m.add_line((0, 0, 0), (4, 0, 2))).saveas(p),
                "off the XY plane"),
    "tilted circle": (lambda p: _doc_with(
        lambda m: m.add_circle((0, 0), 1, dxfattribs={"extrusion": (0, 1, 1)})).saveas(p),
                      "CIRCLE #\\w+ on layer '0' is off the XY plane"),
    "3dface": (lambda p: _doc_with(lambda m: m.add_3dface([(0, 0, 0), (1, 0, 0), (1, 1, 1)])).saveas(p),
               "3DFACE #\\w+ on layer '0' is a 3D entity"),
    "3d polyline": (lambda p: _doc_with(lambda m: m.add_polyline3d([(0, 0, 0), (1, 0, 0), (1, 1, 3)],
                                                                   close=True)).saveas(p),
                    "POLYLINE #\\w+ .* off the XY plane"),
    "self insert": (lambda p: _self_insert().saveas(p), "block 'A' inserts itself \\(A → A\\)"),
    "mutual insert": (lambda p: _mutual_insert().saveas(p), "block 'A' inserts itself \\(A → B → A\\)"),
    "only text": (lambda p: _doc_with(lambda m: m.add_text("x")).saveas(p), "no outlines in the model space"),
}


def _ascii(doc) -> str:
    import io as stdio

    stream = stdio.StringIO()
    doc.write(stream)
    return stream.getvalue()


@pytest.mark.parametrize("case", sorted(BAD_DXF))
def test_bad_dxf_exit_2_one_line_nothing_written(case, tmp_path, capsys):
    import re

    make, needle = BAD_DXF[case]
    path = tmp_path / "bad.dxf"
    make(path)
    before = path.read_bytes()
    for out in ("out.dxf", "out.svg"):
        target = tmp_path / out
        assert main(["tighten", str(path), "-r", "1", "-o", str(target)]) == 2
        line = one_error_line(capsys)
        assert re.search(needle, line), line
        assert str(path) in line
        assert not target.exists()
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.dxf"]


def test_option_for_another_format_is_refused(tmp_path, capsys):
    src = tmp_path / "s.wkt"
    src.write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))")
    for extra, needle in ((["--layer", "CUT"], "--layer applies to DXF input and geodata layers"),
                          (["--nesting", "paint"], "--nesting applies to SVG input only"),
                          (["--keep-style"], "--keep-style applies to SVG output only")):
        assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "o.dxf"), *extra]) == 2
        assert needle in one_error_line(capsys)
    assert main(["tighten", str(src), "-r", "1", "-o", str(tmp_path / "o.svg"), "--dxf-entities",
                 "lwpolyline"]) == 2
    assert "--dxf-entities applies to DXF output only" in one_error_line(capsys)
    with pytest.raises(ValueError, match="layers is an option of DXF input, not WKT"):
        io.read_source(src, layers=["CUT"])
    assert not (tmp_path / "o.dxf").exists() and not (tmp_path / "o.svg").exists()


# ---------------------------------------------------------------------------------------------------------
# Writing in the input's frame
# ---------------------------------------------------------------------------------------------------------
def _dxf_pieces(path):
    """End points and lengths of the LINE, ARC and CIRCLE entities, and the document."""
    doc = ezdxf.readfile(path)
    ends, radii = [], []
    for e in doc.modelspace():
        if e.dxftype() == "LINE":
            ends.append((np.array(e.dxf.start)[:2], np.array(e.dxf.end)[:2]))
        elif e.dxftype() == "ARC":
            radii.append(e.dxf.radius)
            ends.append((np.array(e.start_point)[:2], np.array(e.end_point)[:2]))
        elif e.dxftype() == "CIRCLE":
            radii.append(e.dxf.radius)
    return doc, ends, radii


@pytest.mark.parametrize("unit", ["mm", "in"])
@pytest.mark.parametrize("entities", ["lines-arcs", "lwpolyline"])
def test_dxf_round_trip_keeps_units_and_position(plates, unit, entities, tmp_path, capsys):
    path, s, code = plates[unit]
    r = 2.5 * s
    out = tmp_path / "out.dxf"
    assert main(["tighten", str(path), "-r", str(r), "-o", str(out), "--dxf-entities", entities]) == 0
    T = vt.tighten(io.read_shape(path), r)
    doc = ezdxf.readfile(out)
    assert doc.header["$INSUNITS"] == code
    assert doc.header["$MEASUREMENT"] == (1 if unit == "mm" else 0)
    assert not doc.audit().has_errors
    kinds = {e.dxftype() for e in doc.modelspace()}
    assert kinds <= ({"LINE", "ARC", "CIRCLE"} if entities == "lines-arcs" else {"LWPOLYLINE", "CIRCLE"})
    exact = _loops_bounds(T.loops)
    assert tuple(doc.header["$EXTMIN"])[:2] == pytest.approx(exact[:2], abs=1e-9 * 80 * s)
    assert tuple(doc.header["$EXTMAX"])[:2] == pytest.approx(exact[2:], abs=1e-9 * 80 * s)
    if entities == "lines-arcs":
        _, ends, radii = _dxf_pieces(out)
        assert radii and all(abs(x - r) <= 1e-12 * r for x in radii)
        assert _count_cycles(ends, 1e-9 * 80 * s) == len(T.loops)       # closed within 1e-9 of the part
    # Read back: the same part, at the same place, in the same units; its arcs are exact again.
    back = io.read_dxf(out)
    assert back.units == unit and back.meta["insunits"] == code
    assert _loops_bounds(back.loops) == pytest.approx(exact, abs=1e-9 * 80 * s)
    assert math.fsum(lp.area for lp in back.loops) == pytest.approx(T.area, rel=1e-9)
    assert sum(lp.length for lp in back.loops) == pytest.approx(T.perimeter, rel=1e-9)
    assert all(abs(a.radius - r) <= 1e-9 * r for lp in back.loops for a in lp.arcs)


def _loops_bounds(loops):
    b = np.array([lp.bounds for lp in loops])
    return (b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max())


def _result(loops, r=1.0):
    geom = shapely.orient_polygons(Polygon(loops[0].sample(1e-6), [lp.sample(1e-6) for lp in loops[1:]]))
    return vt.Tightening(loops=loops, geometry=geom, r=r, init="core", tolerance=1e-6, shape=geom)


def test_full_circles_are_written_as_circles(tmp_path):
    square = Loop.from_polygon_ring([(0, 0), (20, 0), (20, 20), (0, 20)])
    quarter = [Arc((5, 5), 2, k * math.pi / 2, -math.pi / 2) for k in range(4, 0, -1)]   # four quarters, cw
    T = _result([square, Loop(quarter), Loop.circle((14, 14), 3, ccw=False)])
    for entities in ("lines-arcs", "lwpolyline"):
        out = tmp_path / f"{entities}.dxf"
        io.write_result(T, out, dxf_entities=entities)
        circles = sorted((tuple(e.dxf.center)[:2], e.dxf.radius) for e in ezdxf.readfile(out).modelspace()
                         if e.dxftype() == "CIRCLE")
        assert circles == [((5, 5), 2), ((14, 14), 3)]
    io.write_result(T, tmp_path / "c.svg", stroke_only=True)
    text = (tmp_path / "c.svg").read_text()
    assert text.count("<circle") == 2 and '<circle id="tightening-2" cx="5" cy="-5" r="2"' in text
    io.write_result(T, tmp_path / "d.svg")
    d = text_of_path(tmp_path / "d.svg")
    assert d.count("A 2 2") == 2 and d.count("A 3 3") == 2              # one circle, two half circles
    back = io.read_svg(tmp_path / "d.svg", flatten=1e-6)
    assert back.area == pytest.approx(400 - 13 * math.pi, abs=1e-4)


def text_of_path(path):
    import re

    return re.search(r'id="tightening" d="([^"]+)"', path.read_text()).group(1)


def test_keep_style_without_styles_warns(plates, tmp_path, capsys):
    path, s, _ = plates["mm"]
    out = tmp_path / "p.svg"
    assert main(["tighten", str(path), "-r", "2.5", "-o", str(out), "--keep-style"]) == 0
    err = capsys.readouterr().err
    assert "no styles to keep" in err and out.exists()
    assert 'id="tightening"' in out.read_text()                     # the default drawing


def test_unitless_inputs_give_unitless_dxf(tmp_path):
    wkt = tmp_path / "s.wkt"
    wkt.write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))")
    out = tmp_path / "s.dxf"
    assert main(["tighten", str(wkt), "-r", "1", "-o", str(out)]) == 0
    doc = ezdxf.readfile(out)
    assert doc.header["$INSUNITS"] == 0                  # not metres (ezdxf's default)
    assert tuple(doc.header["$EXTMIN"])[:2] == pytest.approx((0, 0)) and \
        tuple(doc.header["$EXTMAX"])[:2] == pytest.approx((10, 10))
    assert io.dxf.dxf_frame(unit="px") == (25.4 / 96, 0.0, 0.0, 4)


def test_dxf_input_to_svg_has_its_true_size(plates, tmp_path):
    path, s, _ = plates["in"]
    out = tmp_path / "p.svg"
    assert main(["tighten", str(path), "-r", str(2.5 * s), "-o", str(out)]) == 0
    assert io.svg_unit(out) == "in"
    back = io.read_svg(out, flatten=1e-5 * s)
    T = vt.tighten(io.read_shape(path), 2.5 * s)
    assert back.area == pytest.approx(T.area, rel=1e-5)
    assert back.bounds == pytest.approx(T.geometry.bounds, abs=1e-4 * s)
