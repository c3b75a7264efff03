"""Online mode (footnav.pipeline.online): a recording pushed in chunks gives the offline causal run."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from online_replay import STEP, _check_equal, _chunks, _replay, shared_recordings  # tests/online_replay.py

import footnav
from footnav.core.errors import CompositionError, InvalidInputError
from footnav.core.types import ImuData
from footnav.pipeline import online_foot, online_steps


@pytest.fixture(scope="module")
def walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.simulate("rectangle", seed=3, width_m=12, height_m=6)


@pytest.mark.parametrize(
    "size, detector", [(1, "threshold"), (7, "threshold"), (1000, "threshold"), (7, "glrt"), (1000, "glrt")]
)
def test_chunks_give_the_offline_causal_run(walk, size, detector):
    pipe = footnav.make_pipeline(detector, "ekf", "independent", estimator_params=STEP)
    off = pipe.run(walk.left, walk.right)
    # chunks of 1000 samples: a foot's next chunk comes 10 s after the other's
    got, steps, result, _ = _replay(pipe, walk.left, walk.right, size, max_wait_s=15.0)
    _check_equal(off, got, result)
    # one closed step per stance of each foot, in time order, at the stance's last sample
    for foot in ("left", "right"):
        ref = getattr(off, foot)
        mine = [s for s in steps if s.foot == foot]
        assert len(mine) == len(ref.steps)
        np.testing.assert_allclose([s.t for s in mine], ref.t[ref.steps[:, 1] - 1])
        np.testing.assert_allclose([s.position for s in mine], ref.footprints, atol=1e-9)
    # in time order across the feet; none waited for the other foot beyond max_wait_s
    assert [s.t for s in steps] == sorted(s.t for s in steps)
    assert not any(s.late for s in steps)


def test_bias_states_and_restarted_segments(monkeypatch):
    """Small filter segments (restarts from step-end checkpoints), a standstill longer than
    the step smoother's buffer (4096 samples: cut there), the 15-state filter."""
    monkeypatch.setattr(online_foot, "SEGMENT_SAMPLES", 300)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = footnav.simulate("straight", seed=5, distance_m=8, standstill_s=45.0)
    pipe = footnav.make_pipeline("glrt", "ekf", "independent", estimator_params={**STEP, "bias_states": True})
    off = pipe.run(rec.left, rec.right)
    for size in (7, 333):
        got, _, result, _ = _replay(pipe, rec.left, rec.right, size)
        _check_equal(off, got, result)


def test_clock_skewed_feet_in_chunks_of_different_sizes(walk):
    """The right foot on its own clock (123.4 s ahead), both arriving in other chunk sizes."""
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    off = pipe.run(walk.left, walk.right)
    right = footnav.ImuData(t=walk.right.t + 123.4, acc=walk.right.acc, gyr=walk.right.gyr)
    got, steps, result, _ = _replay(pipe, walk.left, right, 13, 211, clock_offset_s={"right": -123.4}, max_wait_s=5.0)
    _check_equal(off, got, result)
    timely = [s.t for s in steps if not s.late]
    assert timely == sorted(timely)
    assert not any(s.late for s in steps)


def test_a_clock_map_from_exchanges_puts_the_right_foot_on_the_master_clock():
    """Offset and drift, mapped by the ClockMap of the simulator's message exchanges: the stream
    gives the offline run of the same map (the sync stage), sample for sample."""
    from footnav.nav.clock_sync import fit_clock
    from footnav.pipeline.sync import ClockSync

    rec = footnav.simulate(
        "straight", seed=2, distance_m=15.0, clock_offset_s=40.0, clock_drift_ppm=300.0, clock_exchanges=40
    )
    ex = rec.meta["clock_exchanges"]
    clock = fit_clock(ex["tm1"], ex["ti"], ex["tm2"])
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    synced = ClockSync("exchanges").align(rec.left, rec.right, exchanges={"right": ex})
    off = pipe.run(synced.left, synced.right)
    got, steps, result, _ = _replay(pipe, rec.left, rec.right, 17, 90, clocks={"right": clock}, max_wait_s=5.0)
    _check_equal(off, got, result)
    assert not any(s.late for s in steps)
    with pytest.raises(footnav.InvalidParameterError, match="both a clock_offset_s and a clock map"):
        pipe.online(clocks={"right": clock}, clock_offset_s={"right": 1.0})
    with pytest.raises(footnav.InvalidParameterError, match="ClockMap"):
        pipe.online(clocks={"right": 0.5})


def test_a_silent_foot_holds_steps_at_most_max_wait(walk):
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    stream = pipe.online(feet=2, max_wait_s=1.0)
    steps = []
    for chunk in _chunks(walk.left, 50):
        steps += stream.push(left=chunk).steps
    assert steps and all(s.late and s.foot == "left" for s in steps)
    assert walk.left.t[-1] - steps[-1].t < 1.0 + footnav.make_detector("threshold").latency_s + 3.0


def test_shared_recordings(shared_data):
    pipe = footnav.make_pipeline("glrt", "ekf", "independent", estimator_params=STEP)
    for rec in shared_recordings(shared_data, ("azure_fgo", "gaitmap", "ipol_1-1", "pyshoe_2017-11-22-11-22-03")):
        off = pipe.run(rec.left, rec.right)
        for size in (7, 1000):
            got, _, result, _ = _replay(pipe, rec.left, rec.right, size, rate_hz=rec.left.rate_hz)
            _check_equal(off, got, result, feet=("left",) if rec.right is None else ("left", "right"))


def test_latency_one_step_plus_the_detectors(walk):
    """A step's samples are final once the next stance's end is detected: at most the detector's
    latency (plus 3 samples of the stream's own margin) after that stance's last sample arrives."""
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    _, _, _, stream = _replay(pipe, walk.left, None, 1)
    foot = stream.feet[0]
    latency = np.array([newest - end for end, newest in foot.step_final_at])
    bound = math.ceil(pipe.detector.latency_s * walk.left.rate_hz) + 3
    assert len(latency) > 10 and latency.max() <= bound


def test_memory_is_bounded_without_keep():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = footnav.simulate("rectangle", seed=4, width_m=40, height_m=20)
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    stream = pipe.online(feet=2, keep=False)
    n = 0
    for chunk_l, chunk_r in zip(_chunks(rec.left, 100), _chunks(rec.right, 100)):
        update = stream.push(left=chunk_l, right=chunk_r)
        n += update.left.n_samples
        for foot in stream.feet:
            assert foot.input.n < 500 and foot.out.n < 500
            # the arrays too, not only the rows held (_Grow drops by moving an offset)
            assert len(foot.input.arrays[0]) < 2048 and len(foot.out.arrays[0]) < 2048
    assert stream.close() is None
    assert n + stream.last_update.left.n_samples == rec.left.n_samples


def test_grow_buffer_appends_and_drops_in_bounded_arrays():
    rng = np.random.default_rng(5)
    grow = online_foot._Grow([((), np.float64), ((3,), np.float64), ((), np.bool_)])
    held = np.empty(0)  # the rows the buffer must hold, by global index grow.start ...
    total = 0
    for _ in range(3000):
        m = int(rng.integers(0, 300))
        t = np.arange(total, total + m, dtype=float)
        grow.append(t, np.repeat(t[:, None], 3, axis=1), t % 2 == 0)
        total += m
        held = np.concatenate([held, t])
        cut = int(rng.integers(grow.start, grow.end + 1))
        grow.drop_before(cut)
        held = held[cut - (total - len(held)) :] if cut > total - len(held) else held
        assert grow.end == total and grow.n == len(held)
        t_rows, acc_rows, even = grow.rows(grow.start, grow.end)
        np.testing.assert_array_equal(t_rows, held)
        np.testing.assert_array_equal(acc_rows[:, 2], held)
        np.testing.assert_array_equal(even, held % 2 == 0)
        if grow.n:
            assert grow.last() == held[-1]
        assert len(grow.arrays[0]) <= max(64, 8 * (grow.n + 300))


def test_runs_are_the_stance_intervals():
    rng = np.random.default_rng(6)
    for n in [0, 1, 2, 3, 10, 200] * 50:
        mask = rng.random(n) < rng.random()
        assert online_steps.stance_runs(mask) == [tuple(map(int, r)) for r in footnav.core.types.stance_intervals(mask)]


def test_time_stamps_within_a_chunk_are_checked(walk):
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    stream = pipe.online(feet=1)
    stream.push(left=(walk.left.t[:50], walk.left.acc[:50], walk.left.gyr[:50]))
    t = walk.left.t[50:60].copy()
    t[4] = t[3]
    with pytest.raises(InvalidInputError, match=r"duplicate time stamp .* \(same as sample 53\)") as info:
        stream.push(left=(t, walk.left.acc[50:60], walk.left.gyr[50:60]))
    assert info.value.index == 54 and info.value.field == "t"
    # the offline run's message for the same samples
    with pytest.raises(InvalidInputError) as offline:
        ImuData.from_arrays(np.concatenate([walk.left.t[:50], t]), walk.left.acc[:60], walk.left.gyr[:60])
    assert str(offline.value) == str(info.value)


def test_forward_estimate_and_inputs(walk):
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    stream = pipe.online(feet=1)
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame(
        {
            "t": walk.left.t[:400],
            **{f"acc_{a}": walk.left.acc[:400, i] for i, a in enumerate("xyz")},
            **{f"gyr_{a}": walk.left.gyr[:400, i] for i, a in enumerate("xyz")},
        }
    )
    stream.push(left=frame)
    update = stream.push(left={"t": walk.left.t[400], "acc": walk.left.acc[400], "gyr": walk.left.gyr[400]})
    fwd = update.left.forward
    assert fwd is not None and fwd.position_cov.shape == (3, 3) and fwd.t <= walk.left.t[400]
    with pytest.raises(InvalidInputError, match="time goes backwards"):
        stream.push(left=(walk.left.t[10:12], walk.left.acc[10:12], walk.left.gyr[10:12]))
    with pytest.raises(InvalidInputError, match="one-foot stream"):
        stream.push(right=(walk.left.t[401:402], walk.left.acc[401:402], walk.left.gyr[401:402]))


def test_declared_latencies():
    assert footnav.make_detector("threshold").latency_s == pytest.approx(0.04 / 2 + 0.05 + 0.2)
    glrt_any = footnav.make_detector("glrt", combine="any")
    assert glrt_any.latency_s == pytest.approx(glrt_any.window_s + glrt_any.min_stance_s + glrt_any.min_swing_s)
    adaptive = footnav.make_detector("adaptive")
    assert adaptive.latency_s == pytest.approx(adaptive.online_lookahead_s + adaptive.online_block_s)
    assert footnav.make_detector("hmm").latency_s is None
    # dual-gait: the flat zone's 0.27 s, the standing rule's 0.5 s, two find_peaks distances, the block
    dual = footnav.make_detector("dual-gait", standing_s=0.2)  # then the heel strike's search decides
    assert footnav.make_detector("dual-gait").latency_s == pytest.approx(0.27 + 0.5 + 2 * 0.4 + 0.25)
    assert dual.latency_s == pytest.approx(0.27 + 0.3 + 2 * 0.4 + 0.25)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"detector": "hmm", "estimator_params": STEP}, "latency_s = None"),
        ({"detector": "threshold", "estimator_params": {"closed_loop": True}}, "closed_loop=True is offline only"),
        ({"detector": "threshold", "estimator_params": STEP, "fusion": "dtw"}, "offline only: it averages"),
        ({"detector": "threshold", "estimator": "madgwick"}, "step-able filter"),
    ],
)
def test_offline_only_components_are_refused(kwargs, match):
    pipe = footnav.make_pipeline(**kwargs)
    with pytest.raises(CompositionError, match=match):
        pipe.online(feet=2)


def test_warnings_raised_while_pushing_are_in_the_result(walk):
    """A warning raised by a push (here the filter's start: the foot is walking when the
    recording starts) is shown then and recorded in close()'s meta, once."""
    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    left = walk.left.slice(800, walk.left.n_samples)
    with pytest.warns(footnav.DataQualityWarning, match="does not start at standstill"):
        _, _, result, stream = _replay(pipe, left, None, 50)
    texts = [w for w in result.meta["warnings"] if "does not start at standstill" in w]
    assert len(texts) == 1 and stream.warnings == result.meta["warnings"]


def test_close_records_the_offline_runs_checks_of_the_whole_walk(walk):
    """The stance self-check and the saturation found late in the walk: offline they see the whole
    recording, and a stream that kept every sample runs them on it at close, with the same records."""
    from footnav.core.types import ImuData

    pipe = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params=STEP)
    t, acc, gyr = walk.left.t, walk.left.acc.copy(), walk.left.gyr.copy()
    late = slice(len(t) - 600, len(t))  # the last 6 s: beyond the online window of the first seconds
    fs = np.radians(1000.0)  # a common full scale: the late swings beyond it, held flat at it
    assert np.abs(gyr[: late.start]).max() < fs
    gyr[late] = np.clip(gyr[late] * (1.3 * fs / np.abs(gyr[late]).max()), -fs, fs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        clipped = ImuData.from_arrays(t, acc, gyr)
        offline = pipe.run(clipped)
    assert "clipped" in clipped.meta
    stream = pipe.online(feet=1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for a in range(0, len(t), 250):
            stream.push(left=(t[a : a + 250], acc[a : a + 250], gyr[a : a + 250]))
        result = stream.close()
    assert result.meta["input"]["left"]["clipped"] == clipped.meta["clipped"]
    # said once, when the saturated samples arrived (not only at close: a stream without keep says it too)
    assert sum("full scale" in str(w.message) for w in caught) == 1
    assert result.meta["stance_check"] == offline.meta["stance_check"]
    assert result.meta["complete"] is True and result.meta["ended_by"] == "close"
