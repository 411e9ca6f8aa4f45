"""PNG masks: reading with a documented threshold, writing atomically."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from ._checks import check_mask

__all__ = ["load_mask", "save_mask"]


def load_mask(path, threshold: float = 0.5, *, invert: bool = False) -> np.ndarray:
    """Read an image as a mask: True where the pixel is lighter than ``threshold``.

    The image is converted to grey levels in [0, 1] (colour by luminance; an image with transparency
    uses its alpha channel instead, so a drawn shape on a transparent background reads as itself). A pixel
    is True (inside) when its level is ≥ ``threshold``; ``invert=True`` swaps inside and outside, for
    dark shapes on a light background.

    Parameters
    ----------
    path : str or Path
    threshold : float
        In (0, 1]; default ½.
    invert : bool

    Returns
    -------
    (H, W) ndarray of bool

    Raises
    ------
    ValueError
        If the file is not an image Pillow can read, or the threshold is outside (0, 1].

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> m = np.zeros((4, 6), bool); m[1:3, 2:5] = True
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_mask(pathlib.Path(d) / "m.png", m)
    ...     bool((load_mask(pathlib.Path(d) / "m.png") == m).all())
    True
    """
    from PIL import Image, UnidentifiedImageError

    if not (0.0 < float(threshold) <= 1.0):
        raise ValueError(f"threshold must be in (0, 1], got {threshold!r}")
    path = Path(path)
    try:
        with Image.open(path) as img:
            img.load()
            has_alpha = img.mode in ("RGBA", "LA", "PA") or (img.mode == "P" and "transparency" in img.info)
            if has_alpha:
                alpha = np.asarray(img.convert("RGBA"))[:, :, 3]
                if alpha.min() < 255:
                    level = alpha / 255.0
                else:
                    level = np.asarray(img.convert("L")) / 255.0
            elif img.mode in ("1", "L", "P", "RGB", "CMYK", "YCbCr"):
                level = np.asarray(img.convert("L")) / 255.0
            else:   # 16-bit and float greys
                a = np.asarray(img, dtype=float)
                level = a / a.max() if a.max() > 0 else a
    except UnidentifiedImageError:
        raise ValueError(f"{path}: not an image file that can be read") from None
    except OSError as exc:
        if isinstance(exc, (FileNotFoundError, PermissionError, IsADirectoryError)):
            raise
        raise ValueError(f"{path}: malformed image ({exc})") from None
    mask = level >= float(threshold)
    return ~mask if invert else mask


def save_mask(path, mask) -> None:
    """Write a mask as a black-and-white PNG (white inside), through a temporary file and a rename.

    Parameters
    ----------
    path : str or Path
        The folder must exist; an existing file is replaced only once the new one is complete.
    mask : (H, W) array of bool

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_mask(pathlib.Path(d) / "m.png", np.eye(3, dtype=bool))
    ...     sorted(p.name for p in pathlib.Path(d).iterdir())
    ['m.png']
    """
    from PIL import Image

    m = check_mask(mask)
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(2, "output folder does not exist", str(path.parent))
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".png")
    os.close(fd)
    try:
        Image.fromarray(np.where(m, 255, 0).astype(np.uint8), mode="L").save(tmp, format="PNG")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
