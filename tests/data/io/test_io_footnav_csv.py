"""footnav CSV: exact round trip, units, duplicates, comments."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.errors import DataNotFoundError, DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.data.io import read_footnav_csv, read_footnav_recording, write_footnav_csv

HEADER = "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z"


def _imu(n=40, mag=False, seed=1):
    rng = np.random.default_rng(seed)
    acc = np.array([0.1, -0.2, GRAVITY_MPS2]) + 0.01 * rng.standard_normal((n, 3))
    gyr = 0.005 * rng.standard_normal((n, 3))
    # Awkward floats: many digits, tiny and huge magnitudes, negative zero.
    acc[0] = [1e-300, -0.0, 1 / 3]
    gyr[1] = [np.pi, -np.e, 12.3456789123456789]
    t = np.cumsum(rng.uniform(0.009, 0.011, n))
    m = rng.standard_normal((n, 3)) * 40 if mag else None
    return ImuData.from_arrays(t, acc, gyr, m)


@pytest.mark.parametrize("mag", [False, True])
def test_round_trip_is_bit_exact(tmp_path, mag):
    imu = _imu(mag=mag)
    path = write_footnav_csv(imu, tmp_path / "walk.csv")
    text = path.read_text().splitlines()
    assert text[0].startswith("# units: t s, acc m/s^2, gyr rad/s")
    assert text[1] == HEADER + (",mag_x,mag_y,mag_z" if mag else "")
    back = read_footnav_csv(path)
    for name in ("t", "acc", "gyr") + (("mag",) if mag else ()):
        a, b = getattr(imu, name), getattr(back, name)
        assert np.array_equal(a.view(np.int64), b.view(np.int64)), name  # bit for bit, incl. -0.0
    assert back.meta["source"] == str(path)
    assert back.meta["format"] == "footnav_csv"
    assert back.meta["units_converted"] == {}


def test_units_are_converted_and_recorded(tmp_path):
    p = tmp_path / "g.csv"
    p.write_text(HEADER + "\n0,0,0,1,180,0,0\n20,0,0,1,0,-90,0\n")
    imu = read_footnav_csv(p, acc_unit="g", gyr_unit="deg/s", t_unit="ms")
    assert imu.acc[0, 2] == pytest.approx(GRAVITY_MPS2)
    assert imu.gyr[0, 0] == pytest.approx(np.pi)
    assert imu.gyr[1, 1] == pytest.approx(-np.pi / 2)
    assert imu.t[1] == pytest.approx(0.02)
    assert imu.meta["units_converted"] == {"t": "ms -> s", "acc": "g -> m/s^2", "gyr": "deg/s -> rad/s"}


def test_units_comment_is_used_and_a_contradiction_raises(tmp_path):
    p = tmp_path / "c.csv"
    comments = "# recorded by hand\n# units: t s, acc g, gyr deg/s\n"
    p.write_text(comments + HEADER + "\n0,0,0,1,0,0,0\n0.01,0,0,1,0,0,0\n")
    imu = read_footnav_csv(p)
    assert imu.acc[0, 2] == pytest.approx(GRAVITY_MPS2)
    with pytest.raises(InvalidInputError, match="line 2.*units comment says 'g'"):
        read_footnav_csv(p, acc_unit="m/s^2")


def test_duplicate_rows_raise_with_line_and_index_or_are_dropped_and_counted(tmp_path):
    p = tmp_path / "dup.csv"
    rows = ["0,0,0,9.8,0,0,0", "0.01,0,0,9.8,0,0,0", "0.01,0,0,9.8,0,0,0", "0.02,0,0,9.8,0,0,0", "0.02,0,0,9.8,0,0,0"]
    p.write_text("# a comment\n" + HEADER + "\n" + "\n".join(rows) + "\n")
    # exact copies of the previous row carry nothing: dropped by default, said and recorded
    for options in ({}, {"drop_duplicates": True}):
        with pytest.warns(DataQualityWarning, match="dropped 2"):
            imu = read_footnav_csv(p, **options)
        assert imu.n_samples == 3
        dd = imu.meta["duplicates_dropped"]
        assert dd["count"] == 2 and dd["first_line"] == 5 and dd["exact_row_copies"] == 2 and dd["conflicting"] == 0
    # a repeated time with other values is an error naming its line, unless the user drops it
    rows[4] = "0.02,1,0,9.8,0,0,0"
    p.write_text("# a comment\n" + HEADER + "\n" + "\n".join(rows) + "\n")
    with pytest.raises(InvalidInputError, match="different from the previous row") as err:
        read_footnav_csv(p)
    assert err.value.line == 7 and err.value.index == 4 and err.value.path == str(p)
    assert "dup.csv" in str(err.value) and "--drop-duplicates" in str(err.value)


def test_conflicting_duplicate_is_dropped_with_a_warning(tmp_path, warning_text):
    p = tmp_path / "conf.csv"
    p.write_text(HEADER + "\n0,0,0,9.8,0,0,0\n0.01,0,0,9.8,0,0,0\n0.01,5,0,9.8,0,0,0\n0.02,0,0,9.8,0,0,0\n")
    with pytest.warns(DataQualityWarning) as record:
        imu = read_footnav_csv(p, drop_duplicates=True)
    assert "different values" in warning_text(record) and "line 4" in warning_text(record)
    assert imu.meta["duplicates_dropped"]["conflicting"] == 1
    assert imu.acc[1, 0] == 0.0  # the first row of the time stamp was kept


def test_gap_is_reported(tmp_path):
    p = tmp_path / "gap.csv"
    t = [0, 0.01, 0.02, 0.03, 0.08, 0.09]
    p.write_text(HEADER + "\n" + "\n".join(f"{x},0,0,9.8,0,0,0" for x in t) + "\n")
    with pytest.warns(DataQualityWarning, match="gap"):
        imu = read_footnav_csv(p)
    assert imu.meta["gaps"] == [(4, pytest.approx(0.05))]


def test_backwards_time_raises_with_line(tmp_path):
    p = tmp_path / "back.csv"
    p.write_text(HEADER + "\n0,0,0,9.8,0,0,0\n0.02,0,0,9.8,0,0,0\n0.01,0,0,9.8,0,0,0\n")
    with pytest.raises(InvalidInputError, match="line 4.*backwards"):
        read_footnav_csv(p)


def test_header_errors(tmp_path):
    p = tmp_path / "h.csv"
    p.write_text("t,acc_x,acc_y,acc_z,gyr_x,gyr_y\n0,0,0,9.8,0,0\n")
    with pytest.raises(InvalidInputError, match=r"line 1.*missing \['gyr_z'\]"):
        read_footnav_csv(p)
    p.write_text("# only comments\n")
    with pytest.raises(InvalidInputError, match="only comment lines"):
        read_footnav_csv(p)
    with pytest.raises(DataNotFoundError, match="nope.csv"):
        read_footnav_csv(tmp_path / "nope.csv")


def test_unterminated_but_complete_last_line_is_accepted(tmp_path):
    p = tmp_path / "u.csv"
    p.write_text(HEADER + "\n0,0,0,9.8,0,0,0\n0.01,0,0,9.8,0,0,0")
    assert read_footnav_csv(p).n_samples == 2


def test_recording_of_two_feet(tmp_path):
    left = write_footnav_csv(_imu(seed=1), tmp_path / "l.csv")
    right = write_footnav_csv(_imu(seed=2), tmp_path / "r.csv")
    rec = read_footnav_recording(left, right)
    assert rec.n_feet == 2 and rec.truth_left is None
    assert rec.left.meta["foot"] == "left" and rec.right.meta["foot"] == "right"
    assert rec.meta["format"] == "footnav_csv" and rec.meta["files"] == {"left": str(left), "right": str(right)}
