"""What ``verify()`` costs against the tightening it checks, on fast-path and general shapes (issue 26).

For each case: the engine's path, the CPU time of `tighten` and of a first ``verify()`` on its result
(which builds the exact context when the fast path ran: S's exact offsets), their ratio, and whether
verify was clean. Cases, the same on every run:

* fast path: smooth wavy stars (2000 and 20 000 vertices), the glyphs of `benchmarks/corpus.py` at a
  twentieth of their stroke width, 40 building footprints of `bench_geo.footprints(1000)` at r = 1 m,
  a crop of the Grace Hopper bright-regions mask at r = 0.37 px (every pixel corner isolated);
* general: the same glyphs at half their stroke width, `tests.shapes_dense.admin_outline(4000)` at
  r = 600, a pixel blob at r = 3.

``--src`` imports ``vectortighten`` from another tree (e.g. a ``git archive`` of an older commit), so
two versions can be run one after the other on the same inputs.

    python benchmarks/verify_cost.py [--src TREE] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from _trees import use_tree

HERE = Path(__file__).resolve().parent


def cases():
    sys.path.insert(0, str(HERE.parent))
    sys.path.insert(0, str(HERE))
    import shapely
    from scipy import ndimage
    from shapely.geometry import Polygon

    import bench_geo
    import corpus

    from tests import shapes_dense as sd

    out = []
    for n in (2000, 20_000):
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        rad = 10 + 0.8 * np.sin(7 * t) + 0.3 * np.sin(19 * t)
        out.append(("fast", f"wavy star {n}", Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)])), 0.3))
    glyphs = corpus.glyphs()
    out += [("fast", f"glyph {c.name} r=0.05w", c.shape, 0.05 * c.width) for c in glyphs[::4]]
    fps = bench_geo.footprints(1000)[:40]
    out += [("fast", f"footprint {i}", g, 1.0) for i, g in enumerate(fps)]
    hopper = ndimage.gaussian_filter(corpus._grey("grace_hopper.jpg"), 1.5)
    mask = corpus._valid(corpus._pixel_outline(corpus._largest(hopper > 0.7, 40)))
    out.append(("fast", "Grace Hopper bright, crop 250 px, r=0.37", corpus._valid(
        shapely.clip_by_rect(mask, 0, -250, 250, 0)), 0.3713))
    out += [("general", f"glyph {c.name} r=0.5w", c.shape, 0.5 * c.width) for c in glyphs[::4]]
    out += [("general", "admin 4000 r=600", sd.admin_outline(4000, seed=0), 600.0),
            ("general", "pixel blob 60px r=3", sd.pixel_blob(60, seed=0), 3.0)]
    return out


def tighten_and_verify(vt, S, r: float):
    """CPU seconds of ``vt.tighten(S, r)`` and of a first ``verify()`` of it, verify's findings, the path."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t0 = time.process_time()
        T = vt.tighten(S, r)
        t1 = time.process_time()
        problems = T.verify()
        t2 = time.process_time()
    return t1 - t0, t2 - t1, problems, T._cache.get("_path", "?")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", default=None)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        todo = cases()
    if args.src:
        use_tree(args.src)
    import vectortighten as vt

    rows, ratios = [], {"fast": [], "general": [], "convex": []}
    for group, name, S, r in todo:
        tighten_s, verify_s, problems, path = tighten_and_verify(vt, S, r)
        ratio = verify_s / max(tighten_s, 1e-6)
        ratios.setdefault(path, []).append(ratio)
        rows.append(f"| {group} | {name} | {path} | {tighten_s:.3f} | {verify_s:.3f} | {ratio:.2f} | "
                    f"{'clean' if not problems else problems[0][:50]} |")
        print(rows[-1], flush=True)
    lines = [f"vectortighten from `{vt.__file__}`; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; CPU s.",
             "", "| path | results | median verify/tighten | max |", "|---|---|---|---|"]
    for path, v in ratios.items():
        if v:
            lines.append(f"| {path} | {len(v)} | {statistics.median(v):.2f} | {max(v):.2f} |")
    lines += ["", "| group | case | path | tighten s | verify s | verify/tighten | verify |",
              "|---|---|---|---|---|---|---|", *rows, ""]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text)


if __name__ == "__main__":
    main()
