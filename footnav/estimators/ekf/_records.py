"""The EKF's named types: its noise, its state, a checkpoint, the smoother's record, the loop's scratch.

Everything the forward loop (:mod:`._loop`), the backward pass (:mod:`._backward`), the step-able
filter (:mod:`.filter`) and the smoother (:mod:`.smoother`) hand each other is one of these, with
named fields, so no module reads another's data by position. They are ``NamedTuple`` s where the
compiled loop receives them (numba passes a tuple of arrays as one argument, at no cost, and reads
its fields by name) and dataclasses elsewhere.

Per foot, the error state is ``[dphi, dv, dp]`` (9 states) or ``[dphi, dv, dp, dba, dbg]`` (15);
foot f's block starts at ``f * n_states`` of the joint state, each 3-vector at the offsets below.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import NamedTuple, cast

import numpy as np
from numpy.typing import NDArray

from footnav.estimators.ekf._buffers import staggered

__all__ = [
    "ACC_BIAS",
    "ATT",
    "EV_CALLER_UPDATE",
    "EV_OWN_UPDATE",
    "EV_SAMPLE",
    "GYR_BIAS",
    "POS",
    "RECORD_PLACE",
    "SMOOTHED_PLACE",
    "VEL",
    "CallerUpdate",
    "Checkpoint",
    "EventKind",
    "FilterNoise",
    "FilterState",
    "Outputs",
    "Record",
    "Samples",
    "Smoothed",
    "UpdateLog",
    "Work",
    "empty_log",
    "empty_record",
    "work",
]

#: Offsets of the blocks of one foot's error state.
ATT, VEL, POS, ACC_BIAS, GYR_BIAS = 0, 3, 6, 9, 12


@dataclass(frozen=True)
class FilterNoise:
    """Noise of the filter, SI units; densities are per sqrt(Hz) and scaled with dt.

    Attributes
    ----------
    acc_mps2_sqrthz, gyr_radps_sqrthz
        White-noise densities driving the velocity and the attitude error.
    zupt_std_mps
        Standard deviation of the zero-velocity pseudo-measurement.
    acc_bias_walk_mps3_sqrthz, gyr_bias_walk_radps2_sqrthz
        Bias random walks (15 states only).
    zaru_std_radps
        Standard deviation of the zero-angular-rate update (15 states only); 0: none.
    """

    acc_mps2_sqrthz: float
    gyr_radps_sqrthz: float
    zupt_std_mps: float
    acc_bias_walk_mps3_sqrthz: float = 0.0
    gyr_bias_walk_radps2_sqrthz: float = 0.0
    zaru_std_radps: float = 0.0  # 0: no zero-angular-rate update

    def q_diag(self, n: int) -> NDArray[np.float64]:
        """Diagonal of Q / dt for one foot's n states."""
        q = np.zeros(n)
        q[ATT : ATT + 3] = self.gyr_radps_sqrthz**2
        q[VEL : VEL + 3] = self.acc_mps2_sqrthz**2
        if n == 15:
            q[ACC_BIAS : ACC_BIAS + 3] = self.acc_bias_walk_mps3_sqrthz**2
            q[GYR_BIAS : GYR_BIAS + 3] = self.gyr_bias_walk_radps2_sqrthz**2
        return q


class FilterState(NamedTuple):
    """The nominal state of every foot and the joint error covariance at one instant (nav frame, SI).

    Attributes
    ----------
    q
        (feet, 4) attitude quaternions [w, x, y, z], body to nav.
    v, p
        (feet, 3) velocity (m/s) and position (m).
    ba, bg
        (feet, 3) accelerometer (m/s^2) and gyroscope (rad/s) bias estimates (zero and fixed
        with 9 states).
    f_n
        (feet, 3) specific force in nav at each foot's current sample: the next transition's F
        takes it from the start of its interval.
    cov
        (N, N) joint error covariance, N = feet x states per foot.
    """

    q: NDArray[np.float64]
    v: NDArray[np.float64]
    p: NDArray[np.float64]
    ba: NDArray[np.float64]
    bg: NDArray[np.float64]
    f_n: NDArray[np.float64]
    cov: NDArray[np.float64]

    def copy(self) -> FilterState:
        """A copy whose arrays share nothing with this one."""
        return FilterState(*(np.array(x) for x in self))


class CallerUpdate(NamedTuple):
    """A caller's measurement update (:meth:`InsFilter.update`), as the smoother undoes it.

    Attributes
    ----------
    h
        (m, N) H over the joint error state.
    gain
        (N, m) K = P H' S^-1.
    sy
        (m,) S^-1 y.
    y
        (m,) the innovation y = h(x^) - z.
    """

    h: NDArray[np.float64]
    gain: NDArray[np.float64]
    sy: NDArray[np.float64]
    y: NDArray[np.float64]


@dataclass
class Checkpoint:
    """Filter state after every update at one instant: where a replay or the smoother restarts the run.

    Attributes
    ----------
    n_events
        Events (samples and caller updates) processed before this checkpoint, over all feet.
    k
        (feet,) each foot's last processed sample, an index of the filter's concatenated samples.
    state
        The :class:`FilterState` there.
    step_end
        A foot's stance ended here (with ``InsFilter.step_stops``).
    n_log
        Entries of the filter's :class:`UpdateLog` made before this checkpoint (a replay of the
        segment after it applies the entries from there on).
    updates
        Measurement updates the caller applied at this instant after the per-sample ones, in
        order: what the smoother needs to undo them backwards.
    """

    n_events: int
    k: NDArray[np.int64]
    state: FilterState
    step_end: bool
    updates: list[CallerUpdate] = field(default_factory=list)
    n_log: int = 0

    @classmethod
    def pending(cls, n_events: int, k: NDArray[np.int64], *, step_end: bool, n_log: int) -> Checkpoint:
        """A checkpoint whose ``state`` the caller's update sets right after (None until then)."""
        return cls(n_events, k, cast(FilterState, None), step_end=step_end, n_log=n_log)


class Samples(NamedTuple):
    """Input samples: time (s), specific force (m/s^2), angular rate (rad/s), stance mask (the
    detector's: a stance's end is a step) and the samples that get a zero-velocity update (the
    stance, or its settled part: :meth:`footnav.estimators.ekf.EkfEstimator.zupt_rows`); rows of
    one foot, or of all feet concatenated (the loop's view)."""

    t: NDArray[np.float64]
    acc: NDArray[np.float64]
    gyr: NDArray[np.float64]
    stance: NDArray[np.bool_]
    zupt: NDArray[np.bool_]


class Outputs(NamedTuple):
    """The forward filter's per-sample results: attitude (M, 4), velocity (M, 3), position (M, 3)
    and the position covariance's xx, xy, yy, zz (M, 4), nav frame, SI."""

    q: NDArray[np.float64]
    v: NDArray[np.float64]
    p: NDArray[np.float64]
    pcov: NDArray[np.float64]


class Smoothed(NamedTuple):
    """Smoothed attitude (M, 4), velocity (M, 3) and position (M, 3) of the concatenated samples
    of all feet, nav frame, SI."""

    q: NDArray[np.float64]
    v: NDArray[np.float64]
    p: NDArray[np.float64]


class EventKind(IntEnum):
    """What an event of a :class:`Record` is (its ``kind``)."""

    #: A sample: its transition, then its own updates (the ZUPT, and the ZARU after it).
    SAMPLE = 0
    #: The loop's own position update between samples (a range projection, :class:`UpdateLog`):
    #: one update of a 3-block, no sample, no transition.
    OWN_UPDATE = 1
    #: A caller's update between samples (:meth:`InsFilter.update`) of ``width`` rows: K in
    #: its first update row, H' in its second; no sample, no transition.
    CALLER_UPDATE = 2


#: :class:`EventKind` as plain ints, which the compiled code compares with.
EV_SAMPLE, EV_OWN_UPDATE, EV_CALLER_UPDATE = (
    int(EventKind.SAMPLE),
    int(EventKind.OWN_UPDATE),
    int(EventKind.CALLER_UPDATE),
)

#: Update rows an event of each kind takes (a sample: one when it has updates, else none).
CALLER_UPDATE_ROWS = 2


class Record(NamedTuple):
    """The event log the backward pass reads (samples, and updates between them), filled by
    the compiled loop and by the caller's updates: never the covariance.

    The first seven arrays have a row per event. The last four (``base``, ``gain``, ``sy``,
    ``y``) have rows per event *with updates* (``width`` not 0; a caller's takes two), in the
    events' order: a sample in swing has none, so a walk's record takes about 60 % of the bytes
    of one with a gain per sample, and the whole-walk smoother's budget holds more of the walk
    (:mod:`.smoother`). The backward pass finds an event's rows by counting down from the rows
    used.

    Attributes
    ----------
    foot
        (n,) the event's foot.
    k
        (n,) its sample, an index of the concatenated samples (read for ``EV_SAMPLE`` only).
    fdt
        (n, 3) f^n dt at the start of the interval (samples).
    dt
        (n,) the interval, s (samples).
    c
        (n, 3, 3) C at the start of the interval (samples; bias states only).
    kind
        (n,) an :class:`EventKind`.
    width
        (n,) gain columns its update rows use: a sample's 0, 3 (ZUPT) or 6 (and ZARU), three
        per 3-block update; the loop's own update 3; a caller's m (its rows).
    base
        (rows, 2) first error state of each 3-block update of the row (samples, own updates).
    gain
        (rows, N, cols) K, three columns per 3-block update; a caller's update: K (m columns),
        then H' in its second row (so m up to ``cols`` needs no wider rows).
    sy
        (rows, cols) S^-1 y.
    y
        (rows, cols) the innovations y.
    """

    foot: NDArray[np.int64]
    k: NDArray[np.int64]
    fdt: NDArray[np.float64]
    dt: NDArray[np.float64]
    c: NDArray[np.float64]
    kind: NDArray[np.int32]
    width: NDArray[np.int32]
    base: NDArray[np.int64]
    gain: NDArray[np.float64]
    sy: NDArray[np.float64]
    y: NDArray[np.float64]

    def head(self, n: int, rows: int) -> Record:
        """Views of the first ``n`` events and their first ``rows`` update rows."""
        # _make is Record(*arrays): mypy cannot match a star-unpacked generator to the fields
        return Record._make((*(a[:n] for a in self[:_PER_EVENT]), *(a[:rows] for a in self[_PER_EVENT:])))

    def copy_head(self, n: int, rows: int, *, stagger: bool = False) -> Record:
        """Copies of :meth:`head`, sharing nothing with this record; ``stagger``: in one buffer
        at staggered page offsets (:mod:`._buffers`; worth its up to ten pages for a long
        segment that the backward pass reads, not for a short one)."""
        head = self.head(n, rows)
        if not stagger:
            return Record._make(np.array(a) for a in head)
        copies = staggered([(a.shape, a.dtype) for a in head], first=RECORD_PLACE)
        for dst, src in zip(copies, head):
            dst[...] = src
        return Record(*copies)


#: The :class:`Record`'s arrays with a row per event (the rest have a row per update row).
_PER_EVENT = 7


#: Place of the record's arrays in :func:`footnav.estimators.ekf._buffers.staggered`'s pattern,
#: after the filter's eight per-sample arrays.
RECORD_PLACE = 8
#: Place of the smoothed copies, after the record's eleven arrays.
SMOOTHED_PLACE = RECORD_PLACE + 11


def empty_record(
    big: int, n: int = 0, columns: int = 6, *, rows: int | None = None, zero: bool = True, bias_states: bool = True
) -> Record:
    """Buffers of the compiled loop's :class:`Record` for ``n`` events and ``rows`` update rows
    (default ``n``) of a filter with ``big`` error states and ``columns`` gain columns: 3 per
    update at a sample (3 for a ZUPT, 6 with the ZARU), m for a caller's update of m rows (which
    takes two rows, K and H'). Narrow rows keep the backward pass's reads of K contiguous.
    ``zero=False`` leaves them uninitialised (the loop writes an event before the backward pass
    reads it). ``bias_states=False`` (9 states): no room for C, which only the bias columns of F
    read."""
    i8, f8 = np.int64, np.float64
    cols = max(3, columns)
    r = n if rows is None else int(rows)
    return Record(
        *staggered(
            [
                ((n,), i8),  # foot
                ((n,), i8),  # global sample index
                ((n, 3), f8),  # f^n dt at the start of the interval
                ((n,), f8),  # dt
                ((n if bias_states else 0, 3, 3), f8),  # C at the start of the interval (bias states only)
                ((n,), np.int32),  # kind (EventKind)
                ((n,), np.int32),  # width: gain columns of its update rows
                ((r, 2), i8),  # per update row: first error state of each update's 3-block
                ((r, big, cols), f8),  # K, three columns per update; a caller's: K, then H' in the next row
                ((r, cols), f8),  # S^-1 y (two updates of 3 at a sample, or a caller's)
                ((r, cols), f8),  # y
            ],
            zero=zero,
            first=RECORD_PLACE,
        )
    )


class UpdateLog(NamedTuple):
    """Position updates the compiled loop made itself (a range constraint's projections,
    :meth:`footnav.estimators.ekf.filter.InsFilter.run_range_constrained`), in order: what a
    replay from a checkpoint applies again at the same instants, so that the loop needs no
    checkpoint at each of them. Entry j: after ``event[j]`` samples of the run, foot
    ``foot[j]``'s position measured with innovation ``y[j]`` (m) and variance ``r[j]`` (m^2) per
    axis."""

    event: NDArray[np.int64]
    foot: NDArray[np.int64]
    y: NDArray[np.float64]
    r: NDArray[np.float64]


def empty_log(n: int = 0) -> UpdateLog:
    """An :class:`UpdateLog` with room for ``n`` entries."""
    return UpdateLog(np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64), np.zeros((n, 3)), np.zeros(n))


class Work(NamedTuple):
    """Scratch of the compiled loop, allocated once per filter in Python: an allocation in the
    loop would cost per call, and one with a constant shape a numpy helper compiled per shape."""

    c: NDArray[np.float64]  # (3, 3) C for the bias columns of F
    c_next: NDArray[np.float64]  # (3, 3) the strapdown's rotation matrix
    dq: NDArray[np.float64]  # (4,)
    q_tmp: NDArray[np.float64]  # (4,)
    a_prev: NDArray[np.float64]  # (3,) bias-corrected specific force and angular rate, k-1 and k
    w_prev: NDArray[np.float64]
    a_cur: NDArray[np.float64]
    w_cur: NDArray[np.float64]
    f_prev: NDArray[np.float64]  # (3,) f^n at the start of the interval
    y: NDArray[np.float64]  # (6,) ZUPT and ZARU innovations
    sy: NDArray[np.float64]  # (3,) S^-1 y of the ZUPT
    sy_z: NDArray[np.float64]  # (3,) and of the ZARU
    dx: NDArray[np.float64]  # (N,) correction
    gain: NDArray[np.float64]  # (N, 3) K of the ZUPT
    gain_z: NDArray[np.float64]  # (N, 3) and of the ZARU
    hp: NDArray[np.float64]  # (3, N) H P
    kt: NDArray[np.float64]  # (rows,) the backward pass's S^-1 y - K' mu
    offset: NDArray[np.float64]  # (feet, 3) the step-wise smoother's position chaining
    seen: NDArray[np.float64]  # (feet,)


def work(big: int, n_feet: int, rows: int = 6) -> Work:
    """Scratch for a filter with ``big`` error states over ``n_feet`` feet, caller updates of up
    to ``rows`` rows."""
    z = np.zeros
    return Work(
        z((3, 3)),
        z((3, 3)),
        z(4),
        z(4),
        z(3),
        z(3),
        z(3),
        z(3),
        z(3),
        z(6),
        z(3),
        z(3),
        z(big),
        z((big, 3)),
        z((big, 3)),
        z((3, big)),
        z(max(rows, 6)),
        z((n_feet, 3)),
        z(n_feet),
    )
