"""The ``footnav`` argument parser: every command, its options and help, and the argparse types
of the options."""

from __future__ import annotations

import argparse
import sys
import textwrap

from footnav.cli._common import EXIT_USAGE
from footnav.cli._evaluate import cmd_compare_detectors, cmd_evaluate
from footnav.cli._follow import cmd_follow
from footnav.cli._plugins import cmd_demo, cmd_plugins
from footnav.cli._run import cmd_run
from footnav.cli._simulate import cmd_simulate
from footnav.cli._warmup import cmd_warmup

EPILOG_RUN = """examples:
  footnav run --left L.csv --right R.csv --acc-unit g --gyr-unit deg/s --out results/walk1
  footnav run --left data/gaitmap_example --out results/gaitmap
  footnav run --left walk.mat --out results/pyshoe
  footnav run --left L.csv --pipeline pipeline.toml --out results/walk1 --force
  footnav run --left L.csv --right R.csv --fusion step-vector --out results/walk1 --plot walk1.png
  footnav run --left imu.csv --rate-hz 100 --acc-unit g --gyr-unit deg/s --out results/x  (AccX,..,GyrZ, no t)
  footnav run --left log.txt --format delimited --columns t=0,acc=1:4,gyr=4:7 --t-unit ms --out results/x
"""

EPILOG_FOLLOW = """examples:
  footnav follow --left L.csv --right R.csv --out results/live      (files another program appends to)
  sensor-reader | footnav follow --left - --out results/live       (CSV lines on standard input)
  footnav follow --left walk.csv --detector glrt --idle-s 10 --out results/live
  footnav follow --left L.csv --right R.csv --view --out results/live  (the walk drawn live; report.html at the end)
Ctrl-C, SIGTERM or SIGHUP end it; the result folder then holds everything up to the last sample
read (summary.json: "complete": false, "ended_by"). A bad row, a refused chunk or a failing
component end it too, with the rows before written, and exit code 2 (bad input) or 1.
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
        raise argparse.ArgumentTypeError(
            f"{text!r}: expected DIST:DEG pairs separated by commas, e.g. 10:90,5:-90"
        ) from None
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


def build_parser() -> argparse.ArgumentParser:
    from footnav._version import __version__

    parser = _Parser(
        prog="footnav", description="Foot-mounted inertial navigation: one or both feet, composable methods."
    )
    parser.add_argument("--version", action="version", version=f"footnav {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log what footnav does")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser(
        "plugins",
        help="list every registered component",
        description="List every registered component (kind, name, origin package, what it is), "
        "or one component's parameters.",
        epilog="examples:\n  footnav plugins | grep detector\n  footnav plugins ekf",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("name", nargs="?", help="a component's name: show its parameters")
    p.set_defaults(func=cmd_plugins)

    from footnav.data.io.load import READERS

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
    p.add_argument(
        "--acc-unit",
        choices=["m/s^2", "g"],
        help="accelerometer unit of a footnav CSV or delimited table (default: what the file says, else m/s^2)",
    )
    p.add_argument(
        "--gyr-unit", choices=["rad/s", "deg/s"], help="gyroscope unit (footnav CSV, delimited, gaitmap; default rad/s)"
    )
    p.add_argument(
        "--t-unit", choices=["s", "ms", "us"], help="time unit of a footnav CSV or delimited table (default s)"
    )
    p.add_argument(
        "--rate-hz",
        type=_positive,
        help="sampling rate, Hz, for files without time stamps (delimited without a time column, "
        "headerless 6-column, ximu_cal: default 256)",
    )
    p.add_argument(
        "--columns",
        metavar="SPEC",
        help="columns of a delimited table (--format delimited), by index or header name: "
        "t=0,acc=1:4,gyr=4:7 or acc=AccX,AccY,AccZ,gyr=GyrX,GyrY,GyrZ; groups t, counter, acc, gyr, mag "
        "(default: found from the header names)",
    )
    p.add_argument(
        "--drop-duplicates",
        action="store_true",
        help="also drop rows that repeat a time stamp with different values "
        "(exact copies are always dropped; recorded)",
    )
    p.add_argument(
        "--pipeline",
        help="pipeline TOML file ([detector], [estimator], [fusion] tables, optional [heading_aid] and [sync])",
    )
    p.add_argument(
        "--sync",
        choices=["data"],
        help="put the right foot on the left foot's clock first, found from the data (two feet recorded "
        "on unsynchronised clocks; both should start and end standing). More options: a [sync] table",
    )
    p.add_argument("--detector", help="detector name (see footnav plugins)")
    p.add_argument("--estimator", help="estimator name")
    p.add_argument("--fusion", help="fusion name")
    p.add_argument(
        "--heading-aid", help="heading aid name, e.g. dominant-directions for hallway walks (docs/heading.md)"
    )
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
            "feet there; rows without a header: t,acc_x..gyr_z or foot,t,acc_x..gyr_z), print one line per closed step "
            "(time, foot, footprint position, stride length, "
            "heading) and write the same result folder as 'footnav run' at the end: at the end of standard "
            "input, after --idle-s seconds without a new row, or at Ctrl-C. docs/online.md explains the online mode.",
            width=100,
        ),
        epilog=EPILOG_FOLLOW,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--left", required=True, help="left (or only) foot's CSV file, or - for standard input")
    p.add_argument("--right", help="right foot's CSV file")
    p.add_argument(
        "--feet", type=int, choices=[1, 2], default=1, help="feet on standard input (a 'foot' column), default 1"
    )
    p.add_argument(
        "--acc-unit", choices=["m/s^2", "g"], help="accelerometer unit (default: the '# units:' line, else m/s^2)"
    )
    p.add_argument("--gyr-unit", choices=["rad/s", "deg/s"], help="gyroscope unit")
    p.add_argument("--t-unit", choices=["s", "ms", "us", "ns"], help="time unit")
    p.add_argument("--pipeline", help="pipeline TOML file (its components must run online)")
    p.add_argument("--detector", help="detector name (default adaptive, as footnav run; final 2.75 s after a sample)")
    p.add_argument(
        "--estimator", help="estimator name (default ekf: each step smoothed at its end, the whole walk at the end)"
    )
    p.add_argument("--fusion", help="fusion name (default independent)")
    p.add_argument("--idle-s", type=_positive, default=5.0, help="end after this long without a new row, s (files)")
    p.add_argument("--poll-s", type=_positive, default=0.05, help="how often a file is read for new rows, s")
    p.add_argument(
        "--max-wait-s", type=_positive, default=2.0, help="longest wait for the other foot before a step is printed, s"
    )
    p.add_argument("--plot", help="a live figure (PNG) of the footprints so far, redrawn as steps close and at the end")
    p.add_argument("--plot-every-s", type=_positive, default=1.0, help="redraw the --plot figure at most this often, s")
    p.add_argument(
        "--view",
        action="store_true",
        help="draw the footprints live in a window (its own process: the stream is not slowed); without a "
        "display it draws off-screen and report.html at the end is the view (needs matplotlib)",
    )
    p.add_argument(
        "--view-every-s", type=_positive, default=0.25, help="redraw the --view window at most this often, s"
    )
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
    p.add_argument(
        "scenario",
        nargs="?",
        default="straight",
        choices=["straight", "rectangle", "path"],
        help="straight, rectangle or path (default straight)",
    )
    p.add_argument(
        "--segments",
        type=_segments,
        help="path: walk DIST m then turn DEG, ...: 10:90,5:-90,3:0; stairs:N:RISE_M[:TREAD_M] a flight",
    )
    p.add_argument(
        "--set",
        type=_option,
        action="append",
        metavar="NAME=VALUE",
        help="any simulator option, e.g. --set distance_m=50 --set noise=false (footnav.simulate's docs)",
    )
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
        "  footnav evaluate --pipeline a.toml --pipeline b.toml --dataset gaitmap \\\n"
        "      --out results/ab --plot results/ab-figs\n"
        "  footnav evaluate --dataset gaitmap --jobs 2\n"
        "  footnav evaluate --dataset gaitmap --dask-scheduler tcp://10.0.0.5:8786\n"
        "  footnav evaluate walk/left.csv",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recordings", nargs="*", help="recording files or folders (format guessed)")
    p.add_argument("--dataset", action="append", default=[], help="shared recording by name (repeatable)")
    p.add_argument(
        "--pipeline", action="append", default=[], help="pipeline TOML (repeatable; default pipeline if none)"
    )
    p.add_argument("--data-dir", help="shared data folder (default $FOOTNAV_DATA or ../shared/data)")
    p.add_argument("--csv", help="also write the table as CSV")
    p.add_argument(
        "--out", help="write the report (CSV, JSON with versions and input hashes, pipelines) to this folder"
    )
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
        description="Run the default pipeline on the bundled azure_fgo recording (two feet, 60 Hz, "
        "with ground truth) and print the accuracy table.",
        epilog="examples:\n  footnav demo\n  footnav demo --plot demo.png\n  footnav demo --no-plot",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--plot", default="footnav-demo.png", help="trajectory figure to write when matplotlib is installed")
    p.add_argument("--no-plot", action="store_true", help="do not write the figure")
    p.set_defaults(func=cmd_demo)

    p = sub.add_parser(
        "warmup",
        help="compile the numerical kernels into numba's cache (once, after installing)",
        description=(
            "Run every built-in component once on a short simulated walk, so that numba compiles its kernels "
            "into its cache now instead of in the first real run (several seconds). Run it as the user who will "
            "run footnav, with the same NUMBA_CACHE_DIR: a read-only installation caches per user."
        ),
        epilog=(
            "examples:\n  footnav warmup\n  footnav warmup --jobs 1\n  NUMBA_CACHE_DIR=/opt/cache/numba footnav warmup"
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--jobs",
        type=int,
        default=-1,
        help="processes compiling at once after the default pipeline (default -1: every core; 1: this process only)",
    )
    p.set_defaults(func=cmd_warmup)
    return parser
