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

from footnav.detectors.hmm.features import ModelGrid
from footnav.detectors.hmm.model import EVENTS, STANCE

__all__ = ["Decoded", "decode_offline", "on_samples", "transition_events"]


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


def decode_offline(model, features: NDArray[np.float64]) -> Decoded:
    """Viterbi path and forward-backward stance probability of the whole recording.

    ``model`` is the hmmlearn model of :func:`~footnav.detectors.hmm.model.build_hmm`;
    ``features`` its observations on the model-rate grid, (M, F). hmmlearn's public ``decode``
    and ``score_samples``.
    """
    path_log_prob, states = model.decode(features, algorithm="viterbi")
    log_likelihood, posteriors = model.score_samples(features)
    return Decoded(states, posteriors[:, STANCE], float(log_likelihood), float(path_log_prob))


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
    return {
        name: change[(phases[change - 1] == a) & (phases[change] == b)].astype(np.int64)
        for name, a, b in EVENTS
    }
