"""Exceptions and warnings raised by vectortighten.

Every error subclasses the matching built-in, so ``except ValueError`` keeps working for callers who do
not know this package.
"""

__all__ = [
    "CRSError",
    "ConvergenceWarning",
    "EmptyTighteningWarning",
    "FeatureErrorWarning",
    "GeometryTypeError",
    "InvalidGeometryError",
    "InvalidRadiusError",
    "PassThroughWarning",
    "RepairWarning",
    "TighteningError",
]


class TighteningError(Exception):
    """Base class of every error raised by vectortighten."""


class InvalidGeometryError(TighteningError, ValueError):
    """The shape is empty, has non-finite coordinates, or cannot be repaired into a valid polygon."""


class GeometryTypeError(TighteningError, TypeError):
    """The argument is not a polygonal shapely geometry."""


class InvalidRadiusError(TighteningError, ValueError):
    """The radius (or a tolerance) is not a positive finite number."""


class RepairWarning(UserWarning):
    """An invalid polygon (self-intersection, bow-tie) was repaired with ``shapely.make_valid``."""


class ConvergenceWarning(UserWarning):
    """The exact finish did not settle on every loop.

    ``Tightening.converged`` is then False, and ``Tightening.verify()`` says where the result falls short.
    """


class CRSError(TighteningError, ValueError):
    """A geodata layer's coordinate reference system is missing, unreadable, or in degrees.

    ``r`` is a length in the layer's CRS units, so a geographic CRS (degrees) must first be reprojected
    to a projected one (``to_crs``, or ``--to-crs`` on the command line).
    """


class EmptyTighteningWarning(UserWarning):
    """Some features of a batch (`tighten_all`) have an empty result; their rows keep an empty geometry."""


class PassThroughWarning(UserWarning):
    """Some geometries of a batch are not polygonal (points, lines) and were passed through unchanged."""


class FeatureErrorWarning(UserWarning):
    """Some features of a batch failed (``errors="warn"``) and were given an empty geometry."""
