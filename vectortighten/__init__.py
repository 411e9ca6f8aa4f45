"""vectortighten: exact r-tightening of planar shapes.

The r-tightening of a shape S (Williams & Rossignac) keeps every part of S that a disk of radius r can
trace and replaces corners, gaps, thin parts and small pieces by the shortest boundary that stays in the
mortar, so that its radius of curvature is at least r everywhere. This package computes it exactly, as
straight segments and circular arcs of radius r.
"""

from .curves import Arc, Loop, Segment, Side, common_tangents, disk_tangent, tangent_directions
from .errors import (
    GeometryTypeError,
    InvalidGeometryError,
    InvalidRadiusError,
    RepairWarning,
    TighteningError,
)

__version__ = "0.1.0"

__all__ = [
    "Arc",
    "GeometryTypeError",
    "InvalidGeometryError",
    "InvalidRadiusError",
    "Loop",
    "RepairWarning",
    "Segment",
    "Side",
    "TighteningError",
    "common_tangents",
    "disk_tangent",
    "tangent_directions",
]
