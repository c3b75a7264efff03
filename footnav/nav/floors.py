"""Floors: level strides held level, stair strides kept, floors changed counted.

A ZUPT filter does not observe height: each stance starts while the foot still settles, the
filter takes that motion for an error grown over the swing and lifts the footprint by a few
centimetres (docs/height.md), so a flat walk climbs steadily. Stairs and level floors differ by
far more than that: a foot on stairs rises or falls by at least one riser per stride (building
codes: 0.10-0.22 m; on the shared stair recordings 0.15-0.44 m per stride), a foot on a level
floor by its drift (on the shared walks within +-0.075 m for 95 % of strides).

:func:`hold_floors` takes one foot's trajectory and its stances, measures each stride's rise
(stance-to-stance height change) and removes it where it is smaller than ``level_rise_max_m``:
the level stride's stance keeps the height of the stance before it. This is the relative height
pseudo-measurement z_k - z_(k-1) = 0 of a stride classified as level, spread as a smoother spreads
it: the correction of stride k grows linearly in time over its swing and is whole at the stance
(shaping it by the forward filter's growth of height variance instead gave the same figures to
1 mm on every shared recording). A stride rising more keeps its rise. Unlike a height-zero measurement at
every stance (gaitmap's ``level_walking``), stairs stay stairs; but a ramp whose rise per stride
is below the bound is flattened (a 5 % slope at 1.5 m strides: 0.075 m).

:func:`floor_changes` counts floors: a flight is a run of stair strides in one direction (level
strides between them up to :data:`LANDING_STRIDES`, a landing), and a flight whose net rise is
at least :data:`FLOOR_MIN_RISE_M` changes the level by ``max(1, round(rise / STOREY_M))``.

A stride is a stair one only when the strapdown agrees: its own height change over the swing
(:func:`swing_rises`: the forward filter's height just before the stance's first zero-velocity
update, less its height at the previous stance's last one: the integration alone, before the
update shares its velocity residual with position) rises or falls by at least half the bound
(:data:`SWING_SHARE`), in the same direction, once the strapdown's own offset on level strides
is removed (:func:`swing_offsets`: a clipping accelerometer loses height at every stride). Where
the filter lifts a level stride by a false residual at the landing (the foot still moving when
the update starts) the strapdown did not rise and the stride is held; a real stair rises in both
(docs/height.md, section 9). Without the swing's rise (another estimator, a coupled fusion) the
filter's rise decides alone.

The correction of a stride needs only that stride's two stances, so :class:`FloorHolder` makes it
as the samples come, stance by stance (a live stream's samples, :mod:`footnav.pipeline.online`),
and :func:`hold_floors` is the same holder fed a whole trajectory: both give the same numbers.
"""

from __future__ import annotations

from collections import OrderedDict, deque
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import FootTrajectory, FusionResult
from footnav.nav.stride_hold import close_stances, runs_of, swing_rises_into

__all__ = [
    "FLOOR_MIN_RISE_M",
    "LANDING_STRIDES",
    "LEVEL_RISE_MAX_M",
    "STOREY_M",
    "FloorHolder",
    "Floors",
    "floor_changes",
    "hold_floors",
    "hold_result_floors",
    "stair_strides",
    "stance_heights",
    "stance_swing_rises",
    "swing_offsets",
    "swing_rises",
]

#: A stride rising or falling less than this (m) is level (see the module's docstring).
LEVEL_RISE_MAX_M = 0.075
#: A flight of stairs changes the level when its net rise is at least this (m): a storey is
#: 2.0-4.5 m, half a storey (a half-landing's flight, 1.0-1.7 m) does not count.
FLOOR_MIN_RISE_M = 1.8
#: Height of one storey for counting several floors in one flight (m).
STOREY_M = 3.0
#: Level strides a flight may hold between two stair strides (a landing) and stay one flight.
LANDING_STRIDES = 4
#: Level strides before each whose swing rises give the strapdown's offset (median).
SWING_OFFSET_STRIDES = 15
#: The strapdown's resolution per stride, a share of ``level_rise_max_m``: a stair stride's swing
#: must rise at least this much of the bound (its offset removed), and an offset counts from it
#: on. A sound strapdown's level strides scatter by a few cm about zero (on the shared walks their
#: median is within 0.03 m); a flight's first stride can rise less than the bound in it (gaitmap's
#: stairs, left foot: 0.08 m in the filter, 0.07 m in the strapdown).
SWING_SHARE = 0.5


@dataclass(frozen=True, eq=False)
class Floors:
    """One foot's vertical summary (heights in m, the nav frame's z).

    Attributes
    ----------
    rise_m
        (K-1,) rise of each stride, stance to stance, as estimated before any correction.
    stair
        (K-1,) True where the stride is a stair stride (``|rise_m| >= level_rise_max_m``, and
        the swing's own rise agrees where it is known).
    level
        (K,) floor index of each stance: 0 at the start, +1 per floor up, -1 per floor down.
    climb_m, descent_m
        Sum of the stair strides' rises and falls (>= 0 each).
    removed_m
        Sum of the level strides' rises that were removed (the drift held back), signed.
    walked_m
        Horizontal distance from the first stance to the last, summed over strides, m.
    level_rise_max_m
        The bound that classified the strides, m.
    swing_held
        Strides that rose by the bound but were held level because the swing's own rise did not
        (:func:`swing_rises`).
    flights
        One dict per flight: first and last stride, ``rise_m``, ``floors`` (signed).
    """

    rise_m: NDArray[np.float64]
    stair: NDArray[np.bool_]
    level: NDArray[np.int64]
    climb_m: float
    descent_m: float
    removed_m: float
    walked_m: float
    level_rise_max_m: float
    swing_held: int = 0
    flights: list[dict] = field(default_factory=list)

    def to_meta(self) -> dict:
        """The JSON-ready summary for a result's meta."""
        walked_m = self.walked_m
        return {
            "level_rise_max_m": float(self.level_rise_max_m),
            "level_strides": int(np.sum(~self.stair)),
            "stair_strides": int(np.sum(self.stair)),
            "swing_held_strides": int(self.swing_held),
            "removed_m": round(float(self.removed_m), 4),
            "removed_m_per_100m": round(100.0 * float(self.removed_m) / walked_m, 3) if walked_m > 0 else 0.0,
            "climb_m": round(float(self.climb_m), 4),
            "descent_m": round(float(self.descent_m), 4),
            "floors_changed": int(self.level[-1]) if len(self.level) else 0,
            "floors_up": sum(f["floors"] for f in self.flights if f["floors"] > 0),
            "floors_down": -sum(f["floors"] for f in self.flights if f["floors"] < 0),
            "flights": self.flights,
        }


def stance_heights(z: NDArray[np.float64], steps: NDArray[np.int64]) -> NDArray[np.float64]:
    """Height of each stance interval ``steps`` (K, 2, none empty) of ``z``: its median, m
    (sorted within each interval at once: the middle value or the mean of the middle two)."""
    steps = np.asarray(steps, dtype=np.int64).reshape(-1, 2)
    n = steps[:, 1] - steps[:, 0]
    if len(n) == 0:
        return np.zeros(0)
    zs = z[_ranges(steps[:, 0], n)]
    zs = zs[np.lexsort((zs, np.repeat(np.arange(len(n)), n)))]
    first = np.concatenate(([0], np.cumsum(n)[:-1]))
    return 0.5 * (zs[first + (n - 1) // 2] + zs[first + n // 2])


def swing_rises(
    z_forward: NDArray[np.float64], zupt: NDArray[np.bool_], before: tuple[float, bool, float] = (np.nan, False, np.nan)
) -> tuple[NDArray[np.float64], tuple[float, bool, float]]:
    """The strapdown's own rise over each swing, at the first sample of each zero-velocity run.

    Parameters
    ----------
    z_forward
        (N,) the forward filter's height per sample (after that sample's updates), m.
    zupt
        (N,) the samples that got a zero-velocity update.
    before
        What the samples before these left: the height at the last update sample, whether the
        sample before these had an update, and its height (:func:`swing_rises` 's second output);
        by default nothing before.

    Returns
    -------
    rise, carry
        (N,) NaN but at the first update sample of each run after the first: the height just
        before it (the swing's integration, no update yet) minus the height at the previous run's
        last update sample, m; and ``before`` for the samples that follow. The same numbers in
        any chunks.
    """
    z = np.ascontiguousarray(z_forward, dtype=float)
    zupt = np.ascontiguousarray(zupt, dtype=bool)
    out = np.full(len(z), np.nan)
    if len(z) == 0:
        return out, before
    z_last, prev_zupt, prev_z = before
    z_last = swing_rises_into(z, zupt, out, float(z_last), bool(prev_zupt), float(prev_z))
    return out, (float(z_last), bool(zupt[-1]), float(z[-1]))


def stance_swing_rises(rise: NDArray[np.float64], steps: NDArray[np.int64]) -> NDArray[np.float64]:
    """(K,) each stance's swing rise: the first finite value of ``rise`` (N,: :func:`swing_rises`)
    within each stance interval of ``steps`` (K, 2, none empty), NaN where none."""
    steps = np.asarray(steps, dtype=np.int64).reshape(-1, 2)
    n = steps[:, 1] - steps[:, 0]
    if len(n) == 0:
        return np.zeros(0)
    vals = np.asarray(rise, dtype=float)[_ranges(steps[:, 0], n)]
    pos = np.where(np.isfinite(vals), np.arange(len(vals)), len(vals))
    at = np.minimum.reduceat(pos, np.concatenate(([0], np.cumsum(n)[:-1])))
    return np.where(at < len(vals), vals[np.minimum(at, len(vals) - 1)], np.nan)


def stair_strides(
    rise: NDArray[np.float64], swing: NDArray[np.float64], level_rise_max_m: float = LEVEL_RISE_MAX_M
) -> NDArray[np.bool_]:
    """Which strides are stair strides: the filter's ``rise`` (m) at least ``level_rise_max_m``
    either way, and the swing's own rise ``swing`` (m, :func:`swing_rises`, its offset
    :func:`swing_offsets` added) at least :data:`SWING_SHARE` of it the same way, where it is
    known (not NaN). Same shapes in, a bool array out."""
    rise, swing = np.asarray(rise, dtype=float), np.asarray(swing, dtype=float)
    agree = (np.abs(swing) >= SWING_SHARE * level_rise_max_m) & (np.sign(swing) == np.sign(rise))
    return (np.abs(rise) >= level_rise_max_m) & (np.isnan(swing) | agree)


def swing_offsets(
    rise: NDArray[np.float64],
    swing: NDArray[np.float64],
    level_rise_max_m: float = LEVEL_RISE_MAX_M,
    history: deque | None = None,
) -> tuple[NDArray[np.float64], deque]:
    """The strapdown's own offset before each stride, to add to its swing rise: minus the median
    swing rise ``swing`` (m) of the :data:`SWING_OFFSET_STRIDES` latest strides before it whose
    filter ``rise`` (m) is level (under ``level_rise_max_m``), when that median is at least
    :data:`SWING_SHARE` of the bound, else 0 (and 0 with none before); ``history``: those
    earlier swing rises, oldest first (updated and returned).

    On a level stride the true rise is zero, so there the strapdown's swing rise is its own
    error: an accelerometer that clips, or reads off scale, loses (or gains) height at every
    stride alike (the simulator's storey clipped at 3 g: -0.14 m per stride), and the filter's
    update gives it back. A landing that starts the update while the foot still moves lifts the
    filter, not the strapdown, so it is not taken for the strapdown's offset (docs/height.md,
    section 9)."""
    n_win = SWING_OFFSET_STRIDES
    old = np.asarray(history or (), dtype=float)[-n_win:]
    swing = np.asarray(swing, dtype=float)
    kept = (np.abs(np.asarray(rise, dtype=float)) < level_rise_max_m) & np.isfinite(swing)
    values = np.concatenate((np.full(n_win, np.nan), old, swing[kept]))
    # before stride k the window holds the latest n_win values of ``values`` counted so far
    count = len(old) + np.concatenate(([0], np.cumsum(kept)[:-1])).astype(np.int64)
    out = np.zeros(len(swing))
    some = count > 0
    if some.any():
        windows = np.lib.stride_tricks.sliding_window_view(values, n_win)[count[some]]
        m = np.nanmedian(windows, axis=1)
        out[some] = np.where(np.abs(m) >= SWING_SHARE * level_rise_max_m, -m, 0.0)
    return out, deque(values[n_win:][-n_win:].tolist(), maxlen=n_win)


def floor_changes(rise_m: NDArray[np.float64], stair: NDArray[np.bool_]) -> tuple[NDArray[np.int64], list[dict]]:
    """Floor index per stance (K,) and the flights of stairs, from the strides' rises (K-1,)."""
    level = np.zeros(len(rise_m) + 1, dtype=np.int64)
    flights: list[dict] = []
    k = 0
    n = len(rise_m)
    while k < n:
        if not stair[k]:
            k += 1
            continue
        sign, first, last, gap = np.sign(rise_m[k]), k, k, 0
        j = k + 1
        while j < n and gap <= LANDING_STRIDES:
            if stair[j]:
                if np.sign(rise_m[j]) != sign:
                    break
                last, gap = j, 0
            else:
                gap += 1
            j += 1
        rise = float(np.sum(rise_m[first : last + 1] * stair[first : last + 1]))
        floors = int(sign * max(1, round(abs(rise) / STOREY_M))) if abs(rise) >= FLOOR_MIN_RISE_M else 0
        flights.append({"first_stride": first, "last_stride": last, "rise_m": round(rise, 4), "floors": floors})
        level[last + 1 :] += floors
        k = last + 1
    return level, flights


class FloorHolder:
    """Hold level strides level, stance by stance, on samples given in time order.

    :meth:`push` takes a foot's next samples (time s, nav-frame position m and velocity m/s,
    quaternion, stance flags, and where known the swing's own rise, :func:`swing_rises`) and
    returns those it could correct: every sample up to the end of
    the last stance known to have ended (the next sample is a swing one, or ``closed``). The
    others wait for their stride's next stance. :meth:`flush` ends the walk and returns the
    rest. Only heights and vertical velocities change.

    Parameters
    ----------
    level_rise_max_m
        A stride rising or falling less than this is level, m.
    keep_strides
        Keep every stride's rise for :meth:`floors` (memory grows with the walk); False keeps
        the running totals only (an endless stream that keeps no past).
    """

    #: Stances closed at once in one compiled call, at most; more by the vectorised rule (the
    #: same bits, see :meth:`_close_stances`; :func:`hold_floors` takes that rule always).
    compiled_max_stances = 64

    def __init__(self, level_rise_max_m: float = LEVEL_RISE_MAX_M, *, keep_strides: bool = True) -> None:
        self.level_rise_max_m = float(level_rise_max_m)
        self.keep_strides = bool(keep_strides)
        self._rows: list[list[NDArray]] = []  # waiting samples: chunks of (t, p, v, q, stance, swing rise)
        self._prev_h: float | None = None  # height of the last closed stance (as estimated)
        self._prev_end_t = 0.0  # time of its last sample, s
        self._prev_xy: NDArray[np.float64] | None = None  # its footprint in the plane, m
        self._before = 0.0  # correction held at the last closed stance, m
        self.rises: list[float] = []
        self.stairs: list[bool] = []
        self.swing_held = 0
        self._offsets: deque = deque(maxlen=SWING_OFFSET_STRIDES)  # the latest level strides' swing rises
        self.walked_m = 0.0
        #: stance end time (s) -> the correction its samples got (m), in time order, until
        #: :meth:`held_at` has been asked for it or a later one
        self._held_at: OrderedDict[float, float] = OrderedDict()

    def push(
        self, t, position, velocity, quaternion, stance, *, closed: bool = False, swing_rise=None
    ) -> tuple[NDArray, ...]:
        """Add samples; return the corrected ``(t, position, velocity, quaternion, stance)`` of
        those now final (copies). ``closed``: the stance at the end of these samples has ended.
        ``swing_rise``: (N,) the swing's own rise at the first update sample of each stance,
        NaN elsewhere (:func:`swing_rises`); None: not known (the filter's rise decides alone)."""
        if len(t):
            sw = np.full(len(t), np.nan) if swing_rise is None else np.array(swing_rise, float)
            self._rows.append(
                [
                    np.array(t, float),
                    np.array(position, float),
                    np.array(velocity, float),
                    np.array(quaternion, float),
                    np.asarray(stance, bool).copy(),
                    sw,
                ]
            )
        return self._release(closed)

    def flush(self) -> tuple[NDArray, ...]:
        """The walk ended: close its last stance and return every waiting sample."""
        out = self._release(True)
        if self._rows:  # a swing after the last stance keeps the last stance's correction
            t, p, v, q, s, _ = self._joined()
            p[:, 2] += self._before
            self._rows = []
            out = tuple(np.concatenate([a, b]) for a, b in zip(out, (t, p, v, q, s)))
        return out

    def held_at(self, t: float) -> float | None:
        """The correction (m) the samples of the stance that ended at ``t`` (s) got, for a
        footprint made elsewhere; None when no stance ended there or it was asked before. The
        stances before it are forgotten: ask in time order."""
        while self._held_at:
            first, shift = self._held_at.popitem(last=False)
            if first >= t:
                if first > t:  # not this one's: keep it for a later footprint
                    self._held_at[first] = shift
                    self._held_at.move_to_end(first, last=False)
                    return None
                return shift
        return None

    def floors(self) -> Floors:
        """The strides so far: rises, classes, floors and totals (``keep_strides`` only)."""
        if not self.keep_strides:
            raise RuntimeError("FloorHolder(keep_strides=False) keeps no strides to summarise")
        rise = np.asarray(self.rises, dtype=float)
        stair = np.asarray(self.stairs, dtype=bool)
        level, flights = floor_changes(rise, stair)
        return Floors(
            rise_m=rise,
            stair=stair,
            level=level if self._prev_h is not None else np.zeros(0, np.int64),
            climb_m=float(np.sum(np.where(stair & (rise > 0), rise, 0.0))),
            descent_m=float(-np.sum(np.where(stair & (rise < 0), rise, 0.0))),
            removed_m=float(np.sum(np.where(stair, 0.0, rise))),
            walked_m=self.walked_m,
            level_rise_max_m=self.level_rise_max_m,
            swing_held=self.swing_held,
            flights=flights,
        )

    def _joined(self) -> list[NDArray]:
        if len(self._rows) > 1:
            self._rows = [[np.concatenate(c) for c in zip(*self._rows)]]
        return self._rows[0]

    def _release(self, closed: bool) -> tuple[NDArray, ...]:
        empty = (np.empty(0), np.empty((0, 3)), np.empty((0, 3)), np.empty((0, 4)), np.empty(0, bool))
        if not self._rows:
            return empty
        t, p, v, q, s, sw = rows = self._joined()
        runs = runs_of(s)
        if len(runs) and runs[-1, 1] == len(s) and not closed:  # the last stance may go on
            runs = runs[:-1]
        if len(runs) == 0:
            return empty
        self._close_stances(t, p, v, sw, runs)
        done = int(runs[-1, 1])
        out = tuple(x[:done] for x in (t, p, v, q, s))
        self._rows = [[x[done:] for x in rows]] if done < len(t) else []
        return out

    def _close_stances(self, t, p, v, sw, runs: NDArray[np.int64]) -> None:
        """Correct the stances ``runs`` (K, 2) and the swing before each, in place: the whole
        of ``t[:runs[-1, 1]]``. A few stances (a live stream's push) in one compiled call
        (:func:`footnav.nav.stride_hold.close_stances`), where the vectorised rule's numpy calls
        cost 50 times the work; many (a whole walk, :func:`hold_floors`) by that rule, which
        then costs little and spares the offline run the kernel's compilation: the same
        operations, the same bits."""
        if len(runs) > self.compiled_max_stances:
            self._close_vectorised(t, p, v, sw, runs)
            return
        first = self._prev_h is None  # the first stance of the walk: nothing to hold before it
        prev_x, prev_y = (0.0, 0.0) if first else (float(self._prev_xy[0]), float(self._prev_xy[1]))
        rise, stair, held, by_swing, h, end_t, xs, ys, walked, history = close_stances(
            t,
            p,
            v,
            sw,
            np.ascontiguousarray(runs, dtype=np.int64),
            self.level_rise_max_m,
            SWING_SHARE,
            SWING_OFFSET_STRIDES,
            first,
            0.0 if first else self._prev_h,
            self._prev_end_t,
            prev_x,
            prev_y,
            self._before,
            self.walked_m,
            np.array(self._offsets, dtype=float),
        )
        counted = slice(1 if first else 0, None)  # the walk's first stance has no stride
        if self.keep_strides:
            self.rises.extend(rise[counted].tolist())
            self.stairs.extend(stair[counted].tolist())
        self.swing_held += int(np.count_nonzero(by_swing))
        self.walked_m = float(walked)
        self._offsets = deque(history.tolist(), maxlen=SWING_OFFSET_STRIDES)
        self._held_at.update(zip(end_t.tolist(), held.tolist()))
        self._before = float(held[-1])
        self._prev_h, self._prev_end_t, self._prev_xy = float(h[-1]), float(end_t[-1]), np.array([xs[-1], ys[-1]])

    def _close_vectorised(self, t, p, v, sw, runs: NDArray[np.int64]) -> None:
        """:meth:`_close_stances` by numpy calls over all the stances at once."""
        a, b = runs[:, 0], runs[:, 1]
        n = b - a
        h = stance_heights(p[:, 2], runs)
        idx = _ranges(a, n)
        first = np.concatenate(([0], np.cumsum(n)[:-1]))
        xy = np.add.reduceat(p[idx, :2], first, axis=0) / n[:, None]
        end_t = t[b - 1]
        if self._prev_h is None:  # the first stance of the walk: nothing to hold before it
            prev_h = np.concatenate(([h[0]], h[:-1]))
            prev_xy = np.concatenate((xy[:1], xy[:-1]))
            prev_end = np.concatenate(([t[0]], end_t[:-1]))
            counted = np.arange(len(runs)) > 0
        else:
            prev_h = np.concatenate(([self._prev_h], h[:-1]))
            prev_xy = np.concatenate((self._prev_xy[None], xy[:-1]))
            prev_end = np.concatenate(([self._prev_end_t], end_t[:-1]))
            counted = np.ones(len(runs), bool)
        rise = h - prev_h
        swing = np.where(counted, stance_swing_rises(sw, runs), np.nan)  # the walk's first stance has no stride
        offset, self._offsets = swing_offsets(rise, swing, self.level_rise_max_m, self._offsets)
        stair = stair_strides(rise, swing + offset, self.level_rise_max_m)
        held_by_swing = (np.abs(rise) >= self.level_rise_max_m) & ~stair
        level = counted & ~stair
        c = np.where(level, -rise, 0.0)
        # at each stance; summed from the last one held, in order, so that samples given in any
        # chunks give the same bits as the whole walk
        held = np.cumsum(np.concatenate(([self._before], c)))[1:]
        before = np.concatenate(([self._before], held[:-1]))  # at the stance before each
        # the swing before stance k: from the last sample of stance k-1 to the first of stance k
        lo = np.concatenate(([0], b[:-1]))
        m = a - lo
        sw = _ranges(lo, m)
        k = np.repeat(np.arange(len(runs)), m)
        span = t[a] - prev_end
        span = np.where(span > 0, span, 1.0)  # only the walk's first stance can start at its first sample
        p[sw, 2] += before[k] + c[k] * (t[sw] - prev_end[k]) / span[k]
        v[sw, 2] += (c / span)[k]
        p[idx, 2] += np.repeat(held, n)
        if self.keep_strides:
            self.rises.extend(rise[counted].tolist())
            self.stairs.extend((~level[counted]).tolist())
        self.swing_held += int(np.sum(held_by_swing & counted))
        steps_m = np.linalg.norm(xy - prev_xy, axis=1)[counted]
        self.walked_m = float(np.cumsum(np.concatenate(([self.walked_m], steps_m)))[-1])
        self._held_at.update(zip(end_t.tolist(), held.tolist()))
        self._before = float(held[-1])
        self._prev_h, self._prev_end_t, self._prev_xy = float(h[-1]), float(end_t[-1]), xy[-1].copy()


def _ranges(starts: NDArray[np.int64], lengths: NDArray[np.int64]) -> NDArray[np.int64]:
    """The indices ``starts[i] .. starts[i] + lengths[i] - 1`` of every i, concatenated."""
    total = int(lengths.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    offsets = np.repeat(starts - np.concatenate(([0], np.cumsum(lengths)[:-1])), lengths)
    return np.arange(total) + offsets


def hold_floors(traj: FootTrajectory, *, level_rise_max_m: float = LEVEL_RISE_MAX_M) -> FootTrajectory:
    """``traj`` with its level strides held level (a new trajectory; ``meta["vertical"]`` holds
    the :class:`Floors` summary).

    Parameters
    ----------
    traj
        A foot's trajectory (nav frame, z up) with its stance intervals ``steps`` (and where
        known the swing's own rise before each, ``swing_rise_m``).
    level_rise_max_m
        A stride rising or falling less than this is level, m.
    """
    n = len(traj.t)
    mask = np.zeros(n, dtype=bool)
    for a, b in np.asarray(traj.steps, dtype=np.int64).reshape(-1, 2):
        mask[a:b] = True
    swing = None
    if traj.swing_rise_m is not None and len(traj.steps):
        swing = np.full(n, np.nan)
        swing[traj.steps[:, 0]] = traj.swing_rise_m
    holder = FloorHolder(level_rise_max_m)
    holder.compiled_max_stances = 0  # a whole walk: numpy's calls cost little, and need no compilation
    first = holder.push(traj.t, traj.position, traj.velocity, traj.quaternion, mask, swing_rise=swing)
    _, pos, vel, _, _ = (np.concatenate([a, b]) for a, b in zip(first, holder.flush()))
    meta = {**traj.meta, "vertical": {"model": "floors", **holder.floors().to_meta()}}
    return replace(traj, position=pos, velocity=vel, meta=meta)


def hold_result_floors(result: FusionResult, *, level_rise_max_m: float = LEVEL_RISE_MAX_M) -> FusionResult:
    """:func:`hold_floors` on each foot of a fusion's result; the pedestrian path's height moves
    by the mean of the feet's corrections at its times."""
    feet = [
        None if tr is None else hold_floors(tr, level_rise_max_m=level_rise_max_m) for tr in (result.left, result.right)
    ]
    shift = [
        np.interp(result.path.t, new.t, new.position[:, 2] - old.position[:, 2])
        for new, old in zip(feet, (result.left, result.right))
        if new is not None and len(new.t)
    ]
    pos = np.array(result.path.position)
    if shift:
        pos[:, 2] += np.mean(shift, axis=0)
    path = replace(result.path, position=pos)
    return replace(result, left=feet[0], right=feet[1], path=path)
