"""``footnav plugins`` (every registered component, or one component's parameters) and
``footnav demo``."""

from __future__ import annotations

import argparse
import sys
import textwrap

from footnav.cli._common import EXIT_OK, _format_table
from footnav.core.errors import FootnavError

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
            needs = [
                n for n, f in (("two feet", e.cls.needs_two_feet), ("magnetometer", e.cls.needs_magnetometer)) if f
            ]
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


def cmd_demo(args: argparse.Namespace) -> int:
    from footnav.demo import run_demo

    report = run_demo(plot=None if args.no_plot else args.plot)
    print(report.text)
    return EXIT_OK
