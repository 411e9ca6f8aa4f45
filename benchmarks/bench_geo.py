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
* on the first ``--paired`` features, block by block, the baseline right before the serial engine: the
  ratio of the two with both under the same load (the steadiest figure on a shared machine);
* on the first ``--loop`` features, a plain Python loop of ``vt.tighten(g, r).geometry`` against
  ``tighten_all`` of the same features: what the vectorised wrapper itself costs.

CPU seconds of this process for the baseline and the loop. The engine runs are measured three ways: CPU
seconds (of this process serially, of the two workers with ``processes=2``), wall-clock seconds, and the
seconds each process spent runnable but waiting for a core (Linux schedstat). On a shared machine the
wall clock of ``processes=2`` says little by itself: with the kernel's autogroup scheduling (on by
default on desktop Linux) all processes of one session share one session's fair share of the cores, so
two workers get no more CPU than one process would while other sessions are busy. Wall clock less the
time waiting for a core estimates what two idle cores would give. Medians of ``--repeats`` for the
baseline and the loop comparison; the engine runs take minutes, so they run ``--engine-repeats`` times
(default 1). ``--profile K`` profiles the serial engine on K features and prints where the time goes.

Run:  python benchmarks/bench_geo.py [--n 10000] [--repeats 3] [--engine-repeats 1] [--paired 1000]
      [--profile 300]
It prints a markdown report and writes it to benchmarks/results/geo.md.
"""

from __future__ import annotations

import argparse
import cProfile
import glob
import io
import os
import platform
import pstats
import statistics
import sys
import threading
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


def schedstat(pid: int | str = "self") -> tuple[float, float] | None:
    """CPU seconds and run-queue seconds (runnable, waiting for a core) of a process's threads so far.

    From Linux's ``/proc/PID/task/*/schedstat``; None where it cannot be read (another system).
    """
    run = wait = 0
    found = False
    for f in glob.glob(f"/proc/{pid}/task/*/schedstat"):
        try:
            a, b, _ = Path(f).read_text().split()
        except (OSError, ValueError):
            continue
        run, wait, found = run + int(a), wait + int(b), True
    return (run / 1e9, wait / 1e9) if found else None


def timed_serial(fn):
    """``fn()`` in this process: its CPU, wall-clock and run-queue seconds, and what it returned."""
    s0, c0, t0 = schedstat(), time.process_time(), time.perf_counter()
    out = fn()
    wall, cpu, s1 = time.perf_counter() - t0, time.process_time() - c0, schedstat()
    wait = s1[1] - s0[1] if s0 and s1 else float("nan")
    return {"wall": wall, "cpu": cpu, "wait": [wait]}, out


def timed_workers(fn):
    """``fn()`` that starts and joins worker processes: wall-clock seconds, the workers' CPU seconds and
    each worker's run-queue seconds (its schedstat, polled every 20 ms while it lives), and its result."""
    import resource

    def children_cpu():
        u = resource.getrusage(resource.RUSAGE_CHILDREN)
        return u.ru_utime + u.ru_stime

    me = os.getpid()
    last: dict[int, tuple[float, float]] = {}
    stop = threading.Event()

    def poll():
        while not stop.is_set():
            for f in glob.glob(f"/proc/{me}/task/*/children"):
                try:
                    pids = Path(f).read_text().split()
                except OSError:
                    continue
                for pid in pids:
                    try:         # the workers, not multiprocessing's resource tracker
                        if b"spawn_main" not in Path(f"/proc/{pid}/cmdline").read_bytes():
                            continue
                    except OSError:
                        continue
                    got = schedstat(pid)
                    if got is not None:
                        last[int(pid)] = got
            stop.wait(0.02)

    watcher = threading.Thread(target=poll, daemon=True)
    c0, t0 = children_cpu(), time.perf_counter()
    watcher.start()
    try:
        out = fn()
    finally:
        stop.set()
        watcher.join()
    wall = time.perf_counter() - t0
    return {"wall": wall, "cpu": children_cpu() - c0, "wait": [w for _, w in last.values()]}, out


def idle_estimate(run: dict) -> float:
    """Wall-clock seconds less the least run-queue wait of the process(es) that did the work.

    What the run would take if no other process had held the cores it waited for: every worker waits
    for a core at least that long, and the wall clock ends with the last of them. An estimate (it
    ignores that cores shared by hyper-threads or memory bandwidth slow each other).
    """
    waits = [w for w in run["wait"] if w == w]
    return run["wall"] - min(waits) if waits else float("nan")


def paired(a: np.ndarray, r: float, q: int, k: int, block: int = 100, repeats: int = 3):
    """CPU seconds of the baseline and of serial `tighten_all` on the first k features, block by block.

    Each block of ``block`` features is timed with the baseline (median of ``repeats``) right before the
    engine, so both see the same load on the machine: on a shared machine a core's speed moves by 2× over
    minutes (another process on its hyper-thread), and a ratio of two runs minutes apart moves with it.
    """
    base = engine = 0.0
    for s in range(0, min(k, len(a)), block):
        part = a[s:s + block]
        base += statistics.median(timed(lambda: opening_closing(part, r, q))[0] for _ in range(repeats))
        engine += timed(quiet(lambda: vt.tighten_all(part, r)))[0]
    return base, engine


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
    ap.add_argument("--paired", type=int, default=1000,
                    help="features timed block by block against the baseline (0: none)")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "geo.md")
    args = ap.parse_args(argv)
    r = args.r
    a = footprints(args.n)
    nv = shapely.get_num_coordinates(a)
    q = quad_segs_for(r, 1e-5 * r)

    base, base_default, serial, spread = [], [], [], []
    load = [os.getloadavg()[0]]
    for k in range(max(args.repeats, args.engine_repeats)):
        if k < args.repeats:
            base.append(timed(lambda: opening_closing(a, r, q))[0])
            base_default.append(timed(lambda: opening_closing(a, r, 8))[0])
        if k < args.engine_repeats:
            run, out = timed_serial(quiet(lambda: vt.tighten_all(a, r)))
            serial.append(run)
            run, out2 = timed_workers(quiet(lambda: vt.tighten_all(a, r, processes=2)))
            spread.append(run)
            load.append(os.getloadavg()[0])
            assert [shapely.to_wkb(g) for g in out] == [shapely.to_wkb(g) for g in out2]
        print(f"run {k + 1}: baseline {base[-1]:.2f} s" + (
              f", serial {serial[-1]['cpu']:.1f} s cpu {serial[-1]['wall']:.1f} s wall, processes=2 "
              f"{spread[-1]['wall']:.1f} s wall" if k < args.engine_repeats else ""), file=sys.stderr, flush=True)
    m = args.loop
    t_loop, t_all = [], []
    for _ in range(args.repeats):
        t_loop.append(timed(quiet(lambda: [vt.tighten(g, r).geometry for g in a[:m]]))[0])
        t_all.append(timed(quiet(lambda: vt.tighten_all(a[:m], r)))[0])
    t_loop, t_all = statistics.median(t_loop), statistics.median(t_all)
    pb, pe = paired(a, r, q, args.paired) if args.paired else (float('nan'), float('nan'))
    paths = {"fast": 0, "convex": 0, "general": 0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for g in a[:m]:
            paths[vt.tighten(g, r)._cache["_path"]] += 1
    empty = int(sum(g.is_empty for g in out))

    def med(runs, key):
        return statistics.median(key(x) for x in runs)

    b, bd = statistics.median(base), statistics.median(base_default)
    s_cpu, s_wall, s_idle = (med(serial, lambda x: x["cpu"]), med(serial, lambda x: x["wall"]),
                             med(serial, idle_estimate))
    p_cpu, p_wall, p_idle = (med(spread, lambda x: x["cpu"]), med(spread, lambda x: x["wall"]),
                             med(spread, idle_estimate))
    s_wait = med(serial, lambda x: x["wait"][0])
    p_wait = [statistics.median(x["wait"][k] for x in spread if len(x["wait"]) > k)
              for k in range(min(len(x["wait"]) for x in spread))]
    try:
        autogroup = Path("/proc/sys/kernel/sched_autogroup_enabled").read_text().strip() == "1"
    except OSError:
        autogroup = None
    n = args.n
    waits = ", ".join(f"{w:.1f}" for w in p_wait) or "n/a"
    lines = [
        "# tighten_all on building footprints vs shapely's vectorised opening + closing",
        "",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores (shared with other work while this ran), "
        f"Python {platform.python_version()}, shapely {shapely.__version__} "
        f"(GEOS {shapely.geos_version_string}). Baseline: CPU seconds, medians of {args.repeats}; engine "
        f"runs: medians of {args.engine_repeats}, serial and processes=2 alternately; 1-minute load average "
        f"{min(load):.1f}–{max(load):.1f} during the runs. Command: `python benchmarks/bench_geo.py --n {n} "
        f"--repeats {args.repeats} --engine-repeats {args.engine_repeats} --loop {m}`.",
        "",
        f"Dataset: {n} footprints (seed 0), {int(nv.sum())} vertices, {int(np.median(nv))} per footprint "
        f"(5–95 %: {int(np.percentile(nv, 5))}–{int(np.percentile(nv, 95))}); r = {r:g} m, tolerance 1e-5·r "
        f"(quad_segs {q} for the baseline). {empty} footprints vanish (no 2r-wide part). Engine path on the "
        f"first {m}: {paths['fast']} fast, {paths['convex']} convex (closed form), {paths['general']} general.",
        "",
        f"| run | CPU (s) | wall (s) | waiting for a core (s) | wall − wait (s) | features/s | ratio to "
        f"opening + closing (quad_segs {q}) |",
        "|---|---:|---:|---:|---:|---:|---:|",
        f"| shapely opening + closing, quad_segs {q} (baseline) | {b:.2f} | | | | {n / b:,.0f} (cpu) | 1 |",
        f"| shapely opening + closing, quad_segs 8 (default) | {bd:.2f} | | | | {n / bd:,.0f} (cpu) | "
        f"{bd / b:.2f} |",
        f"| tighten_all, serial | {s_cpu:.1f} | {s_wall:.1f} | {s_wait:.1f} | {s_idle:.1f} | "
        f"{n / s_cpu:,.0f} (cpu) | {s_cpu / b:.1f} (cpu / cpu) |",
        f"| tighten_all, processes=2 | {p_cpu:.1f} (workers) | {p_wall:.1f} | {waits} (per worker) | "
        f"{p_idle:.1f} | {n / p_idle:,.0f} (wall − wait) | {p_idle / b:.1f} (wall − wait / cpu) |",
        "",
        f"processes=2 against serial: wall clock {s_wall / p_wall:.2f}× as fast as measured; cores used "
        f"(CPU / wall) {s_cpu / s_wall:.2f} serially and {p_cpu / p_wall:.2f} by the two workers; "
        f"{s_idle / p_idle:.2f}× with the time spent waiting for a core taken out (`idle_estimate`: what "
        f"two idle cores would give; an estimate, not a measurement). Kernel autogroup scheduling: "
        f"{ {True: 'on', False: 'off', None: 'unknown'}[autogroup] } (when on, the processes of one session "
        f"share one fair share of the cores, so on a busy machine more processes do not get more CPU). The "
        f"workers' CPU over the serial run's: {p_cpu / s_cpu:.2f}. Identical geometries serially and in "
        f"parallel: yes (checked).",
        "",
        f"Paired ratio (the first {min(args.paired, n)} footprints in blocks of 100, the baseline timed "
        f"right before the engine on each block, so both see the same load): baseline {pb:.2f} s, "
        f"tighten_all {pe:.1f} s, ratio **{pe / pb:.1f}** (CPU / CPU).",
        "",
        f"Wrapper overhead, first {m} footprints: loop of `vt.tighten(g, r).geometry` {t_loop:.2f} s, "
        f"`tighten_all` {t_all:.2f} s ({100 * (t_all / t_loop - 1):+.1f} %).",
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
