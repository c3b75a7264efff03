"""Analytic motion profiles of the simulated foot: quintics, the min-jerk blend and the lift bump.

Each returns its value and first two time derivatives, so the IMU signals follow without
numerical differentiation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

# The lift bump 64 u^3 (1-u)^3 peaks at 1 for u = 1/2 and is flat to second order at both ends.
_BUMP_GAIN = 64.0


def _quintic_coefficients(p0: float, v0: float, p1: float, v1: float, duration: float) -> NDArray[np.float64]:
    """Coefficients c0..c5 in normalised time u in [0, 1] of the quintic from (p0, v0, 0) to (p1, v1, 0).

    Values in the unit of p, rates v in unit/s; zero acceleration at both ends keeps the profile
    second-order continuous with a rest or another such segment.
    """
    d0, d1 = v0 * duration, v1 * duration
    big_p = p1 - p0 - d0
    big_v = d1 - d0
    return np.array([p0, d0, 0.0, 10 * big_p - 4 * big_v, -15 * big_p + 7 * big_v, 6 * big_p - 3 * big_v])


def _polyval(c: NDArray, u: NDArray, duration: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Value and first two time derivatives of per-sample quintics ``c`` (N, 6) at ``u`` (N,)."""
    c0, c1, c2, c3, c4, c5 = c.T
    val = c0 + u * (c1 + u * (c2 + u * (c3 + u * (c4 + u * c5))))
    d1 = c1 + u * (2 * c2 + u * (3 * c3 + u * (4 * c4 + u * 5 * c5)))
    d2 = 2 * c2 + u * (6 * c3 + u * (12 * c4 + u * 20 * c5))
    return val, d1 / duration, d2 / duration**2


def _smoothstep(u: NDArray, duration: float) -> tuple[NDArray, NDArray, NDArray]:
    """Minimum-jerk 0 -> 1 blend and its time derivatives; rest (zero rate and acceleration) at both ends."""
    w = 1.0 - u
    return (u**3 * (10.0 - 15.0 * u + 6.0 * u**2), 30.0 * u**2 * w**2 / duration, 60.0 * u * w * (w - u) / duration**2)


def _bump(u: NDArray, duration: float) -> tuple[NDArray, NDArray, NDArray]:
    """0 -> 1 -> 0 lift profile 64 u^3 (1-u)^3 and its time derivatives, flat to second order at the ends."""
    g = u * (1.0 - u)
    dg = 1.0 - 2.0 * u
    return (
        _BUMP_GAIN * g**3,
        3 * _BUMP_GAIN * g**2 * dg / duration,
        3 * _BUMP_GAIN * g * (2 * dg**2 - 2 * g) / duration**2,
    )
