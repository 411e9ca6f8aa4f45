"""Argument checks shared by the raster functions: one clear error naming the problem."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["check_mask", "check_radius"]


def check_radius(r, name: str = "r") -> float:
    """``r`` as a float; `ValueError` unless it is a finite number > 0 (pixels)."""
    try:
        value = float(r)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number of pixels, got {type(r).__name__}") from None
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a finite number of pixels > 0, got {r!r}")
    return value


def check_mask(mask, name: str = "mask", *, allow_uniform: bool = True) -> np.ndarray:
    """A boolean copy-free view of ``mask``; refuses what is not a binary 2-D image.

    Accepted: a 2-D array of booleans, or of numbers that are all 0 or 1. Anything else (grey levels,
    NaN, 3-D stacks, empty arrays) raises `ValueError` naming the problem; threshold grey images first,
    or read them with `raster.load_mask`, whose threshold is documented. With ``allow_uniform=False`` an
    all-False or all-True mask is refused too (it has no boundary to tighten).
    """
    a = np.asarray(mask)
    if a.ndim != 2:
        raise ValueError(f"{name} must be a 2-D image, got an array with {a.ndim} dimension(s) {a.shape}")
    if a.size == 0:
        raise ValueError(f"{name} is empty (shape {a.shape})")
    if a.dtype != bool:
        if not (np.issubdtype(a.dtype, np.integer) or np.issubdtype(a.dtype, np.floating)):
            raise ValueError(f"{name} must be boolean or 0/1 numbers, got dtype {a.dtype}")
        if not np.isin(a, (0, 1)).all():
            bad = a[~np.isin(a, (0, 1))].ravel()[0]
            raise ValueError(f"{name} is not binary (found the value {bad!r}); threshold it first, e.g. "
                             f"mask > 0.5, or read it with raster.load_mask")
        a = a.astype(bool)
    if not allow_uniform:
        if not a.any():
            raise ValueError(f"{name} has no True pixel: there is no shape to tighten")
        if a.all():
            raise ValueError(f"{name} is True everywhere: the shape has no boundary to tighten")
    return a
