"""Which footnav modules each experiment of docs/papers.md ran, and their sources' digests.

docs/make_papers.py runs each paper's walks under :class:`ModuleTracker` and ends the paper's
section with a line ``<!-- inputs KEY: path=sha256[:12] ... -->``; :func:`stale` compares those
digests with the sources now, so tests/test_docs.py fails as soon as a module an experiment used
has changed since the page was generated, and names the modules and the command that regenerates
only those sections (``python docs/make_papers.py --only KEY``).

A module counts as used when a Python function of it ran (``sys.setprofile``) or when a numba
kernel of it was reachable from one (kernels call each other without Python frames). The
generator itself (docs/make_papers.py and this file) is an input of every section.
"""

from __future__ import annotations

import hashlib
import re
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "footnav"
GENERATOR = ("docs/make_papers.py", "docs/papers_inputs.py")
_LINE = re.compile(r"^<!-- inputs (\S+): (.*) -->$", re.M)


class ModuleTracker:
    """Context manager: the footnav source files (relative to the repository) whose Python code ran
    inside it, in :attr:`files`."""

    def __init__(self) -> None:
        self.files: set[str] = set()
        self._seen: set[str] = set()

    def _hook(self, frame: Any, event: str, arg: Any) -> None:
        if event == "call":
            self._seen.add(frame.f_code.co_filename)

    def __enter__(self) -> ModuleTracker:
        self._previous = sys.getprofile()
        sys.setprofile(self._hook)
        return self

    def __exit__(self, *exc: object) -> None:
        sys.setprofile(self._previous)
        self.files |= {_relative(f) for f in self._seen if _relative(f)}
        self.files |= _kernels_reachable(self.files)


def _relative(filename: str) -> str | None:
    try:
        path = Path(filename).resolve()
        path.relative_to(PACKAGE)
    except (OSError, ValueError):
        return None
    return path.relative_to(ROOT).as_posix()


def _kernels_reachable(files: set[str]) -> set[str]:
    """Modules of the numba kernels reachable from the loaded modules of ``files`` through module
    globals, transitively (a jitted call runs no Python frame the profiler would see)."""
    by_file = {}
    for mod in list(sys.modules.values()):
        f = getattr(mod, "__file__", None)
        rel = _relative(f) if f else None
        if rel:
            by_file[rel] = mod
    todo = [vars(by_file[f]) for f in files if f in by_file]
    out: set[str] = set()
    done: set[int] = set()
    while todo:
        names = todo.pop()
        for obj in list(names.values()):
            py_func = getattr(obj, "py_func", None)  # a numba Dispatcher
            if py_func is None or id(py_func) in done:
                continue
            done.add(id(py_func))
            rel = _relative(py_func.__code__.co_filename)
            if rel:
                out.add(rel)
                todo.append(py_func.__globals__)
    return out


def digest(relative: str) -> str:
    """First 12 hex digits of the sha256 of a file's bytes (relative to the repository)."""
    return hashlib.sha256((ROOT / relative).read_bytes()).hexdigest()[:12]


def record(key: str, files: set[str]) -> str:
    """The page's line for paper ``key``: every input with its digest."""
    inputs = sorted(set(files) | set(GENERATOR))
    return f"<!-- inputs {key}: " + " ".join(f"{f}={digest(f)}" for f in inputs) + " -->"


def recorded(text: str) -> dict[str, dict[str, str]]:
    """{paper key: {input: digest}} from a page's lines."""
    return {m.group(1): dict(item.split("=", 1) for item in m.group(2).split()) for m in _LINE.finditer(text)}


def stale(text: str) -> dict[str, list[str]]:
    """{paper key: the inputs that changed or vanished since the page recorded them} (only the
    papers with such inputs)."""
    out = {}
    for key, inputs in recorded(text).items():
        changed = [f for f, d in inputs.items() if not (ROOT / f).is_file() or digest(f) != d]
        if changed:
            out[key] = changed
    return out
