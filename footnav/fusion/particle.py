"""Particle-filter dual-foot fusion with lateral systematic drift (Lee, Cho & Park (2022)).

Two modes (``ParticleFusion(mode=...)``):

``"paper"`` -- the paper as written (:mod:`footnav.fusion.particle_ekf` holds one foot):

* each foot's EKF has the error state of eq. 3, ``[dp_z, dv (3), dphi_h (2), db_a (3)]``:
  no horizontal position, no heading, no gyro bias (the first standstill's mean rate), Phi of
  eq. 6, ZUPT of eq. 7; the horizontal position is a cloud of ``n_particles`` particles
  (eq. 2, 8-9);
* **propagation at every time update** (Algorithm 1, eq. 10-12): each particle moves with the
  mechanization's displacement plus a draw of ``N(0, P_vel dt^2)`` and, while the foot moves,
  the lateral drift ``C_b^n [0, f', 0]'`` with ``f' = Rayleigh(sigma_sys_m) - offset``, the
  offset the Rayleigh mean (``drift_mean="zero"``) or ``drift_offset_m`` (``"offset"``), split
  over the swing's samples so that one step's sum has the moments of one draw
  (:func:`footnav.fusion.particle_ekf.drift_scales`); ``sigma_sys_m=0``: no drift;
* **fusion** (eq. 13-14): at the end of each zero-velocity phase of a foot, the two clouds'
  means and covariances (1/N) are summed into one Gaussian mixture with equal weights, whose
  mean *and* covariance (``sum a_i (Sigma_i + (mu_i - mu)(mu_i - mu)')``) are the pedestrian's
  position;
* **update** (eq. 15-16): each particle of that foot is weighed by ``N(p_fused | x_n, Sigma^i)``
  and the cloud is resampled systematically (Kitagawa 1996). ``Sigma^i`` is the shoe's own
  cloud covariance (eq. 14; ``likelihood_cov="fused"``: the mixture's); the Gaussian is taken
  across the shoe's heading (``likelihood_axes``) around the pedestrian shifted by half
  ``step_width_m`` to the shoe's side. The particles never feed back into the EKF; no smoothing.

``"footnav"`` (default) -- footnav's variant: both feet in footnav's generic joint EKF
``[phi, v, p(, b)]`` (:mod:`footnav.fusion.joint`, with its RTS smoother); the particles move
once per step by the EKF's displacement and covariance growth; the drift is zero-mean; the
update uses the fused *mean* only, across the foot's heading, shifted by half the step width;
the EKF follows the cloud by Jeffrey's rule. Its points 1-5 below.

Measured (issue 36) on the paper's experiment rebuilt on the simulator (docs/make_papers.py:
the MTw's noise of Table 1, its 20 deg/h bias stability as a gyro bias walk of 7e-6
rad/s^2/sqrt(Hz), the paper's symmetric drift ``simulate(mirrored_yaw_rate_radps=6e-4)``, Sec.
2.1; threshold detector, forward EKF; 10 seeds; errors after aligning each track on its first
five steps, Sec. 2.1), total over both feet, paper mode with ``sigma_sys_m=0.1`` against
independent feet: square (3 laps, Table 3 waypoint error) 0.42 against 0.85 m (-51 %; paper
0.315 against 0.89 m, -65 %); straight 70 m (Table 2 final error) 0.39 against 0.86 m (-55 %;
paper -31 %). The other readings: ``likelihood_cov="fused"`` -9 % / -52 % (square / straight:
the mixture's covariance holds the feet's separation, so once they drift apart the weights are
nearly uniform), ``likelihood_axes="2d"`` +40 % / +112 %, ``drift_mean="offset"``
(``drift_offset_m=0.1``) -51 % / -31 %, ``step_width_m=0`` -33 % / -59 % (at sigma 0.05);
``sigma_sys_m`` 0 / 0.02 / 0.05 / 0.1 / 0.2 on the square: -2 / -14 / -36 / -51 / -53 % (a
cloud can only move within its own spread, which the drift term sets).

footnav's reading (``mode="footnav"``), where the paper leaves room:

1. *The feet in one frame.* Both feet run in the joint filter of :mod:`footnav.fusion.joint`
   (first step along +x, left foot at +y); the PF is their only coupling.
2. *Propagation noise.* ``P_vel dt^2`` summed over a step is, with the EKF's correlations, the
   growth of the EKF's horizontal position covariance from the foot's previous stance end to
   this one; that growth (its positive part) is the Gaussian term of eq. 10.
3. *The measurement.* The likelihood uses the component across the foot's heading only, and the
   pedestrian position shifted by half the step width to the foot's side. When a stance ends
   the other foot has just landed half a stride ahead and ``step_width_m`` to the side; taken
   literally (the foot's 2-D position measured by the pedestrian's), eq. 15 pulls the feet
   together along the walk at every step, and without the shift it pulls both onto the centre
   line. Measured on the simulator (20 seeds, gyro bias walk 5e-5 rad/s^2/sqrt(Hz), final
   errors, independent feet: E_p 0.62 m straight, 4.7 m rectangle): literal 2-D, E_p 3.65 m
   straight and 9.0 m rectangle (cw); lateral without the shift, the feet end 0.05 m apart
   instead of 0.2 m and E_p 0.68 m straight; as here, 0.21 m and 0.48 m. The drift the PF
   corrects is lateral (Sec. 2).
4. *Offset Rayleigh.* Offset by the Rayleigh mean, so the drift is skewed but unbiased (the
   paper fits the offset to a histogram; an unbiased drift needs no such fit). The foot's
   lateral axis is its heading relative to the first step (the sensor's yaw minus the yaw it
   had facing the first step), so a sensor mounted askew on the shoe does not turn it.
5. *The EKF follows the PF, without double counting.* After each PF update the EKF's
   horizontal position must be the PF's. Applying the cloud's mean and covariance as an
   ordinary position measurement would count the position information twice: the cloud's
   prior *is* the EKF's prior (same displacement, same covariance growth; the drift term
   apart), so the EKF would end with ``(P^-1 + Sigma^-1)^-1``, tighter than either, and its
   mean between its own and the PF's. Instead the EKF's horizontal-position marginal is
   *replaced* by the PF's (Jeffrey's rule, the conditional ``p(x_EKF | x_PF)`` of eq. 8 kept):
   this is the Kalman update with the equivalent measurement that carries only the information the
   PF added, ``R^-1 = Sigma^-1 -
   P^-1`` (see :func:`equivalent_measurement`). The other states (velocity, attitude, biases)
   move by their regression on the position, ``P_xp P_pp^-1 (mu - p^)``. Where the cloud is
   wider than the EKF (the drift term, which the EKF does not model), a measurement cannot
   widen the EKF: there the mean still follows the PF and the EKF's variance is kept.
   Measured against the double-counting update (20 seeds as in point 3): E_p the same within
   the seeds' spread (0.48 / 3.74 / 3.47 m against 0.48 / 4.04 / 3.43 m, straight / cw / ccw),
   the feet's final separation closer to the truth (|E_s - 0.2| 0.014-0.021 m against
   0.020-0.030 m).

All randomness comes from ``seed`` (``numpy.random.default_rng``).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from footnav.core.component import FootEstimator, Fusion
from footnav.core.errors import CompositionError
from footnav.core.parameters import MAX_LENGTH_M, require, require_in_range, require_non_negative
from footnav.core.types import FootTrajectory, FusionResult, ImuData, StanceResult
from footnav.fusion.independent import midpoint_path
from footnav.fusion.joint import (
    LEFT,
    RIGHT,
    EventQueue,
    FeetView,
    closing_time,
    finish_joint,
    first_step_yaw,
    forward_only,
    fuse_on_common_span,
    start_joint,
)
from footnav.fusion.particle_cloud import (
    _MIN_VAR_M2,
    _gaussian_weights,
    _moments,
    _propagate,
    _psd_sqrt_t,
    _weigh_and_resample,
    equivalent_measurement,
    gaussian_sum,
    mixture_mean,
    offset_rayleigh,
    systematic_resample,
)
from footnav.fusion.particle_ekf import N_STATES, PaperFoot, drift_scales
from footnav.nav import quaternion as quat
from footnav.nav.initial_alignment import align_first_stance

__all__ = ["MODES", "ParticleFusion", "ParticleSession"]

#: Values of ``ParticleFusion(mode=...)``.
MODES = ("paper", "footnav")
#: Values of ``drift_mean``, ``likelihood_cov`` and ``likelihood_axes`` (``mode="paper"``), default first.
DRIFT_MEANS, LIKELIHOOD_COVS, LIKELIHOOD_AXES = ("zero", "offset"), ("own", "fused"), ("lateral", "2d")

_EQUAL = np.ones(2)  # the Gaussian sum weighs the feet equally


#: The estimator parameters paper mode reads for its own EKF (eq. 3), with EkfEstimator's defaults.
_PAPER_NOISE_DEFAULTS = {
    "acc_noise_mps2_sqrthz": 0.05,
    "gyr_noise_radps_sqrthz": 2e-3,
    "acc_bias_walk_mps3_sqrthz": 1e-3,
    "zupt_std_mps": 0.01,
    "init_velocity_std_mps": 0.01,
    "init_attitude_std_rad": 0.01,
    "init_acc_bias_std_mps2": 0.05,
}


class ParticleFusion(Fusion):
    """Each foot's horizontal position in a particle filter, fused by a Gaussian sum (Lee, Cho & Park (2022)).

    Parameters
    ----------
    mode : {"footnav", "paper"}
        ``"paper"``: the paper's eq. 3 EKF, particles at each time update with the Rayleigh
        drift, the Gaussian sum as each shoe's measurement (eq. 10-16; read as the four
        parameters below say); ``"footnav"``: footnav's variant (joint EKF with RTS smoothing,
        points 1-5 of the module docstring).
    n_particles : int
        Particles per foot (Lee, Cho & Park (2022), Sec. 3.2: 100).
    sigma_sys_m : float
        Scale sigma of the offset-Rayleigh lateral drift per step, m (Lee, Cho & Park (2022),
        eq. 12; fitted there to Fig. 2's histogram, no number given). 0: no drift term at all,
        whatever ``drift_offset_m``; only the EKF's Gaussian spread.
    drift_offset_m : float
        ``"paper"`` with ``drift_mean="offset"``: the offset of eq. 12's Rayleigh distribution,
        m ("the Rayleigh distribution expressed in the positive domain was offset so that the
        negative domain could also be expressed", Sec. 2.2). With the default, sigma, the mode
        is at zero and the mean ``0.25 sigma`` per step toward the other foot.
    drift_mean : {"zero", "offset"}
        ``"paper"`` only: ``"zero"`` offsets eq. 12's Rayleigh by its mean ``sigma sqrt(pi/2)``
        (skewed, unbiased: the paper's text describes only the skew, "the mode of the
        distribution is skewed from the center", Sec. 2.2); ``"offset"`` by ``drift_offset_m``.
        ``"footnav"`` always offsets by the mean.
    likelihood_cov : {"own", "fused"}
        ``"paper"`` only: the ``Sigma^i`` of eq. 15, ``L ~ N(p_fused | mu^i, Sigma^i)``.
        ``"own"``: as eq. 14 defines it, "the mean and covariance representing each shoe's
        measured position", shoe i's own cloud covariance; ``"fused"``: the Gaussian sum's
        covariance (eq. 13), which holds the spread between the two clouds.
    likelihood_axes : {"lateral", "2d"}
        ``"paper"`` only: ``"lateral"`` weighs by the component of eq. 15 across shoe i's heading
        ("Position error occurs only in the lateral direction", Sec. 3.2); ``"2d"`` by the 2-D
        Gaussian as printed, which also pulls the foot along the walk toward the other foot,
        half a stride ahead when a stance ends.
    step_width_m : float
        Lateral distance between the feet, m: where the feet start, and each foot's offset from
        the pedestrian position in the likelihood, half of it to the foot's side (the
        simulator's walker: 0.2 m). 0 with ``"paper"``: both shoes start at the origin and each
        is taken for the pedestrian ("the estimated shoe position in each shoe can be assumed
        as two measures of pedestrian position", Sec. 3.2).
    seed : int
        Seed of ``numpy.random.default_rng`` for the particles.

    Notes
    -----
    ``mode="footnav"``, per foot and stance end (module docstring for the paper mode)::

        x_n <- x_n + dp_EKF + N(0, P_pos) - s l f'(sigma_sys)              (eq. 10-12)
        p_fused = sum_i a_i N(mu_i, Sigma_i),  mu_i, Sigma_i the clouds    (eq. 13-14)
        q_n = N(l' (x_n - p_fused) - s w / 2 | 0, l' Sigma_i l)            (eq. 15-16)
        systematic resampling; the EKF's horizontal position := the cloud's N(mu, Sigma)

    with ``l`` the foot's lateral axis (its +y, nav frame), ``s`` +1 for the left foot and -1 for
    the right, ``w`` = ``step_width_m``. The result's ``meta`` holds ``pf_updates`` (one per
    stance end but the last of each foot) and ``n_particles``.

    Examples
    --------
    >>> fusion = ParticleFusion(n_particles=1000)  # doctest: +SKIP
    >>> pipe = footnav.make_pipeline("threshold", "ekf", fusion)  # doctest: +SKIP
    >>> res = pipe.run(footnav.simulate("straight", distance_m=50.0))  # doctest: +SKIP
    >>> res.left.position[-1, :2] - res.right.position[-1, :2]  # doctest: +SKIP
    array([-0.009,  0.21 ])
    """

    name = "particle"
    needs_two_feet: ClassVar[bool] = True
    needs_stepable_estimator: ClassVar[bool] = True

    def __init__(
        self,
        *,
        mode: str = "footnav",
        n_particles: int = 100,
        sigma_sys_m: float = 0.05,
        drift_offset_m: float = 0.05,
        drift_mean: str = "zero",
        likelihood_cov: str = "own",
        likelihood_axes: str = "lateral",
        step_width_m: float = 0.2,
        seed: int = 0,
    ) -> None:
        self.mode = mode
        self.drift_mean = drift_mean
        self.likelihood_cov = likelihood_cov
        self.likelihood_axes = likelihood_axes
        self.n_particles = n_particles
        self.sigma_sys_m = sigma_sys_m
        self.drift_offset_m = drift_offset_m
        self.step_width_m = step_width_m
        self.seed = seed

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        # Time and memory grow linearly with n_particles at every stance of the walk: 10**5
        # (1000x the default) is about the largest a one-hour walk finishes with in minutes.
        require_in_range(self, "n_particles", low=2, high=100_000, integer=True)
        # numpy.random.default_rng takes seeds >= 0 only (a negative one raised ValueError)
        require_in_range(self, "seed", low=0, high=2**128, integer=True)
        require_non_negative(self, "sigma_sys_m", "step_width_m", high=MAX_LENGTH_M)
        require(self.mode in MODES, self, "mode", " or ".join(repr(m) for m in MODES))
        require_in_range(self, "drift_offset_m", low=-MAX_LENGTH_M, high=MAX_LENGTH_M)
        require(self.drift_mean in DRIFT_MEANS, self, "drift_mean", " or ".join(repr(m) for m in DRIFT_MEANS))
        require(
            self.likelihood_cov in LIKELIHOOD_COVS,
            self,
            "likelihood_cov",
            " or ".join(repr(m) for m in LIKELIHOOD_COVS),
        )
        require(
            self.likelihood_axes in LIKELIHOOD_AXES,
            self,
            "likelihood_axes",
            " or ".join(repr(m) for m in LIKELIHOOD_AXES),
        )

    def fuse(
        self,
        estimator: FootEstimator,
        left: ImuData,
        stance_left: StanceResult,
        right: ImuData | None = None,
        stance_right: StanceResult | None = None,
    ) -> FusionResult:
        """Both feet's EKFs with their horizontal positions carried by particle clouds.

        On the feet's common time span; outside it each foot alone
        (:func:`footnav.fusion.joint.fuse_on_common_span`).
        """
        return fuse_on_common_span(self, estimator, left, stance_left, right, stance_right, self._fuse_span)

    def _fuse_span(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """:meth:`fuse` on feet that share their whole time span."""
        if self.mode == "paper":
            if getattr(estimator, "closed_loop", False):
                raise CompositionError(
                    f"fusion {self.name!r} mode='paper' runs its own per-foot filters (Lee, Cho & Park 2022, eq. 3) "
                    "and does not apply the estimator's closed_loop; turn closed_loop off or use mode='footnav'"
                )
            return self._fuse_paper(estimator, left, stance_left, right, stance_right)
        return self._fuse_footnav(estimator, left, stance_left, right, stance_right)

    def _fuse_paper(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """Lee, Cho & Park (2022) as written: each foot's EKF of eq. 3 (no horizontal position, no
        yaw) with its particles moved at every time update (eq. 10-12), the clouds' Gaussian sum
        (eq. 13-14) the measurement of each foot's PF at the end of each of its zero-velocity
        phases (eq. 15-16), systematic resampling. No smoothing (the paper filters forward)."""
        rng = np.random.default_rng(self.seed)
        n = int(self.n_particles)
        params = estimator.get_params()
        forward = forward_only(estimator)
        var = {k: float(params.get(k, d)) ** 2 for k, d in _PAPER_NOISE_DEFAULTS.items()}
        noise = [
            var["acc_noise_mps2_sqrthz"],
            var["gyr_noise_radps_sqrthz"],
            var["acc_bias_walk_mps3_sqrthz"],
            var["zupt_std_mps"],
        ]
        cov0 = (
            [0.0]
            + [var["init_velocity_std_mps"]] * 3
            + [var["init_attitude_std_rad"]] * 2
            + [var["init_acc_bias_std_mps2"]] * 3
        )
        assert len(cov0) == N_STATES
        still = float(params.get("still_gyr_max_radps", 0.05))
        half = 0.5 * float(self.step_width_m)
        feet, metas, yaw0 = [], [], []
        for foot, (imu, st) in enumerate(((left, stance_left), (right, stance_right))):
            # the nav frame of the joint filter (joint.start_joint): the first step along +x,
            # the left foot at +y
            yaw = first_step_yaw(forward, imu, st)
            s0, align, meta = align_first_stance(imu, st, still_gyr_max_radps=still, stacklevel=5)
            side = 1.0 if foot == RIGHT else -1.0  # the right shoe's tail along its +y (Sec. 2.2)
            p0 = np.array([0.0, -side * half, 0.0])
            sigma = float(self.sigma_sys_m)
            offset_m = sigma * math.sqrt(0.5 * math.pi) if self.drift_mean == "zero" else float(self.drift_offset_m)
            scale, offset = drift_scales(st.mask, sigma, offset_m)
            feet.append(
                PaperFoot(
                    imu.t,
                    imu.acc,
                    imu.gyr,
                    st.mask,
                    s0,
                    quat.multiply(quat.from_yaw(yaw), align.quaternion),
                    p0,
                    align.gyro_bias_radps,
                    cov0,
                    noise,
                    np.tile(p0[:2], (n, 1)),
                    side,
                    scale,
                    offset,
                )
            )
            metas.append(meta)
            yaw0.append(quat.yaw_of(feet[-1].q[0]))
        events = sorted(
            (float(imu.t[stop - 1]), foot)
            for foot, (imu, st) in enumerate(((left, stance_left), (right, stance_right)))
            for _, stop in st.intervals[:-1]
        )
        times = (left.t, right.t)
        for t, foot in events:
            for f in (LEFT, RIGHT):
                feet[f].run_until(np.searchsorted(times[f], t, side="right") - 1, rng)
            moments = []
            for f in (LEFT, RIGHT):
                mean, cov_c = np.empty(2), np.empty((2, 2))
                _moments(feet[f].cloud, mean, cov_c)  # eq. 14
                moments.append((mean, cov_c))
            # eq. 13: the pedestrian's position, the equal-weight Gaussian sum of the two clouds
            z, cov_z = gaussian_sum(np.array([m for m, _ in moments]), np.array([c for _, c in moments]), _EQUAL)
            # eq. 15-16: q_n = N(p_fused | x_n, Sigma), systematic resampling
            weights = self._paper_weights(feet[foot], z, moments[foot][1], cov_z, yaw0[foot], foot)
            feet[foot].set_cloud(feet[foot].cloud[systematic_resample(weights, rng)])
        out = []
        for f, (imu, st) in enumerate(((left, stance_left), (right, stance_right))):
            feet[f].run_until(len(imu.t) - 1, rng)
            pf = feet[f]
            out.append(
                FootTrajectory(
                    t=imu.t,
                    position=pf.position,
                    velocity=pf.velocity,
                    quaternion=pf.quaternion,
                    position_std=pf.position_std,
                    steps=st.intervals,
                    meta={**metas[f], "estimator": "particle-ekf (Lee, Cho & Park 2022, eq. 3)"},
                )
            )
        meta = {"fusion": self.describe(), "pf_updates": len(events), "n_particles": n}
        return FusionResult(left=out[0], right=out[1], path=midpoint_path(out[0], out[1]), meta=meta)

    def _paper_weights(self, pf: PaperFoot, z, cov_own, cov_fused, yaw0: float, foot: int) -> np.ndarray:
        """Eq. 15's weights of ``pf``'s particles (unnormalised, the largest 1), read as
        ``likelihood_cov``, ``likelihood_axes`` and ``step_width_m`` say (class docstring)."""
        # eq. 14-15 name Sigma^i, shoe i's own covariance; "fused" takes the Gaussian sum's (eq. 13)
        cov = cov_own if self.likelihood_cov == "own" else cov_fused
        heading = quat.yaw_of(pf.q[0]) - yaw0  # relative to the first step: a skewed mount does not turn it
        lateral = np.array([-math.sin(heading), math.cos(heading)])  # the shoe's +y, nav frame
        side = 1.0 if foot == LEFT else -1.0
        # the pedestrian seen from shoe i: half a step width to its side (0: the shoe is the pedestrian)
        z = z + side * 0.5 * float(self.step_width_m) * lateral
        if self.likelihood_axes == "2d":
            return _gaussian_weights(pf.cloud, z, cov)
        d = (pf.cloud - z) @ lateral
        logw = -0.5 * d * d / max(float(lateral @ cov @ lateral), _MIN_VAR_M2)
        return np.exp(logw - logw.max())

    def session(self, estimator: Any, start_s: float) -> ParticleSession:
        """mode="footnav"'s particle updates on a joint filter that grows as samples arrive
        (online mode; :class:`footnav.core.component.FusionSession`), from the feet's common start
        ``start_s`` (s).

        Raises
        ------
        CompositionError
            With ``mode="paper"``: it runs its own per-foot filters (Lee, Cho & Park 2022, eq. 3),
            not the joint filter an online stream feeds.
        """
        self.validate_params()
        if self.mode != "footnav":
            raise CompositionError(
                f"fusion {self.name!r} with mode={self.mode!r} is offline only: it runs its own per-foot filters "
                "(Lee, Cho & Park 2022, eq. 3), not the joint filter an online stream feeds; mode='footnav' runs online"
            )
        return ParticleSession(self)

    def _fuse_footnav(self, estimator, left, stance_left, right, stance_right) -> FusionResult:
        """footnav's variant (module docstring, points 1-5): one session over the whole walk."""
        imus, stances = (left, right), (stance_left, stance_right)
        filt = start_joint(estimator, left, stance_left, right, stance_right, self.step_width_m)
        session = ParticleSession(self, closing_time(estimator, imus, stances))
        landings = [imu.t[st.intervals[1:, 0]] for imu, st in zip(imus, stances)]
        stop = min(left.t[-1], right.t[-1])
        session.advance(filt, stop, landings, FeetView.of(imus, stances), stop_s=stop)
        return finish_joint(estimator, filt, stance_left, stance_right, session.finish(), imus)


class ParticleSession:
    """mode="footnav"'s work on one joint filter (:class:`ParticleFusion`, module docstring points
    1-5; :class:`footnav.core.component.FusionSession`): at the end of each zero-velocity phase of a
    foot but its last, that foot's cloud is moved, weighed by the feet's Gaussian sum and
    resampled, and the joint filter follows the cloud.

    A phase's end is an update only when another phase of the foot follows, so the update at a
    foot's latest phase end is known once the foot lands again: online, the joint filter waits
    there (:meth:`known_until`).

    Parameters
    ----------
    fusion
        The particle fusion (its parameters; the random draws from its ``seed``).
    closing_s
        No update after this time, s (the estimator's closed loop takes over there).
    """

    #: Only the phase end before each landing is read back (a new segment keeps the foot's
    #: latest stance from its start).
    history_s = 0.0

    def __init__(self, fusion: ParticleFusion, closing_s: float = math.inf) -> None:
        self.fusion = fusion
        self.step_width_m = float(fusion.step_width_m)
        self.rng = np.random.default_rng(fusion.seed)
        self.n = int(fusion.n_particles)
        self._events = EventQueue(closing_s)  # (end of a zero-velocity phase, foot), known, not yet applied
        self.n_events = 0
        self._started = False

    def known_until(self, view: FeetView, final_s: float) -> float:
        """Up to (not at) the end of a foot's latest zero-velocity phase that no landing follows
        yet; else every final sample's time."""
        until = final_s
        for mask, times in zip(view.masks, view.times):
            if len(mask) and not mask[-1]:
                back = mask[::-1]
                k = len(mask) - 1 - int(np.argmax(back)) if back.any() else 0
                until = min(until, float(np.nextafter(times[k], -np.inf)))
        return until

    def _begin(self, filt) -> None:
        """The clouds where the EKF starts, spread as it is (before the filter runs)."""
        feet = (LEFT, RIGHT)
        self.pos = [filt.block(f, "pos").start for f in feet]  # x, y of the foot's position error
        self.h_pos = [filt.selection(np.array([o, o + 1])) for o in self.pos]
        # the yaw each sensor has when its foot faces the first step (+x)
        self.yaw0 = [quat.yaw_of(filt.quaternion(f)) for f in feet]
        cov = filt.covariance
        # per foot: the EKF's horizontal position and its covariance at the foot's last PF update
        self.last_p = [filt.position(f)[:2] for f in feet]
        self.last_cov = [cov[o : o + 2, o : o + 2].copy() for o in self.pos]
        # the clouds start where the EKF starts, spread as it is; means: each cloud's at its last update
        self.clouds, self.means = [], []
        self.sqrt_t = np.empty((2, 2))
        for f in feet:
            _psd_sqrt_t(self.last_cov[f], self.sqrt_t)
            self.clouds.append(self.last_p[f] + self.rng.standard_normal((self.n, 2)) @ self.sqrt_t)
            mean, cov_c = np.empty(2), np.empty((2, 2))
            _moments(self.clouds[f], mean, cov_c)
            self.means.append(mean)
        self.resampled, self.logw = np.empty((self.n, 2)), np.empty(self.n)
        self.a, self.y, self.r = np.empty((2, 2)), np.empty(2), np.empty(2)

    def advance(self, filt, until_s: float, landings, view: FeetView, *, stop_s: float | None = None) -> None:
        """Apply the update of every phase end at or before ``until_s`` (s; all of them with
        ``stop_s``, the feet's common end) whose foot has landed again; ``landings``: each foot's
        newly known stance starts, s; ``view``: the feet in the filter's sample indexing."""
        if not self._started:
            self._started = True
            self._begin(filt)
        for foot, new in enumerate(landings):
            times, mask = view.times[foot], view.masks[foot]
            for start_s in np.asarray(new, dtype=float).ravel():
                s = int(np.searchsorted(times, start_s))
                end = s - 1 - int(np.argmax(mask[s - 1 :: -1]))  # the phase the landing follows: its last sample
                self._events.add(times[end], foot)
                self.n_events += 1
        for t, foot in self._events.due(until_s, stop_s is not None):
            self._update(filt, t, foot)

    def _update(self, filt, t: float, foot: int) -> None:
        """The foot's cloud moved, weighed and resampled at the end of its zero-velocity phase at
        ``t`` (s); the joint filter follows it (module docstring, points 1-5)."""
        fusion, rng = self.fusion, self.rng
        filt.run_until(t)
        other = 1 - foot
        o = self.pos[foot]
        cov = filt.covariance
        p, cov_p = filt.position(foot)[:2], cov[o : o + 2, o : o + 2]
        side = 1.0 if foot == LEFT else -1.0
        heading = quat.yaw_of(filt.quaternion(foot)) - self.yaw0[foot]
        lateral = np.array([-math.sin(heading), math.cos(heading)])  # the foot's +y, nav frame
        # eq. 10-12: the cloud of the foot that stood moves with its EKF, spread by the EKF's
        # position covariance growth since its last update (the sum of P_vel dt^2, eq. 11)
        # and by the lateral drift, its tail to the left for the right foot and mirrored
        if fusion.sigma_sys_m > 0:
            drift = -side * offset_rayleigh(fusion.sigma_sys_m, self.n, rng)
        else:
            drift = np.zeros(self.n)
        _psd_sqrt_t(cov_p - self.last_cov[foot], self.sqrt_t)
        mean_f, cov_f = np.empty(2), np.empty((2, 2))
        normals = rng.standard_normal((self.n, 2))
        _propagate(self.clouds[foot], p - self.last_p[foot], self.sqrt_t, normals, drift, lateral, mean_f, cov_f)
        # the other foot's cloud enters the sum only by its mean, which moves with its EKF
        # without drawing
        mean_o = self.means[other] + (filt.position(other)[:2] - self.last_p[other])
        # eq. 13-14: the pedestrian is the Gaussian sum of the two clouds; eq. 15 uses its
        # mean only, so the sum's covariance (and the other cloud's) is never formed
        z = mixture_mean(np.array([mean_f, mean_o]), _EQUAL)
        # eq. 15-16: L = N(p_fused | x_n, Sigma_i) across the foot's heading, with the foot
        # half a step width to its side of the pedestrian; systematic resampling
        var = max(float(lateral @ cov_f @ lateral), _MIN_VAR_M2)
        mean, cov_c = np.empty(2), np.empty((2, 2))
        z_foot = z + side * 0.5 * self.step_width_m * lateral
        _weigh_and_resample(
            self.clouds[foot], z_foot, lateral, var, rng.random(), self.resampled, self.logw, mean, cov_c
        )
        self.clouds[foot], self.resampled = self.resampled, self.clouds[foot]
        # the EKF's horizontal position := the cloud's N(mean, cov) by Jeffrey's rule: only
        # what the PF added enters the EKF (module docstring, point 5)
        equivalent_measurement(p, cov_p + _MIN_VAR_M2 * np.eye(2), mean, cov_c, self.a, self.y, self.r)
        filt.update(self.a @ self.h_pos[foot], self.y, self.r)
        cov = filt.covariance
        self.last_p[foot], self.last_cov[foot] = filt.position(foot)[:2], cov[o : o + 2, o : o + 2].copy()
        self.means[foot] = mean

    def finish(self) -> dict:
        """The fusion's meta, after the last :meth:`advance`."""
        return {"fusion": self.fusion.describe(), "pf_updates": self.n_events, "n_particles": self.n}
