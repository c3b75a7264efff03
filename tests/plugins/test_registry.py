import types

import numpy as np
import pytest

import footnav
from footnav import (
    CompositionError,
    InvalidParameterError,
    PluginError,
    PluginWarning,
    StanceDetector,
    StanceResult,
    UnknownComponentError,
)
from footnav.plugins import manager
from footnav.plugins.manager import build_registry, reset_registry


class HalfDetector(StanceDetector):
    """Test detector: stance in the first half.

    Parameters
    ----------
    fraction : float
        Share of samples in stance.
    """

    name = "half"

    def __init__(self, *, fraction: float = 0.5) -> None:
        self.fraction = fraction

    def detect(self, imu):
        mask = np.arange(imu.n_samples) < self.fraction * imu.n_samples
        return StanceResult(mask)


def _plugin(**hooks):
    mod = types.ModuleType("fake_plugin")
    for name, fn in hooks.items():
        setattr(mod, name, footnav.hookimpl(fn))
    return mod


def test_builtins_are_listed_with_origin_footnav():
    comps = footnav.list_components()
    assert "threshold" in comps["detector"]
    assert "ekf" in comps["estimator"]
    assert "independent" in comps["fusion"]
    reg = manager.get_registry()
    assert {e.origin for e in reg} == {"footnav"}


def test_unknown_name_lists_available_and_suggests():
    with pytest.raises(UnknownComponentError) as err:
        footnav.make_detector("treshold")
    msg = str(err.value)
    assert "available: " in msg and "glrt" in msg and "threshold" in msg and "Did you mean 'threshold'" in msg
    assert isinstance(err.value, LookupError)


def test_unknown_parameter_lists_valid_ones():
    with pytest.raises(InvalidParameterError) as err:
        footnav.make_detector("threshold", windw_s=0.2)
    msg = str(err.value)
    assert "windw_s" in msg and "did you mean 'window_s'" in msg and "gyr_threshold_radps" in msg


def test_invalid_parameter_value_is_reported_at_detect():
    det = footnav.make_detector("threshold", window_s=-1.0)  # constructors only store
    rec_t = np.arange(100) / 100.0
    imu = footnav.ImuData(rec_t, np.tile([0, 0, 9.8], (100, 1)), np.zeros((100, 3)))
    with pytest.raises(InvalidParameterError, match="window_s=-1.0"):
        det.detect(imu)


def test_direct_plugin_registers_and_is_usable_by_name():
    def footnav_register_detectors(register):
        register(HalfDetector)

    reg = build_registry([_plugin(footnav_register_detectors=footnav_register_detectors)], autoload=False)
    entry = reg.get("detector", "half")
    assert entry.cls is HalfDetector and entry.origin == "<direct>" and entry.plugin == "fake_plugin"
    reset_registry(reg)
    pipe = footnav.make_pipeline(detector="half", detector_params={"fraction": 0.3})
    assert pipe.detector.fraction == 0.3


def test_a_duplicate_name_is_reported_and_skipped_and_the_rest_keep_working():
    class Impostor(HalfDetector):
        name = "threshold"

    def footnav_register_detectors(register):
        register(Impostor)
        register(HalfDetector)  # the plugin's other components still register

    with pytest.warns(PluginWarning, match="registered twice") as caught:
        reg = build_registry([_plugin(footnav_register_detectors=footnav_register_detectors)], autoload=False)
    msg = str(caught[0].message)
    assert "footnav.builtin" in msg and "fake_plugin" in msg and "ThresholdDetector" in msg and "Impostor" in msg
    assert reg.get("detector", "threshold").origin == "footnav"  # the built-in keeps its name
    assert reg.get("detector", "half").cls is HalfDetector
    assert [f[0] for f in reg.failed] == ["fake_plugin"]


def test_registering_a_non_component_is_reported_and_skipped():
    def footnav_register_detectors(register):
        register(dict)

    with pytest.warns(PluginWarning, match="subclass of footnav.StanceDetector"):
        reg = build_registry([_plugin(footnav_register_detectors=footnav_register_detectors)], autoload=False)
    assert "threshold" in reg.names("detector")


def test_misspelt_hook_is_a_warning_and_others_still_load():
    def footnav_register_detector(register):  # missing "s"
        register(HalfDetector)

    with pytest.warns(PluginWarning, match="fake_plugin"):
        reg = build_registry([_plugin(footnav_register_detector=footnav_register_detector)], autoload=False)
    assert "half" not in reg.names("detector") and "threshold" in reg.names("detector")
    assert reg.failed and reg.failed[0][0] == "fake_plugin"


class _FakeDist:
    name = "broken-dist"


class _FakeEntryPoint:
    def __init__(self, name, target):
        self.name, self._target, self.dist = name, target, _FakeDist()

    def load(self):
        if isinstance(self._target, Exception):
            raise self._target
        return self._target


def test_broken_entry_point_is_a_warning_naming_it(monkeypatch):
    def footnav_register_detectors(register):
        register(HalfDetector)

    good = _plugin(footnav_register_detectors=footnav_register_detectors)
    eps = [_FakeEntryPoint("broken", ImportError("No module named 'missing_dep'")), _FakeEntryPoint("good", good)]
    monkeypatch.setattr(manager.importlib.metadata, "entry_points", lambda group: eps if group == "footnav" else [])
    with pytest.warns(PluginWarning, match="'broken' from broken-dist failed to import.*missing_dep"):
        reg = build_registry(autoload=True)
    assert "half" in reg.names("detector")
    assert reg.get("detector", "half").origin == "broken-dist"  # the fake dist name of both entries


def test_hook_that_raises_is_a_warning(monkeypatch):
    def footnav_register_detectors(register):
        raise RuntimeError("boom")

    with pytest.warns(PluginWarning, match="boom"):
        reg = build_registry([_plugin(footnav_register_detectors=footnav_register_detectors)], autoload=False)
    assert "threshold" in reg.names("detector")  # the built-ins are untouched


def test_autoload_can_be_disabled_by_environment(monkeypatch):
    calls = []
    monkeypatch.setattr(manager.importlib.metadata, "entry_points", lambda group: calls.append(group) or [])
    monkeypatch.setenv(manager.AUTOLOAD_ENV, "1")
    build_registry()
    assert calls == []
    monkeypatch.delenv(manager.AUTOLOAD_ENV)
    build_registry()
    assert calls == ["footnav"]


def test_two_foot_component_with_one_foot_is_a_composition_error():
    class BothFeet(HalfDetector):
        name = "both-feet"
        needs_two_feet = True

    def footnav_register_detectors(register):
        register(BothFeet)

    reset_registry(build_registry([_plugin(footnav_register_detectors=footnav_register_detectors)], autoload=False))
    pipe = footnav.make_pipeline(detector="both-feet")
    t = np.arange(50) / 100.0
    imu = footnav.ImuData(t, np.tile([0, 0, 9.8], (50, 1)), np.zeros((50, 3)))
    with pytest.raises(CompositionError, match="needs both feet"):
        pipe.run(imu)


def test_parameter_info_has_units_and_descriptions():
    info = {p.name: p for p in footnav.make_estimator("ekf").parameter_info()}
    assert info["zupt_std_mps"].unit == "m/s"
    assert info["acc_noise_mps2_sqrthz"].unit == "m/s^2/sqrt(Hz)"
    assert "zero-velocity" in info["zupt_std_mps"].description
    assert info["zupt_std_mps"].default == 0.01
    madgwick = {p.name: p for p in footnav.make_estimator("madgwick").parameter_info()}
    assert madgwick["acc_error_walk_mps3_sqrthz"].unit == "m/s^3/sqrt(Hz)"
    # every numeric built-in parameter names its unit, except these dimensionless ones
    dimensionless = {"gamma", "max_iter", "tol", "min_std", "seed", "n_particles"}
    # the adaptive detector's ratios (of bounds, peaks and strides)
    dimensionless |= {
        "stance_factor",
        "swing_fraction",
        "min_scale",
        "swing_prominence",
        "stride_fraction",
        "pivot_yaw_share",
    }
    dimensionless |= {"zupt_edge_max_fraction"}  # the EKF's: of a stance's samples
    dimensionless |= {"gyro_scale_std"}  # ekf, madgwick: a fraction of the rate
    dimensionless |= {
        "n_directions",
        "min_stretch_strides",
        "min_strength",
    }  # dominant-directions: counts, a resultant length
    dimensionless |= {"magnitude_tol", "min_stances", "min_fraction"}  # magnetometer: a fraction, a count, a share
    for kind, names in footnav.list_components().items():
        for name in names:
            for p in getattr(footnav, f"make_{kind}")(name).parameter_info():
                if isinstance(p.default, (int, float)) and not isinstance(p.default, bool):
                    assert p.unit or p.name in dimensionless, (kind, name, p.name)


def test_plugin_component_raising_during_run_is_reported_by_name_and_the_rest_keep_working():
    class Broken(HalfDetector):
        name = "broken"

        def detect(self, imu):
            raise ZeroDivisionError("oops")

    def footnav_register_detectors(register):
        register(Broken)

    reg = build_registry([_plugin(footnav_register_detectors=footnav_register_detectors)], autoload=False)
    reset_registry(reg)
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(PluginError, match="detector 'broken' from <direct> failed: ZeroDivisionError: oops") as err:
        footnav.make_pipeline("broken").run(rec)
    assert isinstance(err.value.__cause__, ZeroDivisionError)
    assert footnav.make_pipeline("threshold").run(rec).left.path_length_m > 4.0  # the rest work
    import pathlib
    import tempfile

    # the CLI says so in one line, exit code 1 (not the user's fault)
    import footnav.data.io.footnav_csv as fc
    from footnav.cli import EXIT_INTERNAL, main

    tmp = pathlib.Path(tempfile.mkdtemp())
    fc.write_footnav_csv(rec.left, tmp / "l.csv")
    assert (
        main(["run", "--left", str(tmp / "l.csv"), "--detector", "broken", "--out", str(tmp / "out")]) == EXIT_INTERNAL
    )
    assert not (tmp / "out").exists()


def test_builtins_are_registered_by_reference_under_their_own_names():
    """The built-ins are imported on first use (issue 33); each reference names the class whose
    ``name`` it is registered under."""
    from footnav.plugins.builtin import BUILTINS

    reg = build_registry(autoload=False)
    for kind, pairs in BUILTINS.items():
        assert reg.names(kind) == sorted(name for name, _ in pairs)
        for name, ref in pairs:
            cls = reg.get(kind, name).cls
            assert cls.name == name and f"{cls.__module__}:{cls.__qualname__}".endswith(ref.split(":")[1])


def test_the_default_pipeline_imports_only_its_components():
    import json
    import subprocess
    import sys

    code = (
        "import footnav, sys, json; footnav.make_pipeline(); "
        "print(json.dumps(sorted(m for m in sys.modules if m.startswith('footnav.'))))"
    )
    loaded = set(
        json.loads(
            subprocess.run(
                [sys.executable, "-c", code], capture_output=True, text=True, check=True
            ).stdout.splitlines()[-1]
        )
    )
    assert {"footnav.detectors.adaptive", "footnav.estimators.ekf", "footnav.fusion.independent"} <= loaded
    assert not loaded & {
        "footnav.detectors.hmm",
        "footnav.detectors.glrt",
        "footnav.estimators.madgwick",
        "footnav.fusion.dtw",
        "footnav.fusion.particle",
        "footnav.fusion.step_vector",
    }


def test_a_reference_without_a_name_or_to_a_wrong_class_is_a_plugin_error():
    reg = build_registry(builtins=False, autoload=False)
    with pytest.raises(PluginError, match="by reference"):
        reg.add("detector", "footnav.detectors.glrt:GlrtDetector", name=None, plugin="p", origin="o")
    entry = reg.add("detector", "footnav.fusion.dtw:DtwFusion", name="not-a-detector", plugin="p", origin="o")
    with pytest.raises(PluginError, match="must be a subclass of footnav.StanceDetector"):
        entry.cls  # noqa: B018
