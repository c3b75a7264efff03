"""The online contract (footnav.core.online_contract): the EKF meets it, and a third party's estimator
written here, a plain strapdown with hard zero-velocity resets that knows nothing of footnav's
filter, runs online through ``pipe.online`` as the EKF does (issue 38)."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace
from typing import ClassVar, NamedTuple

import numpy as np
import pytest

import footnav
from footnav import FootEstimator
from footnav.core.errors import InvalidParameterError
from footnav.core.online_contract import OnlineEstimator, OnlineFilter
from footnav.core.types import GRAVITY_MPS2, FootTrajectory
from footnav.estimators.ekf import EkfEstimator
from footnav.nav import quaternion as quat
from footnav.testing import OnlineEstimatorContract, contract_walk

#: Position variance the toy filter adds per second in swing, m^2/s.
_SWING_VAR = 1e-3


class Samples(NamedTuple):
    t: np.ndarray
    acc: np.ndarray
    gyr: np.ndarray
    stance: np.ndarray


class ToyFilter:
    """One foot's strapdown (attitude from the gyro, velocity and position from the specific
    force) with the velocity set to zero in stance: the :class:`OnlineFilter` members and
    nothing more. Its state is (q, v, p, var); a checkpoint at every step end."""

    def __init__(self, t, acc, gyr, stance, start, state, bg, capacity):
        n = len(t)
        room = max(n, int(capacity))
        self._t, self._acc, self._gyr = np.zeros(room), np.zeros((room, 3)), np.zeros((room, 3))
        self._stance = np.zeros(room, dtype=bool)
        self._t[:n], self._acc[:n], self._gyr[:n], self._stance[:n] = t, acc, gyr, stance
        self._n = n
        self._bg = np.asarray(bg, float)
        self._start = int(start)
        self._k = int(start)
        q, v, p, var = state
        self._q, self._v, self._p, self._var = np.array(q, float), np.array(v, float), np.array(p, float), float(var)
        self._out = [np.zeros((room, 4)), np.zeros((room, 3)), np.zeros((room, 3)), np.zeros((room, 4))]
        self._write(slice(0, self._k + 1))  # the samples up to the start hold the initial state
        self.meta: list[dict] = [{}]
        self.checkpoints: list = [self._checkpoint(False)]

    def _state(self):
        return (self._q.copy(), self._v.copy(), self._p.copy(), self._var)

    def _checkpoint(self, step_end):
        return SimpleNamespace(k=np.array([self._k]), step_end=step_end, state=self._state())

    def _write(self, k):
        q, v, p, pcov = self._out
        q[k], v[k], p[k] = self._q, self._v, self._p
        pcov[k] = (self._var, 0.0, self._var, self._var)

    def extend(self, t, acc, gyr, stance, *, foot=0):
        a, m = self._n, len(t)
        self._t[a : a + m], self._acc[a : a + m], self._gyr[a : a + m], self._stance[a : a + m] = t, acc, gyr, stance
        self._n += m

    def run_until(self, t_stop=math.inf):
        while self._k + 1 < self._n and self._t[self._k + 1] <= t_stop:
            k = self._k = self._k + 1
            dt = self._t[k] - self._t[k - 1]
            self._q = quat.normalize(quat.multiply(self._q, quat.from_rotvec((self._gyr[k] - self._bg) * dt)))
            self._v = self._v + (quat.rotate(self._q, self._acc[k]) - [0.0, 0.0, GRAVITY_MPS2]) * dt
            self._p = self._p + self._v * dt
            if self._stance[k]:
                self._v = np.zeros(3)
            else:
                self._var += _SWING_VAR * dt
            self._write(k)
            if self._stance[k] and k + 1 < self._n and not self._stance[k + 1]:
                self.checkpoints.append(self._checkpoint(True))

    def capacity(self, foot):
        return len(self._t)

    def samples(self, foot):
        n = self._n
        return Samples(self._t[:n], self._acc[:n], self._gyr[:n], self._stance[:n])

    def index(self, foot):
        return self._k

    def start_index(self, foot):
        return self._start

    def global_index(self, foot, k):
        return k

    def time(self, foot):
        return float(self._t[self._k])

    def position(self, foot):
        return self._p.copy()

    def velocity(self, foot):
        return self._v.copy()

    def quaternion(self, foot):
        return self._q.copy()

    @property
    def covariance(self):
        return self._var * np.eye(3)

    def block(self, foot, name):
        if name != "pos":
            raise KeyError(name)
        return slice(0, 3)

    def final_outputs(self, foot):
        return tuple(self._out)

    def open_step_start(self, foot):
        return None  # no smoother: every processed sample is final at its step's end

    def close_open_step(self):
        pass

    def rebase(self, keep_from, capacity, *, at=None, step_smoother=None):
        s = int(keep_from[0])
        if at is None:
            state, k = self._state(), self._k
        else:
            cp = self.checkpoints[at]
            state, k = cp.state, int(cp.k[0])
        t, acc, gyr, stance = (x[s:] for x in self.samples(0))
        new = ToyFilter(t, acc, gyr, stance, k - s, state, self._bg, capacity[0])
        for src, dst in zip(self._out, new._out):
            dst[: k - s + 1] = src[s : k + 1]
        new.meta = self.meta
        return new


class ToyEstimator(FootEstimator):
    """A third party's estimator: levelled and de-biased at the first stance, then
    :class:`ToyFilter`."""

    name = "toy-strapdown"

    def __init__(self, *, smoother: str = "none", heading: str = "sensor") -> None:
        self.smoother = smoother
        self.heading = heading

    def validate_params(self) -> None:
        if self.smoother != "none" or self.heading != "sensor":
            raise InvalidParameterError("toy-strapdown: smoother='none' and heading='sensor' only")

    def start(self, imus, stances, *, initial_yaw_rad=None, initial_position_m=None):
        if len(imus) != 1:
            raise InvalidParameterError("toy-strapdown runs one foot per filter")
        imu, mask = imus[0], np.asarray(stances[0].mask, bool)
        first = stances[0].intervals[0]
        a, b = int(first[0]), int(first[1])
        f = imu.acc[a:b].mean(axis=0)
        q0 = quat.from_euler(math.atan2(f[1], f[2]), math.atan2(-f[0], math.hypot(f[1], f[2])), 0.0)
        state = (q0, np.zeros(3), np.zeros(3), 0.0)
        filt = ToyFilter(imu.t, imu.acc, imu.gyr, mask, b - 1, state, imu.gyr[a:b].mean(axis=0), len(imu.t))
        filt.meta = [{"aligned_at": b - 1}]
        return filt

    def package(self, t, q, vel, pos, pos_cov, start_index, filter_meta, steps, *, smoothed, heading, biases=None):
        std = np.sqrt(np.maximum(pos_cov[:, [0, 2, 3]], 0.0))
        meta = {"estimator": self.describe(), **filter_meta}
        return FootTrajectory(t=t, position=pos, velocity=vel, quaternion=q, position_std=std, steps=steps, meta=meta)

    def final_biases(self, filt, foot):
        return None

    def estimate(self, imu, stance):
        filt = self.start([imu], [stance])
        filt.run_until()
        q, v, p, pcov = (x[: len(imu.t)].copy() for x in filt.final_outputs(0))
        return self.package(
            imu.t, q, v, p, pcov, filt.start_index(0), filt.meta[0], stance.intervals, smoothed=False, heading=False
        )


class TestToyEstimatorIsOnline(OnlineEstimatorContract):
    component = ToyEstimator


class TestEkfIsOnline(OnlineEstimatorContract):
    component = EkfEstimator
    params: ClassVar[dict] = {"smoother": "step"}


class TestEkfWholeIsOnline(OnlineEstimatorContract):
    """The default smoother: step-wise live, the whole walk's at close."""

    component = EkfEstimator


def test_the_ekfs_filter_meets_the_online_contract_and_madgwick_does_not():
    rec = contract_walk()
    ekf = EkfEstimator()
    assert isinstance(ekf, OnlineEstimator)
    assert isinstance(ekf.start([rec.left], [footnav.StanceResult(rec.truth_left.stance)]), OnlineFilter)
    assert not isinstance(footnav.make_estimator("madgwick"), OnlineEstimator)


def test_a_third_party_estimator_runs_online_in_a_pipeline():
    """The toy estimator in ``make_pipeline(...).online()``: pushes one sample at a time return
    every sample once, in order, and close gives the offline run; the walk ends near the truth."""
    rec = footnav.simulate("straight", seed=4, distance_m=12.0)
    pipe = footnav.make_pipeline("threshold", ToyEstimator(), "independent")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        offline = pipe.run(rec.left)
        stream = pipe.online(feet=1)
        pushed = [
            stream.push(left=(rec.left.t[i], rec.left.acc[i], rec.left.gyr[i])).left for i in range(rec.left.n_samples)
        ]
        result = stream.close()
    pushed.append(stream.last_update.left)
    t = np.concatenate([u.t for u in pushed])
    np.testing.assert_array_equal(t, rec.left.t)
    np.testing.assert_array_equal(np.concatenate([u.position for u in pushed]), offline.left.position)
    np.testing.assert_array_equal(result.left.position, offline.left.position)
    moved = result.left.position[-1] - result.left.position[0]
    true = rec.truth_left.position[-1] - rec.truth_left.position[0]
    assert np.linalg.norm(moved - true) < 1.0
    assert result.meta["online"]


def test_an_estimator_without_the_online_members_is_refused_naming_them():
    pipe = footnav.make_pipeline("threshold", "madgwick", "independent")
    with pytest.raises(footnav.CompositionError, match="step-able filter.*lacks"):
        pipe.online(feet=1)
