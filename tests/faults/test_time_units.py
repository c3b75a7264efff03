"""Time base, rate, units and sensor checks: inputs that used to give large wrong results with no
warning (issue 14, deliverables 2 and 4). Each case is an error naming the field, or a
DataQualityWarning whose finding is recorded in ``meta``."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

import footnav
from footnav import DataQualityWarning, InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.data.io import load, read_footnav_csv
from footnav.data.io.footnav_csv import write_footnav_csv

pytestmark = pytest.mark.fault

pd = pytest.importorskip("pandas")


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=3, distance_m=12.0)


def _arrays(imu):
    return imu.t.copy(), imu.acc.copy(), imu.gyr.copy()


def _quiet(fn, *args, **kwargs):
    """Call with DataQualityWarning turned into an error: the clean input must pass silently."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DataQualityWarning)
        return fn(*args, **kwargs)


# -- time base -------------------------------------------------------------------------------------
@pytest.mark.parametrize("unit, scale", [("ms", 1e3), ("us", 1e6)])
def test_time_in_ms_or_us_read_as_seconds_is_an_error_naming_the_unit(walk, unit, scale):
    t, acc, gyr = _arrays(walk.left)
    with pytest.raises(InvalidInputError, match=f"t_unit='{unit}'") as err:
        ImuData.from_arrays(t * scale, acc, gyr)
    assert err.value.field == "t"
    imu = _quiet(ImuData.from_arrays, t * scale, acc, gyr, t_unit=unit)  # declared right: fine
    np.testing.assert_allclose(imu.t, t, rtol=1e-12, atol=1e-12)


def test_time_in_ms_in_a_file_is_an_error_naming_file_and_unit(walk, tmp_path):
    t, acc, gyr = _arrays(walk.left)
    path = write_footnav_csv(ImuData(t * 1e3, acc, gyr), tmp_path / "ms.csv")
    path.write_text(path.read_text().split("\n", 1)[1])  # no units comment: the file does not say
    with pytest.raises(InvalidInputError, match="t_unit='ms'") as err:
        read_footnav_csv(path)
    assert err.value.path == str(path)
    assert read_footnav_csv(path, t_unit="ms").rate_hz == pytest.approx(walk.left.rate_hz)


def test_seconds_declared_as_ms_is_an_error(walk):
    t, acc, gyr = _arrays(walk.left)
    with pytest.raises(InvalidInputError, match="that fast.*t_unit='s'"):
        ImuData.from_arrays(t, acc, gyr, t_unit="ms")


def test_datetime_column_is_converted_to_seconds_since_the_first_sample(walk):
    t, acc, gyr = _arrays(walk.left)
    start = pd.Timestamp("2024-05-01 12:00:00")
    frame = pd.DataFrame(np.hstack([acc, gyr]), columns=[f"{s}_{a}" for s in ("acc", "gyr") for a in "xyz"])
    frame["t"] = start + pd.to_timedelta(t - t[0], unit="s")
    imu = _quiet(ImuData.from_dataframe, frame)
    np.testing.assert_allclose(imu.t, t - t[0], atol=1e-9)
    assert imu.meta["t0_datetime"].startswith("2024-05-01T12:00:00")
    assert "datetime64" in imu.meta["time_converted"]


def test_time_zone_aware_datetime_index_is_converted(walk):
    t, acc, gyr = _arrays(walk.left)
    index = pd.DatetimeIndex(pd.Timestamp("2024-05-01 12:00", tz="Europe/Paris") + pd.to_timedelta(t, unit="s"))
    frame = pd.DataFrame(
        np.hstack([acc, gyr]), columns=[f"{s}_{a}" for s in ("acc", "gyr") for a in "xyz"], index=index
    )
    imu = _quiet(ImuData.from_dataframe, frame, time_column=None)
    np.testing.assert_allclose(imu.t, t - t[0], atol=1e-9)
    assert imu.meta["t0_datetime"].startswith("2024-05-01T10:00")  # UTC


def test_timedelta_column_is_converted_to_seconds(walk):
    t, acc, gyr = _arrays(walk.left)
    imu = _quiet(ImuData.from_arrays, pd.Series(pd.to_timedelta(t, unit="s")), acc, gyr)
    np.testing.assert_allclose(imu.t, t, atol=1e-9)
    assert imu.meta["time_converted"] == "timedelta64 -> s"


def test_datetime_with_a_missing_stamp_or_a_unit_is_an_error(walk):
    t, acc, gyr = _arrays(walk.left)
    stamps = np.datetime64("2024-01-01T00:00:00", "ns") + (t * 1e9).astype("timedelta64[ns]")
    stamps[7] = np.datetime64("NaT")
    with pytest.raises(InvalidInputError, match="NaT") as err:
        ImuData.from_arrays(stamps, acc, gyr)
    assert err.value.field == "t" and err.value.index == 7
    with pytest.raises(InvalidInputError, match="own unit") as err:
        ImuData.from_arrays(stamps[8:], acc[8:], gyr[8:], t_unit="ms")
    assert err.value.field == "t_unit"


def test_datetime_objects_are_refused_with_a_way_out(walk):
    t, acc, gyr = _arrays(walk.left)
    objects = list(pd.Timestamp("2024-01-01") + pd.to_timedelta(t, unit="s"))
    objects = np.array([x.to_pydatetime() for x in objects], dtype=object)
    with pytest.raises(InvalidInputError, match="datetime64") as err:
        ImuData.from_arrays(objects, acc, gyr)
    assert err.value.field == "t"


# -- rate --------------------------------------------------------------------------------------
@pytest.mark.parametrize("rate", [5.0, 10.0])
def test_low_rate_is_a_warning_naming_the_rate_and_recorded(rate):
    rec = footnav.simulate("straight", seed=1, distance_m=10.0, rate_hz=100.0)
    step = int(100 / rate)
    imu0 = rec.left
    with pytest.warns(DataQualityWarning, match=f"sampling rate {rate:g} Hz is below the 20-2000 Hz"):
        imu = ImuData.from_arrays(imu0.t[::step], imu0.acc[::step], imu0.gyr[::step])
    assert imu.meta["rate_check"]["rate_hz"] == pytest.approx(rate)
    # built without from_arrays, the run says it
    bare = ImuData(imu0.t[::step], imu0.acc[::step], imu0.gyr[::step])
    with pytest.warns(DataQualityWarning, match=f"{rate:g} Hz"):
        bare.check_units()


def test_high_rate_is_a_warning():
    n = 20000
    t = np.arange(n) / 5000.0
    acc = np.tile([0.0, 0.0, GRAVITY_MPS2], (n, 1))
    with pytest.warns(DataQualityWarning, match="5000 Hz is above") as caught:
        imu = ImuData.from_arrays(t, acc, np.zeros((n, 3)))
    assert imu.meta["rate_check"]["bounds_hz"] == [20.0, 2000.0] and len(caught) == 1


# -- units --------------------------------------------------------------------------------------
def test_deg_per_s_as_rad_per_s_on_a_mostly_still_recording_is_an_error(walk):
    t, acc, gyr = _arrays(walk.left)
    # one stride, then 3 minutes still: far less than 1 % of samples move
    n_still = int(180 * walk.left.rate_hz)
    first_stride = slice(int(2.5 * walk.left.rate_hz), int(4.0 * walk.left.rate_hz))
    t2 = np.concatenate([t[first_stride], t[first_stride][-1] + (np.arange(1, n_still + 1) / walk.left.rate_hz)])
    acc2 = np.vstack([acc[first_stride], np.tile([0.0, 0.0, GRAVITY_MPS2], (n_still, 1))])
    gyr2 = np.vstack([gyr[first_stride], np.zeros((n_still, 3))])
    assert np.percentile(np.linalg.norm(np.degrees(gyr2), axis=1), 99) < 40  # the old check's blind spot
    with pytest.raises(InvalidInputError, match="gyr_unit='deg/s'") as err:
        ImuData.from_arrays(t2, acc2, np.degrees(gyr2))
    assert err.value.field == "gyr" and err.value.index is not None


def test_rad_per_s_declared_as_deg_per_s_is_a_warning(walk):
    t, acc, gyr = _arrays(walk.left)
    with pytest.warns(DataQualityWarning, match="rad/s read as deg/s"):
        imu = ImuData.from_arrays(t, acc, gyr, gyr_unit="deg/s")
    assert imu.meta["gyr_unit_check"]["gyr_peak_radps"] < 0.5


@pytest.mark.parametrize("factor", [2.0, 0.5])
def test_accelerometer_off_by_2x_is_an_error_with_the_rest_reading(walk, factor):
    t, acc, gyr = _arrays(walk.left)
    with pytest.raises(InvalidInputError, match=f"m/s\\^2 at rest \\({factor:.2f} x g") as err:
        ImuData.from_arrays(t, acc * factor, gyr)
    assert err.value.field == "acc"


def test_accelerometer_7_percent_off_g_is_a_warning_with_the_value(walk):
    t, acc, gyr = _arrays(walk.left)
    with pytest.warns(DataQualityWarning, match=r"reads 10\.\d+ m/s\^2 at rest, \+[78]\.\d % off g"):
        imu = ImuData.from_arrays(t, acc * 10.6 / GRAVITY_MPS2, gyr)
    assert imu.meta["acc_at_rest"]["magnitude_mps2"] == pytest.approx(10.6, abs=0.05)
    _quiet(ImuData.from_arrays, t, acc * 1.02, gyr)  # 2 % off: within tolerance, no word


@pytest.mark.parametrize("dps", [250.0, 500.0, 1000.0, 2000.0])
def test_gyroscope_saturation_at_a_common_full_scale_is_a_warning(dps):
    rec = footnav.simulate("straight", seed=3, distance_m=12.0)
    t, acc, gyr = _arrays(rec.left)
    fs = np.radians(dps)
    gyr = gyr * (1.3 * fs / np.abs(gyr).max())  # the walk's peak beyond the range ...
    gyr = np.clip(gyr, -fs, fs)  # ... held flat at it
    first = int(np.argmax((np.abs(gyr) == fs).any(axis=1)))
    with pytest.warns(DataQualityWarning, match=f"full scale \\+-{dps:g} deg/s"):
        imu = ImuData.from_arrays(t, acc, gyr)
    assert imu.meta["clipped"]["gyr_full_scale"] == f"+-{dps:g} deg/s"
    assert imu.meta["clipped"]["gyr_first_index"] == first


@pytest.mark.parametrize("g", [2.0, 4.0, 8.0, 16.0])
def test_accelerometer_saturation_at_a_common_full_scale_is_a_warning(walk, g):
    t, acc, gyr = _arrays(walk.left)
    fs = g * GRAVITY_MPS2
    if np.abs(acc).max() <= fs:  # the walk must exceed the range
        acc = acc + np.where(np.abs(acc - [0, 0, GRAVITY_MPS2]) > 5, np.sign(acc) * fs, 0.0)
    acc = np.clip(acc, -fs, fs)
    with pytest.warns(DataQualityWarning, match=f"full scale \\+-{g:g} g"):
        imu = ImuData.from_arrays(t, acc, gyr)
    assert imu.meta["clipped"]["acc_full_scale"] == f"+-{g:g} g"
    assert imu.meta["clipped"]["first_index"] == int(np.argmax((np.abs(acc) == fs).any(axis=1)))


def test_a_clean_walk_raises_no_check(walk):
    t, acc, gyr = _arrays(walk.left)
    imu = _quiet(ImuData.from_arrays, t, acc, gyr)
    assert not {"rate_check", "gyr_unit_check", "acc_at_rest", "clipped"} & set(imu.meta)


# -- format guessing never invents a rate ---------------------------------------------------------------
def _headerless(walk, path):
    rows = np.hstack([walk.left.acc, walk.left.gyr])
    path.write_text("\n".join(",".join(f"{v:.6f}" for v in r) for r in rows.tolist()) + "\n")
    return path


def test_headerless_six_columns_are_refused_without_a_rate(walk, tmp_path):
    path = _headerless(walk, tmp_path / "sensor100hz.csv")
    with pytest.raises(InvalidInputError, match="rate_hz=") as err:
        load(path)
    assert err.value.field == "rate_hz" and err.value.path == str(path)
    rec = _quiet(load, path, rate_hz=100.0)  # the user says the rate: read, and recorded as guessed
    assert rec.meta["format"] == "openshoe" and rec.left.rate_hz == pytest.approx(100.0)
    assert rec.left.duration_s == pytest.approx(walk.left.duration_s)
    named = _headerless(walk, tmp_path / "OpenShoe_trial.txt")  # the name is the evidence for 820 Hz
    assert load(named).left.rate_hz == pytest.approx(820.0)


# -- bounded reading ---------------------------------------------------------------------------------
@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    for call in (lambda: read_footnav_csv(fifo), lambda: load(fifo)):
        with pytest.raises(InvalidInputError, match="FIFO") as err:
            call()
        assert err.value.path == str(fifo)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_a_device_is_refused():
    with pytest.raises(InvalidInputError, match="device"):
        read_footnav_csv("/dev/zero")
    with pytest.raises(InvalidInputError, match="device"):
        load("/dev/zero")


def test_a_file_above_the_size_limit_is_refused_with_how_to_raise_it(walk, tmp_path, monkeypatch):
    path = write_footnav_csv(walk.left, tmp_path / "big.csv")
    monkeypatch.setenv("FOOTNAV_MAX_INPUT_MB", str(path.stat().st_size / 2e6))
    with pytest.raises(InvalidInputError, match="FOOTNAV_MAX_INPUT_MB") as err:
        read_footnav_csv(path)
    assert err.value.path == str(path)
    monkeypatch.setenv("FOOTNAV_MAX_INPUT_MB", str(path.stat().st_size / 1e6 + 1))
    assert read_footnav_csv(path).n_samples == walk.left.n_samples
