"""vectortighten: exact r-tightening of planar shapes.

The r-tightening of a shape S (Williams & Rossignac) keeps every part of S that a disk of radius r can
trace and replaces corners, gaps, thin parts and small pieces by the shortest boundary that stays in the
mortar, so that its radius of curvature is at least r everywhere. This package computes it exactly, as
straight segments and circular arcs of radius r.
"""

from .centers import ArcCenters, arc_centers
from .comparison import CrossCheck, crosscheck, pixel_squares
from .curves import Arc, Loop, Segment, Side, common_tangents, disk_tangent, tangent_directions
from .hull import relative_convex_hull
from .metrics import is_r_regular, min_radius_of_curvature, n_components, n_holes, perimeter
from .morphology import (
    anticore,
    core,
    fillet,
    fillet_round,
    grow,
    mason,
    mortar,
    pockets,
    round_fillet,
    shrink,
    tolerance_zone,
)
from .engine import Init, Tightening, tighten
from .errors import (
    ConvergenceWarning,
    CRSError,
    EmptyTighteningWarning,
    FeatureErrorWarning,
    GeometryTypeError,
    InvalidGeometryError,
    InvalidRadiusError,
    PassThroughWarning,
    RepairWarning,
    ResourceLimitError,
    TighteningError,
    TighteningFailedError,
)
from .exact_morphology import ExactBoundary, exact_boundary
from .loop_input import FlattenWarning
from .two_radii import TwoRadiiNotSupportedError, TwoRadiiTightening
from . import limits
from .vectorized import core_all, fillet_all, mason_all, mortar_all, tighten_all

__version__ = "0.1.0"

__all__ = [
    "Arc",
    "ArcCenters",
    "CrossCheck",
    "ExactBoundary",
    "FlattenWarning",
    "Init",
    "Tightening",
    "TwoRadiiTightening",
    "anticore",
    "arc_centers",
    "core",
    "core_all",
    "crosscheck",
    "exact_boundary",
    "fillet",
    "fillet_all",
    "fillet_round",
    "grow",
    "is_r_regular",
    "limits",
    "mason",
    "mason_all",
    "min_radius_of_curvature",
    "mortar",
    "mortar_all",
    "n_components",
    "n_holes",
    "perimeter",
    "pixel_squares",
    "pockets",
    "relative_convex_hull",
    "round_fillet",
    "shrink",
    "tighten",
    "tighten_all",
    "tolerance_zone",
    "CRSError",
    "ConvergenceWarning",
    "EmptyTighteningWarning",
    "FeatureErrorWarning",
    "GeometryTypeError",
    "InvalidGeometryError",
    "InvalidRadiusError",
    "Loop",
    "PassThroughWarning",
    "RepairWarning",
    "ResourceLimitError",
    "Segment",
    "Side",
    "TighteningError",
    "TighteningFailedError",
    "TwoRadiiNotSupportedError",
    "common_tangents",
    "disk_tangent",
    "tangent_directions",
]
