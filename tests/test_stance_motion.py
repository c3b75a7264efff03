"""tools/stance_motion.py's ``yaw`` part reads the rate about the vertical that a walk's stances hold."""

from types import SimpleNamespace

import numpy as np
import pytest
from tool_module import load_tool  # tests/tool_module.py

import footnav


@pytest.fixture(scope="module")
def tool():
    return load_tool("stance_motion")


@pytest.fixture(scope="module")
def walk():
    rec = footnav.simulate("straight", distance_m=20.0, noise=False, mounting_rpy_deg=(10.0, -20.0, 30.0))
    truth = rec.truth_left
    mask = np.asarray(truth.stance, bool)
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(int), 0]))
    stance = SimpleNamespace(intervals=edges.reshape(-1, 2), mask=mask)
    return rec.left, truth.quaternion, stance


def test_still_stances_read_zero(tool, walk):
    imu, q, stance = walk
    rates = tool.stance_yaw_rates(imu, stance.mask, stance, q, np.zeros(3))
    assert len(rates) == len(stance.intervals) - 1
    np.testing.assert_allclose(rates, 0.0, atol=1e-9)


def test_a_rate_about_the_vertical_is_read_whatever_the_mounting(tool, walk):
    imu, q, stance = walk
    up_body = footnav.nav.quaternion.as_matrix(q)[:, 2, :]  # nav up in the tilted sensor's frame
    twisted = footnav.ImuData(t=imu.t, acc=imu.acc, gyr=imu.gyr + 0.03 * up_body + [0.001, 0.0, 0.0])
    rates = tool.stance_yaw_rates(twisted, stance.mask, stance, q, np.array([0.001, 0.0, 0.0]))
    np.testing.assert_allclose(rates, 0.03, atol=1e-9)
