"""The dominant-directions heading aid (footnav.nav.dominant_directions, Borenstein et al. 2009,
Jimenez et al. 2012): a known heading drift put on the simulator's truth is taken off again; a
walk without a dominant direction is left as it is; the pipeline stage and its refusals."""

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.errors import CompositionError, InvalidParameterError
from footnav.core.types import FootTrajectory, StanceResult
from footnav.nav.dominant_directions import dominant_direction_correction
from footnav.nav.heading import turn_by


def _truth_trajectory(rec, foot="left"):
    truth = getattr(rec, f"truth_{foot}")
    steps = StanceResult(truth.stance).intervals
    return FootTrajectory(
        t=truth.t,
        position=truth.position - truth.position[0],
        velocity=truth.velocity,
        quaternion=truth.quaternion,
        position_std=np.zeros_like(truth.position),
        steps=steps,
    )


def test_a_linear_heading_drift_on_a_rectangle_is_taken_off():
    rec = footnav.simulate("rectangle", seed=0, width_m=40.0, height_m=20.0, noise=False)
    truth = _truth_trajectory(rec)
    rate = np.radians(3.0) / 60.0  # 3 degrees a minute: far more than a consumer gyro's bias
    drifted = turn_by(truth, -rate * (truth.t - truth.t[0]))  # turn_by turns by minus its argument
    assert np.hypot(*(drifted.position[-1, :2] - truth.position[-1, :2])) > 0.5
    found = dominant_direction_correction(drifted)
    assert found.applied and found.strength > 0.9 and len(found.stretches) >= 4
    fixed = turn_by(drifted, found.at(drifted.t))
    # the correction is relative to the first stretch, which carries its own drift: compare
    # after the best rotation about the start
    err_before = _rotated_rmse(drifted.position, truth.position)
    err_after = _rotated_rmse(fixed.position, truth.position)
    assert err_after < err_before / 5, (err_before, err_after)
    # the error found follows the drift put on: a stretch's is the drift at its middle (the
    # direction of its first to its last footprint), so from the first stretch to the last
    mids = found.knots_s.reshape(-1, 2).mean(axis=1)
    assert np.degrees(found.knots_rad[-1]) == pytest.approx(np.degrees(rate * (mids[-1] - mids[0])), abs=0.3)


def _rotated_rmse(est, ref):
    from footnav.analysis.metrics import ate_rmse

    return ate_rmse(est, ref, dims=2)


def test_a_circle_has_no_dominant_direction_and_is_left_alone():
    rec = footnav.simulate("path", seed=0, segments=[(2.0, 30.0)] * 12, noise=False)
    truth = _truth_trajectory(rec)
    found = dominant_direction_correction(truth)
    assert not found.applied and found.reason
    assert np.array_equal(found.at(truth.t), np.zeros(len(truth.t)))
    meta = found.as_meta()
    assert meta["applied"] is False and meta["correction_end_deg"] == 0.0


def test_turn_by_turns_increments_velocity_and_attitude_and_keeps_the_start():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0, noise=False)
    truth = _truth_trajectory(rec)
    turned = turn_by(truth, np.full(len(truth.t), np.pi / 2))  # -90 deg: +x becomes -y
    assert np.allclose(turned.position[0], truth.position[0])
    assert np.allclose(
        turned.position[:, 0], truth.position[:, 1] - truth.position[0, 1] + turned.position[0, 0], atol=1e-9
    )
    assert np.allclose(
        turned.position[:, 1], -(truth.position[:, 0] - truth.position[0, 0]) + turned.position[0, 1], atol=1e-9
    )
    assert np.allclose(turned.velocity[:, 1], -truth.velocity[:, 0], atol=1e-12)
    assert np.allclose(turned.position[:, 2], truth.position[:, 2])

    def yaw(q):
        return np.arctan2(2 * (q[:, 0] * q[:, 3] + q[:, 1] * q[:, 2]), 1 - 2 * (q[:, 2] ** 2 + q[:, 3] ** 2))

    assert np.allclose(np.angle(np.exp(1j * (yaw(turned.quaternion) - yaw(truth.quaternion)))), -np.pi / 2, atol=1e-9)


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_the_pipeline_stage_records_what_it_did_and_is_refused_online():
    rec = footnav.simulate("rectangle", seed=2, width_m=60.0, height_m=30.0, gyr_bias_walk_radps2_sqrthz=1e-4)
    plain = footnav.make_pipeline()
    aided = footnav.make_pipeline(heading_aid="dominant-directions")
    assert "heading_aid" not in plain.config() and aided.config()["heading_aid"]["name"] == "dominant-directions"
    a, b = footnav.evaluate(plain, rec), footnav.evaluate(aided, rec)
    for foot in ("left", "right"):
        assert b.value("ate_2d", foot) < a.value("ate_2d", foot)
    res = aided.run(rec.left, rec.right)
    meta = res.left.meta["heading_aid"]
    assert meta["name"] == "dominant-directions" and meta["applied"] and meta["strength"] > 0.9
    assert aided.heading_aid.online is False
    with pytest.raises(CompositionError, match="heading aid 'dominant-directions' is offline only"):
        footnav.make_pipeline(
            "threshold", estimator_params={"smoother": "step"}, heading_aid="dominant-directions"
        ).online(feet=1)
    with pytest.raises(InvalidParameterError, match="n_directions"):
        footnav.make_pipeline(heading_aid="dominant-directions", heading_aid_params={"n_directions": 0}).run(rec.left)
    none = footnav.make_pipeline(heading_aid="none").run(rec.left)
    assert np.array_equal(none.left.position, plain.run(rec.left).left.position)


def test_gaitdriven_hallway_walks_footprints_closer_with_the_aid(shared_data):
    """Dev figures (docs/heading.md): footprint RMSE median over the 8 gait-driven walks."""
    from footnav.data.datasets import dataset_names, load_dataset

    names = [n for n in dataset_names(shared_data) if n.startswith("gaitdriven_")]
    if not names:
        pytest.skip("no gait-driven walks in the shared data")
    rmse = {None: [], "dominant-directions": []}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in names:
            rec = load_dataset(name, shared_data)
            for aid, values in rmse.items():
                values.append(
                    footnav.evaluate(footnav.make_pipeline(heading_aid=aid), rec).value("footprint_rmse", "left")
                )
    before, after = np.median(rmse[None]), np.median(rmse["dominant-directions"])
    assert after < 0.85 * before, (before, after)
    assert max(rmse["dominant-directions"]) <= max(rmse[None]) + 1e-9
