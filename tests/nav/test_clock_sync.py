"""Clock synchronisation (seed 002 Sec. 5B) against hand-computed exchanges and the simulator's clocks."""

import warnings

import numpy as np
import pytest

import footnav
from footnav import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.core.types import ImuData
from footnav.nav.clock_from_data import align_from_data
from footnav.nav.clock_sync import ClockMap, apply_clock, fit_clock

# -- seed 002's linear programs --------------------------------------------------------------------

# Two exchanges bound the map to a parallelogram: 10 <= b <= 10.2 and 110 <= 100 a + b <= 110.2.
# LP1 (min a): b = 10.2, a = (110 - 10.2) / 100 = 0.998; LP2 (max a): b = 10, a = (110.2 - 10) / 100
# = 1.002; midpoint a = 1, b = 10.1. A third exchange, 60.05 <= 50 a + b <= 60.3, leaves both
# LP solutions feasible but cuts the corner (a, b) = (1, 10) (where 50 a + b = 60) at the points
# (1.001, 10) and (0.999, 10.1).
HAND = {"tm1": [10.0, 110.0, 60.05], "ti": [0.0, 100.0, 50.0], "tm2": [10.2, 110.2, 60.3]}


def test_hand_computed_linear_programs():
    m = fit_clock(HAND["tm1"], HAND["ti"], HAND["tm2"])
    assert m.method == "exchanges" and m.n == 3 and m.delay_s == 0.0
    assert m.a_bounds == pytest.approx((0.998, 1.002), abs=1e-12)
    assert m.b_bounds == pytest.approx((10.0, 10.2), abs=1e-9)
    assert m.a == pytest.approx(1.0, abs=1e-12) and m.b == pytest.approx(10.1, abs=1e-9)
    # residuals a TI + b - (TM1 + TM2) / 2: 10.1 - 10.1, 110.1 - 110.1, 60.1 - 60.175
    np.testing.assert_allclose(m.residuals_s, [0.0, 0.0, -0.075], atol=1e-9)
    expected = {(1.001, 10.0), (1.002, 10.0), (1.0, 10.2), (0.998, 10.2), (0.999, 10.1)}
    got = {(round(a, 9), round(b, 9)) for a, b in m.vertices}
    assert got == expected
    lo, hi = m.interval([0.0, 50.0, 100.0])
    np.testing.assert_allclose(lo, [10.0, 60.05, 110.0], atol=1e-9)
    np.testing.assert_allclose(hi, [10.2, 60.2, 110.2], atol=1e-9)
    # t = a t_imu + b - delay (seed 002's Delta_ble)
    assert m(50.0) == pytest.approx(60.1)
    shifted = fit_clock(HAND["tm1"], HAND["ti"], HAND["tm2"], delay_s=0.03)
    assert shifted(50.0) == pytest.approx(60.07) and shifted.interval(50.0)[0] == pytest.approx(60.02)


def test_symmetric_constant_delays_give_the_exact_map():
    a, b, d = 1.0001, -0.5, 0.03
    ti = np.array([10.0, 11.0, 12.0, 610.0, 611.0, 612.0])  # IMU clock, start and end of a walk
    t_master = a * ti + b  # when the IMU stamped, on the master's clock
    m = fit_clock(t_master - d, ti, t_master + d)
    assert m.a == pytest.approx(a, abs=1e-12) and m.b == pytest.approx(b, abs=1e-9)
    np.testing.assert_allclose(m.residuals_s, 0.0, atol=1e-9)
    # feasible a: each end of the walk can slide by +-d over 600 s
    assert m.a_bounds[1] - m.a_bounds[0] == pytest.approx(4 * d / 600.0, rel=0.01)
    assert m.drift_ppm == pytest.approx((1 / a - 1) * 1e6)  # the IMU clock runs slow: negative


def test_large_clock_epochs_are_well_conditioned():
    ti = np.array([1e6, 1e6 + 1, 1e6 + 600, 1e6 + 601])  # an IMU clock that has run for 11 days
    true = 0.99995 * ti - 999_900.0
    m = fit_clock(true - 0.01, ti, true + 0.01)
    np.testing.assert_allclose(m(ti), true, rtol=0, atol=1e-7)


# -- the simulator's clocks: acceptance ----------------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1, 2, 3, 4])
def test_simulated_offset_and_drift_recovered_within_a_millisecond_over_ten_minutes(seed):
    rec = footnav.simulate(
        "straight", seed=seed, distance_m=760.0, clock_offset_s=0.35, clock_drift_ppm=50.0, clock_exchanges=200
    )
    assert rec.left.duration_s > 600
    truth, ex = rec.meta["clock"], rec.meta["clock_exchanges"]
    m = fit_clock(ex["tm1"], ex["ti"], ex["tm2"])
    t_imu = rec.right.t
    t_true = truth["a"] * t_imu + truth["b"]
    # 200 exchanges (one-way delay 0.02 s + exponential jitter of mean 0.02 s): measured max error
    # 0.20 ms median, 0.68 ms worst over 200 seeds; 60 exchanges exceed 1 ms in 1 walk in 10
    assert np.abs(m(t_imu) - t_true).max() < 1e-3
    assert m.drift_ppm == pytest.approx(50.0, abs=2.0)
    lo, hi = m.interval(t_imu)
    assert (lo <= t_true + 1e-9).all() and (t_true <= hi + 1e-9).all()  # the guaranteed bound holds
    half_round_trip = 0.5 * (np.asarray(ex["tm2"]) - ex["tm1"])
    assert (np.abs(m.residuals_s) <= half_round_trip + 1e-9).all()
    synced = apply_clock(rec.right, m)
    np.testing.assert_allclose(synced.t, rec.left.t, rtol=0, atol=1e-3)  # back on true time
    assert synced.meta["clock"]["method"] == "exchanges" and synced.meta["clock"]["a"] == m.a
    own = (synced.t + m.delay_s - m.b) / m.a  # the map in meta undoes itself
    np.testing.assert_allclose(own, rec.right.t, rtol=0, atol=1e-9)


def test_synchronised_feet_can_be_fused():
    rec = footnav.simulate("straight", seed=1, distance_m=30.0, clock_offset_s=120.0, clock_exchanges=10)
    with pytest.raises(InvalidInputError, match="one clock"):
        footnav.make_pipeline("dual-gait").run(rec.left, rec.right)
    ex = rec.meta["clock_exchanges"]
    right = apply_clock(rec.right, fit_clock(ex["tm1"], ex["ti"], ex["tm2"]))
    res = footnav.make_pipeline("dual-gait", "ekf", "step-vector").run(rec.left, right)
    assert np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]) < 0.5


# -- from the data ---------------------------------------------------------------------------------

# 60.2 m is 86 steps: the right foot makes the first and the last swing, 44 swings to the left's
# 43, so the walk's ends single out the stride. 59.5 m is 85 steps, 43 swings each: ambiguous.
UNIQUE_M, AMBIGUOUS_M = 60.2, 59.5


def _max_error(rec, m):
    t = rec.right.t
    return np.abs(m(t) - (rec.meta["clock"]["a"] * t + rec.meta["clock"]["b"])).max()


@pytest.mark.parametrize("offset", [0.3537, 7.3456, -20.1234, 45.678])
def test_data_fallback_recovers_a_pure_offset(offset):
    rec = footnav.simulate("straight", seed=0, distance_m=UNIQUE_M, clock_offset_s=offset)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        m = align_from_data(rec.left, rec.right)
    # measured < 0.001 ms over 5 seeds x these offsets: the simulated gait is exactly periodic
    # and symmetric; real step-time asymmetry adds its own size (tens of ms) to the error
    assert _max_error(rec, m) < 1e-3
    assert m.method == "data" and m.a == 1.0 and m.alternatives_b == ()
    assert m.stride_s == pytest.approx(1.1, abs=1e-3)
    assert apply_clock(rec.right, m).meta["clock"]["method"] == "data"


@pytest.mark.parametrize(("stride_period_s", "swing_s"), [(0.9, 0.33), (2.0, 0.8)])
def test_data_fallback_at_other_cadences(stride_period_s, swing_s):
    rec = footnav.simulate(
        "straight", seed=3, distance_m=40.7, clock_offset_s=-3.21, stride_period_s=stride_period_s, swing_s=swing_s
    )
    m = align_from_data(rec.left, rec.right)
    assert m.stride_s == pytest.approx(stride_period_s, abs=1e-3)
    assert _max_error(rec, m) < 1e-3  # measured 0.0013 and 0.0006 ms


def test_data_fallback_with_equal_swing_counts_is_ambiguous_by_a_stride():
    rec = footnav.simulate("straight", seed=0, distance_m=AMBIGUOUS_M, clock_offset_s=7.3456)
    b = rec.meta["clock"]["b"]
    with pytest.warns(DataQualityWarning, match="equally many swings"):
        m = align_from_data(rec.left, rec.right)
    candidates = sorted([m.b, *m.alternatives_b])
    assert len(candidates) == 2 and candidates[1] - candidates[0] == pytest.approx(1.1, abs=2e-3)
    assert min(abs(c - b) for c in candidates) < 1e-3  # the truth is one of the two
    # the simulated walk starts with the right foot (rec.meta["first_foot"]): "other" here
    assert rec.meta["first_foot"] == "right"
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        m = align_from_data(rec.left, rec.right, leading_foot="other")
    assert _max_error(rec, m) < 1e-3 and m.alternatives_b == ()
    wrong = align_from_data(rec.left, rec.right, leading_foot="reference")
    assert abs(_max_error(rec, wrong) - 1.1) < 2e-3


def test_data_fallback_says_when_the_data_contradict_the_leading_foot():
    rec = footnav.simulate("straight", seed=0, distance_m=UNIQUE_M, clock_offset_s=2.0)
    with pytest.warns(DataQualityWarning, match="kept the data's offset"):
        m = align_from_data(rec.left, rec.right, leading_foot="reference")
    assert _max_error(rec, m) < 1e-3


def test_envelope_alone_is_only_good_to_half_a_stride():
    """Why the fallback does more than correlate envelopes: one foot starts or stops half a
    stride before the other, so the envelopes' correlation is off by up to half a stride
    (measured 0.41 s here, 0.54 s on 300 m walks, 0 on this 60.2 m walk)."""
    rec = footnav.simulate("straight", seed=0, distance_m=AMBIGUOUS_M, clock_offset_s=7.3456)
    from footnav.nav.clock_from_data import _Correlation, _energy

    g_ref = np.arange(rec.left.t[0], rec.left.t[-1], 0.01)
    g_oth = np.arange(rec.right.t[0], rec.right.t[-1], 0.01)
    xc = _Correlation(_energy(rec.left, g_ref, 3.0), _energy(rec.right, g_oth, 3.0), 0.01, g_ref[0] - g_oth[0])
    error = abs(xc.peak(-60, 60) - rec.meta["clock"]["b"])
    assert 0.3 < error < 0.6


def test_data_fallback_on_recordings_cut_mid_walk_leaves_the_stride_open():
    rec = footnav.simulate("straight", seed=0, distance_m=UNIQUE_M, clock_offset_s=7.3456)

    def crop(imu, start, stop):
        return ImuData(t=imu.t[start:stop], acc=imu.acc[start:stop], gyr=imu.gyr[start:stop], meta=imu.meta)

    assert rec.left.duration_s > 50.0  # walking from 2 s to about 50 s
    with pytest.warns(DataQualityWarning, match="starts mid-walk and one ends mid-walk"):
        m = align_from_data(crop(rec.left, 1000, 4000), crop(rec.right, 1500, 3500))
    b = rec.meta["clock"]["b"]
    assert len(m.alternatives_b) == 2 and np.ptp([m.b, *m.alternatives_b]) == pytest.approx(2.2, abs=4e-3)
    # modulo a stride it is exact; here the envelope picked a candidate 4 strides off
    strides = (m.b - b) / m.stride_s
    assert abs(strides - round(strides)) * m.stride_s < 1e-3
    # only the end is cut: the start alone leaves two, and the leading foot settles it
    with pytest.warns(DataQualityWarning, match="ends mid-walk"):
        m = align_from_data(rec.left, crop(rec.right, 0, 3500))
    assert len(m.alternatives_b) == 1
    m = align_from_data(rec.left, crop(rec.right, 0, 3500), leading_foot="other")
    assert _max_error(rec, m) < 1e-3 and m.alternatives_b == ()


def test_data_fallback_recovers_drift_over_ten_minutes():
    rec = footnav.simulate("straight", seed=0, distance_m=760.0, clock_offset_s=0.35, clock_drift_ppm=50.0)
    m = align_from_data(rec.left, rec.right, drift=True, leading_foot="other")
    # measured 0.09 ms and -0.29 ppm over 5 seeds (without drift=True: 6 ms, the drift itself)
    assert _max_error(rec, m) < 1e-3
    assert m.drift_ppm == pytest.approx(50.0, abs=2.0) and m.n == 2


def test_data_fallback_on_a_walk_with_turns():
    rec = footnav.simulate("rectangle", seed=0, width_m=30.0, height_m=20.0, clock_offset_s=12.345)
    m = align_from_data(rec.left, rec.right, leading_foot="other")
    assert _max_error(rec, m) < 1e-3  # measured 0.0001 ms


# -- bad input -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "tm1, ti, tm2, match, field, index",
    [
        ([0.0], [1.0], [0.1], "at least 2", "ti", None),
        ([0.0, 1.0], [1.0, 2.0, 3.0], [0.1, 1.1], "has 3 exchanges", "ti", None),
        ([0.0, 1.0], [1.0, 2.0], [0.1], "has 1 exchanges", "tm2", None),
        ([0.0, np.nan], [1.0, 2.0], [0.1, 1.1], "not finite", "tm1", 1),
        ([0.0, 1.0], [1.0, np.inf], [0.1, 1.1], "not finite", "ti", 1),
        ([0.0, 1.0, 2.0], [1.0, 2.0, 3.0], [0.1, 1.1, 1.9], "before its request", "tm2", 2),
        ([[0.0, 1.0]], [1.0, 2.0], [0.1, 1.1], "1-D", "tm1", None),
        (["a", "b"], [1.0, 2.0], [0.1, 1.1], "sequence of times", "tm1", None),
        ([0.0, 1.0], [5.0, 5.0], [0.1, 1.1], "one IMU time", "ti", None),
        ([0.0, 1.0], [2.0, 1.0], [0.1, 1.1], "do not increase", "ti", None),
        # the hand case with the middle exchange moved above the parallelogram: exchange 2
        ([10.0, 110.0, 60.25], [0.0, 100.0, 50.0], [10.2, 110.2, 60.3], "exchange 2", "ti", 2),
        # ... and put first: exchanges 0 and 1 fit each other, exchange 2 contradicts them
        ([60.25, 10.0, 110.0], [50.0, 0.0, 100.0], [60.3, 10.2, 110.2], "exchange 2", "ti", 2),
    ],
)
def test_bad_exchanges_are_named(tm1, ti, tm2, match, field, index):
    with pytest.raises(InvalidInputError, match=match) as err:
        fit_clock(tm1, ti, tm2)
    assert err.value.field == field and err.value.index == index


def test_bad_parameters_are_named():
    with pytest.raises(InvalidParameterError, match="delay_s"):
        fit_clock(HAND["tm1"], HAND["ti"], HAND["tm2"], delay_s=float("nan"))
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    for kwargs, name in (
        ({"rate_hz": 0.0}, "rate_hz"),
        ({"smooth_s": -1.0}, "smooth_s"),
        ({"max_offset_s": float("inf")}, "max_offset_s"),
        ({"leading_foot": "left"}, "leading_foot"),
    ):
        with pytest.raises(InvalidParameterError, match=name):
            align_from_data(rec.left, rec.right, **kwargs)
    with pytest.raises(InvalidInputError, match="feasible interval"):
        ClockMap(a=1.0, b=0.0, method="data").interval(0.0)


def test_recordings_that_do_not_overlap_are_refused():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0, clock_offset_s=500.0)
    with pytest.raises(InvalidInputError, match="overlap"):
        align_from_data(rec.left, rec.right, max_offset_s=60.0)
