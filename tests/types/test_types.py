import warnings

import numpy as np
import pytest

from footnav import DataQualityWarning, ImuData, InvalidInputError, StanceResult
from footnav.core.types import GRAVITY_MPS2, stance_intervals


def _arrays(n=50, rate=100.0):
    t = np.arange(n) / rate
    acc = np.tile([0.0, 0.0, GRAVITY_MPS2], (n, 1))
    gyr = np.zeros((n, 3))
    return t, acc, gyr


def test_valid_data_is_read_only_and_reports_rate():
    t, acc, gyr = _arrays()
    imu = ImuData(t, acc, gyr)
    assert imu.rate_hz == pytest.approx(100.0)
    assert imu.duration_s == pytest.approx(0.49)
    with pytest.raises(ValueError):
        imu.acc[0, 0] = 1.0


def test_nan_in_acc_names_field_and_first_index():
    t, acc, gyr = _arrays()
    acc[7, 1] = np.nan
    acc[9, 0] = np.nan
    with pytest.raises(InvalidInputError) as err:
        ImuData(t, acc, gyr, meta={"source": "walk.csv"})
    assert err.value.field == "acc" and err.value.index == 7
    assert "walk.csv" in str(err.value) and "index 7" in str(err.value)


def test_backwards_time_names_first_bad_index():
    t, acc, gyr = _arrays()
    t[20] = t[18]
    with pytest.raises(InvalidInputError) as err:
        ImuData(t, acc, gyr)
    assert err.value.field == "t" and err.value.index == 20
    assert "backwards" in str(err.value)


def test_wrong_column_count():
    t, acc, gyr = _arrays()
    with pytest.raises(InvalidInputError) as err:
        ImuData(t, acc[:, :2], gyr)
    assert err.value.field == "acc" and "(N, 3)" in str(err.value)


def test_empty_and_single_sample_rejected():
    with pytest.raises(InvalidInputError, match="at least 2 samples"):
        ImuData(np.empty(0), np.empty((0, 3)), np.empty((0, 3)))


def test_length_mismatch():
    t, acc, gyr = _arrays()
    with pytest.raises(InvalidInputError) as err:
        ImuData(t, acc, gyr[:-1])
    assert err.value.field == "gyr"


def test_duplicates_are_an_error_unless_dropped_and_recorded():
    t, acc, gyr = _arrays()
    t = np.insert(t, 10, t[10])
    acc = np.insert(acc, 10, acc[10], axis=0)
    gyr = np.insert(gyr, 10, gyr[10], axis=0)
    with pytest.raises(InvalidInputError, match="duplicate") as err:
        ImuData.from_arrays(t, acc, gyr)
    assert err.value.index == 11
    with pytest.warns(DataQualityWarning, match="dropped 1"):
        imu = ImuData.from_arrays(t, acc, gyr, drop_duplicates=True)
    assert imu.n_samples == 50
    assert imu.meta["duplicates_dropped"] == {"count": 1, "indices": [11]}


def test_gap_is_warned_and_recorded():
    t, acc, gyr = _arrays()
    t[30:] += 0.05  # five missing samples before index 30
    with pytest.warns(DataQualityWarning, match="gap"):
        imu = ImuData(t, acc, gyr)
    assert imu.meta["gaps"] == [(30, pytest.approx(0.06))]


def test_no_warning_without_gap():
    t, acc, gyr = _arrays()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        imu = ImuData(t, acc, gyr)
    assert "gaps" not in imu.meta


@pytest.mark.parametrize(
    "kwargs, acc_scale, gyr_scale, t_scale",
    [
        (dict(acc_unit="g"), GRAVITY_MPS2, 1.0, 1.0),
        (dict(gyr_unit="deg/s"), 1.0, np.pi / 180, 1.0),
        (dict(t_unit="ms"), 1.0, 1.0, 1e-3),
    ],
)
def test_from_arrays_converts_units(kwargs, acc_scale, gyr_scale, t_scale):
    t = np.arange(5.0) * 10
    acc = np.ones((5, 3))
    gyr = np.full((5, 3), 2.0)
    imu = ImuData.from_arrays(t, acc, gyr, check_units=False, **kwargs)  # conversion only
    np.testing.assert_allclose(imu.acc, acc * acc_scale)
    np.testing.assert_allclose(imu.gyr, gyr * gyr_scale)
    np.testing.assert_allclose(imu.t, t * t_scale)


def test_unknown_unit_is_rejected_with_choices():
    t, acc, gyr = _arrays()
    with pytest.raises(InvalidInputError, match="m/s\\^2"):
        ImuData.from_arrays(t, acc, gyr, acc_unit="mg")


def test_stance_intervals_and_result():
    mask = np.array([1, 1, 0, 0, 1, 0, 1, 1, 1], dtype=bool)
    np.testing.assert_array_equal(stance_intervals(mask), [[0, 2], [4, 5], [6, 9]])
    res = StanceResult(mask)
    assert res.n_stances == 3
    with pytest.raises(InvalidInputError):
        StanceResult(mask, score=np.zeros(3))


def test_imu_from_a_pandas_dataframe_and_a_pipeline_on_dataframes():
    pd = pytest.importorskip("pandas")
    import footnav

    rec = footnav.simulate("straight", distance_m=5.0)
    cols = ["t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    frames = [pd.DataFrame(np.column_stack([imu.t, imu.acc, imu.gyr]), columns=cols) for imu in (rec.left, rec.right)]
    imu = ImuData.from_dataframe(frames[0])
    np.testing.assert_array_equal(imu.gyr, rec.left.gyr)
    deg = frames[0].assign(**{c: np.degrees(frames[0][c]) for c in ("gyr_x", "gyr_y", "gyr_z")})
    np.testing.assert_allclose(ImuData.from_dataframe(deg, gyr_unit="deg/s").gyr, rec.left.gyr, atol=1e-12)
    by_frame = footnav.make_pipeline().run(*frames)
    by_imu = footnav.make_pipeline().run(rec.left, rec.right)
    np.testing.assert_array_equal(by_frame.left.position, by_imu.left.position)
    with pytest.raises(InvalidInputError, match="gyr_y"):
        ImuData.from_dataframe(frames[0].drop(columns=["gyr_y"]))


@pytest.mark.parametrize(
    "acc_scale, gyr_scale, unit, field",
    [(1 / GRAVITY_MPS2, 1.0, "acc_unit='g'", "acc"), (1.0, 180 / np.pi, "gyr_unit='deg/s'", "gyr")],
)
def test_units_declared_wrong_are_caught_at_the_edge(acc_scale, gyr_scale, unit, field):
    import footnav

    rec = footnav.simulate("straight", distance_m=10.0)
    imu = rec.left
    with pytest.raises(InvalidInputError, match=unit) as err:
        ImuData.from_arrays(imu.t, imu.acc * acc_scale, imu.gyr * gyr_scale)
    assert err.value.field == field
    wrong = ImuData(imu.t, imu.acc * acc_scale, imu.gyr * gyr_scale)  # the constructor trusts its caller
    with pytest.raises(InvalidInputError, match=unit):
        footnav.make_pipeline().run(wrong)  # but a pipeline checks before it runs


def test_types_leave_the_callers_arrays_writeable():
    """footnav's types hold read-only views: the arrays a user passed in keep their own flags."""
    t = np.arange(200) / 100.0
    acc = np.tile([0.0, 0.0, 9.81], (200, 1))
    gyr = np.zeros((200, 3))
    imu = ImuData(t=t, acc=acc, gyr=gyr)
    assert t.flags.writeable and acc.flags.writeable and gyr.flags.writeable
    assert not (imu.t.flags.writeable or imu.acc.flags.writeable or imu.gyr.flags.writeable)
    assert np.shares_memory(imu.t, t)  # a view, not a copy
    mask = np.zeros(200, dtype=bool)
    stance = StanceResult(mask)
    assert mask.flags.writeable and not stance.mask.flags.writeable
