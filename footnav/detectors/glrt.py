"""GLRT (SHOE) stance detector: Skog, Händel, Nilsson and Rantakokko, "Zero-velocity detection --
an algorithm evaluation", IEEE Trans. Biomed. Eng. 57(11), 2010 (Sec. III, the stance hypothesis
optimal detector); Chistyakov et al. 2021 eq. (4): the foot is at rest when

    T({f_l, w_l}_{W_n}) < gamma,

    T = (1/W) sum_{l in window} [ ||f_l - g f_mean / ||f_mean|| ||^2 / sigma_a^2
                                  + ||w_l||^2 / sigma_g^2 ]

over a window of W samples of specific force f_l (m/s^2) and angular rate w_l (rad/s), with
``f_mean`` the mean specific force of *that* window: at rest the accelerometer reads g along the
window's own "up", so a foot standing tilted (on a slope, on its toes) is still at rest.

Computation. With u = f_mean / ||f_mean||, the accelerometer sum expands to

    sum ||f_l - g u||^2 = sum ||f_l - f_mean||^2 + W (||f_mean|| - g)^2

(the cross term vanishes because sum (f_l - f_mean) = 0), i.e. W x (moving variance + squared
magnitude error of the mean). Both need only window sums of f and ||f||^2, and the gyro term a
window sum of ||w||^2: O(N) by cumulative sums (:func:`~footnav.detectors.threshold.window_sums`),
no loop over windows. The windowing, the ``combine`` rule and the minimum stance duration are the
threshold family's (:class:`~footnav.detectors.threshold.WindowedStanceDetector`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.detectors.threshold import Combine, WindowedStanceDetector, acc_moving_std, gyr_rms

__all__ = ["GlrtDetector", "glrt_statistic", "OPENSHOE_SIGMA_ACC_MPS2", "OPENSHOE_SIGMA_GYR_RADPS"]

#: OpenShoe's accelerometer weight sigma_a (settings.m, ``simdata.sigma_a = 0.01``), m/s^2.
OPENSHOE_SIGMA_ACC_MPS2 = 0.01
#: OpenShoe's gyroscope weight sigma_g (settings.m, ``simdata.sigma_g = 0.1*pi/180``), rad/s.
OPENSHOE_SIGMA_GYR_RADPS = 0.1 * np.pi / 180.0


def glrt_statistic(
    acc: NDArray[np.float64], gyr: NDArray[np.float64], win: int, sigma_acc_mps2: float, sigma_gyr_radps: float
) -> NDArray[np.float64]:
    """SHOE statistic T (Chistyakov et al. (2021), eq. 4) of every full window, by start index, (N-W+1,).

    Window k covers samples k .. k+W-1; its gravity direction is its own mean specific force.

    Parameters
    ----------
    acc, gyr
        Specific force (m/s^2) and angular rate (rad/s), (N, 3).
    win
        Window length W in samples, 1 <= W <= N.
    sigma_acc_mps2, sigma_gyr_radps
        Weights sigma_a (m/s^2) and sigma_g (rad/s) of the two terms.
    """
    acc_std, f_mean = acc_moving_std(acc, win)
    # (1/W) sum ||f_l - g u||^2 = moving variance + (||f_mean|| - g)^2   (module docstring)
    acc_term = acc_std**2 + (np.linalg.norm(f_mean, axis=1) - GRAVITY_MPS2) ** 2
    # (1/W) sum ||w_l||^2 = (RMS angular rate)^2
    gyr_term = gyr_rms(gyr, win) ** 2
    return acc_term / sigma_acc_mps2**2 + gyr_term / sigma_gyr_radps**2


class GlrtDetector(WindowedStanceDetector):
    """Generalised likelihood-ratio (SHOE) stance detector, Chistyakov et al. (2021), eq. 4 / Skog et al. 2010.

    Stance where ``T < gamma``, T the per-sample mean over a window of the squared specific force
    off gravity (gravity along the window's own mean) over sigma_a^2 plus the squared angular rate
    over sigma_g^2 (module docstring). ``score`` is T of the window centred on each sample.

    Parameters
    ----------
    window_s : float
        Window length, s; W = window_s x rate, rounded to an odd number of samples.
    gamma : float
        Threshold on T (dimensionless): a window is at rest when T < gamma.
    sigma_acc_mps2 : float
        Accelerometer weight sigma_a of T, m/s^2 (OpenShoe's 0.01).
    sigma_gyr_radps : float
        Gyroscope weight sigma_g of T, rad/s (OpenShoe's 0.1 deg/s).
    combine : str
        How overlapping windows decide a sample: "center" (the window centred on it), "any"
        (stance if any window holding it is at rest, OpenShoe's rule; widens stance) or "all"
        (only if every window holding it is; narrows stance).
    min_stance_s : float
        Stance runs shorter than this are discarded, s.
    min_swing_s : float
        Gaps shorter than this between two stance runs are bridged (one stance), s.

    Notes
    -----
    Reading the bound: with the other term quiet, ``T < gamma`` means an RMS angular rate below
    ``sigma_g sqrt(gamma)`` or an RMS specific-force error (off the window's own gravity) below
    ``sigma_a sqrt(gamma)``; with the defaults 0.49 rad/s (28 deg/s) and 2.8 m/s^2, the bounds of
    the threshold family. Only ``gamma sigma^2`` matters, so the sigmas keep OpenShoe's values and
    gamma is tuned on the shared recordings: at 2e4 the noisier xio sensor loses stances (xio_long
    loop closure 0.76 m instead of 0.22 m), OpenShoe's own 3e4 (set for W = 3 at 820 Hz) is a
    little worse on xio_long (0.27 m) and the fast pyshoe trials, and at 3e5 the roll of the foot
    at heel strike and heel off passes as stance (azure_fgo 2-D RMSE 0.46 / 0.19 m instead of
    0.28 / 0.05 m).

    How the defaults scale with the rate (valid 60-820 Hz):

    * ``window_s`` is in seconds, so W = 3, 5, 9, 17, 33 samples at 60, 100, 200, 400, 820 Hz:
      the window always spans the same stretch of motion.
    * T is a per-sample mean (the 1/W), so it measures signal power, not energy: the same motion
      gives the same T whatever W, and ``gamma`` does not change with W or the rate.
    * Sensor noise adds ~3 sigma_noise^2 / sigma^2 to T per sensor, and white noise's per-sample
      variance grows with the rate (density^2 x rate): at 820 Hz a consumer gyro
      (0.01 deg/s/sqrt(Hz)) and accelerometer (100 ug/sqrt(Hz)) add ~50 in all, far below gamma,
      so the test bounds motion, not noise, at every rate in the range.
    * Where the motion starts or stops abruptly, ``combine="center"`` puts the stance edge W//2
      samples inside the stance, ``"any"`` on the last still sample and ``"all"`` W-1 samples
      inside: about ``window_s / 2``, 0 and ``window_s`` seconds at any rate (20, 0 and 40 ms with
      the default window), so the stance does not depend on the rate.

    Examples
    --------
    >>> stance = GlrtDetector(gamma=3e4, combine="any").detect(imu)  # doctest: +SKIP
    >>> stance.mask, stance.score  # score = T  # doctest: +SKIP
    """

    name = "glrt"
    _positive_params = ("window_s", "gamma", "sigma_acc_mps2", "sigma_gyr_radps")

    def __init__(
        self,
        *,
        window_s: float = 0.04,
        gamma: float = 8e4,
        sigma_acc_mps2: float = OPENSHOE_SIGMA_ACC_MPS2,
        sigma_gyr_radps: float = OPENSHOE_SIGMA_GYR_RADPS,
        combine: Combine = "center",
        min_stance_s: float = 0.05,
        min_swing_s: float = 0.2,
    ) -> None:
        self.window_s = window_s
        self.gamma = gamma
        self.sigma_acc_mps2 = sigma_acc_mps2
        self.sigma_gyr_radps = sigma_gyr_radps
        self.combine = combine
        self.min_stance_s = min_stance_s
        self.min_swing_s = min_swing_s

    def window_statistic(self, imu: ImuData, win: int) -> NDArray[np.float64]:
        """The SHOE statistic T (Chistyakov et al. 2021, eq. 4) of every full window by start index,
        shape (N-W+1,)."""
        return glrt_statistic(imu.acc, imu.gyr, win, self.sigma_acc_mps2, self.sigma_gyr_radps)

    def window_threshold(self) -> float:
        """The threshold the statistic is compared with: ``gamma``."""
        return float(self.gamma)
