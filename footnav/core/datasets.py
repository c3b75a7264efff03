"""The shared real recordings by name: where each lives and which reader (and truth) it needs.

``footnav evaluate --dataset azure_fgo`` and :func:`load_dataset` resolve names here. The data
folder is, in order: the ``data_dir`` argument, ``$FOOTNAV_DATA``, ``../shared/data`` from the
current folder, ``shared/data`` beside the footnav source tree.
"""

from __future__ import annotations

import os
from pathlib import Path as FilePath
from typing import Callable

from footnav.core.errors import DataNotFoundError, UnknownDatasetError
from footnav.core.types import Recording

__all__ = ["DATA_ENV", "data_dir", "dataset_names", "load_dataset"]

DATA_ENV = "FOOTNAV_DATA"


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
    from footnav.core import io

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


def dataset_names(root: FilePath | None = None) -> list[str]:
    """Every dataset name: the fixed ones and one ``pyshoe_<trial>`` per VICON trial found."""
    names = list(_fixed())
    if root is not None and (root / "pyshoe_vicon").is_dir():
        names += [f"pyshoe_{p.stem}" for p in sorted((root / "pyshoe_vicon").glob("*.mat"))]
    return names


def load_dataset(name: str, data: str | os.PathLike | None = None) -> Recording:
    """Read a shared recording by name, with its truth; the recording's ``name`` is ``name``."""
    root = data_dir(data)
    fixed = _fixed()
    if name in fixed:
        rec = fixed[name](root)
    elif name.startswith("pyshoe_") and (root / "pyshoe_vicon" / f"{name[7:]}.mat").is_file():
        from footnav.core.io import read_pyshoe

        rec = read_pyshoe(root / "pyshoe_vicon" / f"{name[7:]}.mat")
    else:
        raise UnknownDatasetError(f"no dataset named {name!r}; available: {', '.join(dataset_names(root))}")
    from dataclasses import replace

    return replace(rec, name=name)
