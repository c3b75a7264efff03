"""The cyclic left-to-right Gaussian HMM of Li et al. (2018), eq. (1)-(2), and its structural zeros.

A step is a cycle of four hidden states, ``0 stance -> 1 push-up -> 2 swing -> 3 step-down -> 0``:
each state stays or moves to the next (:data:`STRUCTURE`), every other transition is a structural
zero; the emissions are full-covariance Gaussians of the observation vector.

The zeros are held by hmmlearn's own EM, through its public API: :func:`build_hmm` hands
``GaussianHMM`` a ``transmat_`` with the zeros in place, ``init_params=""`` (footnav's
initialisation is kept) and ``params="tmc"`` (pi stays uniform), and Baum-Welch leaves a zero
transition at zero (its expected count is 0, and hmmlearn's M-step keeps zeros of ``transmat_``;
tests/detectors/test_hmm_hmmlearn.py checks it).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "EVENTS",
    "N_STATES",
    "PHASE_NAMES",
    "PUSH_UP",
    "STANCE",
    "STEP_DOWN",
    "STRUCTURE",
    "SWING",
    "build_hmm",
    "initial_emissions",
    "is_cyclic_left_right",
]

#: The four hidden states of Li et al. (2018) (Omega = {1, ..., 4}, Sec. 2), 0-based, in cyclic order.
PHASE_NAMES = ("stance", "push_up", "swing", "step_down")
STANCE, PUSH_UP, SWING, STEP_DOWN = range(len(PHASE_NAMES))
N_STATES = len(PHASE_NAMES)

#: Allowed transitions of eq. (1): state k stays or moves to k+1, step-down returns to stance.
STRUCTURE = np.eye(N_STATES, dtype=bool) | np.roll(np.eye(N_STATES, dtype=bool), 1, axis=1)
STRUCTURE.setflags(write=False)

#: Gait events marked at each transition (name, from state, to state), at the first sample of the new state.
EVENTS = (
    ("heel_off", STANCE, PUSH_UP),
    ("toe_off", PUSH_UP, SWING),
    ("heel_strike", SWING, STEP_DOWN),
    ("foot_flat", STEP_DOWN, STANCE),
)


def initial_emissions(
    x: NDArray[np.float64], z0: NDArray[np.int64], min_std: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Means (N_STATES, F) and covariances (N_STATES, F, F) of the samples ``x`` (M, F) labelled
    ``k`` in ``z0`` (M,), with ``min_std**2`` added to each variance."""
    n_feat = x.shape[1]
    reg = min_std**2 * np.eye(n_feat)
    means = np.empty((N_STATES, n_feat))
    covars = np.empty((N_STATES, n_feat, n_feat))
    for k in range(N_STATES):
        xs = x[z0 == k]
        means[k] = xs.mean(axis=0)
        covars[k] = (np.cov(xs.T).reshape(n_feat, n_feat) if len(xs) > 1 else np.zeros((n_feat, n_feat))) + reg
    return means, covars


def build_hmm(
    startprob: NDArray, transmat: NDArray, means: NDArray, covars: NDArray, *, seed: int, implementation: str = "log"
):
    """hmmlearn's ``GaussianHMM`` of eq. (1)-(2) with these values.

    Each ``fit`` call runs one EM iteration from the current values (no initialisation) and
    updates A, mu and Sigma only; ``implementation`` is hmmlearn's ("scaling" for fitting, "log"
    for decoding).
    """
    from hmmlearn.hmm import GaussianHMM

    model = GaussianHMM(
        n_components=N_STATES,
        covariance_type="full",
        covars_prior=0.0,
        init_params="",  # keep the re-ordered K-means initialisation
        params="tmc",  # pi stays uniform (HmmDetector's Notes)
        n_iter=1,  # one EM iteration per fit call (learning.baum_welch)
        random_state=seed,
        implementation=implementation,
    )
    model.startprob_ = np.array(startprob, dtype=np.float64)
    model.transmat_ = np.array(transmat, dtype=np.float64)
    model.means_ = np.array(means, dtype=np.float64)
    model.covars_ = np.array(covars, dtype=np.float64)
    model.n_features = model.means_.shape[1]
    return model


def is_cyclic_left_right(transmat: NDArray[np.float64]) -> bool:
    """True when ``transmat`` is a transition matrix of eq. (1): zero outside :data:`STRUCTURE`,
    non-negative, rows summing to 1."""
    a = np.asarray(transmat)
    return not (np.any(a[~STRUCTURE] != 0) or np.any(a < 0) or not np.allclose(a.sum(axis=1), 1.0))
