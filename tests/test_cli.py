"""The command line as a user meets it: exit codes, one-line errors, files written or left alone."""

import json
import subprocess
import sys

import pytest
import shapely

from vectortighten.cli import main


@pytest.fixture
def square_wkt(tmp_path):
    path = tmp_path / "square.wkt"
    path.write_text("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0))")
    return path


def test_tighten_wkt_to_geojson(square_wkt, tmp_path, capsys):
    out = tmp_path / "t.geojson"
    assert main(["tighten", str(square_wkt), "-r", "1", "-o", str(out)]) == 0
    data = json.loads(out.read_text())
    props = data["features"][0]["properties"]
    # A square's tightening is its core: the corner formula, perimeter 4a - (8 - 2π) r.
    assert props["perimeter"] == pytest.approx(40 - (8 - 2 * 3.141592653589793), rel=1e-12)
    geom = shapely.geometry.shape(data["features"][0]["geometry"])
    assert geom.area == pytest.approx(100 - (4 - 3.141592653589793), rel=1e-6)


@pytest.mark.parametrize("argv, needle", [
    (["tighten", "missing.wkt", "-r", "1", "-o", "x.wkt"], "No such file"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/no/such/folder/x.wkt"], "does not exist"),
    (["tighten", "{sq}", "-r", "1", "-o", "{tmp}/x.xyz"], "unsupported output format"),
    (["tighten", "{bad}", "-r", "1", "-o", "{tmp}/x.wkt"], "malformed WKT"),
    (["tighten", "{nan}", "-r", "1", "-o", "{tmp}/x.wkt"], "finite"),
    (["tighten", "{sq}", "-r", "1", "-o", "{sq}"], "overwrite the input"),
])
def test_errors_are_one_line(argv, needle, square_wkt, tmp_path, capsys):
    bad = tmp_path / "bad.wkt"
    bad.write_text("POLYGON ((0 0, 1 0")
    nan = tmp_path / "nan.wkt"
    nan.write_text("POLYGON ((0 0, 1 0, NaN 1, 0 0))")
    before = square_wkt.read_text()
    argv = [a.format(sq=square_wkt, tmp=tmp_path, bad=bad, nan=nan) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle.lower() in err[0].lower(), err
    assert square_wkt.read_text() == before
    assert not list(tmp_path.glob(".*tmp"))


@pytest.mark.parametrize("radius", ["0", "-1", "nan", "inf", "abc"])
def test_bad_radius_is_a_usage_error(radius, square_wkt, tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["tighten", str(square_wkt), "-r", radius, "-o", str(tmp_path / "x.wkt")])
    assert exc.value.code == 2
    assert "radius" in capsys.readouterr().err


def test_existing_output_untouched_on_failure(square_wkt, tmp_path):
    out = tmp_path / "keep.wkt"
    out.write_text("old")
    bad = tmp_path / "bad.geojson"
    bad.write_text("{not json")
    assert main(["tighten", str(bad), "-r", "1", "-o", str(out)]) == 2
    assert out.read_text() == "old"


def test_python_dash_m(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "vectortighten", "--help"], capture_output=True, text=True)
    assert proc.returncode == 0 and "tighten" in proc.stdout
