"""Outputs never destroy what a user owns (issue 14, output safety).

Each case names the command, the expected refusal, and checks that every file the user had is
still there, byte for byte.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from footnav.cli import main
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.data.output import MARKER, claim_output, is_footnav_figure

pytestmark = pytest.mark.fault


def _snapshot(root: Path) -> dict[str, str]:
    """Every file under ``root`` (footnav's lock and temporary names aside) and its SHA-256."""
    out = {}
    for p in sorted(root.rglob("*")):
        if p.is_file():
            out[str(p.relative_to(root))] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


@pytest.fixture
def workspace(tmp_path, monkeypatch):
    """A user's folder: a recording in data/, notes, a sub-folder; the working folder is ws/."""
    ws = tmp_path / "ws"
    assert main(["simulate", "straight", "--seed", "3", "--out", str(ws / "data")]) == 0
    (ws / "notes.txt").write_text("my notes\n")
    (ws / "sub").mkdir()
    (ws / "sub" / "keep.txt").write_text("keep me\n")
    (tmp_path / "sibling.txt").write_text("beside the working folder\n")
    monkeypatch.chdir(ws)
    return ws


def _run(*extra: str) -> int:
    return main(["run", "--left", "data/left.csv", *extra])


@pytest.mark.parametrize("out", [".", "..", "data", "data/left.csv", "sub"])
def test_force_never_replaces_a_users_folder_or_file(workspace, out, capsys):
    before = _snapshot(workspace.parent)
    assert _run("--out", out, "--force") == 2
    err = capsys.readouterr().err
    assert "error:" in err and "Traceback" not in err
    assert _snapshot(workspace.parent) == before
    assert not [p for p in workspace.parent.rglob("*") if ".footnav-lock" in p.name or ".partial" in p.name]


def test_force_replaces_only_footnav_results(workspace, capsys):
    assert _run("--out", "res") == 0
    first = (workspace / "res" / "summary.json").read_bytes()
    assert (workspace / "res" / MARKER).is_file()
    assert _run("--out", "res") == 2  # not without --force
    assert "--force" in capsys.readouterr().err
    assert _run("--out", "res", "--force") == 0
    assert (workspace / "res" / "summary.json").read_bytes() != first  # a new run (new runtime)
    # a folder the user filled by hand is refused even with --force
    mine = workspace / "mine"
    mine.mkdir()
    (mine / "a.txt").write_text("mine\n")
    capsys.readouterr()
    assert _run("--out", "mine", "--force") == 2
    assert "not written by footnav" in capsys.readouterr().err
    assert (mine / "a.txt").read_text() == "mine\n" and sorted(os.listdir(mine)) == ["a.txt"]


def test_the_output_is_checked_before_the_work(workspace, monkeypatch, capsys):
    import footnav.pipeline.factory as pipeline

    def no_work(*args, **kwargs):
        raise AssertionError("the pipeline ran although the output was refused")

    monkeypatch.setattr(pipeline.Pipeline, "run", no_work)
    assert _run("--out", "sub") == 2
    assert "not empty" in capsys.readouterr().err


def test_a_refused_run_writes_no_figure(workspace):
    figure = workspace / "figure.png"
    figure.write_bytes(b"my own picture")
    assert _run("--out", "sub", "--plot", "figure.png") == 2  # --out refused
    assert figure.read_bytes() == b"my own picture"
    assert _run("--out", "res", "--plot", "figure.png", "--force") == 2  # not footnav's figure
    assert figure.read_bytes() == b"my own picture" and not (workspace / "res").exists()


def test_figures_footnav_wrote_are_replaced_with_force(workspace):
    pytest.importorskip("matplotlib")
    assert _run("--out", "res", "--plot", "walk.png") == 0
    assert is_footnav_figure(workspace / "walk.png")
    assert _run("--out", "res2", "--plot", "walk.png") == 2  # exists, no --force
    assert _run("--out", "res2", "--plot", "walk.png", "--force") == 0


def test_results_follow_the_umask(workspace):
    old = os.umask(0o027)
    try:
        assert _run("--out", "res") == 0
    finally:
        os.umask(old)
    assert (workspace / "res").stat().st_mode & 0o777 == 0o750


def test_two_concurrent_runs_never_both_succeed(workspace):
    cmd = [
        sys.executable,
        "-m",
        "footnav.cli",
        "run",
        "--left",
        "data/left.csv",
        "--right",
        "data/right.csv",
        "--out",
        "res",
    ]
    procs = [subprocess.Popen(cmd, cwd=workspace, stdout=subprocess.PIPE, stderr=subprocess.PIPE) for _ in range(2)]
    codes = [p.wait(timeout=300) for p in procs]
    assert sorted(codes) == [0, 2], [p.stderr.read()[-300:] for p in procs]
    assert (workspace / "res" / "summary.json").is_file() and (workspace / "res" / MARKER).is_file()


def test_a_lock_held_by_a_live_run_refuses_a_second(tmp_path):
    with claim_output(tmp_path / "res"):
        with pytest.raises(InvalidInputError, match="another footnav run"):
            claim_output(tmp_path / "res")
    claim_output(tmp_path / "res").release()  # released: free again


def test_a_kill_during_replacement_leaves_a_whole_result(tmp_path, monkeypatch):
    import footnav.data.output as output

    target = tmp_path / "res"
    with claim_output(target) as claim, claim.staged() as tmp:
        (tmp / "result.txt").write_text("old\n")
    renames = []
    real_rename = os.rename

    def killed_after_first(src, dst):
        if renames:  # dead: nothing more happens (not even the put-back a Ctrl-C gets)
            raise SystemExit("killed")
        renames.append((src, dst))
        real_rename(src, dst)
        raise SystemExit("killed")  # the old result is aside, the new one not yet in: the process dies here

    monkeypatch.setattr(output.os, "rename", killed_after_first)
    claim = claim_output(target, force=True)
    with pytest.raises(SystemExit), claim.staged() as tmp:
        (tmp / "result.txt").write_text("new\n")
    # no release: the process died, its lock stays
    monkeypatch.setattr(output, "_pid_alive", lambda pid: False)
    monkeypatch.setattr(output.os, "rename", real_rename)
    assert not target.exists()
    aside = [p for p in tmp_path.iterdir() if p.name.endswith(".old")]
    assert len(aside) == 1 and (aside[0] / "result.txt").read_text() == "old\n"  # whole
    # the next claim puts the whole result back and says so
    with pytest.warns(DataQualityWarning, match="put back"):
        claim_output(target, force=True).release()
    assert (target / "result.txt").read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


def test_a_replaced_result_is_deleted_under_a_temporary_name(tmp_path, monkeypatch):
    # a run killed while deleting the replaced result (its marker perhaps already gone) must
    # leave nothing the next claim takes for a whole result: the deletion runs on a .partial
    from footnav.data import output

    target = tmp_path / "res"
    with claim_output(target) as claim, claim.staged() as tmp:
        (tmp / "result.txt").write_text("old\n")
        (tmp / "more.txt").write_text("old\n")
    deleted = []
    real_delete = output._delete_result

    def interrupted(path):
        deleted.append(path.name)
        (path / "result.txt").unlink()  # the deletion got this far
        raise KeyboardInterrupt

    monkeypatch.setattr(output, "_delete_result", interrupted)
    claim = claim_output(target, force=True)
    with pytest.raises(KeyboardInterrupt), claim.staged() as tmp:
        (tmp / "result.txt").write_text("new\n")
    claim.release()  # the half-deleted folder stays named in the lock, under no writer
    monkeypatch.setattr(output, "_delete_result", real_delete)
    assert len(deleted) == 1 and deleted[0].endswith(".partial-old")
    assert (target / "result.txt").read_text() == "new\n"
    with pytest.warns(DataQualityWarning, match="left by an interrupted run"):
        claim_output(target, force=True).release()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]
    assert (target / "result.txt").read_text() == "new\n"


def test_partial_folders_of_killed_runs_are_removed_and_named(tmp_path):
    target = tmp_path / "res"
    leftover = tmp_path / ".res.footnav-999999999-deadbeef.partial"
    leftover.mkdir()
    (leftover / "left.csv").write_text("half")
    # a writer that no longer exists, and the partial it named
    (tmp_path / ".res.footnav-lock").write_text(
        f'{{"footnav": "output-lock", "pid": 999999999}}\n{{"entry": "{leftover.name}", "role": "partial"}}\n'
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        claim_output(target).release()
    assert any("left by an interrupted run" in str(w.message) for w in caught)
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_an_earlier_footnavs_lock_names_nothing_so_its_leftovers_are_only_listed(tmp_path):
    leftover = tmp_path / ".res.deadbeef.partial"
    leftover.mkdir()
    (leftover / "left.csv").write_text("half")
    (tmp_path / ".res.footnav-lock").write_text("999999999\n")  # pid only: an earlier footnav's lock
    with pytest.warns(DataQualityWarning, match=r"earlier footnav.*\.res\.deadbeef\.partial"):
        claim_output(tmp_path / "res").release()
    assert sorted(p.name for p in tmp_path.iterdir()) == [".res.deadbeef.partial"]
    assert (leftover / "left.csv").read_text() == "half"


def test_simulate_and_evaluate_outputs_are_guarded_too(workspace, capsys):
    assert main(["simulate", "straight", "--out", ".", "--force"]) == 2
    assert main(["simulate", "straight", "--out", "sub", "--force"]) == 2
    assert main(["evaluate", "data", "--out", "data", "--force"]) == 2
    assert main(["evaluate", "data", "--csv", "notes.txt", "--force"]) == 2
    assert (workspace / "notes.txt").read_text() == "my notes\n"
    assert (workspace / "sub" / "keep.txt").read_text() == "keep me\n"
    assert (workspace / "data" / "left.csv").is_file()


def test_sigkill_at_any_moment_of_a_replacement_leaves_one_whole_result(workspace):
    import signal
    import time

    cmd = [sys.executable, "-m", "footnav.cli", "run", "--left", "data/left.csv", "--out", "res", "--force"]
    # a user's entries with footnav-like names beside the target survive every recovery (issue 30)
    (workspace / ".res.v2.partial.md").write_text("draft\n")
    (workspace / ".res.backup.partial").mkdir()
    (workspace / ".res.backup.partial" / "keep.txt").write_text("mine\n")
    (workspace / ".res.x.old").mkdir()
    (workspace / ".res.x.old" / MARKER).write_text("{}\n")
    mine = {".res.v2.partial.md", ".res.backup.partial", ".res.x.old"}
    users = _snapshot(workspace)
    assert subprocess.run(cmd, cwd=workspace, capture_output=True).returncode == 0
    whole = {
        "left.csv",
        "path.csv",
        "strides.csv",
        "trajectories.npz",
        "summary.json",
        "pipeline.toml",
        "report.html",
        MARKER,
    }
    start = time.perf_counter()
    subprocess.run(cmd, cwd=workspace, capture_output=True)
    duration = time.perf_counter() - start
    for fraction in (0.3, 0.6, 0.8, 0.9, 0.95, 0.99):
        proc = subprocess.Popen(cmd, cwd=workspace, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(fraction * duration)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DataQualityWarning)
            claim_output(workspace / "res", force=True).release()  # what the next run does first
        assert {p.name for p in (workspace / "res").iterdir()} == whole, fraction
        assert not [p for p in workspace.iterdir() if p.name.startswith(".res.") and p.name not in mine]
        assert {k: v for k, v in _snapshot(workspace).items() if not k.startswith("res/")} == users, fraction
