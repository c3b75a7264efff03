"""``footnav follow``: a pipeline run online on footnav CSV rows as they arrive (a growing file or
standard input), one line per closed step."""

from __future__ import annotations

import argparse
import sys
from contextlib import ExitStack

from footnav.cli._common import EXIT_OK, _claim_figure, _format_table
from footnav.errors import FootnavError

#: Columns of a followed CSV (footnav CSV: ``footnav simulate`` writes it); ``foot`` optional.
FOLLOW_COLUMNS = ("t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z")


class _FollowedCsv:
    """Lines of a footnav CSV as they arrive: units from its ``# units:`` line (or the command
    line), columns from its header (or ``t, acc_x .. gyr_z``), rows split by an optional ``foot``
    column (left / right)."""

    def __init__(self, name: str, units: dict) -> None:
        self.name = name
        self.units = dict(units)  # the command line's, which win over the file's
        self.file_units: dict = {}
        self.columns: list[str] | None = None
        self.line_no = 0

    def rows(self, lines: list[str]) -> dict:
        """``{foot: (t, acc, gyr)}`` of the complete lines, in SI units."""
        import numpy as np

        from footnav.types import GRAVITY_MPS2

        out: dict = {}
        for line in lines:
            self.line_no += 1
            line = line.strip()
            if not line:
                continue
            if line.startswith("#"):
                if line[1:].strip().startswith("units:"):
                    for part in line.split(":", 1)[1].split(","):
                        key, _, unit = part.strip().partition(" ")
                        self.file_units[key.strip()] = unit.strip()
                continue
            cells = [c.strip() for c in line.split(",")]
            if self.columns is None:
                try:
                    float(cells[-1])
                    float(cells[0])
                except ValueError:  # a header
                    self.columns = cells
                    missing = [c for c in FOLLOW_COLUMNS if c not in cells]
                    if missing:
                        raise FootnavError(f"{self.name}, line {self.line_no}: no column(s) {', '.join(missing)} in the header")
                    continue
                self.columns = list(FOLLOW_COLUMNS) if len(cells) == 7 else ["foot", *FOLLOW_COLUMNS]
            if len(cells) != len(self.columns):
                raise FootnavError(f"{self.name}, line {self.line_no}: {len(cells)} values, expected {len(self.columns)} ({','.join(self.columns)})")
            row = dict(zip(self.columns, cells))
            foot = row.get("foot", "left")
            if foot not in ("left", "right"):
                raise FootnavError(f"{self.name}, line {self.line_no}: foot {foot!r}; expected left or right")
            try:
                values = [float(row[c]) for c in FOLLOW_COLUMNS]
            except ValueError as exc:
                raise FootnavError(f"{self.name}, line {self.line_no}: {exc}") from None
            out.setdefault(foot, []).append(values)
        unit = {k: self.units.get(k) or self.file_units.get(k) for k in ("t", "acc", "gyr")}
        scale_t = {None: 1.0, "s": 1.0, "ms": 1e-3}[unit["t"]]
        scale_acc = {None: 1.0, "m/s^2": 1.0, "g": GRAVITY_MPS2}[unit["acc"]]
        scale_gyr = {None: 1.0, "rad/s": 1.0, "deg/s": np.pi / 180.0}[unit["gyr"]]
        result = {}
        for foot, values in out.items():
            a = np.array(values)
            result[foot] = (a[:, 0] * scale_t, a[:, 1:4] * scale_acc, a[:, 4:7] * scale_gyr)
        return result


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
                for line in sys.stdin:
                    q.put(line)
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
        state = {"handle": None, "partial": ""}

        def read_file(path=path, state=state):
            if state["handle"] is None:
                if not os.path.exists(path):
                    return []
                state["handle"] = open(path, encoding="utf-8", newline="")  # noqa: SIM115 - read as it grows, closed at exit
            text = state["partial"] + state["handle"].read()
            lines = text.split("\n")
            state["partial"] = lines.pop()
            return lines

        sources.append((foot, path, read_file))
    return sources


def _step_line(step) -> str:
    import math

    heading = "" if math.isnan(step.heading_rad) else f"{math.degrees(step.heading_rad):8.1f}"
    x, y, z = step.position
    return (f"{step.t:10.3f}  {step.foot:<5}  {x:9.3f} {y:9.3f} {z:7.3f}  {step.stride_length_m:8.3f}  {heading:>8}"
            + ("  (late)" if step.late else ""))


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


def cmd_follow(args: argparse.Namespace) -> int:
    import signal
    import time

    from footnav.data.output import claim_output
    from footnav.pipeline.factory import load_pipeline, make_pipeline
    from footnav.data.results import write_results

    if args.pipeline:
        if any(getattr(args, k) for k in ("detector", "estimator", "fusion")):
            raise FootnavError("give either --pipeline or --detector/--estimator/--fusion, not both")
        pipeline = load_pipeline(args.pipeline)
    else:  # online defaults: a windowed detector, the EKF smoothing each step at its end
        estimator = args.estimator or "ekf"
        pipeline = make_pipeline(args.detector or "threshold", estimator, args.fusion or "independent",
                                 estimator_params={"smoother": "step"} if estimator == "ekf" else None)
    if args.left == "-" and args.right == "-":
        raise FootnavError("only one of --left / --right can be standard input; give both feet there with a 'foot' column")
    two_feet = args.right is not None or args.feet == 2
    stream = pipeline.online(feet=2 if two_feet else 1, max_wait_s=args.max_wait_s)
    inputs = [p for p in (args.left, args.right, args.pipeline) if p and p != "-"]
    units = {"t": args.t_unit, "acc": args.acc_unit, "gyr": args.gyr_unit}
    with ExitStack() as claims:
        out_claim = claims.enter_context(claim_output(args.out, force=args.force, inputs=inputs, what="output folder"))
        plot_claim = _claim_figure(claims, args.plot, args.force, inputs)
        live = _LivePlot(plot_claim, args.plot_every_s, pipeline)
        sources = [(foot, name, read, _FollowedCsv(name, units)) for foot, name, read in _follow_sources(args)]
        print(f"{'t_s':>10}  {'foot':<5}  {'x_m':>9} {'y_m':>9} {'z_m':>7}  {'stride_m':>8}  {'heading_deg':>8}", flush=True)
        last_data = time.monotonic()
        stop = {"interrupted": False}

        def on_sigint(signum, frame) -> None:  # Ctrl-C: end after the current push, never inside it
            stop["interrupted"] = True

        try:
            previous = signal.signal(signal.SIGINT, on_sigint)
        except ValueError:  # not the main thread: Ctrl-C raises KeyboardInterrupt as usual
            previous = None
        try:
            ended = set()
            while len(ended) < len(sources) and not stop["interrupted"]:
                chunks: dict = {}
                for i, (foot, name, read, parser) in enumerate(sources):
                    if i in ended:
                        continue
                    lines = read()
                    if lines and lines[-1] is None:
                        ended.add(i)
                        lines = lines[:-1]
                    for key, rows in parser.rows(lines).items():
                        chunks[foot or key] = rows  # a file per foot: every row is that foot's
                if chunks:  # both feet in one push: neither waits for the other's rows read now
                    for step in stream.push(**chunks).steps:
                        print(_step_line(step), flush=True)
                        live.add(step)
                    live.draw()
                if chunks:
                    last_data = time.monotonic()
                elif time.monotonic() - last_data > args.idle_s:
                    break
                else:
                    time.sleep(args.poll_s)
        except KeyboardInterrupt:
            stop["interrupted"] = True
        finally:
            if previous is not None:
                signal.signal(signal.SIGINT, previous)
        interrupted = stop["interrupted"]
        result = stream.close()
        for step in stream.last_update.steps:
            print(_step_line(step), flush=True)
            live.add(step)
        live.draw(final=True)
        for foot in ("left", "right"):
            path = getattr(args, foot)
            if foot in result.meta["input"] and path not in (None, "-"):
                result.meta["input"][foot]["source"] = path
        summary = {"left_path_length_m": result.left.path_length_m, "left_stances": result.stance_left.n_stances}
        if result.right is not None:
            summary["right_path_length_m"] = result.right.path_length_m
            summary["right_stances"] = result.stance_right.n_stances
        out = write_results(result, out_claim, force=args.force, summary=summary, pipeline_toml=pipeline.to_toml())
    print(_format_table(("quantity", "value"), list(summary.items())))
    print(("interrupted: " if interrupted else "") + f"results written to {out}")
    return EXIT_OK
