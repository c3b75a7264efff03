import time

import numpy as np
import pytest

import footnav
from footnav import CompositionError, InvalidParameterError
from footnav.detectors.threshold import ThresholdDetector


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=0, distance_m=10.0)


def test_names_instances_and_tables_compose_the_same(walk):
    a = footnav.make_pipeline("threshold", "ekf", "independent", detector_params={"window_s": 0.2})
    b = footnav.make_pipeline(ThresholdDetector(window_s=0.2), "ekf")
    c = footnav.make_pipeline({"name": "threshold", "window_s": 0.2})
    assert a.config() == b.config() == c.config()
    ra, rb = a.run(walk.left, walk.right), b.run(walk)
    np.testing.assert_array_equal(ra.left.position, rb.left.position)


def test_instance_with_params_is_refused():
    with pytest.raises(InvalidParameterError, match="constructor"):
        footnav.make_pipeline(ThresholdDetector(), detector_params={"window_s": 0.2})


def test_wrong_kind_is_refused():
    with pytest.raises(CompositionError, match="is a detector; it cannot be used as the estimator"):
        footnav.make_pipeline("threshold", ThresholdDetector())


def test_toml_round_trip(tmp_path):
    pipe = footnav.make_pipeline("threshold", "ekf", estimator_params={"zupt_std_mps": 0.02, "heading": "sensor"})
    path = tmp_path / "p.toml"
    path.write_text(pipe.to_toml())
    again = footnav.load_pipeline(path)
    assert again.config() == pipe.config()
    assert again.estimator.zupt_std_mps == 0.02


def test_toml_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[detector]\nname = 'threshold'\nwindw_s = 1\n")
    with pytest.raises(InvalidParameterError, match="bad.toml.*windw_s"):
        footnav.load_pipeline(bad)
    bad.write_text("[detectr]\nname = 'threshold'\n")
    with pytest.raises(InvalidParameterError, match="detectr"):
        footnav.load_pipeline(bad)
    bad.write_text("[detector\n")
    with pytest.raises(footnav.InvalidInputError, match="not valid TOML"):
        footnav.load_pipeline(bad)
    with pytest.raises(footnav.DataNotFoundError):
        footnav.load_pipeline(tmp_path / "missing.toml")


def test_provenance(walk):
    t0 = time.perf_counter()
    res = footnav.make_pipeline().run(walk.left, walk.right)
    elapsed = time.perf_counter() - t0
    meta = res.meta
    assert meta["footnav_version"] == footnav.__version__
    assert meta["pipeline"]["estimator"]["name"] == "ekf"
    assert meta["input"]["left"]["source"] == "simulator"
    assert isinstance(meta["warnings"], list)
    assert 0 < meta["runtime_s"] <= elapsed  # the run's own time, measured inside the call
    again = footnav.make_pipeline(**meta["pipeline"]).run(walk.left, walk.right)
    np.testing.assert_array_equal(again.left.position, res.left.position)


def test_single_foot_path_is_that_foot(walk):
    res = footnav.make_pipeline().run(walk.left)
    assert res.right is None and res.stance_right is None
    np.testing.assert_array_equal(res.path.position, res.left.position)


def test_midpoint_path_of_two_feet(walk):
    res = footnav.make_pipeline().run(walk.left, walk.right)
    np.testing.assert_allclose(res.path.position, 0.5 * (res.left.position + res.right.position))


def test_the_input_checks_findings_are_recorded_with_the_run():
    import warnings

    rec = footnav.simulate("straight", distance_m=20, rate_hz=100, seed=1)
    imu = rec.left
    slow = footnav.ImuData(imu.t[::10], imu.acc[::10], imu.gyr[::10])  # 10 Hz, built without checks
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = footnav.make_pipeline().run(slow)
    assert any("sampling rate 10 Hz" in w for w in result.meta["warnings"])


@pytest.mark.parametrize("fusion", ["range", "step-vector"])
def test_what_the_fusion_computed_comes_back_with_the_run(walk, fusion, tmp_path):
    pipe = footnav.make_pipeline("threshold", "ekf", fusion)
    res = pipe.run(walk.left, walk.right)
    det = footnav.make_detector("threshold")
    direct = (
        footnav.make_fusion(fusion)
        .fuse(footnav.make_estimator("ekf"), walk.left, det.detect(walk.left), walk.right, det.detect(walk.right))
        .meta
    )
    assert res.meta["fusion"] == direct
    counts = {"range": "checks", "step-vector": "updates"}[fusion]
    assert res.meta["fusion"][counts] > 0  # a 10 m walk has steps to check or update at
    import json

    from footnav.data.results import write_results

    out = write_results(res, tmp_path / "out")
    doc = json.loads((out / "summary.json").read_text())
    assert doc["provenance"]["fusion"][counts] == res.meta["fusion"][counts]
