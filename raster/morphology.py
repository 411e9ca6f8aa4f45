"""The paper's morphology on binary images, through exact Euclidean distance transforms.

Pixel-square semantics. A mask stands for the union of its True pixels' unit squares, centred on the
integer grid. The distance from a pixel's centre to such a union is the distance to the nearest True
pixel's centre less ½ (exact along rows and columns, within 0.21 px diagonally), and distances between
centres come exactly from `scipy.ndimage.distance_transform_edt` (squared distances are integers, so no
rounding can break a relation). With ``d(p, X)`` the distance between centres from pixel p to the nearest
pixel of X:

* ``grow(M, r)``   = {p : d(p, M) < r + ½}     (the paper's S↑r: p's centre within r of M's squares)
* ``shrink(M, r)`` = {p : d(p, ¬M) ≥ r + ½}    (S↓r: the disk of radius r at p's centre misses ¬M's squares)
* ``core``  = grow(shrink(M)),  ``fillet`` = shrink(grow(M)),  ``mortar`` = fillet ∧ ¬core,
  ``anticore`` = ¬fillet.

The half pixel matters: measured between centres, a bar 2r − 1 pixels wide would hold a disk of radius r
and survive the core, one pixel more than it should; a rasterised shape's boundary lies half-way between
its inside and outside pixels, and so does this one's. In particular a part exactly 2r wide has a shrink
of zero width and vanishes, as it does in the exact engine.

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
    """Edge-replicated padding wide enough for ``passes`` operations of radius r."""
    p = passes * math.ceil(r) + 1
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


def _dist_to(mask: np.ndarray) -> np.ndarray:
    """Distance from every pixel to the nearest True pixel of ``mask`` (inf if there is none)."""
    if not mask.any():
        return np.full(mask.shape, np.inf)
    return ndimage.distance_transform_edt(~mask)


def _grow(M: np.ndarray, r: float) -> np.ndarray:
    return _dist_to(M) < r + 0.5


def _shrink(M: np.ndarray, r: float) -> np.ndarray:
    return _dist_to(~M) >= r + 0.5


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


def _core_fillet(M: np.ndarray, r: float) -> tuple[np.ndarray, np.ndarray]:
    if vanishes(M, r):
        # The core is empty at once; the fillet as usual while padding is affordable, else its r → ∞
        # limit, the convex hull.
        p = 2 * math.ceil(r) + 1
        if (M.shape[0] + 2 * p) * (M.shape[1] + 2 * p) > MAX_PADDED_PIXELS:
            return np.zeros_like(M), _hull(M)
        P, p = _pad(M, r, 2)
        return np.zeros_like(M), _crop(_shrink(_grow(P, r), r), p)
    P, p = _pad(M, r, 2)
    return _crop(_grow(_shrink(P, r), r), p), _crop(_shrink(_grow(P, r), r), p)


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
    return _crop(_grow(_shrink(P, r), r), p)


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
    return _crop(_shrink(_grow(P, r), r), p)


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
