"""A third-party component that breaks its contract is named, never blamed on the user's data
(issue 14, deliverable 5)."""

from __future__ import annotations

import types

import numpy as np
import pytest

import footnav
from footnav import FootEstimator, PluginError, StanceDetector, StanceResult
from footnav.plugins.manager import build_registry, reset_registry

pytestmark = pytest.mark.fault


class _Detector(StanceDetector):
    name = "bad-detector"

    def __init__(self, *, behaviour: str = "none") -> None:
        self.behaviour = behaviour

    def detect(self, imu):
        if self.behaviour == "none":
            return None
        if self.behaviour == "short":
            return StanceResult(np.zeros(imu.n_samples - 7, bool))
        if self.behaviour == "exit":
            raise SystemExit(0)
        raise AssertionError(self.behaviour)


class _Estimator(FootEstimator):
    name = "nan-estimator"

    def __init__(self) -> None:
        pass

    def estimate(self, imu, stance):
        traj = footnav.make_estimator("ekf").estimate(imu, stance)
        position = np.array(traj.position)
        position[123:] = np.nan
        return footnav.FootTrajectory(
            traj.t, position, traj.velocity, traj.quaternion, traj.position_std, traj.steps, dict(traj.meta)
        )


@pytest.fixture
def plugins():
    mod = types.ModuleType("bad_plugin")

    def footnav_register_detectors(register):
        register(_Detector)

    def footnav_register_estimators(register):
        register(_Estimator)

    mod.footnav_register_detectors = footnav.hookimpl(footnav_register_detectors)
    mod.footnav_register_estimators = footnav.hookimpl(footnav_register_estimators)
    reset_registry(build_registry([mod], autoload=False))
    yield
    reset_registry()


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", distance_m=10.0, seed=2)


@pytest.mark.parametrize(
    "behaviour, message",
    [
        ("none", "detector 'bad-detector' from <direct> returned NoneType for the left foot, not a StanceResult"),
        ("short", r"returned a stance mask of \d+ samples for the left foot's \d+"),
        ("exit", "detector 'bad-detector' from <direct> failed: SystemExit"),
    ],
)
def test_a_detector_breaking_its_contract_is_named(plugins, walk, behaviour, message):
    pipe = footnav.make_pipeline("bad-detector", detector_params={"behaviour": behaviour})
    with pytest.raises(PluginError, match=message):
        pipe.run(walk.left)


def test_non_finite_positions_from_a_plugin_are_never_returned(plugins, walk):
    with pytest.raises(
        PluginError, match=r"estimator 'nan-estimator' from <direct> returned non-finite positions .*sample 123"
    ):
        footnav.make_pipeline("adaptive", "nan-estimator").run(walk.left)


def test_a_plugin_calling_sys_exit_does_not_end_the_cli_with_success(plugins, walk, tmp_path, capsys):
    from footnav.cli import EXIT_INTERNAL, main
    from footnav.data.io.footnav_csv import write_footnav_csv

    write_footnav_csv(walk.left, tmp_path / "l.csv")
    argv = [
        "run",
        "--left",
        str(tmp_path / "l.csv"),
        "--pipeline",
        str(tmp_path / "p.toml"),
        "--out",
        str(tmp_path / "o"),
    ]
    (tmp_path / "p.toml").write_text('[detector]\nname = "bad-detector"\nbehaviour = "exit"\n')
    assert main(argv) == EXIT_INTERNAL
    assert "SystemExit" in capsys.readouterr().err and not (tmp_path / "o").exists()


def test_the_inputs_provenance_cannot_be_rewritten(walk):
    import json
    import pickle

    class Meddler(StanceDetector):
        name = "meddler"

        def __init__(self) -> None:
            pass

        def detect(self, imu):
            imu.meta["source"] = "/etc/passwd"  # a plugin rewriting the input's provenance
            return footnav.make_detector("adaptive").detect(imu)

    imu = footnav.ImuData(walk.left.t, walk.left.acc, walk.left.gyr, meta={"source": "walk.csv"})
    with pytest.raises(PluginError, match="meddler.*read-only"):
        footnav.make_pipeline(Meddler()).run(imu)
    assert imu.meta["source"] == "walk.csv"
    # still a dict for everything that reads it: copies, pickles (worker processes), JSON
    assert pickle.loads(pickle.dumps(imu)).meta == {"source": "walk.csv"}
    assert json.loads(json.dumps(imu.meta)) == {"source": "walk.csv"}
    changed = {**imu.meta, "source": "other.csv"}
    assert changed["source"] == "other.csv" and imu.meta.copy() == {"source": "walk.csv"}
    for mutate in (
        lambda m: m.update(a=1),
        lambda m: m.pop("source"),
        lambda m: m.clear(),
        lambda m: m.setdefault("b", 2),
    ):
        with pytest.raises(TypeError, match="read-only"):
            mutate(imu.meta)
