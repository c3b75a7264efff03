"""GLRT (SHOE) stance detector: Skog et al., "Zero-velocity detection -- an algorithm evaluation",
IEEE TBME 2010, eq. (9); used in seed 002 eq. (4) (standstill when T < gamma).

For a window of W samples of specific force f_l and angular rate w_l,

    T = (1/W) sum_l [ ||f_l - g f_mean / ||f_mean|| ||^2 / sigma_a^2  +  ||w_l||^2 / sigma_g^2 ]

with the gravity direction taken from the window's own mean specific force ``f_mean`` (so a
tilted foot at rest is still at rest). Expanding the square, sum ||f_l - g u||^2 =
sum ||f_l||^2 - 2 g W ||f_mean|| + W g^2 with u = f_mean / ||f_mean||, so T needs only window sums
of f, ||f||^2 and ||w||^2: O(N) by cumulative sums.

Rate: ``window_s`` is in seconds, so W scales with the rate; T is a per-sample mean, so ``gamma``
does not depend on W. ``sigma_acc_mps2`` and ``sigma_gyr_radps`` weigh the two terms; with the
defaults, T < gamma at rest means roughly |w| below sqrt(gamma) sigma_g ~ 0.96 rad/s or
||f| - g| below sqrt(gamma) sigma_a ~ 5.5 m/s^2 when the other term is quiet (OpenShoe's values;
they work from 60 to 820 Hz because they bound signal magnitudes, not noise).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d, minimum_filter1d

from footnav.core.component import StanceDetector, require
from footnav.core.types import GRAVITY_MPS2, ImuData, StanceResult
from footnav.detectors._stance import centred_mean, stance_result, window_samples

__all__ = ["GlrtDetector", "glrt_statistic"]


def glrt_statistic(
    acc: NDArray[np.float64], gyr: NDArray[np.float64], win: int, sigma_acc: float, sigma_gyr: float
) -> NDArray[np.float64]:
    """SHOE statistic T (Skog 2010 eq. 9) of the window centred on each sample, (N,).

    Parameters
    ----------
    acc, gyr
        Specific force (m/s^2) and angular rate (rad/s), (N, 3).
    win
        Window length W in samples.
    sigma_acc, sigma_gyr
        Weights of the two terms, m/s^2 and rad/s.
    """
    f_mean = centred_mean(acc, win)
    f2_mean = centred_mean(np.einsum("ij,ij->i", acc, acc), win)
    w2_mean = centred_mean(np.einsum("ij,ij->i", gyr, gyr), win)
    # (1/W) sum ||f - g u||^2 = mean ||f||^2 - 2 g ||f_mean|| + g^2
    acc_term = f2_mean - 2.0 * GRAVITY_MPS2 * np.linalg.norm(f_mean, axis=1) + GRAVITY_MPS2**2
    return np.maximum(acc_term, 0.0) / sigma_acc**2 + w2_mean / sigma_gyr**2


class GlrtDetector(StanceDetector):
    """Generalised likelihood-ratio (SHOE) stance detector, seed 002 eq. 4 / Skog et al. 2010.

    Parameters
    ----------
    window_s : float
        Window length, s (W = window_s x rate samples).
    gamma : float
        Threshold on the statistic T (dimensionless); stance where T < gamma.
    sigma_acc_mps2 : float
        Accelerometer weight sigma_a of the statistic, m/s^2.
    sigma_gyr_radps : float
        Gyroscope weight sigma_g of the statistic, rad/s.
    combine : {"center", "any", "all"}
        How windows make a per-sample decision: "center" uses the window centred on the sample;
        "any" marks a sample stance when any window containing it is below gamma (OpenShoe's
        rule, stance grows by up to W-1 samples); "all" only when every such window is.
    min_stance_s : float
        Stance runs shorter than this are discarded, s.

    Examples
    --------
    >>> stance = GlrtDetector(gamma=2e5).detect(imu)  # doctest: +SKIP
    >>> stance.mask, stance.score  # score = T
    """

    name = "glrt"

    def __init__(
        self,
        *,
        window_s: float = 0.05,
        gamma: float = 3e5,
        sigma_acc_mps2: float = 0.01,
        sigma_gyr_radps: float = 0.1 * np.pi / 180.0,
        combine: Literal["center", "any", "all"] = "center",
        min_stance_s: float = 0.05,
    ) -> None:
        self.window_s = window_s
        self.gamma = gamma
        self.sigma_acc_mps2 = sigma_acc_mps2
        self.sigma_gyr_radps = sigma_gyr_radps
        self.combine = combine
        self.min_stance_s = min_stance_s

    def validate_params(self) -> None:
        for name in ("window_s", "gamma", "sigma_acc_mps2", "sigma_gyr_radps"):
            v = getattr(self, name)
            require(isinstance(v, (int, float)) and np.isfinite(v) and v > 0, self, name, "a positive number")
        require(self.combine in ("center", "any", "all"), self, "combine", "'center', 'any' or 'all'")
        v = self.min_stance_s
        require(isinstance(v, (int, float)) and np.isfinite(v) and v >= 0, self, "min_stance_s", "a number >= 0")

    def detect(self, imu: ImuData) -> StanceResult:
        """Stance mask, foot-flat / heel-off events and the statistic T as ``score``."""
        self.validate_params()
        rate = imu.rate_hz
        win = window_samples(self.window_s, rate)
        t_stat = glrt_statistic(imu.acc, imu.gyr, win, self.sigma_acc_mps2, self.sigma_gyr_radps)
        below = t_stat < self.gamma
        if self.combine == "center" or win == 1:
            mask = below
        else:
            # the centred window of c spans c - W//2 .. c - W//2 + W - 1, so the windows that hold
            # sample s are those centred on s + W//2 - (W - 1) .. s + W//2: a W-wide max/min whose
            # scipy origin is (W - 1) - 2 (W//2) (0 for odd W, -1 for even W)
            filt = maximum_filter1d if self.combine == "any" else minimum_filter1d
            mask = filt(below.astype(np.uint8), size=win, origin=(win - 1) - 2 * (win // 2), mode="nearest").astype(bool)
        return stance_result(
            mask, rate, self.min_stance_s, t_stat,
            {"detector": self.describe(), "window_samples": win},
        )
