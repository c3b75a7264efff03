"""The gait plan of a simulated walk: both feet's footfalls and the timing of their swings."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.data.simulate.path import _CentreLine

#: Names of the per-sample gait phase labels in ``FootTruth.meta["phases"]``.
PHASE_NAMES = ("stance", "heel_off", "swing", "foot_flat")
_STANCE, _HEEL_OFF, _SWING, _FOOT_FLAT = range(len(PHASE_NAMES))


@dataclass(frozen=True)
class _Swings:
    """One foot's swings: event times (K,) in s and the footprints it leaves and reaches."""

    t_heel_off: NDArray[np.float64]
    t_toe_off: NDArray[np.float64]
    t_heel_strike: NDArray[np.float64]
    t_foot_flat: NDArray[np.float64]
    xy_from: NDArray[np.float64]
    heading_from: NDArray[np.float64]
    xy_to: NDArray[np.float64]
    heading_to: NDArray[np.float64]
    # heights (m) of the footprints left and reached: zero but on stairs
    z_from: NDArray[np.float64]
    z_to: NDArray[np.float64]
    # each swing's factor on its pitch angles and lift (``swing_scale``); None: all 1
    scale: NDArray[np.float64] | None = None


def _plan(
    line: _CentreLine, opts: dict[str, Any], flights: Sequence[Mapping[str, Any]] = ()
) -> tuple[dict[str, _Swings], dict[str, Any]]:
    """Footprints and swing timing of both feet along ``line``.

    The walk starts with the feet side by side. With ``n`` steps of length ``l = length / n``
    (``l`` close to half the stride) footfalls land at arc lengths ``l, 2 l, ..., n l``, alternating
    right, left, ...; swing ``j`` (j = 0..n) takes its foot from arc length ``(j-1) l`` (0 for the
    first two) to ``min(j+1, n) l``, so the first and the last swing are half strides and the feet
    end side by side. Swing ``j`` starts (heel-off) ``j`` half stride periods after the standstill.

    With ``flights`` of stairs (``_centre_line``'s ``"stairs"``) the level stretches between them
    are stepped as above, each on its own, and a flight of ``N`` stairs takes ``N`` footfalls, one
    per tread (step over step: each swing climbs two risers), at ``tread_m`` apart and ``rise_m``
    higher each; swing ``j`` still goes from footfall ``j-1`` to footfall ``j+1``.
    """
    if flights:
        s_fall, z_fall = _footfalls(line, opts, flights)
        n = len(s_fall) - 1
        j = np.arange(n + 1)
        s_from, s_to = s_fall[np.maximum(j - 1, 0)], s_fall[np.minimum(j + 1, n)]
        z_from, z_to = z_fall[np.maximum(j - 1, 0)], z_fall[np.minimum(j + 1, n)]
        step = line.length_m / n  # the mean step, for the meta
    else:
        n = max(1, int(round(line.length_m / (opts["stride_length_m"] / 2))))
        step = line.length_m / n
        j = np.arange(n + 1)
        s_from = np.maximum(j - 1, 0) * step
        s_to = np.minimum(j + 1, n) * step
        z_from = z_to = np.zeros(n + 1)
    t_ho = opts["standstill_s"] + j * opts["stride_period_s"] / 2
    t_to = t_ho + opts["heel_off_s"]
    t_hs = t_to + opts["swing_s"]
    t_ff = t_hs + opts["foot_flat_s"]
    swings = {}
    for foot, side, first in (("right", -1.0, 0), ("left", 1.0, 1)):
        sel = j % 2 == first
        xy_from, h_from = _footprint(line, s_from[sel], side * opts["step_width_m"] / 2)
        xy_to, h_to = _footprint(line, s_to[sel], side * opts["step_width_m"] / 2)
        scale = None
        if opts["swing_scale"] is not None:  # the foot's own swings in order: 1st, 2nd, ...
            factors = np.asarray(opts["swing_scale"])
            scale = factors[np.arange(int(sel.sum())) % len(factors)]
        swings[foot] = _Swings(
            t_ho[sel], t_to[sel], t_hs[sel], t_ff[sel], xy_from, h_from, xy_to, h_to, z_from[sel], z_to[sel], scale
        )
    duration = float(t_ff[-1] + opts["standstill_s"])
    info = {
        "path_length_m": line.length_m,
        "n_steps": n,
        "step_length_m": step,
        "stride_length_m_actual": 2 * step,
        "duration_s": duration,
        "first_foot": "right",
    }
    if flights:
        info["height_change_m"] = float(z_to[-1])
    return swings, info


def _footfalls(
    line: _CentreLine, opts: dict[str, Any], flights: Sequence[Mapping[str, Any]]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Arc lengths (m) and heights (m) of footfalls 0..n of a walk with stairs, (n+1,) each.

    Footfall 0 is the start. A level stretch of length ``L`` takes ``max(1, round(L / (stride / 2)))``
    equal steps; a flight of ``N`` stairs ``N`` footfalls ``tread_m`` apart, the i-th ``i rise_m``
    above the flight's foot, so after it the height has changed by exactly ``N rise_m``.
    """
    s_fall, z_fall = [0.0], [0.0]
    s, z = 0.0, 0.0
    for flight in [*flights, None]:
        s_next = line.length_m if flight is None else flight["start_m"]
        level = s_next - s
        if level > 0:
            n = max(1, int(round(level / (opts["stride_length_m"] / 2))))
            step = level / n
            s_fall += [s + i * step for i in range(1, n)] + [s_next]
            z_fall += [z] * n
        if flight is None:
            break
        n_steps, rise, tread = flight["n_steps"], flight["rise_m"], flight["tread_m"]
        s_fall += [s_next + i * tread for i in range(1, n_steps + 1)]
        z_fall += [z + i * rise for i in range(1, n_steps + 1)]
        s, z = s_next + n_steps * tread, z + n_steps * rise
    return np.asarray(s_fall), np.asarray(z_fall)


def _footprint(line: _CentreLine, s: NDArray, offset_left_m: float) -> tuple[NDArray, NDArray]:
    xy, heading = line(s)
    normal = np.stack([-np.sin(heading), np.cos(heading)], axis=-1)
    return xy + offset_left_m * normal, heading
