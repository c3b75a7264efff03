"""The time span two feet share, and what a fusion must cut to stay inside it.

A coupled fusion (``range``, ``step-vector``, ``particle``, ``dtw``) ties the feet together at
common instants, so it can only use the time both feet were recorded on one clock. Two
recordings rarely start and stop together: a sensor started late, a file cut short, or a clock
hours off. :func:`common_span` gives the common span and, per foot, the samples inside it and the
seconds cut before and after; it refuses (``InvalidInputError``, field ``t``) when the feet share
less than ``min_common_s`` seconds, naming both spans and pointing to clock synchronisation.
:func:`span_difference` tells the ``independent`` fusion whether the feet's spans differ
markedly (it uses no common instant, but a large difference usually means a wrong file or clock).

Definitions (one place for all fusions):

* the common span is ``[max(t_left[0], t_right[0]), min(t_left[-1], t_right[-1])]``;
* a foot's samples inside it are ``t_start <= t <= t_stop`` (a contiguous index range);
* a coupled fusion warns (DataQualityWarning) when a foot loses more than
  :data:`CUT_WARN_S` seconds; smaller cuts (sensors started by hand a fraction of a second
  apart) are only recorded in ``meta["span"]``;
* the spans differ *markedly* when the starts or the ends are more than
  ``max(MARKED_S, MARKED_FRACTION x the longer duration)`` apart (2 s or 5 %).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from footnav.core.errors import InvalidInputError
from footnav.core.types import ImuData, StanceResult

__all__ = [
    "CUT_WARN_S",
    "MARKED_FRACTION",
    "MARKED_S",
    "MIN_COMMON_S",
    "CommonSpan",
    "FootCut",
    "common_bounds",
    "common_span",
    "slice_stance",
    "span_difference",
]

#: Shortest common span a coupled fusion runs on, s (a few steps).
MIN_COMMON_S = 3.0
#: A coupled fusion warns when a foot loses more than this, s.
CUT_WARN_S = 1.0
#: Spans differ markedly when starts or ends are more than max(MARKED_S, MARKED_FRACTION x the
#: longer duration) apart.
MARKED_S = 2.0
MARKED_FRACTION = 0.05

_SYNC_HINT = (
    "if both feet were recorded together their clocks differ: add the clock-sync stage "
    "(make_pipeline(..., sync='data'), or sync='exchanges' from message exchanges; footnav run --sync data) "
    "or align the time stamps before fusing"
)


def _fmt_span(t: np.ndarray) -> str:
    return f"{float(t[0]):.6g}..{float(t[-1]):.6g} s ({float(t[-1] - t[0]):.4g} s)"


@dataclass(frozen=True)
class FootCut:
    """One foot's part of the common span: samples ``start_index:stop_index`` of ``n_samples``."""

    start_index: int
    stop_index: int
    n_samples: int
    cut_before_s: float
    cut_after_s: float

    @property
    def cut(self) -> bool:
        """True when the foot has samples outside the common span."""
        return self.start_index > 0 or self.stop_index < self.n_samples

    def as_meta(self) -> dict[str, Any]:
        """The record for ``meta``."""
        return {
            "start_index": self.start_index,
            "stop_index": self.stop_index,
            "n_samples": self.n_samples,
            "cut_before_s": self.cut_before_s,
            "cut_after_s": self.cut_after_s,
        }


@dataclass(frozen=True)
class CommonSpan:
    """The common span ``start_s..stop_s`` of two feet and each foot's cut."""

    start_s: float
    stop_s: float
    left: FootCut
    right: FootCut
    left_span_s: tuple[float, float]
    right_span_s: tuple[float, float]

    @property
    def duration_s(self) -> float:
        """Length of the common span, s."""
        return self.stop_s - self.start_s

    @property
    def cut(self) -> bool:
        """True when either foot has samples outside the common span."""
        return self.left.cut or self.right.cut

    @property
    def largest_cut_s(self) -> float:
        """The largest part of either foot cut off, s."""
        return max(self.left.cut_before_s, self.left.cut_after_s, self.right.cut_before_s, self.right.cut_after_s)

    @property
    def warn(self) -> bool:
        """True when a foot loses more than :data:`CUT_WARN_S`."""
        return self.largest_cut_s > CUT_WARN_S

    def as_meta(self) -> dict[str, Any]:
        """The record for ``meta``."""
        return {
            "common_s": [self.start_s, self.stop_s],
            "left_s": list(self.left_span_s),
            "right_s": list(self.right_span_s),
            "left": self.left.as_meta(),
            "right": self.right.as_meta(),
        }

    def message(self, fusion: str, outside: str) -> str:
        """The warning of a coupled fusion that cut a foot: the spans, the cuts, what happened."""
        parts = []
        for foot, c in (("left", self.left), ("right", self.right)):
            if c.cut_before_s > 0 or c.cut_after_s > 0:
                parts.append(f"{foot} foot loses {c.cut_before_s:.3g} s before and {c.cut_after_s:.3g} s after")
        return (
            f"fusion {fusion!r}: the feet do not share their whole time span (left {self.left_span_s[0]:.6g}.."
            f"{self.left_span_s[1]:.6g} s, right {self.right_span_s[0]:.6g}..{self.right_span_s[1]:.6g} s); "
            f"fused on the common span {self.start_s:.6g}..{self.stop_s:.6g} s only ({'; '.join(parts)}); "
            f"{outside}; meta['span'] has the details ({_SYNC_HINT})"
        )


def _foot_cut(t: np.ndarray, start: float, stop: float) -> FootCut:
    i0 = int(np.searchsorted(t, start, side="left"))
    i1 = int(np.searchsorted(t, stop, side="right"))
    return FootCut(i0, i1, len(t), max(0.0, float(start - t[0])), max(0.0, float(t[-1] - stop)))


def common_span(left: ImuData, right: ImuData, *, min_common_s: float = MIN_COMMON_S, fusion: str = "") -> CommonSpan:
    """The time span both feet cover and what each foot loses to it.

    Parameters
    ----------
    left, right
        The two feet's recordings (times in s on what should be one clock).
    min_common_s
        Shortest common span accepted, s.
    fusion
        The fusion's name, for the message.

    Raises
    ------
    InvalidInputError
        Field ``t``: the spans do not overlap or overlap for less than ``min_common_s``; the
        message names both spans and how to put the feet on one clock.
    """
    tl, tr = np.asarray(left.t, float), np.asarray(right.t, float)
    if len(tl) == 0 or len(tr) == 0:
        raise InvalidInputError("a foot has no samples", field="t")
    start, stop = common_bounds((tl[0], tl[-1]), (tr[0], tr[-1]), min_common_s=min_common_s, fusion=fusion)
    return CommonSpan(
        start_s=float(start),
        stop_s=float(stop),
        left=_foot_cut(tl, start, stop),
        right=_foot_cut(tr, start, stop),
        left_span_s=(float(tl[0]), float(tl[-1])),
        right_span_s=(float(tr[0]), float(tr[-1])),
    )


def common_bounds(
    left_s: tuple[float, float], right_s: tuple[float, float], *, min_common_s: float = MIN_COMMON_S, fusion: str = ""
) -> tuple[float, float]:
    """The common span (start, stop), s, of two feet's spans (first and last time, s), as
    :func:`common_span` finds and refuses it (an online stream knows only the ends)."""
    tl, tr = np.asarray(left_s, float), np.asarray(right_s, float)
    start, stop = max(tl[0], tr[0]), min(tl[-1], tr[-1])
    who = f"fusion {fusion!r} uses both feet at the same instants, but " if fusion else ""
    if stop < start + min_common_s:
        if stop <= start:
            gap = f"they share no time span ({float(start - stop):.6g} s apart)"
        else:
            gap = f"they share only {float(stop - start):.3g} s (at least {min_common_s:g} s needed)"
        raise InvalidInputError(
            f"{who}{gap}: left foot {_fmt_span(tl)}, right foot {_fmt_span(tr)}; {_SYNC_HINT}; "
            "or use the 'independent' fusion, which estimates each foot alone",
            field="t",
        )
    return start, stop


def span_difference(left: ImuData, right: ImuData) -> dict[str, Any]:
    """How far apart the feet's spans start and end (s), and whether that is marked.

    Returns ``{"left_s", "right_s", "start_difference_s", "end_difference_s", "tolerance_s",
    "marked", "message"}``: ``marked`` when the starts or the ends are more than ``tolerance_s`` =
    max(:data:`MARKED_S`, :data:`MARKED_FRACTION` x the longer duration) apart; ``message`` the
    warning text then (else None).
    """
    tl, tr = np.asarray(left.t, float), np.asarray(right.t, float)
    d_start, d_end = float(tr[0] - tl[0]), float(tr[-1] - tl[-1])
    tol = max(MARKED_S, MARKED_FRACTION * max(float(tl[-1] - tl[0]), float(tr[-1] - tr[0])))
    marked = abs(d_start) > tol or abs(d_end) > tol
    message = None
    if marked:
        message = (
            f"the feet's time spans differ markedly: left foot {_fmt_span(tl)}, right foot {_fmt_span(tr)} "
            f"(the right starts {d_start:+.4g} s and ends {d_end:+.4g} s from the left; more than {tol:.3g} s); "
            f"each foot is estimated alone over its own span and the path covers the common part only; {_SYNC_HINT}"
        )
    return {
        "left_s": [float(tl[0]), float(tl[-1])],
        "right_s": [float(tr[0]), float(tr[-1])],
        "start_difference_s": d_start,
        "end_difference_s": d_end,
        "tolerance_s": tol,
        "marked": marked,
        "message": message,
    }


def slice_stance(stance: StanceResult, start: int, stop: int) -> StanceResult:
    """Samples ``start:stop`` of a stance result: mask, phases and score cut, events inside kept
    and shifted by ``-start``."""
    events = {
        k: np.asarray(v)[(np.asarray(v) >= start) & (np.asarray(v) < stop)] - start for k, v in stance.events.items()
    }
    return StanceResult(
        mask=stance.mask[start:stop],
        events=events,
        phases=None if stance.phases is None else stance.phases[start:stop],
        score=None if stance.score is None else stance.score[start:stop],
        meta={**stance.meta, "sliced": [int(start), int(stop)]},
    )
