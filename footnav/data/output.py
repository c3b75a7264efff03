"""Where footnav writes: outputs claimed before the work, replaced only when everything in them is
footnav's, put in place atomically; footnav removes only entries it created itself.

Nothing a user owns is deleted or overwritten. An output (a result folder, a figure, a table) is
*claimed* before any work: :func:`claim_output` refuses

* the working folder, any folder above it, a folder holding one of the run's inputs, an input
  itself; a file where a folder goes and a folder where a file goes;
* an existing non-empty output unless ``force``, and even with ``force`` one that footnav did not
  write: a figure must carry footnav's name in its PNG metadata, a table footnav's CSV header, and
  a result folder must hold the marker file :data:`MARKER` *and nothing else than what the marker
  lists* (see below; an empty folder is taken as it is); the refusal names the foreign entries
  (the first few, and how many);
* with ``force``, a result folder that could not be deleted whole: its parent and every folder in
  it (sub-folders too) must be writable, checked before anything moves;
* an output another footnav run is writing (a lock file ``.NAME.footnav-lock`` beside it, created
  atomically with ``O_EXCL``), and a lock file that is not footnav's or not yet readable.

**What footnav wrote.** The marker, written last into a result folder after its contents, lists
them: ``{"files": [...], "folders": [...]}``, relative paths with ``/``. Only names count: a file
footnav wrote and the user changed is still footnav's and is replaced (sizes or hashes would make
every edited ``summary.json`` a refusal). A folder is replaceable when every entry in it is the
marker or listed, as the same kind (a folder where a file was listed is foreign; symbolic links
are entries, never followed). A marker of an earlier footnav without the lists (or one that cannot
be read) allows only top-level files named as footnav names its result files
(:data:`LEGACY_NAMES`, ``pipeline-*.toml``); anything else, sub-folders included, is foreign.
The replaced folder is deleted by that list too: listed files, then listed folders when empty,
the marker, the folder; whatever else appeared in it during the run is kept and named.

**Temporary names.** The claimed output is written under a temporary name beside it
(:meth:`OutputClaim.staged`) and appears only when the work succeeded. Every temporary name
carries a token no user file has, ``footnav-PID-RANDOM`` (the writer's process id, 8 random hex
digits): ``.NAME.TOKEN.partial`` (the output being written; a file keeps its extension),
``.NAME.TOKEN.old`` (the replaced folder, moved aside) and ``.NAME.TOKEN.partial-old`` (the
replaced folder being deleted). The lock file holds JSON lines: a header with the writer's
process id, then one line per temporary name, written *before* the entry is created. A folder
replaces its predecessor by renames: the old one aside, the new one in (an exception between the
two, Ctrl-C say, puts the old one back at once), then the old one renamed to its ``partial-old``
name and deleted by its marker's list.

**Recovery.** A claim that finds the lock of a dead writer takes it over with the entries it
names, then recovers exactly those entries: an aside result is put back when the target is
missing (a run killed between the two renames) and otherwise deleted by its marker's list; a
``partial`` is removed; a ``partial-old`` is deleted by its marker's list (the marker goes last,
so one without it holds nothing footnav wrote and is removed only when empty). Each action is
said in one :class:`~footnav.core.errors.DataQualityWarning`. A claim released while entries it named
still exist (a deletion cut short by Ctrl-C, a replaced folder kept for files added to it during
the run) leaves its lock naming them under no writer (process id 0), for the next claim to
recover. A lock file that is not a readable footnav lock is never removed: the claim refuses,
as it does while another run is still writing its lock; only an empty one older than 10 s (its
writer died before writing it) is replaced, and said. Nothing is ever removed because its name
looks like footnav's: an entry beside the target that no lock names (a user's
``.res.v2.partial.md``) is never touched, and a lock of an earlier footnav holding only a process
id names nothing, so what such a run left is only listed, never removed.
New folders and files follow the user's umask. A kill (SIGKILL included) at any moment is
covered; a power loss is not (nothing is fsynced).
"""

from __future__ import annotations

import json
import os
import re
import secrets
import shutil
import stat
import time
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path as FilePath
from typing import Literal

from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.warning_log import warn
from footnav.data.result_marker import (
    LEGACY_NAMES,
    MARKER,
    _delete_result,
    _foreign,
    _is_real_dir,
    _marker_text,
    _named,
    _recorded,
)

__all__ = ["LEGACY_NAMES", "MARKER", "OutputClaim", "claim_output", "csv_signature", "is_footnav_figure"]

_LOCK = ".footnav-lock"
_PARTIAL = ".partial"
_OLD = ".old"
_DOOMED = ".partial-old"
#: Roles of the temporary entries a lock names: what recovery does with each.
_ROLES = ("partial", "aside", "doomed")
#: Seconds an empty lock may be a run that has created it and not yet written it.
_STARTING_S = 10.0
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


def _writable(folder: FilePath) -> bool:
    """Entries of ``folder`` can be created, renamed and removed by this process."""
    return os.access(folder, os.W_OK | os.X_OK)


def _undeletable(root: FilePath) -> FilePath | None:
    """The first folder (``root`` or one in it) whose entries this process cannot remove."""
    if not _writable(root) or not os.access(root, os.R_OK):
        return root
    for dirpath, dirnames, _ in os.walk(root):
        for d in dirnames:
            sub = FilePath(dirpath) / d
            if not sub.is_symlink() and (not _writable(sub) or not os.access(sub, os.R_OK)):
                return sub
    return None


# --- the lock --------------------------------------------------------------------------------


@dataclass
class _LockState:
    """A lock file read back: its writer and the temporary entries it named, in order."""

    pid: int
    entries: list[tuple[str, str]] = field(default_factory=list)  # (name, role)
    legacy: bool = False  # an earlier footnav's lock: a process id only


def _entry_pattern(target: FilePath) -> re.Pattern[str]:
    # names a lock may make recovery act on: only footnav's spelling for this target, no path
    suffix = re.escape(target.suffix)
    return re.compile(
        rf"\.{re.escape(target.name)}\.footnav-\d+-[0-9a-f]{{8}}"
        rf"(?:{re.escape(_PARTIAL)}(?:{suffix})?|{re.escape(_OLD)}|{re.escape(_DOOMED)})"
    )


def _read_lock(lock: FilePath, target: FilePath) -> _LockState | None:
    """The lock's writer and entries; None when the file is not (yet) a readable footnav lock."""
    try:
        lines = lock.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    if not lines:
        return None
    try:
        head = json.loads(lines[0])
    except ValueError:
        return None
    if isinstance(head, int) and not isinstance(head, bool):
        return _LockState(pid=head, legacy=True)
    if not (isinstance(head, dict) and head.get("footnav") == "output-lock" and isinstance(head.get("pid"), int)):
        return None
    state = _LockState(pid=head["pid"])
    valid = _entry_pattern(target)
    for line in lines[1:]:
        try:
            item = json.loads(line)
        except ValueError:
            continue  # the last line of a writer killed while writing it: its entry was never created
        if (
            isinstance(item, dict)
            and item.get("role") in _ROLES
            and isinstance(item.get("entry"), str)
            and valid.fullmatch(item["entry"])
        ):
            state.entries.append((item["entry"], item["role"]))
    return state


def _lock_lines(entries: Iterable[tuple[str, str]]) -> str:
    return "".join(json.dumps({"entry": name, "role": role}) + "\n" for name, role in entries)


def _abandoned_empty(lock: FilePath) -> bool:
    """An empty lock older than :data:`_STARTING_S`: its writer died before writing a byte (an
    empty file holds nothing to lose; a younger one may be a run that is just starting)."""
    try:
        st = lock.stat()
    except OSError:
        return False
    return st.st_size == 0 and time.time() - st.st_mtime > _STARTING_S


def _take_lock(lock: FilePath, target: FilePath) -> tuple[list[tuple[str, str]], list[str]]:
    """Create the lock file atomically. A lock whose writer is dead is replaced, and the entries
    it named are carried into the new lock (so that a kill during their recovery leaves them
    named); returns them, and notes for the recovery message."""
    inherited: list[tuple[str, str]] = []
    notes: list[str] = []
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)
        except FileExistsError:
            state = _read_lock(lock, target)
            if state is None and _abandoned_empty(lock):
                notes.append(f"replaced an empty {lock.name}, left by a run killed as it started")
                lock.unlink(missing_ok=True)
                continue
            if state is None:
                # also what a lock looks like between another run's creating and writing it
                raise _refuse(
                    f"{lock.name} beside {str(target)!r} is not a readable footnav lock: another footnav run may be "
                    "starting; if none is, move that file away",
                    target,
                ) from None
            if state.pid and _pid_alive(state.pid):
                raise _refuse(
                    f"another footnav run (process {state.pid}) is writing {str(target)!r}; wait for it or choose "
                    f"another output (if no such run exists, remove {lock.name})",
                    target,
                ) from None
            inherited = state.entries
            if state.legacy:
                notes.append(
                    f"replaced the lock of an earlier footnav run (process {state.pid}), which named no "
                    "temporary entries"
                )
            lock.unlink(missing_ok=True)
            continue
        except OSError as exc:
            raise _refuse(f"cannot write beside {str(target)!r}: {exc.strerror or exc}", target) from None
        head = {"footnav": "output-lock", "pid": os.getpid(), "at": datetime.now(timezone.utc).isoformat()}
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(json.dumps(head) + "\n" + _lock_lines(inherited))
        return inherited, notes
    raise _refuse(f"cannot take the lock {lock.name} for {str(target)!r}", target)


def _recover(target: FilePath, entries: list[tuple[str, str]]) -> list[str]:
    """Recover the temporary entries a dead writer's lock named; returns what was done."""
    done = []
    parent = target.parent
    for name, role in entries:
        path = parent / name
        if not (path.exists() or path.is_symlink()):
            continue
        try:
            if role == "partial":
                shutil.rmtree(path) if _is_real_dir(path) else path.unlink()
                done.append(f"removed {name}, left by an interrupted run")
            elif not _is_real_dir(path):
                done.append(f"left {name} as it is: footnav moved a folder there, this is not one")
            elif role == "aside" and not (target.exists() or target.is_symlink()):
                os.rename(path, target)
                done.append(f"put back the result that an interrupted replacement had moved aside ({name})")
            else:
                left = _delete_result(path)
                what = "a replaced result an interrupted run left" if role == "aside" else "left by an interrupted run"
                if left:
                    done.append(f"kept {name} ({what}): it holds entries footnav did not write ({_named(left)})")
                else:
                    done.append(f"removed {name}, {what}")
        except OSError as exc:
            reason = exc.strerror or exc
            done.append(f"could not remove {name}, left by an interrupted run ({reason}); remove it by hand")
    return done


def _legacy_leftovers(target: FilePath) -> list[str]:
    """Names an earlier footnav gave its temporary entries, for the message only: never removed."""
    old = re.compile(rf"\.{re.escape(target.name)}\.[0-9a-f]{{8}}\.(?:partial|old)")
    try:
        return sorted(e.name for e in os.scandir(target.parent) if old.match(e.name))
    except OSError:
        return []


# --- the claim -------------------------------------------------------------------------------


class OutputClaim:
    """An output this process may write; made by :func:`claim_output`, released by ``release``
    (or by leaving its ``with`` block)."""

    def __init__(self, target: FilePath, kind: Kind, lock: FilePath) -> None:
        self.target = target
        self.kind = kind
        self._lock = lock
        self._token = self._new_token()
        self._named: dict[str, str] = {}  # entries this claim's lock names already: name -> role

    @staticmethod
    def _new_token() -> str:
        return f"footnav-{os.getpid()}-{secrets.token_hex(4)}"

    def __enter__(self) -> OutputClaim:
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()

    def release(self) -> None:
        """Remove the lock; the output stays as it is. Entries the lock names that still exist (a
        deletion cut short by Ctrl-C, a replaced folder kept for what the user added to it) stay
        named in it, under no writer, for the next claim to recover."""
        parent = self.target.parent
        left = [(n, r) for n, r in self._named.items() if (parent / n).exists() or (parent / n).is_symlink()]
        try:
            if not left:
                self._lock.unlink()
                return
            head = {"footnav": "output-lock", "pid": 0, "at": datetime.now(timezone.utc).isoformat()}
            self._lock.write_text(json.dumps(head) + "\n" + _lock_lines(left), encoding="utf-8")
        except FileNotFoundError:
            pass

    def _names(self) -> dict[str, FilePath]:
        """This staging's temporary paths by role, with a token none of them exists under (a
        claim staged again, as the live figure of ``follow``, reuses its names)."""
        parent, name = self.target.parent, self.target.name
        while True:
            stem = f".{name}.{self._token}"
            paths = {
                "partial": parent / (stem + _PARTIAL + (self.target.suffix if self.kind == "file" else "")),
                "aside": parent / (stem + _OLD),
                "doomed": parent / (stem + _DOOMED),
            }
            if not any(p.exists() or p.is_symlink() for p in paths.values()):
                return paths
            self._token = self._new_token()

    def _name_in_lock(self, *paths: tuple[str, FilePath]) -> None:
        """Append entries to the lock before they are created: recovery acts on nothing else."""
        new = [(p.name, role) for role, p in paths if p.name not in self._named]
        if not new:
            return
        # one write of whole lines: a kill mid-write cuts at most the last line, whose entry
        # does not exist yet
        fd = os.open(self._lock, os.O_WRONLY | os.O_APPEND)
        try:
            os.write(fd, _lock_lines(new).encode("utf-8"))
        finally:
            os.close(fd)
        self._named.update(new)

    @contextmanager
    def staged(self) -> Iterator[FilePath]:
        """A temporary folder (or file path, same extension) beside the target, put in its place
        when the block ends without an exception and removed when it raises. A folder gets the
        marker, listing what the block wrote into it, last."""
        names = self._names()
        tmp = names["partial"]
        self._name_in_lock(("partial", tmp))
        if self.kind == "folder":
            os.mkdir(tmp)  # mode 0o777 less the umask, as any folder the user makes
        try:
            yield tmp
            if self.kind == "folder":
                (tmp / MARKER).write_text(_marker_text(tmp), encoding="utf-8")
                self._place_folder(tmp, names["aside"], names["doomed"])
            else:
                os.replace(tmp, self.target)
        except BaseException:
            if _is_real_dir(tmp):
                shutil.rmtree(tmp, ignore_errors=True)
            elif tmp.exists() or tmp.is_symlink():
                tmp.unlink()
            raise

    def _place_folder(self, new: FilePath, aside: FilePath, doomed: FilePath) -> None:
        if not self.target.exists():
            os.rename(new, self.target)
            return
        self._name_in_lock(("aside", aside), ("doomed", doomed))
        os.rename(self.target, aside)
        try:
            os.rename(new, self.target)
        except BaseException:
            os.rename(aside, self.target)  # the old result back where it was (Ctrl-C between the renames)
            raise
        # deleted under a temporary name: a run killed while deleting leaves a partial-old for the
        # next claim to finish, never a half-deleted .old it would put back as a whole result
        os.rename(aside, doomed)
        try:
            left = _delete_result(doomed)
        except OSError as exc:
            why = f"it could not be deleted ({exc.strerror or exc})"
        else:
            why = f"it holds entries footnav did not write, added during the run ({_named(left)})" if left else ""
        if why:
            warn(
                f"{self.target}: the replaced result is kept as {doomed.name}: {why}; the next claim of this output "
                "tries again, or move out what is yours and remove that folder",
                DataQualityWarning,
                stacklevel=4,
            )


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
        Replace an existing output, if footnav wrote it (a folder: all of it).
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
        With ``field="out"``: the output would replace something footnav must not touch (its
        message names the foreign entries), could not be replaced whole, is being written by
        another run, or its parent cannot be written.
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
    if not _writable(target.parent):
        raise _refuse(f"cannot write in {str(target.parent)!r} (permission denied)", target)
    lock = target.parent / f".{target.name}{_LOCK}"
    inherited, notes = _take_lock(lock, target)
    claim = OutputClaim(target, kind, lock)
    claim._named.update(inherited)
    try:
        done = notes + _recover(target, inherited)
        leftovers = _legacy_leftovers(target) if notes else []
        if leftovers:
            done.append(f"left {_named(leftovers)} as they are: remove them if an interrupted earlier run left them")
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
            raise _refuse(
                f"{what} {str(target)!r} is a file; footnav writes a folder there, choose another name", target
            )
        try:
            empty = not any(target.iterdir())
        except OSError as exc:
            raise _refuse(f"cannot read {what} {str(target)!r}: {exc.strerror or exc}", target) from None
        if empty:
            return
        if not force:
            raise _refuse(
                f"{what} {str(target)!r} exists and is not empty; choose another or pass --force to replace it", target
            )
        recorded = _recorded(target)
        if recorded is None:
            raise _refuse(
                f"{what} {str(target)!r} was not written by footnav (no {MARKER} in it); footnav replaces only its own "
                "results, even with --force: choose another",
                target,
            )
        try:
            foreign = _foreign(target, recorded)
        except OSError as exc:
            raise _refuse(f"cannot read {what} {str(target)!r}: {exc.strerror or exc}", target) from None
        if foreign:
            raise _refuse(
                f"{what} {str(target)!r} holds {len(foreign)} entr{'y' if len(foreign) == 1 else 'ies'} footnav did "
                f"not write ({_named(foreign)}); footnav replaces only what it wrote, even with --force: move "
                "them out or choose another",
                target,
            )
        _check_replaceable(target, what)
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


def _check_replaceable(target: FilePath, what: str) -> None:
    """Refuse, before anything moves, a folder this process could not move aside and delete."""
    parent = target.parent
    st_parent = parent.stat()
    euid = os.geteuid() if hasattr(os, "geteuid") else None  # no sticky folders on Windows
    sticky = bool(st_parent.st_mode & stat.S_ISVTX)
    if sticky and euid is not None and euid not in (0, st_parent.st_uid, target.stat().st_uid):
        raise _refuse(f"cannot replace {what} {str(target)!r}: {str(parent)!r} lets only its owners move it", target)
    blocked = _undeletable(target)
    if blocked is not None:
        raise _refuse(
            f"cannot replace {what} {str(target)!r}: {str(blocked)!r} is not writable (permission denied); nothing "
            "was moved",
            target,
        )
