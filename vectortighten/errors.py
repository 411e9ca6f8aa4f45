"""Exceptions and warnings raised by vectortighten.

Every error subclasses the matching built-in, so ``except ValueError`` keeps working for callers who do
not know this package, and every error subclasses `TighteningError`, so ``except TighteningError``
catches everything the package raises on purpose. An exception of any other type escaping a public
function is a bug.

The hierarchy::

    TighteningError
    ├── InvalidGeometryError (ValueError)   the shape, or the file it came from, is unusable
    ├── GeometryTypeError (TypeError)       not a polygonal geometry
    ├── InvalidRadiusError (ValueError)     r or a tolerance is not usable (e.g. below what doubles resolve)
    ├── ResourceLimitError (ValueError)     an input would exceed a documented cap (`vectortighten.limits`)
    ├── TighteningFailedError (RuntimeError) the engine could not tighten this (valid) shape
    └── CRSError (ValueError)               a geodata layer's CRS is missing, unreadable or in degrees
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
    "ResourceLimitError",
    "TighteningError",
    "TighteningFailedError",
]


class TighteningError(Exception):
    """Base class of every error raised by vectortighten.

    Catch it to handle every documented failure at once; the message is one line that names the problem
    (and, for a file, the file). The command line reports each of these with exit code 2.

    Examples
    --------
    >>> import vectortighten as vt
    >>> from shapely.geometry import box
    >>> try:
    ...     vt.tighten(box(0, 0, 1, 1), -1)
    ... except vt.TighteningError as exc:
    ...     print(type(exc).__name__, exc)
    InvalidRadiusError r must be a positive finite number, got -1
    """


class InvalidGeometryError(TighteningError, ValueError):
    """The shape is empty, has non-finite coordinates, or cannot be repaired into a valid polygon."""


class GeometryTypeError(TighteningError, TypeError):
    """The argument is not a polygonal shapely geometry."""


class InvalidRadiusError(TighteningError, ValueError):
    """The radius (or a tolerance) is not a positive finite number, or not one doubles can resolve.

    ``tighten`` refuses a radius below `vectortighten.limits.min_radius` of the shape (relative to its size
    and to the magnitude of its coordinates) and a tolerance below `vectortighten.limits.min_tolerance`;
    the message names the limit.
    """


class ResourceLimitError(TighteningError, ValueError):
    """An input would exceed one of the documented caps of `vectortighten.limits`.

    Expanded SVG elements (``<use>`` fan-out), decoded image pixels, vertices of the sampled output: the
    message names the cap and by how much it is exceeded.
    """


class TighteningFailedError(TighteningError, RuntimeError):
    """The engine could not compute a tightening of this (valid) shape.

    Raised instead of an internal exception (a GEOS topology error, a loop that leaves the mortar, surgery
    that does not settle). The shape and r are valid; the message says what failed. Please report it with
    the shape. A result that is computed but fails the final containment check is not raised: it comes
    back with ``converged=False`` and a `ConvergenceWarning`.
    """


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
