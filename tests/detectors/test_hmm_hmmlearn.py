"""The HMM detector's use of hmmlearn: its public API only, and that API holds what the detector needs
(the structural zeros of eq. (1) under EM, one EM iteration per ``fit`` call)."""

import re
from pathlib import Path

import numpy as np
from hmmlearn.hmm import GaussianHMM

import footnav.detectors.hmm
from footnav.detectors.hmm import STRUCTURE
from footnav.detectors.hmm.learning import baum_welch
from footnav.detectors.hmm.model import initial_emissions

MIN_STD = 0.05
#: A cyclic 4-state model with well separated 3-D Gaussian emissions.
TRANSMAT = np.array([[0.9, 0.1, 0, 0], [0, 0.8, 0.2, 0], [0, 0, 0.85, 0.15], [0.3, 0, 0, 0.7]])
MEANS = np.array([[0.0, 0.0, 0.0], [2.0, 3.0, 0.0], [0.0, -5.0, 1.0], [-2.0, 2.0, 0.0]])
COVARS = np.stack([np.eye(3) * s**2 for s in (0.1, 0.5, 0.8, 0.5)])
START_TRANSMAT = np.where(STRUCTURE, 0.5, 0.0)


def _sample(n=3000, seed=0):
    truth = GaussianHMM(4, covariance_type="full", init_params="", params="")
    truth.startprob_, truth.transmat_ = np.full(4, 0.25), TRANSMAT
    truth.means_, truth.covars_ = MEANS, COVARS
    return truth.sample(n, random_state=seed)


def _plain(x, z, n_iter, implementation="log"):
    """hmmlearn's GaussianHMM started where footnav's Baum-Welch starts."""
    model = GaussianHMM(
        4,
        covariance_type="full",
        covars_prior=0.0,
        init_params="",
        params="tmc",
        n_iter=n_iter,
        tol=-np.inf,
        implementation=implementation,
    )
    model.startprob_, model.transmat_ = np.full(4, 0.25), START_TRANSMAT
    model.means_, model.covars_ = initial_emissions(x, z, MIN_STD)
    return model


def _ours(x, z, max_iter):
    return baum_welch(x, [len(x)], z, np.full(4, 0.25), START_TRANSMAT, MIN_STD, seed=0, max_iter=max_iter, tol=-np.inf)


def test_public_em_keeps_the_structural_zeros():
    # what the package relies on: zeros of transmat_ stay zero, pi stays as given when 's' is not
    # in params, init_params="" keeps the initial values
    x, z = _sample()
    model = _plain(x, z, n_iter=20)
    model.fit(x)
    assert np.all(model.transmat_[~STRUCTURE] == 0.0)
    assert np.all(model.transmat_[STRUCTURE] > 0.0)
    np.testing.assert_array_equal(model.startprob_, np.full(4, 0.25))
    np.testing.assert_allclose(model.transmat_, TRANSMAT, atol=0.05)
    model, _ = _ours(x, z, max_iter=20)
    assert np.all(model.transmat_[~STRUCTURE] == 0.0)


def test_each_iteration_is_hmmlearns_em_step_plus_min_std():
    # footnav's Baum-Welch = hmmlearn's EM iteration, then min_std**2 on the variances
    x, z = _sample(seed=1)
    ours, em = _ours(x, z, max_iter=3)
    ref = _plain(x, z, n_iter=1)
    history = []
    for _ in range(3):
        ref.fit(x)
        ref.covars_ = ref.covars_ + MIN_STD**2 * np.eye(3)
        history.append(ref.monitor_.history[-1])
    assert em["n_iter"] == 3 and not any("underflow" in m for m in em["messages"])
    np.testing.assert_allclose(em["history"], history, rtol=1e-12)
    for name in ("transmat_", "means_", "covars_"):
        np.testing.assert_allclose(getattr(ours, name), getattr(ref, name), rtol=0, atol=1e-10, err_msg=name)


def test_a_sample_far_from_every_state_falls_back_to_log_space():
    # hmmlearn's scaled forward pass exponentiates raw log-densities: on a sample far from every
    # Gaussian they all underflow to 0 and it refuses; that iteration and the rest run in log space
    # (one sample in a state of n samples lies at most (n - 1) / sqrt(n) of its std from the
    # state's mean: underflow, below -745 nats, needs n above about 1500)
    x, z = _sample(n=12000, seed=2)
    x[6000] = [1e6, -1e6, 1e6]
    model, em = _ours(x, z, max_iter=3)
    assert model.implementation == "log" and em["n_iter"] == 3
    assert any("underflow" in m and "log space" in m for m in em["messages"]), em["messages"]
    assert np.isfinite(em["history"]).all() and np.isfinite(model.covars_).all()
    assert np.all(model.transmat_[~STRUCTURE] == 0.0)


def test_no_private_hmmlearn_api():
    # issue 18: the package once overrode GaussianHMM._fit_scaling and _do_mstep, which pinned
    # hmmlearn below 0.4. Nothing private of hmmlearn may come back.
    package = Path(footnav.detectors.hmm.__file__).parent
    private = re.compile(r"hmmlearn\.(\w+\.)?_(?!_)|_hmmc|\(\s*(Gaussian|Base)HMM\s*\)|\bmodel\._[a-z]|\.monitor_\._")
    found = [
        f"{path.name}:{n}: {line.strip()}"
        for path in sorted(package.glob("*.py"))
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if private.search(line) and not line.lstrip().startswith("#")
    ]
    assert not found, "private hmmlearn API used (use its public API; see learning.baum_welch):\n" + "\n".join(found)
