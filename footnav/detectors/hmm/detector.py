"""The registered ``hmm`` stance detector: parameters, ``fit``, ``detect``, ``save`` / ``load``.

The method and what footnav adds to the paper are described in :mod:`footnav.detectors.hmm`;
this module ties the steps together: :func:`~footnav.detectors.hmm.learning.learn` (K-means
guess, re-ordering, Baum-Welch, check after decoding) and
:func:`~footnav.detectors.hmm.decoding.decode_offline` on the model-rate grid of
:func:`~footnav.detectors.hmm.features.model_grid`.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from numbers import Integral
from os import PathLike
from pathlib import Path as FilePath
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from footnav.core.component import StanceDetector
from footnav.core.errors import GaitModelError, HmmNotFittedError, InvalidInputError, InvalidParameterError
from footnav.core.parameters import MAX_DURATION_S, require, require_in_range, require_positive
from footnav.core.types import ImuData, StanceResult, stance_intervals
from footnav.core.warning_log import recording
from footnav.detectors.hmm.decoding import (
    MIN_STANCE_S,
    decode_offline,
    min_stance_samples,
    on_samples,
    transition_events,
)
from footnav.detectors.hmm.features import FEATURES, model_grid
from footnav.detectors.hmm.learning import learn
from footnav.detectors.hmm.model import N_STATES, PHASE_NAMES, STANCE, build_hmm, is_cyclic_left_right

if TYPE_CHECKING:
    from numpy.typing import NDArray

__all__ = ["SAVE_FORMAT", "SAVE_VERSION", "HmmDetector"]

#: Format tag and version of :meth:`HmmDetector.save` files.
SAVE_FORMAT = "footnav-hmm-detector"
SAVE_VERSION = 1


def _is_int(value: Any) -> bool:
    return isinstance(value, Integral) and not isinstance(value, bool)


class HmmDetector(StanceDetector):
    """Cyclic left-to-right 4-state HMM of the gait phases, learned without labels (Li et al. (2018), Sec. 2).

    States stance, push-up, swing, step-down; transitions of eq. (1) (stay or go to the next state,
    step-down -> stance); full-covariance Gaussian emissions of the 3-axis angular rate, eq. (2);
    Baum-Welch from a K-means guess re-ordered into the cyclic order (:func:`cyclic_order`); Viterbi
    decoding. ``mask`` is the stance state, ``phases`` the Viterbi state (names in
    ``meta["phase_names"]``), ``score`` the posterior probability of stance (forward-backward),
    ``events`` the four transitions (:mod:`footnav.detectors.hmm`).

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
    min_stance_s : float
        Shortest stance the Viterbi path may hold, s (issue 36; the paper's eq. 1 lets a state
        last one sample): the stance state decoded as a chain of sub-states sharing its emission
        (:func:`~footnav.detectors.hmm.decoding.viterbi_min_stance`). 0.15 s: on the simulator's
        10-min walks with ``swing_scale=(1, 0.5, 1.5)`` the learned model fails its check (495 of
        1373 stance runs one sample long) and decodes 1170 / 710 / 687 stances with a minimum of
        0.05 / 0.1 / 0.15 s, 687 true; without swing variation every minimum gives the truth. A
        foot flat shorter than this (running) is not found: lower it there. Below 0.05 s (the
        learning's check) a returned micro-stance raises :class:`~footnav.core.errors.GaitModelError`.
    seed : int
        Seed of K-means (and of hmmlearn); the same seed gives the same model and detections.

    Attributes
    ----------
    startprob_ : ndarray (4,)
        Initial state probabilities pi (uniform, not learned: :mod:`footnav.detectors.hmm`).
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
    expected phase durations are in seconds, whatever the recording's rate
    (:mod:`footnav.detectors.hmm`). The stance mask and phases come from the model sample nearest
    each recording sample (within half a model period, 5 ms at 100 Hz), the stance probability is
    interpolated linearly in time.

    Initialisation: K-means (scikit-learn, ``seed``, 10 restarts) on the model-rate observations;
    the stance cluster is the one whose samples have the smallest median |w|; the labels are put
    in the cyclic order by :func:`cyclic_order` on the filtered most significant gyro axis; the
    re-labelled sequence gives the initial means and covariances, and Delta_k = (number of runs of
    state k) / (samples of state k), the exit probability of a geometric duration with that mean.
    Baum-Welch starts from these values (hmmlearn ``init_params=""``, ``params="tmc"``).

    Convergence: messages of the fit (log-likelihood decreasing, hmmlearn's degenerate-fit
    warnings) are collected into ``fit_info_["messages"]`` / ``meta["fit"]["messages"]`` instead
    of the log. A small decrease near convergence is expected: the regularisation added after each
    M-step makes EM not exactly monotone, and EM then stops (the gain is below ``tol``). EM that
    stops at ``max_iter`` without meeting ``tol`` is recorded as ``converged=False`` and warned
    about (FootnavWarning).

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

    # the model ``fit`` / ``load`` learn (scikit-learn's trailing underscore): set by setattr,
    # absent before (``is_fitted``), so declared here without a value
    startprob_: NDArray[np.float64]
    transmat_: NDArray[np.float64]
    means_: NDArray[np.float64]
    covars_: NDArray[np.float64]
    features_: str
    model_rate_hz_: float
    fit_info_: dict[str, Any]

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
        min_stance_s: float = 0.15,
        seed: int = 0,
    ) -> None:
        self.features = features
        self.model_rate_hz = model_rate_hz
        self.lowpass_cutoff_hz = lowpass_cutoff_hz
        self.reorder_min_stance_s = reorder_min_stance_s
        self.max_iter = max_iter
        self.tol = tol
        self.min_std = min_std
        self.min_stance_s = min_stance_s
        self.seed = seed

    # -- parameters ---------------------------------------------------------------------------
    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        require(
            isinstance(self.features, str) and self.features in FEATURES,
            self,
            "features",
            " or ".join(repr(f) for f in FEATURES),
        )
        # Upper bounds: the signal is resampled to model_rate_hz (samples, so time and memory of
        # the fit grow with it; 1 kHz is above any foot IMU's useful band) and the fit runs up to
        # max_iter EM iterations; tol and min_std (of standardised features) are harmless when
        # large but overflow when squared.
        require_positive(self, "model_rate_hz", high=1000.0)
        require_positive(self, "lowpass_cutoff_hz", high=500.0)
        require_positive(self, "reorder_min_stance_s", high=MAX_DURATION_S)
        require_positive(self, "tol", "min_std", high=1e6)
        # a stance longer than 2 s is not a step's: every step of a walk would be lost
        require_in_range(self, "min_stance_s", low=0.0, high=2.0)
        require(
            self.lowpass_cutoff_hz < 0.5 * self.model_rate_hz,
            self,
            "lowpass_cutoff_hz",
            f"below the Nyquist frequency of the model rate ({0.5 * self.model_rate_hz:g} Hz)",
        )
        require_in_range(self, "max_iter", low=1, high=10_000, integer=True)
        require(_is_int(self.seed) and 0 <= self.seed < 2**32, self, "seed", "an integer in 0 .. 2**32 - 1")

    @property
    def is_fitted(self) -> bool:
        """True when ``fit`` (or ``load``) has given the detector a model."""
        return hasattr(self, "transmat_")

    # -- learning -----------------------------------------------------------------------------
    def _learn(self, recordings: Sequence[ImuData]) -> dict[str, Any]:
        """Learn a model from ``recordings``; returns the learned values (nothing is stored).

        ``fit_info_["warnings"]`` lists the warnings footnav issued while learning."""
        with recording() as log:
            learned = learn(recordings, **{k: v for k, v in self.get_params().items() if k != "min_stance_s"})
        learned["fit_info_"]["warnings"] = [str(w) for w in log]
        return learned

    def fit(self, imu: ImuData | Sequence[ImuData]) -> HmmDetector:
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
        return {
            k: getattr(self, k) for k in ("startprob_", "transmat_", "means_", "covars_", "features_", "model_rate_hz_")
        }

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
        grid = model_grid(imu, learned["features_"], learned["model_rate_hz_"])
        model = build_hmm(
            learned["startprob_"], learned["transmat_"], learned["means_"], learned["covars_"], seed=self.seed
        )
        # every stance at least min_stance_s: the stance chain of decoding.viterbi_min_stance
        decoded = decode_offline(model, grid.features, min_stance_samples(learned["model_rate_hz_"], self.min_stance_s))
        phases, score = on_samples(decoded, grid, imu.t)
        mask = phases == STANCE
        runs = stance_intervals(mask)
        # (a 1e-9 s margin: 0.05 * 60 Hz is 3.0000000000000004 samples)
        short = int(np.sum((runs[:, 1] - runs[:, 0]) / imu.rate_hz < MIN_STANCE_S - 1e-9)) if len(runs) else 0
        if short:  # the chain rules it out; never hand back a mask that fails the learning's check
            raise GaitModelError(f"the HMM's stance mask has {short} stance runs shorter than {MIN_STANCE_S:g} s")
        events = transition_events(phases)
        meta: dict[str, Any] = {
            "detector": self.describe(),
            "rate_hz": imu.rate_hz,
            "model_rate_hz": learned["model_rate_hz_"],
            "phase_names": PHASE_NAMES,
            "fitted_on_recording": fitted_here,
            "log_likelihood": decoded.log_likelihood,
            "viterbi_log_prob": decoded.path_log_prob,
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
    def load(cls, path: str | PathLike) -> HmmDetector:
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
        shapes = {
            "startprob_": (N_STATES,),
            "transmat_": (N_STATES, N_STATES),
            "means_": (N_STATES, n_feat),
            "covars_": (N_STATES, n_feat, n_feat),
        }
        for key, shape in shapes.items():
            if arrays[key].shape != shape or not np.all(np.isfinite(arrays[key])):
                raise InvalidInputError(
                    f"expected finite values of shape {shape}, got {arrays[key].shape}", field=key, path=path_s
                )
        a = arrays["transmat_"]
        if not is_cyclic_left_right(a):
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
