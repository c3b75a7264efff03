import numpy as np
import pytest

import footnav
from footnav.analysis import metrics
from footnav.analysis.batch import evaluate_many
from footnav.analysis.evaluation import evaluate, trajectory_at
from footnav.core.errors import FootnavError, MetricNotFoundError


@pytest.fixture(scope="module")
def loop():
    return footnav.simulate("rectangle", seed=4, width_m=12.0, height_m=6.0)


def test_metrics_equal_direct_computation(loop):
    pipe = footnav.make_pipeline()
    report = evaluate(pipe, loop, pipeline_name="p")
    res = report.results[(loop.name, "p")]
    for foot, traj, truth in (("left", res.left, loop.truth_left), ("right", res.right, loop.truth_right)):
        assert report.value("ate_2d", foot) == pytest.approx(metrics.ate_rmse(traj.position, truth.position, dims=2))
        assert report.value("loop_closure_2d", foot) == pytest.approx(metrics.loop_closure_error(traj.position).error_m)
        assert report.value("stance_f1", foot) == pytest.approx(
            metrics.sample_scores(res.stance_left.mask if foot == "left" else res.stance_right.mask, truth.stance).f1
        )
        assert report.value("steps_missed", foot) == 0 and report.value("steps_false", foot) == 0
    assert report.value("final_separation", "both") == pytest.approx(
        float(np.linalg.norm(res.left.position[-1] - res.right.position[-1]))
    )


def test_one_foot_recording_has_no_two_foot_metrics(loop):
    one = footnav.Recording(left=loop.left, truth_left=loop.truth_left, name="one")
    report = evaluate(footnav.make_pipeline(), one)
    assert {m.foot for m in report.metrics} == {"left", "both"}
    with pytest.raises(MetricNotFoundError) as exc:
        report.value("final_separation", "both")
    # footnav's own error, still a KeyError for code that catches that; the message unquoted
    assert isinstance(exc.value, FootnavError) and isinstance(exc.value, KeyError)
    assert str(exc.value) == "no metric 'final_separation' for foot 'both'"


def test_many_pipelines_side_by_side(loop):
    pipes = [
        ("loose", footnav.make_pipeline(estimator_params={"zupt_std_mps": 0.5})),
        ("tight", footnav.make_pipeline(estimator_params={"zupt_std_mps": 0.01})),
    ]
    report = evaluate_many(pipes, [loop])
    text = report.to_text().splitlines()
    assert text[0].split()[-2:] == ["loose", "tight"]
    # each pipeline's column is its own: a ZUPT of 0.5 m/s hardly constrains the velocity, so the
    # tight one is better on both feet (measured 5.9 -> 4.2 mm left, 23.6 -> 4.8 mm right)
    for foot in ("left", "right"):
        assert report.value("ate_2d", foot, pipeline="tight") < report.value("ate_2d", foot, pipeline="loose")
    csv_lines = report.to_csv().splitlines()
    assert csv_lines[0] == "recording,pipeline,foot,name,value,unit"
    assert len(csv_lines) == 1 + len(report.metrics)


def test_trajectory_at_interpolates_inside_span_only(loop):
    traj = footnav.make_pipeline().run(loop.left).left
    t = np.array([traj.t[0] - 1.0, traj.t[10], 0.5 * (traj.t[10] + traj.t[11]), traj.t[-1] + 1.0])
    pos, inside = trajectory_at(traj, t)
    np.testing.assert_array_equal(inside, [False, True, True, False])
    assert pos.shape == (2, 3)
    np.testing.assert_allclose(pos[0], traj.position[10])
    np.testing.assert_allclose(pos[1], 0.5 * (traj.position[10] + traj.position[11]))


def test_footprint_truth_reports_footprint_errors_not_ate(loop):
    # footprint truth as the gait-driven reader builds it: positions at a few stance samples
    from footnav.core.types import FootTruth, stance_intervals

    runs = stance_intervals(loop.truth_left.stance)
    idx = ((runs[:, 0] + runs[:, 1]) // 2)[::2]
    truth = FootTruth(
        t=loop.left.t[idx],
        position=loop.truth_left.position[idx] * [1.0, 1.0, 0.0],
        events={"footprint": idx},
        frame="footprints",
    )
    rec = footnav.Recording(left=loop.left, truth_left=truth, name="fp")
    report = evaluate(footnav.make_pipeline(), rec, pipeline_name="p")
    res = report.results[("fp", "p")]
    direct = metrics.footprint_errors(res.left.position, truth.position, index=idx)
    assert report.value("footprint_rmse") == pytest.approx(direct.rmse_m)
    assert report.value("footprint_final_error") == pytest.approx(direct.final_m)
    assert report.value("footprint_rmse") < 0.5
    with pytest.raises(KeyError):
        report.value("ate_2d")


def test_labelled_swings_truth_reports_step_f1_inside_the_boundaries(loop):
    # IPOL-style truth: swings = gaps between the simulator's stances, labelled only inside a
    # span that leaves out the first and last stances; stance False outside the span
    from footnav.core.types import FootTruth, stance_intervals

    runs = stance_intervals(loop.truth_left.stance)
    swings = np.column_stack((runs[:-1, 1], runs[1:, 0]))
    start, end = int(swings[1, 0]), int(swings[-2, 1])
    labelled = np.zeros(len(loop.left.t), dtype=bool)
    labelled[start:end] = True
    truth = FootTruth(
        t=np.empty(0),
        position=np.empty((0, 3)),
        stance=loop.truth_left.stance & labelled,
        events={"toe_off": swings[:, 0], "heel_strike": swings[:, 1]},
        frame="gait_events",
        meta={"labelled": labelled, "trial_boundaries": (start, end)},
    )
    rec = footnav.Recording(left=loop.left, truth_left=truth, name="sw")
    report = evaluate(footnav.make_pipeline(), rec, pipeline_name="p")
    mask = report.results[("sw", "p")].stance_left.mask
    direct = metrics.step_detection_from_swings(
        mask, swings, (start, end), tolerance_samples=round(0.1 * loop.left.rate_hz)
    )
    assert report.value("step_f1") == pytest.approx(direct.f1)
    assert report.value("steps_found") == direct.found and direct.found == len(runs) - 4  # stances between swings 1..22
    assert report.value("steps_missed") == direct.missed and report.value("steps_false") == direct.false
    assert report.value("stance_f1") == pytest.approx(metrics.sample_scores(mask[labelled], truth.stance[labelled]).f1)
    for name in ("ate_2d", "ate_3d", "footprint_rmse"):
        with pytest.raises(KeyError):
            report.value(name)
