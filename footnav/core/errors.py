"""The one error hierarchy of footnav.

Every error footnav raises on purpose derives from :class:`FootnavError`, so a caller can catch
footnav's own failures without catching programming errors. Messages say what failed, where
(field, file, first bad index), what was expected and what was found.
"""

from __future__ import annotations

__all__ = [
    "FootnavError",
    "InvalidInputError",
    "InvalidParameterError",
    "UnknownComponentError",
    "UnknownDatasetError",
    "MetricNotFoundError",
    "CompositionError",
    "PluginError",
    "DataNotFoundError",
    "FootnavWarning",
    "DataQualityWarning",
    "PluginWarning",
    "GaitModelError",
    "HmmNotFittedError",
]


class FootnavError(Exception):
    """Base class of every error footnav raises on purpose."""


class InvalidInputError(FootnavError, ValueError):
    """Input data (arrays, files) violate the data model.

    Parameters
    ----------
    message
        What is wrong, expected versus found.
    field
        The offending field or column (``"acc"``, ``"t"``), if any.
    index
        First bad sample index (0-based), if the problem is per sample.
    path
        File the data came from, if any.
    line
        1-based line in ``path``, if known.
    """

    def __init__(
        self,
        message: str,
        *,
        field: str | None = None,
        index: int | None = None,
        path: str | None = None,
        line: int | None = None,
    ) -> None:
        self.field = field
        self.index = index
        self.path = None if path is None else str(path)
        self.line = line
        where = []
        if self.path is not None:
            where.append(f"file {self.path!r}" + (f" line {line}" if line is not None else ""))
        if field is not None:
            where.append(f"field {field!r}")
        if index is not None:
            where.append(f"index {index}")
        prefix = f"{', '.join(where)}: " if where else ""
        super().__init__(prefix + message)


class InvalidParameterError(FootnavError, ValueError):
    """A component parameter is unknown or has an invalid value."""


class UnknownComponentError(FootnavError, LookupError):
    """No component of that kind is registered under that name."""


class UnknownDatasetError(FootnavError, LookupError):
    """No shared recording is known under that name."""


class MetricNotFoundError(FootnavError, KeyError):
    """An evaluation report has no such metric for that foot (or its run failed); also a
    KeyError, as a missing key is."""

    def __str__(self) -> str:  # KeyError would print the message with quotes around it
        return str(self.args[0]) if self.args else ""


class CompositionError(FootnavError):
    """Components cannot be composed (e.g. a two-foot fusion given one foot)."""


class PluginError(FootnavError):
    """A plugin registered something invalid (duplicate name, not a component class)."""


class DataNotFoundError(FootnavError, FileNotFoundError):
    """A data file or shared data set is not where it was looked for."""


class FootnavWarning(UserWarning):
    """Base class of footnav's warnings."""


class DataQualityWarning(FootnavWarning):
    """Data were accepted but have a property the user must know about (gaps, clipping)."""


class PluginWarning(FootnavWarning):
    """A third-party plugin could not be loaded; the others still work."""


class GaitModelError(InvalidInputError):
    """An unsupervised gait model (the HMM of Li et al. (2018)) could not learn the gait cycle from the data:
    after learning, its stance state is not the stillest state (the mask would be inverted)."""


class HmmNotFittedError(FootnavError, AttributeError):
    """The HMM detector has no learned model (``fit`` was not called) and one is needed (``save``).

    Also an :class:`AttributeError`, as scikit-learn's ``NotFittedError`` is: the learned
    attributes (``transmat_``, ...) do not exist yet. Importable from :mod:`footnav.detectors.hmm`
    as before.
    """
