"""Online coupled fusion (footnav.pipeline.online_joint): both feet in one joint filter as samples
arrive give the offline fusion's result, common span and all.

footnav.pipeline.online_joint: the live forward estimate of a coupled fusion (the joint
filter's state and position covariance per foot) against the offline joint filter at the same
sample (``smoother="none"``, nothing added to ``position_std`` after the filter).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from online_replay import STEP, _check_equal, _replay, shared_recordings  # tests/online_replay.py

import footnav
from footnav.core.errors import CompositionError, InvalidInputError
from footnav.pipeline import online_joint

#: The coupled fusions that run online, with parameters under which they act often on the
#: simulated walk: range with a bound it crosses (about 250 updates), step-vector as published
#: (the pendulum step length; about 30 updates, 20 suspended while turning), particle
#: (mode="footnav": about 50 updates, each with random draws from its seed).
FUSIONS = {"range": {"max_separation_m": 0.6}, "step-vector": {"step_length": "pendulum"}, "particle": {}}
TIGHT = FUSIONS["range"]


@pytest.fixture(scope="module")
def walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.simulate("rectangle", seed=3, width_m=12, height_m=6)


def _pipe(smoother="step", fusion="range", detector="threshold"):
    return footnav.make_pipeline(
        detector, "ekf", fusion, estimator_params={"smoother": smoother}, fusion_params=FUSIONS[fusion]
    )


def _offline(pipe, left, right):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pipe.run(left, right)


def _check_fusion(off, result, got):
    _check_equal(off, got, result)
    np.testing.assert_allclose(result.path.position, off.path.position, atol=1e-9, rtol=0)
    for key in (
        "constraint_updates",
        "checks",
        "updates",
        "suspended_turning",
        "skipped_rear_foot_moving",
        "step_length_m",
        "pf_updates",
        "span",
    ):
        assert result.meta["fusion"].get(key) == off.meta["fusion"].get(key)


def _acts(off):
    """The fusion changed something: updates applied."""
    meta = off.meta["fusion"]
    return meta.get("constraint_updates", 0) + meta.get("updates", 0) + meta.get("pf_updates", 0)


#: Chunk sizes in turn, mostly single samples: each foot's pushes of one sample, interleaved,
#: at an eighth of the pushes of one sample each (which the range fusion is replayed in).
SINGLES = ((1, 1, 1, 2, 1, 37), (1, 1, 3, 1, 1, 29))


@pytest.mark.parametrize(
    "fusion, size_left, size_right",
    [("range", 1, 1)]
    + [(f, *SINGLES) for f in FUSIONS if f != "range"]
    + [(f, *sizes) for f in FUSIONS for sizes in ((7, 13), (1000, 1000))],
)
def test_chunks_give_the_offline_fusion(walk, size_left, size_right, fusion):
    pipe = _pipe(fusion=fusion)
    off = _offline(pipe, walk.left, walk.right)
    assert _acts(off) > 20
    got, steps, result, _ = _replay(pipe, walk.left, walk.right, size_left, size_right)
    _check_fusion(off, result, got)
    for foot in ("left", "right"):
        mine = [s for s in steps if s.foot == foot]
        np.testing.assert_allclose([s.position for s in mine], getattr(off, foot).footprints, atol=1e-9, rtol=0)
    assert [s.t for s in steps] == sorted(s.t for s in steps)


@pytest.mark.parametrize("fusion", FUSIONS)
def test_feet_on_different_spans_are_each_alone_outside_the_common_one(walk, fusion):
    """The right foot starts 0.3 s before the left and stops 1.5 s before it: its first samples
    and the left foot's last ones are each foot alone, continued from the fused edge."""
    left, right = walk.left.slice(30, walk.left.n_samples), walk.right.slice(0, walk.right.n_samples - 150)
    pipe = _pipe(fusion=fusion)
    off = _offline(pipe, left, right)
    span = off.meta["fusion"]["span"]
    assert span["right"]["start_index"] == 30 and span["left"]["stop_index"] < left.n_samples
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got, _, result, _ = _replay(pipe, left, right, 7, 5)
    _check_fusion(off, result, got)
    assert any("do not share their whole time span" in str(w.message) for w in caught)


@pytest.mark.parametrize("fusion", FUSIONS)
def test_segments_restart_where_the_filter_stands(walk, monkeypatch, fusion):
    """Small segments: many restarts, each carrying the smoother's open step, the samples not yet
    final and the past the fusion reads (step-vector: the rear foot's heel strike); nothing is
    filtered twice and the result is the offline one."""
    monkeypatch.setattr(online_joint, "SEGMENT_SAMPLES", 300)
    restarts = []
    original = online_joint.JointStream._restart
    monkeypatch.setattr(
        online_joint.JointStream, "_restart", lambda self, need: (restarts.append(need), original(self, need))
    )
    pipe = _pipe(fusion=fusion)
    off = _offline(pipe, walk.left, walk.right)
    got, _, result, stream = _replay(pipe, walk.left, walk.right, 7, 5)
    _check_fusion(off, result, got)
    assert len(restarts) >= 5
    assert max(stream.joint.filt.capacity(f) for f in range(2)) < 1000


def test_a_clock_offset_puts_the_feet_on_one_clock_before_they_are_fused(walk):
    """The right sensor's clock runs 12.3 ms behind: with clock_offset_s the stream fuses what
    the offline run fuses on the corrected times."""
    skew = 0.0123
    right = footnav.ImuData(t=walk.right.t - skew, acc=walk.right.acc, gyr=walk.right.gyr)
    pipe = _pipe()
    off = _offline(pipe, walk.left, footnav.ImuData(t=right.t + skew, acc=right.acc, gyr=right.gyr))
    got, _, result, _ = _replay(pipe, walk.left, right, 7, 13, clock_offset_s={"right": skew})
    _check_fusion(off, result, got)


def test_forward_filter_without_smoothing(walk):
    pipe = _pipe(smoother="none")
    off = _offline(pipe, walk.left, walk.right)
    got, _, result, _ = _replay(pipe, walk.left, walk.right, 7, 5)
    _check_fusion(off, result, got)


def test_forward_estimate_is_the_joint_filters(walk):
    stream = _pipe().online(feet=2)
    update = stream.push(left=walk.left.slice(0, 1500), right=walk.right.slice(0, 1500))
    for f, foot in enumerate(("left", "right")):
        fwd = getattr(update, foot).forward
        assert fwd is not None and fwd.position_cov.shape == (3, 3)
        np.testing.assert_array_equal(fwd.position, stream.joint.filt.position(f))
    assert update.left.n_samples > 0 and update.left.stance is not None


def test_memory_is_bounded_without_keep():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = footnav.simulate("rectangle", seed=4, width_m=40, height_m=20)
    stream = _pipe().online(feet=2, keep=False)
    n = 0
    for a in range(0, rec.left.n_samples, 100):
        update = stream.push(left=rec.left.slice(a, a + 100), right=rec.right.slice(a, a + 100))
        n += update.left.n_samples
        for foot, jf in zip(stream.feet, stream.joint.feet):
            assert foot.input.n < 800 and jf.out.n < 500 and foot.out.n < 800
            assert not foot.steps.pending  # the per-foot streams report no steps of their own
        assert stream.joint.filt is None or len(stream.joint.filt.checkpoints) < 1000
    assert stream.close() is None
    assert n + stream.last_update.left.n_samples == rec.left.n_samples


@pytest.mark.parametrize("fusion", FUSIONS)
def test_shared_recordings(shared_data, fusion):
    pipe = _pipe(fusion=fusion, detector="glrt")
    seen = 0
    for rec in shared_recordings(shared_data, ("azure_fgo", "ipol_1-1", "ipol_3-3")):  # 3-3: its time stamps jump
        off = _offline(pipe, rec.left, rec.right)
        for size in (7, 1000):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                got, _, result, _ = _replay(pipe, rec.left, rec.right, size, rate_hz=rec.left.rate_hz)
            _check_fusion(off, result, got)
        seen += 1
    if not seen:
        pytest.skip("no shared two-foot recording found")


def test_what_cannot_run_online_is_refused(walk):
    with pytest.raises(CompositionError, match="needs both feet"):
        _pipe().online(feet=1)
    for fusion, params, what in (("particle", {"mode": "paper"}, "mode='paper' is offline only"),):
        pipe = footnav.make_pipeline("threshold", "ekf", fusion, estimator_params=STEP, fusion_params=params)
        with pytest.raises(CompositionError, match=what):
            pipe.online(feet=2)
    stream = _pipe().online(feet=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the right foot does not start at standstill
        stream.push(left=walk.left.slice(0, 200), right=walk.right.slice(2900, 3106))
        with pytest.raises(InvalidInputError, match="share no time span"):
            stream.close()


@pytest.mark.parametrize("size_left, size_right", [(7, 13), (1000, 1000)])
def test_step_vector_calibrated_at_the_first_standstill_online_is_the_offline_fusion(walk, size_left, size_right):
    """calibration="standstill" online: each foot's accelerometer scale from its first stance,
    applied to what its filters take (detection reads the samples as given, as offline): the
    offline fusion, its calibration records and all, assembled from the stream (no rerun)."""
    pipe = footnav.make_pipeline(
        "threshold",
        "ekf",
        "step-vector",
        estimator_params=STEP,
        fusion_params={"step_length": "pendulum", "calibration": "standstill"},
    )
    scaled = [
        footnav.ImuData(t=imu.t, acc=imu.acc * k, gyr=imu.gyr) for imu, k in ((walk.left, 1.02), (walk.right, 0.99))
    ]
    off = _offline(pipe, *scaled)
    cal = off.meta["fusion"]["calibration"]
    assert cal["left"]["acc_scale"] == pytest.approx(1 / 1.02, rel=2e-3) and cal["right"]["acc_scale"] == pytest.approx(
        1 / 0.99, rel=2e-3
    )
    got, _, result, stream = _replay(pipe, *scaled, size_left, size_right)
    assert not stream.rerun  # the stream's own samples: exact
    _check_fusion(off, result, got)
    assert result.meta["fusion"]["calibration"] == cal


def test_step_vector_fits_the_leg_length_online_on_the_steps_so_far(walk):
    """step_length="fitted" (its default) online: no update before LEG_FIT_MIN_STEPS straight
    steps; then the median of the ratios of the steps whose stance began by the update, on each
    foot's own solution. The first fitted value is the offline single-foot runs' median of the
    same steps (until the first update the joint filter is the two single-foot filters); the
    live steps are the same in any chunks; close() is the offline run."""
    from footnav.fusion.joint import FeetView, start_joint
    from footnav.fusion.pendulum import LEG_FIT_MIN_STEPS

    pipe = footnav.make_pipeline("threshold", "ekf", "step-vector", estimator_params=STEP)
    off = _offline(pipe, walk.left, walk.right)
    runs = {}
    for sizes in (SINGLES, (7, 13), (1000, 1000)):
        _, steps, result, stream = _replay(pipe, walk.left, walk.right, *sizes)
        assert stream.rerun  # the fit so far is not the whole walk's: close() reruns offline
        _check_equal(off, {f: getattr(off, f).position for f in ("left", "right")}, result)
        runs[sizes] = (steps, result.meta["online"]["fusion"])
    live = runs[(7, 13)][1]
    for steps, meta in runs.values():  # the same live steps and fit, however chunked
        assert meta == live
        np.testing.assert_array_equal([s.position for s in steps], [s.position for s in runs[(7, 13)][0]])

    fit = live["leg_length_fit"]
    per = fit["per_update"]
    assert fit["steps_fitted"] >= LEG_FIT_MIN_STEPS and fit["updates_waiting"] > 0
    assert len(per["t_s"]) == live["updates"] == off.meta["fusion"]["updates"] - fit["updates_waiting"]
    # the reference: the offline fusion's own ratios on its single-foot runs
    fusion = pipe.fusion
    stances = (off.stance_left, off.stance_right)
    _, singles = start_joint(
        pipe.estimator, walk.left, stances[0], walk.right, stances[1], fusion.step_width_m, return_singles=True
    )
    ratios = fusion.step_ratios(FeetView.of((walk.left, walk.right), stances), singles)
    first = [r for t, r in ratios if t <= per["t_s"][0]]
    assert len(first) >= LEG_FIT_MIN_STEPS
    assert per["leg_length_m"][0] == pytest.approx(float(np.median(first)), rel=1e-9)
    assert per["leg_length_m"][-1] == pytest.approx(off.meta["fusion"]["leg_length_m"], rel=0.01)
    # live footprints: a few fewer updates at the start than offline, centimetres apart
    for foot in ("left", "right"):
        mine = np.array([s.position for s in runs[(7, 13)][0] if s.foot == foot])
        ref = getattr(off, foot).footprints
        assert len(mine) == len(ref) and 0 < np.abs(mine - ref).max() < 0.05


def test_a_plugin_coupled_fusion_without_needs_two_feet_is_refused_on_one_foot():
    from footnav.fusion.range_constraint import RangeConstraintFusion

    class OneFootRange(RangeConstraintFusion):
        name = "one-foot-range"
        needs_two_feet = False

    pipe = footnav.make_pipeline("threshold", footnav.make_estimator("ekf", smoother="step"), OneFootRange())
    with pytest.raises(CompositionError, match="needs feet=2"):
        pipe.online(feet=1)


EST = {"smoother": "none", "vertical": "free", "heading_drift_in_std": False}


@pytest.fixture(scope="module")
def small_walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.simulate("rectangle", seed=3, width_m=8, height_m=4)


@pytest.mark.parametrize(
    "fusion, params", [("range", {"max_separation_m": 0.6}), ("step-vector", {"step_length": "pendulum"})]
)
def test_joint_forward_covariance_is_the_offline_filters_at_the_same_sample(small_walk, fusion, params):
    # mutant: online-joint-forward-cov-block
    pipe = footnav.make_pipeline("threshold", "ekf", fusion, estimator_params=EST, fusion_params=params)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = pipe.run(small_walk.left, small_walk.right)
        stream = pipe.online(feet=2)
        update = stream.push(left=small_walk.left.slice(0, 1500), right=small_walk.right.slice(0, 1500))
    for foot, imu in (("left", small_walk.left), ("right", small_walk.right)):
        fwd, traj = getattr(update, foot).forward, getattr(off, foot)
        k = int(np.searchsorted(imu.t, fwd.t))
        assert imu.t[k] == fwd.t and k > 1000
        np.testing.assert_allclose(fwd.position, traj.position[k], atol=1e-8)
        np.testing.assert_allclose(np.sqrt(np.diag(fwd.position_cov)), traj.position_std[k], rtol=1e-7, atol=1e-12)
