"""What footnav wrote in a result folder: the marker file :data:`MARKER` listing it, the check
that a folder holds nothing else, and deleting by that list (:mod:`footnav.data.output` uses
them to replace only footnav's results; its docstring gives the rules)."""

from __future__ import annotations

import json
import os
import re
from datetime import datetime, timezone
from pathlib import Path as FilePath

__all__ = ["LEGACY_NAMES", "MARKER"]

#: File in every result folder footnav writes: only folders holding it are ever replaced.
MARKER = ".footnav-result"
#: Files footnav writes at the top of its result folders: what a marker without a list allows.
LEGACY_NAMES = frozenset(
    {
        "left.csv",
        "right.csv",
        "path.csv",
        "strides.csv",
        "trajectories.npz",
        "summary.json",
        "pipeline.toml",
        "report.csv",
        "report.json",
        "left_truth.csv",
        "right_truth.csv",
    }
)
_LEGACY_PATTERN = re.compile(r"pipeline-.+\.toml")


#: Foreign entries a refusal names before "and N more".
_SHOWN = 5


def _is_real_dir(path: FilePath) -> bool:
    return path.is_dir() and not path.is_symlink()


# --- what footnav wrote in a result folder --------------------------------------------------


def _listing(root: FilePath) -> tuple[set[str], set[str]]:
    """Files and folders under ``root`` (relative, ``/``-separated; links are files, not followed)."""
    files: set[str] = set()
    folders: set[str] = set()
    for dirpath, dirnames, filenames in os.walk(root):  # os.walk does not follow links by default
        rel = FilePath(dirpath).relative_to(root)
        for d in list(dirnames):
            (folders if not os.path.islink(os.path.join(dirpath, d)) else files).add((rel / d).as_posix())
        files.update((rel / f).as_posix() for f in filenames)
    files.discard(MARKER)
    return files, folders


def _marker_text(root: FilePath) -> str:
    files, folders = _listing(root)
    doc = {
        "written_by": "footnav",
        "at": datetime.now(timezone.utc).isoformat(),
        "pid": os.getpid(),
        "files": sorted(files),
        "folders": sorted(folders),
    }
    return json.dumps(doc) + "\n"


def _recorded(root: FilePath) -> tuple[set[str], set[str]] | None:
    """What the marker of ``root`` says footnav wrote; None without a marker. A marker without the
    lists (an earlier footnav's, or unreadable) allows footnav's usual top-level file names."""
    marker = root / MARKER
    if not marker.is_file() or marker.is_symlink():
        return None
    try:
        doc = json.loads(marker.read_text(encoding="utf-8"))
        files, folders = doc["files"], doc["folders"]
        if all(_relative(x) for x in [*files, *folders]):
            return set(files), set(folders)
    except (OSError, ValueError, TypeError, KeyError):
        pass
    try:
        names = [e.name for e in os.scandir(root) if e.is_file(follow_symlinks=False)]
    except OSError:
        names = []
    return {n for n in names if n in LEGACY_NAMES or _LEGACY_PATTERN.fullmatch(n)}, set()


def _relative(rel: object) -> bool:
    """A marker's entry is a plain relative path inside the folder (a crafted marker names nothing outside)."""
    return isinstance(rel, str) and all(part not in ("", ".", "..") for part in rel.split("/"))


def _inside(root: FilePath, rel: str) -> bool:
    """Every folder on the way from ``root`` to ``rel`` is a real folder: a link put in place of
    a folder footnav wrote never leads a deletion outside ``root``."""
    path = root
    for part in rel.split("/")[:-1]:
        path = path / part
        if not _is_real_dir(path):
            return False
    return True


def _foreign(root: FilePath, recorded: tuple[set[str], set[str]]) -> list[str]:
    """Entries under ``root`` that ``recorded`` does not list as footnav's (a foreign folder is
    named once, with a trailing ``/``, not descended into)."""
    files, folders = recorded
    out: list[str] = []

    def walk(folder: FilePath, prefix: str) -> None:
        with os.scandir(folder) as found:
            entries = sorted(found, key=lambda e: e.name)
        for entry in entries:
            rel = prefix + entry.name
            if entry.is_dir(follow_symlinks=False):
                if rel in folders:
                    walk(FilePath(entry.path), rel + "/")
                else:
                    out.append(rel + "/")
            elif rel not in files and not (rel == MARKER and not prefix):
                out.append(rel)

    walk(root, "")
    return out


def _named(entries: list[str]) -> str:
    shown = ", ".join(entries[:_SHOWN])
    more = len(entries) - _SHOWN
    return shown + (f" and {more} more" if more > 0 else "")


def _delete_result(root: FilePath) -> list[str]:
    """Delete what the marker of ``root`` lists, then the marker and ``root`` if nothing else is
    left; returns what was left (entries footnav did not write). Without a marker only an empty
    ``root`` is removed: the marker is deleted last, so its absence means the listed entries are
    gone already (or ``root`` was an empty folder when claimed)."""
    recorded = _recorded(root)
    if recorded is not None:
        files, folders = recorded
        for rel in sorted(files):
            path = root / rel
            if _inside(root, rel) and (path.is_symlink() or (path.exists() and not path.is_dir())):
                path.unlink()
        for rel in sorted(folders, key=lambda r: r.count("/"), reverse=True):
            path = root / rel
            if _inside(root, rel) and _is_real_dir(path) and not any(path.iterdir()):
                path.rmdir()
        left = _foreign(root, recorded)
        if left:
            return left
        (root / MARKER).unlink()
    else:
        with os.scandir(root) as found:
            left = sorted(e.name + ("/" if e.is_dir(follow_symlinks=False) else "") for e in found)
        if left:
            return left
    root.rmdir()
    return []
