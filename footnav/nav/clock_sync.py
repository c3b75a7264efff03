"""Clock synchronisation of two IMUs from message exchanges (Chistyakov et al. (2021), Sec. 5B), and the clock map.

Chistyakov et al. 2021, Sec. 5B ("Синхронизация устройств"): a master (the phone) and
an IMU exchange time-stamped messages at the start and the end of a recording. Exchange i is
``[TM1_i, TI_i, TM2_i]``: master time when the request leaves, IMU time when the IMU stamps it
(and replies), master time when the reply arrives, all in s. With the master clock affine in the
IMU clock, ``t_master = a t_imu + b``, every exchange bounds the map::

    TM1_i < a TI_i + b < TM2_i

and two linear programs over ``x = [a, b]`` (LP1: min a, LP2: max a, subject to all bounds)
give the feasible interval ``a1 <= a <= a2``; the estimate is the midpoint of their solutions,
``a = (a1 + a2) / 2``, ``b = (b1 + b2) / 2``, and the IMU's samples are mapped to master time by
``t = a t_imu + b - delay`` with ``delay`` the constant radio latency measured separately
(0.03 s for their Bluetooth LE link). The paper reports < 10 ms misalignment over 10 minutes.

Without exchanges, :func:`footnav.nav.clock_from_data.align_from_data` finds the offset (and
drift) between two feet's clocks from the angular-rate energy. Either way the result is a
:class:`ClockMap`, which :func:`apply_clock` applies to a recording; :mod:`footnav.pipeline.sync` runs
both as a pipeline stage.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.core.types import ImuData

__all__ = ["ClockMap", "apply_clock", "fit_clock"]

# Relative tolerance (of the exchanges' round-trip scale) when clipping the feasible polygon.
_CLIP_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class ClockMap:
    """Affine map from an IMU's clock to a reference (master) clock: ``t = a t_imu + b - delay_s``.

    Attributes
    ----------
    a
        Rate, dimensionless (master seconds per IMU second).
    b
        Offset, s (master time at IMU time 0).
    delay_s
        Constant latency subtracted by :meth:`__call__`, s (Chistyakov et al. (2021): the BLE delay, ~0.03 s).
    n
        Exchanges used (``method="exchanges"``) or correlation windows (``method="data"``).
    method
        ``"exchanges"`` (:func:`fit_clock`, Chistyakov et al. (2021), Sec. 5B) or ``"data"``
        (:func:`footnav.nav.clock_from_data.align_from_data`).
    a_bounds, b_bounds
        ``method="exchanges"``: Chistyakov et al. (2021)'s intervals ``a1 <= a <= a2`` and
        ``min(b1, b2) <= b <= max(b1, b2)`` from the LP1/LP2 solutions ``[a1, b1]``, ``[a2, b2]``.
        (The a interval is the whole feasible range; the b interval is the paper's, b at the two
        extreme rates. For the guaranteed range of mapped times use :meth:`interval`.)
        None for a data-driven map.
    residuals_s
        ``method="exchanges"``: per exchange, ``a TI_i + b - (TM1_i + TM2_i) / 2`` in s, the mapped
        IMU stamp against the middle of its round trip: half the difference of the two one-way
        delays when the map is right. A trend in them says the clock is not affine. None otherwise.
    vertices
        ``method="exchanges"``: corners ``[a, b]`` (K, 2) of the polygon of all maps consistent
        with every exchange (the feasible set of LP1/LP2). None otherwise.
    stride_s
        ``method="data"``: stride period found in the gyro energy, s. None otherwise.
    alternatives_b
        ``method="data"``: other offsets b (s, same ``a``) that fit the data as well as ``b``,
        whole strides away; empty when the data single out ``b``.

    Examples
    --------
    >>> m = fit_clock([0.0, 600.0], [10.0, 610.01], [0.04, 600.04])
    >>> round(m.a, 6), round(m.b, 3)
    (0.999983, -9.98)
    >>> round(float(m(10.0)), 9)
    0.02
    """

    a: float
    b: float
    delay_s: float = 0.0
    n: int = 0
    method: str = "exchanges"
    a_bounds: tuple[float, float] | None = None
    b_bounds: tuple[float, float] | None = None
    residuals_s: NDArray[np.float64] | None = field(default=None, repr=False)
    vertices: NDArray[np.float64] | None = field(default=None, repr=False)
    stride_s: float | None = None
    alternatives_b: tuple[float, ...] = ()

    def __call__(self, t_imu: ArrayLike) -> NDArray[np.float64]:
        """Reference-clock times (s) of IMU times ``t_imu`` (s): ``a t_imu + b - delay_s``."""
        return self.a * np.asarray(t_imu, dtype=float) + self.b - self.delay_s

    def interval(self, t_imu: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lowest and highest reference time (s) any map consistent with the exchanges gives.

        The range of ``a t_imu + b - delay_s`` over the feasible polygon (:attr:`vertices`): a
        guaranteed bound if the clocks are affine and the delays non-negative, but not the
        accuracy, which with symmetric delays is much better than the interval's half width.

        Raises
        ------
        InvalidInputError
            The map does not come from exchanges (no feasible polygon).
        """
        if self.vertices is None:
            raise InvalidInputError(
                f"a {self.method!r} clock map has no feasible interval; only fit_clock gives one", field="vertices"
            )
        t = np.asarray(t_imu, dtype=float)
        values = np.multiply.outer(t, self.vertices[:, 0]) + self.vertices[:, 1]
        return values.min(axis=-1) - self.delay_s, values.max(axis=-1) - self.delay_s

    @property
    def drift_ppm(self) -> float:
        """Rate error of the IMU clock against the reference in ppm, ``(1 / a - 1) 1e6``
        (positive: the IMU clock runs fast, as ``clock_drift_ppm`` in :func:`footnav.simulate`)."""
        return (1.0 / self.a - 1.0) * 1e6


# -- from message exchanges (Chistyakov et al. (2021), Sec. 5B) ---------------------------------------------------


def _vector(x: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(f"expected a sequence of times in s, got {x!r}", field=name) from None
    if arr.ndim != 1:
        raise InvalidInputError(f"expected a 1-D sequence of times in s, got shape {arr.shape}", field=name)
    bad = np.flatnonzero(~np.isfinite(arr))
    if len(bad):
        raise InvalidInputError(f"exchange time {arr[bad[0]]!r} is not finite", field=name, index=int(bad[0]))
    return arr


def _lp(c: list[float], a_ub: NDArray, b_ub: NDArray):
    from scipy.optimize import linprog  # here: scipy.optimize is slow to import, and rarely needed

    return linprog(c=c, A_ub=a_ub, b_ub=b_ub, bounds=[(None, None), (None, None)], method="highs")


def _clip(poly: NDArray[np.float64], normal: NDArray[np.float64], limit: float, tol: float) -> NDArray[np.float64]:
    """Convex polygon ``poly`` (K, 2) cut to ``normal . x <= limit`` (Sutherland-Hodgman)."""
    s = poly @ normal - limit
    if (s <= tol).all():
        return poly
    out = []
    for k in range(len(poly)):
        p, q, sp, sq = poly[k], poly[(k + 1) % len(poly)], s[k], s[(k + 1) % len(poly)]
        if sp <= tol:
            out.append(p)
        if (sp < -tol and sq > tol) or (sp > tol and sq < -tol):
            out.append(p + (q - p) * (sp / (sp - sq)))
    return np.array(out).reshape(-1, 2)


def fit_clock(tm1: ArrayLike, ti: ArrayLike, tm2: ArrayLike, *, delay_s: float = 0.0) -> ClockMap:
    """Chistyakov et al. (2021), Sec. 5B: the affine clock map ``t_master = a t_imu + b`` from message exchanges.

    Parameters
    ----------
    tm1, ti, tm2
        Per exchange i, shape (N,): master time the request left, IMU time stamp, master time the
        reply arrived, s. Exchanges spread over the recording (Chistyakov et al. (2021): several at its start
        and several at its end) pin the rate a; exchanges at one time only cannot.
    delay_s
        Constant radio latency subtracted from mapped times, s (Chistyakov et al. (2021): ``Delta_ble`` ~ 0.03 s,
        measured separately; 0 when the exchanges' delays are symmetric).

    Returns
    -------
    ClockMap
        ``method="exchanges"``, with Chistyakov et al. (2021)'s intervals of a and b, the residuals and the
        feasible polygon.

    Raises
    ------
    InvalidInputError
        Fewer than 2 exchanges, arrays not 1-D or of different lengths, non-finite times, a
        reply before its request (``tm2 < tm1``), all IMU stamps equal, or no increasing affine
        map fits all exchanges (``index`` names the first exchange that contradicts those
        before it).
    InvalidParameterError
        ``delay_s`` not finite.

    Notes
    -----
    Every exchange bounds the map, ``TM1_i <= a TI_i + b <= TM2_i`` (Chistyakov et al. (2021) writes strict
    inequalities; the LP solver needs closed ones), i.e. ``A x <= B`` with ``x = [a, b]``, rows
    ``[TI_i, 1]`` and ``[-TI_i, -1]`` of A and ``TM2_i``, ``-TM1_i`` of B. Then

    LP1: ``c' x -> min``, LP2: ``c' x -> max``, ``c = [1, 0]``, solutions ``[a1, b1]``, ``[a2, b2]``;

    ``a = (a1 + a2) / 2``, ``b = (b1 + b2) / 2``, and ``t = a t_imu + b - delay``.

    The LPs are solved in IMU time centred on the mean stamp (same optimum, better conditioned
    when the clocks' epochs are large). The midpoint lies inside the feasible polygon (it is
    convex), so the map satisfies every exchange. Its accuracy depends on the delays: if the
    up and down delays are equal on average, the midpoint is unbiased, and the more exchanges
    with short delays there are, the smaller the polygon; a constant asymmetry ``Delta`` between
    them shifts ``b`` by ``Delta / 2``, which is what ``delay_s`` corrects.

    Examples
    --------
    >>> ti = [10.0, 11.0, 610.0, 611.0]
    >>> true = [1.0001 * t - 0.5 for t in ti]
    >>> m = fit_clock([t - 0.03 for t in true], ti, [t + 0.03 for t in true])
    >>> round(m.a, 9), round(m.b, 6), round(m.drift_ppm, 3)
    (1.0001, -0.5, -99.99)
    """
    m1, i, m2 = _vector(tm1, "tm1"), _vector(ti, "ti"), _vector(tm2, "tm2")
    for name, arr in (("ti", i), ("tm2", m2)):
        if len(arr) != len(m1):
            raise InvalidInputError(
                f"has {len(arr)} exchanges but tm1 has {len(m1)}; give one [tm1, ti, tm2] per exchange", field=name
            )
    if len(i) < 2:
        raise InvalidInputError(f"need at least 2 exchanges, got {len(i)}", field="ti")
    back = np.flatnonzero(m2 < m1)
    if len(back):
        k = int(back[0])
        raise InvalidInputError(
            f"reply received before its request was sent (tm2 {m2[k]!r} < tm1 {m1[k]!r})", field="tm2", index=k
        )
    if np.ptp(i) == 0:
        raise InvalidInputError(
            f"every IMU stamp is {i[0]!r} s: exchanges at one IMU time cannot give the clock rate; "
            "exchange messages at the start and at the end of the recording",
            field="ti",
        )
    if not np.isfinite(delay_s):
        raise InvalidParameterError(f"fit_clock: delay_s={delay_s!r}; expected a finite latency in s")

    # Centre the IMU times: a (t - i0) + c = a t + (c - a i0), and rows [TI, 1], [-TI, -1] (Chistyakov et al. (2021)).
    i0 = float(np.mean(i))
    ic = i - i0
    rows = np.column_stack([ic, np.ones_like(ic)])
    a_ub = np.concatenate([rows, -rows])  # A x <= B
    b_ub = np.concatenate([m2, -m1])
    sols = []
    for sign in (1.0, -1.0):  # LP1: c'x -> min, LP2: c'x -> max (min of -c'x), c = [1, 0]
        res = _lp([sign, 0.0], a_ub, b_ub)
        if res.status == 2:  # infeasible: find the first exchange that contradicts those before it
            lo, hi = 1, len(i)  # exchanges [0, lo) are consistent, [0, hi) are not
            while hi - lo > 1:
                mid = (lo + hi) // 2
                sub = np.r_[0:mid, len(i) : len(i) + mid]
                lo, hi = (mid, hi) if _lp([0.0, 0.0], a_ub[sub], b_ub[sub]).status == 0 else (lo, mid)
            raise InvalidInputError(
                f"no affine clock map fits exchanges 0..{lo}: exchange {lo} (tm1={m1[lo]!r}, ti={i[lo]!r}, "
                f"tm2={m2[lo]!r}) contradicts those before it; a time stamp is wrong or the clock jumped",
                field="ti",
                index=lo,
            )
        if res.status != 0:
            raise InvalidInputError(f"the clock LP failed: {res.message.strip()}", field="ti")
        sols.append(res.x)
    (a1, c1), (a2, c2) = sols
    if a1 <= 0:
        raise InvalidInputError(
            f"the exchanges allow a clock rate a={a1!r} <= 0: the IMU stamps do not increase with master time, "
            "or the exchanges are too close together for their round trips to pin the rate",
            field="ti",
        )
    a = 0.5 * (a1 + a2)  # a = (a1 + a2) / 2
    c = 0.5 * (c1 + c2)  # b = (b1 + b2) / 2, centred

    # Feasible polygon in (a s, c) with s = max |ti - i0|, both in s: a box from the LP bounds, cut
    # by every exchange's two half-planes.
    scale = max(float(np.max(np.abs(ic))), 1e-300)
    u1, u2 = a1 * scale, a2 * scale
    w = ic / scale
    c_lo = float(np.max(m1 - np.maximum(u1 * w, u2 * w)))
    c_hi = float(np.min(m2 - np.minimum(u1 * w, u2 * w)))
    poly = np.array([[u1, c_lo], [u2, c_lo], [u2, c_hi], [u1, c_hi]])
    tol = _CLIP_TOL * max(float(np.max(m2 - m1)), 1e-3)
    for k in range(len(i)):
        poly = _clip(poly, np.array([w[k], 1.0]), m2[k], tol)  # a TI + b <= TM2
        poly = _clip(poly, np.array([-w[k], -1.0]), -m1[k], tol)  # a TI + b >= TM1
    if len(poly) == 0:  # rounding on a degenerate (zero-width) polygon: the LP solutions span it
        poly = np.array([[u1, c1], [u2, c2]])
    verts = np.column_stack([poly[:, 0] / scale, poly[:, 1] - poly[:, 0] / scale * i0])

    b1, b2 = c1 - a1 * i0, c2 - a2 * i0
    return ClockMap(
        a=float(a),
        b=float(c - a * i0),
        delay_s=float(delay_s),
        n=len(i),
        method="exchanges",
        a_bounds=(float(a1), float(a2)),
        b_bounds=(float(min(b1, b2)), float(max(b1, b2))),
        residuals_s=a * ic + c - 0.5 * (m1 + m2),
        vertices=verts,
    )


def apply_clock(imu: ImuData, clock: ClockMap) -> ImuData:
    """``imu`` with its times mapped to the reference clock, ``t = clock(imu.t)`` (s).

    ``meta["clock"]`` records the map (``a``, ``b``, ``delay_s``, ``method``, ``n``,
    ``alternatives_b``): the own-clock times are ``(t + delay_s - b) / a``.

    Raises
    ------
    InvalidInputError
        The map makes the times non-increasing (``a <= 0``), from :class:`ImuData`.
    """
    record = {
        "a": clock.a,
        "b": clock.b,
        "delay_s": clock.delay_s,
        "method": clock.method,
        "n": clock.n,
        "alternatives_b": clock.alternatives_b,
    }
    return replace(imu, t=clock(imu.t), meta={**imu.meta, "clock": record})
