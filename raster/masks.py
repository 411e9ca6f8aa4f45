"""Masks as image people have them: how an image's values say inside and outside, and how to say it back.

A segmentation mask comes as 0/1 ``uint8``, 0/255, ``bool``, 0/65535 ``uint16``, a float 0/1 array, a
greyscale photo to threshold, or an RGB file whose three channels are equal. `binarize` reads all of
them the way image libraries do, and returns with the mask a `MaskValues` that writes a tightened mask
back in the same shape, dtype and values (`MaskValues.encode`); `tighten_mask` is the two around
`raster.tighten`, in scikit-image's conventions: the image first, r in pixels, an array of the image's
shape and dtype back.

The rules (the same on the command line):

* **No threshold: every non-zero pixel is inside.** The inside value written back is the image's own
  non-zero value (1, 255, 65535, True, 1.0). An integer image with more than one non-zero value is read
  this way too, with a `ManyValuesWarning` (it is probably a label image, for `raster.tighten_labels`, or
  a photo, for a threshold); the inside value is then its largest value. A float image with more than
  one non-zero value is refused: it needs a threshold.
* **A threshold t in (0, 1]: a pixel is inside when its level is ≥ t**, the level being the value over
  the dtype's full scale (255 for ``uint8``, 65535 for ``uint16``, the largest value of any integer
  dtype), the value itself for a float image. Colour images are read by luminance (ITU-R 601, as
  Pillow's ``L``); transparent pixels are first laid on white (as scikit-image's ``rgba2rgb``), so a dark
  drawing on a transparent background is read with ``invert=True``. Written back: 0 outside, the
  full scale inside (1.0 for floats, True for bool).
* **Channels**: an image of shape (H, W, C), C ≤ 4, whose colour channels are all equal and whose alpha
  (if any) is opaque is a grey image stored in colour and is read as grey; any other colour image needs
  a threshold. The result keeps the (H, W, C) shape: grey values in every colour channel, alpha opaque.
* ``invert=True`` swaps inside and outside (dark shapes on a light background): the tightened shape's
  pixels are written with the outside value and the others with the inside value, so the file keeps its
  own two values.
* NaN or infinite pixels, complex or object arrays, and more than three dimensions are refused with a
  `ValueError` naming the problem. A (N, H, W) stack is refused here: tighten each slice.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ._checks import check_radius

__all__ = [
    "EmptyMaskWarning",
    "LostLabelWarning",
    "ManyValuesWarning",
    "MaskValues",
    "MaskWarning",
    "binarize",
    "tighten_mask",
]

#: ITU-R 601 luma weights, as Pillow's ``convert("L")``.
_LUMA = np.array([0.299, 0.587, 0.114])


class MaskWarning(UserWarning):
    """Something about a mask the user should know: the base of the raster package's mask warnings."""


class EmptyMaskWarning(MaskWarning):
    """A mask, a threshold's result, or a tightening has no pixel inside."""


class ManyValuesWarning(MaskWarning):
    """An integer image with more than two values was read as a binary mask (every non-zero pixel in)."""


class LostLabelWarning(MaskWarning):
    """A label of a label image has no pixel left after tightening."""


def _full_scale(dtype: np.dtype):
    """The value that means "all the way on" for ``dtype``: True, the largest integer, or 1.0."""
    if dtype.kind == "b":
        return True
    if np.issubdtype(dtype, np.integer):
        return np.iinfo(dtype).max
    return dtype.type(1.0)


def _check_image(image, name: str) -> np.ndarray:
    a = np.asarray(image)
    if a.dtype == object or np.issubdtype(a.dtype, np.complexfloating) or not (
            a.dtype == bool or np.issubdtype(a.dtype, np.number)):
        raise ValueError(f"{name} must hold numbers or booleans, got dtype {a.dtype}")
    if a.ndim == 3 and not 1 <= a.shape[2] <= 4:
        raise ValueError(f"{name} is a 3-D stack of shape {a.shape}, not a 2-D image; tighten each slice "
                         "(the command line's --stack does)")
    if a.ndim not in (2, 3):
        raise ValueError(f"{name} must be a 2-D image (H, W) or (H, W, channels), got shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"{name} is empty (shape {a.shape})")
    if np.issubdtype(a.dtype, np.floating):
        finite = np.isfinite(a)
        if not finite.all():
            bad = a[~finite].ravel()[0]
            raise ValueError(f"{name} has {'NaN' if np.isnan(bad) else 'infinite'} pixels "
                             f"({int((~finite).sum())} of {a.size})")
    return a


@dataclass(frozen=True)
class MaskValues:
    """How a binary mask is written back in the values, dtype and layout of the image it was read from.

    Attributes
    ----------
    dtype : numpy dtype
        The image's.
    inside, outside : scalar
        The values written for pixels inside and outside the (tightened) mask.
    channels : int
        0 for a plain (H, W) image; else C, the (H, W, C) layout to write (grey in every colour channel,
        alpha opaque).
    threshold : float or None
        The threshold the mask was read with.
    invert : bool
        Whether inside and outside were swapped.
    """

    dtype: np.dtype
    inside: object
    outside: object
    channels: int = 0
    threshold: float | None = None
    invert: bool = False

    def encode(self, mask) -> np.ndarray:
        """The mask in the image's values: ``inside`` where True, ``outside`` elsewhere, same layout.

        Examples
        --------
        >>> import numpy as np
        >>> m, values = binarize(np.array([[0, 255], [255, 0]], np.uint8))
        >>> values.encode(~m)
        array([[255,   0],
               [  0, 255]], dtype=uint8)
        """
        m = np.asarray(mask, dtype=bool)
        out = np.where(m, self.inside, self.outside).astype(self.dtype)
        if self.channels:
            out = np.repeat(out[:, :, None], self.channels, axis=2)
            if self.channels in (2, 4):
                out[:, :, -1] = _full_scale(self.dtype)
        return out


def _as_grey(a: np.ndarray, threshold, name: str) -> tuple[np.ndarray, int, bool]:
    """(grey values, channels, is_colour): channels squeezed where they are all equal and opaque."""
    if a.ndim == 2:
        return a, 0, False
    c = a.shape[2]
    colour = a[:, :, : (1 if c <= 2 else 3)]
    alpha = a[:, :, -1] if c in (2, 4) else None
    opaque = alpha is None or bool((alpha == _full_scale(a.dtype)).all())
    first = colour[:, :, 0]
    equal = c <= 2 or bool(((first == colour[:, :, 1]) & (first == colour[:, :, 2])).all())
    if equal and opaque:
        return a[:, :, 0], c, False
    if threshold is None:
        kind = {2: "grey with transparency", 3: "colour (RGB)", 4: "colour with transparency (RGBA)"}[c]
        raise ValueError(f"{name} is a {kind} image, not a mask: give a threshold to read it by "
                         "luminance (--threshold on the command line)")
    return a, c, True


def _level(a: np.ndarray) -> np.ndarray:
    """Grey level in the units of `binarize`'s threshold: value / full scale (integers), value (floats)."""
    if a.dtype == bool:
        return a.astype(np.float32)
    if np.issubdtype(a.dtype, np.integer):
        return a / float(np.iinfo(a.dtype).max)
    return a.astype(np.float64)


def binarize(image, threshold: float | None = None, *, invert: bool = False,
             name: str = "image") -> tuple[np.ndarray, MaskValues]:
    """Read an image as a binary mask, the way image libraries do, and say how to write one back.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array, C ≤ 4
        bool, integer or float values. Not modified.
    threshold : float in (0, 1], optional
        None (default): every non-zero pixel is inside. Else a pixel is inside when its level (value over
        the dtype's full scale; a float's own value; colour by luminance, transparency laid on white) is
        ≥ ``threshold``. See the module's notes for every rule.
    invert : bool
        Swap inside and outside.
    name : str
        What error messages call the image.

    Returns
    -------
    mask : (H, W) ndarray of bool
    values : MaskValues
        ``values.encode(m)`` writes a mask ``m`` back in the image's shape, dtype and values.

    Raises
    ------
    ValueError
        The threshold is outside (0, 1]; the image has NaN or infinite pixels, is a stack, is colour
        without a threshold, or is a float image with more than one non-zero value and no threshold.

    Warns
    -----
    ManyValuesWarning
        An integer image with more than one non-zero value, read as binary.
    EmptyMaskWarning
        No pixel is inside.

    Examples
    --------
    >>> import numpy as np
    >>> m, values = binarize(np.array([[0, 1, 1], [0, 0, 1]], np.uint8))
    >>> int(m.sum()), int(values.inside), values.dtype
    (3, 1, dtype('uint8'))
    >>> m, values = binarize(np.array([[10, 200]], np.uint8), threshold=0.5)
    >>> m.tolist(), int(values.inside)
    ([[False, True]], 255)
    """
    if threshold is not None:
        t = float(threshold)
        if not 0.0 < t <= 1.0:
            raise ValueError(f"threshold must be in (0, 1] (a share of the full scale), got {threshold!r}")
    a = _check_image(image, name)
    grey, channels, colour = _as_grey(a, threshold, name)
    if threshold is not None:
        if colour:
            c = a.shape[2]
            level = _level(a[:, :, :3]) @ _LUMA if c >= 3 else _level(a[:, :, 0])
            if c in (2, 4):                       # transparent pixels count as white, as if on paper
                alpha = _level(a[:, :, -1])
                level = alpha * level + (1.0 - alpha)
        else:
            level = _level(grey)
        mask = level >= t
        inside, outside = _full_scale(a.dtype), a.dtype.type(0)
        what = f"no pixel reaches the threshold {t:g}"
    else:
        mask = grey != 0
        nonzero = np.unique(grey[mask]) if grey.dtype != bool else np.array([True])
        if len(nonzero) > 1:
            if not np.issubdtype(grey.dtype, np.integer):
                raise ValueError(f"{name} is a float image with {len(nonzero)} non-zero values, not a 0/1 "
                                 "mask: give a threshold (--threshold on the command line)")
            warnings.warn(f"{name} has {len(nonzero) + (not mask.all())} distinct values; read as a binary "
                          "mask (every non-zero pixel inside). A label image is tightened label by label "
                          "with tighten_labels (--labels), a greyscale photo with a threshold (--threshold)",
                          ManyValuesWarning, stacklevel=2)
        inside = nonzero[-1] if len(nonzero) else (True if grey.dtype == bool else grey.dtype.type(1))
        outside = grey.dtype.type(0)
        what = "every pixel is zero"
    if invert:
        mask = ~mask
        inside, outside = outside, inside
    if not mask.any():
        warnings.warn(f"{name}: the mask is empty ({what if not invert else 'no pixel is zero'})",
                      EmptyMaskWarning, stacklevel=2)
    return mask, MaskValues(a.dtype, inside, outside, channels, None if threshold is None else t, invert)


def tighten_mask(image, r, *, threshold: float | None = None, invert: bool = False, init: str = "core",
                 return_result: bool = False, name: str = "image", **flow):
    """The r-tightening of a mask image, returned in the image's shape, dtype and values.

    The image is read by `binarize` (every non-zero pixel inside, unless a ``threshold`` is given),
    tightened by `raster.tighten` (the paper's constrained curvature flow) and written back by
    `MaskValues.encode`: a 0/1 ``uint8`` image gives a 0/1 ``uint8`` image, a 0/65535 ``uint16`` one a
    0/65535 ``uint16`` one, a bool one a bool one.

    Parameters
    ----------
    image : (H, W) or (H, W, C) array
        The mask; see `binarize`. Not modified.
    r : float
        Radius, pixels, > 0.
    threshold : float in (0, 1], optional
    invert : bool
    init : {"core", "input", "mason"}
        The flow's initial set (`raster.tighten`).
    return_result : bool
        Also return the `RasterTightening` (None when the mask is empty or full, which are their own
        tightenings and are returned unchanged).
    name : str
        What warnings and errors call the image.
    **flow
        Passed to `raster.tighten` (``levels``, ``iterations``, ``stop``); its defaults otherwise.

    Returns
    -------
    out : ndarray, the image's shape and dtype
    result : RasterTightening or None
        Only with ``return_result=True``.

    Warns
    -----
    EmptyMaskWarning
        The mask is empty, or the tightening is (every part thinner than 2r).
    ManyValuesWarning
        See `binarize`.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40), np.uint16); img[8:32, 8:32] = 65535
    >>> out = tighten_mask(img, 6)
    >>> out.dtype, out.shape, sorted(np.unique(out).tolist()), int(out[8, 8]), int(out[20, 20])
    (dtype('uint16'), (40, 40), [0, 65535], 0, 65535)
    """
    from .flow import tighten

    r = check_radius(r)
    mask, values = binarize(image, threshold, invert=invert, name=name)
    result = None
    if mask.any() and not mask.all():
        result = tighten(mask, r, init=init, **flow)
        out_mask = result.mask
        if not out_mask.any():
            warnings.warn(f"{name}: the tightening is empty: every part is thinner than 2r = {2 * r:g} px",
                          EmptyMaskWarning, stacklevel=2)
    else:
        out_mask = mask
    out = values.encode(out_mask)
    return (out, result) if return_result else out
