"""tools/standstill_bias.py reads each rest's rate and bridges a bias that changed between rests."""

from types import SimpleNamespace

import numpy as np
import pytest
from tool_module import load_tool  # tests/tool_module.py

import footnav


@pytest.fixture(scope="module")
def tool():
    return load_tool("standstill_bias")


def test_a_bias_that_walks_linearly_between_two_rests_is_removed(tool):
    rec = footnav.simulate("straight", distance_m=20.0, noise=False, standstill_s=3.0)
    imu, mask = rec.left, np.asarray(rec.truth_left.stance, bool)
    edges = np.flatnonzero(np.diff(np.r_[0, mask.astype(int), 0])).reshape(-1, 2)
    stance = SimpleNamespace(intervals=edges)
    b0, b1 = np.array([0.002, -0.001, 0.003]), np.array([0.004, 0.001, -0.002])
    u = (imu.t - imu.t[0]) / (imu.t[-1] - imu.t[0])
    drifting = footnav.ImuData(t=imu.t, acc=imu.acc, gyr=imu.gyr + b0 + u[:, None] * (b1 - b0))
    found = tool.rests(drifting, stance, min_rest_s=2.0)
    assert len(found) == 2  # the standstills at both ends; no walking stance lasts 2 s
    fixed = tool.bridged(drifting, found)
    # between the rests' midpoints the bias left is the first rest's, constant: of a change of
    # up to 5e-3 rad/s, what is left is the rests' means against their midpoints' bias
    (a0, e0, *_), (a1, e1, *_) = found
    inner = slice((a0 + e0) // 2, (a1 + e1) // 2)
    left = fixed.gyr[inner] - imu.gyr[inner]
    np.testing.assert_allclose(left, np.broadcast_to(found[0][3], left.shape), atol=1e-5)
    np.testing.assert_allclose(found[0][3], b0 + u[(a0 + e0) // 2] * (b1 - b0), atol=2e-5)
    assert tool.bridged(drifting, found[:1]) is None
