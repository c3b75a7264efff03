"""Fuzzing every reader with generated files: footnav's own errors or a result, never a crash."""

from __future__ import annotations

import tempfile
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from footnav.core.errors import FootnavError
from footnav.data.io import load, read_azure_fgo, read_footnav_csv, read_gaitmap, read_openshoe, read_xio, read_xsens

HEADERS = [
    "# units: t s, acc m/s^2, gyr rad/s\nt,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z",
    (
        "Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),"
        "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)"
    ),
    "// Update Rate: 100.0Hz\nPacketCounter\tAcc_X\tAcc_Y\tAcc_Z\tGyr_X\tGyr_Y\tGyr_Z",
    (
        "sensor,left_sensor,left_sensor,left_sensor,left_sensor,left_sensor,left_sensor,right_sensor,right_sensor,right_sensor,right_sensor,right_sensor,right_sensor\n"
        "axis,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"
    ),
    "time_index,acc_x,acc_y,acc_z,gyro_x,gyro_y,gyro_z,is_zero_vel",
    "",
]
cell = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-(10**6), 10**6).map(str),
    st.sampled_from(["", "nan", "NaN", "inf", "-", "1e999", "0x1F", "abc", " ", "9.81", "1,5"]),
    st.text(alphabet="0123456789.-eE+ ", max_size=8),
)
row = st.lists(cell, min_size=0, max_size=15).flatmap(
    lambda cells: st.sampled_from([",", "\t", ";"]).map(lambda sep: sep.join(cells))
)
content = st.tuples(st.sampled_from(HEADERS), st.lists(row, max_size=40), st.booleans()).map(
    lambda h: h[0] + ("\n" if h[0] else "") + "\n".join(h[1]) + ("\n" if h[2] else "")
)
binary = st.binary(max_size=400)

pytestmark = pytest.mark.fault  # malformed files are bad-input cases

READERS = [read_footnav_csv, read_xio, read_xsens, read_openshoe, read_gaitmap, load]
FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _try(read, path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # data-quality warnings are fine; crashes are not
        try:
            read(path)
        except FootnavError:
            pass


@FUZZ
@given(content)
def test_text_readers_never_crash(text):
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "f.csv"
        p.write_text(text, encoding="utf-8")
        for read in READERS:
            _try(read, p)


@FUZZ
@given(binary)
def test_binary_garbage_never_crashes(data):
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "f.csv"
        p.write_bytes(data)
        for read in READERS:
            _try(read, p)


@settings(max_examples=60, deadline=None)
@given(content, content)
def test_azure_folder_reader_never_crashes(left, right):
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "imuMeasLeft.csv").write_text(left, encoding="utf-8")
        (Path(tmp) / "imuMeasRight.csv").write_text(right, encoding="utf-8")
        _try(read_azure_fgo, Path(tmp))
        _try(load, Path(tmp))


def _valid_lines():
    import footnav
    from footnav.data.io.footnav_csv import write_footnav_csv

    rec = footnav.simulate("straight", distance_m=4.0, standstill_s=0.5)
    with tempfile.TemporaryDirectory() as tmp:
        return write_footnav_csv(rec.left, Path(tmp) / "w.csv").read_text().splitlines()


VALID = _valid_lines()
mutation = st.tuples(
    st.sampled_from(["replace_cell", "drop_line", "duplicate_line", "swap_lines", "truncate", "insert_text"]),
    st.integers(0, len(VALID) - 1),
    st.integers(0, 9),
    cell,
)


@FUZZ
@given(st.lists(mutation, min_size=1, max_size=6))
def test_mutated_valid_files_give_a_result_or_a_footnav_error(mutations):
    lines = list(VALID)
    for kind, i, j, value in mutations:
        i = min(i, len(lines) - 1)
        if kind == "replace_cell":
            cells = lines[i].split(",")
            cells[min(j, len(cells) - 1)] = value
            lines[i] = ",".join(cells)
        elif kind == "drop_line" and len(lines) > 3:
            del lines[i]
        elif kind == "duplicate_line":
            lines.insert(i, lines[i])
        elif kind == "swap_lines" and i + 1 < len(lines):
            lines[i], lines[i + 1] = lines[i + 1], lines[i]
        elif kind == "truncate":
            lines = lines[: max(1, i)]
            lines[-1] = lines[-1][:j]
        elif kind == "insert_text":
            lines.insert(i, value)
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "w.csv"
        p.write_text("\n".join(lines) + "\n")
        for read in (read_footnav_csv, load):
            _try(read, p)
