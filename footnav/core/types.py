"""The data objects that flow between footnav's stages.

recording (:class:`ImuData`) -> detector (:class:`StanceResult`) -> estimator
(:class:`FootTrajectory`) -> fusion (:class:`FusionResult`) -> :class:`PipelineResult`.

All are frozen dataclasses of read-only numpy arrays, SI units, samples on axis 0. Each type names
its frame in a ``frame`` attribute:

* ``"body"`` -- the sensor's own axes (accelerometer and gyroscope axes).
* ``"nav"`` -- footnav's navigation frame: z up, gravity ``[0, 0, -GRAVITY_MPS2]``, x the initial
  walking direction (or the sensor's initial heading when no step is known), origin at the start.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.warning_log import warn

__all__ = [
    "GAP_FACTOR",
    "GRAVITY_MPS2",
    "RATE_BOUNDS_HZ",
    "RATE_ERROR_HZ",
    "FootTrajectory",
    "FootTruth",
    "FusionResult",
    "ImuData",
    "Path",
    "PipelineResult",
    "Recording",
    "StanceResult",
    "detect_clipping",
    "stance_intervals",
]

#: Standard gravity in m/s^2 (CGPM 1901); the magnitude of the nav-frame gravity vector.
GRAVITY_MPS2 = 9.80665

#: A sampling interval longer than GAP_FACTOR x the median interval is reported as a gap. One lost
#: sample makes an interval of about 2 x the median, which time-stamp rounding puts on either side
#: of 2.0; logger jitter without loss stays below ~1.75 x (pyshoe VICON trials: 8.6 ms at 5 ms).
GAP_FACTOR = 1.9

_ACC_SCALE = {"m/s^2": 1.0, "g": GRAVITY_MPS2}
_GYR_SCALE = {"rad/s": 1.0, "deg/s": np.pi / 180.0}
_T_SCALE = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
_MAG_SCALE = {"uT": 1.0, "T": 1e6, "gauss": 100.0, "a.u.": 1.0}


def _readonly(a: NDArray) -> NDArray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


def _as_float_array(value: Any, name: str, ncols: int | None, path: str | None) -> NDArray[np.float64]:
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"cannot convert to float64 ({exc})", field=name, path=path) from None
    if ncols is None:
        if arr.ndim != 1:
            raise InvalidInputError(f"expected shape (N,), got {arr.shape}", field=name, path=path)
    elif arr.ndim != 2 or arr.shape[1] != ncols:
        raise InvalidInputError(f"expected shape (N, {ncols}), got {arr.shape}", field=name, path=path)
    bad = ~np.isfinite(arr)
    if bad.any():
        first = int(np.argmax(bad.reshape(len(arr), -1).any(axis=1)))
        raise InvalidInputError(
            f"non-finite value {arr[first]!r}; every sample must be finite", field=name, index=first, path=path
        )
    return arr


def _first_true(mask: NDArray[np.bool_]) -> int:
    return int(np.argmax(mask))


#: A foot-mounted IMU reads about 1 g of specific force over a recording (the foot stands still
#: much of the time); a median |f| outside these bounds (m/s^2) is not a foot in m/s^2.
ACC_MEDIAN_BOUNDS_MPS2 = (2.5, 30.0)
#: The largest MEMS gyroscope full scale is +-4000 deg/s (70 rad/s). An angular rate held above
#: this (rad/s) for ``PEAK_HOLD_S`` is deg/s read as rad/s. A held peak, not a percentile: on a
#: mostly still recording the few swings are far fewer than 1 % of the samples.
GYR_PEAK_MAX_RADPS = 70.0
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


def _time_seconds(t: Any, t_unit: str, path: str | None) -> tuple[Any, dict[str, Any]]:
    """Time values as float seconds' input: datetime64 / timedelta64 (numpy or pandas, with or
    without a time zone) are converted here; anything else is returned for the unit scale.

    Returns ``(t, record)``: ``record`` is empty, or says what was converted (``meta["time_converted"]``).
    """
    if getattr(t, "dtype", None) is None:  # a list: see what numpy makes of it
        try:
            t = np.asarray(t)
        except (TypeError, ValueError):
            return t, {}  # ragged or odd: the float conversion names the problem
    dtype = t.dtype
    kind = getattr(dtype, "kind", None)
    if kind not in ("M", "m"):
        arr = np.asarray(t) if kind == "O" else None
        if arr is not None and arr.size and hasattr(arr.flat[0], "year"):
            raise InvalidInputError(
                "holds date/time objects; pass them as a datetime64 array (numpy.asarray(t, 'datetime64[ns]') "
                "or a pandas datetime column), which is converted to seconds since the first sample",
                field="t",
                path=path,
            )
        return t, {}
    if t_unit != "s":
        raise InvalidInputError(
            f"t is a {'datetime' if kind == 'M' else 'timedelta'} column, which carries its own unit; "
            f"t_unit={t_unit!r} contradicts it (leave t_unit at its default)",
            field="t_unit",
            path=path,
        )
    tz = getattr(getattr(t, "dt", t), "tz", None)
    if tz is not None:  # pandas, time zone aware: the same instants in UTC, without the zone
        t = t.dt.tz_convert("UTC").dt.tz_localize(None) if hasattr(t, "dt") else t.tz_convert("UTC").tz_localize(None)
    arr = np.asarray(t)
    if arr.dtype.kind not in ("M", "m"):  # a pandas extension type numpy did not keep
        arr = np.asarray(t, dtype="datetime64[ns]" if kind == "M" else "timedelta64[ns]")
    if arr.ndim != 1:
        raise InvalidInputError(f"expected shape (N,), got {arr.shape}", field="t", path=path)
    nat = np.isnat(arr)
    if nat.any():
        i = int(np.argmax(nat))
        raise InvalidInputError("missing time stamp (NaT); every sample needs a time", field="t", index=i, path=path)
    if kind == "M":
        # seconds since the first sample: absolute epoch seconds (~1.7e9) would lose the
        # microseconds in float64, and the nav solution only needs elapsed time
        secs = (arr - arr[0]) / np.timedelta64(1, "s")
        record = {"time_converted": f"datetime64 -> s since the first sample ({np.datetime_as_string(arr[0])}"
                  + (f" {tz}" if tz is not None else "") + ")", "t0_datetime": str(np.datetime_as_string(arr[0]))}
    else:
        secs = arr / np.timedelta64(1, "s")
        record = {"time_converted": "timedelta64 -> s"}
    return np.asarray(secs, dtype=np.float64), record


def _held_peak(x: NDArray[np.float64], hold: int) -> float:
    """Largest value ``x`` stays at or above for ``hold`` consecutive samples."""
    from scipy.ndimage import minimum_filter1d

    if len(x) < hold:
        return float(x.min()) if len(x) else 0.0
    # running minimum of every full window of ``hold`` samples (the filter centres window i on
    # i - hold // 2 .. i + hold - 1 - hold // 2: the padded edge windows are dropped), then its max
    running = minimum_filter1d(x, hold, mode="nearest")
    return float(running[hold // 2 : len(x) - (hold - 1 - hold // 2)].max())


def _at_rest(acc_norm: NDArray[np.float64], gyr_norm: NDArray[np.float64], rate_hz: float) -> NDArray[np.bool_]:
    """Samples inside a ``REST_WINDOW_S`` window of steady |acc| and small |gyr|."""
    from scipy.ndimage import maximum_filter1d, uniform_filter1d

    n = len(acc_norm)
    k = max(5, round(REST_WINDOW_S * rate_hz))
    if n < k:
        return np.zeros(n, dtype=bool)
    # O(N) running moments of the centred windows (no k x N window views: this runs on every
    # input); |acc| is taken about its median so that E[x^2] - E[x]^2 does not cancel ~g^2
    median = float(np.median(acc_norm))
    a = acc_norm - median
    mean_a = uniform_filter1d(a, k, mode="nearest")
    std_a = np.sqrt(np.maximum(uniform_filter1d(a * a, k, mode="nearest") - mean_a * mean_a, 0.0))
    ok = (std_a < REST_ACC_REL_STD * median) & (uniform_filter1d(gyr_norm, k, mode="nearest") < REST_GYR_RADPS)
    # a sample is at rest when any window holding it is (an even window's centre sits half a
    # sample early, so the dilation is shifted back by one to cover exactly those windows)
    return maximum_filter1d(ok.astype(np.uint8), k, mode="constant", cval=0, origin=-1 if k % 2 == 0 else 0) > 0


def _full_scale_of(value: float, scales: tuple[float, ...], unit_si: float) -> float | None:
    """The nominal full scale (in the listed unit) ``|value|`` (SI) saturates at, if any."""
    lo, hi = FULL_SCALE_RATIO
    for fs in scales:
        if lo <= abs(value) / (fs * unit_si) <= hi:
            return fs
    return None


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

    def plateau(x: NDArray[np.float64], floor: float, scales: tuple[float, ...], unit_si: float, key: str) -> NDArray[np.bool_]:
        hit = np.zeros(x.shape, dtype=bool)
        for k in range(x.shape[1]):
            col = x[:, k]
            for extreme in (col.max(), col.min()):
                fs = _full_scale_of(extreme, scales, unit_si)
                if abs(extreme) >= floor or fs is not None:
                    same = col == extreme
                    if same.sum() >= CLIP_MIN_REPEATS:
                        hit[:, k] |= same
                        if fs is not None:
                            found.setdefault(key, fs)
        return hit

    acc_hit = plateau(acc, CLIP_MIN_ACC_MPS2, ACC_FULL_SCALES_G, GRAVITY_MPS2, "acc")
    if acc_full_scale_mps2 is not None:
        acc_hit |= np.abs(acc) >= CLIP_FRACTION_OF_FULL_SCALE * acc_full_scale_mps2
    gyr_hit = plateau(gyr, CLIP_MIN_GYR_RADPS, GYR_FULL_SCALES_DPS, np.pi / 180.0, "gyr")
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


def _unit_hint(raw_dt: float) -> str:
    """Which time unit would make a median interval of ``raw_dt`` (in the file's numbers) a rate
    inside ``RATE_BOUNDS_HZ``."""
    lo, hi = RATE_BOUNDS_HZ
    for unit, scale in _T_SCALE.items():
        rate = 1.0 / (raw_dt * scale)
        if lo <= rate <= hi:
            return f"; if the time stamps are in {unit}, pass t_unit={unit!r} ({rate:.4g} Hz)"
    return ""


def _check_data(
    t: NDArray[np.float64],
    acc: NDArray[np.float64],
    gyr: NDArray[np.float64],
    meta: Mapping[str, Any],
    *,
    acc_full_scale_mps2: float | None = None,
    clipping: bool = True,
) -> list[tuple[str, Any, str]]:
    """Check units, time base, rate, at-rest magnitude and (``clipping``) saturation of SI data.

    Raises InvalidInputError where the data cannot be what they are declared to be; returns the
    findings to warn about as ``(meta key, record, message)``.
    """
    path = meta.get("source")
    label = (path or "ImuData") + (f" ({meta['foot']} foot)" if meta.get("foot") in ("left", "right") else "")
    t_unit = str((meta.get("units_in") or {}).get("t", "s"))
    findings: list[tuple[str, Any, str]] = []

    # -- time base and rate ------------------------------------------------------------------
    dt = float(np.median(np.diff(t)))
    rate = 1.0 / dt
    raw_dt = dt / _T_SCALE.get(t_unit, 1.0)
    if not RATE_ERROR_HZ[0] <= rate <= RATE_ERROR_HZ[1]:
        raise InvalidInputError(
            f"implausible time base: median sampling interval {dt:.4g} s ({rate:.3g} Hz) with t in {t_unit}; "
            f"no foot-mounted IMU samples {'that slowly' if rate < RATE_ERROR_HZ[0] else 'that fast'} "
            f"(footnav is made for {RATE_BOUNDS_HZ[0]:g}-{RATE_BOUNDS_HZ[1]:g} Hz)"
            + (_unit_hint(raw_dt) or "; check the time column's unit"),
            field="t",
            path=path,
        )
    lo, hi = RATE_BOUNDS_HZ
    if not lo <= rate <= hi:
        findings.append((
            "rate_check",
            {"rate_hz": rate, "bounds_hz": [lo, hi]},
            (
                f"{label}: sampling rate {rate:.4g} Hz is {'below' if rate < lo else 'above'} the "
                f"{lo:g}-{hi:g} Hz footnav's detectors and filters are made for; results may be wrong"
                + _unit_hint(raw_dt) + "; recorded in meta['rate_check']"
            ),
        ))

    # -- units -----------------------------------------------------------------------------------
    acc_norm = np.linalg.norm(acc, axis=1)
    gyr_norm = np.linalg.norm(gyr, axis=1)
    f = float(np.median(acc_norm))
    lo_a, hi_a = ACC_MEDIAN_BOUNDS_MPS2
    if not lo_a <= f <= hi_a:
        hint = "the data look like g: read them with acc_unit='g'" if 0.5 <= f < lo_a else (
            "is the accelerometer in another unit, or is its column mapping wrong?")
        raise InvalidInputError(
            f"implausible specific force: median |acc| = {f:.3g} m/s^2, but a foot-mounted IMU reads gravity "
            f"({GRAVITY_MPS2:g} m/s^2) whenever the foot stands still; {hint}",
            field="acc",
            path=path,
        )
    hold = max(3, round(PEAK_HOLD_S * rate))
    w_peak = _held_peak(gyr_norm, hold)
    if w_peak > GYR_PEAK_MAX_RADPS:
        i = int(np.argmax(gyr_norm > GYR_PEAK_MAX_RADPS))
        raise InvalidInputError(
            f"implausible angular rate: |gyr| held above {w_peak:.3g} rad/s, beyond any MEMS gyroscope's range "
            f"(~{GYR_PEAK_MAX_RADPS:g} rad/s = 4000 deg/s); the data look like deg/s: read them with gyr_unit='deg/s'",
            field="gyr",
            index=i,
            path=path,
        )
    n_moving = int(np.count_nonzero(np.abs(acc_norm - f) > ACC_MOVING_MPS2))
    moving = n_moving / len(acc_norm)
    # at least a swing's worth (0.2 s) of motion: a few rows of a test file are no walk
    if moving >= ACC_MOVING_FRACTION and n_moving >= max(10, 0.2 * rate) and w_peak < GYR_PEAK_MIN_RADPS:
        findings.append((
            "gyr_unit_check",
            {"gyr_peak_radps": w_peak, "acc_moving_fraction": moving},
            (
                f"{label}: the foot moves (|acc| is more than 0.5 g off its median in {moving * 100:.0f} % of the "
                f"samples) but turns at most {w_peak:.3g} rad/s "
                f"({np.degrees(w_peak):.3g} deg/s); a walking foot turns at 5-12 rad/s in swing: the gyroscope looks "
                f"like rad/s read as deg/s (declared {(meta.get('units_in') or {}).get('gyr', 'rad/s')!r}); "
                "recorded in meta['gyr_unit_check']"
            ),
        ))

    # -- the accelerometer at rest ----------------------------------------------------------------
    rest = _at_rest(acc_norm, gyr_norm, rate)
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
            findings.append((
                "acc_at_rest",
                {"magnitude_mps2": g_rest, "off_g_fraction": off, "samples": int(rest.sum()), "first_index": first},
                (
                    f"{label}: the accelerometer reads {g_rest:.4g} m/s^2 at rest, {off * 100:+.1f} % off g "
                    f"({GRAVITY_MPS2:g} m/s^2; median over {int(rest.sum())} still samples): an uncalibrated or "
                    "mis-scaled sensor; tilt and distances carry that error; recorded in meta['acc_at_rest']"
                ),
            ))

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
        findings.append((
            "clipped",
            clipped,
            (
                f"{label}: {' and '.join(parts)} at the sensor's full scale: the true value is unknown there "
                "(clipping, saturation); recorded in meta['clipped']"
            ),
        ))
    return findings


class ReadOnlyMeta(dict):
    """A dict that cannot be changed in place: an input's provenance (its ``source`` and the
    changes its reader made) is what the result files and their SHA-256 record, so no component
    may rewrite it. Build a changed copy with ``dataclasses.replace(imu, meta={**imu.meta, ...})``.
    Pickles, compares and serialises (JSON) as a dict."""

    def _refuse(self, *args: Any, **kwargs: Any) -> None:
        raise TypeError(
            "ImuData.meta is read-only (the input's provenance); make a changed copy with "
            "dataclasses.replace(imu, meta={**imu.meta, key: value})"
        )

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = _refuse  # type: ignore[assignment]

    def __ior__(self, other: Any) -> "ReadOnlyMeta":
        self._refuse()
        return self

    def __reduce__(self) -> tuple:
        return (ReadOnlyMeta, (dict(self),))

    def copy(self) -> dict:  # type: ignore[override]
        """A plain, changeable dict."""
        return dict(self)


@dataclass(frozen=True, eq=False)
class ImuData:
    """One inertial sensor's recording, in SI units and the sensor's body frame.

    Parameters
    ----------
    t
        Sample times in s, shape (N,), strictly increasing.
    acc
        Specific force in m/s^2, body frame, shape (N, 3). At rest it points up: +g on the up axis.
    gyr
        Angular rate in rad/s, body frame, shape (N, 3).
    mag
        Magnetic field (any consistent unit, usually uT), body frame, shape (N, 3), or None.
    meta
        Provenance: source file, units converted, gaps, duplicates dropped, clipping.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, fewer than two samples, time not strictly increasing
        (equal times are duplicate rows: drop them explicitly with ``drop_duplicates=True`` in
        :meth:`from_arrays` or a reader). The error names the field, the file (``meta["source"]``)
        and the first bad index.

    Warns
    -----
    DataQualityWarning
        When a sampling interval exceeds ``GAP_FACTOR`` x the median; the gaps are listed in
        ``meta["gaps"]`` as ``(index, dt_s)`` with ``index`` the first sample after the gap.
    """

    t: NDArray[np.float64]
    acc: NDArray[np.float64]
    gyr: NDArray[np.float64]
    mag: NDArray[np.float64] | None = None
    meta: Mapping[str, Any] = field(default_factory=dict)
    frame: str = "body"

    def __post_init__(self) -> None:
        meta = dict(self.meta)
        path = meta.get("source")
        t = _as_float_array(self.t, "t", None, path)
        n = len(t)
        if n < 2:
            raise InvalidInputError(f"need at least 2 samples, got {n}", field="t", path=path)
        acc = _as_float_array(self.acc, "acc", 3, path)
        gyr = _as_float_array(self.gyr, "gyr", 3, path)
        mag = None if self.mag is None else _as_float_array(self.mag, "mag", 3, path)
        for name, arr in (("acc", acc), ("gyr", gyr), ("mag", mag)):
            if arr is not None and len(arr) != n:
                raise InvalidInputError(
                    f"has {len(arr)} samples but t has {n}; every array needs one row per sample",
                    field=name,
                    path=path,
                )
        dt = np.diff(t)
        if (dt == 0).any():
            i = _first_true(dt == 0) + 1
            raise InvalidInputError(
                f"duplicate time stamp t={t[i]!r} s (same as sample {i - 1}); "
                "drop duplicate rows explicitly (drop_duplicates=True)",
                field="t",
                index=i,
                path=path,
            )
        if (dt < 0).any():
            i = _first_true(dt < 0) + 1
            raise InvalidInputError(
                f"time goes backwards: t[{i}]={t[i]!r} s < t[{i - 1}]={t[i - 1]!r} s; "
                "t must be strictly increasing",
                field="t",
                index=i,
                path=path,
            )
        median_dt = float(np.median(dt))
        gap_idx = np.flatnonzero(dt > GAP_FACTOR * median_dt)
        if len(gap_idx) and "gaps" not in meta:
            meta["gaps"] = [(int(i + 1), float(dt[i])) for i in gap_idx]
            warn(
                f"{path or 'ImuData'}: {len(gap_idx)} sampling gap(s) longer than {GAP_FACTOR:g} x the "
                f"median interval {median_dt * 1e3:.3g} ms (first at index {gap_idx[0] + 1}, "
                f"{dt[gap_idx[0]] * 1e3:.3g} ms); listed in meta['gaps']",
                DataQualityWarning,
                stacklevel=3,
            )
        object.__setattr__(self, "t", _readonly(t))
        object.__setattr__(self, "acc", _readonly(acc))
        object.__setattr__(self, "gyr", _readonly(gyr))
        object.__setattr__(self, "mag", None if mag is None else _readonly(mag))
        object.__setattr__(self, "meta", ReadOnlyMeta(meta))

    # -- construction -------------------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        t: Any,
        acc: Any,
        gyr: Any,
        mag: Any = None,
        *,
        acc_unit: str = "m/s^2",
        gyr_unit: str = "rad/s",
        t_unit: str = "s",
        mag_unit: str = "uT",
        drop_duplicates: bool = False,
        meta: Mapping[str, Any] | None = None,
        check_units: bool = True,
        acc_full_scale_mps2: float | None = None,
    ) -> ImuData:
        """Build from arrays in the given units, converting to SI.

        Parameters
        ----------
        t, acc, gyr, mag
            Time (N,), specific force (N, 3), angular rate (N, 3), optional magnetic field (N, 3).
            pandas objects are accepted (converted with ``numpy.asarray``).
        acc_unit
            ``"m/s^2"`` or ``"g"`` (1 g = ``GRAVITY_MPS2``).
        gyr_unit
            ``"rad/s"`` or ``"deg/s"``.
        t_unit
            ``"s"``, ``"ms"``, ``"us"`` or ``"ns"`` for numbers. A datetime64 or timedelta64 ``t``
            (numpy, or a pandas column or index, time-zone aware or not) carries its own unit and
            is converted: datetimes to seconds since the first sample (``meta["t0_datetime"]``
            keeps the first one), timedeltas to seconds; ``meta["time_converted"]`` says so.
            Date/time *objects* (an object array) are refused: convert them to datetime64.
        mag_unit
            ``"uT"``, ``"T"``, ``"gauss"`` or ``"a.u."`` (kept as is).
        drop_duplicates
            Drop samples whose time equals the previous sample's (e.g. repeated rows of a logger).
            The count and the dropped indices are recorded in ``meta["duplicates_dropped"]``.
        meta
            Extra provenance to keep.
        check_units
            Check that the converted data are plausible (:meth:`check_units`): units, time base
            and rate, the accelerometer at rest, saturation. Findings that are not errors are
            warned once (DataQualityWarning) and recorded in ``meta``: ``"rate_check"``,
            ``"gyr_unit_check"``, ``"acc_at_rest"``, ``"clipped"``.
        acc_full_scale_mps2
            The accelerometer's full scale, if known, for clipping detection (:func:`detect_clipping`).

        Raises
        ------
        InvalidInputError
            Unknown unit, wrong shapes, non-finite or missing (NaT) values, duplicate or backwards
            time, and the errors of :meth:`check_units`.
        """
        meta = dict(meta or {})
        scales = {}
        for name, unit, table in (
            ("acc_unit", acc_unit, _ACC_SCALE),
            ("gyr_unit", gyr_unit, _GYR_SCALE),
            ("t_unit", t_unit, _T_SCALE),
            ("mag_unit", mag_unit, _MAG_SCALE),
        ):
            if unit not in table:
                raise InvalidInputError(
                    f"unknown unit {unit!r}; expected one of {sorted(table)}", field=name, path=meta.get("source")
                )
            scales[name] = table[unit]
        path = meta.get("source")
        t, time_record = _time_seconds(t, t_unit, path)
        meta.update(time_record)
        t_arr = _as_float_array(t, "t", None, path) * scales["t_unit"]
        acc_arr = _as_float_array(acc, "acc", 3, path) * scales["acc_unit"]
        gyr_arr = _as_float_array(gyr, "gyr", 3, path) * scales["gyr_unit"]
        mag_arr = None if mag is None else _as_float_array(mag, "mag", 3, path) * scales["mag_unit"]
        meta["units_in"] = {"t": t_unit, "acc": acc_unit, "gyr": gyr_unit, **({"mag": mag_unit} if mag is not None else {})}
        if drop_duplicates and len(t_arr) > 1:
            dup = np.flatnonzero(np.diff(t_arr) == 0) + 1
            if len(dup):
                keep = np.ones(len(t_arr), dtype=bool)
                keep[dup] = False
                t_arr, acc_arr, gyr_arr = t_arr[keep], acc_arr[keep], gyr_arr[keep]
                mag_arr = None if mag_arr is None else mag_arr[keep]
                meta["duplicates_dropped"] = {"count": len(dup), "indices": dup.tolist()}
                warn(
                    f"{path or 'ImuData'}: dropped {len(dup)} sample(s) with a repeated time stamp "
                    f"(first at index {dup[0]}); recorded in meta['duplicates_dropped']",
                    DataQualityWarning,
                    stacklevel=2,
                )
        imu = cls(t=t_arr, acc=acc_arr, gyr=gyr_arr, mag=mag_arr, meta=meta)
        if check_units:
            findings = _check_data(imu.t, imu.acc, imu.gyr, imu.meta, acc_full_scale_mps2=acc_full_scale_mps2)
            if findings:
                imu = replace(imu, meta={**imu.meta, **{key: record for key, record, _ in findings}})
                for _, _, message in findings:
                    warn(message, DataQualityWarning, stacklevel=2)
        return imu

    def check_units(self) -> None:
        """Check that the data can be what they are declared to be (SI units, seconds).

        Raises InvalidInputError for a median |acc| far from gravity (g read as m/s^2), an
        accelerometer more than ``ACC_REST_ERROR_FRACTION`` off g at rest, angular rates no MEMS
        gyroscope measures (deg/s read as rad/s), a time base no foot-mounted IMU has (ms or us
        read as s: ``RATE_ERROR_HZ``). Warns (DataQualityWarning) for a rate outside
        ``RATE_BOUNDS_HZ``, a gyroscope that looks like rad/s read as deg/s, an accelerometer more
        than ``ACC_REST_WARN_FRACTION`` off g at rest (saturation only in :meth:`from_arrays`) --
        unless ``meta`` already records that finding (:meth:`from_arrays` and the readers record and warn once).
        Readers, :meth:`from_arrays` and :meth:`footnav.Pipeline.run` call it; the constructor
        does not, so synthetic test data can be anything."""
        # no clipping search here: saturation is a property of how data were recorded, found where
        # they enter (from_arrays, readers); synthetic data built with the constructor repeat their
        # exact peaks every stride, which the plateau rule would call clipping
        for key, _, message in _check_data(self.t, self.acc, self.gyr, self.meta, clipping=False):
            if key not in self.meta:
                warn(message, DataQualityWarning, stacklevel=2)

    @classmethod
    def from_dataframe(cls, frame: Any, *, time_column: str = "t", **units: Any) -> ImuData:
        """Build from a pandas DataFrame with columns ``t, acc_x..acc_z, gyr_x..gyr_z`` (and
        ``mag_x..mag_z`` if present), in the units given as for :meth:`from_arrays`.

        The time may also be the index (``time_column=None``). A missing column raises
        InvalidInputError naming it and the columns there are.
        """
        columns = [str(c) for c in getattr(frame, "columns", [])]
        needed = [f"{s}_{a}" for s in ("acc", "gyr") for a in "xyz"] + ([time_column] if time_column else [])
        missing = [c for c in needed if c not in columns]
        if missing:
            raise InvalidInputError(
                f"DataFrame lacks column(s) {missing}; it has {columns}. Expected {time_column or '(index)'}, "
                "acc_x, acc_y, acc_z, gyr_x, gyr_y, gyr_z (optional mag_x..mag_z)",
                field=missing[0],
            )
        t = frame[time_column] if time_column else frame.index
        mag_cols = [f"mag_{a}" for a in "xyz"]
        mag = frame[mag_cols] if all(c in columns for c in mag_cols) else None
        return cls.from_arrays(
            t, frame[[f"acc_{a}" for a in "xyz"]], frame[[f"gyr_{a}" for a in "xyz"]], mag,
            meta={"source": units.pop("source", "DataFrame")}, **units,
        )

    # -- views --------------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.t)

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return len(self.t)

    @property
    def duration_s(self) -> float:
        """Time from first to last sample, in s."""
        return float(self.t[-1] - self.t[0])

    @functools.cached_property
    def rate_hz(self) -> float:
        """Nominal sampling rate in Hz: 1 / median sampling interval (computed once: t is read-only)."""
        return float(1.0 / np.median(np.diff(self.t)))

    @property
    def has_mag(self) -> bool:
        return self.mag is not None

    def slice(self, start: int | None = None, stop: int | None = None) -> ImuData:
        """Samples ``start:stop`` as a new ImuData (same meta)."""
        s = np.s_[start:stop]
        return replace(
            self,
            t=self.t[s],
            acc=self.acc[s],
            gyr=self.gyr[s],
            mag=None if self.mag is None else self.mag[s],
            meta={k: v for k, v in self.meta.items() if k != "gaps"},
        )

    def __repr__(self) -> str:
        src = self.meta.get("source")
        return (
            f"ImuData(n={self.n_samples}, rate={self.rate_hz:.4g} Hz, duration={self.duration_s:.4g} s, "
            f"mag={'yes' if self.has_mag else 'no'}, frame={self.frame!r}"
            + (f", source={src!r}" if src else "")
            + ")"
        )


def stance_intervals(mask: NDArray[np.bool_]) -> NDArray[np.int64]:
    """Start and stop (exclusive) indices of each run of True in ``mask``, shape (K, 2)."""
    m = np.asarray(mask, dtype=bool)
    if m.size == 0:
        return np.empty((0, 2), dtype=np.int64)
    d = np.diff(np.concatenate(([False], m, [False])).astype(np.int8))
    starts = np.flatnonzero(d == 1)
    stops = np.flatnonzero(d == -1)
    return np.stack([starts, stops], axis=1).astype(np.int64)


@dataclass(frozen=True, eq=False)
class StanceResult:
    """What a stance detector found in one foot's recording (sample-aligned with its ImuData).

    Parameters
    ----------
    mask
        True where the foot is at zero velocity (stance), shape (N,).
    events
        Gait events as sample indices, e.g. ``{"heel_strike": ..., "foot_flat": ..., "heel_off": ...,
        "toe_off": ...}``; each value int array. Detectors give those they can.
    phases
        Per-sample phase label (int, detector-defined, names in ``meta["phase_names"]``), or None.
    score
        Per-sample detector statistic or stance probability (N,), or None.
    meta
        Detector name, parameters and diagnostics.
    """

    mask: NDArray[np.bool_]
    events: Mapping[str, NDArray[np.int64]] = field(default_factory=dict)
    phases: NDArray[np.int64] | None = None
    score: NDArray[np.float64] | None = None
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        mask = np.asarray(self.mask)
        if mask.ndim != 1:
            raise InvalidInputError(f"expected shape (N,), got {mask.shape}", field="mask")
        object.__setattr__(self, "mask", _readonly(mask.astype(bool)))
        object.__setattr__(
            self, "events", {k: _readonly(np.asarray(v, dtype=np.int64)) for k, v in dict(self.events or {}).items()}
        )
        n = len(mask)
        for name in ("phases", "score"):
            val = getattr(self, name)
            if val is not None:
                arr = np.asarray(val)
                if arr.shape != (n,):
                    raise InvalidInputError(f"expected shape ({n},), got {arr.shape}", field=name)
                object.__setattr__(self, name, _readonly(arr))
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def intervals(self) -> NDArray[np.int64]:
        """(K, 2) start/stop indices of each stance phase."""
        return stance_intervals(self.mask)

    @property
    def n_stances(self) -> int:
        return len(self.intervals)


@dataclass(frozen=True, eq=False)
class FootTrajectory:
    """One foot's estimated motion in the nav frame (z up, x initial walking direction).

    Parameters
    ----------
    t
        Times in s, shape (N,).
    position
        Position of the sensor in m, nav frame, (N, 3).
    velocity
        Velocity in m/s, nav frame, (N, 3).
    quaternion
        Orientation [w, x, y, z], body -> nav, (N, 4), unit norm.
    position_std
        1-sigma position uncertainty per axis in m, (N, 3) (diagonal of the filter covariance).
    steps
        (K, 2) start/stop sample indices of each stance phase used (the footprints).
    meta
        Estimator name, parameters, diagnostics.
    """

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64]
    quaternion: NDArray[np.float64]
    position_std: NDArray[np.float64]
    steps: NDArray[np.int64]
    meta: Mapping[str, Any] = field(default_factory=dict)
    frame: str = "nav"

    def __post_init__(self) -> None:
        n = len(self.t)
        for name, cols in (("position", 3), ("velocity", 3), ("quaternion", 4), ("position_std", 3)):
            arr = np.asarray(getattr(self, name), dtype=np.float64)
            if arr.shape != (n, cols):
                raise InvalidInputError(f"expected shape ({n}, {cols}), got {arr.shape}", field=name)
            object.__setattr__(self, name, _readonly(arr))
        object.__setattr__(self, "t", _readonly(np.asarray(self.t, dtype=np.float64)))
        steps = np.asarray(self.steps, dtype=np.int64).reshape(-1, 2)
        object.__setattr__(self, "steps", _readonly(steps))
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def footprints(self) -> NDArray[np.float64]:
        """Mean position over each stance phase, (K, 3) in m."""
        if len(self.steps) == 0:
            return np.empty((0, 3))
        return np.stack([self.position[a:b].mean(axis=0) for a, b in self.steps])

    @property
    def path_length_m(self) -> float:
        """Horizontal distance travelled, summed over footprints (m); over samples if no steps."""
        pts = self.footprints if len(self.steps) > 1 else self.position
        return float(np.linalg.norm(np.diff(pts[:, :2], axis=0), axis=1).sum())


@dataclass(frozen=True, eq=False)
class Path:
    """The pedestrian's path in the nav frame: position (N, 3) in m at times t (N,) in s."""

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    meta: Mapping[str, Any] = field(default_factory=dict)
    frame: str = "nav"

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=np.float64)
        pos = np.asarray(self.position, dtype=np.float64)
        if pos.shape != (len(t), 3):
            raise InvalidInputError(f"expected shape ({len(t)}, 3), got {pos.shape}", field="position")
        object.__setattr__(self, "t", _readonly(t))
        object.__setattr__(self, "position", _readonly(pos))
        object.__setattr__(self, "meta", dict(self.meta))


@dataclass(frozen=True, eq=False)
class FusionResult:
    """Output of a fusion strategy: both feet (right may be None) and the pedestrian path."""

    left: FootTrajectory
    right: FootTrajectory | None
    path: Path
    meta: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class PipelineResult:
    """Everything a pipeline run produced, with its provenance.

    ``meta`` holds ``"pipeline"`` (the configuration, re-runnable with ``make_pipeline(**...)``),
    ``"footnav_version"``, ``"warnings"`` (the warnings :func:`footnav.warn` issued during this
    run), ``"stance_check"`` (each foot's stances against its gait cycles), ``"fusion"`` (what the
    fusion computed: its update counts, fitted values and suspended intervals, the feet's common
    span), ``"runtime_s"`` and ``"input"`` (the inputs' own meta).
    """

    left: FootTrajectory
    right: FootTrajectory | None
    path: Path
    stance_left: StanceResult
    stance_right: StanceResult | None
    meta: Mapping[str, Any] = field(default_factory=dict)

    def _feet(self) -> list[tuple[str, FootTrajectory, StanceResult]]:
        feet = [("left", self.left, self.stance_left)]
        if self.right is not None and self.stance_right is not None:
            feet.append(("right", self.right, self.stance_right))
        return feet

    def strides(self) -> Any:
        """Gait parameters per stride and foot (:func:`footnav.core.strides.stride_parameters`).

        A stride runs from one mid-stance to the next of the same foot (gaitmap's definition);
        columns ``foot, start_s, end_s, length_m, duration_s, cadence_spm, stance_s, swing_s,
        clearance_m, elevation_m, turn_rad, start_index, end_index`` (SI units in the names), left
        foot's strides first, each foot's in time order.

        Returns
        -------
        pandas.DataFrame or numpy structured array
            A DataFrame when pandas is installed, else a structured array of dtype
            :data:`footnav.core.strides.STRIDE_DTYPE` with the same columns.

        Examples
        --------
        >>> res = footnav.make_pipeline().run(left, right)          # doctest: +SKIP
        >>> res.strides().groupby("foot")["length_m"].mean()          # doctest: +SKIP
        """
        from footnav.core.strides import stride_parameters

        table = np.concatenate([stride_parameters(tr, st, foot=foot) for foot, tr, st in self._feet()])
        try:
            import pandas as pd
        except ImportError:
            return table
        return pd.DataFrame({name: table[name] for name in table.dtype.names})

    def to_dataframe(self) -> Any:
        """Per-sample trajectories of both feet as one long pandas DataFrame.

        Columns ``foot, t_s, pos_x_m, pos_y_m, pos_z_m, vel_x_mps, vel_y_mps, vel_z_mps, q_w, q_x,
        q_y, q_z, pos_std_x_m, pos_std_y_m, pos_std_z_m, stance`` (nav frame, z up; the columns of
        ``left.csv`` written by :func:`footnav.core.results.write_results`), left foot first.

        Raises
        ------
        FootnavError
            pandas is not installed (``pip install pandas``).
        """
        try:
            import pandas as pd
        except ImportError:
            from footnav.core.errors import FootnavError

            raise FootnavError(
                "PipelineResult.to_dataframe() needs pandas, which is not installed: pip install pandas "
                "(or use result.left.position etc. directly)"
            ) from None
        frames = []
        for foot, tr, st in self._feet():
            cols: dict[str, Any] = {"foot": np.full(len(tr.t), foot), "t_s": tr.t}
            for name, arr, axes, unit in (
                ("pos", tr.position, "xyz", "m"),
                ("vel", tr.velocity, "xyz", "mps"),
                ("q", tr.quaternion, "wxyz", ""),
                ("pos_std", tr.position_std, "xyz", "m"),
            ):
                for j, ax in enumerate(axes):
                    cols[f"{name}_{ax}_{unit}" if unit else f"{name}_{ax}"] = arr[:, j]
            cols["stance"] = np.asarray(st.mask, dtype=bool)
            frames.append(pd.DataFrame(cols))
        return pd.concat(frames, ignore_index=True)


@dataclass(frozen=True, eq=False)
class FootTruth:
    """Reference motion of one foot, as far as a recording or the simulator knows it.

    Parameters
    ----------
    t
        Times in s of the reference samples, on the IMU's clock, shape (M,). May differ from the
        IMU's times (e.g. motion capture at 100 Hz); may be empty when only ``closed_loop`` is known.
    position
        Reference position in m, (M, 3), in ``frame``. Readers convert to z up; origin and heading
        are the reference system's own, so align before comparing (see ``footnav.core.metrics``).
    quaternion
        Reference orientation [w, x, y, z], body -> ``frame``, (M, 4), or None.
    velocity
        Reference velocity in m/s, (M, 3), or None.
    stance
        Reference stance mask over the IMU samples (N,), or None. ``meta["stance_source"]`` says
        what it is (simulator truth, mocap-derived, proxy labels of another detector).
    events
        Reference gait events as IMU sample indices (``heel_strike``, ``foot_flat``, ``heel_off``,
        ``toe_off``, ``mid_stance``), possibly empty.
    closed_loop
        True when the walk is known to end where it started.
    frame
        ``"nav"`` for the simulator (footnav's nav frame), else the reference system's name
        (``"vicon"``, ``"mocap"``, ...), always z up after the reader's conversion.
    """

    t: NDArray[np.float64]
    position: NDArray[np.float64]
    quaternion: NDArray[np.float64] | None = None
    velocity: NDArray[np.float64] | None = None
    stance: NDArray[np.bool_] | None = None
    events: Mapping[str, NDArray[np.int64]] = field(default_factory=dict)
    closed_loop: bool = False
    frame: str = "nav"
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=np.float64).reshape(-1)
        m = len(t)
        object.__setattr__(self, "t", _readonly(t))
        pos = np.asarray(self.position, dtype=np.float64).reshape(-1, 3) if m else np.empty((0, 3))
        if len(pos) != m:
            raise InvalidInputError(f"expected shape ({m}, 3), got {pos.shape}", field="position")
        object.__setattr__(self, "position", _readonly(pos))
        for name, cols in (("quaternion", 4), ("velocity", 3)):
            val = getattr(self, name)
            if val is not None:
                arr = np.asarray(val, dtype=np.float64)
                if arr.shape != (m, cols):
                    raise InvalidInputError(f"expected shape ({m}, {cols}), got {arr.shape}", field=name)
                object.__setattr__(self, name, _readonly(arr))
        if self.stance is not None:
            object.__setattr__(self, "stance", _readonly(np.asarray(self.stance, dtype=bool)))
        object.__setattr__(
            self, "events", {k: _readonly(np.asarray(v, dtype=np.int64)) for k, v in dict(self.events or {}).items()}
        )
        object.__setattr__(self, "meta", dict(self.meta))


@dataclass(frozen=True, eq=False)
class Recording:
    """A recording of one or both feet with whatever reference it carries.

    ``left`` is the only foot of a one-foot recording (``right`` is None then). ``truth_left`` and
    ``truth_right`` are None when the recording has no reference for that foot. ``meta`` holds the
    reader's name (``"format"``), the source files and every change the reader made.
    """

    left: ImuData
    right: ImuData | None = None
    truth_left: FootTruth | None = None
    truth_right: FootTruth | None = None
    name: str = ""
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def n_feet(self) -> int:
        return 1 if self.right is None else 2
