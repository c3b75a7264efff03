"""gaitmap example data: two header rows, deg/s, mocap in mm, stride events, clipping."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.io import read_gaitmap

AXES = ("acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")
RATE = 204.8


def _write_imu(path, n=40, clip_at=None, first="index"):
    """Interleaved layout like imu_sample.csv: left/right alternate per axis; gyro in deg/s."""
    rng = np.random.default_rng(3)
    top, axis, cols = ["sensor"], ["axis"], []
    for a in AXES:
        for s, sign in (("left_sensor", 1.0), ("right_sensor", -1.0)):
            top.append(s)
            axis.append(a)
            base = {"acc_z": GRAVITY_MPS2, "gyr_y": sign * 90.0}.get(a, 0.0)  # 90 deg/s on gyr_y
            cols.append(base + 0.01 * rng.standard_normal(n))
    data = np.column_stack(cols)
    if clip_at is not None:
        data[clip_at, AXES.index("acc_z") * 2] = 157.5  # left acc_z at NilsPod's 16 g
    col0 = np.arange(n) if first == "index" else np.arange(n) / RATE
    lines = [",".join(top), ",".join(axis)]
    lines += [f"{c0!r}," + ",".join(repr(v) for v in row) for c0, row in zip(col0.tolist(), data.tolist())]
    if first == "seconds":
        lines[0] = "," + lines[0].split(",", 1)[1]
        lines[1] = "," + lines[1].split(",", 1)[1]
    path.write_text("\n".join(lines) + "\n")
    return data


def _write_mocap(path, n=20):
    # R_FM5 before L_FM5 as in the published file: columns must be found by name.
    markers = ["L_TOE", "R_TOE", "L_FCC", "R_FCC", "R_FM5", "L_FM5"]
    top = [""] + [m for m in markers for _ in "xyz"]
    axis = [""] + [a for _ in markers for a in "xyz"]
    rows = []
    for i in range(n):
        vals = []
        for m in markers:
            side = 1000.0 if m.startswith("L") else 2000.0
            z = {"TOE": 50.0, "FCC": 40.0, "FM5": 45.0}[m.split("_")[1]]
            vals += [side + 10.0 * i, side / 2, z]
        rows.append(f"{i}," + ",".join(map(repr, vals)))
    path.write_text("\n".join([",".join(top), ",".join(axis)] + rows) + "\n")


def _write_events(path):
    path.write_text(
        "s_id,foot,start,end,ic,tc,min_vel,pre_ic\n"
        "0,left,5.0,15.0,12.0,8.0,5.0,2.0\n"
        "1,left,15.0,25.0,22.0,18.0,15.0,12.0\n"
        "2,right,10.0,20.0,17.0,13.0,10.0,7.0\n"
    )


def test_synthetic_units_mocap_events(tmp_path):
    imu_p, mocap_p, ev_p = tmp_path / "imu.csv", tmp_path / "mocap.csv", tmp_path / "ev.csv"
    _write_imu(imu_p)
    _write_mocap(mocap_p)
    _write_events(ev_p)
    rec = read_gaitmap(imu_p, mocap_p, ev_p)
    assert rec.n_feet == 2 and rec.left.n_samples == 40
    assert rec.left.rate_hz == pytest.approx(RATE)
    assert rec.left.t[1] == pytest.approx(1 / RATE)
    assert rec.left.gyr[:, 1].mean() == pytest.approx(np.pi / 2, abs=1e-3)  # 90 deg/s -> rad/s
    assert rec.right.gyr[:, 1].mean() == pytest.approx(-np.pi / 2, abs=1e-3)  # right columns not mixed up
    assert rec.left.acc[:, 2].mean() == pytest.approx(GRAVITY_MPS2, abs=1e-2)
    assert rec.meta["units_converted"] == {"gyr": "deg/s -> rad/s", "mocap": "mm -> m"}
    tl, tr = rec.truth_left, rec.truth_right
    assert tl.t[1] == pytest.approx(0.01)  # 100 Hz mocap
    assert tl.position[0] == pytest.approx([1.0, 0.5, 0.040])  # L_FCC, mm -> m
    assert tr.position[3] == pytest.approx([2.03, 1.0, 0.040])  # R_FCC
    assert tl.frame == "mocap"
    assert tl.events["heel_strike"].tolist() == [2, 12, 22]  # ic and pre_ic
    assert tl.events["toe_off"].tolist() == [8, 18]
    assert tl.events["mid_stance"].tolist() == [5, 15]
    assert tr.events["heel_strike"].tolist() == [7, 17]
    assert tl.meta["strides"].tolist() == [[5, 15], [15, 25]]


def test_synthetic_marker_mean(tmp_path):
    _write_imu(tmp_path / "imu.csv")
    _write_mocap(tmp_path / "mocap.csv")
    rec = read_gaitmap(tmp_path / "imu.csv", tmp_path / "mocap.csv", marker="mean")
    assert rec.truth_left.position[0, 2] == pytest.approx(0.045)  # mean of 50, 40, 45 mm


def test_synthetic_clipping_at_16g(tmp_path, warning_text):
    _write_imu(tmp_path / "imu.csv", clip_at=7)
    with pytest.warns(DataQualityWarning) as record:
        rec = read_gaitmap(tmp_path / "imu.csv")
    assert rec.left.meta["clipped"]["acc"] == 1 and rec.left.meta["clipped"]["first_index"] == 7
    assert "clipped" not in rec.right.meta
    assert "left foot" in warning_text(record)


def test_synthetic_time_column_in_seconds(tmp_path):
    _write_imu(tmp_path / "stair.csv", first="seconds")
    rec = read_gaitmap(tmp_path / "stair.csv")
    assert rec.meta["time_source"] == "first column = time in s"
    assert rec.left.rate_hz == pytest.approx(RATE)


def test_single_header_layout_is_refused(tmp_path):
    p = tmp_path / "ms.csv"
    p.write_text(",index,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n0,23000,0,0,9.8,0,0,0\n1,23001,0,0,9.8,0,0,0\n")
    with pytest.raises(InvalidInputError, match="line 2.*single-header"):
        read_gaitmap(p)


def test_event_not_a_sample_index(tmp_path):
    _write_imu(tmp_path / "imu.csv")
    ev = tmp_path / "ev.csv"
    ev.write_text("s_id,foot,start,end,ic,tc,min_vel,pre_ic\n0,left,5.0,15.0,12.5,8.0,5.0,2.0\n")
    with pytest.raises(InvalidInputError, match="line 2.*'ic'.*whole sample"):
        read_gaitmap(tmp_path / "imu.csv", events_path=ev)


# -- the published example ----------------------------------------------------------------------
def _read(shared_file, name, **kw):
    d = ("gaitmap_example",)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DataQualityWarning)  # the clipping warning is tested below
        return read_gaitmap(shared_file(*d, name), **kw)


def test_shared_imu_mocap_events(shared_file):
    d = "gaitmap_example"
    with pytest.warns(DataQualityWarning, match="full scale"):
        rec = read_gaitmap(
            shared_file(d, "imu_sample.csv"),
            shared_file(d, "mocap_sample.csv"),
            shared_file(d, "stride_events_sample.csv"),
        )
    for imu in (rec.left, rec.right):
        assert imu.n_samples == 7928
        assert imu.rate_hz == pytest.approx(204.8)
        assert imu.duration_s == pytest.approx(7927 / 204.8)
        still = slice(0, 100)  # the subject stands still at the start
        assert np.linalg.norm(imu.acc[still], axis=1).mean() == pytest.approx(GRAVITY_MPS2, abs=0.3)
        assert np.abs(imu.gyr[still]).max() < 0.05  # rad/s: deg/s were converted
        assert np.abs(imu.gyr).max() > 5.0  # swing reaches several rad/s
    # Clipping at +-16 g: six single-sample impact peaks per foot.
    assert rec.left.meta["clipped"]["acc"] == 6 and rec.left.meta["clipped"]["first_index"] == 659
    assert rec.right.meta["clipped"]["acc"] == 6 and rec.right.meta["clipped"]["first_index"] == 769
    for _foot, truth, n_strides in (("left", rec.truth_left, 28), ("right", rec.truth_right, 29)):
        assert len(truth.t) == 3870 and truth.t[-1] == pytest.approx(38.69)
        z = truth.position[:, 2]
        assert 0.02 < np.median(z) < 0.08  # heel ~5 cm above the floor: metres, z up
        assert z.max() > 0.2  # the heel rises in swing (z up, not down)
        assert np.ptp(truth.position[:, 0]) > 15.0  # the 20 m walk
        assert truth.meta["strides"].shape == (n_strides, 2)
        assert len(truth.events["toe_off"]) == n_strides
        # Heel strikes fall where the heel marker is low: the clocks agree.
        hs = truth.events["heel_strike"]
        z_at_hs = np.interp(hs / 204.8, truth.t, z)
        assert np.median(z_at_hs) < np.median(z) + 0.01
        to = truth.events["toe_off"]
        assert np.median(np.interp(to / 204.8, truth.t, z)) > 0.15  # heel high at toe off


def test_shared_not_rotated_is_the_same_data_by_name(shared_file):
    rot = _read(shared_file, "imu_sample.csv")
    raw = _read(shared_file, "imu_sample_not_rotated.csv")
    for a, b in ((rot.left, raw.left), (rot.right, raw.right)):
        assert np.allclose(np.linalg.norm(a.acc, axis=1), np.linalg.norm(b.acc, axis=1), atol=1e-9)
        assert np.allclose(np.linalg.norm(a.gyr, axis=1), np.linalg.norm(b.gyr, axis=1), atol=1e-9)
    assert np.allclose(rot.left.acc[:, 2], raw.left.acc[:, 0], rtol=0, atol=1e-12)  # raw x is gaitmap's z


def test_shared_stairs_and_ic_stride(shared_file):
    up = _read(shared_file, "imu_sample_healthy_stair_up.csv")
    assert up.left.n_samples == 5130 and up.meta["time_source"] == "first column = time in s"
    assert up.left.rate_hz == pytest.approx(204.8)
    ic = _read(shared_file, "imu_sample_ic_stride.csv", rate_hz=102.4)
    assert ic.right.n_samples == 4053 and ic.right.rate_hz == pytest.approx(102.4)
    with pytest.raises(InvalidInputError, match="single-header"):
        _read(shared_file, "imu_sample_ms_left.csv")
