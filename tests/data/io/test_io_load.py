"""load(): guesses the format from the file, records and logs the guess; format= forces it."""

from __future__ import annotations

import logging
import warnings

import numpy as np
import pytest
from scipy.io import savemat

from footnav.core.errors import DataNotFoundError, DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.data.io import READERS, load, write_footnav_csv

KNOWN = {
    "footnav_folder",
    "footnav_csv",
    "gaitmap",
    "azure_fgo",
    "xio",
    "openshoe",
    "pyshoe",
    "xsens",
    "ipol",
    "gaitdriven",
    "ximu_cal",
    "delimited",
}


def _rows(n, sep=",", first=lambda i: repr(i * 0.01)):
    return [
        sep.join([first(i), "0.1", "-0.2", repr(GRAVITY_MPS2), "0.001", "0.002", repr(0.001 * i)]) for i in range(n)
    ]


def _make(kind, tmp):
    """A minimal valid file (or folder) of each format."""
    if kind == "footnav_csv":
        t = np.arange(10) * 0.01
        imu = ImuData.from_arrays(t, np.tile([0, 0, GRAVITY_MPS2], (10, 1)), np.zeros((10, 3)) + t[:, None])
        return write_footnav_csv(imu, tmp / "walk.csv")
    if kind == "footnav_folder":
        import footnav
        from footnav.data.io.footnav_csv import write_footnav_truth

        rec = footnav.simulate("straight", distance_m=3.0, standstill_s=0.5)
        folder = tmp / "sim"
        folder.mkdir()
        for foot in ("left", "right"):
            write_footnav_csv(getattr(rec, foot), folder / f"{foot}.csv")
            write_footnav_truth(getattr(rec, f"truth_{foot}"), folder / f"{foot}_truth.csv")
        return folder
    if kind == "xio":
        p = tmp / "walk.csv"
        p.write_text(
            "Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),"
            "Accelerometer Y (g),Accelerometer Z (g)\n"
            + "\n".join(f"{i * 0.01!r},0.1,-0.2,0.3,0.01,-0.02,{1.0 + 0.001 * i!r}" for i in range(10))
            + "\n"
        )
        return p
    if kind == "ximu_cal":
        p = tmp / "CalInertialAndMag.csv"
        p.write_text(
            "Packet number,Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),"
            "Accelerometer Y (g),Accelerometer Z (g),Magnetometer X (G),Magnetometer Y (G),Magnetometer Z (G)\n"
            + "\n".join(f"{i + 1},0.1,-0.2,0.3,0.01,-0.02,{1.0 + 0.001 * i!r},0.3,-0.1,-0.4" for i in range(10))
            + "\n"
        )
        return p
    if kind == "delimited":
        p = tmp / "export.csv"
        p.write_text("time;AccX;AccY;AccZ;GyrX;GyrY;GyrZ\n" + "\n".join(_rows(10, ";")) + "\n")
        return p
    if kind == "xsens":
        p = tmp / "MT_0123.txt"
        header = "// Update Rate: 100.0Hz\nPacketCounter\tAcc_X\tAcc_Y\tAcc_Z\tGyr_X\tGyr_Y\tGyr_Z\n"
        p.write_text(header + "\n".join(_rows(10, "\t", str)) + "\n")
        return p
    if kind == "openshoe":
        p = tmp / "OpenShoe_walk.txt"  # the name is the evidence for the 820 Hz rate
        p.write_text("\n".join(",".join(r.split(",")[1:]) for r in _rows(10)) + "\n")
        return p
    if kind == "gaitmap":
        p = tmp / "imu_sample.csv"
        axes = "acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"
        rows = [r + "," + ",".join(r.split(",")[1:]) for r in _rows(10, first=str)]
        header = "sensor" + ",left_sensor" * 6 + ",right_sensor" * 6 + "\naxis," + axes + "," + axes + "\n"
        p.write_text(header + "\n".join(rows) + "\n")
        return p
    if kind == "azure_fgo":
        for name in ("imuMeasLeft.csv", "imuMeasRight.csv"):
            (tmp / name).write_text(
                "time_index,acc_x,acc_y,acc_z,gyro_x,gyro_y,gyro_z,is_zero_vel\n"
                + "\n".join(r + ",1" for r in _rows(10, first=str))
                + "\n"
            )
        return tmp
    if kind == "pyshoe":
        p = tmp / "trial.mat"
        imu = np.tile([0.0, 0.0, -GRAVITY_MPS2, 0, 0, 0], (10, 1)) + 1e-3 * np.arange(60).reshape(10, 6)
        savemat(p, {"imu": imu, "ts": (np.arange(10) / 200.0)[None, :]})
        return p
    if kind == "gaitdriven":
        p = tmp / "SensorConnectData_99_LLIO.mat"
        imu = np.tile([0.0, 0.0, -GRAVITY_MPS2, 0, 0, 0], (10, 1)) + 1e-3 * np.arange(60).reshape(10, 6)
        savemat(
            p,
            {
                "imu_data": imu,
                "timestamps": (np.arange(10) / 200.0)[None, :],
                "strideIndex": np.array([[2, 9]]),
                "GCP": np.array([[0.0, 0.0], [0.6, 0.1]]),
            },
        )
        return p
    if kind == "ipol":
        header = "Acquisition frequency: 100 Hz\nPacketCounter\tAcc_X\tAcc_Y\tAcc_Z\tGyr_X\tGyr_Y\tGyr_Z\n"
        for foot in ("lf", "rf"):
            (tmp / f"2-3_{foot}.txt").write_text(header + "\n".join(_rows(10, "\t", str)) + "\n")
        p = tmp / "2-3.json"
        p.write_text('{"TrialBoundaries": [1, 8], "LeftFootEvents": [[2, 4]], "RightFootEvents": [[5, 7]]}')
        return p
    raise AssertionError(kind)


@pytest.mark.parametrize("kind", sorted(KNOWN))
def test_guesses_each_format_records_and_logs(tmp_path, caplog, kind):
    path = _make(kind, tmp_path)
    with caplog.at_level(logging.INFO, logger="footnav.data.io.load"):
        rec = load(path)
    assert rec.meta["format"] == kind and rec.meta["format_guessed"] is True
    assert any(kind in r.getMessage() and str(path) in r.getMessage() for r in caplog.records)
    forced = load(path, format=kind)
    assert forced.meta["format_guessed"] is False
    assert np.array_equal(forced.left.acc, rec.left.acc)


def test_readers_table():
    assert set(READERS) == KNOWN and all(callable(f) for f in READERS.values())


def test_azure_file_in_folder_reads_the_folder(tmp_path):
    _make("azure_fgo", tmp_path)
    rec = load(tmp_path / "imuMeasRight.csv")
    assert rec.meta["format"] == "azure_fgo" and rec.n_feet == 2


def test_unknown_format_lists_the_known_ones(tmp_path):
    p = _make("xio", tmp_path)
    with pytest.raises(InvalidInputError, match="unknown format 'csv'.*footnav_csv.*xsens"):
        load(p, format="csv")
    q = tmp_path / "notes.txt"
    q.write_text("hello, world\n")
    with pytest.raises(InvalidInputError, match="notes.txt' line 1.*known formats: .*pyshoe"):
        load(q)
    empty = tmp_path / "sub"
    empty.mkdir()
    with pytest.raises(InvalidInputError, match="folder.*known formats"):
        load(empty)
    m = tmp_path / "other.mat"
    savemat(m, {"x": np.zeros(3)})
    with pytest.raises(InvalidInputError, match=r"variables \['x'\] matches no known format"):
        load(m)


def test_missing_path(tmp_path):
    with pytest.raises(DataNotFoundError):
        load(tmp_path / "nope.csv")
    with pytest.raises(DataNotFoundError):
        load(tmp_path / "nope.csv", format="xio")


def test_forced_format_and_options_reach_the_reader(tmp_path):
    p = _make("openshoe", tmp_path)
    rec = load(p, format="openshoe", rate_hz=100.0)
    assert rec.left.rate_hz == pytest.approx(100.0)
    with pytest.raises(InvalidInputError):
        load(p, format="xio")  # wrong reader: its own error, not a silent misread


def test_shared_folders_and_files(shared_data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)
        cases = {
            "azure_fgo": shared_data / "azure_fgo",
            "gaitmap": shared_data / "gaitmap_example",
            "xio": shared_data / "xio_gait_tracking" / "long_walk.csv",
            "openshoe": shared_data / "openshoe" / "OpenShoeDataSet.txt",
            "pyshoe": shared_data / "pyshoe_vicon" / "2017-11-22-11-22-03.mat",
        }
        for fmt, path in cases.items():
            if not path.exists():
                continue
            rec = load(path, drop_duplicates=True)
            assert rec.meta["format"] == fmt and rec.meta["format_guessed"]
        if (shared_data / "gaitmap_example").exists():
            rec = load(shared_data / "gaitmap_example")
            # The folder guess brings the mocap and the events along.
            assert len(rec.truth_left.t) == 3870 and "heel_strike" in rec.truth_left.events


def test_footnav_folder_round_trips_the_simulated_truth(tmp_path):
    import footnav

    folder = _make("footnav_folder", tmp_path)
    rec = load(folder)
    sim = footnav.simulate("straight", distance_m=3.0, standstill_s=0.5)
    np.testing.assert_array_equal(rec.left.acc, sim.left.acc)
    np.testing.assert_array_equal(rec.truth_right.position, sim.truth_right.position)
    np.testing.assert_array_equal(rec.truth_left.stance, sim.truth_left.stance)
    assert rec.truth_left.closed_loop is False and rec.name == "sim"
