"""Clock synchronisation of two IMUs: from message exchanges (seed 002 Sec. 5B), or from the data.

Seed 002 (Chistyakov et al. 2021), Sec. 5B: a master (the phone) and an IMU exchange time-stamped
messages at the start and the end of a recording. Exchange i is ``[TM1_i, TI_i, TM2_i]``: master
time when the request leaves, IMU time when it is stamped, master time when the reply arrives.
With the IMU clock affine in master time, every exchange bounds the map::

    TM1_i < a TI_i + b < TM2_i

and two linear programs over ``x = [a, b]`` (LP1: min a, LP2: max a, subject to all bounds) give
the feasible interval of a (and of b); the estimate is the midpoint of the two solutions, and the
IMU's samples are mapped to master time by ``t = a t_imu + b - delay`` with ``delay`` the constant
radio latency measured separately (0.03 s for their Bluetooth LE link).

Without exchanges, :func:`align_from_data` finds the offset (and drift) between two feet's
clocks from the data: the envelope of the angular-rate energy, smoothed over more than a stride,
rises and falls with walking and standing on both feet at once; it aligns clocks to about half a
stride (within a stride the two feet's energies alternate, so a periodic gait cannot say more).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linprog
from scipy.signal import correlate

from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.core.types import ImuData

__all__ = ["ClockMap", "fit_clock", "align_from_data", "apply_clock"]


@dataclass(frozen=True)
class ClockMap:
    """Affine map from an IMU's clock to the reference (master) clock: ``t = a t_imu + b - delay``.

    Attributes
    ----------
    a, b
        Rate (dimensionless) and offset (s).
    a_bounds, b_bounds
        Feasible intervals of a and b given the exchanges (None for a data-driven estimate).
    delay_s
        Constant latency subtracted, s.
    n
        Exchanges used (or correlation windows for a data-driven estimate).
    method
        ``"exchanges"`` (seed 002 Sec. 5B) or ``"data"``.
    """

    a: float
    b: float
    a_bounds: tuple[float, float] | None
    b_bounds: tuple[float, float] | None
    delay_s: float
    n: int
    method: str

    def __call__(self, t_imu: ArrayLike) -> NDArray[np.float64]:
        """Reference-clock times of IMU times ``t_imu`` (s)."""
        return self.a * np.asarray(t_imu, dtype=float) + self.b - self.delay_s

    @property
    def drift_ppm(self) -> float:
        """Rate error of the IMU clock in parts per million (positive: the IMU clock runs slow)."""
        return (self.a - 1.0) * 1e6


def _vector(x: ArrayLike, field: str) -> NDArray[np.float64]:
    arr = np.asarray(x, dtype=float).reshape(-1)
    bad = np.flatnonzero(~np.isfinite(arr))
    if len(bad):
        raise InvalidInputError(f"exchange time {arr[bad[0]]!r} is not finite", field=field, index=int(bad[0]))
    return arr


def fit_clock(tm1: ArrayLike, ti: ArrayLike, tm2: ArrayLike, *, delay_s: float = 0.0) -> ClockMap:
    """Seed 002 Sec. 5B: a and b from message exchanges by two linear programs.

    Parameters
    ----------
    tm1, ti, tm2
        Per exchange: master time the request left, IMU time stamp, master time the reply
        arrived, s. Exchanges spread over the recording (seed 002: at its start and its end)
        pin the rate a; exchanges at one time only pin b.
    delay_s
        Constant radio latency to subtract from mapped times, s.

    Returns
    -------
    ClockMap
        ``a = (a1 + a2) / 2``, ``b = (b1 + b2) / 2`` from LP1 (min a) and LP2 (max a), with the
        feasible intervals.

    Raises
    ------
    InvalidInputError
        Fewer than 2 exchanges, arrays of different lengths, non-finite times, a reply before its
        request (``tm2 < tm1``), or no affine map fits all exchanges (a bad time stamp).
    """
    m1, i, m2 = _vector(tm1, "tm1"), _vector(ti, "ti"), _vector(tm2, "tm2")
    if not (len(m1) == len(i) == len(m2)):
        raise InvalidInputError(f"exchange arrays differ in length: tm1 {len(m1)}, ti {len(i)}, tm2 {len(m2)}", field="ti")
    if len(i) < 2:
        raise InvalidInputError(f"need at least 2 exchanges, got {len(i)}", field="ti")
    back = np.flatnonzero(m2 < m1)
    if len(back):
        raise InvalidInputError(
            f"reply received before its request was sent (tm2 {m2[back[0]]!r} < tm1 {m1[back[0]]!r})",
            field="tm2",
            index=int(back[0]),
        )
    if not np.isfinite(delay_s):
        raise InvalidParameterError(f"delay_s must be finite, got {delay_s!r}")
    # centre the IMU times: the LP is then well conditioned whatever the clocks' epochs
    i0 = float(np.mean(i))
    ic = i - i0
    a_ub = np.concatenate([np.column_stack([ic, np.ones_like(ic)]), -np.column_stack([ic, np.ones_like(ic)])])
    b_ub = np.concatenate([m2, -m1])
    sols = []
    for sign in (1.0, -1.0):  # LP1: min a, LP2: max a
        res = linprog(c=[sign, 0.0], A_ub=a_ub, b_ub=b_ub, bounds=[(None, None), (None, None)], method="highs")
        if res.status != 0:
            raise InvalidInputError(
                f"no affine clock map fits every exchange ({res.message.strip()}); a time stamp is wrong or the "
                "clock is not affine over the exchanges",
                field="ti",
            )
        sols.append(res.x)
    (a1, c1), (a2, c2) = sols
    b1, b2 = c1 - a1 * i0, c2 - a2 * i0  # back from centred times: a (t - i0) + c = a t + (c - a i0)
    return ClockMap(
        a=0.5 * (a1 + a2),
        b=0.5 * (b1 + b2),
        a_bounds=(float(min(a1, a2)), float(max(a1, a2))),
        b_bounds=(float(min(b1, b2)), float(max(b1, b2))),
        delay_s=float(delay_s),
        n=len(i),
        method="exchanges",
    )


def _energy(imu: ImuData, grid: NDArray[np.float64], smooth_s: float) -> NDArray[np.float64]:
    """|gyr|^2 on ``grid`` (s, the IMU's own clock), smoothed by a moving average of ``smooth_s``
    (0: raw), mean removed."""
    energy = np.interp(grid, imu.t, np.sum(imu.gyr**2, axis=1), left=0.0, right=0.0)
    if smooth_s > 0:
        w = max(1, int(round(smooth_s / (grid[1] - grid[0]))))
        energy = np.convolve(energy, np.ones(w) / w, mode="same")
    return energy - energy.mean()


def _lag(ref: NDArray, other: NDArray, dt: float, lo: float, hi: float) -> float:
    """Lag (s) in [lo, hi] at the peak of the cross-correlation of ``ref`` and ``other``
    (``other[n]`` matches ``ref[n + lag / dt]``), refined by a parabola through the peak."""
    xc = correlate(ref, other, mode="full", method="fft")
    lags = np.arange(-len(other) + 1, len(ref)) * dt  # other[n] matches ref[n + lag]
    keep = (lags >= lo) & (lags <= hi)
    xc, lags = xc[keep], lags[keep]
    if len(xc) == 0:
        raise InvalidInputError("recordings do not overlap within the offsets searched", field="t")
    k = int(np.argmax(xc))
    frac = 0.0
    if 0 < k < len(xc) - 1:
        y0, y1, y2 = xc[k - 1], xc[k], xc[k + 1]
        denom = y0 - 2 * y1 + y2
        frac = 0.5 * (y0 - y2) / denom if denom != 0 else 0.0
    return float(lags[k] - frac * dt)


def align_from_data(
    reference: ImuData,
    other: ImuData,
    *,
    rate_hz: float = 100.0,
    smooth_s: float = 3.0,
    max_offset_s: float = 60.0,
    drift: bool = False,
) -> ClockMap:
    """Offset (and drift) of ``other``'s clock against ``reference``'s, from the gyro energy.

    Both feet walk and stand together, so the envelope of |gyr|^2 smoothed over ``smooth_s``
    (more than a stride) is nearly the same curve on both clocks; its cross-correlation peak
    (parabolic sub-sample refinement) gives the offset. With ``drift=True`` the first and last
    thirds are aligned separately and the two offsets give the rate.

    Accuracy: about half a stride (0.5 s). The foot that starts walking first starts its
    envelope half a stride before the other, and nothing in a periodic gait tells which foot
    that was: within a stride the two feet's energies alternate, so any finer alignment is
    ambiguous by whole strides. Good enough to bring two clocks that are seconds or minutes apart
    onto one time line for the detectors and fusions that need that; for the millisecond
    alignment of seed 002 use exchanges (:func:`fit_clock`) or a synchronising event both feet
    record (a stamp with both feet).

    Returns
    -------
    ClockMap
        Maps ``other``'s times to ``reference``'s clock (``method="data"``).
    """
    for name, v in (("rate_hz", rate_hz), ("smooth_s", smooth_s), ("max_offset_s", max_offset_s)):
        if not (np.isfinite(v) and v > 0):
            raise InvalidParameterError(f"align_from_data: {name}={v!r}; expected a positive number")
    dt = 1.0 / rate_hz

    def offset(t_ref: tuple[float, float], t_oth: tuple[float, float]) -> float:
        g_ref = np.arange(t_ref[0], t_ref[1], dt)
        g_oth = np.arange(t_oth[0], t_oth[1], dt)
        if len(g_ref) < 4 or len(g_oth) < 4:
            raise InvalidInputError("recordings too short to align from the data", field="t")
        lag = _lag(_energy(reference, g_ref, smooth_s), _energy(other, g_oth, smooth_s), dt, -max_offset_s, max_offset_s)
        # other's sample at other-time g_oth[0] + s shows what reference shows at g_ref[0] + s + lag
        return g_ref[0] - g_oth[0] + lag

    r0, r1 = float(reference.t[0]), float(reference.t[-1])
    o0, o1 = float(other.t[0]), float(other.t[-1])
    if not drift:
        b = offset((r0, r1), (o0, o1))
        return ClockMap(a=1.0, b=b, a_bounds=None, b_bounds=None, delay_s=0.0, n=1, method="data")
    third_r, third_o = (r1 - r0) / 3, (o1 - o0) / 3
    b_start = offset((r0, r0 + third_r), (o0, o0 + third_o))
    b_end = offset((r1 - third_r, r1), (o1 - third_o, o1))
    t_start, t_end = o0 + third_o / 2, o1 - third_o / 2
    # reference = other + b(t): a = 1 + (b_end - b_start) / (t_end - t_start), b at t = 0
    a = 1.0 + (b_end - b_start) / (t_end - t_start)
    b = b_start + t_start - a * t_start
    return ClockMap(a=a, b=b, a_bounds=None, b_bounds=None, delay_s=0.0, n=2, method="data")


def apply_clock(imu: ImuData, clock: ClockMap) -> ImuData:
    """``imu`` with its times mapped to the reference clock; ``meta["clock"]`` records the map."""
    record = {"a": clock.a, "b": clock.b, "delay_s": clock.delay_s, "method": clock.method, "n": clock.n}
    return replace(imu, t=clock(imu.t), meta={**imu.meta, "clock": record})
