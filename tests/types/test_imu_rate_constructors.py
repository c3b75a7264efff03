"""ImuData from data without time stamps: ``rate_hz`` (issue 34), and sample numbers are not times."""

from __future__ import annotations

import numpy as np
import pytest

import footnav
from footnav.core.errors import InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData

pd = pytest.importorskip("pandas")


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=0, distance_m=10.0).left


def _frame(imu, acc_scale=1.0, gyr_scale=1.0):
    cols = [f"{s}_{a}" for s in ("acc", "gyr") for a in "xyz"]
    return pd.DataFrame(np.hstack([imu.acc * acc_scale, imu.gyr * gyr_scale]), columns=cols)


def test_from_arrays_with_rate_hz_makes_time_row_over_rate(walk):
    imu = ImuData.from_arrays(
        acc=walk.acc / GRAVITY_MPS2, gyr=np.degrees(walk.gyr), rate_hz=100.0, acc_unit="g", gyr_unit="deg/s"
    )
    np.testing.assert_allclose(imu.t, np.arange(len(walk)) / 100.0)
    np.testing.assert_allclose(imu.acc, walk.acc, atol=1e-12)
    np.testing.assert_allclose(imu.gyr, walk.gyr, atol=1e-12)
    assert imu.rate_hz == pytest.approx(100.0) and "100 Hz" in imu.meta["time_source"]


@pytest.mark.parametrize(
    "kwargs,match",
    [
        ({"t": "given", "rate_hz": 100.0}, "not both"),
        ({"rate_hz": 0.0}, "finite number > 0"),
        ({"rate_hz": 100.0, "t_unit": "ms"}, "no time stamps"),
        ({}, "no time: pass t"),
    ],
)
def test_from_arrays_time_or_rate_errors(walk, kwargs, match):
    if kwargs.get("t") == "given":
        kwargs["t"] = walk.t
    with pytest.raises(InvalidInputError, match=match):
        ImuData.from_arrays(acc=walk.acc, gyr=walk.gyr, **kwargs)


def test_from_dataframe_with_rate_hz(walk):
    imu = ImuData.from_dataframe(_frame(walk), rate_hz=100.0)
    np.testing.assert_allclose(imu.t, np.arange(len(walk)) / 100.0)
    np.testing.assert_allclose(imu.acc, walk.acc)


@pytest.mark.parametrize("time_column", ["t", None])
@pytest.mark.parametrize("index", ["range", "ints"])
def test_sample_number_index_is_not_a_time(walk, time_column, index):
    frame = _frame(walk)
    if index == "ints":
        frame.index = np.arange(len(frame), dtype=np.int64) + 5
    with pytest.raises(InvalidInputError, match=r"sample numbers.*rate_hz=") as err:
        ImuData.from_dataframe(frame, time_column=time_column)
    assert err.value.field == "rate_hz" and "t_unit" not in str(err.value)


def test_time_column_and_rate_hz_is_an_error(walk):
    frame = _frame(walk)
    frame["t"] = walk.t
    with pytest.raises(InvalidInputError, match="time column 't'"):
        ImuData.from_dataframe(frame, rate_hz=100.0)


def test_integer_step_time_hint_asks_for_the_rate_not_a_unit(walk):
    # sample numbers passed as t (in s: 1 Hz): the hint is rate_hz, not t_unit='ms' first
    with pytest.raises(InvalidInputError, match=r"look like sample numbers.*rate_hz") as err:
        ImuData.from_arrays(np.arange(len(walk)), walk.acc, walk.gyr)
    assert "pass t_unit" not in str(err.value)


def test_unit_hint_only_names_a_unit_with_a_plausible_rate(walk):
    # 100 Hz stamped in ms, declared s: 0.1 Hz; only ms gives a rate in 20-2000 Hz
    with pytest.raises(InvalidInputError, match=r"t_unit='ms' \(100 Hz\)") as err:
        ImuData.from_arrays(walk.t * 1e3, walk.acc, walk.gyr)
    assert "'us'" not in str(err.value)
    # any hint names only units whose rate falls in RATE_BOUNDS_HZ
    import re

    from footnav.core.types.imu_checks import RATE_BOUNDS_HZ, _unit_hint
    from footnav.core.types.units import _T_SCALE

    for raw_dt in (0.5, 3.0, 7e4, 1e7, 2.5e-6):
        hint = _unit_hint(raw_dt)
        for unit, _rate in re.findall(r"t_unit='(\w+)' \(([\d.e+]+) Hz\)", hint):
            assert RATE_BOUNDS_HZ[0] <= 1.0 / (raw_dt * _T_SCALE[unit]) <= RATE_BOUNDS_HZ[1]
