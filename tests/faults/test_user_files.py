"""The output claim touches only what footnav wrote (issue 30).

A user's entries beside an output, however footnav-like their names, and a user's files inside a
result folder survive every command, byte for byte; what killed runs left is still cleaned, but
only what their lock names.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import warnings
from pathlib import Path

import pytest

from footnav.cli import main
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.data import output
from footnav.data.output import MARKER, claim_output

pytestmark = pytest.mark.fault

#: Entries a user keeps beside ``--out res`` whose names look like footnav's temporary ones.
BESIDE = {
    ".res.v2.partial.md": "draft v2\n",
    ".res.backup.partial/keep.txt": "my backup\n",
    ".res.x.old/summary.json": '{"mine": true}\n',
    ".res.x.old/" + MARKER: '{"written_by": "footnav"}\n',  # a copy of a marker, even
    ".res.deadbeef.old/" + MARKER: "{}\n",  # an earlier footnav's spelling, no lock naming it
    ".res.footnav-lock.bak": "12345\n",
    ".res.footnav-1-0123abcd.partial": "named like footnav's, but no lock names it\n",
}


def _hashes(root: Path, skip: str | None = None) -> dict[str, str]:
    """SHA-256 of every file under ``root`` (except under ``root/skip``), by relative path."""
    out = {}
    for p in sorted(root.rglob("*")):
        rel = p.relative_to(root)
        if p.is_file() and not (skip and rel.parts[0] == skip):
            out[rel.as_posix()] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def _plant(root: Path, files: dict[str, str]) -> None:
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)


def _ours(root: Path) -> list[str]:
    """footnav's lock and temporary names left in ``root``."""
    return sorted(p.name for p in root.iterdir() if ".footnav-" in p.name and p.name not in BESIDE)


@pytest.fixture(scope="module")
def recording(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("walk") / "data"
    assert main(["simulate", "straight", "--seed", "1", "--set", "distance_m=8", "--out", str(folder)]) == 0
    return folder


@pytest.fixture
def ws(tmp_path, recording, monkeypatch):
    """A working folder with the recording in data/, notes, and the entries of :data:`BESIDE`."""
    root = tmp_path / "ws"
    root.mkdir()
    (root / "data").mkdir()
    for f in recording.iterdir():
        (root / "data" / f.name).write_bytes(f.read_bytes())
    _plant(root, {"notes.txt": "my notes\n", "sub/keep.txt": "keep me\n", **BESIDE})
    monkeypatch.chdir(root)
    return root


COMMANDS = {
    "run": ["run", "--left", "data/left.csv", "--right", "data/right.csv", "--out", "res"],
    "evaluate": ["evaluate", "data", "--out", "res"],
    "simulate": ["simulate", "straight", "--set", "distance_m=8", "--out", "res"],
    "follow": ["follow", "--left", "data/left.csv", "--idle-s", "0.5", "--out", "res"],
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_command_leaves_every_user_file_alone(ws, command, capsys):
    args = COMMANDS[command]
    before = _hashes(ws, skip="res")
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)  # a first run has nothing to recover
        assert main(args) == 0
    assert (ws / "res" / MARKER).is_file()
    assert _hashes(ws, skip="res") == before
    capsys.readouterr()
    assert main(args) == 2  # exists, no --force
    assert "--force" in capsys.readouterr().err
    assert _hashes(ws, skip="res") == before
    edited = json.loads((ws / "res" / MARKER).read_text())["files"][0]
    (ws / "res" / edited).write_text("edited by hand\n")  # footnav's file, changed: still footnav's
    assert main([*args, "--force"]) == 0
    assert _hashes(ws, skip="res") == before and _ours(ws) == []
    recorded = json.loads((ws / "res" / MARKER).read_text())
    assert sorted(recorded["files"]) == sorted(os.listdir(ws / "res"))[1:]  # all but the marker (sorted first)
    # a file of the user's inside the result: --force refuses, naming it, and nothing changes
    (ws / "res" / "notes.txt").write_text("mine\n")
    everything = _hashes(ws)
    capsys.readouterr()
    assert main([*args, "--force"]) == 2
    err = capsys.readouterr().err
    assert "notes.txt" in err and "did not write" in err and "Traceback" not in err
    assert _hashes(ws) == everything and _ours(ws) == []


def test_user_files_inside_a_result_make_force_refuse_naming_them(ws, capsys):
    assert main(COMMANDS["run"]) == 0
    _plant(ws / "res", {"notes.txt": "mine\n", "figs/a.png": "not a png\n"})
    for i in range(6):
        (ws / "res" / f"x{i}.txt").write_text(f"{i}\n")
    everything = _hashes(ws)
    capsys.readouterr()
    assert main([*COMMANDS["run"], "--force"]) == 2
    err = capsys.readouterr().err
    assert "8 entries footnav did not write" in err
    assert "(figs/, notes.txt, x0.txt, x1.txt, x2.txt and 3 more)" in err  # the first few, and how many
    assert _hashes(ws) == everything and _ours(ws) == []
    with pytest.raises(InvalidInputError) as refused:
        claim_output(ws / "res", force=True)
    assert refused.value.field == "out"


def test_a_users_folder_where_footnav_wrote_a_file_is_foreign(tmp_path):
    target = tmp_path / "res"
    with claim_output(target) as claim, claim.staged() as tmp:
        (tmp / "figs").mkdir()
        (tmp / "figs" / "a.png").write_text("footnav's\n")
        (tmp / "left.csv").write_text("footnav's\n")
    (target / "left.csv").unlink()
    (target / "left.csv").mkdir()
    (target / "left.csv" / "mine.txt").write_text("mine\n")
    (target / "figs" / "b.png").write_text("mine\n")
    with pytest.raises(InvalidInputError, match=r"2 entries .*figs/b\.png, left\.csv/"):
        claim_output(target, force=True)
    (target / "figs" / "b.png").unlink()
    (target / "left.csv" / "mine.txt").unlink()
    (target / "left.csv").rmdir()
    claim_output(target, force=True).release()  # footnav's sub-folder, footnav's files: replaceable


def test_a_marker_without_a_list_allows_only_footnavs_file_names(tmp_path):
    target = tmp_path / "res"
    _plant(
        target,
        {
            MARKER: '{"written_by": "footnav"}\n',
            "left.csv": "x\n",
            "summary.json": "{}\n",
            "pipeline-default.toml": "x\n",
        },
    )
    claim_output(target, force=True).release()
    _plant(target, {"plot.png": "mine\n"})
    with pytest.raises(InvalidInputError, match="plot.png"):
        claim_output(target, force=True)
    (target / "plot.png").unlink()
    with claim_output(target, force=True) as claim, claim.staged() as tmp:
        (tmp / "right.csv").write_text("new\n")
    assert sorted(os.listdir(target)) == [MARKER, "right.csv"]


def _dead_lock(folder: Path, target: str, *entries: tuple[str, str]) -> None:
    lines = [json.dumps({"footnav": "output-lock", "pid": 999999999})]
    lines += [json.dumps({"entry": name, "role": role}) for name, role in entries]
    (folder / f".{target}.footnav-lock").write_text("\n".join(lines) + "\n")


def test_a_killed_runs_named_entries_are_cleaned_and_nothing_else(ws, capsys):
    partial = ".res.footnav-999999999-0badc0de.partial"
    doomed = ".res.footnav-999999999-0badc0de.partial-old"
    _plant(
        ws,
        {
            f"{partial}/left.csv": "half\n",
            f"{doomed}/path.csv": "half\n",
            f"{doomed}/{MARKER}": json.dumps({"files": ["path.csv"], "folders": []}),
        },
    )
    # names that are not footnav's temporary spelling: a lock never makes footnav touch them
    _dead_lock(
        ws,
        "res",
        (partial, "partial"),
        (doomed, "doomed"),
        ("notes.txt", "partial"),
        ("../ws/notes.txt", "partial"),
        (".res.v2.partial.md", "partial"),
    )
    before = _hashes(ws, skip="res")
    before = {
        k: v
        for k, v in before.items()  # footnav's, and to go
        if k.split("/")[0] not in (partial, doomed, ".res.footnav-lock")
    }
    assert main(COMMANDS["run"]) == 0
    said = capsys.readouterr().err  # the command line prints footnav's warnings
    assert f"removed {partial}" in said and f"removed {doomed}" in said
    assert _hashes(ws, skip="res") == before and _ours(ws) == []


def test_a_killed_file_temp_is_cleaned_by_its_lock_only(tmp_path):
    temp = tmp_path / ".fig.png.footnav-999999999-0badc0de.partial.png"
    temp.write_bytes(b"half a figure")
    mine = tmp_path / ".fig.png.footnav-999999999-0badc0df.partial.png"  # no lock names it
    mine.write_bytes(b"mine")
    _dead_lock(tmp_path, "fig.png", (temp.name, "partial"))
    with pytest.warns(DataQualityWarning, match="removed .fig.png.footnav-999999999-0badc0de"):
        claim = claim_output(tmp_path / "fig.png", kind="file")
    with claim, claim.staged() as tmp:
        assert ".footnav-" in tmp.name and tmp.suffix == ".png"
        tmp.write_bytes(b"new figure")
    assert not temp.exists() and mine.read_bytes() == b"mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == [mine.name, "fig.png"]


def test_a_killed_replacement_is_put_back_from_its_lock(tmp_path):
    aside = tmp_path / ".res.footnav-999999999-0badc0de.old"
    _plant(aside, {"left.csv": "old\n", MARKER: json.dumps({"files": ["left.csv"], "folders": []})})
    _plant(tmp_path, {".res.x.old/left.csv": "mine\n", f".res.x.old/{MARKER}": "{}\n"})
    _dead_lock(tmp_path, "res", (aside.name, "aside"))
    with pytest.warns(DataQualityWarning, match="put back"):
        claim_output(tmp_path / "res", force=True).release()
    assert (tmp_path / "res" / "left.csv").read_text() == "old\n"
    assert (tmp_path / ".res.x.old" / "left.csv").read_text() == "mine\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".res.x.old", "res"]


def test_a_lock_that_is_not_footnavs_is_never_removed(tmp_path):
    lock = tmp_path / ".res.footnav-lock"
    lock.write_text("my own notes\n")
    with pytest.raises(InvalidInputError, match="not a readable footnav lock"):
        claim_output(tmp_path / "res")
    assert lock.read_text() == "my own notes\n"


def test_an_empty_lock_is_a_run_starting_until_it_is_old(tmp_path):
    lock = tmp_path / ".res.footnav-lock"
    lock.touch()  # a run between creating its lock and writing it: wait for it
    with pytest.raises(InvalidInputError, match="may be starting"):
        claim_output(tmp_path / "res")
    os.utime(lock, (lock.stat().st_atime - 60, lock.stat().st_mtime - 60))  # its writer died then
    with pytest.warns(DataQualityWarning, match="empty .res.footnav-lock"):
        claim_output(tmp_path / "res").release()
    assert list(tmp_path.iterdir()) == []


def test_files_added_to_the_old_result_during_the_run_are_kept(tmp_path):
    target = tmp_path / "res"
    with claim_output(target) as claim, claim.staged() as tmp:
        (tmp / "left.csv").write_text("old\n")
    claim = claim_output(target, force=True)
    with pytest.warns(DataQualityWarning, match="notes.txt"), claim, claim.staged() as tmp:
        (tmp / "left.csv").write_text("new\n")
        (target / "notes.txt").write_text("written while the run worked\n")
    kept = [p for p in tmp_path.iterdir() if p.name.endswith(".partial-old")]
    assert len(kept) == 1 and (kept[0] / "notes.txt").read_text() == "written while the run worked\n"
    assert (target / "left.csv").read_text() == "new\n"
    # the kept folder stays named in the lock: the next claim says so again, and still keeps it
    with pytest.warns(DataQualityWarning, match="kept .*notes.txt"):
        claim_output(target, force=True).release()
    assert (kept[0] / "notes.txt").is_file()


def _mode_bits_writable(path) -> bool:
    # as root os.access ignores the mode bits: judge by the owner's bits as a user would
    return os.stat(path).st_mode & stat.S_IWUSR != 0 and os.access(path, os.W_OK | os.X_OK)


@pytest.mark.parametrize("locked", ["res", "res/figs", "."])
def test_a_read_only_old_result_fails_before_anything_moves(ws, locked, monkeypatch, capsys):
    if os.geteuid() == 0:
        monkeypatch.setattr(output, "_writable", _mode_bits_writable)
    with claim_output("res") as claim, claim.staged() as tmp:
        (tmp / "figs").mkdir()
        (tmp / "figs" / "a.png").write_text("footnav's\n")
    everything = _hashes(ws)
    names = sorted(os.listdir(ws))
    os.chmod(locked, 0o555)
    try:
        capsys.readouterr()
        assert main([*COMMANDS["run"], "--force"]) == 2
        err = capsys.readouterr().err.strip()
        shown = locked
        assert len(err.splitlines()) == 1 and "permission denied" in err and f"{shown}'" in err, err
    finally:
        os.chmod(locked, 0o755)
    assert _hashes(ws) == everything and sorted(os.listdir(ws)) == names
