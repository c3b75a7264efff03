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

import warnings
from dataclasses import dataclass, field, replace
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError

__all__ = [
    "GRAVITY_MPS2",
    "GAP_FACTOR",
    "ImuData",
    "StanceResult",
    "FootTrajectory",
    "Path",
    "FusionResult",
    "PipelineResult",
    "FootTruth",
    "Recording",
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
_T_SCALE = {"s": 1.0, "ms": 1e-3}
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
#: MEMS gyroscopes measure up to about 2000 deg/s (35 rad/s); a 99th percentile of |w| above
#: this (rad/s) is angular rate in deg/s read as rad/s.
GYR_P99_MAX_RADPS = 40.0


def _check_units(acc: NDArray[np.float64], gyr: NDArray[np.float64], path: str | None) -> None:
    """Raise InvalidInputError when the magnitudes say the units are not the declared SI ones."""
    f = float(np.median(np.linalg.norm(acc, axis=1)))
    lo, hi = ACC_MEDIAN_BOUNDS_MPS2
    if not lo <= f <= hi:
        hint = "the data look like g: read them with acc_unit='g'" if 0.5 <= f < lo else (
            "is the accelerometer in another unit, or is its column mapping wrong?")
        raise InvalidInputError(
            f"implausible specific force: median |acc| = {f:.3g} m/s^2, but a foot-mounted IMU reads gravity "
            f"({GRAVITY_MPS2:g} m/s^2) whenever the foot stands still; {hint}",
            field="acc",
            path=path,
        )
    w = float(np.percentile(np.linalg.norm(gyr, axis=1), 99))
    if w > GYR_P99_MAX_RADPS:
        raise InvalidInputError(
            f"implausible angular rate: 99th percentile of |gyr| = {w:.3g} rad/s, beyond any MEMS gyroscope's "
            f"range (~35 rad/s = 2000 deg/s); the data look like deg/s: read them with gyr_unit='deg/s'",
            field="gyr",
            path=path,
        )


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
            warnings.warn(
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
        object.__setattr__(self, "meta", meta)

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
    ) -> "ImuData":
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
            ``"s"`` or ``"ms"``.
        mag_unit
            ``"uT"``, ``"T"``, ``"gauss"`` or ``"a.u."`` (kept as is).
        drop_duplicates
            Drop samples whose time equals the previous sample's (e.g. repeated rows of a logger).
            The count and the dropped indices are recorded in ``meta["duplicates_dropped"]``.
        meta
            Extra provenance to keep.
        check_units
            Check that the converted magnitudes are plausible (:meth:`check_units`).
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
                meta["duplicates_dropped"] = {"count": int(len(dup)), "indices": dup.tolist()}
                warnings.warn(
                    f"{path or 'ImuData'}: dropped {len(dup)} sample(s) with a repeated time stamp "
                    f"(first at index {dup[0]}); recorded in meta['duplicates_dropped']",
                    DataQualityWarning,
                    stacklevel=2,
                )
        imu = cls(t=t_arr, acc=acc_arr, gyr=gyr_arr, mag=mag_arr, meta=meta)
        if check_units:
            imu.check_units()
        return imu

    def check_units(self) -> None:
        """Raise InvalidInputError when the magnitudes say the data are not in the SI units they
        are declared in: a median |acc| far from gravity (g read as m/s^2), or angular rates no
        MEMS gyroscope measures (deg/s read as rad/s). Readers, :meth:`from_arrays` and
        :meth:`footnav.Pipeline.run` call it; the constructor does not, so synthetic test data
        can be anything."""
        _check_units(self.acc, self.gyr, self.meta.get("source"))

    @classmethod
    def from_dataframe(cls, frame: Any, *, time_column: str = "t", **units: Any) -> "ImuData":
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

    def slice(self, start: int | None = None, stop: int | None = None) -> "ImuData":
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
    ``"footnav_version"``, ``"warnings"`` (messages raised during the run), ``"runtime_s"`` and the
    inputs' own meta.
    """

    left: FootTrajectory
    right: FootTrajectory | None
    path: Path
    stance_left: StanceResult
    stance_right: StanceResult | None
    meta: Mapping[str, Any] = field(default_factory=dict)


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
