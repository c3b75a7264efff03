"""OpenShoe: no header, 6 columns, t from the row index at 820 Hz, clipping plateaus."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.io import read_openshoe


def _write(path, acc, gyr):
    path.write_text("\n".join(",".join(f"{v:.8f}" for v in row) for row in np.hstack([acc, gyr]).tolist()) + "\n")


def test_synthetic_time_from_index(tmp_path, rest_imu):
    acc, gyr = rest_imu(100)
    p = tmp_path / "shoe.txt"
    _write(p, acc, gyr)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # clean data: no warning at all
        rec = read_openshoe(p)
    imu = rec.left
    assert imu.n_samples == 100 and imu.t[10] == pytest.approx(10 / 820.0)
    assert imu.rate_hz == pytest.approx(820.0)
    assert read_openshoe(p, rate_hz=100.0).left.duration_s == pytest.approx(0.99)
    assert np.allclose(imu.acc, acc, atol=1e-8) and "clipped" not in imu.meta
    assert "row index" in imu.meta["time_source"]


def test_synthetic_clipping_plateau(tmp_path, rest_imu):
    acc, gyr = rest_imu(100)
    acc[40:44, 2] = 160.0  # saturated: the same maximum code four times
    acc[70, 0] = -120.0  # a single large peak: not a plateau
    p = tmp_path / "clip.txt"
    _write(p, acc, gyr)
    with pytest.warns(DataQualityWarning, match="4 accelerometer sample"):
        imu = read_openshoe(p).left
    assert imu.meta["clipped"]["acc"] == 4 and imu.meta["clipped"]["first_index"] == 40


def test_synthetic_header_is_not_data(tmp_path):
    p = tmp_path / "h.txt"
    p.write_text("acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n0,0,9.8,0,0,0\n")
    with pytest.raises(InvalidInputError, match="h.txt' line 1.*non-numeric value 'acc_x'"):
        read_openshoe(p)


def test_shared_data_set(shared_file):
    p = shared_file("openshoe", "OpenShoeDataSet.txt")
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)  # no gaps, no clipping plateau
        rec = read_openshoe(p)
    imu = rec.left
    assert imu.n_samples == 51055 and imu.rate_hz == pytest.approx(820.0)
    assert imu.duration_s == pytest.approx(51054 / 820.0)
    for still in (imu.t < 2.5, imu.t > imu.t[-1] - 7.0):  # still at start and end
        assert np.linalg.norm(imu.acc[still], axis=1).mean() == pytest.approx(GRAVITY_MPS2, abs=0.1)
        assert imu.acc[still, 2].mean() > 9.5  # sensor z up
        assert np.abs(imu.gyr[still]).mean() < 0.03
    assert "clipped" not in imu.meta  # peaks up to ~17 g but no repeated maximum
    assert imu.meta["acc_max_abs_mps2"] == pytest.approx(165.28, abs=0.01)
    assert rec.truth_left is None
