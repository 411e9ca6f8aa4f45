"""The paper's morphology on binary images, through exact Euclidean distance transforms.

Pixel-square semantics. A mask stands for the union S of its True pixels' closed unit squares, centred on
the integer grid. Distances between centres
come exactly from `scipy.ndimage.distance_transform_edt` (squared distances are integers, so no rounding
can break a relation). With ``d(p, X)`` the distance between centres from pixel p to the nearest pixel
of X:

* ``grow(M, r)``   = {p : d(p, M) < r + ½}     (the paper's S↑r: p's centre within r of M's squares)
* ``shrink(M, r)`` = {p : d(p, ¬M) ≥ r + ½}    (S↓r: the disk of radius r at p's centre misses ¬M's squares)

The half pixel is the distance from a centre to its square's edge: along rows and columns these are exact
(a bar 2r − 1 pixels wide, measured between centres, would otherwise hold a disk of radius r and survive
one pixel more than it should); diagonally the true distance to a square is up to 0.21 px less.

**The core keeps parts exactly 2r wide (the paper's closed shrink).** The core R_r(S) is the union of
the open disks of radius r inside S, and the shrink is closed (distance ≥ r from ¬S), so a bar of S
exactly 2r wide holds a row of such disks and is core. A bar of a mask is a whole number w of pixels
wide, so its centre line lies on pixel centres when w is odd and on pixel *edges* when w is even: at a
whole radius r, the disks that fit a 2r-wide bar are centred on pixel edges and corners, never on
centres, and ``grow(shrink(M))`` (which only tries disks at centres) loses the bar. The core therefore
takes the disks of both families:

* a disk centred on a pixel centre c is, on pixels, {p : |p − c| < r + ½} (the pixels whose squares
  it meets, exactly along rows and columns); it fits where ``shrink(M, r)`` holds c, and these disks
  make the opening ``grow(shrink(M))``;
* a disk centred on a pixel corner k meets the square of pixel q exactly when q lies within r of one of
  the four pixels around k (per axis, the gap from k to q's square is the gap from q to the nearest of
  those four pixels' centres), so on pixels it is {p : |p − b| < r for one of k's four pixels b}, with
  no approximation: it fits M exactly when all four have ``d(·, ¬M) ≥ r``.

A pixel disk fits when all its pixels are True, and ``core`` is the union of the fitting ones of both
families: a union of openings, itself an opening (increasing, ``core ⊆ M``, idempotent). A pixel is core
when its square meets a disk of radius r that fits S (for corner-centred disks exactly; for pixel-centred
ones up to the half-pixel rule's diagonal error).
Along rows and columns it is exact at every radius: a bar (or a staircase step) w pixels wide is core
exactly when w ≥ 2r, so at a whole radius a stroke of 2r pixels is kept and one of 2r − 1 is not.
``fillet(M) = ¬core(¬M)``: a gap exactly 2r wide is anticore. ``mortar`` = fillet ∧ ¬core,
``anticore`` = ¬fillet.

Hence ``core ⊆ M ⊆ fillet`` holds exactly and every operation is dual to its partner under complement:
``shrink(¬M) = ¬grow(M)`` and ``core(¬M) = anticore(M)``, pixel for pixel.

The image border: pixels beyond the image are taken to repeat the nearest border pixel (edge
replication), so a shape that touches the border is not eroded there and complementing the image commutes
with every operation. Results have the input's shape.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from ._checks import check_mask, check_radius

__all__ = ["anticore", "core", "fillet", "fillet_round", "grow", "mason", "mortar", "round_fillet",
           "shrink"]


#: Largest padded image (pixels) the morphology builds: a radius much larger than the image would pad it
#: by the radius on every side (a 100 × 100 mask at r = 10⁵ asks for 1.6·10¹¹ pixels).
MAX_PADDED_PIXELS = 4 * 8192 * 8192


def _pad(mask: np.ndarray, r: float, passes: int) -> tuple[np.ndarray, int]:
    """Edge-replicated padding wide enough for ``passes`` operations of radius r.

    For an opening (``passes=2``) of a mask whose True pixels all lie at least ``ceil(r) + 2`` pixels from
    every border, ``ceil(r) + 2`` is enough, with the same result on the image, pixel for pixel: beyond the
    image every pixel is False and every pixel farther than r + ½ from the True ones (the border's own
    pixels among them) is a centre of the complement's shrink, so the nearest such centre to an image
    pixel, and every disk that reaches it, is found within the narrower frame (a point beyond it is
    never nearer than its projection onto the frame's edge, itself such a centre), and every corner
    where a disk fits lies farther from the frame's edge than `_opening`'s box reaches.
    """
    return _pad_by(mask, r, _pad_width(mask, r, passes))


def _pad_width(mask: np.ndarray, r: float, passes: int) -> int:
    """`_pad`'s width, pixels."""
    p = passes * math.ceil(r) + 1
    if passes == 2 and mask.any():
        k = math.ceil(r) + 2
        rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
        h, w = mask.shape
        if rows[0] >= k and cols[0] >= k and rows[-1] <= h - 1 - k and cols[-1] <= w - 1 - k:
            p = min(p, k)
    return p


def _pad_by(mask: np.ndarray, r: float, p: int) -> tuple[np.ndarray, int]:
    """``mask`` edge-replicated by p pixels on every side (refused beyond `MAX_PADDED_PIXELS`)."""
    h, w = mask.shape
    if (h + 2 * p) * (w + 2 * p) > MAX_PADDED_PIXELS:
        raise ValueError(f"r = {r:g} px is too large for this {h} × {w} mask: its morphology would pad it to "
                         f"{(h + 2 * p) * (w + 2 * p):.3g} pixels (limit {MAX_PADDED_PIXELS:,}); a mask "
                         "that touches the image border continues beyond it, so r must stay within the "
                         "limit")
    return np.pad(mask, p, mode="edge"), p


def vanishes(M: np.ndarray, r: float) -> bool:
    """Whether no pixel disk of radius ``r`` fits in the mask's box and the mask stays off the border.

    The padding continues the border pixels outward; a mask with no True pixel on the border is
    surrounded by background. Then a disk of radius r inside the mask, or an enclosed one outside it,
    needs ``2r`` at most the larger side of the box of True pixels: beyond that the core, the enclosed
    anticore and every tightening are empty.
    """
    if M[0].any() or M[-1].any() or M[:, 0].any() or M[:, -1].any():
        return False
    rows, cols = np.flatnonzero(M.any(axis=1)), np.flatnonzero(M.any(axis=0))
    if not len(rows):
        return True
    return 2.0 * r > max(rows[-1] - rows[0], cols[-1] - cols[0]) + 2


def _hull(M: np.ndarray) -> np.ndarray:
    """Pixels whose centres lie in the convex hull of the True pixels' squares (the fillet as r → ∞)."""
    import shapely

    rows, cols = np.nonzero(M)
    corners = np.concatenate([np.column_stack([cols + dx, rows + dy])
                              for dx in (-0.5, 0.5) for dy in (-0.5, 0.5)])
    hull = shapely.convex_hull(shapely.multipoints(corners))
    yy, xx = np.mgrid[0:M.shape[0], 0:M.shape[1]]
    return shapely.contains_xy(hull, xx.ravel(), yy.ravel()).reshape(M.shape) | M


def _crop(a: np.ndarray, p: int) -> np.ndarray:
    return a[p:-p, p:-p]


def _edt_squared(mask: np.ndarray) -> np.ndarray:
    """Squared distance from every True pixel of ``mask`` to the nearest False pixel (0 on False pixels),
    as whole numbers: `scipy.ndimage.distance_transform_edt`'s feature transform, with the squared
    distances summed in integers rather than in float64 (a third less time on a million pixels; the
    square root of the result is ``distance_transform_edt(mask)`` bit for bit). ``mask`` must hold at
    least one False pixel."""
    ft = ndimage.distance_transform_edt(mask, return_distances=False, return_indices=True)
    h, w = mask.shape
    if h * h + w * w >= 2 ** 31:
        ft = ft.astype(np.int64)
    dy, dx = ft[0], ft[1]
    dy -= np.arange(h, dtype=dy.dtype)[:, None]
    dx -= np.arange(w, dtype=dx.dtype)[None, :]
    np.multiply(dy, dy, out=dy)
    np.multiply(dx, dx, out=dx)
    dy += dx
    return dy


def _edt(mask: np.ndarray) -> np.ndarray:
    """``scipy.ndimage.distance_transform_edt(mask)``, the same values (float64), faster (`_edt_squared`)."""
    mask = np.asarray(mask, dtype=bool)
    if mask.all():
        return ndimage.distance_transform_edt(mask)
    return np.sqrt(_edt_squared(mask), dtype=np.float64)


def _dist_to(mask: np.ndarray) -> np.ndarray:
    """Distance from every pixel to the nearest True pixel of ``mask`` (inf if there is none)."""
    if not mask.any():
        return np.full(mask.shape, np.inf)
    return _edt(~mask)


def _grow(M: np.ndarray, r: float) -> np.ndarray:
    return _dist_to(M) < r + 0.5


def _shrink(M: np.ndarray, r: float) -> np.ndarray:
    return _dist_to(~M) >= r + 0.5


#: Relative precision of a tie: a distance within this fraction of r of it counts as r (squared distances
#: between centres are integers, so a true tie is exact and any other value is far from it).
_TIE = 1e-12


def _corner_disk(r: float) -> tuple[np.ndarray, int]:
    """The pixel disk of radius r about a corner: ``disk[a + n − 1, b + n − 1]`` for the pixel offset
    (a, b), a, b in −n + 1 … n, from the pixel whose bottom-right corner it is (the corner lies at
    (½, ½) from it)."""
    n = max(math.ceil(r), 1)
    off = np.arange(-n + 1, n + 1) - 0.5
    return (off[:, None] ** 2 + off[None, :] ** 2 < (r * (1.0 - _TIE)) ** 2), n


def _fft_count(src: np.ndarray, kernel: np.ndarray, n: int, *, spread: bool) -> np.ndarray:
    """For each pixel k, how many True pixels of ``src`` lie at k + o for the kernel's offsets o
    (``spread=False``, a correlation), or how many True pixels k of ``src`` have the pixel at k + o
    (``spread=True``, a convolution); offsets as in `_corner_disk`. Counted by FFT, rounded."""
    from scipy import fft      # not scipy.signal's fftconvolve: importing scipy.signal takes a second or more

    k = kernel.astype(np.float32)
    if not spread:
        k = k[::-1, ::-1]
    h, w = src.shape
    shape = (fft.next_fast_len(h + k.shape[0] - 1, real=True), fft.next_fast_len(w + k.shape[1] - 1, real=True))
    full = fft.irfft2(fft.rfft2(src.astype(np.float32), shape) * fft.rfft2(k, shape), shape)
    lo = n - 1 if spread else n
    return np.rint(full[lo:lo + h, lo:lo + w])


def _box(sel: np.ndarray, margin: int) -> tuple[slice, slice]:
    rows, cols = np.flatnonzero(sel.any(axis=1)), np.flatnonzero(sel.any(axis=0))
    return (slice(max(rows[0] - margin, 0), rows[-1] + margin + 1),
            slice(max(cols[0] - margin, 0), cols[-1] + margin + 1))


def _opening(P: np.ndarray, r: float, parts: bool = False):
    """The core of a (padded) mask: the union of its openings by the pixel disks of radius r centred on
    pixel centres and on pixel corners (see the module's docstring).

    With ``parts``, returns ``(core, core_c, sd)``: the core, its pixel-centred part
    ``grow(shrink(P))``, and a signed distance to the core's sub-pixel edge, pixels (negative on the
    core): the distance to the nearest disk centre less the disk's radius, r + ½ for a pixel-centred
    disk (its pixels are those whose squares it meets: on a straight edge the edge lies half-way between
    pixels, as for squares) and r for a corner-centred one (exact). Where a digital arc leaves a lone
    stair pixel whose centre the arc barely covers, this puts the edge just past that centre, not half a
    pixel past it."""
    d = _dist_to(~P)
    centre = d >= r + 0.5
    dc = _dist_to(centre)
    out = dc < r + 0.5
    core_c = out.copy() if parts else None
    fits, box = _corner_fits(P, r, d, centre)
    if fits is not None:
        disk, n = _corner_disk(r)
        covered = _fft_count(fits, disk, n, spread=True) > 0
        out[box] |= covered
    if not parts:
        return out
    sd = (dc - (r + 0.5)).astype(np.float32)
    if fits is not None:
        # Only near the edge (deeper in, the pixel-centred disks' depth is as good: Φ there is far from
        # the front and the traced edges never reach it), and beyond two pixels outside the pixel-centred
        # disks only near the corner-centred ones: every use of the distance clips it to ±2 or reads it on
        # the core alone, and a pixel whose nearest fitting corner is within r + 2 lies within 3.5 px of a
        # pixel that corner's disk covers (the chessboard reach of 4 below).
        sub = sd[box]
        reach = ndimage.maximum_filter(covered, size=2 * _CORNER_REACH + 1, mode="constant")
        near = np.flatnonzero(((sub > -2.0) & ((sub <= 2.0) | reach)).ravel())
        flat = sub.ravel()
        flat[near] = np.minimum(flat[near], _dist_to_corners(fits, near) - r)
        sd[box] = flat.reshape(sub.shape)
    # Ties and the nearest-corner search aside, the sign already agrees with the core; make it certain.
    sd = np.where(out, np.minimum(sd, -0.02), np.maximum(sd, 0.02)).astype(np.float32)
    return out, core_c, sd


#: Chessboard reach (pixels) around the corner-centred disks' pixels within which `_opening` finds the
#: distance to the nearest fitting corner (see there).
_CORNER_REACH = 4


def _corner_fits(P, r, d, centre):
    """The corner-centred disks of radius r that fit P and that the pixel-centred ones do not already
    cover, as an array over a box of P (``fits[i, j]``: the corner at the bottom-right of pixel (i, j) of
    the box), and the box; (None, None) if there are none."""
    # The open disk of radius r about the corner at the bottom-right of pixel (i, j) meets a pixel's square
    # exactly when the pixel lies within r of one of the corner's four pixels (i, j), (i + 1, j),
    # (i, j + 1), (i + 1, j + 1): it fits S when all four are at least r from every outside pixel. Where all
    # four are pixel-centred disk centres, their disks cover the corner's (a pixel within r of the corner
    # is within r + ½ of the nearest of the four), so those are skipped.
    def four(a: np.ndarray) -> np.ndarray:
        q = np.zeros_like(a)
        q[:-1, :-1] = a[:-1, :-1] & a[1:, :-1] & a[:-1, 1:] & a[1:, 1:]
        return q

    fits = four(d >= r * (1.0 - _TIE)) & ~four(centre)
    if not fits.any():
        return None, None
    n = max(math.ceil(r), 1)
    box = _box(fits, n + 1)
    return fits[box], box


def _dist_to_corners(fits: np.ndarray, where: np.ndarray) -> np.ndarray:
    """Distance from the pixel centres of ``where`` (flat indices) to the nearest corner of ``fits`` (as
    in `_corner_fits`), exact: a k-d tree of the corners, queried at those pixels only (the fitting
    corners line the core's edge and ``where`` is a band along it, so this is a few tens of thousands of
    points where a feature transform would cover the whole box)."""
    from scipy.spatial import cKDTree

    fi, fj = np.nonzero(fits)
    ii, jj = np.unravel_index(where, fits.shape)
    tree = cKDTree(np.column_stack([fi + 0.5, fj + 0.5]))
    best, _ = tree.query(np.column_stack([ii, jj]).astype(float))
    return best


def grow(mask, r):
    """Pixels whose centre is closer than ``r`` to a True pixel's square (the paper's S↑r).

    Parameters
    ----------
    mask : (H, W) array of bool
        The shape; True inside.
    r : float
        Radius in pixels, > 0.

    Returns
    -------
    (H, W) ndarray of bool

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((5, 5), bool); m[2, 2] = True
    >>> int(grow(m, 1.5).sum())       # the pixel, its 8 neighbours (1, √2) but not the next ring (2)
    9
    """
    M = check_mask(mask)
    r = check_radius(r)
    P, p = _pad(M, r, 1)
    return _crop(_grow(P, r), p)


def shrink(mask, r):
    """Pixels where a disk of radius ``r`` at the centre misses every False pixel's square (S↓r).

    Parameters
    ----------
    mask : (H, W) array of bool
    r : float
        Radius in pixels, > 0.

    Returns
    -------
    (H, W) ndarray of bool

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((9, 9), bool); m[1:8, 1:8] = True
    >>> int(shrink(m, 2).sum())       # a 7 × 7 square: 2.5 px from each side leaves the 3 × 3 centre
    9
    """
    M = check_mask(mask)
    r = check_radius(r)
    P, p = _pad(M, r, 1)
    return _crop(_shrink(P, r), p)


def _core_fillet_both(M: np.ndarray, r: float):
    """``(core, fillet, core_c, fillet_c, sd_core, sd_anticore)``: `_core_fillet`; the same with
    pixel-centred disks only (a smaller core and anticore; `tighten` gives its coarse levels these looser
    constraints); and the signed distances to the core's and the anticore's sub-pixel edges (negative
    inside each, see `_opening`)."""
    if vanishes(M, r):
        R, F = _core_fillet(M, r)
        return R, F, R, F, np.where(R, -0.5, 0.5).astype(np.float32), np.where(F, 0.5, -0.5).astype(np.float32)
    pc, pa = _opening_pads(M, r)
    P, p = _pad_by(M, r, pc)
    R, Rc, dR = _opening(P, r, parts=True)
    R, Rc, dR = _crop(R, p), _crop(Rc, p), _crop(dR, p)
    P, p = _pad_by(~M, r, pa)
    A, Ac, dA = _opening(P, r, parts=True)
    return R, _crop(~A, p), Rc, _crop(~Ac, p), dR, _crop(dA, p)


def _opening_pads(M: np.ndarray, r: float) -> tuple[int, int]:
    """The padding (pixels) `_core_fillet_both` gives the mask for its core and for its anticore.

    `_pad`'s for an opening, unless every border pixel has one value. Say False: edge replication then
    surrounds the image with False pixels, and

    * the core needs one pixel of frame: a disk that fits the mask lies inside it, and the border's own
      False pixels are nearer to every True pixel than any pixel beyond them;
    * the anticore needs ``ceil(r) + 2``, as in `_pad`: every frame pixel at depth r + ½ or more is a
      centre of the complement's shrink (it is at least that far from every True pixel), so the nearest
      centre to an image pixel lies within the frame (a point beyond it is never nearer than its
      projection onto the frame's edge); a corner where a disk fits and the centres do not cover has a
      pixel nearer than r + ½ to the mask, so its four pixels lie within depth ``ceil(r) + 1``; the
      nearest such corner to an image pixel is found exactly (`_dist_to_corners`); a disk's pixels
      beyond the frame are beyond the image.

    The result on the image is the same, pixel for pixel, as with the full padding. True: the same with
    the roles exchanged.
    """
    p = _pad_width(M, r, 2)
    border = np.concatenate([M[0], M[-1], M[:, 0], M[:, -1]])
    if not border.any():
        return 1, min(p, math.ceil(r) + 2)
    if border.all():
        return min(p, math.ceil(r) + 2), 1
    return p, p


def _core_fillet(M: np.ndarray, r: float) -> tuple[np.ndarray, np.ndarray]:
    if vanishes(M, r):
        # The core is empty at once; the fillet as usual while padding is affordable, else its r → ∞
        # limit, the convex hull.
        p = 2 * math.ceil(r) + 1
        if (M.shape[0] + 2 * p) * (M.shape[1] + 2 * p) > MAX_PADDED_PIXELS:
            return np.zeros_like(M), _hull(M)
        P, p = _pad(M, r, 2)
        return np.zeros_like(M), _crop(~_opening(~P, r), p)
    P, p = _pad(M, r, 2)
    return _crop(_opening(P, r), p), _crop(~_opening(~P, r), p)


def core(mask, r):
    """The core R_r(M) = grow(shrink(M)): the union of the pixel disks of radius r that fit in M.

    Parameters
    ----------
    mask : (H, W) array of bool
    r : float
        Radius in pixels, > 0.

    Returns
    -------
    (H, W) ndarray of bool, a subset of ``mask``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((40, 40), bool); m[5:35, 5:35] = True; m[18:21, 35:39] = True   # a square with a stub
    >>> c = core(m, 4)
    >>> bool((c <= m).all()), bool(c[19, 36]), bool(c[19, 19])     # the stub is too thin to keep
    (True, False, True)
    """
    M = check_mask(mask)
    r = check_radius(r)
    P, p = _pad(M, r, 2)
    return _crop(_opening(P, r), p)


def fillet(mask, r):
    """The fillet F_r(M) = shrink(grow(M)): M with its gaps and concave corners filled at radius r.

    Parameters
    ----------
    mask : (H, W) array of bool
    r : float
        Radius in pixels, > 0.

    Returns
    -------
    (H, W) ndarray of bool, a superset of ``mask``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((30, 30), bool); m[5:25, 5:25] = True; m[14:16, 8:22] = False   # a 2-px crack
    >>> bool(fillet(m, 3)[14, 15])
    True
    """
    M = check_mask(mask)
    r = check_radius(r)
    P, p = _pad(M, r, 2)
    return _crop(~_opening(~P, r), p)


def mortar(mask, r):
    """The mortar M_r = fillet ∧ ¬core: where a tightening may differ from the input.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20), bool); m[4:16, 4:16] = True
    >>> mo = mortar(m, 5)
    >>> bool(mo[4, 4]), bool(mo[10, 10])      # a corner is mortar, the middle is core
    (True, False)
    """
    M = check_mask(mask)
    r = check_radius(r)
    R, F = _core_fillet(M, r)
    return F & ~R


def anticore(mask, r):
    """The anticore ¬F_r(M): pixels that no tightening contains.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20), bool); m[4:16, 4:16] = True
    >>> bool(anticore(m, 3)[0, 0]), bool(anticore(m, 3)[10, 10])
    (True, False)
    """
    return ~fillet(mask, r)


def round_fillet(mask, r):
    """R∘F: the core of the fillet (biased to add material where there is detail).

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20), bool); m[4:16, 4:16] = True
    >>> bool((round_fillet(m, 3) == core(m, 3)).all())    # a square has no concave detail
    True
    """
    return core(fillet(mask, r), r)


def fillet_round(mask, r):
    """F∘R: the fillet of the core (biased to remove material where there is detail).

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20), bool); m[4:16, 4:16] = True
    >>> bool((fillet_round(m, 3) <= m).all())
    True
    """
    return fillet(core(mask, r), r)


def mason(mask, r):
    """The self-dual Mason filter: each mortar component takes R∘F or F∘R, whichever differs less from M.

    Components are 8-connected. Where the two choices differ equally from M, the component keeps M itself,
    so that ``mason(¬M) = ¬mason(M)`` exactly.

    Parameters
    ----------
    mask : (H, W) array of bool
    r : float
        Radius in pixels, > 0.

    Returns
    -------
    (H, W) ndarray of bool

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((30, 30), bool); m[5:25, 5:25] = True
    >>> bool((mason(m, 3) == ~mason(~m, 3)).all())
    True
    """
    M = check_mask(mask)
    r = check_radius(r)
    R, F = _core_fillet(M, r)
    RF = core(F, r)
    FR = fillet(R, r)
    labels, n = ndimage.label(F & ~R, structure=np.ones((3, 3), bool))
    if n == 0:
        return M.copy()
    d_rf = np.bincount(labels.ravel(), weights=(RF ^ M).ravel(), minlength=n + 1)
    d_fr = np.bincount(labels.ravel(), weights=(FR ^ M).ravel(), minlength=n + 1)
    choice = np.where(d_rf < d_fr, 1, np.where(d_fr < d_rf, 2, 0))[labels]
    out = M.copy()
    out[choice == 1] = RF[choice == 1]
    out[choice == 2] = FR[choice == 2]
    out[labels == 0] = M[labels == 0]
    return out
