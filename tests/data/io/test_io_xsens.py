"""Xsens MTw ASCII export: rate from the preamble, time from the uint16 PacketCounter (wrap, gaps)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.io import read_xsens

PREAMBLE = [
    "// General information:",
    "//  MT Manager version: 4.8.1",
    "// Device information:",
    "//  DeviceId: 00B41234",
    "// Device settings:",
    "//  Filter Profile: general(39.2)",
    "// Update Rate: 100.0Hz",
]
COLUMNS = ["PacketCounter", "SampleTimeFine", "Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z"] + [
    "Mag_X",
    "Mag_Y",
    "Mag_Z",
]


def _write(path, counters, *, sep="\t", preamble=PREAMBLE, columns=COLUMNS):
    rows = []
    for k, c in enumerate(counters):
        vals = {
            "PacketCounter": str(c),
            "SampleTimeFine": str(1000 * k),
            "Acc_X": "0.1",
            "Acc_Y": "-0.2",
            "Acc_Z": repr(GRAVITY_MPS2 + 1e-4 * k),
            "Gyr_X": "0.001",
            "Gyr_Y": repr(0.002 * k),
            "Gyr_Z": "0",
            "Mag_X": "0.5",
            "Mag_Y": "-0.3",
            "Mag_Z": "0.8",
        }
        rows.append(sep.join(vals[c] for c in columns))
    path.write_text("\n".join(list(preamble) + [sep.join(columns)] + rows) + "\n")


# 65530..65535, then 0, 1, (2 lost), 3, 4, (5, 6, 7 lost), 8, 9
COUNTERS = [65530, 65531, 65532, 65533, 65534, 65535, 0, 1, 3, 4, 8, 9]


def test_synthetic_wrap_and_gaps(tmp_path, warning_text):
    p = tmp_path / "mtw.txt"
    _write(p, COUNTERS)
    with pytest.warns(DataQualityWarning) as record:
        rec = read_xsens(p)
    text = warning_text(record)
    assert "4 lost packet(s) in 2 gap(s)" in text and "line 17" in text  # counter 3 is on line 17
    imu = rec.left
    assert imu.n_samples == 12
    # Time from the unwrapped counter, not the row number: continuous across the wrap.
    assert imu.t[0] == pytest.approx(655.30)
    assert np.diff(imu.t)[:7] == pytest.approx(np.full(7, 0.01))
    assert imu.t[6] == pytest.approx(655.36)  # counter 0 after 65535
    assert imu.duration_s == pytest.approx((65536 + 9 - 65530) / 100.0)  # 0.15 s, not 0.11 s
    assert imu.meta["counter_wraps"] == 1
    assert imu.meta["lost_packets"] == {"count": 4, "gaps": [(8, 1), (10, 3)]}
    assert imu.meta["gaps"] == [(8, pytest.approx(0.02)), (10, pytest.approx(0.04))]  # a single lost packet too
    assert imu.rate_hz == pytest.approx(100.0) and imu.meta["rate_source"] == "file (Update Rate)"
    assert imu.acc[0, 2] == pytest.approx(GRAVITY_MPS2) and imu.gyr[3, 1] == pytest.approx(0.006)
    assert imu.mag[0].tolist() == [0.5, -0.3, 0.8] and imu.meta["units_in"]["mag"] == "a.u."
    assert imu.meta["ignored_columns"] == ["SampleTimeFine"]
    assert any("wrapped 1" in c for c in rec.meta["changes"])


def test_synthetic_space_separated_without_mag_and_reordered(tmp_path):
    p = tmp_path / "mtw.txt"
    cols = ["Gyr_X", "Gyr_Y", "Gyr_Z", "PacketCounter", "Acc_X", "Acc_Y", "Acc_Z"]
    _write(p, [10, 11, 12], sep="  ", columns=cols)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        imu = read_xsens(p).left
    assert imu.mag is None and imu.t[0] == pytest.approx(0.10) and imu.acc[1, 0] == 0.1


def test_synthetic_duplicate_packet(tmp_path, warning_text):
    p = tmp_path / "dup.txt"
    _write(p, [1, 2, 2, 3])
    with pytest.raises(InvalidInputError) as err:
        read_xsens(p)
    assert err.value.line == 11 and err.value.index == 2 and "dup.txt" in str(err.value)
    with pytest.warns(DataQualityWarning) as record:
        imu = read_xsens(p, drop_duplicates=True).left
    # The repeated packet carries different values: dropped, but said so.
    assert "dropped 1" in warning_text(record) and "different values" in warning_text(record)
    assert imu.n_samples == 3 and imu.meta["lost_packets"]["count"] == 0 and imu.meta["gaps"] == []


def test_synthetic_rate_rules(tmp_path):
    p = tmp_path / "norate.txt"
    _write(p, [1, 2, 3], preamble=["// exported"])
    with pytest.raises(InvalidInputError, match="line 2.*Update Rate"):
        read_xsens(p)
    assert read_xsens(p, rate_hz=60.0).left.rate_hz == pytest.approx(60.0)
    q = tmp_path / "rate.txt"
    _write(q, [1, 2, 3])
    with pytest.raises(InvalidInputError, match="line 7.*file says 100 Hz"):
        read_xsens(q, rate_hz=60.0)


def test_synthetic_counter_backwards_and_bad_counter(tmp_path):
    p = tmp_path / "back.txt"
    _write(p, [100, 101, 99, 102])
    with pytest.raises(InvalidInputError, match="line 11.*out of order"):
        read_xsens(p)
    _write(p, [1, 2, 70000])
    with pytest.raises(InvalidInputError, match="line 11.*not a uint16"):
        read_xsens(p)


def test_synthetic_missing_columns(tmp_path):
    p = tmp_path / "cols.txt"
    _write(p, [1, 2], columns=["PacketCounter", "Acc_X", "Acc_Y", "Acc_Z"])
    with pytest.raises(InvalidInputError, match=r"line 8.*missing columns \['Gyr_X'"):
        read_xsens(p)


def test_acquisition_frequency_preamble(tmp_path):
    # The IPOL gait data set's exports carry one preamble line, "Acquisition frequency: 100 Hz",
    # and a float PacketCounter ("0.0"): the rate comes from that line, time from the counter.
    p = tmp_path / "ipol_like.txt"
    cols = ["PacketCounter", "Acc_X", "Acc_Y", "Acc_Z", "Gyr_X", "Gyr_Y", "Gyr_Z", "Mag_X", "Mag_Y", "Mag_Z"]
    rows = [
        f"{c:.1f}\t0.1\t-0.2\t{GRAVITY_MPS2 + 1e-4 * k!r}\t0.001\t{0.002 * k!r}\t0\t0.5\t-0.3\t0.8"
        for k, c in enumerate([0, 1, 2, 4, 5])
    ]
    p.write_text("\n".join(["Acquisition frequency: 50 Hz", "\t".join(cols)] + rows) + "\n")
    with pytest.warns(DataQualityWarning, match="1 lost packet"):
        imu = read_xsens(p).left
    assert imu.rate_hz == pytest.approx(50.0)
    assert imu.meta["rate_source"] == "file (Acquisition frequency)"
    np.testing.assert_allclose(imu.t, [0.0, 0.02, 0.04, 0.08, 0.10])
    assert imu.has_mag
    with pytest.raises(InvalidInputError, match="line 1.*file says 50 Hz"):
        read_xsens(p, rate_hz=100.0)
