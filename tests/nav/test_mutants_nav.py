"""Tests that kill the mutants of ``tools/mutate.py`` the rest of the suite let through (issue 17, item 6).

Every expected value here is worked out by hand or from a closed-form motion, never read from
footnav's own output. The comment above each test names the mutant it was written for.
"""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.types import ImuData, StanceResult
from footnav.nav import quaternion as quat
from footnav.nav.mechanization import strapdown

G = 9.80665  # m/s^2, written out: not read from the library


# quat-as-rotvec-limit: below |q_vec| = 1e-12 the rotation vector is 2 q_vec (angle -> 2 sin(angle / 2))
def test_as_rotvec_of_a_tiny_rotation_is_twice_the_vector_part():
    q = np.array([1.0, 1e-14, -2e-14, 3e-14])
    np.testing.assert_allclose(quat.as_rotvec(q), [2e-14, -4e-14, 6e-14], rtol=1e-12)


# quat-from-yaw-sign: a turn of +90 deg about z is [cos 45, 0, 0, sin 45] and takes x to y
def test_from_yaw_is_a_positive_turn_about_z():
    h = np.sqrt(0.5)
    np.testing.assert_allclose(quat.from_yaw(np.pi / 2), [h, 0.0, 0.0, h], atol=1e-15)
    np.testing.assert_allclose(quat.rotate(quat.from_yaw(np.pi / 2), [1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-15)


# quat-conjugate-index: the conjugate negates all three vector components
def test_conjugate_negates_the_whole_vector_part():
    np.testing.assert_array_equal(quat.conjugate([0.5, 0.1, -0.2, 0.3]), [0.5, -0.1, 0.2, -0.3])


def _imu(t, acc, gyr):
    return ImuData(t=t, acc=acc, gyr=gyr)


# mech-bias-sign: a still sensor that reads only its gyro bias keeps its attitude once the bias
# is subtracted
def test_strapdown_subtracts_the_gyro_bias():
    n, rate = 201, 100.0
    t = np.arange(n) / rate
    bias = np.array([0.01, -0.02, 0.03])
    acc = np.tile([0.0, 0.0, G], (n, 1))
    q, v, p = strapdown(_imu(t, acc, np.tile(bias, (n, 1))), np.array([1.0, 0, 0, 0]), gyro_bias_radps=bias)
    np.testing.assert_allclose(q[-1], [1.0, 0, 0, 0], atol=1e-12)
    np.testing.assert_allclose(p[-1], 0.0, atol=1e-12)


# mech-loop-swapped-samples: without rotation, a force growing linearly in time (jerk j along x)
# gives v = j t^2 / 2 exactly under the trapezoidal / Simpson rule, p = j t^3 / 6 to O(dt^2)
def test_strapdown_integrates_a_linear_force_exactly():
    n, rate, jerk = 201, 100.0, 1.5
    t = np.arange(n) / rate
    acc = np.zeros((n, 3))
    acc[:, 0] = jerk * t
    acc[:, 2] = G
    q, v, p = strapdown(_imu(t, acc, np.zeros((n, 3))), np.array([1.0, 0, 0, 0]))
    np.testing.assert_allclose(v[:, 0], jerk * t**2 / 2, atol=1e-9)
    np.testing.assert_allclose(v[:, 1:], 0.0, atol=1e-9)
    # trapezoid on v = j t^2 / 2: error j T dt^2 / 12 = 2.5e-5 m at T = 2 s
    np.testing.assert_allclose(p[:, 0], jerk * t**3 / 6, atol=3e-5)


# win-length-round: the window is the odd number of samples nearest window_s * rate_hz, ties upward
@pytest.mark.parametrize(
    ("window_s", "rate_hz", "expected"),
    [
        (0.079, 100.0, 7),
        (0.08, 100.0, 9),
        (0.069, 100.0, 7),
        (0.04, 1 / 0.01, 5),
        (0.05, 200.0, 11),
        (0.059, 200.0, 11),
    ],
)
def test_window_is_the_nearest_odd_sample_count(window_s, rate_hz, expected):
    from footnav.nav.windows import window_samples

    assert window_samples(window_s, rate_hz, 10_000) == expected


# align-start-boundary: a first stance that starts at sample 1 is a recording that does not start
# at standstill: warned, and the estimate starts there
def test_first_stance_at_sample_one_is_reported():
    from footnav.core.errors import DataQualityWarning
    from footnav.nav.initial_alignment import align_first_stance

    n = 300
    imu = _imu(np.arange(n) / 100.0, np.tile([0.0, 0.0, G], (n, 1)), np.zeros((n, 3)))
    mask = np.zeros(n, bool)
    mask[1:100] = True
    mask[200:] = True
    with pytest.warns(DataQualityWarning, match="index 1"):
        s0, align, meta = align_first_stance(imu, StanceResult(mask), still_gyr_max_radps=0.05)
    assert s0 == 1 and meta["estimate_start_index"] == 1
    assert meta["alignment_samples"] == [1, 100, 99]


# drift-lever-sign: a yaw-rate error b rad/s turns the walked path: dp = dpsi J v dt with
# J v = [-v_y, v_x]. Walking at 1 m/s along the diagonal (1, 1)/sqrt(2), dpsi = b t, so at T the
# position error is b T^2 / 2 along (-1, 1)/sqrt(2): var_xx = var_yy = -cov_xy = (s T^2 / 2)^2 / 2
def test_heading_drift_covariance_of_a_diagonal_walk():
    from footnav.nav.heading_drift import heading_drift_cov

    t = np.arange(1001) / 100.0
    vel = np.tile([np.sqrt(0.5), np.sqrt(0.5), 0.0], (len(t), 1))
    std = 0.01
    cov = heading_drift_cov(t, vel, 0, std, 0.0)
    expected = (std * 10.0**2 / 2) ** 2 / 2  # 0.125 m^2
    np.testing.assert_allclose(cov[-1], [expected, -expected, expected], rtol=0.01)


def _gait(rate_hz, swing_centres_s, duration_s, *, acc_swing=True, extra=()):
    """Gyro y bumps 9 sin^2 over 0.4 s centred at ``swing_centres_s`` (and (centre, height, width)
    bumps ``extra``), the foot lifted and lowered (8 sin(2 pi u) m/s^2) during each main bump."""
    t = np.arange(int(duration_s * rate_hz)) / rate_hz
    gyr = np.zeros((len(t), 3))
    acc = np.tile([0.0, 0.0, G], (len(t), 1))
    bumps = [(c, 9.0, 0.4) for c in swing_centres_s] + list(extra)
    for c, height, width in bumps:
        u = (t - (c - width / 2)) / width
        inside = (u >= 0) & (u <= 1)
        gyr[inside, 1] += height * np.sin(np.pi * u[inside]) ** 2
        if acc_swing and height == 9.0:
            acc[inside, 2] += 8.0 * np.sin(2 * np.pi * u[inside])
    return _imu(t, acc, gyr)


# check-over-swing-unfiltered: gyro peaks without the swing's acceleration (turning on the spot)
# are not swings, so a stance there is not reported as a stance in a swing
def test_turning_without_swinging_is_no_stance_in_a_swing():
    from footnav.nav.stance_check import check_stances

    imu = _gait(100.0, [1.0, 2.0, 3.0, 4.0, 5.0], 6.0, acc_swing=False)
    check = check_stances(imu, StanceResult(np.ones(imu.n_samples, bool)))
    assert len(check.over_swing_s) == 0 and check.n_cycles == 0


# check-missed-time: a gait cycle without stance is reported at the midpoint of its two swing peaks
def test_missed_stances_are_reported_between_the_swing_peaks():
    from footnav.nav.stance_check import check_stances

    imu = _gait(100.0, [1.0, 2.0, 3.0, 4.0, 5.0], 6.0)
    check = check_stances(imu, StanceResult(np.zeros(imu.n_samples, bool)))
    np.testing.assert_allclose(check.missed_s, [1.5, 2.5, 3.5, 4.5], atol=0.011)


# check-suspicious-boundary: "at least max(2, 5 %) of the gait cycles"
def test_two_bad_cycles_of_ten_are_suspicious_and_one_is_not():
    from footnav.nav.stance_check import StanceCheck

    def check(missed):
        return StanceCheck(
            n_cycles=10, n_stances=10, missed_s=np.array(missed), over_swing_s=np.array([]), stride_s=1.0
        )

    assert check([1.5, 2.5]).suspicious
    assert not check([1.5]).suspicious


# gait-stride-mean, gait-no-max-stride: the stride time is the median of the peak intervals
# shorter than max_stride_s (a pause is not a stride)
def test_stride_time_is_the_median_of_intervals_without_pauses():
    from footnav.nav.gait_cycles import swing_peaks

    centres = [1.0, 2.0, 3.0, 4.0, 5.3, 9.3, 13.3]  # intervals 1, 1, 1, 1.3, then two 4 s pauses
    peaks = swing_peaks(_gait(100.0, centres, 14.5).gyr, 100.0)
    np.testing.assert_allclose(peaks.index / 100.0, centres, atol=0.011)
    assert peaks.stride_s == pytest.approx(1.0, abs=0.011)


# gait-distance-min: once the stride time is known, peaks closer than stride_fraction of it are
# one swing (the larger kept); a second bump 0.4 s after a swing in one of six strides is dropped
def test_a_second_bump_within_a_stride_is_not_a_swing():
    from footnav.nav.gait_cycles import swing_peaks

    centres = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    imu = _gait(100.0, centres, 7.0, extra=[(3.4, 6.0, 0.2)])
    peaks = swing_peaks(imu.gyr, 100.0)
    np.testing.assert_allclose(peaks.index / 100.0, centres, atol=0.011)


# strides-dt-prepend: sample k's share of the time is t[k+1] - t[k]; with uneven sampling the swing
# of samples 2 and 3 lasts from t[2] to t[4] (the first stance sample after it)
def test_swing_time_with_uneven_sampling():
    from footnav.core.types import FootTrajectory
    from footnav.nav.strides import stride_parameters

    t = np.array([0.0, 0.1, 0.3, 0.6, 1.0, 1.5])
    n = len(t)
    traj = FootTrajectory(
        t=t,
        position=np.zeros((n, 3)),
        velocity=np.zeros((n, 3)),
        quaternion=np.tile([1.0, 0, 0, 0], (n, 1)),
        position_std=np.zeros((n, 3)),
        steps=np.empty((0, 2)),
    )
    mask = np.array([True, True, False, False, True, True])
    out = stride_parameters(traj, mask, mid_stance=[0, 5])
    assert out["swing_s"][0] == pytest.approx(0.7)
    assert out["stance_s"][0] == pytest.approx(0.8)


# metrics-rmse-mean: ATE is a root mean square. Errors 1, 1, 0, 0 m after the best fit (identity:
# the cross-covariance is diag(4, 8)) give sqrt(1/2), not their mean 1/2
def test_ate_is_a_root_mean_square():
    from footnav.analysis.metrics import ate_rmse

    ref = np.array([[-1.0, 0.0], [1.0, 0.0], [0.0, -2.0], [0.0, 2.0]])
    est = np.array([[-2.0, 0.0], [2.0, 0.0], [0.0, -2.0], [0.0, 2.0]])
    assert ate_rmse(est, ref) == pytest.approx(np.sqrt(0.5), abs=1e-12)


# metrics-waypoint-radius: a pass at exactly radius_m counts
def test_a_pass_at_exactly_the_radius_counts():
    from footnav.analysis.metrics import waypoint_errors

    x = np.linspace(-3.0, 3.0, 61)
    ref = np.column_stack([x, np.ones_like(x)])
    res = waypoint_errors(ref + [0.0, 0.25], ref, [[0.0, 0.0]], radius_m=1.0)
    np.testing.assert_allclose(res.errors_m, [0.25])


# metrics-deviation-min-distance: the ratio counts samples with s_k >= min_distance_m
def test_deviation_ratio_includes_the_minimum_distance():
    from footnav.analysis.metrics import max_deviation

    ref = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    est = np.array([[0.0, 0.0], [1.0, 0.5], [2.0, 0.1]])
    res = max_deviation(est, ref, min_distance_m=1.0)
    assert res.max_ratio == pytest.approx(0.5) and res.max_ratio_index == 1


# metrics-interp-duplicates: times must increase strictly
def test_interpolation_refuses_repeated_times():
    from footnav.analysis.metrics import interpolate_positions
    from footnav.core.errors import InvalidInputError

    with pytest.raises(InvalidInputError):
        interpolate_positions([0.0, 1.0, 1.0, 2.0], np.zeros((4, 3)), [0.5])


# metrics-distance-3d: the start heading comes from the first distance_m walked horizontally; a
# climb straight up first (stairs, a lift) does not count
def test_start_heading_uses_horizontal_distance():
    from footnav.analysis.metrics import align_at_start

    climb = np.column_stack([np.zeros(11), np.zeros(11), np.linspace(0.0, 3.0, 11)])
    s = np.linspace(0.2, 4.0, 20)
    ref = np.vstack([climb, np.column_stack([np.zeros(20), s, np.full(20, 3.0)])])
    est = np.vstack([climb, np.column_stack([s, np.zeros(20), np.full(20, 3.0)])])
    np.testing.assert_allclose(align_at_start(est, ref).aligned, ref, atol=1e-12)


# dtw-tie-break: among equal accumulated costs the diagonal step wins (the path with fewest pairs)
def test_dtw_prefers_the_diagonal_on_ties():
    from footnav.nav.dtw import dtw_align

    res = dtw_align(np.zeros((3, 1)), np.zeros((3, 1)), return_path=True)
    np.testing.assert_array_equal(res.path, [[0, 0], [1, 1], [2, 2]])
