"""The input checks of one foot's online stream: the checks :class:`~footnav.core.types.ImuData` and
its readers run on a recording, run on chunks as they arrive, with the same messages.

Per chunk, before the stream takes it (:meth:`ChunkChecks.check`; nothing changes when it raises):
shape (a transposed ``(3, N)`` chunk is refused naming its shape), non-finite values, time that
does not increase (across chunks too), samples beyond any foot IMU's range and angular rates held
beyond any gyroscope's (:func:`~footnav.core.types.imu_checks.check_extremes`); the error names the
sample by its index in the foot's stream, as the offline error names it in the recording, and
says what the offline check of the whole recording says, however the samples are chunked. Sampling
gaps are found per chunk
once the median interval is known and warned as offline (``records["gaps"]``).

Checks that need more than a chunk run when their data have arrived, and at the end on what
arrived if that is earlier:

* the time base and rate (:func:`~footnav.core.types.imu_checks.check_time_base`) on the first
  ``TIME_BASE_SAMPLES`` samples: time in ms or us read as s is an error before the filter starts;
* units, the accelerometer at rest and saturation (``_check_data``) on the first
  ``CHECK_WINDOW_S`` seconds, extended up to ``CHECK_WINDOW_MAX_S`` while the foot has not moved
  enough for the gyroscope's unit to be judged; and again on the whole recording at the end of a
  stream that kept every sample (``keep=True``, :meth:`ChunkChecks.finish_whole`), as offline.
  Saturation later in the walk is found chunk by chunk as well (:class:`_ExtremeTally`: the
  plateau rule of :func:`~footnav.core.types.imu_checks.detect_clipping` on the largest and smallest
  value of each axis so far), so a stream with ``keep=False`` reports it when it happens.

Findings that are not errors are warned (DataQualityWarning) when found and kept in
:attr:`ChunkChecks.records` under the keys the offline run records in the input's meta
(``"gaps"``, ``"rate_check"``, ``"gyr_unit_check"``, ``"acc_at_rest"``, ``"clipped"``);
:meth:`OnlineStream.close` puts them into the result's ``meta["input"][foot]``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav._numba import njit
from footnav.core.errors import DataQualityWarning
from footnav.core.types._arrays import _as_float_array
from footnav.core.types._derived import row_norms
from footnav.core.types.imu_checks import (
    ACC_FULL_SCALES_G,
    ACC_MAX_MPS2,
    ACC_MOVING_FRACTION,
    ACC_MOVING_MPS2,
    CLIP_MIN_ACC_MPS2,
    CLIP_MIN_GYR_RADPS,
    CLIP_MIN_REPEATS,
    GRAVITY_MPS2,
    GYR_FULL_SCALES_DPS,
    GYR_PEAK_MAX_RADPS,
    _check_data,
    _full_scale_of,
    check_extremes,
    check_time_base,
    check_time_order,
    data_label,
    find_gaps,
    gap_message,
    peak_hold,
)
from footnav.core.types.sample_checks import check_same_rows
from footnav.core.warning_log import warn

__all__ = ["CHECK_WINDOW_MAX_S", "CHECK_WINDOW_S", "MAX_GAP_WARNINGS", "TIME_BASE_SAMPLES", "ChunkChecks"]

#: Samples whose median interval decides the time base (a few tenths of a second at usual
#: rates; enough for a median that one lost sample does not move).
TIME_BASE_SAMPLES = 16
#: Seconds of a foot's first data the unit, at-rest and saturation checks run on ...
CHECK_WINDOW_S = 10.0
#: ... extended up to this long (s) while the foot has not yet moved (``ACC_MOVING_FRACTION``):
#: a walk that starts with a long standstill shows its gyroscope's unit only once it walks.
CHECK_WINDOW_MAX_S = 60.0
#: Gap warnings a stream shows one by one; later gaps are only recorded (a flaky link would
#: otherwise print one line per chunk).
MAX_GAP_WARNINGS = 10


@dataclass
class _Pending:
    """What :meth:`ChunkChecks.check` found for a chunk, taken by :meth:`ChunkChecks.accept`."""

    chunk: tuple[NDArray, NDArray, NDArray]  # the chunk as received
    tail: tuple[NDArray, NDArray, NDArray]  # the samples held back after it
    median_dt: float | None
    gaps: list[tuple[int, float]] = field(default_factory=list)
    findings: list[tuple[str, Any, str]] = field(default_factory=list)
    head_done: bool = False


class _ExtremeTally:
    """The largest and smallest value of each axis of one sensor so far, how many samples held
    it and the first of them: :func:`~footnav.core.types.imu_checks.detect_clipping`'s plateau rule,
    kept up chunk by chunk (a saturated ADC repeats its extreme code)."""

    def __init__(self, floor: float, scales: tuple[float, ...], unit_si: float) -> None:
        self.floor, self.scales, self.unit_si = floor, scales, unit_si
        self.value = np.full(6, np.nan)  # max of axes 0-2, then min of axes 0-2 (as -value)
        self.count = np.zeros(6, dtype=np.int64)
        self.first = np.zeros(6, dtype=np.int64)

    def add(self, x: NDArray, offset: int) -> None:
        """Take the samples ``x`` (M, 3), the first being sample ``offset`` of the stream."""
        if len(x) == 0:
            return
        _tally(np.ascontiguousarray(x, dtype=np.float64), self.value, self.count, self.first, int(offset))

    def clipped(self) -> tuple[int, int, float | None] | None:
        """(samples, first index, nominal full scale or None) of the plateaus found, or None."""
        hits = [
            k
            for k in range(6)
            if self.count[k] >= CLIP_MIN_REPEATS
            and (abs(self.value[k]) >= self.floor or _full_scale_of(self.value[k], self.scales, self.unit_si))
        ]
        if not hits:
            return None
        fs = next((f for f in (_full_scale_of(self.value[k], self.scales, self.unit_si) for k in hits) if f), None)
        return int(sum(self.count[k] for k in hits)), int(min(self.first[k] for k in hits)), fs


@njit(cache=True)
def _tally(x, value, count, first, offset):
    # _ExtremeTally.add in one compiled call (a push's chunk per foot and sensor): column k of
    # (x, -x), its largest value (NaN if it holds one, as numpy's max), how many samples hold it
    # and the first of them
    m = x.shape[0]
    for k in range(6):
        c = k % 3
        peak = x[0, c] if k < 3 else -x[0, c]
        for i in range(1, m):
            v = x[i, c] if k < 3 else -x[i, c]
            if np.isnan(peak):
                break
            if np.isnan(v) or v > peak:
                peak = v
        if np.isnan(value[k]) or peak > value[k]:  # a new extreme: count it afresh
            n, at = 0, -1
            for i in range(m):
                v = x[i, c] if k < 3 else -x[i, c]
                if v == peak:
                    n += 1
                    if at < 0:
                        at = i
            value[k], count[k], first[k] = peak, n, offset + max(at, 0)
        elif peak == value[k]:
            for i in range(m):
                v = x[i, c] if k < 3 else -x[i, c]
                if v == peak:
                    count[k] += 1


def _empty() -> tuple[NDArray, NDArray, NDArray]:
    return np.empty(0), np.empty((0, 3)), np.empty((0, 3))


def _join(
    first: tuple[NDArray, NDArray, NDArray], then: tuple[NDArray, NDArray, NDArray]
) -> tuple[NDArray, NDArray, NDArray]:
    if not len(first[0]):  # the common case: nothing held back
        return then
    return tuple(np.concatenate((a, b)) for a, b in zip(first, then))  # type: ignore[return-value]


class ChunkChecks:
    """The input checks of one foot's stream (see the module docstring).

    A chunk whose last samples turn faster than ``GYR_PEAK_MAX_RADPS`` keeps them back (at most
    the peak hold, 2 samples at 100 Hz) until the samples after them say whether they are a held
    run (deg/s read as rad/s) or single samples: the stream gets them with the next chunk or at
    the end, so every chunking gives the offline run's verdict. A walk never turns that fast: its
    samples pass at once.

    Parameters
    ----------
    foot
        ``"left"`` or ``"right"``: named in the warnings when there is no ``source``.
    source
        The file or device the samples come from (named in errors and warnings, as offline), if any.
    units_in
        The units the caller converted from (``{"t": "ms", ...}``), for the unit hints.
    """

    def __init__(self, foot: str, source: str | None = None, units_in: Mapping[str, str] | None = None) -> None:
        self.meta: dict[str, Any] = {"units_in": dict(units_in or {"t": "s", "acc": "m/s^2", "gyr": "rad/s"})}
        # named as offline: by its source (a file per foot); without one, by its foot
        self.meta.update({"source": source} if source is not None else {"foot": foot})
        self.path = source
        #: findings, under the keys the offline run records in the input's meta
        self.records: dict[str, Any] = {}
        self.n = 0  # samples received (checked and taken)
        self.t_last: float | None = None
        self.median_dt: float | None = None
        self.head_done = False
        self._head: list[tuple[NDArray, NDArray, NDArray]] = []  # chunks until the window check ran
        self._tail = _empty()  # received, held back from the stream (see the class docstring)
        self._acc_median: float | None = None  # of the checked window: the accelerometer's unit is settled
        self._window_tried = -np.inf  # time of the newest sample at the last window check tried
        self._gap_warnings = 0
        self._acc_tally = _ExtremeTally(CLIP_MIN_ACC_MPS2, ACC_FULL_SCALES_G, GRAVITY_MPS2)
        self._gyr_tally = _ExtremeTally(CLIP_MIN_GYR_RADPS, GYR_FULL_SCALES_DPS, np.pi / 180.0)

    @property
    def label(self) -> str:
        """How warnings name this foot's data (as offline: its source)."""
        return self.path or data_label(self.meta)

    @property
    def held_back(self) -> int:
        """Samples received but not yet passed on to the stream."""
        return len(self._tail[0])

    def check(self, t: Any, acc: Any, gyr: Any) -> tuple[tuple[NDArray, NDArray, NDArray], _Pending]:
        """Check a chunk before it is taken; returns the samples to pass on now (the chunk, after
        any held back before it, less any held back now) and the findings for :meth:`accept`.

        Raises
        ------
        InvalidInputError
            Naming the field, the source and the first bad sample's index in the foot's stream.
        """
        path, n0 = self.path, self.n
        t = _as_float_array(t, "t", None, path, offset=n0)
        acc = _as_float_array(acc, "acc", 3, path, offset=n0)
        gyr = _as_float_array(gyr, "gyr", 3, path, offset=n0)
        check_same_rows(len(t), {"acc": acc, "gyr": gyr}, path)
        pending = _Pending((t, acc, gyr), self._tail, self.median_dt)
        if len(t) == 0:
            return _empty(), pending
        dt = check_time_order(t, path=path, offset=n0, previous=self.t_last)
        n = n0 + len(t)

        def head() -> list:  # every sample so far, until the window check ran (built when needed)
            return self._head + [(t, acc, gyr)] if not self.head_done else []

        if pending.median_dt is None and n >= TIME_BASE_SAMPLES:
            pending.median_dt, findings, pending.gaps = self._time_base(head())
            pending.findings += findings
        elif pending.median_dt is not None:  # dt[0] ends at sample n0 (it starts at the previous chunk's last)
            pending.gaps = find_gaps(dt, pending.median_dt, n0)
        joined = _join(self._tail, (t, acc, gyr))
        keep = self._extremes(joined, n - len(joined[0]), pending.median_dt, head, final=False)
        pending.tail = tuple(x[keep:] for x in joined)  # type: ignore[assignment]
        t_first = float(self._head[0][0][0]) if self._head else float(t[0])
        if not self.head_done and pending.median_dt is not None and self._window_due(t_first, float(t[-1])):
            pending.head_done, findings = self._window(head(), pending.median_dt, final=False)
            pending.findings += findings
        return tuple(x[:keep] for x in joined), pending  # type: ignore[return-value]

    def _time_base(self, head: list) -> tuple[float, list[tuple[str, Any, str]], list[tuple[int, float]]]:
        """The median interval of the first ``TIME_BASE_SAMPLES`` samples (all, at an earlier end),
        the time base's findings, and the gaps of every interval so far."""
        t = np.concatenate([h[0] for h in head])
        median_dt = float(np.median(np.diff(t[:TIME_BASE_SAMPLES])))
        return median_dt, check_time_base(median_dt, self.meta), find_gaps(np.diff(t), median_dt, 1)

    def _extremes(self, joined: tuple, offset: int, median_dt: float | None, head: Any, final: bool) -> int:
        """Check the samples not yet passed on for extremes; returns how many can pass on now.
        ``head()`` gives every sample received so far until the window check ran."""
        _, acc, gyr = joined
        gyr_norm = row_norms(gyr)
        hold = 3 if median_dt is None else peak_hold(1.0 / median_dt)
        keep = len(gyr_norm)
        if not final and gyr_norm[-1] > GYR_PEAK_MAX_RADPS:  # never in a walk: the trailing fast run
            slow = np.flatnonzero(gyr_norm <= GYR_PEAK_MAX_RADPS)
            run = len(gyr_norm) - (int(slow[-1]) + 1 if len(slow) else 0)
            keep = len(gyr_norm) if run >= hold else len(gyr_norm) - run
        acc_median = self._acc_median
        if acc_median is None and len(acc) and row_norms(acc).max() > ACC_MAX_MPS2:
            # before the window check settled the unit: the median of everything received so far
            received = head()
            acc_median = float(np.median(row_norms(np.concatenate([h[1] for h in received]) if received else acc)))
        check_extremes(
            acc, gyr, path=self.path, offset=offset, hold=hold, settled=keep, acc_median=acc_median, gyr_norm=gyr_norm
        )
        return keep

    def accept(self, pending: _Pending) -> None:
        """Take a checked chunk: its findings warned and recorded."""
        t, acc, gyr = pending.chunk
        self._tail = pending.tail
        if len(t) == 0:
            return
        self._acc_tally.add(acc, self.n)
        self._gyr_tally.add(gyr, self.n)
        self.n += len(t)
        self.t_last, self.median_dt = float(t[-1]), pending.median_dt
        if not self.head_done:
            self._head.append((t, acc, gyr))
        self._take(pending.findings, pending.gaps)
        if pending.head_done:
            self.head_done = True
            self._acc_median = float(np.median(row_norms(np.concatenate([h[1] for h in self._head]))))
            self._head = []
        if self.head_done and "clipped" not in self.records:  # the window check covered the head
            self._take(self._clipping(), [])

    def _clipping(self) -> list[tuple[str, Any, str]]:
        """Saturation found by the tallies, as the offline check words and records it."""
        acc, gyr = self._acc_tally.clipped(), self._gyr_tally.clipped()
        if acc is None and gyr is None:
            return []
        parts = []
        record: dict[str, Any] = {
            "acc": 0,
            "first_index": None,
            "gyr": 0,
            "gyr_first_index": None,
            "acc_full_scale": None,
            "gyr_full_scale": None,
            "online": True,
        }
        if acc is not None:
            record.update(acc=acc[0], first_index=acc[1], acc_full_scale=f"+-{acc[2]:g} g" if acc[2] else None)
            fs = f", full scale {record['acc_full_scale']}" if acc[2] else ""
            parts.append(f"{acc[0]} accelerometer sample(s) (first at index {acc[1]}{fs})")
        if gyr is not None:
            record.update(gyr=gyr[0], gyr_first_index=gyr[1], gyr_full_scale=f"+-{gyr[2]:g} deg/s" if gyr[2] else None)
            fs = f", full scale {record['gyr_full_scale']}" if gyr[2] else ""
            parts.append(f"{gyr[0]} gyroscope sample(s) (first at index {gyr[1]}{fs})")
        message = (
            f"{self.label}: {' and '.join(parts)} at the sensor's full scale so far: the true value is unknown "
            "there (clipping, saturation); recorded in meta['clipped']"
        )
        return [("clipped", record, message)]

    def finish(self) -> tuple[NDArray, NDArray, NDArray]:
        """At the stream's end: the checks still waiting for data, on what arrived; returns the
        samples held back, to pass on before the stream ends.

        Raises
        ------
        InvalidInputError
            As :meth:`check`, for what only the end decides.
        """
        if self.n < 2:
            return self._tail
        findings: list[tuple[str, Any, str]] = []
        gaps: list[tuple[int, float]] = []
        if self.median_dt is None:
            self.median_dt, findings, gaps = self._time_base(self._head)
        self._extremes(self._tail, self.n - self.held_back, self.median_dt, lambda: self._head, final=True)
        if not self.head_done:
            findings += self._window(self._head, self.median_dt, final=True)[1]
            self.head_done, self._head = True, []
        self._take(findings, gaps)
        tail, self._tail = self._tail, _empty()
        return tail

    def finish_whole(self, imu: Any) -> None:
        """At the end of a stream that kept every sample: the unit, at-rest and saturation checks
        on the whole recording, as offline (findings not yet recorded are warned and recorded)."""
        findings = _check_data(imu.t, imu.acc, imu.gyr, self.meta, median_dt=self.median_dt, time_base=False)
        if "clipped" in self.records:  # warned during the stream; the whole recording's count is the record
            self.records.update((key, record) for key, record, _ in findings if key == "clipped")
        self._take([f for f in findings if f[0] not in self.records], [])

    def _window_due(self, t_first: float, t_now: float) -> bool:
        """Whether to try the window check now: once ``CHECK_WINDOW_S`` are in, then at most once per
        second of data while the foot stands (each try reads the whole window)."""
        if t_now - t_first < CHECK_WINDOW_S or t_now - self._window_tried < 1.0:
            return False
        self._window_tried = t_now
        return True

    def _window(self, head: list, median_dt: float, final: bool) -> tuple[bool, list[tuple[str, Any, str]]]:
        """The unit, at-rest and saturation checks on the first seconds, once they are in."""
        t = np.concatenate([h[0] for h in head])
        span = t[-1] - t[0]
        if not final and span < CHECK_WINDOW_S:
            return False, []
        acc = np.concatenate([h[1] for h in head])
        if not final and span < CHECK_WINDOW_MAX_S:
            norm = row_norms(acc)
            moving = int(np.count_nonzero(np.abs(norm - np.median(norm)) > ACC_MOVING_MPS2))
            if moving < max(10, 0.2 / median_dt) or moving < ACC_MOVING_FRACTION * len(norm):
                return False, []  # still standing: the gyroscope's unit cannot be judged yet
        gyr = np.concatenate([h[2] for h in head])
        return True, _check_data(t, acc, gyr, self.meta, median_dt=median_dt, time_base=False)

    def _take(self, findings: list[tuple[str, Any, str]], gaps: list[tuple[int, float]]) -> None:
        for key, record, message in findings:
            self.records[key] = record
            warn(message, DataQualityWarning, stacklevel=4)
        if gaps:
            self.records.setdefault("gaps", []).extend(gaps)
            if self._gap_warnings < MAX_GAP_WARNINGS:
                self._gap_warnings += 1
                more = (
                    "" if self._gap_warnings < MAX_GAP_WARNINGS else " (later gaps are recorded there without a word)"
                )
                warn(gap_message(self.label, gaps, self.median_dt) + more, DataQualityWarning, stacklevel=4)
