import numpy as np
import pytest

from footnav.core.types import GRAVITY_MPS2, StanceResult
from footnav.nav import quaternion as quat
from footnav.nav.initial_alignment import align_at_rest

from .conftest import G, _imu


def test_roll_pitch_from_gravity_and_bias_from_still_samples():
    roll, pitch = np.radians(10.0), np.radians(-25.0)
    q_true = quat.from_euler(roll, pitch, 0.0)
    f_body = quat.rotate(quat.conjugate(q_true), [0.0, 0.0, GRAVITY_MPS2])  # at rest: C' [0, 0, g]
    n = 200
    acc = np.tile(f_body, (n, 1))
    bias = np.array([0.01, -0.02, 0.005])
    gyr = np.tile(bias, (n, 1))
    gyr[150:] += [0.0, 0.5, 0.0]  # the foot starts to lift inside the detected stance
    al = align_at_rest(acc, gyr, 0, n, still_gyr_max_radps=0.05)
    np.testing.assert_allclose(quat.as_euler(al.quaternion), [roll, pitch, 0.0], atol=1e-12)
    np.testing.assert_allclose(al.gyro_bias_radps, bias, atol=1e-15)
    assert al.n_used == 150
    # without the stillness test the motion leaks into the bias: 0.5 * 50 / 200 = 0.125 rad/s on y
    loose = align_at_rest(acc, gyr, 0, n)
    assert loose.gyro_bias_radps[1] == pytest.approx(-0.02 + 0.125)


def test_empty_range_is_an_error():
    from footnav import InvalidInputError

    with pytest.raises(InvalidInputError, match="empty standstill"):
        align_at_rest(np.zeros((5, 3)), np.zeros((5, 3)), 3, 3)


# mutant: align-start-boundary
# align-start-boundary: a first stance that starts at sample 1 is a recording that does not start
# at standstill: warned, and the estimate starts there
def test_first_stance_at_sample_one_is_reported():
    from footnav.core.errors import DataQualityWarning
    from footnav.nav.initial_alignment import align_first_stance

    n = 300
    imu = _imu(np.arange(n) / 100.0, np.tile([0.0, 0.0, G], (n, 1)), np.zeros((n, 3)))
    mask = np.zeros(n, bool)
    mask[1:100] = True
    mask[200:] = True
    with pytest.warns(DataQualityWarning, match="index 1"):
        s0, align, meta = align_first_stance(imu, StanceResult(mask), still_gyr_max_radps=0.05)
    assert s0 == 1 and meta["estimate_start_index"] == 1
    assert meta["alignment_samples"] == [1, 100, 99]
