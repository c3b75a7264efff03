"""The one place footnav reaches into hmmlearn's private API, and why.

hmmlearn's public API holds the model of eq. (1)-(2) as it is: ``transmat_`` initialised with
the structural zeros stays zero under Baum-Welch (``BaseHMM._do_mstep`` keeps every zero of
``transmat_`` at zero), ``init_params=""`` keeps footnav's initialisation and ``params="tmc"``
leaves pi uniform. Two things of footnav's fit have no public equivalent, and
:class:`CyclicGaussianHMM` overrides two private methods of ``GaussianHMM`` for them:

* ``_fit_scaling`` (the E-step of ``implementation="scaling"``): the emission probabilities are
  divided by their per-sample maximum before the scaled forward-backward, and the scale is added
  back to the log-likelihood. hmmlearn exponentiates the raw log-densities, which underflow to 0
  for every state on a sample far from all Gaussians (then the fit fails on NaNs). A per-sample
  factor common to all states changes neither the posteriors nor the transition counts. The
  public alternative, ``implementation="log"``, is about twice as slow and not bit-identical.
* ``_do_mstep``: ``min_covar`` is added to the covariance diagonals after every M-step (scikit-
  learn's ``reg_covar``), so a noise-free stance cannot make a covariance singular. hmmlearn's
  ``min_covar`` only enters the initialisation for full covariances, and its public
  ``covars_prior`` is divided by each state's occupancy, a different regularisation.

Both rely on hmmlearn 0.3's internals: ``_fit_scaling(X)`` returning ``(frameprob, log_prob,
posteriors, fwdlattice, bwdlattice)``, ``_compute_log_likelihood``, ``_compute_posteriors_scaling``,
the ``_covars_`` attribute, and ``hmmlearn._hmmc.forward_scaling`` / ``backward_scaling``.
:func:`check_private_api` checks them before the first fit and raises :class:`HmmlearnApiError`
naming what changed; tests/detectors/test_hmm_hmmlearn.py checks them and what the overrides
compute against hmmlearn's public results, so a new hmmlearn that changes them fails loudly.
"""

from __future__ import annotations

import importlib
import inspect
from functools import cache

import numpy as np

from footnav.core.errors import FootnavError

__all__ = ["HmmlearnApiError", "check_private_api", "gaussian_hmm_class"]

#: hmmlearn's private members the overrides use or call: (module, attribute, its parameters, or
#: None for a compiled function whose signature cannot be read).
PRIVATE_API = (
    ("hmmlearn.hmm", "GaussianHMM._fit_scaling", ("self", "X")),
    ("hmmlearn.hmm", "GaussianHMM._do_mstep", ("self", "stats")),
    ("hmmlearn.hmm", "GaussianHMM._compute_log_likelihood", ("self", "X")),
    ("hmmlearn.hmm", "GaussianHMM._compute_posteriors_scaling", ("self", "fwdlattice", "bwdlattice")),
    ("hmmlearn._hmmc", "forward_scaling", None),
    ("hmmlearn._hmmc", "backward_scaling", None),
)


class HmmlearnApiError(FootnavError, ImportError):
    """The installed hmmlearn lacks a private member footnav's HMM detector overrides or calls."""


@cache
def check_private_api() -> None:
    """Raise :class:`HmmlearnApiError` naming every member of :data:`PRIVATE_API` that is missing
    or takes other parameters in the installed hmmlearn."""
    import hmmlearn

    problems = []
    for module, attribute, params in PRIVATE_API:
        try:
            obj = importlib.import_module(module)
            for name in attribute.split("."):
                obj = getattr(obj, name)
        except (ImportError, AttributeError):
            problems.append(f"{module}.{attribute} is missing")
            continue
        if params is not None and tuple(inspect.signature(obj).parameters) != params:
            problems.append(f"{module}.{attribute}{inspect.signature(obj)} no longer takes ({', '.join(params)})")
    if problems:
        raise HmmlearnApiError(
            f"hmmlearn {hmmlearn.__version__} changed private API that footnav's 'hmm' detector overrides "
            f"({'; '.join(problems)}); install hmmlearn 0.3.x (pip install 'hmmlearn>=0.3,<0.4') or update "
            "footnav/detectors/hmm/_hmmlearn_private.py"
        )


@cache
def gaussian_hmm_class() -> type:
    """:class:`CyclicGaussianHMM`, defined on first use (hmmlearn is imported lazily)."""
    from hmmlearn import _hmmc
    from hmmlearn.hmm import GaussianHMM

    check_private_api()

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

