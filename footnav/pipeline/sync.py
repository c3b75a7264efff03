"""The clock-synchronisation stage: both feet on one clock before stance detection.

DESIGN.md's data flow is ``recording -> [sync + calibrate] -> detector -> estimator -> fusion``;
this module is the sync step. It applies :mod:`footnav.nav.clock_sync`: the message-exchange
map of Chistyakov et al. (2021), Sec. 5B (:func:`~footnav.nav.clock_sync.fit_clock`), or the
data-driven offset between the feet (:func:`~footnav.nav.clock_from_data.align_from_data`). The
pipeline runs it when given one (``make_pipeline(..., sync="data")``, a ``[sync]`` table in a
pipeline file, ``footnav run --sync data``); :func:`synchronise` runs it on a Recording alone.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any, ClassVar, Literal

from footnav.core.component import Component
from footnav.core.errors import InvalidInputError
from footnav.core.parameters import MAX_DURATION_S, require, require_in_range, require_non_negative, require_positive
from footnav.core.types import ImuData, Recording
from footnav.nav.clock_from_data import align_from_data
from footnav.nav.clock_sync import ClockMap, apply_clock, fit_clock

__all__ = ["ClockSync", "SyncResult", "synchronise", "recording_exchanges", "EXCHANGES_KEY"]

#: ``ImuData.meta`` key of a foot's message exchanges: a mapping with arrays ``tm1``, ``ti`` and
#: ``tm2`` in s (Chistyakov et al. (2021), Sec. 5B; see :func:`footnav.nav.clock_sync.fit_clock`).
EXCHANGES_KEY = "clock_exchanges"

_FEET = ("left", "right")


@dataclass(frozen=True)
class SyncResult:
    """Both feet on one clock, and the map applied to each.

    Attributes
    ----------
    left, right
        The feet with their times mapped (``right`` None for one foot). Each mapped foot's
        ``meta["clock"]`` records its map (:func:`~footnav.nav.clock_sync.apply_clock`).
    clocks
        ``{"left": ClockMap, "right": ClockMap}`` for the feet whose times were mapped.
    masters
        Feet taken to be on the master clock (``"exchanges"`` without their own), times kept.
    """

    left: ImuData
    right: ImuData | None
    clocks: Mapping[str, ClockMap]
    masters: tuple[str, ...] = ()

    def record(self) -> dict[str, Any]:
        """Plain-value summary for a result's meta: per mapped foot, its a, b (s), delay (s),
        drift (ppm), method, count and the offsets the data could not rule out (s)."""
        return {
            foot: {
                "method": c.method,
                "a": c.a,
                "b_s": c.b,
                "delay_s": c.delay_s,
                "drift_ppm": c.drift_ppm,
                "n": c.n,
                "alternatives_b_s": list(c.alternatives_b),
            }
            for foot, c in self.clocks.items()
        } | {foot: {"method": "master (no exchanges; times kept)"} for foot in self.masters}


class ClockSync(Component):
    """Put both feet on one clock.

    Parameters
    ----------
    method
        ``"data"``: the right foot's clock is mapped onto the left's from the gyro energy
        (:func:`~footnav.nav.clock_from_data.align_from_data`; needs both feet, still at both ends).
        ``"exchanges"``: each foot's clock is mapped onto the master's from its message exchanges
        (arrays ``tm1``, ``ti``, ``tm2`` in s; Chistyakov et al. (2021), Sec. 5B,
        :func:`~footnav.nav.clock_sync.fit_clock`), found in ``imu.meta["clock_exchanges"]`` or
        given to :meth:`align`. A foot without exchanges is taken to be the master (its times
        are kept; the record says so); at least one foot must have them.
    delay_s
        ``"exchanges"``: constant radio latency subtracted, s (Chistyakov et al. (2021): ~0.03 s
        over Bluetooth LE; 0 for symmetric delays).
    max_offset_s
        ``"data"``: largest offset between the feet's clocks searched, s.
    smooth_s
        ``"data"``: window of the walking/standing envelope, s (more than a stride).
    drift
        ``"data"``: also estimate the rate (the clocks drift apart).
    leading_foot
        ``"data"``: ``"left"`` or ``"right"`` if known to have started walking; settles offsets
        a whole stride apart that the data alone leave open.
    """

    kind: ClassVar[str] = "sync"
    name: ClassVar[str] = "clock"

    def __init__(
        self,
        method: Literal["data", "exchanges"] = "data",
        *,
        delay_s: float = 0.0,
        max_offset_s: float = 60.0,
        smooth_s: float = 3.0,
        drift: bool = False,
        leading_foot: Literal["left", "right"] | None = None,
    ) -> None:
        self.method = method
        self.delay_s = delay_s
        self.max_offset_s = max_offset_s
        self.smooth_s = smooth_s
        self.drift = drift
        self.leading_foot = leading_foot

    @property
    def needs_two_feet(self) -> bool:  # type: ignore[override]
        """Whether the method needs both feet (``data`` does)."""
        return self.method == "data"

    def validate_params(self) -> None:
        """Check every parameter (:meth:`footnav.core.component.Component.validate_params`); raises
        InvalidParameterError."""
        require(self.method in ("data", "exchanges"), self, "method", "'data' or 'exchanges'")
        require_non_negative(self, "delay_s", high=MAX_DURATION_S)
        require_positive(self, "smooth_s", high=MAX_DURATION_S)
        # an offset of hours is a clock set wrongly, not a start-up delay; the search grid grows with it
        require_in_range(self, "max_offset_s", low=0.0, high=3600.0, low_open=True)
        require(isinstance(self.drift, bool), self, "drift", "True or False")
        require(self.leading_foot in (None, "left", "right"), self, "leading_foot", "None, 'left' or 'right'")

    def align(
        self, left: ImuData, right: ImuData | None = None, *, exchanges: Mapping[str, Mapping[str, Any]] | None = None
    ) -> SyncResult:
        """Map the feet's times onto one clock.

        Parameters
        ----------
        left, right
            The feet, each on its own clock (s); ``right`` None for one foot.
        exchanges
            ``"exchanges"`` only: ``{"left": {"tm1", "ti", "tm2"}, "right": ...}`` for feet whose
            ``meta`` does not carry them (a recording keeps them in its own meta; see
            :func:`synchronise`).

        Raises
        ------
        InvalidInputError
            ``"data"`` with one foot; ``"exchanges"`` with no foot's exchanges, exchanges that
            are not a mapping of ``tm1``, ``ti``, ``tm2`` (field named), or that fit no
            increasing affine clock (from :func:`~footnav.nav.clock_sync.fit_clock`).
        """
        self.validate_params()
        if self.method == "data":
            if right is None:
                raise InvalidInputError("clock sync from the data needs both feet; only one was given", field="right")
            lead = None if self.leading_foot is None else ("reference" if self.leading_foot == "left" else "other")
            clock = align_from_data(
                left, right, smooth_s=self.smooth_s, max_offset_s=self.max_offset_s, drift=self.drift, leading_foot=lead
            )
            return SyncResult(left, apply_clock(right, clock), {"right": clock})
        feet = {foot: imu for foot, imu in zip(_FEET, (left, right)) if imu is not None}
        given = dict(exchanges or {})
        found = {foot: given.get(foot, imu.meta.get(EXCHANGES_KEY)) for foot, imu in feet.items()}
        found = {foot: ex for foot, ex in found.items() if ex is not None}
        if not found:
            raise InvalidInputError(
                f"clock sync from exchanges found none: give them in a foot's meta[{EXCHANGES_KEY!r}] or as "
                "align(..., exchanges={'right': {'tm1': ..., 'ti': ..., 'tm2': ...}})",
                field=EXCHANGES_KEY,
            )
        clocks = {foot: self._exchange_clock(ex, foot) for foot, ex in found.items()}
        mapped = {foot: apply_clock(imu, clocks[foot]) if foot in clocks else imu for foot, imu in feet.items()}
        masters = tuple(foot for foot in feet if foot not in clocks)
        return SyncResult(mapped["left"], mapped.get("right"), clocks, masters)

    def _exchange_clock(self, exchanges: Any, foot: str) -> ClockMap:
        where = f"the {foot} foot's {EXCHANGES_KEY}"
        if not isinstance(exchanges, Mapping) or not {"tm1", "ti", "tm2"} <= set(exchanges):
            raise InvalidInputError(
                f"{where} must be a mapping of arrays 'tm1', 'ti', 'tm2' in s; got {type(exchanges).__name__}",
                field=f"{foot}.{EXCHANGES_KEY}",
            )
        try:
            return fit_clock(exchanges["tm1"], exchanges["ti"], exchanges["tm2"], delay_s=self.delay_s)
        except InvalidInputError as exc:
            error = InvalidInputError(f"{where}: {exc}", field=f"{foot}.{EXCHANGES_KEY}")
            error.index = exc.index  # the exchange, already named in the message
            raise error from None


def recording_exchanges(recording: Recording) -> dict[str, Mapping[str, Any]]:
    """The message exchanges a Recording keeps in its own meta, by foot.

    A recording (the simulator's, with ``clock_exchanges``) holds them in ``meta["clock_exchanges"]``
    for the foot ``meta["clock"]["foot"]`` names (the right foot if none is named).
    """
    found = recording.meta.get(EXCHANGES_KEY)
    if found is None:
        return {}
    clock = recording.meta.get("clock")
    foot = clock.get("foot", "right") if isinstance(clock, Mapping) else "right"
    return {foot: found}


def synchronise(recording: Recording, sync: ClockSync | None = None) -> tuple[Recording, SyncResult]:
    """``recording`` with both feet on one clock (``sync`` defaults to ``ClockSync("data")``).

    The returned Recording's ``meta["sync"]`` holds :meth:`SyncResult.record`. Truth is not
    moved: the simulator's truths are on true time, which is the master's (exchanges) or the
    left foot's (data) clock.

    Examples
    --------
    >>> rec = footnav.simulate("straight", distance_m=20.0, clock_offset_s=0.35)  # doctest: +SKIP
    >>> synced, res = synchronise(rec)  # doctest: +SKIP
    >>> round(res.clocks["right"].b, 2)  # doctest: +SKIP
    -0.35
    """
    sync = ClockSync() if sync is None else sync
    result = sync.align(recording.left, recording.right, exchanges=recording_exchanges(recording))
    meta = {**recording.meta, "sync": result.record()}
    return replace(recording, left=result.left, right=result.right, meta=meta), result
