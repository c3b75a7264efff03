"""Step-vector fusion as Zhao et al. (2019) publish it, against independent references.

The references: hand-computed quaternions (eq. 4-6), the simulator's truth (its quaternions, heel
strikes, step length and final positions) and a scale error injected into simulated data.

``python tests/fusion/test_step_vector_paper.py`` prints the measurements quoted in the
docstring of :class:`footnav.fusion.step_vector.StepVectorFusion`.
"""

from __future__ import annotations

import sys
import warnings
from dataclasses import replace

import numpy as np
import pytest

import footnav
from footnav import DataQualityWarning, InvalidInputError
from footnav.cli import main
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion.independent import IndependentFusion
from footnav.fusion.step_vector import StepVectorFusion, leg_length_from_height, pendulum_step_length
from footnav.nav import quaternion as quat
from footnav.nav.calibration import calibrate_at_rest

# a consumer-grade gyro (bias walk 10x the simulator's default): the feet drift apart as in the
# paper's experiments
DRIFTY = {"gyr_bias_walk_radps2_sqrthz": 1e-4}

#: What the paper publishes, spelled out (the defaults, apart from the calibration).
PAPER = {"step_length": "pendulum", "leg_length_m": 0.9, "relative_frame": "attitude", "calibration": "standstill"}


def _fuse(fusion, rec):
    det = footnav.make_detector("threshold")
    return fusion.fuse(EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))


def _es_ep(res, rec) -> tuple[float, float]:
    """Eq. 8: final foot separation E_s and the feet's mean final position error E_p (m, 2-D)."""
    es = float(np.linalg.norm(res.left.position[-1, :2] - res.right.position[-1, :2]))
    ep = [
        float(np.linalg.norm(tr.position[-1, :2] - truth.position[-1, :2]))
        for tr, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right))
    ]
    return es, float(np.mean(ep))


def _scaled(rec, scale: float):
    """``rec`` with both accelerometers reading ``scale`` times the specific force."""
    return replace(
        rec, left=replace(rec.left, acc=rec.left.acc * scale), right=replace(rec.right, acc=rec.right.acc * scale)
    )


# -- eq. 4-6 by hand ------------------------------------------------------------------------------


def test_pendulum_step_length_on_hand_computed_quaternions():
    # the foot lands 20 deg toe-up (pitch -20 deg) and is flat at the other foot's heel strike:
    # theta = 20 deg, S = 2 * 0.9 * sin(10 deg) = 0.312567 m, whatever the heading
    for yaw in (0.0, 1.2, -2.5):
        q1 = quat.from_euler(0.0, np.radians(-20.0), yaw)
        q2 = quat.from_euler(0.0, 0.0, yaw)
        assert pendulum_step_length(q1, q2, 0.9) == pytest.approx(0.3125667198, abs=1e-9)
        assert pendulum_step_length(q1, -q2, 0.9) == pytest.approx(0.3125667198, abs=1e-9)  # q and -q
    # a 90 deg swing: S = 2 l sin(45 deg) = sqrt(2) l
    assert pendulum_step_length(
        quat.from_euler(0.0, np.radians(45.0), 0.0), quat.from_euler(0.0, np.radians(-45.0), 0.0), 1.0
    ) == pytest.approx(np.sqrt(2.0))


def test_leg_length_from_height_is_winters_ratio():
    assert leg_length_from_height(1.70) == pytest.approx(0.901)
    assert StepVectorFusion().leg_length_m == pytest.approx(leg_length_from_height(1.70), abs=0.002)


# -- why eq. 6 with the true leg is short on the simulator ----------------------------------------


def _truth_pendulum(rec, leg_length_m: float) -> np.ndarray:
    """Eq. 5-6 on the simulator's true quaternions between its true heel strikes."""
    phases = {f: getattr(rec, f"truth_{f}").meta["phases"] for f in ("left", "right")}
    # heel strike = first sample of foot-flat (phase 3, simulate.PHASE_NAMES)
    hs = {f: np.flatnonzero((p[1:] == 3) & (p[:-1] != 3)) + 1 for f, p in phases.items()}
    out = []
    for front, rear in (("left", "right"), ("right", "left")):
        q = getattr(rec, f"truth_{rear}").quaternion
        for k in hs[front]:
            earlier = hs[rear][hs[rear] < k]
            if len(earlier):
                out.append(pendulum_step_length(q[earlier[-1]], q[k], leg_length_m))
    return np.array(out)


def test_simulator_foot_turns_only_by_its_heel_strike_pitch():
    # The simulator's rear foot is flat when the front heel strikes (its heel-off starts then at
    # the earliest), so theta of eq. 5 is the heel-strike pitch alone: 20 deg gives
    # 2 * 0.9 * sin(10 deg) = 0.313 m for its 0.70 m steps. A heel strike at the leg's swing
    # angle, 2 asin(0.7 / 1.8) = 45.8 deg, gives the true step: eq. 5-6 themselves are right.
    rec = footnav.simulate("straight", distance_m=10.0, noise=False)
    s = _truth_pendulum(rec, 0.9)
    # at 100 Hz the first foot-flat sample may lie up to 10 ms after the heel strike
    assert np.median(s) == pytest.approx(2 * 0.9 * np.sin(np.radians(10.0)), abs=1e-9)
    np.testing.assert_allclose(s, 2 * 0.9 * np.sin(np.radians(10.0)), atol=0.02)
    rec = footnav.simulate(
        "straight", distance_m=10.0, noise=False, heel_strike_pitch_deg=np.degrees(2 * np.arcsin(0.7 / 1.8))
    )
    assert np.median(_truth_pendulum(rec, 0.9)) == pytest.approx(0.7, abs=1e-6)
    assert rec.meta["step_length_m"] == pytest.approx(0.7, abs=0.02)


def test_fusion_measures_theta_as_the_truth_does():
    rec = footnav.simulate("straight", seed=0, distance_m=20.0)
    res = _fuse(StepVectorFusion(step_length="pendulum", leg_length_m=0.9), rec)
    truth = np.median(_truth_pendulum(rec, 0.9))
    assert res.meta["step_length_m"]["median"] == pytest.approx(truth, abs=0.03)  # 0.293 vs 0.313


# -- the paper's fusion on simulated walks ---------------------------------------------------------


@pytest.mark.parametrize(
    "scenario, opts, ep_gain",
    [
        ("straight", {"distance_m": 100.0}, 1.0),
        ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}, 0.8),
    ],
)
def test_paper_mode_reduces_es_and_ep_against_independent_fusion(scenario, opts, ep_gain):
    es_ind, ep_ind, es_pap, ep_pap = [], [], [], []
    for seed in range(5):
        rec = footnav.simulate(scenario, seed=seed, **DRIFTY, **opts)
        for fusion, es_list, ep_list in (
            (IndependentFusion(), es_ind, ep_ind),
            (StepVectorFusion(**PAPER), es_pap, ep_pap),
        ):
            es, ep = _es_ep(_fuse(fusion, rec), rec)
            es_list.append(es)
            ep_list.append(ep)
    # measured over 5 seeds: |E_s - 0.2| 1.25 -> 0.009 m straight, 13.2 -> 0.021 m rectangle (the
    # paper's Table I: E_s 7.33 -> 0.42 m, 33.18 -> 0.37 m); E_p 1.15 -> 1.05 m straight (where
    # the pair walks on the mean of two heading drifts), 9.22 -> 6.41 m rectangle
    assert np.mean(np.abs(np.array(es_pap) - 0.2)) * 20 < np.mean(np.abs(np.array(es_ind) - 0.2))
    assert np.mean(ep_pap) < ep_gain * np.mean(ep_ind) + 0.1


def test_heading_frame_is_immune_to_a_sensor_yawed_on_the_shoe():
    rec = footnav.simulate("straight", seed=0, distance_m=50.0, mounting_rpy_deg=(0.0, 0.0, 10.0), **DRIFTY)
    _, ep_att = _es_ep(_fuse(StepVectorFusion(relative_frame="attitude"), rec), rec)
    _, ep_head = _es_ep(_fuse(StepVectorFusion(relative_frame="heading"), rec), rec)
    _, ep_ind = _es_ep(_fuse(IndependentFusion(), rec), rec)
    # the paper's C_b^n turns the step vector by the mounting yaw (measured 10.6 vs 1.17 m at 100 m)
    assert ep_head < 1.5 * ep_ind + 0.2
    assert ep_att > 3 * ep_head


# -- Sec. II-A: accelerometer scale from a standstill --------------------------------------------


@pytest.mark.parametrize("scale", [0.97, 1.0, 1.02])
def test_standstill_calibration_recovers_an_injected_scale(scale):
    rec = footnav.simulate("straight", distance_m=5.0, noise=False)
    cal = calibrate_at_rest(_scaled(rec, scale).left, 0, 150)  # the first 2 s are still
    assert cal.acc_scale == pytest.approx(1.0 / scale, rel=1e-9)
    np.testing.assert_allclose(cal.gyro_bias_radps, 0.0, atol=1e-12)
    fixed = cal.apply(_scaled(rec, scale).left)
    np.testing.assert_allclose(fixed.acc, rec.left.acc, rtol=1e-9, atol=1e-9)
    assert fixed.meta["calibration"]["acc_scale"] == pytest.approx(1.0 / scale)


def test_standstill_calibration_with_sensor_noise_and_bias():
    # the simulator's accelerometer bias (2e-2 m/s^2, 1 sigma) reads as a 0.2 % scale error
    for seed in range(5):
        rec = footnav.simulate("straight", seed=seed, distance_m=5.0)
        cal = calibrate_at_rest(_scaled(rec, 1.02).right, 0, 150)
        assert cal.acc_scale == pytest.approx(1.0 / 1.02, rel=8e-3)
        assert np.all(np.abs(cal.gyro_bias_radps) < 0.01)


def test_standstill_calibration_refuses_a_walk():
    rec = footnav.simulate("straight", distance_m=5.0, noise=False)
    with pytest.raises(InvalidInputError, match="not a standstill"):
        calibrate_at_rest(_scaled(rec, 1.5).left, 0, 150)
    with pytest.raises(InvalidInputError, match="fewer than 2"):
        calibrate_at_rest(rec.left, 10, 11)


def test_fusion_calibration_undoes_an_injected_scale_error():
    ep = {"none": [], "standstill": []}
    for seed in range(2):
        rec = _scaled(footnav.simulate("straight", seed=seed, distance_m=100.0, **DRIFTY), 1.02)
        for mode, errors in ep.items():
            res = _fuse(StepVectorFusion(calibration=mode), rec)
            errors.append(_es_ep(res, rec)[1])
            if mode == "standstill":
                cal = res.meta["calibration"]
                assert cal["left"]["acc_scale"] == pytest.approx(1 / 1.02, rel=8e-3)
                assert cal["right"]["gyro_bias_radps"] is None  # the estimator's job
    assert np.mean(ep["standstill"]) < 0.8 * np.mean(ep["none"])  # measured 1.85 -> 1.05 m


def test_fusion_calibration_warns_without_a_standstill():
    rec = footnav.simulate("straight", distance_m=10.0, standstill_s=0.3)
    with pytest.warns(DataQualityWarning, match="uncalibrated"):
        res = _fuse(StepVectorFusion(calibration="standstill"), rec)
    assert res.meta["calibration"]["left"] is None


@pytest.mark.parametrize(
    "param, value",
    [
        ("step_length", "guess"),
        ("relative_frame", "yaw"),
        ("calibration", True),
        ("leg_length_m", None),
        ("leg_length_m", 0.0),
    ],
)
def test_bad_choices_are_refused(param, value):
    rec = footnav.simulate("straight", distance_m=5.0)
    with pytest.raises(footnav.InvalidParameterError, match=param):
        _fuse(StepVectorFusion(**{param: value}), rec)


# -- the CLI writes its results -------------------------------------------------------------------


@pytest.mark.parametrize("params", [{}, {"step_length": "fitted", "relative_frame": "heading"}])
def test_cli_run_step_vector_writes_results(tmp_path, params):
    walk = tmp_path / "walk"
    assert main(["simulate", "straight", "--seed", "1", "--out", str(walk)]) == 0
    out = tmp_path / "res"
    args = ["run", "--left", str(walk / "left.csv"), "--right", str(walk / "right.csv"), "--out", str(out)]
    if params:
        pipe = tmp_path / "pipe.toml"
        pipe.write_text(footnav.make_pipeline("adaptive", "ekf", "step-vector", fusion_params=params).to_toml())
        args += ["--pipeline", str(pipe)]
    else:
        args += ["--fusion", "step-vector"]
    assert main(args) == 0
    assert {"left.csv", "right.csv", "path.csv", "summary.json", "pipeline.toml"} <= {p.name for p in out.iterdir()}
    again = footnav.load_pipeline(out / "pipeline.toml")
    assert again.fusion.name == "step-vector"
    assert again.fusion.get_params() == StepVectorFusion(**params).get_params()


# -- the measurements quoted in the docstrings ---------------------------------------------------


def _measure(n_seeds: int = 5) -> None:  # pragma: no cover - run by hand
    modes = {
        "independent": None,
        "paper": {"step_length": "pendulum", "relative_frame": "attitude"},
        "pendulum + heading": {"step_length": "pendulum", "relative_frame": "heading"},
        "fitted + attitude": {"step_length": "fitted", "relative_frame": "attitude"},
        "fitted + heading (defaults)": {"step_length": "fitted", "relative_frame": "heading"},
        "paper + calibration": {"step_length": "pendulum", "relative_frame": "attitude", "calibration": "standstill"},
    }
    walks = {
        "straight 100 m": ("straight", {"distance_m": 100.0}, 1.0),
        "rectangle cw": ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "cw"}, 1.0),
        "rectangle ccw": ("rectangle", {"width_m": 105.0, "height_m": 68.0, "direction": "ccw"}, 1.0),
        "straight, sensor yawed 10 deg": ("straight", {"distance_m": 100.0, "mounting_rpy_deg": (0.0, 0.0, 10.0)}, 1.0),
        "straight, acc scale 1.02": ("straight", {"distance_m": 100.0}, 1.02),
    }
    warnings.simplefilter("ignore")
    for walk, (scenario, opts, scale) in walks.items():
        rows = {m: [] for m in modes}
        for seed in range(n_seeds):
            rec = _scaled(footnav.simulate(scenario, seed=seed, **DRIFTY, **opts), scale)
            for m, p in modes.items():
                res = _fuse(IndependentFusion() if p is None else StepVectorFusion(**p), rec)
                s = res.meta.get("step_length_m", {}).get("median") if p is not None else None
                rows[m].append((*_es_ep(res, rec), np.nan if s is None else s))
        print(f"## {walk}: |E_s - 0.2| / E_p (m), median S (m)")
        for m, v in rows.items():
            v = np.array(v)
            print(
                f"  {m:22s} {np.mean(np.abs(v[:, 0] - 0.2)):.3f} / {v[:, 1].mean():.3f}   S {np.nanmean(v[:, 2]):.3f}"
            )
    from footnav.analysis.evaluation import evaluate
    from footnav.data.datasets import load_dataset

    for name in ("azure_fgo", "gaitmap"):
        try:
            rec = load_dataset(name)
        except footnav.FootnavError as exc:
            print(name, "not available:", exc)
            continue
        for det in ("dual-gait", "adaptive"):
            for m, p in modes.items():
                if p is None:
                    continue
                rep = evaluate(footnav.make_pipeline(det, "ekf", "step-vector", fusion_params=p), rec)
                print(
                    f"{name} {det:9s} {m:22s} "
                    f"ATE {rep.value('ate_2d', 'left'):.3f} / {rep.value('ate_2d', 'right'):.3f}"
                )


if __name__ == "__main__":  # pragma: no cover
    _measure(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
