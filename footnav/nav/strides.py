"""Stride parameters of one foot: length, duration, cadence, stance and swing time, clearance,
elevation change and turning angle, from its trajectory and its stances.

A stride runs from one mid-stance of a foot to the next mid-stance of the same foot, as gaitmap's
spatial parameters define it ([1]_: ``min_vel`` strides, "the stride length is calculated based on
the pythagoras in the floor plane" between the positions at the ``start`` and the ``end`` of the
stride). Between two mid-stances the foot is at rest at both ends, so the positions there are the
ones a ZUPT filter knows best, and a stride is the whole swing with half a stance on either side.

References
----------
.. [1] A. Küderle et al., "gaitmap -- An open ecosystem for IMU-based human gait analysis and
   algorithm benchmarking", IEEE Open J. Eng. Med. Biol. 5 (2024) 163-172;
   ``gaitmap.parameters.SpatialParameterCalculation`` / ``TemporalParameterCalculation`` (2.6).
.. [2] C. M. Kanzler et al., "Inertial sensor based and shoe size independent gait analysis
   including heel and toe clearance estimation", Proc. IEEE EMBC 2015, 5424-5427.
.. [3] A. Rampp et al., "Inertial sensor-based stride parameter calculation from gait sequences in
   geriatric patients", IEEE Trans. Biomed. Eng. 62 (4) (2015) 1089-1097.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import FootTrajectory, StanceResult, stance_intervals
from footnav.nav import quaternion as quat
from footnav.nav.floors import LEVEL_RISE_MAX_M, floor_changes

__all__ = ["STRIDE_COLUMNS", "STRIDE_DTYPE", "mid_stances", "stride_parameters"]

#: Columns of a stride table, in order, SI units in the names. ``foot`` first, then the five
#: columns ``strides.csv`` promises (``start_s, end_s, length_m, duration_s``), then the rest.
STRIDE_COLUMNS = (
    "foot",
    "start_s",
    "end_s",
    "length_m",
    "duration_s",
    "cadence_spm",
    "stance_s",
    "swing_s",
    "clearance_m",
    "elevation_m",
    "turn_rad",
    "turn_deg",
    "first",
    "last",
    "standstill",
    "kind",
    "level",
    "start_index",
    "end_index",
)

#: numpy dtype of a stride table (the structured-array form of :func:`stride_parameters`).
STRIDE_DTYPE = np.dtype(
    [("foot", "U5")]
    + [(c, np.float64) for c in STRIDE_COLUMNS[1:-7]]
    + [("first", np.bool_), ("last", np.bool_), ("standstill", np.bool_)]
    + [("kind", "U5"), ("level", np.int64), ("start_index", np.int64), ("end_index", np.int64)]
)

#: Steps per stride: a stride of one foot holds one step of each foot, so cadence (steps/min) =
#: 2 x 60 / stride duration (the usual clinical convention for one foot's strides).
STEPS_PER_STRIDE = 2
SECONDS_PER_MINUTE = 60.0

#: A stride is a ``standstill`` one when one of its stances lasts more than this multiple of the
#: foot's median stance (a pause: the walker stood), ...
STANDSTILL_STANCE_FACTOR = 1.5
#: ... or when it lasts more than this multiple of the foot's median stride (a pause mid-stride,
#: or a stance the detector split). Either way its cadence is not the walk's.
STANDSTILL_DURATION_FACTOR = 2.0


def mid_stances(stance: StanceResult | ArrayLike) -> NDArray[np.int64]:
    """Mid-stance sample of each stance phase: the middle sample of each run of stance.

    Parameters
    ----------
    stance
        A :class:`StanceResult` or a stance mask (N,).

    Returns
    -------
    NDArray[np.int64]
        (K,) sample indices, ``(start + stop - 1) // 2`` of each stance interval ``[start, stop)``.

    Notes
    -----
    gaitmap takes the sample of minimum gyroscope energy inside the stance (``min_vel``) [1]_. A
    ZUPT filter holds the foot still over the whole stance, so any sample inside it gives the same
    position within millimetres; the middle one needs no raw signal and splits the stance time
    evenly between the two strides that share it.
    """
    mask = stance.mask if isinstance(stance, StanceResult) else np.asarray(stance, dtype=bool)
    iv = stance_intervals(mask)
    return ((iv[:, 0] + iv[:, 1] - 1) // 2).astype(np.int64)


def _turn(q_start: NDArray[np.float64], q_end: NDArray[np.float64]) -> NDArray[np.float64]:
    """Heading change (rad, wrapped to (-pi, pi]) from ``q_start`` to ``q_end`` (body -> nav).

    The twist about nav z of the relative rotation ``q_end * conj(q_start)``: 2 atan2(q_z, q_w). It
    equals yaw(q_end) - yaw(q_start) when the foot is level at both mid-stances, and unlike the
    Euler yaw it does not depend on how the sensor is mounted on the foot (gaitmap, too, takes
    the rotation about z between the first and last orientation of the stride [1]_).
    """
    rel = quat.multiply(q_end, quat.conjugate(q_start))
    angle = 2.0 * np.arctan2(rel[..., 3], rel[..., 0])
    return -((-angle + np.pi) % (2.0 * np.pi) - np.pi)  # wrap to (-pi, pi]


def _standstill(
    t: NDArray[np.float64],
    mask: NDArray[np.bool_],
    i0: NDArray[np.int64],
    i1: NDArray[np.int64],
    duration: NDArray[np.float64],
) -> NDArray[np.bool_]:
    """Strides holding a pause: a stance longer than 1.5x the median stance, or a stride longer
    than 2x the median stride (:data:`STANDSTILL_STANCE_FACTOR`, :data:`STANDSTILL_DURATION_FACTOR`)."""
    iv = stance_intervals(mask)
    long_duration = duration > STANDSTILL_DURATION_FACTOR * np.median(duration)
    if len(iv) == 0:  # explicit mid-stances on a mask without stances: only the durations say
        return long_duration
    stop = np.minimum(iv[:, 1], len(t) - 1)
    stance_s = t[stop] - t[iv[:, 0]]
    long_stance = stance_s > STANDSTILL_STANCE_FACTOR * np.median(stance_s)
    # the stances touched by each stride: those holding i0 and i1 and any between (explicit mids)
    k0 = np.searchsorted(iv[:, 0], i0, side="right") - 1
    k1 = np.searchsorted(iv[:, 0], i1, side="right") - 1
    cum = np.concatenate(([0], np.cumsum(long_stance)))
    touches_long = cum[np.maximum(k1, 0) + 1] - cum[np.maximum(k0, 0)] > 0
    return touches_long | long_duration


def stride_parameters(
    trajectory: FootTrajectory,
    stance: StanceResult | ArrayLike,
    *,
    foot: str = "left",
    mid_stance: ArrayLike | None = None,
) -> NDArray:
    """Gait parameters of every stride of one foot.

    Parameters
    ----------
    trajectory
        The foot's trajectory (nav frame, z up), N samples.
    stance
        Its stances: a :class:`StanceResult` or a mask (N,), on the trajectory's samples.
    foot
        ``"left"`` or ``"right"``, written into the ``foot`` column.
    mid_stance
        Mid-stance sample indices (K,), one per stance, increasing; default
        :func:`mid_stances` of ``stance``. Pass a detector's or a reference's own (e.g. gaitmap's
        ``min_vel``) to reproduce its stride borders; each must lie in a stance phase.

    Returns
    -------
    NDArray
        Structured array of dtype :data:`STRIDE_DTYPE`, one row per stride (K - 1 rows for K
        stances), columns :data:`STRIDE_COLUMNS`:

        ``start_s``, ``end_s``
            Times of the two mid-stances ``i0``, ``i1`` (s).
        ``length_m``
            ``|p_xy(i1) - p_xy(i0)|``: horizontal displacement between the two mid-stance positions
            (gaitmap's stride length [1]_ [3]_).
        ``duration_s``
            ``end_s - start_s``.
        ``cadence_spm``
            Steps per minute, ``120 / duration_s`` (two steps per stride of one foot).
        ``stance_s``, ``swing_s``
            Swing = from the end of the stance holding ``i0`` to the start of the next stance
            (``t[a1] - t[b0]``, ``b0`` the first swing sample); stance = ``duration_s - swing_s``,
            the second half of the first stance plus the first half of the next (gaitmap: stance
            time = stride time - swing time [1]_). With more than one swing between the two
            mid-stances (a mid-stance passed explicitly) all swing samples count.
        ``clearance_m``
            Maximum height of the trajectory during the stride above the straight line joining
            the two mid-stance heights (on level ground: above the starting stance, gaitmap's
            "max. sensor lift" [1]_ [2]_; the line keeps stairs and slopes from counting as lift).
            It is the sensor's clearance, not the toe's or the heel's.
        ``elevation_m``
            ``z(i1) - z(i0)``.
        ``turn_rad``, ``turn_deg``
            Heading change between the two mid-stances, from the quaternions, wrapped to
            (-pi, pi]; positive to the left (counter-clockwise seen from above); in degrees too,
            for filters such as ``turn_deg.abs() < 20``.
        ``first``, ``last``
            The foot's first (last) stride: it starts (ends) in the stance before (after) the
            walk, usually a standstill, so its duration and cadence are not the walk's.
        ``standstill``
            One of the stride's stances lasts more than :data:`STANDSTILL_STANCE_FACTOR` x the
            foot's median stance, or the stride more than :data:`STANDSTILL_DURATION_FACTOR` x
            the median stride: a pause. Average only strides without ``first``, ``last`` and
            ``standstill`` for steady-state gait.
        ``kind``
            ``"stair"`` when ``|elevation_m|`` is at least the bound of a level stride (the
            trajectory's ``meta["vertical"]["level_rise_max_m"]``, else
            :data:`footnav.nav.floors.LEVEL_RISE_MAX_M`), else ``"level"``.
        ``level``
            Floor index at the stride's end: 0 at the first stride, +-1 per storey climbed or
            descended (:func:`footnav.nav.floors.floor_changes`).
        ``start_index``, ``end_index``
            ``i0``, ``i1`` (samples of the trajectory).

    Raises
    ------
    InvalidInputError
        The stance mask does not have the trajectory's length, or ``mid_stance`` is not
        increasing inside ``[0, N)``.

    Examples
    --------
    >>> res = footnav.make_pipeline().run(left, right)            # doctest: +SKIP
    >>> strides = stride_parameters(res.left, res.stance_left)      # doctest: +SKIP
    >>> strides["length_m"].mean()                                  # doctest: +SKIP
    1.41
    """
    mask = stance.mask if isinstance(stance, StanceResult) else np.asarray(stance, dtype=bool)
    n = len(trajectory.t)
    if mask.shape != (n,):
        raise InvalidInputError(
            f"stance mask has shape {mask.shape}, the trajectory {n} samples; pass the stance of this foot",
            field="stance",
        )
    if mid_stance is None:
        mids = mid_stances(mask)
    else:
        mids = np.asarray(mid_stance, dtype=np.int64).reshape(-1)
        if len(mids) and (mids.min() < 0 or mids.max() >= n or np.any(np.diff(mids) <= 0)):
            raise InvalidInputError(
                f"mid_stance must be increasing sample indices in [0, {n}), got {mids.min()}..{mids.max()}",
                field="mid_stance",
            )
    out = np.zeros(max(len(mids) - 1, 0), dtype=STRIDE_DTYPE)
    if len(out) == 0:
        return out
    t, pos = trajectory.t, trajectory.position
    i0, i1 = mids[:-1], mids[1:]
    out["foot"] = foot
    out["start_index"], out["end_index"] = i0, i1
    out["start_s"], out["end_s"] = t[i0], t[i1]
    out["duration_s"] = t[i1] - t[i0]
    out["length_m"] = np.linalg.norm(pos[i1, :2] - pos[i0, :2], axis=1)
    out["cadence_spm"] = STEPS_PER_STRIDE * SECONDS_PER_MINUTE / out["duration_s"]
    out["elevation_m"] = pos[i1, 2] - pos[i0, 2]
    out["turn_rad"] = _turn(trajectory.quaternion[i0], trajectory.quaternion[i1])
    out["turn_deg"] = np.degrees(out["turn_rad"])
    out["first"][0] = out["last"][-1] = True
    out["standstill"] = _standstill(t, mask, i0, i1, out["duration_s"])
    bound = trajectory.meta.get("vertical", {}).get("level_rise_max_m", LEVEL_RISE_MAX_M)
    stair = np.abs(out["elevation_m"]) >= bound
    out["kind"] = np.where(stair, "stair", "level")
    out["level"] = floor_changes(out["elevation_m"], stair)[0][1:]
    # swing time: the samples off stance between the two mid-stances, each dt long
    dt = np.diff(t, append=t[-1])
    swing_dt = np.where(mask, 0.0, dt)
    cum = np.concatenate(([0.0], np.cumsum(swing_dt)))
    out["swing_s"] = cum[i1] - cum[i0]
    out["stance_s"] = out["duration_s"] - out["swing_s"]
    for k, (a, b) in enumerate(zip(i0, i1)):
        z = pos[a : b + 1, 2]
        frac = (t[a : b + 1] - t[a]) / (t[b] - t[a])
        out["clearance_m"][k] = np.max(z - (z[0] + frac * (z[-1] - z[0])))  # height above the chord
    return out
