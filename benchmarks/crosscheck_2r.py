"""Issue 24: the cross-check at whole-pixel radii on pixel masks (pixel flow against the exact engine).

Pixel blobs (`tests.shapes_dense.pixel_blob`, 60 × 60 px, four seeds) are tightened at r = 3 and 8 px,
both inits, by the pixel flow (`raster.tighten`, defaults) and exactly on the mask's own pixel squares
(`crosscheck(..., mask_reference=True)`): at whole-pixel radii the blobs' strokes and gaps are often
exactly 2r wide, the case of the closed shrink. Prints, per case, the Hausdorff distance in pixels and
whether the topology agrees, and the count within 2 px with equal topology.

    python benchmarks/crosscheck_2r.py
"""

from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import vectortighten as vt  # noqa: E402
from tests import shapes_dense as sd  # noqa: E402


def main() -> int:
    rows, ok = [], 0
    for seed in range(4):
        S = sd.pixel_blob(60, seed)
        for r in (3, 8):
            for init in ("core", "input"):
                t0 = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    C = vt.crosscheck(S, float(r), pixel_size=1.0, init=init, mask_reference=True)
                good = C.agree_on_mask
                ok += bool(good)
                rows.append(f"| blob seed {seed} | {r} | {init} | {C.mask_hausdorff_px:.2f} | {C.mask_topology} | "
                            f"{C.raster_topology} | {'yes' if good else 'no'} | {time.perf_counter() - t0:.1f} |")
                print(rows[-1], flush=True)
    print(f"\n**{ok} of {len(rows)} within 2 px with equal topology.**")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
