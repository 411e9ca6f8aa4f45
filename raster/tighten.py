"""r-tightening of a binary image by constrained level-set curvature flow (the paper's §3).

Sign convention: ``phi < 0`` inside the evolving set, ``phi > 0`` outside, in pixel units. The flow is
curve-shortening flow, ``phi_t = kappa·|grad phi|`` with ``kappa = div(grad phi / |grad phi|)`` (positive where
the set is convex), so convex parts of the front move inwards and concave parts outwards. (The paper writes
``Phi_t = −F|grad Phi|`` with ``F`` "equal to the curvature"; with its own sign convention, negative inside,
that is the level-set equation ``Phi_t + F|grad Phi| = 0`` with ``F = −kappa``, which is what is done here.)

The flow runs only in the mortar; core pixels are frozen at negative values and anticore pixels at positive
values, so they never change side. It is restricted to a narrow band (chessboard distance 3 around sign
changes, rebuilt when the front reaches the band's outer layers) and to the bounding box of the mortar, and it
runs coarse-to-fine (multiscale) as in the paper.

Every step is odd in ``phi`` (negating ``phi`` and swapping core and anticore negates every intermediate value
exactly in IEEE arithmetic), and exact zeros of ``phi`` are resolved by the input mask, so ``init="input"`` is
self-dual pixel for pixel: ``tighten(~M, r, init="input", outside=True).mask == ~tighten(M, r,
init="input").mask``.
"""

from __future__ import annotations

import enum
import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage as ndi

from ._validation import check_mask, check_outside, check_radius
from .morphology import _core_fillet_padded, _edt, _grow, _pad, _pad_width, _shrink

__all__ = ["Init", "RasterTightening", "tighten"]

# Largest |phi| used anywhere (pixels); keeps infinite distances (empty core) out of the arithmetic.
_PHI_CAP = 1.0e6
# Added to |grad phi|^2 before dividing (pixel units); far below any gradient of a distance function.
_GRAD_EPS = 1.0e-8
# Value to which frozen pixels are clamped after a change of scale (pixels).
_FROZEN = 0.5
# Width of the border ring (pixels, at each level) that never moves; keeps stencils inside the arrays.
_RING = 2


class Init(enum.Enum):
    """Initial condition of the flow."""

    CORE = "core"
    """Start from the core ``R_r(S)`` (the paper's implementation)."""
    INPUT = "input"
    """Start from the input ``S`` (self-dual, §4.2)."""
    MASON = "mason"
    """Start from Mason(S) (self-dual, §4.2)."""


@dataclass(frozen=True, eq=False)
class RasterTightening:
    """Result of `tighten`.

    Attributes
    ----------
    mask : (h, w) ndarray of bool
        The r-tightening (True = inside); ``core ⊆ mask ⊆ fillet`` exactly.
    phi : (h, w) ndarray of float32
        Final level-set function (pixels), negative inside; ``mask == (phi < 0)``.
    core, fillet : (h, w) ndarray of bool
        ``R_r(S)`` and ``F_r(S)`` of the input (see `raster.core`, `raster.fillet`).
    r : float
        Radius in pixels.
    init : Init
        Initial condition used.
    levels : int
        Number of resolution levels (1 = single scale).
    scales : tuple of int
        Downsampling factor of each level, coarsest first (e.g. ``(16, 8, 4, 2, 1)``).
    iterations : tuple of int
        Iterations of flow run at each level, coarsest first.
    rebuilds : tuple of int
        Narrow-band constructions at each level, coarsest first.
    timings : dict of str to float
        Seconds per phase: ``"morphology"`` (core, fillet and the initial set), ``"init"`` (signed distance
        and downsampling), ``"flow x<f>"`` for each level, ``"finish"`` and ``"total"``.
    """

    mask: np.ndarray
    phi: np.ndarray
    core: np.ndarray
    fillet: np.ndarray
    r: float
    init: Init
    levels: int
    scales: tuple[int, ...]
    iterations: tuple[int, ...]
    rebuilds: tuple[int, ...]
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def mortar(self) -> np.ndarray:
        """``fillet & ~core``: where the tightening may differ from the input."""
        return self.fillet & ~self.core

    @property
    def anticore(self) -> np.ndarray:
        """``~fillet``."""
        return ~self.fillet


# ---------------------------------------------------------------------------------------------------------
# Small array helpers.


def _signed_distance(inside: np.ndarray) -> np.ndarray:
    """Signed distance (float32, pixels) to the boundary of a set of pixels, half a pixel off the centres.

    ``-(d_in - 1/2)`` inside and ``d_out - 1/2`` outside, so ``±1/2`` on either side of a boundary; exactly
    negated for the complement.
    """
    d_in = _edt(inside)
    d_out = _edt(~inside)
    phi = np.where(inside, 0.5 - d_in, d_out - 0.5)
    np.clip(phi, -_PHI_CAP, _PHI_CAP, out=phi)
    return phi.astype(np.float32)


def _sign3(phi: np.ndarray) -> np.ndarray:
    """-1, 0 or 1 as int8 (symmetric under negation, unlike ``phi < 0``)."""
    return (phi > 0).view(np.int8) - (phi < 0).view(np.int8)


def _dilate(a: np.ndarray, k: int) -> np.ndarray:
    """Chessboard dilation of a bool array by k pixels (nothing enters from beyond the border)."""
    out = a.copy()
    for s in range(1, k + 1):
        out[:, s:] |= a[:, :-s]
        out[:, :-s] |= a[:, s:]
    rows = out.copy()
    for s in range(1, k + 1):
        out[s:, :] |= rows[:-s, :]
        out[:-s, :] |= rows[s:, :]
    return out


def _block_count(a: np.ndarray, f: int) -> np.ndarray:
    h, w = a.shape
    return a.reshape(h // f, f, w // f, f).sum(axis=(1, 3), dtype=np.int32)


def _block_mean(a: np.ndarray, f: int) -> np.ndarray:
    h, w = a.shape
    return a.reshape(h // f, f, w // f, f).mean(axis=(1, 3), dtype=np.float32)


def _upsample2(a: np.ndarray) -> np.ndarray:
    """Bilinear ×2 upsampling with pixel-centre alignment (edges replicated); odd in ``a``."""

    def along0(x: np.ndarray) -> np.ndarray:
        prev = np.concatenate([x[:1], x[:-1]], axis=0)
        nxt = np.concatenate([x[1:], x[-1:]], axis=0)
        out = np.empty((2 * x.shape[0],) + x.shape[1:], dtype=x.dtype)
        out[0::2] = np.float32(0.75) * x + np.float32(0.25) * prev
        out[1::2] = np.float32(0.75) * x + np.float32(0.25) * nxt
        return out

    return along0(along0(a).T).T.copy()


# ---------------------------------------------------------------------------------------------------------
# The flow at one level.


@dataclass
class _FlowStats:
    iterations: int = 0
    rebuilds: int = 0


def _flow(phi: np.ndarray, movable: np.ndarray, iterations: int, dt: float, tol: float) -> _FlowStats:
    """Constrained curvature flow on ``phi`` (modified in place) where ``movable``, narrow band.

    ``movable`` must be False on the outermost `_RING` pixels. Each step moves the front by at most one
    pixel (``|kappa|`` is limited to ``1/dt``). Stops after ``iterations`` steps, or earlier once the zero level
    moves less than ``tol`` pixels in a step.
    """
    stats = _FlowStats()
    h, w = phi.shape
    p = phi.reshape(-1)
    mov = movable.reshape(-1)
    dt32 = np.float32(dt)
    kmax = np.float32(1.0 / dt)
    eps = np.float32(_GRAD_EPS)
    half, quarter, two = np.float32(0.5), np.float32(0.25), np.float32(2.0)

    def build() -> tuple[np.ndarray, np.ndarray]:
        s = _sign3(phi)
        front = s == 0
        d = s[:, 1:] != s[:, :-1]
        front[:, 1:] |= d
        front[:, :-1] |= d
        d = s[1:, :] != s[:-1, :]
        front[1:, :] |= d
        front[:-1, :] |= d
        near = _dilate(front, 1)
        band = _dilate(near, 2)
        idx = np.flatnonzero(band.reshape(-1) & mov)
        return idx, near.reshape(-1)[idx]

    idx = np.empty(0, np.intp)
    is_near = np.empty(0, bool)
    need_build = True
    while stats.iterations < iterations:
        if need_build:
            idx, is_near = build()
            stats.rebuilds += 1
            need_build = False
            if idx.size == 0:
                break
        c = p[idx]
        e = p[idx + 1]
        wv = p[idx - 1]
        n = p[idx - w]
        s = p[idx + w]
        px = (e - wv) * half
        py = (s - n) * half
        pxx = e - two * c + wv
        pyy = s - two * c + n
        pxy = (p[idx + w + 1] - p[idx + w - 1] - p[idx - w + 1] + p[idx - w - 1]) * quarter
        g2 = px * px + py * py + eps
        num = pxx * (py * py) - two * px * py * pxy + pyy * (px * px)
        g = np.sqrt(g2)
        kappa = num / (g2 * g)
        np.clip(kappa, -kmax, kmax, out=kappa)
        dphi = dt32 * kappa * g
        new = c + dphi
        p[idx] = new
        stats.iterations += 1
        # The front reached the outer layers of the band: rebuild it before the next step.
        far = ~is_near
        if (_sign3(new[far]) != _sign3(c[far])).any():
            need_build = True
        # Early stop: the zero level (pixels next to a sign change) moved less than tol pixels.
        if tol > 0 and not need_build:
            moved = dt32 * np.abs(kappa[is_near])
            if moved.size == 0 or float(moved.max()) < tol:
                break
    return stats


# ---------------------------------------------------------------------------------------------------------
# Initial sets.


def _mason_padded(mp: np.ndarray, core_p: np.ndarray, fillet_p: np.ndarray, r: float) -> np.ndarray:
    """Mason(S) on a padded mask: per 8-connected mortar component, R∘F or F∘R, whichever is nearer S.

    Ties (equal symmetric differences) keep S in that component, which keeps the filter self-dual.
    """
    rf = _grow(_shrink(fillet_p, r), r)  # R(F(S))
    fr = _shrink(_grow(core_p, r), r)  # F(R(S))
    mort = fillet_p & ~core_p
    labels, n = ndi.label(mort, structure=np.ones((3, 3), bool))
    if n == 0:
        return mp.copy()
    lab = labels[mort]
    d_rf = np.bincount(lab, weights=(rf != mp)[mort], minlength=n + 1)
    d_fr = np.bincount(lab, weights=(fr != mp)[mort], minlength=n + 1)
    choice = np.sign(d_rf - d_fr).astype(np.int8)  # -1: RF nearer, 1: FR nearer, 0: tie
    pick = choice[labels]
    out = mp.copy()
    out[mort] = np.where(pick[mort] < 0, rf[mort], np.where(pick[mort] > 0, fr[mort], mp[mort]))
    return out


def _auto_levels(r: float, coarsest_r: float) -> int:
    levels = 1
    while r / 2**levels >= coarsest_r:
        levels += 1
    return levels


# ---------------------------------------------------------------------------------------------------------
# Public entry point.


def tighten(
    mask,
    r: float,
    *,
    init: str | Init = "core",
    levels: int | None = None,
    iterations: int = 100,
    dt: float = 0.25,
    tol: float = 1e-3,
    coarsest_r: float = 2.0,
    outside: bool = False,
) -> RasterTightening:
    """r-tighten a binary image by constrained level-set curvature flow (Williams & Rossignac, §3).

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside): bool, or numbers that are all 0 or 1. Not modified.
    r : float
        Radius in pixels, positive and finite.
    init : {"core", "input", "mason"} or Init, default "core"
        Initial condition: the core ``R_r(S)`` (the paper's implementation), the input ``S`` (self-dual), or
        Mason(S) — in each 8-connected component of the mortar, ``R_r(F_r(S))`` or ``F_r(R_r(S))``, whichever
        differs from ``S`` in fewer pixels there, and ``S`` itself on a tie (self-dual).
    levels : int, optional
        Number of resolution levels. Default: halve the resolution while ``r / 2**k >= coarsest_r`` (r = 40
        gives 5 levels, r = 75 gives 6, as in the paper). ``levels=1`` is single-scale.
    iterations : int, default 100
        Maximum iterations of flow per level (the paper's 100).
    dt : float, default 0.25
        Time step in pixel² units, at most 0.5 (stability of the explicit scheme); curvature is limited to
        ``1/dt`` per pixel so that the front crosses at most one pixel per step.
    tol : float, default 1e-3
        Early stop at a level once the zero level moves less than ``tol`` pixels in one step (0 disables).
    coarsest_r : float, default 2.0
        Smallest radius, in pixels of the coarsest level, used to choose ``levels`` automatically.
    outside : bool, default False
        Value of every pixel beyond the image border (False: the border does not act as shape).

    Returns
    -------
    RasterTightening
        ``mask`` (same shape as the input; ``core ⊆ mask ⊆ fillet`` exactly), ``phi``, ``core``, ``fillet``,
        levels, iterations per level and timings per phase.

    Raises
    ------
    ValueError
        If ``mask`` is not a 2-D binary array, has no pixels, or holds no pixel of the ``outside`` value
        (entirely True by default: the shape is the whole image and its only boundary is the image border;
        pad the image with background first if that is meant). Also for a bad ``r``, ``init``, ``levels``,
        ``iterations``, ``dt`` or ``tol``. An all-background mask gives an empty result, and an ``r`` so
        large that everything vanishes gives an empty mask, not an error.

    Notes
    -----
    Morphology uses exact distance transforms (the paper used Danielsson's approximation). The flow works on
    the bounding box of the mortar plus a margin, in float32. At a coarse level of factor ``f`` a pixel is
    core (anticore) when more than half of its ``f × f`` block is, and ``phi`` is the block mean divided by
    ``f``; going finer, ``phi`` is upsampled bilinearly and doubled, then clamped to ``≤ −1/2`` on core and
    ``≥ 1/2`` on anticore pixels. The final mask is ``phi < 0``, with exact zeros taken from the input, then
    forced between core and fillet (a no-op in practice: frozen pixels never change sign).

    References
    ----------
    J. Williams and J. Rossignac, "Tightening: curvature-limiting morphological simplification", 2005, §3.
    J. A. Sethian, *Level Set Methods and Fast Marching Methods*, Cambridge University Press, 1999.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((40, 40), bool); m[5:35, 5:35] = True
    >>> res = tighten(m, 8.0)
    >>> bool(res.mask[5, 5]), bool(res.mask[20, 20]), int(m.sum() - res.mask.sum()) > 40
    (False, True, True)
    """
    t_start = time.perf_counter()
    m = check_mask(mask)
    r = check_radius(r)
    o = check_outside(outside)
    try:
        init_kind = Init(init.value if isinstance(init, Init) else init)
    except ValueError:
        raise ValueError(f"init must be one of 'core', 'input', 'mason', got {init!r}") from None
    if levels is None:
        n_levels = _auto_levels(r, float(coarsest_r))
    elif isinstance(levels, bool) or not isinstance(levels, int | np.integer) or levels < 1:
        raise ValueError(f"levels must be a positive integer or None, got {levels!r}")
    else:
        n_levels = int(levels)
    if isinstance(iterations, bool) or not isinstance(iterations, int | np.integer) or iterations < 0:
        raise ValueError(f"iterations must be a non-negative integer, got {iterations!r}")
    if not (isinstance(dt, int | float) and 0 < dt <= 0.5):
        raise ValueError(f"dt must be a number in (0, 0.5] (pixels²), got {dt!r}")
    if not (isinstance(tol, int | float) and tol >= 0):
        raise ValueError(f"tol must be a non-negative number of pixels, got {tol!r}")
    if (m == (not o)).all():
        what = "True" if not o else "False"
        raise ValueError(
            f"mask is entirely {what}: the shape fills the whole image and its only boundary is the image "
            "border, so there is nothing to tighten; pad the image with background pixels if that is meant"
        )

    timings: dict[str, float] = {}
    # ---- morphology (on an image padded so that the fillet is exact beyond the border)
    t0 = time.perf_counter()
    pw = _pad_width(r)
    mp = _pad(m, pw, o)
    core_p, fillet_p, d_in, d_out = _core_fillet_padded(mp, r)
    if init_kind is Init.MASON:
        init_p = _mason_padded(mp, core_p, fillet_p, r)
    elif init_kind is Init.CORE:
        init_p = core_p
    else:
        init_p = mp
    mortar_p = fillet_p & ~core_p
    timings["morphology"] = time.perf_counter() - t0

    # ---- initial phi
    t0 = time.perf_counter()
    if init_kind is Init.INPUT:
        phi_p = np.where(mp, 0.5 - d_in, d_out - 0.5)
        np.clip(phi_p, -_PHI_CAP, _PHI_CAP, out=phi_p)
        phi_p = phi_p.astype(np.float32)
    else:
        phi_p = _signed_distance(init_p)
    del d_in, d_out

    scales = tuple(2**k for k in range(n_levels - 1, -1, -1))
    its: list[int] = []
    rebuilds: list[int] = []
    rows = np.flatnonzero(mortar_p.any(axis=1))
    if rows.size:
        cols = np.flatnonzero(mortar_p.any(axis=0))
        fmax = scales[0]
        margin = 2 * fmax + 4
        h_p, w_p = mortar_p.shape
        y0, y1 = max(0, rows[0] - margin), min(h_p, rows[-1] + 1 + margin)
        x0, x1 = max(0, cols[0] - margin), min(w_p, cols[-1] + 1 + margin)
        ch, cw = y1 - y0, x1 - x0
        ph, pwid = (-ch) % fmax, (-cw) % fmax
        # The mortar lies at least 2 pixels inside the padded image; pad the crop to a multiple of the
        # coarsest factor by replicating its edges (frozen pixels there).
        crop = (slice(y0, y1), slice(x0, x1))
        ext = ((0, ph), (0, pwid))
        core_c = np.pad(core_p[crop], ext, mode="edge")
        anti_c = np.pad(~fillet_p[crop], ext, mode="edge")
        phi_c = np.pad(phi_p[crop], ext, mode="edge")
        timings["init"] = time.perf_counter() - t0

        phi_k = None
        for f in scales:
            t0 = time.perf_counter()
            if f == 1:
                core_k, anti_k = core_c, anti_c
            else:
                half_block = f * f / 2
                core_k = _block_count(core_c, f) > half_block
                anti_k = _block_count(anti_c, f) > half_block
            if phi_k is None:
                phi_k = _block_mean(phi_c, f) / np.float32(f) if f > 1 else phi_c.copy()
            else:
                phi_k = _upsample2(phi_k) * np.float32(2.0)
            np.minimum(phi_k, -_FROZEN, out=phi_k, where=core_k)
            np.maximum(phi_k, _FROZEN, out=phi_k, where=anti_k)
            movable = ~(core_k | anti_k)
            movable[:_RING, :] = False
            movable[-_RING:, :] = False
            movable[:, :_RING] = False
            movable[:, -_RING:] = False
            st = _flow(phi_k, movable, iterations, float(dt), float(tol))
            its.append(st.iterations)
            rebuilds.append(st.rebuilds)
            timings[f"flow x{f}"] = time.perf_counter() - t0
        phi_p[crop] = phi_k[:ch, :cw]
    else:
        timings["init"] = time.perf_counter() - t0

    # ---- finish: sign → mask, ties from the input, forced between core and fillet
    t0 = time.perf_counter()
    phi = phi_p[pw:-pw, pw:-pw]
    core_m = core_p[pw:-pw, pw:-pw]
    fillet_m = fillet_p[pw:-pw, pw:-pw]
    out = (phi < 0) | ((phi == 0) & m)
    out = (out | core_m) & fillet_m
    # phi's sign agrees with the mask (only exact ties or forced pixels change, by a tiny amount).
    tiny = np.float32(1e-3)
    phi = np.where(out, np.minimum(phi, -tiny), np.maximum(phi, tiny)).astype(np.float32)
    timings["finish"] = time.perf_counter() - t0
    timings["total"] = time.perf_counter() - t_start
    return RasterTightening(
        mask=out,
        phi=phi,
        core=core_m.copy(),
        fillet=fillet_m.copy(),
        r=r,
        init=init_kind,
        levels=n_levels,
        scales=scales,
        iterations=tuple(its),
        rebuilds=tuple(rebuilds),
        timings=timings,
    )
