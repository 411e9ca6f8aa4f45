"""Speed of the geodesic module (triangulation, sleeve, closed geodesic) on the engine's real inputs.

The inputs are made here, from the shapes of ``bench_tighten.py``: ``vectortighten.tighten(S, r,
tolerance=1e-5·r)`` is run once per shape and size with the engine's calls into ``vectortighten.geodesic``
recorded (the free-space polygon given to ``triangulate`` and every ring given to ``sleeve``). Each
function is then timed on those inputs, the median of ``--repeats`` runs:

* ``triangulate(domain)``;
* ``crossings(T, ring)`` (the walk along the ring), on a fresh triangulation each run, so its one-off
  per-triangulation set-up is included;
* ``sleeve(T, ring)`` (crossings and their cyclic reduction), likewise;
* ``closed_geodesic(T, portals)`` (the funnel).

Times are the process's CPU time by default (``--clock cpu``; steadier than wall time on a shared machine,
and the same on an idle one: all of this runs on one thread), or wall time with ``--clock wall``.

With ``--baseline REV`` the same functions of ``vectortighten/geodesic.py`` at git revision REV are timed
too, alternately with the current ones (the machines are noisy), and their outputs are checked to be
identical (triangles, crossings, portals, geodesic vertices and sides).

Run:  python benchmarks/bench_geodesic.py [--sizes 1000 10000 100000] [--repeats 7] [--baseline REV]
It prints a markdown table and writes it to benchmarks/results/geodesic.md.
"""

from __future__ import annotations

import argparse
import importlib.util
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import shapely

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import vectortighten as vt  # noqa: E402
import vectortighten.engine as engine  # noqa: E402
import vectortighten.geodesic as geodesic  # noqa: E402
from benchmarks.bench_tighten import traced_contour, wavy_star  # noqa: E402

SHAPES = {
    "rough star": (lambda n: wavy_star(n, waves=60, amp=0.02), 1.0),
    "traced contour": (traced_contour, 0.6),
}


def capture(S, r: float) -> list[tuple[object, list[np.ndarray]]]:
    """The domains triangulated and the rings sleeved while tightening S (each domain with its rings)."""
    domains: list = []
    rings: dict[int, list[np.ndarray]] = {}
    which: dict[int, int] = {}
    tri, slv = engine.triangulate, engine.sleeve

    def rec_triangulate(domain):
        T = tri(domain)
        which[id(T)] = len(domains)
        domains.append(domain)
        rings[len(domains) - 1] = []
        return T

    def rec_sleeve(T, ring):
        rings[which[id(T)]].append(np.array(ring, dtype=float))
        return slv(T, ring)

    engine.triangulate, engine.sleeve = rec_triangulate, rec_sleeve
    try:
        vt.tighten(S, r, tolerance=1e-5 * r)
    finally:
        engine.triangulate, engine.sleeve = tri, slv
    return [(domains[i], rings[i]) for i in range(len(domains)) if rings[i]]


def load_revision(rev: str):
    """``vectortighten/geodesic.py`` at a git revision, imported as a stand-alone module."""
    src = subprocess.run(["git", "show", f"{rev}:vectortighten/geodesic.py"], cwd=HERE.parent, check=True,
                         capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "geodesic_baseline.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("geodesic_baseline", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod       # dataclasses look their module up while the class is made
    spec.loader.exec_module(mod)
    return mod


def outputs(G, domain, ring) -> tuple:
    """Everything the engine uses from the module, for an identity check."""
    T = G.triangulate(domain)
    e, lw = G.crossings(T, ring)
    P = G.sleeve(T, ring)
    g = G.closed_geodesic(T, P)
    geo = (None,) if g is None else (g.vertices.tolist(), g.sides.tolist())
    return (T.xy.tobytes(), T.tri.tobytes(), e.tolist(), lw.tolist(), P.tolist()) + geo


def timings(G, domain, ring, clock=time.process_time) -> dict[str, float]:
    """One run of each function (seconds)."""
    out = {}
    t0 = clock()
    T = G.triangulate(domain)
    out["triangulate"] = clock() - t0
    t0 = clock()
    G.crossings(T, ring)
    out["crossings"] = clock() - t0
    T = G.triangulate(domain)
    t0 = clock()
    P = G.sleeve(T, ring)
    out["sleeve"] = clock() - t0
    t0 = clock()
    G.closed_geodesic(T, P)
    out["closed_geodesic"] = clock() - t0
    return out


FUNCTIONS = ("triangulate", "crossings", "sleeve", "closed_geodesic")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10_000, 100_000])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--shapes", nargs="+", default=list(SHAPES))
    parser.add_argument("--baseline", metavar="REV",
                        help="also time vectortighten/geodesic.py at this git revision")
    parser.add_argument("--clock", choices=["cpu", "wall"], default="cpu")
    parser.add_argument("--out", type=Path, default=HERE / "results" / "geodesic.md")
    args = parser.parse_args(argv)
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    base = load_revision(args.baseline) if args.baseline else None
    mods = [("current", geodesic)] + ([(args.baseline, base)] if base else [])
    rows = []
    for name in args.shapes:
        make, r = SHAPES[name]
        for n in args.sizes:
            S = make(n)
            for domain, rings in capture(S, r):
                ring = max(rings, key=len)              # the longest loop given to this domain
                same = None
                if base is not None:
                    same = outputs(geodesic, domain, ring) == outputs(base, domain, ring)
                runs = {label: {f: [] for f in FUNCTIONS} for label, _ in mods}
                for _ in range(args.repeats):           # alternate, so that both see the same machine load
                    for label, G in mods:
                        for f, t in timings(G, domain, ring, clock).items():
                            runs[label][f].append(t)
                T = geodesic.triangulate(domain)
                row = {"shape": name, "n": n, "r": r, "domain": len(T.xy), "triangles": len(T.tri),
                       "ring": len(ring), "portals": len(geodesic.sleeve(T, ring)), "same": same,
                       "t": {label: {f: statistics.median(v) for f, v in d.items()}
                             for label, d in runs.items()}}
                rows.append(row)
                cur = row["t"]["current"]
                msg = "  ".join(f"{f} {1e3 * cur[f]:.1f} ms" for f in FUNCTIONS)
                if base is not None:
                    old = row["t"][args.baseline]
                    msg += "  | baseline " + "  ".join(f"{1e3 * old[f]:.1f}" for f in FUNCTIONS)
                    msg += f"  | identical: {same}"
                print(f"{name:15s} n={n:>7d} domain {row['domain']:>6d} ring {row['ring']:>6d}  {msg}",
                      flush=True)
    head = ["shape", "n", "domain vertices", "triangles", "ring points", "portals"]
    lines = [
        "# Geodesic module speed on the engine's inputs",
        "",
        f"Machine: {platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}, shapely "
        f"{shapely.__version__}. Medians of {args.repeats} runs, {args.clock} time in ms. Command: `python "
        f"benchmarks/bench_geodesic.py --sizes {' '.join(map(str, args.sizes))} --repeats {args.repeats}"
        f" --clock {args.clock}"
        + (f" --baseline {args.baseline}`" if base else "`") + ".",
        "",
    ]
    if base is None:
        lines += ["| " + " | ".join(head + list(FUNCTIONS)) + " |",
                  "|" + "---|" * 2 + "---:|" * (len(head) - 2 + len(FUNCTIONS))]
        for m in rows:
            t = m["t"]["current"]
            lines.append(f"| {m['shape']} | {m['n']} | {m['domain']} | {m['triangles']} | {m['ring']} | "
                         f"{m['portals']} | " + " | ".join(f"{1e3 * t[f]:.1f}" for f in FUNCTIONS) + " |")
    else:
        cols = [f"{f} ({args.baseline} → now)" for f in FUNCTIONS]
        lines += ["| " + " | ".join(head + cols + ["identical"]) + " |",
                  "|" + "---|" * 2 + "---:|" * (len(head) - 2 + len(FUNCTIONS)) + "---|"]
        for m in rows:
            t, o = m["t"]["current"], m["t"][args.baseline]
            cells = [f"{1e3 * o[f]:.1f} → {1e3 * t[f]:.1f} (×{o[f] / t[f]:.1f})" for f in FUNCTIONS]
            lines.append(f"| {m['shape']} | {m['n']} | {m['domain']} | {m['triangles']} | {m['ring']} | "
                         f"{m['portals']} | " + " | ".join(cells) + f" | {m['same']} |")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
