"""The command line as a user meets it: exit codes, one-line errors, files written or left alone, batches."""

import json
import math
import os
import re
import subprocess
import sys
import types

import numpy as np
import pytest
import shapely

from vectortighten import cli, io
from vectortighten.cli import main

SQUARE_SVG = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 20">'
              '<path d="M 2 2 H 12 V 12 H 2 Z M 4 4 V 8 H 8 V 4 Z"/></svg>')
BILLION_LAUGHS = ('<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa">'
                  '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]>'
                  '<svg xmlns="http://www.w3.org/2000/svg"><rect width="9" height="9"/><text>&c;</text></svg>')
XXE = ('<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
       '<svg xmlns="http://www.w3.org/2000/svg"><rect width="9" height="9"/><text>&x;</text></svg>')


@pytest.fixture
def square_wkt(tmp_path):
    path = tmp_path / "square.wkt"
    path.write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))")
    return path


@pytest.fixture
def files(tmp_path):
    """Inputs good and bad, by name."""
    made = {
        "sq.svg": SQUARE_SVG,
        "bad.svg": "<svg><rect",
        "notsvg.svg": "<html/>",
        "badpath.svg": '<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 L 1 zz"/></svg>',
        "nan.svg": '<svg xmlns="http://www.w3.org/2000/svg"><polygon points="0,0 nan,4 4,4"/></svg>',
        "laughs.svg": BILLION_LAUGHS,
        "xxe.svg": XXE,
        "bad.wkt": "POLYGON ((0 0, 1 0",
        "nan.wkt": "POLYGON ((0 0, 1 0, NaN 1, 0 0))",
        "bad.geojson": "{not json",
        "nan.geojson": '{"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [NaN, 4], [0, 0]]]}',
        "line.geojson": '{"type": "LineString", "coordinates": [[0, 0], [4, 0]]}',
    }
    for name, text in made.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\nnot really")
    return tmp_path


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "Traceback" not in err[0]
    return err[0]


# ---------------------------------------------------------------------------------------------------------
# Single files
# ---------------------------------------------------------------------------------------------------------
def test_tighten_wkt_to_geojson(square_wkt, tmp_path, capsys):
    out = tmp_path / "t.geojson"
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(out)]) == 0
    data = json.loads(out.read_text())
    props = data["features"][0]["properties"]
    # A square's tightening is its core: the corner formula, perimeter 4a - (8 - 2π) r.
    assert props["perimeter"] == pytest.approx(40 - (8 - 2 * math.pi), rel=1e-12)
    geom = shapely.geometry.shape(data["features"][0]["geometry"])
    assert geom.area == pytest.approx(100 - (4 - math.pi), rel=1e-6)
    assert "perimeter" in capsys.readouterr().out


def test_svg_to_svg_and_dxf(files, tmp_path, capsys):
    svg_out, dxf_out = tmp_path / "t.svg", tmp_path / "t.dxf"
    assert main(["tighten", str(files / "sq.svg"), "-r", "0.5", "-o", str(svg_out),
                 "--layers", "input,core,mortar"]) == 0
    radii = {float(m) for m in re.findall(r"A (\S+) \S+ 0 0 [01]", svg_out.read_text())}
    assert radii == {0.5}
    back = io.read_svg(svg_out, flatten=1e-5)
    # A 10×10 square with a 4×4 hole drawn the other way round (non-zero rule: a hole), r = 0.5.
    expected = 100 - 16 - (4 - math.pi) * 0.25 + (4 - math.pi) * 0.25
    assert back.area == pytest.approx(expected, abs=1e-3)
    pytest.importorskip("ezdxf")
    import ezdxf

    assert main(["tighten", str(files / "sq.svg"), "-r", "0.5", "-o", str(dxf_out)]) == 0
    arcs = ezdxf.readfile(dxf_out).modelspace().query("ARC")
    assert len(arcs) == 8 and {a.dxf.radius for a in arcs} == {0.5}


def test_output_into_existing_folder(square_wkt, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(out), "--format", "svg"]) == 0
    assert (out / "square.svg").exists()


@pytest.mark.parametrize("name, needle", [
    ("bad.svg", "malformed SVG"),
    ("notsvg.svg", "not <svg>"),
    ("badpath.svg", "bad path data"),
    ("nan.svg", "NaN"),
    ("laughs.svg", "refused"),
    ("xxe.svg", "refused"),
    ("bad.wkt", "malformed WKT"),
    ("nan.wkt", "NaN"),
    ("bad.geojson", "malformed GeoJSON"),
    ("nan.geojson", "NaN"),
    ("line.geojson", "no polygons"),
    ("missing.svg", "No such file"),
])
def test_bad_inputs_are_one_line(name, needle, files, tmp_path, capsys):
    out = tmp_path / "out.svg"
    out.write_text("keep")
    assert main(["tighten", str(files / name), "-r", "1", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert needle.lower() in line.lower() and name in line, line
    assert out.read_text() == "keep"
    assert not list(tmp_path.glob(".*.tmp*"))


@pytest.mark.parametrize("argv, needle", [
    (["tighten", "missing.wkt", "-r", "1", "-o", "x.wkt"], "No such file"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/no/such/folder/x.wkt"], "does not exist"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/x.xyz"], "unsupported output format"),
    (["tighten", "{sq}", "-r", "1", "-o", "{sq}"], "overwrite the input"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/./square.wkt"], "overwrite the input"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/x.wkt", "--tolerance", "5"], "tolerance"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/x.wkt", "--format", "svg"], "disagrees"),
    (["tighten", "{sq}", "{sq}", "-r", "1", "-o", "{tmp}/o"], "both be written"),
    (["tighten", "{sq}", "{other}", "-r", "1", "-o", "{tmp}/no/o"], "does not exist"),
    (["tighten", "{sq}", "{sq}", "-r", "1", "-o", "{sq}"], "not a folder"),
    (["tighten", "{tmp}/empty", "-r", "1", "-o", "{tmp}/o"], "no input files"),
    (["demo", "-o", "{tmp}/no/such/dir"], "does not exist"),
])
def test_errors_are_one_line(argv, needle, square_wkt, tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    other = tmp_path / "other.wkt"
    other.write_text("POLYGON ((0 0, 5 0, 5 5, 0 0))")
    before = square_wkt.read_text()
    argv = [a.format(sq=square_wkt, tmp=tmp_path, other=other) for a in argv]
    assert main(argv) == 2
    line = one_error_line(capsys)
    assert needle.lower() in line.lower(), line
    assert square_wkt.read_text() == before
    assert not list(tmp_path.glob(".*tmp*"))


def test_symlinked_output_to_input_refused(square_wkt, tmp_path, capsys):
    link = tmp_path / "link.wkt"
    link.symlink_to(square_wkt)
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(link)]) == 2
    assert "overwrite the input" in one_error_line(capsys)
    assert square_wkt.read_text().startswith("POLYGON")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root reads any file")
def test_unreadable_input(square_wkt, tmp_path, capsys):
    square_wkt.chmod(0)
    try:
        assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(tmp_path / "x.wkt")]) == 2
    finally:
        square_wkt.chmod(0o644)
    assert "Permission denied" in one_error_line(capsys)


def test_unreadable_input_simulated(square_wkt, tmp_path, capsys, monkeypatch):
    def denied(self):
        raise PermissionError(13, "Permission denied", str(self))

    monkeypatch.setattr(type(square_wkt), "read_bytes", denied)
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(tmp_path / "x.wkt")]) == 2
    line = one_error_line(capsys)
    assert "Permission denied" in line and str(square_wkt) in line


@pytest.mark.parametrize("radius", ["0", "-1", "nan", "inf", "abc"])
def test_bad_radius_is_one_line(radius, square_wkt, tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["tighten", str(square_wkt), "-r", radius, "-o", str(tmp_path / "x.wkt")])
    assert exc.value.code == 2
    assert "radius" in one_error_line(capsys)


def test_usage_errors_are_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["tighten", "x.svg", "-o", "y.svg"])           # -r missing
    assert exc.value.code == 2 and "-r/--radius" in one_error_line(capsys)
    with pytest.raises(SystemExit):
        main(["frobnicate"])
    assert "invalid choice" in one_error_line(capsys)
    with pytest.raises(SystemExit):
        main(["tighten", "x.svg", "-r", "1", "-o", "y.svg", "--layers", "core,bogus"])
    assert "bogus" in one_error_line(capsys)


def test_existing_output_untouched_on_failure(square_wkt, tmp_path):
    out = tmp_path / "keep.wkt"
    out.write_text("old")
    bad = tmp_path / "bad.geojson"
    bad.write_text("{not json")
    assert main(["tighten", str(bad), "-r", "1", "-o", str(out)]) == 2
    assert out.read_text() == "old"


def test_writer_crash_leaves_existing_output(square_wkt, tmp_path, monkeypatch, capsys):
    out = tmp_path / "keep.svg"
    out.write_text("old")

    def broken(result, **options):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(io.svg, "svg_document", broken)
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(out)]) == 2
    assert "No space left" in one_error_line(capsys)
    assert out.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["keep.svg", "square.wkt"]


def test_internal_error_is_one_line_exit_1(square_wkt, tmp_path, monkeypatch, capsys):
    import vectortighten.engine as engine

    def bug(*a, **k):
        raise RuntimeError("surgery did not settle")

    monkeypatch.setattr(engine, "tighten", bug)
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(tmp_path / "x.wkt")]) == 1
    line = one_error_line(capsys)
    assert "internal error" in line and "surgery" in line


def test_repair_warning_is_one_line(tmp_path, capsys):
    bowtie = tmp_path / "bowtie.wkt"
    bowtie.write_text("POLYGON ((0 0, 10 10, 10 0, 0 10, 0 0))")
    assert main(["tighten", str(bowtie), "-r", "0.5", "-o", str(tmp_path / "t.wkt")]) == 0
    line = one_error_line(capsys)
    assert line.startswith("vectortighten: warning:") and "make_valid" in line


def test_empty_result_warns(tmp_path, capsys):
    small = tmp_path / "small.wkt"
    small.write_text("POLYGON ((0 0, 1 0, 1 1, 0 1, 0 0))")
    assert main(["tighten", str(small), "-r", "2", "-o", str(tmp_path / "t.svg")]) == 0
    assert "empty" in one_error_line(capsys)


# ---------------------------------------------------------------------------------------------------------
# Batches
# ---------------------------------------------------------------------------------------------------------
@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "in"
    d.mkdir()
    (d / "a.svg").write_text(SQUARE_SVG)
    (d / "b.wkt").write_text("POLYGON ((0 0, 8 0, 8 3, 3 3, 3 8, 0 8, 0 0))")
    (d / "c.geojson").write_text('{"type": "Polygon", "coordinates": [[[0, 0], [4, 0]')   # malformed
    (d / "notes.txt").write_text("ignored")
    return d


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_batch_folder_one_malformed(folder, tmp_path, capsys, jobs):
    out = tmp_path / "out"
    code = main(["tighten", str(folder), "-r", "0.5", "-o", str(out), "--jobs", jobs])
    assert code == 2
    captured = capsys.readouterr()
    errors = [ln for ln in captured.err.splitlines() if "error:" in ln]
    assert len(errors) == 1 and "c.geojson" in errors[0] and "malformed GeoJSON" in errors[0]
    assert "1 of 3 file(s) failed" in captured.err
    assert sorted(p.name for p in out.iterdir()) == ["a.svg", "b.wkt"]
    assert len(captured.out.strip().splitlines()) == 2
    assert "Traceback" not in captured.err


def test_batch_list_with_format_and_progress(folder, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["tighten", str(folder / "a.svg"), str(folder / "b.wkt"), "-r", "0.5", "-o", str(out),
            "--format", "geojson", "--progress", "--jobs", "1"]
    assert main(argv) == 0
    assert sorted(p.name for p in out.iterdir()) == ["a.geojson", "b.geojson"]
    err = capsys.readouterr().err
    assert "2/2" in err and "[" in err


def test_batch_missing_file_continues(folder, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["tighten", str(folder / "a.svg"), str(folder / "nope.svg"), "-r", "0.5", "-o", str(out),
            "--jobs", "1"]
    assert main(argv) == 2
    assert (out / "a.svg").exists()
    err = capsys.readouterr().err
    assert "No such file" in err and "nope.svg" in err


# ---------------------------------------------------------------------------------------------------------
# PNG masks: the raster path
# ---------------------------------------------------------------------------------------------------------
def _mask_png(path):
    from PIL import Image

    mask = np.zeros((40, 60), dtype=np.uint8)
    mask[5:35, 5:50] = 255
    mask[18:22, 50:58] = 255                     # a thin bar: goes with r = 3
    Image.fromarray(mask).save(path)


def test_png_errors(tmp_path, capsys, files):
    assert main(["tighten", str(files / "bad.png"), "-r", "3", "-o", str(tmp_path / "t.png")]) == 2
    err = one_error_line(capsys)
    assert "bad.png" in err and "PNG" in err
    src = tmp_path / "m.png"
    _mask_png(src)
    assert main(["tighten", str(src), "-r", "3", "-o", str(tmp_path / "t.jpg")]) == 2
    assert "JPG cannot hold a mask" in one_error_line(capsys)
    assert not list(tmp_path.glob("t.*")) and not list(tmp_path.glob(".t.*"))


def test_png_without_raster_tighten_is_one_line(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "raster", types.ModuleType("raster"))
    src = tmp_path / "m.png"
    _mask_png(src)
    assert main(["tighten", str(src), "-r", "3", "-o", str(tmp_path / "t.png")]) == 2
    assert "raster" in one_error_line(capsys)


def test_png_with_the_real_raster_package(tmp_path, capsys):
    raster = pytest.importorskip("raster")
    if not all(hasattr(raster, n) for n in ("load_mask", "save_mask", "tighten")):
        pytest.skip("the raster package has no tighten yet")
    src, out = tmp_path / "m.png", tmp_path / "t.png"
    _mask_png(src)
    assert main(["tighten", str(src), "-r", "3", "-o", str(out)]) == 0
    mask = raster.load_mask(out)
    assert mask.shape == (40, 60) and mask[20, 30] and not mask[20, 56]


def test_vector_to_png_rendering(square_wkt, tmp_path):
    out = tmp_path / "t.png"
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------------------------------------------------
# Help
# ---------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("command", sorted(cli.COMMANDS))
def test_help_has_examples(command, capsys):
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "examples:" in out and f"vectortighten {command}" in out


def test_python_dash_m(tmp_path, square_wkt):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    proc = subprocess.run([sys.executable, "-m", "vectortighten", "--help"], capture_output=True, text=True,
                          env=env)
    assert proc.returncode == 0 and "tighten" in proc.stdout and "examples:" in proc.stdout
    proc = subprocess.run([sys.executable, "-m", "vectortighten", "tighten", str(tmp_path / "none.wkt"),
                           "-r", "1", "-o", str(tmp_path / "x.wkt")], capture_output=True, text=True, env=env)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1


def test_hard_link_to_input_refused(square_wkt, tmp_path, capsys):
    link = tmp_path / "hard.wkt"
    os.link(square_wkt, link)
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(link)]) == 2
    assert "overwrite the input" in one_error_line(capsys)
    assert square_wkt.read_text().startswith("POLYGON")


def test_batch_refusal_creates_no_folder(square_wkt, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["tighten", str(square_wkt), str(square_wkt), "-r", "1", "-o", str(out)]) == 2
    assert not out.exists()


def test_svg_in_mm_stays_in_mm(tmp_path):
    src = tmp_path / "mm.svg"
    src.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="30mm" height="20mm" viewBox="0 0 30 20">'
                   '<rect x="5" y="5" width="20" height="10"/></svg>')
    out = tmp_path / "t.svg"
    assert main(["tighten", str(src), "-r", "2", "-o", str(out)]) == 0
    assert io.svg_unit(out) == "mm"
    back = io.read_svg(out, flatten=1e-5)
    assert back.area == pytest.approx(200 - (4 - math.pi) * 4, abs=1e-3)


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and "vectortighten" in capsys.readouterr().out


# -- compare and figures -----------------------------------------------------------------------------------
def test_compare_prints_table_and_plots(tmp_path, capsys):
    src = tmp_path / "l.wkt"
    src.write_text("POLYGON ((0 0, 12 0, 12 5, 5 5, 5 12, 0 12, 0 0))")
    plot = tmp_path / "check.png"
    assert main(["compare", str(src), "-r", "1.5", "--plot", str(plot)]) == 0
    out = capsys.readouterr().out
    assert "Hausdorff distance" in out and "agree" in out and "yes" in out
    assert plot.stat().st_size > 1000


def test_compare_against_the_mask(tmp_path, capsys):
    src = tmp_path / "two.wkt"
    src.write_text("MULTIPOLYGON (((0 0, 6 0, 6 6, 0 6, 0 0)), ((6.015 0, 12 0, 12 6, 6.015 6, 6.015 0)))")
    assert main(["compare", str(src), "-r", "1", "--pixel-size", "0.05", "--mask-reference",
                 "--supersample", "1"]) == 0
    out = capsys.readouterr().out
    rows = dict(line.split("  ", 1) for line in out.splitlines())
    assert rows["agree"].strip().startswith("no") and rows["agree on the mask"].strip() == "yes"


def test_compare_bad_plot_extension(tmp_path, capsys):
    src = tmp_path / "s.wkt"
    src.write_text("POLYGON ((0 0, 4 0, 4 4, 0 4, 0 0))")
    assert main(["compare", str(src), "-r", "1", "--plot", str(tmp_path / "x.txt")]) == 2
    assert "must be .png" in capsys.readouterr().err


def test_figures_command_one_figure(tmp_path, capsys):
    assert main(["figures", "-o", str(tmp_path / "figs"), "--only", "fig2_round_fillet"]) == 0
    assert (tmp_path / "figs" / "fig2_round_fillet.png").stat().st_size > 1000
    assert main(["figures", "-o", str(tmp_path / "figs"), "--only", "fig99"]) == 2
    assert "unknown figure" in capsys.readouterr().err


def test_compare_supersamples_by_default(tmp_path, capsys):
    # A disk of radius 1.02·r: its shrink, 0.4 px across at r/20, holds no pixel centre of a plain
    # rasterisation, and the pixel result loses the disk; supersampled (the default, 7) it keeps it, as
    # the exact one.
    src = tmp_path / "disk.wkt"
    src.write_text(shapely.Point(0.3, 0.1).buffer(1.02, quad_segs=64).wkt)
    results = {}
    for extra in ([], ["--supersample", "1"]):
        assert main(["compare", str(src), "-r", "1", "--pixel-size", "0.05", *extra]) == 0
        rows = dict(line.split("  ", 1) for line in capsys.readouterr().out.splitlines())
        results[tuple(extra)] = (rows["raster: components, holes"].strip(), rows["agree"].strip()[:3])
    assert results[()] == ("1, 0", "yes")
    assert results[("--supersample", "1")] == ("0, 0", "no ")


def test_compare_supersampled(tmp_path, capsys):
    src = tmp_path / "wedge.wkt"
    src.write_text("POLYGON ((0 0, 5.87 1.25, 5.87 -1.25, 0 0))")
    assert main(["compare", str(src), "-r", "0.5", "--supersample", "3"]) == 0
    rows = dict(line.split("  ", 1) for line in capsys.readouterr().out.splitlines())
    assert rows["agree"].strip().startswith("yes")
    with pytest.raises(SystemExit) as exc:
        main(["compare", str(src), "-r", "0.5", "--supersample", "2"])
    assert exc.value.code == 2 and "must be odd" in capsys.readouterr().err
