"""Every registered component's defaults survive Pipeline.to_toml() -> footnav.load_pipeline()."""

from __future__ import annotations

import pytest
import tomllib

import footnav

#: The other two stages of a pipeline built around the component under test.
BASE = {"detector": "threshold", "estimator": "ekf", "fusion": "independent"}


def _components():
    return [
        pytest.param(kind, name, id=f"{kind}-{name}")
        for kind, names in footnav.list_components().items()
        for name in names
    ]


@pytest.mark.parametrize("kind, name", _components())
def test_defaults_round_trip_through_toml(kind, name, tmp_path):
    pipe = footnav.make_pipeline(**{**BASE, kind: name})
    comp = getattr(pipe, kind)
    text = pipe.to_toml()
    tomllib.loads(text)  # valid TOML
    path = tmp_path / "pipeline.toml"
    path.write_text(text, encoding="utf-8")
    again = footnav.load_pipeline(path)
    assert again.config() == pipe.config()
    assert type(getattr(again, kind)) is type(comp)
    # TOML has no null: a None default (from the data, fitted) is left out and read back as None
    assert getattr(again, kind).get_params() == comp.get_params()


def test_none_that_is_not_the_default_cannot_be_saved():
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params={"init_gyr_bias_std_radps": 1e-4})
    assert "init_gyr_bias_std_radps = 0.0001" in pipe.to_toml()
    pipe.detector.window_s = None  # not a default: a missing key would mean something else
    with pytest.raises(footnav.core.errors.InvalidParameterError, match="cannot be written to TOML"):
        pipe.to_toml()


def test_step_vector_options_round_trip(tmp_path):
    params = {"step_length": "fitted", "leg_length_m": 0.95, "relative_frame": "heading", "calibration": "standstill"}
    pipe = footnav.make_pipeline("dual-gait", "ekf", "step-vector", fusion_params=params)
    path = tmp_path / "pipeline.toml"
    path.write_text(pipe.to_toml(), encoding="utf-8")
    again = footnav.load_pipeline(path)
    assert again.config() == pipe.config()
    assert {k: again.fusion.get_params()[k] for k in params} == params


def test_parameter_names_are_read_per_class_and_constructor():
    """Component._param_names is cached: a subclass with its own constructor, and a class whose
    constructor is replaced later, must still report their own parameters."""
    from footnav.core.component import StanceDetector

    class Base(StanceDetector):
        name = "base-probe"

        def __init__(self, a_s: float = 1.0) -> None:
            self.a_s = a_s

    class Child(Base):
        name = "child-probe"

        def __init__(self, a_s: float = 1.0, b_s: float = 2.0) -> None:
            super().__init__(a_s)
            self.b_s = b_s

    assert Base().get_params() == {"a_s": 1.0}
    assert Child().get_params() == {"a_s": 1.0, "b_s": 2.0}
    assert Base().get_params() == {"a_s": 1.0}

    def replaced(self, c_s: float = 3.0) -> None:
        self.c_s = c_s

    Base.__init__ = replaced
    assert Base().get_params() == {"c_s": 3.0}
