"""Unsupervised cyclic left-to-right HMM stance detector: Li, Derrode, Benyoussef and
Pieczynski, "Unsupervised pedestrian trajectory reconstruction from IMU sensors", TAIMA 2018, Sec. 2.

A step is a cycle of four hidden states (Li et al. (2018), Sec. 1-2, after Mannini and Sabatini 2011)::

    0 stance -> 1 push-up -> 2 swing -> 3 step-down -> 0 stance -> ...

with the cyclic left-to-right transition matrix of eq. (1) -- each state stays or moves to the next,
step-down returns to stance, every other entry is a structural zero -- and Gaussian emissions of
the 3-axis angular rate ``y_n = [w_x, w_y, w_z]`` (rad/s, sensor frame), eq. (2):
``p(y_n | x_n = k) = N(mu_k, Sigma_k)`` with full 3x3 covariances. Theta = {pi_k, Delta_k, mu_k,
Sigma_k} is learned without labels by Baum-Welch (hmmlearn's ``GaussianHMM``), from an initial
guess made by K-means and re-ordered into the cyclic order (:func:`cyclic_order`, Li et al. (2018), Fig. 2),
because "Kmeans is not able to provide [the transition order] since it does not take into account
past observations" (Sec. 2). The stance state is the paper's zero-velocity state ("Stance phase is
also called zero-velocity state, as the foot is not moving", Sec. 1): the detector's mask is the
Viterbi path's stance state, with no post-processing.

What footnav adds to the paper, and why:

* **Model rate.** The HMM runs at ``model_rate_hz`` (100 Hz, the paper's rate, Sec. 4): every
  recording is low-pass filtered (when faster) and interpolated onto that grid, and the results are
  mapped back to the recording's samples. An HMM's per-sample transition probabilities Delta_k fix
  the expected phase durations *in samples*, and its emission log-likelihoods grow with the number
  of (correlated) samples per second: at 400 Hz, the zero crossings of the pitch rate inside the
  swing are four times as many samples and outweigh the transition penalty, and EM ends with
  spurious one-sample stances (22 false steps on a simulated 30 m walk; none at 100 Hz). At a fixed
  model rate the learned model means the same thing at every recording rate, and one fitted on a
  100 Hz recording applies unchanged to a 400 Hz one.
* **Initial probabilities** pi are kept uniform, not learned: EM on one recording drives pi to the
  recording's first state (pi becomes one-hot), which would forbid a new recording to start in any
  other phase.
* **Covariance regularisation**: ``min_std**2`` is added to each emission variance after every
  M-step (scikit-learn's ``reg_covar``; hmmlearn's ``min_covar`` only acts at initialisation for
  full covariances), so a noise-free stance cannot make a covariance singular.

Events come from the Viterbi path's transitions, each at the first sample of the new phase:
stance -> push-up is ``heel_off``, push-up -> swing ``toe_off``, swing -> step-down
``heel_strike``, step-down -> stance ``foot_flat``. The model splits the non-stance part of a step by
the sense of the foot's pitch rotation, so these are the pitch-rate landmarks rather than ground
contacts: ``toe_off`` is where the toe-down rotation of push-off ends (the pitch rate's zero
crossing early in the swing), ``heel_strike`` where the toe-up rotation of the swing ends.
"""

from __future__ import annotations

import json
import logging
import math
from dataclasses import dataclass
from numbers import Integral
from os import PathLike
from pathlib import Path as FilePath
from typing import Any, ClassVar, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.signal import butter, find_peaks, sosfiltfilt

from footnav.core.component import MAX_DURATION_S, StanceDetector, require, require_in_range, require_positive
from footnav.core.errors import (
    DataQualityWarning,
    FootnavWarning,
    GaitModelError,
    HmmNotFittedError,
    InvalidInputError,
    InvalidParameterError,
)
from footnav.core.types import GRAVITY_MPS2, ImuData, StanceResult, stance_intervals
from footnav.core.warning_log import recording, warn

__all__ = [
    "HmmDetector",
    "HmmNotFittedError",
    "GaitModelError",
    "CyclicOrder",
    "cyclic_order",
    "cyclic_order_votes",
    "significant_axis",
    "lowpass",
    "PHASE_NAMES",
    "FEATURES",
    "STRUCTURE",
]

#: The four hidden states of Li et al. (2018) (Omega = {1, ..., 4}, Sec. 2), 0-based, in cyclic order.
PHASE_NAMES = ("stance", "push_up", "swing", "step_down")
STANCE, PUSH_UP, SWING, STEP_DOWN = range(len(PHASE_NAMES))
N_STATES = len(PHASE_NAMES)

#: Allowed transitions of eq. (1): state k stays or moves to k+1, step-down returns to stance.
STRUCTURE = (np.eye(N_STATES, dtype=bool) | np.roll(np.eye(N_STATES, dtype=bool), 1, axis=1))
STRUCTURE.setflags(write=False)

#: Gait events marked at each transition (name, from state, to state), at the first sample of the new state.
EVENTS = (
    ("heel_off", STANCE, PUSH_UP),
    ("toe_off", PUSH_UP, SWING),
    ("heel_strike", SWING, STEP_DOWN),
    ("foot_flat", STEP_DOWN, STANCE),
)

#: Observation vectors: the paper's 3-axis angular rate (rad/s), optionally with |f| - g (m/s^2).
FEATURES = {"gyr": ("gyr_x", "gyr_y", "gyr_z"), "gyr+acc_norm": ("gyr_x", "gyr_y", "gyr_z", "acc_norm")}

#: Order of every Butterworth low-pass here; applied forwards and backwards (zero phase), so the
#: magnitude response is squared (effective order 8) and peaks and valleys are not delayed.
BUTTER_ORDER = 4
#: Anti-alias cutoff before resampling to the model rate, as a fraction of the model rate (0.4 x
#: 100 Hz = 40 Hz): below the new Nyquist frequency (0.5) with margin for the filter's roll-off,
#: far above the gait's content (a few Hz).
ANTI_ALIAS_FRACTION = 0.4
#: Relative rate difference below which a recording is taken at the model rate as it is.
SAME_RATE_RTOL = 1e-6
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
#: Stance runs of the decoded training recording shorter than this are not steps (s): a stance
#: state visited for one or two model samples at a zero crossing of the swing's rate.
MICRO_STANCE_S = 0.05
#: Largest share of micro stance runs a learned model may produce on its training recording (one is
#: always tolerated).
MAX_MICRO_STANCE_SHARE = 0.01
#: Factor on ``min_std`` of the single documented refit when the check after decoding fails.
FALLBACK_MIN_STD_FACTOR = 4.0
#: K-means restarts (scikit-learn's n_init); the best of these by inertia is used.
KMEANS_N_INIT = 10
#: Format tag and version of :meth:`HmmDetector.save` files.
SAVE_FORMAT = "footnav-hmm-detector"
SAVE_VERSION = 1

_LOG = logging.getLogger("hmmlearn")


# ---------------------------------------------------------------------------------------------
# signal helpers
# ---------------------------------------------------------------------------------------------
def lowpass(x: ArrayLike, cutoff_hz: float, rate_hz: float) -> NDArray[np.float64]:
    """Zero-phase Butterworth low-pass (order ``BUTTER_ORDER``, forwards and backwards) along axis 0.

    scipy.signal ``butter`` + ``sosfiltfilt``. A signal shorter than scipy's default edge padding
    is padded by what it has (no error on short recordings); a cutoff at or above the Nyquist
    frequency returns the signal unchanged.
    """
    x = np.asarray(x, dtype=np.float64)
    if cutoff_hz >= 0.5 * rate_hz or len(x) < 2:
        return x.copy()
    sos = butter(BUTTER_ORDER, cutoff_hz, btype="low", fs=rate_hz, output="sos")
    default_pad = 3 * (2 * len(sos) + 1)
    return sosfiltfilt(sos, x, axis=0, padlen=min(default_pad, len(x) - 1))


def significant_axis(gyr: ArrayLike, rate_hz: float, cutoff_hz: float) -> tuple[NDArray[np.float64], int]:
    """Low-pass filtered angular rate of its most significant axis (Li et al. (2018), Sec. 2, first step).

    "we filter the angular rate by using a low-pass Butterworth filter, and select the most
    significant axis, i.e. the axis whose signal has the largest magnitude": the axis with the
    largest RMS of the filtered rate (the pitch axis of a walking foot).

    Parameters
    ----------
    gyr
        Angular rate (N, 3) in rad/s.
    rate_hz
        Its sampling rate in Hz.
    cutoff_hz
        Cutoff frequency of the low-pass in Hz.

    Returns
    -------
    signal, axis
        The filtered rate of that axis (N,) in rad/s, and the axis index.
    """
    filtered = lowpass(gyr, cutoff_hz, rate_hz)
    axis = int(np.argmax(np.sqrt(np.mean(filtered**2, axis=0))))
    return filtered[:, axis], axis


# ---------------------------------------------------------------------------------------------
# re-ordering of K-means labels into the cyclic order (Li et al. (2018), Sec. 2, Fig. 2)
# ---------------------------------------------------------------------------------------------
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
       most significant axis, :func:`significant_axis`) inside the period; the stance label is
       dropped ("the peaks and valleys indicate the states of non-stance phases").
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


# ---------------------------------------------------------------------------------------------
# hmmlearn model
# ---------------------------------------------------------------------------------------------
def _gaussian_hmm_class():
    from hmmlearn.hmm import GaussianHMM

    class CyclicGaussianHMM(GaussianHMM):
        """hmmlearn's GaussianHMM with two changes that do not touch the model of eq. (1)-(2).

        * After every M-step ``min_covar`` is added to the covariance diagonals: hmmlearn's
          ``min_covar`` only enters the initialisation for full covariances.
        * Scaled forward-backward on emission probabilities divided by their per-sample maximum
          (the scale is added back to the log-likelihood): hmmlearn's scaling implementation
          exponentiates raw log-densities, which underflow to 0 for every state on a sample far
          from all Gaussians. The posteriors and transition counts are unchanged by a per-sample
          factor common to all states. About twice as fast as the log implementation.

        Structural zeros of ``transmat_`` stay zero under Baum-Welch: the expected count of a
        transition of probability 0 is 0 (hmmlearn's Dirichlet prior is 1, i.e. none).
        """

        def _fit_scaling(self, X):
            from hmmlearn import _hmmc

            log_frameprob = self._compute_log_likelihood(X)
            shift = log_frameprob.max(axis=1, keepdims=True)
            frameprob = np.exp(log_frameprob - shift)
            log_prob, fwdlattice, scaling = _hmmc.forward_scaling(self.startprob_, self.transmat_, frameprob)
            bwdlattice = _hmmc.backward_scaling(self.startprob_, self.transmat_, frameprob, scaling)
            posteriors = self._compute_posteriors_scaling(fwdlattice, bwdlattice)
            return frameprob, log_prob + float(shift.sum()), posteriors, fwdlattice, bwdlattice

        def _do_mstep(self, stats):
            super()._do_mstep(stats)
            if "c" in self.params:
                self._covars_ = self._covars_ + self.min_covar * np.eye(self.n_features)

    return CyclicGaussianHMM


def _build_hmm(
    startprob: NDArray, transmat: NDArray, means: NDArray, covars: NDArray, *, min_covar: float, seed: int,
    max_iter: int = 1, tol: float = 0.0, implementation: str = "log",
):
    cls = _gaussian_hmm_class()
    model = cls(
        n_components=N_STATES,
        covariance_type="full",
        min_covar=min_covar,
        covars_prior=0.0,
        init_params="",  # keep the re-ordered K-means initialisation
        params="tmc",  # pi stays uniform (module docstring)
        n_iter=max_iter,
        tol=tol,
        random_state=seed,
        implementation=implementation,
    )
    model.startprob_ = np.array(startprob, dtype=np.float64)
    model.transmat_ = np.array(transmat, dtype=np.float64)
    model.means_ = np.array(means, dtype=np.float64)
    model.covars_ = np.array(covars, dtype=np.float64)
    model.n_features = model.means_.shape[1]
    return model


def _check_model(model, x: NDArray, lengths: Sequence[int], gyr_norm: NDArray, rate: float) -> dict[str, Any]:
    """Check after decoding of a learned model on its training data (Viterbi path).

    * ``stance_stillest``: the stance state has the smallest median |w| of the four states, below
      ``STANDSTILL_MAX_RADPS`` (else its mask would not be stance: the inverted mask of a collapsed
      model).
    * ``micro_share``: share of stance runs shorter than ``MICRO_STANCE_S``, at most
      ``MAX_MICRO_STANCE_SHARE`` (else one non-stance state has become a broad catch-all of the
      movement and the stance state is visited for one or two samples at zero crossings of the
      swing's rate: false steps); a single one is tolerated.
    """
    states = np.concatenate([model.decode(x[a:b], algorithm="viterbi")[1]
                             for a, b in zip(np.cumsum([0, *lengths[:-1]]), np.cumsum(lengths))])
    med = [float(np.median(gyr_norm[states == k])) if np.any(states == k) else float("inf") for k in range(N_STATES)]
    stillest = bool(np.argmin(med) == STANCE and med[STANCE] < STANDSTILL_MAX_RADPS)
    runs = stance_intervals(states == STANCE)
    n_runs = len(runs)
    micro = int(np.sum((runs[:, 1] - runs[:, 0]) < MICRO_STANCE_S * rate)) if n_runs else 0
    share = micro / n_runs if n_runs else 1.0
    problems = []
    if not stillest:
        problems.append("stance state median |w| " + ", ".join(f"{m:.3g}" for m in med) + " rad/s per state")
    if micro > max(1.0, MAX_MICRO_STANCE_SHARE * n_runs):
        problems.append(f"{micro} of {n_runs} stance runs shorter than {MICRO_STANCE_S:g} s")
    return {
        "ok": not problems,
        "stance_stillest": stillest,
        "median_rate_per_state": med,
        "n_stance_runs": n_runs,
        "n_micro_stances": micro,
        "micro_share": share,
        "problem": "; ".join(problems),
    }


class _Capture(logging.Handler):
    """Collects hmmlearn's log records (convergence, degenerate-fit messages) during one fit."""

    def __init__(self) -> None:
        super().__init__(level=logging.DEBUG)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(f"hmmlearn {record.levelname.lower()}: {record.getMessage()}")


# ---------------------------------------------------------------------------------------------
# the detector
# ---------------------------------------------------------------------------------------------

def _is_int(value: Any) -> bool:
    return isinstance(value, Integral) and not isinstance(value, bool)


@dataclass(frozen=True)
class _ModelGrid:
    """One recording's features on the model-rate grid and the map back to its samples."""

    features: NDArray[np.float64]  # (M, F) at the model rate
    t_model: NDArray[np.float64]  # (M,) s
    nearest: NDArray[np.int64]  # (N,) model sample nearest to each recording sample


class HmmDetector(StanceDetector):
    """Cyclic left-to-right 4-state HMM of the gait phases, learned without labels (Li et al. (2018), Sec. 2).

    States stance, push-up, swing, step-down; transitions of eq. (1) (stay or go to the next state,
    step-down -> stance); full-covariance Gaussian emissions of the 3-axis angular rate, eq. (2);
    Baum-Welch from a K-means guess re-ordered into the cyclic order (:func:`cyclic_order`); Viterbi
    decoding. ``mask`` is the stance state, ``phases`` the Viterbi state (names in
    ``meta["phase_names"]``), ``score`` the posterior probability of stance (forward-backward),
    ``events`` the four transitions (module docstring).

    ``fit(imu or [imu, ...])`` learns the model and keeps it (``startprob_``, ``transmat_``,
    ``means_``, ``covars_``, ``fit_info_``); ``detect`` then applies it without refitting. An
    unfitted detector fits a fresh model on each recording it is given and does not keep it;
    ``meta["fitted_on_recording"]`` says which happened. ``save`` / ``load`` write and read the
    learned model as JSON.

    Parameters
    ----------
    features : str
        Observation vector: "gyr" (the paper's 3-axis angular rate, rad/s) or "gyr+acc_norm"
        (adds |specific force| - g, m/s^2).
    model_rate_hz : float
        Rate at which the HMM runs, Hz: recordings are low-pass filtered (when faster) and
        interpolated onto it, results mapped back. 100 Hz is the paper's rate.
    lowpass_cutoff_hz : float
        Cutoff of the zero-phase Butterworth low-pass applied to the angular rate before the
        re-ordering looks for its peaks and valleys, Hz.
    reorder_min_stance_s : float
        K-means stance runs at least this long delimit the movement periods of the re-ordering, s
        (the paper's 0.3 s).
    max_iter : int
        Largest number of Baum-Welch (EM) iterations.
    tol : float
        EM stops when an iteration gains less log-likelihood than this (nats, whole training set
        at the model rate).
    min_std : float
        Regularisation of the emission covariances: min_std**2 is added to each variance after
        every M-step, in the unit of the feature (rad/s for the angular rate, m/s^2 for acc_norm).
    seed : int
        Seed of K-means (and of hmmlearn); the same seed gives the same model and detections.

    Attributes
    ----------
    startprob_ : ndarray (4,)
        Initial state probabilities pi (uniform, not learned: module docstring).
    transmat_ : ndarray (4, 4)
        Learned transition matrix A of eq. (1), per model-rate sample; the structural zeros are
        exact zeros.
    means_ : ndarray (4, F)
        Learned emission means mu_k of eq. (2), feature units.
    covars_ : ndarray (4, F, F)
        Learned emission covariances Sigma_k of eq. (2).
    features_ : str
        ``features`` the model was learned with.
    model_rate_hz_ : float
        ``model_rate_hz`` the model was learned at.
    fit_info_ : dict
        How the fit went: EM iterations, convergence, log-likelihood, the re-ordering's votes,
        warnings and hmmlearn messages.

    Raises
    ------
    InvalidInputError
        When a model has to be learned from a recording without walking (all standstill), without
        standstill, or with fewer than ``MIN_GAIT_CYCLES`` gait cycles (e.g. 2 s long): the
        message names the problem. A fitted detector decodes any recording (an all-standstill one
        is all stance, one without standstill has no stance and no events).

    Notes
    -----
    Rate independence: every parameter is in seconds or physical units, and the model itself lives
    at ``model_rate_hz``: the transition probabilities Delta_k are per model-rate sample, i.e. the
    expected phase durations are in seconds, whatever the recording's rate (module docstring). The
    stance mask and phases come from the model sample nearest each recording sample (within half a
    model period, 5 ms at 100 Hz), the stance probability is interpolated linearly in time.

    Initialisation: K-means (scikit-learn, ``seed``, 10 restarts) on the model-rate observations;
    the stance cluster is the one whose samples have the smallest median |w|; the labels are put
    in the cyclic order by :func:`cyclic_order` on the filtered most significant gyro axis; the
    re-labelled sequence gives the initial means and covariances, and Delta_k = (number of runs of
    state k) / (samples of state k), the exit probability of a geometric duration with that mean.
    Baum-Welch starts from these values (hmmlearn ``init_params=""``, ``params="tmc"``).

    Convergence: hmmlearn's messages (log-likelihood decreasing, degenerate fits) are collected
    during the fit into ``fit_info_["messages"]`` / ``meta["fit"]["messages"]`` instead of the
    log. A small decrease near convergence is expected: the regularisation added after each M-step
    makes EM not exactly monotone, and hmmlearn then stops (the gain is below ``tol``). EM that stops at ``max_iter`` without meeting ``tol`` is recorded as
    ``converged=False`` and warned about (FootnavWarning).

    Examples
    --------
    >>> det = HmmDetector(seed=0).fit([walk_1, walk_2])  # doctest: +SKIP
    >>> det.transmat_.round(3)  # doctest: +SKIP
    >>> stance = det.detect(walk_3)  # no refit  # doctest: +SKIP
    >>> det.save("hmm.json"); HmmDetector.load("hmm.json").detect(walk_3)  # doctest: +SKIP
    """

    name: ClassVar[str] = "hmm"
    #: No bounded latency: the stance is the Viterbi path of the whole recording (a forward-
    #: filtering decoder with a fitted model would be online; not implemented).
    latency_s = None

    def __init__(
        self,
        *,
        features: str = "gyr",
        model_rate_hz: float = 100.0,
        lowpass_cutoff_hz: float = 5.0,
        reorder_min_stance_s: float = 0.3,
        max_iter: int = 100,
        tol: float = 1e-2,
        min_std: float = 0.05,
        seed: int = 0,
    ) -> None:
        self.features = features
        self.model_rate_hz = model_rate_hz
        self.lowpass_cutoff_hz = lowpass_cutoff_hz
        self.reorder_min_stance_s = reorder_min_stance_s
        self.max_iter = max_iter
        self.tol = tol
        self.min_std = min_std
        self.seed = seed

    # -- parameters ---------------------------------------------------------------------------
    def validate_params(self) -> None:
        require(isinstance(self.features, str) and self.features in FEATURES, self, "features",
                " or ".join(repr(f) for f in FEATURES))
        # Upper bounds: the signal is resampled to model_rate_hz (samples, so time and memory of
        # the fit grow with it; 1 kHz is above any foot IMU's useful band) and the fit runs up to
        # max_iter EM iterations; tol and min_std (of standardised features) are harmless when
        # large but overflow when squared.
        require_positive(self, "model_rate_hz", high=1000.0)
        require_positive(self, "lowpass_cutoff_hz", high=500.0)
        require_positive(self, "reorder_min_stance_s", high=MAX_DURATION_S)
        require_positive(self, "tol", "min_std", high=1e6)
        require(self.lowpass_cutoff_hz < 0.5 * self.model_rate_hz, self, "lowpass_cutoff_hz",
                f"below the Nyquist frequency of the model rate ({0.5 * self.model_rate_hz:g} Hz)")
        require_in_range(self, "max_iter", low=1, high=10_000, integer=True)
        require(_is_int(self.seed) and 0 <= self.seed < 2**32, self, "seed", "an integer in 0 .. 2**32 - 1")

    @property
    def is_fitted(self) -> bool:
        """True when ``fit`` (or ``load``) has given the detector a model."""
        return hasattr(self, "transmat_")

    # -- features -----------------------------------------------------------------------------
    def _grid(self, imu: ImuData, features: str, model_rate_hz: float) -> _ModelGrid:
        if not isinstance(imu, ImuData):
            raise InvalidInputError(f"expected an ImuData recording, got {type(imu).__name__}")
        x = imu.gyr
        if features == "gyr+acc_norm":
            x = np.column_stack([x, np.linalg.norm(imu.acc, axis=1) - GRAVITY_MPS2])
        rate = imu.rate_hz
        t0 = float(imu.t[0])
        # + 1e-9: a duration of exactly k model periods must not round down to k - 1
        n_model = int(math.floor(imu.duration_s * model_rate_hz + 1e-9)) + 1
        t_model = t0 + np.arange(n_model) / model_rate_hz
        if abs(rate / model_rate_hz - 1.0) < SAME_RATE_RTOL and n_model == imu.n_samples:
            # already at the model rate: the samples themselves, no interpolation
            return _ModelGrid(np.array(x, dtype=np.float64), np.array(imu.t), np.arange(imu.n_samples))
        if rate > model_rate_hz:
            x = lowpass(x, ANTI_ALIAS_FRACTION * model_rate_hz, rate)
        feats = np.column_stack([np.interp(t_model, imu.t, x[:, j]) for j in range(x.shape[1])])
        nearest = np.clip(np.rint((imu.t - t0) * model_rate_hz).astype(np.int64), 0, n_model - 1)
        return _ModelGrid(feats, t_model, nearest)

    def _baum_welch(self, x, lengths, z0, startprob, transmat, min_std):
        """EM from the re-ordered K-means labels ``z0``; returns the model and how the fit went."""
        n_feat = x.shape[1]
        reg = min_std**2 * np.eye(n_feat)
        means = np.empty((N_STATES, n_feat))
        covars = np.empty((N_STATES, n_feat, n_feat))
        for k in range(N_STATES):
            xs = x[z0 == k]
            means[k] = xs.mean(axis=0)
            covars[k] = (np.cov(xs.T).reshape(n_feat, n_feat) if len(xs) > 1 else np.zeros((n_feat, n_feat))) + reg
        model = _build_hmm(startprob, transmat, means, covars, min_covar=min_std**2, seed=self.seed,
                           max_iter=int(self.max_iter), tol=float(self.tol), implementation="scaling")
        # hmmlearn's log messages are collected here, not silenced elsewhere
        handler = _Capture()
        old_propagate = _LOG.propagate
        _LOG.addHandler(handler)
        _LOG.propagate = False
        try:
            model.fit(x, lengths)
        finally:
            _LOG.removeHandler(handler)
            _LOG.propagate = old_propagate
        return model, {
            "history": list(model.monitor_.history),
            "n_iter": model.monitor_.iter,
            "messages": handler.messages,
        }

    # -- learning -----------------------------------------------------------------------------
    def _learn(self, recordings: Sequence[ImuData]) -> dict[str, Any]:
        """Learn a model from ``recordings``; returns the learned values (nothing is stored).

        ``fit_info_["warnings"]`` lists the warnings footnav issued while learning."""
        with recording() as log:
            learned = self._learn_model(recordings)
        learned["fit_info_"]["warnings"] = [str(w) for w in log]
        return learned

    def _learn_model(self, recordings: Sequence[ImuData]) -> dict[str, Any]:
        from sklearn.cluster import KMeans

        rate = float(self.model_rate_hz)
        grids = [self._grid(imu, self.features, rate) for imu in recordings]
        x = np.concatenate([g.features for g in grids])
        lengths = [len(g.features) for g in grids]
        total_s = sum(imu.duration_s for imu in recordings)
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
        km = KMeans(n_clusters=N_STATES, n_init=KMEANS_N_INIT, random_state=self.seed).fit(x)
        labels = km.labels_.astype(np.int64)
        counts = np.bincount(labels, minlength=N_STATES)
        median_rate = np.array(
            [np.median(gyr_norm[labels == k]) if counts[k] else np.inf for k in range(N_STATES)]
        )
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
        per_recording = [significant_axis(g.features[:, :3], rate, self.lowpass_cutoff_hz) for g in grids]
        axis_signal = np.concatenate([sig for sig, _ in per_recording])
        km_runs = stance_intervals(labels == stance_label)
        km_run_s = (km_runs[:, 1] - km_runs[:, 0]) / rate
        min_stance_s = float(self.reorder_min_stance_s)
        if len(km_run_s):
            min_stance_s = min(min_stance_s, REORDER_STANCE_FRACTION * float(np.quantile(km_run_s, 0.9)))
        order = cyclic_order_votes(
            labels, axis_signal, rate, stance_label=stance_label, min_stance_s=min_stance_s,
            lengths=lengths,
        )
        if order.n_movements < MIN_GAIT_CYCLES:
            raise InvalidInputError(
                f"found {order.n_movements} gait cycle(s) (movement periods between stance runs of at least "
                f"{min_stance_s:.3g} s) in {total_s:.3g} s of data; need at least {MIN_GAIT_CYCLES} to "
                "learn the gait model (recording too short, or no standstill between steps)"
            )
        state_of_label = np.argsort(order.permutation)
        z0 = state_of_label[labels]

        # initial Theta from the re-ordered guess: means, covariances, and Delta_k from the mean
        # run length of each state (a geometric duration of mean L samples leaves with 1/L)
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
        startprob = np.full(N_STATES, 1.0 / N_STATES)

        # Baum-Welch, then the check after decoding (stance the stillest state, stance runs that are
        # steps); one documented refit with a coarser covariance floor when the check fails
        min_std = float(self.min_std)
        model, em = self._baum_welch(x, lengths, z0, startprob, transmat, min_std)
        check = _check_model(model, x, lengths, gyr_norm, rate)
        fallback = None
        if not check["ok"]:
            first = check
            min_std = FALLBACK_MIN_STD_FACTOR * float(self.min_std)
            model, em = self._baum_welch(x, lengths, z0, startprob, transmat, min_std)
            check = _check_model(model, x, lengths, gyr_norm, rate)
            fallback = {
                "reason": first["problem"],
                "first_check": first,
                "action": f"refit with min_std={min_std:g} ({FALLBACK_MIN_STD_FACTOR:g} x min_std)",
            }
            if not check["stance_stillest"]:
                raise GaitModelError(
                    f"the HMM could not learn the gait cycle: after Baum-Welch (also refitted with min_std={min_std:g}) "
                    f"the stance state is not the stillest state ({check['problem']}); its mask would not be "
                    "stance. Fit the detector on a longer or cleaner walk and detect this recording with it"
                )
            warn(
                f"HmmDetector: the learned model failed the check after decoding ({first['problem']}); "
                f"{fallback['action']}" + ("" if check["ok"] else f", still: {check['problem']}")
                + "; recorded in fit_info_['fallback']",
                DataQualityWarning,
                stacklevel=3,
            )
        history = em["history"]
        # hmmlearn's monitor_.converged is also True when it merely ran out of iterations
        converged = len(history) >= 2 and history[-1] - history[-2] < float(self.tol)
        if not converged:
            warn(
                f"HmmDetector: Baum-Welch did not converge in max_iter={self.max_iter} iterations (last gain "
                f"{history[-1] - history[-2] if len(history) >= 2 else float('nan'):.3g} nats >= tol={self.tol:g}); "
                "recorded in fit_info_['converged']",
                FootnavWarning,
                stacklevel=3,
            )
        info = {
            "n_iter": int(em["n_iter"]),
            "converged": bool(converged),
            "log_likelihood": float(history[-1]) if history else float("nan"),
            "n_samples": int(len(x)),
            "n_recordings": len(recordings),
            "duration_s": float(total_s),
            "kmeans_centers": km.cluster_centers_.tolist(),
            "kmeans_permutation": order.permutation.tolist(),
            "significant_axis": [int(axis) for _, axis in per_recording],
            "n_movements": int(order.n_movements),
            "votes": order.votes,
            "vote_fallback": order.fallback,
            "reorder_min_stance_s": min_stance_s,
            "initial_transmat": transmat.tolist(),
            "min_std": min_std,
            "check": check,
            "fallback": fallback,
            "messages": em["messages"],
            "warnings": [],  # filled by _learn
        }
        return {
            "startprob_": np.array(model.startprob_, dtype=np.float64),
            # as Baum-Welch left it: the structural zeros are zeros by EM itself (tested), not forced
            "transmat_": np.array(model.transmat_, dtype=np.float64),
            "means_": np.array(model.means_, dtype=np.float64),
            "covars_": np.array(model.covars_, dtype=np.float64),
            "features_": self.features,
            "model_rate_hz_": rate,
            "fit_info_": info,
        }

    def fit(self, imu: ImuData | Sequence[ImuData]) -> "HmmDetector":
        """Learn the model from one recording or several (each its own sequence) and keep it.

        Parameters
        ----------
        imu
            An :class:`ImuData` or a sequence of them (one foot each; several walks, both feet).

        Returns
        -------
        HmmDetector
            ``self``, with ``startprob_``, ``transmat_``, ``means_``, ``covars_``, ``features_``,
            ``model_rate_hz_`` and ``fit_info_`` set.

        Raises
        ------
        InvalidInputError
            No recording, not ImuData, all standstill, no standstill, too few gait cycles.
        """
        self.validate_params()
        recordings = [imu] if isinstance(imu, ImuData) else list(imu)
        if not recordings:
            raise InvalidInputError("fit() needs at least one recording")
        for k, r in enumerate(recordings):
            if not isinstance(r, ImuData):
                raise InvalidInputError(f"recording {k} is a {type(r).__name__}, expected ImuData")
        for key, value in self._learn(recordings).items():
            setattr(self, key, value)
        return self

    def _fitted_model(self) -> dict[str, Any]:
        if self.features_ != self.features or self.model_rate_hz_ != self.model_rate_hz:
            raise InvalidParameterError(
                f"detector 'hmm' was fitted with features={self.features_!r}, model_rate_hz={self.model_rate_hz_!r} "
                f"but now has features={self.features!r}, model_rate_hz={self.model_rate_hz!r}; fit again"
            )
        return {k: getattr(self, k) for k in ("startprob_", "transmat_", "means_", "covars_", "features_",
                                               "model_rate_hz_")}

    # -- detection ----------------------------------------------------------------------------
    def detect(self, imu: ImuData) -> StanceResult:
        """Stance (Viterbi stance state), phases, stance probability and events of one recording.

        Uses the fitted model when there is one; otherwise learns one on ``imu`` (not kept).

        Parameters
        ----------
        imu
            One foot's recording, any sampling rate.

        Returns
        -------
        StanceResult
            ``mask`` (stance state of the Viterbi path), ``phases`` (0 stance, 1 push-up, 2 swing,
            3 step-down; ``meta["phase_names"]``), ``score`` (posterior probability of stance,
            forward-backward), ``events`` (``heel_off``, ``toe_off``, ``heel_strike``,
            ``foot_flat``: first sample of the new phase). ``meta["fitted_on_recording"]`` is True
            when the model was learned on ``imu``; then ``meta["fit"]`` and ``meta["model"]`` hold
            how the fit went and the learned values.

        Raises
        ------
        InvalidInputError
            Unfitted, and ``imu`` cannot teach the model (all standstill, no standstill, fewer than
            ``MIN_GAIT_CYCLES`` gait cycles); or ``imu`` is not ImuData.
        InvalidParameterError
            A parameter value is invalid, or ``features`` / ``model_rate_hz`` changed since ``fit``.
        """
        self.validate_params()
        if not isinstance(imu, ImuData):
            raise InvalidInputError(f"expected an ImuData recording, got {type(imu).__name__}")
        fitted_here = not self.is_fitted
        learned = self._learn([imu]) if fitted_here else self._fitted_model()
        grid = self._grid(imu, learned["features_"], learned["model_rate_hz_"])
        model = _build_hmm(learned["startprob_"], learned["transmat_"], learned["means_"], learned["covars_"],
                           min_covar=float(self.min_std) ** 2, seed=self.seed)
        log_prob_path, states = model.decode(grid.features, algorithm="viterbi")
        log_likelihood, posteriors = model.score_samples(grid.features)

        phases = states[grid.nearest].astype(np.int64)
        mask = phases == STANCE
        score = np.clip(np.interp(imu.t, grid.t_model, posteriors[:, STANCE]), 0.0, 1.0)
        change = np.flatnonzero(phases[1:] != phases[:-1]) + 1
        events = {
            name: change[(phases[change - 1] == a) & (phases[change] == b)].astype(np.int64)
            for name, a, b in EVENTS
        }
        meta: dict[str, Any] = {
            "detector": self.describe(),
            "rate_hz": imu.rate_hz,
            "model_rate_hz": learned["model_rate_hz_"],
            "phase_names": PHASE_NAMES,
            "fitted_on_recording": fitted_here,
            "log_likelihood": float(log_likelihood),
            "viterbi_log_prob": float(log_prob_path),
            "event_convention": "first sample of the new phase: heel_off stance->push_up, toe_off push_up->swing, "
            "heel_strike swing->step_down, foot_flat step_down->stance",
        }
        if fitted_here:
            meta["fit"] = learned["fit_info_"]
            meta["model"] = {
                k: np.asarray(learned[k]).tolist() for k in ("startprob_", "transmat_", "means_", "covars_")
            }
        return StanceResult(mask=mask, events=events, phases=phases, score=score, meta=meta)

    # -- persistence --------------------------------------------------------------------------
    def save(self, path: str | PathLike) -> None:
        """Write the parameters and the learned model to ``path`` as JSON (exact float round trip).

        Raises
        ------
        HmmNotFittedError
            The detector has no model yet.
        """
        if not self.is_fitted:
            raise HmmNotFittedError("detector 'hmm' has no model to save; call fit(imu) first")
        doc = {
            "format": SAVE_FORMAT,
            "version": SAVE_VERSION,
            "params": self.get_params(),
            "features_": self.features_,
            "model_rate_hz_": float(self.model_rate_hz_),
            "startprob_": self.startprob_.tolist(),
            "transmat_": self.transmat_.tolist(),
            "means_": self.means_.tolist(),
            "covars_": self.covars_.tolist(),
            "fit_info_": self.fit_info_,
        }
        # Python's json writes floats with repr(), the shortest string that reads back bit-exact
        FilePath(path).write_text(json.dumps(doc, indent=1, allow_nan=True), encoding="utf-8")

    @classmethod
    def load(cls, path: str | PathLike) -> "HmmDetector":
        """Read a detector written by :meth:`save`: same parameters, same model, no refit.

        Raises
        ------
        InvalidInputError
            Not a saved HMM detector, or its model is malformed (shapes, transitions outside the
            structure of eq. (1), rows not summing to 1, covariances not positive definite).
        """
        path_s = str(path)
        try:
            doc = json.loads(FilePath(path).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise InvalidInputError(f"cannot read a saved HMM detector ({exc})", path=path_s) from None
        if not isinstance(doc, dict) or doc.get("format") != SAVE_FORMAT:
            raise InvalidInputError(f"not a saved HMM detector (expected format {SAVE_FORMAT!r})", path=path_s)
        if doc.get("version") != SAVE_VERSION:
            raise InvalidInputError(f"unsupported version {doc.get('version')!r}; expected {SAVE_VERSION}", path=path_s)
        try:
            det = cls(**doc["params"])
            det.validate_params()
            features = doc["features_"]
            n_feat = len(FEATURES[features])
            arrays = {
                "startprob_": np.asarray(doc["startprob_"], dtype=np.float64),
                "transmat_": np.asarray(doc["transmat_"], dtype=np.float64),
                "means_": np.asarray(doc["means_"], dtype=np.float64),
                "covars_": np.asarray(doc["covars_"], dtype=np.float64),
            }
            model_rate = float(doc["model_rate_hz_"])
        except (KeyError, TypeError, ValueError, InvalidParameterError) as exc:
            raise InvalidInputError(f"malformed saved HMM detector ({exc})", path=path_s) from None
        shapes = {"startprob_": (N_STATES,), "transmat_": (N_STATES, N_STATES), "means_": (N_STATES, n_feat),
                  "covars_": (N_STATES, n_feat, n_feat)}
        for key, shape in shapes.items():
            if arrays[key].shape != shape or not np.all(np.isfinite(arrays[key])):
                raise InvalidInputError(f"expected finite values of shape {shape}, got {arrays[key].shape}",
                                        field=key, path=path_s)
        a = arrays["transmat_"]
        if np.any(a[~STRUCTURE] != 0) or np.any(a < 0) or not np.allclose(a.sum(axis=1), 1.0):
            raise InvalidInputError(
                "not a cyclic left-to-right transition matrix (eq. 1)", field="transmat_", path=path_s
            )
        if np.any(np.linalg.eigvalsh(arrays["covars_"]) <= 0):
            raise InvalidInputError("covariances must be positive definite", field="covars_", path=path_s)
        for key, value in arrays.items():
            setattr(det, key, value)
        det.features_ = features
        det.model_rate_hz_ = model_rate
        det.fit_info_ = doc.get("fit_info_", {})
        return det
