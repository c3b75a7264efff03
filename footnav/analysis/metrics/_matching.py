"""One-to-one matching of detected to reference events within a tolerance (linear sum
assignment), and the timing error of the matched events."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linear_sum_assignment

from footnav.analysis.metrics._checks import _events, _readonly
from footnav.core.errors import InvalidParameterError


class EventMatches(NamedTuple):
    """One-to-one matching of events (:func:`match_events`); a plain 3-tuple.

    Attributes
    ----------
    matches
        (K, 2) pairs ``[detected, reference]`` of event positions (samples), sorted by reference.
    missed
        Reference events without a detected partner (sorted).
    false
        Detected events without a reference partner (sorted).
    """

    matches: NDArray
    missed: NDArray
    false: NDArray


def match_events(detected: ArrayLike, reference: ArrayLike, *, tolerance: float) -> EventMatches:
    """Match detected to reference events one to one, within ``tolerance`` samples.

    A detected event d and a reference event r may match if ``|d - r| <= tolerance``. Among all
    one-to-one matchings the one with the most pairs is chosen, and among those the one with the
    smallest total ``sum |d - r|`` (linear sum assignment, ``scipy.optimize.linear_sum_assignment``,
    on each cluster of events that lie within ``tolerance`` of each other, so large inputs stay
    cheap). Each event is used at most once: a detected event never counts for two references.

    Parameters
    ----------
    detected, reference
        Event positions in samples (K,) and (L,), any order; either may be empty.
    tolerance
        Largest allowed ``|d - r|`` in samples (inclusive), >= 0.

    Returns
    -------
    EventMatches
        ``(matches, missed, false)``; found = ``len(matches)``.
    """
    det = _events(detected, "detected")
    ref = _events(reference, "reference")
    tol = float(tolerance)
    if not np.isfinite(tol) or tol < 0:
        raise InvalidParameterError(f"tolerance must be >= 0 samples, got {tolerance!r}")
    dtype = np.result_type(det.dtype, ref.dtype)
    det_s = np.sort(det).astype(dtype)
    ref_s = np.sort(ref).astype(dtype)
    nd, nr = len(det_s), len(ref_s)
    used_d = np.zeros(nd, bool)
    used_r = np.zeros(nr, bool)
    pairs: list[tuple[int, int]] = []
    if nd and nr:
        values = np.concatenate((det_s, ref_s)).astype(np.float64)
        is_ref = np.concatenate((np.zeros(nd, bool), np.ones(nr, bool)))
        idx = np.concatenate((np.arange(nd), np.arange(nr)))
        order = np.argsort(values, kind="stable")
        values, is_ref, idx = values[order], is_ref[order], idx[order]
        # No pair can span a gap wider than the tolerance, so clusters are independent problems.
        cuts = np.flatnonzero(np.diff(values) > tol) + 1
        for lo, hi in zip(np.concatenate(([0], cuts)), np.concatenate((cuts, [len(values)]))):
            r_in = is_ref[lo:hi]
            di, ri = idx[lo:hi][~r_in], idx[lo:hi][r_in]
            if len(di) == 0 or len(ri) == 0:
                continue
            if len(di) == 1 and len(ri) == 1:
                if abs(float(det_s[di[0]]) - float(ref_s[ri[0]])) <= tol:
                    pairs.append((int(di[0]), int(ri[0])))
                continue
            c = np.abs(det_s[di].astype(np.float64)[:, None] - ref_s[ri].astype(np.float64)[None, :])
            allowed = c <= tol
            # A forbidden pair costs more than any complete set of allowed pairs, so the assignment
            # first maximises the number of allowed pairs, then minimises their summed distance.
            big = (tol + 1.0) * (min(c.shape) + 1)
            rows, cols = linear_sum_assignment(np.where(allowed, c, big))
            for r_, c_ in zip(rows, cols):
                if allowed[r_, c_]:
                    pairs.append((int(di[r_]), int(ri[c_])))
    if pairs:
        pi = np.array(pairs, dtype=np.int64)
        pi = pi[np.argsort(pi[:, 1], kind="stable")]
        used_d[pi[:, 0]] = True
        used_r[pi[:, 1]] = True
        matches = np.stack((det_s[pi[:, 0]], ref_s[pi[:, 1]]), axis=1)
    else:
        matches = np.empty((0, 2), dtype=dtype)
    return EventMatches(_readonly(matches), _readonly(ref_s[~used_r]), _readonly(det_s[~used_d]))


@dataclass(frozen=True)
class TimingError:
    """Timing error of matched events, s.

    Attributes
    ----------
    mean_abs_error_s, std_abs_error_s, max_abs_error_s
        Mean, population standard deviation (ddof = 0) and maximum of ``|t_det - t_ref|``, s
        (nan when nothing matched).
    mean_error_s
        Mean signed ``t_det - t_ref`` (positive = detected late), s.
    n_matched, n_missed, n_false
        Event counts of the underlying :func:`match_events`.
    """

    mean_abs_error_s: float
    std_abs_error_s: float
    max_abs_error_s: float
    mean_error_s: float
    n_matched: int
    n_missed: int
    n_false: int


def event_timing_error(detected: ArrayLike, reference: ArrayLike, *, tolerance: float, rate_hz: float) -> TimingError:
    """Timing error in s of detected gait events against reference events.

    Events are matched one to one within ``tolerance`` samples (:func:`match_events`); for the K
    matched pairs ``e_k = (d_k - r_k) / rate_hz`` and the result gives mean, std and max of
    ``|e_k|`` and the mean of ``e_k``. Complements the counts of [Li2018] Table 1 (which gives no
    timing figure) for detectors that report gait events (heel strike, toe off, ...).

    Parameters
    ----------
    detected, reference
        Event positions in samples (K,), (L,).
    tolerance
        Matching tolerance in samples.
    rate_hz
        Sampling rate in Hz converting samples to s.
    """
    if not np.isfinite(rate_hz) or rate_hz <= 0:
        raise InvalidParameterError(f"rate_hz must be a positive rate in Hz, got {rate_hz!r}")
    m = match_events(detected, reference, tolerance=tolerance)
    nan = float("nan")
    if len(m.matches) == 0:
        return TimingError(nan, nan, nan, nan, 0, len(m.missed), len(m.false))
    e = (m.matches[:, 0].astype(np.float64) - m.matches[:, 1].astype(np.float64)) / float(rate_hz)
    ae = np.abs(e)
    return TimingError(
        float(ae.mean()), float(ae.std()), float(ae.max()), float(e.mean()), len(m.matches), len(m.missed), len(m.false)
    )
