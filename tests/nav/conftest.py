"""Helpers shared by the nav tests (imported: ``from .conftest import G, _gait, _imu``)."""

from __future__ import annotations

import numpy as np

from footnav.core.types import ImuData

G = 9.80665  # m/s^2, written out: not read from the library


def _imu(t, acc, gyr):
    return ImuData(t=t, acc=acc, gyr=gyr)


def _gait(rate_hz, swing_centres_s, duration_s, *, acc_swing=True, extra=()):
    """Gyro y bumps 9 sin^2 over 0.4 s centred at ``swing_centres_s`` (and (centre, height, width)
    bumps ``extra``), the foot lifted and lowered (8 sin(2 pi u) m/s^2) during each main bump."""
    t = np.arange(int(duration_s * rate_hz)) / rate_hz
    gyr = np.zeros((len(t), 3))
    acc = np.tile([0.0, 0.0, G], (len(t), 1))
    bumps = [(c, 9.0, 0.4) for c in swing_centres_s] + list(extra)
    for c, height, width in bumps:
        u = (t - (c - width / 2)) / width
        inside = (u >= 0) & (u <= 1)
        gyr[inside, 1] += height * np.sin(np.pi * u[inside]) ** 2
        if acc_swing and height == 9.0:
            acc[inside, 2] += 8.0 * np.sin(2 * np.pi * u[inside])
    return _imu(t, acc, gyr)
