"""Observations of the HMM detector on the model-rate grid, and the paper's filtered pitch-like rate.

Li et al. (2018), Sec. 2 observe the 3-axis angular rate (eq. 2); footnav optionally adds
|specific force| - g. Every recording is low-pass filtered (when faster than the model rate) and
interpolated onto the model-rate grid (:func:`model_grid`); decoded states map back to the
recording's samples through :attr:`ModelGrid.nearest`. :func:`significant_axis` is the first step
of the re-ordering: the low-pass filtered rate of the axis with the largest magnitude.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import GRAVITY_MPS2, ImuData
from footnav.nav.interpolation import interp_columns

__all__ = ["FEATURES", "ModelGrid", "lowpass", "model_grid", "significant_axis"]

#: Observation vectors: the paper's 3-axis angular rate (rad/s), optionally with |f| - g (m/s^2).
FEATURES = {"gyr": ("gyr_x", "gyr_y", "gyr_z"), "gyr+acc_norm": ("gyr_x", "gyr_y", "gyr_z", "acc_norm")}

#: Order of every Butterworth low-pass here; applied forwards and backwards (zero phase), so the
#: magnitude response is squared (effective order 8) and peaks and valleys are not delayed.
BUTTER_ORDER = 4
#: Anti-alias cutoff before resampling to the model rate, as a fraction of the model rate (0.4 x
#: 100 Hz = 40 Hz): below the new Nyquist frequency (0.5) with margin for the filter's roll-off,
#: far above the gait's content (a few Hz).
ANTI_ALIAS_FRACTION = 0.4
#: Relative rate difference below which a recording is taken at the model rate as it is.
SAME_RATE_RTOL = 1e-6


def lowpass(x: ArrayLike, cutoff_hz: float, rate_hz: float) -> NDArray[np.float64]:
    """Zero-phase Butterworth low-pass (order ``BUTTER_ORDER``, forwards and backwards) along axis 0.

    scipy.signal ``butter`` + ``sosfiltfilt``. A signal shorter than scipy's default edge padding
    is padded by what it has (no error on short recordings); a cutoff at or above the Nyquist
    frequency returns the signal unchanged.
    """
    x = np.asarray(x, dtype=np.float64)
    if cutoff_hz >= 0.5 * rate_hz or len(x) < 2:
        return x.copy()
    from scipy.signal import butter, sosfiltfilt  # here: scipy.signal takes ~0.3 s to import

    sos = butter(BUTTER_ORDER, cutoff_hz, btype="low", fs=rate_hz, output="sos")
    default_pad = 3 * (2 * len(sos) + 1)
    return sosfiltfilt(sos, x, axis=0, padlen=min(default_pad, len(x) - 1))


def significant_axis(gyr: ArrayLike, rate_hz: float, cutoff_hz: float) -> tuple[NDArray[np.float64], int]:
    """Low-pass filtered angular rate of its most significant axis (Li et al. (2018), Sec. 2, first step).

    "we filter the angular rate by using a low-pass Butterworth filter, and select the most
    significant axis, i.e. the axis whose signal has the largest magnitude": the axis with the
    largest RMS of the filtered rate (the pitch axis of a walking foot).

    Parameters
    ----------
    gyr
        Angular rate (N, 3) in rad/s.
    rate_hz
        Its sampling rate in Hz.
    cutoff_hz
        Cutoff frequency of the low-pass in Hz.

    Returns
    -------
    signal, axis
        The filtered rate of that axis (N,) in rad/s, and the axis index.
    """
    filtered = lowpass(gyr, cutoff_hz, rate_hz)
    axis = int(np.argmax(np.sqrt(np.mean(filtered**2, axis=0))))
    return filtered[:, axis], axis


@dataclass(frozen=True)
class ModelGrid:
    """One recording's features on the model-rate grid and the map back to its samples."""

    features: NDArray[np.float64]  # (M, F) at the model rate
    t_model: NDArray[np.float64]  # (M,) s
    nearest: NDArray[np.int64]  # (N,) model sample nearest to each recording sample


def model_grid(imu: ImuData, features: str, model_rate_hz: float) -> ModelGrid:
    """``imu``'s observation vectors (``FEATURES[features]``) resampled to ``model_rate_hz``.

    A recording already at the model rate is taken as it is; a faster one is low-pass filtered
    at ``ANTI_ALIAS_FRACTION`` of the model rate first; then every feature is interpolated
    linearly onto the grid ``t[0] + k / model_rate_hz``.
    """
    if not isinstance(imu, ImuData):
        raise InvalidInputError(f"expected an ImuData recording, got {type(imu).__name__}")
    x = imu.gyr
    if features == "gyr+acc_norm":
        x = np.column_stack([x, np.linalg.norm(imu.acc, axis=1) - GRAVITY_MPS2])
    rate = imu.rate_hz
    t0 = float(imu.t[0])
    # + 1e-9: a duration of exactly k model periods must not round down to k - 1
    n_model = int(math.floor(imu.duration_s * model_rate_hz + 1e-9)) + 1
    t_model = t0 + np.arange(n_model) / model_rate_hz
    if abs(rate / model_rate_hz - 1.0) < SAME_RATE_RTOL and n_model == imu.n_samples:
        # already at the model rate: the samples themselves, no interpolation
        return ModelGrid(np.array(x, dtype=np.float64), np.array(imu.t), np.arange(imu.n_samples))
    if rate > model_rate_hz:
        x = lowpass(x, ANTI_ALIAS_FRACTION * model_rate_hz, rate)
    feats = interp_columns(t_model, imu.t, x)
    nearest = np.clip(np.rint((imu.t - t0) * model_rate_hz).astype(np.int64), 0, n_model - 1)
    return ModelGrid(feats, t_model, nearest)
