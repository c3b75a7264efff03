"""``footnav follow`` on a CSV file another process appends to."""

from __future__ import annotations

import os
import queue
import signal
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import footnav

#: The logger of the tests: bursts of 40 rows every 0.15 s (0.4 s of walk: 2.7x real time), each
#: flushed, optionally holding at a time until the test has seen what it waits for.
WRITER = Path(__file__).with_name("live_writer.py")


def _writer(source: Path, target: Path, *args: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, str(WRITER), str(source), str(target), *args])


def _footnav(*args: str, **kwargs) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "footnav.cli", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kwargs,
    )


@pytest.fixture(scope="module")
def walk_csv(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("walk")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "simulate",
            "straight",
            "--set",
            "distance_m=20",
            "--out",
            str(folder / "sim"),
        ],
        check=True,
        capture_output=True,
    )
    return folder / "sim"


def _step_lines(text: str) -> list[list[str]]:
    return [line.split() for line in text.splitlines() if line.strip() and line.split()[1:2] in (["left"], ["right"])]


def test_follow_prints_steps_as_they_happen_and_writes_the_result_folder(walk_csv, tmp_path):
    left, right, go = tmp_path / "left.csv", tmp_path / "right.csv", tmp_path / "go"
    # follow starts first and waits for the files to appear; the writers start once it is up, and
    # hold at 15 s of walk until follow has printed a step (adaptive's steps are final from ~13 s)
    follow = _footnav(
        "follow", "--left", str(left), "--right", str(right), "--idle-s", "3", "--out", str(tmp_path / "out")
    )
    lines = [follow.stdout.readline()]
    assert "stride_m" in lines[0]
    writers = [
        _writer(walk_csv / f"{foot}.csv", path, "--hold-after-s", "15", "--go", str(go))
        for foot, path in (("left", left), ("right", right))
    ]
    writing = None
    for line in iter(follow.stdout.readline, ""):
        lines.append(line)
        if writing is None and _step_lines(line):
            writing = all(w.poll() is None for w in writers)  # held: the walk is not all written yet
            go.touch()
    rc = follow.wait(timeout=60)
    for w in writers:
        w.wait(timeout=10)
    assert rc == 0, follow.stderr.read()
    text = "".join(lines)
    assert writing, "a step is printed while the file is still being written"
    steps = _step_lines(text)
    # the result folder is footnav run's, and equal to the offline run of the default pipeline
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "run",
            "--left",
            str(walk_csv / "left.csv"),
            "--right",
            str(walk_csv / "right.csv"),
            "--out",
            str(tmp_path / "offline"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    assert sorted(os.listdir(tmp_path / "out")) == sorted(os.listdir(tmp_path / "offline"))
    pipe = footnav.make_pipeline()
    off = pipe.run(footnav.load(str(walk_csv / "left.csv")).left, footnav.load(str(walk_csv / "right.csv")).left)
    got = np.load(tmp_path / "out" / "trajectories.npz")
    for foot in ("left", "right"):
        np.testing.assert_allclose(got[f"{foot}_position"], getattr(off, foot).position, atol=1e-9, rtol=0)
        assert sum(s[1] == foot for s in steps) == len(getattr(off, foot).steps)


def test_ctrl_c_saves_everything_so_far(walk_csv, tmp_path):
    left = tmp_path / "left.csv"
    writer = _writer(walk_csv / "left.csv", left)
    follow = _footnav("follow", "--left", str(left), "--idle-s", "60", "--out", str(tmp_path / "out"))
    for line in iter(follow.stdout.readline, ""):
        if len(_step_lines(line)) and float(line.split()[0]) > 3.0:
            break
    follow.send_signal(signal.SIGINT)
    out, err = follow.communicate(timeout=60)
    writer.wait(timeout=30)
    assert follow.returncode == 0, err
    assert "interrupted (SIGINT): results written to" in out and "(incomplete)" in out
    saved = np.load(tmp_path / "out" / "trajectories.npz")
    assert len(saved["left_t"]) > 300 and "right_t" not in saved


def test_standard_input_with_a_foot_column(walk_csv, tmp_path):
    rows = ["foot,t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"]
    for foot in ("left", "right"):
        rows += [f"{foot},{line}" for line in (walk_csv / f"{foot}.csv").read_text().splitlines()[2:]]
    done = subprocess.run(
        [sys.executable, "-m", "footnav.cli", "follow", "--left", "-", "--feet", "2", "--out", str(tmp_path / "out")],
        input="\n".join(rows) + "\n",
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    steps = _step_lines(done.stdout)
    assert {s[1] for s in steps} == {"left", "right"}
    assert (tmp_path / "out" / "right.csv").is_file()


def test_a_coupled_fusion_follows_both_feet(walk_csv, tmp_path):
    """--fusion range: both feet in one joint filter; the result folder holds the offline run."""
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "follow",
            "--left",
            str(walk_csv / "left.csv"),
            "--right",
            str(walk_csv / "right.csv"),
            "--fusion",
            "range",
            "--idle-s",
            "0.3",
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert {s[1] for s in _step_lines(done.stdout)} == {"left", "right"}
    pipe = footnav.make_pipeline("adaptive", "ekf", "range")
    off = pipe.run(footnav.load(str(walk_csv / "left.csv")).left, footnav.load(str(walk_csv / "right.csv")).left)
    got = np.load(tmp_path / "out" / "trajectories.npz")
    for foot in ("left", "right"):
        np.testing.assert_allclose(got[f"{foot}_position"], getattr(off, foot).position, atol=1e-9, rtol=0)
    assert "range" in (tmp_path / "out" / "pipeline.toml").read_text()


def test_offline_only_pipeline_is_refused(walk_csv, tmp_path):
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "follow",
            "--left",
            str(walk_csv / "left.csv"),
            "--detector",
            "hmm",
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2
    assert "cannot run online" in done.stderr


def _lines_of(proc: subprocess.Popen) -> queue.Queue:
    """Each line ``proc`` prints, as it prints it (None at its end), read by a thread of its own."""
    lines: queue.Queue = queue.Queue()

    def read() -> None:
        for line in iter(proc.stdout.readline, ""):
            lines.put(line)
        lines.put(None)

    threading.Thread(target=read, daemon=True).start()
    return lines


def _next_step(lines: queue.Queue, after_s: float = -1.0) -> list[str]:
    """The next step line printed for a time past ``after_s``; fails if follow ends first (the
    timeout is a guard against a hang, not a speed claim)."""
    while (line := lines.get(timeout=120)) is not None:
        for step in _step_lines(line):
            if float(step[0]) > after_s:
                return step
    raise AssertionError("follow ended before the step it was waited for")


def _drawn_after(figure: Path, before: int | None) -> int:
    """The figure's mtime once it differs from ``before`` (follow draws right after it prints a
    step: an event the test waits for, with a guard against a hang)."""
    for _ in range(6000):
        if figure.is_file() and (mtime := figure.stat().st_mtime_ns) != before:
            return mtime
        time.sleep(0.02)
    raise AssertionError(f"{figure.name} was not (re)drawn after a step was printed")


def test_live_plot_is_redrawn_while_the_walk_goes_on(walk_csv, tmp_path):
    """The walk comes on standard input in three parts; follow's figure is drawn once the first
    part gives steps and redrawn once the second gives more, each before the next part is sent."""
    from footnav.data.output import is_footnav_figure

    figure = tmp_path / "steps.png"
    follow = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "follow",
            "--left",
            "-",
            "--plot",
            str(figure),
            "--plot-every-s",
            "1e-6",
            "--out",
            str(tmp_path / "out"),
        ],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    lines = _lines_of(follow)
    rows = (walk_csv / "left.csv").read_text().splitlines(keepends=True)
    t = np.array([float(r.split(",", 1)[0]) for r in rows[2:]])
    # adaptive's steps are final from ~13 s (10 s start-up, 2.75 s latency); the walk lasts 20.6 s
    cut = 2 + np.searchsorted(t, [15.0, 18.5])
    try:
        follow.stdin.write("".join(rows[: cut[0]]))
        follow.stdin.flush()
        first = _next_step(lines)
        drawn = [_drawn_after(figure, None)]
        follow.stdin.write("".join(rows[cut[0] : cut[1]]))
        follow.stdin.flush()
        _next_step(lines, after_s=float(first[0]))
        drawn.append(_drawn_after(figure, drawn[0]))
        follow.stdin.write("".join(rows[cut[1] :]))
        follow.stdin.close()
        assert follow.wait(timeout=120) == 0, follow.stderr.read()
    finally:
        if follow.poll() is None:
            follow.kill()
            follow.wait(timeout=10)
    assert figure.stat().st_mtime_ns != drawn[1]  # and once more at the end, with every step
    assert is_footnav_figure(figure)
    assert not list(tmp_path.glob(".steps.png.*"))  # no staged file left beside it


def test_live_plot_never_replaces_a_users_file(walk_csv, tmp_path):
    mine = tmp_path / "mine.png"
    mine.write_bytes(b"not footnav's")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "follow",
            "--left",
            str(walk_csv / "left.csv"),
            "--idle-s",
            "0.5",
            "--plot",
            str(mine),
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode != 0
    assert mine.read_bytes() == b"not footnav's"


def test_follow_on_a_running_trial_misses_no_stance(shared_data, tmp_path):
    """A pyshoe running trial written as a footnav CSV and followed: a step is printed for every
    stance the offline default finds after its start-up (of its 38 stances, threshold, follow's
    detector before issue 35, finds 9)."""
    from footnav.data.datasets import load_dataset
    from footnav.data.io.footnav_csv import write_footnav_csv

    try:
        rec = load_dataset("pyshoe_2017-11-27-11-18-11", shared_data)
    except footnav.DataNotFoundError:
        pytest.skip("pyshoe running trial not found")
    write_footnav_csv(rec.left, tmp_path / "run.csv")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "footnav.cli",
            "follow",
            "--left",
            str(tmp_path / "run.csv"),
            "--idle-s",
            "0.3",  # the file is whole before follow starts: the default 5 s would be a wait
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    printed = [float(s[0]) for s in _step_lines(done.stdout)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        off = footnav.make_pipeline().run(footnav.load(str(tmp_path / "run.csv")).left)
    ends = off.left.t[off.left.steps[:, 1] - 1]
    after = ends[ends >= off.left.t[0] + 10.0]  # the detector's start-up (online_startup_s)
    assert len(after) >= 20
    assert all(np.min(np.abs(np.asarray(printed) - t)) < 1e-3 for t in after)  # printed to 1 ms
