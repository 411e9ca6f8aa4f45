"""Masks for the pixel method: PNG images read as boolean masks and written back."""

from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np

from vectortighten.errors import InvalidGeometryError

from ._common import MissingDependencyError, atomic_path

__all__ = ["read_mask", "write_mask"]


def read_mask(path, *, threshold: float = 0.5) -> np.ndarray:
    """Read a PNG as a boolean mask with ``raster.load_mask`` (pixels brighter than ``threshold`` are set).

    Raises
    ------
    InvalidGeometryError
        The image cannot be decoded.
    MissingDependencyError
        The ``raster`` package lacks ``load_mask``.
    """
    raster = _raster("load_mask")
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(2, "No such file or directory", str(path))
    try:
        return np.asarray(raster.load_mask(path, threshold=threshold), dtype=bool)
    except (OSError, ValueError, SyntaxError) as exc:
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise InvalidGeometryError(f"{path}: malformed PNG ({exc})") from None


def _raster(*names: str):
    """The ``raster`` package, checked to offer ``names``."""
    try:
        raster = importlib.import_module("raster")
    except ImportError:
        raise MissingDependencyError("PNG masks need the 'raster' package (part of vectortighten)") from None
    missing = [n for n in names if not hasattr(raster, n)]
    if missing:
        raise MissingDependencyError(f"this version of the raster package has no {', '.join(missing)}")
    return raster


def write_mask(mask, path) -> None:
    """Write a boolean mask as a PNG with ``raster.save_mask``, atomically."""
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise ValueError(f"{path}: a mask is written as .png only")
    raster = _raster("save_mask")
    with atomic_path(path) as tmp:
        raster.save_mask(tmp, mask)
