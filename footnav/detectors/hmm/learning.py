"""Learning the HMM detector's model: Baum-Welch from the initial guess, and the check after decoding.

EM (hmmlearn, :func:`baum_welch`) starts from the re-ordered K-means guess
(:mod:`~footnav.detectors.hmm.initialise`). The learned model is then decoded on its own training
data and checked (:func:`check_model`): stance must be the stillest state, and its runs must be
steps, not one-sample visits at the zero crossings of the swing's rate. When the check fails the
model is refitted once with a coarser covariance floor (``FALLBACK_MIN_STD_FACTOR`` x
``min_std``), with a warning; a model whose stance state is still not the stillest raises
:class:`~footnav.core.errors.GaitModelError`. :func:`learn` runs all of it and returns the learned
values with how the fit went (``fit_info_``).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, FootnavWarning, GaitModelError
from footnav.core.types import ImuData, stance_intervals
from footnav.core.warning_log import warn
from footnav.detectors.hmm.features import model_grid
from footnav.detectors.hmm.initialise import STANDSTILL_MAX_RADPS, initial_guess
from footnav.detectors.hmm.model import N_STATES, STANCE, build_hmm, initial_emissions

__all__ = ["baum_welch", "check_model", "learn"]

#: Stance runs of the decoded training recording shorter than this are not steps (s): a stance
#: state visited for one or two model samples at a zero crossing of the swing's rate.
MICRO_STANCE_S = 0.05
#: Largest share of micro stance runs a learned model may produce on its training recording (one is
#: always tolerated).
MAX_MICRO_STANCE_SHARE = 0.01
#: Factor on ``min_std`` of the single documented refit when the check after decoding fails.
FALLBACK_MIN_STD_FACTOR = 4.0

_LOG = logging.getLogger("hmmlearn")
#: A log-likelihood drop larger than this between EM iterations is reported (hmmlearn's own
#: tolerance: the square root of the float64 epsilon).
EM_DECREASE_TOL = float(np.finfo(float).eps ** 0.5)


class _Capture(logging.Handler):
    """Collects hmmlearn's log records (degenerate-fit warnings) during one fit, each once (EM
    calls hmmlearn's ``fit`` once per iteration)."""

    def __init__(self) -> None:
        super().__init__(level=logging.DEBUG)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        message = f"hmmlearn {record.levelname.lower()}: {record.getMessage()}"
        if message not in self.messages:
            self.messages.append(message)


def baum_welch(
    x: NDArray[np.float64],
    lengths: Sequence[int],
    z0: NDArray[np.int64],
    startprob: NDArray[np.float64],
    transmat: NDArray[np.float64],
    min_std: float,
    *,
    seed: int,
    max_iter: int,
    tol: float,
):
    """EM from the re-ordered K-means labels ``z0``; returns the model and how the fit went.

    One hmmlearn ``fit`` call per EM iteration (``n_iter=1``, ``init_params=""``: each call runs
    one E-step on the current values and one M-step), then ``min_std**2`` added to the variances
    (scikit-learn's ``reg_covar``, which hmmlearn has no public equivalent of). EM stops when an
    iteration gains less than ``tol`` nats or after ``max_iter`` iterations. hmmlearn's scaled
    forward-backward is used (about twice as fast as its log-space one); when it underflows (a
    sample far from every Gaussian) that iteration and the rest run in log space. hmmlearn's
    public API only (footnav once overrode its private ``_fit_scaling`` and ``_do_mstep`` instead;
    the learned values agree to the last few bits, the decoded phases exactly).
    """
    means, covars = initial_emissions(x, z0, min_std)
    model = build_hmm(startprob, transmat, means, covars, seed=seed, implementation="scaling")
    reg = min_std**2 * np.eye(x.shape[1])
    history: list[float] = []
    handler = _Capture()
    old_propagate = _LOG.propagate
    _LOG.addHandler(handler)
    _LOG.propagate = False
    try:
        for _ in range(max_iter):
            if np.any(model.transmat_.sum(axis=1) == 0):
                # a state no longer visited: hmmlearn's fit would refuse the matrix
                handler.messages.append("footnav: a row of transmat_ has zero sum (a state never visited); EM stopped")
                break
            try:
                model.fit(x, lengths)
            except ValueError as exc:
                if "underflow" not in str(exc):
                    raise
                handler.messages.append(f"footnav: {exc}; EM continues in log space")
                model.set_params(implementation="log")
                model.fit(x, lengths)
            model.covars_ = model.covars_ + reg
            log_prob = float(model.monitor_.history[-1])
            if history and log_prob - history[-1] < -EM_DECREASE_TOL:
                handler.messages.append(
                    f"footnav: log-likelihood decreased from {history[-1]} to {log_prob} "
                    f"(delta {log_prob - history[-1]})"
                )
            history.append(log_prob)
            if len(history) >= 2 and history[-1] - history[-2] < tol:
                break
    finally:
        _LOG.removeHandler(handler)
        _LOG.propagate = old_propagate
    return model, {"history": history, "n_iter": len(history), "messages": handler.messages}


def check_model(model, x: NDArray, lengths: Sequence[int], gyr_norm: NDArray, rate: float) -> dict[str, Any]:
    """Check after decoding of a learned model on its training data (Viterbi path).

    * ``stance_stillest``: the stance state has the smallest median |w| of the four states, below
      ``STANDSTILL_MAX_RADPS`` (else its mask would not be stance: the inverted mask of a collapsed
      model).
    * ``micro_share``: share of stance runs shorter than ``MICRO_STANCE_S``, at most
      ``MAX_MICRO_STANCE_SHARE`` (else one non-stance state has become a broad catch-all of the
      movement and the stance state is visited for one or two samples at zero crossings of the
      swing's rate: false steps); a single one is tolerated.
    """
    states = np.concatenate(
        [
            model.decode(x[a:b], algorithm="viterbi")[1]
            for a, b in zip(np.cumsum([0, *lengths[:-1]]), np.cumsum(lengths))
        ]
    )
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


def learn(
    recordings: Sequence[ImuData],
    *,
    features: str,
    model_rate_hz: float,
    lowpass_cutoff_hz: float,
    reorder_min_stance_s: float,
    max_iter: int,
    tol: float,
    min_std: float,
    seed: int,
) -> dict[str, Any]:
    """Learn the model of eq. (1)-(2) from ``recordings`` (each its own sequence) with the
    detector's parameters; returns the learned values (``startprob_``, ``transmat_``, ``means_``,
    ``covars_``, ``features_``, ``model_rate_hz_``, ``fit_info_``)."""
    rate = float(model_rate_hz)
    grids = [model_grid(imu, features, rate) for imu in recordings]
    x = np.concatenate([g.features for g in grids])
    lengths = [len(g.features) for g in grids]
    total_s = sum(imu.duration_s for imu in recordings)
    guess = initial_guess(
        x,
        lengths,
        rate,
        total_s=total_s,
        lowpass_cutoff_hz=lowpass_cutoff_hz,
        reorder_min_stance_s=reorder_min_stance_s,
        seed=seed,
    )
    z0, startprob, transmat, order = guess.z0, guess.startprob, guess.transmat, guess.order
    gyr_norm = np.linalg.norm(x[:, :3], axis=1)
    em_params: dict[str, Any] = {"seed": seed, "max_iter": int(max_iter), "tol": float(tol)}

    # Baum-Welch, then the check after decoding (stance the stillest state, stance runs that are
    # steps); one documented refit with a coarser covariance floor when the check fails
    min_std = float(min_std)
    model, em = baum_welch(x, lengths, z0, startprob, transmat, min_std, **em_params)
    check = check_model(model, x, lengths, gyr_norm, rate)
    fallback = None
    if not check["ok"]:
        first = check
        min_std = FALLBACK_MIN_STD_FACTOR * min_std
        model, em = baum_welch(x, lengths, z0, startprob, transmat, min_std, **em_params)
        check = check_model(model, x, lengths, gyr_norm, rate)
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
            f"{fallback['action']}"
            + ("" if check["ok"] else f", still: {check['problem']}")
            + "; recorded in fit_info_['fallback']",
            DataQualityWarning,
            stacklevel=3,
        )
    history = em["history"]
    # hmmlearn's monitor_.converged is also True when it merely ran out of iterations
    converged = len(history) >= 2 and history[-1] - history[-2] < float(tol)
    if not converged:
        warn(
            f"HmmDetector: Baum-Welch did not converge in max_iter={max_iter} iterations (last gain "
            f"{history[-1] - history[-2] if len(history) >= 2 else float('nan'):.3g} nats >= tol={tol:g}); "
            "recorded in fit_info_['converged']",
            FootnavWarning,
            stacklevel=3,
        )
    info = {
        "n_iter": int(em["n_iter"]),
        "converged": bool(converged),
        "log_likelihood": float(history[-1]) if history else float("nan"),
        "n_samples": len(x),
        "n_recordings": len(recordings),
        "duration_s": float(total_s),
        "kmeans_centers": guess.kmeans_centers.tolist(),
        "kmeans_permutation": order.permutation.tolist(),
        "significant_axis": guess.significant_axes,
        "n_movements": int(order.n_movements),
        "votes": order.votes,
        "vote_fallback": order.fallback,
        "reorder_min_stance_s": guess.reorder_min_stance_s,
        "initial_transmat": transmat.tolist(),
        "min_std": min_std,
        "check": check,
        "fallback": fallback,
        "messages": em["messages"],
        "warnings": [],  # filled by HmmDetector._learn
    }
    return {
        "startprob_": np.array(model.startprob_, dtype=np.float64),
        # as Baum-Welch left it: the structural zeros are zeros by EM itself (tested), not forced
        "transmat_": np.array(model.transmat_, dtype=np.float64),
        "means_": np.array(model.means_, dtype=np.float64),
        "covars_": np.array(model.covars_, dtype=np.float64),
        "features_": features,
        "model_rate_hz_": rate,
        "fit_info_": info,
    }
