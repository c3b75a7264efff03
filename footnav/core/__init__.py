"""footnav's contracts layer: what every other layer builds on and a plugin author programs against.

* :mod:`footnav.core.errors` -- the one error and warning hierarchy (public also as
  :mod:`footnav.errors`);
* :mod:`footnav.core.warning_log` -- :func:`~footnav.core.warning_log.warn` and the per-run record of
  warnings that ends in a result's ``meta["warnings"]``;
* :mod:`footnav.core.types` -- the data objects that flow between the stages, with their frames and
  SI units, and the input checks;
* :mod:`footnav.core.parameters` -- a component parameter's unit, description and value checks;
* :mod:`footnav.core.component` -- the component bases (scikit-learn's parameter contract) and the
  offline Protocols of detectors, estimators, fusions and heading aids;
* :mod:`footnav.core.online_contract` -- the Protocols an estimator implements to run online.

It imports nothing of footnav above it (``tests/test_layers.py``): the numerics of :mod:`footnav.nav`
are the next layer up, the components the one after. The public names are re-exported by the
package root (``footnav.ImuData``, ``footnav.StanceDetector``, ...).
"""
