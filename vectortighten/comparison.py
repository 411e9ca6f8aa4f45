"""Cross-check: the exact vector tightening against the paper's pixel method on the same shape.

Two independent computations of one definition: `vectortighten.tighten` (exact arcs and segments) and
`raster.tighten` (level-set curvature flow on a rasterised copy). Their agreement is the evidence that
either is right; where they disagree, one of them is wrong.
"""

from __future__ import annotations

import math
from pathlib import Path
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy import ndimage

from ._validation import check_radius, check_shape

__all__ = ["AGREE_PX", "KINDS", "CrossCheck", "Disagreement", "crosscheck", "pixel_squares", "plot_crosscheck"]

#: The agreement the project promises: boundaries within this many pixels (Hausdorff), equal topology.
AGREE_PX = 2.0

#: The verdicts of `CrossCheck.explain`, in the order they are tried.
KINDS = ("defect of the pixel side", "defect of the exact side", "rasterisation (not resolvable)",
         "rasterisation (resolvable)", "unconverged flow", "two valid tightenings", "unexplained")


@dataclass
class Disagreement:
    """One region where the exact and the pixel tightening differ, and why (`CrossCheck.explain`).

    Attributes
    ----------
    kind : str
        One of `KINDS`: ``"defect of the pixel side"`` (the pixel result breaks core ⊆ T ⊆ F here, or has
        a component holding no core or a hole holding no anticore: a tight loop around nothing of them
        could still shrink); ``"rasterisation (not resolvable)"`` (the exact tightening of S moved by
        the rasterisation's own error, half a pixel diagonal, agrees with the pixel result here, and
        usually so does the exact tightening of the pixel input: no pixel method can decide this region at
        this pixel size; the evidence gives the stroke or gap width of S there against 2r, and the pixel
        sizes. Where S is about 2r wide the pixel input's exact tightening may differ from both, since
        the pixel morphology tries disk centres only on the fine grid); ``"defect of the exact side"`` (the exact result's `verify` reports violations; tried
        before the rasterisation, since the exact tightening of the pixel input, right, would agree with
        the pixel result there too); ``"rasterisation (resolvable)"`` (the exact tightening of the pixel
        input agrees with the pixel result, S moved by half a pixel diagonal does not: a finer grid
        resolves it); ``"unconverged flow"`` (the flow did not rest at some level);
        ``"two valid tightenings"`` (both sides are
        valid and the core or the anticore has several parts, where tightenings are not unique: see
        ``perimeters``); ``"unexplained"`` (none of these: both sides look valid and the tightening
        should be unique, so one of them is wrong; ``evidence`` says what was checked).
    pixels : int
        Pixels of the region (a connected component of the symmetric difference).
    depth_px : float
        How far the region reaches from the exact tightening's boundary, pixels.
    centre : (float, float)
        The region's centroid, in S's units.
    bbox : (int, int, int, int)
        (row0, col0, row1, col1) of the region on the grid, end exclusive.
    topology : str
        What the region changes in the topology ("" if nothing): the change of components − holes that
        replacing the exact result by the pixel result there makes, in words.
    perimeters : dict or None
        For ``"two valid tightenings"``: the perimeter of each result ("exact", "pixel", in S's units)
        and ``"shorter"``, the name of the shorter one.
    evidence : list of str
        The checks behind the verdict, one sentence each.
    """

    kind: str
    pixels: int
    depth_px: float
    centre: tuple
    bbox: tuple
    topology: str = ""
    perimeters: dict | None = None
    evidence: list = field(default_factory=list)

    def text(self) -> str:
        """The verdict in one paragraph."""
        where = f"({self.centre[0]:.4g}, {self.centre[1]:.4g})"
        head = f"{self.kind}: {self.pixels} px near {where}, reaching {self.depth_px:.2g} px from the exact boundary"
        if self.topology:
            head += f"; {self.topology}"
        lines = [head]
        if self.perimeters:
            p = self.perimeters
            lines.append(f"  perimeters: exact {p['exact']:.6g}, pixel {p['pixel']:.6g}; shorter: {p['shorter']}")
        lines += [f"  - {e}" for e in self.evidence]
        return "\n".join(lines)


@dataclass
class CrossCheck:
    """The comparison of a vector and a raster tightening of one shape on one grid.

    Attributes
    ----------
    r, pixel_size : float
        The radius and the pixel side, in the shape's units.
    init : str
    hausdorff_px : float
        Hausdorff distance between the two boundaries (the vector loops, the raster's sub-pixel
        contour), pixels. ``inf`` when exactly one of them is empty.
    symmetric_difference_px : int
        Pixels where the rasterised vector tightening and the raster tightening differ.
    mortar_px : int
        Pixels of the (raster) mortar; the share below is relative to it.
    vector_topology, raster_topology : (int, int)
        (components, holes) of each result.
    vector, raster : object
        The two results (`Tightening` and `raster.RasterTightening`), and ``grid``, the `raster.Grid`.
    mask_hausdorff_px : float or None
        With ``mask_reference=True``: the Hausdorff distance (pixels) between the raster result and the
        exact tightening of the rasterised input itself (the union of its pixel squares). This separates
        the two sources of a disagreement: the flow's own error shows here, the rasterisation of S does
        not (the mask is exactly what the flow was given).
    mask_topology : (int, int) or None
        (components, holes) of that exact tightening of the mask.
    """

    r: float
    pixel_size: float
    init: str
    hausdorff_px: float
    symmetric_difference_px: int
    mortar_px: int
    vector_topology: tuple
    raster_topology: tuple
    vector: object = field(repr=False)
    raster: object = field(repr=False)
    grid: object = field(repr=False)
    vector_mask: np.ndarray = field(repr=False)
    mask_hausdorff_px: float | None = None
    mask_topology: tuple | None = None
    supersample: int = 1
    mask_vector: object = field(default=None, repr=False)

    @property
    def symmetric_difference_share(self) -> float:
        """Symmetric difference as a share of the mortar's area (0 when the mortar is empty)."""
        return self.symmetric_difference_px / self.mortar_px if self.mortar_px else 0.0

    @property
    def same_topology(self) -> bool:
        return tuple(self.vector_topology) == tuple(self.raster_topology)

    @property
    def agree(self) -> bool:
        """Equal topology and boundaries within `AGREE_PX` pixels."""
        return _within_target(self.vector_topology, self.raster_topology, self.hausdorff_px)

    @property
    def agree_on_mask(self) -> bool | None:
        """Whether the raster result agrees (equal topology, ≤ `AGREE_PX`) with the exact tightening of
        the mask it was computed from; None unless the check was made with ``mask_reference=True``."""
        if self.mask_hausdorff_px is None:
            return None
        return _within_target(self.mask_topology, self.raster_topology, self.mask_hausdorff_px)

    def table(self) -> str:
        """The comparison as a plain-text table."""
        rows = [
            ("radius r", f"{self.r:g} ({self.r / self.pixel_size:.4g} px)"),
            ("pixel size", f"{self.pixel_size:g}"),
            ("init", self.init),
            ("grid", f"{self.grid.shape[1]} × {self.grid.shape[0]} px"),
            ("vector: components, holes", "%d, %d" % self.vector_topology),
            ("raster: components, holes", "%d, %d" % self.raster_topology),
            ("Hausdorff distance", f"{self.hausdorff_px:.3g} px"),
            ("symmetric difference", f"{self.symmetric_difference_px} px "
                                     f"({100 * self.symmetric_difference_share:.3g}% of the mortar)"),
            ("agree", f"{'yes' if self.agree else 'no'} (equal topology and ≤ {AGREE_PX:g} px)"),
        ]
        if self.mask_hausdorff_px is not None:
            rows += [
                ("exact of the mask: comp., holes", "%d, %d" % self.mask_topology),
                ("raster vs exact of the mask", f"{self.mask_hausdorff_px:.3g} px"),
                ("agree on the mask", "yes" if self.agree_on_mask else "no"),
            ]
        width = max(len(k) for k, _ in rows)
        return "\n".join(f"{k:<{width}}  {v}" for k, v in rows)


    def explain(self) -> list[Disagreement]:
        """Classify each region where the two results differ beyond the rasterisation allowance.

        A region is a connected component (8-connected) of the symmetric difference of the rasterised
        exact tightening and the pixel result that reaches more than `AGREE_PX` pixels from the exact
        boundary (``AGREE_PX − 1`` when the check does not agree: a mask samples each boundary at the
        pixel centres, half a pixel either way) or changes the topology (components − holes) where it
        lies. Each gets a verdict from
        `KINDS`, tried in order, with the evidence: the pixel result's own ``core ⊆ T ⊆ F`` and whether
        each of its components holds core and each hole anticore; the exact tightening of the pixel input
        itself (the union of the fine mask's squares) and of S moved by ±½ pixel diagonal; whether the
        flow rested at every level; the exact side's `Tightening.verify`; and the parts of the core and
        the anticore (tightenings are unique only when each is connected).

        Costs up to three more exact tightenings (the mask's, computed once unless the check was made
        with ``mask_reference=True``, and the two moved copies of S, only if a region needs them).

        Returns
        -------
        list of Disagreement
            Largest first; empty when no region reaches beyond the allowance.

        Examples
        --------
        >>> from shapely.geometry import box
        >>> c = crosscheck(box(0, 0, 10, 10), 2.0, pixel_size=0.1)
        >>> c.explain()
        []
        """
        return _explain(self)

    def explain_text(self, found: list | None = None) -> str:
        """`explain`'s verdicts as readable text (``found``: a list `explain` returned, to reuse it)."""
        found = self.explain() if found is None else found
        if not found:
            if self.agree:
                return "no region differs beyond the rasterisation allowance: the two agree"
            return (f"no region differs beyond the rasterisation allowance, yet the check does not agree "
                    f"(topology {self.vector_topology} vs {self.raster_topology}, "
                    f"{self.hausdorff_px:.3g} px)")
        kinds = {}
        for d in found:
            kinds[d.kind] = kinds.get(d.kind, 0) + 1
        head = f"{len(found)} differing region(s): " + ", ".join(f"{n} {k}" for k, n in kinds.items())
        return "\n".join([head] + [d.text() for d in found])


def _within_target(topology_a, topology_b, hausdorff_px: float) -> bool:
    """Equal (components, holes) and boundaries within `AGREE_PX` pixels."""
    return bool(tuple(topology_a) == tuple(topology_b) and hausdorff_px <= AGREE_PX)


def _topology(mask: np.ndarray) -> tuple[int, int]:
    """(components, holes) of a mask: 8-connected inside, 4-connected outside (the dual pair)."""
    padded = np.pad(mask, 1)
    _, n_in = ndimage.label(padded, structure=np.ones((3, 3), bool))
    _, n_out = ndimage.label(~padded)
    return int(n_in), int(n_out) - 1


def pixel_squares(mask: np.ndarray, grid):
    """The union of a mask's pixel squares, in world coordinates: exactly the shape a pixel method sees.

    The squares are unioned on integer corners, where shared edges coincide exactly, and only then scaled
    onto the grid, so that neighbouring squares never miss each other by rounding.

    Parameters
    ----------
    mask : (rows, cols) bool array
        Row 0 is the top of the grid.
    grid : raster.Grid
        Places the pixels in the world (pixel side ``grid.pixel_size``, in the world's units).

    Returns
    -------
    shapely Polygon or MultiPolygon (empty when the mask is)

    Examples
    --------
    >>> import numpy as np, raster
    >>> grid = raster.Grid(x0=0.0, y_top=2.0, pixel_size=0.5, shape=(4, 4))
    >>> mask = np.zeros((4, 4), bool); mask[1:3, 1:4] = True
    >>> P = pixel_squares(mask, grid)
    >>> P.area, P.bounds
    (1.5, (0.5, 0.5, 2.0, 1.5))
    """
    from shapely import affinity

    rows, cols = np.nonzero(np.asarray(mask, dtype=bool))
    if len(rows) == 0:
        return shapely.Polygon()
    squares = shapely.union_all(shapely.box(cols, -rows - 1, cols + 1, -rows))
    h = grid.pixel_size
    return affinity.affine_transform(squares, [h, 0.0, 0.0, h, grid.x0, grid.y_top])


def crosscheck(S, r: float, *, pixel_size: float, init: str = "core", levels: int | None = None,
               iterations: int | None = None, mask_reference: bool = False, supersample: int = 7,
               finish: str = "mpp") -> CrossCheck:
    """Tighten S exactly and on pixels, and compare the two on the same grid.

    The grid covers S's bounds grown by 2r plus two pixels, so nothing a tightening adds leaves it. S is
    rasterised (pixel centres inside), tightened with `raster.tighten` at radius ``r / pixel_size``
    pixels; the vector tightening is rasterised on the same grid.

    Parameters
    ----------
    S : shapely Polygon or MultiPolygon
    r : float
        Radius, in S's units.
    pixel_size : float
        Pixel side, in S's units. The raster method needs r of several pixels; ``r / 20`` or finer is
        what the project's agreement target assumes.
    init : {"core", "input", "mason"}
    levels, iterations : int, optional
        Passed to `raster.tighten`: resolution levels (default: the paper's multiscale scheme,
        `raster.default_levels`) and the most steps a level. The default, None, is `raster.tighten`'s:
        each level flows until its front rests (with a safety cap), so that a cross-check compares the
        definitions, not a time budget (the paper's 100 leave long, nearly straight fronts short of where
        they settle). ``levels=1`` runs the flow at full resolution only (thousands of steps).
    mask_reference : bool
        Also tighten the rasterised input exactly (`pixel_squares` of the mask) and compare the raster
        result with it (``mask_hausdorff_px``, ``mask_topology``): the pixel flow measured on the very
        input it was given, free of the error of rasterising S. Costs a second exact tightening, of a
        staircase with many corners.
    finish : {"mpp", "none"}
        The pixel flow's final step (see `raster.tighten`); ``"none"`` compares the paper's flow alone.
    supersample : int, odd, ≥ 1
        Rasterise S this many times finer (pixels of side ``pixel_size / supersample``, in S's units) and
        let `raster.tighten` compute its core, fillet and start, and their signed distances, there (its
        ``supersample``); the flow and the comparison stay on the grid of ``pixel_size``. The default, 7,
        is the measured choice (``benchmarks/results/crosscheck_corpus.md``): on the 32-shape corpus
        at ``r / 20``, 5 left three shapes (a glyph, two countries; six cases) 2.02 to 2.15 px off
        where the exact answer turns on S moved by half a fine pixel, which 7 decides (1.47 to 1.62
        px), at about twice the time of 5 (the morphology on the fine grid is nearly all of it). On
        five shapes (`benchmarks/crosscheck_supersample.py`): plain morphology (1) misses the 2 px bar
        on a country outline (4.15 px), 3 leaves it at 1.73 px, 5 at 0.88 px; 5 takes 4.6 to 21 times
        as long as 1. 1 is the paper's
        method on a plain rasterisation, `raster.tighten`'s own default (a mask has no finer version).
        A fine grid over `raster.MAX_SUPERSAMPLED_PIXELS` falls back to 1 with a warning. With
        ``mask_reference`` the reference is the union of the fine mask's squares.

    Returns
    -------
    CrossCheck

    Raises
    ------
    ValueError
        If ``pixel_size`` or ``r`` is not a positive finite number, ``supersample`` is not an odd whole
        number ≥ 1, the grid would exceed 60 million pixels (use a larger ``pixel_size``), or no pixel
        centre falls inside S.

    Warns
    -----
    raster.SupersampleWarning
        If the fine grid would exceed `raster.MAX_SUPERSAMPLED_PIXELS` (50 million pixels, about 3.5 GB
        of morphology): the check then runs with ``supersample=1`` (plain morphology) and says so.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> c = crosscheck(box(0, 0, 10, 10), 2.0, pixel_size=0.1)
    >>> c.agree, c.vector_topology, c.hausdorff_px < 2
    (True, (1, 0), True)
    """
    import raster

    from .engine import tighten

    S = check_shape(S)
    r = check_radius(r)
    pixel_size = check_radius(pixel_size, "pixel_size")
    margin = 2 * r + 2 * pixel_size
    grid = raster.Grid.covering(S.bounds, pixel_size, margin)
    if grid.shape[0] * grid.shape[1] > 60_000_000:
        raise ValueError(f"pixel_size {pixel_size:g} makes a grid of {grid.shape[1]} × {grid.shape[0]} "
                         f"pixels; use a larger pixel size")
    if isinstance(supersample, bool) or not isinstance(supersample, (int, np.integer)) or supersample < 1 \
            or supersample % 2 == 0:
        raise ValueError(f"supersample must be an odd whole number ≥ 1, got {supersample!r}")
    n_fine = grid.shape[0] * grid.shape[1] * supersample * supersample
    limit = raster.flow.MAX_SUPERSAMPLED_PIXELS
    if supersample > 1 and n_fine > limit:
        import warnings

        warnings.warn(f"crosscheck: supersample {supersample} would make a grid of {n_fine:,} pixels, over the "
                      f"limit of {limit:,} for supersampled morphology "
                      f"(raster.MAX_SUPERSAMPLED_PIXELS); using plain morphology (supersample 1)",
                      raster.SupersampleWarning, stacklevel=2)
        supersample = 1
    fine = raster.Grid(grid.x0, grid.y_top, pixel_size / supersample,
                       (grid.shape[0] * supersample, grid.shape[1] * supersample))
    T = tighten(S, r, init=init)
    mask, _ = raster.rasterize(S, fine)
    if not mask.any():
        raise ValueError(f"pixel_size {pixel_size:g} is too coarse: no pixel centre falls inside S")
    RT = raster.tighten(mask, r / fine.pixel_size, init=init, levels=levels, iterations=iterations,
                        supersample=int(supersample), finish=finish)
    vmask, _ = raster.rasterize(T.geometry, grid) if not T.geometry.is_empty else (np.zeros(grid.shape, bool), grid)
    contour = raster.contours(RT, grid)
    h = _boundary_distance(T.geometry, contour, pixel_size)
    mask_h = mask_topo = TM = None
    if mask_reference:
        TM = tighten(pixel_squares(mask, fine), r, init=init)
        mask_topo = (TM.n_components, TM.n_holes)
        mask_h = _boundary_distance(TM.geometry, contour, pixel_size)
    return CrossCheck(r=r, pixel_size=pixel_size, init=str(getattr(init, "value", init)), hausdorff_px=float(h),
                      supersample=int(supersample), mask_vector=TM if mask_reference else None,
                      symmetric_difference_px=int((vmask ^ RT.mask).sum()), mortar_px=int(RT.mortar.sum()),
                      vector_topology=(T.n_components, T.n_holes), raster_topology=_topology(RT.mask),
                      vector=T, raster=RT, grid=grid, vector_mask=vmask, mask_hausdorff_px=mask_h,
                      mask_topology=mask_topo)


def _euler8(a: np.ndarray) -> int:
    """Euler number (components − holes) of a mask, 8-connected inside, by counting its 2 × 2 quads."""
    p = np.pad(a.astype(np.int8), 1)
    q = p[:-1, :-1] + p[:-1, 1:] + p[1:, :-1] + p[1:, 1:]
    diag = (q == 2) & (p[:-1, :-1] == p[1:, 1:])
    return int((np.count_nonzero(q == 1) - np.count_nonzero(q == 3) - 2 * np.count_nonzero(diag)) // 4)


def _without(parts_mask: np.ndarray, labels: np.ndarray, n: int, lacking: np.ndarray) -> np.ndarray:
    """The union of the labelled parts (1..n) that hold no pixel of ``lacking``."""
    if n == 0:
        return np.zeros(labels.shape, bool)
    has = np.asarray(ndimage.maximum(lacking, labels, np.arange(1, n + 1)), dtype=bool)
    bad = np.r_[False, ~has]
    return bad[labels] & parts_mask


def _explain(check: CrossCheck) -> list[Disagreement]:
    import raster

    from .engine import tighten

    T, RT, grid = check.vector, check.raster, check.grid
    vm, pm = check.vector_mask, RT.mask
    diff = vm ^ pm
    lab, n = ndimage.label(diff, structure=np.ones((3, 3), bool))
    if n == 0:
        return []
    if vm.any():
        depth = np.where(vm, ndimage.distance_transform_edt(vm), ndimage.distance_transform_edt(~vm)) - 0.5
    else:
        depth = np.full(vm.shape, np.inf)
    ids = np.arange(1, n + 1)
    deep = np.asarray(ndimage.maximum(depth, lab, ids), dtype=float)
    sizes = np.bincount(lab.ravel(), minlength=n + 1)[1:]
    boxes = ndimage.find_objects(lab)
    h = grid.pixel_size
    # The pixel result's own validity: core ⊆ T ⊆ F, every component holds core, every hole anticore.
    lost_core = RT.core & ~pm
    outside = pm & ~RT.fillet
    eight = np.ones((3, 3), bool)
    lab_in, n_in = ndimage.label(pm, structure=eight)
    no_core = _without(pm, lab_in, n_in, RT.core)
    lab_out, n_out = ndimage.label(np.pad(~pm, 1))
    hollow = _without(lab_out > 0, lab_out, n_out, np.pad(~RT.fillet, 1))
    hollow &= lab_out != lab_out[0, 0]
    hollow = hollow[1:-1, 1:-1]
    lazy: dict = {}

    def exact_of_mask():
        if "mask" not in lazy:
            TM = check.mask_vector
            if TM is None:
                ss = check.supersample
                fine = raster.Grid(grid.x0, grid.y_top, h / ss, (grid.shape[0] * ss, grid.shape[1] * ss))
                mask, _ = raster.rasterize(T.shape, fine)
                TM = tighten(pixel_squares(mask, fine), check.r, init=check.init)
            lazy["mask"] = _rasterised(TM.geometry, grid)
        return lazy["mask"]

    def moved():
        if "moved" not in lazy:
            delta = h / check.supersample * math.sqrt(0.5)
            lazy["moved"] = [_rasterised(tighten(T.shape.buffer(sign * delta, join_style="mitre", mitre_limit=10.0),
                                                 check.r, init=check.init).geometry, grid) for sign in (-1, 1)]
        return lazy["moved"]

    def verified():
        if "verify" not in lazy:
            lazy["verify"] = T.verify()
        return lazy["verify"]

    def width() -> str:
        # How wide S is where the region lies (its pixel centres' largest distance to ∂S, inside and
        # outside S: half the widest stroke or gap there), against 2r, and the pixel sizes.
        rows_, cols_ = np.nonzero(region_full)
        pts = shapely.points(grid.x0 + (cols_ + 0.5) * h, grid.y_top - (rows_ + 0.5) * h)
        inside_s = shapely.contains(T.shape, pts)
        dist = shapely.distance(T.shape.boundary, pts)
        # The centres come within ½ pixel diagonal of the widest point: the width lies in [2d, 2d + h√2].
        parts_ = []
        for sel, what in ((inside_s, "a stroke"), (~inside_s, "a gap")):
            if sel.any():
                w0 = 2 * float(dist[sel].max())
                parts_.append(f"{what} of S {w0:.4g} to {w0 + h * math.sqrt(2):.4g} wide")
        return (f"width: the region lies in {' and '.join(parts_)}, against 2r = {2 * check.r:.4g}; pixel "
                f"{h:.4g}, morphology pixel {h / check.supersample:.4g} (½ diagonal "
                f"{h / check.supersample * math.sqrt(0.5):.3g})")

    # A mask samples each boundary at the pixel centres, so a region of depth d holds boundary points up to
    # d + ½ px apart (and as little as d − ½): when the check does not agree, look from AGREE_PX − 1 on.
    allowance = AGREE_PX if check.agree else AGREE_PX - 1.0
    rest = (f"pixel: the flow rested at every level (steps {RT.iterations})" if RT.is_converged else
            f"pixel: the flow did not rest at every level (rested: {RT.converged}, steps: {RT.iterations}, "
            f"budget: {RT.budget})")
    out = []
    for j in range(n):
        sl = boxes[j]
        region_full = lab == j + 1
        r0, r1 = max(sl[0].start - 1, 0), min(sl[0].stop + 1, vm.shape[0])
        c0, c1 = max(sl[1].start - 1, 0), min(sl[1].stop + 1, vm.shape[1])
        win = (slice(r0, r1), slice(c0, c1))
        region = region_full[win]
        flipped = vm[win].copy()
        flipped[region] = pm[win][region]
        d_euler = _euler8(flipped) - _euler8(vm[win])
        if deep[j] <= allowance and d_euler == 0:
            continue
        rows, cols = np.nonzero(region)
        cy = grid.y_top - (rows.mean() + r0 + 0.5) * h
        cx = grid.x0 + (cols.mean() + c0 + 0.5) * h
        topo = ""
        if d_euler:
            more = "pixel" if d_euler < 0 else "exact"
            topo = (f"components − holes {d_euler:+d} in the pixel result here "
                    f"(a hole or a join more, or a part less, in the {more} result)")
        d = Disagreement(kind="unexplained", pixels=int(sizes[j]), depth_px=float(deep[j]), centre=(cx, cy),
                         bbox=(sl[0].start, sl[1].start, sl[0].stop, sl[1].stop), topology=topo)
        ev = d.evidence
        n_lost, n_out_f = int(lost_core[win][region].sum()), int(outside[win][region].sum())
        n_nocore, n_hollow = int(no_core[win][region].sum()), int(hollow[win][region].sum())
        if n_hollow and not T.fillet.is_empty:
            # The pixel anticore is sampled at the pixel centres; a sliver of the exact one may fall between.
            inner = lab_out[1:-1, 1:-1]
            hole = pixel_squares(np.isin(inner, np.unique(inner[region_full & hollow])), grid)
            if hole.difference(T.fillet).area > 1e-9 * h * h:
                n_hollow = 0
        if n_lost or n_out_f or n_nocore or n_hollow:
            d.kind = "defect of the pixel side"
            if n_lost or n_out_f:
                ev.append(f"pixel: core ⊆ T ⊆ F fails here ({n_lost} core pixels outside T, "
                          f"{n_out_f} pixels of T in the anticore)")
            if n_nocore:
                ev.append(f"pixel: a component of T ({n_nocore} px here) holds no core pixel: a tight loop "
                          f"around it could still shrink")
            if n_hollow:
                ev.append(f"pixel: a hole of T ({n_hollow} px here) holds no anticore (pixel or exact): a tight "
                          f"loop around it could still shrink")
            ev.append(rest)
            out.append(d)
            continue
        ev.append("pixel: core ⊆ T ⊆ F holds here; its components here hold core, its holes anticore")
        problems = verified()
        if problems:
            d.kind = "defect of the exact side"
            ev += [f"exact verify(): {p}" for p in problems]
            ev.append(rest)
            out.append(d)
            continue
        ev.append("exact verify(): no violation")
        mm = exact_of_mask()
        share_mask = float((mm[win] == pm[win])[region].mean())
        ev.append(f"the exact tightening of the pixel input agrees with the pixel result on "
                  f"{100 * share_mask:.0f}% of the region")
        if share_mask >= 0.5:
            shares = [float((tm[win] == pm[win])[region].mean()) for tm in moved()]
            ev.append(f"S moved by ∓½ pixel diagonal: its exact tightening agrees with the pixel result on "
                      f"{100 * shares[0]:.0f}% / {100 * shares[1]:.0f}% of the region")
            d.kind = "rasterisation (not resolvable)" if max(shares) >= 0.5 else "rasterisation (resolvable)"
            ev.append(width())
            ev.append(rest)
            out.append(d)
            continue
        # The pixel morphology tries disk centres only at the fine pixels' centres and corners, the exact
        # engine anywhere: where S is about 2r wide, the exact tightening of the mask's squares may keep a
        # disk the pixel core cannot hold (or lose one), and the share above says nothing. What decides is
        # whether moving S by the rasterisation's own error changes the exact answer to the pixel one.
        shares = [float((tm[win] == pm[win])[region].mean()) for tm in moved()]
        ev.append(f"S moved by ∓½ pixel diagonal: its exact tightening agrees with the pixel result on "
                  f"{100 * shares[0]:.0f}% / {100 * shares[1]:.0f}% of the region")
        if max(shares) >= 0.5:
            d.kind = "rasterisation (not resolvable)"
            ev.append(width())
            ev.append("the exact answer here changes when S moves by the rasterisation's own error, so no "
                      "pixel method at this pixel size can decide it (the exact tightening of the mask, another "
                      "rasterisation, decides it otherwise)")
            ev.append(rest)
            out.append(d)
            continue
        ev.append(rest)
        if not RT.is_converged:
            d.kind = "unconverged flow"
            out.append(d)
            continue
        core_parts = len(shapely.get_parts(T.core)) if not T.core.is_empty else 0
        anti_parts = 1 + sum(len(p.interiors) for p in shapely.get_parts(T.fillet))
        ev.append(f"the core has {core_parts} part(s), the anticore {anti_parts}")
        if core_parts > 1 or anti_parts > 1:
            d.kind = "two valid tightenings"
            pe = float(T.perimeter)
            pp = float(raster.contours(RT, grid).length)
            d.perimeters = {"exact": pe, "pixel": pp, "shorter": "exact" if pe < pp else "pixel"}
        else:
            ev.append("with a connected core and anticore the tightening is unique, so one side is wrong")
        out.append(d)
    out.sort(key=lambda d: -d.pixels)
    return out


def _rasterised(geometry, grid) -> np.ndarray:
    import raster

    if geometry.is_empty:
        return np.zeros(grid.shape, bool)
    return raster.rasterize(geometry, grid)[0]


def _boundary_distance(a, b, pixel_size: float) -> float:
    """Hausdorff distance between the boundaries of two shapes, pixels (0 if both are empty, inf if one)."""
    if a.is_empty and b.is_empty:
        return 0.0
    if a.is_empty or b.is_empty:
        return math.inf
    return float(shapely.hausdorff_distance(a.boundary, b.boundary, densify=0.25) / pixel_size)


def plot_crosscheck(check: CrossCheck, path, *, S=None) -> None:
    """Draw a `CrossCheck` in three panels and write it (PNG or SVG by extension), atomically.

    Panels: the input with its mortar; the two results overlaid (vector loops and the raster's sub-pixel
    contour); where they differ, pixel by pixel.

    Parameters
    ----------
    check : CrossCheck
    path : str or Path
        Output image; its folder must exist.
    S : shapely geometry, optional
        The input, drawn in the first panel.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    import raster

    from .io import atomic_path
    from .plotting import COLORS, draw_geometry, draw_loops

    T, RT, grid = check.vector, check.raster, check.grid
    x0, y0, x1, y1 = grid.bounds
    extent = (x0, x1, y0, y1)
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2), constrained_layout=True)
    ax = axes[0]
    draw_geometry(ax, T.mortar, facecolor=COLORS["mortar"], edgecolor="none")
    draw_geometry(ax, T.core, facecolor=COLORS["core"], edgecolor="none")
    if S is not None:
        draw_geometry(ax, S, facecolor="none", edgecolor=COLORS["input"], linewidth=0.8)
    ax.set_title(f"input, core (dark) and mortar (grey), r = {check.r:g}", fontsize=9)
    ax = axes[1]
    draw_loops(ax, T.loops, tolerance=T.tolerance, linewidth=1.6, label="vector (exact)")
    contour = raster.contours(RT, grid)
    draw_geometry(ax, contour, facecolor="none", edgecolor=COLORS["raster"], linewidth=1.0, linestyle="--")
    ax.plot([], [], color=COLORS["raster"], linestyle="--", label="raster (pixel flow)")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"init={check.init!r}: vector {check.vector_topology}, raster {check.raster_topology} "
                 f"(components, holes)", fontsize=9)
    ax = axes[2]
    diff = np.zeros(RT.mask.shape, dtype=np.uint8)
    diff[check.vector_mask & RT.mask] = 1
    diff[check.vector_mask & ~RT.mask] = 2
    diff[~check.vector_mask & RT.mask] = 3
    ax.imshow(diff, origin="upper", extent=extent, interpolation="nearest", vmin=0, vmax=3,
              cmap=ListedColormap(["white", "0.85", COLORS["tight"], COLORS["raster"]]))
    ax.set_title(f"difference: {check.symmetric_difference_px} px "
                 f"({100 * check.symmetric_difference_share:.2g}% of the mortar), "
                 f"Hausdorff {check.hausdorff_px:.3g} px", fontsize=9)
    for ax in axes:
        ax.set_aspect("equal")
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_xticks([])
        ax.set_yticks([])
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=Path(path).suffix.lstrip(".").lower() or "png")
    plt.close(fig)
