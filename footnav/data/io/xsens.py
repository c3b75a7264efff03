"""Xsens MTw text export (MT Manager "Export to ASCII"): one sensor per file.

Format::

    // General information:
    //  MT Manager version: 4.8.1
    // Device information:
    //  DeviceId: 00B4xxxx
    // Update Rate: 100.0Hz
    PacketCounter<TAB>SampleTimeFine<TAB>Acc_X<TAB>Acc_Y<TAB>Acc_Z<TAB>Gyr_X<TAB>...<TAB>Mag_Z
    1234<TAB>...

* Lines before the column header (the first line holding ``PacketCounter``) are preamble; the
  rate is read from the one saying ``Update Rate: <r>Hz`` (MT Manager) or ``Acquisition
  frequency: <r> Hz`` (the one-line preamble of the IPOL gait data set's exports, see
  :mod:`footnav.data.io.ipol`).
* Column header and rows are tab separated (or ``,``/``;``, or white space, as the header line
  is): columns are found by name, extra columns are ignored.
* ``Acc_*`` m/s^2, ``Gyr_*`` rad/s, ``Mag_*`` arbitrary units (normalised to the field at
  calibration), all in the sensor's axes (z up, out of the case's top).
* ``PacketCounter`` is a uint16 that wraps at 65536. Time comes from the counter, NOT the row
  number: t = unwrapped counter / rate, so lost packets leave gaps (``meta["gaps"]``,
  ``meta["lost_packets"]``) instead of silently shortening the recording. A repeated counter is
  a duplicate sample (error unless ``drop_duplicates``).
"""

from __future__ import annotations

import re
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import Recording
from footnav.core.warning_log import warn
from footnav.data.io._text import build_imu, changes_of, parse_table, read_text, split_header

__all__ = ["read_xsens", "XSENS_COUNTER_MODULUS", "unwrap_counter"]

FORMAT = "xsens"
#: PacketCounter is a uint16: it wraps from 65535 to 0.
XSENS_COUNTER_MODULUS = 65536
#: A forward step of more than half the modulus is indistinguishable from a counter going
#: backwards (packets out of order): refused rather than guessed.
_MAX_FORWARD_STEP = XSENS_COUNTER_MODULUS // 2
_RATE = re.compile(r"(update\s*rate|acquisition\s*frequency)\s*:?\s*([0-9]*\.?[0-9]+)\s*hz", re.IGNORECASE)
_COUNTER = "PacketCounter"
_ACC = ("Acc_X", "Acc_Y", "Acc_Z")
_GYR = ("Gyr_X", "Gyr_Y", "Gyr_Z")
_MAG = ("Mag_X", "Mag_Y", "Mag_Z")


def unwrap_counter(counter: NDArray[np.float64]) -> NDArray[np.int64]:
    """Unwrap a uint16 packet counter: each step is taken modulo 65536 (0 = repeated packet).

    Steps of half the modulus or more are not unwrapped (see ``read_xsens``); this function
    only computes ``counter[0] + cumsum(step mod 65536)``.
    """
    c = np.asarray(counter, dtype=np.int64)
    steps = np.diff(c) % XSENS_COUNTER_MODULUS
    return np.concatenate(([c[0]], c[0] + np.cumsum(steps)))


def read_xsens(
    path: Any, *, rate_hz: float | None = None, drop_duplicates: bool = False, acc_full_scale_mps2: float | None = None
) -> Recording:
    """Read an Xsens MTw ASCII export (one sensor).

    Parameters
    ----------
    path
        The text export; see the module docstring.
    rate_hz
        Sampling rate. Default: the preamble's ``Update Rate`` (or ``Acquisition frequency``).
        Given when the file has one, the
        two must agree (else InvalidInputError: one of them is wrong).
    drop_duplicates
        Drop rows repeating the previous packet counter (recorded); without it they raise.
    acc_full_scale_mps2
        Accelerometer full scale for clipping detection (MTw: 16 g), if wanted.

    Returns
    -------
    Recording
        ``left`` = the sensor: t = unwrapped PacketCounter / rate (first packet's counter
        included, so t need not start at 0), acc m/s^2, gyr rad/s, mag a.u. when present;
        ``meta["counter_wraps"]``, ``meta["lost_packets"]`` and ``meta["gaps"]`` (every counter
        step > 1, as ``(index, dt_s)``) record what the counter showed. No truth.
    """
    tf = read_text(path)
    hk = next((k for k, line in enumerate(tf.lines) if _COUNTER in line and not line.lstrip().startswith("//")), None)
    if hk is None:
        raise InvalidInputError(
            f"no column header with {_COUNTER!r}; expected e.g. '{_COUNTER}\\tAcc_X\\tAcc_Y\\tAcc_Z\\tGyr_X\\t...'",
            path=tf.path,
            line=1,
        )
    file_rate = None
    rate_line = None
    rate_label = "Update Rate"
    for k in range(hk):
        m = _RATE.search(tf.lines[k])
        if m:
            file_rate, rate_line = float(m.group(2)), k + 1
            rate_label = "Update Rate" if m.group(1).lower().startswith("update") else "Acquisition frequency"
    if rate_hz is None and file_rate is None:
        raise InvalidInputError(
            "no 'Update Rate: <r>Hz' (or 'Acquisition frequency: <r> Hz') line before the column header; pass rate_hz",
            path=tf.path,
            line=hk + 1,
        )
    if rate_hz is not None and file_rate is not None and not np.isclose(rate_hz, file_rate):
        raise InvalidInputError(
            f"rate_hz={rate_hz:g} was given but the file says {file_rate:g} Hz", path=tf.path, line=rate_line
        )
    rate = float(rate_hz if rate_hz is not None else file_rate)
    if not rate > 0:
        raise InvalidInputError(f"update rate {rate:g} Hz; must be positive", path=tf.path, line=rate_line)

    header_line = tf.lines[hk]
    delimiter = next((d for d in ("\t", ",", ";") if d in header_line), None)
    header = split_header(header_line, delimiter)
    missing = [c for c in (_COUNTER,) + _ACC + _GYR if c not in header]
    if missing:
        raise InvalidInputError(f"missing columns {missing}; found {header}", path=tf.path, line=hk + 1)
    has_mag = all(c in header for c in _MAG)
    data, lines = parse_table(tf, hk + 1, header, delimiter=delimiter)
    col = {name: j for j, name in enumerate(header)}
    counter = data[:, col[_COUNTER]]
    bad = (counter != np.round(counter)) | (counter < 0) | (counter >= XSENS_COUNTER_MODULUS)
    if bad.any():
        i = int(np.argmax(bad))
        raise InvalidInputError(
            f"PacketCounter {counter[i]!r} is not a uint16", path=tf.path, line=int(lines[i]), field=_COUNTER, index=i
        )
    steps = np.diff(counter.astype(np.int64)) % XSENS_COUNTER_MODULUS
    huge = np.flatnonzero(steps >= _MAX_FORWARD_STEP)
    if len(huge):
        i = int(huge[0]) + 1
        raise InvalidInputError(
            f"PacketCounter steps from {int(counter[i - 1])} to {int(counter[i])}: either packets out of order or "
            f">= {_MAX_FORWARD_STEP} lost; the counter cannot be unwrapped reliably",
            path=tf.path,
            line=int(lines[i]),
            field=_COUNTER,
            index=i,
        )
    unwrapped = unwrap_counter(counter)
    wraps = int(np.sum(np.diff(counter) < 0))

    # Gaps from the counter, on the rows that will be kept: ImuData's own rule (> 2 x median
    # interval) would miss a single lost packet (exactly 2 x).
    keep_rows = np.concatenate(([True], steps != 0)) if drop_duplicates else np.ones(len(counter), dtype=bool)
    kept = unwrapped[keep_rows]
    kept_steps = np.diff(kept)
    gap_idx = np.flatnonzero(kept_steps > 1)
    gaps = [(int(i + 1), float(kept_steps[i] / rate)) for i in gap_idx]
    lost = int(np.sum(kept_steps[gap_idx] - 1))
    meta = {
        "foot": "unknown (one sensor)",
        "rate_hz": rate,
        "rate_source": f"file ({rate_label})" if rate_hz is None else "caller",
        "time_source": f"unwrapped PacketCounter / {rate:g} Hz",
        "counter_wraps": wraps,
        "lost_packets": {"count": lost, "gaps": [(i, int(kept_steps[i - 1] - 1)) for i, _ in gaps]},
        "gaps": gaps,
        "ignored_columns": [c for c in header if c not in (_COUNTER,) + _ACC + _GYR + (_MAG if has_mag else ())],
    }
    imu, _ = build_imu(
        unwrapped / rate,
        data[:, [col[c] for c in _ACC]],
        data[:, [col[c] for c in _GYR]],
        data[:, [col[c] for c in _MAG]] if has_mag else None,
        path=tf.path,
        fmt=FORMAT,
        line_numbers=lines,
        mag_unit="a.u.",
        drop_duplicates=drop_duplicates,
        acc_full_scale_mps2=acc_full_scale_mps2,
        meta=meta,
    )
    if gaps:
        first = gaps[0][0]
        warn(
            f"{tf.path}: {lost} lost packet(s) in {len(gaps)} gap(s) of the PacketCounter (first before sample "
            f"{first}, line {int(lines[np.flatnonzero(keep_rows)[first]])}); time follows the counter, the gaps are "
            "in meta['gaps'] and meta['lost_packets']",
            DataQualityWarning,
            stacklevel=2,
        )
    changes = changes_of("sensor", imu)
    if wraps:
        changes.append(f"sensor: PacketCounter wrapped {wraps} time(s) at 65536, unwrapped")
    return Recording(
        left=imu,
        name=FilePath(tf.path).stem,
        meta={
            "format": FORMAT,
            "source": tf.path,
            "rate_hz": rate,
            "units_converted": imu.meta["units_converted"],
            "changes": changes,
        },
    )
