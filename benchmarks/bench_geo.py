"""Speed of `tighten_all` on many small real-looking polygons against shapely's vectorised opening + closing.

The dataset: N building footprints in metres (seeded), the kind a city's cadastre holds: a rectangle
8–25 m by 8–20 m with up to three wings (rectilinear unions), up to two recesses 0.5–2 m wide cut into
it, its edges digitised every 2–4 m with 5 cm of noise, rotated at random and laid out on a 40 m grid;
19–44 vertices each (median 30). r = 1 m: every corner is rounded, recesses narrower than 2 m are
filled, and wings narrower than 2 m vanish.

Timed in the same process, alternately:

* the baseline: shapely's vectorised ``buffer(buffer(a, -r), r)`` and ``buffer(buffer(a, r), -r)`` on the
  whole array, with the ``quad_segs`` that the tolerance (1e-5·r) gives — the opening and closing at the
  engine's precision; also at shapely's default ``quad_segs`` (8) for reference;
* ``vectortighten.tighten_all(a, r)`` serially and with ``processes=2``;
* on the first ``--loop`` features, a plain Python loop of ``vt.tighten(g, r).geometry`` against
  ``tighten_all`` of the same features: what the vectorised wrapper itself costs.

CPU seconds of this process for the baseline, the serial runs and the loop (the machine is shared, and
its wall clock moves with the other work); wall-clock seconds for ``processes=2``, with the CPU seconds
its two workers spent. Medians of ``--repeats`` for the baseline and the loop comparison; the engine runs
take minutes, so they run ``--engine-repeats`` times (default 1). ``--profile K`` profiles the serial
engine on K features and prints where the time goes.

Run:  python benchmarks/bench_geo.py [--n 10000] [--repeats 3] [--engine-repeats 1] [--profile 300]
It prints a markdown report and writes it to benchmarks/results/geo.md.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import os
import platform
import pstats
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import Polygon

import vectortighten as vt
from vectortighten._validation import quad_segs_for

HERE = Path(__file__).resolve().parent


def footprint(rng: np.random.Generator) -> Polygon:
    """One building footprint (metres), see the module's docstring."""
    w, h = rng.uniform(8, 25), rng.uniform(8, 20)
    parts = [shapely.box(0, 0, w, h)]
    for _ in range(rng.integers(0, 4)):                                  # wings
        x0, y0 = rng.uniform(-4, w), rng.uniform(-4, h)
        parts.append(shapely.box(x0, y0, x0 + rng.uniform(3, 10), y0 + rng.uniform(3, 10)))
    g = shapely.union_all(parts)
    for _ in range(rng.integers(0, 3)):                                  # recesses
        x0, y0 = rng.uniform(0, w), rng.uniform(0, h)
        g = g.difference(shapely.box(x0, y0, x0 + rng.uniform(0.5, 2), y0 + rng.uniform(0.5, 2)))
    if g.geom_type != "Polygon":
        g = max(g.geoms, key=lambda p: p.area)
    g = shapely.segmentize(Polygon(g.exterior), rng.uniform(2, 4))       # digitised edges
    c = shapely.get_coordinates(g)
    c = c + rng.normal(0, 0.05, c.shape)
    c[-1] = c[0]
    g = shapely.make_valid(Polygon(c))
    if g.geom_type != "Polygon":
        g = max(shapely.get_parts(g), key=lambda p: p.area if p.geom_type == "Polygon" else 0)
    return affinity.rotate(g, rng.uniform(0, 180))


def footprints(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n)))
    out = np.empty(n, dtype=object)
    for i in range(n):
        out[i] = affinity.translate(footprint(rng), (i % side) * 40.0, (i // side) * 40.0)
    return out


def opening_closing(a: np.ndarray, r: float, q: int):
    op = shapely.buffer(shapely.buffer(a, -r, quad_segs=q), r, quad_segs=q)
    cl = shapely.buffer(shapely.buffer(a, r, quad_segs=q), -r, quad_segs=q)
    return op, cl


def timed(fn, clock=time.process_time):
    t = clock()
    out = fn()
    return clock() - t, out


def timed_workers(fn):
    """Wall-clock seconds of ``fn`` and the CPU seconds of the worker processes it started and joined."""
    import resource

    def children():
        u = resource.getrusage(resource.RUSAGE_CHILDREN)
        return u.ru_utime + u.ru_stime

    c0, t0 = children(), time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, children() - c0, out


def quiet(fn):
    def run():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return fn()
    return run


def profile(a: np.ndarray, r: float, k: int) -> str:
    pr = cProfile.Profile()
    pr.enable()
    quiet(lambda: vt.tighten_all(a[:k], r))()
    pr.disable()
    buf = io.StringIO()
    pstats.Stats(pr, stream=buf).sort_stats("cumulative").print_stats(30)
    return buf.getvalue()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10000)
    ap.add_argument("--r", type=float, default=1.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--engine-repeats", type=int, default=1)
    ap.add_argument("--loop", type=int, default=500)
    ap.add_argument("--profile", type=int, default=0)
    ap.add_argument("--out", type=Path, default=HERE / "results" / "geo.md")
    args = ap.parse_args(argv)
    r = args.r
    a = footprints(args.n)
    nv = shapely.get_num_coordinates(a)
    q = quad_segs_for(r, 1e-5 * r)

    base, base_default, serial, spread, spread_cpu = [], [], [], [], []
    load = [os.getloadavg()[0]]
    for k in range(max(args.repeats, args.engine_repeats)):
        if k < args.repeats:
            base.append(timed(lambda: opening_closing(a, r, q))[0])
            base_default.append(timed(lambda: opening_closing(a, r, 8))[0])
        if k < args.engine_repeats:
            t, out = timed(quiet(lambda: vt.tighten_all(a, r)))
            serial.append(t)
            t, c, out2 = timed_workers(quiet(lambda: vt.tighten_all(a, r, processes=2)))
            spread.append(t)
            spread_cpu.append(c)
            load.append(os.getloadavg()[0])
            assert [shapely.to_wkb(g) for g in out] == [shapely.to_wkb(g) for g in out2]
        print(f"run {k + 1}: baseline {base[-1]:.2f} s" + (f", serial {serial[-1]:.1f} s, processes=2 "
              f"{spread[-1]:.1f} s" if k < args.engine_repeats else ""), file=sys.stderr, flush=True)
    m = args.loop
    t_loop, t_all = [], []
    for _ in range(args.repeats):
        t_loop.append(timed(quiet(lambda: [vt.tighten(g, r).geometry for g in a[:m]]))[0])
        t_all.append(timed(quiet(lambda: vt.tighten_all(a[:m], r)))[0])
    t_loop, t_all = statistics.median(t_loop), statistics.median(t_all)
    paths = {"fast": 0, "convex": 0, "general": 0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for g in a[:m]:
            paths[vt.tighten(g, r)._cache["_path"]] += 1
    empty = int(sum(g.is_empty for g in out))

    b, bd, s, p, pc = (statistics.median(x) for x in (base, base_default, serial, spread, spread_cpu))
    n = args.n
    lines = [
        "# tighten_all on building footprints vs shapely's vectorised opening + closing",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared with other work while this ran), "
        f"Python {platform.python_version()}, shapely {shapely.__version__} "
        f"(GEOS {shapely.geos_version_string}). "
        f"CPU seconds (wall-clock for processes=2); baseline medians of {args.repeats}, engine runs "
        f"{args.engine_repeats}; 1-minute load average {min(load):.1f}–{max(load):.1f} during the runs. "
        f"Command: `python benchmarks/bench_geo.py --n {n} --repeats {args.repeats} "
        f"--engine-repeats {args.engine_repeats} --loop {m}`.",
        "",
        f"Dataset: {n} footprints (seed 0), {int(nv.sum())} vertices, {int(np.median(nv))} per footprint "
        f"(5–95 %: {int(np.percentile(nv, 5))}–{int(np.percentile(nv, 95))}); r = {r:g} m, tolerance 1e-5·r "
        f"(quad_segs {q} for the baseline). {empty} footprints vanish (no 2r-wide part). Engine path on the "
        f"first {m}: {paths['fast']} fast, {paths['convex']} convex (closed form), {paths['general']} general.",
        "",
        f"| run | time (s) | features/s | ratio to opening + closing (quad_segs {q}) |",
        "|---|---:|---:|---:|",
        f"| shapely opening + closing, quad_segs {q} (baseline) | {b:.2f} cpu | {n / b:,.0f} | 1 |",
        f"| shapely opening + closing, quad_segs 8 (default) | {bd:.2f} cpu | {n / bd:,.0f} | {bd / b:.2f} |",
        f"| tighten_all, serial | {s:.1f} cpu | {n / s:,.0f} | {s / b:.0f} |",
        f"| tighten_all, processes=2 | {p:.1f} wall ({pc:.0f} cpu in the workers) | {n / p:,.0f} | "
        f"{p / b:.0f} (wall / cpu) |",
        "",
        f"Wrapper overhead, first {m} footprints: loop of `vt.tighten(g, r).geometry` {t_loop:.2f} s, "
        f"`tighten_all` {t_all:.2f} s ({100 * (t_all / t_loop - 1):+.1f} %). Parallel speed-up with two "
        f"processes: {s / p:.2f}× (serial cpu / parallel wall; the workers' cpu over the serial: "
        f"{pc / s:.2f}). Identical geometries serially and in parallel: yes (checked).",
        "",
    ]
    if args.profile:
        lines += [f"Profile of the serial engine on the first {args.profile} footprints (cumulative):", "",
                  "```", profile(a, r, args.profile).strip(), "```", ""]
    text = "\n".join(lines)
    print(text)
    args.out.parent.mkdir(exist_ok=True)
    tmp = args.out.with_suffix(".md.tmp")
    tmp.write_text(text)
    os.replace(tmp, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
