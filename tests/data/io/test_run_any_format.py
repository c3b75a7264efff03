"""``footnav run`` reads every format ``footnav.load`` reads, with the reader options as flags."""

import json

import numpy as np
import pytest

import footnav
from footnav.cli import main
from footnav.data.io import write_footnav_csv


def _ran(out, n_feet):
    doc = json.loads((out / "summary.json").read_text())
    assert doc["summary"]["left_stances"] > 5
    assert ("right_stances" in doc["summary"]) == (n_feet == 2)
    return doc


@pytest.mark.parametrize("as_file", [False, True])
def test_gaitmap_example_runs_both_feet(shared_file, tmp_path, capsys, as_file):
    imu_csv = shared_file("gaitmap_example", "imu_sample.csv")
    assert main(["run", "--left", str(imu_csv if as_file else imu_csv.parent), "--out", str(tmp_path / "o")]) == 0
    assert "holds both feet" in capsys.readouterr().err
    doc = _ran(tmp_path / "o", 2)
    assert doc["provenance"]["input"]["left"]["format"] == "gaitmap"
    assert (tmp_path / "o" / "strides.csv").read_text().startswith("foot,start_s,end_s,length_m,duration_s")


def test_xio_csv_with_its_duplicate_rows_runs(shared_file, tmp_path):
    assert (
        main(["run", "--left", str(shared_file("xio_gait_tracking", "short_walk.csv")), "--out", str(tmp_path / "o")])
        == 0
    )
    doc = _ran(tmp_path / "o", 1)
    assert doc["provenance"]["input"]["left"]["duplicates_dropped"]["count"] == 205


def test_pyshoe_mat_runs_and_refuses_unit_flags_it_cannot_take(shared_file, tmp_path, capsys):
    mat = shared_file("pyshoe_vicon", "2017-11-22-11-22-03.mat")
    assert main(["run", "--left", str(mat), "--out", str(tmp_path / "o")]) == 0
    _ran(tmp_path / "o", 1)
    assert main(["run", "--left", str(mat), "--acc-unit", "g", "--out", str(tmp_path / "p")]) == 2
    err = capsys.readouterr().err
    assert "--acc-unit does not apply to pyshoe files" in err and not (tmp_path / "p").exists()


def test_headerless_file_needs_the_rate_and_then_runs(tmp_path, capsys):
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    f = tmp_path / "h6.csv"
    np.savetxt(f, np.column_stack([rec.left.acc, rec.left.gyr]), delimiter=",")
    assert main(["run", "--left", str(f), "--out", str(tmp_path / "o")]) == 2
    assert "--rate-hz" in capsys.readouterr().err
    assert main(["run", "--left", str(f), "--rate-hz", "100", "--out", str(tmp_path / "o")]) == 0
    doc = _ran(tmp_path / "o", 1)
    # the right rate gives the right distance (a wrong one scales every length)
    assert doc["summary"]["left_path_length_m"] == pytest.approx(10.0, rel=0.1)


def test_a_two_foot_recording_with_right_is_refused(shared_file, tmp_path, capsys):
    folder = shared_file("gaitmap_example", "imu_sample.csv").parent
    rec = footnav.simulate("straight", seed=0, distance_m=5.0)
    one = tmp_path / "one.csv"
    write_footnav_csv(rec.left, one)
    assert main(["run", "--left", str(folder), "--right", str(one), "--out", str(tmp_path / "o")]) == 2
    assert "holds both feet already" in capsys.readouterr().err
