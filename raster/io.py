"""Mask and label images on disk: read exactly as stored, written back in the same size, dtype and values.

Formats, by extension:

* **PNG** (``.png``), **BMP** (``.bmp``): read and written with Pillow. PNG holds bool (1-bit), 8- and
  16-bit grey, 8-bit grey + alpha, RGB and RGBA, and palette images; BMP bool, 8-bit grey, RGB and RGBA.
  A palette image's values are its palette indices (as in the PASCAL VOC label PNGs); the palette and
  its transparency are written back.
* **TIFF** (``.tif``, ``.tiff``): read and written with tifffile, any integer, float or bool dtype,
  grey or RGB(A), one page or a stack of pages. Photometric interpretation (``miniswhite`` bilevel
  scans), palette (colormap) and resolution are written back; a compressed input is written back with
  deflate (zlib). A compression tifffile cannot decode without the optional imagecodecs package (LZW,
  JPEG) is decoded by Pillow instead.
* **GIF** (``.gif``) and **JPEG** (``.jpg``, ``.jpeg``): read only (GIF frames are a stack; JPEG is lossy
  and a mask written to it would not keep its values).

Every image is checked against a declared size before it is decoded: at most `MAX_PIXELS` pixels in all
(every page of a stack counted), so a forged header cannot make the reader allocate gigabytes. A
truncated or malformed file raises `ValueError` naming the file and the format. Writers go through a
temporary file in the output's folder and a rename: a failed write leaves no partial file and an
existing one untouched.

How values become a mask and back is `raster.masks` (`binarize`, `MaskValues`); label images are
tightened by `raster.tighten_labels`.
"""

from __future__ import annotations

import logging
import math
import os
import struct
import tempfile
import warnings
import zlib
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ._checks import check_mask

__all__ = [
    "IMAGE_READ_EXTENSIONS",
    "IMAGE_WRITE_EXTENSIONS",
    "MAX_PIXELS",
    "MaskImage",
    "load_mask",
    "read_image",
    "save_mask",
    "write_image",
]

#: Largest number of pixels (width × height × pages) an image may declare: 8192 × 8192.
MAX_PIXELS = 8192 * 8192

_FORMATS = {".png": "png", ".bmp": "bmp", ".tif": "tiff", ".tiff": "tiff", ".gif": "gif", ".jpg": "jpeg",
            ".jpeg": "jpeg"}
#: Extensions `read_image` reads.
IMAGE_READ_EXTENSIONS = tuple(_FORMATS)
#: Extensions `write_image` writes (JPEG and GIF are read only).
IMAGE_WRITE_EXTENSIONS = (".png", ".tif", ".tiff", ".bmp")

# What a Pillow file's failure to decode looks like (beyond the OSError of a missing file).
_DECODE_ERRORS = (OSError, SyntaxError, ValueError, EOFError, struct.error, zlib.error, IndexError,
                  KeyError, TypeError)


@dataclass(frozen=True)
class MaskImage:
    """An image as stored in its file, with what must travel to the file written back.

    Attributes
    ----------
    data : ndarray
        The values exactly as stored: (H, W), (H, W, C) with C ≤ 4 channels, or a stack (N, H, W) or
        (N, H, W, C) of N pages or frames.
    format : {"png", "bmp", "tiff", "gif", "jpeg"}
    stack : bool
        Whether ``data`` is a stack (its first axis the pages).
    palette : tuple of int or None
        Palette images: the RGB palette (Pillow's flat list, or a TIFF colormap flattened).
    transparency : object
        A palette PNG's transparency entry (index or bytes), or None.
    resolution : tuple (x, y, unit) or None
        Pixels per unit, unit "inch" or "cm".
    photometric : str or None
        TIFF only: the photometric interpretation ("minisblack", "miniswhite", "rgb", "palette").
    compressed : bool
        TIFF only: whether the input was compressed (the output then is, with deflate).
    """

    data: np.ndarray
    format: str
    stack: bool = False
    palette: tuple | None = None
    transparency: object = None
    resolution: tuple | None = None
    photometric: str | None = None
    compressed: bool = False

    @property
    def slices(self) -> list[np.ndarray]:
        """The 2-D images (or (H, W, C)) of the file: one, or each page of a stack."""
        return list(self.data) if self.stack else [self.data]

    def with_data(self, data) -> MaskImage:
        """The same file description with other values (of the same layout)."""
        return replace(self, data=np.asarray(data))


def _format_of(path: Path, allowed) -> str:
    ext = path.suffix.lower()
    if ext not in allowed:
        raise ValueError(f"{path}: unsupported image format {ext or '(none)'!r}; expected one of "
                         f"{', '.join(allowed)}")
    return _FORMATS[ext]


class _SizeLimitError(ValueError):
    """A declared size above the limit (kept apart from decoding errors)."""


def _check_size(path: Path, pixels: int, described: str, max_pixels: int) -> None:
    if pixels > max_pixels:
        raise _SizeLimitError(f"{path}: the image declares {described} = {pixels:,} pixels, more than the "
                              f"limit of {max_pixels:,} (raster.io.MAX_PIXELS; pass max_pixels= to raise it)")


def _pil_array(img) -> np.ndarray:
    """The values of one Pillow frame, exactly: bool, uint8, uint16, int32, float32, or uint8 channels."""
    mode = img.mode
    if mode in ("1", "L", "P", "I", "F", "RGB", "RGBA", "LA"):
        return np.asarray(img)
    if mode.startswith("I;16"):
        return np.asarray(img).astype(np.uint16)
    if mode in ("PA",):
        return np.asarray(img.convert("RGBA"))
    return np.asarray(img.convert("RGB"))


def _read_pillow(path: Path, fmt: str, max_pixels: int) -> MaskImage:
    from PIL import Image, ImageSequence, UnidentifiedImageError

    limit = Image.MAX_IMAGE_PIXELS
    try:
        # Pillow's own decompression-bomb check is replaced by ours, made on the declared size.
        Image.MAX_IMAGE_PIXELS = None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            with Image.open(path) as im:
                w, h = im.size
                n = int(getattr(im, "n_frames", 1))
                _check_size(path, w * h * n, f"{w} × {h}" + (f" × {n} frames" if n > 1 else ""), max_pixels)
                frames = []
                for frame in ImageSequence.Iterator(im):
                    frame.load()
                    frames.append(_pil_array(frame))
                palette = tuple(im.getpalette() or ()) if im.mode == "P" else None
                transparency = im.info.get("transparency") if im.mode == "P" else None
                dpi = im.info.get("dpi")
                real = (im.format or "").lower()
    except UnidentifiedImageError:
        raise ValueError(f"{path}: not an image file that can be read (expected {fmt.upper()})") from None
    except (FileNotFoundError, PermissionError, IsADirectoryError):
        raise
    except _SizeLimitError:
        raise
    except _DECODE_ERRORS as exc:
        raise ValueError(f"{path}: malformed {fmt.upper()} ({exc or type(exc).__name__})") from None
    finally:
        Image.MAX_IMAGE_PIXELS = limit
    if len({(f.shape, f.dtype.str) for f in frames}) > 1:
        raise ValueError(f"{path}: its frames differ in size or kind; only stacks of like frames are read")
    data = np.stack(frames) if len(frames) > 1 else frames[0]
    if real == "png" and data.dtype == np.int32 and data.size and data.min() >= 0 and data.max() < 2 ** 16:
        data = data.astype(np.uint16)      # a 16-bit PNG that an older Pillow opened as 32-bit
    resolution = (float(dpi[0]), float(dpi[1]), "inch") if dpi and all(dpi) else None
    return MaskImage(data, fmt if real != "tiff" else "tiff", stack=len(frames) > 1, palette=palette,
                     transparency=transparency, resolution=resolution)


@contextmanager
def _tifffile_log():
    """Collect what tifffile logs (it reports damaged tags on its logger) instead of printing it."""
    logger = logging.getLogger("tifffile")
    records: list[str] = []

    class _Collect(logging.Handler):
        def emit(self, record):
            records.append(record.getMessage())

    handler = _Collect(logging.WARNING)
    old = logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        yield records
    finally:
        logger.removeHandler(handler)
        logger.propagate = old


def _read_tiff(path: Path, max_pixels: int) -> MaskImage:
    import tifffile

    with _tifffile_log() as log:
        try:
            with tifffile.TiffFile(path) as tif:
                if not tif.series:
                    raise ValueError("no image in the file")
                series = tif.series[0]
                shape, axes = tuple(series.shape), series.axes
                page = tif.pages[0]
                pixels = math.prod(n for n, ax in zip(shape, axes) if ax != "S")
                _check_size(path, pixels, " × ".join(map(str, shape)), max_pixels)
                photometric = page.photometric.name.lower() if page.photometric is not None else None
                compressed = int(page.compression) != 1
                colormap = page.colormap
                resolution = None
                unit = getattr(page.resolutionunit, "name", "").lower()
                if unit in ("inch", "centimeter") and all(page.resolution):
                    resolution = (float(page.resolution[0]), float(page.resolution[1]),
                                  "inch" if unit == "inch" else "cm")
                try:
                    data = series.asarray()
                except ValueError as exc:
                    if "imagecodecs" not in str(exc):
                        raise
                    data = None
        except (FileNotFoundError, PermissionError, IsADirectoryError, MemoryError, _SizeLimitError):
            raise
        except Exception as exc:   # tifffile raises many kinds on a damaged file (struct, zlib, its own)
            detail = str(exc) or type(exc).__name__
            if log and detail not in log[0]:
                detail += f"; {log[0]}"
            raise ValueError(f"{path}: malformed TIFF ({detail})") from None
    if data is None:      # a compression only imagecodecs decodes for tifffile: Pillow's libtiff can
        img = _read_pillow(path, "tiff", max_pixels)
        samples = "S" if img.data.ndim - img.stack == 3 else ""
        data, axes = img.data, ("I" if img.stack else "") + "YX" + samples
    data, stack = _normalise_axes(data, axes, path)
    palette = None
    if colormap is not None and photometric == "palette":
        cm = np.asarray(colormap)
        cm = (cm >> 8) if cm.max() > 255 else cm
        palette = tuple(int(v) for v in cm.T.ravel())
    return MaskImage(data, "tiff", stack=stack, palette=palette, resolution=resolution,
                     photometric=photometric, compressed=compressed)


def _normalise_axes(data: np.ndarray, axes: str, path: Path) -> tuple[np.ndarray, bool]:
    """Reorder tifffile's axes to (pages, Y, X, samples) and say whether there are pages."""
    if "Y" not in axes or "X" not in axes:
        raise ValueError(f"{path}: the TIFF's axes {axes!r} hold no 2-D image")
    if "S" in axes and axes.index("S") < axes.index("Y"):        # planar samples: move them last
        data = np.moveaxis(data, axes.index("S"), -1)
        axes = axes.replace("S", "") + "S"
    lead = axes.index("Y")
    if axes[lead:] not in ("YX", "YXS"):
        raise ValueError(f"{path}: unsupported TIFF axes {axes!r}")
    if lead == 0:
        return data, False
    pages = math.prod(data.shape[:lead])
    data = data.reshape((pages,) + data.shape[lead:])
    if pages == 1:
        return data[0], False
    return data, True


def read_image(path, *, max_pixels: int = MAX_PIXELS) -> MaskImage:
    """Read an image file's values exactly as stored (no conversion, no threshold).

    Parameters
    ----------
    path : str or Path
        ``.png``, ``.tif``/``.tiff``, ``.bmp``, ``.gif``, ``.jpg``/``.jpeg``.
    max_pixels : int
        Refuse a file that declares more pixels than this (width × height × pages), before decoding it.

    Returns
    -------
    MaskImage

    Raises
    ------
    ValueError
        Unsupported extension, malformed or truncated file, declared size above ``max_pixels``.
    OSError
        The file is missing or unreadable.

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> labels = np.zeros((4, 5), np.uint16); labels[1:3, 1:4] = 40000
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_image(pathlib.Path(d) / "l.png", labels)
    ...     img = read_image(pathlib.Path(d) / "l.png")
    >>> img.format, img.data.dtype, bool((img.data == labels).all())
    ('png', dtype('uint16'), True)
    """
    path = Path(path)
    fmt = _format_of(path, IMAGE_READ_EXTENSIONS)
    if not path.exists():
        raise FileNotFoundError(2, "No such file or directory", str(path))
    if path.is_dir():
        raise IsADirectoryError(21, "Is a directory", str(path))
    if fmt == "tiff":
        return _read_tiff(path, int(max_pixels))
    return _read_pillow(path, fmt, int(max_pixels))


@contextmanager
def _atomic(path: Path):
    if not path.parent.is_dir():
        raise FileNotFoundError(2, "output folder does not exist", str(path.parent))
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    _PENDING.add(tmp)
    try:  # mkstemp makes the file private; give it the mode of the file it replaces, or the usual one
        umask = os.umask(0o022)
        os.umask(umask)
        os.chmod(tmp, path.stat().st_mode & 0o7777 if path.exists() else 0o666 & ~umask)
    except OSError:
        pass
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        _PENDING.discard(tmp)
        if os.path.exists(tmp):
            os.unlink(tmp)


#: Temporary files being written by `_atomic` in this process (a batch worker being terminated removes
#: them: `vectortighten.io._common.discard_pending`).
_PENDING: set[str] = set()


def _pil_image(a: np.ndarray, fmt: str, like: MaskImage | None):
    from PIL import Image

    where = f"a {fmt.upper()}"
    if a.ndim == 2:
        if a.dtype == bool:
            return Image.fromarray(a)
        if a.dtype == np.uint8:
            img = Image.fromarray(a, mode="P" if like is not None and like.palette else "L")
            if like is not None and like.palette:
                img.putpalette(list(like.palette))
                if like.transparency is not None and fmt == "png":
                    img.info["transparency"] = like.transparency
            return img
        if a.dtype == np.uint16 and fmt == "png":
            return Image.fromarray(a)
    elif a.dtype == np.uint8 and a.shape[2] in ((2, 3, 4) if fmt == "png" else (3, 4)):
        return Image.fromarray(a, mode={2: "LA", 3: "RGB", 4: "RGBA"}[a.shape[2]])
    kinds = "bool, 8- and 16-bit grey, 8-bit colour" if fmt == "png" else "bool, 8-bit grey and 8-bit colour"
    layout = f"{a.shape[2]}-channel " if a.ndim == 3 else ""
    raise ValueError(f"{where} holds {kinds}; this image is {layout}{a.dtype}: write it as .tif")


def write_image(path, data, *, like: MaskImage | None = None) -> None:
    """Write image values to a file exactly (format by extension), atomically.

    Parameters
    ----------
    path : str or Path
        ``.png``, ``.tif``/``.tiff`` or ``.bmp``; the folder must exist.
    data : ndarray
        (H, W), (H, W, C), or a stack (N, H, W[, C]) for TIFF. PNG: bool, uint8, uint16; BMP: bool, uint8.
    like : MaskImage, optional
        The image the values came from: its palette, transparency, resolution, photometric
        interpretation, compression and stack layout are written back.

    Raises
    ------
    ValueError
        The format cannot hold these values (e.g. int32 labels as PNG), or the extension is not writable.
    FileNotFoundError
        The output folder does not exist.
    """
    path = Path(path)
    fmt = _format_of(path, IMAGE_WRITE_EXTENSIONS)
    a = np.asarray(data)
    stack = like.stack if like is not None else a.ndim == 4 or (a.ndim == 3 and a.shape[2] > 4)
    if fmt == "tiff":
        _write_tiff(path, a, like)
        return
    if stack:
        raise ValueError(f"{path}: a stack of {a.shape[0]} images is written as .tif, not {fmt.upper()}")
    img = _pil_image(a, fmt, like)
    options = {}
    if like is not None and like.resolution is not None:
        x, y, unit = like.resolution
        options["dpi"] = (x, y) if unit == "inch" else (x * 2.54, y * 2.54)
    with _atomic(path) as tmp:
        img.save(tmp, format=fmt.upper(), **options)


def _write_tiff(path: Path, a: np.ndarray, like: MaskImage | None) -> None:
    import tifffile

    plain = a.ndim == 2 or (like is not None and like.stack and a.ndim == 3)
    options: dict = {"metadata": None}
    photometric = like.photometric if like is not None else None
    if plain:
        if photometric == "palette" and like.palette and a.dtype in (np.uint8, np.uint16):
            cm = np.asarray(like.palette, dtype=np.uint16).reshape(-1, 3).T * 257
            size = 2 ** (8 * a.dtype.itemsize)
            options["colormap"] = np.pad(cm, ((0, 0), (0, max(0, size - cm.shape[1]))))[:, :size]
            options["photometric"] = "palette"
        else:
            options["photometric"] = "miniswhite" if photometric == "miniswhite" else "minisblack"
    else:
        options["photometric"] = "rgb" if a.shape[-1] in (3, 4) else "minisblack"
        options["planarconfig"] = "contig"
        if a.shape[-1] in (2, 4):
            options["extrasamples"] = ("unassalpha",)
    if like is not None and like.compressed:
        options["compression"] = "zlib"
    if like is not None and like.resolution is not None:
        x, y, unit = like.resolution
        options["resolution"] = (x, y)
        options["resolutionunit"] = "INCH" if unit == "inch" else "CENTIMETER"
    with _atomic(path) as tmp:
        try:
            tifffile.imwrite(tmp, a, **options)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"{path}: cannot write these values as TIFF ({exc})") from None


def load_mask(path, threshold: float | None = None, *, invert: bool = False,
              max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """Read an image file as a binary mask (`raster.binarize`'s rules).

    Without a threshold every non-zero pixel is inside (0/1, 0/255, 0/65535 and bool masks alike); with
    ``threshold`` in (0, 1] a pixel is inside when its grey level (value over the dtype's full scale;
    colour by luminance, transparency laid on white) is ≥ ``threshold``. ``invert=True`` swaps inside and
    outside, for dark shapes on a light background.

    Parameters
    ----------
    path : str or Path
    threshold : float, optional
    invert : bool
    max_pixels : int
        See `read_image`.

    Returns
    -------
    (H, W) ndarray of bool

    Raises
    ------
    ValueError
        Malformed file, a stack, a colour image without a threshold, NaN pixels, threshold outside (0, 1].

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> m = np.zeros((4, 6), np.uint8); m[1:3, 2:5] = 1          # a 0/1 mask, the most common kind
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_image(pathlib.Path(d) / "m.png", m)
    ...     int(load_mask(pathlib.Path(d) / "m.png").sum())
    6
    """
    from .masks import binarize

    img = read_image(path, max_pixels=max_pixels)
    if img.stack:
        raise ValueError(f"{path}: a stack of {img.data.shape[0]} images, not one mask; read it with "
                         "read_image and binarize each slice")
    mask, _ = binarize(img.data, threshold, invert=invert, name=str(path))
    return mask


def save_mask(path, mask, values=None, *, like: MaskImage | None = None) -> None:
    """Write a binary mask to an image file, atomically.

    Parameters
    ----------
    path : str or Path
        ``.png``, ``.tif``/``.tiff`` or ``.bmp``. The folder must exist; an existing file is replaced
        only once the new one is complete.
    mask : (H, W) array of bool
    values : MaskValues, optional
        The values to write (from `raster.binarize` of the image the mask came from); default: 0 outside
        and 255 inside, 8-bit.
    like : MaskImage, optional
        The file the mask came from (palette, resolution, ... written back; see `write_image`).

    Examples
    --------
    >>> import numpy as np, tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     save_mask(pathlib.Path(d) / "m.png", np.eye(3, dtype=bool))
    ...     sorted(p.name for p in pathlib.Path(d).iterdir())
    ['m.png']
    """
    m = check_mask(mask)
    data = values.encode(m) if values is not None else np.where(m, 255, 0).astype(np.uint8)
    write_image(path, data, like=like)
