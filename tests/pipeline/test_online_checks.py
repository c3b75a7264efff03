"""footnav.pipeline.online_checks: the live stream judges the gyroscope's unit once the foot has
moved enough, at the push the rule names (a numpy count on the samples pushed so far).

The walk starts with 25 s of standing and its angular rate is divided by 57.3 (as if rad/s data
had been declared deg/s): the unit check must warn, but only once at least max(10, 0.2 s) samples
*and* 5 % of the window have |acc| more than 0.5 g off its median (a standing foot cannot tell a
unit)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.errors import DataQualityWarning
from footnav.core.types import GRAVITY_MPS2


@pytest.mark.parametrize("light_swings", [False, True])
def test_the_unit_check_waits_for_enough_motion_and_no_longer(light_swings):
    # mutant: online-check-standing-and, online-check-moving-one-sided. With light_swings the
    # specific force of every swing sample is scaled to 0.3 (|f| ~3 m/s^2, far *below* the
    # median): motion that only a two-sided count sees
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = footnav.simulate("straight", seed=1, distance_m=20.0, standstill_s=25.0)
    imu = rec.left
    gyr = imu.gyr / 57.3
    if light_swings:
        acc = imu.acc.copy()
        acc[~rec.truth_left.stance] *= 0.3
        imu = footnav.ImuData(t=imu.t, acc=acc, gyr=imu.gyr)
    chunk = 150  # 1.5 s per push (the check is tried at most once per second)
    stops = list(range(chunk, imu.n_samples, chunk))
    # the rule, on the samples pushed so far (each window check reads them all)
    expected = None
    for i, stop in enumerate(stops):
        if imu.t[stop - 1] - imu.t[0] < 10.0:
            continue
        norm = np.linalg.norm(imu.acc[:stop], axis=1)
        moving = np.count_nonzero(np.abs(norm - np.median(norm)) > 0.5 * GRAVITY_MPS2)
        if moving >= max(10, 0.2 * imu.rate_hz) and moving >= 0.05 * stop:
            expected = i
            break
    assert expected is not None and imu.t[stops[expected]] < 60.0
    assert _push_until_unit_warning(imu, gyr, stops) == expected


def test_the_window_check_is_tried_at_most_once_per_second_of_data():
    # mutant: online-check-window-due-and. Pushes of 0.4 s: once the first 10 s are in, the check
    # is tried at a push only when a second of data has passed since its last try, so the
    # warning comes at the first *tried* push where the foot has moved enough, which is not
    # the first push where it has (checked below: the case tells the two apart)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = footnav.simulate("straight", seed=1, distance_m=20.0, standstill_s=25.0)
    imu = rec.left
    gyr = imu.gyr / 57.3
    for chunk in (40, 30, 70, 90):
        stops = list(range(chunk, imu.n_samples, chunk))
        tried, first_moved, first_tried = -np.inf, None, None
        for i, stop in enumerate(stops):
            t_now = imu.t[stop - 1]
            norm = np.linalg.norm(imu.acc[:stop], axis=1)
            moving = np.count_nonzero(np.abs(norm - np.median(norm)) > 0.5 * GRAVITY_MPS2)
            enough = t_now - imu.t[0] >= 10.0 and moving >= max(10, 0.2 * imu.rate_hz) and moving >= 0.05 * stop
            if enough and first_moved is None:
                first_moved = i
            due = t_now - imu.t[0] >= 10.0 and t_now - tried >= 1.0
            if due:
                tried = t_now
                if enough:
                    first_tried = i
                    break
        if first_tried != first_moved:
            break
    assert first_moved is not None and first_tried is not None and first_tried > first_moved
    assert _push_until_unit_warning(imu, gyr, stops) == first_tried


def _push_until_unit_warning(imu, gyr, stops) -> int | None:
    """The index of the push (chunks ending at ``stops``) at which a one-foot stream first warns
    that the angular rate looks like deg/s, or None."""
    stream = footnav.make_pipeline("threshold", "ekf", "independent", estimator_params={"smoother": "step"}).online(
        feet=1
    )
    start = 0
    for i, stop in enumerate(stops):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            stream.push(left=(imu.t[start:stop], imu.acc[start:stop], gyr[start:stop]))
        start = stop
        if any(issubclass(w.category, DataQualityWarning) and "deg/s" in str(w.message) for w in caught):
            return i
    return None
