"""Every text reader on broken files: an InvalidInputError naming file, line (and column)."""

from __future__ import annotations

from pathlib import Path

import pytest

from footnav.core.errors import DataNotFoundError, InvalidInputError
from footnav.data.io import read_azure_fgo, read_footnav_csv, read_gaitmap, read_openshoe, read_xio, read_xsens

N_ROWS = 8


def _rows(sep, ncols, first=lambda i: f"{i * 0.01!r}", base=6.0):
    """Rows of plausible values (|acc| near gravity in the file's unit): readers check the units."""
    return [sep.join([first(i)] + [repr(base + 0.1 * (i + j)) for j in range(ncols - 1)]) for i in range(N_ROWS)]


def _footnav(tmp: Path):
    p = tmp / "f.csv"
    header = "# units: t s, acc m/s^2, gyr rad/s\nt,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n"
    p.write_text(header + "\n".join(_rows(",", 7)) + "\n")
    return p, lambda: read_footnav_csv(p), 3, ","


def _gaitmap(tmp: Path):
    p = tmp / "g.csv"
    axes = ["acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    top = ",".join(["sensor"] + ["left_sensor"] * 6 + ["right_sensor"] * 6)
    axis = ",".join(["axis"] + axes * 2)
    p.write_text(top + "\n" + axis + "\n" + "\n".join(_rows(",", 13, first=str)) + "\n")
    return p, lambda: read_gaitmap(p), 3, ","


def _azure(tmp: Path):
    header = "time_index,acc_x,acc_y,acc_z,gyro_x,gyro_y,gyro_z,is_zero_vel"
    rows = [",".join([str(i)] + [repr(6.0 + 0.1 * (i + j)) for j in range(6)] + ["1"]) for i in range(N_ROWS)]
    for name in ("imuMeasLeft.csv", "imuMeasRight.csv"):
        (tmp / name).write_text(header + "\n" + "\n".join(rows) + "\n")
    return tmp / "imuMeasLeft.csv", lambda: read_azure_fgo(tmp), 2, ","


def _xio(tmp: Path):
    p = tmp / "x.csv"
    header = (
        "Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),"
        "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)"
    )
    p.write_text(header + "\n" + "\n".join(_rows(",", 7, base=0.6)) + "\n")
    return p, lambda: read_xio(p), 2, ","


def _openshoe(tmp: Path):
    p = tmp / "o.txt"
    p.write_text("\n".join(_rows(",", 6)) + "\n")
    return p, lambda: read_openshoe(p), 1, ","


def _xsens(tmp: Path):
    p = tmp / "m.txt"
    p.write_text(
        "// Update Rate: 100.0Hz\nPacketCounter\tAcc_X\tAcc_Y\tAcc_Z\tGyr_X\tGyr_Y\tGyr_Z\n"
        + "\n".join(_rows("\t", 7, first=str))
        + "\n"
    )
    return p, lambda: read_xsens(p), 3, "\t"


FORMATS = {
    "footnav_csv": _footnav,
    "gaitmap": _gaitmap,
    "azure_fgo": _azure,
    "xio": _xio,
    "openshoe": _openshoe,
    "xsens": _xsens,
}


@pytest.fixture(params=sorted(FORMATS))
def valid(request, tmp_path):
    path, read, first_data_line, sep = FORMATS[request.param](tmp_path)
    read()  # the unbroken file reads
    return path, read, first_data_line, sep


def _check(err, path: Path, line: int):
    assert err.path == str(path) and err.line == line
    assert f"{path.name}' line {line}" in str(err)


def test_empty_file(valid):
    path, read, _, _ = valid
    path.write_text("")
    with pytest.raises(InvalidInputError, match="empty") as err:
        read()
    _check(err.value, path, 1)


def test_truncated_last_line(valid):
    path, read, first, sep = valid
    lines = path.read_text().splitlines()
    cells = lines[-1].split(sep)
    lines[-1] = sep.join(cells[:2]) + sep + cells[2][:2]  # cut off mid-row, no line ending
    path.write_text("\n".join(lines))
    with pytest.raises(InvalidInputError, match="truncated last line") as err:
        read()
    _check(err.value, path, first + N_ROWS - 1)


def test_wrong_number_of_columns(valid):
    path, read, first, sep = valid
    lines = path.read_text().splitlines()
    bad = first + 2  # 1-based line of the third data row
    lines[bad - 1] += sep + "1.5"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError, match="columns") as err:
        read()
    _check(err.value, path, bad)


def test_non_numeric_cell(valid):
    path, read, first, sep = valid
    lines = path.read_text().splitlines()
    bad = first + 4
    cells = lines[bad - 1].split(sep)
    cells[3] = "abc"
    lines[bad - 1] = sep.join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError, match="non-numeric value 'abc' in column") as err:
        read()
    _check(err.value, path, bad)
    assert err.value.field is not None


def test_nan_cell(valid):
    path, read, first, sep = valid
    lines = path.read_text().splitlines()
    bad = first + 1
    cells = lines[bad - 1].split(sep)
    cells[2] = "nan"
    lines[bad - 1] = sep.join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError, match="non-finite value 'nan'") as err:
        read()
    _check(err.value, path, bad)


def test_header_only(valid):
    path, read, first, _ = valid
    lines = path.read_text().splitlines()[: first - 1]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError) as err:
        read()
    assert err.value.path == str(path) and err.value.line is not None


@pytest.mark.parametrize(
    "read",
    [read_footnav_csv, read_gaitmap, read_azure_fgo, read_xio, read_openshoe, read_xsens],
    ids=lambda f: f.__name__,
)
def test_missing_file(tmp_path, read):
    with pytest.raises(DataNotFoundError, match="missing.csv"):
        read(tmp_path / "missing.csv")
