"""Where footnav writes: outputs claimed before the work, replaced only when footnav wrote them,
put in place atomically.

Nothing a user owns is deleted or overwritten. An output (a result folder, a figure, a table) is
*claimed* before any work: :func:`claim_output` refuses

* the working folder, any folder above it, a folder holding one of the run's inputs, an input
  itself; a file where a folder goes and a folder where a file goes;
* an existing non-empty output unless ``force``, and even with ``force`` one that footnav did not
  write: a result folder carries the marker file :data:`MARKER`, a figure footnav's name in its
  PNG metadata, a table footnav's CSV header;
* an output another footnav run is writing (a lock file beside it, created atomically with
  ``O_EXCL`` and holding the writer's process id).

The claimed output is written under a temporary name beside it (:meth:`OutputClaim.staged`) and
appears only when the work succeeded. A folder replaces its predecessor by two renames: the old
one aside, the new one in, then the old one renamed to a temporary name and deleted; a run
killed between the two renames leaves the old result whole beside the target, and the next claim
of that output puts it back and says so.
Temporary names left by killed runs (``.NAME.*.partial``) are removed by the next claim, which
says so too (under the lock nothing beside the target can belong to a live run). New folders and files follow the user's umask.
"""

from __future__ import annotations

import json
import os
import secrets
import shutil
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path as FilePath
from typing import Literal

from footnav.errors import DataQualityWarning, InvalidInputError
from footnav.warning_log import warn

__all__ = ["MARKER", "OutputClaim", "claim_output", "csv_signature", "is_footnav_figure"]

#: File in every result folder footnav writes: only folders holding it are ever replaced.
MARKER = ".footnav-result"
_LOCK = ".footnav-lock"
_PARTIAL = ".partial"
_OLD = ".old"
#: Bytes read from the top of a PNG when looking for footnav's name in its metadata.
_PNG_HEAD = 1 << 16
#: Software entry footnav writes into the metadata of its figures.
FIGURE_SOFTWARE = "footnav"

Kind = Literal["folder", "file"]


def is_footnav_figure(path: FilePath) -> bool:
    """True for a PNG whose metadata names footnav as its software (see :mod:`footnav.analysis.plot`)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(_PNG_HEAD)
    except OSError:
        return False
    return head.startswith(b"\x89PNG") and f"Software\x00{FIGURE_SOFTWARE}".encode() in head


def csv_signature(header: str) -> Callable[[FilePath], bool]:
    """A check that a file's first line is ``header``: the table is one footnav wrote."""

    def check(path: FilePath) -> bool:
        try:
            with open(path, encoding="utf-8", errors="replace") as fh:
                return fh.readline().rstrip("\r\n") == header
        except OSError:
            return False

    return check


def _refuse(message: str, path: FilePath) -> InvalidInputError:
    return InvalidInputError(message, path=str(path), field="out")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, another user's
        return True
    except OSError:
        return False
    return True


class OutputClaim:
    """An output this process may write; made by :func:`claim_output`, released by ``release``
    (or by leaving its ``with`` block)."""

    def __init__(self, target: FilePath, kind: Kind, lock: FilePath) -> None:
        self.target = target
        self.kind = kind
        self._lock = lock

    def __enter__(self) -> OutputClaim:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

    def release(self) -> None:
        """Remove the lock; the output stays as it is."""
        try:
            self._lock.unlink()
        except FileNotFoundError:
            pass

    @contextmanager
    def staged(self) -> Iterator[FilePath]:
        """A temporary folder (or file path, same extension) beside the target, put in its place
        when the block ends without an exception and removed when it raises."""
        parent, name = self.target.parent, self.target.name
        token = secrets.token_hex(4)
        if self.kind == "folder":
            tmp = parent / f".{name}.{token}{_PARTIAL}"
            os.mkdir(tmp)  # mode 0o777 less the umask, as any folder the user makes
        else:
            tmp = parent / f".{name}.{token}{_PARTIAL}{self.target.suffix}"
        try:
            yield tmp
            if self.kind == "folder":
                (tmp / MARKER).write_text(
                    json.dumps({"written_by": "footnav", "at": datetime.now(timezone.utc).isoformat(), "pid": os.getpid()})
                    + "\n",
                    encoding="utf-8",
                )
                self._place_folder(tmp, parent / f".{name}.{token}{_OLD}")
            else:
                os.replace(tmp, self.target)
        except BaseException:
            if tmp.is_dir():
                shutil.rmtree(tmp, ignore_errors=True)
            elif tmp.exists():
                tmp.unlink()
            raise

    def _place_folder(self, new: FilePath, aside: FilePath) -> None:
        if self.target.exists():
            os.rename(self.target, aside)
            os.rename(new, self.target)
            # deleted under a temporary name: a run killed while deleting (the marker perhaps
            # gone, other files not) leaves a .partial for the next claim to remove, never a
            # half-deleted .old it would take for a whole result
            doomed = aside.with_name(aside.name[: -len(_OLD)] + _PARTIAL + "-old")
            os.rename(aside, doomed)
            # the claim allowed only an empty folder or one footnav wrote
            shutil.rmtree(doomed) if (doomed / MARKER).exists() else os.rmdir(doomed)
        else:
            os.rename(new, self.target)


def _recover(target: FilePath) -> list[str]:
    """Clean what killed runs left beside ``target``; returns what was done, for one message."""
    done = []
    parent, name = target.parent, target.name
    olds = sorted(parent.glob(f".{name}.*{_OLD}"), key=lambda p: p.stat().st_mtime)
    for old in olds:
        if not (old / MARKER).exists():
            continue
        if not target.exists():
            os.rename(old, target)
            done.append(f"put back the result that an interrupted replacement had moved aside ({old.name})")
        else:
            shutil.rmtree(old)
            done.append(f"removed {old.name}, a replaced result an interrupted run left")
    for partial in parent.glob(f".{name}.*{_PARTIAL}*"):
        shutil.rmtree(partial) if partial.is_dir() else partial.unlink()
        done.append(f"removed {partial.name}, left by an interrupted run")
    return done


def _take_lock(lock: FilePath, target: FilePath) -> None:
    """Create the lock file atomically; a lock whose writer is dead is replaced."""
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)
        except FileExistsError:
            try:
                pid = int(lock.read_text(encoding="utf-8").strip() or "0")
            except (OSError, ValueError):
                pid = 0
            if pid and _pid_alive(pid):
                raise _refuse(
                    f"another footnav run (process {pid}) is writing {str(target)!r}; wait for it or choose another "
                    f"output (if no such run exists, remove {lock.name})",
                    target,
                ) from None
            lock.unlink(missing_ok=True)
            continue
        except OSError as exc:
            raise _refuse(f"cannot write beside {str(target)!r}: {exc.strerror or exc}", target) from None
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(f"{os.getpid()}\n")
        return
    raise _refuse(f"cannot take the lock {lock.name} for {str(target)!r}", target)


def claim_output(
    path: str | os.PathLike,
    *,
    kind: Kind = "folder",
    force: bool = False,
    inputs: Iterable[str | os.PathLike] = (),
    signature: Callable[[FilePath], bool] | None = None,
    what: str = "output",
) -> OutputClaim:
    """Claim ``path`` for this run's output, before any work; see the module docstring.

    Parameters
    ----------
    path
        The result folder (``kind="folder"``) or file (``kind="file"``).
    force
        Replace an existing output, if footnav wrote it.
    inputs
        The run's input files: never replaced, and no folder holding one is either.
    signature
        For a file: recognises one footnav wrote (e.g. :func:`is_footnav_figure`); without it an
        existing file is never replaced.
    what
        How messages name the output (``"output folder"``, ``"figure"``).

    Raises
    ------
    InvalidInputError
        With ``field="out"``: the output would replace something footnav must not touch, or is
        being written by another run, or its parent cannot be written.
    """
    target = FilePath(path)
    resolved = target.resolve()
    cwd = FilePath.cwd().resolve()
    if resolved == cwd or resolved in cwd.parents:
        raise _refuse(f"{what} {str(target)!r} is the working folder or holds it; choose a new folder", target)
    for item in inputs:
        src = FilePath(item).resolve()
        if src == resolved:
            raise _refuse(f"{what} {str(target)!r} is an input of this run; choose another", target)
        if resolved in src.parents:
            raise _refuse(f"{what} {str(target)!r} holds the input {str(item)!r}; choose another", target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _refuse(f"cannot create the folder of {what} {str(target)!r}: {exc.strerror or exc}", target) from None
    if not os.access(target.parent, os.W_OK | os.X_OK):
        raise _refuse(f"cannot write in {str(target.parent)!r} (permission denied)", target)
    lock = target.parent / f".{target.name}{_LOCK}"
    _take_lock(lock, target)
    claim = OutputClaim(target, kind, lock)
    try:
        # with the lock held, whatever a run left beside the target is from a run that died
        done = _recover(target)
        if done:
            warn(f"{target}: " + "; ".join(done), DataQualityWarning, stacklevel=2)
        _check_existing(target, kind, force, signature, what)
    except BaseException:
        claim.release()
        raise
    return claim


def _check_existing(
    target: FilePath, kind: Kind, force: bool, signature: Callable[[FilePath], bool] | None, what: str
) -> None:
    if not (target.exists() or target.is_symlink()):
        return
    if target.is_symlink():
        raise _refuse(f"{what} {str(target)!r} is a symbolic link; footnav does not write through links", target)
    if kind == "folder":
        if not target.is_dir():
            raise _refuse(f"{what} {str(target)!r} is a file; footnav writes a folder there, choose another name", target)
        if not any(target.iterdir()):
            return
        if not force:
            raise _refuse(
                f"{what} {str(target)!r} exists and is not empty; choose another or pass --force to replace it", target
            )
        if not (target / MARKER).is_file():
            raise _refuse(
                f"{what} {str(target)!r} was not written by footnav (no {MARKER} in it); footnav replaces only its own "
                "results, even with --force: choose another",
                target,
            )
        return
    if target.is_dir():
        raise _refuse(f"{what} {str(target)!r} is a folder; footnav writes a file there, choose another name", target)
    if not force:
        raise _refuse(f"{what} {str(target)!r} exists; choose another or pass --force to replace it", target)
    if signature is None or not signature(target):
        raise _refuse(
            f"{what} {str(target)!r} was not written by footnav; footnav replaces only its own files, even with "
            "--force: choose another",
            target,
        )

