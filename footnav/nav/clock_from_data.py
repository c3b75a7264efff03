"""Clock offset (and drift) between two feet from their data, for recordings without clock exchanges.

Chistyakov et al. (2021), Sec. 5B synchronises the IMUs by message exchanges
(:func:`footnav.nav.clock_sync.fit_clock`). Without them, :func:`align_from_data` finds the
offset (and drift) between two feet's clocks from the angular-rate energy, as a
:class:`~footnav.nav.clock_sync.ClockMap` with ``method="data"``; see its Notes for what the
data can and cannot tell.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.core.types import ImuData
from footnav.core.warning_log import warn
from footnav.nav.clock_sync import ClockMap

__all__ = ["align_from_data"]

# Data fallback: the angular-rate energy is smoothed over this window (s) to find where each foot
# starts and stops walking, and a foot counts as moving above this fraction of the 99th
# percentile of its smoothed energy (a standstill is orders of magnitude below a swing).
_ACTIVITY_SMOOTH_S = 0.1
_ACTIVITY_FRACTION = 0.05
# Stride periods searched in the autocorrelation of the gyro energy, s (slow to brisk walking).
_STRIDE_RANGE_S = (0.5, 3.0)


# -- from the data --------------------------------------------------------------------------------


def _energy(imu: ImuData, grid: NDArray[np.float64], smooth_s: float) -> NDArray[np.float64]:
    """|gyr|^2 in (rad/s)^2 on ``grid`` (s, the IMU's own clock), moving average over ``smooth_s``
    (0: none)."""
    energy = np.interp(grid, imu.t, np.sum(imu.gyr**2, axis=1))
    w = int(round(smooth_s / (grid[1] - grid[0])))
    if w > 1:
        energy = np.convolve(energy, np.ones(w) / w, mode="same")
    return energy


def _parabolic(y: NDArray, k: int) -> float:
    """Sub-sample offset of the extremum of the parabola through ``y[k-1:k+2]`` (0 at an end)."""
    if not 0 < k < len(y) - 1:
        return 0.0
    y0, y1, y2 = y[k - 1], y[k], y[k + 1]
    denom = y0 - 2 * y1 + y2
    return float(0.5 * (y0 - y2) / denom) if denom != 0 else 0.0


class _Correlation:
    """Cross-correlation of two energies against the offset ``b`` (s) that aligns them:
    ``other``'s sample at its time ``t`` matches ``ref``'s at ``t + b``."""

    def __init__(self, ref: NDArray, other: NDArray, dt: float, b_zero: float) -> None:
        from scipy.signal import correlate  # here: scipy.signal takes ~0.3 s to import

        ref, other = ref - ref.mean(), other - other.mean()
        self.xc = correlate(ref, other, mode="full", method="fft")
        self.b = b_zero + np.arange(-len(other) + 1, len(ref)) * dt
        self.dt = dt

    def peak(self, lo: float, hi: float) -> float | None:
        """Offset of the highest correlation in [lo, hi], refined by a parabola; None if none."""
        keep = np.flatnonzero((self.b >= lo) & (self.b <= hi))
        if len(keep) == 0:
            return None
        k = int(keep[np.argmax(self.xc[keep])])
        return float(self.b[k] + _parabolic(self.xc, k) * self.dt)


def _stride_period(energy: NDArray, dt: float) -> float:
    """Stride period (s) at the autocorrelation peak of one foot's energy, parabola-refined."""
    from scipy.signal import correlate  # here: scipy.signal takes ~0.3 s to import

    e = energy - energy.mean()
    ac = correlate(e, e, mode="full", method="fft")[len(e) - 1 :]
    lo, hi = int(_STRIDE_RANGE_S[0] / dt), min(int(_STRIDE_RANGE_S[1] / dt), len(ac) - 2)
    if hi <= lo:
        raise InvalidInputError("recording too short to find a stride period in the gyro energy", field="t")
    k = lo + int(np.argmax(ac[lo:hi]))
    return (k + _parabolic(ac, k)) * dt


def _activity_span(imu: ImuData, dt: float) -> tuple[float, float, bool, bool]:
    """First and last time (s, own clock) the foot moves, and whether each lies inside the
    recording (a standstill before / after it) rather than at its edge."""
    grid = np.arange(imu.t[0], imu.t[-1], dt)
    e = _energy(imu, grid, _ACTIVITY_SMOOTH_S)
    moving = np.flatnonzero(e > _ACTIVITY_FRACTION * np.percentile(e, 99))
    if len(moving) == 0:
        return float(grid[0]), float(grid[-1]), False, False
    margin = int(round(1.0 / dt))  # a second of standstill at least
    return float(grid[moving[0]]), float(grid[moving[-1]]), moving[0] > margin, moving[-1] < len(grid) - 1 - margin


def align_from_data(
    reference: ImuData,
    other: ImuData,
    *,
    rate_hz: float = 100.0,
    smooth_s: float = 3.0,
    max_offset_s: float = 60.0,
    drift: bool = False,
    leading_foot: Literal["reference", "other"] | None = None,
) -> ClockMap:
    """Offset (and drift) of ``other``'s clock against ``reference``'s from the gyro energy.

    A fallback for two feet recorded without clock exchanges (Chistyakov et al. (2021), Sec. 5B synchronises by
    exchanges, :func:`fit_clock`). Both recordings should start and end with both feet still
    for a second or more; a recording that starts or ends mid-walk leaves the whole-stride
    choice open (a DataQualityWarning, candidates in ``alternatives_b``).

    Parameters
    ----------
    reference, other
        The two feet's recordings, each on its own clock (s).
    rate_hz
        Common grid on which the energies |gyr|^2 are resampled, Hz.
    smooth_s
        Moving-average window of the coarse (walking/standing envelope) step, s; more than a
        stride.
    max_offset_s
        Largest clock offset searched, s.
    drift
        Also estimate the rate: the first and last thirds of the recordings are aligned
        separately. Assumes the drift moves the clocks apart by less than half a stride over
        the recording (half of a 1.1 s stride over 10 min is 900 ppm).
    leading_foot
        Which foot started walking, if known (``"reference"`` or ``"other"``). Used only where
        the data leave two offsets a stride apart equally likely (see Notes).

    Returns
    -------
    ClockMap
        Maps ``other``'s times to ``reference``'s clock, ``method="data"``, ``n`` the windows
        correlated (1, or 2 with ``drift``), ``stride_s`` the stride period found and
        ``alternatives_b`` the offsets the data could not rule out.

    Raises
    ------
    InvalidParameterError
        A non-positive or non-finite ``rate_hz``, ``smooth_s`` or ``max_offset_s``, or an
        unknown ``leading_foot``.
    InvalidInputError
        Recordings too short, or not overlapping within ``max_offset_s``.

    Warns
    -----
    DataQualityWarning
        When the whole-stride choice is ambiguous and ``leading_foot`` is not given, or the
        data contradict ``leading_foot``; ``alternatives_b`` holds the other candidates.

    Notes
    -----
    The two feet swing alternately: within a stride the energy of one foot is high while the
    other's is low, so their energies are anti-phase and a plain cross-correlation peaks half a
    stride away from the true offset. Three steps, tried on simulated walks
    (``footnav.simulate(..., clock_offset_s=...)``):

    1. *Coarse*: the energies smoothed over ``smooth_s`` (the walking/standing envelope), cross-
       correlated. The envelopes of the two feet differ at their ends by half a stride (one
       foot starts or stops first), so this is only good to about half a stride (measured 0 to
       0.54 s for a 1.1 s stride, depending on the walk).
    2. *Within the stride*: the raw energies cross-correlated near the coarse offset. The peaks
       lie where one foot's swings meet the other's, at ``b + T/2 + k T`` (T the stride period),
       and the midpoint of two neighbouring peaks, refined by parabolas, is ``b`` modulo T.
       This assumes one foot swings exactly half a stride after the other: a step-time
       asymmetry ``delta`` (the time from a reference swing to the next other swing, minus T/2)
       shifts both peaks, and the offset, by ``delta``; it is indistinguishable from a clock
       offset. In the simulator (symmetric gait, no step-to-step variability) the error is
       < 1 ms; on real gait the walker's step-time asymmetry goes into the offset in full (not
       measured here: no two-foot recording with a clock reference was at hand).
    3. *Which stride*: the candidates ``b + k T`` are told apart by where each foot starts and
       stops moving. Feet alternate, so on the right candidate the first swings of the two
       feet are about T/2 apart and so are the last ones. When one foot both starts and ends
       the walk (one more swing than the other) a single candidate fits; when the feet make
       equally many swings, ``b`` and ``b + T`` (or ``b - T``) fit equally well: one is "the
       reference foot led and the other stopped last", the other the reverse, and nothing in
       the gyro energy of a periodic gait tells them apart. Then ``leading_foot`` decides;
       without it the candidate nearest the coarse estimate is returned (a coin toss), with a
       DataQualityWarning and the other in ``alternatives_b``. With only one end of the walk in
       both recordings, two candidates fit (``leading_foot`` settles it if that end is the
       start); with neither, the offset is known only modulo the stride.

    So: the offset modulo a stride is as good as the gait is symmetric; the whole-stride choice
    needs a standstill at both ends and either unequal step counts or the leading foot. For
    the millisecond alignment of Chistyakov et al. (2021) use exchanges (:func:`fit_clock`) or an event both
    feet record (stamping both feet together).

    Examples
    --------
    >>> import footnav
    >>> rec = footnav.simulate("straight", distance_m=30.0, clock_offset_s=4.2)
    >>> m = align_from_data(rec.left, rec.right, leading_foot="other")
    >>> round(float(m(rec.right.t[0])), 3)
    0.0
    """
    for name, v in (("rate_hz", rate_hz), ("smooth_s", smooth_s), ("max_offset_s", max_offset_s)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.number)) or not (np.isfinite(v) and v > 0):
            raise InvalidParameterError(f"align_from_data: {name}={v!r}; expected a positive number")
    if leading_foot not in (None, "reference", "other"):
        raise InvalidParameterError(
            f"align_from_data: leading_foot={leading_foot!r}; expected 'reference', 'other' or None"
        )
    dt = 1.0 / rate_hz
    r0, r1 = float(reference.t[0]), float(reference.t[-1])
    o0, o1 = float(other.t[0]), float(other.t[-1])

    def grids(span_r: tuple[float, float], span_o: tuple[float, float]) -> tuple[NDArray, NDArray]:
        g_ref, g_oth = np.arange(*span_r, dt), np.arange(*span_o, dt)
        if len(g_ref) < 4 or len(g_oth) < 4:
            raise InvalidInputError("recordings too short to align from the data", field="t")
        return g_ref, g_oth

    # 1. Coarse: walking/standing envelopes over the whole recordings.
    g_ref, g_oth = grids((r0, r1), (o0, o1))
    coarse = _Correlation(_energy(reference, g_ref, smooth_s), _energy(other, g_oth, smooth_s), dt, g_ref[0] - g_oth[0])
    b_coarse = coarse.peak(-max_offset_s, max_offset_s)
    if b_coarse is None:
        raise InvalidInputError(f"the recordings do not overlap at any offset within +-{max_offset_s} s", field="t")
    period = _stride_period(_energy(reference, g_ref, 0.0), dt)

    # 2. Within the stride: anti-phase peaks at b + T/2 + k T; their midpoints are b + k T.
    def fine(span_r: tuple[float, float], span_o: tuple[float, float], near: float) -> tuple[float, float]:
        g_r, g_o = grids(span_r, span_o)
        xc = _Correlation(_energy(reference, g_r, 0.0), _energy(other, g_o, 0.0), dt, g_r[0] - g_o[0])
        p1 = xc.peak(near - period, near + period)
        if p1 is None:
            raise InvalidInputError("the recordings do not overlap near the coarse offset", field="t")
        side = 1.0 if p1 < near else -1.0  # the neighbouring peak on the side of `near`
        lo, hi = sorted((p1 + side * period / 2, p1 + side * 3 * period / 2))
        p2 = xc.peak(lo, hi)
        stride = abs(p2 - p1) if p2 is not None else period
        mid = 0.5 * (p1 + p2) if p2 is not None else p1 - side * period / 2
        return mid + round((near - mid) / stride) * stride, stride

    if drift:
        third_r, third_o = (r1 - r0) / 3, (o1 - o0) / 3
        b_start, stride = fine((r0, r0 + third_r), (o0, o0 + third_o), b_coarse)
        b_end, _ = fine((r1 - third_r, r1), (o1 - third_o, o1), b_start)
        t_start, t_end = o0 + third_o / 2, o1 - third_o / 2
        # reference = other + b(t), b(t) linear: a = 1 + (b_end - b_start) / (t_end - t_start)
        a = 1.0 + (b_end - b_start) / (t_end - t_start)
        b = b_start - (a - 1.0) * t_start
    else:
        a, (b, stride) = 1.0, fine((r0, r1), (o0, o1), b_coarse)

    # 3. Which stride: the feet's first swings T/2 apart, and their last swings.
    f_ref, l_ref, start_ok_r, end_ok_r = _activity_span(reference, dt)
    f_oth, l_oth, start_ok_o, end_ok_o = _activity_span(other, dt)
    # every candidate b + k T within the offsets searched
    k_max = int(np.ceil((max_offset_s + abs(b)) / stride))
    ks = np.arange(-k_max, k_max + 1)
    ks = ks[np.abs(b + ks * stride) <= max_offset_s + stride]
    d_start = a * f_oth + b + ks * stride - f_ref  # > 0: the reference foot started first
    d_end = a * l_oth + b + ks * stride - l_ref  # > 0: the other foot stopped last
    edge_start, edge_end = start_ok_r and start_ok_o, end_ok_r and end_ok_o
    if edge_start or edge_end:  # |d| = T/2 at each usable edge on a right candidate, >= 3T/2 otherwise
        cost = edge_start * np.abs(d_start) + edge_end * np.abs(d_end)
        fits = np.flatnonzero(cost < cost.min() + stride / 2)
    else:  # the recordings begin and end mid-walk: any whole stride fits; report the neighbours
        fits = np.flatnonzero(np.abs(b + ks * stride - b_coarse) < 1.5 * stride)
    if leading_foot is not None and edge_start:
        agree = fits[(d_start[fits] > 0) == (leading_foot == "reference")]
        if len(agree) == 0:
            warn(
                f"align_from_data: the data say the {'other' if leading_foot == 'reference' else 'reference'} "
                f"foot started walking, not the {leading_foot!r} one; kept the data's offset",
                DataQualityWarning,
                stacklevel=2,
            )
        else:
            fits = agree
    best = int(fits[np.argmin(np.abs(b + ks[fits] * stride - b_coarse))])
    alternatives = tuple(float(b + k * stride) for k in ks[fits] if k != ks[best])
    if alternatives:
        if edge_start and edge_end:
            why = "the feet made equally many swings; pass leading_foot= if you know which foot started walking"
        elif edge_start:
            why = "a recording ends mid-walk; pass leading_foot= if you know which foot started walking"
        elif edge_end:
            why = "a recording starts mid-walk"
        else:
            why = (
                f"a recording starts mid-walk and one ends mid-walk: the offset is known only modulo the "
                f"stride, {stride:.3f} s, and is as likely any whole number of strides away"
            )
        warn(
            f"align_from_data: offsets {b + ks[best] * stride:.3f} s and "
            f"{', '.join(f'{x:.3f}' for x in alternatives)} s (a stride apart) fit the data equally well "
            f"({why}); returned the one nearest the walking envelope's",
            DataQualityWarning,
            stacklevel=2,
        )
    return ClockMap(
        a=float(a),
        b=float(b + ks[best] * stride),
        n=2 if drift else 1,
        method="data",
        stride_s=float(stride),
        alternatives_b=alternatives,
    )
