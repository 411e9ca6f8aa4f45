"""Real shapes of the kinds users bring, for the benchmarks and the exactness checks.

Every shape is made from data that ships with the project's dependencies, so nothing is downloaded:

* ``glyph``: letters of five fonts bundled with matplotlib (DejaVu Sans Bold, DejaVu Serif, DejaVu Sans
  Mono, STIX General Italic, Computer Modern Roman), outlines from their Bézier curves, 100 units tall;
* ``icon``: matplotlib's toolbar icons (SVG, 72 × 72 pt), read with `vectortighten.io.read_svg` after the
  invisible page rectangle matplotlib puts under each is taken out;
* ``contour``: traced elevation contours — the coast of matplotlib's ``topobathy.npz`` (Vancouver Island
  and the Puget Sound) and a level of ``jacksboro_fault_dem.npz``, both as marching-squares (sub-pixel)
  polygons after a cubic upsampling, and the coast as a pixel-by-pixel outline;
* ``country``: outlines of Natural Earth's low-resolution countries (shipped in pyogrio's test fixtures),
  projected to an equal-area projection, in metres (skipped when pyogrio or pyproj is missing);
* ``mask``: segmentation masks traced pixel by pixel (the union of the pixel squares): thresholded photos
  and scans from matplotlib's sample data (Grace Hopper, an MRI slice, two logos);
* ``cad``: machined parts drawn as a CAD user would (plates with holes and slots, a gear, a bracket, a
  flange), polygons with arcs flattened at 1e-4 of the part's size.

A case's radii are fractions of its *stroke width* ``w = 2·area / perimeter`` (for a long thin part of
width w this is w; for a disk of radius a it is a): `Case.radii` gives them.

Run ``python benchmarks/corpus.py`` for a table of the corpus (names, vertices, stroke widths).
"""

from __future__ import annotations

import gzip
import math
import re
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import shapely
import shapely.affinity
from shapely.geometry import MultiPolygon, Point, Polygon, box

__all__ = ["FAMILIES", "Case", "cases"]


@dataclass(frozen=True)
class Case:
    """One real shape: its family, a name, and the shape (valid, oriented)."""

    family: str
    name: str
    shape: Polygon | MultiPolygon

    @property
    def n_vertices(self) -> int:
        return int(shapely.get_num_coordinates(self.shape))

    @property
    def width(self) -> float:
        """The stroke width ``2·area / perimeter``."""
        return 2.0 * self.shape.area / self.shape.length

    def radii(self, fractions=(0.25, 0.5, 1.0)) -> list[float]:
        """Radii at these fractions of the stroke width."""
        return [f * self.width for f in fractions]


def _data(*parts) -> Path:
    import matplotlib

    return Path(matplotlib.get_data_path()).joinpath(*parts)


def _valid(geom) -> Polygon | MultiPolygon:
    geom = shapely.make_valid(geom) if not geom.is_valid else geom
    polys = [g for g in shapely.get_parts(geom) if isinstance(g, Polygon) and g.area > 0]
    geom = polys[0] if len(polys) == 1 else MultiPolygon(polys)
    return shapely.orient_polygons(geom)


# -- glyphs -------------------------------------------------------------------------------------------------
_FONTS = {
    "DejaVu Sans Bold": ("DejaVuSans-Bold.ttf", "a&@8Q"),
    "DejaVu Serif": ("DejaVuSerif.ttf", "gRk%"),
    "DejaVu Sans Mono": ("DejaVuSansMono.ttf", "B#e"),
    "STIX General Italic": ("STIXGeneralItalic.ttf", "fSy"),
    "Computer Modern Roman": ("cmr10.ttf", "Mw"),
}


def _glyph(font_file: str, ch: str, size: float = 100.0):
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextPath

    from vectortighten.io import fill_rings

    tp = TextPath((0, 0), ch, size=size, prop=FontProperties(fname=str(_data("fonts", "ttf", font_file))))
    return fill_rings([p for p in tp.to_polygons(closed_only=True) if len(p) >= 4], "nonzero")


def glyphs() -> list[Case]:
    return [Case("glyph", f"{font} '{ch}'", _valid(_glyph(file, ch)))
            for font, (file, chars) in _FONTS.items() for ch in chars]


# -- icons --------------------------------------------------------------------------------------------------
_ICONS = ("home", "help", "filesave", "move", "zoom_to_rect", "subplots", "back", "forward",
          "qt4_editor_options", "matplotlib")
_INVISIBLE = re.compile(rb"<path[^>]*opacity:0;[^>]*/>", re.S)


def icons() -> list[Case]:
    from vectortighten.io import read_svg

    out = []
    for name in _ICONS:
        data = _INVISIBLE.sub(b"", _data("images", f"{name}.svg").read_bytes())
        out.append(Case("icon", name, _valid(read_svg(data))))
    return out


# -- traced contours ------------------------------------------------------------------------------------------
def _marching(z: np.ndarray, level: float, min_area: float) -> Polygon | MultiPolygon:
    """The region ``z > level`` as marching-squares polygons (cell units, y up), small pieces dropped."""
    import contourpy

    gen = contourpy.contour_generator(z=z, fill_type=contourpy.FillType.OuterOffset)
    filled, offsets = gen.filled(level, np.inf)
    polys = []
    for pts, off in zip(filled, offsets, strict=True):
        rings = [pts[a:b] for a, b in zip(off[:-1], off[1:], strict=True)]
        poly = Polygon(rings[0], rings[1:])
        if abs(poly.area) >= min_area:
            polys.append(poly)
    geom = shapely.union_all(polys) if len(polys) > 1 else polys[0]
    return shapely.affinity.scale(geom, 1, -1, origin=(0, 0))


def _pixel_outline(mask: np.ndarray) -> Polygon | MultiPolygon:
    """The union of the True pixels' unit squares (row i, column j is [j, j+1] × [−i−1, −i]), exactly."""
    boxes = []
    for i, row in enumerate(mask):
        d = np.diff(np.r_[0, row.astype(np.int8), 0])
        start, stop = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
        boxes.append(shapely.box(start, -i - 1, stop, -i))
    return shapely.simplify(shapely.union_all(np.concatenate(boxes)), 0.0)


@cache
def _topo(zoom: float) -> np.ndarray:
    from scipy import ndimage

    topo = np.load(_data("sample_data", "topobathy.npz"))["topo"].astype(float)
    return ndimage.zoom(topo, zoom, order=3) if zoom != 1 else topo


def contours() -> list[Case]:
    from scipy import ndimage

    out = [Case("contour", "topobathy coast, marching squares ×4", _valid(_marching(_topo(4.0), 0.0, 4.0)))]
    out.append(Case("contour", "topobathy coast, pixel outline ×4", _valid(_pixel_outline(_topo(4.0) > 0))))
    dem = np.load(_data("sample_data", "jacksboro_fault_dem.npz"))["elevation"].astype(float)
    dem = ndimage.zoom(dem, 3.0, order=3)
    level = float(np.percentile(dem, 60))
    out.append(Case("contour", "jacksboro DEM, 60th-percentile contour ×3", _valid(_marching(dem, level, 9.0))))
    return out


# -- countries ------------------------------------------------------------------------------------------------
_COUNTRIES = ("Norway", "Chile", "Greece", "Japan", "United Kingdom", "Italy", "Indonesia", "Canada",
              "Madagascar", "Brazil")


def countries() -> list[Case]:
    try:
        import pyogrio
        import pyproj
    except ImportError:
        return []
    path = Path(pyogrio.__file__).parent / "tests" / "fixtures" / "naturalearth_lowres" / "naturalearth_lowres.shp"
    if not path.exists():
        return []
    info = pyogrio.read_info(path)
    table = pyogrio.read_dataframe(path, columns=["name"]) if _has_geopandas() else None
    if table is None:
        names, geoms = _read_plain(path, pyogrio)
    else:
        names, geoms = list(table["name"]), list(table.geometry)
    to_ea = pyproj.Transformer.from_crs(info["crs"], "+proj=eqearth +datum=WGS84 +units=m", always_xy=True)
    out = []
    for name, geom in zip(names, geoms, strict=True):
        if name in _COUNTRIES:
            projected = shapely.transform(geom, lambda c: np.column_stack(to_ea.transform(c[:, 0], c[:, 1])))
            out.append(Case("country", name, _valid(projected)))
    return out


def _has_geopandas() -> bool:
    try:
        import geopandas  # noqa: F401
    except ImportError:
        return False
    return True


def _read_plain(path, pyogrio):
    _, _, wkb, fields = pyogrio.raw.read(path, columns=["name"])
    return list(fields[0]), list(shapely.from_wkb(wkb))


# -- masks ------------------------------------------------------------------------------------------------------
def _grey(name: str) -> np.ndarray:
    from PIL import Image

    with Image.open(_data("sample_data", name)) as img:
        if img.mode in ("RGBA", "LA"):
            return np.asarray(img.convert("RGBA"))[:, :, 3] / 255.0
        return np.asarray(img.convert("L")) / 255.0


def masks() -> list[Case]:
    from scipy import ndimage

    out = []
    hopper = ndimage.gaussian_filter(_grey("grace_hopper.jpg"), 1.5)
    out.append(Case("mask", "Grace Hopper, dark regions", _valid(_pixel_outline(_largest(hopper < 0.25, 40)))))
    with gzip.open(_data("sample_data", "s1045.ima.gz")) as f:
        mri = np.frombuffer(f.read(), np.uint16).reshape(256, 256).astype(float)
    mri = ndimage.gaussian_filter(mri, 1.0)
    out.append(Case("mask", "MRI slice, tissue", _valid(_pixel_outline(_largest(mri > np.percentile(mri, 55), 30)))))
    out.append(Case("mask", "matplotlib logo", _valid(_pixel_outline(_largest(_grey("logo2.png") < 0.6, 20)))))
    out.append(Case("mask", "present box (alpha)", _valid(_pixel_outline(_largest(_grey("Minduka_Present_Blue_Pack.png") > 0.5, 20)))))
    return out


def _largest(mask: np.ndarray, min_pixels: int) -> np.ndarray:
    """The mask without its components smaller than ``min_pixels`` (speckle, as a user would clean)."""
    from scipy import ndimage

    lab, n = ndimage.label(mask)
    sizes = np.bincount(lab.ravel())
    keep = sizes >= min_pixels
    keep[0] = False
    return keep[lab]


# -- CAD parts ----------------------------------------------------------------------------------------------------
def _q(size: float) -> int:
    """``quad_segs`` for arcs of a part of this size, chords within 1e-4 of it."""
    return max(8, math.ceil(math.pi / (4 * math.acos(1 - 1e-4))))


def cads() -> list[Case]:
    q = _q(1.0)
    plate = box(0, 0, 120, 80).buffer(-6, quad_segs=q).buffer(6, quad_segs=q)
    for x, y in ((12, 12), (108, 12), (12, 68), (108, 68)):
        plate = plate.difference(Point(x, y).buffer(4, quad_segs=q))
    slot = shapely.LineString([(40, 40), (80, 40)]).buffer(5, quad_segs=q)
    plate = plate.difference(slot).difference(box(55, 70, 65, 80))              # a slot and a notch
    gear = _gear(teeth=24, module=2.0)
    bracket = Polygon([(0, 0), (60, 0), (60, 8), (8, 8), (8, 50), (0, 50)]).buffer(2, quad_segs=q).buffer(-2, quad_segs=q)
    bracket = bracket.difference(Point(30, 4).buffer(2.5, quad_segs=q)).difference(Point(4, 30).buffer(2.5, quad_segs=q))
    flange = Point(0, 0).buffer(50, quad_segs=q).difference(Point(0, 0).buffer(25, quad_segs=q))
    for k in range(6):
        a = k * math.pi / 3
        flange = flange.difference(Point(38 * math.cos(a), 38 * math.sin(a)).buffer(4, quad_segs=q))
    return [Case("cad", "plate with holes, slot and notch", _valid(plate)),
            Case("cad", "spur gear, 24 teeth", _valid(gear)),
            Case("cad", "angle bracket", _valid(bracket)),
            Case("cad", "flange, six bolt holes", _valid(flange))]


def _gear(teeth: int, module: float) -> Polygon:
    """A spur gear's outline: trapezoidal teeth with flat tips and roots, and a bore with a keyway."""
    pitch = module * teeth / 2
    outer, root = pitch + module, pitch - 1.25 * module
    pts = []
    for k in range(teeth):
        a = 2 * math.pi * k / teeth
        w = math.pi / teeth
        for ang, rad in ((a - 0.5 * w, root), (a - 0.3 * w, outer), (a + 0.3 * w, outer), (a + 0.5 * w, root)):
            pts.append((rad * math.cos(ang), rad * math.sin(ang)))
    bore = Point(0, 0).buffer(0.25 * pitch, quad_segs=_q(1.0)).union(box(-2, 0, 2, 0.25 * pitch + 2))
    return Polygon(pts).difference(bore)


FAMILIES = {"glyph": glyphs, "icon": icons, "contour": contours, "country": countries, "mask": masks,
            "cad": cads}


def cases(families=None) -> list[Case]:
    """The corpus, family by family (all families by default)."""
    out = []
    for name in families or FAMILIES:
        out += FAMILIES[name]()
    return out


if __name__ == "__main__":
    print("| family | name | vertices | parts | holes | stroke width |")
    print("|---|---|---:|---:|---:|---:|")
    for c in cases():
        parts = list(shapely.get_parts(c.shape))
        holes = sum(len(p.interiors) for p in parts)
        print(f"| {c.family} | {c.name} | {c.n_vertices} | {len(parts)} | {holes} | {c.width:.4g} |")
