"""A radius 0 on one side of a two-radii tightening, for the general engine.

With ``r = (0, b)`` the core is S itself: the "disks" of side +1 are S's convex vertices (points: the loop
turns there with a corner) and the loop may not enter S's interior. With ``(a, 0)`` the fillet is S: the
disks of side −1 are S's reflex vertices and the loop may not leave S. Call Z the region the loop must stay
out of the interior of: S for side +1, the closure of S's complement for side −1.

The engine's tests for a positive radius are distances (a piece nearer than r to a centre or to a piece
of the shrink); at radius 0 they never fire. Here instead:

* `zero_offsets` is the "shrink by 0": S's own edges as its straight pieces, no arcs, and Z's convex
  vertices as its corners (the centres of that side);
* `zero_entries` tells, for straight loop pieces, whether each enters Z's interior (an exact predicate,
  GEOS's DE-9IM relation of the segment with S), how deep (the farthest vertex of Z beyond the segment on
  the boundary chain the segment cuts off, a vertex of Z that is convex for Z), and which centre that is:
  the corner the loop must turn about instead. Arcs of the other side never enter Z (their disks lie in
  the closed complement of Z), so only segments are tested.
"""

from __future__ import annotations

import numpy as np
import shapely

from .centers import boundary_edges

__all__ = ["zero_offsets", "zero_corner_vertices", "zero_entries"]


def zero_corner_vertices(S, side: int) -> np.ndarray:
    """Indices (as `centers.boundary_edges` numbers them: vertex i starts edge i) of S's vertices that are
    corners of Z: left turns for side +1 (convex vertices of S), right turns for side −1 (reflex ones).
    S must be oriented (exteriors counter-clockwise, holes clockwise)."""
    a, b, nxt = boundary_edges(S)
    if len(a) == 0:
        return np.zeros(0, dtype=np.int64)
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    u = b[prv] - a[prv]                  # the edge arriving at vertex i
    v = b - a                            # the edge leaving it
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return np.flatnonzero(cross * side > 0)


def zero_offsets(S, side: int, precision: float):
    """`offsets.OffsetPieces` for a radius 0: S's edges, no arcs, Z's corners (see the module notes).

    Examples
    --------
    >>> from shapely.geometry import Polygon
    >>> L = Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    >>> zero_offsets(L, 1, 0.0).corners.tolist()          # five convex vertices
    [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 2.0], [0.0, 2.0]]
    >>> zero_offsets(L, -1, 0.0).corners.tolist()         # one reflex vertex
    [[1.0, 1.0]]
    """
    from .morphology import _orient
    from .offsets import OffsetPieces

    S = _orient(S)
    a, b, _ = boundary_edges(S)
    keep = np.any(a != b, axis=1)
    corners = a[zero_corner_vertices(S, side)]
    return OffsetPieces(side=side, r=0.0, seg=np.stack([a[keep], b[keep]], axis=1).reshape(-1, 2, 2),
                        seg_edge=np.flatnonzero(keep), arc_center=np.zeros((0, 2)), arc_start=np.zeros(0),
                        arc_sweep=np.zeros(0), corners=corners.reshape(-1, 2), precision=precision)


def _crossings(p, q, a, b):
    """Where segment pq properly crosses edge ab: (t along pq, +1 into S / −1 out of S), or None.

    S lies on the left of its edges. Touching at an end of either segment is not a crossing (those are
    the vertices the loop passes through, or the segment's own ends).
    """
    u, e = q - p, b - a
    den = e[0] * u[1] - e[1] * u[0]           # cross(e, u): > 0 when pq goes from e's right to its left
    if den == 0.0:
        return None
    w = a - p
    t = (w[0] * e[1] - w[1] * e[0]) / (u[0] * e[1] - u[1] * e[0])
    s = (w[0] * u[1] - w[1] * u[0]) / (u[0] * e[1] - u[1] * e[0])
    if not (0.0 < t < 1.0 and 0.0 < s < 1.0):
        return None
    return t, (1 if den > 0 else -1)


def zero_entries(ctx, P: np.ndarray, Q: np.ndarray, z: int, pattern=None):
    """For straight loop pieces ``P[i] → Q[i]``, the entries into Z's interior (``z`` its side).

    Returns a list of ``(i, centre, depth)``: the piece, the corner of Z the loop must turn about instead
    (a centre index of the context, side z; −1 if no centre stands there) and how far beyond the piece
    that corner lies. A piece that touches Z only along its boundary is not an entry. The relation of each
    piece with S is GEOS's exact DE-9IM predicate; depths are measured from the piece's line.
    """
    out = []
    if len(P) == 0:
        return out
    lines = shapely.linestrings(np.stack([P, Q], axis=1))
    # The piece's interior meets S's interior (side +1) or its exterior (side −1).
    pat = "T********" if z > 0 else "**T******"
    hit = np.flatnonzero(shapely.relate_pattern(lines, ctx.S, pat))
    if len(hit) == 0:
        return out
    a, b, nxt, index = ctx._s_index()
    vc = ctx.zero_vertex_centre
    si, ei = index.near_segments(P[hit], Q[hit], 0.0)
    for k, i in enumerate(hit.tolist()):
        p, q = P[i], Q[i]
        u = q - p
        L2 = float(u @ u)
        if L2 == 0.0:
            continue
        # Crossings of the piece with S's edges, in order along it; where it goes into Z and out again.
        cr = []
        for e in ei[si == k].tolist():
            x = _crossings(p, q, a[e], b[e])
            if x is not None:
                cr.append((x[0], x[1] * z, e))           # +1: into Z
        cr.sort()
        # The chains of Z's boundary the piece cuts off: from the edge it enters Z by to the one it leaves
        # by, forward along S's rings; a piece starting (ending) inside Z starts (ends) at the vertex or
        # edge its end lies on.
        spans = []
        start = None if not cr or cr[0][1] > 0 else _end_edge(ctx, p, first=True)
        for _, into, e in cr:
            if into > 0:
                start = nxt[e]
            elif start is not None:
                spans.append((start, e))
                start = None
        if start is not None:
            spans.append((start, _end_edge(ctx, q, first=False)))
        if not spans:
            spans.append((_end_edge(ctx, p, first=True), _end_edge(ctx, q, first=False)))
        best, best_depth = -1, 0.0
        for first, last in spans:
            if first is None or last is None or first == nxt[last]:
                continue                         # no vertex between (in and out through one edge: rounding)
            j, steps = int(first), 0
            chain = []
            while steps <= len(a):
                chain.append(j)
                if j == last:
                    break
                j, steps = int(nxt[j]), steps + 1
            if j != last:
                continue                         # the ends lie on different rings: not a cut-off chain
            chain = np.array(chain, dtype=np.int64)
            # Beyond the piece: on its right for side +1 (Z must stay on the left), on its left for −1.
            # The farthest from its line is a vertex of the convex hull of the piece and the chain it cuts
            # off, a corner the loop must turn about (it may lie beyond the piece's ends: a leaning spike).
            w = a[chain] - p
            depth = -z * (u[0] * w[:, 1] - u[1] * w[:, 0]) / np.sqrt(L2)
            ok = vc[chain] >= 0
            if ok.any():
                k_best = int(np.argmax(np.where(ok, depth, -np.inf)))
                if depth[k_best] > best_depth:
                    best, best_depth = int(vc[chain[k_best]]), float(depth[k_best])
        out.append((i, best, best_depth))
    return out


def _end_edge(ctx, x, first: bool):
    """The vertex (edge start) a chain begins at after the piece's start ``x`` (``first``), or ends at
    before its end: the vertex itself is the piece's own disk, so the chain begins at the next one and ends
    at the one before; on an edge's interior, at that edge's end (its start)."""
    a, b, nxt, index = ctx._s_index()
    j = ctx.zero_vertex_at(x)
    if j >= 0:
        if first:
            return int(nxt[j])
        prv = np.flatnonzero(nxt == j)
        return int(prv[0]) if len(prv) else None
    e, _ = index.nearest(x[None, :])
    e = int(e[0])
    return int(nxt[e]) if first else e
