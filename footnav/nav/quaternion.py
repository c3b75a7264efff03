"""Unit quaternions [w, x, y, z], body -> navigation (Hamilton product).

``q`` rotates a body-frame vector into the nav frame: ``v_nav = rotate(q, v_body)``, and
``as_matrix(q)`` is the direction-cosine matrix C_b^n. Vectorised numpy functions take (..., 4)
arrays; the ``*_nb`` functions are numba kernels for per-sample loops (scalars in, scalars out or
written into a preallocated output, no allocation).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav._numba import njit  # numba.njit that survives a read-only install

__all__ = [
    "IDENTITY",
    "yaw_of",
    "wrap_angle",
    "multiply",
    "conjugate",
    "normalize",
    "as_matrix",
    "from_matrix",
    "rotate",
    "from_rotvec",
    "as_rotvec",
    "from_euler",
    "as_euler",
    "yaw",
    "from_yaw",
]

IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


def _q(q: ArrayLike) -> NDArray[np.float64]:
    return np.asarray(q, dtype=np.float64)


def multiply(p: ArrayLike, q: ArrayLike) -> NDArray[np.float64]:
    """Hamilton product p * q (apply q, then p), broadcasting over leading axes."""
    p, q = _q(p), _q(q)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ],
        axis=-1,
    )


def conjugate(q: ArrayLike) -> NDArray[np.float64]:
    """Inverse rotation of a unit quaternion."""
    q = _q(q).copy()
    q[..., 1:] *= -1.0
    return q


def normalize(q: ArrayLike) -> NDArray[np.float64]:
    """Unit-norm quaternion with w >= 0 (the same rotation, one canonical sign)."""
    q = _q(q)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return np.where(q[..., :1] < 0, -q, q)


def as_matrix(q: ArrayLike) -> NDArray[np.float64]:
    """Direction-cosine matrix C_b^n (..., 3, 3) of unit quaternion(s) q."""
    w, x, y, z = np.moveaxis(_q(q), -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=-2,
    )


def from_matrix(c: ArrayLike) -> NDArray[np.float64]:
    """Quaternion (w >= 0) of rotation matrix / matrices (..., 3, 3) (Shepperd's method)."""
    c = np.asarray(c, dtype=np.float64)
    m = c.reshape(-1, 3, 3)
    tr = np.trace(m, axis1=1, axis2=2)
    cand = np.stack([tr, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], axis=1)
    k = np.argmax(cand, axis=1)
    out = np.empty((len(m), 4))
    for i, (mi, ki) in enumerate(zip(m, k)):
        if ki == 0:
            s = 2.0 * np.sqrt(1.0 + tr[i])
            out[i] = [0.25 * s, (mi[2, 1] - mi[1, 2]) / s, (mi[0, 2] - mi[2, 0]) / s, (mi[1, 0] - mi[0, 1]) / s]
        elif ki == 1:
            s = 2.0 * np.sqrt(1.0 + mi[0, 0] - mi[1, 1] - mi[2, 2])
            out[i] = [(mi[2, 1] - mi[1, 2]) / s, 0.25 * s, (mi[0, 1] + mi[1, 0]) / s, (mi[0, 2] + mi[2, 0]) / s]
        elif ki == 2:
            s = 2.0 * np.sqrt(1.0 + mi[1, 1] - mi[0, 0] - mi[2, 2])
            out[i] = [(mi[0, 2] - mi[2, 0]) / s, (mi[0, 1] + mi[1, 0]) / s, 0.25 * s, (mi[1, 2] + mi[2, 1]) / s]
        else:
            s = 2.0 * np.sqrt(1.0 + mi[2, 2] - mi[0, 0] - mi[1, 1])
            out[i] = [(mi[1, 0] - mi[0, 1]) / s, (mi[0, 2] + mi[2, 0]) / s, (mi[1, 2] + mi[2, 1]) / s, 0.25 * s]
    return normalize(out.reshape(c.shape[:-2] + (4,)))


def rotate(q: ArrayLike, v: ArrayLike) -> NDArray[np.float64]:
    """Rotate body-frame vector(s) v (..., 3) into the nav frame: C_b^n(q) v."""
    return np.einsum("...ij,...j->...i", as_matrix(q), np.asarray(v, dtype=np.float64))


def from_rotvec(r: ArrayLike) -> NDArray[np.float64]:
    """Quaternion of rotation vector r (..., 3) in rad (axis * angle)."""
    r = np.asarray(r, dtype=np.float64)
    angle = np.linalg.norm(r, axis=-1, keepdims=True)
    half = 0.5 * angle
    # sin(a/2)/a -> 1/2 as a -> 0; the series keeps small rotations exact to double precision
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(angle > 1e-8, np.sin(half) / np.where(angle > 0, angle, 1.0), 0.5 - angle**2 / 48.0)
    return np.concatenate([np.cos(half), k * r], axis=-1)


def as_rotvec(q: ArrayLike) -> NDArray[np.float64]:
    """Rotation vector (..., 3) in rad of unit quaternion(s), angle in [0, pi]."""
    q = normalize(q)
    s = np.linalg.norm(q[..., 1:], axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(s, q[..., :1])
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(s > 1e-12, angle / np.where(s > 0, s, 1.0), 2.0)
    return k * q[..., 1:]


def from_euler(roll: ArrayLike, pitch: ArrayLike, yaw: ArrayLike) -> NDArray[np.float64]:
    """Quaternion from ZYX Euler angles in rad: C_b^n = Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = (np.asarray(a, dtype=np.float64) * 0.5 for a in (roll, pitch, yaw))
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.stack(
        [
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ],
        axis=-1,
    )


def as_euler(q: ArrayLike) -> NDArray[np.float64]:
    """ZYX Euler angles (..., 3) = [roll, pitch, yaw] in rad."""
    w, x, y, z = np.moveaxis(normalize(q), -1, 0)
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - x * z), -1.0, 1.0))
    yw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.stack([roll, pitch, yw], axis=-1)


def yaw(q: ArrayLike) -> NDArray[np.float64]:
    """Heading (rotation about nav z) in rad of quaternion(s) q."""
    return as_euler(q)[..., 2]


def yaw_of(q: NDArray[np.float64]) -> float:
    """:func:`yaw` of one quaternion [w, x, y, z] as a float, rad: the ZYX yaw
    ``atan2(2 (w z + x y), 1 - 2 (y^2 + z^2))`` of q normalised, without the array machinery
    (per-step loops: :func:`yaw` of one quaternion costs some 20 numpy calls). Equal to
    :func:`yaw` to a few 1e-16 rad (rounding)."""
    w, x, y, z = (float(c) for c in q)
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def wrap_angle(angle_rad):
    """``angle_rad`` (a number or an array) wrapped to [-pi, pi), rad; a float for a number."""
    wrapped = (np.asarray(angle_rad, dtype=float) + np.pi) % (2.0 * np.pi) - np.pi
    return float(wrapped) if wrapped.ndim == 0 else wrapped


def from_yaw(angle: ArrayLike) -> NDArray[np.float64]:
    """Quaternion of a rotation by ``angle`` rad about the nav z axis."""
    a = np.asarray(angle, dtype=np.float64) * 0.5
    z = np.zeros_like(a)
    return np.stack([np.cos(a), z, z, np.sin(a)], axis=-1)


# -- numba kernels ------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def multiply_nb(p: NDArray, q: NDArray, out: NDArray) -> None:
    """out = p * q (Hamilton); out must not alias p or q."""
    out[0] = p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3]
    out[1] = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2]
    out[2] = p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1]
    out[3] = p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0]


@njit(cache=True, inline="always")
def from_rotvec_nb(rx: float, ry: float, rz: float, out: NDArray) -> None:
    """out = quaternion of rotation vector (rx, ry, rz) in rad."""
    a2 = rx * rx + ry * ry + rz * rz
    if a2 < 0.01:
        # below 0.1 rad (every per-sample turn of a foot at >= 100 Hz) the series to angle^6 is
        # exact to rounding (next terms < 1e-17) and avoids sin, cos and sqrt
        out[0] = 1.0 - a2 * (1.0 / 8.0 - a2 * (1.0 / 384.0 - a2 / 46080.0))
        k = 0.5 - a2 * (1.0 / 48.0 - a2 * (1.0 / 3840.0 - a2 / 645120.0))
    else:
        angle = np.sqrt(a2)
        k = np.sin(0.5 * angle) / angle
        out[0] = np.cos(0.5 * angle)
    out[1] = k * rx
    out[2] = k * ry
    out[3] = k * rz


@njit(cache=True, inline="always")
def as_matrix_nb(q: NDArray, out: NDArray) -> None:
    """out (3, 3) = C_b^n of unit quaternion q."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    out[0, 0] = 1 - 2 * (y * y + z * z)
    out[0, 1] = 2 * (x * y - w * z)
    out[0, 2] = 2 * (x * z + w * y)
    out[1, 0] = 2 * (x * y + w * z)
    out[1, 1] = 1 - 2 * (x * x + z * z)
    out[1, 2] = 2 * (y * z - w * x)
    out[2, 0] = 2 * (x * z - w * y)
    out[2, 1] = 2 * (y * z + w * x)
    out[2, 2] = 1 - 2 * (x * x + y * y)


@njit(cache=True, inline="always")
def normalize_nb(q: NDArray) -> None:
    """Normalise q in place to unit norm."""
    n = np.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    for i in range(4):
        q[i] /= n
