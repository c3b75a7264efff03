"""The inverted pendulum of a step and the leg length it needs (Zhao et al. (2019), eq. 5-6).

The supporting foot turns about the hip while the other swings past it: from the supporting
foot's attitude q1 at its own heel strike and q2 at the other foot's heel strike::

    q = q1 (x) q2*,   theta = 2 acos(q[1])      (eq. 5)
    S = 2 l sin(theta / 2)                      (eq. 6)

with ``l`` "the pendulum length approximated by user's leg length". The step-vector fusion
(:mod:`footnav.fusion.step_vector`) takes ``l`` given (:func:`leg_length_from_height`) or
fitted to the walk's own strides (:func:`leg_ratio`: offline over the whole walk, online as the
walk goes, :class:`LegLengthFit`).
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np

from footnav.nav import quaternion as quat

__all__ = [
    "LEG_FIT_MIN_STEPS",
    "LEG_FIT_WINDOW",
    "LEG_LENGTH_PER_HEIGHT",
    "LegLengthFit",
    "leg_length_from_height",
    "leg_ratio",
    "pendulum_step_length",
]

#: Leg length (floor to greater trochanter, the hip's pivot) per body height: 0.530 H in Winter
#: (2009), Fig. 4.1, after Drillis and Contini (1966).
LEG_LENGTH_PER_HEIGHT = 0.530

#: Online, ``step_length="fitted"`` applies no step update before this many straight steps have
#: been fitted (three strides of each foot); then the median of the latest ``LEG_FIT_WINDOW``.
LEG_FIT_MIN_STEPS = 6
LEG_FIT_WINDOW = 500


def leg_length_from_height(body_height_m: float) -> float:
    """Leg length from body height, m: ``LEG_LENGTH_PER_HEIGHT * body_height_m`` (Winter 2009).

    Parameters
    ----------
    body_height_m : float
        The walker's height, m.

    Returns
    -------
    float
        Floor-to-hip length, m; pass it as ``StepVectorFusion(leg_length_m=...)``.

    Examples
    --------
    >>> round(leg_length_from_height(1.70), 3)
    0.901
    """
    return LEG_LENGTH_PER_HEIGHT * float(body_height_m)


def leg_ratio(
    xy0: np.ndarray, xy1: np.ndarray, yaw0: float, yaw1: float, swing: float, turn_rad: float
) -> float | None:
    """One straight step's pendulum length, m: half the front foot's stride from ``xy0`` to
    ``xy1`` (m, its stance starts in its own solution) over the rear foot's ``swing`` (eq. 6 with
    l = 1); None when the stride is under 0.2 m, turns more than ``turn_rad`` (its yaws ``yaw0``,
    ``yaw1``, rad) or the rear foot hardly swung."""
    stride = float(np.linalg.norm(np.asarray(xy1)[:2] - np.asarray(xy0)[:2]))
    if stride < 0.2 or abs(quat.wrap_angle(yaw1 - yaw0)) > turn_rad or not swing > 1e-3:
        return None
    return 0.5 * stride / swing


def pendulum_step_length(q1: np.ndarray, q2: np.ndarray, leg_length_m: float) -> float:
    """Step length of the inverted pendulum, Zhao et al. (2019), eq. 4-6.

    Parameters
    ----------
    q1, q2 : ndarray, shape (4,)
        Supporting foot's attitude [w, x, y, z] (body -> nav) at the start and the end of the step.
    leg_length_m : float
        Pendulum length l, m.

    Returns
    -------
    float
        S = 2 l sin(theta/2), m, with theta the angle of ``q1 (x) q2*`` (eq. 5).

    Notes
    -----
    ``theta = 2 acos(|q[1]|)``: the absolute value picks the shorter of the two rotations a
    quaternion and its negative describe (eq. 5 as printed assumes q[1] >= 0).
    """
    # q = q1 (x) q2* (eq. 5); its scalar part, all eq. 5 needs, is the dot product of q1 and q2
    w = (
        float(q1[0]) * float(q2[0])
        + float(q1[1]) * float(q2[1])
        + float(q1[2]) * float(q2[2])
        + float(q1[3]) * float(q2[3])
    )
    theta = 2.0 * math.acos(min(abs(w), 1.0))  # theta = 2 acos(q[1])
    return 2.0 * leg_length_m * math.sin(0.5 * theta)  # S = 2 l sin(theta/2)  (eq. 6)


class LegLengthFit:
    """The pendulum length of ``step_length="fitted"`` fitted on the steps seen so far (online).

    Offline, ``l`` is the median over the whole walk of :func:`leg_ratio` (half the front foot's
    stride in its own single-foot solution over the rear foot's swing of eq. 6 with l = 1).
    Online the same ratio is taken at each landing: the swing from the joint filter's attitude
    of the rear foot (before its step update; until the first one the joint filter is the two
    single-foot filters), the stride from the front foot's own forward solution at its stance
    starts (``add_starts``), known once the stance that the landing opens has begun. The length
    used at a time is the median of the ratios of the steps whose stance began by then, the latest
    ``LEG_FIT_WINDOW``; None before ``LEG_FIT_MIN_STEPS`` of them.

    Parameters
    ----------
    turn_rad
        A step whose front foot turns more than this between its stances is not fitted, rad.
    """

    def __init__(self, turn_rad: float) -> None:
        self.turn_rad = float(turn_rad)
        #: (foot, its heel strike s) -> the start of the stance it opened, s
        self.stance_of: dict[tuple[int, float], float] = {}
        self._starts: list[deque] = [deque(maxlen=16), deque(maxlen=16)]  # (t, xy, yaw) per foot
        self._swings: list[tuple[float, int, float]] = []  # (front's stance start s, front, swing)
        self.ratios: deque[float] = deque(maxlen=LEG_FIT_WINDOW)
        self.n_fitted = 0
        self._leg: float | None = None  # the median of ``ratios`` once enough, kept until one is added
        self.waiting = 0  # updates not applied: too few steps fitted
        #: (time s, leg length m) of every update applied
        self.used: list[tuple[float, float]] = []

    def add_starts(self, foot: int, starts: list[tuple[float, np.ndarray, np.ndarray]]) -> None:
        """The foot's own solution at its newest stance starts: (time s, position m, quaternion)."""
        self._starts[foot].extend((float(t), np.array(p[:2], dtype=float), quat.yaw_of(q)) for t, p, q in starts)

    def landing(self, front: int, t: float, swing: float) -> None:
        """A landing of ``front`` at its heel strike ``t`` (s), the rear foot's ``swing``."""
        start = self.stance_of.pop((front, float(t)), None)
        if start is not None:
            self._swings.append((start, front, float(swing)))

    def leg_at(self, t: float) -> float | None:
        """The leg length at time ``t`` (s), m: from the steps whose stance began at or before ``t``."""
        waiting = []
        for start, front, swing in self._swings:
            if start > t:
                waiting.append((start, front, swing))
                continue
            known = [s for s in self._starts[front] if s[0] <= start]
            if len(known) >= 2 and known[-1][0] == start:
                (_, xy0, yaw0), (_, xy1, yaw1) = known[-2], known[-1]
                ratio = leg_ratio(xy0, xy1, yaw0, yaw1, swing, self.turn_rad)
                if ratio is not None:
                    self.ratios.append(ratio)
                    self.n_fitted += 1
                    if self.n_fitted >= LEG_FIT_MIN_STEPS:
                        self._leg = float(np.median(self.ratios))
        self._swings = waiting
        return self.latest()

    def latest(self) -> float | None:
        """The leg length now, m (None: fewer than ``LEG_FIT_MIN_STEPS`` steps fitted)."""
        return self._leg

    def as_meta(self) -> dict[str, Any]:
        """The fit's record for ``meta``: its limits, the steps fitted and the length used per update."""
        return {
            "min_steps": LEG_FIT_MIN_STEPS,
            "window": LEG_FIT_WINDOW,
            "steps_fitted": self.n_fitted,
            "updates_waiting": self.waiting,
            "first_update_s": self.used[0][0] if self.used else None,
            "per_update": {"t_s": [t for t, _ in self.used], "leg_length_m": [leg for _, leg in self.used]},
        }
