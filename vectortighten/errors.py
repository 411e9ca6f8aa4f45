"""Exceptions and warnings raised by vectortighten.

Every error subclasses the matching built-in, so ``except ValueError`` keeps working for callers who do
not know this package.
"""

__all__ = [
    "ConvergenceWarning",
    "GeometryTypeError",
    "InvalidGeometryError",
    "InvalidRadiusError",
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
