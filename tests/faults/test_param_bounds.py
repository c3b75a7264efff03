"""Parameters at absurd magnitudes are refused by name, never overflow, exhaust memory or hang.

Every numeric parameter of every registered component is set to +-1e308 (integers to +-10**12)
and the component's action method runs on a tiny simulated walk: it must raise
InvalidParameterError naming the parameter, its value and the expected range, or, for the few
values listed in ``_HARMLESS``, run normally. The simulator's numeric options get the same, and
the three cases of issue 14 (``rate_hz=2e5``, ``n_particles=10**9``, ``dtw_rate_hz=1e6``) are
checked by name. Parametrised over the registry: a new component is covered when registered.
"""

from __future__ import annotations

import numpy as np
import pytest

import footnav
from footnav import InvalidParameterError

pytestmark = pytest.mark.fault

_MAKERS = {
    "detector": footnav.make_detector,
    "estimator": footnav.make_estimator,
    "fusion": footnav.make_fusion,
    "heading_aid": footnav.make_heading_aid,
}

#: (kind, name, parameter, value) that are valid and cheap, so the run must simply succeed.
_HARMLESS = {("fusion", "particle", "seed", 10**12): "any integer >= 0 seeds numpy's generator"}


def _refused_before_work(info) -> bool:
    """The refusal was raised by a component's ``validate_params`` (what every action method
    calls first), so no work ran: a property of the call, not of the machine's speed."""
    return any(entry.name == "validate_params" for entry in info.traceback)


def _numeric_cases():
    cases = []
    for kind, names in footnav.list_components().items():
        for name in names:
            for info in _MAKERS[kind](name).parameter_info():
                default = info.default
                if isinstance(default, bool):
                    continue
                if isinstance(default, int):
                    values = (10**12, -(10**12))
                elif isinstance(default, float) or (default is None and info.name.endswith(("_m", "_radps"))):
                    values = (1e308, -1e308)  # None: fitted or from the data (leg_length_m, init_gyr_bias_std_radps)
                else:
                    continue
                cases += [pytest.param(kind, name, info.name, v, id=f"{kind}-{name}-{info.name}={v:g}") for v in values]
    return cases


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", distance_m=4.0, seed=3)


@pytest.fixture(scope="module")
def stances(walk):
    detector = footnav.make_detector("threshold")
    return detector.detect(walk.left), detector.detect(walk.right)


def _act(component, walk, stances):
    """Run the component's action method on the walk (both feet where it takes two)."""
    if component.kind == "detector":
        return component.detect_pair(walk.left, walk.right)
    if component.kind == "estimator":
        return component.estimate(walk.left, stances[0])
    if component.kind == "heading_aid":
        fused = footnav.make_fusion("independent").fuse(
            footnav.make_estimator("ekf"), walk.left, stances[0], walk.right, stances[1]
        )
        return component.correct(fused, walk.left, walk.right)
    return component.fuse(footnav.make_estimator("ekf"), walk.left, stances[0], walk.right, stances[1])


@pytest.mark.parametrize(("kind", "name", "param", "value"), _numeric_cases())
def test_absurd_parameter_is_refused_by_name(kind, name, param, value, walk, stances):
    component = _MAKERS[kind](name, **{param: value})
    if (kind, name, param, value) in _HARMLESS:
        result = _act(component, walk, stances)  # a fusion: it runs, and its answer is a walk
        assert np.isfinite(result.left.position).all() and result.left.path_length_m > 3.0  # a 4 m walk
        return
    with pytest.raises(InvalidParameterError) as info:
        _act(component, walk, stances)
    message = str(info.value)
    assert f"{param}={value!r}" in message and "expected" in message, message
    assert _refused_before_work(info), [entry.name for entry in info.traceback]


_SIMULATE_SKIP = {"noise", "direction", "mounting_rpy_deg", "segments"}


def _simulate_cases():
    from footnav.data.simulate import _COMMON_DEFAULTS, _SCENARIO_DEFAULTS

    cases = [pytest.param("rate_hz", v, id=f"rate_hz={v:g}") for v in (1e308, -1e308)]
    for name, default in {**_COMMON_DEFAULTS, **_SCENARIO_DEFAULTS["straight"]}.items():
        if name in _SIMULATE_SKIP or isinstance(default, bool):
            continue
        values = (10**12, -(10**12)) if isinstance(default, int) else (1e308, -1e308)
        cases += [pytest.param(name, v, id=f"{name}={v:g}") for v in values]
    return cases


@pytest.mark.parametrize(("option", "value"), _simulate_cases())
def test_absurd_simulate_option_is_refused_by_name(option, value):
    with pytest.raises(InvalidParameterError, match=option) as info:
        footnav.simulate("straight", **{option: value})
    # refused while the options are resolved, before any sample is simulated
    assert any(entry.name == "_resolve_options" for entry in info.traceback), [e.name for e in info.traceback]


@pytest.mark.parametrize(
    "options",
    [{"mounting_rpy_deg": (0.0, 1e308, 0.0)}, {"segments": [(1e308, 0.0)]}, {"segments": [(5.0, 1e308)]}],
    ids=["mounting", "segment-length", "segment-turn"],
)
def test_absurd_simulate_sequences_are_refused(options):
    scenario = "path" if "segments" in options else "straight"
    with pytest.raises(InvalidParameterError, match=next(iter(options))):
        footnav.simulate(scenario, **options)


# -- the three cases of issue 14 ----------------------------------------------------------------


def test_simulate_rate_2e5_is_refused_before_allocating():
    # before: accepted; 17 million samples per foot (issue 14: exhausts memory)
    with pytest.raises(InvalidParameterError, match=r"rate_hz=200000\.0 .*\(0, 10000\] Hz"):
        footnav.simulate("straight", rate_hz=2e5)


def test_simulate_sample_budget_names_the_walk():
    # each option within its range, the product beyond the budget: a 100 km walk at 1 kHz
    with pytest.raises(InvalidParameterError, match="samples per foot"):
        footnav.simulate("straight", rate_hz=1000.0, distance_m=1e5)


def test_a_billion_particles_are_refused(walk, stances):
    # before: accepted (issue 14: exhausts memory or time)
    fusion = footnav.make_fusion("particle", n_particles=10**9)
    with pytest.raises(InvalidParameterError, match=r"n_particles=1000000000 .*\[2, 100000\]"):
        _act(fusion, walk, stances)


def test_dtw_at_a_megahertz_is_refused(walk, stances):
    # before: accepted (issue 14: exhausts memory or time)
    fusion = footnav.make_fusion("dtw", dtw_rate_hz=1e6)
    with pytest.raises(InvalidParameterError, match=r"dtw_rate_hz=1000000\.0 .*\(0, 50\] Hz"):
        _act(fusion, walk, stances)


def test_the_bounds_admit_the_defaults_and_the_upper_values(walk, stances):
    """The ranges are inclusive: the largest allowed value still runs (finite output)."""
    for kind, name, params in [("fusion", "particle", {"n_particles": 2000}), ("fusion", "dtw", {"dtw_rate_hz": 50.0})]:
        result = _act(_MAKERS[kind](name, **params), walk, stances)
        assert np.isfinite(result.path.position).all()
