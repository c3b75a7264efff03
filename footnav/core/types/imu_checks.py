"""Plausibility checks of one sensor's data in SI units: units, time base and rate, the
accelerometer at rest, saturation (clipping).

:meth:`footnav.core.types.ImuData.from_arrays`, :meth:`~footnav.core.types.ImuData.check_units`
and the readers run them. Their thresholds are the module constants below, each with the reason
for its value.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit
from footnav.core.errors import InvalidInputError
from footnav.core.types._derived import row_norms
from footnav.core.types.sample_checks import (
    ACC_MAX_MPS2,
    ACC_MEDIAN_BOUNDS_MPS2,
    GAP_FACTOR,
    GYR_MAX_RADPS,
    GYR_PEAK_MAX_RADPS,
    _acc_median_error,
    check_extremes,
    check_time_order,
    find_gaps,
    gap_message,
)
from footnav.core.types.units import _T_SCALE, GRAVITY_MPS2

__all__ = [
    "ACC_FULL_SCALES_G",
    "ACC_MAX_MPS2",
    "ACC_MEDIAN_BOUNDS_MPS2",
    "ACC_MOVING_FRACTION",
    "ACC_MOVING_MPS2",
    "ACC_REST_ERROR_FRACTION",
    "ACC_REST_WARN_FRACTION",
    "CLIP_FRACTION_OF_FULL_SCALE",
    "CLIP_MIN_ACC_MPS2",
    "CLIP_MIN_GYR_RADPS",
    "CLIP_MIN_REPEATS",
    "FULL_SCALE_RATIO",
    "GAP_FACTOR",
    "GYR_FULL_SCALES_DPS",
    "GYR_MAX_RADPS",
    "GYR_PEAK_MAX_RADPS",
    "GYR_PEAK_MIN_RADPS",
    "PEAK_HOLD_S",
    "RATE_BOUNDS_HZ",
    "RATE_ERROR_HZ",
    "REST_ACC_REL_STD",
    "REST_GYR_RADPS",
    "REST_MIN_S",
    "REST_WINDOW_S",
    "check_extremes",
    "check_time_base",
    "check_time_order",
    "data_label",
    "clipped_acc",
    "detect_clipping",
    "find_gaps",
    "gap_message",
    "peak_hold",
]

#: A walking foot pitches at 5-12 rad/s in swing (every shared recording: held peaks 2-17 rad/s).
#: A foot that moves (``ACC_MOVING_MPS2``) but whose held peak stays below this (rad/s) is rad/s
#: read as deg/s (57 x too small: swings of ~0.1-0.2 rad/s).
GYR_PEAK_MIN_RADPS = 0.5
#: The foot moves when at least ``ACC_MOVING_FRACTION`` of the samples have | |acc| - median |acc| |
#: above ``ACC_MOVING_MPS2`` (0.5 g): in a walk the swings are 30-40 % of the time; a few knocks on
#: a still sensor (or a clipped spike) are not walking.
ACC_MOVING_MPS2 = 0.5 * GRAVITY_MPS2
ACC_MOVING_FRACTION = 0.05
#: A peak counts when held this long (at least 3 samples): single-sample glitches are not peaks.
PEAK_HOLD_S = 0.01
#: Window (s) over which a sample counts as at rest: |acc| steady within ``REST_ACC_REL_STD`` of
#: its median and mean |gyr| below ``REST_GYR_RADPS``. Scale free, so a mis-scaled accelerometer
#: still shows its rest phases.
REST_WINDOW_S = 0.1
REST_ACC_REL_STD = 0.02
REST_GYR_RADPS = 0.5
#: At least this long (s) at rest in total before the at-rest magnitude is judged.
REST_MIN_S = 0.25
#: At rest an accelerometer reads g. More than this fraction off g is a DataQualityWarning (cheap
#: uncalibrated sensors are 1-5 % off: the IPOL left-foot sensors read 3.5-6.7 % above g, every
#: other shared recording within 2.5 %) ...
ACC_REST_WARN_FRACTION = 0.03
#: ... and more than this fraction off is an error: no accelerometer, calibrated or not, is 25 %
#: off; it is a wrong unit or scale (2 x: 19.6 m/s^2 at rest) that would otherwise show up later
#: as "no stance phase detected".
ACC_REST_ERROR_FRACTION = 0.25

#: Sampling rates (Hz) footnav's detectors and filters are made for: at 20 Hz a 0.4 s swing has 8
#: samples and a fast walk's stance 3-4, fewer do not resolve the gait cycle (windows of a few
#: samples, strapdown rotation of > 0.5 rad per sample in swing); above 2 kHz no foot-mounted IMU
#: on record, and the filters' noise models (per-sample white noise, windows in samples) were
#: tuned and tested at 60-820 Hz. Outside: DataQualityWarning naming the rate, ``meta["rate_check"]``.
RATE_BOUNDS_HZ = (20.0, 2000.0)
#: Outside these rates (Hz) the time stamps are not in the declared unit: 1 kHz in ms read as s is
#: 1 Hz, 100 Hz in us read as s 1e-4 Hz; 100 Hz in s declared ms 100 kHz. InvalidInputError
#: naming the unit that gives a plausible rate.
RATE_ERROR_HZ = (1.5, 100_000.0)

#: Common full scales of MEMS gyroscopes (deg/s) and accelerometers (g).
GYR_FULL_SCALES_DPS = (250.0, 500.0, 1000.0, 2000.0)
ACC_FULL_SCALES_G = (2.0, 4.0, 8.0, 16.0)
#: A plateau within this ratio of a nominal full scale is saturation at that full scale: a 16-bit
#: sensor's largest code is 0.999-1.15 x nominal (e.g. 8.75 mdps/LSB x 32767 = 287 deg/s on a
#: 250 deg/s range), calibration moves it a few percent either way.
FULL_SCALE_RATIO = (0.95, 1.2)

#: An extreme value held by at least this many samples of one axis is a full-scale plateau.
CLIP_MIN_REPEATS = 3
#: Plateaus below this magnitude are the rest readings of a quantised sensor, not clipping (unless
#: they sit at a common full scale, ``FULL_SCALE_RATIO``).
CLIP_MIN_ACC_MPS2 = 2.0 * GRAVITY_MPS2
#: Gyroscope plateaus below this magnitude (rad/s, ~290 deg/s) are not clipping either (same
#: exception).
CLIP_MIN_GYR_RADPS = 5.0
#: With a known full scale, readings at or above this fraction of it count as clipped: after the
#: sensor's calibration (scale, cross-axis) a saturated raw axis is no longer one constant value.
CLIP_FRACTION_OF_FULL_SCALE = 0.98


def peak_hold(rate_hz: float) -> int:
    """Samples a peak must hold at ``rate_hz`` (``PEAK_HOLD_S``, at least 3)."""
    return max(3, round(PEAK_HOLD_S * rate_hz))


def _kernel_array(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``x`` as a writable C-contiguous float64 array (a copy only when it is not): numba
    compiles a kernel once per array type, and a read-only array is another type (each of this
    module's kernels was compiled twice on a first call)."""
    return np.require(x, np.float64, ["C", "W"])


def _held_peak(x: NDArray[np.float64], hold: int) -> float:
    """Largest value ``x`` stays at or above for ``hold`` consecutive samples."""
    if len(x) < hold:
        return float(x.min()) if len(x) else 0.0
    return float(_max_of_window_minima(_kernel_array(x), hold))


@njit(cache=True)
def _max_of_window_minima(x: NDArray[np.float64], hold: int) -> float:
    # the maximum over every full window of ``hold`` samples of its minimum (min and max are
    # exact, so this is the value of a running minimum filter's maximum)
    best = -np.inf
    if hold <= 32:  # a few samples at usual rates (3 at 100 Hz): direct, branch-light
        for i in range(len(x) - hold + 1):
            m = x[i]
            for j in range(i + 1, i + hold):
                m = min(m, x[j])
            best = max(best, m)
        return best
    # long holds (kHz rates): a monotonic queue of the window's candidates for its minimum, O(N)
    queue = np.empty(len(x), dtype=np.int64)
    head = tail = 0
    for i in range(len(x)):
        while tail > head and x[queue[tail - 1]] >= x[i]:
            tail -= 1
        queue[tail] = i
        tail += 1
        if queue[head] <= i - hold:
            head += 1
        if i >= hold - 1 and x[queue[head]] > best:
            best = x[queue[head]]
    return best


@njit(cache=True)
def _count_beyond(x: NDArray[np.float64], centre: float, bound: float) -> int:
    # np.count_nonzero(np.abs(x - centre) > bound) without its two temporaries
    count = 0
    for v in x:
        if abs(v - centre) > bound:
            count += 1
    return count


def _at_rest(
    acc_norm: NDArray[np.float64], gyr_norm: NDArray[np.float64], rate_hz: float, median: float
) -> NDArray[np.bool_]:
    """Samples inside a ``REST_WINDOW_S`` window of steady |acc| and small |gyr|; ``median`` is
    ``np.median(acc_norm)`` (the caller has it: one sort of N values less)."""
    n = len(acc_norm)
    k = max(5, round(REST_WINDOW_S * rate_hz))
    if n < k:
        return np.zeros(n, dtype=bool)
    acc, gyr = _kernel_array(acc_norm), _kernel_array(gyr_norm)
    return _rest_mask(acc, gyr, median, k, REST_ACC_REL_STD * median, REST_GYR_RADPS)


@njit(cache=True)
def _running_mean(x: NDArray[np.float64], k: int) -> NDArray[np.float64]:
    # scipy.ndimage.uniform_filter1d(x, k, mode="nearest") with the arithmetic of scipy 1.17's
    # (a running window sum, (entering - leaving) added per sample, divided by k for each output;
    # the ends repeat the first / last sample), so the same bits as the filter this replaced
    n = len(x)
    s1 = k // 2
    out = np.empty(n)
    total = 0.0
    for j in range(k):
        total += x[min(max(j - s1, 0), n - 1)]
    out[0] = total / k
    for i in range(1, n):
        total += x[min(max(i + k - 1 - s1, 0), n - 1)] - x[min(max(i - 1 - s1, 0), n - 1)]
        out[i] = total / k
    return out


@njit(cache=True)
def _rest_mask(
    acc_norm: NDArray[np.float64],
    gyr_norm: NDArray[np.float64],
    median: float,
    k: int,
    acc_std_max: float,
    gyr_max: float,
) -> NDArray[np.bool_]:
    # O(N) running moments of the centred windows (no k x N window views: this runs on every
    # input); |acc| is taken about its median so that E[x^2] - E[x]^2 does not cancel ~g^2
    n = len(acc_norm)
    a = acc_norm - median
    mean_a = _running_mean(a, k)
    mean_a2 = _running_mean(a * a, k)
    mean_g = _running_mean(gyr_norm, k)
    # count[i]: steady windows centred before sample i
    count = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):
        steady = np.sqrt(max(mean_a2[i] - mean_a[i] * mean_a[i], 0.0)) < acc_std_max and mean_g[i] < gyr_max
        count[i + 1] = count[i] + steady
    # a sample is at rest when any window holding it is: the windows centred from i - left to
    # i + k - 1 - left (an even window's centre sits half a sample early: left = k/2 - 1)
    left = k // 2 - (1 if k % 2 == 0 else 0)
    rest = np.empty(n, dtype=np.bool_)
    for i in range(n):
        rest[i] = count[min(i + k - left, n)] > count[max(i - left, 0)]
    return rest


def _full_scale_of(value: float, scales: tuple[float, ...], unit_si: float) -> float | None:
    """The nominal full scale (in the listed unit) ``|value|`` (SI) saturates at, if any."""
    lo, hi = FULL_SCALE_RATIO
    for fs in scales:
        if lo <= abs(value) / (fs * unit_si) <= hi:
            return fs
    return None


def _plateau(
    x: NDArray[np.float64], floor: float, scales: tuple[float, ...], unit_si: float
) -> tuple[NDArray[np.bool_], float | None]:
    """The plateau rule of :func:`detect_clipping` on one sensor's (N, 3) samples: the samples
    held at an axis' extreme, and the common full scale the first plateau sits at (or None)."""
    hit = np.zeros(x.shape, dtype=bool)
    found = None
    for k in range(x.shape[1]):
        col = x[:, k]
        for extreme in (col.max(), col.min()):
            fs = _full_scale_of(extreme, scales, unit_si)
            if abs(extreme) >= floor or fs is not None:
                same = col == extreme
                if same.sum() >= CLIP_MIN_REPEATS:
                    hit[:, k] |= same
                    if fs is not None and found is None:
                        found = fs
    return hit, found


def clipped_acc(
    acc: NDArray[np.float64], *, acc_full_scale_mps2: float | None = None, fraction: float = CLIP_FRACTION_OF_FULL_SCALE
) -> NDArray[np.bool_]:
    """The accelerometer's clipped samples, per axis (N, 3): :func:`detect_clipping`'s two rules,
    the full-scale one at ``fraction`` of ``acc_full_scale_mps2``."""
    hit, _ = _plateau(acc, CLIP_MIN_ACC_MPS2, ACC_FULL_SCALES_G, GRAVITY_MPS2)
    if acc_full_scale_mps2 is not None:
        hit |= np.abs(acc) >= fraction * acc_full_scale_mps2
    return hit


def detect_clipping(
    acc: NDArray[np.float64], gyr: NDArray[np.float64], *, acc_full_scale_mps2: float | None = None
) -> dict[str, Any] | None:
    """Find samples at the sensor's full scale.

    Two rules, either marks a sample of one axis as clipped:

    * plateau: the axis' largest (or smallest) value is held by at least ``CLIP_MIN_REPEATS``
      samples and its magnitude is at least ``CLIP_MIN_ACC_MPS2`` (``CLIP_MIN_GYR_RADPS`` for the
      gyroscope) or lies at a common full scale (``GYR_FULL_SCALES_DPS``, ``ACC_FULL_SCALES_G``,
      within ``FULL_SCALE_RATIO``) -- a saturated ADC repeats its maximum code;
    * full scale (accelerometer, only when the format documents it): ``|a| >=
      CLIP_FRACTION_OF_FULL_SCALE * acc_full_scale_mps2``.

    Returns
    -------
    dict or None
        ``{"acc": n, "first_index": i, "gyr": m, "gyr_first_index": j, "acc_full_scale": "+-2 g",
        "gyr_full_scale": "+-250 deg/s", "rule": ...}`` with ``n`` (``m``) the number of samples
        with at least one clipped accelerometer (gyroscope) axis, ``i`` (``j``) the first such
        sample (None if none), the full scales the plateaus sit at (None when not a common one);
        None when nothing is clipped.
    """
    found: dict[str, float] = {}
    acc_hit, fs_acc = _plateau(acc, CLIP_MIN_ACC_MPS2, ACC_FULL_SCALES_G, GRAVITY_MPS2)
    if fs_acc is not None:
        found["acc"] = fs_acc
    if acc_full_scale_mps2 is not None:
        acc_hit |= np.abs(acc) >= CLIP_FRACTION_OF_FULL_SCALE * acc_full_scale_mps2
    gyr_hit, fs_gyr = _plateau(gyr, CLIP_MIN_GYR_RADPS, GYR_FULL_SCALES_DPS, np.pi / 180.0)
    if fs_gyr is not None:
        found["gyr"] = fs_gyr
    acc_rows = acc_hit.any(axis=1)
    gyr_rows = gyr_hit.any(axis=1)
    if not acc_rows.any() and not gyr_rows.any():
        return None
    rule = f"extreme value repeated >= {CLIP_MIN_REPEATS} times"
    if acc_full_scale_mps2 is not None:
        rule += f", or |acc| >= {CLIP_FRACTION_OF_FULL_SCALE:g} x full scale {acc_full_scale_mps2:.4g} m/s^2"
    return {
        "acc": int(acc_rows.sum()),
        "first_index": int(np.argmax(acc_rows)) if acc_rows.any() else None,
        "gyr": int(gyr_rows.sum()),
        "gyr_first_index": int(np.argmax(gyr_rows)) if gyr_rows.any() else None,
        "acc_full_scale_mps2": acc_full_scale_mps2,
        "acc_full_scale": f"+-{found['acc']:g} g" if "acc" in found and acc_rows.any() else None,
        "gyr_full_scale": f"+-{found['gyr']:g} deg/s" if "gyr" in found and gyr_rows.any() else None,
        "rule": rule,
    }


#: Time values stepping by exactly 1 are sample numbers far more often than milliseconds.
_SAMPLE_NUMBER_HINT = (
    "; the time values step by exactly 1: they look like sample numbers, not times; give the sampling rate "
    "instead (ImuData.from_arrays(acc=..., gyr=..., rate_hz=100.0), from_dataframe(frame, rate_hz=...), "
    "command line --rate-hz); only a 1 kHz logger's millisecond stamps step by 1 too (t_unit='ms')"
)


def _unit_hint(raw_dt: float) -> str:
    """Which time unit would make a median interval of ``raw_dt`` (in the file's numbers) a rate
    inside ``RATE_BOUNDS_HZ``."""
    lo, hi = RATE_BOUNDS_HZ
    for unit, scale in _T_SCALE.items():
        rate = 1.0 / (raw_dt * scale)
        if lo <= rate <= hi:
            return f"; if the time stamps are in {unit}, pass t_unit={unit!r} ({rate:.4g} Hz)"
    return ""


def data_label(meta: Mapping[str, Any]) -> str:
    """How warnings name a sensor's data: its file and foot."""
    path = meta.get("source")
    return (path or "ImuData") + (f" ({meta['foot']} foot)" if meta.get("foot") in ("left", "right") else "")


def check_time_base(median_dt: float, meta: Mapping[str, Any]) -> list[tuple[str, Any, str]]:
    """Check the time base and rate of data whose median sampling interval is ``median_dt`` (s).

    Raises InvalidInputError outside ``RATE_ERROR_HZ`` (the time stamps are not in the declared
    unit, ``meta["units_in"]["t"]``; the message names the unit that fits); returns the finding
    ``("rate_check", record, message)`` outside ``RATE_BOUNDS_HZ``.
    """
    path = meta.get("source")
    t_unit = str((meta.get("units_in") or {}).get("t", "s"))
    dt = median_dt
    rate = 1.0 / dt
    raw_dt = dt / _T_SCALE.get(t_unit, 1.0)
    if not RATE_ERROR_HZ[0] <= rate <= RATE_ERROR_HZ[1]:
        raise InvalidInputError(
            f"implausible time base: median sampling interval {dt:.4g} s ({rate:.3g} Hz) with t in {t_unit}; "
            f"no foot-mounted IMU samples {'that slowly' if rate < RATE_ERROR_HZ[0] else 'that fast'} "
            f"(footnav is made for {RATE_BOUNDS_HZ[0]:g}-{RATE_BOUNDS_HZ[1]:g} Hz)"
            + (_SAMPLE_NUMBER_HINT if raw_dt == 1.0 else (_unit_hint(raw_dt) or "; check the time column's unit")),
            field="t",
            path=path,
        )
    lo, hi = RATE_BOUNDS_HZ
    if lo <= rate <= hi:
        return []
    return [
        (
            "rate_check",
            {"rate_hz": rate, "bounds_hz": [lo, hi]},
            (
                f"{data_label(meta)}: sampling rate {rate:.4g} Hz is {'below' if rate < lo else 'above'} the "
                f"{lo:g}-{hi:g} Hz footnav's detectors and filters are made for; results may be wrong"
                + _unit_hint(raw_dt)
                + "; recorded in meta['rate_check']"
            ),
        )
    ]


def _check_data(
    t: NDArray[np.float64],
    acc: NDArray[np.float64],
    gyr: NDArray[np.float64],
    meta: Mapping[str, Any],
    *,
    acc_full_scale_mps2: float | None = None,
    clipping: bool = True,
    median_dt: float | None = None,
    time_base: bool = True,
) -> list[tuple[str, Any, str]]:
    """Check units, (``time_base``) time base and rate, at-rest magnitude and (``clipping``)
    saturation of SI data.

    Raises InvalidInputError where the data cannot be what they are declared to be; returns the
    findings to warn about as ``(meta key, record, message)``. ``median_dt`` is the median of
    ``np.diff(t)`` when the caller has it (ImuData keeps it), saving a sort of the intervals.
    """
    path = meta.get("source")
    dt = float(np.median(np.diff(t))) if median_dt is None else median_dt
    rate = 1.0 / dt
    findings = check_time_base(dt, meta) if time_base else []
    label = data_label(meta)

    # -- units -----------------------------------------------------------------------------------
    # shared with the detectors within a pipeline run (the same bits as np.linalg.norm)
    acc_norm = row_norms(acc)
    gyr_norm = row_norms(gyr)
    f = float(np.median(acc_norm))
    lo_a, hi_a = ACC_MEDIAN_BOUNDS_MPS2
    if not lo_a <= f <= hi_a:
        raise _acc_median_error(f, path)
    hold = peak_hold(rate)
    w_peak = _held_peak(gyr_norm, hold)
    # a held peak beyond any gyroscope (deg/s read as rad/s), single absurd samples (a corrupt
    # record: the median and the held peak do not see them)
    check_extremes(acc, gyr, path=path, hold=hold, acc_median=f, acc_norm=acc_norm, gyr_norm=gyr_norm)
    n_moving = _count_beyond(_kernel_array(acc_norm), f, ACC_MOVING_MPS2)
    moving = n_moving / len(acc_norm)
    # at least a swing's worth (0.2 s) of motion: a few rows of a test file are no walk
    if moving >= ACC_MOVING_FRACTION and n_moving >= max(10, 0.2 * rate) and w_peak < GYR_PEAK_MIN_RADPS:
        findings.append(
            (
                "gyr_unit_check",
                {"gyr_peak_radps": w_peak, "acc_moving_fraction": moving},
                (
                    f"{label}: the foot moves (|acc| is more than 0.5 g off its median in {moving * 100:.0f} % of the "
                    f"samples) but turns at most {w_peak:.3g} rad/s "
                    f"({np.degrees(w_peak):.3g} deg/s); a walking foot turns at 5-12 rad/s in swing: "
                    "the gyroscope looks like rad/s read as deg/s "
                    f"(declared {(meta.get('units_in') or {}).get('gyr', 'rad/s')!r}); "
                    "recorded in meta['gyr_unit_check']"
                ),
            )
        )

    # -- the accelerometer at rest ----------------------------------------------------------------
    rest = _at_rest(acc_norm, gyr_norm, rate, f)
    if rest.sum() >= max(10, REST_MIN_S * rate):
        g_rest = float(np.median(acc_norm[rest]))
        off = g_rest / GRAVITY_MPS2 - 1.0
        first = int(np.argmax(rest))
        if abs(off) > ACC_REST_ERROR_FRACTION:
            raise InvalidInputError(
                f"the accelerometer reads {g_rest:.3g} m/s^2 at rest ({g_rest / GRAVITY_MPS2:.2f} x g, median over "
                f"{int(rest.sum())} still samples, the first at index {first}), not g = {GRAVITY_MPS2:g} m/s^2: "
                "a wrong unit or scale factor (acc_unit, the sensor's range setting) or a wrong column",
                field="acc",
                index=first,
                path=path,
            )
        if abs(off) > ACC_REST_WARN_FRACTION:
            findings.append(
                (
                    "acc_at_rest",
                    {"magnitude_mps2": g_rest, "off_g_fraction": off, "samples": int(rest.sum()), "first_index": first},
                    (
                        f"{label}: the accelerometer reads {g_rest:.4g} m/s^2 at rest, {off * 100:+.1f} % off g "
                        f"({GRAVITY_MPS2:g} m/s^2; median over {int(rest.sum())} still samples): an uncalibrated or "
                        "mis-scaled sensor; tilt and distances carry that error; recorded in meta['acc_at_rest']"
                    ),
                )
            )

    # -- saturation ------------------------------------------------------------------------------
    clipped = detect_clipping(acc, gyr, acc_full_scale_mps2=acc_full_scale_mps2) if clipping else None
    if clipped is not None:
        parts = []
        if clipped["acc"]:
            fs = f", full scale {clipped['acc_full_scale']}" if clipped["acc_full_scale"] else ""
            parts.append(f"{clipped['acc']} accelerometer sample(s) (first at index {clipped['first_index']}{fs})")
        if clipped["gyr"]:
            fs = f", full scale {clipped['gyr_full_scale']}" if clipped["gyr_full_scale"] else ""
            parts.append(f"{clipped['gyr']} gyroscope sample(s) (first at index {clipped['gyr_first_index']}{fs})")
        findings.append(
            (
                "clipped",
                clipped,
                (
                    f"{label}: {' and '.join(parts)} at the sensor's full scale: the true value is unknown there "
                    "(clipping, saturation); recorded in meta['clipped']"
                ),
            )
        )
    return findings
