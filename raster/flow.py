"""The paper's r-tightening on pixels: constrained level-set curvature flow in the mortar (its §3).

Φ is negative inside the evolving set and positive outside; the set is {Φ < 0}. The flow moves each
level curve along its normal with speed equal to its curvature κ = ∇·(∇Φ/|∇Φ|), which shortens the
curve: ``Φ_t = κ |∇Φ|`` (with this sign convention; the paper writes ``Φ_t = −F|∇Φ|`` for the same
motion with the opposite sign of Φ). The speed is zero in the core and the anticore, so they stay inside
and outside. The steps follow the paper:

* Φ starts as the signed distance to the boundary of the initial set (the core, the input, or Mason(M)),
  from exact Euclidean distance transforms, ±½ pixel so that no pixel sits on the front; in the core and
  the anticore, where it never changes, it is the signed distance to their own edges;
* κ|∇Φ| from two passes of central differences: the unit normal field, then its divergence;
* Δt ∝ 1 / max |κ| so that the front crosses at most one pixel a step (and at most the explicit scheme's
  stability bound, ¼ pixel² per unit time);
* updates only in a narrow band (chessboard distance 3 around the sign changes), rebuilt when the front
  reaches the band's edge;
* multiscale: the constraints are sampled every 2^k pixels for k = L−1, …, 0 where the coarsest pixel
  is still a little smaller than r/2 (the paper's five levels at r = 40 and six at r = 75); the flow
  runs at the coarsest level, Φ is doubled in resolution by linear interpolation and flows again
  (each finer level reaches the coarse result from its own initial set by simple pixels, without
  pressing two fronts a pixel apart, and keeps its own Φ where that changed nothing; `_homotopic`,
  `_reinitialise`);
* at most ``iterations`` steps a level, and an early stop when the front rests: no pixel changes sign
  for `STOP_WINDOW` (50) steps and over those steps Φ near the front changes, net, by less than
  ``stop`` pixels a step.

Everything is symmetric under Φ → −Φ, so with ``init="input"`` the flow commutes with complementing the
image, pixel for pixel.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from ._checks import check_mask, check_radius
from .morphology import _core_fillet_both, _edt, _edt_squared, mason, vanishes
from .mpp import mpp_finish

__all__ = ["MAX_SUPERSAMPLED_PIXELS", "NotConvergedWarning", "RasterTightening", "SupersampleWarning",
           "default_levels", "signed_distance", "tighten"]

INITS = ("core", "input", "mason")
FINISHES = ("mpp", "none")
_EPS = 1e-12
#: Steps over which a level's rest is judged (see `tighten`'s ``stop``).
STOP_WINDOW = 50
#: The least step cap a level gets when `tighten` runs until rest.
MIN_CAP = 2000
#: Steps of cap per pixel of a level's height + width, when that is more than `MIN_CAP`.
CAP_PER_PIXEL = 4


class NotConvergedWarning(UserWarning):
    """A level of the flow ran out of steps before its front rested."""


class SupersampleWarning(UserWarning):
    """Supersampled morphology was asked for on a mask larger than `MAX_SUPERSAMPLED_PIXELS`; plain
    morphology on the flow's own grid was used instead."""


#: Largest fine mask (pixels) on which `tighten` computes supersampled morphology: its distance
#: transforms and signed distances peak at about 70 bytes a fine pixel (measured with tracemalloc on a
#: 1500 × 1500 mask, padding included), so this is about 3.5 GB. Above it, `tighten` samples the mask at
#: the blocks' centres and runs plain morphology there, with a `SupersampleWarning`.
MAX_SUPERSAMPLED_PIXELS = 50_000_000


@dataclass
class RasterTightening:
    """The result of `tighten`.

    Attributes
    ----------
    mask : (H, W) ndarray of bool
        The tightening: True inside.
    phi : (H, W) ndarray of float32
        The final level-set function (negative inside), in pixels near the front.
    core, fillet : (H, W) ndarray of bool
        The constraints: ``core ⊆ mask ⊆ fillet``.
    r : float
        The radius, pixels.
    init : str
        The initial condition.
    levels : int
        Resolution levels used (1 = single scale).
    iterations : list of int
        Steps run at each level, coarsest first.
    timings : dict of str to float
        Seconds per phase: ``"morphology"``, ``"init"``, ``"flow level k"`` (k = 0 is full resolution),
        and ``"total"``.
    converged : list of bool
        Whether the front rested at each level, coarsest first (False: the step cap or the budget ran
        out first; `tighten` then warns with `NotConvergedWarning`).
    budget : str
        The step budget the flow ran with: ``"until rest"`` (the default), or the paper's 100 steps a
        level, or another fixed number.
    finish : str
        The final step applied after the flow (``"mpp"`` or ``"none"``, see `tighten`).
    curves : shapely Polygon or MultiPolygon, or None
        With the minimum-perimeter finish, its loops in pixel coordinates (x = column, y = −row): the
        exact curves ``mask`` samples at the pixel centres, which `raster.contours` returns. None where
        the finish kept the flow's own pixels (or did not run); then `raster.contours` traces Φ.
    """

    mask: np.ndarray
    phi: np.ndarray
    core: np.ndarray
    fillet: np.ndarray
    r: float
    init: str
    levels: int
    iterations: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    converged: list = field(default_factory=list)
    budget: str = "until rest"
    finish: str = "none"
    curves: object = None

    @property
    def is_converged(self) -> bool:
        """Whether the front rested at every level (see `converged`)."""
        return all(self.converged)

    @property
    def mortar(self) -> np.ndarray:
        """Where the tightening may differ from the input: fillet ∧ ¬core."""
        return self.fillet & ~self.core

    @property
    def anticore(self) -> np.ndarray:
        """¬fillet."""
        return ~self.fillet


def signed_distance(mask) -> np.ndarray:
    """Signed Euclidean distance to the boundary of a mask, in pixels: negative inside, positive outside.

    The boundary is taken half-way between a True and a False pixel, so a pixel next to the boundary has
    |value| ½, and ``signed_distance(~m) == -signed_distance(m)`` exactly.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((5, 5), bool); m[1:4, 1:4] = True
    >>> float(signed_distance(m)[2, 2]), float(signed_distance(m)[0, 2])
    (-1.5, 0.5)
    """
    M = check_mask(mask)
    out = np.zeros(M.shape, dtype=np.float32)
    if M.any() and not M.all():
        # Inside: the distance to the nearest outside pixel; outside: to the nearest inside one (squared,
        # whole numbers, then one square root for both).
        d = np.sqrt(np.where(M, _edt_squared(M), _edt_squared(~M)), dtype=np.float64)
        out = np.where(M, 0.5 - d, d - 0.5).astype(np.float32)
    else:
        out[:] = -1e6 if M.all() else 1e6
    return out


def _box_around(region: np.ndarray) -> tuple[slice, slice] | None:
    """The bounding box of a non-empty mask with a one-pixel margin (clipped to the array); None if the
    box is the whole array or the mask is empty."""
    rows, cols = np.flatnonzero(region.any(axis=1)), np.flatnonzero(region.any(axis=0))
    if not len(rows):
        return None
    h, w = region.shape
    box = (slice(max(rows[0] - 1, 0), min(rows[-1] + 2, h)), slice(max(cols[0] - 1, 0), min(cols[-1] + 2, w)))
    return None if box[0].stop - box[0].start == h and box[1].stop - box[1].start == w else box


def _signed_distance_within(mask: np.ndarray, region: np.ndarray) -> np.ndarray:
    """`signed_distance(mask)` at every pixel of the box around ``mask | region`` (`_box_around`), computed
    on that box alone; +inf outside it.

    Exact in the box: every pixel of ``mask`` lies in it, so an outside pixel's nearest inside pixel does,
    and the box's margin (or the image's own edge) is outside ``mask``, nearer to an inside pixel than
    anything beyond it. `tighten` and `_reinitialise` read the result only in the fillet (the set and its
    mortar), which ``region`` covers; Figure 8's fillet fills 79 % of its image.
    """
    box = _box_around(mask | region)
    if box is None:
        return signed_distance(mask)
    out = np.full(mask.shape, np.inf, dtype=np.float32)
    out[box] = signed_distance(mask[box])
    return out


def default_levels(r: float) -> int:
    """Resolution levels for radius r: halve while r/2^k stays above two pixels.

    Examples
    --------
    >>> default_levels(40), default_levels(75), default_levels(3)
    (5, 6, 1)
    """
    r = check_radius(r)
    levels = 1
    while r / 2 ** levels >= 2.0:
        levels += 1
    return levels


def _front(neg: np.ndarray) -> np.ndarray:
    """Pixels with a 4-neighbour of the other sign."""
    f = np.zeros_like(neg)
    d = neg[1:, :] != neg[:-1, :]
    f[1:, :] |= d
    f[:-1, :] |= d
    d = neg[:, 1:] != neg[:, :-1]
    f[:, 1:] |= d
    f[:, :-1] |= d
    return f


class _Band:
    """The narrow band: flat indices of the movable pixels within chessboard distance 3 of the front."""

    WIDTH = 3

    def __init__(self, phi: np.ndarray, movable: np.ndarray):
        front = _front(phi < 0)
        near = ndimage.maximum_filter(front, size=2 * self.WIDTH + 1, mode="constant")
        inner = ndimage.maximum_filter(front, size=2 * self.WIDTH - 1, mode="constant")
        self.idx = np.flatnonzero((near & movable).ravel())
        # The band's rim: when the front reaches it, the band is rebuilt.
        self.rim = (near & ~inner).ravel()[self.idx]
        #: The band's neighbours' flat indices for `_speed`, filled in by `_flow` on first use.
        self.j = None


# Offsets within chessboard distance 4, nearest first: where a band pixel looks for the other side.
_NEAR = sorted(((dr, dc) for dr in range(-4, 5) for dc in range(-4, 5) if (dr, dc) != (0, 0)),
               key=lambda o: (o[0] ** 2 + o[1] ** 2, o))


def _fronts(neg: np.ndarray, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Which front each pixel near the band belongs to: the sign component it lies in, and the one across.

    ``neg`` is the (padded) inside set, ``idx`` the band's flat indices. Returns flat arrays ``comp``
    (inside components numbered 1, 2, …, outside ones −1, −2, …, both with 8-adjacency: parts touching
    at a corner count as one, so the rule is the same for a set and its complement and the flow stays
    self-dual) and ``owner``: at the band pixels and their neighbours, the component of the nearest pixel
    of the other sign within four pixels (0 if none). A pixel's front is the boundary between its own
    component and its owner.
    """
    eight = np.ones((3, 3), bool)
    comp_in, _ = ndimage.label(neg, structure=eight)
    comp_out, _ = ndimage.label(~neg, structure=eight)
    comp = np.where(neg, comp_in, -comp_out).astype(np.int32).ravel()
    owner = np.zeros_like(comp)
    W = neg.shape[1]
    mark = np.zeros(comp.size, dtype=bool)
    for o in (-W - 1, -W, -W + 1, -1, 0, 1, W - 1, W, W + 1):
        mark[np.clip(idx + o, 0, comp.size - 1)] = True
    region = np.flatnonzero(mark)
    sign = comp[region] > 0
    todo = np.ones(region.size, dtype=bool)
    for dr, dc in _NEAR:
        if not todo.any():
            break
        j = np.clip(region + dr * W + dc, 0, comp.size - 1)
        hit = todo & ((comp[j] > 0) != sign)
        owner[region[hit]] = comp[j[hit]]
        todo &= ~hit
    return comp, owner


def _offsets(W: int) -> np.ndarray:
    """Flat offsets of the eight neighbours in `_speed`'s order (e, w, s, n, ne, sw, nw, se: opposites
    paired), for a row length W."""
    return np.array((1, -1, W, -W, -W + 1, W - 1, -W - 1, W + 1))


def _foreign(P: np.ndarray, idx: np.ndarray, W: int, comp: np.ndarray, owner: np.ndarray,
             j: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Where `_speed` must not read a neighbour: the band's positions (into ``idx``) that have a neighbour
    on another front, and for those an (8, n) mask of which neighbours (in `_offsets`' order) do.

    ``j`` (8, N): the neighbours' flat indices, if already known.
    """
    if j is None:
        j = _offsets(W)[:, None] + idx[None, :]
    foreign = _foreign_at(P.ravel(), idx, j, comp, owner)
    cols = np.flatnonzero(foreign.any(axis=0))
    return cols, foreign[:, cols]


def _foreign_at(flat: np.ndarray, idx: np.ndarray, j: np.ndarray, comp: np.ndarray,
                owner: np.ndarray) -> np.ndarray:
    """(8, N) bool: which neighbours ``j`` of the pixels ``idx`` lie on another front than the pixel's own
    (a neighbour of the pixel's sign that another front owns, or one of the other sign in a component
    that is not the pixel's owner)."""
    c_neg = flat[idx] < 0
    own_c = owner[idx]
    same = (flat[j] < 0) == c_neg[None, :]
    return np.where(same, owner[j] != own_c, comp[j] != own_c)


class _ForeignCache:
    """`_foreign` for the band, kept from step to step: it depends only on the signs of Φ and on the
    front labels, so after a step it changes only around the pixels that changed sign (whose labels
    `_flow` swaps), and is recomputed there. Built again from scratch when the band or the labels are.
    """

    #: Flat-offset reach (chessboard) around a pixel that changed sign within which a band pixel's
    #: foreign neighbours may change: its neighbours (1), and a pixel of the padded frame, which copies a
    #: border pixel next to it (2).
    REACH = 2

    def __init__(self, P: np.ndarray, band: "_Band", W: int, comp: np.ndarray, owner: np.ndarray):
        self.idx, self.j, self.W = band.idx, band.j, W
        self.full = _foreign_at(P.ravel(), self.idx, self.j, comp, owner)
        self.where = np.full(P.size, -1, dtype=np.int64)
        self.where[self.idx] = np.arange(self.idx.size)
        k = self.REACH
        self.near = np.array([dr * W + dc for dr in range(-k, k + 1) for dc in range(-k, k + 1)])
        self._result = None

    def changed(self, flat: np.ndarray, pos: np.ndarray, comp: np.ndarray, owner: np.ndarray) -> None:
        """The pixels at flat indices ``pos`` changed sign (and their labels were updated)."""
        around = np.clip((pos[:, None] + self.near[None, :]).ravel(), 0, self.where.size - 1)
        at = np.unique(self.where[around])
        at = at[at >= 0]
        if at.size:
            self.full[:, at] = _foreign_at(flat, self.idx[at], self.j[:, at], comp, owner)
            self._result = None

    def result(self) -> tuple[np.ndarray, np.ndarray]:
        if self._result is None:
            cols = np.flatnonzero(self.full.any(axis=0))
            self._result = (cols, self.full[:, cols])
        return self._result


def _speed(P: np.ndarray, idx: np.ndarray, W: int, comp=None, owner=None, *, j=None,
           foreign=None) -> tuple[np.ndarray, np.ndarray]:
    """κ|∇Φ| at the flat indices ``idx`` of the (padded, row length W) array P, in two passes.

    First pass: the unit normal n = ∇Φ/|∇Φ| by central differences at the four half-way points around each
    pixel; second pass: its divergence by differences of those. Multiplied by |∇Φ| at the pixel.

    With ``comp`` and ``owner`` (flat, from `_fronts`), each pixel sees only its own front: a neighbour that
    belongs to another front (two fronts a pixel or two apart, across a gap or a wall) is replaced by the
    linear continuation of Φ through the pixel from the opposite neighbour, as if the other front were not
    there. Without it, the crease of Φ between two fronts reads as a strong curvature and draws them
    together, which the continuous flow never does: fronts merge only where one of them moves.

    ``j`` (the neighbours' flat indices, ``_offsets(W)[:, None] + idx``) and ``foreign`` (`_foreign`'s
    result for the current signs and labels) may be passed in when already known; the result is the same.
    """
    flat = P.ravel()
    c = flat[idx]
    # e, w, s, n, ne, sw, nw, se (opposites paired), gathered at once: one (8, N) array.
    if j is None:
        j = _offsets(W)[:, None] + idx[None, :]
    v = flat[j]
    if comp is not None:
        cols, fmask = foreign if foreign is not None else _foreign(P, idx, W, comp, owner, j)
        if cols.size:
            # Only the few pixels with a neighbour on another front change: the others keep their values.
            cc = c[cols]
            sub = v[:, cols]
            for a in range(0, 8, 2):
                b = a + 1
                fa, fb = fmask[a], fmask[b]
                va, vb = sub[a], sub[b]
                # A foreign neighbour continues Φ linearly from the opposite one; both foreign: no slope.
                na = np.where(fa, np.where(fb, cc, 2 * cc - vb), va)
                nb = np.where(fb, np.where(fa, cc, 2 * cc - va), vb)
                sub[a], sub[b] = na, nb
            v[:, cols] = sub
    e, w, s, n, ne, sw, nw, se = v
    # Normal at the east and west half-points (x between columns), and at the south and north ones.
    gx_e = e - c
    gy_e = 0.25 * (s + se - n - ne)
    gx_w = c - w
    gy_w = 0.25 * (s + sw - n - nw)
    gy_s = s - c
    gx_s = 0.25 * (e + se - w - sw)
    gy_n = c - n
    gx_n = 0.25 * (e + ne - w - nw)
    div = (gx_e / np.sqrt(gx_e * gx_e + gy_e * gy_e + _EPS) - gx_w / np.sqrt(gx_w * gx_w + gy_w * gy_w + _EPS)
           + gy_s / np.sqrt(gy_s * gy_s + gx_s * gx_s + _EPS) - gy_n / np.sqrt(gy_n * gy_n + gx_n * gx_n + _EPS))
    grad = np.sqrt(0.25 * ((e - w) ** 2 + (s - n) ** 2))
    # A structure one pixel thick (both neighbours along a row or a column across the front) has
    # central differences that cancel: |∇Φ| = 0 however curved it is, and it would never move. There Φ
    # changes by about one pixel a pixel, as everywhere near the front.
    thin = (((e < 0) == (w < 0)) & ((e < 0) != (c < 0))) | (((s < 0) == (n < 0)) & ((s < 0) != (c < 0)))
    grad = np.where(thin, np.maximum(grad, 1.0), grad)
    return div, grad


# The eight neighbours in ring order (N, NE, E, SE, S, SW, W, NW) as (row, column) offsets.
_RING = ((-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1))


def _components_in_ring(bits: tuple, adjacency: int) -> int:
    """Connected components of the set pixels of a 3 × 3 ring (centre excluded) that touch the centre.

    With ``adjacency=8`` all set ring pixels count and diagonal steps connect; with 4, only components
    that contain one of the four direct neighbours count and only side steps connect.
    """
    on = [i for i in range(8) if bits[i]]
    seen, count = set(), 0
    for start in on:
        if start in seen:
            continue
        stack, comp = [start], {start}
        while stack:
            i = stack.pop()
            for j in on:
                if j in comp:
                    continue
                di = abs(_RING[i][0] - _RING[j][0])
                dj = abs(_RING[i][1] - _RING[j][1])
                if (di <= 1 and dj <= 1) if adjacency == 8 else (di + dj == 1):
                    comp.add(j)
                    stack.append(j)
        seen |= comp
        if adjacency == 8 or any(i % 2 == 0 for i in comp):
            count += 1
    return count


def _simple_table() -> np.ndarray:
    """For each of the 256 rings: whether flipping the centre changes no topology, in (8,4) nor in (4,8).

    A pixel is simple for a set F when its ring has one F-component and one component of the complement
    touching it (Rosenfeld). Asking both connectivity pairs makes the test symmetric under complement.
    """
    table = np.zeros(256, dtype=bool)
    for code in range(256):
        fg = tuple((code >> i) & 1 for i in range(8))
        bg = tuple(1 - b for b in fg)
        table[code] = (_components_in_ring(fg, 8) == 1 and _components_in_ring(bg, 4) == 1
                       and _components_in_ring(fg, 4) == 1 and _components_in_ring(bg, 8) == 1)
    return table


_SIMPLE = _simple_table()


def _bridge_table() -> np.ndarray:
    """For each of the 256 rings: whether its set pixels fall into two or more 8-connected groups.

    A pixel of one sign whose ring holds two separate groups of the other sign stands between two fronts
    (of one part or of two) a pixel apart: a one-pixel moat between inside pixels, or a one-pixel wall
    between outside ones. The same table serves both signs (with the ring's bits inverted for an inside
    pixel), so the test commutes with complementing the image.
    """
    return np.array([_components_in_ring(tuple((code >> i) & 1 for i in range(8)), 8) >= 2
                     for code in range(256)])


_BRIDGE = _bridge_table()


def _ring_codes(flat: np.ndarray, pos: np.ndarray, W: int) -> np.ndarray:
    """The 8-bit code of each pixel's ring (bit i: `_RING`'s i-th neighbour inside), the index into
    `_SIMPLE`. ``flat`` (row length W) is the inside set, or Φ (inside where negative); ``pos`` are flat
    indices away from its edge. Only the rings are read, so Φ is never compared as a whole."""
    offsets = np.array([dr * W + dc for dr, dc in _RING])
    ring = flat[pos[:, None] + offsets[None, :]]
    if ring.dtype != bool:
        ring = ring < 0
    return (ring * (1 << np.arange(8))).sum(axis=1)


#: Half the side of the window in which `_pressed` looks for the two fronts to meet, pixels.
PRESS_REACH = 3


def _pressed(inside: np.ndarray, where: np.ndarray | None = None) -> np.ndarray:
    """Pixels that stand between two fronts a pixel apart, in an ``inside`` set (its one-pixel frame is
    never marked: its ring runs off the array); only pixels of ``where`` are tested, if given.

    A pixel is pressed when its ring holds two groups of the other sign (`_bridge_table`) that do not
    meet within `PRESS_REACH` pixels of it: two parts (or two stretches of one part's front) facing each
    other across a moat one pixel wide, or, for the other sign, two outside regions across a wall one
    pixel thick. The groups either side of a spike shorter than `PRESS_REACH` (an upsampled remnant, say)
    meet round its tip: that is one front folded, not two pressed together. The test commutes with
    complementing the set.
    """
    out = np.zeros_like(inside)
    H, W = inside.shape
    if H < 3 or W < 3:
        return out
    code = np.zeros((H - 2, W - 2), dtype=np.intp)
    for bit, (dr, dc) in enumerate(_RING):
        code |= inside[1 + dr:H - 1 + dr, 1 + dc:W - 1 + dc].astype(np.intp) << bit
    centre = inside[1:-1, 1:-1]
    candidate = np.where(centre, _BRIDGE[255 - code], _BRIDGE[code])
    if where is not None:
        candidate &= where[1:-1, 1:-1]
    eight = np.ones((3, 3), bool)
    k = PRESS_REACH
    for y, x in np.argwhere(candidate) + 1:
        y0, x0 = max(y - k, 0), max(x - k, 0)
        other = inside[y0:y + k + 1, x0:x + k + 1] != inside[y, x]
        label, _ = ndimage.label(other, structure=eight)
        groups = {label[y - y0 + dr, x - x0 + dc] for dr, dc in _RING} - {0}
        out[y, x] = len(groups) >= 2
    return out


def _homotopic(start: np.ndarray, target: np.ndarray, movable: np.ndarray) -> np.ndarray:
    """Move the set ``start`` towards ``target`` by flipping simple pixels only, a layer at a time.

    Only ``movable`` pixels change. A pixel flips when it differs from the target and flipping it changes no
    component or hole (or removes a one-pixel component or hole, so small parts can vanish as in the flow).

    Where a flip would merge or split, the start's parts were pressed together (or pulled apart) on the
    coarse grid. Two cases:

    * a part (or a hole) that is *free*, every pixel of it movable, holds no constraint that keeps it
      alive: the flow may shrink it to nothing, and the coarse level did (its flow never merges). Such a
      part beside a refused pixel vanishes as a whole, and the flips go on, so that what the target holds
      there regrows from the other side (a thin bar of the input, in the mortar, that a neighbour's front
      sweeps over);
    * otherwise the change is left to this level: every pixel of the connected region of change around a
      refused pixel keeps the start's value, so that the flow starts there from this level's initial set
      and re-grows (or re-shrinks) what truly belongs (changes that are not 8-adjacent never see each
      other's pixels, so undoing one keeps every other flip simple).

    Parts can also be pressed together without any flip being refused: where two parts (or two arms of
    one) are apart on this grid but their samples touch on the coarse one, the coarse flow treats them as
    one and fills the neck between them; reached by simple flips, that fill leaves the two fronts with a
    moat one pixel wide, which no Φ on this grid can hold open (a front's staircase moves by half a pixel
    as it settles, and a moat pixel that crosses joins the parts). Dually, a wall one pixel thick is left
    between two outside regions where the coarse flow thinned a bar the continuous flow keeps. Such a
    change is left to this level too: wherever the result has a pixel between two fronts a pixel apart
    (`_pressed`) that the start does not have, the connected region of change around it keeps the
    start's value.

    The result has the start's topology up to vanished parts, presses no fronts together that the start
    does not, and equals the target elsewhere.
    """
    s0 = np.pad(start, 1, mode="edge")
    cur = s0.copy()
    tgt = np.pad(target, 1, mode="edge")
    mov = np.pad(movable, 1, mode="constant")
    W = cur.shape[1]
    flat = cur.ravel()

    def flip_simple() -> np.ndarray:
        # The pixels still to flip: a flip makes a pixel equal to the target for good, so the list only
        # loses the ones flipped (kept in flat order, as a fresh search would give it).
        cand = np.flatnonzero(((cur != tgt) & mov).ravel())
        while cand.size:
            parity = (cand // W % 2) * 2 + (cand % W % 2)
            done = np.zeros(cand.size, dtype=bool)
            for sub in range(4):
                at = np.flatnonzero(parity == sub)
                if at.size == 0:
                    continue
                p = cand[at]
                code = _ring_codes(flat, p, W)
                was = flat[p]
                ok = _SIMPLE[code] | ((code == 255) & ~was) | ((code == 0) & was)
                flat[p[ok]] = ~was[ok]
                done[at[ok]] = True
            if not done.any():
                break
            cand = cand[~done]
        return (cur != tgt) & mov

    stuck = flip_simple()
    if stuck.any():
        eight = np.ones((3, 3), bool)
        near = ndimage.maximum_filter(stuck, size=3, mode="constant")     # its 3 × 3 dilation
        vanish = np.zeros_like(cur)
        for side, structure in ((cur, eight), (~cur, None)):    # parts 8-connected, holes 4-connected
            label, n = ndimage.label(side, structure=structure)
            # Per label: anchored (holds a pixel that cannot move), and free parts beside a stuck pixel.
            anchored = np.zeros(n + 1, dtype=bool)
            anchored[label[side & ~mov]] = True
            free = (label > 0) & ~anchored[label]
            hit = np.zeros(n + 1, dtype=bool)
            hit[label[free & near]] = True
            vanish |= free & hit[label]
        if vanish.any():
            cur[vanish] = ~cur[vanish]
            stuck = flip_simple()
    if stuck.any():
        change, n = ndimage.label((s0 != tgt) & mov, structure=np.ones((3, 3), bool))
        hit = np.zeros(n + 1, dtype=bool)
        hit[change[stuck]] = True               # (label 0 too, as before, if a stuck pixel has it)
        undo = hit[change]
        cur[undo] = s0[undo]
    # Fronts pressed a pixel apart by the coarse level: undo each region of change within `PRESS_REACH` of
    # such a pixel. A pixel farther than that from every change sees the start's window, and is pressed
    # exactly when it was at the start; every round undoes at least one region, so the loop ends.
    eight = np.ones((3, 3), bool)
    reach = 2 * PRESS_REACH + 1
    while True:
        moved = cur != s0
        pressed = _pressed(cur, ndimage.maximum_filter(moved, size=reach)) if moved.any() else moved
        if pressed.any():
            pressed &= ~_pressed(s0, pressed)
        if not pressed.any():
            break
        change, n = ndimage.label(moved & mov, structure=eight)
        hit = np.zeros(n + 1, dtype=bool)
        hit[change[ndimage.maximum_filter(pressed, size=reach)]] = True
        hit[0] = False
        if not hit.any():
            break
        undo = hit[change]
        cur[undo] = s0[undo]
    return cur[1:-1, 1:-1].copy()


def _keep_topology(flat: np.ndarray, idx: np.ndarray, old: np.ndarray, new: np.ndarray, W: int) -> np.ndarray:
    """Apply a step's sign changes only at simple pixels, in four passes of pixels never 8-adjacent.

    ``new`` holds the step's values (already written); returns them with every refused sign change undone
    (the pixel keeps its old value).
    """
    flips = np.flatnonzero((old < 0) != (new < 0))
    if flips.size == 0:
        return new
    pos = idx[flips]
    flat[pos] = old[flips]                      # undo, then redo pass by pass where allowed
    parity = (pos // W % 2) * 2 + (pos % W % 2)
    out = new.copy()
    for sub in range(4):
        sel = parity == sub
        if not sel.any():
            continue
        p = pos[sel]
        code = _ring_codes(flat, p, W)
        k = flips[sel]
        # Simple pixels, and the last pixel of a component or a hole: small parts may vanish (creating
        # one, a pixel unlike all its neighbours turning, may not).
        ok = _SIMPLE[code] | ((code == 255) & (old[k] >= 0)) | ((code == 0) & (old[k] < 0))
        flat[p[ok]] = new[k[ok]]
        out[k[~ok]] = old[k[~ok]]
    return out


def _flow(phi: np.ndarray, movable: np.ndarray, iterations: int, stop: float,
          keep_topology: bool = False, own_front: bool = True,
          rest: str = "front") -> tuple[np.ndarray, int, bool]:
    """Run the constrained flow on one level; returns Φ, the number of steps taken and whether the front
    rested (the rest test below passed, or no front was left) before ``iterations`` steps ran out.

    With ``keep_topology`` a pixel changes sign only where that changes no component or hole (a simple
    pixel): the coarse levels use it, because there fronts a pixel or two apart would merge across gaps
    the full-resolution flow keeps open.
    """
    H, W0 = phi.shape
    P = np.pad(phi, 1, mode="edge")              # a one-pixel frame so every band pixel has 8 neighbours
    Wp = W0 + 2
    mov = np.pad(movable, 1, mode="constant")
    band = _Band(P, mov)
    steps = 0
    flat = P.ravel()
    comp = owner = foreign = None
    stale = own_front
    snapshot, last_flip = None, 0
    rested = iterations == 0 and band.idx.size == 0
    # The topology rest test's first window starts with the level itself: its starting set is the one the
    # first check compares with (the front test needs a window's worth of Φ first).
    last_inside, last_topo_flip = ((P[1:-1, 1:-1] < 0) if rest == "topology" else None), 0
    for steps in range(1, iterations + 1):
        if band.idx.size == 0:
            steps -= 1
            rested = True
            break
        idx = band.idx
        if stale:
            comp, owner = _fronts(P < 0, idx)
            stale = False
            foreign = None
        if band.j is None:
            band.j = _offsets(Wp)[:, None] + idx[None, :]
            foreign = None
        if own_front and foreign is None:
            foreign = _ForeignCache(P, band, Wp, comp, owner)
        kappa, grad = _speed(P, idx, Wp, comp, owner, j=band.j,
                             foreign=foreign.result() if foreign is not None else None)
        kmax = float(np.abs(kappa).max()) if kappa.size else 0.0
        dt = 0.25 if kmax <= 4.0 else 1.0 / kmax
        old = flat[idx]
        new = old + (dt * kappa * grad).astype(np.float32)
        flat[idx] = new
        # Φ stays 1-Lipschitz across pixels, as a distance is: |Φ| at most 1 beside the front, and at most
        # a neighbour's |Φ| + 1 elsewhere. Where a front rests against a constraint that holds it back (a
        # hole's anticore, which the hole's edge would shrink into), the flow otherwise keeps pushing Φ
        # behind it deeper, step after step, without moving the front: the front across the part (a thin
        # ring's other side) then has ever more to undo, and the part never vanishes.
        neg = new < 0
        q = flat[band.j[:4]]                    # the four side neighbours (e, w, s, n), after the step
        bound = np.where((q < 0) != neg, np.float32(1.0), np.abs(q) + np.float32(1.0)).min(axis=0)
        over = np.abs(new) > bound
        if over.any():
            new = np.where(over, np.copysign(bound, new), new).astype(np.float32)
            flat[idx] = new
        if keep_topology:
            new = _keep_topology(flat, idx, old, new, Wp)
        # Keep the frame equal to the border pixels (edge replication).
        P[0, :], P[-1, :], P[:, 0], P[:, -1] = P[1, :], P[-2, :], P[:, 1], P[:, -2]
        flips = (old < 0) != (new < 0)
        if flips.any():
            last_flip = steps
            if rest == "topology":
                fl = idx[flips]
                if not _SIMPLE[_ring_codes(flat, fl, Wp)].all():
                    last_topo_flip = steps
        if steps % STOP_WINDOW == 0 and rest == "topology" and stop > 0:
            # Only the homotopy class is needed (a minimum-perimeter finish follows): the level rests
            # when its parts and holes stayed the same over a whole window without a pixel changing a
            # component or a hole, the first window included (from the level's starting set: a coarse
            # level, which keeps its topology, then rests after one window, and the full-resolution level
            # as soon as one window of its own passes without a change).
            # (The counts are only needed when the window was quiet; the set at the window's start is
            # kept, and counted then.)
            inside_now = P[1:-1, 1:-1] < 0
            if last_inside is not None and steps - last_topo_flip >= STOP_WINDOW and (
                    np.array_equal(inside_now, last_inside)
                    or _topology_counts(inside_now) == _topology_counts(last_inside)):
                rested = True
                break
            last_inside = inside_now
        elif steps % STOP_WINDOW == 0:
            # Rest is judged on the net change over a window: a pixel that swings in place every step (at a
            # constraint's corner, say) moves Φ by a tenth of a pixel a step forever and never rests step
            # by step, while the front it sits on has long stopped.
            if snapshot is not None and steps - last_flip >= STOP_WINDOW:
                near = np.abs(P) <= 1.0
                if float(np.abs(P - snapshot)[near].max(initial=0.0)) < stop * STOP_WINDOW:
                    rested = True
                    break
            snapshot = P.copy()
        # Rebuild the band when the front reaches its rim; inside it, the band still holds the front.
        rebuild = flips.any() and band.rim[flips].any()
        if rebuild:
            band = _Band(P, mov)
        if own_front and flips.any():
            # A pixel that crossed a front joins the component across it. Where that changed a component or
            # a hole (a pixel not simple after the step), and whenever the band moves on, the labels and
            # owners are found again from scratch.
            pos = idx[flips]
            code = _ring_codes(flat, pos, Wp)
            if rebuild or not _SIMPLE[code].all():
                stale = True
            else:
                comp[pos], owner[pos] = owner[pos], comp[pos].copy()
                foreign.changed(flat, pos, comp, owner)
    return P[1:-1, 1:-1].copy(), steps, rested


def _topology_counts(inside: np.ndarray) -> tuple[int, int]:
    """Components (8-connected) and holes (4-connected outside parts not touching the edge) of a set."""
    _, n = ndimage.label(inside, structure=np.ones((3, 3), bool))
    lab, m = ndimage.label(np.pad(~inside, 1, constant_values=True))
    return int(n), int(m) - 1


def _reinitialise(base: np.ndarray, inside: np.ndarray, movable: np.ndarray) -> np.ndarray:
    """Φ for a level that starts from ``inside`` (the coarse result reached by `_homotopic`).

    ``base`` is the level's own Φ: the signed distance to its initial set, and, with supersampling, to
    where the fine mask puts that set's edge, a fraction of a pixel off the pixel centres. Where the
    transfer changed the set, Φ in the mortar becomes the signed distance to the new front, so that the
    narrow gaps the coarse level left between fronts get their true width in Φ. Everywhere else ``base``
    is kept: a pixel whose distance to its front, plus a pixel, is less than its distance to every
    changed pixel has that same front nearest, and ``base`` places it to a fraction of a pixel, where
    the distance to the pixel staircase would move it up to half a pixel (enough for two fronts a pixel
    apart to meet). Outside the mortar Φ is always ``base``.
    """
    changed = (inside != (base < 0)) & movable
    if not changed.any():
        return base.copy()
    # Both distances are read only in ``movable``: on the box around it and the set (exact there, see
    # `_signed_distance_within`; the changed pixels, all movable, lie in it too).
    box = _box_around(inside | movable)
    if box is None:
        box = (slice(None), slice(None))
    reach = np.full(base.shape, np.inf)
    reach[box] = _edt(~changed[box])
    redo = movable & (reach <= np.abs(base) + 1.0)
    out = base.copy()
    if inside.any() and not inside.all():
        out[redo] = _signed_distance_at(inside[box], np.flatnonzero(redo[box].ravel()))
    else:
        out[redo] = np.where(inside[redo], -0.5, 0.5)
    return out


def _signed_distance_at(M: np.ndarray, where: np.ndarray) -> np.ndarray:
    """`signed_distance(M)` at the flat indices ``where`` only (float32), the same values: an inside
    pixel's nearest outside pixel has an inside pixel beside it (the pixel one step back towards it,
    along its longer axis, is nearer, so inside), and vice versa, so each distance is found by a k-d tree
    of the pixels along the other side's edge, queried at ``where`` (a few tens of thousands of pixels
    where two feature transforms would cover the whole array). ``M`` holds both values."""
    from scipy.spatial import cKDTree

    edge_in = M & ~_interior(M)
    edge_out = ~M & ~_interior(~M)
    ii, jj = np.unravel_index(where, M.shape)
    at_in = M[ii, jj]
    pts = np.column_stack([ii, jj]).astype(float)
    d = np.empty(where.size)
    for sel, edge in ((at_in, edge_out), (~at_in, edge_in)):
        if sel.any():
            d[sel] = cKDTree(np.argwhere(edge).astype(float)).query(pts[sel])[0]
    return np.where(at_in, 0.5 - d, d - 0.5).astype(np.float32)


def _interior(M: np.ndarray) -> np.ndarray:
    """Pixels of M whose four side neighbours within the array are all in M."""
    out = M.copy()
    out[1:] &= M[:-1]
    out[:-1] &= M[1:]
    out[:, 1:] &= M[:, :-1]
    out[:, :-1] &= M[:, 1:]
    return out


def _check_supersample(k, shape: tuple[int, int]) -> int:
    """An odd whole number ≥ 1 that leaves at least one block in each direction."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1 or k % 2 == 0:
        raise ValueError(f"supersample must be an odd whole number ≥ 1, got {k!r}")
    if k > 1 and min(shape) < k:
        raise ValueError(f"supersample {k} is larger than the mask ({shape[1]} × {shape[0]} px)")
    return int(k)


def _downsample(a: np.ndarray, k: int) -> np.ndarray:
    s = 2 ** k
    return a[::s, ::s]


def _upsample(phi: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """Φ at twice the resolution (values doubled: Φ is in pixels), by linear interpolation."""
    h, w = shape
    rows = np.arange(h) / 2.0
    cols = np.arange(w) / 2.0
    r0 = np.minimum(np.floor(rows).astype(int), phi.shape[0] - 1)
    c0 = np.minimum(np.floor(cols).astype(int), phi.shape[1] - 1)
    r1 = np.minimum(r0 + 1, phi.shape[0] - 1)
    c1 = np.minimum(c0 + 1, phi.shape[1] - 1)
    fr = (rows - r0)[:, None].astype(np.float32)
    fc = (cols - c0)[None, :].astype(np.float32)
    top = phi[r0][:, c0] * (1 - fc) + phi[r0][:, c1] * fc
    bot = phi[r1][:, c0] * (1 - fc) + phi[r1][:, c1] * fc
    return (2.0 * (top * (1 - fr) + bot * fr)).astype(np.float32)


#: Above this radius (pixels) every part of the core and of the anticore holds a pixel centre: each holds
#: an open disk of radius r, and a disk of radius over √2/2 always holds one.
_SLACK_RADIUS = 0.75


def _drop_slack_parts(inside: np.ndarray, R: np.ndarray, F: np.ndarray) -> np.ndarray:
    """``inside`` with its holes that hold no anticore filled and its components that hold no core removed.

    A tightening's boundary loop around a region of mortar alone is not tight: it can shrink within the
    mortar until it vanishes (a tight loop turns left only around core disks and right only around
    anticore disks). The flow can leave such a part behind where it does not rest, e.g. a hole cut off by
    a chain of single pixels joined at their corners (8-connected) that it keeps swinging; the level set
    would close it. Components are 8-connected, holes 4-connected (the dual pair).
    """
    lab, n = ndimage.label(np.pad(~inside, 1, constant_values=True))     # the frame joins the outside
    if n > 1:
        anti = np.asarray(ndimage.maximum(np.pad(~F, 1), lab, np.arange(1, n + 1)), dtype=bool)
        fill = np.r_[False, ~anti]
        fill[lab[0, 0]] = False                         # the outside is not a hole
        inside = inside | fill[lab[1:-1, 1:-1]]
    lab, n = ndimage.label(inside, structure=np.ones((3, 3), bool))
    if n:
        has = np.asarray(ndimage.maximum(R, lab, np.arange(1, n + 1)), dtype=bool)
        inside = inside & np.r_[False, has][lab]
    return inside


def _step_cap(shape: tuple[int, int]) -> int:
    """The safety net on a level's steps when ``iterations`` is None: `MIN_CAP`, or the level's
    perimeter in pixels times `CAP_PER_PIXEL` if that is more."""
    return max(MIN_CAP, CAP_PER_PIXEL * (shape[0] + shape[1]))


def tighten(mask, r, *, init: str = "core", levels: int | None = None, iterations: int | None = None,
            stop: float = 1e-3, supersample: int = 1, finish: str = "mpp") -> RasterTightening:
    """The r-tightening of a binary image by constrained level-set curvature flow (the paper's §3).

    Parameters
    ----------
    mask : (H, W) array of bool (or of 0/1 numbers)
        The shape, True inside. Not modified.
    r : float
        The radius in pixels, > 0.
    init : {"core", "input", "mason"}
        The initial set: the core (the paper's method), the input (self-dual), or Mason(M) (self-dual).
    levels : int, optional
        Resolution levels of the multiscale scheme; default `default_levels(r)`. 1 = single scale.
    iterations : int, optional
        Largest number of steps a level. By default (None) each level flows until its front rests (the
        ``stop`` test), with a safety cap of `_step_cap` steps (at least `MIN_CAP`, more on large
        levels) that a converging flow does not reach; ``iterations=100`` reproduces the paper's budget
        of 100 steps a level (it says so in ``budget``, and warns if a level had not rested by then).
    stop : float
        Early stop: a level ends when no pixel has changed sign for `STOP_WINDOW` steps and over those
        steps Φ within a pixel of the front has changed, net, by less than this many pixels a step (net,
        so that a pixel swinging in place does not keep a resting front flowing). With the
        minimum-perimeter finish (the default), which needs only the homotopy class, a level rests
        instead when over `STOP_WINDOW` steps (the first window starting with the level) no pixel
        changed a component or a hole and their counts stayed the same; ``stop=0`` turns both tests off.
    supersample : int, odd, ≥ 1
        The mask is sampled this many times finer than the grid the flow runs on (1, the default, is the
        paper's method). The morphology (core, fillet, the initial set) is computed on the fine mask, and
        so are the signed distances to their boundaries; the flow runs on the centre pixel of each
        ``supersample × supersample`` block, with those distances in its own pixels, so that its
        constraints and its start lie where the fine mask puts them, to a fraction of a pixel. Where the
        mask is a rasterised vector shape, this removes most of the rasterisation error from the disks
        that fit an acute corner (a boundary off by δ moves such a disk by δ/sin α in a wedge of
        half-angle α). ``r`` and ``mask`` are in the fine pixels; the result is on the coarse grid
        (``mask.shape // supersample``) and its ``r`` is in coarse pixels. A mask of more than
        `MAX_SUPERSAMPLED_PIXELS` pixels is sampled at its blocks' centres and gets plain morphology
        instead, with a `SupersampleWarning` that gives the limit (the same result grid and units).
    finish : {"mpp", "none"}
        A final step after the flow: ``"mpp"`` (the default) replaces each boundary loop by the shortest
        loop homotopic to it in the pixel mortar (`raster.mpp.mpp_finish`, the paper's §4.7), which makes
        long straight tight segments straight where the flow leaves them bowed; ``"none"`` returns the
        flow's own result (the paper's method).

    Returns
    -------
    RasterTightening
        ``mask`` satisfies ``core ⊆ mask ⊆ fillet`` exactly. If r is so large that the core is empty and
        the flow shrinks everything away, ``mask`` is all False.

    Raises
    ------
    ValueError
        If the mask is not a binary 2-D image, is all False or all True, or r is not a finite number > 0.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:60, :60]
    >>> square = (abs(xx - 30) < 20) & (abs(yy - 30) < 20)
    >>> T = tighten(square, 8)
    >>> bool((T.core <= T.mask).all() and (T.mask <= T.fillet).all()), bool(T.mask[11, 11])
    (True, False)
    """
    t_start = time.perf_counter()
    M = check_mask(mask, allow_uniform=False)
    r = check_radius(r)
    if init not in INITS:
        raise ValueError(f"init must be one of {', '.join(INITS)}, got {init!r}")
    if finish not in FINISHES:
        raise ValueError(f"finish must be one of {', '.join(FINISHES)}, got {finish!r}")
    ss = _check_supersample(supersample, M.shape)
    if ss > 1 and M.size > MAX_SUPERSAMPLED_PIXELS:
        warnings.warn(f"raster.tighten: a {M.shape[1]} × {M.shape[0]} px mask is too large for supersampled "
                      f"morphology (limit {MAX_SUPERSAMPLED_PIXELS:,} pixels, about 70 bytes each); using "
                      f"plain morphology on the centres of its {ss} × {ss} blocks", SupersampleWarning,
                      stacklevel=2)
        c = ss // 2
        M = np.ascontiguousarray(M[c:c + ss * (M.shape[0] // ss):ss, c:c + ss * (M.shape[1] // ss):ss])
        if not M.any() or M.all():
            raise ValueError("the mask sampled at its blocks' centres is all False or all True")
        r, ss = r / ss, 1
    if levels is None:
        levels = default_levels(r / ss)
    elif int(levels) != levels or levels < 1:
        raise ValueError(f"levels must be a whole number ≥ 1, got {levels!r}")
    if iterations is not None and (isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer))
                                   or iterations < 0):
        raise ValueError(f"iterations must be a whole number ≥ 0 or None, got {iterations!r}")
    levels = int(levels)
    timings = {}
    t0 = time.perf_counter()
    R, F, R_c, F_c, sd_R, sd_A = _core_fillet_both(M, r)
    timings["morphology"] = time.perf_counter() - t0
    if vanishes(M, r):        # no disk of radius r fits: every tightening is empty, at once
        timings["total"] = time.perf_counter() - t_start
        return RasterTightening(mask=np.zeros_like(M), phi=np.full(M.shape, 0.5, dtype=np.float32), core=R,
                                fillet=F, r=r, init=init, levels=levels, iterations=[], timings=timings)
    t0 = time.perf_counter()
    start = {"core": R, "input": M, "mason": mason(M, r) if init == "mason" else None}[init]
    # Φ beyond the box around the fillet (and the start) is anticore's, set below: the start's signed
    # distance is needed only in that box.
    phi0 = _signed_distance_within(start, F) if start.any() and not start.all() else \
        np.where(start, -0.5, 0.5).astype(np.float32)
    # The constraints: Φ < 0 in the core and > 0 in the anticore, for good. There Φ is the signed distance
    # to the constraint's own edge (−½ and +½ on its first pixels), not to the initial set: a front that
    # reaches the anticore then sees it as a boundary half a pixel away, and settles against it.
    # On a constraint's edge Φ is the signed distance to its sub-pixel edge (`_core_fillet_both`): half a
    # pixel on a straight edge, a fraction where an arc barely covers a lone stair pixel (there the square
    # would hold the front 0.7 px beyond the arc).
    if R.any():
        # From the core, Φ there already is ½ − its distance transform (in float32, which rounds the same).
        own = phi0[R] if start is R and not R.all() else 0.5 - _edt(R)[R]
        phi0[R] = np.maximum(own, sd_R[R])
    if not F.all():
        A = ~F
        phi0[A] = np.minimum(_edt(A)[A] - 0.5, -sd_A[A])
    if ss > 1:
        # The flow's grid: the centre pixel of each ss × ss block, Φ in its pixels. In the mortar Φ keeps the
        # fine distances, a fraction of a pixel; a constraint pixel stays at least ½ from the front, as at
        # ss = 1: one whose centre the fine constraint's edge all but grazes would otherwise pin the front
        # to it (a front in a notch of the core stalled 3 px short of the tight position).
        c = ss // 2
        rows, cols = M.shape[0] // ss, M.shape[1] // ss
        pick = (slice(c, c + ss * rows, ss), slice(c, c + ss * cols, ss))
        R, F, phi0 = R[pick], F[pick], (phi0[pick] / np.float32(ss)).astype(np.float32)
        R_c, F_c = R_c[pick], F_c[pick]
        sd_R, sd_A = sd_R[pick] / np.float32(ss), sd_A[pick] / np.float32(ss)
        phi0[R] = np.minimum(phi0[R], -0.5)
        phi0[~F] = np.maximum(phi0[~F], 0.5)
        r = r / ss
    movable = F & ~R
    # The coarse levels flow with the pixel-centred constraints only (`raster.morphology`): the
    # corner-centred disks add a part exactly 2r wide, and single pixels along the constraints' arcs,
    # which sampled every 2^k pixels stand alone and would pinch the coarse fronts (a bar held between two
    # parts of the anticore was cut so). The full-resolution level has the exact constraints.
    movable_c = F_c & ~R_c
    timings["init"] = time.perf_counter() - t0
    counts, converged = [], []
    phi = None
    for k in range(levels - 1, -1, -1):
        t0 = time.perf_counter()
        base = _downsample(phi0, k) / np.float32(2 ** k)
        mov_k = _downsample(movable if k == 0 else movable_c, k)
        if phi is None:
            phi_k = base.copy()
        else:
            target = np.where(mov_k, _upsample(phi, base.shape), base) < 0
            # The coarse level saw this level's initial set and constraints sampled every other pixel, where
            # parts a pixel apart may touch; reach its result from this level's own initial set by simple
            # pixels only, so that topology comes from this level (the full-resolution flow, free of the
            # topology check, merges and splits what truly meets or pinches off).
            inside = _homotopic(base < 0, target, mov_k)
            phi_k = _reinitialise(base, inside, mov_k)
        cap = _step_cap(mov_k.shape) if iterations is None else int(iterations)
        phi, n, rested = _flow(phi_k, mov_k, cap, stop, keep_topology=k > 0,
                               rest="topology" if finish == "mpp" else "front")
        counts.append(n)
        converged.append(rested)
        timings[f"flow level {k}"] = time.perf_counter() - t0
    out = (phi < 0) | R
    out &= F
    if r > _SLACK_RADIUS:
        out = _drop_slack_parts(out, R, F)
    curves = None
    if finish == "mpp":
        t0 = time.perf_counter()
        out, curves = mpp_finish(out, R, F, core_sd=sd_R, anticore_sd=sd_A, return_curves=True)
        timings["finish"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start
    budget = "until rest" if iterations is None else (
        "the paper's 100 steps a level" if iterations == 100 else f"{int(iterations)} steps a level")
    if not all(converged):
        late = [levels - 1 - i for i, ok in enumerate(converged) if not ok]
        warnings.warn(f"raster.tighten: the flow did not rest within {budget} at level(s) "
                      f"{', '.join(map(str, late))} (0 = full resolution); the result is not converged",
                      NotConvergedWarning, stacklevel=2)
    return RasterTightening(mask=out, phi=phi, core=R, fillet=F, r=r, init=init, levels=levels,
                            iterations=counts, timings=timings, converged=converged, budget=budget,
                            finish=finish, curves=curves)
