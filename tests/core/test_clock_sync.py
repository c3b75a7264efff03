"""Clock synchronisation (seed 002 Sec. 5B) against hand-computed exchanges and the simulator's clocks."""

import numpy as np
import pytest

import footnav
from footnav import InvalidInputError
from footnav.core.clock_sync import align_from_data, apply_clock, fit_clock


def test_symmetric_constant_delays_give_the_exact_map():
    a, b, d = 1.0001, -0.5, 0.03
    ti = np.array([10.0, 11.0, 12.0, 610.0, 611.0, 612.0])  # IMU clock, start and end of a walk
    t_master = a * ti + b  # when the IMU stamped, on the master's clock
    tm1, tm2 = t_master - d, t_master + d
    m = fit_clock(tm1, ti, tm2)
    assert m.a == pytest.approx(a, abs=1e-12) and m.b == pytest.approx(b, abs=1e-9)
    assert m.a_bounds[0] < a < m.a_bounds[1] and m.b_bounds[0] < b < m.b_bounds[1]
    # feasible a: the two ends can each slide by +-d over 600 s
    assert m.a_bounds[1] - m.a_bounds[0] == pytest.approx(4 * d / 600.0 * a, rel=0.02)
    assert m(100.0) == pytest.approx(a * 100 + b)
    assert fit_clock(tm1, ti, tm2, delay_s=0.03)(100.0) == pytest.approx(a * 100 + b - 0.03)
    assert m.drift_ppm == pytest.approx(100.0, rel=1e-6)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_simulated_offset_and_drift_recovered_within_a_millisecond_over_ten_minutes(seed):
    rec = footnav.simulate("straight", seed=seed, distance_m=760.0, clock_offset_s=0.35, clock_drift_ppm=50.0, clock_exchanges=60)
    assert rec.left.duration_s > 600
    truth, ex = rec.meta["clock"], rec.meta["clock_exchanges"]
    m = fit_clock(ex["tm1"], ex["ti"], ex["tm2"])
    t_imu = rec.right.t
    error = m(t_imu) - (truth["a"] * t_imu + truth["b"])
    # measured 0.27-0.97 ms over 6 seeds with 60 exchanges (20 exchanges: 0.4-2.4 ms)
    assert np.abs(error).max() < 1e-3
    synced = apply_clock(rec.right, m)
    np.testing.assert_allclose(synced.t, rec.left.t, atol=1e-3)  # back on true time
    assert synced.meta["clock"]["method"] == "exchanges"


@pytest.mark.parametrize("offset", [0.35, 7.3, -20.0])
def test_data_fallback_aligns_to_half_a_stride(offset):
    rec = footnav.simulate("straight", seed=0, distance_m=300.0, clock_offset_s=offset, clock_drift_ppm=50.0)
    truth = rec.meta["clock"]
    for drift in (False, True):
        m = align_from_data(rec.left, rec.right, drift=drift)
        error = m(rec.right.t) - (truth["a"] * rec.right.t + truth["b"])
        # measured 0.53-0.56 s: the half stride by which one foot starts before the other
        assert np.abs(error).max() < 0.6
        assert m.method == "data"


def test_synchronised_feet_can_be_fused():
    rec = footnav.simulate("straight", seed=1, distance_m=30.0, clock_offset_s=120.0, clock_exchanges=10)
    with pytest.raises(InvalidInputError, match="one clock"):
        footnav.make_pipeline("dual-gait").run(rec.left, rec.right)
    ex = rec.meta["clock_exchanges"]
    right = apply_clock(rec.right, fit_clock(ex["tm1"], ex["ti"], ex["tm2"]))
    res = footnav.make_pipeline("dual-gait", "ekf", "step-vector").run(rec.left, right)
    assert np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]) < 0.5


@pytest.mark.parametrize(
    "tm1, ti, tm2, match, field, index",
    [
        ([0.0], [1.0], [0.1], "at least 2", "ti", None),
        ([0.0, 1.0], [1.0, 2.0, 3.0], [0.1, 1.1], "differ in length", "ti", None),
        ([0.0, np.nan], [1.0, 2.0], [0.1, 1.1], "not finite", "tm1", 1),
        ([0.0, 1.0], [1.0, 2.0], [0.1, 0.9], "before its request", "tm2", 1),
        ([0.0, 1.0, 2.0], [1.0, 2.0, 2.5], [0.1, 1.1, 2.1], "no affine", "ti", None),
    ],
)
def test_bad_exchanges_are_named(tm1, ti, tm2, match, field, index):
    with pytest.raises(InvalidInputError, match=match) as err:
        fit_clock(tm1, ti, tm2)
    assert err.value.field == field and err.value.index == index


def test_simulator_clock_options_change_nothing_else():
    plain = footnav.simulate("straight", seed=4, distance_m=10.0)
    clocked = footnav.simulate("straight", seed=4, distance_m=10.0, clock_offset_s=3.0, clock_drift_ppm=-80.0, clock_exchanges=8)
    np.testing.assert_array_equal(plain.left.t, clocked.left.t)
    np.testing.assert_array_equal(plain.right.acc, clocked.right.acc)  # same noise streams
    np.testing.assert_allclose(clocked.right.t, (1 - 80e-6) * plain.right.t + 3.0, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(clocked.truth_right.t, plain.truth_right.t)  # truth on true time
    assert len(clocked.meta["clock_exchanges"]["ti"]) == 8
    with pytest.raises(footnav.InvalidParameterError, match="clock_exchanges"):
        footnav.simulate("straight", distance_m=5.0, clock_exchanges=1)
