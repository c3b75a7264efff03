"""Every registered component's defaults survive Pipeline.to_toml() -> footnav.load_pipeline()."""

from __future__ import annotations

import pytest
import tomllib

import footnav

#: The other two stages of a pipeline built around the component under test.
BASE = {"detector": "threshold", "estimator": "ekf", "fusion": "independent"}


def _components():
    return [pytest.param(kind, name, id=f"{kind}-{name}") for kind, names in footnav.list_components().items() for name in names]


@pytest.mark.parametrize("kind, name", _components())
def test_defaults_round_trip_through_toml(kind, name, tmp_path):
    pipe = footnav.make_pipeline(**{**BASE, kind: name})
    comp = getattr(pipe, kind)
    for param, value in comp.get_params().items():
        # TOML has no null: a None default makes every pipeline with this component unsavable
        assert value is not None, f"{kind} {name!r}: parameter {param} defaults to None, which TOML cannot hold"
    text = pipe.to_toml()
    tomllib.loads(text)  # valid TOML
    path = tmp_path / "pipeline.toml"
    path.write_text(text, encoding="utf-8")
    again = footnav.load_pipeline(path)
    assert again.config() == pipe.config()
    assert type(getattr(again, kind)) is type(comp)


def test_step_vector_options_round_trip(tmp_path):
    params = {"step_length": "fitted", "leg_length_m": 0.95, "relative_frame": "heading", "calibration": "standstill"}
    pipe = footnav.make_pipeline("dual-gait", "ekf", "step-vector", fusion_params=params)
    path = tmp_path / "pipeline.toml"
    path.write_text(pipe.to_toml(), encoding="utf-8")
    again = footnav.load_pipeline(path)
    assert again.config() == pipe.config()
    assert {k: again.fusion.get_params()[k] for k in params} == params
