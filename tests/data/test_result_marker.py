"""footnav.data.result_marker: what a result folder's marker lets footnav delete, on crafted
folders (a user's file in a listed sub-folder named like the marker, a link where a listed folder
was, a marker naming a path outside, an earlier footnav's marker and a lookalike file name)."""

from __future__ import annotations

import json
import os

import pytest

from footnav.data.result_marker import MARKER, _delete_result, _foreign, _recorded


def _marker(root, files, folders=()):
    (root / MARKER).write_text(json.dumps({"files": list(files), "folders": list(folders)}))


def test_a_marker_named_file_in_a_sub_folder_is_the_users(tmp_path):
    # mutant: marker-foreign-any-level (only the top-level marker is footnav's)
    root = tmp_path / "res"
    (root / "figs").mkdir(parents=True)
    (root / "figs" / "a.png").write_bytes(b"png")
    (root / "figs" / MARKER).write_text("my notes")
    _marker(root, ["figs/a.png"], ["figs"])
    assert _foreign(root, _recorded(root)) == [f"figs/{MARKER}"]
    assert _delete_result(root) == [f"figs/{MARKER}"]
    assert (root / "figs" / MARKER).read_text() == "my notes"


def test_a_link_in_place_of_a_listed_folder_is_not_followed(tmp_path):
    # mutant: marker-inside-follows-links
    outside = tmp_path / "mine"
    outside.mkdir()
    (outside / "a.csv").write_text("mine\n")
    root = tmp_path / "res"
    root.mkdir()
    os.symlink(outside, root / "sub")
    _marker(root, ["sub/a.csv", "b.csv"], ["sub"])
    (root / "b.csv").write_text("x\n")
    left = _delete_result(root)
    assert (outside / "a.csv").read_text() == "mine\n"
    assert left == ["sub"] and not (root / "b.csv").exists()


def test_a_marker_naming_a_path_outside_names_nothing(tmp_path):
    # mutant: marker-relative-allows-parent
    (tmp_path / "victim.txt").write_text("mine\n")
    root = tmp_path / "res"
    root.mkdir()
    (root / "summary.json").write_text("{}")
    _marker(root, ["../victim.txt", "summary.json"])
    files, folders = _recorded(root)
    assert "../victim.txt" not in files and folders == set()
    _delete_result(root)
    assert (tmp_path / "victim.txt").read_text() == "mine\n"


def test_an_earlier_marker_allows_footnavs_file_names_exactly(tmp_path):
    # mutant: marker-legacy-prefix-match
    root = tmp_path / "res"
    root.mkdir()
    (root / MARKER).write_text("written by footnav 0.1\n")
    for name in ("summary.json", "pipeline-a.toml", "pipeline-a.toml.bak"):
        (root / name).write_text("x")
    files, _ = _recorded(root)
    assert "pipeline-a.toml" in files and "pipeline-a.toml.bak" not in files
    assert _foreign(root, (files, set())) == ["pipeline-a.toml.bak"]


@pytest.mark.parametrize("rel", ["", ".", "a/../b", "a//b"])
def test_odd_marker_entries_fall_back_to_the_legacy_names(tmp_path, rel):
    root = tmp_path / "res"
    root.mkdir()
    (root / "summary.json").write_text("{}")
    _marker(root, ["summary.json", rel])
    files, folders = _recorded(root)
    assert rel not in files and folders == set()
