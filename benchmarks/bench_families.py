"""The general engine against shapely's opening + closing, family by family, 1k to 1M vertices (issue 20).

Families (each at about n vertices; r in the shape's units):

* ``harmonic star``: a star of radius 30 with a smooth 5-fold wave of amplitude 3 and ripples of
  amplitudes 3r, r, 0.5r and 0.1r (harmonics 23, 41, 97 and 211): ripples comparable to r, so the whole
  boundary is in the mortar and the general engine does the work; r = 1;
* ``jagged star``: a star of radius 10 with independent radial noise (standard deviation 0.05) at every
  vertex; r = 0.5;
* ``traced outline``: the pixel-staircase outline of a noisy blob (`tests.strategies.pixel_outline`, a
  segmentation mask's traced boundary); r = 0.6;
* ``coastline``: the traced land of matplotlib's ``topobathy.npz`` (`bench_tighten.coastline`, islands,
  fjords and channels); r = 1.5 cells;
* ``many parts``: a MultiPolygon of building footprints (`bench_geo.footprint`, about 30 vertices each;
  n/30 of them, 33 000 at a million vertices); r = 1 m.

``MORE_FAMILIES`` (by name with ``--families``, not in the default table) are shapes nothing was tuned on:
a star with ripples of 2r and 0.15r (the issue's own example), a comb of teeth thinner than 2r, a spiral
strip thinner than 2r, a union of random disks.

Each measurement runs in its own process (so that its peak memory is its own): the shape is built, then
the baseline (``S.buffer(-r).buffer(r)`` and ``S.buffer(r).buffer(-r)`` at shapely's default quad_segs,
8, and again at the tolerance 1e-5·r, quad_segs 176) and ``vectortighten.tighten(S, r)`` are timed
alternately, CPU time, medians of ``--repeats`` (1 from 100k vertices on), then ``T.verify()`` once. The
ratio is tighten over the opening + closing at shapely's default. Peak memory is the process's peak
resident set during the tightening, over what it held before. A size is skipped when the previous size
of the family took longer than ``--budget`` seconds (tighten or baseline), the growth making the next one
impractical here.

Run:  python benchmarks/bench_families.py [--families ...] [--sizes 1000 10000 100000 1000000]
It writes benchmarks/results/families.md and a log-log plot benchmarks/results/families.png.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import re
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))


def harmonic_star(n: int, r: float = 1.0) -> Polygon:
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = (30 + 3 * np.sin(5 * t) + 3 * r * np.sin(23 * t) + r * np.sin(41 * t + 1)
           + 0.5 * r * np.sin(97 * t + 2) + 0.1 * r * np.sin(211 * t + 3))
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


def jagged_star(n: int, seed: int = 3) -> Polygon:
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 10 * (1 + 0.04 * np.sin(12 * t)) + rng.normal(0, 0.05, n)
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


def traced_outline(n: int) -> Polygon:
    from tests.strategies import pixel_outline

    return pixel_outline(n, 7)


def coastline(n: int):
    from bench_tighten import coastline as make

    return make(n)


def many_parts(n: int) -> MultiPolygon:
    from bench_geo import footprints

    parts = footprints(max(1, round(n / 30)), seed=1)
    return MultiPolygon([p for p in parts])


def two_harmonic_star(n: int, r: float = 1.0) -> Polygon:
    """The issue's own example: ripples of 2r and 0.15r (harmonics 31 and 173) on a smooth wave."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 30 + 3 * np.sin(5 * t) + 2 * r * np.sin(31 * t + 31) + 0.15 * r * np.sin(173 * t + 173)
    return Polygon(np.column_stack([rad * np.cos(t), rad * np.sin(t)]))


def comb(n: int, r: float = 1.0) -> Polygon:
    """n/8 teeth 1.5r wide and 1.5r apart (narrower than 2r: they vanish) on a back 3.5r wide."""
    w = 1.5 * r
    pts = []
    for i in range(max(2, n // 8)):
        x = 2 * i * w
        pts += [(x, 0.0), (x, 10 * r), (x + w, 10 * r), (x + w, 0.5 * r)]
    end = 2 * max(2, n // 8) * w
    return Polygon(pts + [(end, 0.5 * r), (end, -3 * r), (0.0, -3 * r)])


def spiral_strip(n: int, r: float = 1.0) -> Polygon:
    """A strip 1.6r wide wound three times (thinner than 2r: its tightening is empty)."""
    t = np.linspace(0, 6 * np.pi, n // 2)
    a = 2 + 1.2 * t
    outer = np.column_stack([(a + 1.6 * r) * np.cos(t), (a + 1.6 * r) * np.sin(t)])
    inner = np.column_stack([a * np.cos(t), a * np.sin(t)])
    return Polygon(np.vstack([outer, inner[::-1]]))


def disk_union(n: int, r: float = 1.0, seed: int = 1):
    """The union of n/64 random disks of radius 0.5r to 3r in a 40 × 40 square (necks, pockets, islands)."""
    rng = np.random.default_rng(seed)
    disks = [shapely.Point(rng.uniform(0, 40, 2)).buffer(rng.uniform(0.5, 3) * r, quad_segs=16)
             for _ in range(max(1, n // 64))]
    return shapely.union_all(disks)


FAMILIES = {
    "harmonic star": (harmonic_star, 1.0),
    "jagged star": (jagged_star, 0.5),
    "traced outline": (traced_outline, 0.6),
    "coastline": (coastline, 1.5),
    "many parts": (many_parts, 1.0),
}

#: Shapes that no optimisation was tuned on (added as a check on "a star unlike the benchmark's"): run them
#: with ``--families`` or `ab_families`; not in the default table.
MORE_FAMILIES = {
    "two-harmonic star": (two_harmonic_star, 1.0),
    "comb": (comb, 1.0),
    "spiral strip": (spiral_strip, 1.0),
    "disk union": (disk_union, 1.0),
}
ALL_FAMILIES = {**FAMILIES, **MORE_FAMILIES}


def _rss_kib() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def measure_one(family: str, n: int, repeats: int) -> dict:
    """One family at one size, in this process (run by `main` in a child process)."""
    import vectortighten as vt
    from vectortighten._validation import quad_segs_for

    make, r = ALL_FAMILIES[family]
    S = make(n)
    tol = 1e-5 * r
    q = quad_segs_for(r, tol)
    clock = time.process_time

    def opening_closing(qs):
        shapely.buffer(shapely.buffer(S, -r, quad_segs=qs), r, quad_segs=qs)
        shapely.buffer(shapely.buffer(S, r, quad_segs=qs), -r, quad_segs=qs)

    def timed(fn):
        t0 = clock()
        out = fn()
        return clock() - t0, out

    base8, base_tol, mine = [], [], []
    rss0 = _rss_kib()
    T = None
    for _ in range(repeats):
        base8.append(timed(lambda: opening_closing(8))[0])
        base_tol.append(timed(lambda: opening_closing(q))[0])
        dt, T = timed(lambda: vt.tighten(S, r, tolerance=tol))
        mine.append(dt)
    peak = max(0, _rss_kib() - rss0) / 1024.0
    tv, problems = timed(T.verify)
    return {
        "family": family, "r": r,
        "vertices": len(shapely.get_coordinates(S)) - len(shapely.get_rings(S)),
        "parts": int(shapely.get_num_geometries(S)),
        "base8": statistics.median(base8), "base_tol": statistics.median(base_tol),
        "tighten": statistics.median(mine), "verify": tv, "verified": not problems,
        "path": T._cache.get("_path", "?"), "pieces": sum(len(L) for L in T.loops), "peak_mib": peak,
    }


def profile_one(family: str, n: int, top: int = 25) -> str:
    """cProfile of one ``tighten`` of a family at one size: the heaviest entries, cumulative and own time."""
    import cProfile
    import io
    import pstats

    import vectortighten as vt

    make, r = ALL_FAMILIES[family]
    S = make(n)
    pr = cProfile.Profile(time.process_time)     # CPU time: the machine is shared
    pr.enable()
    vt.tighten(S, r, tolerance=1e-5 * r)
    pr.disable()
    out = io.StringIO()
    st = pstats.Stats(pr, stream=out)
    st.sort_stats("cumulative").print_stats(top)
    st.sort_stats("tottime").print_stats(12)
    text = out.getvalue().replace(str(HERE.parent) + "/", "")
    return "\n".join(ln for ln in text.splitlines() if ln.strip())


def _child(family: str, n: int, repeats: int, timeout: float) -> dict:
    cmd = [sys.executable, __file__, "--child", family, str(n), str(repeats)]
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, check=False)
    except subprocess.TimeoutExpired:
        return {"family": family, "vertices": n, "error": f"over {timeout:.0f} s"}
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith("{")]
    if out.returncode != 0 or not lines:
        tail = (out.stderr.strip().splitlines() or ["no output"])[-1]
        return {"family": family, "vertices": n, "error": tail}
    return json.loads(lines[-1])


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fams = list(dict.fromkeys(m["family"] for m in rows))
    fig, ax = plt.subplots(figsize=(7, 5))
    for i, fam in enumerate(fams):
        sub = [m for m in rows if m["family"] == fam and "error" not in m]
        if not sub:
            continue
        x = [m["vertices"] for m in sub]
        colour = f"C{i}"
        ax.plot(x, [m["tighten"] for m in sub], "o-", color=colour, label=f"{fam}: tighten")
        ax.plot(x, [m["base8"] for m in sub], "s--", color=colour, alpha=0.6,
                label=f"{fam}: opening + closing")
    xs = np.array([1e3, 1e6])
    ax.plot(xs, 1e-3 * xs / 1e3 * np.log(xs) / np.log(1e3), ":", color="grey", label="n log n")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("vertices")
    ax.set_ylabel("CPU seconds")
    ax.set_title("vectortighten.tighten vs shapely opening + closing (quad_segs 8)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "--child":
        print(json.dumps(measure_one(argv[1], int(argv[2]), int(argv[3]))), flush=True)
        return 0
    if argv and argv[0] == "--from-logs":
        # --from-logs OUT.md LOG...: the report of runs split across processes, from their progress lines
        write_report(rows_from_logs(argv[2:]), Path(argv[1]), command="several runs, see below", repeats=3)
        return 0
    if argv and argv[0] == "--profile":
        # --profile N FAMILY...: one profiled run of each family at N vertices, to families_profiles_N.md
        n, fams = int(argv[1]), argv[2:] or list(FAMILIES)
        path = HERE / "results" / f"families_profiles_{n}.md"
        parts = [f"# Where the time goes: cProfile of one `tighten` per family at ~{n} vertices", "",
                 f"Command: `python benchmarks/bench_families.py --profile {n} "
                 f"{' '.join(repr(f) for f in fams)}` (CPU time; profiling inflates it, the ratios between "
                 "entries are what to read).", ""]
        for fam in fams:
            parts += [f"## {fam}", "", "```", profile_one(fam, n), "```", ""]
            print(f"profiled {fam}", flush=True)
        path.write_text("\n".join(parts) + "\n")
        return 0
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(ALL_FAMILIES))
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000, 1_000_000])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--budget", type=float, default=60.0,
                        help="skip the next size of a family after one that took longer (s)")
    parser.add_argument("--timeout", type=float, default=1800.0)
    parser.add_argument("--out", type=Path, default=HERE / "results" / "families.md")
    args = parser.parse_args(argv)
    rows = []
    for fam in args.families:
        skip = False
        for n in args.sizes:
            if skip:
                rows.append({"family": fam, "vertices": n, "error": "skipped (previous size over budget)"})
                continue
            m = _child(fam, n, args.repeats if n < 100_000 else 1, args.timeout)
            rows.append(m)
            if "error" in m:
                print(f"{fam:15s} n={n:>8d} {m['error']}", flush=True)
                skip = True
                continue
            m["ratio"] = m["tighten"] / m["base8"]
            m["ratio_tol"] = m["tighten"] / m["base_tol"]
            print(f"{fam:15s} n={m['vertices']:>8d} base8 {m['base8']:.3f}s base_tol {m['base_tol']:.3f}s "
                  f"tighten {m['tighten']:.3f}s ratio {m['ratio']:.1f} ({m['path']}, verified "
                  f"{m['verified']}, verify {m['verify']:.2f}s, peak {m['peak_mib']:.0f} MiB)", flush=True)
            skip = max(m["tighten"], m["base8"], m["base_tol"]) > args.budget
    write_report(rows, args.out, command=(
        f"`python benchmarks/bench_families.py --families {' '.join(repr(f) for f in args.families)} "
        f"--sizes {' '.join(map(str, args.sizes))} --repeats {args.repeats} --budget {args.budget:g}`"),
        repeats=args.repeats)
    return 0


_LINE = re.compile(r"^(?P<family>.+?)\s+n=\s*(?P<vertices>\d+) (?:base8 (?P<base8>[\d.]+)s base_tol "
                   r"(?P<base_tol>[\d.]+)s tighten (?P<tighten>[\d.]+)s ratio [\d.]+ \((?P<path>\w+), "
                   r"verified "
                   r"(?P<verified>\w+), verify (?P<verify>[\d.]+)s, peak (?P<peak>\d+) MiB\)|(?P<error>.+))$")


_PARTS = {"harmonic star": 1, "jagged star": 1, "traced outline": 1}


def rows_from_logs(paths) -> list[dict]:
    """The rows of earlier runs, from the progress lines they printed (runs split across processes)."""
    rows = []
    for path in paths:
        for ln in Path(path).read_text().splitlines():
            m = _LINE.match(ln.strip())
            if not m or m["family"] not in ALL_FAMILIES:
                continue
            row = {"family": m["family"], "vertices": int(m["vertices"])}
            if m["error"]:
                row["error"] = m["error"]
            else:
                row.update(r=ALL_FAMILIES[m["family"]][1], parts=_PARTS.get(m["family"], "–"),
                           base8=float(m["base8"]),
                           base_tol=float(m["base_tol"]), tighten=float(m["tighten"]), path=m["path"],
                           verified=m["verified"] == "True", verify=float(m["verify"]),
                           peak_mib=float(m["peak"]))
                row["ratio"] = row["tighten"] / row["base8"]
                row["ratio_tol"] = row["tighten"] / row["base_tol"]
            rows.append(row)
    order = list(ALL_FAMILIES)
    return sorted(rows, key=lambda m: (order.index(m["family"]), m["vertices"]))


def write_report(rows: list[dict], out: Path, command: str, repeats: int) -> None:
    """The markdown table, the growth exponents and the log-log plot of ``rows``."""
    families = list(dict.fromkeys(m["family"] for m in rows))
    lines = [
        "# The general engine by family (issue 20)",
        "",
        f"Machine: {platform.machine()}, 2 cores shared with other work, Python {platform.python_version()}, "
        f"shapely {shapely.__version__} (GEOS {'.'.join(map(str, shapely.geos_version))}). CPU seconds, "
        f"medians of {repeats} alternating runs below 100k vertices, 1 from there on. Command: {command}.",
        "",
        "*opening + closing*: `S.buffer(-r).buffer(r)` and `S.buffer(r).buffer(-r)` at shapely's default "
        "quad_segs (8), and at the engine's tolerance 1e-5·r (quad_segs 176); *ratio*: tighten over the "
        "first; *verified*: `T.verify()` found nothing (its own time beside it); *peak*: the peak resident "
        "memory of the measuring process during the runs, over what it held once the shape was built "
        "(0: no more than building the shape took).",
        "",
        "| family | vertices | parts | r | opening + closing, default (s) | at 1e-5·r (s) | tighten (s) "
        "| ratio | ratio at 1e-5·r | path | verified | verify (s) | peak (MiB) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---:|---:|",
    ]
    for m in rows:
        if "error" in m:
            lines.append(f"| {m['family']} | ~{m['vertices']} | | | | | {m['error']} | | | | | | |")
            continue
        lines.append(
            f"| {m['family']} | {m['vertices']} | {m['parts']} | {m['r']:g} | {m['base8']:.3f} "
            f"| {m['base_tol']:.3f} | {m['tighten']:.3f} | {m['ratio']:.1f} | {m['ratio_tol']:.1f} "
            f"| {m['path']} | {'yes' if m['verified'] else 'no'} | {m['verify']:.2f} | {m['peak_mib']:.0f} |")
    lines += ["", "Growth of the tightening's time (exponent of n between consecutive sizes):", ""]
    for fam in families:
        sub = [m for m in rows if m["family"] == fam and "error" not in m]
        exps = [math.log(b["tighten"] / a["tighten"]) / math.log(b["vertices"] / a["vertices"])
                for a, b in zip(sub, sub[1:], strict=False)]
        lines.append(f"- {fam}: " + (", ".join(f"{e:.2f}" for e in exps) or "–"))
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    (out.with_suffix(".json")).write_text(json.dumps(rows, indent=1))
    plot(rows, out.with_suffix(".png"))
    print("\n".join(lines))




if __name__ == "__main__":
    sys.exit(main())
