"""Gait events against the simulator's true event times (issue 17, item 3).

The detector tests check their events against their own rule (``foot_flat`` = first sample of a
stance run, ``heel_off`` = its last; the HMM's events follow its state order). Here every event
a detector reports is matched to the simulator's exact event time
(``truth.meta["event_times_s"]``, the instants the gait model changes phase) of the same stride.

Tolerances, and today's measured worst (2026-11-25, seeds 1 and 2, rectangle and straight walk at
100 Hz; both feet):

* stance edges (``foot_flat``, ``heel_off``) of the windowed detectors (``threshold``,
  ``adaptive``, ``glrt``, ``acc-*``, ``ared``): 30 ms, half their 0.04 s window plus one sample
  (a centred window reaches into the motion 20 ms before it starts); measured 20 ms, the
  detected stance lies inside the true one.
* ``dual-gait``: heel strike within one sample (10 ms; measured 0: it marks the impact, and the
  truth's index is the nearest sample), ``foot_flat`` / ``heel_off`` 30 ms as above (measured
  20 ms), ``toe_off`` 0.1 s (measured 50 ms early in every stride: 2x).
* ``hmm`` (on a 10 m straight walk, its fit being slow): ``heel_off`` / ``foot_flat`` 30 ms
  (measured 10 and 0 ms on both walks above); its ``toe_off`` and ``heel_strike`` split the
  swing coarsely (measured on the walks above: toe-off 30-420 ms late, heel strike 20-90 ms
  early), so they are checked to lie inside the true swing (after the true heel-off, before
  the true foot-flat) and in order, not to a tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

import footnav
from footnav.core.types import FootTrajectory
from footnav.nav.strides import stride_parameters

WINDOWED = ["threshold", "adaptive", "glrt", "acc-magnitude", "acc-variance", "ared"]
EDGE_TOL_S = 0.03


@pytest.fixture(
    scope="module",
    params=[(1, "rectangle", {"width_m": 12.0, "height_m": 6.0}), (2, "straight", {"distance_m": 20.0})],
    ids=["rectangle", "straight"],
)
def walk(request):
    seed, scenario, opts = request.param
    return footnav.simulate(scenario, seed=seed, rate_hz=100.0, **opts)


def _feet(rec):
    return ((rec.left, rec.truth_left), (rec.right, rec.truth_right))


def _errors_s(imu, detected, true_times_s):
    """Signed error (s) of each detected event against the nearest true event time."""
    t = imu.t[np.asarray(detected, dtype=np.int64)]
    d = t[:, None] - np.asarray(true_times_s)[None, :]
    return d[np.arange(len(t)), np.abs(d).argmin(axis=1)]


@pytest.mark.parametrize("name", WINDOWED)
def test_stance_edges_at_the_true_foot_flat_and_heel_off(walk, name):
    detector = footnav.make_pipeline(name, "ekf", "independent").detector
    for imu, truth in _feet(walk):
        events = detector.detect(imu).events
        true_s = truth.meta["event_times_s"]
        # the first stance starts with the recording and the last ends with it: no gait event
        foot_flat, heel_off = events["foot_flat"][1:], events["heel_off"][:-1]
        assert len(foot_flat) == len(true_s["foot_flat"]) and len(heel_off) == len(true_s["heel_off"])
        assert np.abs(_errors_s(imu, foot_flat, true_s["foot_flat"])).max() <= EDGE_TOL_S
        assert np.abs(_errors_s(imu, heel_off, true_s["heel_off"])).max() <= EDGE_TOL_S


def test_dual_gait_events_at_the_true_times(walk):
    left, right = footnav.make_pipeline("dual-gait", "ekf", "independent").detector.detect_pair(walk.left, walk.right)
    for (imu, truth), stance in zip(_feet(walk), (left, right)):
        true_s = truth.meta["event_times_s"]
        for name, tol in (
            ("heel_strike", 1.0 / imu.rate_hz + 1e-9),
            ("foot_flat", EDGE_TOL_S),
            ("heel_off", EDGE_TOL_S),
            ("toe_off", 0.1),
        ):
            assert len(stance.events[name]) == len(true_s[name]), name
            assert np.abs(_errors_s(imu, stance.events[name], true_s[name])).max() <= tol, name


def test_hmm_events_at_the_true_stance_edges_and_inside_the_true_swing():
    # its own short walk: the HMM's fit takes seconds per foot on the walks above
    walk = footnav.simulate("straight", seed=2, rate_hz=100.0, distance_m=10.0)
    detector = footnav.make_pipeline("hmm", "ekf", "independent").detector
    for imu, truth in _feet(walk):
        events = detector.detect(imu).events
        true_s = truth.meta["event_times_s"]
        for name in ("heel_off", "foot_flat"):
            assert len(events[name]) == len(true_s[name]), name
            assert np.abs(_errors_s(imu, events[name], true_s[name])).max() <= EDGE_TOL_S, name
        # each stride's toe-off and heel strike between its true heel-off and foot-flat, in order
        t_to, t_hs = imu.t[events["toe_off"]], imu.t[events["heel_strike"]]
        assert len(t_to) == len(t_hs) == len(true_s["heel_off"])
        assert (true_s["heel_off"] < t_to).all() and (t_to < t_hs).all() and (t_hs < true_s["foot_flat"]).all()


def test_stride_stance_and_swing_times_against_the_true_phases(walk):
    # per stride: swing = from the end of one stance to the start of the next, which in the
    # simulator is heel-off + swing + foot-flat (0.65 s); the stance edges are each within 30 ms
    # (above), so within 60 ms; duration is the stride period (1.1 s) within a sample
    opts = walk.meta["options"]
    true_swing = opts["heel_off_s"] + opts["swing_s"] + opts["foot_flat_s"]
    detector = footnav.make_pipeline("threshold", "ekf", "independent").detector
    for imu, truth in _feet(walk):
        traj = FootTrajectory(
            t=truth.t,
            position=truth.position,
            velocity=truth.velocity,
            quaternion=truth.quaternion,
            position_std=np.zeros_like(truth.position),
            steps=np.empty((0, 2)),
        )
        s = stride_parameters(traj, detector.detect(imu))[1:-1]  # whole strides (not the first / last half ones)
        assert len(s) >= 5
        np.testing.assert_allclose(s["swing_s"], true_swing, atol=2 * EDGE_TOL_S)
        np.testing.assert_allclose(s["duration_s"], opts["stride_period_s"], atol=1.0 / imu.rate_hz + 1e-9)
