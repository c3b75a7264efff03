"""The ``footnav`` command.

Exit codes: 0 success, 2 bad usage or bad input (one-line message, no traceback), 1 internal error.

One module per command group, each importing only the shared helpers below it:
``_run`` (run), ``_follow`` (follow), ``_simulate`` (simulate), ``_warmup`` (warmup), ``_evaluate`` (evaluate,
compare-detectors), ``_plugins`` (plugins, demo), ``_parser`` (the argument parser) and
``_common`` (exit codes, tables, figure claims). ``main`` is here, with what it installs
around a command: the warning printer, the compile notice and the one-line error messages.
"""

from __future__ import annotations

import gc
import logging
import sys
import warnings
from collections.abc import Sequence

from footnav.cli._common import EXIT_INTERNAL, EXIT_OK, EXIT_USAGE, REPORT_CSV_HEADER, clip_text
from footnav.cli._evaluate import cmd_compare_detectors, cmd_evaluate
from footnav.cli._follow import FOLLOW_COLUMNS, cmd_follow
from footnav.cli._parser import EPILOG_FOLLOW, EPILOG_RUN, build_parser
from footnav.cli._plugins import PLUGINS_WIDTH, cmd_demo, cmd_plugins
from footnav.cli._run import READER_FLAGS, cmd_run
from footnav.cli._simulate import cmd_simulate
from footnav.cli._warmup import cmd_warmup, warm_worker
from footnav.core.errors import FootnavError, FootnavWarning, PluginError

__all__ = [
    "EPILOG_FOLLOW",
    "EPILOG_RUN",
    "EXIT_INTERNAL",
    "EXIT_OK",
    "EXIT_USAGE",
    "FOLLOW_COLUMNS",
    "PLUGINS_WIDTH",
    "READER_FLAGS",
    "REPORT_CSV_HEADER",
    "build_parser",
    "cmd_compare_detectors",
    "cmd_demo",
    "cmd_evaluate",
    "cmd_follow",
    "cmd_plugins",
    "cmd_run",
    "cmd_simulate",
    "cmd_warmup",
    "main",
    "warm_worker",
]


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
                    print(
                        "footnav: compiling the numerical kernels (once: they are cached for the next runs) ...",
                        file=sys.stderr,
                        flush=True,
                    )
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


#: The longest error message the command line prints (characters): a message quoting a garbled
#: 50 MB line, or a huge parameter, is cut, saying how long it was.
MAX_MESSAGE_CHARS = 1000


def _one_message(text: object) -> str:
    """An error message as printed: at most ``MAX_MESSAGE_CHARS`` characters."""
    return clip_text(text, MAX_MESSAGE_CHARS)


def _os_message(exc: OSError) -> str:
    """One line for an error of the file system or the network: what, on which file."""
    where = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
    return f"{exc.strerror or exc}{':' if where else ''}{where}"


def main(argv: Sequence[str] | None = None) -> int:
    """The ``footnav`` command; ``argv`` None: the process's arguments (the program itself)."""
    try:
        return _main(argv)
    finally:
        if argv is None:
            # The process ends next: Python's last garbage collections walk every object numba
            # made (0.1 s of a 1 s footnav run). Frozen objects are skipped; atexit still runs.
            gc.freeze()


def _main(argv: Sequence[str] | None) -> int:
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
        print(f"footnav {args.command}: error: {_one_message(exc)}", file=sys.stderr)
        return EXIT_INTERNAL
    except FootnavError as exc:
        print(f"footnav {args.command}: error: {_one_message(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except UnicodeDecodeError as exc:  # a binary file where text was expected (pipeline TOML, CSV)
        print(
            f"footnav {args.command}: error: not a UTF-8 text file ({exc.reason} at byte {exc.start})", file=sys.stderr
        )
        return EXIT_USAGE
    except OSError as exc:  # unreadable input, full disk, read-only folder, unreachable scheduler
        if args.verbose:
            raise
        print(f"footnav {args.command}: error: {_one_message(_os_message(exc))}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("footnav: interrupted", file=sys.stderr)
        return EXIT_INTERNAL
    except Exception as exc:  # a bug: one line, the traceback with -v
        if args.verbose:
            raise
        print(
            f"footnav {args.command}: internal error: {type(exc).__name__}: {_one_message(exc)} "
            "(run with -v for the traceback, and please report it)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL
