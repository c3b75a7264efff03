"""The generic delimited-text route and the x-IMU CalInertialAndMag format (issue 34): hand-made
files, the loaded numbers against hand-computed SI values, through ``footnav.load`` and ``footnav run``."""

from __future__ import annotations

import json

import numpy as np
import pytest

import footnav
from footnav.cli import main
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.io import guess_format, load, read_delimited, read_ximu_cal

G = GRAVITY_MPS2
D2R = np.pi / 180.0
XIMU_HEADER = (
    "Packet number,Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),Accelerometer X (g),"
    "Accelerometer Y (g),Accelerometer Z (g),Magnetometer X (G),Magnetometer Y (G),Magnetometer Z (G)"
)


def _g_rows(n, sep=","):
    """acc (g) then gyr (deg/s): still sensor, a small ramp so no row repeats."""
    return [sep.join(["0.01", "-0.02", repr(1.0 + 0.001 * i), "1.5", "-3", repr(0.5 * i)]) for i in range(n)]


def test_plain_acc_gyr_header_without_time_needs_only_the_rate(tmp_path):
    p = tmp_path / "export.csv"
    p.write_text("AccX,AccY,AccZ,GyrX,GyrY,GyrZ\n" + "\n".join(_g_rows(12)) + "\n")
    assert guess_format(p)[0] == "delimited"
    with pytest.raises(InvalidInputError, match=r"no time column.*rate_hz=100") as err:
        load(p, acc_unit="g", gyr_unit="deg/s")
    assert err.value.field == "rate_hz" and err.value.path == str(p)
    rec = load(p, rate_hz=100.0, acc_unit="g", gyr_unit="deg/s")
    imu = rec.left
    np.testing.assert_allclose(imu.t, np.arange(12) / 100.0)
    np.testing.assert_allclose(imu.acc[3], [0.01 * G, -0.02 * G, 1.003 * G])
    np.testing.assert_allclose(imu.gyr[3], [1.5 * D2R, -3 * D2R, 1.5 * D2R])
    assert rec.meta["format"] == "delimited" and rec.meta["rate_hz"] == 100.0
    assert imu.meta["columns"] == {"acc": ["AccX", "AccY", "AccZ"], "gyr": ["GyrX", "GyrY", "GyrZ"]}
    assert "units_assumed" not in imu.meta


def test_defaulted_units_are_recorded_and_named_when_the_data_contradict_them(tmp_path):
    p = tmp_path / "export.csv"
    p.write_text("AccX,AccY,AccZ,GyrX,GyrY,GyrZ\n" + "\n".join(_g_rows(12)) + "\n")
    with pytest.raises(InvalidInputError, match=r"acc_unit='g'.*m/s\^2 was assumed.*--acc-unit") as err:
        load(p, rate_hz=100.0, gyr_unit="deg/s")
    assert err.value.field == "acc" and err.value.path == str(p)
    si = tmp_path / "si.csv"
    si.write_text("ax,ay,az,gx,gy,gz\n" + "\n".join(f"0.1,-0.2,{G!r},0.01,0,{0.001 * i!r}" for i in range(12)) + "\n")
    imu = load(si, rate_hz=50.0).left
    assert imu.meta["units_assumed"] == {"acc": "m/s^2", "gyr": "rad/s"}
    np.testing.assert_allclose(imu.acc[0], [0.1, -0.2, G])


@pytest.mark.parametrize("sep", [";", "\t", " "])
def test_delimiters_comments_and_columns_by_index_with_ms_time(tmp_path, sep):
    p = tmp_path / "log.txt"
    rows = [sep.join([repr(5.0 * i), *r.split(",")]) for i, r in enumerate(_g_rows(10))]
    p.write_text(
        "# logger v2\n# rate 200 Hz\n" + "\n".join(rows[:4]) + "\n# pause marker\n" + "\n".join(rows[4:]) + "\n"
    )
    rec = load(p, format="delimited", columns="t=0,acc=1:4,gyr=4:7", t_unit="ms", acc_unit="g", gyr_unit="deg/s")
    imu = rec.left
    np.testing.assert_allclose(imu.t, np.arange(10) * 0.005)
    np.testing.assert_allclose(imu.acc[9], [0.01 * G, -0.02 * G, 1.009 * G])
    np.testing.assert_allclose(imu.gyr[9, 2], 4.5 * D2R)


def test_columns_by_header_name_in_any_order_with_header_units(tmp_path):
    p = tmp_path / "odd.csv"
    p.write_text(
        "w1 [deg/s],w2 [deg/s],w3 [deg/s],f1,f2,f3,stamp\n"
        + "\n".join(f"1.5,-3,{0.5 * i!r},0.01,-0.02,{1.0 + 0.001 * i!r},{0.01 * i!r}" for i in range(10))
        + "\n"
    )
    with pytest.raises(InvalidInputError, match=r"cannot tell the format.*--format delimited --columns"):
        guess_format(p)
    rec = load(
        p,
        format="delimited",
        columns={"t": "stamp", "acc": "f1,f2,f3", "gyr": ["w1 [deg/s]", "w2 [deg/s]", "w3 [deg/s]"]},
        acc_unit="g",
    )
    np.testing.assert_allclose(rec.left.gyr[4], [1.5 * D2R, -3 * D2R, 2.0 * D2R])  # deg/s from the header
    np.testing.assert_allclose(rec.left.acc[4, 2], 1.004 * G)
    np.testing.assert_allclose(rec.left.t, np.arange(10) * 0.01)


def test_unknown_header_error_gives_an_example_from_the_file(tmp_path):
    p = tmp_path / "mystery.csv"
    p.write_text("alpha,beta,gamma,delta,eps,zeta\n" + "\n".join(_g_rows(5)) + "\n")
    with pytest.raises(InvalidInputError) as err:
        load(p)
    assert "--format delimited --columns" in str(err.value) and "acc=alpha,beta,gamma,gyr=delta,eps,zeta" in str(
        err.value
    )
    assert "--rate-hz 100" in str(err.value)


def test_counter_column_is_not_a_time(tmp_path):
    p = tmp_path / "c.csv"
    counters = [0, 1, 2, 3, 5, 6, 7, 8, 9, 10]  # one packet lost after 3
    p.write_text(
        "SampleIndex,AccX,AccY,AccZ,GyrX,GyrY,GyrZ\n"
        + "\n".join(f"{c}," + r for c, r in zip(counters, _g_rows(10)))
        + "\n"
    )
    with pytest.raises(InvalidInputError, match=r"'SampleIndex' is a packet counter, not a time"):
        load(p, acc_unit="g", gyr_unit="deg/s")
    with pytest.warns(DataQualityWarning, match=r"counter column 'SampleIndex'.*index 4"):
        imu = load(p, rate_hz=100.0, acc_unit="g", gyr_unit="deg/s").left
    np.testing.assert_allclose(imu.t, np.arange(10) / 100.0)
    assert imu.meta["counter_irregular"]["first_index"] == 4 and imu.meta["counter_irregular"]["first_line"] == 6


def test_bad_inputs_are_named(tmp_path):
    p = tmp_path / "bad.csv"
    rows = _g_rows(10)
    rows[6] = rows[6].replace("-0.02", "n/a")
    p.write_text("AccX,AccY,AccZ,GyrX,GyrY,GyrZ\n" + "\n".join(rows) + "\n")
    with pytest.raises(InvalidInputError, match="non-numeric value 'n/a'") as err:
        load(p, rate_hz=100.0, acc_unit="g", gyr_unit="deg/s")
    assert (err.value.line, err.value.field) == (8, "AccY")
    q = tmp_path / "t.csv"
    q.write_text(
        "time,AccX,AccY,AccZ,GyrX,GyrY,GyrZ\n"
        + "\n".join(f"{0.01 * i!r}," + r for i, r in enumerate(_g_rows(10)))
        + "\n"
    )
    with pytest.raises(InvalidInputError, match="has a time column") as err:
        load(q, rate_hz=100.0)
    assert err.value.field == "rate_hz"
    for spec, match in (
        ("acc=1:3,gyr=4:7", "needs 3"),
        ("acc=AccQ,AccY,AccZ,gyr=4:7", "'AccQ'.*not found"),
        ("speed=1,acc=1:4,gyr=4:7", "unknown column group"),
        ("acc=1:4,gyr=5:8", "outside"),
    ):
        with pytest.raises(InvalidInputError, match=match) as err:
            read_delimited(q, columns=spec)
        assert err.value.field == "columns"


def test_ximu_cal_export(tmp_path):
    p = tmp_path / "CalInertialAndMag.csv"
    rows = [f"{i + 1},10,-20,{0.5 * i!r},0.01,-0.02,{1.0 + 0.001 * i!r},0.3,-0.1,-0.45" for i in range(20)]
    p.write_text(XIMU_HEADER + "\n" + "\n".join(rows) + "\n")
    assert guess_format(p)[0] == "ximu_cal"
    rec = load(p)
    imu = rec.left
    assert rec.meta["format"] == "ximu_cal"
    np.testing.assert_allclose(imu.t, np.arange(20) / 256.0)
    np.testing.assert_allclose(imu.gyr[2], [10 * D2R, -20 * D2R, 1.0 * D2R])
    np.testing.assert_allclose(imu.acc[2], [0.01 * G, -0.02 * G, 1.002 * G])
    np.testing.assert_allclose(imu.mag[2], [30.0, -10.0, -45.0])  # G -> uT
    assert imu.meta["columns"]["counter"] == ["Packet number"]
    np.testing.assert_allclose(read_ximu_cal(p, rate_hz=128.0).left.t[1], 1 / 128.0)
    other = tmp_path / "x.csv"
    other.write_text("a,b\n1,2\n")
    with pytest.raises(InvalidInputError, match="not an x-IMU") as err:
        read_ximu_cal(other)
    assert err.value.path == str(other) and err.value.line == 1


def _walk_columns():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    return rec.left, rec.left.acc / G, np.degrees(rec.left.gyr)


def _summary(out):
    return json.loads((out / "summary.json").read_text())


def test_cli_runs_plain_ximu_and_mapped_tables_with_flags_only(tmp_path, capsys):
    left, acc_g, gyr_dps = _walk_columns()
    n = len(left)
    plain = tmp_path / "plain.csv"
    np.savetxt(
        plain,
        np.column_stack([acc_g, gyr_dps]),
        delimiter=",",
        header="AccX,AccY,AccZ,GyrX,GyrY,GyrZ",
        comments="",
        fmt="%.10g",
    )
    assert (
        main(
            [
                "run",
                "--left",
                str(plain),
                "--rate-hz",
                "100",
                "--acc-unit",
                "g",
                "--gyr-unit",
                "deg/s",
                "--out",
                str(tmp_path / "a"),
            ]
        )
        == 0
    )
    doc = _summary(tmp_path / "a")
    assert doc["provenance"]["input"]["left"]["format"] == "delimited"
    assert doc["summary"]["left_path_length_m"] == pytest.approx(10.0, abs=0.5)
    ximu = tmp_path / "CalInertialAndMag.csv"
    np.savetxt(
        ximu,
        np.column_stack([np.arange(n) + 1, gyr_dps, acc_g, np.tile([0.3, -0.1, -0.45], (n, 1))]),
        delimiter=",",
        header=XIMU_HEADER,
        comments="",
        fmt="%.10g",
    )
    assert main(["run", "--left", str(ximu), "--rate-hz", "100", "--out", str(tmp_path / "b")]) == 0
    assert _summary(tmp_path / "b")["summary"]["left_path_length_m"] == pytest.approx(10.0, abs=0.5)
    mapped = tmp_path / "log.tsv"
    np.savetxt(
        mapped,
        np.column_stack([gyr_dps, left.t * 1e3, acc_g]),
        delimiter="\t",
        fmt="%.10g",
        header="exported by a logger",
        comments="# ",
    )
    assert (
        main(
            [
                "run",
                "--left",
                str(mapped),
                "--format",
                "delimited",
                "--columns",
                "t=3,acc=4:7,gyr=0:3",
                "--t-unit",
                "ms",
                "--acc-unit",
                "g",
                "--gyr-unit",
                "deg/s",
                "--out",
                str(tmp_path / "c"),
            ]
        )
        == 0
    )
    assert _summary(tmp_path / "c")["summary"]["left_path_length_m"] == pytest.approx(10.0, abs=0.5)
    capsys.readouterr()
    # --columns does not apply to a named format
    assert main(["run", "--left", str(ximu), "--columns", "acc=1:4,gyr=4:7", "--out", str(tmp_path / "d")]) == 2
    assert "--columns does not apply to ximu_cal" in capsys.readouterr().err


def test_footnav_columns_in_another_order_stay_footnav_csv_and_headerless_tables_map_by_index(tmp_path):
    p = tmp_path / "reordered.csv"
    p.write_text(
        "# units: t s, acc g, gyr deg/s\nacc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,t\n"
        + "\n".join(r + f",{0.01 * i!r}" for i, r in enumerate(_g_rows(10)))
        + "\n"
    )
    assert guess_format(p)[0] == "footnav_csv"
    np.testing.assert_allclose(load(p).left.gyr[2, 2], 1.0 * D2R)
    q = tmp_path / "bare.txt"
    q.write_text("\n".join(r.replace(",", " ") for r in _g_rows(10)) + "\n")
    rec = load(q, format="delimited", rate_hz=200.0, acc_unit="g", gyr_unit="deg/s")
    assert rec.left.meta["columns_found"].startswith("no header: 6 columns")
    np.testing.assert_allclose(rec.left.t[-1], 9 / 200.0)
    np.testing.assert_allclose(rec.left.acc[-1, 2], 1.009 * G)
