"""Bad input and failures on a live stream (issue 30): the online stream's chunk checks give the
offline errors and warnings, a refused push takes nothing, a stream that cannot end whole says why
and carries what was final, and ``footnav follow`` ends on a signal or a bad row with the result
folder written, exit codes as documented, a one-line error and no lock left behind."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import footnav
from footnav import DataQualityWarning, InvalidInputError
from footnav.core.types import ImuData

pytestmark = pytest.mark.fault

CHUNK = 200  # samples per push (2 s at 100 Hz)
BAD = 600  # 0-based line of the bad row in a followed CSV (2 header lines: sample 598, t = 5.98 s)


def _pipe():
    return footnav.make_pipeline("threshold", "ekf", "independent", estimator_params={"smoother": "step"})


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=1, distance_m=8.0)


def _arrays(imu):
    return imu.t.copy(), imu.acc.copy(), imu.gyr.copy()


def _chunks(t, acc, gyr, size=CHUNK):
    return [(t[a : a + size], acc[a : a + size], gyr[a : a + size]) for a in range(0, len(t), size)]


def _feed(stream, t, acc, gyr, size=CHUNK):
    """Push every chunk; the first refused push's error (None if none) and the samples taken before it."""
    for chunk in _chunks(t, acc, gyr, size):
        before = stream.stats()["samples"]["left"]
        try:
            stream.push(left=chunk)
        except InvalidInputError as exc:
            return exc, before
    return None, stream.stats()["samples"]["left"]


# -- the chunk checks give the offline errors --------------------------------------------------------


def _nan_acc(t, acc, gyr):
    acc[350, 1] = np.nan
    return t, acc, gyr, 350


def _inf_gyr(t, acc, gyr):
    gyr[777, 2] = np.inf
    return t, acc, gyr, 777


def _duplicate_t(t, acc, gyr):
    t[300] = t[299]
    return t, acc, gyr, 300


def _backwards_mid_chunk(t, acc, gyr):
    t[300] = t[298]
    return t, acc, gyr, 300


def _backwards_across_chunks(t, acc, gyr):  # the first sample of a chunk before the last of the previous one
    t[2 * CHUNK] = t[2 * CHUNK - 1] - 0.005
    return t, acc, gyr, 2 * CHUNK


def _acc_1e30(t, acc, gyr):
    acc[500] = [1e30, 0.0, 0.0]
    return t, acc, gyr, 500


def _gyr_1e3(t, acc, gyr):
    gyr[500] = [0.0, 0.0, 1e3]
    return t, acc, gyr, 500


def _time_in_ms(t, acc, gyr):
    return t * 1e3, acc, gyr, None


def _gyr_in_deg_s(t, acc, gyr):
    return t, acc, np.degrees(gyr), "any"


CASES = {
    "non-finite acc": (_nan_acc, "non-finite"),
    "non-finite gyr": (_inf_gyr, "non-finite"),
    "duplicate time": (_duplicate_t, "duplicate time stamp"),
    "time backwards": (_backwards_mid_chunk, "time goes backwards"),
    "time backwards across chunks": (_backwards_across_chunks, "time goes backwards"),
    "acc 1e30": (_acc_1e30, "a corrupt record"),
    "gyr 1e3 rad/s": (_gyr_1e3, "a corrupt record"),
    "time in ms read as s": (_time_in_ms, "implausible time base"),
    "gyr deg/s read as rad/s": (_gyr_in_deg_s, "gyr_unit='deg/s'"),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("size", [CHUNK, 7, 1], ids=["chunks of 200", "chunks of 7", "one sample a push"])
def test_a_refused_chunk_has_the_offline_error_and_takes_nothing(walk, case, size):
    make, words = CASES[case]
    t, acc, gyr, index = make(*_arrays(walk.left))
    stream = _pipe().online(feet=1)
    online, taken = _feed(stream, t, acc, gyr, size)
    assert online is not None, f"{case}: every push was taken"
    with pytest.raises(InvalidInputError) as offline:
        ImuData.from_arrays(t, acc, gyr)
    assert str(online) == str(offline.value)
    assert words in str(online)
    assert online.field == offline.value.field and online.index == offline.value.index
    if isinstance(index, int):
        assert online.index == index
    if case == "time in ms read as s":
        assert online.field == "t" and taken < 16 <= taken + size  # refused with the 16th sample's chunk
        assert stream.stats()["final"]["left"] == 0  # before any step
    # the refused push took nothing: the stream holds what it held before that push
    assert stream.stats()["samples"]["left"] == taken


def test_a_transposed_chunk_is_refused_naming_its_shape_and_the_stream_goes_on(walk):
    t, acc, gyr = _arrays(walk.left)
    with pytest.raises(InvalidInputError) as offline:
        ImuData.from_arrays(t[:CHUNK], acc[:CHUNK].T, gyr[:CHUNK])
    stream = _pipe().online(feet=1)
    with pytest.raises(InvalidInputError) as first:
        stream.push(left=(t[:CHUNK], acc[:CHUNK].T, gyr[:CHUNK]))
    assert str(first.value) == str(offline.value)
    assert f"expected shape (N, 3), got (3, {CHUNK})" in str(first.value)
    # a later chunk transposed: refused, nothing taken, and the stream goes on as if never pushed
    stream.push(left=(t[:CHUNK], acc[:CHUNK], gyr[:CHUNK]))
    with pytest.raises(InvalidInputError, match=r"expected shape \(N, 3\), got \(3, 200\)") as later:
        stream.push(left=(t[CHUNK : 2 * CHUNK], acc[CHUNK : 2 * CHUNK], gyr[CHUNK : 2 * CHUNK].T))
    assert later.value.field == "gyr"
    assert stream.stats()["samples"]["left"] == CHUNK
    for chunk in _chunks(t, acc, gyr)[1:]:
        stream.push(left=chunk)
    clean = _pipe().online(feet=1)
    for chunk in _chunks(t, acc, gyr):
        clean.push(left=chunk)
    assert np.array_equal(stream.close().left.position, clean.close().left.position)


GAP_WORDS = "sampling gap(s) longer than 1.9 x the median interval"


def _gap_warnings(caught) -> list[str]:
    return [
        str(w.message) for w in caught if issubclass(w.category, DataQualityWarning) and GAP_WORDS in str(w.message)
    ]


def test_a_sampling_gap_is_warned_with_the_offline_message_and_recorded(walk):
    t, acc, gyr = _arrays(walk.left)
    t[600:] += 5.0
    with warnings.catch_warnings(record=True) as off_caught:
        warnings.simplefilter("always")
        imu = ImuData.from_arrays(t, acc, gyr)
    offline = _gap_warnings(off_caught)
    assert len(offline) == 1
    stream = _pipe().online(feet=1)
    with warnings.catch_warnings(record=True) as on_caught:
        warnings.simplefilter("always")
        for chunk in _chunks(t, acc, gyr):
            stream.push(left=chunk)
        result = stream.close()
    online = _gap_warnings(on_caught)
    assert len(online) == 1
    # the same message after the data's label (online: the foot is named, "ImuData (left foot): ...")
    assert online[0].split(": ", 1)[1] == offline[0].split(": ", 1)[1]
    assert any(online[0] in w for w in stream.warnings)
    gaps = result.meta["input"]["left"]["gaps"]
    assert [i for i, _ in gaps] == [i for i, _ in imu.meta["gaps"]] == [600]
    assert gaps[0][1] == pytest.approx(imu.meta["gaps"][0][1])
    assert any(GAP_WORDS in w for w in result.meta["warnings"])
    # and the filter bridges the gap as the offline run does
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        offline_run = _pipe().run(imu)
    assert np.array_equal(result.left.position, offline_run.left.position)


# -- two feet: a push is atomic --------------------------------------------------------------------


@pytest.mark.parametrize("bad_foot", ["left", "right"])
def test_a_two_foot_push_with_one_bad_chunk_takes_neither_and_can_be_retried(walk, bad_foot):
    feet = {foot: _arrays(getattr(walk, foot)) for foot in ("left", "right")}
    chunks = {foot: _chunks(*feet[foot]) for foot in feet}
    n = len(chunks["left"])

    def run(break_at):
        stream = _pipe().online(feet=2)
        for k in range(n):
            if k == break_at:
                t, acc, gyr = (a.copy() for a in chunks[bad_foot][k])
                acc[50, 0] = np.nan
                bad = dict(left=chunks["left"][k], right=chunks["right"][k]) | {bad_foot: (t, acc, gyr)}
                before = stream.stats()
                with pytest.raises(InvalidInputError, match="non-finite"):
                    stream.push(**bad)
                after = stream.stats()
                assert after["samples"] == before["samples"] and after["final"] == before["final"]
            stream.push(left=chunks["left"][k], right=chunks["right"][k])  # the retry with good data
        return stream.close()

    retried, clean = run(break_at=2), run(break_at=None)
    assert retried.meta["complete"] is True
    for foot in ("left", "right"):
        assert np.array_equal(getattr(retried, foot).position, getattr(clean, foot).position)
        assert np.array_equal(getattr(retried, foot).t, getattr(clean, foot).t)


def test_a_two_foot_push_error_names_the_bad_foot(walk):
    L, R = _arrays(walk.left), _arrays(walk.right)
    acc = R[1][:CHUNK].copy()
    acc[50, 0] = np.nan
    stream = _pipe().online(feet=2)
    with pytest.raises(InvalidInputError) as err:
        stream.push(left=(L[0][:CHUNK], L[1][:CHUNK], L[2][:CHUNK]), right=(R[0][:CHUNK], acc, R[2][:CHUNK]))
    assert err.value.foot == "right" and err.value.index == 50 and err.value.field == "acc"


# -- a stream that cannot end whole ------------------------------------------------------------------


def test_close_without_the_right_foot_raises_with_the_left_foots_whole_walk(walk):
    t, acc, gyr = _arrays(walk.left)
    stream = _pipe().online(feet=2)
    one = _pipe().online(feet=1)
    for chunk in _chunks(t, acc, gyr):
        stream.push(left=chunk)
        one.push(left=chunk)
    alone = one.close()
    with pytest.raises(InvalidInputError, match="no samples of the right foot") as err:
        stream.close()
    partial = err.value.partial
    assert partial is not None
    assert np.array_equal(partial.left.position, alone.left.position)
    assert np.array_equal(partial.left.t, t)
    assert partial.right is None
    assert partial.meta["complete"] is False
    assert "no samples of the right foot" in partial.meta["ended_by"]
    assert err.value.feet["right"] is None and err.value.feet["left"] is not None
    # closing again: the same error, not "already closed"
    with pytest.raises(InvalidInputError, match="no samples of the right foot") as again:
        stream.close()
    assert "closed" not in str(again.value)
    assert again.value.partial is not None
    assert np.array_equal(again.value.partial.left.position, alone.left.position)


def _dual_gait():
    return footnav.make_pipeline("dual-gait", "ekf", "independent", estimator_params={"smoother": "step"})


def test_dual_gait_without_the_right_foot_raises_with_the_left_foots_whole_walk(walk):
    """Both feet are decided together (footnav.pipeline.online_pair): with one silent, the other's
    samples are decided with it absent, as offline where one foot's recording is missing there,
    and the left foot's whole walk is the partial result."""
    from footnav.detectors.dual_gait import DualGaitDetector

    t, acc, gyr = _arrays(walk.left)
    stream = _dual_gait().online(feet=2)
    for chunk in _chunks(t, acc, gyr):
        stream.push(left=chunk)
    with pytest.raises(InvalidInputError, match="no samples of the right foot") as err:
        stream.close()
    partial = err.value.partial
    assert partial is not None and partial.right is None and partial.meta["complete"] is False
    assert "no samples of the right foot" in partial.meta["ended_by"]
    assert np.array_equal(partial.left.t, t)
    alone = DualGaitDetector().window_masks(walk.left, None)["left"]
    assert alone.any() and np.array_equal(partial.stance_left.mask, alone)


def test_dual_gait_failing_in_a_push_ends_the_stream_with_what_was_final(walk):
    pipeline = _dual_gait()
    original, calls = pipeline.detector.window_masks, {"n": 0}

    def window_masks(left, right):
        calls["n"] += 1
        if calls["n"] > 20:
            raise RuntimeError("detector exploded")
        return original(left, right)

    pipeline.detector.window_masks = window_masks
    stream = pipeline.online(feet=2)
    L, R = _chunks(*_arrays(walk.left), 100), _chunks(*_arrays(walk.right), 100)
    final = []
    with pytest.raises(RuntimeError, match="detector exploded"):
        for left, right in zip(L, R):
            final.append(stream.push(left=left, right=right).left.position)
    final = np.concatenate(final)
    assert len(final) > 100, "the test needs steps that became final before the failure"
    with pytest.raises(InvalidInputError, match="RuntimeError: detector exploded"):
        stream.push(left=L[-1], right=R[-1])
    with pytest.raises(RuntimeError, match="detector exploded") as err:
        stream.close()
    partial = err.value.partial
    assert partial.meta["complete"] is False and "detector exploded" in partial.meta["ended_by"]
    assert np.array_equal(partial.left.position[: len(final)], final)


def _failing_detector(pipeline, after_calls):
    """The pipeline's detector, raising RuntimeError from its ``after_calls``+1-th detect on."""
    original = pipeline.detector.detect
    calls = {"n": 0}

    def detect(imu):
        calls["n"] += 1
        if calls["n"] > after_calls:
            raise RuntimeError("detector exploded")
        return original(imu)

    pipeline.detector.detect = detect
    return calls


def test_a_component_failing_in_a_push_ends_the_stream_with_what_was_final(walk):
    t, acc, gyr = _arrays(walk.left)
    pipeline = _pipe()
    _failing_detector(pipeline, after_calls=6)
    stream = pipeline.online(feet=1)
    final_t, final_pos = [], []
    chunks = _chunks(t, acc, gyr, 100)
    failed_at = None
    for k, chunk in enumerate(chunks):
        try:
            update = stream.push(left=chunk)
        except RuntimeError as exc:
            assert "detector exploded" in str(exc)
            failed_at = k
            break
        final_t.append(update.left.t)
        final_pos.append(update.left.position)
    assert failed_at is not None and failed_at + 1 < len(chunks)
    final_t, final_pos = np.concatenate(final_t), np.concatenate(final_pos)
    assert len(final_t) > 100, "the test needs steps that became final before the failure"
    # later pushes are refused, naming the failure
    with pytest.raises(InvalidInputError, match="RuntimeError: detector exploded"):
        stream.push(left=chunks[failed_at + 1])
    # close raises the failure with what was final before it
    with pytest.raises(RuntimeError, match="detector exploded") as err:
        stream.close()
    partial = err.value.partial
    # what was final, and the samples after the last closed stance, which waited for the next
    # stance's height (level strides held level) and now keep the last stance's, as offline
    n = len(final_t)
    assert np.array_equal(partial.left.t[:n], final_t) and len(partial.left.t) - n < 200
    assert np.array_equal(partial.left.position[:n], final_pos)
    assert partial.meta["complete"] is False
    assert "RuntimeError: detector exploded" in partial.meta["ended_by"]
    with pytest.raises(RuntimeError, match="detector exploded"):
        stream.close()


def test_a_component_failing_at_close_raises_with_what_was_final(walk):
    t, acc, gyr = _arrays(walk.left)
    pipeline = _pipe()
    calls = _failing_detector(pipeline, after_calls=10**9)
    stream = pipeline.online(feet=1)
    final_pos = [stream.push(left=chunk).left.position for chunk in _chunks(t, acc, gyr)]
    final_pos = np.concatenate(final_pos)
    assert 100 < len(final_pos) < len(t)
    calls["n"] = 10**10  # the detection at the end fails
    with pytest.raises(RuntimeError, match="detector exploded") as err:
        stream.close()
    n = len(final_pos)  # and the samples that waited for the next stance (see above)
    assert np.array_equal(err.value.partial.left.position[:n], final_pos)
    assert err.value.partial.meta["complete"] is False
    assert "detector exploded" in err.value.partial.meta["ended_by"]


def test_a_normal_close_is_complete_and_closing_again_returns_it(walk):
    stream = _pipe().online(feet=1)
    for chunk in _chunks(*_arrays(walk.left)):
        stream.push(left=chunk)
    result = stream.close()
    assert result.meta["complete"] is True
    assert result.meta["ended_by"] == "close"
    assert stream.close() is result
    with pytest.raises(InvalidInputError, match="closed"):
        stream.push(left=_chunks(*_arrays(walk.left))[0])


# -- a single absurd sample in a recording --------------------------------------------------------------


@pytest.mark.parametrize("field, value", [("acc", [1e30, 0.0, 0.0]), ("gyr", [0.0, 0.0, 1e3])])
def test_a_single_absurd_sample_is_refused_offline_naming_it(walk, field, value):
    t, acc, gyr = _arrays(walk.left)
    (acc if field == "acc" else gyr)[500] = value
    with pytest.raises(InvalidInputError, match="a corrupt record") as err:
        ImuData.from_arrays(t, acc, gyr)
    assert err.value.field == field and err.value.index == 500
    # the constructor does not check; the pipeline does (no silent 1e29 m)
    imu = ImuData(t, acc, gyr)
    with pytest.raises(InvalidInputError, match="a corrupt record") as run_err:
        footnav.make_pipeline().run(imu)
    assert run_err.value.field == field and run_err.value.index == 500
    with pytest.raises(InvalidInputError, match="a corrupt record"):
        _pipe().run(imu, walk.right)


# -- footnav follow ----------------------------------------------------------------------------------

#: The logger of the follow tests (tests/live_writer.py): bursts of 40 rows every 0.15 s.
WRITER = Path(__file__).parents[1] / "live_writer.py"


def _cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "footnav.cli", *args]


def _follow(*args: str, **kwargs) -> subprocess.CompletedProcess:
    """``footnav follow``: in this process on files (a second of interpreter start and import
    less per case), in a child process on standard input (it reads the real descriptor)."""
    if "input" in kwargs:
        return subprocess.run(
            _cli("follow", *args), capture_output=True, text=True, timeout=120, check=False, env=os.environ, **kwargs
        )
    import contextlib
    import io
    import warnings

    from footnav.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), warnings.catch_warnings():
        code = main(["follow", *args])
    return subprocess.CompletedProcess(["footnav", "follow", *args], code, out.getvalue(), err.getvalue())


@pytest.fixture(scope="module")
def walk_csv(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("live") / "sim"
    subprocess.run(
        _cli("simulate", "straight", "--set", "distance_m=8", "--out", str(folder)),
        check=True,
        capture_output=True,
        env=os.environ,
        timeout=120,
    )
    return folder


def _lines(walk_csv, foot="left") -> list[str]:
    return (walk_csv / f"{foot}.csv").read_text().splitlines()


def _step_lines(text: str) -> list[list[str]]:
    return [line.split() for line in text.splitlines() if line.split()[1:2] in (["left"], ["right"])]


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())["summary"]


def _no_lock_left(folder: Path) -> None:
    leftovers = [p.name for p in folder.iterdir() if "lock" in p.name.lower()]
    assert not leftovers, leftovers


def _error_lines(stderr: str) -> list[str]:
    assert "Traceback" not in stderr, stderr
    return [line for line in stderr.splitlines() if line.startswith("footnav follow: error:")]


def _assert_steps_in_result(steps: list[list[str]], saved) -> None:
    """Each printed step is a stance of the saved result: it ends at the step's time, and its mean
    position is the printed footprint."""
    t, mask, pos = saved["left_t"], saved["left_stance"].astype(int), saved["left_position"]
    edges = np.flatnonzero(np.diff(np.r_[0, mask, 0]))
    stances = list(zip(edges[::2], edges[1::2]))
    for step in steps:
        ts, xyz = float(step[0]), np.array([float(v) for v in step[2:5]])
        match = [(a, b) for a, b in stances if abs(t[b - 1] - ts) < 1e-6]
        assert match, f"step at {ts} s is not a stance of the result"
        a, b = match[0]
        np.testing.assert_allclose(pos[a:b].mean(axis=0), xyz, atol=6e-4)


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGHUP"])
def test_a_stop_signal_writes_everything_so_far_and_exits_0(walk_csv, tmp_path, sig):
    left, out = tmp_path / "left.csv", tmp_path / "res"
    follow = subprocess.Popen(
        _cli("follow", "--left", str(left), "--idle-s", "60", "--out", str(out)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ,
    )
    writer = subprocess.Popen([sys.executable, str(WRITER), str(walk_csv / "left.csv"), str(left)])
    try:
        printed = []
        for line in iter(follow.stdout.readline, ""):
            printed += _step_lines(line)
            if len(printed) >= 2 and float(printed[-1][0]) > 3.0:
                break
        assert len(printed) >= 2, "follow ended before printing steps"
        follow.send_signal(getattr(signal, sig))
        rest, err = follow.communicate(timeout=120)  # a guard against a hang, not a speed claim
    finally:
        for proc in (follow, writer):
            if proc.poll() is None:
                proc.kill()
                proc.wait(timeout=10)
    assert follow.returncode == 0, err
    assert f"interrupted ({sig})" in rest and "(incomplete)" in rest
    summary = _summary(out)
    assert summary["complete"] is False
    assert summary["ended_by"] == f"interrupted ({sig})"
    saved = np.load(out / "trajectories.npz")
    assert len(saved["left_t"]) > 300 and "right_t" not in saved
    assert saved["left_t"][-1] >= float(printed[-1][0])
    # every step printed (before the signal and at the end) is in the result
    _assert_steps_in_result(printed + _step_lines(rest), saved)
    _no_lock_left(tmp_path)


def _bad_file(walk_csv, tmp_path, kind: str) -> tuple[Path, float]:
    lines = _lines(walk_csv)
    cells = lines[BAD].split(",")
    if kind == "garbled":
        lines[BAD] = f"{cells[0]},1.0,xx%%garbage"
    elif kind == "nan cell":
        lines[BAD] = ",".join([cells[0], "nan", *cells[2:]])
    elif kind == "time backwards":
        lines[BAD] = ",".join(["1.0", *cells[1:]])
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines) + "\n")
    return path, float(lines[BAD - 1].split(",")[0])


@pytest.mark.parametrize(
    "kind, names", [("garbled", "line 601"), ("nan cell", "index 598"), ("time backwards", "index 598")]
)
def test_a_bad_row_ends_follow_with_the_walk_up_to_it(walk_csv, tmp_path, kind, names):
    path, t_before = _bad_file(walk_csv, tmp_path, kind)
    out = tmp_path / "res"
    done = _follow("--left", str(path), "--idle-s", "1", "--out", str(out))
    assert done.returncode == 2, done.stderr
    errors = _error_lines(done.stderr)
    assert len(errors) == 1, done.stderr
    assert names in errors[0]
    summary = _summary(out)
    assert summary["complete"] is False
    assert summary["ended_by"].startswith("bad input") and names in summary["ended_by"]
    _no_lock_left(tmp_path)
    # the result holds the walk up to the row before the bad one
    assert (out / "trajectories.npz").is_file(), f"{kind}: no trajectory written; the rows before the bad one are lost"
    saved = np.load(out / "trajectories.npz")
    assert saved["left_t"][-1] == pytest.approx(t_before, abs=1e-9)
    assert len(saved["left_t"]) == BAD - 2


def test_headerless_standard_input_with_a_foot_column(walk_csv, tmp_path):
    rows = []
    for foot in ("left", "right"):
        rows += [f"{foot},{line}" for line in _lines(walk_csv, foot)[2:]]
    out = tmp_path / "res"
    done = _follow("--left", "-", "--feet", "2", "--out", str(out), input="\n".join(rows) + "\n")
    assert done.returncode == 0, done.stderr
    assert {s[1] for s in _step_lines(done.stdout)} == {"left", "right"}
    assert _summary(out)["complete"] is True
    saved = np.load(out / "trajectories.npz")
    # follow runs the default pipeline
    off = footnav.make_pipeline().run(
        footnav.load(str(walk_csv / "left.csv")).left, footnav.load(str(walk_csv / "right.csv")).left
    )
    for foot in ("left", "right"):
        np.testing.assert_allclose(saved[f"{foot}_position"], getattr(off, foot).position, atol=1e-9, rtol=0)


def _with_time_scale(walk_csv, path: Path, scale: float, units_line: str | None) -> Path:
    lines = _lines(walk_csv)
    rows = []
    for line in lines[2:]:
        cells = line.split(",")
        rows.append(",".join([str(round(float(cells[0]) * scale)), *cells[1:]]))
    path.write_text("\n".join(([units_line] if units_line else []) + [lines[1], *rows]) + "\n")
    return path


def test_time_in_microseconds_from_the_units_line_gives_the_seconds_result(walk_csv, tmp_path):
    us = _with_time_scale(walk_csv, tmp_path / "us.csv", 1e6, "# units: t us, acc m/s^2, gyr rad/s")
    a = _follow("--left", str(us), "--idle-s", "0.3", "--out", str(tmp_path / "us"))
    b = _follow("--left", str(walk_csv / "left.csv"), "--idle-s", "0.3", "--out", str(tmp_path / "s"))
    assert a.returncode == 0, a.stderr
    assert b.returncode == 0, b.stderr
    sa, sb = _summary(tmp_path / "us"), _summary(tmp_path / "s")
    assert sa["complete"] is True
    assert abs(sa["left_path_length_m"] - sb["left_path_length_m"]) < 1e-6
    assert sa["left_stances"] == sb["left_stances"]
    ta, tb = np.load(tmp_path / "us" / "trajectories.npz"), np.load(tmp_path / "s" / "trajectories.npz")
    np.testing.assert_allclose(ta["left_t"], tb["left_t"], atol=1e-9, rtol=0)
    np.testing.assert_allclose(ta["left_position"], tb["left_position"], atol=1e-6, rtol=0)


def test_time_in_ms_without_a_units_line_is_refused_with_the_hint(walk_csv, tmp_path):
    ms = _with_time_scale(walk_csv, tmp_path / "ms.csv", 1e3, None)
    done = _follow("--left", str(ms), "--idle-s", "0.3", "--out", str(tmp_path / "res"))
    assert done.returncode == 2, done.stderr
    errors = _error_lines(done.stderr)
    assert len(errors) == 1
    assert "implausible time base" in errors[0] and "t_unit='ms'" in errors[0]
    assert _summary(tmp_path / "res")["complete"] is False
    _no_lock_left(tmp_path)


@pytest.mark.parametrize("kind", ["a long garbled line", "a long number cell"])
def test_a_huge_line_gives_a_short_error(walk_csv, tmp_path, kind):
    lines = _lines(walk_csv)
    if kind == "a long garbled line":
        lines[BAD] = "1," + "9" * 5_000_000
    else:
        cells = lines[BAD].split(",")
        cells[3] = "9" * 5_000_000
        lines[BAD] = ",".join(cells)
    path = tmp_path / "huge.csv"
    path.write_text("\n".join(lines) + "\n")
    out = tmp_path / "res"
    done = _follow("--left", str(path), "--idle-s", "0.3", "--out", str(out))
    assert done.returncode == 2
    assert len(_error_lines(done.stderr)) == 1
    assert len(done.stderr) < 1000, done.stderr[:2000]
    assert max(len(line) for line in done.stdout.splitlines()) < 1000
    assert (out / "summary.json").stat().st_size < 100_000
    _no_lock_left(tmp_path)


def test_a_deeply_nested_pipeline_toml_is_a_one_line_error(walk_csv, tmp_path):
    toml = tmp_path / "deep.toml"
    toml.write_text("a = " + "[" * 100_000 + "]" * 100_000 + "\n")
    done = _follow(
        "--left", str(walk_csv / "left.csv"), "--pipeline", str(toml), "--idle-s", "0.3", "--out", str(tmp_path / "res")
    )
    assert done.returncode == 2, done.stderr[-2000:]
    assert "RecursionError" not in done.stderr and "Traceback" not in done.stderr
    lines = [line for line in done.stderr.splitlines() if line.strip() and not line.startswith("footnav: compil")]
    assert len(lines) == 1, done.stderr[-2000:]
    assert lines[0].startswith("footnav follow: error:") and "deep.toml" in lines[0]
    assert len(lines[0]) < 1000
    _no_lock_left(tmp_path)


def test_a_bad_foot_name_on_standard_input_ends_follow_with_the_rows_before(walk_csv, tmp_path):
    rows = [f"left,{line}" for line in _lines(walk_csv)[2:]]
    rows[BAD - 2] = "centre," + rows[BAD - 2].split(",", 1)[1]
    out = tmp_path / "res"
    done = _follow("--left", "-", "--feet", "2", "--out", str(out), input="\n".join(rows) + "\n")
    assert done.returncode == 2, done.stderr
    errors = _error_lines(done.stderr)
    assert len(errors) == 1 and "line 599" in errors[0] and "'centre'" in errors[0]
    summary = _summary(out)
    assert summary["complete"] is False and summary["ended_by"].startswith("bad input")
    saved = np.load(out / "trajectories.npz")
    assert len(saved["left_t"]) == BAD - 2
    _no_lock_left(tmp_path)


def test_two_feet_on_standard_input_without_right_rows_writes_the_left_walk(walk_csv, tmp_path):
    rows = [f"left,{line}" for line in _lines(walk_csv)[2:]]
    out = tmp_path / "res"
    done = _follow("--left", "-", "--feet", "2", "--out", str(out), input="\n".join(rows) + "\n")
    assert done.returncode == 2, done.stderr
    errors = _error_lines(done.stderr)
    assert len(errors) == 1 and "no samples of the right foot" in errors[0]
    summary = _summary(out)
    assert summary["complete"] is False and "no samples of the right foot" in summary["ended_by"]
    saved = np.load(out / "trajectories.npz")
    assert "right_t" not in saved
    assert len(saved["left_t"]) == len(rows)
    one = _follow("--left", str(walk_csv / "left.csv"), "--idle-s", "0.3", "--out", str(tmp_path / "one"))
    assert one.returncode == 0, one.stderr
    alone = np.load(tmp_path / "one" / "trajectories.npz")
    np.testing.assert_array_equal(saved["left_position"], alone["left_position"])
    _no_lock_left(tmp_path)


def test_a_stop_signal_before_any_row_exits_0_with_a_summary(tmp_path):
    """The help: "Ctrl-C, SIGTERM or SIGHUP end it; the result folder then holds everything up to the
    last sample read"; the docstring: signals end it incomplete with exit 0 (the user stopped it)."""
    out = tmp_path / "res"
    args = ("--left", str(tmp_path / "not-yet.csv"), "--idle-s", "60", "--out", str(out))
    follow = subprocess.Popen(
        _cli("follow", *args), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=os.environ
    )
    try:
        assert "stride_m" in follow.stdout.readline()  # printed once the stop handlers are in place
        follow.send_signal(signal.SIGTERM)
        rest, err = follow.communicate(timeout=60)
    finally:
        if follow.poll() is None:
            follow.kill()
            follow.wait(timeout=10)
    summary = _summary(out)
    assert summary["complete"] is False
    assert summary["ended_by"].startswith("interrupted (SIGTERM)")
    _no_lock_left(tmp_path)
    assert follow.returncode == 0, err


def test_a_units_line_after_rows_is_not_applied_silently(walk_csv, tmp_path):
    """The offline reader refuses a '# units:' line after the rows (a line of 3 columns); follow
    must not re-scale the rows with it (here: gyr in deg/s from 6 s on, a silently wrong walk)."""
    lines = (walk_csv / "left.csv").read_text().splitlines(keepends=True)
    path, out = tmp_path / "left.csv", tmp_path / "res"
    path.write_text("".join(lines[: BAD + 2]))
    # threshold: its steps are printed from the first seconds on (adaptive's wait for 10 s of walk)
    follow = subprocess.Popen(
        _cli("follow", "--left", str(path), "--detector", "threshold", "--idle-s", "1", "--out", str(out)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ,
    )
    try:
        for line in iter(follow.stdout.readline, ""):  # the first rows are read and pushed
            if _step_lines(line) and float(line.split()[0]) > 4.0:
                break
        with path.open("a") as f:
            f.write("# units: t s, acc m/s^2, gyr deg/s\n")
            f.writelines(lines[BAD + 2 :])
        rest, err = follow.communicate(timeout=60)
    finally:
        if follow.poll() is None:
            follow.kill()
            follow.wait(timeout=10)
    args = ("--left", str(path), "--detector", "threshold", "--out", str(tmp_path / "off"))
    offline = subprocess.run(
        _cli("run", *args), capture_output=True, text=True, timeout=120, check=False, env=os.environ
    )
    assert offline.returncode == 2 and f"line {BAD + 3}" in offline.stderr
    summary = _summary(out)
    assert not (follow.returncode == 0 and summary["complete"]), (
        f"follow took the units line and finished 'complete' (left path {summary.get('left_path_length_m')} m)"
    )
    assert follow.returncode == 2 and summary["ended_by"].startswith("bad input")


@pytest.mark.parametrize("source", ["file", "standard input"])
def test_a_line_that_is_not_utf8_is_a_bad_row_with_the_rows_before_kept(walk_csv, tmp_path, source):
    lines = [line.encode() for line in _lines(walk_csv)]
    lines[BAD] = b"5.98,\xff\xfe\x00garbage,1,2,3,4,5"
    data = b"\n".join(lines) + b"\n"
    out = tmp_path / "res"
    if source == "file":
        (tmp_path / "bad.csv").write_bytes(data)
        args, kwargs = ("--left", str(tmp_path / "bad.csv"), "--idle-s", "0.5"), {}
    else:
        args, kwargs = ("--left", "-"), {"input": data}
    done = subprocess.run(
        _cli("follow", *args, "--out", str(out)),
        capture_output=True,
        timeout=120,
        check=False,
        env=os.environ,
        **kwargs,
    )
    stderr = done.stderr.decode("utf-8", errors="replace")
    assert done.returncode == 2, stderr
    errors = _error_lines(stderr)
    assert len(errors) == 1 and "line 601" in errors[0], stderr
    saved = np.load(out / "trajectories.npz")
    assert len(saved["left_t"]) == BAD - 2
    assert _summary(out)["complete"] is False
    _no_lock_left(tmp_path)


def test_an_endless_line_is_a_bad_row_not_a_wait(walk_csv, tmp_path):
    """A line without its newline longer than 1 MiB: a bad row at once (not --idle-s later), a
    short error, the rows before kept."""
    lines = _lines(walk_csv)
    path, out = tmp_path / "endless.csv", tmp_path / "res"
    path.write_text("\n".join(lines[:BAD]) + "\n" + "1," + "9" * (3 << 20))  # no newline at the end
    done = _follow("--left", str(path), "--idle-s", "60", "--out", str(out))
    # had it waited for the line's end, --idle-s would have ended it, complete (exit 0)
    assert done.returncode == 2, done.stderr[:2000]
    assert not _summary(out)["ended_by"].startswith("idle"), _summary(out)["ended_by"]
    assert len(_error_lines(done.stderr)) == 1 and len(done.stderr) < 1000, done.stderr[:2000]
    assert len(np.load(out / "trajectories.npz")["left_t"]) == BAD - 2
    _no_lock_left(tmp_path)


def test_a_closed_standard_output_ends_follow_with_the_result_written(walk_csv, tmp_path):
    """``footnav follow ... | head``: the reader goes away; follow stops as at a signal, exit 0."""
    left, out = tmp_path / "left.csv", tmp_path / "res"
    follow = subprocess.Popen(
        _cli("follow", "--left", str(left), "--idle-s", "60", "--out", str(out)),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=os.environ,
    )
    try:
        assert "stride_m" in follow.stdout.readline()
        follow.stdout.close()
        left.write_text((walk_csv / "left.csv").read_text())
        err = follow.stderr.read()
        follow.wait(timeout=60)
    finally:
        if follow.poll() is None:
            follow.kill()
            follow.wait(timeout=10)
    assert follow.returncode == 0, err
    assert "Traceback" not in err and "BrokenPipe" not in err
    summary = _summary(out)
    assert summary["complete"] is False and "standard output closed" in summary["ended_by"]
    assert len(np.load(out / "trajectories.npz")["left_t"]) > 0
    _no_lock_left(tmp_path)


def test_an_endless_line_on_standard_input_is_a_bad_row_not_a_wait(walk_csv, tmp_path):
    """As a file's (MAX_LINE_BYTES): a producer that sends 3 MiB without a newline and keeps the
    pipe open must not be waited for (nor its line held whatever its length)."""
    lines = _lines(walk_csv)
    out = tmp_path / "res"
    with open(tmp_path / "stdout", "w") as so, open(tmp_path / "stderr", "w") as se:
        follow = subprocess.Popen(
            _cli("follow", "--left", "-", "--idle-s", "60", "--out", str(out)),
            stdin=subprocess.PIPE,
            stdout=so,
            stderr=se,
            env=os.environ,
        )
        try:
            follow.stdin.write(("\n".join(lines[:BAD]) + "\n1," + "9" * (3 << 20)).encode())
            follow.stdin.flush()
            try:
                # standard input stays open: follow must end on the line itself. Had it waited for
                # the line's end, it would wait for ever; the timeout is a guard, not a speed claim
                follow.wait(timeout=120)
                waited = False
            except subprocess.TimeoutExpired:
                waited = True
        finally:
            follow.stdin.close()  # the end of input: follow ends
            try:
                follow.wait(timeout=60)
            except subprocess.TimeoutExpired:
                follow.kill()
                follow.wait(timeout=10)
    assert not waited, "follow held the endless line of standard input until its end"
    stderr = (tmp_path / "stderr").read_text()
    assert follow.returncode == 2, stderr[:2000]
    assert len(stderr) < 1000
    assert len(np.load(out / "trajectories.npz")["left_t"]) == BAD - 2
