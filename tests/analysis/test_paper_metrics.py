"""The papers' metrics in footnav.evaluate: start alignment, waypoint errors, E_s / E_p, feet DTW,
mean +- std over seeds -- each against a hand-computed case or the simulator's truth."""

import functools

import numpy as np
import pytest

import footnav
from footnav.analysis import metrics


def _turn(p, yaw):
    c, s = np.cos(yaw), np.sin(yaw)
    return p @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T


def test_align_at_start_undoes_a_known_turn_and_shift():
    t = np.linspace(0, 20, 401)
    ref = np.column_stack([t, np.sin(t / 3), 0.01 * t])
    est = _turn(ref - ref[0], -0.7) + [5.0, -2.0, 1.0]
    aligned = metrics.align_at_start(est, ref).aligned
    np.testing.assert_allclose(aligned, ref, atol=1e-12)


def test_align_at_start_uses_only_the_start():
    # drift after the first metres must stay visible (a whole-walk fit would spread it)
    t = np.linspace(0, 20, 401)
    ref = np.column_stack([t, np.zeros_like(t), np.zeros_like(t)])
    est = ref.copy()
    est[:, 1] += np.where(t > 5, 0.1 * (t - 5), 0.0)  # 1.5 m sideways by the end
    aligned = metrics.align_at_start(est, ref, distance_m=2.0).aligned
    assert aligned[-1, 1] == pytest.approx(1.5, abs=1e-9)
    assert metrics.rigid_align(est, ref).aligned[-1, 1] < 1.0


def test_waypoint_errors_count_every_pass():
    # out and back along x: the waypoint at x = 5 is passed twice, x = 10 once (the turn)
    x = np.concatenate([np.linspace(0, 10, 101), np.linspace(10, 0, 101)[1:]])
    ref = np.column_stack([x, np.zeros_like(x), np.zeros_like(x)])
    est = ref + [0.0, 0.3, 0.0]
    est[100:, 1] = 0.5  # further off on the way back
    wp = metrics.waypoint_errors(est, ref, [[5.0, 0.1], [10.0, 0.0], [50.0, 0.0]], radius_m=1.0)
    assert list(wp.waypoint) == [0, 0, 1]
    np.testing.assert_allclose(wp.errors_m, [0.3, 0.5, 0.5])
    assert ref[wp.index[0], 0] == pytest.approx(5.0) and ref[wp.index[1], 0] == pytest.approx(5.0)
    assert wp.mean_m == pytest.approx(1.3 / 3) and wp.max_m == pytest.approx(0.5)


@pytest.fixture(scope="module")
def loop_report():
    rec = footnav.simulate("rectangle", seed=2, width_m=20.0, height_m=10.0)
    return rec, footnav.evaluate(footnav.make_pipeline("threshold", "ekf", "range"), rec)


def test_end_error_of_a_closed_walk_is_its_return_error(loop_report):
    # the truth returns to its start, so the start-aligned end error is ||p_end - p_start||
    # of the estimate: a rotation keeps lengths
    rec, rep = loop_report
    traj = rep.results[(rec.name, "threshold+ekf+range")].left
    for dims in (2, 3):
        direct = np.linalg.norm(traj.position[-1, :dims] - traj.position[0, :dims])
        assert rep.value(f"end_error_{dims}d") == pytest.approx(direct, abs=1e-6)
        assert rep.value(f"loop_closure_{dims}d") == pytest.approx(direct, abs=1e-9)
    assert rep.value("end_error_3d") >= rep.value("end_error_2d")


def test_feet_metrics_of_a_two_foot_run(loop_report):
    rec, rep = loop_report
    res = rep.results[(rec.name, "threshold+ekf+range")]
    assert rep.value("final_separation", "both") == pytest.approx(
        np.linalg.norm(res.left.position[-1] - res.right.position[-1])
    )
    # the feet walk side by side 0.2 m apart: their DTW distance is about the step width
    assert 0.05 < rep.value("dtw_distance_feet", "both") < 0.5
    # the rectangle's four turn apexes and its end are marked; each passed once
    assert np.isfinite(rep.value("waypoint_error_mean")) and rep.value("waypoint_error_max") >= rep.value(
        "waypoint_error_mean"
    )


def test_summary_is_mean_and_sample_std_over_seeds():
    runs = [functools.partial(footnav.simulate, "straight", seed=s, distance_m=10.0) for s in range(3)]
    rep = footnav.evaluate_many(footnav.make_pipeline(), runs)
    values = [m.value for m in rep.metrics if m.name == "end_error_3d" and m.foot == "left"]
    assert len(values) == 3
    row = next(r for r in rep.summary() if r["name"] == "end_error_3d" and r["foot"] == "left")
    assert row["n"] == 3
    assert row["mean"] == pytest.approx(np.mean(values)) and row["std"] == pytest.approx(np.std(values, ddof=1))
    assert "end_error_3d" in rep.summary_text() and "+-" in rep.summary_text()
