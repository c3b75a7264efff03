"""Tests of the walking simulator: determinism, physical consistency of IMU vs truth, geometry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from footnav.core.errors import InvalidParameterError
from footnav.core.types import GRAVITY_MPS2, FootTruth, ImuData, Recording, stance_intervals
from footnav.data.simulate import PHASE_NAMES, simulate
from footnav.nav import quaternion as quat

G_N = np.array([0.0, 0.0, -GRAVITY_MPS2])
SHORT = {"distance_m": 6.0, "standstill_s": 1.0}
# A free path with a left and a right turn: exercises heading changes while the foot pitches.
TURNING = {"segments": [(2.0, 90.0), (1.0, -60.0), (1.0, 0.0)], "standstill_s": 1.0}


def _feet(rec: Recording):
    return (("left", rec.left, rec.truth_left), ("right", rec.right, rec.truth_right))


def _footprints(truth: FootTruth) -> np.ndarray:
    return np.array([truth.position[a:b].mean(axis=0) for a, b in stance_intervals(truth.stance)])


def _airborne(truth: FootTruth) -> np.ndarray:
    """True between each toe-off and the following heel strike."""
    out = np.zeros(len(truth.t), dtype=bool)
    for a, b in zip(truth.events["toe_off"], truth.events["heel_strike"]):
        out[a:b] = True
    return out


def _qmul(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    )


def _qrot(q, v):
    """C_b^n(q) v, written out independently of footnav.nav.quaternion."""
    w, x, y, z = q
    return (
        (1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y - w * z) * v[1] + 2 * (x * z + w * y) * v[2],
        2 * (x * y + w * z) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z - w * x) * v[2],
        2 * (x * z - w * y) * v[0] + 2 * (y * z + w * x) * v[1] + (1 - 2 * (x * x + y * y)) * v[2],
    )


def _mean_rate_turn(q, w_a, w_b, dt):
    """``q`` turned by the rotation vector of the mean of the rates ``w_a``, ``w_b`` over ``dt``."""
    r = [0.5 * (w_a[i] + w_b[i]) * dt for i in range(3)]
    angle = math.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2)
    s = math.sin(0.5 * angle) / angle if angle > 0 else 0.5
    return _qmul(q, (math.cos(0.5 * angle), s * r[0], s * r[1], s * r[2]))


def _strapdown(imu: ImuData, q0: np.ndarray, p0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Independent strapdown from rest at ``p0`` with attitude ``q0``: position, velocity (N, 3).

    Quaternion update by the rotation vector of the mean rate over each interval, trapezoidal
    velocity and position integration; plain Python floats (N is a few thousand).
    """
    t, f, w = imu.t.tolist(), imu.acc.tolist(), imu.gyr.tolist()
    g = GRAVITY_MPS2
    q = tuple(float(c) for c in q0)
    f0 = _qrot(q, f[0])
    a_prev = [f0[0], f0[1], f0[2] - g]
    v = [0.0, 0.0, 0.0]
    p = [float(c) for c in p0]
    pos, vel = [list(p)], [list(v)]
    for k in range(len(t) - 1):
        dt = t[k + 1] - t[k]
        q = _mean_rate_turn(q, w[k], w[k + 1], dt)
        norm = math.sqrt(sum(c * c for c in q))
        q = tuple(c / norm for c in q)
        fa = _qrot(q, f[k + 1])
        a = [fa[0], fa[1], fa[2] - g]
        v_next = [v[i] + 0.5 * (a_prev[i] + a[i]) * dt for i in range(3)]
        p = [p[i] + 0.5 * (v[i] + v_next[i]) * dt for i in range(3)]
        v, a_prev = v_next, a
        pos.append(p)
        vel.append(v)
    return np.array(pos), np.array(vel)


# -- determinism ---------------------------------------------------------------------------------


def test_same_seed_identical_different_seed_different():
    a = simulate("straight", seed=3, **SHORT)
    b = simulate("straight", seed=3, **SHORT)
    c = simulate("straight", seed=4, **SHORT)
    for x, y in ((a.left, b.left), (a.right, b.right)):
        assert np.array_equal(x.acc, y.acc) and np.array_equal(x.gyr, y.gyr)
    assert not np.array_equal(a.left.acc, c.left.acc)
    assert not np.array_equal(a.left.gyr, c.left.gyr)
    # Each foot has its own generator: the two sensors' errors are not the same draws.
    bias_l, bias_r = (t.meta["biases"]["gyr_turn_on_radps"] for t in (a.truth_left, a.truth_right))
    assert not np.allclose(bias_l, bias_r)
    # The walk itself does not depend on the seed.
    assert np.array_equal(a.truth_left.position, c.truth_left.position)


# -- noise-free physical consistency ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("scenario", "opts"),
    [("straight", SHORT), ("path", TURNING), ("path", {**TURNING, "mounting_rpy_deg": (10.0, -25.0, 40.0)})],
)
def test_strapdown_of_noise_free_imu_reproduces_truth_stride_by_stride(scenario, opts):
    # From each flat stance to the next (how a zero-velocity-aided filter sees the data).
    rec = simulate(scenario, rate_hz=500.0, noise=False, **opts)
    for _, imu, truth in _feet(rec):
        ints = stance_intervals(truth.stance)
        assert len(ints) >= 4
        for (a, _), (b, _) in zip(ints[:-1], ints[1:]):
            pos, vel = _strapdown(imu.slice(a, b + 1), truth.quaternion[a], truth.position[a])
            assert np.abs(pos - truth.position[a : b + 1]).max() < 1e-3  # m, over a 1.4 m stride
            assert np.abs(vel - truth.velocity[a : b + 1]).max() < 3e-3  # m/s, peaks ~6 m/s


def test_strapdown_over_whole_walk_converges_to_truth():
    # Without any reset the only error left is the integrator's truncation, which must shrink
    # like dt^2; a modelling inconsistency would not.
    opts = {**TURNING, "mounting_rpy_deg": (10.0, -25.0, 40.0)}
    err = {}
    for rate in (500.0, 1000.0):
        rec = simulate("path", rate_hz=rate, noise=False, **opts)
        pos, _ = _strapdown(rec.left, rec.truth_left.quaternion[0], rec.truth_left.position[0])
        err[rate] = np.abs(pos - rec.truth_left.position).max()
    assert err[1000.0] < 1e-2  # m, over 12 strides and two turns
    assert err[500.0] / err[1000.0] > 3.5


def test_stance_is_exactly_still_and_reads_gravity():
    rec = simulate("path", noise=False, mounting_rpy_deg=(5.0, 10.0, -30.0), **TURNING)
    for _, imu, truth in _feet(rec):
        still = (truth.velocity == 0).all(axis=1) & (imu.gyr == 0).all(axis=1)
        assert np.array_equal(truth.stance, still)
        s = truth.stance
        expected = np.einsum("nji,j->ni", quat.as_matrix(truth.quaternion[s]), -G_N)
        np.testing.assert_allclose(imu.acc[s], expected, atol=1e-9)
        # Position constant within each stance phase, on the ground (z = 0).
        for a, b in stance_intervals(s):
            assert np.ptp(truth.position[a:b], axis=0).max() == 0.0
            assert truth.position[a, 2] == 0.0


def test_gyro_and_acc_match_finite_differences_of_truth():
    rate = 2000.0
    rec = simulate("path", rate_hz=rate, noise=False, **TURNING)
    dt = 1.0 / rate
    for _, imu, truth in _feet(rec):
        q = truth.quaternion
        qdot = (q[2:] - q[:-2]) / (2 * dt)
        w_fd = 2.0 * quat.multiply(quat.conjugate(q[1:-1]), qdot)[:, 1:]
        np.testing.assert_allclose(w_fd, imu.gyr[1:-1], atol=1.5e-3)  # rad/s, peaks ~9 rad/s
        # Fourth-order central differences: the 10 ms heel-strike impact is too sharp for second order.
        p = truth.position
        v_fd = (8 * (p[3:-1] - p[1:-3]) - (p[4:] - p[:-4])) / (12 * dt)
        np.testing.assert_allclose(v_fd, truth.velocity[2:-2], atol=2e-4)  # m/s
        # The jerk jumps where the gait phase changes (profiles are C2), so the central
        # difference of velocity is only second-order accurate away from those samples.
        phase = truth.meta["phases"]
        near = np.zeros(len(phase), dtype=bool)
        for i in np.flatnonzero(np.diff(phase) != 0):
            near[max(i - 2, 0) : i + 4] = True
        v = truth.velocity
        a_fd = (8 * (v[3:-1] - v[1:-3]) - (v[4:] - v[:-4])) / (12 * dt)
        a_imu = quat.rotate(q[2:-2], imu.acc[2:-2]) + G_N
        keep = ~near[2:-2]
        np.testing.assert_allclose(a_fd[keep], a_imu[keep], atol=2e-2)  # m/s^2, peaks ~40 m/s^2


def test_signals_are_continuous():
    # Jumps would not shrink with the sampling interval; continuous signals' steps halve.
    steps = {}
    for rate in (1000.0, 2000.0):
        rec = simulate("path", rate_hz=rate, noise=False, **TURNING)
        steps[rate] = [
            np.abs(np.diff(x, axis=0)).max()
            for x in (rec.left.acc, rec.left.gyr, rec.truth_left.velocity, rec.truth_left.quaternion)
        ]
    for fine, coarse in zip(steps[2000.0], steps[1000.0]):
        assert fine < 0.6 * coarse


# -- geometry and gait ----------------------------------------------------------------------------


def test_straight_walk_geometry_and_gait():
    rec = simulate("straight", noise=False)
    prints = {foot: _footprints(truth) for foot, _, truth in _feet(rec)}
    for foot, side in (("left", 1.0), ("right", -1.0)):
        fp = prints[foot]
        np.testing.assert_allclose(fp[0], [0.0, side * 0.1, 0.0], atol=1e-12)
        np.testing.assert_allclose(fp[-1], [100.0, side * 0.1, 0.0], atol=1e-9)
        np.testing.assert_allclose(fp[:, 1], side * 0.1, atol=1e-9)  # step width kept
        strides = np.diff(fp[1:-1, 0])
        np.testing.assert_allclose(strides, 1.4, atol=0.01)
    assert not rec.truth_left.closed_loop

    for _foot, _, truth in _feet(rec):
        ev = truth.events
        k = len(ev["heel_off"])
        assert k > 60 and all(len(ev[name]) == k for name in ("toe_off", "heel_strike", "foot_flat"))
        assert (ev["heel_off"] < ev["toe_off"]).all() and (ev["toe_off"] < ev["heel_strike"]).all()
        assert (ev["heel_strike"] < ev["foot_flat"]).all() and (ev["foot_flat"][:-1] < ev["heel_off"][1:]).all()
        # Stance (zero velocity) fraction of each full stride.
        ho = ev["heel_off"]
        frac = [truth.stance[a:b].mean() for a, b in zip(ho[:-1], ho[1:])]
        assert 0.3 < min(frac) and max(frac) < 0.6

    air_l, air_r = _airborne(rec.truth_left), _airborne(rec.truth_right)
    assert not (air_l & air_r).any()
    # While one foot is airborne the other is flat on the ground.
    assert rec.truth_right.stance[air_l].all() and rec.truth_left.stance[air_r].all()


def test_foot_motion_is_realistic():
    rec = simulate("straight", noise=False, **SHORT)
    for _, imu, truth in _feet(rec):
        roll, pitch, _ = np.degrees(quat.as_euler(truth.quaternion)).T
        np.testing.assert_allclose(roll, 0.0, atol=1e-9)
        assert 20 < pitch.max() < 45  # toe down (positive about y-left) around toe-off
        assert -30 < pitch.min() < -15  # toe up at heel strike
        to, hs = truth.events["toe_off"], truth.events["heel_strike"]
        assert (pitch[to] > 15).all() and (pitch[hs] < -10).all()
        assert 0.08 < truth.position[:, 2].max() < 0.2  # foot lift, m
        # Heel and toe never go through the ground (the sensor is 6 cm above it when flat) but by
        # the sole's compression at the heel-strike impact, A sigma^2 = 4 mm.
        geo = truth.meta["foot_geometry_m"]
        opts = truth.meta["options"]
        squeeze = opts["heel_strike_impact_mps2"] * opts["heel_strike_impact_s"] ** 2
        for point in (geo["heel"], geo["toe"]):
            z = truth.position[:, 2] + quat.rotate(truth.quaternion, point)[:, 2]
            assert z.min() > -geo["sensor_height"] - squeeze - 1e-9
        # No zero-velocity instant outside stance (a detector could mistake it for a stance).
        speed = np.linalg.norm(truth.velocity, axis=1)
        assert speed[~truth.stance].min() > 0.01
        assert 3.0 < speed.max() < 7.0
        assert 4.0 < np.abs(imu.gyr).max() < 12.0  # rad/s


@pytest.mark.parametrize(("direction", "sign"), [("ccw", 1.0), ("cw", -1.0)])
def test_rectangle_closes_and_traces_the_rectangle(direction, sign):
    rec = simulate("rectangle", direction=direction, noise=False)
    centre = []
    for _foot, _, truth in _feet(rec):
        assert truth.closed_loop
        fp = _footprints(truth)
        np.testing.assert_allclose(fp[-1], fp[0], atol=1e-9)
        centre.append(fp)
        yaw = np.unwrap(quat.yaw(truth.quaternion))
        assert yaw[-1] == pytest.approx(sign * 2 * np.pi, abs=1e-9)
        assert (sign * np.diff(yaw) >= -1e-12).all()  # only ever turns one way
    allfp = np.vstack(centre)
    x0, y0 = allfp[:, :2].min(axis=0)
    x1, y1 = allfp[:, :2].max(axis=0)
    assert x1 - x0 == pytest.approx(105.0, abs=0.5)
    assert y1 - y0 == pytest.approx(68.0, abs=0.5)
    assert (x0, x1) == (pytest.approx(-52.5, abs=0.3), pytest.approx(52.5, abs=0.3))
    assert sign * (y0 + y1) / 2 == pytest.approx(34.0, abs=0.3)
    # The footprints lie on the rectangle's sides (within step width and corner rounding).
    x, y = allfp[:, 0], allfp[:, 1]
    dist = np.minimum.reduce([np.abs(x - x0), np.abs(x - x1), np.abs(y - y0), np.abs(y - y1)])
    assert dist.max() < 0.8


def test_turns_are_gradual_and_signed():
    rec = simulate("path", noise=False, segments=[(5.0, 90.0), (5.0, -45.0), (3.0, 0.0)])
    for _, _, truth in _feet(rec):
        yaw = np.unwrap(quat.yaw(truth.quaternion))
        assert yaw[-1] == pytest.approx(np.radians(45.0), abs=1e-9)
        assert np.degrees(yaw.max()) == pytest.approx(90.0, abs=1e-6)
        # The heading changes only while airborne, and by well under 90 deg per swing.
        turning = np.abs(np.diff(yaw)) > 1e-12
        assert not (truth.stance[:-1] & truth.stance[1:] & turning).any()
        assert turning[truth.meta["phases"][1:] == PHASE_NAMES.index("swing")].any()
        per_stance = np.array([yaw[a] for a, _ in stance_intervals(truth.stance)])
        changes = np.abs(np.diff(per_stance))
        assert np.degrees(changes.max()) < 60.0
        assert (changes > np.radians(5.0)).sum() >= 3  # the 90 deg turn takes several strides
    assert not rec.truth_left.closed_loop
    square = simulate("path", noise=False, segments=[(10.0, 90.0)] * 4)
    assert square.truth_left.closed_loop


def test_rate_does_not_change_truth():
    a = simulate("path", rate_hz=100.0, **TURNING)
    b = simulate("path", rate_hz=400.0, **TURNING)
    for ta, tb in ((a.truth_left, b.truth_left), (a.truth_right, b.truth_right)):
        assert len(tb.t) == 4 * (len(ta.t) - 1) + 1
        np.testing.assert_array_equal(tb.t[::4], ta.t)
        np.testing.assert_allclose(tb.position[::4], ta.position, atol=1e-12)
        np.testing.assert_allclose(tb.velocity[::4], ta.velocity, atol=1e-12)
        np.testing.assert_allclose(tb.quaternion[::4], ta.quaternion, atol=1e-12)
        np.testing.assert_array_equal(tb.stance[::4], ta.stance)
        for name, idx in ta.events.items():
            assert np.abs(tb.t[tb.events[name]] - ta.t[idx]).max() <= 0.5 / 100.0 + 1e-12


# -- sensor errors ---------------------------------------------------------------------------------


def test_noise_levels_and_recorded_biases():
    rate = 200.0
    gyr_d, acc_d = 2e-3, 5e-3
    rec = simulate(
        "straight",
        rate_hz=rate,
        seed=7,
        gyr_noise_density_radps_sqrthz=gyr_d,
        acc_noise_density_mps2_sqrthz=acc_d,
        gyr_bias_walk_radps2_sqrthz=0.0,
        acc_bias_walk_mps3_sqrthz=0.0,
        **SHORT,
    )
    clean = simulate("straight", rate_hz=rate, noise=False, **SHORT)
    for (_, imu, truth), (_, ref, _) in zip(_feet(rec), _feet(clean)):
        b = truth.meta["biases"]
        eg, ea = imu.gyr - ref.gyr, imu.acc - ref.acc
        np.testing.assert_allclose(eg.std(axis=0), gyr_d * math.sqrt(rate), rtol=0.08)
        np.testing.assert_allclose(ea.std(axis=0), acc_d * math.sqrt(rate), rtol=0.08)
        np.testing.assert_allclose(eg.mean(axis=0), b["gyr_turn_on_radps"], atol=4 * gyr_d * math.sqrt(rate / len(eg)))
        np.testing.assert_allclose(ea.mean(axis=0), b["acc_turn_on_mps2"], atol=4 * acc_d * math.sqrt(rate / len(ea)))
        assert np.abs(b["gyr_turn_on_radps"]).max() > 0
        np.testing.assert_array_equal(truth.meta["gyr_true_radps"], ref.gyr)


def test_bias_random_walk_grows_like_sqrt_time():
    walk = 1e-3
    rec = simulate("straight", seed=1, distance_m=3.0, standstill_s=30.0, gyr_bias_walk_radps2_sqrthz=walk)
    series = [t.meta["biases"]["gyr_radps"] for t in (rec.truth_left, rec.truth_right)]
    dur = rec.left.duration_s
    drift = np.concatenate([s[-1] - s[0] for s in series])
    # Six independent axes: the RMS drift is walk * sqrt(duration) within sampling spread.
    assert 0.3 * walk * math.sqrt(dur) < np.sqrt(np.mean(drift**2)) < 2.0 * walk * math.sqrt(dur)
    np.testing.assert_array_equal(series[0][0], rec.truth_left.meta["biases"]["gyr_turn_on_radps"])


# -- API -------------------------------------------------------------------------------------------


def test_recording_structure_and_meta():
    rec = simulate("rectangle", width_m=10.0, height_m=6.0, seed=5)
    assert isinstance(rec, Recording) and rec.name == "sim-rectangle" and rec.n_feet == 2
    for _foot, imu, truth in _feet(rec):
        assert imu.meta["source"] == "simulator" and imu.meta["scenario"] == "rectangle"
        assert imu.rate_hz == pytest.approx(100.0)
        assert truth.frame == "nav" and np.array_equal(truth.t, imu.t)
        assert truth.meta["stance_source"] == "simulator" and truth.meta["seed"] == 5
        assert truth.meta["options"]["width_m"] == 10.0 and truth.meta["scenario"] == "rectangle"
        assert set(truth.events) == {"heel_strike", "foot_flat", "heel_off", "toe_off"}
        assert truth.stance.shape == (len(imu),) and truth.quaternion.shape == (len(imu), 4)
        np.testing.assert_allclose(np.linalg.norm(truth.quaternion, axis=1), 1.0, atol=1e-12)
        assert "gyr_noise_density_radps_sqrthz" in truth.meta["noise_params"]
        # Both feet still at the start and the end for the requested standstill.
        assert truth.stance[: int(2.0 * 100)].all() and truth.stance[-int(2.0 * 100) :].all()
    np.testing.assert_allclose(rec.truth_left.position[0], [0, 0.1, 0])
    np.testing.assert_allclose(rec.truth_right.position[0], [0, -0.1, 0])


@pytest.mark.parametrize(
    ("args", "kwargs", "must_name"),
    [
        (("circle",), {}, ["circle", "straight", "rectangle", "path"]),
        (("straight",), {"distance_m": -5.0}, ["distance_m"]),
        (("straight",), {"distanse_m": 5.0}, ["distanse_m", "distance_m", "stride_length_m"]),
        (("straight",), {"width_m": 5.0}, ["width_m", "distance_m"]),
        (("rectangle",), {"direction": "left"}, ["direction", "ccw", "cw"]),
        (("rectangle",), {"width_m": 2.0}, ["width_m", "turn_radius_m"]),
        (("path",), {}, ["segments"]),
        (("path",), {"segments": [(5.0, 90.0), (-1.0, 0.0)]}, ["segments"]),
        (("straight",), {"swing_s": 0.9}, ["swing_s", "stride_period_s"]),
        (("straight",), {"noise": "yes"}, ["noise"]),
        (("straight",), {"mounting_rpy_deg": (1.0, 2.0)}, ["mounting_rpy_deg"]),
        (("straight",), {"rate_hz": 0.0}, ["rate_hz"]),
        (("straight",), {"clock_offset_s": float("nan")}, ["clock_offset_s"]),
        (("straight",), {"clock_offset_s": True}, ["clock_offset_s"]),
        (("straight",), {"clock_drift_ppm": 2e5}, ["clock_drift_ppm", "ppm"]),
        (("straight",), {"clock_exchanges": 1}, ["clock_exchanges", ">= 2"]),
        (("straight",), {"clock_exchanges": -4}, ["clock_exchanges"]),
        (("straight",), {"clock_exchanges": 10.0}, ["clock_exchanges"]),
        (("straight",), {"clock_exchanges": True}, ["clock_exchanges"]),
        (("straight",), {"exchange_delay_s": -0.01}, ["exchange_delay_s"]),
        (("straight",), {"exchange_jitter_s": float("inf")}, ["exchange_jitter_s"]),
        (("straight",), {"clock_ofset_s": 1.0}, ["clock_ofset_s", "clock_offset_s"]),
    ],
)
def test_bad_options_raise(args, kwargs, must_name):
    with pytest.raises(InvalidParameterError) as info:
        simulate(*args, **kwargs)
    for word in must_name:
        assert word in str(info.value)


def test_an_hour_long_walk_is_simulated():
    # its speed is measured by benchmarks/bench_simulate.py, not asserted here
    rec = simulate("straight", distance_m=4600.0)  # about an hour at 1.27 m/s
    assert rec.left.duration_s > 3600.0 and rec.right.duration_s > 3600.0


@pytest.mark.parametrize("rate", [100.0, 400.0])
def test_heel_strike_impact_is_the_spike_at_each_heel_strike_and_moves_nothing(rate):
    rec = simulate("straight", rate_hz=rate, noise=False, **SHORT)
    flat = simulate("straight", rate_hz=rate, noise=False, heel_strike_impact_mps2=0.0, **SHORT)
    for (_, imu, truth), (_, imu0, truth0) in zip(_feet(rec), _feet(flat)):
        hs = truth.events["heel_strike"]
        f = np.linalg.norm(imu.acc, axis=1)
        half = int(0.02 * rate)
        # the largest |f| near each heel strike is the impact, at the heel strike, above 2 g
        for k in hs:
            win = f[k - half : k + half + 1]
            assert abs(int(np.argmax(win)) - half) <= max(1, int(0.005 * rate))
            assert win.max() > 2 * GRAVITY_MPS2
        # it is a vibration of the sole, A sigma^2 = 4 mm deep, gone 60 ms after the heel strike
        dz = truth.position[:, 2] - truth0.position[:, 2]
        assert 3.0e-3 < -dz.min() < 4.1e-3
        after = np.zeros(len(dz), dtype=bool)
        for k in hs:
            after[k + int(0.06 * rate) : k + int(0.1 * rate)] = True
        assert np.abs(dz[after]).max() < 1e-9
        np.testing.assert_array_equal(truth.stance, truth0.stance)
        np.testing.assert_allclose(imu.acc - imu0.acc, truth.meta["acc_impact_mps2"], atol=1e-12)


def test_impact_longer_than_foot_flat_is_refused():
    with pytest.raises(InvalidParameterError, match="heel_strike_impact_s"):
        simulate("straight", distance_m=5.0, heel_strike_impact_s=0.03)


# -- sensor clock (seed 002 Sec. 5B) -------------------------------------------------------------

CLOCKED = {"distance_m": 10.0, "clock_offset_s": 3.0, "clock_drift_ppm": -80.0, "clock_exchanges": 8}


def test_clock_options_off_by_default_and_change_only_the_right_time_stamps():
    plain = simulate("straight", seed=4, distance_m=10.0)
    assert "clock" not in plain.meta and "clock_exchanges" not in plain.meta
    assert "clock" not in plain.truth_right.meta and "time_base" not in plain.right.meta
    np.testing.assert_array_equal(plain.right.t, plain.left.t)
    clocked = simulate("straight", seed=4, **CLOCKED)
    for a, b in ((plain.left, clocked.left), (plain.truth_left, clocked.truth_left)):
        np.testing.assert_array_equal(a.t, b.t)
    # the sensors' random streams are untouched by the clock and the exchanges' delays
    for name in ("acc", "gyr"):
        np.testing.assert_array_equal(getattr(plain.left, name), getattr(clocked.left, name))
        np.testing.assert_array_equal(getattr(plain.right, name), getattr(clocked.right, name))
    np.testing.assert_array_equal(plain.truth_right.position, clocked.truth_right.position)
    np.testing.assert_array_equal(clocked.truth_right.t, plain.truth_right.t)  # truth on true time
    # t_imu = (1 + drift 1e-6) t + offset, and the recorded map takes it back: t = a t_imu + b
    np.testing.assert_allclose(clocked.right.t, (1 - 80e-6) * plain.right.t + 3.0, rtol=0, atol=1e-12)
    clock = clocked.meta["clock"]
    assert clock["foot"] == "right" and clock["offset_s"] == 3.0 and clock["drift_ppm"] == -80.0
    np.testing.assert_allclose(clock["a"] * clocked.right.t + clock["b"], plain.right.t, rtol=0, atol=1e-12)
    assert clocked.truth_right.meta["clock"] == clock
    assert "sensor clock" in clocked.right.meta["time_base"]


def test_clock_exchanges_bracket_the_true_map_and_are_seeded():
    rec = simulate("straight", seed=2, **CLOCKED)
    ex, clock = rec.meta["clock_exchanges"], rec.meta["clock"]
    assert all(len(ex[k]) == 8 for k in ("tm1", "ti", "tm2"))
    t_stamp = clock["a"] * ex["ti"] + clock["b"]  # true time at which the sensor stamped
    delay = 0.02  # exchange_delay_s, plus an exponential jitter of mean exchange_jitter_s = 0.02
    assert (t_stamp - ex["tm1"] >= delay - 1e-12).all() and (ex["tm2"] - t_stamp >= delay - 1e-12).all()
    # mean one-way delay 0.04 s: loose bounds for 16 exponential draws
    assert 0.02 < np.mean(np.r_[t_stamp - ex["tm1"], ex["tm2"] - t_stamp]) < 0.08
    # half at the start and half at the end of the walk
    assert (ex["tm1"][:4] <= rec.left.duration_s / 3).all() and (ex["tm1"][4:] >= 2 * rec.left.duration_s / 3).all()
    again = simulate("straight", seed=2, **CLOCKED)
    other = simulate("straight", seed=3, **CLOCKED)
    np.testing.assert_array_equal(again.meta["clock_exchanges"]["ti"], ex["ti"])
    assert not np.array_equal(other.meta["clock_exchanges"]["ti"], ex["ti"])


def test_exchanges_without_jitter_have_exactly_the_fixed_delay():
    rec = simulate("straight", seed=0, distance_m=10.0, clock_exchanges=4, exchange_delay_s=0.03, exchange_jitter_s=0.0)
    ex, clock = rec.meta["clock_exchanges"], rec.meta["clock"]
    assert clock["a"] == 1.0 and clock["b"] == 0.0  # exchanges alone: the sensor clock is true time
    np.testing.assert_allclose(ex["ti"] - ex["tm1"], 0.03, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ex["tm2"] - ex["ti"], 0.03, rtol=0, atol=1e-12)


# -- the mirrored yaw drift (Lee, Cho & Park 2022, Sec. 2.1) ---------------------------------------


def _attitude(imu: ImuData, q0: np.ndarray) -> tuple[float, float, float, float]:
    """Final attitude of the independent integrator of :func:`_strapdown` (rotation vectors of
    the mean rate), plain floats."""
    t, w = imu.t.tolist(), imu.gyr.tolist()
    q = tuple(float(c) for c in q0)
    for k in range(len(t) - 1):
        q = _mean_rate_turn(q, w[k], w[k + 1], t[k + 1] - t[k])
    return q


def test_mirrored_yaw_rate_off_is_bit_identical_to_the_default():
    for scenario, opts in (("straight", SHORT), ("path", {**TURNING, "mounting_rpy_deg": (5.0, -10.0, 20.0)})):
        a = simulate(scenario, seed=3, **opts)
        b = simulate(scenario, seed=3, mirrored_yaw_rate_radps=0.0, **opts)
        for x, y in ((a.left, b.left), (a.right, b.right)):
            np.testing.assert_array_equal(x.gyr, y.gyr)
            np.testing.assert_array_equal(x.acc, y.acc)
        np.testing.assert_array_equal(a.truth_right.quaternion, b.truth_right.quaternion)
        assert not a.truth_left.meta["gyr_mirrored_yaw_radps"].any()


def test_mirrored_yaw_rate_turns_each_foot_by_b_times_its_moving_time():
    # Hand computation: the drift acts while the foot is off flat stance, heel_off_s + swing_s
    # + foot_flat_s = 0.65 s per swing, so after the walk the integrated attitude is the truth
    # turned about the vertical by +b (left) / -b (right) times 0.65 s x the number of swings.
    b = 5e-3
    opts = {**SHORT, "mounting_rpy_deg": (10.0, -25.0, 40.0)}
    rec = simulate("straight", rate_hz=500.0, noise=False, mirrored_yaw_rate_radps=b, **opts)
    plain = simulate("straight", rate_hz=500.0, noise=False, **opts)
    for sign, (foot, imu, truth) in zip((1.0, -1.0), _feet(rec)):
        n_swings = len(truth.events["heel_off"])
        expected = sign * b * (0.1 + 0.45 + 0.1) * n_swings
        w, x, y, z = _attitude(imu, truth.quaternion[0])
        tw, tx, ty, tz = truth.quaternion[-1]
        d = _qmul((w, x, y, z), (tw, -tx, -ty, -tz))  # q_int q_true^-1: the error in nav axes
        assert math.hypot(d[1], d[2]) < 1e-5  # no tilt error: about the vertical only
        # the rate is a step sampled at 500 Hz: the trapezoid gives each swing's two edges half
        # a sample each, so one sample (2 ms) of b per swing is lost
        expected -= sign * b * n_swings / 500.0
        assert 2 * math.atan2(d[3], d[0]) == pytest.approx(expected, abs=1e-6), foot
        # stance samples read exactly what they read without the drift
        other = plain.left if foot == "left" else plain.right
        np.testing.assert_array_equal(imu.gyr[truth.stance], other.gyr[truth.stance])
        assert np.linalg.norm(imu.gyr - other.gyr, axis=1).max() == pytest.approx(b, rel=1e-9)


def test_mirrored_yaw_rate_out_of_range_is_refused():
    with pytest.raises(InvalidParameterError, match="mirrored_yaw_rate_radps"):
        simulate("straight", mirrored_yaw_rate_radps=2.0, **SHORT)
    with pytest.raises(InvalidParameterError, match="mirrored_yaw_rate_radps"):
        simulate("straight", mirrored_yaw_rate_radps=float("nan"), **SHORT)


def test_scale_factor_errors_scale_the_true_signals_per_axis():
    base = simulate("straight", seed=3)
    scaled = simulate("straight", seed=3, gyr_scale_error=(0.01, 0.0, -0.02), acc_scale_error=0.005)
    meta = base.truth_left.meta
    np.testing.assert_allclose(scaled.left.gyr - base.left.gyr, meta["gyr_true_radps"] * [0.01, 0.0, -0.02], atol=1e-12)
    np.testing.assert_allclose(scaled.left.acc - base.left.acc, meta["acc_true_mps2"] * 0.005, atol=1e-12)
    # off (the default) leaves every signal bit-identical
    off = simulate("straight", seed=3, gyr_scale_error=0.0, acc_scale_error=(0, 0, 0))
    assert np.array_equal(off.left.gyr, base.left.gyr) and np.array_equal(off.right.acc, base.right.acc)


@pytest.mark.parametrize("bad", [0.25, -0.3, float("nan"), (0.1, 0.2), "x"])
def test_scale_factor_errors_outside_the_range_are_refused(bad):
    with pytest.raises(InvalidParameterError, match="gyr_scale_error"):
        simulate("straight", gyr_scale_error=bad)


@pytest.mark.parametrize("k", [0.02, -0.02])
def test_a_gyro_scale_error_turns_a_u_turn_by_its_fraction(k):
    """Noise-free, the only heading error is the scale factor's: k x 180 deg at the U-turn, the
    way back's direction against the truth's less the first leg's."""
    import footnav

    rec = simulate("path", seed=0, segments=[(10.0, 180.0), (10.0, 0.0)], noise=False, gyr_scale_error=k)
    est, ref = footnav.make_pipeline().run(rec.left).left.position[:, :2], rec.truth_left.position[:, :2]
    n = len(est)

    def leg_error(a, b):
        d_est, d_ref = est[b] - est[a], ref[b] - ref[a]
        return np.arctan2(d_est[1], d_est[0]) - np.arctan2(d_ref[1], d_ref[0])

    turn = quat.wrap_angle(leg_error(3 * n // 5, 19 * n // 20) - leg_error(n // 20, 2 * n // 5))
    assert np.degrees(turn) == pytest.approx(k * 180.0, rel=0.05)
