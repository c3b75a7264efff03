"""footnav.nav.vertical_check: each condition of ``suspicious`` alone, both signs of a trend.

The walks are hand-built (flat stances joined by straight swings); every expected figure is
worked out from the stride list: trend = sum of the level strides' rises, rate = 100 trend / walked.

docs/height.md's figures (which shared recordings warn with ``vertical="free"``, none with the
default) come from this loop::

    import warnings, footnav
    from footnav.data.datasets import load_dataset, dataset_names
    for v in ("floors", "free"):
        for n in [n for n in dataset_names() if not n.startswith(("ipol_", "gaitdriven_"))]:
            rec = load_dataset(n)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = footnav.make_pipeline(estimator_params={"vertical": v}).run(rec.left, rec.right)
            print(v, n, {f: m["rate_m_per_100m"] for f, m in res.meta["vertical_check"].items() if m["suspicious"]})
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav import DataQualityWarning
from footnav.core.types import FootTrajectory
from footnav.nav.floors import LEVEL_RISE_MAX_M
from footnav.nav.vertical_check import WARN_RATE_M_PER_100M, WARN_STEADY_FRACTION, check_vertical


def _walk(rises, stride_m=1.5, stance_n=10, swing_n=10):
    n = stance_n * (len(rises) + 1) + swing_n * len(rises)
    pos = np.zeros((n, 3))
    steps, k, h, x = [], 0, 0.0, 0.0
    for i in range(len(rises) + 1):
        steps.append((k, k + stance_n))
        pos[k : k + stance_n] = [x, 0.0, h]
        k += stance_n
        if i < len(rises):
            u = np.arange(1, swing_n + 1)[:, None] / (swing_n + 1)
            pos[k : k + swing_n] = [x, 0.0, h] + u * [stride_m, 0.0, rises[i]]
            h, x, k = h + rises[i], x + stride_m, k + swing_n
    return FootTrajectory(
        t=np.arange(n) / 100.0,
        position=pos,
        velocity=np.zeros((n, 3)),
        quaternion=np.tile([1.0, 0, 0, 0], (n, 1)),
        position_std=np.zeros((n, 3)),
        steps=np.array(steps),
    )


def test_a_steady_sinking_is_as_suspicious_as_a_steady_climb():
    # mutant: vcheck-rate-one-sided, vcheck-trend-one-sided. 20 strides of 1.5 m sinking 3 cm:
    # trend -0.6 m over 30 m, -2 m per 100 m, every stride alike
    check = check_vertical(_walk([-0.03] * 20))
    assert (check.level_strides, check.stair_strides) == (20, 0)
    assert check.trend_m == pytest.approx(-0.6) and check.walked_m == pytest.approx(30.0)
    assert check.rate_m_per_100m == pytest.approx(-2.0) and check.steady_fraction == 1.0
    assert check.suspicious
    assert "sinks 2.00 m per 100 m" in check.message("left", "ekf")


def test_too_few_level_strides_alone_say_nothing():
    # mutant: vcheck-and-or (7 level strides; every other condition holds)
    check = check_vertical(_walk([0.05] * 7))
    assert check.level_strides == 7 and abs(check.rate_m_per_100m) > 0.5 and check.trend_m >= 0.25
    assert not check.suspicious
    assert check_vertical(_walk([0.05] * 8)).suspicious


def test_a_small_rate_over_a_long_walk_alone_says_nothing():
    # 200 strides of 1.5 m rising 2 mm: trend 0.4 m (>= 0.25) but 0.13 m per 100 m (< 0.5)
    check = check_vertical(_walk([0.002] * 200))
    assert check.trend_m == pytest.approx(0.4) and check.rate_m_per_100m == pytest.approx(0.4 / 3.0)
    assert not check.suspicious


def test_a_small_trend_over_a_short_walk_alone_says_nothing():
    # 10 strides of 1.5 m rising 2 cm: 1.33 m per 100 m but 0.2 m in all (< 0.25)
    check = check_vertical(_walk([0.02] * 10))
    assert check.rate_m_per_100m == pytest.approx(0.2 / 15 * 100) and check.trend_m == pytest.approx(0.2)
    assert not check.suspicious
    assert check_vertical(_walk([0.026] * 10)).suspicious  # 0.26 m


def test_an_unsteady_trend_alone_says_nothing():
    # 10 strides up 12 cm and 10 down 6 cm... level strides must stay under LEVEL_RISE_MAX_M
    up, down = 0.9 * LEVEL_RISE_MAX_M, -0.5 * LEVEL_RISE_MAX_M
    check = check_vertical(_walk([up, down] * 10))
    assert check.steady_fraction == pytest.approx(0.5) and check.level_strides == 20
    assert abs(check.trend_m) >= 0.25 or abs(check.rate_m_per_100m) >= 0.5
    assert not check.suspicious


def test_a_big_drop_is_a_stair_not_a_level_stride():
    # mutant: vcheck-level-one-sided (a stride falling more than LEVEL_RISE_MAX_M is a stair down)
    check = check_vertical(_walk([-2.0 * LEVEL_RISE_MAX_M] * 5 + [0.0] * 5))
    assert (check.level_strides, check.stair_strides) == (5, 5)
    assert check.trend_m == 0.0 and not check.suspicious


def test_a_steady_climb_on_level_strides_is_suspicious_with_its_rate():
    check = check_vertical(_walk([0.03] * 20))  # 0.6 m over 30 m: 2 m per 100 m
    assert check.level_strides == 20 and check.stair_strides == 0
    assert check.trend_m == pytest.approx(0.6) and check.walked_m == pytest.approx(30.0)
    assert check.rate_m_per_100m == pytest.approx(2.0) and check.steady_fraction == 1.0
    assert check.suspicious
    msg = check.message("left", "ekf")
    assert "rises 2.00 m per 100 m" in msg and "vertical='floors'" in msg


def test_stairs_noise_and_short_walks_are_not_drift():
    stairs = check_vertical(_walk([0.0] * 5 + [0.17 * 2] * 10 + [0.0] * 5))
    assert stairs.stair_strides == 10 and not stairs.suspicious and stairs.trend_m == 0.0
    rng = np.random.default_rng(1)
    noise = check_vertical(_walk(list(rng.normal(0.0, 0.02, 40))))
    assert not noise.suspicious and noise.steady_fraction < WARN_STEADY_FRACTION, noise  # rises either way
    assert abs(noise.rate_m_per_100m) < WARN_RATE_M_PER_100M
    short = check_vertical(_walk([0.03] * 5))  # steady, but 0.15 m in all
    assert short.rate_m_per_100m == pytest.approx(2.0) and not short.suspicious
    assert check_vertical(_walk([])).level_strides == 0


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_the_pipeline_checks_every_foot_and_warns_with_the_rate():
    rec = footnav.simulate("straight", seed=3, distance_m=100.0)
    pipe = footnav.make_pipeline()
    held = pipe.run(rec.left, rec.right)
    assert set(held.meta["vertical_check"]) == {"left", "right"}
    assert not any(m["suspicious"] for m in held.meta["vertical_check"].values())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = pipe._check_vertical(_walk([0.03] * 20), _walk([0.0] * 20))
    assert out["left"]["suspicious"] and not out["right"]["suspicious"]
    said = [str(w.message) for w in caught if issubclass(w.category, DataQualityWarning)]
    assert len(said) == 1 and said[0].startswith("left foot, estimator 'ekf': the height rises 2.00 m per 100 m")


def test_online_close_records_the_same_check(tmp_path):
    rec = footnav.simulate("straight", seed=3, distance_m=60.0)
    pipe = footnav.make_pipeline("threshold", estimator_params={"smoother": "step"})
    offline = pipe.run(rec.left)
    stream = pipe.online(feet=1)
    for i in range(0, rec.left.n_samples, 500):
        stream.push(left=(rec.left.t[i : i + 500], rec.left.acc[i : i + 500], rec.left.gyr[i : i + 500]))
    online = stream.close()
    assert online.meta["vertical_check"] == offline.meta["vertical_check"]
    assert online.left.meta["vertical"] == offline.left.meta["vertical"]


def test_shared_free_filter_warns_on_the_x_io_loop_and_the_default_does_not(shared_data):
    from footnav.data.datasets import load_dataset

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rec = load_dataset("xio_short", shared_data)
        held = footnav.make_pipeline().run(rec.left)
        free = footnav.make_pipeline(estimator_params={"vertical": "free"}).run(rec.left)
    assert not held.meta["vertical_check"]["left"]["suspicious"]
    assert free.meta["vertical_check"]["left"]["suspicious"]
    assert free.meta["vertical_check"]["left"]["rate_m_per_100m"] == pytest.approx(1.30, abs=0.05)
    assert held.left.meta["vertical"]["removed_m"] == pytest.approx(0.294, abs=0.01)
