"""Vertical accuracy of the EKF on noise-free level walks, and the 15-state forward track.

The bounds come from how a sampled signal can be integrated at all. Every rule that uses the
samples at t_k (trapezoid, Simpson with the mid-interval attitude as in
:mod:`footnav.nav.mechanization`, cubic interpolation) leaves a local error of order dt^3 f'',
and these telescope (Euler-Maclaurin): over one motion the velocity error is
``-dt^2 / 12 * (sum of the jumps of the nav-frame jerk)``. For a gait whose jerk is continuous
and zero at rest that sum is zero and what is left is of higher order. The simulator's gait
(quintic profiles, continuous up to acceleration) has jerk jumps at every phase boundary:
vertically +3000 m/s^3 at heel-off, -1300 at toe-off, -700 at heel strike and +1700 at
foot-flat, +2700 per swing, so any scheme is off by -22 mm/s per swing at 100 Hz (measured
-22.4, predicted -22.5) and -1.4 mm/s at 400 Hz. The ZUPT removes that from the velocity but
not fully from the position: the EKF ends about 2.3 mm per step low at 100 Hz and 0.14 mm at
400 Hz, falling with dt^2. (Between two rests even the O(dt) terms of a first-order rule
telescope, -dt/2 [f] and -dt/2 [v] with f^n and v equal at both ends: in a scratch run,
velocity and position by the rectangle rule gave -0.13 and -0.009 m per 100 m at 100 and
400 Hz against -0.16 and -0.010 m, so the integration order is not the cause.)
"""

import numpy as np
import pytest
from numpy.polynomial import polynomial as P

import footnav
from footnav import StanceResult
from footnav.analysis import metrics
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.estimators.ekf import EkfEstimator


def _z_end_error(traj, truth_position):
    return float(traj.position[-1, 2] - (truth_position[-1, 2] - truth_position[0, 2]))


def _simulated_z_error_per_100m(rate_hz):
    rec = footnav.simulate("straight", seed=0, rate_hz=rate_hz, distance_m=100.0, noise=False)
    traj = EkfEstimator().estimate(rec.left, StanceResult(rec.truth_left.stance))
    walked_m = metrics.travelled_distance(rec.truth_left.position, dims=2)
    return _z_end_error(traj, rec.truth_left.position) * 100.0 / walked_m


def test_simulated_level_walk_vertical_error_is_the_sampling_limit_and_falls_with_dt_squared():
    e100, e400 = _simulated_z_error_per_100m(100.0), _simulated_z_error_per_100m(400.0)
    # measured -0.16 m and -0.010 m per 100 m: the sampling limit of the simulator's gait (module
    # docstring), second order in dt (16x from 100 to 400 Hz; a first-order scheme gives 4x)
    assert abs(e100) < 0.25
    assert abs(e400) < 0.02  # 0.25 / 16 = 1.6 cm
    assert abs(e400) < abs(e100) / 10.0 + 0.002


def _profiles(order):
    """Polynomials in u on [0, 1] whose first ``order`` derivatives vanish at both ends: forward
    progress (0 -> 1), lift (0 -> 1 -> 0) and pitch (toe down, then up; peak 1)."""
    bump = P.polymul(P.polypow([0.0, 1.0], order + 1), P.polypow([1.0, -1.0], order + 1))
    s = P.polyint(bump)
    s = s / P.polyval(1.0, s)
    lift = bump / P.polyval(0.5, bump)
    pitch = P.polymul(bump, [1.0, -2.0])
    pitch = pitch / np.max(np.abs(P.polyval(np.linspace(0.0, 1.0, 1001), pitch)))
    return s, lift, pitch


def _smooth_walk(rate_hz, n_steps=70, step_m=1.4, move_s=0.65, rest_s=0.45, lift_m=0.12, pitch_rad=0.5, still_s=2.0):
    """A sagittal foot walk with jerk-continuous motion (profiles flat to 4th order at each
    boundary) and its exact IMU samples: ImuData, true positions (N, 3), standstill mask."""
    profiles = _profiles(4)
    t = np.arange(round((2 * still_s + n_steps * (move_s + rest_s)) * rate_hz) + 1) / rate_hz
    x = np.zeros((len(t), 3, 3))  # (forward, up, pitch) x (value, rate, acceleration)
    moving = np.zeros(len(t), dtype=bool)
    for i in range(n_steps):
        t0 = still_s + i * (move_s + rest_s) + rest_s
        m = (t > t0) & (t < t0 + move_s)
        moving[m] = True
        u = (t[m] - t0) / move_s
        for j, (poly, amp) in enumerate(zip(profiles, (step_m, lift_m, pitch_rad))):
            for d in range(3):
                x[m, j, d] = amp * P.polyval(u, P.polyder(poly, d)) / move_s**d
        x[t >= t0 + move_s, 0, 0] = (i + 1) * step_m
    c, s = np.cos(x[:, 2, 0]), np.sin(x[:, 2, 0])
    ax, az = x[:, 0, 2], x[:, 1, 2] + GRAVITY_MPS2  # a^n - g^n
    zero = np.zeros(len(t))
    acc = np.stack([c * ax - s * az, zero, s * ax + c * az], axis=1)  # C' (a - g), C = Ry(pitch)
    gyr = np.stack([zero, x[:, 2, 1], zero], axis=1)
    pos = np.stack([x[:, 0, 0], zero, x[:, 1, 0]], axis=1)
    return ImuData(t=t, acc=acc, gyr=gyr), pos, ~moving


@pytest.mark.parametrize("rate_hz", [100.0, 400.0])
def test_jerk_continuous_level_walk_ends_within_2cm_per_100m(rate_hz):
    # the mechanization itself: with no jerk jumps the dt^2 term cancels (measured 0.9 cm per
    # 98 m at 100 Hz, 0.01 cm at 400 Hz)
    imu, pos, still = _smooth_walk(rate_hz)
    traj = EkfEstimator(heading="sensor").estimate(imu, StanceResult(still))
    per_100m = 100.0 / pos[-1, 0]
    assert abs(_z_end_error(traj, pos)) * per_100m < 0.02
    assert np.linalg.norm(traj.position[-1, :2] - pos[-1, :2]) * per_100m < 0.02


def test_forward_15_state_track_length():
    # The unsmoothed 15-state track is longer than the walk when its gyro-bias priors are much
    # looser than the sensor (defaults: heading std 0.6 rad after 13 min against a true heading
    # error of 0.04 rad): every stance then moves heading and position, sideways jumps that a
    # per-sample path length counts (+5 % here, +17 % over 1075 m). The footprints, and the
    # track with priors that match the simulated sensor, stay within 0.5 %.
    rec = footnav.simulate("straight", seed=0, distance_m=300.0)
    stance = footnav.make_detector("threshold").detect(rec.left)
    length = metrics.travelled_distance(rec.truth_left.position, dims=2)
    loose = EkfEstimator(bias_states=True, smoother="none").estimate(rec.left, stance)
    assert loose.path_length_m == pytest.approx(length, rel=0.005)
    matched = EkfEstimator(
        bias_states=True, smoother="none", gyr_bias_walk_radps2_sqrthz=1e-5, init_gyr_bias_std_radps=2e-4
    ).estimate(rec.left, stance)
    assert metrics.travelled_distance(matched.position, dims=2) == pytest.approx(length, rel=0.01)


def _early_stance(mask, n):
    """``mask`` with every stance but the first starting ``n`` samples early (the foot still descending)."""
    from footnav.core.types.stance import stance_intervals

    out = mask.copy()
    for a, _ in stance_intervals(mask)[1:]:
        out[max(a - n, 0) : a] = True
    return out


def test_an_early_stance_start_makes_a_level_walk_climb_and_the_zupt_start_delay_removes_it():
    # docs/height.md: a zero-velocity update applied while the foot still descends is taken for a
    # velocity error grown over the whole swing, and the footprint is raised by about v T / 2. On
    # the simulator's exact truth a stance mask 40 ms early (the foot comes down at 0.2-0.5 m/s
    # there) climbs 4.1 m on a 50 m level walk with the update on the whole stance (measured);
    # delaying the ZUPT by as much gives back the true mask's result exactly (-0.02 m, the
    # sampling limit above)
    rec = footnav.simulate("straight", seed=0, rate_hz=200.0, distance_m=50.0, noise=False)
    truth = rec.truth_left
    early = StanceResult(_early_stance(truth.stance, 8))
    whole = EkfEstimator(zupt_edges="detected")
    exact = _z_end_error(whole.estimate(rec.left, StanceResult(truth.stance)), truth.position)
    climbed = _z_end_error(whole.estimate(rec.left, early), truth.position)
    delayed_traj = EkfEstimator(zupt_edges="detected", zupt_start_delay_s=0.04).estimate(rec.left, early)
    delayed = _z_end_error(delayed_traj, truth.position)
    assert abs(exact) < 0.05
    assert climbed > 2.0
    assert abs(delayed - exact) < 0.005
    # the outputs' steps are still the detector's stances
    assert np.array_equal(delayed_traj.steps, early.intervals)


def test_the_settled_edges_find_the_feet_rest_in_an_early_stance():
    # the default update (zupt_edges="settled") finds where the foot has come to rest from its own
    # accelerometer: the same 40 ms early mask ends +0.045 m (noise-free; the true mask -0.02 m)
    # and -0.035 m with the simulator's noise (true mask -0.10 m), not +4 m (measured)
    for noise, bound in ((False, 0.1), (True, 0.15)):
        rec = footnav.simulate("straight", seed=0, rate_hz=200.0, distance_m=50.0, noise=noise)
        truth = rec.truth_left
        early = StanceResult(_early_stance(truth.stance, 8))
        exact = _z_end_error(
            EkfEstimator(zupt_edges="detected").estimate(rec.left, StanceResult(truth.stance)), truth.position
        )
        settled_traj = EkfEstimator().estimate(rec.left, early)
        assert abs(_z_end_error(settled_traj, truth.position) - exact) < bound
        assert np.array_equal(settled_traj.steps, early.intervals)


def test_zupt_edges_keep_the_middle_of_short_stances():
    # a 40 ms stance at 200 Hz (8 samples) loses at most a quarter of itself at each edge
    mask = np.zeros(200, dtype=bool)
    mask[0:40] = True
    mask[100:108] = True
    est = EkfEstimator(zupt_edges="detected", zupt_start_delay_s=0.1, zupt_end_advance_s=0.1)
    t, acc = np.arange(200) / 200.0, np.tile([0.0, 0.0, GRAVITY_MPS2], (200, 1))
    zupt = est.zupt_rows(t, acc, mask, first_whole=True)
    assert zupt[0:40].all()  # the first stance aligns the filter: whole
    assert np.flatnonzero(zupt[100:108]).tolist() == [2, 3, 4, 5]
    assert not zupt[40:100].any() and not zupt[108:].any()


def test_zupt_edges_are_refused_online():
    from footnav.core.errors import CompositionError

    pipe = footnav.make_pipeline("threshold", "ekf", estimator_params={"smoother": "step", "zupt_start_delay_s": 0.05})
    with pytest.raises(CompositionError, match="zupt_start_delay_s"):
        pipe.online(feet=1)


def test_the_swing_rise_is_the_strapdown_s_and_follows_the_stairs():
    # each stance's swing_rise_m is the forward filter's own height change over the swing before
    # it (footnav.nav.floors.swing_rises): on the simulator's storey (12 stairs of 0.17 m up, a
    # U-turn, 12 down, with noise) it is the true stride rise within 3 cm, stairs and level alike
    # (measured: 1.2 cm at worst on seed 1, 0.8-1.4 cm on seeds 0-2; the smoothed filter's rise
    # 0.4-0.5 cm), and strapdown alone from the forward state at the previous stance's last
    # update, over the same samples (footnav.nav.mechanization), gives it too
    from footnav.nav.floors import stance_heights
    from footnav.nav.mechanization import strapdown

    legs = [(1.4, 0.0), ("stairs", 12, 0.17), (2.8, 180.0), ("stairs", 12, -0.17), (1.4, 0.0)]
    rec = footnav.simulate("path", seed=1, rate_hz=100.0, segments=legs)
    truth = rec.truth_left
    stance = StanceResult(truth.stance)
    est = EkfEstimator()
    traj = est.estimate(rec.left, stance)
    steps = traj.steps
    rise = traj.swing_rise_m
    assert rise.shape == (len(steps),) and np.isnan(rise[0]) and np.isfinite(rise[1:]).all()
    true = np.diff(stance_heights(truth.position[:, 2], steps))
    assert np.max(np.abs(rise[1:] - true)) < 0.03
    assert np.sum(np.abs(true) > 0.2) >= 10  # the stairs are in it, both ways
    forward = EkfEstimator(smoother="none").estimate(rec.left, stance)
    zupt = est.zupt_rows(rec.left.t, rec.left.acc, truth.stance, first_whole=True)
    bias = np.asarray(forward.meta.get("gyro_bias_radps", np.zeros(3)))
    for k in (3, len(steps) // 2, len(steps) - 2):
        e = steps[k - 1, 0] + np.flatnonzero(zupt[steps[k - 1, 0] : steps[k - 1, 1]])[-1]
        s = steps[k, 0] + np.flatnonzero(zupt[steps[k, 0] : steps[k, 1]])[0]
        seg = ImuData(t=rec.left.t[e:s].copy(), acc=rec.left.acc[e:s].copy(), gyr=rec.left.gyr[e:s].copy())
        _, _, p = strapdown(seg, forward.quaternion[e], forward.velocity[e], forward.position[e], gyro_bias_radps=bias)
        assert p[-1, 2] - p[0, 2] == pytest.approx(rise[k], abs=2e-3)
