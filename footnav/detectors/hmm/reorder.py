"""Re-ordering of K-means labels into the cyclic order of the gait phases (Li et al. (2018), Sec. 2, Fig. 2).

K-means gives the four clusters of the angular rate arbitrary labels; "Kmeans is not able to
provide [the transition order] since it does not take into account past observations" (Sec. 2).
:func:`cyclic_order_votes` finds which label is stance, push-up, swing and step-down from the
order in which the labels appear at the peaks and valleys of the filtered rate in each movement
period, by majority vote.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import stance_intervals
from footnav.detectors.hmm.model import N_STATES

__all__ = ["CyclicOrder", "cyclic_order", "cyclic_order_votes"]


@dataclass(frozen=True)
class CyclicOrder:
    """Result of :func:`cyclic_order_votes`.

    Attributes
    ----------
    permutation
        ``permutation[k]`` is the label of cyclic state k (0 stance, 1 push-up, 2 swing,
        3 step-down), shape (n_states,).
    n_movements
        Movement periods found (between two stance runs of at least ``min_stance_s``).
    orders
        The order list of each movement period: labels of its peaks and valleys in time order,
        stance label dropped, each label kept at its first appearance.
    votes
        ``votes[p][label]``: movement periods whose first label not yet assigned was ``label``,
        when position p (1 push-up, 2 swing, 3 step-down) was decided; an empty list when no vote.
    fallback
        Positions decided without votes, by the labels' mean relative time in the movement periods.
    """

    permutation: NDArray[np.int64]
    n_movements: int
    orders: list[list[int]]
    votes: list[list[int]]
    fallback: list[int]


def _movement_periods(stance: NDArray[np.bool_], min_len: int) -> NDArray[np.int64]:
    """(M, 2) start/stop of the stretches between consecutive stance runs of >= min_len samples."""
    runs = stance_intervals(stance)
    runs = runs[(runs[:, 1] - runs[:, 0]) >= min_len]
    if len(runs) < 2:
        return np.empty((0, 2), dtype=np.int64)
    return np.stack([runs[:-1, 1], runs[1:, 0]], axis=1)


def cyclic_order_votes(
    labels: ArrayLike,
    signal: ArrayLike,
    rate_hz: float,
    *,
    stance_label: int | None = None,
    min_stance_s: float = 0.3,
    n_states: int = N_STATES,
    lengths: Sequence[int] | None = None,
) -> CyclicOrder:
    """Re-order K-means labels into the cyclic order of the gait phases, with the vote details.

    Li et al. (2018), Sec. 2 (diagram of Fig. 2), as implemented here:

    1. The stance label is the stillest cluster (given as ``stance_label``, else the label whose
       samples have the smallest mean ``|signal|``).
    2. "we search for the movement durations between every stance phase that lasts longer than a
       threshold, e.g. 0.3s": runs of the stance label lasting at least ``min_stance_s`` delimit
       the movement periods. Shorter stance runs do not: K-means gives the stance label to the
       zero crossings of the rate inside a swing ("angular rate goes across zero at transition
       between two states, then Kmeans wrongly classifies the state as stance phase"), which cut
       a movement into pieces much shorter than 0.3 s.
    3. "we find the states corresponding to all the peaks and valleys in every movement duration":
       the labels at the local maxima and minima of ``signal`` (the low-pass filtered rate of the
       most significant axis, :func:`~footnav.detectors.hmm.features.significant_axis`) inside
       the period; the stance label is dropped ("the peaks and valleys indicate the states of
       non-stance phases").
    4. "we sort these states by time and only keep the first one if one state repeats twice or
       more": one order list per movement period.
    5. "we count the most firstly appeared state in the order list, which means the push-up phase,
       the state of swing phase and step-down phase can be derived in the same way": position p
       (push-up, then swing, then step-down) goes to the label that comes first most often in the
       order lists once the labels of the earlier positions are removed (ties: the smaller label).
       A position without any vote (e.g. when the step-down peak always carries the push-up
       label, as on a symmetric simulated step) takes the remaining label that comes earliest on
       average in the movement periods (relative time 0 at the start, 1 at the end).

    Parameters
    ----------
    labels
        K-means labels (N,), integers 0 .. n_states - 1.
    signal
        Low-pass filtered angular rate of the most significant axis (N,), rad/s.
    rate_hz
        Sampling rate of both, Hz.
    stance_label
        The stance cluster's label, or None to pick it from ``signal``.
    min_stance_s
        Stance runs at least this long delimit movement periods, s.
    n_states
        Number of labels / cyclic states.
    lengths
        Lengths of concatenated independent recordings (hmmlearn's convention); movement periods
        never span two of them. None: one recording.

    Returns
    -------
    CyclicOrder
        ``permutation`` and the vote details.
    """
    lab = np.asarray(labels)
    sig = np.asarray(signal, dtype=np.float64)
    if lab.ndim != 1 or sig.shape != lab.shape:
        raise InvalidInputError(f"labels {lab.shape} and signal {sig.shape} must be 1-D of the same length")
    if len(lab) and (lab.min() < 0 or lab.max() >= n_states):
        raise InvalidInputError(f"labels must lie in 0 .. {n_states - 1}, found {lab.min()} .. {lab.max()}")
    lab = lab.astype(np.int64)
    if stance_label is None:
        sums = np.bincount(lab, weights=np.abs(sig), minlength=n_states)
        counts = np.bincount(lab, minlength=n_states)
        stance_label = int(np.argmin(np.where(counts > 0, sums / np.maximum(counts, 1), np.inf)))
    min_len = max(1, int(round(min_stance_s * rate_hz)))
    bounds = np.cumsum([0, *(lengths if lengths is not None else [len(lab)])])

    orders: list[list[int]] = []
    from scipy.signal import find_peaks  # here: scipy.signal takes ~0.3 s to import

    position_sum = np.zeros(n_states)
    position_count = np.zeros(n_states)
    for lo, hi in zip(bounds[:-1], bounds[1:]):
        seg_lab, seg_sig = lab[lo:hi], sig[lo:hi]
        for start, stop in _movement_periods(seg_lab == stance_label, min_len):
            part = seg_sig[start:stop]
            extrema = np.sort(np.concatenate([find_peaks(part)[0], find_peaks(-part)[0]]))
            seen = seg_lab[start:stop][extrema]
            seen = seen[seen != stance_label]
            # np.unique's first indices, re-sorted by time: "only keep the first one"
            _, first = np.unique(seen, return_index=True)
            orders.append([int(v) for v in seen[np.sort(first)]])
            rel = (np.arange(stop - start) + 0.5) / (stop - start)
            position_sum += np.bincount(seg_lab[start:stop], weights=rel, minlength=n_states)
            position_count += np.bincount(seg_lab[start:stop], minlength=n_states)

    mean_position = np.where(position_count > 0, position_sum / np.maximum(position_count, 1), np.inf)
    assigned = [stance_label]
    votes: list[list[int]] = []
    fallback: list[int] = []
    for p in range(1, n_states):
        count = np.zeros(n_states, dtype=np.int64)
        for order in orders:
            rest = [v for v in order if v not in assigned]
            if rest:
                count[rest[0]] += 1
        if count.sum() > 0:
            votes.append(count.tolist())
            assigned.append(int(np.argmax(count)))
        else:
            votes.append([])
            fallback.append(p)
            free = [v for v in range(n_states) if v not in assigned]
            # stable sort: labels that never occur in a movement (inf) keep label order
            assigned.append(int(min(free, key=lambda v: (mean_position[v], v))))
    return CyclicOrder(np.asarray(assigned, dtype=np.int64), len(orders), orders, votes, fallback)


def cyclic_order(
    labels: ArrayLike,
    signal: ArrayLike,
    rate_hz: float,
    *,
    stance_label: int | None = None,
    min_stance_s: float = 0.3,
    n_states: int = N_STATES,
    lengths: Sequence[int] | None = None,
) -> NDArray[np.int64]:
    """Permutation putting K-means labels into the cyclic order of Li et al. (2018) (Sec. 2, Fig. 2).

    ``permutation[k]`` is the K-means label of cyclic state k (0 stance, 1 push-up, 2 swing,
    3 step-down); the re-labelled sequence is ``argsort(permutation)[labels]``. See
    :func:`cyclic_order_votes` for the procedure and the parameters.
    """
    return cyclic_order_votes(
        labels,
        signal,
        rate_hz,
        stance_label=stance_label,
        min_stance_s=min_stance_s,
        n_states=n_states,
        lengths=lengths,
    ).permutation
