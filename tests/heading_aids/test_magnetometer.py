"""The magnetometer heading aid, against the simulator's truth and hand-made fields."""

import warnings

import numpy as np
import pytest

import footnav
from footnav.analysis import metrics
from footnav.core.errors import CompositionError, DataQualityWarning
from footnav.nav import quaternion as quat
from footnav.nav.magnetic_heading import hard_iron_offset, magnetic_heading_correction

#: Four laps of a 60 x 30 m block (5 minutes) with a consumer gyro that drifts (bias walk 1e-4).
BLOCK = {"segments": [(60.0, 90.0), (30.0, 90.0)] * 4, "gyr_bias_walk_radps2_sqrthz": 1e-4, "magnetometer": True}
#: A steel zone on the second side: 15 uT mostly horizontal, within 6 m.
ZONE = (60.0, 15.0, 6.0, 15.0, -10.0, 5.0)


@pytest.fixture(scope="module")
def block():
    return footnav.simulate("path", seed=1, mag_hard_iron_ut=5.0, mag_disturbances=[ZONE], **BLOCK)


@pytest.fixture(scope="module")
def runs(block):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        return {aid: footnav.make_pipeline(heading_aid=aid).run(block) for aid in ("none", "magnetometer")}


def _ate(result, rec):
    return [
        metrics.ate_rmse(tr.position, truth.position, dims=2)
        for tr, truth in ((result.left, rec.truth_left), (result.right, rec.truth_right))
    ]


def test_heading_drift_is_removed_despite_hard_iron_and_a_steel_zone(block, runs):
    before, after = _ate(runs["none"], block), _ate(runs["magnetometer"], block)
    assert max(after) < 0.5  # measured 0.32 / 0.25 m, from 5.83 / 1.14 m
    assert after[0] < 0.2 * before[0]
    # the path turns with the feet
    assert metrics.ate_rmse(runs["magnetometer"].path.position, block.truth_left.position, dims=2) < 0.5


def test_the_hard_iron_found_is_the_simulated_one(block, runs):
    found = np.array(runs["magnetometer"].left.meta["heading_aid"]["hard_iron"])
    # within 0.5 uT (1 % of the field, under a degree of heading): a foot pitches but hardly
    # rolls, so the sensor's vertical is the least covered axis (measured 0.30 uT off there)
    np.testing.assert_allclose(found, block.truth_left.meta["magnetometer"]["hard_iron_ut"], atol=0.5)


def test_the_stances_left_out_are_those_in_the_steel_zone(block, runs):
    meta = runs["magnetometer"].left.meta["heading_aid"]
    truth = block.truth_left.position
    steps = runs["magnetometer"].left.steps
    mid = truth[(steps[:, 0] + steps[:, 1] - 1) // 2]
    inside = int((np.hypot(mid[:, 0] - ZONE[0], mid[:, 1] - ZONE[1]) <= ZONE[2]).sum())
    rejected = meta["rejected_magnitude"] + meta["rejected_dip"]
    assert inside > 5
    assert abs(rejected - inside) <= 2  # a stance on the zone's edge may go either way
    assert meta["accepted"] + rejected == meta["stances"] == len(steps)


def test_sphere_fit_recovers_an_offset_and_refuses_without_coverage():
    rng = np.random.default_rng(4)
    field = np.array([20.0, 5.0, -40.0])
    offset = np.array([3.0, -7.0, 2.0])
    q = quat.normalize(rng.normal(size=(2000, 4)))  # attitudes all round
    readings = np.einsum("nji,j->ni", quat.as_matrix(q), field) + offset + rng.normal(0, 0.3, (2000, 3))
    found, why = hard_iron_offset(readings)
    assert why == ""
    np.testing.assert_allclose(found, offset, atol=0.1)
    # a sensor that only ever yawed a little: the readings lie on a small cap of the sphere
    yaw = rng.uniform(-0.2, 0.2, 2000)
    q_cap = np.column_stack([np.cos(yaw / 2), 0 * yaw, 0 * yaw, np.sin(yaw / 2)])
    cap = np.einsum("nji,j->ni", quat.as_matrix(q_cap), field) + offset
    found, why = hard_iron_offset(cap)
    assert found is None and "cover too little" in why


def test_a_disturbed_field_leaves_the_walk_as_it_is_and_says_so():
    # steel all along: every 6 m the field along the walk changes by 5 uT (10 % of it)
    zones = [(x, 0.0, 3.0, 5.0 * i - 25.0, 0.0, 0.0) for i, x in enumerate(range(0, 61, 6))]
    rec = footnav.simulate("straight", seed=2, distance_m=60.0, magnetometer=True, mag_disturbances=zones)
    plain = footnav.make_pipeline().run(rec)
    with pytest.warns(DataQualityWarning, match="'magnetometer' not applied: .* passed the field's gates"):
        aided = footnav.make_pipeline(heading_aid="magnetometer").run(rec)
    meta = aided.left.meta["heading_aid"]
    assert not meta["applied"] and meta["rejected_magnitude"] > 0
    np.testing.assert_array_equal(aided.left.position, plain.left.position)
    assert any("'magnetometer' not applied" in str(w) for w in aided.meta["warnings"])


def test_no_magnetometer_is_refused_before_any_work():
    rec = footnav.simulate("straight", seed=2, distance_m=6.0)
    with pytest.raises(CompositionError, match="'magnetometer' needs a magnetometer"):
        footnav.make_pipeline(heading_aid="magnetometer").run(rec)
    traj = footnav.make_pipeline().run(rec).left
    assert magnetic_heading_correction(traj, rec.left).reason == "the recording has no magnetometer"


def test_magnetometer_signals_leave_the_others_unchanged():
    a = footnav.simulate("straight", seed=5, distance_m=6.0)
    b = footnav.simulate("straight", seed=5, distance_m=6.0, magnetometer=True, clock_offset_s=0.5)
    c = footnav.simulate("straight", seed=5, distance_m=6.0, clock_offset_s=0.5)
    np.testing.assert_array_equal(a.left.gyr, b.left.gyr)
    np.testing.assert_array_equal(c.right.acc, b.right.acc)
    assert a.left.mag is None and b.right.mag is not None
    # at rest, level, heading 0: the reading is the nav field (hard iron and noise aside)
    noise_free = footnav.simulate("straight", seed=5, distance_m=6.0, magnetometer=True, noise=False)
    np.testing.assert_allclose(
        noise_free.left.mag[0], noise_free.truth_left.meta["magnetometer"]["field_nav_ut"], atol=1e-9
    )
