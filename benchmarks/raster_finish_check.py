"""Figures 8 and 9: raster.tighten (defaults or given options) against the exact tightening; prints time,
the time of one EDT, steps and convergence per level, and the boundary Hausdorff distance (px).

Usage: python benchmarks/raster_finish_check.py 8|9 "dict(...)"  (run from the repository root)
"""
import sys, time, warnings, numpy as np
sys.path.insert(0, 'figures')
from _shapes import coastline
from _raster_fig import _rasterize, hausdorff
import raster, vectortighten as vt
from scipy import ndimage
which = sys.argv[1] if len(sys.argv) > 1 else "8"
if which == "8":
    S, W, H, r = coastline(1.0), 1102, 832, 40.0
else:
    from _shapes import turtle; S, W, H, r = turtle(1.0), 1050, 825, 75.0


mask, grid = _rasterize(raster, S, (H, W))
t0=time.perf_counter(); ndimage.distance_transform_edt(mask); t_edt=time.perf_counter()-t0
kw = eval(sys.argv[2]) if len(sys.argv) > 2 else {}
t0=time.perf_counter()
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    res = raster.tighten(mask, r, **kw)
t=time.perf_counter()-t0
print("time", round(t,2), "edt", round(t_edt,3), "ratio", round(t/t_edt,1), res.iterations, res.converged, [str(x.message)[:80] for x in w])
print({k: round(v,2) for k,v in res.timings.items()})
T = vt.tighten(S, r, init="core")
C = raster.contours(res, grid)
T = vt.tighten(S, r, init=kw.get("init", "core"))
C = raster.contours(res, grid)
print("hausdorff", round(hausdorff(C, T.geometry),2), vt.n_components(C), vt.n_holes(C), vt.n_components(T.geometry), vt.n_holes(T.geometry))
