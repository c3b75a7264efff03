"""The unsupervised initial guess of the HMM detector: K-means, re-ordered into the cyclic order.

Li et al. (2018), Sec. 2: "Commonly, the initialization is performed using Kmeans". K-means on
the model-rate observations gives four clusters; the stillest is stance; the others are put in
the order push-up, swing, step-down by :func:`~footnav.detectors.hmm.reorder.cyclic_order_votes`
on each recording's filtered most significant rate axis. The re-labelled sequence gives the
initial transition matrix (:func:`initial_transmat`) and, in
:func:`~footnav.detectors.hmm.model.initial_emissions`, the initial means and covariances.

This is also where data that cannot teach the model are refused, each with its own message: far
too few samples, no walking (all standstill), no standstill, fewer than ``MIN_GAIT_CYCLES`` gait
cycles.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import stance_intervals
from footnav.detectors.hmm.features import significant_axis
from footnav.detectors.hmm.model import N_STATES
from footnav.detectors.hmm.reorder import CyclicOrder, cyclic_order_votes

__all__ = ["MIN_GAIT_CYCLES", "STANDSTILL_MAX_RADPS", "InitialGuess", "initial_guess", "initial_transmat"]

#: A gait model needs this many movement periods (gait cycles) to be learned: 40 free parameters
#: (4 means, 4 full 3x3 covariances, 4 transition probabilities) and a majority vote need more
#: than one or two strides.
MIN_GAIT_CYCLES = 3
#: Bound on the angular rate of the stillest K-means cluster (median |w| of its samples), rad/s.
#: footnav's threshold detectors call a foot still below 0.5 rad/s (29 deg/s); a recording whose
#: stillest cluster turns faster has no standstill, one whose fastest cluster turns slower no walk.
STANDSTILL_MAX_RADPS = 0.5
#: Quantile of |w| over the stillest K-means cluster that must lie below STANDSTILL_MAX_RADPS. Not
#: the median: on running (pyshoe 2017-11-27-11-24-07) K-means gives the stance cluster the slow
#: parts of the swing too and its median is 0.55 rad/s while its lower quartile is 0.02 rad/s; a
#: walk with its stances cut out has a lower quartile of 0.64 rad/s.
STANDSTILL_QUANTILE = 0.25
#: The re-ordering's stance threshold (``reorder_min_stance_s``, the paper's "e.g. 0.3s") is lowered
#: to this fraction of the 90th percentile of the K-means stance runs when that is shorter: running
#: stances last 0.15-0.2 s and none reaches 0.3 s (1-2 movement periods found in 20 s of running).
REORDER_STANCE_FRACTION = 0.5
#: K-means restarts (scikit-learn's n_init); the best of these by inertia is used.
KMEANS_N_INIT = 10


@dataclass(frozen=True)
class InitialGuess:
    """Where Baum-Welch starts, and how the guess was made.

    Attributes
    ----------
    z0
        Re-ordered K-means labels: the cyclic state of each model-rate sample, (M,).
    startprob
        Initial state probabilities pi, uniform (N_STATES,).
    transmat
        Initial transition matrix of eq. (1), :func:`initial_transmat`, (N_STATES, N_STATES).
    kmeans_centers
        K-means cluster centres in K-means' label order, (N_STATES, F).
    order
        The re-ordering and its votes.
    reorder_min_stance_s
        The stance threshold of the re-ordering actually used, s.
    significant_axes
        Each recording's most significant gyro axis.
    """

    z0: NDArray[np.int64]
    startprob: NDArray[np.float64]
    transmat: NDArray[np.float64]
    kmeans_centers: NDArray[np.float64]
    order: CyclicOrder
    reorder_min_stance_s: float
    significant_axes: list[int]


def initial_transmat(z0: NDArray[np.int64], lengths: Sequence[int]) -> NDArray[np.float64]:
    """Transition matrix of eq. (1) with Delta_k from the mean run length of each state in ``z0``.

    A geometric duration of mean L samples leaves with probability 1/L: Delta_k = (runs of state
    k) / (samples of state k), capped at 0.5. ``lengths`` are the lengths of the concatenated
    recordings; each recording's first sample starts a run.
    """
    run_start = np.ones(len(z0), dtype=bool)
    run_start[1:] = z0[1:] != z0[:-1]
    run_start[np.cumsum([0, *lengths[:-1]])] = True  # a recording's first sample starts a run
    n_runs = np.bincount(z0[run_start], minlength=N_STATES)
    transmat = np.zeros((N_STATES, N_STATES))
    for k in range(N_STATES):
        # K-means labels never leave a cluster empty; 0.5 caps a state made of 1-sample runs
        leave = min(n_runs[k] / max(int(np.sum(z0 == k)), 1), 0.5)
        transmat[k, k] = 1.0 - leave
        transmat[k, (k + 1) % N_STATES] = leave
    return transmat


def initial_guess(
    x: NDArray[np.float64],
    lengths: Sequence[int],
    rate: float,
    *,
    total_s: float,
    lowpass_cutoff_hz: float,
    reorder_min_stance_s: float,
    seed: int,
) -> InitialGuess:
    """K-means guess of the four states, re-ordered into the cyclic order.

    Parameters
    ----------
    x
        The recordings' observations on the model-rate grid, concatenated, (M, F); the first
        three features are the angular rate, rad/s.
    lengths
        The length of each recording in ``x`` (hmmlearn's convention).
    rate
        The model rate, Hz.
    total_s
        The recordings' total duration, s (for the messages).
    lowpass_cutoff_hz, reorder_min_stance_s, seed
        The detector's parameters.

    Raises
    ------
    InvalidInputError
        Far too few samples, no walking, no standstill, fewer than ``MIN_GAIT_CYCLES`` cycles.
    """
    from sklearn.cluster import KMeans

    n_feat = x.shape[1]
    # per state: a mean, a full covariance and one exit probability Delta_k
    n_free = N_STATES * (n_feat + n_feat * (n_feat + 1) // 2 + 1)
    if len(x) < n_free:
        raise InvalidInputError(
            f"{total_s:.3g} s of data ({len(x)} samples at {rate:g} Hz) is far too short to learn the "
            f"4-state gait model ({n_free} free parameters); need at least {MIN_GAIT_CYCLES} gait cycles"
        )
    gyr_norm = np.linalg.norm(x[:, :3], axis=1)

    # K-means guess (Li et al. (2018), Sec. 2: "Commonly, the initialization is performed using Kmeans")
    km = KMeans(n_clusters=N_STATES, n_init=KMEANS_N_INIT, random_state=seed).fit(x)
    labels = km.labels_.astype(np.int64)
    counts = np.bincount(labels, minlength=N_STATES)
    median_rate = np.array([np.median(gyr_norm[labels == k]) if counts[k] else np.inf for k in range(N_STATES)])
    stance_label = int(np.argmin(median_rate))
    fastest = float(np.max(median_rate[np.isfinite(median_rate)]))
    if fastest < STANDSTILL_MAX_RADPS:
        raise InvalidInputError(
            f"no walking: all standstill? Every K-means cluster of the angular rate turns slower than "
            f"{STANDSTILL_MAX_RADPS:g} rad/s (the fastest at {fastest:.3g} rad/s median); the HMM learns the "
            "gait phases from walking (fit on a walk, then detect this recording)"
        )
    still_rate = float(np.quantile(gyr_norm[labels == stance_label], STANDSTILL_QUANTILE))
    if still_rate > STANDSTILL_MAX_RADPS:
        raise InvalidInputError(
            f"no standstill: the stillest quarter of the stillest K-means cluster of the angular rate turns "
            f"faster than {still_rate:.3g} rad/s, above {STANDSTILL_MAX_RADPS:g} rad/s; the foot never "
            "stands still, so there is no stance phase to learn"
        )

    # re-ordering into the cyclic order (Fig. 2), per recording on its own filtered signal
    bounds = np.cumsum([0, *lengths])
    per_axis = [significant_axis(x[a:b, :3], rate, lowpass_cutoff_hz) for a, b in zip(bounds[:-1], bounds[1:])]
    axis_signal = np.concatenate([sig for sig, _ in per_axis])
    km_runs = stance_intervals(labels == stance_label)
    km_run_s = (km_runs[:, 1] - km_runs[:, 0]) / rate
    min_stance_s = float(reorder_min_stance_s)
    if len(km_run_s):
        min_stance_s = min(min_stance_s, REORDER_STANCE_FRACTION * float(np.quantile(km_run_s, 0.9)))
    order = cyclic_order_votes(
        labels, axis_signal, rate, stance_label=stance_label, min_stance_s=min_stance_s, lengths=lengths
    )
    if order.n_movements < MIN_GAIT_CYCLES:
        raise InvalidInputError(
            f"found {order.n_movements} gait cycle(s) (movement periods between stance runs of at least "
            f"{min_stance_s:.3g} s) in {total_s:.3g} s of data; need at least {MIN_GAIT_CYCLES} to "
            "learn the gait model (recording too short, or no standstill between steps)"
        )
    state_of_label = np.argsort(order.permutation)
    z0 = state_of_label[labels]
    transmat = initial_transmat(z0, lengths)
    startprob = np.full(N_STATES, 1.0 / N_STATES)
    return InitialGuess(
        z0=z0,
        startprob=startprob,
        transmat=transmat,
        kmeans_centers=km.cluster_centers_,
        order=order,
        reorder_min_stance_s=min_stance_s,
        significant_axes=[int(axis) for _, axis in per_axis],
    )
