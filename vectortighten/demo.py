"""The embedded example: a shape with every kind of detail a tightening treats, and the demo it drives.

`demo_shape` has sharp convex and reflex corners, a narrow slot, a small hole and a large one, a thin bar to
a second part, a spike and a tiny island; with `DEMO_RADIUS` each of them shows a different behaviour.
"""

from __future__ import annotations

from pathlib import Path

import shapely
from shapely.geometry import Point, Polygon, box

__all__ = ["DEMO_RADIUS", "demo_shape", "run_demo"]

#: The radius the demo uses, in the units of `demo_shape` (which is about 64 × 30).
DEMO_RADIUS = 2.0


def demo_shape() -> Polygon:
    """The demo's input: a body with a slot, two holes and a spike, a bar to a triangle, and an island.

    Examples
    --------
    >>> S = demo_shape()
    >>> S.is_valid, S.geom_type, len(S.geoms)
    (True, 'MultiPolygon', 2)
    """
    body = Polygon([(0, 0), (30, 0), (33, 6), (36, 0), (40, 0), (40, 24), (0, 24), (-6, 14), (0, 12)])
    body = body.difference(box(17.4, 15, 18.6, 25))                     # a slot narrower than 2r
    body = body.difference(Point(9, 16).buffer(1.2, quad_segs=8))       # a hole smaller than r: filled
    body = body.difference(Point(26, 12).buffer(4.5, quad_segs=32))     # a hole larger than r: kept
    bar = box(40, 10.5, 50, 12.0)                                        # thinner than 2r
    tip = Polygon([(50, 3), (62, 11), (50, 21)])
    island = Point(56, 26).buffer(1.6, quad_segs=16)                     # smaller than r: vanishes
    return shapely.orient_polygons(shapely.union_all([body, bar, tip, island]))


def _save(fig, path: Path) -> None:
    """Write a figure to ``path`` through a temporary file in the same folder, then rename it."""
    from .io import atomic_path

    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format=path.suffix.lstrip("."))


def run_demo(outdir, *, r: float = DEMO_RADIUS) -> list[Path]:
    """Run the demo: tighten `demo_shape` and draw it, writing ``demo.svg`` and ``demo.png`` in ``outdir``.

    The picture has six panels: the input; its core, mortar and anticore (the paper's Figure 3); the
    fillet; the tightening from the core (the paper's method); from the input (self-dual); each labelled
    with its perimeter, components and holes.

    Parameters
    ----------
    outdir : str or Path
        Existing folder to write into.
    r : float
        The radius (default `DEMO_RADIUS`).

    Returns
    -------
    list of Path
        The files written.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     [p.name for p in run_demo(d)]
    ['demo.svg', 'demo.png']
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from .engine import tighten
    from .morphology import anticore, core, fillet, mortar
    from .plotting import COLORS, draw_geometry, draw_loops

    outdir = Path(outdir)
    if not outdir.is_dir():
        raise FileNotFoundError(f"output folder {str(outdir)!r} does not exist")
    S = demo_shape()
    R, F, M, A = core(S, r), fillet(S, r), mortar(S, r), anticore(S, r)
    tights = {init: tighten(S, r, init=init) for init in ("core", "input")}
    fig, axes = plt.subplots(2, 3, figsize=(15, 6.5))
    panels = [
        ("input S", [(S, COLORS["input"], None)]),
        (f"core (dark), mortar (grey), anticore (white), r = {r:g}",
         [(A, "white", "0.5"), (M, COLORS["mortar"], None), (R, COLORS["core"], None)]),
        ("fillet F(S) and S", [(F, COLORS["mortar"], None), (S, "none", COLORS["input"])]),
    ]
    for ax, (title, layers) in zip(axes[0], panels):
        for geom, face, edge in layers:
            draw_geometry(ax, geom, facecolor=face, edgecolor=edge or "none", linewidth=0.8)
        ax.set_title(title, fontsize=9)
    for ax, (init, T) in zip(axes[1], tights.items()):
        draw_geometry(ax, M, facecolor=COLORS["mortar"], edgecolor="none")
        draw_geometry(ax, R, facecolor=COLORS["core"], edgecolor="none", alpha=0.8)
        draw_loops(ax, T.loops, tolerance=T.tolerance, linewidth=1.6)
        ax.set_title(f"tightening, init={init!r}: perimeter {T.perimeter:.2f}, "
                     f"{T.n_components} parts, {T.n_holes} hole(s)", fontsize=9)
    ax = axes[1, 2]
    draw_geometry(ax, S, facecolor="none", edgecolor=COLORS["input"], linewidth=0.8, linestyle="--")
    draw_loops(ax, tights["core"].loops, tolerance=r / 100, linewidth=1.6)
    ax.set_title(f"input {S.length:.2f} long → tightened {tights['core'].perimeter:.2f}", fontsize=9)
    x0, y0, x1, y1 = S.bounds
    for ax in axes.flat:
        ax.set_aspect("equal")
        ax.set_xlim(x0 - 2 * r, x1 + 2 * r)
        ax.set_ylim(y0 - 2 * r, y1 + 2 * r)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle("vectortighten demo: exact r-tightening (segments and arcs of radius r)", fontsize=11)
    written = []
    for name in ("demo.svg", "demo.png"):
        path = outdir / name
        _save(fig, path)
        written.append(path)
    plt.close(fig)
    return written
