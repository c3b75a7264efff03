"""IPOL gait data set: both feet, Xsens MTw Awinda, hand-checked swings (Voisard et al., IPOL 2023).

C. Voisard, N. de l'Escalopier, D. Ricard, L. Oudre, "A Reference Data Set for the Study of
Healthy Subject Gait with Inertial Measurement Units", Image Processing On Line 13 (2023),
article 497. One trial is three files sharing a stem ``<subject>-<trial>``:

* ``<stem>_lf.txt`` (left foot) and ``<stem>_rf.txt`` (right foot)::

      Acquisition frequency: 100 Hz
      PacketCounter<TAB>Acc_X<TAB>Acc_Y<TAB>Acc_Z<TAB>Gyr_X<TAB>Gyr_Y<TAB>Gyr_Z<TAB>Mag_X<TAB>Mag_Y<TAB>Mag_Z
      0.0<TAB>5.09<TAB>...

  acc m/s^2, gyro rad/s, mag Xsens a.u., sensor axes (on the dorsum of the foot). Read by
  :func:`~footnav.data.io.xsens.read_xsens`: time = unwrapped PacketCounter / rate, because
  packets are lost over the radio link (4 % on average, up to 17 % of one file) -- the row
  number is not time.
* ``<stem>.json``: ``Subject``, ``Trial``, ``Age`` (years), ``Gender``, ``Height`` (cm),
  ``Weight`` (kg), ``TrialBoundaries [start, end]``, ``UTurnBoundaries [start, end]``,
  ``LeftFootEvents`` / ``RightFootEvents`` = lists of ``[toe_off, heel_strike]`` pairs, each one
  SWING of that foot, all in PacketCounter units counted from counter 0.

What the data show (46 trials of subjects 1-8, checked when this reader was written):

* The two feet share one clock: both counters start at 0, 1 or 2 and, in counter units, the
  labelled swings of the left and right foot do not overlap (walking always has a double
  support): no overlapping pair in 37 of 46 trials, at most 2 (U-turn shuffling) in the others,
  and shifting one foot's counter by anything from -7 to +6 samples keeps it so in every trial
  -- a window centred on zero shift. So t of both feet is ``counter / rate`` on one time axis. The feet's
  files still differ: different packets are lost, and they end at different counters (1-1: both
  files have 2,913 rows, but the left ends at counter 2998 and the right at 3044).
* ``TrialBoundaries`` start at the trial's first toe-off and end at its last heel strike inside
  the walk; some trials have swings labelled after the end (shuffling after stopping). No swing
  straddles a boundary, and every labelled event lies inside its foot's counter span.

Truth, per foot (:class:`~footnav.core.types.FootTruth`, ``frame="gait_events"``, no positions):

* ``events["toe_off"]``, ``events["heel_strike"]``: every labelled swing's events as sample
  indices of that foot's file, i.e. the row whose counter is nearest to the labelled counter
  (the exact counter may be a lost packet; ``meta["event_mapping_max_error_samples"]``).
* ``meta["trial_boundaries"] = (start, end)``: the labelled span as half-open sample indices
  ``start <= i < end``. Half-open because ``end`` is a heel strike: the span ends as the last
  swing ends, and a one-sample stance at the end would be an artefact of the convention.
* ``meta["labelled"]``: boolean mask, True on the samples of that span. Outside it the truth
  says nothing (the foot may still be moving, or not yet).
* ``stance``: True where labelled and not in a swing; a swing covers ``toe_off <= i <
  heel_strike``. So the stance phases are the gaps between consecutive swings (heel strike i to
  toe-off i + 1), plus, for the foot that does not start (or end) the trial, the part of its
  standing still before its first swing (after its last) that lies inside the span. ``stance``
  is False outside the span: use it only together with ``meta["labelled"]`` (see
  :func:`footnav.analysis.metrics.step_detection_from_swings`).
* ``meta["uturn_boundaries"]`` (half-open sample indices), the raw counters of everything
  (``*_counter``), and ``meta["subject"]`` (age in years, height in m, weight in kg).
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataNotFoundError, DataQualityWarning, InvalidInputError
from footnav.core.types import FootTruth, ImuData, Recording
from footnav.core.warning_log import warn
from footnav.data.io._text import changes_of
from footnav.data.io.xsens import read_xsens

__all__ = ["ipol_trial_files", "read_ipol"]

FORMAT = "ipol"
_FOOT_SUFFIX = {"left": "_lf.txt", "right": "_rf.txt"}
_EVENT_KEY = {"left": "LeftFootEvents", "right": "RightFootEvents"}
_CM_PER_M = 100.0


def ipol_trial_files(path: Any) -> tuple[str, FilePath, FilePath, FilePath]:
    """The stem and the ``_lf.txt``, ``_rf.txt`` and ``.json`` paths of an IPOL trial.

    ``path`` may be any of the three files or the stem itself (``.../1-1``). Existence is not
    checked here.
    """
    p = FilePath(path)
    name = p.name
    for suffix in (*_FOOT_SUFFIX.values(), ".json"):
        if name.endswith(suffix):
            name = name[: -len(suffix)]
            break
    base = p.with_name(name)
    return name, base.with_name(name + "_lf.txt"), base.with_name(name + "_rf.txt"), base.with_name(name + ".json")


def _counters(imu: ImuData, rate: float) -> NDArray[np.int64]:
    # read_xsens set t = unwrapped counter / rate exactly, so rounding recovers the counter
    return np.round(imu.t * rate).astype(np.int64)


def _nearest_rows(counter: NDArray[np.int64], values: NDArray[np.int64]) -> tuple[NDArray[np.int64], int]:
    """Row of ``counter`` nearest to each value (ties: the earlier row), and the largest distance."""
    if len(values) == 0:
        return np.empty(0, dtype=np.int64), 0
    hi = np.clip(np.searchsorted(counter, values), 1, len(counter) - 1)
    lo = hi - 1
    take_hi = np.abs(counter[hi] - values) < np.abs(values - counter[lo])
    rows = np.where(take_hi, hi, lo)
    return rows.astype(np.int64), int(np.max(np.abs(counter[rows] - values)))


def _pair(value: Any, src: str, field: str) -> tuple[int, int]:
    arr = np.asarray(value)
    if arr.shape != (2,) or not np.issubdtype(arr.dtype, np.number) or np.any(arr != np.round(arr)):
        raise InvalidInputError(f"expected [start, end] as two integer counters, got {value!r}", path=src, field=field)
    a, b = int(arr[0]), int(arr[1])
    if not 0 <= a < b:
        raise InvalidInputError(f"expected 0 <= start < end, got [{a}, {b}]", path=src, field=field)
    return a, b


def _swings(value: Any, src: str, field: str) -> NDArray[np.int64]:
    try:
        arr = np.asarray(value, dtype=np.float64).reshape(-1, 2) if len(value) else np.empty((0, 2))
    except (TypeError, ValueError):
        raise InvalidInputError(
            "expected a list of [toe_off, heel_strike] counter pairs", path=src, field=field
        ) from None
    bad = ~np.isfinite(arr).all(axis=1) | (arr != np.round(arr)).any(axis=1) | (arr < 0).any(axis=1)
    bad |= arr[:, 0] >= arr[:, 1]
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"swing {arr[i].tolist()} is not a pair of counters with toe_off < heel_strike",
            path=src,
            field=field,
            index=i,
        )
    # a swing must end before the next one starts (touching is allowed: a zero-length stance
    # would only be a labelling slip, not an overlap of two swings)
    overlap = np.flatnonzero(arr[1:, 0] < arr[:-1, 1])
    if len(overlap):
        i = int(overlap[0]) + 1
        raise InvalidInputError(
            f"swing {arr[i].tolist()} starts before the previous one {arr[i - 1].tolist()} ends; swings must be in "
            "time order and disjoint",
            path=src,
            field=field,
            index=i,
        )
    return arr.astype(np.int64)


def _foot_truth(foot: str, imu: ImuData, rate: float, info: dict[str, Any], src: str) -> tuple[FootTruth, list[str]]:
    counter = _counters(imu, rate)
    n = len(counter)
    notes: list[str] = []
    swings_c = _swings(info.get(_EVENT_KEY[foot], []), src, _EVENT_KEY[foot])
    outside = (swings_c[:, 0] < counter[0]) | (swings_c[:, 1] > counter[-1])
    if outside.any():
        i = int(np.argmax(outside))
        warn(
            f"{src}: {int(outside.sum())} {foot} swing(s) lie outside the {foot} file's counter span "
            f"[{counter[0]}, {counter[-1]}] (first: {swings_c[i].tolist()}); dropped from the truth",
            DataQualityWarning,
            stacklevel=3,
        )
        notes.append(f"{foot}: dropped {int(outside.sum())} labelled swing(s) outside the file's counter span")
        swings_c = swings_c[~outside]
    tb_c = _pair(info["TrialBoundaries"], src, "TrialBoundaries")
    ut_c = _pair(info["UTurnBoundaries"], src, "UTurnBoundaries") if "UTurnBoundaries" in info else None
    swings, err_sw = _nearest_rows(counter, swings_c.reshape(-1))
    swings = swings.reshape(-1, 2)
    tb, err_tb = _nearest_rows(counter, np.asarray(tb_c, dtype=np.int64))
    ut, err_ut = _nearest_rows(counter, np.asarray(ut_c if ut_c else (), dtype=np.int64))
    labelled = np.zeros(n, dtype=bool)
    labelled[tb[0] : tb[1]] = True
    swing_mask = np.zeros(n, dtype=bool)
    for a, b in swings:
        swing_mask[a:b] = True
    stance = labelled & ~swing_mask
    meta: dict[str, Any] = {
        "source": src,
        "foot": foot,
        "stance_source": (
            "hand-checked swings (Voisard et al., IPOL 2023): stance = labelled samples between consecutive swings; "
            "False outside meta['labelled'] means 'not labelled', not 'swing'"
        ),
        "labelled": labelled,
        "trial_boundaries": (int(tb[0]), int(tb[1])),
        "trial_boundaries_counter": tb_c,
        "uturn_boundaries": (int(ut[0]), int(ut[1])) if ut_c else None,
        "uturn_boundaries_counter": ut_c,
        "swings": swings,
        "swings_counter": swings_c,
        "swings_inside": (swings[:, 0] >= tb[0]) & (swings[:, 1] <= tb[1]),
        "event_mapping": "each labelled counter -> the row of this foot's file with the nearest PacketCounter",
        "event_mapping_max_error_samples": max(err_sw, err_tb, err_ut),
    }
    truth = FootTruth(
        t=np.empty(0),
        position=np.empty((0, 3)),
        stance=stance,
        events={"toe_off": swings[:, 0], "heel_strike": swings[:, 1]},
        frame="gait_events",
        meta=meta,
    )
    return truth, notes


def _subject(info: dict[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, name in (("Subject", "subject"), ("Trial", "trial"), ("Gender", "gender"), ("Filename", "filename")):
        if key in info:
            out[name] = info[key]
    if "Age" in info:
        out["age_years"] = float(info["Age"])
    if "Height" in info:
        out["height_m"] = float(info["Height"]) / _CM_PER_M
    if "Weight" in info:
        out["weight_kg"] = float(info["Weight"])
    return out


def read_ipol(path: Any, *, drop_duplicates: bool = False, acc_full_scale_mps2: float | None = None) -> Recording:
    """Read one trial of the IPOL gait data set (Voisard et al., IPOL 2023, art. 497): both feet.

    Parameters
    ----------
    path
        The trial's ``.json``, ``_lf.txt`` or ``_rf.txt`` file, or its stem (``.../1-1``).
    drop_duplicates
        Drop rows repeating the previous PacketCounter (recorded); without it they raise.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection (MTw: 16 g), if wanted.

    Returns
    -------
    Recording
        ``left`` = ``_lf.txt``, ``right`` = ``_rf.txt``: t = PacketCounter / rate in s on the
        clock both feet share (see the module docstring), acc m/s^2, gyr rad/s, mag a.u., sensor
        axes; lost packets in each foot's ``meta["gaps"]``. ``truth_left`` / ``truth_right``:
        :class:`FootTruth` with no positions, the labelled swings as ``events`` and the stance
        mask, valid only where ``meta["labelled"]`` (module docstring). ``meta["subject"]``:
        the subject's data. Without the ``.json`` the truth is None (DataQualityWarning).

    Raises
    ------
    DataNotFoundError
        A foot's file is missing.
    InvalidInputError
        A malformed file (named, with line or field and index).
    """
    stem, lf, rf, js = ipol_trial_files(path)
    for f in (lf, rf):
        if not f.exists():
            raise DataNotFoundError(f"IPOL trial {stem!r}: {str(f)!r} does not exist (need both _lf.txt and _rf.txt)")
    feet: dict[str, ImuData] = {}
    rate = None
    for foot, f in (("left", lf), ("right", rf)):
        rec = read_xsens(f, drop_duplicates=drop_duplicates, acc_full_scale_mps2=acc_full_scale_mps2)
        imu = rec.left
        if rate is not None and not np.isclose(rate, rec.meta["rate_hz"]):
            raise InvalidInputError(
                f"rate {rec.meta['rate_hz']:g} Hz differs from the left foot's {rate:g} Hz", path=str(f), line=1
            )
        rate = float(rec.meta["rate_hz"])
        feet[foot] = replace(imu, meta={**imu.meta, "foot": foot})
    assert rate is not None

    truths: dict[str, FootTruth | None] = {"left": None, "right": None}
    changes: list[str] = []
    meta: dict[str, Any] = {"format": FORMAT, "source": str(js if js.exists() else lf)}
    if js.exists():
        src = str(js)
        try:
            info = json.loads(js.read_text(encoding="utf-8"))
        except (UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise InvalidInputError(f"not a JSON file ({exc})", path=src) from None
        if not isinstance(info, dict) or "TrialBoundaries" not in info:
            raise InvalidInputError(
                "no 'TrialBoundaries'; expected an IPOL trial description", path=src, field="TrialBoundaries"
            )
        for foot in ("left", "right"):
            truths[foot], notes = _foot_truth(foot, feet[foot], rate, info, src)
            changes += notes
        meta["subject"] = _subject(info)
        meta["trial_boundaries_counter"] = _pair(info["TrialBoundaries"], src, "TrialBoundaries")
        if "UTurnBoundaries" in info:
            meta["uturn_boundaries_counter"] = _pair(info["UTurnBoundaries"], src, "UTurnBoundaries")
    else:
        warn(f"IPOL trial {stem!r}: {str(js)!r} not found; read without truth", DataQualityWarning, stacklevel=2)
    changes = changes_of("left", feet["left"]) + changes_of("right", feet["right"]) + changes
    meta.update(
        {
            "files": {"left": str(lf), "right": str(rf), "json": str(js) if js.exists() else None},
            "rate_hz": rate,
            "clock": (
                "shared: t = PacketCounter / rate for both feet (counters start at 0-2 in both; the labelled swings "
                "of the two feet never overlap in counter units)"
            ),
            "units_converted": {},
            "changes": changes,
            "reference": "Voisard et al., A Reference Data Set for the Study of Healthy Subject Gait with IMUs, "
            "IPOL 13 (2023), art. 497",
        }
    )
    return Recording(
        left=feet["left"],
        right=feet["right"],
        truth_left=truths["left"],
        truth_right=truths["right"],
        name=stem,
        meta=meta,
    )
