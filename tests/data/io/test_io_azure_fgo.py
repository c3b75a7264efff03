"""azure_fgo: both feet at 60 Hz, z-down truth turned 180 deg about x, publisher detector in meta."""

from __future__ import annotations

import numpy as np
import pytest

from footnav.core.errors import DataNotFoundError, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.io import read_azure_fgo

IMU_HEADER = "time_index,acc_x,acc_y,acc_z,gyro_x,gyro_y,gyro_z,is_zero_vel"
GT_HEADER = "time_index,pos_left_x,pos_left_y,pos_left_z,pos_right_x,pos_right_y,pos_right_z"


def _write_folder(root, rest_imu, n=30):
    for k, name in enumerate(("imuMeasLeft.csv", "imuMeasRight.csv")):
        acc, gyr = rest_imu(n, seed=k)
        zv = (np.arange(n) % 10 < 5).astype(int)
        rows = [f"{i}," + ",".join(map(repr, [*acc[i].tolist(), *gyr[i].tolist()])) + f",{zv[i]}" for i in range(n)]
        (root / name).write_text(IMU_HEADER + "\n" + "\n".join(rows) + "\n")
    # Truth in the publisher's z-down frame (x forward, y right, z down): the feet walk along +x,
    # then turn RIGHT to +y, 0.1 m above the floor (z = -0.1).
    s = np.arange(n) / (n - 1)
    x = (np.minimum(s, 0.5) * 2).tolist()
    y = (np.maximum(s - 0.5, 0) * 2).tolist()
    rows = [f"{i},{x[i]!r},{y[i]!r},-0.1,{x[i]!r},{y[i] + 0.2!r},-0.12" for i in range(n)]
    (root / "positionGt.csv").write_text(GT_HEADER + "\n" + "\n".join(rows) + "\n")
    return np.array(x), np.array(y)


def test_synthetic_truth_is_rotated_not_mirrored(tmp_path, rest_imu):
    x, y = _write_folder(tmp_path, rest_imu)
    rec = read_azure_fgo(tmp_path)
    assert rec.n_feet == 2 and rec.left.n_samples == 30
    assert rec.left.rate_hz == pytest.approx(60.0) and rec.left.t[-1] == pytest.approx(29 / 60)
    tl = rec.truth_left
    assert np.allclose(tl.position[:, 0], x) and np.allclose(tl.position[:, 1], -y)
    assert np.allclose(tl.position[:, 2], 0.1)  # 0.1 m above the floor, z up
    assert np.allclose(rec.truth_right.position[:, 2], 0.12)
    assert np.linalg.det(np.array(tl.meta["rotation_matrix"])) == pytest.approx(1.0)  # a rotation
    # A right turn stays a right turn (clockwise seen from above); flipping z alone would make
    # it a left turn.
    d1 = tl.position[5] - tl.position[0]
    d2 = tl.position[-1] - tl.position[-6]
    assert np.cross(d1, d2)[2] < 0
    assert tl.t[3] == pytest.approx(3 / 60)


def test_synthetic_publisher_detector_is_meta_not_truth(tmp_path, rest_imu):
    _write_folder(tmp_path, rest_imu)
    rec = read_azure_fgo(tmp_path / "imuMeasLeft.csv")  # a file of the folder works too
    zv = rec.left.meta["publisher_zero_velocity"]
    assert zv.dtype == bool and zv[:5].all() and not zv[5:10].any()
    assert rec.truth_left.stance is None and rec.truth_right.stance is None
    assert "not truth" in rec.left.meta["publisher_zero_velocity_note"]


def test_synthetic_missing_and_bad_files(tmp_path, rest_imu):
    with pytest.raises(DataNotFoundError):
        read_azure_fgo(tmp_path / "nowhere")
    _write_folder(tmp_path, rest_imu)
    (tmp_path / "imuMeasRight.csv").unlink()
    with pytest.raises(DataNotFoundError, match="imuMeasRight.csv"):
        read_azure_fgo(tmp_path)
    _write_folder(tmp_path, rest_imu)
    p = tmp_path / "imuMeasLeft.csv"
    lines = p.read_text().splitlines()
    lines[3] = lines[3].rsplit(",", 1)[0] + ",2"
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(InvalidInputError, match="imuMeasLeft.csv' line 4.*is_zero_vel"):
        read_azure_fgo(tmp_path)


def test_synthetic_without_truth(tmp_path, rest_imu):
    _write_folder(tmp_path, rest_imu)
    (tmp_path / "positionGt.csv").unlink()
    rec = read_azure_fgo(tmp_path)
    assert rec.truth_left is None and rec.meta["truth_rotation"] is None


# -- the published recording --------------------------------------------------------------------
def _path_length(p):
    return float(np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1).sum())


def test_shared_recording(shared_file):
    rec = read_azure_fgo(shared_file("azure_fgo"))
    for _foot, imu, truth, length in (
        ("left", rec.left, rec.truth_left, 63.0),
        ("right", rec.right, rec.truth_right, 74.0),
    ):
        assert imu.n_samples == 7201 and imu.rate_hz == pytest.approx(60.0) and imu.duration_s == pytest.approx(120.0)
        zv = imu.meta["publisher_zero_velocity"]
        assert 0.2 < zv.mean() < 0.5
        # At the publisher's zero-velocity samples: |acc| ~ g, sensor z up, gyro small.
        assert np.linalg.norm(imu.acc[zv], axis=1).mean() == pytest.approx(GRAVITY_MPS2, abs=0.2)
        assert imu.acc[zv, 2].mean() > 9.0
        assert np.median(np.linalg.norm(imu.gyr[zv], axis=1)) < 0.2
        assert len(truth.t) == 7201 and np.array_equal(truth.t, imu.t)
        z = truth.position[:, 2]
        # z up after the rotation: positive, the foot lower in stance than in swing, bounded.
        assert 0.03 < np.median(z) < 0.15
        assert z[zv].mean() < z[~zv].mean()
        assert np.ptp(z) < 0.2
        assert _path_length(truth.position) == pytest.approx(length, rel=0.1)
        assert truth.stance is None


def test_shared_full_length_undoes_the_column_swap(shared_file):
    root = shared_file("azure_fgo")
    shared_file("azure_fgo", "ImuFootLeft.mat")
    full = read_azure_fgo(root, full_length=True)
    csv = read_azure_fgo(root)
    assert full.left.n_samples == 17402 and full.left.duration_s == pytest.approx(17401 / 60)
    off = full.meta["csv_offset_in_mat"]
    sl = slice(off, off + 7201)
    assert np.allclose(full.left.acc[sl], csv.left.acc, atol=1e-12)  # left = mat columns 7-12
    assert np.allclose(full.right.gyr[sl], csv.right.gyr, atol=1e-12)  # right = mat columns 1-6
    assert np.allclose(full.truth_left.position[sl], csv.truth_left.position, atol=1e-12)
    assert np.allclose(full.truth_right.position[sl], csv.truth_right.position, atol=1e-12)
    assert full.meta["undocumented_columns"].shape == (17402, 5)
