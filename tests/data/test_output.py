"""footnav.data.output: a claim's recovery acts on its own output's temporary names only.

A dead writer's lock is read as a list of entries to recover. Entries of *another* output, or a
user's names that look like footnav's (another extension, a longer token, a dot where the target
has another character), must be left alone even when such a lock names them: only names spelled
exactly ``.TARGET.footnav-PID-8HEX.(partial[.ext]|old|partial-old)`` are footnav's for TARGET.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

from footnav.core.errors import DataQualityWarning
from footnav.data.output import MARKER, claim_output

TOKEN = "footnav-999999999-0badc0de"


def _dead_lock(folder: Path, target: str, *entries: tuple[str, str]) -> None:
    lines = [json.dumps({"footnav": "output-lock", "pid": 0})]  # released with entries left: no writer
    lines += [json.dumps({"entry": name, "role": role}) for name, role in entries]
    (folder / f".{target}.footnav-lock").write_text("\n".join(lines) + "\n")


def _folder(path: Path, marked: bool = True) -> None:
    path.mkdir()
    (path / "left.csv").write_text("x\n")
    if marked:
        (path / MARKER).write_text(json.dumps({"files": ["left.csv"], "folders": []}))


def _claim(path: Path, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        claim_output(path, **kw).release()
    return " ".join(str(w.message) for w in caught if issubclass(w.category, DataQualityWarning))


def test_a_lock_naming_other_outputs_and_lookalikes_recovers_only_its_own(tmp_path):
    # mutant: output-entry-prefix-match, output-entry-unescaped, output-entry-any-token
    own = f".res.v2.{TOKEN}.partial"
    others = [
        f".res.v2x.{TOKEN}.partial",  # another output's (res.v2x)
        f".resxv2.{TOKEN}.partial",  # another output's (resxv2): the dot in res.v2 is a dot
        f".res.v2.{TOKEN}.partial.md",  # a user's notes, named like footnav's
        f".res.v2.{TOKEN}0.partial",  # a 9-digit token is not footnav's
        f".res.v2.{TOKEN}.partial-mine",
    ]
    for name in [own, *others]:
        _folder(tmp_path / name, marked=False)
    _dead_lock(tmp_path, "res.v2", *[(n, "partial") for n in [own, *others]])
    said = _claim(tmp_path / "res.v2")
    assert f"removed {own}" in said
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(others)
    for name in others:
        assert (tmp_path / name / "left.csv").read_text() == "x\n"


def test_a_file_outputs_lock_recovers_its_extension_only(tmp_path):
    own, other = f".fig.png.{TOKEN}.partial.png", f".fig.png.{TOKEN}.partial.pngx"
    for name in (own, other):
        (tmp_path / name).write_bytes(b"half")
    _dead_lock(tmp_path, "fig.png", (own, "partial"), (other, "partial"))
    _claim(tmp_path / "fig.png", kind="file")
    assert sorted(p.name for p in tmp_path.iterdir()) == [other]


def test_a_doomed_result_is_deleted_even_when_the_target_is_missing(tmp_path):
    # mutant: output-recover-aside-or. Only an *aside* result goes back in place, and only when
    # the target is missing; a result being deleted (partial-old) never becomes the output
    doomed = tmp_path / f".res.{TOKEN}.partial-old"
    _folder(doomed)
    _dead_lock(tmp_path, "res", (doomed.name, "doomed"))
    said = _claim(tmp_path / "res")
    assert "put back" not in said and f"removed {doomed.name}" in said
    assert list(tmp_path.iterdir()) == []


def test_an_aside_result_with_the_target_present_is_deleted_not_put_back(tmp_path):
    aside = tmp_path / f".res.{TOKEN}.old"
    _folder(aside)
    target = tmp_path / "res"
    _folder(target)
    (target / "left.csv").write_text("new\n")
    _dead_lock(tmp_path, "res", (aside.name, "aside"))
    said = _claim(target, force=True)
    assert "put back" not in said and f"removed {aside.name}" in said
    assert (target / "left.csv").read_text() == "new\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["res"]


@pytest.mark.parametrize("role", ["aside", "doomed"])
def test_a_file_where_a_folder_was_named_is_left_alone(tmp_path, role):
    name = f".res.{TOKEN}.old" if role == "aside" else f".res.{TOKEN}.partial-old"
    (tmp_path / name).write_text("mine\n")
    _dead_lock(tmp_path, "res", (name, role))
    said = _claim(tmp_path / "res")
    assert f"left {name} as it is" in said
    assert (tmp_path / name).read_text() == "mine\n"
