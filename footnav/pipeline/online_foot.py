"""One foot of an online stream (:mod:`footnav.pipeline.online`): detection on a short window,
the forward filter in fixed-size segments continued from step-end checkpoints, step-wise
smoothing, footprints and the frame's heading.

Global sample indices count the foot's samples since the stream began; the filter segment's
local index ``k`` is global ``seg0 + k``. What the stream guarantees (the offline causal run,
bounded memory, the latency) is explained in :mod:`footnav.pipeline.online`.

A segment is the estimator's online filter (:class:`footnav.core.online_contract.OnlineFilter`, e.g. the
EKF's) with room for the samples to come (``capacity``), fed the final samples with ``extend``
and started from a step-end checkpoint of the previous segment with ``rebase``: the stream reads
no filter's internals. What a push takes and returns is in :mod:`footnav.pipeline.online_io`.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.online_contract import OnlineFilter
from footnav.core.types import FootTrajectory, ImuData, StanceResult, stance_intervals
from footnav.core.warning_log import recording
from footnav.nav.floors import stance_swing_rises, swing_rises
from footnav.nav.heading import rotate_about_z
from footnav.nav.initial_alignment import bridged_gaps
from footnav.pipeline.online_checks import ChunkChecks
from footnav.pipeline.online_io import ClosedStep, FootUpdate, ForwardEstimate, as_chunk, empty_update
from footnav.pipeline.online_steps import StepTracker

__all__ = ["SEGMENT_SAMPLES", "ClosedStep", "FootStream", "FootUpdate", "ForwardEstimate", "as_chunk"]

#: Samples a filter segment holds at first (grown when a stance or swing outlasts it).
SEGMENT_SAMPLES = 16384


class _Grow:
    """Growing (N, ...) arrays with a moving start: append at the end, drop from the front, in
    amortised O(1) per sample and memory proportional to what is kept.

    The rows held are ``arrays[off : off + n]``: dropping only moves ``off``, and the rows are
    moved to the front (or the arrays reallocated) only when an append finds no room at the
    end, so a push's drop and append cost no copy of the rows kept.
    """

    def __init__(self, shapes: list[tuple[tuple[int, ...], Any]]) -> None:
        self.arrays = [np.empty((64, *s), dtype=d) for s, d in shapes]
        self.start = 0  # global index of the first row held
        self.n = 0  # rows held
        self.off = 0  # array index of the first row held

    @property
    def end(self) -> int:
        return self.start + self.n

    def append(self, *rows: NDArray) -> None:
        m = len(rows[0])
        off, n = self.off, self.n
        cap = len(self.arrays[0])
        if off + n + m > cap:
            # no room at the end: move the rows to the front, in arrays of twice what is needed
            # when more than half full (or mostly empty: they shrink), so a move is rare
            need = n + m
            size = max(2 * need, 64) if (2 * need > cap or 8 * need < cap) else cap
            if size != cap:
                arrays = [np.empty((size, *a.shape[1:]), a.dtype) for a in self.arrays]
                for dst, src in zip(arrays, self.arrays):
                    dst[:n] = src[off : off + n]
                self.arrays = arrays
            else:
                for a in self.arrays:
                    a[:n] = a[off : off + n]
            self.off = off = 0
        a0 = off + n
        for a, r in zip(self.arrays, rows):
            a[a0 : a0 + m] = r
        self.n = n + m

    def drop_before(self, g: int) -> None:
        """Forget rows before global index ``g`` (the room is reused by a later append)."""
        cut = min(max(g - self.start, 0), self.n)
        self.off += cut
        self.start += cut
        self.n -= cut

    def rows(self, a: int, b: int) -> list[NDArray]:
        """Views of global rows ``a:b``."""
        i = self.off - self.start
        return [x[a + i : b + i] for x in self.arrays]

    def last(self) -> Any:
        """The first array's newest row."""
        return self.arrays[0][self.off + self.n - 1]


# -- one foot -------------------------------------------------------------------------------------


class FootStream:
    """Detection, forward filter with step-wise smoothing, and the final samples of one foot.

    Global sample indices count the foot's samples since the stream began; the filter segment's
    local index ``k`` is global ``seg0 + k``.
    """

    def __init__(self, stream: Any, foot: str, offset_s: float, input_meta: Any = None) -> None:
        self.stream = stream
        self.foot = foot
        self.offset_s = float(offset_s)
        meta = dict(input_meta or {})
        #: the recording's input checks, run on each chunk before the stream takes it
        self.checks = ChunkChecks(foot, meta.get("source"), meta.get("units_in"))
        # input not yet dropped: t, acc, gyr and the final stance decision
        self.input = _Grow([((), np.float64), ((3,), np.float64), ((3,), np.float64), ((), np.bool_)])
        #: the detector's own form for windows (``online_windows``, e.g. adaptive's), parameters
        #: checked once, with the per-sample quantities it sums, kept beside the input; else each
        #: window is an ImuData for its ``detect``
        make = getattr(stream.pipeline.detector, "online_windows", None)
        self.windows = make() if make is not None else None
        self.features = _Grow([((), np.float64)] * self.windows.n_features) if self.windows is not None else None
        #: every sample pushed (``keep=True``): the whole recording's checks at the end, as offline
        self.raw = _Grow([((), np.float64), ((3,), np.float64), ((3,), np.float64)]) if stream.keep else None
        self.n_final = 0  # samples whose stance decision is final
        self.n_fed = 0  # final samples copied into the filter segment
        #: the first sample another reader still needs (a joint filter, :mod:`.online_joint`)
        self.hold: float = math.inf
        self.first_t = math.nan  # the first sample's time, s
        self.rate_hz: float | None = None
        self.lag = 0  # detection latency, samples
        self.block = 0  # decisions made final together (0: all that are old enough), samples
        self.startup = 0  # the first decisions wait for this many samples
        self.margin = 0  # final samples re-detected before the frontier, samples
        self.run_start: int | None = None  # start of the stance run open at the frontier
        self.first_stance_closed = False
        self.filt: OnlineFilter | None = None
        self.seg0 = 0
        self.n_checkpoints = 1  # the segment's checkpoints already read
        self.start_index = 0  # where the filter started (the first stance), global
        self.meta: dict = {}
        # final (smoothed) outputs: t, q, v, p, position covariance (xx, xy, yy, zz), stance, and
        # the swing's own rise at each stance's first update (footnav.nav.floors.swing_rises)
        self.out = _Grow(
            [
                ((), np.float64),
                ((4,), np.float64),
                ((3,), np.float64),
                ((3,), np.float64),
                ((4,), np.float64),
                ((), np.bool_),
                ((), np.float64),
            ]
        )
        self._swing_carry: tuple[float, bool, float] = (math.nan, False, math.nan)
        self.n_out = 0
        self.emitted = 0
        self.t_final = -math.inf
        # footprints and closed steps; the heading of the first step, unless the frame is the sensor's
        heading = stream.pipeline.estimator.heading
        self.steps = StepTracker(foot, None if heading == "first-step" else 0.0)
        #: (global index of the step end, newest received sample's global index when it became
        #: final) of the latest steps: the latency, measured
        self.step_final_at: deque[tuple[int, int]] = deque(maxlen=256)
        self.finished = False
        self._grid = np.empty(0)  # np.arange(n) / rate_hz for the last detection window's n
        self._imu: ImuData | None = None  # the first detection window (see _window_imu)
        self._pos_block: slice | None = None  # the filter's position block (one filter layout per stream)
        self._rot: tuple[float, NDArray] | None = None  # (psi, the 3 x 3 turn by -psi about z)
        #: the fusion's calibration of this foot (its ``foot_calibration``), found at the
        #: filter's start: the accelerometer scale the filters' samples get (detection reads
        #: the samples as given, as offline) and its record
        self.acc_scale: float | None = None
        self.calibration: dict | None = None
        #: record the forward solution at each stance start in ``alone_starts`` (a coupled
        #: fusion that reads each foot alone: ``Fusion.reads_feet_alone``)
        self.record_starts = False
        #: the stance decisions come from both feet together (:mod:`.online_pair`, a detector
        #: that needs both feet): this foot only keeps its samples and filters what is decided
        self.paired = False
        self.alone_starts: list[tuple[float, NDArray, NDArray]] = []
        self._starts_done = 0  # global index: stance starts before it are recorded
        self._last_stance = False

    def closed_until(self) -> float:
        """Every step of this foot that ends before this time (s) has been returned or is held
        with the released ones: the filter's newest sample, or the first step awaiting the heading."""
        if self.filt is None:
            return -math.inf
        t = self.filt.time(0)
        return min(t, self.steps.first_waiting_s - 1e-9)

    @property
    def psi(self) -> float | None:
        """The turn (rad about z) from the filter's frame to the output frame, once known."""
        return self.steps.psi

    @property
    def t_last(self) -> float:
        """Time of the newest sample pushed, s (-inf before any)."""
        return float(self.input.last()) if self.input.n else -math.inf

    # -- input and detection --------------------------------------------------------------------
    def push(self, t: NDArray, acc: NDArray, gyr: NDArray) -> None:
        """Take a chunk of the foot's samples (time s, specific force m/s^2, angular rate rad/s, body) and decide what
        it can."""
        if len(t) == 0:
            return
        if self.offset_s:
            t = t + self.offset_s
        # checked by self.checks (the stream's push): shapes, values, time order across chunks
        if self.input.end == 0:
            self.first_t = float(t[0])
        self.input.append(t, acc, gyr, False)  # the stance decision, once final
        if self.features is not None:
            self.features.append(*self.windows.features(acc, gyr))
        if self.raw is not None:
            self.raw.append(t, acc, gyr)
        self._detect(final=False)
        if not self.paired:  # else the pair's detection filters once it has decided
            self._filter(final=False)

    def _detect(self, final: bool) -> None:
        inp = self.input
        n_in = inp.end
        if n_in < 2:
            if final:
                raise InvalidInputError(f"the {self.foot} foot has {n_in} sample(s); need at least 2", field=self.foot)
            return
        if self.rate_hz is None:
            # the latency in samples needs the rate: wait for a second of data (or the end)
            tt = inp.rows(inp.start, inp.end)[0]
            if self.stream.rate_hz is not None:
                self.rate_hz = float(self.stream.rate_hz)
            elif not final and tt[-1] - tt[0] < 1.0:
                return
            else:
                self.rate_hz = float(1.0 / np.median(np.diff(tt)))
            det = self.stream.pipeline.detector
            block_s = float(getattr(det, "online_block_s", 0.0))
            self.block = max(1, round(block_s * self.rate_hz)) if block_s else 0
            self.startup = round(float(getattr(det, "online_startup_s", 0.0)) * self.rate_hz)
            self.lag = math.ceil((self.stream.latency_s - block_s) * self.rate_hz) + 2
            self.margin = 3 * self.lag + 8
        if self.paired:
            return
        if self.block and not final:
            # in blocks on windows of fixed sample indices (the detector's online_block_s)
            while max(self.n_final + self.block + self.lag, self.startup) <= n_in:
                end = max(self.n_final + self.block + self.lag, self.startup)
                self._detect_window(end, end - self.lag)
            return
        frontier = n_in if final else n_in - self.lag
        if frontier > self.n_final:
            self._detect_window(n_in, frontier)

    def _detect_window(self, end: int, frontier: int) -> None:
        """Detect on the samples up to ``end`` (global) from ``margin`` before the first not yet
        final, and take the decisions up to ``frontier`` as final."""
        inp = self.input
        a = max(self.n_final - self.margin, inp.start)
        t, acc, gyr, _ = inp.rows(a, end)
        # the detector's rate is the median interval's: the stream's rate, not each window's own
        # (jittered sampling gives windows of other lengths), so it sees the samples on a grid
        # at that rate (a windowed detector counts samples; the time stamps give it the rate)
        if len(self._grid) != len(t):  # the window's length changes rarely: its grid is kept
            self._grid = np.arange(len(t)) / self.rate_hz
        if self.windows is not None and self._imu is not None:
            # the detector's windows from the kept per-sample quantities, at the first window's rate
            window = self.windows.mask(acc, gyr, *self.features.rows(a, end), self._imu.rate_hz)
        else:
            t = t[0] + self._grid
            with recording(quiet=True):  # a window's gaps were warned about with the recording
                window = self.stream.pipeline.detector.detect(self._window_imu(t, acc.copy(), gyr.copy())).mask
        self.decide(np.asarray(window, dtype=bool)[self.n_final - a : frontier - a])

    def decide(self, new: NDArray[np.bool_]) -> None:
        """Make the stance decisions ``new`` of the next samples (from the first not yet final) final."""
        a = self.n_final
        self.input.rows(a, a + len(new))[3][:] = new
        self._track_runs(new)
        self.n_final = a + len(new)

    def _window_imu(self, t: NDArray, acc: NDArray, gyr: NDArray) -> ImuData:
        """The detection window as an ImuData (the arrays are the caller's fresh copies).

        The first window goes through ImuData's checks; later ones take its fields with their
        own arrays, unchecked: the checks would find nothing (the stream's ChunkChecks checked the values and
        shapes, ``t`` is a grid: strictly increasing, without gaps) and cost as much as a
        threshold detector's work on a one-second window."""
        if self._imu is None:
            self._imu = ImuData(t=t, acc=acc, gyr=gyr)
            return self._imu
        return self._imu.same_grid(t, acc, gyr)

    def _track_runs(self, new: NDArray[np.bool_]) -> None:
        """Whether the first stance has ended, from the newly final decisions."""
        if self.first_stance_closed:
            return
        if self.run_start is not None and not new[0]:
            self.first_stance_closed = True
            return
        for s, e in stance_intervals(new):
            if e < len(new):
                self.first_stance_closed = True
                return
            self.run_start = self.n_final + int(s) if self.run_start is None else self.run_start

    # -- the filter ---------------------------------------------------------------------------------
    def _filter(self, final: bool) -> None:
        if self.filt is None and not self._start(final):
            return
        stop = self.whole_stances_until(self.n_fed, self.n_final, final)
        if stop - self.seg0 > self.filt.capacity(0):
            self._restart()
        if stop > self.n_fed:
            rows, zupt = self.filter_rows(self.n_fed, stop, first_whole=False)
            self.filt.extend(*rows, **zupt)
            self.n_fed = stop
        self._run(final)
        if self.record_starts:
            self._record_starts()
        self._harvest(final)
        self.input.drop_before(min(self.n_final - self.margin, self.n_fed, self.hold))
        if self.features is not None:
            self.features.drop_before(self.input.start)

    def _run(self, final: bool) -> None:
        """Filter the fed samples: all at the end; else up to the one before the newest final
        sample, whose step end needs the next sample's decision (as in the offline loop)."""
        filt = self.filt
        last = self.n_fed - 1 - self.seg0
        if final:
            filt.run_until()
        elif last - 1 > filt.index(0):
            filt.run_until(float(filt.samples(0).t[last - 1]))

    def whole_stances_until(self, start: int, stop: int, final: bool) -> int:
        """Where the filter may stop taking final samples (global indices ``start`` to ``stop``)
        without splitting a stance: ``stop``, or the start of the stance it would cut (never
        before ``start``), when the estimator's zero-velocity update needs each stance whole
        (``trims_stances``: the update's edges are found on the whole stance). A stance is whole
        once the decision after it is swing, or the stream has ended."""
        if stop <= start or not getattr(self.stream.pipeline.estimator, "trims_stances", False):
            return stop
        if final:  # the stream (or the feet's common span) ends at stop: its last stance is whole there
            return stop
        stance = self.input.rows(start, min(stop + 1, self.n_final))[3]
        last = stop - start - 1
        if not stance[last] or (last + 1 < len(stance) and not stance[last + 1]):
            return stop
        swing = np.flatnonzero(~stance[: last + 1])  # the run cut: after the last swing sample
        return start + (int(swing[-1]) + 1 if len(swing) else 0)

    def filter_rows(self, a: int, b: int, *, first_whole: bool) -> tuple[list[NDArray], dict[str, NDArray]]:
        """The filter's input rows ``(t, acc, gyr, stance)`` of global samples ``a`` to ``b``
        (:meth:`calibrated`) and, where the estimator's update is not the whole stance, its
        ``zupt`` rows (:meth:`footnav.estimators.ekf.EkfEstimator.zupt_rows`; the stances in
        them whole, :meth:`whole_stances_until`), as keyword arguments of ``extend``."""
        rows = self.calibrated(self.input.rows(a, b))
        est = self.stream.pipeline.estimator
        if not getattr(est, "trims_stances", False):
            return rows, {}
        zupt = est.zupt_rows(rows[0], rows[1], rows[3], first_whole=first_whole)
        return rows, ({} if zupt is None else {"zupt": zupt})

    def calibrated(self, rows: list[NDArray]) -> list[NDArray]:
        """Input rows ``(t, acc, gyr, stance)`` as the filters take them: with the fusion's
        accelerometer scale (:attr:`acc_scale`), as its offline ``fuse`` scales the recording."""
        if self.acc_scale is None:
            return rows
        return [rows[0], rows[1] * self.acc_scale, *rows[2:]]

    def _record_starts(self) -> None:
        """The forward solution at the stance starts the filter has passed since the last call
        (the first sample it filtered counts as one when in stance)."""
        filt = self.filt
        lo, k_now = self._starts_done - self.seg0, filt.index(0)
        if k_now < lo:
            return
        fed = filt.samples(0)
        stance = fed.stance[lo : k_now + 1]
        before = np.concatenate(([self._last_stance], stance[:-1]))
        ks = np.flatnonzero(stance & ~before) + lo
        if len(ks):
            # the forward estimate per sample: a coupled fusion's filter has it (JointFilter.outputs)
            q, _, p = cast(Any, filt).outputs(0)[:3]
            self.alone_starts.extend((float(fed.t[k]), p[k].copy(), q[k].copy()) for k in ks)
        self._last_stance = bool(stance[-1])
        self._starts_done = self.seg0 + k_now + 1

    def _start(self, final: bool) -> bool:
        """Align the filter once the first stance is final (``estimator.start``), in a segment;
        the fusion's calibration of the foot first (:meth:`footnav.core.component.Fusion.foot_calibration`)."""
        est = self.stream.pipeline.estimator
        if not self.first_stance_closed and not final:
            return False
        stop = self.whole_stances_until(0, self.n_final, final)
        t, acc, gyr, mask = (x.copy() for x in self.input.rows(0, stop))
        cal = self.stream.pipeline.fusion.foot_calibration(
            ImuData(t=t, acc=acc, gyr=gyr, meta=self.input_meta()), StanceResult(mask=mask), self.foot
        )
        if cal is not None:
            self.acc_scale, self.calibration = float(cal.acc_scale), cal.as_meta(gyro_bias=False)
            acc = acc * self.acc_scale
        # with no stance at all this raises the estimator's own error, as offline
        # the foot's source names what the estimator warns; the gaps it crosses are said at close
        # (bridged_gaps), when all of them are known, as the offline estimate says them once
        first = est.start([ImuData(t=t, acc=acc, gyr=gyr, meta=self.input_meta())], [StanceResult(mask=mask)])
        self.start_index = first.start_index(0)
        self._starts_done = self.start_index
        self.seg0 = 0
        # the aligned state (f^n too, from the first stance's sample): its first checkpoint
        self.filt = first.rebase([0], [max(SEGMENT_SAMPLES, 2 * self.n_final)], at=0, step_smoother=self._smooths)
        self.n_fed = stop
        self.filt.meta = first.meta
        self.meta = dict(first.meta[0])
        self.n_checkpoints = 1
        return True

    @property
    def _smooths(self) -> bool:
        # the whole-walk smoother's samples are given step-wise smoothed as they become final
        return self.stream.pipeline.estimator.smoother != "none"

    def _restart(self) -> None:
        """A new segment from the old one's last checkpoint (a step end, or a full smoother
        buffer: after either the smoother's record is empty), with the state, the outputs and
        the smoother's chaining value there; the final samples after it are filtered again (the
        loop is deterministic: the same numbers). Without any checkpoint the segment grows, from
        its start (its first checkpoint)."""
        old = self.filt
        if len(old.checkpoints) > 1:  # the first is the segment's start
            at = len(old.checkpoints) - 1
            shift = int(old.checkpoints[at].k[0])
            size = max(SEGMENT_SAMPLES, 2 * (self.n_final - self.seg0 - shift))
            new = old.rebase([shift], [size], at=at)  # closes a full buffer's step where it stands
            self._harvest(False, upto=shift)
        else:  # a stance or swing longer than the segment: a longer one, from the same start
            shift, size = 0, 2 * max(old.capacity(0), self.n_final - self.seg0)
            new = old.rebase([0], [size], at=0)
        n = self.n_fed - self.seg0 - shift
        self.filt = new
        self.seg0 += shift
        self.n_checkpoints = 1
        # the fed samples after the checkpoint again (the same numbers: the loop is deterministic)
        if n - 2 > new.index(0):
            new.run_until(float(new.samples(0).t[n - 2]))

    def _harvest(self, final: bool, upto: int | None = None) -> None:
        """Move the samples up to the last closed step (all of them at the end) to the outputs.

        A checkpoint at a step end closes a step; one at a full smoother buffer closes its
        samples once the next sample has cut the buffer (or ``upto``: a restart cuts it)."""
        filt = self.filt
        k_now = filt.index(0)
        cps = filt.checkpoints
        end = None
        i = self.n_checkpoints
        while i < len(cps):
            cp = cps[i]
            k = int(cp.k[0])
            if not (cp.step_end or k < k_now or (upto is not None and k <= upto)):
                break
            if cp.step_end:
                self.step_final_at.append((self.seg0 + k, self.input.end - 1))
            end = k
            i += 1
        self.n_checkpoints = i
        if final:
            filt.close_open_step()
            end = k_now
        if end is None or self.seg0 + end < self.n_out:
            return
        a, b = self.n_out - self.seg0, end + 1
        q, v, p, pcov = filt.final_outputs(0)
        fed = filt.samples(0)
        t, stance = fed.t[a:b], fed.stance[a:b]
        # the swing's own rise at each stance (the floors' stair check), from a filter that gives
        # its forward outputs (the ekf's; the online contract does not ask for them)
        forward = getattr(filt, "outputs", None)
        if forward is None:
            swing = np.full(b - a, np.nan)
        else:
            zupt = getattr(fed, "zupt", fed.stance)
            swing, self._swing_carry = swing_rises(forward(0)[2][a:b, 2], zupt[a:b], self._swing_carry)
        self.out.append(t, q[a:b], v[a:b], p[a:b], pcov[a:b], stance, swing)
        next_stance = False if final else bool(fed.stance[b]) if b < self.n_fed - self.seg0 else True
        self.steps.add(t, p[a:b], stance, next_stance)
        self.n_out = self.seg0 + b
        self.t_final = float(t[-1]) if len(t) else self.t_final
        if final:
            self.steps.finish()

    # -- what a push returns ------------------------------------------------------------------------
    def take(self) -> FootUpdate:
        """The samples that became final since the last call, with the forward estimate now."""
        forward = self.forward()
        if self.psi is None or self.emitted >= self.n_out:
            return empty_update(forward)
        t, q, v, p, pcov, stance, swing = self.out.rows(self.emitted, self.n_out)
        t, q, v, p = t.copy(), q.copy(), v.copy(), p.copy()
        if self.psi:
            # the covariance is turned too (rotate_about_z turns all four), into a scratch copy:
            # a FootUpdate does not carry it
            rotate_about_z(-self.psi, p, v, q, pcov.copy())
        self.emitted = self.n_out
        if not self.stream.keep:
            self.out.drop_before(self.n_out)
        return FootUpdate(t, p, v, q, forward, stance.copy(), swing.copy())

    def forward(self) -> ForwardEstimate | None:
        """The forward filter's state at its newest sample, in the output frame."""
        filt = self.filt
        if filt is None:
            return None
        pos, vel, q = filt.position(0), filt.velocity(0), filt.quaternion(0)
        if self._pos_block is None:
            self._pos_block = filt.block(0, "pos")
        sl = self._pos_block
        cov = filt.covariance[sl, sl]
        if self.psi:
            if self._rot is None or self._rot[0] != self.psi:  # psi is set once: turned with one matrix
                c, s = math.cos(-self.psi), math.sin(-self.psi)
                self._rot = (self.psi, np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]))
            rot = self._rot[1]
            p, v, qq = pos[None], vel[None], q[None]  # the filter's copies, turned in place
            rotate_about_z(-self.psi, p, v, qq, np.zeros((1, 4)))
            pos, vel, q, cov = p[0], v[0], qq[0], rot @ cov @ rot.T
        return ForwardEstimate(filt.time(0), pos, vel, q, cov)

    # -- the end ------------------------------------------------------------------------------------
    def end_input(self) -> None:
        """No more samples: the foot's own end checks and the last detection (a paired foot's
        detection set-up only: the pair decides, :mod:`.online_pair`)."""
        if self.input.end == 0:
            raise InvalidInputError(f"no samples of the {self.foot} foot were pushed", field=self.foot)
        self._detect(final=True)

    def finish(self) -> None:
        """The end: every sample decided (:meth:`end_input`) and filtered."""
        if self.finished:
            return
        self.finished = True
        self.end_input()
        self._filter(final=True)

    def input_meta(self) -> dict[str, Any]:
        """The meta of an ImuData cut from this foot's samples for a component: its source, no gaps
        (they were warned as they arrived, and the estimate's crossing of them is said at close)."""
        return {**self.checks.meta, "gaps": []}

    def bridged_gaps(self) -> list[tuple[int, float]]:
        """The sampling gaps the filter integrated across (after its start), as offline."""
        return bridged_gaps(self.checks.records.get("gaps", ()), self.start_index)

    def whole_input(self) -> ImuData | None:
        """Every sample pushed, as the foot's ImuData (``keep=True``; else None), with its input
        records: for the whole recording's checks at the end."""
        if self.raw is None or self.raw.n < 2:
            return None
        t, acc, gyr = (np.array(x) for x in self.raw.rows(0, self.raw.end))
        with recording(quiet=True):  # its gaps were warned about as they arrived
            return ImuData(t=t, acc=acc, gyr=gyr, meta={**self.checks.meta, **self.checks.records})

    def trajectory(self) -> tuple[FootTrajectory, StanceResult]:
        """The foot's whole result, made as :meth:`EkfEstimator.trajectory` makes it offline."""
        est = self.stream.pipeline.estimator
        t, q, v, p, pcov, mask, swing = (np.array(x) for x in self.out.rows(0, self.n_out))
        runs = stance_intervals(mask)
        stance = StanceResult(
            mask=mask,
            events={"foot_flat": runs[:, 0], "heel_off": runs[:, 1] - 1},
            meta={
                "detector": self.stream.pipeline.detector.describe(),
                "online": True,
                "latency_s": self.stream.latency_s,
            },
        )
        traj = est.package(
            t,
            q,
            v,
            p,
            pcov,
            self.start_index,
            self.meta,
            runs,
            smoothed=est.smoother != "none",
            heading=est.heading == "first-step",
            biases=est.final_biases(self.filt, 0),
        )
        if getattr(self.filt, "outputs", None) is not None:  # what the ekf's trajectory carries offline
            traj = replace(traj, swing_rise_m=stance_swing_rises(swing, runs))
        traj.meta["online"] = True
        return traj, stance
