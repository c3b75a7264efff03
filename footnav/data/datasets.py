"""The shared real recordings by name: where each lives and which reader (and truth) it needs.

``footnav evaluate --dataset azure_fgo`` and :func:`load_dataset` resolve names here. The data
folder is, in order: the ``data_dir`` argument, ``$FOOTNAV_DATA``, ``../shared/data`` from the
current folder, ``shared/data`` beside the footnav source tree. The recordings in
:data:`BUNDLED` ship inside the package (``footnav/data/``): they load from there when the data
folder is missing or lacks them, so ``footnav evaluate --dataset azure_fgo`` works in a fresh
install.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import replace
from importlib import resources
from pathlib import Path as FilePath

from footnav.core.errors import DataNotFoundError, UnknownDatasetError
from footnav.core.types import Recording

__all__ = ["BUNDLED", "DATA_ENV", "data_dir", "dataset_names", "load_dataset"]

DATA_ENV = "FOOTNAV_DATA"
#: Datasets shipped inside the package, in ``footnav/data/<name>/`` (package data).
BUNDLED = ("azure_fgo",)


def data_dir(explicit: str | os.PathLike | None = None) -> FilePath:
    """The shared data folder; DataNotFoundError says where it looked and how to point at it."""
    candidates = []
    if explicit is not None:
        candidates.append(FilePath(explicit))
    elif os.environ.get(DATA_ENV):
        candidates.append(FilePath(os.environ[DATA_ENV]))
    else:
        candidates.append(FilePath.cwd().parent / "shared" / "data")
        candidates.append(FilePath(__file__).resolve().parents[3] / "shared" / "data")
    for c in candidates:
        if c.is_dir():
            return c
    raise DataNotFoundError(
        f"shared data folder not found (looked in {', '.join(str(c) for c in candidates)}); "
        f"pass --data-dir or set {DATA_ENV}"
    )


def _fixed() -> dict[str, Callable[[FilePath], Recording]]:
    from footnav.data import io

    def gaitmap(root: FilePath) -> Recording:
        d = root / "gaitmap_example"
        return io.read_gaitmap(d / "imu_sample.csv", d / "mocap_sample.csv", d / "stride_events_sample.csv")

    return {
        "azure_fgo": lambda root: io.read_azure_fgo(root / "azure_fgo"),
        "gaitmap": gaitmap,
        "xio_short": lambda root: io.read_xio(root / "xio_gait_tracking" / "short_walk.csv", drop_duplicates=True),
        "xio_long": lambda root: io.read_xio(root / "xio_gait_tracking" / "long_walk.csv", drop_duplicates=True),
        "openshoe": lambda root: io.read_openshoe(root / "openshoe" / "OpenShoeDataSet.txt"),
    }


#: Folders of the trial sets found by globbing, and how a file's name becomes a dataset name.
_IPOL_DIR = "ipol_dev"
_GAITDRIVEN_DIR = "gaitdriven_dev"
_GAITDRIVEN_PREFIX, _GAITDRIVEN_SUFFIX = "SensorConnectData_", "_LLIO.mat"


def _trial_order(stem: str) -> tuple:
    # "1-10" after "1-9": numeric parts compared as numbers
    return tuple(int(x) if x.isdigit() else x for x in stem.replace("_", "-").split("-"))


def _ipol_trials(root: FilePath) -> list[str]:
    d = root / _IPOL_DIR
    if not d.is_dir():
        return []
    return sorted((p.stem for p in d.glob("*.json") if (d / f"{p.stem}_lf.txt").is_file()), key=_trial_order)


def _gaitdriven_trials(root: FilePath) -> list[str]:
    d = root / _GAITDRIVEN_DIR
    if not d.is_dir():
        return []
    nn = [
        p.name[len(_GAITDRIVEN_PREFIX) : -len(_GAITDRIVEN_SUFFIX)]
        for p in d.glob(f"{_GAITDRIVEN_PREFIX}*{_GAITDRIVEN_SUFFIX}")
    ]
    return sorted(nn, key=_trial_order)


def dataset_names(root: FilePath | None = None) -> list[str]:
    """Every dataset name: the fixed ones, then one name per trial found under ``root``.

    ``pyshoe_<trial>`` per pyshoe VICON trial (Wagstaff et al. 2020), ``ipol_<subject>-<trial>``
    per IPOL gait trial (Voisard et al., IPOL 2023; e.g. ``ipol_1-1``) and ``gaitdriven_<NN>``
    per gait-driven trial (Cetin & Koroglu 2026; e.g. ``gaitdriven_31``). ``root`` None looks in
    :func:`data_dir` (the trial sets are then listed when the shared data are there).
    """
    if root is None:
        try:
            root = data_dir()
        except DataNotFoundError:
            root = None
    else:
        root = FilePath(root)  # a str names the folder too
    names = list(_fixed())
    if root is not None and (root / "pyshoe_vicon").is_dir():
        names += [f"pyshoe_{p.stem}" for p in sorted((root / "pyshoe_vicon").glob("*.mat"))]
    if root is not None:
        names += [f"ipol_{s}" for s in _ipol_trials(root)]
        names += [f"gaitdriven_{s}" for s in _gaitdriven_trials(root)]
    return names


def _bundled(name: str) -> Recording:
    """A :data:`BUNDLED` recording, read from the package's own copy."""
    with resources.as_file(resources.files("footnav") / "data") as root:
        return _fixed()[name](FilePath(root))


def load_dataset(name: str, data: str | os.PathLike | None = None) -> Recording:
    """Read a shared recording by name, with its truth; the recording's ``name`` is ``name``.

    A :data:`BUNDLED` name is read from the data folder when it holds it, else from the copy
    inside the package; every other name needs the data folder (:func:`data_dir`).
    """
    if name in BUNDLED:
        try:
            shared = data_dir(data) / name
        except DataNotFoundError:
            shared = None
        if shared is None or not shared.is_dir():
            return replace(_bundled(name), name=name)
    root = data_dir(data)
    fixed = _fixed()
    if name in fixed:
        rec = fixed[name](root)
    elif name.startswith("pyshoe_") and (root / "pyshoe_vicon" / f"{name[7:]}.mat").is_file():
        from footnav.data.io import read_pyshoe

        rec = read_pyshoe(root / "pyshoe_vicon" / f"{name[7:]}.mat")
    elif name.startswith("ipol_") and (root / _IPOL_DIR / f"{name[5:]}.json").is_file():
        from footnav.data.io import read_ipol

        rec = read_ipol(root / _IPOL_DIR / f"{name[5:]}.json")
    elif (
        name.startswith("gaitdriven_")
        and (root / _GAITDRIVEN_DIR / f"{_GAITDRIVEN_PREFIX}{name[11:]}{_GAITDRIVEN_SUFFIX}").is_file()
    ):
        from footnav.data.io import read_gaitdriven

        rec = read_gaitdriven(root / _GAITDRIVEN_DIR / f"{_GAITDRIVEN_PREFIX}{name[11:]}{_GAITDRIVEN_SUFFIX}")
    else:
        raise UnknownDatasetError(f"no dataset named {name!r}; available: {', '.join(dataset_names(root))}")
    return replace(rec, name=name)
