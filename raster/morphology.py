"""The paper's morphological operations on binary images, through exact Euclidean distance transforms.

Pixel-centre semantics
----------------------
A mask is a set of pixels: pixel ``(i, j)`` (row i, column j) is centred at the point ``(j, i)``, and the
boundary of the shape is taken half-way between the centres of a True and a False pixel, as for a shape
rasterised by its pixel centres. So a centre's distance to the shape is its Euclidean distance to the nearest
True centre minus 1/2, and its distance to the complement is the distance to the nearest False centre minus
1/2. Distances are exact (`scipy.ndimage.distance_transform_edt`), in pixels. Beyond the image border every
pixel has the value ``outside`` (False by default: the image is surrounded by background, so the border never
acts as shape). With ``S`` the set of True pixels (Williams & Rossignac, §2.2–2.4):

* grow ``S↑r`` — pixels whose centre is at distance **< r + 1/2** from the centre of a pixel of ``S``;
* shrink ``S↓r`` — pixels whose centre is at distance **≥ r + 1/2** from the centre of every pixel not in
  ``S``; ``shrink(S, r) = ¬grow(¬S, r)`` exactly;
* core ``R_r(S) = S↓r↑r`` (opening), fillet ``F_r(S) = S↑r↓r`` (closing);
* mortar ``M_r(S) = F_r(S) − R_r(S)``, anticore ``¬F_r(S)``.

(Measuring from centre to centre without the half pixel would make every corner arc of the core half a pixel
too tight: the corners of a 240-pixel square lose 1228 pixels at r = 40 instead of (4 − π)r² ≈ 1373; with
the half pixel, 1392.)

The discrete inclusions ``core ⊆ S ⊆ fillet`` hold exactly, pixel for pixel: distances between pixel centres
are square roots of integers, computed the same way on both sides of every comparison. So does duality:
``core(¬S) = ¬fillet(S)`` when ``outside`` is flipped too.

References
----------
J. Williams and J. Rossignac, "Tightening: curvature-limiting morphological simplification", ACM Symposium
on Solid and Physical Modeling, 2005.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage as ndi

from ._validation import check_mask, check_outside, check_radius

__all__ = ["anticore", "core", "fillet", "grow", "mortar", "shrink"]


# ---------------------------------------------------------------------------------------------------------
# Private kernels on padded arrays. The outermost ring of a padded array holds the value that every pixel
# beyond it has too, so the nearest pixel of either kind is always found inside the array.


def _edt(x: np.ndarray) -> np.ndarray:
    """Distance (pixels) from every True pixel of ``x`` to the nearest False pixel centre; 0 on False.

    Returns ``inf`` everywhere when ``x`` has no False pixel (scipy would invent one beyond the border).
    """
    if x.all():
        return np.full(x.shape, np.inf)
    return ndi.distance_transform_edt(x)


# Half a pixel: the boundary of a mask lies half-way between pixel centres.
_HALF = 0.5


def _grow(xp: np.ndarray, r: float) -> np.ndarray:
    """``xp↑r`` on a padded array: pixels at distance < r + 1/2 from a True pixel."""
    return _edt(~xp) < r + _HALF


def _shrink(xp: np.ndarray, r: float) -> np.ndarray:
    """``xp↓r`` on a padded array: pixels at distance ≥ r + 1/2 from every False pixel."""
    return _edt(xp) >= r + _HALF


def _pad_width(r: float) -> int:
    """Padding (pixels) after which a grow-then-shrink (or shrink-then-grow) sees a constant border."""
    return int(math.ceil(r)) + 3


def _pad(mask: np.ndarray, width: int, outside: bool) -> np.ndarray:
    return np.pad(mask, width, mode="constant", constant_values=outside)


def _core_fillet_padded(mp: np.ndarray, r: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Core and fillet of a padded mask, plus the distances used (4 distance transforms).

    Returns ``(core, fillet, d_in, d_out)`` where ``d_in`` is the distance of each pixel of ``mp`` to the
    nearest pixel outside it and ``d_out`` the distance of each pixel outside ``mp`` to the nearest pixel in it.
    """
    d_in = _edt(mp)
    d_out = _edt(~mp)
    shrunk = d_in >= r + _HALF
    grown = d_out < r + _HALF
    core_p = _grow(shrunk, r)
    fillet_p = _shrink(grown, r)
    return core_p, fillet_p, d_in, d_out


def _unpad(xp: np.ndarray, width: int) -> np.ndarray:
    return xp[width:-width, width:-width]


# ---------------------------------------------------------------------------------------------------------
# Public operations.


def grow(mask, r: float, *, outside: bool = False) -> np.ndarray:
    """Grow (dilate) a mask by r pixels: ``S↑r``.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside). Bool, or numbers that are all 0 or 1.
    r : float
        Radius in pixels, positive and finite.
    outside : bool, default False
        Value of every pixel beyond the image border.

    Returns
    -------
    grown : (h, w) ndarray of bool
        Pixels whose centre is at Euclidean distance < r + 1/2 from the centre of a pixel of ``S``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((5, 5), bool); m[2, 2] = True
    >>> grow(m, 1.0).astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 1, 1, 1, 0],
           [0, 0, 0, 0, 0]])
    """
    m = check_mask(mask)
    r = check_radius(r)
    o = check_outside(outside)
    return _unpad(_grow(_pad(m, 1, o), r), 1)


def shrink(mask, r: float, *, outside: bool = False) -> np.ndarray:
    """Shrink (erode) a mask by r pixels: ``S↓r = ¬((¬S)↑r)``.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside).
    r : float
        Radius in pixels, positive and finite.
    outside : bool, default False
        Value of every pixel beyond the image border (False: the border is the edge of the shape).

    Returns
    -------
    shrunk : (h, w) ndarray of bool
        Pixels whose centre is at distance ≥ r + 1/2 from the centre of every pixel not in ``S``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((5, 5), bool); m[1:4, 1:4] = True
    >>> shrink(m, 1.0).astype(int)
    array([[0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 1, 0, 0],
           [0, 0, 0, 0, 0],
           [0, 0, 0, 0, 0]])
    """
    m = check_mask(mask)
    r = check_radius(r)
    o = check_outside(outside)
    return _unpad(_shrink(_pad(m, 1, o), r), 1)


def core(mask, r: float, *, outside: bool = False) -> np.ndarray:
    """Core (rounding, opening) ``R_r(S) = S↓r↑r``: the union of the r-disks (pixel sets) inside S.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside).
    r : float
        Radius in pixels, positive and finite.
    outside : bool, default False
        Value of every pixel beyond the image border.

    Returns
    -------
    core : (h, w) ndarray of bool
        ``grow(shrink(S, r), r)``, computed on an image padded so that the border does not act as shape;
        ``core ⊆ S`` exactly.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((9, 9), bool); m[1:8, 1:8] = True
    >>> c = core(m, 3.0)
    >>> bool(c[4, 4]), bool(c[1, 1]), bool((c & ~m).any())
    (True, False, False)
    """
    m = check_mask(mask)
    r = check_radius(r)
    o = check_outside(outside)
    w = _pad_width(r)
    return _unpad(_grow(_shrink(_pad(m, w, o), r), r), w)


def fillet(mask, r: float, *, outside: bool = False) -> np.ndarray:
    """Fillet (closing) ``F_r(S) = S↑r↓r``: the complement of the r-disks (pixel sets) outside S.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside).
    r : float
        Radius in pixels, positive and finite.
    outside : bool, default False
        Value of every pixel beyond the image border.

    Returns
    -------
    fillet : (h, w) ndarray of bool
        ``shrink(grow(S, r), r)``, computed on an image padded so that the border does not act as shape;
        ``S ⊆ fillet`` exactly.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((9, 9), bool); m[1:8, 1:3] = True; m[1:8, 5:8] = True
    >>> fillet(m, 3.0)[4, 3:5].tolist()   # the 2-pixel gap is filled
    [True, True]
    """
    m = check_mask(mask)
    r = check_radius(r)
    o = check_outside(outside)
    w = _pad_width(r)
    return _unpad(_shrink(_grow(_pad(m, w, o), r), r), w)


def mortar(mask, r: float, *, outside: bool = False) -> np.ndarray:
    """Mortar ``M_r(S) = F_r(S) − R_r(S)``: the pixels a tightening may change.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside).
    r : float
        Radius in pixels, positive and finite.
    outside : bool, default False
        Value of every pixel beyond the image border.

    Returns
    -------
    mortar : (h, w) ndarray of bool
        ``fillet(S, r) & ~core(S, r)``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((12, 12), bool); m[2:10, 2:10] = True
    >>> mo = mortar(m, 3.0)
    >>> bool(mo[2, 2]), bool(mo[5, 5]), bool(mo[0, 0])   # corner, middle, far outside
    (True, False, False)
    """
    m = check_mask(mask)
    r = check_radius(r)
    o = check_outside(outside)
    w = _pad_width(r)
    c, f, _, _ = _core_fillet_padded(_pad(m, w, o), r)
    return _unpad(f & ~c, w)


def anticore(mask, r: float, *, outside: bool = False) -> np.ndarray:
    """Anticore ``¬F_r(S)``: the pixels that stay outside every r-tightening.

    Parameters
    ----------
    mask : (h, w) array_like of bool
        The set ``S`` (True = inside).
    r : float
        Radius in pixels, positive and finite.
    outside : bool, default False
        Value of every pixel beyond the image border.

    Returns
    -------
    anticore : (h, w) ndarray of bool
        ``~fillet(S, r)``; equals ``core(~S, r, outside=not outside)``.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((9, 9), bool); m[2:7, 2:7] = True
    >>> bool(anticore(m, 2.0)[0, 0]), bool(anticore(m, 2.0)[4, 4])
    (True, False)
    """
    return ~fillet(mask, r, outside=outside)
