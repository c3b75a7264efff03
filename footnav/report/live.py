"""The live view of ``footnav follow --view``: the walk's footprints drawn as steps become final,
in a window of its own process, so that drawing never holds up the stream.

The stream's process only appends each final step to a list and, at most every
:attr:`LiveView.every_s` seconds, sends the new ones through a pipe (a few numbers a step); the
view's process (matplotlib, started with ``spawn``) redraws at most as often. Without a display
(no ``DISPLAY`` nor ``WAYLAND_DISPLAY`` on Linux, or ``MPLBACKEND=Agg``) it draws off-screen: the
command says so, and the ``report.html`` written at the end is what to open. The window closes
when the command ends; the report holds the whole walk.
"""

from __future__ import annotations

import os
import sys
import time
from typing import Any

__all__ = ["LiveView", "has_display"]

#: Steps the view marks as the latest, per foot.
LATEST = 6


def has_display() -> bool:
    """Whether a window can be opened: not on a Linux/BSD machine without an X or Wayland display,
    nor when matplotlib is told to draw to files only (``MPLBACKEND=Agg``)."""
    if os.environ.get("MPLBACKEND", "").lower() in ("agg", "svg", "pdf", "ps", "cairo", "template"):
        return False
    if sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")):
        return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))
    return True


class LiveView:
    """Draw closed steps live in another process; see the module docstring.

    >>> view = LiveView("follow: adaptive + ekf")                      # doctest: +SKIP
    >>> view.add(update.steps); view.flush()                            # after each push, doctest: +SKIP
    >>> view.close()                                                    # at the end, doctest: +SKIP
    """

    def __init__(self, title: str, every_s: float = 0.25, *, window: bool | None = None) -> None:
        import multiprocessing

        self.every_s = float(every_s)
        self.window = has_display() if window is None else window
        self._pending: list[tuple[float, str, float, float, float]] = []
        self._last = -float("inf")
        self.sent = 0
        ctx = multiprocessing.get_context("spawn")  # no fork of a process holding numba's threads
        self._reader, self._writer = ctx.Pipe(duplex=True)
        self._process = ctx.Process(
            target=_view_main, args=(self._reader, title, self.every_s, self.window), name="footnav-view", daemon=True
        )
        self._process.start()
        self._reader.close()  # the child's end

    def wait_ready(self, timeout_s: float = 30.0) -> bool:
        """Wait until the view's process has started and drawn its empty figure (a benchmark
        times the stream after that; the command does not wait)."""
        try:
            return self._writer.poll(timeout_s) and self._writer.recv() == "ready"
        except (OSError, EOFError):
            return False

    def add(self, steps) -> None:
        """Keep ``steps`` (closed steps: ``t``, ``foot``, ``position``) to send."""
        for s in steps:
            x, y, z = (float(v) for v in s.position)
            self._pending.append((float(s.t), str(s.foot), x, y, z))

    def flush(self, force: bool = False) -> None:
        """Send the kept steps when :attr:`every_s` has passed since the last sending (or ``force``)."""
        now = time.monotonic()
        if not self._pending or (not force and now - self._last < self.every_s):
            return
        try:
            self._writer.send(self._pending)
        except (OSError, EOFError):  # the view was closed by its user: the stream goes on
            pass
        self.sent += len(self._pending)
        self._pending, self._last = [], now

    def close(self, wait_s: float = 3.0) -> None:
        """Send what is left and the end; give the view ``wait_s`` to draw it, then end it."""
        self.flush(force=True)
        try:
            self._writer.send(None)
        except (OSError, EOFError):
            pass
        self._writer.close()
        self._process.join(wait_s)
        if self._process.is_alive():
            self._process.terminate()
            self._process.join(1.0)


def _view_main(conn, title: str, every_s: float, window: bool) -> None:  # pragma: no cover - its own process
    """The view's process: receive steps, redraw at most every ``every_s`` seconds."""
    import matplotlib

    if not window:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    colors = {"left": "tab:blue", "right": "tab:red"}
    steps: dict[str, list[tuple[float, float, float]]] = {"left": [], "right": []}
    if window:
        plt.ion()
    fig, ax = plt.subplots(figsize=(7, 6), layout="constrained")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, alpha=0.3)
    lines = {f: ax.plot([], [], ".-", color=c, lw=1, ms=4, label=f)[0] for f, c in colors.items()}
    latest = {f: ax.plot([], [], "o", color=c, ms=9, mfc="none", mew=1.6)[0] for f, c in colors.items()}
    ax.legend(loc="upper left", fontsize="small")
    if window:
        plt.show(block=False)
    fig.canvas.draw()
    try:
        conn.send("ready")
    except (OSError, EOFError):
        return
    dirty, last, ended, t_last = False, -float("inf"), False, 0.0
    while True:
        timeout = max(0.0, every_s - (time.monotonic() - last)) if dirty else 0.2
        try:
            got: Any = conn.recv() if conn.poll(timeout) else []
        except (EOFError, OSError):
            got = None
        if got is None:
            ended = True
        else:
            for t, foot, x, y, _z in got:
                steps.setdefault(foot, []).append((t, x, y))
                t_last = max(t_last, t)
            dirty = dirty or bool(got)
        if (dirty and time.monotonic() - last >= every_s) or ended:
            for foot, line in lines.items():
                xy = np.array([(x, y) for _, x, y in steps.get(foot, [])]).reshape(-1, 2)
                line.set_data(xy[:, 0], xy[:, 1])
                latest[foot].set_data(xy[-LATEST:, 0], xy[-LATEST:, 1])
                line.set_label(f"{foot}: {len(xy)} steps")
            ax.legend(loc="upper left", fontsize="small")
            ax.relim()
            ax.autoscale_view()
            ax.set_title(f"{title}\n{t_last:.1f} s" + (" (ended)" if ended else ""), fontsize="medium")
            fig.canvas.draw_idle() if window else fig.canvas.draw()
            dirty, last = False, time.monotonic()
        if window:
            try:
                fig.canvas.flush_events()
            except Exception:  # noqa: BLE001 - the window was closed: nothing more to show
                return
        if ended:
            return
