"""A picture of a tightening (PNG, through matplotlib)."""

from __future__ import annotations

from ._common import _bounds

__all__ = ["write_picture"]


def write_picture(result, f, layers) -> None:
    """Draw ``result`` (and ``layers``) into the open binary file ``f`` as a PNG."""
    from vectortighten import plotting

    x0, y0, x1, y1 = _bounds(result, layers)
    w, h = max(x1 - x0, 1e-300), max(y1 - y0, 1e-300)
    aspect = min(4.0, max(0.25, w / h))
    fig, ax = plotting.new_axes(figsize=(6.0 * min(1.0, aspect), 6.0 * min(1.0, 1.0 / aspect)))
    try:
        if "mortar" in layers:
            plotting.draw_geometry(ax, result.mortar, facecolor=plotting.COLORS["mortar"], edgecolor="none")
        if "core" in layers:
            plotting.draw_geometry(ax, result.core, facecolor=plotting.COLORS["core"], edgecolor="none",
                                   alpha=0.85)
        plotting.draw_geometry(ax, result.geometry, facecolor=plotting.COLORS["tight"],
                               edgecolor=plotting.COLORS["tight"], alpha=0.6 if layers else 1.0,
                               linewidth=1.0)
        if "input" in layers:
            plotting.draw_geometry(ax, result.shape, edgecolor=plotting.COLORS["input"], linewidth=0.8,
                                   linestyle="--")
        m = 0.05 * max(w, h)
        ax.set_xlim(x0 - m, x1 + m)
        ax.set_ylim(y0 - m, y1 + m)
        fig.savefig(f, format="png", dpi=150)
    finally:
        # plotting.new_axes opened the figure through pyplot; close it there (imported lazily, as plotting
        # and the demo do).
        import matplotlib.pyplot as plt  # noqa: TID251

        plt.close(fig)
