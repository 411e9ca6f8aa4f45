"""A minimum-perimeter-polygon finish for the pixel flow (the paper's §4.7 and its reference [25]).

Curvature flow straightens a long, nearly straight tight segment only slowly: its curvature, and so its
speed, goes to zero as it straightens, and a few hundred steps leave it bowed by several pixels. The
finish replaces each boundary loop of the flow's result by the shortest closed curve homotopic to it in
the *pixel mortar*, the union of the fillet's pixel squares less the core's: Sklansky's minimum-perimeter
polygon, a relative convex hull (Klette and Rosenfeld's "Digital geometry", ch. 7). The flow only has to
find the homotopy class, which it does long before it rests; the finish makes the straight stretches
straight and leaves the arcs on the constraint's pixel corners.

The curves are computed with the exact engine's funnel on a constrained triangulation of the mortar
(`vectortighten.geodesic`), then the result is sampled at the pixel centres. ``core ⊆ result ⊆ fillet``
holds exactly: a core pixel's centre is half a pixel inside the curve's obstacle, an anticore pixel's
centre half a pixel outside the curve's domain.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy import ndimage
from shapely.geometry import Polygon

__all__ = ["mpp_finish"]

#: How far the mortar is thickened where core and fillet touch, pixels (room for the curve there).
_THICKEN = 1e-6


def _squares(mask: np.ndarray):
    """Union of the True pixels' unit squares, x = column, y = −row (pixel (i, j) is [j, j+1] × [−i−1, −i]),
    with collinear vertices removed.

    Each row's runs of True pixels become boxes, and the boxes are joined by a coverage union, which
    only dissolves the edges they share (several times faster than a general union on a mask of a
    million pixels). A coverage needs shared edges to have the same vertices, so each box's bottom edge
    also holds the ends of the next row's runs that fall inside it, and its top edge those of the row
    above.
    """
    m = np.asarray(mask, dtype=np.int8)
    if not m.any():
        return Polygon()
    H, W = m.shape
    d = np.diff(np.pad(m, ((0, 0), (1, 1))), axis=1)
    si, sj = np.nonzero(d == 1)             # row-major, so the k-th start and the k-th end pair up
    _, ej = np.nonzero(d == -1)
    # Every run end, keyed by (row, x) and sorted: the ends of row i inside (a, b) are one slice of it.
    stride = np.int64(W + 2)
    row_key = si.astype(np.int64) * stride
    ends = np.sort(np.concatenate([row_key + sj, row_key + ej]))

    def inside(row: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        base = row.astype(np.int64) * stride
        lo = np.searchsorted(ends, base + sj, side="right")
        hi = np.searchsorted(ends, base + ej, side="left")
        return lo, np.where((row >= 0) & (row < H), np.maximum(hi, lo), lo)

    blo, bhi = inside(si + 1)               # on the bottom edge (y = −i − 1): the next row's run ends
    tlo, thi = inside(si - 1)               # on the top edge (y = −i): the previous row's
    nb, nt = bhi - blo, thi - tlo
    # Each ring: bottom-left, the bottom edge's points (x increasing), bottom-right, top-right, the top
    # edge's points (x decreasing), top-left, and bottom-left again to close it.
    count = nb + nt + 5
    box = np.repeat(np.arange(si.size), count)
    k = np.arange(box.size) - np.repeat(np.cumsum(count) - count, count)
    nbk, ntk = nb[box], nt[box]
    x = np.where(k <= nbk, sj[box], ej[box]).astype(float)
    y = np.where((k <= nbk + 1) | (k == nbk + ntk + 4), -si[box] - 1.0, -si[box] * 1.0)
    x[k >= nbk + ntk + 3] = sj[box][k >= nbk + ntk + 3]
    on_b = (k >= 1) & (k <= nbk)
    x[on_b] = ends[blo[box[on_b]] + k[on_b] - 1] - (si[box[on_b]] + 1) * stride
    on_t = (k >= nbk + 3) & (k < nbk + ntk + 3)
    x[on_t] = ends[thi[box[on_t]] - 1 - (k[on_t] - nbk[on_t] - 3)] - (si[box[on_t]] - 1) * stride
    rings = shapely.linearrings(np.column_stack([x, y]), indices=box)
    return shapely.coverage_union_all(shapely.polygons(rings)).simplify(0)


def _part_mask(part, shape) -> np.ndarray:
    """The pixels whose centre lies in a polygon of `_squares`' coordinates."""
    out = np.zeros(shape, dtype=bool)
    x0, y0, x1, y1 = part.bounds
    i0, i1 = max(int(-y1), 0), min(int(np.ceil(-y0)), shape[0])
    j0, j1 = max(int(x0), 0), min(int(np.ceil(x1)), shape[1])
    jj, ii = np.meshgrid(np.arange(j0, j1), np.arange(i0, i1))
    shapely.prepare(part)
    out[i0:i1, j0:j1] = shapely.contains_xy(part, jj + 0.5, -ii - 0.5)
    return out


def _part_pixels(part, labels: np.ndarray) -> np.ndarray:
    """The pixels of one part of `_squares` (a polygon of it): the 4-connected component of the mask
    (labelled ``labels``, by `ndimage.label`'s default 4-adjacency) whose squares make it. Two squares
    that share an edge lie in one part and two that share only a corner do not, so the parts are the
    4-connected components; any interior point of the part lies in a pixel of its component. The same
    as `_part_mask` (the pixels whose centre the part holds), without a point-in-polygon test."""
    x, y = shapely.get_coordinates(shapely.point_on_surface(part))[0]
    i = min(max(int(np.floor(-y)), 0), labels.shape[0] - 1)
    j = min(max(int(np.floor(x)), 0), labels.shape[1] - 1)
    k = labels[i, j]
    if k == 0:                  # not expected (the point lies inside the part); fall back on the test
        return _part_mask(part, labels.shape)
    return labels == k


def _box_of(a: np.ndarray) -> tuple[slice, slice]:
    """The bounding box of a non-empty mask with a one-pixel margin (clipped to the array): a set's
    components and holes are the same within it as in the whole array."""
    rows, cols = np.flatnonzero(a.any(axis=1)), np.flatnonzero(a.any(axis=0))
    return (slice(max(rows[0] - 1, 0), rows[-1] + 2), slice(max(cols[0] - 1, 0), cols[-1] + 2))


def _topology(inside: np.ndarray) -> tuple[int, int]:
    """Components (8-connected) and holes (4-connected) of a pixel set."""
    _, n = ndimage.label(inside, structure=np.ones((3, 3), bool))
    _, m = ndimage.label(np.pad(~inside, 1, constant_values=True))
    return int(n), int(m) - 1


def _only_vanished(before: np.ndarray, after: np.ndarray) -> bool:
    """Whether ``after`` differs from ``before`` by parts of ``before`` that vanished and nothing else
    among its parts: at least one part is gone, no part of ``after`` overlaps two parts of ``before`` or
    none, and no part of ``before`` holds two of ``after`` (a loop that shrinks to nothing in the mortar,
    a thin ring against a hole's anticore; the holes such a part made merge with what surrounds it).
    `mpp_finish` asks it of the set and of its complement, so that a gap that closes is the same event
    as a part that vanishes."""
    eight = np.ones((3, 3), bool)
    lb, nb = ndimage.label(before, structure=eight)
    la, na = ndimage.label(after, structure=eight)
    if na >= nb:
        return False
    if na == 0:
        return True
    pairs = np.unique(np.stack([la[after], lb[after]]), axis=1)
    pairs = pairs[:, pairs[1] > 0]
    per_after = np.bincount(pairs[0], minlength=na + 1)[1:]
    per_before = np.bincount(pairs[1], minlength=nb + 1)[1:]
    return bool((per_after == 1).all() and (per_before <= 1).all())


#: Two shortest loops closer than this (pixels) touch: both run along the same constraint's edge (each
#: within `_THICKEN` of it).
_TOUCH = 1e-4


#: Most times `mpp_finish` wraps a merged set again (each time the set has fewer parts, or as many
#: parts and fewer holes, so the count is bounded anyway; this only caps the work).
_MAX_REWRAPS = 20


def _touch_groups(polys: list) -> int:
    """How many groups the polygons fall into when those closer than `_TOUCH` are joined."""
    tree = shapely.STRtree(polys)
    left, right = tree.query(polys, predicate="dwithin", distance=_TOUCH)
    parent = list(range(len(polys)))

    def find(a: int) -> int:
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in zip(left, right):
        parent[find(int(a))] = find(int(b))
    return len({find(a) for a in range(len(polys))})


def _touching_merges(out: np.ndarray, before: np.ndarray, pieces: list, reps: list) -> bool:
    """Whether ``out`` has fewer parts than ``before`` only where wrapped pieces touch: each part of ``out``
    (8-connected) that holds two or more parts of ``before`` holds pieces that are joined by a chain of
    pieces touching one another (closer than `_TOUCH`), and every part of ``before`` in it is one of
    those pieces' own. ``pieces`` are the finished loops as polygons, ``reps`` a core pixel (row, column) each
    holds (None if it holds none)."""
    eight = np.ones((3, 3), bool)
    la, na = ndimage.label(out, structure=eight)
    lb, nb = ndimage.label(before, structure=eight)
    if na >= nb or not pieces:
        return False
    # Which parts of ``before`` each part of ``out`` holds.
    pairs = np.unique(np.stack([la[before & out], lb[before & out]]), axis=1)
    held = {}
    for a, b in pairs.T:
        if a > 0 and b > 0:
            held.setdefault(int(a), set()).add(int(b))
    # The part of ``out`` each piece lies in.
    piece_of = {}
    for k, rep in enumerate(reps):
        if rep is not None and la[rep] > 0:
            piece_of.setdefault(int(la[rep]), []).append(k)
    tree = shapely.STRtree(pieces)
    left, right = tree.query(pieces, predicate="dwithin", distance=_TOUCH)
    touch = {(int(a), int(b)) for a, b in zip(left, right)}
    for a, parts in held.items():
        if len(parts) < 2:
            continue
        ks = piece_of.get(a, [])
        if len(ks) < len(parts):
            return False                    # a part of ``before`` in it has no loop of its own here
        seen, stack = {ks[0]}, [ks[0]]
        while stack:
            u = stack.pop()
            for v in ks:
                if v not in seen and (u, v) in touch:
                    seen.add(v)
                    stack.append(v)
        if len(seen) != len(ks):
            return False
    return True


def _rings(geom) -> list[tuple[int, np.ndarray, bool]]:
    """(part index, coordinates, is_exterior) for every ring of every polygon part."""
    out = []
    for k, part in enumerate(shapely.get_parts(geom)):
        if part.is_empty:
            continue
        out.append((k, shapely.get_coordinates(part.exterior), True))
        out += [(k, shapely.get_coordinates(h), False) for h in part.interiors]
    return out


def _edge_polygon(inside: np.ndarray, sd: np.ndarray):
    """The region a constraint covers, to sub-pixel accuracy: the zero level of its signed distance
    ``sd`` (negative on ``inside``), linear on the four triangles of each square of pixel centres (so
    that the level of −sd is the same curve and the finish commutes with complementing the image),
    clipped to the pixels' squares (it never reaches past them, so the core's and the anticore's regions
    never overlap, and a region that meets the image's edge meets it along the squares' edge). In
    `_squares`' coordinates."""
    import contourpy

    from .grid import _rings_to_polygons

    if not inside.any():
        return Polygon()
    f = np.where(inside, np.minimum(sd, -1e-3), np.maximum(sd, 1e-3)).clip(-2.0, 2.0)
    f = np.pad(np.pad(f, 1, mode="edge"), 1, constant_values=2.0)
    gen = contourpy.contour_generator(z=f, name="serial", line_type="Separate", quad_as_tri=True)
    rings = []
    for line in gen.lines(0.0):
        if len(line) < 4:
            continue
        ring = np.column_stack([line[:, 0] - 2.0 + 0.5, -(line[:, 1] - 2.0) - 0.5])
        if not np.array_equal(ring[0], ring[-1]):
            ring = np.vstack([ring, ring[:1]])
        rings.append(ring)
    return shapely.intersection(_rings_to_polygons(rings), _squares(inside))


def mpp_finish(mask, core, fillet, *, core_sd=None, anticore_sd=None, return_curves: bool = False,
               _depth: int = 0):
    """Replace each boundary loop of ``mask`` by the shortest loop homotopic to it in the pixel mortar.

    Parameters
    ----------
    mask, core, fillet : (H, W) arrays of bool
        A set between its constraints (``core ⊆ mask ⊆ fillet``), e.g. the flow's result.
    core_sd, anticore_sd : (H, W) arrays of float, optional
        Signed distances to the core's and the anticore's sub-pixel edges, pixels, negative inside each
        (as `raster.tighten` builds them). With them, the loops wrap the constraints' traced edges
        (within their pixels' squares) instead of the whole squares, which stand up to 0.7 px beyond a
        digital arc's lone stair pixels.
    return_curves : bool
        Also return the shortest loops themselves, as polygons in pixel coordinates (x = column,
        y = −row, pixel centres on whole numbers), or None where the result is the input's pixels (a
        part or the whole kept as the flow left it).

    Returns
    -------
    (H, W) ndarray of bool, or (that, curves) with ``return_curves``
        The pixels whose centre lies inside the shortest loops (loops that overlap merge; a loop that can
        shrink to nothing, one around no core, vanishes; parts whose shortest loops touch merge, and so
        do holes whose loops touch, and the merged set is wrapped again, as the level set goes on from
        the merged front). ``core ⊆ result ⊆ fillet`` holds exactly.

    Examples
    --------
    >>> import numpy as np
    >>> core = np.zeros((20, 20), bool); core[4:16, 4:6] = True; core[4:16, 14:16] = True
    >>> fillet = np.zeros((20, 20), bool); fillet[2:18, 2:18] = True
    >>> start = fillet.copy()                                   # a loose loop around both bars
    >>> out = mpp_finish(start, core, fillet)
    >>> bool(out[4:16, 4:16].all()), bool(out[3, 10])           # the taut loop: the bars' convex hull
    (True, False)
    """
    M = np.asarray(mask, dtype=bool)
    R = np.asarray(core, dtype=bool)
    F = np.asarray(fillet, dtype=bool)
    movable = F & ~R
    if not movable.any() or not M.any():
        return ((M | R) & F, None) if return_curves else (M | R) & F
    # Work on the fillet's bounding box, in its own coordinates: the result is then the same, pixel for
    # pixel, however the image around it is cropped or padded (funnel corners and sample points round
    # alike; a loop's edge often passes exactly through a pixel centre).
    rows, cols = np.flatnonzero(F.any(axis=1)), np.flatnonzero(F.any(axis=0))
    # With the constraints' sub-pixel edges, two pixels of anticore around the box: the edge of the
    # anticore beyond the fillet lies inside those pixels' squares, as it does when the box is the image.
    g = 0 if core_sd is None or anticore_sd is None else 2
    box = (slice(max(rows[0] - g, 0), rows[-1] + 1 + g), slice(max(cols[0] - g, 0), cols[-1] + 1 + g))
    if F[box].shape != F.shape:
        out = (M | R) & F
        out[box], curves = mpp_finish(M[box], R[box], F[box],
                                      core_sd=None if core_sd is None else np.asarray(core_sd)[box],
                                      anticore_sd=None if anticore_sd is None else np.asarray(anticore_sd)[box],
                                      return_curves=True)
        if curves is not None:
            curves = shapely.transform(curves, lambda xy: xy + [box[1].start, -box[0].start])
        return (out, curves) if return_curves else out
    from vectortighten.geodesic import ShortestLoops

    if core_sd is None or anticore_sd is None:
        inner = _squares(R)
        outer = _squares(F)
    else:
        inner = _edge_polygon(R, np.asarray(core_sd, dtype=float))
        h, w = F.shape
        outer = shapely.difference(shapely.box(0, -h, w, 0), _edge_polygon(~F, np.asarray(anticore_sd, dtype=float)))
    domain = shapely.difference(outer.buffer(_THICKEN, join_style="mitre", mitre_limit=50.0),
                                inner.buffer(-_THICKEN, join_style="mitre", mitre_limit=50.0)
                                if not inner.is_empty else Polygon())
    shortest = ShortestLoops(domain, probe=8)

    kept_own = False
    merged_holes = False

    def wrap(ring: np.ndarray) -> Polygon | None:
        nonlocal kept_own
        try:
            geo = shortest(ring)
        except RuntimeError:
            kept_own = True
            return Polygon(ring)            # no consistent geodesic: keep the flow's own loop
        if geo is None or len(geo.xy) < 3:
            return None
        return shapely.make_valid(Polygon(geo.xy))

    out = R.copy()
    ii, jj = np.nonzero(movable)
    xs, ys = jj + 0.5, -ii - 0.5
    inside = np.zeros(len(ii), dtype=bool)
    tie = np.zeros(len(ii), dtype=bool)
    pieces, reps = [], []
    # Each part of the set is wrapped and sampled on its own: two loops that come to touch along a line
    # share no pixel centre and stay two parts; loops that overlap share pixels and merge, as the level set
    # merges them.
    parts_lab, _ = ndimage.label(M)             # 4-connected: the parts of the union of M's squares
    for part in shapely.get_parts(_squares(M)):
        shell = wrap(shapely.get_coordinates(part.exterior))
        if shell is None:
            continue
        holes = [w for w in (wrap(shapely.get_coordinates(h)) for h in part.interiors) if w is not None]
        piece = shell.difference(shapely.union_all(holes)) if holes else shell
        if piece.is_empty:
            continue
        x0, y0, x1, y1 = piece.bounds
        near = np.flatnonzero((xs >= x0) & (xs <= x1) & (ys >= y0) & (ys <= y1))
        shapely.prepare(piece)
        got = near[shapely.contains_xy(piece, xs[near], ys[near])]
        # A pixel centre on the curve itself (a straight stretch through centres) keeps the flow's side:
        # the same rule for the set and its complement, so the finish commutes with complementing.
        # (Only a centre left out beside one taken in can be on the curve.)
        taken = np.zeros(M.shape, dtype=bool)
        taken[ii[got], jj[got]] = True
        beside = np.zeros_like(taken)
        beside[1:] |= taken[:-1]
        beside[:-1] |= taken[1:]
        beside[:, 1:] |= taken[:, :-1]
        beside[:, :-1] |= taken[:, 1:]
        cand = near[beside[ii[near], jj[near]] & ~taken[ii[near], jj[near]]]
        on = cand[shapely.dwithin(piece.boundary, shapely.points(xs[cand], ys[cand]), 1e-9)]
        tie[on] = True
        # A guard: the wrapped part must stay one part with no more holes than it had (a funnel that
        # failed on a degenerate sleeve could give a self-touching curve); otherwise keep the flow's own.
        mine = np.zeros(M.shape, dtype=bool)
        mine[ii[got], jj[got]] = True
        own = _part_pixels(part, parts_lab)
        mine |= R & own
        topo = _topology(mine[_box_of(mine)]) if mine.any() else (0, 0)
        groups = _touch_groups(holes) if topo != (1, len(holes)) and len(holes) > 1 else len(holes)
        if topo == (1, groups) and groups < len(holes):
            merged_holes = True                 # hole loops that touch: the wall between them vanishes
        elif topo != (1, len(holes)) and topo[0] != 0:
            own &= movable
            inside |= own[ii, jj]
            kept_own = True
            continue
        inside[got] = True
        pieces.append(piece)
        held = np.argwhere(R & own)             # its core pixels: in the result whatever the loops do
        reps.append(tuple(held[0]) if len(held) else None)
    inside[tie] = M[ii[tie], jj[tie]]
    out[ii, jj] = inside
    out = (out | R) & F
    # The flow found the topology; the finish only straightens. Two changes are the level set's own: a
    # part that vanishes (its loop shrinks to nothing), and parts whose shortest loops touch, which merge
    # (the flow stops once its topology rests, and a front that is still coming may meet another: the
    # concave side of one part straightening onto the core of its neighbour). Then the merged set is
    # wrapped again, as the level set goes on from the merged front. Where the sampled loops only come to
    # touch on pixels (two curves apart, whose samples are diagonally adjacent), keep the flow's result.
    before = (M | R) & F
    if _topology(out) != _topology(before) and not (_only_vanished(before, out) or _only_vanished(~before, ~out)):
        same_parts = _topology(out)[0] == _topology(before)[0]
        if not kept_own and _depth < _MAX_REWRAPS and (merged_holes if same_parts else
                                                        _touching_merges(out, before, pieces, reps)):
            return mpp_finish(out, R, F, core_sd=core_sd, anticore_sd=anticore_sd, return_curves=return_curves,
                              _depth=_depth + 1)
        return (before, None) if return_curves else before
    if not return_curves:
        return out
    if kept_own:
        return out, None
    # The loops, to pixel coordinates; the core's parts that no loop holds are its own (their pixels are
    # in the result whatever the loops do).
    curves = shapely.union_all(pieces) if pieces else Polygon()
    return out, shapely.transform(curves, lambda xy: xy + [-0.5, 0.5])

