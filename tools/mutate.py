"""Mutation run over footnav's numerical modules: apply realistic bugs one at a time, run the tests.

Usage::

    python tools/mutate.py                 # every mutant, 2 at a time (about 30-40 minutes)
    python tools/mutate.py --list          # the mutants, one line each
    python tools/mutate.py --check         # every snippet is found exactly where it should be
    python tools/mutate.py --only ins-zupt-sign range-mirror -j 1
    python tools/mutate.py --overlay tests/pipeline/test_new.py   # add an uncommitted file to each copy
    python tools/mutate.py --group issue37 # the third round's mutants (issue 37)

Each mutant is a small edit of one file (an exact snippet and its replacement; a few mutants
change several snippets that must change together, such as every place one constant is
written). The kinds are those a refactor or a speed-up lets slip: a flipped sign, an index or a
window one off, a wrong constant, a dropped ``dt``, a transposed matrix, swapped arguments, ``<``
for ``<=`` at a boundary, a missing term.

A mutant is applied to a private copy of the repository (``git archive HEAD``, plus the
``--overlay`` paths from the working tree), never to the checkout itself, and that copy's tests
run with their own numba cache (``NUMBA_CACHE_DIR`` inside the copy, so nothing compiled from a
mutant is ever loaded elsewhere). The tests are the subset that covers the module
(``pytest -x -q -p no:cacheprovider <paths>``); the mutant is *killed* when they fail, *timeout*
when they run longer than ``--timeout`` (also a detection: the code hangs), and *survived* when
they pass. Before the mutants, the unmutated copy must pass every subset (the baseline).

The score is (killed + timeout) / mutants. ``--json`` writes every outcome.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# -- test subsets, per module ---------------------------------------------------------------------

QUAT = [
    "tests/nav/test_quaternion.py",
    "tests/nav/test_mechanization.py",
    "tests/estimators/test_ins_filter.py",
    "tests/estimators/test_ekf.py",
]
FILTER = [
    "tests/estimators/test_ins_filter.py",
    "tests/nav/test_mechanization.py",
    "tests/nav/test_quaternion.py",
    "tests/estimators/test_smoother.py",
    "tests/estimators",
    "tests/types/test_constants.py",
]
SMOOTH = FILTER + ["tests/fusion/test_fusion_geometry.py"]
ALIGN = ["tests/nav/test_initial_alignment.py", "tests/estimators/test_ekf.py"]
WINDOWS = ["tests/detectors", "tests/nav/test_stance_check.py", "tests/nav/test_windows.py"]
GAIT = ["tests/nav/test_stance_check.py", "tests/detectors/test_adaptive.py", "tests/nav/test_gait_cycles.py"]
STRIDES = ["tests/nav/test_strides.py"]
HEADING_DRIFT = ["tests/estimators", "tests/nav/test_heading_drift.py"]
METRICS = [
    "tests/analysis/test_metrics.py",
    "tests/analysis/test_paper_metrics.py",
    "tests/analysis/test_evaluation.py",
]
DTW = ["tests/nav/test_dtw.py", "tests/fusion/test_dtw.py"]
DETECT = ["tests/detectors", "tests/nav/test_windows.py"]
MADGWICK = [
    "tests/estimators/test_madgwick.py",
    "tests/estimators/test_madgwick_reference.py",
    "tests/estimators/test_vertical.py",
    "tests/types/test_constants.py",
]
FUSION = ["tests/fusion"]


@dataclass(frozen=True)
class Mutant:
    """One realistic bug: ``edits`` are (snippet, replacement) or (snippet, replacement, n) with n
    the occurrence (0-based) when the snippet is not unique in ``path``."""

    name: str
    path: str
    edits: tuple
    tests: list[str] = field(hash=False)
    kind: str = ""


def M(name, path, edits, tests, kind=""):
    if isinstance(edits[0], str):
        edits = (edits,)
    return Mutant(name, path, tuple(edits), tests, kind)


Q, MECH = "footnav/nav/quaternion.py", "footnav/nav/mechanization.py"
_EKF = "footnav/estimators/ekf/"
KER, BACK, LOOP, REC = _EKF + "_kernels.py", _EKF + "_backward.py", _EKF + "_loop.py", _EKF + "_records.py"
FILT, SM = _EKF + "filter.py", _EKF + "smoother.py"
KAL = "footnav/nav/kalman.py"
AL, WIN, HD = "footnav/nav/initial_alignment.py", "footnav/nav/windows.py", "footnav/nav/heading_drift.py"
SC, GC, ST = "footnav/nav/stance_check.py", "footnav/nav/gait_cycles.py", "footnav/nav/strides.py"
MET_AL, MET_TR = "footnav/analysis/metrics/_alignment.py", "footnav/analysis/metrics/_trajectory.py"
MET_DEV, MET_ST = "footnav/analysis/metrics/_deviation.py", "footnav/analysis/metrics/_strides.py"
MET_MA, MET_CH = "footnav/analysis/metrics/_matching.py", "footnav/analysis/metrics/_checks.py"
DT = "footnav/nav/dtw.py"
DTH, DTA = "footnav/nav/dtw_heading.py", "footnav/nav/dtw_average.py"
GLRT, THR, ADA = "footnav/detectors/glrt.py", "footnav/detectors/threshold.py", "footnav/detectors/adaptive.py"
DG = "footnav/detectors/dual_gait.py"
HMM_FEATURES, HMM_REORDER = "footnav/detectors/hmm/features.py", "footnav/detectors/hmm/reorder.py"
MW, EKFP = "footnav/estimators/madgwick.py", _EKF + "estimator.py"
RC, SV, FD = "footnav/fusion/range_constraint.py", "footnav/fusion/step_vector.py", "footnav/fusion/dtw.py"
PEN = "footnav/fusion/pendulum.py"
PF, PE, JN = "footnav/fusion/particle.py", "footnav/fusion/particle_ekf.py", "footnav/fusion/joint.py"
PFC = "footnav/fusion/particle_cloud.py"
OCH = "footnav/pipeline/online_checks.py"
ONLINE_CHECKS = [
    "tests/pipeline/test_online_checks.py",
    "tests/pipeline/test_online_clipping.py",
    "tests/faults/test_time_units.py",
]
RES, PYS = "footnav/data/results.py", "footnav/data/io/pyshoe.py"
DATA_RES = ["tests/data/test_results.py", "tests/nav/test_strides.py"]
DATA_PYS = ["tests/data/io/test_pyshoe.py", "tests/data/io/test_io_pyshoe.py"]
TC = "footnav/analysis/truth_checks.py"
TRUTH = ["tests/analysis/test_truth_checks.py", "tests/faults/test_truth_checks.py"]
METRICS_NEW = ["tests/analysis/test_metrics.py"] + METRICS
STRIDES_NEW = ["tests/nav/test_strides.py"] + STRIDES
OF, OJ = "footnav/pipeline/online_foot.py", "footnav/pipeline/online_joint.py"
FL, DD, IC = "footnav/nav/floors.py", "footnav/nav/dominant_directions.py", "footnav/core/types/imu_checks.py"
HT = "footnav/nav/heading.py"  # turn_by: the heading aids' turn
ONLINE_FWD = ["tests/pipeline/test_online_foot.py", "tests/pipeline/test_online_joint.py"]
NAV_HD = ["tests/nav/test_heading_drift.py", "tests/estimators/test_consistency.py"]
NAV_FL = ["tests/nav/test_floors.py"]
NAV_DD = [
    "tests/nav/test_dominant_directions.py",
    "tests/heading_aids/test_dominant_directions.py",
    "tests/heading_aids/test_magnetometer.py",
]
TYPES_IC = ["tests/types/test_imu_checks.py", "tests/faults/test_time_units.py"]
OUT, MARK = "footnav/data/output.py", "footnav/data/result_marker.py"
DATA_OUT = ["tests/data/test_output.py", "tests/data/test_result_marker.py", "tests/faults/test_user_files.py"]
PEKF = ["tests/fusion/test_particle_ekf.py", "tests/fusion/test_particle_paper.py"]
VC, SPN = "footnav/nav/vertical_check.py", "footnav/nav/spans.py"
NAV_VC = ["tests/nav/test_vertical_check.py"]
NAV_SPN = ["tests/nav/test_spans.py", "tests/fusion/test_spans.py"]
JOINT = ["tests/fusion/test_joint.py", "tests/fusion/test_spans.py"]

# issue 37: the code added or changed since the last round, with the test files that mirror it
FR, CAL = "footnav/nav/final_rest.py", "footnav/nav/calibration.py"
NAV_FR = ["tests/nav/test_final_rest.py", "tests/estimators/test_ekf.py"]
NAV_CAL = ["tests/nav/test_calibration.py", "tests/fusion/test_step_vector_paper.py"]
NAV_SC = ["tests/nav/test_stance_check.py"]
ADAPT = ["tests/detectors/test_adaptive.py"]

MUTANTS: list[Mutant] = [
    # -- nav/quaternion.py ------------------------------------------------------------------
    M(
        "quat-mul-nb-term",
        Q,
        (
            "out[1] = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2]",
            "out[1] = p[0] * q[1] + p[1] * q[0] - p[2] * q[3] + p[3] * q[2]",
        ),
        QUAT,
        "sign",
    ),
    M("quat-rotvec-series-const", Q, ("k = 0.5 - a2 * (1.0 / 48.0", "k = 0.5 - a2 * (1.0 / 24.0"), QUAT, "constant"),
    M("quat-rotvec-large-half", Q, ("out[0] = np.cos(0.5 * angle)", "out[0] = np.cos(angle)"), QUAT, "constant"),
    M(
        "quat-matrix-nb-transposed",
        Q,
        ("out[1, 2] = 2 * (y * z - w * x)", "out[1, 2] = 2 * (y * z + w * x)"),
        QUAT,
        "transpose",
    ),
    M(
        "quat-matrix-np-transposed",
        Q,
        (
            "np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z)",
            "np.stack([2 * (x * y - w * z), 1 - 2 * (x * x + z * z)",
        ),
        QUAT,
        "transpose",
    ),
    M(
        "quat-from-matrix-w-branch",
        Q,
        (
            "(mi[0, 2] - mi[2, 0]) / s, (mi[1, 0] - mi[0, 1]) / s]",
            "(mi[0, 2] - mi[2, 0]) / s, (mi[0, 1] - mi[1, 0]) / s]",
        ),
        QUAT,
        "transpose",
    ),
    M(
        "quat-from-matrix-x-branch",
        Q,
        ("out[i] = [(mi[2, 1] - mi[1, 2]) / s, 0.25 * s", "out[i] = [(mi[1, 2] - mi[2, 1]) / s, 0.25 * s"),
        QUAT,
        "sign",
    ),
    M(
        "quat-as-rotvec-limit",
        Q,
        ("angle / np.where(s > 0, s, 1.0), 2.0)", "angle / np.where(s > 0, s, 1.0), 1.0)"),
        QUAT,
        "constant",
    ),
    M("quat-from-euler-term", Q, ("sr * cp * cy - cr * sp * sy,", "sr * cp * cy + cr * sp * sy,"), QUAT, "sign"),
    M("quat-as-euler-pitch", Q, ("2 * (w * y - x * z)", "2 * (w * y + x * z)"), QUAT, "sign"),
    M("quat-normalize-nb", Q, ("q[i] /= n", "q[i] *= n"), QUAT, "operator"),
    M("quat-conjugate-index", Q, ("q[..., 1:] *= -1.0", "q[..., 2:] *= -1.0"), QUAT, "off-by-one"),
    M("quat-from-yaw-sign", Q, ("[np.cos(a), z, z, np.sin(a)]", "[np.cos(a), z, z, -np.sin(a)]"), QUAT, "sign"),
    # -- nav/mechanization.py ---------------------------------------------------------------
    M("mech-half-rotation", MECH, ("h = 0.25 * dt", "h = 0.5 * dt"), FILTER, "constant"),
    M("mech-gravity-no-dt", MECH, ("dv -= GRAVITY_MPS2 * dt", "dv -= GRAVITY_MPS2"), FILTER, "dropped dt"),
    M(
        "mech-position-rectangle",
        MECH,
        ("p[f, i] += 0.5 * (v[f, i] + v_new) * dt", "p[f, i] += v[f, i] * dt"),
        FILTER,
        "missing term",
    ),
    M(
        "mech-simpson-weight",
        MECH,
        ("a_prev + 2.0 * f_mid[i] + fi", "a_prev + 4.0 * f_mid[i] + fi"),
        FILTER,
        "constant",
    ),
    M("mech-gravity-axis", MECH, ("if i == 2:", "if i == 1:"), FILTER, "off-by-one"),
    M(
        "mech-nav-side-increment",
        MECH,
        (
            "q_tmp[1] = w * dq[1] + x * dq[0] + y * dq[3] - z * dq[2]",
            "q_tmp[1] = w * dq[1] + x * dq[0] - y * dq[3] + z * dq[2]",
            0,
        ),
        FILTER,
        "transpose",
    ),
    M(
        "mech-loop-swapped-samples",
        MECH,
        ("acc[k - 1], gyr[k - 1], acc[k], gyr[k]", "acc[k], gyr[k - 1], acc[k - 1], gyr[k]"),
        FILTER,
        "swapped arguments",
    ),
    M(
        "mech-bias-sign",
        MECH,
        ("imu.gyr - np.asarray(gyro_bias_radps", "imu.gyr + np.asarray(gyro_bias_radps"),
        FILTER,
        "sign",
    ),
    # -- estimators/ekf/ (kernels, backward, loop, records, filter) ----------------------------
    M(
        "ins-zupt-sign",
        LOOP,
        ("y[0], y[1], y[2] = v[f, 0], v[f, 1], v[f, 2]", "y[0], y[1], y[2] = -v[f, 0], -v[f, 1], -v[f, 2]"),
        FILTER,
        "sign",
    ),
    M(
        "ins-q-no-dt",
        KER,
        ("cov[o + a, o + a] += q_diag[a] * dt", "cov[o + a, o + a] += q_diag[a]"),
        FILTER,
        "dropped dt",
    ),
    M(
        "ins-f-rows-skew",
        KER,
        ("cov[o + 4, j] = v1 + z * a0 - x * a2", "cov[o + 4, j] = v1 - z * a0 + x * a2"),
        FILTER,
        "transpose",
    ),
    M("ins-f-cols-index", KER, ("cov[i, o + 8] += dt * v2", "cov[i, o + 8] += dt * v1"), FILTER, "off-by-one"),
    M(
        "ins-f-rows-acc-bias-sign",
        KER,
        ("cov[o + 3 + i, j] -= dt * (c[i, 0] * b0", "cov[o + 3 + i, j] += dt * (c[i, 0] * b0"),
        FILTER,
        "sign",
    ),
    M(
        "ins-f-cols-gyr-bias-transposed",
        KER,
        (
            "cov[i, o + r] += dt * (c[r, 0] * g0 + c[r, 1] * g1 + c[r, 2] * g2)",
            "cov[i, o + r] += dt * (c[0, r] * g0 + c[1, r] * g1 + c[2, r] * g2)",
        ),
        FILTER,
        "transpose",
    ),
    M(
        "ins-update-missing-r",
        KAL,
        ("cov[o + 1, o + 2], cov[o + 2, o + 2] + r", "cov[o + 1, o + 2], cov[o + 2, o + 2]"),
        FILTER,
        "missing term",
    ),
    M("ins-zaru-gate", LOOP, ("ZARU_GATE = 16.27", "ZARU_GATE = 1.627"), FILTER, "constant"),
    M("ins-sym3-inverse", KAL, ("i02 = b * e - c * d", "i02 = c * d - b * e"), FILTER, "sign"),
    M("ins-feedback-position-sign", KER, ("p[f, i] -= dx[o + 6 + i]", "p[f, i] += dx[o + 6 + i]"), FILTER, "sign"),
    M(
        "ins-feedback-body-side",
        KER,
        (
            "q_tmp[1] = dq[0] * x + dq[1] * w + dq[2] * z - dq[3] * y",
            "q_tmp[1] = dq[0] * x + dq[1] * w - dq[2] * z + dq[3] * y",
        ),
        FILTER,
        "transpose",
    ),
    M(
        "ins-feedback-gyr-bias-index",
        KER,
        ("bg[f, i] -= dx[o + 12 + i]", "bg[f, i] -= dx[o + 9 + i]"),
        FILTER,
        "off-by-one",
    ),
    M(
        "ins-ft-index",
        BACK,
        ("mu[o + 3] = v0 + dt * mu[o + 6]", "mu[o + 3] = v0 + dt * mu[o + 7]"),
        SMOOTH,
        "off-by-one",
    ),
    M("ins-ft-skew-sign", BACK, ("mu[o] = a0 + z * v1 - y * v2", "mu[o] = a0 - z * v1 + y * v2"), SMOOTH, "transpose"),
    M("ins-finv-sign", BACK, ("d[o + 6] -= dt * d[o + 3]", "d[o + 6] += dt * d[o + 3]"), SMOOTH, "sign"),
    M(
        "ins-smooth-q-no-dt",
        BACK,
        ("d[o + i] -= q_diag[i] * dt * mu[o + i]", "d[o + i] -= q_diag[i] * mu[o + i]"),
        SMOOTH,
        "dropped dt",
    ),
    M(
        "ins-smooth-position-sign",
        BACK,
        ("sm_p[k, i] = out_p[k, i] - d[o + 6 + i]", "sm_p[k, i] = out_p[k, i] + d[o + 6 + i]"),
        SMOOTH,
        "sign",
    ),
    M(
        "ins-step-chain-no-correction",
        BACK,
        ("offset[f, i] = d[f * n + 6 + i] + sm_p[k0, i] - out_p[k0, i]", "offset[f, i] = sm_p[k0, i] - out_p[k0, i]"),
        SMOOTH,
        "missing term",
    ),
    M("ins-step-chain-start-index", BACK, ("k0 = ev_k[e] - 1", "k0 = ev_k[e]"), SMOOTH, "off-by-one"),
    M(
        "ins-next-foot-boundary",
        LOOP,
        ("if tn <= t_stop and tn < best:", "if tn < t_stop and tn < best:"),
        SMOOTH,
        "boundary",
    ),
    M("ins-step-end-test", LOOP, ("and not stance[kn + 1]:", "and not stance[kn]:"), SMOOTH, "off-by-one"),
    M(
        "ins-zaru-innovation-sign",
        LOOP,
        ("y[3 + i] = bg[f, i] - gyr[kn, i]", "y[3 + i] = gyr[kn, i] - bg[f, i]"),
        FILTER,
        "sign",
    ),
    M(
        "ins-pcov-index",
        LOOP,
        ("out_pcov[kn, 1] = cov[o + POS, o + POS + 1]", "out_pcov[kn, 1] = cov[o + POS, o + POS + 2]"),
        FILTER,
        "off-by-one",
    ),
    M(
        "ins-q-acc-not-squared",
        REC,
        ("q[VEL : VEL + 3] = self.acc_mps2_sqrthz**2", "q[VEL : VEL + 3] = self.acc_mps2_sqrthz"),
        FILTER,
        "missing term",
    ),
    M(
        "ins-f-end-of-interval",
        LOOP,
        ("predict_cov(cov, o, n, f_prev, c, dt, q_diag)", "predict_cov(cov, o, n, f_n[f], c, dt, q_diag)"),
        FILTER,
        "off-by-one",
    ),
    M("ins-update-r-as-std", KAL, ("acc += r[a]", "acc += np.sqrt(r[a])"), SMOOTH + ["tests/fusion"], "wrong unit"),
    M("ins-update-dx-sign", KAL, ("dx[i] = acc", "dx[i] = -acc"), SMOOTH + ["tests/fusion"], "sign"),
    # -- estimators/ekf/smoother.py ---------------------------------------------------------
    M(
        "smooth-caller-adjoint-sign",
        SM,
        ("mu += h.T @ (sy - gain.T @ mu)", "mu += h.T @ (sy + gain.T @ mu)"),
        SMOOTH + ["tests/fusion"],
        "sign",
    ),
    M("smooth-initial-position-sign", SM, ("out.p[a : k + 1] - d[6:9]", "out.p[a : k + 1] + d[6:9]"), SMOOTH, "sign"),
    M(
        "smooth-initial-velocity-dropped",
        SM,
        ("sm_v[a : k + 1] = out.v[a : k + 1] - d[3:6]", "sm_v[a : k + 1] = out.v[a : k + 1]"),
        SMOOTH,
        "missing term",
    ),
    M(
        "smooth-caller-updates-order",
        SM,
        ("for h, gain, sy, _ in reversed(cps[b].updates[", "for h, gain, sy, _ in (cps[b].updates["),
        SMOOTH + ["tests/fusion", "tests/estimators/test_smoother.py"],
        "order",
    ),
    M(
        "smooth-step-h-sign",
        SM,
        ("record.gain[row + 1, :, :m] = h.T", "record.gain[row + 1, :, :m] = -h.T"),
        SMOOTH + ["tests/fusion"],
        "sign",
    ),
    M(
        "smooth-initial-q-swapped",
        SM,
        ("quat.multiply(dq, out.q[a : k + 1])", "quat.multiply(out.q[a : k + 1], dq)"),
        SMOOTH,
        "swapped arguments",
    ),
    M(
        "smooth-keep-threshold",
        SM,
        ("while self.nbytes > self.budget_bytes:", "while self.nbytes > 2 * self.budget_bytes:"),
        SMOOTH,
        "constant",
    ),
    # -- nav/initial_alignment.py -----------------------------------------------------------
    M("align-roll-sign", AL, ("roll = np.arctan2(f[1], f[2])", "roll = np.arctan2(-f[1], f[2])"), ALIGN, "sign"),
    M(
        "align-pitch-sign",
        AL,
        ("pitch = np.arctan2(-f[0], np.hypot(f[1], f[2]))", "pitch = np.arctan2(f[0], np.hypot(f[1], f[2]))"),
        ALIGN,
        "sign",
    ),
    M(
        "align-min-still-boundary",
        AL,
        ("if still.sum() < MIN_STILL_SAMPLES:", "if still.sum() > MIN_STILL_SAMPLES:"),
        ALIGN,
        "boundary",
    ),
    M(
        "align-bias-all-samples",
        AL,
        ("gyro_bias_radps=np.mean(gyr[start:stop][still], axis=0)", "gyro_bias_radps=np.mean(gyr[start:stop], axis=0)"),
        ALIGN,
        "missing term",
    ),
    M("align-start-boundary", AL, ("if s0 > 0:", "if s0 > 1:"), ALIGN, "boundary"),
    # -- nav/windows.py ---------------------------------------------------------------------
    M(
        "win-length-round",
        WIN,
        ("2 * int(np.floor(window_s * rate_hz / 2.0", "2 * int(np.round(window_s * rate_hz / 2.0"),
        WINDOWS,
        "rounding",
    ),
    M(
        "win-centred-shift",
        WIN,
        (
            "np.arange(n_samples) - win // 2, 0, n_samples - win)",
            "np.arange(n_samples) - win // 2 + 1, 0, n_samples - win)",
        ),
        WINDOWS,
        "off-by-one",
    ),
    M(
        "win-rms-denominator",
        WIN,
        ("np.maximum(sum_of_squares, 0.0) / win)", "np.maximum(sum_of_squares, 0.0) / (win - 1))"),
        WINDOWS,
        "off-by-one",
    ),
    M("win-variance-sign", WIN, ("mean_sq_c - np.einsum", "mean_sq_c + np.einsum"), WINDOWS, "sign"),
    M(
        "win-gravity-literal",
        WIN,
        ("(row_norms(acc) - GRAVITY_MPS2) ** 2", "(row_norms(acc) - 9.81) ** 2"),
        WINDOWS,
        "constant",
    ),
    # -- nav/heading_drift.py ---------------------------------------------------------------
    M(
        "drift-lever-sign",
        HD,
        ("ax, ay = -vel[k - 1, 1] * dt, vel[k - 1, 0] * dt", "ax, ay = vel[k - 1, 1] * dt, vel[k - 1, 0] * dt"),
        HEADING_DRIFT,
        "sign",
    ),
    M(
        "drift-cross-term",
        HD,
        ("p[i, 2] += dt * p[i, 3] + turn * p[i, 4]", "p[i, 2] += 0.5 * dt * p[i, 3] + turn * p[i, 4]"),
        HEADING_DRIFT,
        "constant",
    ),
    M("drift-walk-no-dt", HD, ("p[3, 3] += q2 * dt", "p[3, 3] += q2"), HEADING_DRIFT, "dropped dt"),
    M(
        "drift-sem-no-n",
        HD,
        (
            "np.sqrt(np.mean(np.var(used, axis=0, ddof=1)) / len(used))",
            "np.sqrt(np.mean(np.var(used, axis=0, ddof=1)))",
        ),
        HEADING_DRIFT,
        "missing term",
    ),
    # -- nav/stance_check.py, nav/gait_cycles.py -------------------------------------------
    M(
        "check-swinging-flip",
        SC,
        ("swinging = acc_dev[idx] >= SWING_ACC_MPS2", "swinging = acc_dev[idx] <= SWING_ACC_MPS2"),
        GAIT,
        "operator",
    ),
    M(
        "check-over-swing-unfiltered",
        SC,
        ("over_swing_s = t[idx[swinging & mask[idx]]]", "over_swing_s = t[idx[mask[idx]]]"),
        GAIT,
        "missing term",
    ),
    M("check-suspicious-boundary", SC, ("return bad >= max(_MIN_WARN", "return bad > max(_MIN_WARN"), GAIT, "boundary"),
    M(
        "check-missed-time",
        SC,
        ("missed_s = 0.5 * (t[a[missed]] + t[b[missed]])", "missed_s = t[a[missed]]"),
        GAIT,
        "missing term",
    ),
    M(
        "gait-stride-mean",
        GC,
        ("stride_s = median(intervals, m) / rate_hz", "stride_s = intervals[:m].sum() / m / rate_hz"),
        GAIT,
        "statistic",
    ),
    M("gait-no-max-stride", GC, ("if idx[i] - idx[i - 1] < max_stride_s * rate_hz:", "if True:"), GAIT, "missing term"),
    M(
        "gait-distance-min",
        GC,
        ("distance = max(int(min_stride_s * rate_hz)", "distance = min(int(min_stride_s * rate_hz)"),
        GAIT,
        "operator",
    ),
    M("gait-swing-acc-const", GC, ("SWING_ACC_MPS2 = 2.0", "SWING_ACC_MPS2 = 20.0"), GAIT, "constant"),
    # -- nav/strides.py ---------------------------------------------------------------------
    M(
        "strides-mid-stance",
        ST,
        ("(iv[:, 0] + iv[:, 1] - 1) // 2", "(iv[:, 0] + iv[:, 1]) // 2"),
        STRIDES,
        "off-by-one",
    ),
    M(
        "strides-cadence",
        ST,
        ("STEPS_PER_STRIDE * SECONDS_PER_MINUTE / out", "SECONDS_PER_MINUTE / out"),
        STRIDES,
        "missing term",
    ),
    M(
        "strides-turn-wrap",
        ST,
        ("return -((-angle + np.pi) % (2.0 * np.pi) - np.pi)", "return (angle + np.pi) % (2.0 * np.pi) - np.pi"),
        STRIDES,
        "boundary",
    ),
    M(
        "strides-turn-swapped",
        ST,
        ("quat.multiply(q_end, quat.conjugate(q_start))", "quat.multiply(q_start, quat.conjugate(q_end))"),
        STRIDES,
        "swapped arguments",
    ),
    M(
        "strides-swing-mask",
        ST,
        ("swing_dt = np.where(mask, 0.0, dt)", "swing_dt = np.where(mask, dt, 0.0)"),
        STRIDES,
        "swapped arguments",
    ),
    M(
        "strides-clearance-chord",
        ST,
        ("np.max(z - (z[0] + frac * (z[-1] - z[0])))", "np.max(z - z[0])"),
        STRIDES,
        "missing term",
    ),
    M(
        "strides-dt-prepend",
        ST,
        ("dt = np.diff(t, append=t[-1])", "dt = np.diff(t, prepend=t[0])"),
        STRIDES,
        "off-by-one",
    ),
    # -- analysis/metrics/ -----------------------------------------------------------------------
    M("metrics-umeyama-reflection", MET_AL, ("sign[-1] = -1.0", "sign[-1] = 1.0"), METRICS, "missing term"),
    M(
        "metrics-umeyama-scale-trans",
        MET_AL,
        ("trans = mu_d - scale * rot @ mu_s", "trans = mu_d - rot @ mu_s"),
        METRICS,
        "missing term",
    ),
    M("metrics-umeyama-transposed", MET_AL, ("cov = xd.T @ xs / n", "cov = xs.T @ xd / n"), METRICS, "transpose"),
    M(
        "metrics-start-yaw-sign",
        MET_AL,
        ("np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])", "np.sum(a[:, 1] * b[:, 0] - a[:, 0] * b[:, 1])"),
        METRICS,
        "sign",
    ),
    M(
        "metrics-rmse-mean",
        MET_TR,
        (
            "return float(np.sqrt(np.mean(np.sum(diff**2, axis=1))))",
            "return float(np.mean(np.sqrt(np.sum(diff**2, axis=1))))",
        ),
        METRICS,
        "statistic",
    ),
    M("metrics-waypoint-radius", MET_TR, ("near = d <= radius_m", "near = d < radius_m"), METRICS, "boundary"),
    M(
        "metrics-deviation-min-distance",
        MET_DEV,
        ("ok = (s >= min_distance_m) & (s > 0)", "ok = (s > min_distance_m) & (s > 0)"),
        METRICS,
        "boundary",
    ),
    M("metrics-step-length-sign", MET_ST, ("err = le - lr", "err = lr - le"), METRICS, "sign"),
    M(
        "metrics-match-tolerance",
        MET_MA,
        ("float(ref_s[ri[0]])) <= tol:", "float(ref_s[ri[0]])) < tol:"),
        METRICS,
        "boundary",
    ),
    M("metrics-percent", MET_CH, ("float(_PERCENT * num / den)", "float(num / den)"), METRICS, "constant"),
    M(
        "metrics-interp-duplicates",
        MET_DEV,
        ("if len(tt) < 2 or (np.diff(tt) <= 0).any():", "if len(tt) < 2 or (np.diff(tt) < 0).any():"),
        METRICS,
        "boundary",
    ),
    M(
        "metrics-distance-3d",
        MET_AL,
        (
            "np.cumsum(np.linalg.norm(np.diff(ref[:, :2], axis=0), axis=1))))\n    k",
            "np.cumsum(np.linalg.norm(np.diff(ref, axis=0), axis=1))))\n    k",
        ),
        METRICS,
        "index",
    ),
    # -- nav/dtw.py, dtw_heading.py, dtw_average.py -----------------------------------------
    M(
        "dtw-tie-break",
        DT,
        ("v = cur[k - 1]\n                if v < best:", "v = cur[k - 1]\n                if v <= best:"),
        DTW,
        "boundary",
    ),
    M(
        "dtw-end-cell",
        DT,
        ("kend = (m - 1) - max(0, n - 1 - band)", "kend = (m - 1) - max(0, n - band)"),
        DTW,
        "off-by-one",
    ),
    M(
        "dtw-backtrack-offset",
        DT,
        ("s = steps[i, j - max(0, i - band)]", "s = steps[i, j - max(0, i - band - 1)]"),
        DTW,
        "off-by-one",
    ),
    M("dtw-mean-denominator", DT, ("per = total / n_pairs if", "per = total / n if"), DTW, "wrong variable"),
    M(
        "dtw-rotation-transposed",
        DTH,
        ("xy @ np.array([[c, s], [-s, c]])", "xy @ np.array([[c, -s], [s, c]])"),
        DTW,
        "transpose",
    ),
    M(
        "dtw-average-index",
        DTA,
        ("position = 0.5 * (pa[i] + pb[j])", "position = 0.5 * (pa[i] + pb[i])"),
        DTW,
        "wrong index",
    ),
    M("dtw-heading-bracket", DTH, ("step = 2.0 * np.pi / grid", "step = np.pi / grid"), DTW, "constant"),
    M("dtw-shift-sign", DTH, ("shift = pa[0] - pb[0] if", "shift = pb[0] - pa[0] if"), DTW, "sign"),
    M("dtw-band-check", DT, ("if band_i < abs(n - m):", "if band_i < abs(n - m) - 1:"), DTW, "off-by-one"),
    # -- detectors ----------------------------------------------------------------------------
    M(
        "glrt-no-one-over-w",
        GLRT,
        (
            "return acc_term / sigma_acc_mps2**2 + gyr_term / sigma_gyr_radps**2",
            "return win * (acc_term / sigma_acc_mps2**2 + gyr_term / sigma_gyr_radps**2)",
        ),
        DETECT,
        "missing term",
    ),
    M(
        "glrt-sigma-not-squared",
        GLRT,
        ("acc_term / sigma_acc_mps2**2", "acc_term / sigma_acc_mps2"),
        DETECT,
        "missing term",
    ),
    M(
        "glrt-sigma-gyr-degrees",
        GLRT,
        ("OPENSHOE_SIGMA_GYR_RADPS = 0.1 * np.pi / 180.0", "OPENSHOE_SIGMA_GYR_RADPS = 0.1"),
        DETECT,
        "wrong unit",
    ),
    M(
        "thr-combine-center-shift",
        THR,
        ("np.arange(n_samples) - win // 2, 0, k_last)", "np.arange(n_samples) - win // 2 + 1, 0, k_last)"),
        DETECT,
        "off-by-one",
    ),
    M("thr-min-stance-boundary", THR, ("if j - i < min_len:", "if j - i <= min_len:"), DETECT, "boundary"),
    M(
        "thr-min-swing-boundary",
        THR,
        ("if stop >= 0 and i - stop < min_gap:", "if stop >= 0 and i - stop <= min_gap:"),
        DETECT,
        "boundary",
    ),
    M("thr-heel-off-index", THR, ('"heel_off": runs[:, 1] - 1}', '"heel_off": runs[:, 1]}'), DETECT, "off-by-one"),
    M(
        "thr-combine-slice",
        THR,
        ("filtered[win // 2 : win // 2 + n_samples]", "filtered[win // 2 + 1 : win // 2 + 1 + n_samples]"),
        DETECT,
        "off-by-one",
    ),
    M(
        "thr-neutral-pad",
        THR,
        ('neutral = combine == "all"', 'neutral = combine == "any"'),
        DETECT,
        "swapped arguments",
    ),
    M(
        "adaptive-ceiling-max",
        ADA,
        ("min(height[k], height[k + 1])", "max(height[k], height[k + 1])"),
        DETECT,
        "operator",
    ),
    M(
        "adaptive-pivot-acc-not-squared",
        ADA,
        ("self.pivot_acc_mps2**2,\n            self.max_pivot_s", "self.pivot_acc_mps2,\n            self.max_pivot_s"),
        DETECT,
        "missing term",
    ),
    M(
        "dual-gait-first-peak",
        DG,
        ("found = (j >= 0) & (imu.t[starts]", "found = (j > 0) & (imu.t[starts]"),
        DETECT,
        "boundary",
    ),
    M(
        "dual-gait-opening-flat",
        DG,
        ("starts = starts[starts > 0]", "starts = starts[starts >= 0]"),
        DETECT,
        "boundary",
    ),
    M(
        "hmm-model-samples",
        HMM_FEATURES,
        (
            "int(math.floor(imu.duration_s * model_rate_hz + 1e-9)) + 1",
            "int(math.floor(imu.duration_s * model_rate_hz + 1e-9))",
        ),
        DETECT,
        "off-by-one",
    ),
    M(
        "hmm-position-centre",
        HMM_REORDER,
        ("rel = (np.arange(stop - start) + 0.5) / (stop - start)", "rel = np.arange(stop - start) / (stop - start)"),
        DETECT,
        "missing term",
    ),
    # -- estimators ---------------------------------------------------------------------------
    M(
        "madgwick-gradient-reversed",
        MW,
        (
            ("d0 -= beta * s0 / sn", "d0 += beta * s0 / sn"),
            ("d1 -= beta * s1 / sn", "d1 += beta * s1 / sn"),
            ("d2 -= beta * s2 / sn", "d2 += beta * s2 / sn"),
            ("d3 -= beta * s3 / sn", "d3 += beta * s3 / sn"),
        ),
        MADGWICK,
        "sign",
    ),
    M(
        "madgwick-gravity-9.81",
        MW,
        (
            ("a_prev[2] -= GRAVITY_MPS2", "a_prev[2] -= 9.81"),
            ("(GRAVITY_MPS2 if i == 2 else 0.0)", "(9.81 if i == 2 else 0.0)"),
        ),
        MADGWICK,
        "constant",
    ),
    M(
        "madgwick-qdot-term",
        MW,
        ("0.5 * (q0 * gx + q2 * gz - q3 * gy),", "0.5 * (q0 * gx - q2 * gz + q3 * gy),"),
        MADGWICK,
        "sign",
    ),
    M(
        "madgwick-velocity-rectangle",
        MW,
        ("v_new = v[i] + 0.5 * (a_prev[i] + a_new) * dt", "v_new = v[i] + a_new * dt"),
        MADGWICK,
        "missing term",
    ),
    M("madgwick-innovation-sign", MW, ("innov[i] = v[i] - de[3 + i]", "innov[i] = v[i] + de[3 + i]"), MADGWICK, "sign"),
    M(
        "madgwick-q-no-dt",
        MW,
        ("p[3 + i, 3 + i] += var_acc * dt", "p[3 + i, 3 + i] += var_acc"),
        MADGWICK,
        "dropped dt",
    ),
    M("madgwick-output-sign", MW, ("r_out[k, i] = r[i] - de[i]", "r_out[k, i] = r[i] + de[i]"), MADGWICK, "sign"),
    M(
        "madgwick-magnetic-heading-sign",
        MW,
        ("psi = -float(np.arctan2(h[1], h[0]))", "psi = float(np.arctan2(h[1], h[0]))"),
        MADGWICK,
        "sign",
    ),
    M(
        "madgwick-imu-gradient-term",
        MW,
        (
            "s1 = 2.0 * q3 * f0 + 2.0 * q0 * f1 - 4.0 * q1 * f2\n",
            "s1 = 2.0 * q3 * f0 + 2.0 * q0 * f1 + 4.0 * q1 * f2\n",
        ),
        MADGWICK,
        "sign",
    ),
    M(
        "madgwick-f-transposed",
        MW,
        (
            "m[3 + i, j] = p[3 + i, j] + dt * (c[i, 0] * p[6, j] + c[i, 1] * p[7, j] + c[i, 2] * p[8, j])",
            "m[3 + i, j] = p[3 + i, j] + dt * (c[0, i] * p[6, j] + c[1, i] * p[7, j] + c[2, i] * p[8, j])",
        ),
        MADGWICK,
        "transpose",
    ),
    M(
        "gravity-constant",
        "footnav/core/types/units.py",
        ("GRAVITY_MPS2 = 9.80665", "GRAVITY_MPS2 = 9.81"),
        MADGWICK + ["tests/estimators/test_ekf.py"],
        "constant",
    ),
    # -- fusion ------------------------------------------------------------------------------
    M("range-mirror", RC, ("z = p[anchor] + sign * bound * u", "z = p[anchor] - sign * bound * u"), FUSION, "sign"),
    M("range-symmetric-sign", RC, ("centre + 0.5 * bound * u", "centre - 0.5 * bound * u"), FUSION, "sign"),
    M(
        "range-anchor-swapped",
        RC,
        ("anchor = LEFT if feet_standing[LEFT] else RIGHT", "anchor = RIGHT if feet_standing[LEFT] else LEFT"),
        FUSION,
        "swapped arguments",
    ),
    M(
        "range-landing-index",
        RC,
        ("imu.t[stance.intervals[1:, 0]]", "imu.t[stance.intervals[1:, 0] - 1]"),
        FUSION,
        "off-by-one",
    ),
    M(
        "step-vector-width-side",
        SV,
        ("side = 1.0 if front == LEFT else -1.0", "side = -1.0 if front == LEFT else 1.0"),
        FUSION,
        "sign",
    ),
    M("step-vector-theta-half", PEN, ("theta = 2.0 * math.acos(", "theta = math.acos("), FUSION, "constant"),
    M(
        "step-vector-pendulum-factor",
        PEN,
        ("return 2.0 * leg_length_m * math.sin(0.5 * theta)", "return leg_length_m * math.sin(0.5 * theta)"),
        FUSION,
        "constant",
    ),
    M("step-vector-fit-half", PEN, ("return 0.5 * stride / swing", "return stride / swing"), FUSION, "constant"),
    M(
        "step-vector-innovation-sign",
        SV,
        (
            "y = (filt.position(front) - filt.position(rear)) - dp_n",
            "y = (filt.position(rear) - filt.position(front)) - dp_n",
        ),
        FUSION,
        "sign",
    ),
    M(
        "step-vector-rot-transposed",
        SV,
        ("rot = np.array([[c, -sn, 0.0], [sn, c, 0.0]", "rot = np.array([[c, sn, 0.0], [-sn, c, 0.0]"),
        FUSION,
        "transpose",
    ),
    M(
        "step-vector-frame-dropped",
        SV,
        ("filt.update(rot.T @ h, rot.T @ y, self._r)", "filt.update(h, y, self._r)"),
        FUSION,
        "missing term",
    ),
    M(
        "step-vector-heel-strike-boundary",
        SV,
        ('j = np.searchsorted(hs, starts, side="right") - 1', 'j = np.searchsorted(hs, starts, side="left") - 1'),
        FUSION,
        "boundary",
    ),
    M(
        "dtw-fusion-band-wider",
        FD,
        ("band = max(1, int(round(band_s * rate_hz)))", "band = max(1, int(round(band_s * rate_hz)) + 1)"),
        FUSION,
        "off-by-one",
    ),
    M(
        "dtw-fusion-heading-band-wider",
        FD,
        (
            "band = max(int(round(self.band_s * self.dtw_rate_hz)),",
            "band = max(int(round(self.band_s * self.dtw_rate_hz)) + 1,",
        ),
        FUSION,
        "off-by-one",
    ),
    M("dtw-fusion-heading-sign", FD, ("yaws[RIGHT] += angle", "yaws[RIGHT] -= angle"), FUSION, "sign"),
    M(
        "joint-start-sides",
        JN,
        (
            "[np.array([0.0, half, 0.0]), np.array([0.0, -half, 0.0])]",
            "[np.array([0.0, -half, 0.0]), np.array([0.0, half, 0.0])]",
        ),
        FUSION,
        "swapped arguments",
    ),
    M(
        "dtw-fusion-offset-side",
        FD,
        ("side = 1.0 if moving == LEFT else -1.0", "side = -1.0 if moving == LEFT else 1.0"),
        FUSION,
        "sign",
    ),
    M(
        "particle-update-late",
        PF,
        ("landings = [imu.t[st.intervals[1:, 0]]", "landings = [imu.t[st.intervals[1:, 0] + 1]"),
        FUSION,
        "off-by-one",
    ),
    M(
        "particle-paper-update-late",
        PF,
        ("(float(imu.t[stop - 1]), foot)", "(float(imu.t[stop]), foot)", 0),
        FUSION,
        "off-by-one",
    ),
    M(
        "particle-weights-unnormalised",
        PFC,
        (("cum = logw[0] / total", "cum = logw[0]"), ("cum += logw[j] / total", "cum += logw[j]")),
        FUSION,
        "missing term",
    ),
    M(
        "particle-systematic-unnormalised",
        PFC,
        ("cum = np.cumsum(w / w.sum())", "cum = np.cumsum(w)"),
        FUSION,
        "missing term",
    ),
    M(
        "particle-systematic-points",
        PFC,
        ("points = (rng.random() + np.arange(n)) / n", "points = (rng.random() + np.arange(n)) / (n + 1)"),
        FUSION,
        "off-by-one",
    ),
    M("particle-rayleigh-mean", PFC, ("sigma_m * np.sqrt(np.pi / 2)", "sigma_m * np.sqrt(np.pi)"), FUSION, "constant"),
    M("particle-mixture-spread", PFC, ('+ np.einsum("i,ij,ik->jk", a, d, d)', ""), FUSION, "missing term"),
    M(
        "particle-eig-radius",
        PFC,
        ("rad = np.sqrt(0.25 * (p - s) ** 2 + q * q)", "rad = np.sqrt(0.5 * (p - s) ** 2 + q * q)"),
        FUSION,
        "constant",
    ),
    M(
        "particle-foot-offset-sign",
        PF,
        (
            "z_foot = z + side * 0.5 * self.step_width_m * lateral",
            "z_foot = z - side * 0.5 * self.step_width_m * lateral",
        ),
        FUSION,
        "sign",
    ),
    M("particle-drift-sign", PF, ("drift = -side * offset_rayleigh", "drift = side * offset_rayleigh"), FUSION, "sign"),
    M(
        "particle-gaussian-half",
        PFC,
        ('logw = -0.5 * np.einsum("ni,ij,nj->n"', 'logw = -np.einsum("ni,ij,nj->n"'),
        FUSION,
        "constant",
    ),
    M(
        "particle-ekf-scale-sqrt",
        PE,
        ("s = sigma_m / math.sqrt(b - a)", "s = sigma_m / (b - a)"),
        FUSION,
        "missing term",
    ),
    M(
        "particle-ekf-q-no-dt",
        PE,
        ("cov[VEL + i, VEL + i] += noise[0] * dt", "cov[VEL + i, VEL + i] += noise[0]"),
        FUSION,
        "dropped dt",
    ),
    M(
        "particle-ekf-lateral-transposed",
        PE,
        ("lat_x, lat_y = side * c[0, 1], side * c[1, 1]", "lat_x, lat_y = side * c[1, 0], side * c[1, 1]"),
        FUSION,
        "transpose",
    ),
    M("joint-half-width", JN, ("half = 0.5 * float(step_width_m)", "half = float(step_width_m)"), FUSION, "constant"),
    M("joint-alone-std", JN, ("np.sqrt(fused.position_std[k] ** 2 + grow)", "np.sqrt(grow)"), FUSION, "missing term"),
    M(
        "joint-alone-rotation-transposed",
        JN,
        ("(pos - alone_anchor[0]) @ rot.T + fused_anchor[0]", "(pos - alone_anchor[0]) @ rot + fused_anchor[0]"),
        FUSION,
        "transpose",
    ),
    # -- issue 37: nav/final_rest.py, nav/calibration.py, nav/stance_check.py, detectors/adaptive.py --
    M(
        "final-rest-or-and",
        FR,
        (
            "if tail_s > FINAL_REST_MAX_TAIL_S or rest_s < need_s:",
            "if tail_s > FINAL_REST_MAX_TAIL_S and rest_s < need_s:",
        ),
        NAV_FR,
        "or/and",
    ),
    M(
        "final-rest-need-min",
        FR,
        ("need_s = max(FINAL_REST_MIN_S, 2.0 * median_s)", "need_s = min(FINAL_REST_MIN_S, 2.0 * median_s)"),
        NAV_FR,
        "operator",
    ),
    M(
        "final-rest-tail-boundary",
        FR,
        ("if tail_s > FINAL_REST_MAX_TAIL_S or", "if tail_s >= FINAL_REST_MAX_TAIL_S or"),
        NAV_FR,
        "boundary",
    ),
    M(
        "final-rest-rest-last-sample",
        FR,
        ("rest_s = float(t[b - 1] - t[a])", "rest_s = float(t[b] - t[a])"),
        NAV_FR,
        "off-by-one",
    ),
    M(
        "calib-mean-of-norms",
        CAL,
        (
            "f_norm = float(np.linalg.norm(imu.acc[start:stop].mean(axis=0)))",
            "f_norm = float(np.linalg.norm(imu.acc[start:stop], axis=1).mean())",
        ),
        NAV_CAL,
        "biased estimator",
    ),
    M(
        "calib-bias-whole-recording",
        CAL,
        ("gyro_bias_radps=imu.gyr[start:stop].mean(axis=0)", "gyro_bias_radps=imu.gyr.mean(axis=0)"),
        NAV_CAL,
        "missing term",
    ),
    M(
        "calib-one-sided",
        CAL,
        (
            "if not abs(f_norm / GRAVITY_MPS2 - 1.0) <= MAX_SCALE_ERROR:",
            "if not f_norm / GRAVITY_MPS2 - 1.0 <= MAX_SCALE_ERROR:",
        ),
        NAV_CAL,
        "one-sided",
    ),
    M(
        "calib-scale-inverted",
        CAL,
        ("acc_scale=GRAVITY_MPS2 / f_norm,", "acc_scale=f_norm / GRAVITY_MPS2,"),
        NAV_CAL,
        "swapped arguments",
    ),
    M(
        "check-cycle-either-swings",
        SC,
        ("stride &= swinging[:-1] & swinging[1:]", "stride &= swinging[:-1] | swinging[1:]"),
        NAV_SC,
        "and/or",
    ),
    M(
        "check-cycle-first-peak-only",
        SC,
        ("stride &= swinging[:-1] & swinging[1:]", "stride &= swinging[:-1]"),
        NAV_SC,
        "missing term",
    ),
    M(
        "check-count-offset",
        SC,
        ("missed = (count[b] - count[a + 1]) == 0", "missed = (count[b] - count[a + 2]) == 0"),
        NAV_SC,
        "off-by-one",
    ),
    M(
        "check-max-stride-boundary",
        SC,
        ("& ((b - a) <= max_stride_s * imu.rate_hz)", "& ((b - a) < min_stride_s * 4 * imu.rate_hz)"),
        NAV_SC,
        "constant",
    ),
    M(
        "adaptive-pivot-up-next",
        ADA,
        (
            "c[2 * g + 1, 0] - c[2 * g, 0], c[2 * g + 1, 1] - c[2 * g, 1], c[2 * g + 1, 2] - c[2 * g, 2]",
            "c[2 * g + 3, 0] - c[2 * g + 2, 0], c[2 * g + 3, 1] - c[2 * g + 2, 1], c[2 * g + 3, 2] - c[2 * g + 2, 2]",
        ),
        ADAPT,
        "off-by-one",
    ),
    M(
        "adaptive-pivot-share-inverted",
        ADA,
        ("and yaw >= pivot_yaw_share * total", "and total - yaw >= pivot_yaw_share * total"),
        ADAPT,
        "operator",
    ),
    # -- issue 37: nav/vertical_check.py, nav/spans.py, fusion/joint.py (outside the common span) --
    M(
        "vcheck-rate-one-sided",
        VC,
        ("and abs(self.rate_m_per_100m) >= WARN_RATE_M_PER_100M", "and self.rate_m_per_100m >= WARN_RATE_M_PER_100M"),
        NAV_VC,
        "one-sided",
    ),
    M(
        "vcheck-trend-one-sided",
        VC,
        ("and abs(self.trend_m) >= WARN_TREND_M", "and self.trend_m >= WARN_TREND_M"),
        NAV_VC,
        "one-sided",
    ),
    M(
        "vcheck-and-or",
        VC,
        (
            "self.level_strides >= MIN_LEVEL_STRIDES\n            and",
            "self.level_strides >= MIN_LEVEL_STRIDES\n            or",
        ),
        NAV_VC,
        "and/or",
    ),
    M("vcheck-trend-dropped", VC, ("and abs(self.trend_m) >= WARN_TREND_M\n", "\n"), NAV_VC, "missing term"),
    M("vcheck-level-negated", VC, ("level = ~stair_strides(", "level = stair_strides("), NAV_VC, "negation"),
    M(
        "spans-marked-and",
        SPN,
        ("marked = abs(d_start) > tol or abs(d_end) > tol", "marked = abs(d_start) > tol and abs(d_end) > tol"),
        NAV_SPN,
        "or/and",
    ),
    M(
        "spans-marked-one-sided",
        SPN,
        ("marked = abs(d_start) > tol or", "marked = d_start > tol or"),
        NAV_SPN,
        "one-sided",
    ),
    M(
        "spans-tolerance-min",
        SPN,
        ("tol = max(MARKED_S, MARKED_FRACTION", "tol = min(MARKED_S, MARKED_FRACTION"),
        NAV_SPN,
        "operator",
    ),
    M(
        "spans-stop-side",
        SPN,
        ('i1 = int(np.searchsorted(t, stop, side="right"))', 'i1 = int(np.searchsorted(t, stop, side="left"))'),
        NAV_SPN,
        "boundary",
    ),
    M(
        "spans-refusal-boundary",
        SPN,
        ("if stop < start + min_common_s:", "if stop <= start + min_common_s:"),
        NAV_SPN,
        "boundary",
    ),
    M(
        "joint-continue-velocity-unturned",
        JN,
        ("fused_anchor[0], vel @ rot.T,", "fused_anchor[0], vel,"),
        JOINT,
        "missing term",
    ),
    M(
        "joint-continue-velocity-transposed",
        JN,
        ("fused_anchor[0], vel @ rot.T,", "fused_anchor[0], vel @ rot,"),
        JOINT,
        "transpose",
    ),
    M(
        "joint-continue-turn-sign",
        JN,
        (
            "turn = float(quat.yaw(fused_anchor[1]) - quat.yaw(alone_anchor[1]))",
            "turn = float(quat.yaw(alone_anchor[1]) - quat.yaw(fused_anchor[1]))",
        ),
        JOINT,
        "sign",
    ),
    M(
        "check-count-includes-peak",
        SC,
        ("missed = (count[b] - count[a + 1]) == 0", "missed = (count[b] - count[a]) == 0"),
        NAV_SC,
        "off-by-one",
    ),
    # -- issue 37: fusion/particle_ekf.py (the paper-mode foot's EKF, eq. 3-7; its height) --------
    M("particle-ekf-pz-feedback-sign", PE, ("p[0, 2] -= dxs[PZ]", "p[0, 2] += dxs[PZ]"), PEKF, "sign"),
    M(
        "particle-ekf-att-feedback-sign",
        PE,
        ("from_rotvec_nb(dxs[ATT], dxs[ATT + 1], 0.0, dq)", "from_rotvec_nb(-dxs[ATT], -dxs[ATT + 1], 0.0, dq)"),
        PEKF,
        "sign",
    ),
    M("particle-ekf-ba-feedback-sign", PE, ("ba[i] -= dxs[ACC_BIAS + i]", "ba[i] += dxs[ACC_BIAS + i]"), PEKF, "sign"),
    M(
        "particle-ekf-bias-phi-sign",
        PE,
        (
            ("tmp[VEL + i, col] += dt * (acc_term - bias_term)", "tmp[VEL + i, col] += dt * (acc_term + bias_term)"),
            ("cov[r, VEL + i] += dt * (acc_term - bias_term)", "cov[r, VEL + i] += dt * (acc_term + bias_term)"),
        ),
        PEKF,
        "sign",
    ),
    M(
        "particle-ekf-pz-phi-dropped",
        PE,
        (("tmp[PZ, col] += dt * cov[VEL + 2, col]", "pass"), ("cov[r, PZ] += dt * tmp[r, VEL + 2]", "pass")),
        PEKF,
        "missing term",
    ),
    M("particle-ekf-att-q-dropped", PE, ("cov[ATT + 1, ATT + 1] += noise[1] * dt", "pass"), PEKF, "missing term"),
    M(
        "particle-ekf-skew-transposed",
        PE,
        ("fa = ((0.0, -fz), (fz, 0.0), (-fy, fx))", "fa = ((0.0, fz), (-fz, 0.0), (fy, -fx))"),
        PEKF,
        "transpose",
    ),
    M(
        "particle-ekf-out-height-dropped",
        PE,
        (
            "out_pos[k, 0], out_pos[k, 1], out_pos[k, 2] = mx, my, p[0, 2]",
            "out_pos[k, 0], out_pos[k, 1], out_pos[k, 2] = mx, my, 0.0",
        ),
        PEKF,
        "missing term",
    ),
    M(
        "particle-ekf-std-z-index",
        PE,
        (
            "out_std[k, 2] = math.sqrt(max(cov[PZ, PZ], 0.0))",
            "out_std[k, 2] = math.sqrt(max(cov[VEL + 2, VEL + 2], 0.0))",
        ),
        PEKF,
        "off-by-one",
    ),
    M(
        "particle-ekf-zupt-r-dropped",
        PE,
        (
            "cov[VEL, VEL] + noise[3],\n                cov[VEL, VEL + 1],",
            "cov[VEL, VEL],\n                cov[VEL, VEL + 1],",
        ),
        PEKF,
        "missing term",
    ),
    # -- issue 37: data/output.py, data/result_marker.py (clean-up acts on its own names only) -----
    M(
        "output-entry-prefix-match",
        OUT,
        ('and valid.fullmatch(item["entry"])', 'and valid.match(item["entry"])'),
        DATA_OUT,
        "boundary",
    ),
    M(
        "output-entry-unescaped",
        OUT,
        ('rf"\\.{re.escape(target.name)}\\.footnav-', 'rf"\\.{target.name}\\.footnav-'),
        DATA_OUT,
        "missing term",
    ),
    M("output-entry-any-token", OUT, ('\\d+-[0-9a-f]{{8}}"', '\\d+-[0-9a-f]+"'), DATA_OUT, "boundary"),
    M(
        "output-recover-aside-or",
        OUT,
        (
            'elif role == "aside" and not (target.exists() or target.is_symlink()):',
            'elif role == "aside" or not (target.exists() or target.is_symlink()):',
        ),
        DATA_OUT,
        "and/or",
    ),
    M(
        "output-recover-file-as-folder",
        OUT,
        ("            elif not _is_real_dir(path):\n", "            elif not path.exists():\n"),
        DATA_OUT,
        "missing term",
    ),
    M(
        "output-partial-suffix-kind",
        OUT,
        (
            '(self.target.suffix if self.kind == "file" else "")',
            '(self.target.suffix if self.kind == "folder" else "")',
        ),
        DATA_OUT,
        "swapped arguments",
    ),
    M(
        "marker-foreign-any-level",
        MARK,
        (
            "elif rel not in files and not (rel == MARKER and not prefix):",
            "elif rel not in files and not rel.endswith(MARKER):",
        ),
        DATA_OUT,
        "missing term",
    ),
    M(
        "marker-inside-follows-links",
        MARK,
        (
            "        if not _is_real_dir(path):\n            return False",
            "        if not path.is_dir():\n            return False",
        ),
        DATA_OUT,
        "missing term",
    ),
    M(
        "marker-relative-allows-parent",
        MARK,
        ('part not in ("", ".", "..")', 'part not in ("", ".")'),
        DATA_OUT,
        "missing term",
    ),
    M(
        "marker-legacy-prefix-match",
        MARK,
        ("_LEGACY_PATTERN.fullmatch(n)", "_LEGACY_PATTERN.match(n)"),
        DATA_OUT,
        "boundary",
    ),
    # -- issue 37: the online forward estimate, heading drift, floors, dominant directions, input checks --
    M(
        "online-forward-cov-turned-back",
        OF,
        ("c, s = math.cos(-self.psi), math.sin(-self.psi)", "c, s = math.cos(self.psi), math.sin(self.psi)"),
        ONLINE_FWD,
        "sign",
    ),
    M(
        "online-forward-cov-transposed",
        OF,
        (
            "pos, vel, q, cov = p[0], v[0], qq[0], rot @ cov @ rot.T",
            "pos, vel, q, cov = p[0], v[0], qq[0], rot.T @ cov @ rot",
        ),
        ONLINE_FWD,
        "transpose",
    ),
    M(
        "online-joint-forward-cov-block",
        OJ,
        (
            'sl = filt.block(f, "pos")\n            out.append(\n                ForwardEstimate',
            'sl = filt.block(0, "pos")\n            out.append(\n                ForwardEstimate',
        ),
        ONLINE_FWD,
        "index",
    ),
    M(
        "drift-xy-cross-swapped",
        HD,
        (
            "p[0, j] += ax * p[2, j]\n            p[1, j] += ay * p[2, j]",
            "p[0, j] += ay * p[2, j]\n            p[1, j] += ax * p[2, j]",
        ),
        NAV_HD,
        "swapped arguments",
    ),
    M(
        "drift-psi-bias-term",
        HD,
        ("p[2, j] += dt * p[3, j] + turn * p[4, j]", "p[2, j] += turn * p[4, j]"),
        NAV_HD,
        "missing term",
    ),
    M(
        "drift-scale-turn-missing",
        HD,
        ("p[i, 2] += dt * p[i, 3] + turn * p[i, 4]", "p[i, 2] += dt * p[i, 3]"),
        NAV_HD,
        "missing term",
    ),
    M(
        "drift-turn-shorter-way",
        HD,
        ("    if w < 0.0:\n        w, x, y, z = -w, -x, -y, -z\n", ""),
        NAV_HD,
        "missing term",
    ),
    M(
        "drift-start-offset",
        HD,
        ("for k in range(start + 1, len(t)):", "for k in range(start, len(t)):"),
        NAV_HD,
        "off-by-one",
    ),
    M("drift-ddof0", HD, ("np.var(used, axis=0, ddof=1)", "np.var(used, axis=0)"), NAV_HD, "biased estimator"),
    M(
        "drift-still-unfiltered",
        HD,
        (
            "    if still.sum() < MIN_STILL_SAMPLES:  # as align_at_rest: then the whole range is used\n"
            "        still[:] = True",
            "    still[:] = True",
        ),
        NAV_HD,
        "missing term",
    ),
    M(
        "floors-upper-median",
        FL,
        ("return 0.5 * (zs[first + (n - 1) // 2] + zs[first + n // 2])", "return zs[first + n // 2]"),
        NAV_FL,
        "statistic",
    ),
    M(
        "floors-flight-sign-kept",
        FL,
        ("if np.sign(rise_m[j]) != sign:", "if np.sign(rise_m[j]) == sign:"),
        NAV_FL,
        "operator",
    ),
    M(
        "floors-floor-one-sided",
        FL,
        ("if abs(rise) >= FLOOR_MIN_RISE_M else 0", "if rise >= FLOOR_MIN_RISE_M else 0"),
        NAV_FL,
        "one-sided",
    ),
    M(
        "floors-stair-one-sided",
        FL,
        (
            "return (np.abs(rise) >= level_rise_max_m) & (np.isnan(swing) | agree)",
            "return (rise >= level_rise_max_m) & (np.isnan(swing) | agree)",
        ),
        NAV_FL,
        "one-sided",
    ),
    M(
        "floors-landing-boundary",
        FL,
        ("while j < n and gap <= LANDING_STRIDES:", "while j < n and gap < LANDING_STRIDES:"),
        NAV_FL,
        "boundary",
    ),
    M(
        "floors-descent-sign",
        FL,
        (
            "descent_m=float(-np.sum(np.where(stair & (rise < 0), rise, 0.0)))",
            "descent_m=float(np.sum(np.where(stair & (rise < 0), rise, 0.0)))",
        ),
        NAV_FL,
        "sign",
    ),
    M(
        "dd-straight-either-side",
        DD,
        ("& (turn_in < limit) & (turn_out < limit)", "& ((turn_in < limit) | (turn_out < limit))"),
        NAV_DD,
        "and/or",
    ),
    M(
        "dd-refusal-and",
        DD,
        (
            "if strength < min_strength or straight.sum() < min_stretch_strides:",
            "if strength < min_strength and straight.sum() < min_stretch_strides:",
        ),
        NAV_DD,
        "or/and",
    ),
    M(
        "dd-gate-one-sided",
        DD,
        ("use = straight & (np.abs(off) < np.radians(gate_deg))", "use = straight & (off < np.radians(gate_deg))"),
        NAV_DD,
        "one-sided",
    ),
    M(
        "dd-turn-velocity-sign",
        HT,
        (
            "vel = np.column_stack([c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1], v[:, 2]])",
            "vel = np.column_stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1], v[:, 2]])",
        ),
        NAV_DD,
        "sign",
    ),
    M("dd-turn-attitude-sign", HT, ("half = -0.5 * dpsi", "half = 0.5 * dpsi"), NAV_DD, "sign"),
    M(
        "dd-stretch-length",
        DD,
        ("if j - k + 1 >= min_stretch_strides:", "if j - k >= min_stretch_strides:"),
        NAV_DD,
        "off-by-one",
    ),
    M(
        "imu-rest-warn-one-sided",
        IC,
        ("if abs(off) > ACC_REST_WARN_FRACTION:", "if off > ACC_REST_WARN_FRACTION:"),
        TYPES_IC,
        "one-sided",
    ),
    M(
        "imu-rest-error-one-sided",
        IC,
        ("if abs(off) > ACC_REST_ERROR_FRACTION:", "if off > ACC_REST_ERROR_FRACTION:"),
        TYPES_IC,
        "one-sided",
    ),
    M(
        "imu-rest-all-samples",
        IC,
        ("g_rest = float(np.median(acc_norm[rest]))", "g_rest = float(np.median(acc_norm))"),
        TYPES_IC,
        "missing term",
    ),
    M(
        "imu-gyr-unit-or",
        IC,
        (
            "if moving >= ACC_MOVING_FRACTION and n_moving >= max(10, 0.2 * rate) and w_peak",
            "if moving >= ACC_MOVING_FRACTION or n_moving >= max(10, 0.2 * rate) and w_peak",
        ),
        TYPES_IC,
        "and/or",
    ),
    M(
        "gait-second-pass-or",
        GC,
        ("if stride_fraction > 0 and m >= 3:", "if stride_fraction > 0 or m >= 3:"),
        NAV_SC + ["tests/detectors/test_adaptive.py"],
        "and/or",
    ),
    # -- issue 37: strides (standstill strides), metrics (height), the truth checks before metrics --
    M(
        "strides-standstill-and",
        ST,
        ("return touches_long | long_duration", "return touches_long & long_duration"),
        STRIDES_NEW,
        "or/and",
    ),
    M(
        "strides-standstill-mean",
        ST,
        (
            "long_stance = stance_s > STANDSTILL_STANCE_FACTOR * np.median(stance_s)",
            "long_stance = stance_s > STANDSTILL_STANCE_FACTOR * np.mean(stance_s)",
        ),
        STRIDES_NEW,
        "statistic",
    ),
    M(
        "strides-standstill-k0-side",
        ST,
        ('k0 = np.searchsorted(iv[:, 0], i0, side="right") - 1', 'k0 = np.searchsorted(iv[:, 0], i0, side="left") - 1'),
        STRIDES_NEW,
        "boundary",
    ),
    M(
        "metrics-height-rmse-offset",
        MET_TR,
        ("return float(np.sqrt(np.mean((d - d.mean()) ** 2)))", "return float(np.sqrt(np.mean(d**2)))"),
        METRICS_NEW,
        "missing term",
    ),
    M(
        "truth-coverage-and",
        TC,
        ("if n_in < 2 or coverage < COVERAGE_MIN:", "if n_in < 2 and coverage < COVERAGE_MIN:"),
        TRUTH,
        "or/and",
    ),
    M(
        "truth-scale-or",
        TC,
        (
            "if ratio > SCALE_ERROR_RATIO and speed > MAX_FOOT_SPEED_MPS:",
            "if ratio > SCALE_ERROR_RATIO or speed > MAX_FOOT_SPEED_MPS:",
        ),
        TRUTH,
        "and/or",
    ),
    M(
        "truth-scale-warn-one-sided",
        TC,
        ("if ratio > SCALE_WARN_RATIO or ratio < 1.0 / SCALE_WARN_RATIO:", "if ratio > SCALE_WARN_RATIO:"),
        TRUTH,
        "one-sided",
    ),
    # -- issue 37: data/results.py, data/io/pyshoe.py ----------------------------------------------
    M(
        "results-right-stance-left",
        RES,
        (
            '_write_trajectory(traj, stance.mask, tmp / f"{foot}.csv")',
            '_write_trajectory(traj, result.stance_left.mask, tmp / f"{foot}.csv")',
        ),
        DATA_RES,
        "wrong variable",
    ),
    M(
        "results-jsonable-or",
        RES,
        (
            "if isinstance(value, float) and not np.isfinite(value):",
            "if isinstance(value, float) or not np.isfinite(value):",
        ),
        DATA_RES,
        "and/or",
    ),
    M(
        "results-velocity-column",
        RES,
        (
            "[traj.t, traj.position, traj.velocity, traj.quaternion",
            "[traj.t, traj.position, traj.position, traj.quaternion",
        ),
        DATA_RES,
        "wrong variable",
    ),
    M(
        "pyshoe-rest-one-sided",
        PYS,
        (
            "np.abs(np.linalg.norm(acc, axis=1) - GRAVITY_MPS2) < REST_ACC_TOL_MPS2",
            "(np.linalg.norm(acc, axis=1) - GRAVITY_MPS2) < REST_ACC_TOL_MPS2",
        ),
        DATA_PYS,
        "one-sided",
    ),
    M(
        "pyshoe-rest-or",
        PYS,
        (
            "rest = (np.linalg.norm(gyr, axis=1) < REST_GYR_RADPS) & (",
            "rest = (np.linalg.norm(gyr, axis=1) < REST_GYR_RADPS) | (",
        ),
        DATA_PYS,
        "and/or",
    ),
    # -- issue 37: pipeline/online_checks.py (the live stream's input checks) -----------------------
    M(
        "online-check-moving-one-sided",
        OCH,
        (
            "moving = int(np.count_nonzero(np.abs(norm - np.median(norm)) > ACC_MOVING_MPS2))",
            "moving = int(np.count_nonzero(norm - np.median(norm) > ACC_MOVING_MPS2))",
        ),
        ONLINE_CHECKS,
        "one-sided",
    ),
    M(
        "online-check-standing-and",
        OCH,
        (
            "if moving < max(10, 0.2 / median_dt) or moving < ACC_MOVING_FRACTION * len(norm):",
            "if moving < max(10, 0.2 / median_dt) and moving < ACC_MOVING_FRACTION * len(norm):",
        ),
        ONLINE_CHECKS,
        "or/and",
    ),
    M(
        "online-check-window-due-and",
        OCH,
        (
            "if t_now - t_first < CHECK_WINDOW_S or t_now - self._window_tried < 1.0:",
            "if t_now - t_first < CHECK_WINDOW_S and t_now - self._window_tried < 1.0:",
        ),
        ONLINE_CHECKS,
        "or/and",
    ),
]

#: Mutants of the last rounds, runnable together (``--group NAME``). ``issue37``: the mutants written
#: for the code added since the second round (from ``final-rest-or-and`` on) and the 16 of the
#: earlier rounds whose snippets the refactors since rewrote (ported to the current code).
PORTED_ISSUE37 = (
    "ins-update-r-as-std",
    "ins-update-dx-sign",
    "smooth-caller-updates-order",
    "smooth-step-h-sign",
    "smooth-keep-threshold",
    "win-gravity-literal",
    "thr-min-stance-boundary",
    "thr-min-swing-boundary",
    "range-anchor-swapped",
    "step-vector-theta-half",
    "step-vector-pendulum-factor",
    "step-vector-frame-dropped",
    "step-vector-heel-strike-boundary",
    "particle-update-late",
    "particle-foot-offset-sign",
    "joint-alone-rotation-transposed",
)
_FIRST_ISSUE37 = [m.name for m in MUTANTS].index("final-rest-or-and")
GROUPS: dict[str, list[str]] = {
    "issue37": [m.name for m in MUTANTS if m.name in PORTED_ISSUE37] + [m.name for m in MUTANTS[_FIRST_ISSUE37:]]
}

#: Mutants that cannot change any result, with the reason (reported, not counted as survivors to kill).
EQUIVALENT: dict[str, str] = {
    "smooth-initial-position-sign": "P0 has zero position rows in every footnav start (the start position defines the "
    "frame), so d = P0 mu has d[6:9] = 0 and its sign cannot matter",
    "smooth-keep-threshold": "which segments the whole-walk smoother keeps in memory is a memory policy: kept and "
    "replayed segments smooth exactly alike (tests/estimators/test_ins_filter.py)",
    "dual-gait-opening-flat": "a flat zone at sample 0 has no swing peak at or before it (find_peaks never reports "
    "the first sample), so j = -1 and it is dropped either way",
    "dual-gait-first-peak": "in practice: the pitch rate has a toe-off and a mid-swing peak, so the first landing's "
    "last peak has j >= 1; j = 0 needs a recording that starts inside the first swing",
    "hmm-position-centre": "in practice: +0.5 moves every state's mean position within a segment by the same "
    "0.5 / L; only their order is used, and it changes only for states closer than that",
}


# -- running ----------------------------------------------------------------------------------------


def apply(mutant: Mutant, root: Path) -> None:
    """Edit ``mutant.path`` under ``root``; ValueError when a snippet is missing or ambiguous."""
    path = root / mutant.path
    text = path.read_text(encoding="utf-8")
    for edit in mutant.edits:
        old, new = edit[0], edit[1]
        count = text.count(old)
        if len(edit) == 3:
            nth = edit[2]
            if count <= nth:
                raise ValueError(f"{mutant.name}: occurrence {nth} of {old!r} not in {mutant.path} ({count} found)")
            at = -1
            for _ in range(nth + 1):
                at = text.index(old, at + 1)
        else:
            if count != 1:
                raise ValueError(f"{mutant.name}: {old!r} occurs {count} times in {mutant.path}, expected once")
            at = text.index(old)
        text = text[:at] + new + text[at + len(old) :]
    path.write_text(text, encoding="utf-8")


def export(repo: Path, dest: Path, overlay: list[str]) -> None:
    """``git archive HEAD`` of ``repo`` into ``dest``, then the ``overlay`` paths from the working tree."""
    archive = subprocess.run(["git", "-C", str(repo), "archive", "HEAD"], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    for rel in overlay:
        src = repo / rel
        if src.is_dir():
            shutil.copytree(src, dest / rel, dirs_exist_ok=True, ignore=shutil.ignore_patterns("__pycache__"))
        else:
            (dest / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / rel)


def _env(copy: Path) -> dict[str, str]:
    """The copy's footnav first on the path (before an editable install of the checkout), its own
    numba cache."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH",)}
    env["NUMBA_CACHE_DIR"] = str(copy / ".numba-cache")
    env["PYTHONPATH"] = str(copy)
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def imports_the_copy(copy: Path) -> bool:
    """True when ``import footnav`` in the copy's environment loads the copy, not the checkout."""
    code = "import footnav, sys; print(footnav.__file__)"
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=copy, env=_env(copy), capture_output=True, text=True, check=True
    )
    return Path(out.stdout.strip()).resolve().is_relative_to(copy.resolve())


#: The test runs in progress (each in its own session): ended with the run (SIGTERM, Ctrl-C), so
#: none outlives its removed copy.
_RUNNING: set[subprocess.Popen] = set()


def _end_running() -> None:
    for proc in list(_RUNNING):
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass


def run_tests(copy: Path, tests: list[str], timeout_s: float) -> tuple[str, float, str]:
    """Run ``tests`` in ``copy`` with its own numba cache: (outcome, seconds, last output)."""
    env = _env(copy)
    paths = sorted({p for p in tests if (copy / p).exists()}, key=tests.index)
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", *paths]
    start = time.monotonic()
    proc = subprocess.Popen(
        cmd, cwd=copy, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
    )
    _RUNNING.add(proc)
    try:
        out, _ = proc.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, _ = proc.communicate()
        return "timeout", time.monotonic() - start, out[-2000:]
    finally:
        _RUNNING.discard(proc)
    seconds = time.monotonic() - start
    if proc.returncode == 0:
        return "survived", seconds, out[-2000:]
    if proc.returncode == 1:
        return "killed", seconds, out[-2000:]
    return "killed", seconds, f"pytest exit {proc.returncode}\n" + out[-2000:]  # errors at collection count too


def run_one(mutant: Mutant | None, base: Path, workdir: Path, timeout_s: float, tests: list[str] | None = None) -> dict:
    copy = Path(tempfile.mkdtemp(prefix="mutant-", dir=workdir))
    try:
        shutil.copytree(base, copy, dirs_exist_ok=True)
        if mutant is not None:
            apply(mutant, copy)
        outcome, seconds, tail = run_tests(copy, tests or mutant.tests, timeout_s)
    finally:
        shutil.rmtree(copy, ignore_errors=True)
    name = mutant.name if mutant else "baseline"
    return {
        "name": name,
        "path": mutant.path if mutant else "",
        "kind": mutant.kind if mutant else "",
        "outcome": outcome,
        "seconds": round(seconds, 1),
        "tail": tail,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--list", action="store_true", help="list the mutants and exit")
    parser.add_argument("--check", action="store_true", help="check that every mutant applies to HEAD, run nothing")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="run these mutants only")
    parser.add_argument("--group", choices=sorted(GROUPS), help="run this group of mutants only (see GROUPS)")
    parser.add_argument(
        "-j", "--jobs", type=int, default=2, help="mutants run at once (default 2; each compiles numba kernels)"
    )
    parser.add_argument("--timeout", type=float, default=600.0, help="seconds per mutant before it counts as a timeout")
    parser.add_argument(
        "--overlay", nargs="*", default=[], metavar="PATH", help="working-tree paths copied over HEAD in each copy"
    )
    parser.add_argument("--no-baseline", action="store_true", help="skip the unmutated run")
    parser.add_argument(
        "--tests", nargs="+", metavar="PATH", help="run these tests for every mutant instead of its subset"
    )
    parser.add_argument("--json", type=Path, help="write every outcome here")
    args = parser.parse_args(argv)

    mutants = MUTANTS
    names = [m.name for m in MUTANTS]
    if len(set(names)) != len(names):
        raise SystemExit("duplicate mutant names")
    if args.group:
        args.only = [*(args.only or []), *GROUPS[args.group]]
    if args.only:
        unknown = set(args.only) - set(names)
        if unknown:
            raise SystemExit(f"unknown mutants: {', '.join(sorted(unknown))}")
        mutants = [m for m in MUTANTS if m.name in args.only]
    if args.list:
        for m in mutants:
            print(f"{m.name:40s} {m.path:38s} {m.kind}")
        print(f"{len(mutants)} mutants in {len({m.path for m in mutants})} files")
        return 0

    signal.signal(
        signal.SIGTERM, lambda *_: (_end_running(), sys.exit(143))
    )  # so the copies are removed (finally below)
    workdir = Path(tempfile.mkdtemp(prefix="footnav-mutate-"))
    try:
        base = workdir / "base"
        base.mkdir()
        export(ROOT, base, args.overlay)
        if args.check:
            bad = 0
            for m in mutants:
                scratch = workdir / "check"
                shutil.rmtree(scratch, ignore_errors=True)
                (scratch / m.path).parent.mkdir(parents=True)
                shutil.copy2(base / m.path, scratch / m.path)
                try:
                    apply(m, scratch)
                except ValueError as exc:
                    print(exc)
                    bad += 1
            print(f"{len(mutants) - bad} of {len(mutants)} mutants apply")
            return 1 if bad else 0
        t0 = time.monotonic()
        if not imports_the_copy(base):
            raise SystemExit("import footnav in the copy loads another footnav: the mutants would not be tested")
        if not args.no_baseline:
            every = args.tests or sorted({p for m in mutants for p in m.tests})
            base_run = run_one(None, base, workdir, 4 * args.timeout, every)
            print(f"baseline: {base_run['outcome']} in {base_run['seconds']} s", flush=True)
            if base_run["outcome"] != "survived":
                print(base_run["tail"])
                print("the unmutated copy fails its tests: fix that first")
                return 2
        results = []
        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = [pool.submit(run_one, m, base, workdir, args.timeout, args.tests) for m in mutants]
            for fut in as_completed(futures):
                r = fut.result()
                results.append(r)
                print(
                    f"[{len(results):3d}/{len(mutants)}] {r['outcome']:8s} {r['seconds']:6.1f} s  {r['name']}",
                    flush=True,
                )
    finally:
        _end_running()
        shutil.rmtree(workdir, ignore_errors=True)
    order = {n: i for i, n in enumerate(names)}
    results.sort(key=lambda r: order[r["name"]])
    detected = [r for r in results if r["outcome"] in ("killed", "timeout")]
    survivors = [r for r in results if r["outcome"] == "survived"]
    score = 100.0 * len(detected) / len(results) if results else float("nan")
    print()
    print(
        f"{len(results)} mutants, {len(detected)} killed "
        f"({sum(r['outcome'] == 'timeout' for r in results)} by timeout), "
        f"{len(survivors)} survived: score {score:.1f} % in {(time.monotonic() - t0) / 60:.1f} min"
    )
    for r in survivors:
        why = EQUIVALENT.get(r["name"], "")
        print(f"  survived: {r['name']} ({r['path']}){'  equivalent: ' + why if why else ''}")
    if args.json:
        args.json.write_text(json.dumps({"score_percent": score, "results": results}, indent=1), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
