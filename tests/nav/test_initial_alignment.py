import numpy as np
import pytest

from footnav.core.types import GRAVITY_MPS2
from footnav.nav import quaternion as quat
from footnav.nav.initial_alignment import align_at_rest


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
