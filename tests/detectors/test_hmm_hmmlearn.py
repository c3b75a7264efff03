"""The HMM detector's use of hmmlearn: the structural zeros through the public API, and the two
private overrides (footnav/detectors/hmm/_hmmlearn_private.py), which must fail loudly on an
hmmlearn that changes what they rely on."""

import numpy as np
import pytest
from hmmlearn.base import BaseHMM
from hmmlearn.hmm import GaussianHMM

from footnav.detectors.hmm import STRUCTURE, _hmmlearn_private
from footnav.detectors.hmm._hmmlearn_private import HmmlearnApiError, check_private_api
from footnav.detectors.hmm.model import build_hmm

MIN_COVAR = 0.05**2
#: A cyclic 4-state model with well separated 3-D Gaussian emissions.
TRANSMAT = np.array([[0.9, 0.1, 0, 0], [0, 0.8, 0.2, 0], [0, 0, 0.85, 0.15], [0.3, 0, 0, 0.7]])
MEANS = np.array([[0.0, 0.0, 0.0], [2.0, 3.0, 0.0], [0.0, -5.0, 1.0], [-2.0, 2.0, 0.0]])
COVARS = np.stack([np.eye(3) * s**2 for s in (0.1, 0.5, 0.8, 0.5)])


def _sample(n=3000, seed=0):
    truth = GaussianHMM(4, covariance_type="full", init_params="", params="")
    truth.startprob_, truth.transmat_ = np.full(4, 0.25), TRANSMAT
    truth.means_, truth.covars_ = MEANS, COVARS
    return truth.sample(n, random_state=seed)[0]


def _start(model):
    """The initial guess, a little off the truth (as footnav's K-means guess is)."""
    model.startprob_ = np.full(4, 0.25)
    model.transmat_ = np.where(STRUCTURE, 0.5, 0.0)
    model.means_ = MEANS + 0.3
    model.covars_ = COVARS * 2.0
    model.n_features = 3
    return model


def test_public_em_keeps_the_structural_zeros():
    # what the package relies on from hmmlearn's public API: zeros of transmat_ stay zero, pi
    # stays as given when 's' is not in params, init_params="" keeps the initial values
    x = _sample()
    model = _start(GaussianHMM(4, covariance_type="full", init_params="", params="tmc", n_iter=20))
    model.fit(x)
    assert np.all(model.transmat_[~STRUCTURE] == 0.0)
    assert np.all(model.transmat_[STRUCTURE] > 0.0)
    np.testing.assert_array_equal(model.startprob_, np.full(4, 0.25))
    np.testing.assert_allclose(model.transmat_, TRANSMAT, atol=0.05)


def test_private_api_is_the_one_the_overrides_were_written_for():
    check_private_api.cache_clear()
    check_private_api()  # raises HmmlearnApiError naming what changed


def test_a_changed_private_api_is_a_clear_error(monkeypatch):
    from hmmlearn import _hmmc

    def fit_scaling(self, X, lengths):  # a new parameter
        raise AssertionError("not called")

    monkeypatch.setattr(BaseHMM, "_fit_scaling", fit_scaling)
    monkeypatch.delattr(_hmmc, "backward_scaling")
    check_private_api.cache_clear()
    _hmmlearn_private.gaussian_hmm_class.cache_clear()
    try:
        with pytest.raises(HmmlearnApiError, match=r"hmmlearn .* changed private API .*GaussianHMM\._fit_scaling"
                           r"\(self, X, lengths\) no longer takes \(self, X\).*_hmmc\.backward_scaling is missing"
                           r".*hmmlearn>=0\.3,<0\.4"):
            build_hmm(np.full(4, 0.25), TRANSMAT, MEANS, COVARS, min_covar=MIN_COVAR, seed=0)
    finally:
        monkeypatch.undo()
        check_private_api.cache_clear()
        _hmmlearn_private.gaussian_hmm_class.cache_clear()


def test_overrides_are_called_and_compute_what_their_docstring_says():
    # One EM iteration of the footnav model equals hmmlearn's public log-space EM iteration plus
    # min_covar on the covariance diagonals: the overridden M-step regularises, the overridden
    # E-step gives hmmlearn's posteriors. Fails when hmmlearn stops calling the overrides or
    # changes what they must return.
    x = _sample(seed=1)
    ours = _start(build_hmm(np.full(4, 0.25), TRANSMAT, MEANS, COVARS, min_covar=MIN_COVAR, seed=0,
                            max_iter=1, implementation="scaling"))
    ref = _start(GaussianHMM(4, covariance_type="full", min_covar=MIN_COVAR, covars_prior=0.0, init_params="",
                             params="tmc", n_iter=1, implementation="log"))
    ours.fit(x)
    ref.fit(x)
    assert ours.monitor_.iter == ref.monitor_.iter == 1
    np.testing.assert_allclose(ours.monitor_.history, ref.monitor_.history, rtol=1e-12)
    np.testing.assert_allclose(ours.transmat_, ref.transmat_, rtol=0, atol=1e-10)
    np.testing.assert_allclose(ours.means_, ref.means_, rtol=0, atol=1e-10)
    np.testing.assert_allclose(ours.covars_, ref.covars_ + MIN_COVAR * np.eye(3), rtol=0, atol=1e-10)


def test_shifted_estep_survives_samples_far_from_every_state():
    # hmmlearn's own scaling E-step exponentiates raw log-densities: on a sample far from every
    # Gaussian they all underflow to 0 and the fit fails; the override divides by the largest.
    x = _sample(seed=2)
    x[1500] = [60.0, -80.0, 40.0]
    plain = _start(GaussianHMM(4, covariance_type="full", init_params="", params="tmc", n_iter=3,
                               implementation="scaling"))
    with np.errstate(all="ignore"), pytest.raises(ValueError, match="underflow"):
        plain.fit(x)
    ours = _start(build_hmm(np.full(4, 0.25), TRANSMAT, MEANS, COVARS, min_covar=MIN_COVAR, seed=0,
                            max_iter=3, implementation="scaling"))
    ours.fit(x)
    assert np.isfinite(ours.monitor_.history).all()
    assert np.all(ours.transmat_[~STRUCTURE] == 0.0) and np.isfinite(ours.covars_).all()
