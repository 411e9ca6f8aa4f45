"""Every figure script runs and writes a non-empty PNG (into a temporary folder)."""

import importlib.util
from pathlib import Path

import pytest

FIGURES_DIR = Path(__file__).resolve().parent.parent / "figures"


def _make_all():
    spec = importlib.util.spec_from_file_location("figures_make_all", FIGURES_DIR / "make_all.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


make_all = _make_all()
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
RASTER = {"fig8_raster_40", "fig9_raster_75"}


def _check(paths, name):
    pngs = [p for p in paths if p.suffix == ".png"]
    assert [p.name for p in pngs] == [f"{name}.png"]
    data = pngs[0].read_bytes()
    assert data.startswith(PNG_MAGIC) and len(data) > 5000
    assert not [p for p in pngs[0].parent.iterdir() if p.name.startswith(".")]   # no temporary left


@pytest.mark.parametrize("name", [n for n in make_all.FIGURES if n not in RASTER])
def test_figure_writes_png(name, tmp_path):
    paths = make_all.load(name).draw(tmp_path)
    _check(paths, name)


@pytest.mark.parametrize("name", sorted(RASTER))
def test_raster_figure_at_reduced_size(name, tmp_path):
    paths = make_all.load(name).draw(tmp_path, scale=0.25)
    _check(paths, name)


def test_svg_option(tmp_path):
    paths = make_all.load("fig1_grow_shrink").draw(tmp_path, svg=True)
    assert sorted(p.suffix for p in paths) == [".png", ".svg"]
    assert all(p.stat().st_size > 0 for p in paths)


def test_run_all_selection(tmp_path):
    paths = make_all.run_all(tmp_path / "out", names=["fig5_tight_curves"])
    assert [p.name for p in paths] == ["fig5_tight_curves.png"]



def test_raster_figure_without_raster_package(tmp_path, monkeypatch):
    helper = make_all.load("_raster_fig")
    monkeypatch.setattr(helper, "raster_module", lambda: None)
    paths = make_all.load("fig9_raster_75").draw(tmp_path, scale=0.25)
    _check(paths, "fig9_raster_75")
