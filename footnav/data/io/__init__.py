"""File readers: every supported recording format -> :class:`~footnav.core.types.Recording`.

Each reader converts to SI units, keeps the sensor's axes as the body frame (or says which proper
rotation it applied), converts reference positions to z up, and records in meta what it read
(``format``, ``source``), what it converted and every change it made (duplicates dropped, gaps,
clipping). It never fixes data silently: duplicate time stamps raise unless
``drop_duplicates=True``; bad files raise :class:`~footnav.core.errors.InvalidInputError` naming
the file, line and column; missing files raise :class:`~footnav.core.errors.DataNotFoundError`.

=============== ===================================== =========================================
format          reader                                data
=============== ===================================== =========================================
footnav_csv     :func:`read_footnav_csv` (ImuData),   footnav's own CSV, one foot per file
                :func:`read_footnav_recording`
gaitmap         :func:`read_gaitmap`                  both feet, mocap, stride events
azure_fgo       :func:`read_azure_fgo`                both feet, per-sample position truth
xio             :func:`read_xio`                      one foot, closed loop
openshoe        :func:`read_openshoe`                 one foot, 820 Hz, no truth
pyshoe          :func:`read_pyshoe`                   one foot, Vicon truth, proxy stance labels
xsens           :func:`read_xsens`                    Xsens MTw ASCII export, one sensor
ipol            :func:`read_ipol`                     both feet (Xsens), hand-checked swings
gaitdriven      :func:`read_gaitdriven`               one foot, hand-marked footprints
ximu_cal        :func:`read_ximu_cal`                 x-IMU CalInertialAndMag CSV, 256 Hz, mag
delimited       :func:`read_delimited`                any delimited table, columns mapped
=============== ===================================== =========================================

:func:`load` guesses the format; :data:`READERS` maps the names to the readers.
"""

from __future__ import annotations

from footnav.data.io.azure_fgo import read_azure_fgo
from footnav.data.io.delimited import read_delimited
from footnav.data.io.footnav_csv import read_footnav_csv, read_footnav_recording, write_footnav_csv
from footnav.data.io.gaitdriven import read_gaitdriven
from footnav.data.io.gaitmap import read_gaitmap
from footnav.data.io.ipol import read_ipol
from footnav.data.io.load import READERS, guess_format, load
from footnav.data.io.openshoe import read_openshoe
from footnav.data.io.pyshoe import read_pyshoe
from footnav.data.io.ximu import read_ximu_cal
from footnav.data.io.xio import read_xio
from footnav.data.io.xsens import read_xsens

__all__ = [
    "read_footnav_csv",
    "read_footnav_recording",
    "write_footnav_csv",
    "read_gaitmap",
    "read_azure_fgo",
    "read_xio",
    "read_openshoe",
    "read_pyshoe",
    "read_xsens",
    "read_ipol",
    "read_gaitdriven",
    "read_ximu_cal",
    "read_delimited",
    "load",
    "guess_format",
    "READERS",
]
