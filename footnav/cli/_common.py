"""What the commands share: exit codes, the CSV table header, plain-text tables, and claiming
a figure path (with the matplotlib check) before any work."""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from contextlib import ExitStack

from footnav.core.errors import FootnavError

EXIT_OK, EXIT_INTERNAL, EXIT_USAGE = 0, 1, 2
#: First line of every table footnav writes as CSV (EvaluationReport.to_csv): how --force knows one.
REPORT_CSV_HEADER = "recording,pipeline,foot,name,value,unit"


def clip_text(text: object, limit: int = 80) -> str:
    """``text`` for a message: at most ``limit`` characters of it, saying how long it was (a
    garbled 50 MB line is quoted, not printed)."""
    text = str(text)
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


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


def _require_matplotlib(flag: str = "--plot") -> None:
    """``flag`` (--plot, --view) without matplotlib is an error before any work, with the install command."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise FootnavError(f"{flag} needs matplotlib: pip install 'footnav[plot]'") from None


def _claim_figure(claims: ExitStack, path, force: bool, inputs):
    """Claim a figure path (None when not asked for, or when matplotlib is missing: said once)."""
    from footnav.data.output import claim_output, is_footnav_figure

    if not path:
        return None
    _require_matplotlib()
    return claims.enter_context(
        claim_output(path, kind="file", force=force, inputs=inputs, signature=is_footnav_figure, what="figure")
    )


def _plot_trajectories(result, recording, path) -> None:
    from footnav.analysis.plot import plot_trajectories

    plot_trajectories(result, recording, path)
