"""Checks made once at the public boundary of `raster`; code inside the package trusts their results."""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["check_mask", "check_outside", "check_radius"]


def check_radius(r, name: str = "r") -> float:
    """Return ``r`` (pixels) as a float, or raise ValueError unless it is a positive finite number."""
    if isinstance(r, bool) or not isinstance(r, numbers.Real):
        raise ValueError(f"{name} must be a positive finite number of pixels, got {r!r}")
    value = float(r)
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number of pixels, got {r!r}")
    return value


def check_outside(outside) -> bool:
    """Return ``outside`` as a bool (the value of every pixel beyond the image border)."""
    if isinstance(outside, bool | np.bool_):
        return bool(outside)
    if isinstance(outside, numbers.Integral) and int(outside) in (0, 1):
        return bool(outside)
    raise ValueError(f"outside must be True or False (the value beyond the image border), got {outside!r}")


def check_mask(mask, name: str = "mask") -> np.ndarray:
    """Return ``mask`` as a new 2-D bool array, or raise ValueError naming the problem.

    Accepted: bool arrays, and numeric arrays whose values are all 0 or 1. Anything else (other values,
    NaN, strings, 0-size or non-2-D arrays) is refused. The caller's array is never modified, and never
    returned itself (the result is always a fresh copy).
    """
    try:
        a = np.asarray(mask)
    except Exception as exc:  # pragma: no cover - exotic array-likes
        raise ValueError(f"{name} must be a 2-D array of booleans, got {type(mask).__name__}") from exc
    if a.ndim != 2:
        raise ValueError(f"{name} must be a 2-D array, got {a.ndim} dimension(s) with shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"{name} is empty (shape {a.shape}): there are no pixels")
    if a.dtype == np.bool_:
        return a.copy()
    if not (np.issubdtype(a.dtype, np.integer) or np.issubdtype(a.dtype, np.floating)):
        raise ValueError(f"{name} must hold booleans or the numbers 0 and 1, got dtype {a.dtype}")
    binary = (a == 0) | (a == 1)
    if not binary.all():
        bad = a[~binary].ravel()[0]
        raise ValueError(
            f"{name} must be binary (bool, or only the values 0 and 1), but it holds {bad!r}; "
            "threshold it first, e.g. mask > 0.5"
        )
    return a == 1
