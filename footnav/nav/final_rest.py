"""The final rest of a walk: where a closed-loop measurement may be applied.

Chistyakov et al. (2021), Alg. 1, use a known end position "at the final standstill": the walker
returns to the start and stands still there. Applied anywhere else (a walk cut short, a last
stance that is only a step), the measurement pulls a mid-walk foot to the start and bends the
whole smoothed trajectory. :func:`final_rest` finds the final standstill and refuses a recording
that does not end with one.

A final rest is the last stance phase when it reaches the end of the recording (at most
``FINAL_REST_MAX_TAIL_S`` of movement after it: a hand reaching for the sensor) and lasts at least
``FINAL_REST_MIN_S`` and twice the walk's median stance: longer than any walking stance. On the
shared recordings walking stances last 0.27-0.68 s (median) and the final rests of the closed
walks 2-14 s.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import InvalidInputError
from footnav.core.types import StanceResult

__all__ = ["FINAL_REST_MAX_TAIL_S", "FINAL_REST_MIN_S", "final_rest"]

#: Longest movement after the final standstill, s.
FINAL_REST_MAX_TAIL_S = 0.5
#: Shortest final standstill, s (and at least twice the median stance).
FINAL_REST_MIN_S = 1.0


def final_rest(t: NDArray[np.float64], stance: StanceResult, *, what: str = "closed_loop") -> int:
    """Index of the last sample of the walk's final standstill.

    Parameters
    ----------
    t
        The foot's sample times, s.
    stance
        Its stance phases (mask aligned with ``t``).
    what
        Who asks, for the message (e.g. ``"ekf: closed_loop"``).

    Returns
    -------
    int
        The last sample of the final stance phase, where the closed-loop measurement belongs.

    Raises
    ------
    InvalidInputError
        Field ``stance``: no stance at all, or the last stance does not reach the end of the
        recording or is no longer than a walking stance; the message gives both durations.
    """
    runs = stance.intervals
    if len(runs) == 0:
        raise InvalidInputError(f"{what}: no stance phase, so no final standstill to close the loop at", field="stance")
    a, b = int(runs[-1, 0]), int(runs[-1, 1])
    rest_s = float(t[b - 1] - t[a])
    tail_s = float(t[-1] - t[b - 1])
    walking = t[runs[:-1, 1] - 1] - t[runs[:-1, 0]]
    median_s = float(np.median(walking)) if len(walking) else 0.0
    need_s = max(FINAL_REST_MIN_S, 2.0 * median_s)
    if tail_s > FINAL_REST_MAX_TAIL_S or rest_s < need_s:
        why = (
            f"the foot moves for {tail_s:.2f} s after its last stance"
            if tail_s > FINAL_REST_MAX_TAIL_S
            else f"its last stance lasts {rest_s:.2f} s, no longer than a walking step (median stance {median_s:.2f} s)"
        )
        raise InvalidInputError(
            f"{what}: the recording does not end at rest ({why}); the closed loop needs the walker to stand "
            f"still at the start point at the end, for at least {need_s:.2f} s within {FINAL_REST_MAX_TAIL_S:g} s "
            "of the last sample. Turn closed_loop off for this recording",
            field="stance",
            index=a,
        )
    return b - 1
