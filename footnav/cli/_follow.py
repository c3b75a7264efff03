"""``footnav follow``: a pipeline run online on footnav CSV rows as they arrive (a growing file or
standard input), one line per closed step."""

from __future__ import annotations

import argparse
import sys
from contextlib import ExitStack

from footnav.cli._common import EXIT_INTERNAL, EXIT_OK, EXIT_USAGE, _claim_figure, _format_table, clip_text
from footnav.core.errors import FootnavError, InvalidInputError


def _scales() -> dict[str, dict[str, float]]:
    """The offline reader's units (footnav.core.types.units), by column group; imported when a
    command runs, so that ``footnav --help`` does not import numba."""
    from footnav.core.types.units import _ACC_SCALE, _GYR_SCALE, _T_SCALE

    return {"t": _T_SCALE, "acc": _ACC_SCALE, "gyr": _GYR_SCALE}


#: Columns of a followed CSV (footnav CSV: ``footnav simulate`` writes it); ``foot`` optional.
FOLLOW_COLUMNS = ("t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")


class _FollowedCsv:
    """Lines of a footnav CSV as they arrive: units from its ``# units:`` line (or the command
    line), columns from its header (or, without one, ``t, acc_x .. gyr_z`` with an optional
    ``foot`` column first: ``left,0.01,...``), rows split by that column (left / right).

    The units and their conversion are the offline reader's (``# units: t us`` included);
    :meth:`rows` stops at the first bad line and returns the rows before it with the error."""

    def __init__(self, name: str, units: dict) -> None:
        self.name = name
        self.units = {k: v for k, v in units.items() if v}  # the command line's, which win over the file's
        self.file_units: dict = {}
        self.columns: list[str] | None = None
        self.line_no = 0

    @property
    def units_in(self) -> dict[str, str]:
        """The units the rows are converted from (the command line's, else the file's, else SI)."""
        return {
            k: self.units.get(k) or self.file_units.get(k) or si
            for k, si in (("t", "s"), ("acc", "m/s^2"), ("gyr", "rad/s"))
        }

    def _error(self, message: str) -> InvalidInputError:
        return InvalidInputError(message, path=self.name, line=self.line_no)

    def rows(self, lines: list[str]) -> tuple[dict, FootnavError | None]:
        """``({foot: (t, acc, gyr)}, error)``: the complete lines' rows in SI units up to the
        first bad line, and that line's error (None when every line is good)."""
        out: dict = {}
        error = None
        for line in lines:
            try:
                self._row(line, out)
            except FootnavError as exc:
                error = exc
                break
        return self._convert(out), error

    def _row(self, line: str, out: dict) -> None:
        self.line_no += 1
        line = line.strip()
        if not line:
            return
        if line.startswith("#"):
            if line[1:].strip().startswith("units:"):
                from footnav.data.io.footnav_csv import _parse_units_comment

                if self.columns is not None:  # the rows read so far were converted with other units
                    raise self._error("a '# units:' line after the header or the rows; it must come before them")

                self.file_units.update(_parse_units_comment(clip_text(line, 400), self.name, self.line_no))
                for key, unit in self.units_in.items():
                    if unit not in _scales()[key]:
                        raise self._error(
                            f"unknown {key} unit {clip_text(unit)!r}; expected one of {sorted(_scales()[key])}"
                        )
            return
        cells = [c.strip() for c in line.split(",")]
        if self.columns is None:
            if cells[0] in ("left", "right") or (_number(cells[0]) and _number(cells[-1])):  # no header
                if len(cells) not in (7, 8):
                    raise self._error(
                        f"{len(cells)} values; expected t,acc_x..gyr_z (7) or foot,t,acc_x..gyr_z (8), or a header"
                    )
                self.columns = list(FOLLOW_COLUMNS) if len(cells) == 7 else ["foot", *FOLLOW_COLUMNS]
            else:
                self.columns = cells
                missing = [c for c in FOLLOW_COLUMNS if c not in cells]
                if missing:
                    raise self._error(f"no column(s) {', '.join(missing)} in the header {clip_text(line)!r}")
                return
        if len(cells) != len(self.columns):
            raise self._error(
                f"{len(cells)} values, expected {len(self.columns)} ({','.join(self.columns)}): {clip_text(line)!r}"
            )
        row = dict(zip(self.columns, cells))
        foot = row.get("foot", "left")
        if foot not in ("left", "right"):
            raise self._error(f"foot {clip_text(foot)!r}; expected left or right")
        values = []
        for c in FOLLOW_COLUMNS:
            if not _number(row[c]):
                raise self._error(f"column {c}: {clip_text(row[c])!r} is not a number")
            values.append(float(row[c]))
        out.setdefault(foot, []).append(values)

    def _convert(self, out: dict) -> dict:
        import numpy as np

        unit = self.units_in
        scale = {k: _scales()[k][unit[k]] for k in ("t", "acc", "gyr")}
        result = {}
        for foot, values in out.items():
            a = np.array(values)
            result[foot] = (a[:, 0] * scale["t"], a[:, 1:4] * scale["acc"], a[:, 4:7] * scale["gyr"])
        return result


def _number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _split_lines(data: bytes) -> tuple[list[str], bytes]:
    """The complete lines of ``data`` (decoded: a line that is not UTF-8 is a bad row, its
    neighbours stay good) and the bytes of the line not yet complete; a line longer than
    ``MAX_LINE_BYTES`` is returned as it is (a bad row, not a wait)."""
    lines = data.split(b"\n")
    partial = lines.pop()
    if len(partial) > MAX_LINE_BYTES:
        lines.append(partial)
        partial = b""
    return [line.decode("utf-8", errors="replace") for line in lines], partial


def _follow_sources(args: argparse.Namespace) -> list:
    """(foot or None, name, reader) per input: a reader returns the complete new lines, or None
    at the end of standard input."""
    import os
    import queue
    import threading

    sources = []
    for foot, path in (("left", args.left), ("right", args.right)):
        if path is None:
            continue
        if path == "-":
            lines: queue.Queue = queue.Queue()

            def pump(q=lines) -> None:
                # the file descriptor, not sys.stdin: a thread blocked in the buffered reader holds
                # its lock, and the interpreter aborts at exit; lines split and decoded here as a
                # file's are (_split_lines)
                fd, partial = sys.stdin.fileno(), b""
                while block := os.read(fd, 1 << 16):
                    got, partial = _split_lines(partial + block)
                    for line in got:
                        q.put(line)
                if partial:
                    q.put(partial.decode("utf-8", errors="replace"))
                q.put(None)

            threading.Thread(target=pump, daemon=True).start()

            def read_stdin(q=lines):
                got = []
                while True:
                    try:
                        line = q.get_nowait()
                    except queue.Empty:
                        return got
                    if line is None:
                        return got + [None]
                    got.append(line)

            sources.append((None if args.right is None else foot, "standard input", read_stdin))
            continue
        state = {"handle": None, "partial": b""}

        def read_file(path=path, state=state):
            if state["handle"] is None:
                if not os.path.exists(path):
                    return []
                state["handle"] = open(path, "rb")  # noqa: SIM115 - read as it grows, closed at exit
            lines, state["partial"] = _split_lines(state["partial"] + state["handle"].read())
            return lines

        sources.append((foot, path, read_file))
    return sources


def _say(text: str, stop: dict) -> None:
    """Print a line of the live output; when standard output has gone (``follow | head``), end
    the stream as a stop signal would (the result folder is still written)."""
    try:
        print(text, flush=True)
    except BrokenPipeError:
        import os

        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - the rest of the run's prints go nowhere
        stop["signal"] = stop.get("signal") or "standard output closed"


def _step_line(step) -> str:
    import math

    heading = "" if math.isnan(step.heading_rad) else f"{math.degrees(step.heading_rad):8.1f}"
    x, y, z = step.position
    return f"{step.t:10.3f}  {step.foot:<5}  {x:9.3f} {y:9.3f} {z:7.3f}  {step.stride_length_m:8.3f}  {heading:>8}" + (
        "  (late)" if step.late else ""
    )


class _LivePlot:
    """The figure of ``follow --plot``: the closed steps' footprints, redrawn at most every
    ``every_s`` seconds (wall time) while steps arrive and once at the end. Each drawing replaces
    the file atomically (the claim's staged write), so a viewer never reads half a PNG."""

    def __init__(self, claim, every_s: float, pipeline) -> None:
        self.claim = claim
        self.every_s = every_s
        self.title = "footnav follow: " + " + ".join(c.get("name", k) for k, c in pipeline.config().items())
        self.steps: list = []
        self.drawn = 0  # steps in the figure on disk
        self.last = -float("inf")

    def add(self, step) -> None:
        if self.claim is not None:
            self.steps.append(step)

    def draw(self, final: bool = False) -> None:
        import time

        if self.claim is None or (len(self.steps) == self.drawn and not final):
            return
        now = time.monotonic()
        if not final and now - self.last < self.every_s:
            return
        from footnav.analysis.plot import plot_steps

        with self.claim.staged() as tmp:
            plot_steps(self.steps, tmp, title=self.title)
        self.drawn, self.last = len(self.steps), now


#: A line of a followed file longer than this (bytes) without its newline is a bad row (a 7-column
#: row is under 200 bytes): the reader does not wait for, nor hold, an endless line.
MAX_LINE_BYTES = 1 << 20

#: Signals that end ``follow`` as Ctrl-C does: the result of what was read is written (SIGTERM:
#: ``systemctl stop``, ``docker stop``, ``timeout``; SIGHUP: the terminal closed).
_STOP_SIGNALS = ("SIGINT", "SIGTERM", "SIGHUP")


# complexity: the follow loop and its endings (signals, bad rows, units, end of input) in one
# place, each tested in tests/faults/test_live_stream.py
def cmd_follow(args: argparse.Namespace) -> int:  # noqa: C901
    """Follow a walk live; see the module docstring and ``footnav follow --help``.

    However the stream ends, the result folder holds everything that became final: at the end
    of input or after ``--idle-s`` (complete, exit 0); at SIGINT, SIGTERM or SIGHUP (incomplete,
    exit 0: the user stopped it); at a bad row, a refused chunk or a failing component (incomplete,
    exit 2 for bad input, 1 for a component's failure). A bad row ends the stream rather than being
    skipped: the rows after it cannot be trusted more than the offline reader trusts the rest of a
    file with that row. ``summary.json`` and the result's ``meta`` say ``complete`` and ``ended_by``.
    """
    import signal
    import time

    from footnav.data.output import claim_output
    from footnav.data.results import write_results
    from footnav.pipeline.factory import load_pipeline, make_pipeline

    if args.pipeline:
        if any(getattr(args, k) for k in ("detector", "estimator", "fusion")):
            raise FootnavError("give either --pipeline or --detector/--estimator/--fusion, not both")
        pipeline = load_pipeline(args.pipeline)
    else:  # the offline defaults: adaptive detector, EKF (step-wise live, the whole walk at the end)
        pipeline = make_pipeline(args.detector or "adaptive", args.estimator or "ekf", args.fusion or "independent")
    if args.left == "-" and args.right == "-":
        raise FootnavError(
            "only one of --left / --right can be standard input; give both feet there with a 'foot' column"
        )
    two_feet = args.right is not None or args.feet == 2
    units = {"t": args.t_unit, "acc": args.acc_unit, "gyr": args.gyr_unit}
    raw_sources = _follow_sources(args)
    parsers = {name: _FollowedCsv(name, units) for _, name, _ in raw_sources}
    feet = ("left", "right") if two_feet else ("left",)
    # each foot's source: its file, or standard input for the feet read there
    named = {foot: name for foot, name, _ in raw_sources if foot is not None}
    stdin = next((name for foot, name, _ in raw_sources if foot is None), None)
    # standard input with both feet: each foot's samples named by their foot too
    input_meta = {
        foot: {
            "source": named[foot] if foot in named else stdin + (f" ({foot} foot)" if two_feet else ""),
            "units_in": parsers[named.get(foot, stdin)].units_in,
        }
        for foot in feet
        if named.get(foot, stdin) is not None
    }
    stream = pipeline.online(feet=2 if two_feet else 1, max_wait_s=args.max_wait_s, input_meta=input_meta)
    inputs = [p for p in (args.left, args.right, args.pipeline) if p and p != "-"]
    with ExitStack() as claims:
        out_claim = claims.enter_context(claim_output(args.out, force=args.force, inputs=inputs, what="output folder"))
        plot_claim = _claim_figure(claims, args.plot, args.force, inputs)
        live = _LivePlot(plot_claim, args.plot_every_s, pipeline)
        view = _start_view(args, pipeline)
        if view is not None:
            claims.callback(view.close)
        sources = [(foot, name, read, parsers[name]) for foot, name, read in raw_sources]
        stop: dict = {"signal": None}

        def on_signal(signum, frame) -> None:  # end after the current push, never inside it
            stop["signal"] = stop["signal"] or signal.Signals(signum).name

        previous = {}
        for name in _STOP_SIGNALS:
            if hasattr(signal, name):
                try:
                    previous[name] = signal.signal(getattr(signal, name), on_signal)
                except ValueError:  # not the main thread: Ctrl-C raises KeyboardInterrupt as usual
                    break
        ended_by, code = "end of input", EXIT_OK
        try:
            # the header after the handlers: a caller that sees it may signal (tests do)
            _say(
                f"{'t_s':>10}  {'foot':<5}  {'x_m':>9} {'y_m':>9} {'z_m':>7}  {'stride_m':>8}  {'heading_deg':>8}", stop
            )
            last_data = time.monotonic()
            ended = set()
            while len(ended) < len(sources) and stop["signal"] is None:
                chunks: dict = {}
                bad = None
                for i, (foot, _name, read, parser) in enumerate(sources):
                    if i in ended:
                        continue
                    lines = read()
                    if lines and lines[-1] is None:
                        ended.add(i)
                        lines = lines[:-1]
                    rows, error = parser.rows(lines)
                    for key, chunk in rows.items():
                        chunks[foot or key] = chunk  # a file per foot: every row is that foot's
                        stream.describe_input(foot or key, units_in=parser.units_in)  # a '# units:' line read now
                    bad = bad or error
                if chunks:  # both feet in one push: neither waits for the other's rows read now
                    update, refused = _push_good_rows(stream, chunks)
                    bad = refused or bad
                    for step in update.steps:
                        _say(_step_line(step), stop)
                        live.add(step)
                    live.draw()
                    if view is not None:
                        view.add(update.steps)
                        view.flush()
                if bad is not None:
                    raise bad
                if chunks:
                    last_data = time.monotonic()
                elif time.monotonic() - last_data > args.idle_s:
                    ended_by = f"idle: no new row for {args.idle_s:g} s"
                    break
                else:
                    time.sleep(args.poll_s)
            if stop["signal"] is not None:
                ended_by = f"interrupted ({stop['signal']})"
        except KeyboardInterrupt:
            ended_by = "interrupted (SIGINT)"
        except FootnavError as exc:
            ended_by, code = f"bad input: {exc}", EXIT_USAGE
        except Exception as exc:  # noqa: BLE001 - a component's failure: what was final is still written
            ended_by, code = f"failure: {type(exc).__name__}: {exc}", EXIT_INTERNAL
        finally:
            for name, handler in previous.items():
                signal.signal(getattr(signal, name), handler)
        result, close_error = _close(stream)
        stopped_before_data = ended_by.startswith("interrupted") and not any(stream.stats()["received"].values())
        if stopped_before_data:
            ended_by += "; no row had been read"
        if close_error is not None and code == EXIT_OK and not stopped_before_data:
            code = EXIT_USAGE if isinstance(close_error, FootnavError) else EXIT_INTERNAL
            ended_by = f"{ended_by}; at the end: {type(close_error).__name__}: {close_error}"
        for step in stream.last_update.steps:
            _say(_step_line(step), stop)
            live.add(step)
        live.draw(final=True)
        if view is not None:
            view.add(stream.last_update.steps)
            view.flush(force=True)
        complete = code == EXIT_OK and not ended_by.startswith("interrupted") and close_error is None
        summary: dict = {"complete": complete, "ended_by": ended_by}
        if result is not None:
            result.meta["complete"], result.meta["ended_by"] = complete, ended_by
            summary |= {"left_path_length_m": result.left.path_length_m, "left_stances": result.stance_left.n_stances}
            if result.right is not None:
                summary["right_path_length_m"] = result.right.path_length_m
                summary["right_stances"] = result.stance_right.n_stances
            out = write_results(
                result, out_claim, force=args.force, summary=summary, pipeline_toml=pipeline.to_toml(), html=True
            )
        else:
            out = _write_nothing_final(out_claim, summary, stream, pipeline.to_toml())
    print(_format_table(("quantity", "value"), [(k, clip_text(str(v), 200)) for k, v in summary.items()]))
    if code != EXIT_OK:
        print(f"footnav follow: error: {clip_text(ended_by, 600)}", file=sys.stderr)
    print(
        ("" if complete else clip_text(ended_by, 200) + ": ")
        + f"results written to {out}"
        + ("" if complete else " (incomplete)")
    )
    return code


def _start_view(args: argparse.Namespace, pipeline):
    """The live view of ``--view`` (:class:`footnav.report.live.LiveView`), or None; says when
    there is no display to draw on."""
    if not getattr(args, "view", False):
        return None
    from footnav.cli._common import _require_matplotlib

    _require_matplotlib("--view")
    from footnav.report.live import LiveView, has_display

    if not has_display():
        print(
            "footnav follow: no display: --view draws off-screen; open report.html in the output folder at the end",
            file=sys.stderr,
        )
    title = "footnav follow: " + " + ".join(c.get("name", k) for k, c in pipeline.config().items())
    return LiveView(title, args.view_every_s)


def _push_good_rows(stream, chunks: dict):
    """Push the rows up to the first the stream refuses: ``(update, error)``, the error None
    when every row was taken. A refused chunk names its foot and first bad sample, so the rows
    before it are pushed again without it (nothing read before a bad row is lost)."""
    from footnav.core.errors import InvalidInputError

    first = None
    while True:
        try:
            return stream.push(**chunks), first
        except InvalidInputError as exc:
            foot, index = getattr(exc, "foot", None), exc.index
            if foot is None or index is None:  # a finding about the whole chunk: nothing to keep
                raise
            first = first or exc
            keep = index - stream.stats()["received"][foot]
            if keep >= len(chunks[foot][0]):  # not a sample of this chunk: nothing to cut it at
                raise first from None
            if keep > 0:
                chunks = {**chunks, foot: tuple(x[:keep] for x in chunks[foot])}
            else:  # a sample held back from an earlier chunk, or this chunk's first
                chunks = {k: v for k, v in chunks.items() if k != foot}
            if not chunks:
                raise first from None


def _close(stream):
    """``(result, error)`` of closing the stream: the whole result, or what the error carries
    (each foot's own estimate up to where it was final) and the error."""
    try:
        return stream.close(), None
    except Exception as exc:  # noqa: BLE001 - written as far as it got, and said
        return getattr(exc, "partial", None), exc


def _write_nothing_final(claim, summary: dict, stream, pipeline_toml: str):
    """The result folder of a stream that ended before any sample was final: ``summary.json``
    (why, and the samples read), ``pipeline.toml`` and a ``report.html`` saying so."""
    import json

    from footnav.data.results import atomic_folder, versions

    doc = {
        "summary": summary,
        "provenance": {
            "warnings": list(stream.warnings),
            "online": stream.stats(),
            "complete": False,
            "ended_by": summary["ended_by"],
        },
        "versions": versions(),
    }
    from footnav.report import REPORT_NAME
    from footnav.report.result import nothing_final_html

    with atomic_folder(claim) as tmp:
        (tmp / "summary.json").write_text(json.dumps(doc, indent=2, default=str) + "\n", encoding="utf-8")
        (tmp / "pipeline.toml").write_text(pipeline_toml, encoding="utf-8")
        page = nothing_final_html(summary, [str(w) for w in stream.warnings], pipeline_toml)
        (tmp / REPORT_NAME).write_text(page, encoding="utf-8")
    return claim.target
