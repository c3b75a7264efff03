"""Warnings recorded with the run that raised them, safe under threads.

:func:`warnings.catch_warnings` swaps process-global state: two pipelines running in two threads
record each other's warnings, and the filters one restores can undo the other's. footnav does not
use it for provenance. Every warning footnav issues goes through :func:`warn`, which appends it to
the log of the run in progress in the *current context* (a :class:`contextvars.ContextVar`, so one
per thread and per asyncio task) and then hands it to :mod:`warnings` as usual, where the user's
filters decide what is shown. The log records the warning even when a filter hides it.

Third-party components record their warnings in the run's ``meta["warnings"]`` the same way, by
calling :func:`footnav.warn`; a bare :func:`warnings.warn` is shown as usual but not recorded.
"""

from __future__ import annotations

import contextlib
import contextvars
import warnings
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from footnav.core.errors import DataQualityWarning

__all__ = ["RecordedWarning", "merge_warnings", "recording", "warn"]


@dataclass(frozen=True)
class RecordedWarning:
    """One warning issued during a run: its category and message."""

    category: type[Warning]
    message: str

    def __str__(self) -> str:
        return f"{self.category.__name__}: {self.message}"


_LOG: contextvars.ContextVar[list[RecordedWarning] | None] = contextvars.ContextVar("footnav_warning_log", default=None)
#: True inside ``recording(quiet=True)``: warnings are recorded, not shown.
_QUIET: contextvars.ContextVar[bool] = contextvars.ContextVar("footnav_warning_quiet", default=False)


def warn(message: str, category: type[Warning] = DataQualityWarning, stacklevel: int = 1) -> None:
    """Issue a warning and record it with the run in progress in this context, if any.

    Parameters
    ----------
    message
        What is suspect, and what was done about it.
    category
        A :class:`Warning` subclass; footnav's own are :class:`~footnav.DataQualityWarning` and
        :class:`~footnav.PluginWarning`.
    stacklevel
        As for :func:`warnings.warn`, counted from the caller of this function.
    """
    log = _LOG.get()
    if log is not None:
        log.append(RecordedWarning(category, str(message)))
    if not _QUIET.get():
        warnings.warn(message, category, stacklevel=stacklevel + 1)


@contextlib.contextmanager
def recording(*, quiet: bool = False) -> Iterator[list[RecordedWarning]]:
    """Collect the warnings :func:`warn` issues in this context until the block ends.

    Nested blocks each see their own warnings; the outer block sees the inner's too, since a
    warning inside a nested run is also a warning of the enclosing one. With ``quiet`` the
    block's warnings are only collected, neither shown nor passed to the outer block (for work
    repeated on overlapping windows, such as online detection, whose warnings were already said
    once). Unlike ``warnings.catch_warnings`` it changes no process-wide state.
    """
    outer = _LOG.get()
    log: list[RecordedWarning] = []
    token = _LOG.set(log)
    quiet_token = _QUIET.set(True) if quiet else None
    try:
        yield log
    finally:
        _LOG.reset(token)
        if quiet_token is not None:
            _QUIET.reset(quiet_token)
        elif outer is not None:
            outer.extend(log)


def merge_warnings(*groups: Iterable[str | RecordedWarning]) -> list[str]:
    """The warnings of several groups (strings or :class:`RecordedWarning`) as one list of
    strings, in order, each once: a run's ``meta["warnings"]`` after what reading its files said."""
    return list(dict.fromkeys(str(w) for group in groups for w in group))
