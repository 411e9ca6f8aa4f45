"""DXF: a tightening written as LINE and ARC entities (arcs of radius exactly r).

ezdxf (``pip install vectortighten[dxf]``) is imported only when a DXF file is met.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from vectortighten.curves import Segment

from ._common import _require

__all__ = ["write_dxf"]


_DXF_UNITS = {"in": 1, "mm": 4, "cm": 5}    # $INSUNITS codes


def write_dxf(result, tmp: Path, layers, unit=None) -> None:
    """Write ``result`` to the file ``tmp`` as DXF R2010: LINE, ARC and CIRCLE entities, ``layers`` as LWPOLYLINEs."""
    ezdxf = _require("ezdxf", "dxf", "writing DXF")
    doc = ezdxf.new("R2010", setup=False)
    if unit in _DXF_UNITS:
        doc.header["$INSUNITS"] = _DXF_UNITS[unit]
    msp = doc.modelspace()
    doc.layers.add("TIGHTENING", color=1)
    for loop in result.loops:
        for p in loop.pieces:
            attribs = {"layer": "TIGHTENING"}
            if isinstance(p, Segment):
                msp.add_line(p.start, p.end, dxfattribs=attribs)
            elif abs(p.sweep) >= 2 * math.pi * (1 - 1e-12):
                msp.add_circle(p.center, p.radius, dxfattribs=attribs)
            else:
                # DXF arcs always run counter-clockwise from start_angle to end_angle: a clockwise piece
                # (negative sweep) is written from its end to its start.
                a0, a1 = (p.start_angle, p.end_angle) if p.sweep > 0 else (p.end_angle, p.start_angle)
                msp.add_arc(p.center, p.radius, math.degrees(a0) % 360.0, math.degrees(a1) % 360.0,
                            dxfattribs=attribs)
    for name in layers:
        geom = result.shape if name == "input" else getattr(result, name)
        doc.layers.add(name.upper(), color={"input": 5, "core": 7, "mortar": 8}[name])
        for poly in shapely.get_parts(geom):
            if not isinstance(poly, Polygon) or poly.is_empty:
                continue
            for ring in (poly.exterior, *poly.interiors):
                msp.add_lwpolyline(np.asarray(ring.coords)[:-1], close=True,
                                   dxfattribs={"layer": name.upper()})
    doc.saveas(tmp)
