"""Every CLI failure: one line on stderr, exit 2 (input, usage, file system) or 1 (a bug), no
traceback unless -v (issue 14, deliverable 8)."""

from __future__ import annotations

import errno

import pytest

from footnav.cli import main

pytestmark = pytest.mark.fault


@pytest.fixture(scope="module")
def walk(tmp_path_factory):
    out = tmp_path_factory.mktemp("sim") / "walk"
    assert main(["simulate", "straight", "--seed", "1", "--out", str(out)]) == 0
    return out


#: The command line's notice while numba compiles (a first run with an empty cache) is not an error.
_COMPILE_NOTICE = ("footnav: compiling the numerical kernels", "footnav: compiled in ")


def _one_line(err: str) -> str:
    lines = [line for line in err.splitlines() if line.startswith("footnav") and not line.startswith(_COMPILE_NOTICE)]
    assert "Traceback" not in err and len(lines) == 1, err
    return lines[0]


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["simulate", "straight", "--seed", "-1", "--out", "x"], "a seed is an integer >= 0"),
        (["simulate", "straight", "--rate-hz", "0", "--out", "x"], "not a finite number > 0"),
        (["simulate", "straight", "--rate-hz", "nan", "--out", "x"], "not a finite number > 0"),
    ],
)
def test_bad_numbers_are_usage_errors(argv, expected, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    assert expected in _one_line(capsys.readouterr().err)


def test_a_binary_pipeline_file(walk, tmp_path, capsys):
    toml = tmp_path / "p.toml"
    toml.write_bytes(b"\xff\xfe[detector]\n")
    assert main(["run", "--left", str(walk / "left.csv"), "--pipeline", str(toml), "--out", str(tmp_path / "r")]) == 2
    assert "not a UTF-8 text file" in _one_line(capsys.readouterr().err)
    assert not (tmp_path / "r").exists()


def test_a_full_disk_leaves_nothing_and_says_so(walk, tmp_path, monkeypatch, capsys):
    import numpy as np

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp_path / "r" / "trajectories.npz"))

    monkeypatch.setattr(np, "savez", full)
    assert main(["run", "--left", str(walk / "left.csv"), "--out", str(tmp_path / "r")]) == 2
    assert "No space left on device" in _one_line(capsys.readouterr().err)
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no result, no partial folder, no lock


def test_a_bug_is_one_line_and_exit_1_with_the_traceback_under_v(walk, tmp_path, monkeypatch, capsys):
    from footnav.pipeline import factory as pipeline

    def bug(*args, **kwargs):
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr(pipeline.Pipeline, "run", bug)
    argv = ["run", "--left", str(walk / "left.csv"), "--out", str(tmp_path / "r")]
    assert main(argv) == 1
    line = _one_line(capsys.readouterr().err)
    assert "internal error: ZeroDivisionError" in line and "-v" in line
    with pytest.raises(ZeroDivisionError):
        main(["-v", *argv])


def test_simulate_refuses_a_negative_seed_by_name():
    import footnav
    from footnav.core.errors import InvalidParameterError

    with pytest.raises(InvalidParameterError, match="seed=-1 is invalid; expected an integer >= 0"):
        footnav.simulate(seed=-1)
