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
Viterbi path's stance state, with no post-processing; the path is decoded with a minimum stance
duration (below).

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
  full covariances, its ``covars_prior`` is divided by each state's occupancy), so a noise-free
  stance cannot make a covariance singular. Baum-Welch therefore runs one hmmlearn ``fit``
  iteration at a time (:func:`~footnav.detectors.hmm.learning.baum_welch`): hmmlearn's public API
  only, no private method overridden.

* **Minimum stance duration** (issue 36). Eq. (1) lets a state last one sample, and a model
  whose swing state does not cover the swing's zero crossings decodes a one-sample stance there
  (a false step; the learning's check counts them). The decoder
  (:func:`~footnav.detectors.hmm.decoding.viterbi_min_stance`) makes the stance state a chain of
  sub-states sharing the stance emission, ``min_stance_s`` long (0.15 s: 16 sub-states at
  100 Hz), entered from step-down and left for push-up from its last sub-state: an
  expanded-state HMM with the same cyclic left-right structure, structural zeros and learned
  values (the first sub-states' stay probability becomes 1). Baum-Welch and its check still run
  on the plain four-state model; the detector raises :class:`~footnav.core.errors.GaitModelError`
  rather than return a stance shorter than the check's 0.05 s. On the simulator's 10-min walks
  (66 turns) at 60 / 100 / 200 Hz: unchanged without swing variation or with ``swing_scale``
  0.7-1.3 (687 of 687 stances, none false); with ``swing_scale=(1, 0.5, 1.5)`` the learned model
  fails its check and the plain path has about 300-480 false stances, the chain none.

Events come from the Viterbi path's transitions, each at the first sample of the new phase:
stance -> push-up is ``heel_off``, push-up -> swing ``toe_off``, swing -> step-down
``heel_strike``, step-down -> stance ``foot_flat``. The model splits the non-stance part of a step by
the sense of the foot's pitch rotation, so these are the pitch-rate landmarks rather than ground
contacts: ``toe_off`` is where the toe-down rotation of push-off ends (the pitch rate's zero
crossing early in the swing), ``heel_strike`` where the toe-up rotation of the swing ends.

The sub-package, one concept per module, each importing only modules above it in this list:

============== ==============================================================================
module         what
============== ==============================================================================
``model``      the states, eq. (1)'s structure and events, the hmmlearn model
``features``   observations on the model-rate grid, low-pass, significant axis
``reorder``    the re-ordering of K-means labels into the cyclic order (Fig. 2)
``initialise`` the K-means guess, the data it refuses, the initial transitions
``learning``   Baum-Welch (hmmlearn's public API), the check after decoding, the one refit
``decoding``   Viterbi + forward-backward; phases, stance probability, events
``detector``   :class:`HmmDetector`, the registered ``hmm`` component
============== ==============================================================================
"""

from __future__ import annotations

from footnav.core.errors import GaitModelError, HmmNotFittedError
from footnav.detectors.hmm.detector import HmmDetector
from footnav.detectors.hmm.features import FEATURES, lowpass, significant_axis
from footnav.detectors.hmm.model import PHASE_NAMES, STRUCTURE
from footnav.detectors.hmm.reorder import CyclicOrder, cyclic_order, cyclic_order_votes

__all__ = [
    "FEATURES",
    "PHASE_NAMES",
    "STRUCTURE",
    "CyclicOrder",
    "GaitModelError",
    "HmmDetector",
    "HmmNotFittedError",
    "cyclic_order",
    "cyclic_order_votes",
    "lowpass",
    "significant_axis",
]
