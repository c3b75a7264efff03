"""Regenerate docs/papers.md: each of the four papers footnav implements, its experiment rebuilt on
the simulator, run as published and with footnav's own choices, beside the paper's own figures.

Run:  python docs/make_papers.py               (every walk at the paper's length, 5-20 seeds; several minutes)
      python docs/make_papers.py --quick       (shorter walks, one seed, two for one walk; for the tests)
      python docs/make_papers.py --jobs 2      (seeds of a walk on 2 processes)
      python docs/make_papers.py --check       (which sections are stale: a module they ran changed)
      python docs/make_papers.py --only 004    (regenerate these papers' sections, keep the others)

Each section ends with the digests of the footnav modules its experiment ran
(docs/papers_inputs.py); tests/test_docs.py fails when one of them changed since.

Every footnav figure comes from :func:`footnav.evaluate_many` on :func:`footnav.simulate` walks
(one call per seed, so each run's trajectories are at hand for the few figures ``evaluate`` does
not report: the papers' detected-step count, travelled distance, DTW distance to the truth and
maximum deviation ratio) and :meth:`footnav.EvaluationReport.summary` (mean +- std over seeds).
The paper's own figures are typed in from the text of shared/seeds (the table and equation
numbers are given beside each). The page stamps the date, the machine, the versions and the git
state of footnav it ran with.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import subprocess
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))  # this checkout's footnav

# after the sys.path change above, so that this checkout's footnav is the one imported
import footnav  # noqa: E402
from footnav.analysis import metrics  # noqa: E402
from footnav.analysis.evaluation import EvaluationReport, Metric, trajectory_at  # noqa: E402

sys.path.insert(0, str(HERE))  # papers_inputs, also in joblib workers
import papers_inputs  # noqa: E402

#: Rate at which the papers' DTW distance to the truth (Li et al. 2018, Table 2) is computed, Hz.
TRUTH_DTW_RATE_HZ = 1.0


# ---------------------------------------------------------------------------------------------
# what a section is made of
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Walk:
    """A simulated walk: ``footnav.simulate(scenario, **options)``, full and quick."""

    label: str
    scenario: str
    options: dict[str, Any]
    seeds: int
    quick_options: dict[str, Any] | None = None  # None: the same walk in --quick
    quick_seeds: int = 1  # --quick checks that every row is made, not the spread (one walk keeps 2)

    def make(self, quick: bool) -> tuple[dict[str, Any], int]:
        opts = self.options if not quick or self.quick_options is None else self.quick_options
        return opts, self.quick_seeds if quick else self.seeds


@dataclass(frozen=True)
class Row:
    """One row of a paper's table: the paper's figure beside the two footnav configurations."""

    label: str
    paper: str  # as printed in the paper
    metric: str
    foot: str
    walk: str
    paper_pipe: str  # key of Paper.pipelines: the configuration "as published"
    best_pipe: str  # key of Paper.pipelines: footnav's defaults / best choice


@dataclass(frozen=True)
class Paper:
    key: str
    title: str
    reference: str
    did: str
    data: str
    rebuilt: str
    walks: dict[str, Walk]
    pipelines: dict[str, tuple[str, str, str, dict[str, dict[str, Any]]]]
    rows: list[Row]
    verdict: str
    notes: list[str] = field(default_factory=list)

    def pipeline(self, key: str) -> footnav.Pipeline:
        det, est, fus, params = self.pipelines[key]
        return footnav.make_pipeline(det, est, fus, **params)

    def describe(self, key: str) -> str:
        det, est, fus, params = self.pipelines[key]
        bits = [
            f"`{det}`",
            f"`{est}`" + (f" {_params(params.get('estimator_params'))}" if params.get("estimator_params") else ""),
            f"`{fus}`" + (f" {_params(params.get('fusion_params'))}" if params.get("fusion_params") else ""),
        ]
        if params.get("detector_params"):
            bits[0] += f" {_params(params['detector_params'])}"
        return " + ".join(bits)


def _params(p: dict[str, Any]) -> str:
    return "(" + ", ".join(f"{k}={v!r}" for k, v in p.items()) + ")"


def _path_rectangle(width_m: float, height_m: float, laps: int) -> list[tuple[float, float]]:
    """``simulate("path")`` segments: ``laps`` times round a width x height rectangle (left turns),
    starting and ending in the middle of a width side."""
    lap = [(height_m, 90.0), (width_m, 90.0), (height_m, 90.0), (width_m, 90.0)]
    segments = [(width_m / 2, 90.0)] + (lap * laps)[:-1] + [(width_m / 2, 0.0)]
    return segments


def _loop_002(length_m: float, speed_mps: float, laps: int, standstill_s: float) -> dict[str, Any]:
    """A walk of Chistyakov et al. 2021, Table 1: ``laps`` laps of a 2:1 rectangle, ``length_m`` round
    in all, at ``speed_mps`` (stride 1.4 m, the stride period set from the speed)."""
    side = length_m / laps / 6.0
    speed = speed_mps
    return {
        "segments": _path_rectangle(2 * side, side, laps),
        "rate_hz": 125.0,
        "standstill_s": standstill_s,
        "stride_length_m": 1.4,
        "stride_period_s": round(1.4 / speed, 3),
    }


# ---------------------------------------------------------------------------------------------
# the four papers
# ---------------------------------------------------------------------------------------------
#: Zhao et al. 2019 used 400 Hz ADIS16448s on grass, where the feet drift apart by 7-33 m without
#: fusion (Table I); the simulator's gyro with a 10x bias random walk (as in accuracy.md) makes the
#: feet drift apart too. The paper gives no noise figures for its sensor.
SENSOR_001 = {"rate_hz": 400.0, "standstill_s": 8.0, "gyr_bias_walk_radps2_sqrthz": 1e-4}
#: Lee, Cho & Park 2022, Table 1 (Xsens MTw): gyro 0.05 deg/s/sqrt(Hz), acc 0.003 m/s^2/sqrt(Hz), gyro
#: bias stability 20 deg/h (9.7e-5 rad/s), here a bias walk reaching it over the 3-min walk (9.7e-5 /
#: sqrt(180 s) = 7e-6 rad/s^2/sqrt(Hz)); 100 Hz; about 5 s standstill (Sec. 4). The paper's error source
#: (Sec. 2.1): the feet drift in opposite directions (symmetric drift, from the sampling rate), the
#: simulator's mirrored yaw rate (+b left, -b right while the foot moves); b = 6e-4 rad/s gives the
#: standalone errors of Tables 2-3 (total 0.86 / 0.85 m on the straight / square; the paper 0.75 / 0.89 m).
SENSOR_004 = {
    "standstill_s": 5.0,
    "gyr_noise_density_radps_sqrthz": math.radians(0.05),
    "acc_noise_density_mps2_sqrthz": 3e-3,
    "gyr_bias_walk_radps2_sqrthz": 7e-6,
    "mirrored_yaw_rate_radps": 6e-4,
}
#: sigma_sys of eq. 12, which the paper fits to Fig. 2's histogram without giving it: the square's
#: waypoint error falls with it up to 0.1 m and no further (fusion/particle.py docstring).
SIGMA_SYS_004_M = 0.1
SQUARE_SIDE_M = 93.0 / 4  # Sec. 4: "the circumference of the square is about 93 m"

FORWARD = {"smoother": "none"}

ZHAO = Paper(
    key="001",
    title="Zhao et al. 2019: dual-gait analysis and step-vector fusion",
    reference='H. Zhao, Z. Wang, S. Qiu, Y. Shen, L. Zhang, K. Tang and G. Fortino, "Heading drift '
    "reduction for foot-mounted inertial navigation system via multi-sensor fusion and dual-gait "
    'analysis", IEEE Sensors J., 2019, doi:10.1109/JSEN.2018.2866802 (shared/seeds/001).',
    did="One ADIS16448 on each heel (gyro +-1000 deg/s, accelerometer +-18 g, 400 Hz, 330 Hz bandwidth), "
    "calibrated during an ~8 s standstill (Sec. II-A). Dual-gait detector: heel-strike peaks plus "
    "flat-zone ZUPT, a stance ending at the contralateral heel strike (Sec. III-A). A 9-state "
    "error filter per foot [attitude, velocity, position] with one time update and two measurement "
    "updates: ZUPT and the relative position of the feet [step length from the inverted pendulum "
    "S = 2 l sin(theta/2), shoulder width, 0] rotated by the rear foot (eq. 4-7), suspended while "
    "turning. Four subjects: a 100 m straight line (12 walks) and the 346 m periphery of a "
    "105 m x 68 m football pitch, 12 walks clockwise and 12 counter-clockwise, on grass. Metrics "
    "(eq. 8): final foot separation E_s and final position error E_p of each foot, mean +- std "
    "(Table I).",
    data="Not public (no data set is mentioned).",
    rebuilt='`simulate("straight", distance_m=100)` and `simulate("rectangle")` (105 m x 68 m, 346 m '
    "round, CW and CCW, back to the start) at 400 Hz with an 8 s standstill; the simulator's "
    "sensor noise with a 10x gyro bias random walk (1e-4 rad/s^2/sqrt(Hz)) so that independent "
    "feet drift apart as the paper's do. E_s = `final_separation` (3-D), E_p = `end_error_3d` "
    "(start and initial heading aligned, as with the paper's known start).",
    walks={
        "straight": Walk(
            "straight 100 m",
            "straight",
            {"distance_m": 100.0, **SENSOR_001},
            5,
            {"distance_m": 30.0, **SENSOR_001, "rate_hz": 100.0},
        ),
        "cw": Walk(
            "rectangle 105 m x 68 m, CW",
            "rectangle",
            {"direction": "cw", **SENSOR_001},
            5,
            {"width_m": 20.0, "height_m": 10.0, "direction": "cw", **SENSOR_001, "rate_hz": 100.0},
        ),
        "ccw": Walk(
            "rectangle 105 m x 68 m, CCW",
            "rectangle",
            {"direction": "ccw", **SENSOR_001},
            5,
            {"width_m": 20.0, "height_m": 10.0, "direction": "ccw", **SENSOR_001, "rate_hz": 100.0},
        ),
    },
    pipelines={
        "paper-without": ("dual-gait", "ekf", "independent", {"estimator_params": FORWARD}),
        "paper-with": (
            "dual-gait",
            "ekf",
            "step-vector",
            {
                "estimator_params": FORWARD,
                "fusion_params": {
                    "step_length": "pendulum",
                    "leg_length_m": 0.9,
                    "relative_frame": "attitude",
                    "calibration": "standstill",
                },
            },
        ),
        "best-without": ("adaptive", "ekf", "independent", {}),
        "best-with": (
            "adaptive",
            "ekf",
            "step-vector",
            {"fusion_params": {"step_length": "fitted", "relative_frame": "heading"}},
        ),
    },
    rows=[],  # filled below
    verdict="",  # VERDICTS below
)
_TABLE_I = {  # walk: (without E_s, E_p left, E_p right | with E_s, E_p left, E_p right); None: not printed
    "straight": (("7.33 ± 3.31", "4.41 ± 2.21", "2.98 ± 1.45"), ("0.42 ± 0.14", "1.59 ± 0.49", "1.46 ± 0.58")),
    "cw": (("33.18 ± 14.02", "18.95 ± 7.00"), ("0.37 ± 0.09", "2.67 ± 1.05")),
    "ccw": (("31.32 ± 16.34", "14.55 ± 10.09"), ("0.32 ± 0.05", "3.42 ± 1.88")),
}
for _walk, (_without, _with) in _TABLE_I.items():
    for _name, _figs in (("without", _without), ("with", _with)):
        _where = f"{ZHAO.walks[_walk].label}, {_name} relative position updates"
        ZHAO.rows.append(
            Row(f"{_where}: E_s (m)", _figs[0], "final_separation", "both", _walk, f"paper-{_name}", f"best-{_name}")
        )
        if len(_figs) == 3:
            ZHAO.rows.append(
                Row(
                    f"{_where}: E_p left (m)",
                    _figs[1],
                    "end_error_3d",
                    "left",
                    _walk,
                    f"paper-{_name}",
                    f"best-{_name}",
                )
            )
            ZHAO.rows.append(
                Row(
                    f"{_where}: E_p right (m)",
                    _figs[2],
                    "end_error_3d",
                    "right",
                    _walk,
                    f"paper-{_name}",
                    f"best-{_name}",
                )
            )
        else:  # Table I prints one position error for the rectangle rows; footnav: mean of the feet
            ZHAO.rows.append(
                Row(
                    f"{_where}: E_p (m; one figure printed, footnav: mean of the feet)",
                    _figs[1],
                    "end_error_3d",
                    "mean",
                    _walk,
                    f"paper-{_name}",
                    f"best-{_name}",
                )
            )

_T002 = {  # N: (duration s, length m, DTW Alg. [6], DTW Alg. 1, max deviation, max ratio)
    1: (88.3, 71.92, "0.45", "0.09", "0.53", "0.03"),
    4: (215.0, 240.39, "4.93", "0.50", "3.94", "0.04"),
    7: (625.5, 706.68, "13.96", "5.49", "6.01", "0.11"),
}
_LAPS_002 = {1: 1, 4: 3, 7: 8}
CHISTYAKOV = Paper(
    key="002",
    title="Chistyakov et al. 2021: closed-loop EKF + RTS (Alg. 1), GLRT, two-foot DTW fusion (Alg. 2)",
    reference='I. A. Chistyakov, I. V. Grishov, A. A. Nikulin, M. V. Pikhletsky and I. B. Gartsev, "Pedestrian '
    'navigation: how can inertial measurement units assist smartphones?", Russian Technological '
    "J. 9(2), 22-34, 2021, doi:10.32362/2500-316X-2021-9-2-22-34 (in Russian, English abstract; "
    "shared/seeds/002).",
    did="Two MIMU22BLPX units (each an array of four InvenSense MPU-9250) on the instep, streamed over "
    "Bluetooth LE at 125 Hz to a phone (Sec. 5). Standstill by the GLRT statistic T < gamma "
    "(Skog et al. 2010, eq. 4). Alg. 1: an error-state Kalman filter with attitude feedback and an "
    "RTS smoother, ZUPT, and the known start = end position used as a measurement at the final "
    "standstill (closed loop). Alg. 2: both feet in one pass, the other foot's horizontal position "
    "as a measurement at mid-swing, after the initial heading mismatch is found by minimising the "
    "DTW distance between the Alg. 1 tracks. Seven closed walks of 1-10 min (72-707 m; the abstract "
    "says indoors, Sec. 5 that the RTK reference needed open sky). Metrics: the banded DTW distance "
    "between the two feet's tracks (Table 1: Kalman filter + smoother [6] vs Alg. 1) and the "
    "maximum deviation of Alg. 2 from an RTK GNSS track on the helmet, with the maximum ratio of "
    "deviation to the distance walked so far (Table 2).",
    data="The paper names a public data set (gartsev.ru/projects/rtj2021); that host is unreachable "
    "from here and nothing was downloaded.",
    rebuilt="Three of the seven walks (N = 1, 4, 7: the shortest, a middle one and the longest), each "
    'laps of a 2:1 rectangle (`simulate("path", segments=...)`: N1 one lap of 24 m x 12 m, N4 '
    "three laps of 26.7 m x 13.4 m, N7 eight laps of 29.4 m x 14.7 m, indoor-sized) with the "
    "paper's length, at the paper's mean speed (stride period from the duration), 125 Hz, 5 s "
    "standstills; the simulator's default sensor noise (the paper gives no noise figures). DTW "
    "= `dtw_distance_feet` (mean per matched pair at 10 Hz, 2 s band), max deviation = "
    "`max_deviation_2d` of the worse foot against its own truth (the paper compares the averaged "
    "track with an antenna on the helmet), ratio = `metrics.max_deviation(...).max_ratio` "
    "(deviation / distance so far, after the first 5 m).",
    walks={
        f"N{n}": Walk(
            f"walk N{n}: {d:g} s, {length:g} m ({_LAPS_002[n]} lap{'s' * (_LAPS_002[n] > 1)})",
            "path",
            _loop_002(length, length / (d - 10.0), _LAPS_002[n], 5.0),
            5,
            _loop_002(length / (4 if n == 1 else 8), length / (d - 10.0), 1, 5.0),
        )
        for n, (d, length, *_r) in _T002.items()
    },
    pipelines={
        "paper-alg6": ("glrt", "ekf", "independent", {"estimator_params": {"smoother": "whole", "closed_loop": False}}),
        "paper-alg1": ("glrt", "ekf", "independent", {"estimator_params": {"smoother": "whole", "closed_loop": True}}),
        "paper-alg2": (
            "glrt",
            "ekf",
            "dtw",
            {
                "estimator_params": {"smoother": "whole", "closed_loop": True},
                "fusion_params": {"heading_tracks": "smoothed"},
            },
        ),
        "best-alg6": ("adaptive", "ekf", "independent", {}),
        "best-alg1": ("adaptive", "ekf", "independent", {"estimator_params": {"closed_loop": True}}),
        "best-alg2": ("adaptive", "ekf", "dtw", {"estimator_params": {"closed_loop": True}}),
    },
    rows=[],
    verdict="",
)
for _n, (_d, _l, _dtw6, _dtw1, _dev, _ratio) in _T002.items():
    _w = f"N{_n}"
    CHISTYAKOV.rows.extend(
        [
            Row(
                f"walk N{_n}, Table 1: DTW distance between the feet, Kalman filter + RTS [6] (m)",
                _dtw6,
                "dtw_distance_feet",
                "both",
                _w,
                "paper-alg6",
                "best-alg6",
            ),
            Row(
                f"walk N{_n}, Table 1: DTW distance between the feet, Alg. 1 (closed loop) (m)",
                _dtw1,
                "dtw_distance_feet",
                "both",
                _w,
                "paper-alg1",
                "best-alg1",
            ),
            Row(
                f"walk N{_n}, Table 2: maximum deviation, Alg. 2 (m; footnav: worse foot)",
                _dev,
                "max_deviation_2d",
                "worse",
                _w,
                "paper-alg2",
                "best-alg2",
            ),
            Row(
                f"walk N{_n}, Table 2: max ratio of deviation to distance walked, Alg. 2 (footnav: worse foot)",
                _ratio,
                "max_deviation_ratio",
                "worse",
                _w,
                "paper-alg2",
                "best-alg2",
            ),
        ]
    )

#: Li et al. 2018's course: 1075 m of road (the shape is not given; this one has five turns and
#: does not return to its start), 729 steps per foot (Sec. 4) -> stride 1.475 m.
SEGMENTS_003 = [(250.0, 90.0), (120.0, 90.0), (180.0, -90.0), (80.0, -90.0), (200.0, 90.0), (245.0, 0.0)]
LI = Paper(
    key="003",
    title="Li, Derrode et al. 2018: HMM stance detection, Madgwick + 9-state KF",
    reference='H. Li, S. Derrode, L. Benyoussef and W. Pieczynski, "Unsupervised pedestrian trajectory '
    'reconstruction from IMU sensors", TAIMA 2018, hal-01786223 (shared/seeds/003).',
    did="One Shimmer3 on a shoe (accelerometer +-8 g, gyro +-1000 deg/s, magnetometer 2.5 Ga), 100 Hz, "
    "a short standstill first (Sec. 4). Stance by a cyclic left-to-right 4-state HMM on the 3-axis "
    "gyro, K-means initialisation re-ordered into the gait cycle, Baum-Welch (Sec. 2); orientation "
    "by Madgwick's gradient descent and a 9-state error KF [position, velocity, acceleration] (GDA, "
    "Sec. 3), against a threshold detector [3] and a 15-state INS-EKF-ZUPT (IEZ). One 1075 m walk "
    "on a road, truth from OpenStreetMap. Metrics: steps detected / missed / false (Table 1; 729 "
    "true steps per foot) and end-to-end error, travelled distance and its error, DTW distance to "
    "the truth (Table 2).",
    data="Not public (no data set is mentioned).",
    rebuilt='A 1075 m walk (`simulate("path")`, five 90 deg turns, not closed: the paper\'s course '
    "shape is not given) with a stride of 1075/729 m so that each foot makes about 729 steps, "
    "100 Hz, the simulator's default noise and 2 s standstills; the left foot is scored (the "
    "paper had one sensor). Detected steps = `steps_found + steps_false`; travelled distance = "
    "the 2-D reference length x (1 + `travelled_distance_error_percent` / 100); end-to-end = "
    "`end_error_2d` and `end_error_2d_percent`; DTW = `metrics.dtw_distance(..., "
    'normalize="none")` of the start-aligned 2-D track against the truth at 1 Hz (an '
    "unnormalised sum like the paper's; its sample rate is not given, so the figures are not "
    "comparable in scale). `--quick` walks 150 m.",
    walks={
        "road": Walk(
            "1075 m road",
            "path",
            {"segments": SEGMENTS_003, "stride_length_m": 1075 / 729},
            5,
            {"segments": [(60.0, 90.0), (40.0, -90.0), (50.0, 0.0)], "stride_length_m": 1075 / 729},
        )
    },
    pipelines={
        "hmm+gda": ("hmm", "madgwick", "independent", {}),
        "threshold+gda": ("threshold", "madgwick", "independent", {}),
        "hmm+iez": ("hmm", "ekf", "independent", {"estimator_params": {"bias_states": True, "smoother": "none"}}),
        "best": ("adaptive", "ekf", "independent", {}),
    },
    rows=[
        Row(
            "Table 1, LR-HMM: steps detected (729 true in the paper)",
            "735",
            "steps_detected",
            "left",
            "road",
            "hmm+gda",
            "best",
        ),
        Row("Table 1, LR-HMM: steps missed", "0", "steps_missed", "left", "road", "hmm+gda", "best"),
        Row("Table 1, LR-HMM: false detections", "6 (0.823 %)", "steps_false", "left", "road", "hmm+gda", "best"),
        Row("Table 1, threshold [3]: steps detected", "724", "steps_detected", "left", "road", "threshold+gda", "best"),
        Row("Table 1, threshold [3]: steps missed", "17", "steps_missed", "left", "road", "threshold+gda", "best"),
        Row(
            "Table 1, threshold [3]: false detections",
            "14 (1.920 %)",
            "steps_false",
            "left",
            "road",
            "threshold+gda",
            "best",
        ),
    ],
    verdict="",
)
for _label, _pipe, _figs in (
    ("HMM+GDA", "hmm+gda", ("23.31", "2.16", "1077.69", "0.25", "8784")),
    ("Threshold+GDA", "threshold+gda", ("24.76", "2.30", "1131.19", "5.22", "8617")),
    ("HMM+IEZ", "hmm+iez", ("16.11", "1.49", "1078.52", "0.32", "12809")),
):
    LI.rows.extend(
        [
            Row(f"Table 2, {_label}: end-to-end error (m)", _figs[0], "end_error_2d", "left", "road", _pipe, "best"),
            Row(
                f"Table 2, {_label}: end-to-end error (% of distance)",
                _figs[1],
                "end_error_2d_percent",
                "left",
                "road",
                _pipe,
                "best",
            ),
            Row(
                f"Table 2, {_label}: travelled distance (m; truth 1075)",
                _figs[2],
                "travelled_distance_2d",
                "left",
                "road",
                _pipe,
                "best",
            ),
            Row(
                f"Table 2, {_label}: travelled distance error (%)",
                _figs[3],
                "travelled_distance_error_percent",
                "left",
                "road",
                _pipe,
                "best",
            ),
            Row(
                f"Table 2, {_label}: DTW distance to the truth (sum; footnav at 1 Hz, m)",
                _figs[4],
                "dtw_distance_truth",
                "left",
                "road",
                _pipe,
                "best",
            ),
        ]
    )

LEE = Paper(
    key="004",
    title="Lee, Cho & Park 2022: particle-filter dual-foot PDR with lateral drift",
    reference='J. H. Lee, S. Y. Cho and C. G. Park, "Dual foot-PDR system considering lateral position '
    'error characteristics", J. Position. Navig. Timing, 2022 (shared/seeds/004).',
    did="An Xsens MTw on the outside of each shoe, at the rear (Table 1: gyro noise 0.05 deg/s/sqrt(Hz), "
    "bias stability 20 deg/h, accelerometer noise 0.003 m/s^2/sqrt(Hz)), 100 Hz, gyro bias from about "
    "5 s of standstill (Sec. 4). Zero velocity by a threshold detector (Lee et al. 2012). Each foot: "
    "an EKF without horizontal position (eq. 3) and a 100-particle filter for it, propagated with "
    "the velocity covariance and an offset-Rayleigh lateral drift (eq. 10-12); the two clouds are "
    "fused by a Gaussian sum (eq. 13-14), which each filter takes as a measurement at the end of each "
    "zero-velocity phase (eq. 15-16). Baselines: standalone feet and a range constraint (Prateek et "
    "al. 2013). Walks: 70 m straight (20 times), a square 93 m round with three turns back to the "
    "start, about 3 min (6 times, 3 each way), a 300 m corridor loop (3 people x 3). Metrics: final "
    "position error (straight, Table 2), mean waypoint error (square, Table 3), position error of "
    "the long loop (Table 4; the text gives the return error, about 1.5 m), left and right.",
    data="Not public (no data set is mentioned).",
    rebuilt='`simulate("straight", distance_m=70)`; the square of `benchmarks/bench_particle.py --square` '
    '(`simulate("path")`, 23.25 m sides from the middle of a side, three laps, back to the start; '
    '`--quick`: one lap); `simulate("rectangle", width_m=100, height_m=50)` for the 300 m loop '
    "(`--quick`: 40 m x 20 m); 100 Hz, the MTw's noise densities, its 20 deg/h bias stability as a "
    "gyro bias random walk of 7e-6 rad/s^2/sqrt(Hz) (reached over the 3-min walk), 5 s standstill, and "
    "the paper's error source, the feet drifting in opposite directions (Sec. 2.1): "
    "`mirrored_yaw_rate_radps=6e-4` (+b on the left foot's yaw rate, -b on the right's while the foot "
    "moves), which gives the standalone totals of Tables 2-3. Errors as the paper measured them: each "
    "track turned onto the walking direction by its first five steps (Sec. 2.1; "
    "`metrics.align_on_first_steps`), then the final error (`end_error_2d_5steps`, Table 2), the mean "
    "error at the corners the simulator marks (`waypoint_error_5steps`, Table 3) and their *total*, "
    "both feet averaged. Table 4 keeps `end_error_2d` (start-aligned on 2 m). Paper-mode estimators "
    "run forward only (the paper smooths nothing); the range constraint is footnav's `range` with "
    "its defaults (1 m). `sigma_sys_m` (eq. 12) is not given by the paper (fitted to Fig. 2); 0.1 m.",
    walks={
        "straight": Walk("straight 70 m", "straight", {"distance_m": 70.0, **SENSOR_004}, 20, quick_seeds=2),
        "square": Walk(
            "square 93 m, three laps",
            "path",
            {"segments": _path_rectangle(SQUARE_SIDE_M, SQUARE_SIDE_M, 3), **SENSOR_004},
            6,
            {"segments": _path_rectangle(SQUARE_SIDE_M, SQUARE_SIDE_M, 1), **SENSOR_004},
        ),
        "long": Walk(
            "loop 300 m",
            "rectangle",
            {"width_m": 100.0, "height_m": 50.0, **SENSOR_004},
            9,
            {"width_m": 40.0, "height_m": 20.0, **SENSOR_004},
        ),
    },
    pipelines={
        "paper-standalone": ("threshold", "ekf", "independent", {"estimator_params": FORWARD}),
        "paper-range": ("threshold", "ekf", "range", {"estimator_params": FORWARD}),
        "paper-proposed": (
            "threshold",
            "ekf",
            "particle",
            {"estimator_params": FORWARD, "fusion_params": {"mode": "paper", "sigma_sys_m": SIGMA_SYS_004_M}},
        ),
        "paper-fused": (
            "threshold",
            "ekf",
            "particle",
            {
                "estimator_params": FORWARD,
                "fusion_params": {"mode": "paper", "sigma_sys_m": SIGMA_SYS_004_M, "likelihood_cov": "fused"},
            },
        ),
        "best-standalone": ("adaptive", "ekf", "independent", {}),
        "best-range": ("adaptive", "ekf", "range", {}),
        "best-proposed": ("adaptive", "ekf", "particle", {"fusion_params": {"mode": "footnav"}}),
    },
    rows=[],
    verdict="",
)
#: Tables 2-3 of Lee, Cho & Park 2022: (left, right); the total is their mean (both feet averaged).
for _walk, _metric, _table, _figs in (
    (
        "straight",
        "end_error_2d_5steps",
        "Table 2 (straight), final position error",
        {
            "standalone": ("0.52 ± 0.32", "0.97 ± 0.33"),
            "range": ("0.40 ± 0.23", "0.82 ± 0.21"),
            "proposed": ("0.48 ± 0.13", "0.55 ± 0.18"),
            "fused": None,
        },
    ),
    (
        "square",
        "waypoint_error_5steps",
        "Table 3 (square), mean waypoint error",
        {
            "standalone": ("0.50 ± 0.55", "1.28 ± 1.46"),
            "range": ("0.46 ± 0.61", "0.40 ± 0.68"),
            "proposed": ("0.32 ± 0.53", "0.31 ± 0.54"),
            "fused": None,
        },
    ),
    (
        "long",
        "end_error_2d",
        "Table 4 (300 m loop), return position error",
        {"proposed": ("1.58 ± 0.97", "1.53 ± 1.01")},
    ),
):
    for _method, _lr in _figs.items():
        if _lr is None:  # the other reading of eq. 15: no figure of its own in the paper
            _lr, _best = ("(proposed)", "(proposed)"), "best-proposed"
            _name = "proposed, eq. 15 with the Gaussian sum's covariance"
        else:
            _best, _name = f"best-{_method}", _method
        _total = "n/a"
        if _lr[0][0].isdigit():
            _total = f"{(float(_lr[0].split()[0]) + float(_lr[1].split()[0])) / 2:.3f}"
        elif _method == "fused":
            _total = "(proposed)"
        _feet = (("left", _lr[0]), ("right", _lr[1])) + ((("total", _total),) if _walk != "long" else ())
        for _foot, _fig in _feet:
            LEE.rows.append(
                Row(f"{_table}, {_name}, {_foot} (m)", _fig, _metric, _foot, _walk, f"paper-{_method}", _best)
            )

PAPERS = [ZHAO, CHISTYAKOV, LI, LEE]


# ---------------------------------------------------------------------------------------------
# running
# ---------------------------------------------------------------------------------------------
def _extra_metrics(report: EvaluationReport, rec: footnav.Recording, pipe_name: str) -> list[Metric]:
    """The figures the papers report that ``evaluate`` does not, from the same run."""
    out: list[tuple[str, str, float, str]] = []

    def value(name: str, foot: str) -> float:
        try:
            return report.value(name, foot, pipeline=pipe_name)
        except KeyError:
            return float("nan")

    result = report.results[(rec.name, pipe_name)]
    feet = [("left", result.left, rec.truth_left)] + (
        [("right", result.right, rec.truth_right)] if result.right is not None else []
    )
    ratios, devs, ends, five = [], [], [], []
    for foot, traj, truth in feet:
        out.append((foot, "steps_detected", value("steps_found", foot) + value("steps_false", foot), "count"))
        ref_len = value("reference_path_length", foot)
        out.append(
            (foot, "travelled_distance_2d", ref_len * (1 + value("travelled_distance_error_percent", foot) / 100), "m")
        )
        est, inside = trajectory_at(traj, truth.t)
        ref = truth.position[inside]
        aligned = metrics.align_at_start(est, ref).aligned
        ratio = metrics.max_deviation(aligned, ref, dims=2).max_ratio
        out.append((foot, "max_deviation_ratio", ratio, ""))
        ratios.append(ratio)
        devs.append(value("max_deviation_2d", foot))
        ends.append(value("end_error_3d", foot))
        step = max(1, round(1.0 / (TRUTH_DTW_RATE_HZ * float(np.median(np.diff(truth.t))))))
        dtw = metrics.dtw_distance(aligned[::step], ref[::step], dims=2, normalize="none")
        out.append((foot, "dtw_distance_truth", float(dtw.total_cost), "m"))
        # Lee, Cho & Park 2022 (Sec. 2.1): each track turned onto the walking direction by its
        # first five steps (align_at_start's first 2 m multiply any sideways move there over the walk)
        landings = np.searchsorted(truth.t[inside], truth.t[truth.events["heel_strike"]])
        on5 = metrics.align_on_first_steps(est, ref, landings).aligned
        wps = truth.meta.get("waypoints_m")
        wp = metrics.waypoint_errors(on5, ref, wps).mean_m if wps is not None and len(wps) else float("nan")
        end5 = float(np.linalg.norm(on5[-1, :2] - ref[-1, :2]))
        five.append((wp, end5))
        out += [(foot, "waypoint_error_5steps", wp, "m"), (foot, "end_error_2d_5steps", end5, "m")]
    out.append(("worse", "max_deviation_2d", float(np.max(devs)), "m"))
    out.append(("worse", "max_deviation_ratio", float(np.max(ratios)), ""))
    out.append(("mean", "end_error_3d", float(np.mean(ends)), "m"))
    # Lee, Cho & Park 2022, Tables 2-3 "total": both feet averaged
    out.append(("total", "waypoint_error_5steps", float(np.mean([w for w, _ in five])), "m"))
    out.append(("total", "end_error_2d_5steps", float(np.mean([e for _, e in five])), "m"))
    return [Metric(rec.name, pipe_name, foot, name, float(v), unit) for foot, name, v, unit in out]


def _one_seed(
    paper: Paper, walk: Walk, opts: dict[str, Any], pipe_keys: list[str], seed: int
) -> tuple[EvaluationReport, set[str]]:
    """One seed's report and the footnav modules it ran (papers_inputs.ModuleTracker)."""
    with warnings.catch_warnings(), papers_inputs.ModuleTracker() as used:
        warnings.simplefilter("ignore")  # stance checks and data notes are recorded in meta
        rec = footnav.simulate(walk.scenario, seed=seed, **opts)
        pipes = {k: paper.pipeline(k) for k in pipe_keys}
        report = footnav.evaluate_many(pipes, [rec])
        extra = [m for k in pipe_keys for m in _extra_metrics(report, rec, k)]
    return EvaluationReport(report.metrics + tuple(extra)), used.files


def run_paper(
    paper: Paper, quick: bool, jobs: int
) -> tuple[dict[tuple[str, str, str, str], tuple[float, float, int]], set[str]]:
    """{(walk, pipeline, foot, metric): (mean, std, n)} over the seeds of each walk, and the
    footnav modules the runs used."""
    out, files = {}, set()
    for wkey, walk in paper.walks.items():
        pipe_keys = sorted({k for r in paper.rows if r.walk == wkey for k in (r.paper_pipe, r.best_pipe)})
        opts, n_seeds = walk.make(quick)
        if jobs > 1:
            from joblib import Parallel, delayed

            runs = Parallel(n_jobs=jobs)(delayed(_one_seed)(paper, walk, opts, pipe_keys, s) for s in range(n_seeds))
        else:
            runs = [_one_seed(paper, walk, opts, pipe_keys, s) for s in range(n_seeds)]
        total = EvaluationReport(())
        for r, used in runs:
            total = total + r
            files |= used
        for row in total.summary():
            out[(wkey, row["pipeline"], row["foot"], row["name"])] = (row["mean"], row["std"], row["n"])
        print(f"  {paper.key} {walk.label}: {n_seeds} seeds x {len(pipe_keys)} pipelines", file=sys.stderr, flush=True)
    return out, files


def _cell(stat: tuple[float, float, int] | None, metric: str) -> str:
    if stat is None:
        return "n/a"
    mean, std, n = stat
    digits = (
        1
        if metric in ("steps_detected", "steps_missed", "steps_false", "travelled_distance_2d", "dtw_distance_truth")
        else 3
        if metric == "max_deviation_ratio"
        else 2
    )
    if metric == "dtw_distance_truth":
        digits = 0
    text = f"{mean:.{digits}f}"
    if n > 1:
        text += f" ± {std:.{digits}f}"
    return text


def section(paper: Paper, stats: dict, quick: bool, files: set[str] = frozenset()) -> list[str]:
    lines = [
        f"## {paper.key}: {paper.title}",
        "",
        f"*{paper.reference}*",
        "",
        f"**What the paper did.** {paper.did}",
        "",
        f"**Data.** {paper.data}",
        "",
        f"**Rebuilt here.** {paper.rebuilt}",
        "",
    ]
    lines += ["| walk | seeds (full run) |", "|---|---|"]
    for walk in paper.walks.values():
        lines.append(f"| {walk.label} | {walk.seeds} |")
    lines += ["", "Configurations (footnav component names and the parameters that make them):", ""]
    for key in paper.pipelines:
        lines.append(f"- `{key}`: {paper.describe(key)}")
    lines += ["", "| metric | paper's own figure | footnav paper-mode | footnav best |", "|---|---|---|---|"]
    for row in paper.rows:
        p = _cell(stats.get((row.walk, row.paper_pipe, row.foot, row.metric)), row.metric)
        b = _cell(stats.get((row.walk, row.best_pipe, row.foot, row.metric)), row.metric)
        lines.append(f"| {row.label} [`{row.paper_pipe}` / `{row.best_pipe}`] | {row.paper} | {p} | {b} |")
    lines += [""]
    if quick:
        lines += [
            "*(--quick run: shortened walks, one seed (two for one walk); the paragraph below is of the full run.)*",
            "",
        ]
    lines += [f"**What matches, what does not, and why.** {paper.verdict}", ""]
    lines += paper.notes
    lines += [papers_inputs.record(paper.key, set(files)), ""]
    return lines


def stamp() -> str:
    def git(*args: str) -> str:
        try:
            return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=True).stdout.rstrip()
        except (OSError, subprocess.CalledProcessError):
            return "?"

    dirty = [line[3:] for line in git("status", "--porcelain", "--", "footnav").splitlines() if line]
    state = f"git {git('rev-parse', '--short', 'HEAD')}"
    if dirty:
        state += " with uncommitted changes in " + ", ".join(f"`{d}`" for d in dirty)
    return (
        f"Run on {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC on {platform.machine()} "
        f"{platform.system()} {platform.release()} ({os.cpu_count()} CPUs) with footnav {footnav.__version__} "
        f"({state}), Python {platform.python_version()}, numpy {np.__version__}."
    )


INTRO = """# The four papers, rebuilt on the simulator

footnav implements four papers (shared/seeds). For each: what the paper did, its experiment rebuilt
as closely as the simulator allows, run with the paper's configuration ("paper-mode": the
component parameters that make it as published) and with footnav's defaults or best choice
("best"), over several seeds, beside the paper's own figures.

**Read the comparison for what it is.** The simulated walks are not the papers' data: the
simulator's feet are rigid, its ground is flat and hard, its sensor errors are white noise plus
bias random walks, and its heading errors are independent per foot. None of the four data sets is
available here (002 names one, on a host that cannot be reached; nothing was downloaded). The
papers' numbers come from real people, sensors and surfaces; where footnav's number is close it
says the method behaves as described, not that footnav reproduces the paper's result; where it is
far, the paragraph under each table says why as far as we can tell.

Columns: *paper's own figure* as printed (mean ± std over the paper's walks where it gives them);
*footnav paper-mode* and *footnav best*: mean ± std over the seeds of the simulated walk (sample
std). The configuration of each row is named in brackets `[paper-mode / best]` and listed above its
table. Metric names are those of `footnav.evaluate` (definitions in `footnav/analysis/metrics/`).

"""


#: The paragraph under each table. It describes the full run (the figures on this page when it was
#: generated without --quick); rerunning changes the last digits, not the picture.
VERDICTS = {
    "001": (
        "*Matches:* the step-vector update makes the feet end where they should: E_s is 0.21-0.22 m in "
        "every walk, against the true 0.2 m (the simulated step width) and the paper's 0.32-0.42 m; "
        "without it the feet end 2.3 m (straight) and 15-16 m (rectangle) apart, the paper's order of "
        "magnitude (7 m and 31-33 m) but smaller, because the simulated gyro drifts less than the "
        "paper's sensors on grass (the bias walk is our choice; the paper gives no noise figures). On "
        "the straight walk E_p falls a little (1.6 to 1.3-1.4 m in paper mode; the paper: 4.4 / 3.0 to "
        "1.6 / 1.5 m). *Does not match:* on the rectangle the paper's E_p falls from 15-19 m to "
        "2.7-3.4 m, footnav's only from about 10 m to 6.6-7.3 m. In the simulator the two feet's "
        "heading errors are independent random walks: coupling the feet makes them agree (E_s) and "
        "averages their headings, which removes about 1/sqrt(2) of the heading error, not all of it. "
        "The paper's feet drifted in opposite directions (the symmetric drift Lee et al. 2022 "
        "describe), which a relative-position update cancels. *Paper mode against footnav's choices:* "
        "the pendulum step length with the true leg length is short on the simulator (the "
        "`fusion/step_vector.py` docstring: 0.29-0.31 m for 0.70 m steps; the straight walk comes out "
        "about 6 % long in distance travelled on seed 0, 0.1 % with the fitted length), yet E_p "
        "differs by only 0.1-0.4 m, because the update mostly corrects heading, which the step "
        "length hardly affects. Without the update, dual-gait with a forward filter and adaptive "
        "with RTS smoothing give the same figures to 0.02 m: the error is heading drift, which "
        "neither the detector nor the smoother observes."
    ),
    "002": (
        "*Matches:* the ordering within footnav: the closed loop (Alg. 1) brings the feet's tracks "
        "closer on the longest walk (DTW 0.47 to 0.38 m) and the errors grow with the walk's length. "
        "*Does not match:* the size. The paper's Table 1 DTW distances of the open filter are 0.45-14 m "
        "and of Alg. 1 0.09-5.5 m; the simulator's are 0.27-0.47 m, and about 0.2 m of that is the "
        "true distance between the feet (the simulated step width; the paper's 0.09 m for walk 1 "
        "is below any real step width, so its tracks were probably matched or offset in a way the "
        "text does not spell out). The paper's cheap MEMS units and Bluetooth-streamed, "
        "re-synchronised clocks drift far more than the simulator's sensor; with so little drift "
        "there is little for the closed loop to remove, which is why Alg. 1 changes the shorter "
        "walks by 0.01 m. Table 2's maximum deviation of Alg. 2 (0.53-6.0 m, 2-11 % of the distance "
        "so far) against footnav's 0.2-1.9 m (about 1 %) is the same story, and the paper measures "
        "the averaged track against a GNSS antenna on the helmet (about 1 cm RTK, but the head is "
        "not above the feet), footnav each foot against its own exact truth. GLRT against "
        "`adaptive`, and the paper's heading search on the smoothed tracks against footnav's default, "
        "make no measurable difference here (the two columns agree to 0.01 m)."
    ),
    "003": (
        "*Matches:* the travelled distance of HMM+GDA (1089 m, +0.27 %; the paper 1077.7 m, +0.25 %) "
        "and, by chance of the drift, the end-to-end error (about 26 m, 2.4 %; the paper 23.3 m, "
        "2.2 %), though over five seeds the end error ranges widely (std 27 m): it is heading drift, "
        "which varies from walk to walk; the 15-state filter's end error is as wide (24 +- 26 m; the "
        "paper 16 m against 23 m), so five seeds cannot tell the two apart. *Does not match:* stance detection is "
        "perfect on the simulator for the HMM, the threshold detector and `adaptive` alike (738 of "
        "the simulated walk's 738 stance phases per foot, none missed or false), where the paper "
        "counts 6 false HMM detections and 17 missed, 14 false for its threshold detector. Real gait "
        "varies from step to step and the road was not flat; the simulator's walker repeats one "
        "clean step, so Table 1 cannot be reproduced here. The threshold detector's 5 % distance "
        "error in the paper comes from those misses; here it is 0.28 %. The paper's DTW figures are "
        "unnormalised sums at an unstated rate and cannot be compared with footnav's 1 Hz sums. "
        "*The IEZ row's travelled distance:* footnav's forward-only 15-state filter (`ekf` with "
        "`bias_states=True, smoother='none'`) made the per-sample track 18 % longer than the truth "
        "while its velocity integrated to the right length: with loose gyro bias priors (2e-3 rad/s, "
        "walk 1e-4 rad/s^2/sqrt(Hz)) the vertical gyro bias, which a zero-velocity update hardly "
        "observes, carried a heading std of 0.6 rad after 13 minutes, and each stance sample's update "
        "re-placed the position by 1-2 cm through it, back and forth (the stance detector was not the "
        "cause: the HMM's stance equals the truth's here, and `threshold` gave the same 17.5 %). The "
        "prior now comes from the data (the initial standstill's standard error, 1.1e-4 rad/s here) "
        "with the library's gyro walk (1e-5): 1.0 % long (the paper 0.32 %; the 9-state forward "
        "filter 0.3 %). What is left is the same re-placing, smaller; the smoothed filters have none."
    ),
    "004": (
        "*Matches:* with the paper's error source (opposite drifts of the two feet) the standalone feet "
        "err as the paper's (totals 0.84 m straight, 1.03 m square; the paper 0.745 and 0.89 m), and the "
        "paper's method as written reproduces its result: on the square (Table 3) the total waypoint "
        "error falls by 60 % (1.03 to 0.41 m; the paper 65 %, 0.89 to 0.315 m), on the straight walk "
        "(Table 2) by 51 % (0.84 to 0.41 m; the paper 31 %). *Which reading reproduces which table:* "
        "eq. 15 with `Sigma^i` as eq. 14 defines it, shoe i's own cloud covariance (`likelihood_cov="
        '"own"`, `paper-proposed`), reproduces both; with the Gaussian sum\'s covariance '
        '(`"fused"`, `paper-fused`) the straight walk still falls by 48 % but the square only by 8 %: '
        "that covariance holds the distance between the two clouds, so once the feet have drifted apart "
        "the weights are nearly uniform. Both take the likelihood across the shoe's heading around the "
        "pedestrian shifted by half the step width (the 2-D Gaussian as printed pulls each foot along "
        "the walk toward the other, half a stride ahead when a stance ends: +40 % on the square; the "
        "`fusion/particle.py` docstring measures each choice). *Does not match:* the range constraint "
        "helps more here than in the paper on the straight walk (0.44 against 0.61 m), and the 300 m "
        "loop (Table 4, a 100 m x 50 m rectangle here instead of the building's corridors, start-aligned "
        "on 2 m) errs more than the paper's (1.8 / 2.2 m against 1.6 / 1.5 m), where footnav mode's joint "
        "EKF, which estimates heading, returns within 1.0 m. The paper's standard deviations are over "
        "waypoints, footnav's over seeds of each walk's mean. Which drift rate the paper's sensors had is "
        "not known: 6e-4 rad/s is chosen to give Tables 2-3's standalone errors, and "
        "`sigma_sys_m=0.1` m is footnav's (the square's error falls with it up to 0.1 m: -2 / -14 / "
        "-36 / -51 / -53 % at 0 / 0.02 / 0.05 / 0.1 / 0.2 m on 10 seeds)."
    ),
}


def _sections(text: str) -> dict[str, str]:
    """{paper key: its section's text} of a generated page."""
    out = {}
    for chunk in text.split("\n## ")[1:]:
        out[chunk.split(":", 1)[0]] = "## " + chunk.rstrip("\n") + "\n"
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter walks, one seed (two for one walk): the tests' run")
    ap.add_argument("--jobs", type=int, default=1, help="processes for the seeds of a walk")
    ap.add_argument("--out", default=str(HERE / "papers.md"))
    ap.add_argument("--check", action="store_true", help="name the stale sections of --out (exit 1 if any)")
    ap.add_argument("--only", default="", help="comma-separated paper keys to rerun; the others are kept from --out")
    args = ap.parse_args(argv)
    out = Path(args.out)
    if args.check:
        stale = papers_inputs.stale(out.read_text(encoding="utf-8"))
        for key, changed in stale.items():
            print(f"{key}: {', '.join(changed)} changed; python docs/make_papers.py --only {key}")
        return 1 if stale else 0
    only = [k for k in args.only.split(",") if k]
    kept = _sections(out.read_text(encoding="utf-8")) if only else {}
    lines = [
        INTRO.rstrip(),
        "",
        "Generated by `python docs/make_papers.py"
        + (" --quick" if args.quick else "")
        + "` (do not edit by hand). "
        + stamp()
        + (f" Sections rerun then: {', '.join(only)}; the others are kept from the previous run." if only else ""),
        "",
    ]
    for paper in PAPERS:
        if only and paper.key not in only:
            lines += kept[paper.key].rstrip("\n").split("\n") + [""]
            continue
        stats, files = run_paper(paper, args.quick, args.jobs)
        paper = Paper(**{**paper.__dict__, "verdict": VERDICTS.get(paper.key) or paper.verdict})
        lines += section(paper, stats, args.quick, files)
    out.write_text("\n".join(lines).rstrip("\n") + "\n", encoding="utf-8")
    print(f"wrote {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
