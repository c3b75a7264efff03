"""Coupled two-foot fusions built on the joint filter: step vector (Zhao et al. 2019) and range constraint."""

import numpy as np
import pytest

import footnav
from footnav import CompositionError, StanceResult
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.range_constraint import RangeConstraintFusion
from footnav.fusion.step_vector import StepVectorFusion, pendulum_step_length

# a consumer-grade gyro (bias walk 10x the simulator's default) so that the feet drift apart as
# in seed 001's experiments
DRIFTY = {"gyr_bias_walk_radps2_sqrthz": 1e-4}


def _fuse(fusion, rec):
    det = footnav.make_detector("threshold")
    return fusion.fuse(EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))


def _es_ep(res, rec):
    es = float(np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]))
    ep = [
        float(np.linalg.norm(tr.position[-1, :2] - truth.position[-1, :2]))
        for tr, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right))
    ]
    return es, ep


def test_pendulum_step_length_hand_computed():
    q1 = footnav.nav.quaternion.from_euler(0.0, np.radians(-20.0), 0.3)
    q2 = footnav.nav.quaternion.from_euler(0.0, np.radians(40.0), 0.3)
    # theta = 60 deg about one axis: S = 2 l sin(30 deg) = l
    assert pendulum_step_length(q1, q2, 0.9) == pytest.approx(0.9, rel=1e-12)
    assert pendulum_step_length(q1, q1, 0.9) == pytest.approx(0.0, abs=1e-7)


@pytest.mark.parametrize(
    "scenario, opts",
    [
        ("straight", {"distance_m": 100.0}),
        ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}),
        ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"}),
    ],
)
def test_step_vector_keeps_the_feet_together_and_the_walk_on_course(scenario, opts):
    es_ind, es_sv, ep_ind, ep_sv = [], [], [], []
    for seed in range(5):
        rec = footnav.simulate(scenario, seed=seed, **DRIFTY, **opts)
        ind, sv = _fuse(IndependentFusion(), rec), _fuse(StepVectorFusion(), rec)
        for res, es_list, ep_list in ((ind, es_ind, ep_ind), (sv, es_sv, ep_sv)):
            es, ep = _es_ep(res, rec)
            es_list.append(es)
            ep_list.extend(ep)
        assert sv.meta["updates"] > 50 and sv.meta["skipped_rear_foot_moving"] == 0
    # seed 001 Table I: E_s 7.33 -> 0.42 m, 33 -> 0.37 m. The feet end 0.2 m apart, which bounds
    # E_s from below: the separation *error* is what must shrink 5x (measured 1.25 -> 0.02 m
    # straight, 13.2 -> 0.02 m rectangles; E_s itself 1.45 -> 0.22, 13.4-14.5 -> 0.22-0.23 m)
    err_ind, err_sv = np.abs(np.array(es_ind) - 0.2), np.abs(np.array(es_sv) - 0.2)
    assert np.mean(err_sv) * 5 <= np.mean(err_ind)
    assert np.mean(es_sv) * (5 if scenario == "rectangle" else 3) <= np.mean(es_ind)
    # the pair walks on the mean of two independent heading drifts (measured 1.16 -> 0.99 m
    # straight, 9.2-9.8 -> 6.2-6.9 m rectangles)
    assert np.mean(ep_sv) < np.mean(ep_ind)


def test_step_vector_suspends_updates_in_turns():
    rec = footnav.simulate("rectangle", seed=0, width_m=20.0, height_m=10.0)
    res = _fuse(StepVectorFusion(), rec)
    # four corners of about three steps each, per foot
    assert 8 <= res.meta["suspended_turning"] <= 40


def test_fitted_leg_length_gets_the_walk_length_and_the_paper_one_is_used_as_given():
    rec = footnav.simulate("straight", seed=0, distance_m=30.0)
    fitted = _fuse(StepVectorFusion(step_length="fitted"), rec)
    assert fitted.meta["step_length"] == "fitted"
    assert 1.5 < fitted.meta["leg_length_m"] < 3.5  # the foot turns less than the leg: l > leg
    paper = _fuse(StepVectorFusion(step_length="pendulum", leg_length_m=0.9), rec)
    assert paper.meta["leg_length_m"] == 0.9 and paper.meta["step_length"] == "pendulum"
    length = lambda res: float(np.linalg.norm(res.path.position[-1, :2] - res.path.position[0, :2]))  # noqa: E731
    assert abs(length(fitted) - 30.0) < abs(length(paper) - 30.0)


@pytest.mark.parametrize("fusion", [StepVectorFusion, RangeConstraintFusion])
def test_one_foot_is_refused_before_running(fusion):
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(CompositionError, match="needs both feet|two feet"):
        footnav.make_pipeline("threshold", "ekf", fusion.name).run(rec.left)


def test_range_constraint_bounds_the_separation():
    rec = footnav.simulate("rectangle", seed=0, width_m=40.0, height_m=20.0, **DRIFTY)
    ind = _fuse(IndependentFusion(), rec)
    bound = 1.0
    res = _fuse(RangeConstraintFusion(max_separation_m=bound), rec)
    sep_ind = np.linalg.norm(ind.left.position - ind.right.position, axis=1)
    assert sep_ind.max() > 2 * bound  # without it the feet drift apart
    sep = np.linalg.norm(res.left.position - res.right.position, axis=1)
    # checked every 50 ms: between checks the feet may pass the bound by a stride's worth at most
    assert sep.max() < bound + 0.6
    assert res.meta["constraint_updates"] > 0
    es_ind, _ = _es_ep(ind, rec)
    es, _ = _es_ep(res, rec)
    assert es < es_ind


def test_fusions_need_a_stepable_estimator():
    class NoFilter(footnav.core.component.FootEstimator):
        name = "no-filter"

        def __init__(self):
            pass

    rec = footnav.simulate("straight", distance_m=5.0)
    st = StanceResult(rec.truth_left.stance)
    with pytest.raises(CompositionError, match="step-able"):
        StepVectorFusion().fuse(NoFilter(), rec.left, st, rec.right, StanceResult(rec.truth_right.stance))


@pytest.mark.parametrize("fusion", ["range", "step-vector", "dtw", "particle"])
def test_coupled_fusion_with_an_estimator_without_a_filter_fails_before_detecting(fusion, monkeypatch):
    rec = footnav.simulate("straight", distance_m=5.0)
    pipe = footnav.make_pipeline("threshold", "madgwick", fusion)

    def never(*args, **kwargs):  # the check must come before any work
        raise AssertionError("the detector ran")

    monkeypatch.setattr(pipe.detector, "detect_pair", never)
    with pytest.raises(CompositionError, match="step-able"):
        pipe.run(rec)
