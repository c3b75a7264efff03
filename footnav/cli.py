"""The ``footnav`` command.

Exit codes: 0 success, 2 bad usage or bad input (one-line message, no traceback), 1 internal error.
"""

from __future__ import annotations

import argparse
import logging
import sys
import textwrap
import warnings
from contextlib import ExitStack, nullcontext
from pathlib import Path as FilePath
from typing import Sequence

from footnav.core.errors import FootnavError, FootnavWarning, PluginError

EXIT_OK, EXIT_INTERNAL, EXIT_USAGE = 0, 1, 2
#: First line of every table footnav writes as CSV (EvaluationReport.to_csv): how --force knows one.
REPORT_CSV_HEADER = "recording,pipeline,foot,name,value,unit"

EPILOG_RUN = """examples:
  footnav run --left L.csv --right R.csv --acc-unit g --gyr-unit deg/s --out results/walk1
  footnav run --left data/gaitmap_example --out results/gaitmap
  footnav run --left walk.mat --out results/pyshoe
  footnav run --left L.csv --pipeline pipeline.toml --out results/walk1 --force
  footnav run --left L.csv --right R.csv --fusion step-vector --out results/walk1 --plot walk1.png
"""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str):  # argparse exits 2 with usage; keep it, but one line of message
        self.print_usage(sys.stderr)
        self.exit(EXIT_USAGE, f"footnav: error: {message}\n")


def _seed(text: str) -> int:
    """argparse type: a seed is an integer >= 0 (numpy's generators refuse negative ones)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"{text!r} is negative; a seed is an integer >= 0")
    return value


def _positive(text: str) -> float:
    """argparse type: a finite number > 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (value > 0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number > 0")
    return value


def _warning_printer(verbose: bool):
    """``warnings.showwarning`` for the command line: one line per warning, in the user's words
    (footnav's own without their class, others with it), the source line only with ``-v``."""

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        kind = "" if issubclass(category, FootnavWarning) else f"{category.__name__}: "
        where = f" ({filename}:{lineno})" if verbose else ""
        print(f"footnav: warning: {kind}{message}{where}", file=sys.stderr if file is None else file)

    return show


def _compile_notice():
    """A numba event listener that says on stderr when numba compiles footnav's kernels (the
    first run after installing, or after the cache was cleared: several seconds of silence
    otherwise) and, with :meth:`report`, how long it took. numba is imported here, not when the
    CLI starts, so ``footnav --help`` stays quick."""
    import time

    from numba.core import event

    class CompileNotice(event.Listener):
        def __init__(self) -> None:
            self.depth, self.started, self.seconds, self.said = 0, 0.0, 0.0, False

        def on_start(self, ev) -> None:
            if self.depth == 0:  # nested events are callees compiled for their caller
                self.started = time.perf_counter()
                if not self.said:
                    self.said = True
                    print("footnav: compiling the numerical kernels (once: they are cached for the next runs) ...",
                          file=sys.stderr, flush=True)
            self.depth += 1

        def on_end(self, ev) -> None:
            self.depth -= 1
            if self.depth == 0:
                self.seconds += time.perf_counter() - self.started

        def listening(self):
            return event.install_listener("numba:compile", self)

        def report(self) -> None:
            if self.said:
                print(f"footnav: compiled in {self.seconds:.1f} s", file=sys.stderr)

    return CompileNotice()


def _segments(text: str) -> list[tuple[float, float]]:
    """argparse type: ``10:90,5:-90`` -> [(10.0, 90.0), (5.0, -90.0)] (m, deg);
    ``stairs:12:0.17[:0.3]`` -> ("stairs", 12, 0.17[, 0.3]) (count, rise m, tread m)."""
    try:
        pairs = [
            ("stairs", int(item.split(":")[1]), *(float(x) for x in item.split(":")[2:]))
            if item.strip().startswith("stairs:")
            else tuple(float(x) for x in item.split(":"))
            for item in text.split(",")
            if item.strip()
        ]
    except (ValueError, IndexError):
        raise argparse.ArgumentTypeError(f"{text!r}: expected DIST:DEG pairs separated by commas, e.g. 10:90,5:-90") from None
    if not pairs or any(len(p) != 2 and p[0] != "stairs" for p in pairs):
        raise argparse.ArgumentTypeError(f"{text!r}: expected DIST:DEG pairs separated by commas, e.g. 10:90,5:-90")
    return pairs  # type: ignore[return-value]


def _option(text: str) -> tuple[str, object]:
    """argparse type: ``NAME=VALUE`` with VALUE a number, true/false, or text."""
    name, sep, raw = text.partition("=")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(f"{text!r}: expected NAME=VALUE")
    low = raw.strip().lower()
    if low in ("true", "false"):
        return name.strip(), low == "true"
    for kind in (int, float):
        try:
            return name.strip(), kind(raw)
        except ValueError:
            pass
    return name.strip(), raw.strip()


def _os_message(exc: OSError) -> str:
    """One line for an error of the file system or the network: what, on which file."""
    where = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
    return f"{exc.strerror or exc}{':' if where else ''}{where}"


def _format_table(header: Sequence[str], rows: Sequence[Sequence[object]], width: int | None = None) -> str:
    """A plain-text table; with ``width``, the last column wraps so that no line is wider."""
    cells = [[str(h) for h in header]] + [[_fmt(c) for c in r] for r in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(header))]
    offset = sum(widths[:-1]) + 2 * (len(header) - 1)
    room = None if width is None else max(20, width - offset)
    if room is not None:
        widths[-1] = min(widths[-1], room)
    lines = []
    for k, row in enumerate(cells):
        last = textwrap.wrap(row[-1], room) if room is not None and len(row[-1]) > room else [row[-1]]
        lines.append("  ".join(c.ljust(w) for c, w in zip(row[:-1] + [last[0] if last else ""], widths)).rstrip())
        lines += [(" " * offset + more).rstrip() for more in last[1:]]
        if k == 0:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.3f}"
    return str(value)


# -- commands ---------------------------------------------------------------------------------


#: Widest line ``footnav plugins`` prints.
PLUGINS_WIDTH = 120


def _summary_line(cls: type) -> str:
    """A class's docstring summary (its first paragraph, on one line)."""
    import inspect

    return " ".join((inspect.getdoc(cls) or "").strip().split("\n\n")[0].split()).rstrip(".")


def cmd_plugins(args: argparse.Namespace) -> int:
    from footnav.plugins.manager import get_registry

    reg = get_registry()
    if args.name:
        entries = [e for e in reg if e.name == args.name]
        if not entries:
            names = ", ".join(sorted({e.name for e in reg}))
            raise FootnavError(f"no component named {args.name!r}; registered: {names}")
        for e in entries:
            needs = [n for n, f in (("two feet", e.cls.needs_two_feet), ("magnetometer", e.cls.needs_magnetometer)) if f]
            print(f"{e.name} ({e.kind}, from {e.origin}){': needs ' + ', '.join(needs) if needs else ''}")
            print(textwrap.fill(_summary_line(e.cls), width=PLUGINS_WIDTH, initial_indent="  ", subsequent_indent="  "))
            rows = [(p.name, repr(p.default), p.unit or "-", p.description or "-") for p in e.cls.parameter_info()]
            if rows:
                print()
                print(_format_table(("parameter", "default", "unit", "description"), rows, width=PLUGINS_WIDTH))
        return EXIT_OK
    rows = [(e.kind, e.name, e.origin, _summary_line(e.cls)) for e in reg]
    print(_format_table(("kind", "name", "origin", "description"), rows, width=PLUGINS_WIDTH))
    print("footnav plugins NAME: one component's parameters")
    for name, origin, err in reg.failed:
        print(f"failed plugin: {name} ({origin}): {err}", file=sys.stderr)
    return EXIT_OK


def _pipeline_from_args(args: argparse.Namespace):
    from footnav.core.pipeline import load_pipeline, make_pipeline

    sync = getattr(args, "sync", None)
    if args.pipeline:
        if any(getattr(args, k) for k in ("detector", "estimator", "fusion")):
            raise FootnavError("give either --pipeline or --detector/--estimator/--fusion, not both")
        pipeline = load_pipeline(args.pipeline)
        if sync is not None:
            if pipeline.sync is not None:
                raise FootnavError(f"{args.pipeline} has a [sync] table already; give it or --sync, not both")
            return make_pipeline(pipeline.detector, pipeline.estimator, pipeline.fusion, sync=sync)
        return pipeline
    return make_pipeline(args.detector or "adaptive", args.estimator or "ekf", args.fusion or "independent", sync=sync)


#: CLI flag -> reader option (footnav.core.io.load.reader_options says which reader takes which).
READER_FLAGS = {"format": "--format", "acc_unit": "--acc-unit", "gyr_unit": "--gyr-unit", "t_unit": "--t-unit",
                "rate_hz": "--rate-hz", "drop_duplicates": "--drop-duplicates"}


def _read_recording(path: str, args: argparse.Namespace):
    """Read ``path`` in any format footnav reads, with the reader options given on the command
    line; an option the file's reader does not take is an error naming both."""
    from footnav.core.io.load import guess_format, load, reader_options

    given = {k: getattr(args, k) for k in READER_FLAGS if k != "format" and getattr(args, k, None) not in (None, False)}
    fmt = args.format or guess_format(path)[0]
    accepted = reader_options(fmt)
    refused = [READER_FLAGS[k] for k in given if k not in accepted]
    if refused:
        takes = ", ".join(READER_FLAGS[k] for k in READER_FLAGS if k in accepted) or "none"
        raise FootnavError(
            f"{path}: {' and '.join(refused)} {'does' if len(refused) == 1 else 'do'} not apply to {fmt} files (the "
            f"format fixes them); options this format takes: {takes}"
        )
    return load(path, format=args.format, **given)


def _run_inputs(args: argparse.Namespace):
    """The left and right feet from --left / --right: one file per foot, or one two-foot
    recording (gaitmap, IPOL, azure_fgo ...) given as --left."""
    rec = _read_recording(args.left, args)
    if args.right is None:
        if rec.right is not None:
            print(f"footnav: {args.left} holds both feet ({rec.meta.get('format')}): running both", file=sys.stderr)
        return rec.left, rec.right
    if rec.right is not None:
        raise FootnavError(f"{args.left} holds both feet already; give it alone, without --right")
    other = _read_recording(args.right, args)
    if other.right is not None:
        raise FootnavError(f"{args.right} holds both feet; give it alone as --left")
    return rec.left, other.left


def cmd_run(args: argparse.Namespace) -> int:
    from footnav.core.output import claim_output
    from footnav.core.results import write_results

    pipeline = _pipeline_from_args(args)
    inputs = [p for p in (args.left, args.right, args.pipeline) if p]
    with ExitStack() as claims:
        # every output is claimed before any work, and appears only when all of it succeeded
        out_claim = claims.enter_context(claim_output(args.out, force=args.force, inputs=inputs, what="output folder"))
        plot_claim = _claim_figure(claims, args.plot, args.force, inputs)
        left, right = _run_inputs(args)
        result = pipeline.run(left, right)
        summary = {
            "left_path_length_m": result.left.path_length_m,
            "left_stances": result.stance_left.n_stances,
        }
        if result.right is not None:
            summary["right_path_length_m"] = result.right.path_length_m
            summary["right_stances"] = result.stance_right.n_stances
        with plot_claim.staged() if plot_claim else nullcontext() as figure:
            if figure is not None:
                _plot_trajectories(result, None, figure)
            out = write_results(result, out_claim, force=args.force, summary=summary, pipeline_toml=pipeline.to_toml())
    print(_format_table(("quantity", "value"), list(summary.items())))
    print(f"results written to {out}")
    if plot_claim:
        print(f"figure: {args.plot}")
    return EXIT_OK


EPILOG_FOLLOW = """examples:
  footnav follow --left L.csv --right R.csv --out results/live      (files another program appends to)
  sensor-reader | footnav follow --left - --out results/live       (CSV lines on standard input)
  footnav follow --left walk.csv --detector glrt --idle-s 10 --out results/live
Ctrl-C ends it; the result folder then holds everything up to the last sample read.
"""

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

        from footnav.core.types import GRAVITY_MPS2

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


def cmd_follow(args: argparse.Namespace) -> int:
    import signal
    import time

    from footnav.core.output import claim_output
    from footnav.core.pipeline import load_pipeline, make_pipeline
    from footnav.core.results import write_results

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


def _require_matplotlib() -> None:
    """--plot without matplotlib is an error before any work, with the install command."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise FootnavError("--plot needs matplotlib: pip install 'footnav[plot]'") from None


def _claim_figure(claims: ExitStack, path, force: bool, inputs):
    """Claim a figure path (None when not asked for, or when matplotlib is missing: said once)."""
    from footnav.core.output import claim_output, is_footnav_figure

    if not path:
        return None
    _require_matplotlib()
    return claims.enter_context(
        claim_output(path, kind="file", force=force, inputs=inputs, signature=is_footnav_figure, what="figure")
    )


def _plot_trajectories(result, recording, path) -> None:
    from footnav.plot import plot_trajectories

    plot_trajectories(result, recording, path)


def cmd_simulate(args: argparse.Namespace) -> int:
    import footnav
    from footnav.core.io.footnav_csv import write_footnav_csv, write_footnav_truth
    from footnav.core.output import claim_output

    out = FilePath(args.out)
    options = dict(args.set or [])
    if args.segments is not None:
        options["segments"] = args.segments
    if args.scenario == "path" and "segments" not in options:
        raise FootnavError("the path scenario needs --segments, e.g. --segments 10:90,5:-90,3:0 (metres:turn degrees)")
    with claim_output(out, force=args.force, what="output folder") as claim:
        rec = footnav.simulate(args.scenario, seed=args.seed, rate_hz=args.rate_hz, **options)
        with claim.staged() as tmp:
            for side, imu, truth in (("left", rec.left, rec.truth_left), ("right", rec.right, rec.truth_right)):
                write_footnav_csv(imu, tmp / f"{side}.csv")
                write_footnav_truth(truth, tmp / f"{side}_truth.csv")
    print(f"simulated {args.scenario!r} walk, {rec.left.duration_s:.1f} s at {args.rate_hz:g} Hz, written to {out}")
    return EXIT_OK


def cmd_demo(args: argparse.Namespace) -> int:
    from footnav.demo import run_demo

    report = run_demo(plot=None if args.no_plot else args.plot)
    print(report.text)
    return EXIT_OK


def cmd_evaluate(args: argparse.Namespace) -> int:
    from footnav.core.batch import evaluate_many
    from footnav.core.datasets import load_dataset
    from footnav.core.io import load
    from footnav.core.output import claim_output, csv_signature
    from footnav.core.pipeline import load_pipeline, make_pipeline
    from footnav.core.results import write_report

    if not args.dataset and not args.recordings:
        raise FootnavError("nothing to evaluate: give --dataset NAME and/or recording paths")
    inputs = [*args.recordings, *args.pipeline]
    with ExitStack() as claims:
        out_claim = (
            claims.enter_context(claim_output(args.out, force=args.force, inputs=inputs, what="output folder"))
            if args.out
            else None
        )
        # a table with failed pairs has a last column "error" (EvaluationReport.to_csv)
        ours = [csv_signature(REPORT_CSV_HEADER), csv_signature(REPORT_CSV_HEADER + ",error")]
        csv_claim = (
            claims.enter_context(claim_output(args.csv, kind="file", force=args.force, inputs=inputs,
                                              signature=lambda path: any(s(path) for s in ours), what="table"))
            if args.csv
            else None
        )
        plot_claim = None
        if args.plot:
            _require_matplotlib()
            plot_claim = claims.enter_context(claim_output(args.plot, force=args.force, inputs=inputs, what="figure folder"))
        pipelines = [(FilePath(p).stem, load_pipeline(p)) for p in args.pipeline] or [("default", make_pipeline())]
        recordings = [load_dataset(name, args.data_dir) for name in args.dataset]
        recordings += [load(path) for path in args.recordings]
        backend = "dask" if args.dask_scheduler else "loky"
        logging.getLogger("footnav").info("evaluating %d pipeline(s) on %d recording(s)", len(pipelines), len(recordings))
        report = evaluate_many(pipelines, recordings, n_jobs=args.jobs, backend=backend, scheduler=args.dask_scheduler)
        with ExitStack() as staged:
            figures = staged.enter_context(plot_claim.staged()) if plot_claim else None
            if figures is not None:
                from footnav.plot import plot_position_errors, plot_trajectories

                by_name = {rec.name: rec for rec in recordings}
                for (rec_name, pname), result in report.results.items():
                    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in f"{rec_name}-{pname}")
                    rec = by_name.get(rec_name)
                    plot_trajectories(result, rec, figures / f"{safe}.png")
                    if rec is not None and rec.truth_left is not None:
                        plot_position_errors(result, rec, figures / f"{safe}-errors.png")
            if csv_claim:
                staged.enter_context(csv_claim.staged()).write_text(report.to_csv(), encoding="utf-8")
            if out_claim:
                write_report(report, out_claim, pipelines={name: pipe.to_toml() for name, pipe in pipelines})
    print(report.to_text())
    if args.csv:
        print(f"table written to {args.csv}")
    if args.out:
        print(f"report written to {args.out}")
    if plot_claim:
        print(f"figures written to {args.plot}")
    return EXIT_INTERNAL if report.failures else EXIT_OK  # the failures are listed under the table


def cmd_compare_detectors(args: argparse.Namespace) -> int:
    from footnav.core.output import claim_output, csv_signature

    sources = [x for x in (args.recording, args.dataset, args.simulate) if x]
    if len(sources) != 1:
        raise FootnavError("give exactly one of RECORDING, --dataset NAME or --simulate SCENARIO")
    inputs = [args.recording] if args.recording else []
    with ExitStack() as claims:
        csv_claim = (
            claims.enter_context(claim_output(args.csv, kind="file", force=args.force, inputs=inputs,
                                              signature=csv_signature(REPORT_CSV_HEADER), what="table"))
            if args.csv
            else None
        )
        plot_claim = _claim_figure(claims, args.plot, args.force, inputs)
        return _compare(args, csv_claim, plot_claim)


def _compare(args: argparse.Namespace, csv_claim, plot_claim) -> int:
    import footnav
    from footnav.core.comparison import compare_detectors
    from footnav.core.datasets import load_dataset
    from footnav.core.io import load

    if args.recording:
        rec = load(args.recording)
    elif args.dataset:
        rec = load_dataset(args.dataset, args.data_dir)
    else:
        rec = footnav.simulate(args.simulate, seed=args.seed, rate_hz=args.rate_hz)
    names = [d.strip() for d in args.detectors.split(",") if d.strip()] if args.detectors else None
    comparison = compare_detectors(rec, names, tolerance_s=args.tolerance_s)
    with ExitStack() as staged:
        if csv_claim:
            staged.enter_context(csv_claim.staged()).write_text(comparison.to_csv(), encoding="utf-8")
        if plot_claim:
            comparison.plot(staged.enter_context(plot_claim.staged()), seconds=tuple(args.seconds) if args.seconds else None)
    print(comparison.to_text())
    if csv_claim:
        print(f"table written to {args.csv}")
    if plot_claim:
        print(f"figure: {args.plot}")
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    from footnav import __version__

    parser = _Parser(prog="footnav", description="Foot-mounted inertial navigation: one or both feet, composable methods.")
    parser.add_argument("--version", action="version", version=f"footnav {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log what footnav does")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser(
        "plugins",
        help="list every registered component",
        description="List every registered component (kind, name, origin package, what it is), or one component's parameters.",
        epilog="examples:\n  footnav plugins | grep detector\n  footnav plugins ekf",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("name", nargs="?", help="a component's name: show its parameters")
    p.set_defaults(func=cmd_plugins)

    from footnav.core.io.load import READERS

    p = sub.add_parser(
        "run",
        help="run a pipeline on a recording of one or both feet",
        description=textwrap.fill(
            "Run a pipeline on a recording in any format footnav reads (" + ", ".join(READERS) + "; "
            "guessed from the file unless --format is given): one file per foot, or one two-foot recording as --left. "
            "docs/your-own-sensor.md lists the formats and how to bring any other sensor in.",
            width=100,
        ),
        epilog=EPILOG_RUN,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--left", required=True, help="left (or only) foot's recording, or a two-foot recording")
    p.add_argument("--right", help="right foot's recording")
    p.add_argument("--format", choices=list(READERS), help="the recordings' format (default: guessed from each file)")
    p.add_argument("--acc-unit", choices=["m/s^2", "g"], help="accelerometer unit of a footnav CSV (default: its '# units:' line, else m/s^2)")
    p.add_argument("--gyr-unit", choices=["rad/s", "deg/s"], help="gyroscope unit (footnav CSV, gaitmap)")
    p.add_argument("--t-unit", choices=["s", "ms"], help="time unit of a footnav CSV (default s)")
    p.add_argument("--rate-hz", type=_positive, help="sampling rate, Hz, for files without time stamps (e.g. headerless 6-column)")
    p.add_argument("--drop-duplicates", action="store_true",
                   help="also drop rows that repeat a time stamp with different values (exact copies are always dropped; recorded)")
    p.add_argument("--pipeline", help="pipeline TOML file ([detector], [estimator], [fusion] tables, optional [sync])")
    p.add_argument("--sync", choices=["data"],
                   help="put the right foot on the left foot's clock first, found from the data (two feet recorded "
                        "on unsynchronised clocks; both should start and end standing). More options: a [sync] table")
    p.add_argument("--detector", help="detector name (see footnav plugins)")
    p.add_argument("--estimator", help="estimator name")
    p.add_argument("--fusion", help="fusion name")
    p.add_argument("--out", required=True, help="output folder (must not exist or be empty)")
    p.add_argument("--force", action="store_true", help="replace an output folder (and figure) that footnav wrote")
    p.add_argument("--plot", help="also write the trajectory figure (PNG) here")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser(
        "follow",
        help="run a pipeline on samples as they arrive (a growing CSV file, or standard input)",
        description=textwrap.fill(
            "Follow a walk live: read footnav CSV rows (t, acc_x..gyr_z; '# units:' line or --acc-unit etc.) as "
            "another program appends them to a file, or from standard input ('-'; a 'foot' column gives both "
            "feet there), print one line per closed step (time, foot, footprint position, stride length, "
            "heading) and write the same result folder as 'footnav run' at the end: at the end of standard "
            "input, after --idle-s seconds without a new row, or at Ctrl-C. docs/online.md explains the online mode.",
            width=100,
        ),
        epilog=EPILOG_FOLLOW,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--left", required=True, help="left (or only) foot's CSV file, or - for standard input")
    p.add_argument("--right", help="right foot's CSV file")
    p.add_argument("--feet", type=int, choices=[1, 2], default=1, help="feet on standard input (a 'foot' column), default 1")
    p.add_argument("--acc-unit", choices=["m/s^2", "g"], help="accelerometer unit (default: the '# units:' line, else m/s^2)")
    p.add_argument("--gyr-unit", choices=["rad/s", "deg/s"], help="gyroscope unit")
    p.add_argument("--t-unit", choices=["s", "ms"], help="time unit")
    p.add_argument("--pipeline", help="pipeline TOML file (its components must run online)")
    p.add_argument("--detector", help="detector name (default threshold: it runs online; adaptive does not)")
    p.add_argument("--estimator", help="estimator name (default ekf, smoothing each step at its end)")
    p.add_argument("--fusion", help="fusion name (default independent)")
    p.add_argument("--idle-s", type=_positive, default=5.0, help="end after this long without a new row, s (files)")
    p.add_argument("--poll-s", type=_positive, default=0.05, help="how often a file is read for new rows, s")
    p.add_argument("--max-wait-s", type=_positive, default=2.0, help="longest wait for the other foot before a step is printed, s")
    p.add_argument("--out", required=True, help="output folder (must not exist or be empty)")
    p.add_argument("--force", action="store_true", help="replace an output folder that footnav wrote")
    p.set_defaults(func=cmd_follow)

    p = sub.add_parser(
        "simulate",
        help="write a simulated two-foot walk to CSV",
        description="Simulate a two-foot walk and write left.csv, right.csv (footnav CSV, SI) and their truth.",
        epilog="example:\n  footnav simulate rectangle --rate-hz 100 --seed 1 --out sim/rect",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scenario", nargs="?", default="straight", choices=["straight", "rectangle", "path"],
                   help="straight, rectangle or path (default straight)")
    p.add_argument("--segments", type=_segments, help="path: walk DIST m then turn DEG, ...: 10:90,5:-90,3:0; stairs:N:RISE_M[:TREAD_M] a flight")
    p.add_argument("--set", type=_option, action="append", metavar="NAME=VALUE",
                   help="any simulator option, e.g. --set distance_m=50 --set noise=false (footnav.simulate's docs)")
    p.add_argument("--seed", type=_seed, default=0, help="simulator seed (an integer >= 0)")
    p.add_argument("--rate-hz", type=_positive, default=100.0, help="sampling rate, Hz")
    p.add_argument("--out", required=True)
    p.add_argument("--force", action="store_true")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser(
        "evaluate",
        help="measure pipelines against the truth of recordings",
        description="Run one or more pipelines on recordings with truth and print every metric each supports.",
        epilog="examples:\n  footnav evaluate --dataset azure_fgo --dataset xio_short\n"
        "  footnav evaluate --pipeline a.toml --pipeline b.toml --dataset gaitmap --out results/ab --plot results/ab-figs\n"
        "  footnav evaluate --dataset gaitmap --jobs 2\n"
        "  footnav evaluate --dataset gaitmap --dask-scheduler tcp://10.0.0.5:8786\n"
        "  footnav evaluate walk/left.csv",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recordings", nargs="*", help="recording files or folders (format guessed)")
    p.add_argument("--dataset", action="append", default=[], help="shared recording by name (repeatable)")
    p.add_argument("--pipeline", action="append", default=[], help="pipeline TOML (repeatable; default pipeline if none)")
    p.add_argument("--data-dir", help="shared data folder (default $FOOTNAV_DATA or ../shared/data)")
    p.add_argument("--csv", help="also write the table as CSV")
    p.add_argument("--out", help="write the report (CSV, JSON with versions and input hashes, pipelines) to this folder")
    p.add_argument("--force", action="store_true", help="replace an --out / --plot folder or --csv that footnav wrote")
    p.add_argument("--plot", help="write a trajectory figure per run (PNG) into this folder")
    p.add_argument("--jobs", type=int, default=1, help="parallel worker processes (-1: every core)")
    p.add_argument("--dask-scheduler", metavar="ADDRESS", help="run on a Dask cluster (tcp://host:8786)")
    p.set_defaults(func=cmd_evaluate)

    p = sub.add_parser(
        "compare-detectors",
        help="compare stance detectors on one recording (table and figure)",
        description="Run stance detectors on one recording and compare them against its reference: steps "
        "found / missed / false, per-sample F1, event timing errors, runtime.",
        epilog="examples:\n  footnav compare-detectors --simulate straight --plot detectors.png\n"
        "  footnav compare-detectors --dataset gaitmap --detectors threshold,glrt,hmm --plot g.png --seconds 5 15\n"
        "  footnav compare-detectors walk/left.csv --detectors threshold,glrt",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recording", nargs="?", help="recording file or folder (format guessed)")
    p.add_argument("--dataset", help="shared recording by name (see footnav evaluate)")
    p.add_argument("--simulate", metavar="SCENARIO", help="a simulated walk: straight, rectangle")
    p.add_argument("--seed", type=_seed, default=0, help="simulator seed (an integer >= 0)")
    p.add_argument("--rate-hz", type=_positive, default=100.0, help="simulator rate, Hz")
    p.add_argument("--detectors", help="comma-separated names (default: every detector that fits)")
    p.add_argument("--tolerance-s", type=_positive, default=0.15, help="matching tolerance for steps and events, s")
    p.add_argument("--data-dir", help="shared data folder")
    p.add_argument("--csv", help="also write the table as CSV")
    p.add_argument("--plot", help="write the stance figure (PNG) here")
    p.add_argument("--force", action="store_true", help="replace a --csv / --plot that footnav wrote before")
    p.add_argument("--seconds", type=float, nargs=2, metavar=("START", "STOP"), help="time window of the figure")
    p.set_defaults(func=cmd_compare_detectors)

    p = sub.add_parser(
        "demo",
        help="run the default pipeline on the bundled real recording",
        description="Run the default pipeline on the bundled azure_fgo recording (two feet, 60 Hz, with ground truth) and print the accuracy table.",
        epilog="examples:\n  footnav demo\n  footnav demo --plot demo.png\n  footnav demo --no-plot",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--plot", default="footnav-demo.png", help="trajectory figure to write when matplotlib is installed")
    p.add_argument("--no-plot", action="store_true", help="do not write the figure")
    p.set_defaults(func=cmd_demo)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="footnav: %(message)s")
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    try:
        notice = _compile_notice()
        with warnings.catch_warnings(), notice.listening():  # both restored on return
            warnings.showwarning = _warning_printer(args.verbose)
            try:
                return args.func(args)
            finally:
                notice.report()
    except PluginError as exc:  # not the user's input: a component package's bug
        print(f"footnav {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_INTERNAL
    except FootnavError as exc:
        print(f"footnav {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except UnicodeDecodeError as exc:  # a binary file where text was expected (pipeline TOML, CSV)
        print(f"footnav {args.command}: error: not a UTF-8 text file ({exc.reason} at byte {exc.start})", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:  # unreadable input, full disk, read-only folder, unreachable scheduler
        if args.verbose:
            raise
        print(f"footnav {args.command}: error: {_os_message(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("footnav: interrupted", file=sys.stderr)
        return EXIT_INTERNAL
    except Exception as exc:  # a bug: one line, the traceback with -v
        if args.verbose:
            raise
        print(
            f"footnav {args.command}: internal error: {type(exc).__name__}: {exc} "
            "(run with -v for the traceback, and please report it)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
