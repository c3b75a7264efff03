"""Decoding a recording with a learned model: the phase of every sample, stance probability, events.

:func:`decode_offline` is the detector's decoder: the Viterbi path of the whole recording and the
forward-backward (smoothed) probability of stance, both at the model rate. Neither is causal: a
sample's state depends on the samples after it. :func:`on_samples` maps a :class:`Decoded` back
to the recording's samples and :func:`transition_events` marks the gait events at the path's
transitions.

A causal decoder for online use (issue 19: forward filtering, or Viterbi with a fixed lag)
would be a second function returning a :class:`Decoded` from the same model and observations;
the mapping to samples and the events are shared.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install
from footnav.detectors.hmm.features import ModelGrid
from footnav.detectors.hmm.model import EVENTS, N_STATES, STANCE

__all__ = [
    "MIN_STANCE_S",
    "Decoded",
    "decode_offline",
    "min_stance_samples",
    "on_samples",
    "transition_events",
    "viterbi_min_stance",
]

#: Shortest stance the detector may return, s: the learning check's micro-stance limit
#: (:data:`~footnav.detectors.hmm.learning.MICRO_STANCE_S`).
MIN_STANCE_S = 0.05


def min_stance_samples(model_rate_hz: float, min_stance_s: float = MIN_STANCE_S) -> int:
    """Sub-states of the stance chain at ``model_rate_hz``: ``min_stance_s`` in model samples, plus
    one so that a shortest stance still spans ``min_stance_s`` once mapped to a slower recording's
    nearest samples (1 for 0 s: the plain path)."""
    if min_stance_s <= 0:
        return 1
    return int(np.ceil(min_stance_s * float(model_rate_hz) - 1e-9)) + 1


@dataclass(frozen=True)
class Decoded:
    """One recording decoded at the model rate.

    Attributes
    ----------
    states
        The decoded state of each model-rate sample (0 stance, 1 push-up, 2 swing, 3 step-down), (M,).
    stance_probability
        Probability of stance at each model-rate sample, (M,).
    log_likelihood
        Log-likelihood of the observations under the model, nats.
    path_log_prob
        Log-probability of the decoded path (Viterbi), nats.
    """

    states: NDArray[np.int64]
    stance_probability: NDArray[np.float64]
    log_likelihood: float
    path_log_prob: float


def decode_offline(model, features: NDArray[np.float64], min_stance: int = 1) -> Decoded:
    """Viterbi path and forward-backward stance probability of the whole recording.

    ``model`` is the hmmlearn model of :func:`~footnav.detectors.hmm.model.build_hmm`;
    ``features`` its observations on the model-rate grid, (M, F). hmmlearn's public
    ``score_samples`` gives the stance probability; the path is hmmlearn's ``decode`` with
    ``min_stance`` 1, else :func:`viterbi_min_stance` (every stance run at least ``min_stance``
    model samples).
    """
    log_likelihood, posteriors = model.score_samples(features)
    if min_stance <= 1:
        path_log_prob, states = model.decode(features, algorithm="viterbi")
    else:
        path_log_prob, states = viterbi_min_stance(model, features, min_stance)
    return Decoded(states, posteriors[:, STANCE], float(log_likelihood), float(path_log_prob))


def _log(a: NDArray[np.float64]) -> NDArray[np.float64]:
    a = np.asarray(a, dtype=np.float64)
    return np.where(a > 0, np.log(np.where(a > 0, a, 1.0)), -np.inf)


def viterbi_min_stance(model, features: NDArray[np.float64], min_stance: int) -> tuple[float, NDArray[np.int64]]:
    """The most probable path of eq. (1)-(2) in which every stance run lasts ``min_stance`` samples
    or more (Li et al. (2018) give stance no minimum: a stance visited for one sample at a zero
    crossing of the swing's rate is a false step).

    The stance state becomes a chain of ``min_stance`` sub-states sharing its emission
    ``N(mu_0, Sigma_0)`` (an expanded-state HMM): step-down enters the first with the learned
    ``a_30``, each moves to the next with probability 1, the last stays with ``a_00`` or leaves for
    push-up with ``a_01``. The cyclic left-right structure and its structural zeros are kept, the
    learned values unchanged; a path that starts in stance starts in the first sub-state and one
    that ends in stance ends in the last, so no stance run, not even at the ends, is shorter.
    Emissions from the model's means and covariances (scipy); returns (log-probability of the
    path, states (M,) in 0..3).
    """
    from scipy.stats import multivariate_normal

    x = np.asarray(features, dtype=np.float64)
    log_b = np.column_stack(
        [multivariate_normal(model.means_[k], model.covars_[k], allow_singular=True).logpdf(x) for k in range(N_STATES)]
    ).reshape(len(x), N_STATES)
    log_a, log_pi = _log(model.transmat_), _log(model.startprob_)
    states = np.empty(len(x), dtype=np.int64)
    score = _viterbi_chain(log_b, log_a, log_pi, int(min_stance), states)
    return float(score), states


@njit(cache=True)
def _viterbi_chain(log_b, log_a, log_pi, d, out):
    """Viterbi on the expanded chain of :func:`viterbi_min_stance`: states 0..d-1 the stance
    sub-states, d + k - 1 the phase k = 1..3; writes the phases to ``out``; returns the path's
    log-probability."""
    m, n_phase = log_b.shape
    n = d + n_phase - 1
    phase = np.empty(n, dtype=np.int64)
    for j in range(n):
        phase[j] = 0 if j < d else j - d + 1
    delta = np.full(n, -np.inf)
    back = np.empty((m, n), dtype=np.int64)
    delta[0] = log_pi[0] + log_b[0, 0]
    for k in range(1, n_phase):
        delta[d + k - 1] = log_pi[k] + log_b[0, k]
    new = np.empty(n)
    for t in range(1, m):
        for j in range(n):
            p = phase[j]
            best, arg = -np.inf, j
            if p == 0:
                if j == 0:  # entered from step-down (the last phase)
                    best, arg = delta[n - 1] + log_a[n_phase - 1, 0], n - 1
                else:
                    best, arg = delta[j - 1], j - 1
                if j == d - 1:  # the last sub-state also stays
                    stay = delta[j] + log_a[0, 0]
                    if stay > best:
                        best, arg = stay, j
            else:
                prev = d - 1 if p == 1 else j - 1  # push-up from the chain's end, else the phase before
                best, arg = delta[prev] + log_a[p - 1, p], prev
                stay = delta[j] + log_a[p, p]
                if stay > best:
                    best, arg = stay, j
            new[j] = best + log_b[t, p]
            back[t, j] = arg
        for j in range(n):
            delta[j] = new[j]
    best, j = -np.inf, d - 1
    for i in range(n):
        if (phase[i] != 0 or i == d - 1) and delta[i] > best:
            best, j = delta[i], i
    for t in range(m - 1, -1, -1):
        out[t] = phase[j]
        if t > 0:
            j = back[t, j]
    return best


def on_samples(
    decoded: Decoded, grid: ModelGrid, t: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """The phase (N,) and stance probability (N,) at the recording's sample times ``t`` (N,), s.

    The phase is the model sample's nearest each recording sample (within half a model period),
    the probability is interpolated linearly in time.
    """
    phases = decoded.states[grid.nearest].astype(np.int64)
    score = np.clip(np.interp(t, grid.t_model, decoded.stance_probability), 0.0, 1.0)
    return phases, score


def transition_events(phases: NDArray[np.int64]) -> dict[str, NDArray[np.int64]]:
    """Gait events of :data:`~footnav.detectors.hmm.model.EVENTS`: the first sample of each new
    phase, by the transition that enters it."""
    change = np.flatnonzero(phases[1:] != phases[:-1]) + 1
    return {name: change[(phases[change - 1] == a) & (phases[change] == b)].astype(np.int64) for name, a, b in EVENTS}
