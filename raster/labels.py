"""Tightening a label image: every label's region tightened, one label image back.

A label image (a segmentation) gives each pixel an integer: 0 for the background, another value for the
object it belongs to. `tighten_labels` tightens each label's region M_ℓ alone, with `raster.tighten`
(the paper's constrained curvature flow), on a crop of its bounding box grown by 2r + 3 pixels, where it
gives the same result as on the whole image. That yields, for every label, its tightening T_ℓ, its core
R_ℓ and its fillet F_ℓ, with R_ℓ ⊆ T_ℓ ⊆ F_ℓ. Where neighbours touch, the T_ℓ may overlap (a label's
fillet reaches into a neighbour's concavity) or leave a gap (both round a corner where they meet). The
rule that makes one label image of them is symmetric: it looks at distances and at the input, never at
the labels' values.

**The rule.** Let d_ℓ(p) be the signed distance from pixel p to the boundary of T_ℓ (negative inside, in
pixels, ``raster.signed_distance``), and U the union of all labels.

1. A pixel of a label's core R_ℓ takes that label (cores of different labels never overlap).
2. Otherwise the pixel's candidates are the labels whose fillet F_ℓ holds it, and it takes the candidate
   with the smallest d_ℓ(p): among tightenings that hold it, the one it lies deepest in; among those that
   do not, the nearest front. It takes it if some T_ℓ holds the pixel, or if the pixel lies in the core
   of the union, R_r(U) (a disk of radius r inside the labelled area covers it: two labels met there, and
   the input had no gap); otherwise it is background.
3. Ties of d_ℓ go to the label the pixel had in the input, then to the label whose first pixel (in row
   order) comes first. Both depend on where the labels are, not on their values.

**Guarantees** (tested): every output pixel has exactly one value; each label's region contains its own
core and lies in its own fillet (R_ℓ ⊆ out_ℓ ⊆ F_ℓ); background appears only where no T_ℓ holds a pixel
and the union's core does not cover it, so touching labels keep a shared border with no gap between them;
renaming the labels renames the output and changes nothing else. A label that has no pixel left is
reported (`LostLabelWarning`, `LabelTightening.lost`).

**What it is not**: the union of the output is not the tightening of the union. Where two labels meet at
a reflex corner of their union, neither label's fillet reaches into it, so it is not filled (it would be
by a binary tightening of the union); and labels that are each thinner than 2r but thick together keep
their input pixels where they touch (rule 2, through the union's core) rather than vanish.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from ._checks import check_radius
from .masks import EmptyMaskWarning, LostLabelWarning

__all__ = ["LabelTightening", "tighten_labels"]

#: Extra pixels of crop beyond 2r around each label (the fillet reaches r from the label, and the
#: morphology sees r + ½ beyond that).
_CROP_PAD = 3


@dataclass
class LabelTightening:
    """The result of `tighten_labels` with ``return_result=True``.

    Attributes
    ----------
    labels : ndarray
        The tightened label image: the input's shape and dtype, 0 for the background.
    r : float
        Radius, pixels.
    init : str
        The flow's initial set.
    values : ndarray
        The labels of the input (non-zero values), sorted.
    area_in, area_out : ndarray of int
        Pixels of each label (in the order of ``values``) in the input and the output.
    vanished : list
        Labels whose own tightening is empty (every part thinner than 2r with ``init="core"``).
    lost : list
        Labels with no pixel in the output (vanished, or every pixel taken by neighbours' cores).
    conflicts : int
        Pixels that more than one label's tightening held.
    filled : int
        Pixels that no label's tightening held, given to the nearest front because the union's core
        covers them (rule 2 of `raster.labels`).
    timings : dict of str to float
        Seconds: ``"labels"`` (the per-label flows), ``"union core"``, ``"total"``.
    """

    labels: np.ndarray
    r: float
    init: str
    values: np.ndarray
    area_in: np.ndarray
    area_out: np.ndarray
    vanished: list = field(default_factory=list)
    lost: list = field(default_factory=list)
    conflicts: int = 0
    filled: int = 0
    timings: dict = field(default_factory=dict)


def _check_labels(labels, name: str) -> np.ndarray:
    a = np.asarray(labels)
    if a.ndim != 2:
        if a.ndim == 3 and a.shape[2] <= 4:
            raise ValueError(f"{name} is a colour image {a.shape}, not a label image (one value a pixel)")
        if a.ndim == 3:
            raise ValueError(f"{name} must be a 2-D label image, got shape {a.shape}; tighten a stack slice "
                             "by slice (the command line's --stack does)")
        raise ValueError(f"{name} must be a 2-D label image, got an array of shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"{name} is empty (shape {a.shape})")
    if a.dtype == bool or np.issubdtype(a.dtype, np.integer):
        return a
    if np.issubdtype(a.dtype, np.floating):
        if not np.isfinite(a).all():
            raise ValueError(f"{name} has NaN or infinite pixels")
        if not (a == np.round(a)).all():
            raise ValueError(f"{name} is a float image with fractional values, not a label image")
        return a
    raise ValueError(f"{name} must hold integer labels, got dtype {a.dtype}")


def _dense(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(values, dense): the non-zero values sorted, and the image as indices 1..K into them (0 = none)."""
    if a.dtype == bool:
        return np.array([True]) if a.any() else np.array([], bool), a.astype(np.int32)
    if np.issubdtype(a.dtype, np.integer) and a.min() >= 0 and a.max() < 2 ** 24:
        present = np.bincount(a.ravel()) > 0
        present[0] = False
        lut = np.cumsum(present).astype(np.int32) * present
        return np.flatnonzero(present).astype(a.dtype), lut[a]
    values, inverse = np.unique(a, return_inverse=True)
    inverse = inverse.reshape(a.shape).astype(np.int32)
    zero = np.searchsorted(values, 0)
    if zero < len(values) and values[zero] == 0:
        dense = np.where(inverse < zero, inverse + 1, inverse)
        dense[inverse == zero] = 0
        return np.delete(values, zero), dense.astype(np.int32)
    return values, inverse + 1


def _aligned_crop(sl, shape, margin: int, align: int) -> tuple[slice, slice]:
    """Grow the bounding box ``sl`` by ``margin``, clip it to the image, start it at a multiple of ``align``.

    So the flow's coarse levels sample the same pixels as on the whole image.
    """
    out = []
    for s, n in zip(sl, shape):
        a = max(0, s.start - margin)
        a -= a % align
        out.append(slice(a, min(n, s.stop + margin)))
    return tuple(out)


def _listing(values, limit: int = 10) -> str:
    shown = ", ".join(str(v.item() if hasattr(v, "item") else v) for v in values[:limit])
    return shown + (f" and {len(values) - limit} more" if len(values) > limit else "")


def tighten_labels(labels, r, *, init: str = "core", return_result: bool = False, name: str = "labels",
                   levels: int | None = None, iterations: int | None = None, stop: float | None = None):
    """Tighten every label of a label image and return one label image of the same shape and dtype.

    Each label's region is tightened alone by `raster.tighten`; overlaps and gaps where labels touch are
    resolved by the symmetric rule of `raster.labels` (a label's core is its own; elsewhere the nearest
    front among the labels whose fillet holds the pixel; gaps filled only inside the union's core).

    Parameters
    ----------
    labels : (H, W) array of int (or bool, or float holding whole numbers)
        0 is the background, every other value one label (negative values too). Not modified.
    r : float
        Radius, pixels, > 0.
    init : {"core", "input", "mason"}
        The initial set of each label's flow (`raster.tighten`).
    return_result : bool
        Also return a `LabelTightening` (what was lost, conflicts, timings).
    name : str
        What warnings and errors call the image.
    levels, iterations, stop : optional
        Passed to `raster.tighten` when given; its defaults otherwise.

    Returns
    -------
    out : ndarray, the shape and dtype of ``labels``
        Background 0; each pixel one of the input's labels.
    result : LabelTightening
        Only with ``return_result=True``.

    Raises
    ------
    ValueError
        Not a 2-D image of whole numbers; r not a finite number > 0.

    Warns
    -----
    LostLabelWarning
        Some labels have no pixel left (listed).
    EmptyMaskWarning
        The input has no label, or the output has none left.

    Examples
    --------
    Two touching squares of different sizes: their shared border stays without a gap, their outer
    corners are rounded.

    >>> import numpy as np
    >>> img = np.zeros((60, 90), np.uint16)
    >>> img[10:50, 10:50] = 7; img[20:40, 50:75] = 3
    >>> out = tighten_labels(img, 6)
    >>> out.dtype, out.shape, sorted(np.unique(out).tolist())
    (dtype('uint16'), (60, 90), [0, 3, 7])
    >>> int(out[10, 10]), int(out[30, 49]), int(out[30, 50]), bool((out[20:40, 49:51] > 0).all())
    (0, 7, 3, True)
    """
    from .flow import default_levels, signed_distance, tighten
    from .morphology import core

    t_start = time.perf_counter()
    a = _check_labels(labels, name)
    r = check_radius(r)
    flow = {k: v for k, v in (("levels", levels), ("iterations", iterations), ("stop", stop))
            if v is not None}
    values, dense = _dense(a)
    K = len(values)
    shape = a.shape
    zero = np.zeros(K, dtype=np.int64)
    if K == 0:
        warnings.warn(f"{name}: no label (every pixel is 0)", EmptyMaskWarning, stacklevel=2)
        out = a.copy()
        res = LabelTightening(out, r, init, values, zero, zero.copy(), timings={"total": 0.0})
        return (out, res) if return_result else out
    slices = ndimage.find_objects(dense)
    # Rank of each label by its first pixel in row order: the last tie-break (rank[0], "no label", is last).
    first = np.empty(K + 1, dtype=np.int64)
    first[0] = np.iinfo(np.int64).max
    for k, sl in enumerate(slices, start=1):
        row = sl[0].start
        cols = np.flatnonzero(dense[row, sl[1]] == k)
        first[k] = row * shape[1] + sl[1].start + cols[0]
    rank = np.argsort(np.argsort(first))
    align = 2 ** (int(levels if levels is not None else default_levels(r)) - 1)
    margin = math.ceil(2 * r) + _CROP_PAD
    best_key = np.full(shape, np.inf, dtype=np.float32)
    best = np.zeros(shape, dtype=np.int32)
    held = np.zeros(shape, dtype=np.uint16)
    vanished = []
    t0 = time.perf_counter()
    for k, sl in enumerate(slices, start=1):
        box = _aligned_crop(sl, shape, margin, align)
        crop = dense[box]
        M = crop == k
        if M.all():                       # the label fills the image: nothing to tighten
            T = R = F = M
        else:
            res = tighten(M, r, init=init, **flow)
            T, R, F = res.mask, res.core, res.fillet
        if not T.any():
            vanished.append(k)
        held[box] += T
        key = signed_distance(T)
        key[R] = -np.inf
        cur_key, cur = best_key[box], best[box]
        own_k, own_cur = M, (crop == cur) & (cur > 0)
        beats = (own_k & ~own_cur) | ((own_k == own_cur) & (rank[k] < rank[cur]))
        win = F & ((key < cur_key) | ((key == cur_key) & beats))
        cur_key[win] = key[win]
        cur[win] = k
    t_labels = time.perf_counter() - t0
    t0 = time.perf_counter()
    claimed = best_key < 0
    gap = ~claimed & (best > 0)
    if gap.any():
        gap &= core(dense > 0, r)
    t_union = time.perf_counter() - t0
    out_dense = np.where(claimed | gap, best, 0)
    lut = np.concatenate([np.zeros(1, dtype=a.dtype), values.astype(a.dtype)])
    out = lut[out_dense]
    area_in = np.bincount(dense.ravel(), minlength=K + 1)[1:]
    area_out = np.bincount(out_dense.ravel(), minlength=K + 1)[1:]
    lost = [values[i] for i in np.flatnonzero(area_out == 0)]
    vanished_values = [values[k - 1] for k in vanished]
    if lost:
        warnings.warn(f"{name}: {len(lost)} of {K} label(s) vanished (no part wider than 2r = {2 * r:g} px "
                      f"of its own, or taken by neighbours' cores): {_listing(lost)}",
                      LostLabelWarning, stacklevel=2)
    if not out_dense.any():
        warnings.warn(f"{name}: the tightening is empty: every label is thinner than 2r = {2 * r:g} px",
                      EmptyMaskWarning, stacklevel=2)
    if not return_result:
        return out
    timings = {"labels": t_labels, "union core": t_union, "total": time.perf_counter() - t_start}
    res = LabelTightening(out, r, init, values, area_in, area_out, vanished=vanished_values, lost=lost,
                          conflicts=int((held >= 2).sum()), filled=int(gap.sum()), timings=timings)
    return out, res
