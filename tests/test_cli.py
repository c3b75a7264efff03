import json

import numpy as np
import pytest

import footnav
from footnav.cli import main


@pytest.fixture(scope="module")
def sim_csv(tmp_path_factory):
    out = tmp_path_factory.mktemp("sim")
    assert main(["simulate", "straight", "--seed", "1", "--out", str(out / "walk")]) == 0
    return out / "walk"


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert footnav.__version__ in capsys.readouterr().out


def test_plugins_lists_builtins(capsys):
    assert main(["plugins"]) == 0
    out = capsys.readouterr().out
    rows = {tuple(l.split()[:3]) for l in out.splitlines()[2:]}
    assert {("detector", "threshold", "footnav"), ("estimator", "ekf", "footnav"), ("fusion", "independent", "footnav")} <= rows
    assert "zupt_std_mps=0.01 [m/s]" in out


def test_run_writes_results_and_refuses_to_overwrite(sim_csv, tmp_path, capsys):
    out = tmp_path / "res"
    args = ["run", "--left", str(sim_csv / "left.csv"), "--right", str(sim_csv / "right.csv"), "--out", str(out)]
    assert main(args) == 0
    assert {p.name for p in out.iterdir()} == {"left.csv", "right.csv", "path.csv", "summary.json", "pipeline.toml"}
    doc = json.loads((out / "summary.json").read_text())
    assert doc["provenance"]["footnav_version"] == footnav.__version__
    assert doc["summary"]["left_path_length_m"] == pytest.approx(100.0, rel=0.05)
    left = np.loadtxt(out / "left.csv", delimiter=",")
    assert left.shape[1] == 15
    assert footnav.load_pipeline(out / "pipeline.toml").config() == footnav.make_pipeline().config()
    capsys.readouterr()
    assert main(args) == 2
    assert "--force" in capsys.readouterr().err
    assert main(args + ["--force"]) == 0


def test_bad_input_exits_2_with_one_line_and_leaves_no_folder(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n0,0,0,9.8,0,0,0\n0.01,nan,0,9.8,0,0,0\n0.02,0,0,9.8,0,0,0\n")
    out = tmp_path / "res"
    assert main(["run", "--left", str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "bad.csv" in err and "acc" in err
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [bad]


def test_missing_file_and_unknown_component_exit_2(sim_csv, tmp_path, capsys):
    assert main(["run", "--left", str(tmp_path / "nope.csv"), "--out", str(tmp_path / "o")]) == 2
    assert main(["run", "--left", str(sim_csv / "left.csv"), "--detector", "nope", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "no detector named 'nope'; available:" in err and "threshold" in err


def test_usage_error_exits_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["run", "--left"])
    assert exc.value.code == 2


def test_demo_prints_the_accuracy_table(tmp_path, capsys):
    fig = tmp_path / "demo.png"
    assert main(["demo", "--plot", str(fig)]) == 0
    out = capsys.readouterr().out
    lines = {l.split()[0]: l.split() for l in out.splitlines() if l.startswith(("left", "right"))}
    for foot in ("left", "right"):
        rmse = float(lines[foot][3])
        assert 0.0 < rmse < 1.0
    assert "final foot separation" in out
    assert fig.exists() and fig.stat().st_size > 10_000
