"""Checks of a truth before it scores an estimate: its time base, how much of the walk it covers,
its length unit and its handedness (a mirrored plane, a z axis down).

:func:`footnav.evaluate` runs :func:`check_truth` on each foot's truth (with positions) before it
computes any metric. A truth that cannot be what it claims -- positions in mm or cm, times in ms,
no overlap with the recording -- raises :class:`~footnav.core.errors.InvalidInputError` (in a batch:
an :class:`~footnav.analysis.evaluation.EvaluationFailure` with that message, the other recordings
still scored). A suspect one -- covering part of the walk, mirrored, a path length far from the
estimate's -- gives a :class:`~footnav.core.errors.DataQualityWarning` and its record in
``EvaluationReport.checks`` (shown under :meth:`EvaluationReport.to_text`). Every check's figure
is recorded, warning or not.

The comparisons are like with like: the truth's points against the estimate sampled at the
truth's own times (:func:`~footnav.analysis.evaluation.trajectory_at`) over the span both cover,
so a footprint or waypoint truth is compared with the estimate at its footprints or waypoints.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from footnav.analysis.metrics import rigid_align
from footnav.analysis.metrics._alignment import _umeyama
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import FootTrajectory, FootTruth
from footnav.core.warning_log import warn
from footnav.nav.interpolation import interp_columns

__all__ = ["TruthCheck", "check_truth"]

# --- time base -------------------------------------------------------------------------------
#: A truth whose time span is more than this many times the estimate's is an error: it leaves at
#: least 95 % of itself outside the recording. A genuine truth spans the recording or less (the
#: readers cut motion capture to the IMU's clock); ratios near 1e3 / 1e6 / 1e9 are times in ms /
#: us / ns, and a truth 20 times longer than the walk is the wrong truth or one not cut to it.
TIME_SPAN_RATIO_MAX = 20.0
#: Factors by which a time in that unit exceeds the same time in s (named in the error).
TIME_UNITS = {"ms": 1e3, "us": 1e6, "ns": 1e9}
#: A unit is named when the ratio found is within this factor of its scale.
UNIT_MATCH_FACTOR = 3.0

# --- coverage ----------------------------------------------------------------------------------
#: Coverage is the estimate's horizontal distance travelled inside the span the truth covers, as a
#: fraction of its whole distance: standing still before or after the truth starts costs nothing
#: (the metrics lose nothing there), walking outside it does. Below COVERAGE_WARN the metrics
#: describe part of the walk only: a warning. Below COVERAGE_MIN (or with fewer than 2 truth
#: points inside the recording) they describe nothing: an error. 1 % is a sliver that a genuine
#: truth never leaves (a clock offset or a unit error does): 6 s of a 10-minute walk.
COVERAGE_WARN = 0.9
COVERAGE_MIN = 0.01

# --- scale -------------------------------------------------------------------------------------
#: ``ratio`` = the truth's horizontal path through its own points / the estimate's through the
#: same times, both taken at most every PATH_STEP_S. A truth in mm gives ~1000, in cm ~100, in
#: inches ~39. Above SCALE_ERROR_RATIO it is an error when the truth's own speeds confirm it
#: (below): no working estimate is 20 times too short, yet one that hardly moved (all stance)
#: is -- then the truth's speeds are a foot's and only a warning is given. Outside
#: [1 / SCALE_WARN_RATIO, SCALE_WARN_RATIO] (and not an error): a warning, since a bad estimate
#: (missed strides, divergence) or a truth in feet (3.28) can both do that. A small ratio is never
#: an error: a truth in km (0.001) cannot be told from a truth standing still while the estimate
#: drifts. The shared recordings' ratios (80 runs of docs/make_accuracy.py): 0.80-1.16, and 0.30
#: and 3.18 where the walking-tuned "threshold" detector fails (the estimate diverged on a fast
#: trial, stalled on a crawl): warnings that are the estimate's, as the message allows.
SCALE_ERROR_RATIO = 20.0
SCALE_WARN_RATIO = 1.5
#: The paths are measured through points at least this far apart in time (s): a dense truth's
#: jitter adds length with every point (pyshoe's 200 Hz Vicon on a trial moving within 1.3 m:
#: 16.8 m through every point, 5.3 m at 0.2 s, the estimate 4.7 m), while 0.2 s still follows
#: each stride (a swing lasts ~0.4 s). Sparser truths (footprints, waypoints) keep every point.
PATH_STEP_S = 0.2
#: No foot moves faster than this (m/s; a sprinter's swing peaks near 20 m/s): the truth's 99th
#: percentile speed between its points (robust to a few marker glitches) above it confirms a
#: truth not in metres.
MAX_FOOT_SPEED_MPS = 20.0
#: Length units by their factor to metres' numbers (named in the error).
LENGTH_UNITS = {"mm": 1e3, "cm": 1e2, "in": 1 / 0.0254}

# --- handedness --------------------------------------------------------------------------------
#: The truth looks mirrored when the best 2-D fit of the estimate with a reflection (det = -1)
#: leaves less than MIRROR_FIT_RATIO of the residual RMS of the best proper rotation, that
#: proper residual is at least MIRROR_MIN_RESIDUAL of the truth's horizontal extent (RMS distance
#: to its centroid), and the reflection's at most MIRROR_MAX_FIT of it: a mirror image that no
#: rotation aligns leaves errors of the walk's own size, and the reflection then fits; a straight
#: walk, its own mirror image, leaves none and is not flagged, nor is a diverged estimate that
#: neither fits. Measured (the 80 runs of docs/make_accuracy.py on the shared recordings): genuine
#: truths give ratios of 1.10-38.9, or 0.998 where the estimate diverged (32 m RMS, 3.7 times the
#: extent); the same truths with y negated, default pipeline: 0.03-0.66 with reflection residuals
#: of 5-16 % of the extent (gaitmap's out-and-back walk, 0.68 with a proper residual of 4 %, is
#: left to the 3-D check below).
MIRROR_FIT_RATIO = 0.8
MIRROR_MIN_RESIDUAL = 0.05
MIRROR_MAX_FIT = 0.5
#: The 3-D fit (``ate_3d``) turns the estimate's z by more than 90 deg (R[2,2] < 0): it has
#: turned the estimate upside down, the way a planar mirror image is matched by a proper rotation.
#: Genuine shared truths: 0.1-4 deg on walks with turns, up to 79 deg on a nearly straight or
#: small walk (gaitmap's out-and-back, a pyshoe crawl) with a poor estimate: the tilt about the
#: walking direction only the foot's lift constrains. y negated: 124-180 deg.
FLIP_MIN_TILT_DEG = 90.0
#: A truth whose z points down with x, y kept (left-handed, its horizontal plane not mirrored) is
#: told by its height changes: their correlation with the estimate's at the same times, taken
#: HEIGHT_STEP_S apart (the swing's rise and fall; the estimate's slow height drift drops out).
#: Measured on the shared recordings with heights (the 80 runs of docs/make_accuracy.py, every
#: estimator and fusion) and the simulator: 0.62-1.00, so -0.62 to -1.00 with z negated; below
#: HEIGHT_CORR_MIN the heights run opposite.
HEIGHT_STEP_S = 0.05
HEIGHT_CORR_MIN = -0.3


@dataclass(frozen=True)
class TruthCheck:
    """One check of one foot's truth: its figure and its verdict.

    Attributes
    ----------
    recording, pipeline, foot
        Whose truth (``foot`` is ``"left"`` or ``"right"``).
    name
        ``"time_span"`` (truth span / estimate span), ``"coverage"`` (fraction of the estimate's
        distance inside the truth's span), ``"scale"`` (truth path / estimate path),
        ``"mirror_2d"`` (RMS residual of the best reflection / of the best rotation, horizontal)
        ``"tilt_3d"`` (deg by which the 3-D fit of ``ate_3d`` turns the estimate's z) or
        ``"height"`` (correlation of the truth's height changes with the estimate's).
    value
        The figure, in ``unit``.
    unit
        ``""`` for ratios and fractions, ``"deg"``.
    status
        ``"ok"`` or ``"warning"`` (errors are raised, not recorded here).
    message
        What was found (numbers) and, for a warning, what to check or pass.
    """

    recording: str
    pipeline: str
    foot: str
    name: str
    value: float
    unit: str
    status: str
    message: str

    def __str__(self) -> str:
        value = f"{self.value:.4g}" + (f" {self.unit}" if self.unit else "")
        return f"{self.recording} / {self.pipeline} / {self.foot}: {self.name} = {value}: {self.message}"


class _Refused(Exception):
    """A finding that makes the truth unusable; check_truth turns it into InvalidInputError."""

    def __init__(self, message: str, field: str | None = None, index: int | None = None) -> None:
        super().__init__(message)
        self.field, self.index = field, index


@dataclass(frozen=True)
class _Finding:
    """One check's figure: ``found`` says it in words; ``warning`` (or None) what is suspect."""

    name: str
    value: float
    unit: str
    found: str
    warning: str | None = None


def _path_2d(p: NDArray) -> float:
    """Horizontal distance along the points, in their unit."""
    return float(np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1).sum())


def _unit_named(ratio: float, units: dict[str, float]) -> str | None:
    """The unit whose factor is within UNIT_MATCH_FACTOR of ``ratio`` (the nearest), or None."""
    best = min(units, key=lambda u: abs(np.log(ratio / units[u])))
    return best if abs(np.log(ratio / units[best])) <= np.log(UNIT_MATCH_FACTOR) else None


def _fit_rms(est: NDArray, ref: NDArray, *, reflection: bool) -> float:
    """RMS residual (m) of the best rigid fit of ``est`` onto ``ref``, proper or (``reflection``) improper."""
    rot, trans, _ = _umeyama(est, ref, False, reflection=reflection)
    return float(np.sqrt(np.mean(np.sum((est @ rot.T + trans - ref) ** 2, axis=1))))


def _finite(traj: FootTrajectory, truth: FootTruth, foot: str) -> None:
    """Refuse non-finite times or positions (the metrics would refuse them too)."""
    for field, what, values, times in (
        ("estimate", "estimated", traj.position, traj.t),
        (f"truth_{foot}", "truth", truth.position, truth.t),
    ):
        bad = ~np.isfinite(values).all(axis=1) | ~np.isfinite(times)
        if bad.any():
            i = int(np.argmax(bad))
            raise _Refused(
                f"non-finite {what} position or time at t = {float(times[i])!r} s; every value must be finite", field, i
            )


def _time_span(traj: FootTrajectory, truth: FootTruth) -> _Finding:
    """The truth's time span over the estimate's; refused above TIME_SPAN_RATIO_MAX (times in ms?)."""
    t_est0, t_est1 = float(traj.t[0]), float(traj.t[-1])
    span_est = t_est1 - t_est0
    t0, t1 = float(np.min(truth.t)), float(np.max(truth.t))
    ratio = (t1 - t0) / span_est if span_est > 0 else float("inf")
    if ratio > TIME_SPAN_RATIO_MAX:
        unit = _unit_named(ratio, TIME_UNITS)
        what = (
            f"its times look like {unit} (a ratio near {TIME_UNITS[unit]:g}): pass FootTruth.t in s "
            f"(divide by {TIME_UNITS[unit]:g}) on the IMU's clock"
            if unit
            else "pass FootTruth.t in s on the IMU's clock, cut to the recording's span"
        )
        raise _Refused(
            f"spans {t1 - t0:.6g} (t {t0:.6g} to {t1:.6g}), {ratio:.4g} times the recording's "
            f"{span_est:.6g} s (t {t_est0:.6g} to {t_est1:.6g} s); {what}"
        )
    return _Finding(
        "time_span", ratio, "", f"truth spans {t1 - t0:.3f} s, {ratio:.3f} of the recording's {span_est:.3f} s"
    )


def _coverage(traj: FootTrajectory, truth: FootTruth, inside: NDArray[np.bool_]) -> _Finding:
    """The fraction of the estimate's horizontal distance inside the truth's span; refused below
    COVERAGE_MIN or with fewer than 2 truth points in the recording, warned below COVERAGE_WARN."""
    t_est0, t_est1 = float(traj.t[0]), float(traj.t[-1])
    t0, t1 = float(np.min(truth.t)), float(np.max(truth.t))
    lo, hi = max(t_est0, t0), min(t_est1, t1)
    dist_all = _path_2d(traj.position)
    dist_in = 0.0
    if hi > lo:
        within = (traj.t > lo) & (traj.t < hi)
        ends = interp_columns(np.array([lo, hi]), traj.t, traj.position[:, :3])
        dist_in = _path_2d(np.vstack([ends[:1], traj.position[within], ends[1:]]))
    span_est = t_est1 - t_est0
    time_cover = max(0.0, hi - lo) / span_est if span_est > 0 else 0.0
    coverage = dist_in / dist_all if dist_all > 0 else time_cover  # an estimate that never moved: by time
    found = (
        f"the truth (t {t0:.3f} to {t1:.3f} s) covers {max(0.0, hi - lo):.3f} s of the recording's {span_est:.3f} s "
        f"({t_est0:.3f} to {t_est1:.3f} s) and {100 * coverage:.1f} % of the estimate's distance "
        f"({dist_in:.2f} of {dist_all:.2f} m)"
    )
    n_in = int(inside.sum())
    if n_in < 2 or coverage < COVERAGE_MIN:
        raise _Refused(
            f"{found}, with {n_in} truth point(s) inside the recording: nothing to score; give the truth's "
            "times in s on the IMU's clock (FootTruth.t), or the truth of this recording"
        )
    warning = (
        (
            f"{found}: the errors are of that part only; give the truth of the whole walk, or cut the recording "
            "to the truth's span"
        )
        if coverage < COVERAGE_WARN
        else None
    )
    return _Finding("coverage", coverage, "", found, warning)


def _scale(t_in: NDArray, ref: NDArray, est: NDArray) -> _Finding:
    """The truth's horizontal path over the estimate's at the same times (points >= PATH_STEP_S
    apart); refused when above SCALE_ERROR_RATIO at speeds above MAX_FOOT_SPEED_MPS."""
    if np.all(np.diff(t_in) > 0):
        keep = np.unique(np.append(np.searchsorted(t_in, np.arange(t_in[0], t_in[-1], PATH_STEP_S)), len(t_in) - 1))
    else:  # times not increasing: the path through the points as given
        keep = np.arange(len(t_in))
    path_truth, path_est = _path_2d(ref[keep]), _path_2d(est[keep])
    ratio = path_truth / path_est if path_est > 0 else (float("inf") if path_truth > 0 else 1.0)
    dt = np.diff(t_in[keep])
    speeds = np.linalg.norm(np.diff(ref[keep, :2], axis=0), axis=1)[dt > 0] / dt[dt > 0]
    speed = float(np.percentile(speeds, 99)) if len(speeds) else 0.0
    found = (
        f"the truth's path is {path_truth:.4g} (horizontal, through {len(keep)} of its points, >= {PATH_STEP_S:g} s "
        f"apart) against the estimate's {path_est:.4g} m at the same times: ratio {ratio:.4g}, the truth's speed "
        f"(99th percentile) {speed:.4g} per s"
    )
    if ratio > SCALE_ERROR_RATIO and speed > MAX_FOOT_SPEED_MPS:
        unit = _unit_named(ratio, LENGTH_UNITS)
        what = f"it looks like {unit} (a ratio near {LENGTH_UNITS[unit]:.4g})" if unit else "it is not in metres"
        divide = f", divide by {LENGTH_UNITS[unit]:.4g}" if unit else ""
        raise _Refused(
            f"{found}, faster than any foot ({MAX_FOOT_SPEED_MPS:g} m/s): {what}; convert the truth's "
            f"positions to metres (FootTruth.position in m{divide}); footnav's readers convert the units "
            "they know, so a truth built by hand or read by other code is the suspect"
        )
    warning = None
    if ratio > SCALE_WARN_RATIO or ratio < 1.0 / SCALE_WARN_RATIO:
        warning = (
            f"{found}: either the estimate's distance is wrong (missed or false strides, divergence) or the truth "
            "is not in metres (feet: ratio 3.28; km: 0.001); convert FootTruth.position to m if so"
        )
    return _Finding("scale", ratio, "", found, warning)


def _mirror(ref: NDArray, est: NDArray) -> _Finding:
    """The best horizontal fit's RMS residual with a reflection over that with a rotation."""
    rms_rot = _fit_rms(est[:, :2], ref[:, :2], reflection=False)
    rms_ref = _fit_rms(est[:, :2], ref[:, :2], reflection=True)
    extent = float(np.sqrt(np.mean(np.sum((ref[:, :2] - ref[:, :2].mean(axis=0)) ** 2, axis=1))))
    ratio = rms_ref / rms_rot if rms_rot > 0 else 1.0
    found = (
        f"the best horizontal fit leaves {rms_rot:.3f} m RMS with a rotation and {rms_ref:.3f} m with a "
        f"reflection (ratio {ratio:.3f}; the truth's extent {extent:.3f} m)"
    )
    mirrored = ratio < MIRROR_FIT_RATIO and MIRROR_MIN_RESIDUAL * extent < rms_rot and rms_ref < MIRROR_MAX_FIT * extent
    warning = (
        (
            f"{found}: the truth looks mirrored (a left-handed frame, e.g. y flipped, or z down with x, y kept); "
            "negate its y (or turn a z-down frame 180 deg about x) so that it is right-handed and z up"
        )
        if mirrored
        else None
    )
    return _Finding("mirror_2d", ratio, "", found, warning)


def _tilt(ref: NDArray, est: NDArray) -> _Finding:
    """The angle (deg) by which the 3-D fit of ``ate_3d`` turns the estimate's z axis."""
    rot = rigid_align(est, ref, dims=3).rotation
    tilt = float(np.degrees(np.arccos(np.clip(rot[2, 2], -1.0, 1.0))))
    found = f"the 3-D fit of ate_3d turns the estimate's z axis by {tilt:.1f} deg"
    warning = (
        (
            f"{found} (upside down): ate_3d scores an estimate turned over; the truth is mirrored or not z up "
            "(make it right-handed with z up), or the walk too flat and straight to fix the tilt; trust ate_2d"
        )
        if tilt > FLIP_MIN_TILT_DEG
        else None
    )
    return _Finding("tilt_3d", tilt, "deg", found, warning)


def _height(t_in: NDArray, ref: NDArray, est: NDArray) -> _Finding | None:
    """Correlation of the truth's height changes with the estimate's (None without height changes)."""
    keep = (
        np.unique(np.searchsorted(t_in, np.arange(t_in[0], t_in[-1], HEIGHT_STEP_S)))
        if np.all(np.diff(t_in) > 0)
        else np.arange(len(t_in))
    )
    dz_ref, dz_est = np.diff(ref[keep, 2]), np.diff(est[keep, 2])
    dz_ref, dz_est = dz_ref - dz_ref.mean(), dz_est - dz_est.mean()
    norm = float(np.sqrt((dz_ref**2).sum() * (dz_est**2).sum()))
    if len(dz_ref) < 3 or norm == 0.0:
        return None
    corr = float((dz_ref * dz_est).sum() / norm)
    found = (
        f"the truth's height changes correlate {corr:.3f} with the estimate's ({len(dz_ref)} steps of "
        f">= {HEIGHT_STEP_S:g} s)"
    )
    warning = (
        (
            f"{found}: they run opposite, so the truth's z points down; negate its z (a left-handed frame "
            "with x, y kept) or turn a right-handed z-down frame 180 deg about x (y -> -y, z -> -z)"
        )
        if corr < HEIGHT_CORR_MIN
        else None
    )
    return _Finding("height", corr, "", found, warning)


def check_truth(
    traj: FootTrajectory, truth: FootTruth, *, foot: str, recording: str = "", pipeline: str = ""
) -> tuple[TruthCheck, ...]:
    """Check a truth with positions against the estimate it is about to score.

    Run in this order, each on what the previous ones passed: finite values, the time span
    (``time_span``), the coverage of the walk (``coverage``), the length unit (``scale``), the
    handedness (``mirror_2d``, with 3 points or more) and, unless the truth is footprints, the
    tilt of the 3-D fit (``tilt_3d``) and the sign of its heights (``height``, where they vary).
    The module's constants hold the thresholds and why.

    Parameters
    ----------
    traj
        The foot's estimate (times in s, positions in m).
    truth
        The foot's truth, ``len(truth.t) >= 2`` (a truth without positions has nothing to check).
    foot, recording, pipeline
        Names for the messages and the records.

    Returns
    -------
    tuple of TruthCheck
        Every check's figure, in the order run; each ``"warning"`` was also issued as a
        :class:`~footnav.core.errors.DataQualityWarning` through :func:`footnav.warn`.

    Raises
    ------
    InvalidInputError
        Non-finite values; the truth's times span more than ``TIME_SPAN_RATIO_MAX`` times the
        recording (times in ms?); it covers under ``COVERAGE_MIN`` of the walk's distance (or has
        fewer than 2 points in the recording); its positions are not in metres (path ratio above
        ``SCALE_ERROR_RATIO`` and speeds above ``MAX_FOOT_SPEED_MPS``). The message gives the
        figures and the conversion to make; ``field`` is ``truth_<foot>`` (``estimate`` for a
        non-finite estimate) and ``path`` the truth's file when known.
    """
    source = truth.meta.get("source")
    whose = f"the {foot} foot's truth" + (f" of {recording!r}" if recording else "")
    findings: list[_Finding] = []
    try:
        _finite(traj, truth, foot)
        findings.append(_time_span(traj, truth))
        inside = (truth.t >= traj.t[0]) & (truth.t <= traj.t[-1])
        findings.append(_coverage(traj, truth, inside))
        t_in, ref = truth.t[inside], truth.position[inside]
        est = interp_columns(t_in, traj.t, traj.position[:, :3])  # the estimate at the truth's times
        findings.append(_scale(t_in, ref, est))
        if len(t_in) >= 3:
            findings.append(_mirror(ref, est))
        if truth.frame != "footprints":  # footprints have no height, and no ate_3d
            findings.append(_tilt(ref, est))
            if (height := _height(t_in, ref, est)) is not None:
                findings.append(height)
    except _Refused as refused:
        field = refused.field or f"truth_{foot}"
        path = source if isinstance(source, str) and field != "estimate" else None
        raise InvalidInputError(f"{whose}: {refused}", field=field, index=refused.index, path=path) from None
    for f in findings:  # after a refusal the error says it all
        if f.warning:
            warn(f"evaluate: {whose}: {f.warning}", DataQualityWarning, stacklevel=3)
    return tuple(
        TruthCheck(
            recording,
            pipeline,
            foot,
            f.name,
            float(f.value),
            f.unit,
            "warning" if f.warning else "ok",
            f.warning or f.found,
        )
        for f in findings
    )
