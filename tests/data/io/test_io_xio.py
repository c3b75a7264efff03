"""x-io Gait-Tracking CSV: g and deg/s, real time stamps with gaps and exact duplicate rows."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.io import read_xio

HEADER = (
    "Time (s),Gyroscope X (deg/s),Gyroscope Y (deg/s),Gyroscope Z (deg/s),"
    "Accelerometer X (g),Accelerometer Y (g),Accelerometer Z (g)"
)


def _write(path, n=40, dup_rows=(5, 20), gap_after=30):
    t = np.arange(n) * 0.0025
    t[gap_after:] += 0.01  # a 12.5 ms gap
    t = t.tolist()
    rows = []
    for i in range(n):
        row = f"{t[i]!r},{0.5 * i},-90,{1e-3 * i},{0.001 * i},0,1"
        rows.append(row)
        if i in dup_rows:
            rows.append(row)  # the logger repeats the row
    path.write_text(HEADER + "\n" + "\n".join(rows) + "\n")


def test_synthetic_exact_duplicates_are_dropped_by_default(tmp_path, warning_text):
    p = tmp_path / "walk.csv"
    _write(p)
    with pytest.warns(DataQualityWarning) as record:
        rec = read_xio(p)
    assert "dropped 2" in warning_text(record)
    # Row i=5 is on line 7 (header + rows 0..5); its copy on line 8 is sample index 6.
    assert rec.left.meta["duplicates_dropped"]["first_line"] == 8 and rec.left.n_samples == 40


def test_synthetic_drop_units_gap_truth(tmp_path, warning_text):
    p = tmp_path / "walk.csv"
    _write(p)
    with pytest.warns(DataQualityWarning) as record:
        rec = read_xio(p, drop_duplicates=True)
    text = warning_text(record)
    assert "dropped 2" in text and "gap" in text
    imu = rec.left
    assert imu.n_samples == 40
    dd = imu.meta["duplicates_dropped"]
    assert dd["count"] == 2 and dd["exact_row_copies"] == 2 and dd["first_line"] == 8
    assert imu.meta["gaps"] == [(30, pytest.approx(0.0125))]
    assert imu.acc[0, 2] == pytest.approx(GRAVITY_MPS2)  # g -> m/s^2
    assert imu.gyr[0, 1] == pytest.approx(-np.pi / 2)  # deg/s -> rad/s
    assert imu.meta["units_converted"] == {"acc": "g -> m/s^2", "gyr": "deg/s -> rad/s"}
    truth = rec.truth_left
    assert truth.closed_loop and len(truth.t) == 0 and truth.position.shape == (0, 3)
    assert rec.meta["format"] == "xio" and rec.meta["source"] == str(p)


def test_synthetic_header_units_are_read(tmp_path):
    p = tmp_path / "si.csv"
    hdr = HEADER.replace("(deg/s)", "(rad/s)").replace("(g)", "(m/s^2)")
    p.write_text(hdr + "\n0,0,0,1,0,0,9.8\n0.01,0,0,1,0,0,9.8\n")
    imu = read_xio(p).left
    assert imu.gyr[0, 2] == 1.0 and imu.acc[0, 2] == 9.8
    p.write_text(HEADER.replace("(g)", "(furlong)") + "\n0,0,0,1,0,0,9.8\n")
    with pytest.raises(InvalidInputError, match="line 1.*unknown unit 'furlong'"):
        read_xio(p)


# -- the published walks ------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name, n_rows, n_dup, dup_line, dup_index, max_gap_ms",
    [("short_walk.csv", 16539, 205, 4, 2, 12.55), ("long_walk.csv", 28132, 252, 3, 1, 17.57)],
)
def test_shared_walks(shared_file, name, n_rows, n_dup, dup_line, dup_index, max_gap_ms):
    p = shared_file("xio_gait_tracking", name)
    # the publisher's own files: every repeated time stamp is an exact copy, dropped by default
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        rec = read_xio(p)
    assert any(issubclass(w.category, DataQualityWarning) and "dropped" in str(w.message) for w in record)
    imu = rec.left
    assert imu.meta["duplicates_dropped"]["count"] == n_dup
    assert (
        imu.meta["duplicates_dropped"]["first_line"] == dup_line
        and imu.meta["duplicates_dropped"]["indices"][0] == dup_index
    )
    assert imu.meta["duplicates_dropped"]["exact_row_copies"] == n_dup  # all exact copies
    assert imu.n_samples == n_rows - n_dup
    assert imu.rate_hz == pytest.approx(398.3, abs=1.0)
    gaps_ms = [dt * 1e3 for _, dt in imu.meta["gaps"]]
    assert max(gaps_ms) == pytest.approx(max_gap_ms, abs=0.05)
    still = imu.t < 1.0  # still at the start
    assert np.linalg.norm(imu.acc[still], axis=1).mean() == pytest.approx(GRAVITY_MPS2, rel=0.03)
    assert np.abs(imu.gyr[still]).mean() < 0.05
    assert np.abs(imu.gyr).max() > 5.0  # ~600 deg/s in swing, in rad/s
    assert rec.truth_left.closed_loop
