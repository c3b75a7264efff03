"""One inertial sensor's recording (:class:`ImuData`) and its read-only provenance (:class:`ReadOnlyMeta`)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types._arrays import _as_float_array, _readonly
from footnav.core.types.imu_checks import GAP_FACTOR, _check_data, check_time_order, find_gaps, gap_message
from footnav.core.types.sample_checks import check_same_rows
from footnav.core.types.units import _ACC_SCALE, _GYR_SCALE, _MAG_SCALE, _T_SCALE, _time_seconds
from footnav.core.warning_log import warn

__all__ = ["GAP_FACTOR", "ImuData", "ReadOnlyMeta"]


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

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = __ior__ = _refuse  # type: ignore[assignment]

    def __reduce__(self) -> tuple:
        return (ReadOnlyMeta, (dict(self),))

    def copy(self) -> dict:
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
    #: Median sampling interval, s: set per instance by __post_init__ (ClassVar keeps it out of
    #: the dataclass's fields, so constructor, replace and asdict do not see it).
    _median_dt: ClassVar[float]

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
        check_same_rows(n, {"acc": acc, "gyr": gyr, "mag": mag}, path)
        dt = check_time_order(t, path=path)
        median_dt = float(np.median(dt))
        gaps = find_gaps(dt, median_dt)
        if gaps and "gaps" not in meta:
            meta["gaps"] = gaps
            warn(gap_message(path or "ImuData", gaps, median_dt), DataQualityWarning, stacklevel=3)
        object.__setattr__(self, "t", _readonly(t))
        object.__setattr__(self, "acc", _readonly(acc))
        object.__setattr__(self, "gyr", _readonly(gyr))
        object.__setattr__(self, "mag", None if mag is None else _readonly(mag))
        object.__setattr__(self, "meta", ReadOnlyMeta(meta))
        # kept for rate_hz and check_units: t is read-only, so its median interval never changes
        object.__setattr__(self, "_median_dt", median_dt)

    # -- construction -------------------------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        t: Any = None,
        acc: Any = None,
        gyr: Any = None,
        mag: Any = None,
        *,
        rate_hz: float | None = None,
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
            pandas objects are accepted (converted with ``numpy.asarray``). ``t`` may be left out
            (None) when ``rate_hz`` is given.
        rate_hz
            Sampling rate (Hz) of data without time stamps: ``t = sample index / rate_hz``
            (``meta["time_source"]`` says so). Give ``t`` or ``rate_hz``, not both.
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
        t = _time_from_rate(t, acc, gyr, rate_hz, t_unit, meta)
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
        meta["units_in"] = {
            "t": t_unit,
            "acc": acc_unit,
            "gyr": gyr_unit,
            **({"mag": mag_unit} if mag is not None else {}),
        }
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
            findings = _check_data(
                imu.t, imu.acc, imu.gyr, imu.meta, acc_full_scale_mps2=acc_full_scale_mps2, median_dt=imu._median_dt
            )
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
        for key, _, message in _check_data(
            self.t, self.acc, self.gyr, self.meta, clipping=False, median_dt=self._median_dt
        ):
            if key not in self.meta:
                warn(message, DataQualityWarning, stacklevel=2)

    @classmethod
    def from_dataframe(
        cls, frame: Any, *, time_column: str | None = "t", rate_hz: float | None = None, **units: Any
    ) -> ImuData:
        """Build from a pandas DataFrame with columns ``t, acc_x..acc_z, gyr_x..gyr_z`` (and
        ``mag_x..mag_z`` if present), in the units given as for :meth:`from_arrays`.

        The time may also be the index (``time_column=None``). Without time stamps give
        ``rate_hz``: ``t = row / rate_hz``. An index of sample numbers (a RangeIndex, or integers
        stepping by 1) is not a time: without a time column it is an error asking for
        ``rate_hz``. A missing column raises InvalidInputError naming it and the columns there are.
        """
        columns = [str(c) for c in getattr(frame, "columns", [])]
        source = units.pop("source", "DataFrame")
        path = None if source == "DataFrame" else source  # errors name a file only when there is one
        has_t = bool(time_column) and time_column in columns
        if rate_hz is not None and has_t:
            raise InvalidInputError(
                f"rate_hz={rate_hz!r} given, but the DataFrame has a time column {time_column!r}; give one of them "
                "(time_column=None and rate_hz for data without time)",
                field="rate_hz",
                path=path,
            )
        if rate_hz is None and not has_t and _is_sample_numbers(getattr(frame, "index", None)):
            index = frame.index
            raise InvalidInputError(
                f"the DataFrame has no time column{f' {time_column!r}' if time_column else ''} and its index holds "
                f"sample numbers ({type(index).__name__} {index[0]!r}..{index[-1]!r}, step 1), not times; pass the "
                "sampling rate: ImuData.from_dataframe(frame, rate_hz=100.0) (t = row / rate_hz)",
                field="rate_hz",
                path=path,
            )
        needed = [f"{s}_{a}" for s in ("acc", "gyr") for a in "xyz"] + (
            [time_column] if time_column and rate_hz is None else []
        )
        missing = [c for c in needed if c not in columns]
        if missing:
            raise InvalidInputError(
                f"DataFrame lacks column(s) {missing}; it has {columns}. Expected {time_column or '(index)'}, "
                "acc_x, acc_y, acc_z, gyr_x, gyr_y, gyr_z (optional mag_x..mag_z); without time stamps pass "
                "rate_hz=...",
                field=missing[0],
                path=path,
            )
        t = None if rate_hz is not None else (frame[time_column] if time_column else frame.index)
        mag_cols = [f"mag_{a}" for a in "xyz"]
        mag = frame[mag_cols] if all(c in columns for c in mag_cols) else None
        return cls.from_arrays(
            t,
            frame[[f"acc_{a}" for a in "xyz"]],
            frame[[f"gyr_{a}" for a in "xyz"]],
            mag,
            rate_hz=rate_hz,
            meta={"source": source},
            **units,
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
        return float(1.0 / self._median_dt)

    @property
    def has_mag(self) -> bool:
        """Whether the recording has a magnetometer (``mag``)."""
        return self.mag is not None

    def same_grid(self, t: NDArray[np.float64], acc: NDArray[np.float64], gyr: NDArray[np.float64]) -> ImuData:
        """This recording's frame, meta and sampling interval with other samples, **unchecked**.

        For a caller that has checked the samples itself and keeps them on this recording's
        grid: footnav's online stream hands each detection window over this way, where the
        checks of the constructor would cost as much as the detector's work on the window.
        The arrays are taken (made read-only), not copied."""
        imu = object.__new__(ImuData)
        fields = imu.__dict__
        fields.update(self.__dict__)
        fields.pop("rate_hz", None)  # a cached property: recomputed from the same interval
        for name, a in (("t", t), ("acc", acc), ("gyr", gyr)):
            a.setflags(write=False)
            fields[name] = a
        fields["mag"] = None
        return imu

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
            f"mag={'yes' if self.has_mag else 'no'}, frame={self.frame!r}" + (f", source={src!r}" if src else "") + ")"
        )


def _is_sample_numbers(index: Any) -> bool:
    """Whether a DataFrame index holds sample numbers (integers stepping by 1), not times."""
    if index is None or len(index) < 2:
        return False
    step = getattr(index, "step", None)  # a pandas RangeIndex
    if step is not None:
        return step == 1
    arr = np.asarray(index)
    return arr.dtype.kind in "iu" and bool((np.diff(arr) == 1).all())


def _time_from_rate(t: Any, acc: Any, gyr: Any, rate_hz: float | None, t_unit: str, meta: dict[str, Any]) -> Any:
    """``t`` as given, or ``sample index / rate_hz`` when the data have no time stamps."""
    path = meta.get("source")
    if acc is None or gyr is None:
        raise InvalidInputError("acc and gyr are required", field="acc" if acc is None else "gyr", path=path)
    if rate_hz is None:
        if t is None:
            raise InvalidInputError(
                "no time: pass t (its unit as t_unit) or, for data without time stamps, the sampling rate rate_hz=...",
                field="t",
                path=path,
            )
        return t
    if t is not None:
        raise InvalidInputError(f"give t or rate_hz={rate_hz!r}, not both", field="rate_hz", path=path)
    try:
        rate = float(rate_hz)
    except (TypeError, ValueError):
        rate = float("nan")
    if not (np.isfinite(rate) and rate > 0):
        raise InvalidInputError(f"rate_hz={rate_hz!r} is not a finite number > 0", field="rate_hz", path=path)
    if t_unit != "s":
        raise InvalidInputError(
            f"t_unit={t_unit!r} with rate_hz: there are no time stamps to have a unit", field="t_unit", path=path
        )
    n = np.shape(acc)[0] if np.ndim(acc) >= 1 else 0
    meta["time_source"] = f"sample index / {rate:g} Hz (no time stamps given)"
    return np.arange(n) / rate
