"""The report's page: one self-contained HTML file (its style inline, no script, no link to
anything outside it) built from sections; the text parts (tables, warnings and self-checks in
plain words, provenance) need nothing but the standard library and numpy.

Nothing in the page names a place on the machine that made it: input files are given by name and
SHA-256, and every text taken from the run (warnings, messages) has the inputs' folders, the
working folder and the home folder cut out (:func:`scrub`).
"""

from __future__ import annotations

import html
import math
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path as FilePath
from typing import Any

__all__ = ["PLOT_HINT", "checks_html", "page", "provenance_html", "scrub", "section", "table", "warnings_html"]

#: What the page says in place of its figures when matplotlib is missing.
PLOT_HINT = "Figures need matplotlib: <code>pip install 'footnav[plot]'</code>, then run again."

_STYLE = """
:root{color-scheme:light;--fg:#1d1d1f;--muted:#5f6368;--line:#d9dce1;--soft:#f4f6f8;--warn:#8a4b00;--warnbg:#fff4e0;--ok:#0b6b2e}
*{box-sizing:border-box}
body{font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;color:var(--fg);margin:0 auto;
max-width:1100px;padding:1rem 1.2rem 3rem}
h1{font-size:1.5rem;margin:.4rem 0}
h2{font-size:1.2rem;margin:2rem 0 .5rem;border-bottom:1px solid var(--line);padding-bottom:.2rem}
h3{font-size:1.05rem;margin:1.2rem 0 .4rem}
p,li{max-width:75ch}.muted{color:var(--muted)}
nav{font-size:.9rem;margin:.4rem 0 1rem}nav a{margin-right:.9rem;white-space:nowrap}
figure{margin:.5rem 0 1rem}figure svg{width:100%;height:auto;display:block}
figcaption{color:var(--muted);font-size:.88rem}
.scroll{overflow-x:auto;max-width:100%;-webkit-overflow-scrolling:touch}
table{border-collapse:collapse;font-size:.85rem;font-variant-numeric:tabular-nums}
th,td{border-bottom:1px solid var(--line);padding:.25rem .55rem;text-align:right;white-space:nowrap}
th{background:var(--soft);position:sticky;top:0}td.t,th.t{text-align:left}
tr.steady td{background:#eef8f0}td.best{font-weight:700;color:var(--ok)}td.best::after{content:" \\2605"}
.warn{background:var(--warnbg);border-left:4px solid var(--warn);padding:.5rem .8rem;margin:.5rem 0}
.ok{border-left:4px solid var(--ok);padding:.3rem .8rem;margin:.5rem 0}
pre{background:var(--soft);padding:.6rem;overflow-x:auto;font-size:.8rem}
code{font-size:.9em}
dl{display:grid;grid-template-columns:max-content 1fr;gap:.15rem 1rem}
dt{color:var(--muted)}dd{margin:0;overflow-wrap:anywhere}
@media (max-width:600px){body{font-size:14px;padding:.6rem}figure svg{min-width:560px}th,td{padding:.2rem .35rem}}
"""


def esc(text: object) -> str:
    return html.escape(str(text), quote=True)


def scrub(text: object, places: Iterable[str] = ()) -> str:
    """``text`` without the machine's places: each of ``places`` (input files, by their full
    path: replaced by their name), then the working folder and the home folder (``.`` and ``~``),
    then any other absolute path (replaced by its last part)."""
    out = str(text)
    for place in sorted({str(p) for p in places if p}, key=len, reverse=True):
        out = out.replace(place, FilePath(place).name)
    for folder, short in ((os.getcwd(), "."), (os.path.expanduser("~"), "~")):
        if len(folder) > 1:
            out = out.replace(folder + os.sep, short + "/").replace(folder, short)
    # what is left: an absolute path in a message (a temporary folder, another input)
    return re.sub(r"(?<![\w.~])(/[^\s/'\"():,;]+)+/([^\s/'\"():,;]+)", r"\2", out)


def section(anchor: str, title: str, body: str) -> str:
    """An HTML section with its anchor and heading."""
    return f'<section id="{esc(anchor)}"><h2>{esc(title)}</h2>\n{body}\n</section>\n'


def figure(svg: str | None, caption: str, *, figures_ok: bool) -> str:
    if svg is None:
        return f'<p class="muted">{PLOT_HINT if not figures_ok else "Nothing to draw."}</p>'
    return f'<figure><div class="scroll">{svg}</div><figcaption>{caption}</figcaption></figure>'


def table(
    header: Sequence[str],
    rows: Sequence[Sequence[object]],
    *,
    row_class: Sequence[str] | None = None,
    cell_class: Mapping[tuple[int, int], str] | None = None,
    text_columns: Iterable[int] = (0,),
) -> str:
    """An HTML table in a horizontally scrolling box (a narrow screen scrolls it, not the page)."""
    left = set(text_columns)
    cls = dict(cell_class or {})
    head = "".join(f"<th{' class=t' if j in left else ''}>{esc(h)}</th>" for j, h in enumerate(header))
    body = []
    for i, row in enumerate(rows):
        rc = f' class="{row_class[i]}"' if row_class and row_class[i] else ""
        classes = [" ".join(c for c in ("t" if j in left else "", cls.get((i, j), "")) if c) for j in range(len(row))]
        cells = "".join(f'<td class="{c}">{esc(fmt(v))}</td>' for c, v in zip(classes, row))
        body.append(f"<tr{rc}>{cells}</tr>")
    return f'<div class="scroll"><table><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table></div>'


def fmt(value: object) -> str:
    if isinstance(value, bool):
        return "yes" if value else ""
    if isinstance(value, float):
        if not math.isfinite(value):
            return ""
        return f"{value:.3f}" if abs(value) < 1000 else f"{value:.0f}"
    return str(value)


def page(title: str, subtitle: str, sections: Sequence[tuple[str, str, str]]) -> str:
    """The whole document: a heading, a list of links to the sections, the sections."""
    links = " ".join(f'<a href="#{esc(a)}">{esc(t)}</a>' for a, t, _ in sections)  # spaces: room to wrap
    body = "".join(section(a, t, b) for a, t, b in sections)
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f'<meta name="generator" content="footnav"><title>{esc(title)}</title><style>{_STYLE}</style></head>\n'
        f'<body><h1>{esc(title)}</h1><p class="muted">{subtitle}</p><nav>{links}</nav>\n{body}</body></html>\n'
    )


# --- warnings and self-checks, in plain words ------------------------------------------------

_STANCE_TRY = (
    "try another stance detector (<code>--detector</code>, see <code>footnav plugins</code>) or compare them "
    "with <code>footnav compare-detectors</code>; look at the stance figure above"
)
_VERTICAL_TRY = (
    "the height drifts over level walking: check the sensor's mounting and the recording's units, or "
    'keep <code>vertical = "floors"</code> in the estimator (the default) to hold level strides level'
)


def warnings_html(warnings: Sequence[str], places: Iterable[str]) -> str:
    """The run's warnings as an HTML list, each with where it came from (or a note that there was none)."""
    if not warnings:
        return '<p class="ok">The run issued no warning.</p>'
    items = "".join(f"<li>{esc(scrub(w, places))}</li>" for w in warnings)
    return (
        f'<div class="warn"><p>The run issued {len(warnings)} warning(s): each says what it found and, '
        f"where footnav knows one, what to try.</p><ul>{items}</ul></div>"
    )


def _signed(value: object) -> str:
    """A signed figure to the centimetre, without the sign of a rounded zero (-0.00)."""
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        return "?"
    return f"{round(float(value), 2) + 0.0:+.2f}"


def checks_html(meta: Mapping[str, Any]) -> str:
    """Each self-check of the run (stances against gait cycles, height trend, how the stream
    ended, the feet's common span) as one sentence per foot, with what to try when it is off."""
    out = []
    for foot, c in (meta.get("stance_check") or {}).items():
        missed, over = c.get("cycles_without_stance", 0), c.get("stances_over_swing", 0)
        text = (
            f"<b>{esc(foot)} stances</b>: {c.get('stances', '?')} stances for {c.get('gait_cycles', '?')} gait cycles "
            f"(stride {c.get('stride_s', float('nan')):.2f} s); {missed} cycle(s) without a stance, {over} stance(s) "
            "across a swing."
        )
        if c.get("suspicious"):
            at = (c.get("cycles_without_stance_at_s") or []) + (c.get("stances_over_swing_at_s") or [])
            where = f" First at {', '.join(f'{t:g} s' for t in at[:5])}." if at else ""
            out.append(f'<p class="warn">{text}{where} The detector and the gait disagree: {_STANCE_TRY}.</p>')
        else:
            out.append(f'<p class="ok">{text} Fine.</p>')
    for foot, c in (meta.get("vertical_check") or {}).items():
        text = (
            f"<b>{esc(foot)} height</b>: {c.get('level_strides', '?')} level and {c.get('stair_strides', '?')} stair "
            f"strides over {c.get('walked_m', float('nan')):.1f} m; trend over level strides "
            f"{_signed(c.get('trend_m'))} m ({_signed(c.get('rate_m_per_100m'))} m per 100 m)."
        )
        if c.get("suspicious"):
            out.append(f'<p class="warn">{text} That is a steady drift: {_VERTICAL_TRY}.</p>')
        else:
            out.append(f'<p class="ok">{text} Fine.</p>')
    span = (meta.get("fusion") or {}).get("span") or {}
    if span.get("marked"):
        out.append(
            '<p class="warn"><b>feet</b>: the two feet\'s recordings start or end '
            f"{span.get('start_difference_s', 0):.1f} / {span.get('end_difference_s', 0):.1f} s apart: "
            "were they recorded together? Try <code>--sync data</code> when their clocks differ.</p>"
        )
    if "complete" in meta:
        ended = esc(scrub(meta.get("ended_by", "")))
        if meta["complete"]:
            out.append(f'<p class="ok"><b>stream</b>: complete ({ended}).</p>')
        else:
            out.append(
                f'<p class="warn"><b>stream</b>: incomplete, ended by {ended}: the result holds what was '
                "final by then.</p>"
            )
    return "".join(out) or '<p class="muted">No self-check ran for this result.</p>'


def provenance_html(
    meta: Mapping[str, Any],
    versions: Mapping[str, Any],
    hashes: Mapping[str, str],
    pipeline_toml: str | None,
    extra: Mapping[str, Any] | None = None,
) -> str:
    """The pipeline, the versions and the inputs (file names and SHA-256, never their folders)."""
    pipe = meta.get("pipeline") or {}
    named = " + ".join(f"{kind} {c.get('name', '?')}" for kind, c in pipe.items())
    items = [("pipeline", named or ("its TOML below" if pipeline_toml else "unknown"))]
    items += [(k, v) for k, v in (extra or {}).items()]
    items += [(name, v) for name, v in versions.items() if v]
    runtime = meta.get("runtime_s")
    if isinstance(runtime, (int, float)):
        items.append(("run time", f"{runtime:.2f} s"))
    dl = "".join(f"<dt>{esc(k)}</dt><dd>{esc(v)}</dd>" for k, v in items)
    inputs = (
        table(("input file", "SHA-256"), [(FilePath(p).name, h) for p, h in hashes.items()])
        if hashes
        else '<p class="muted">No input file (a stream or data in memory).</p>'
    )
    toml = f"<h3>Pipeline (TOML)</h3><pre>{esc(pipeline_toml)}</pre>" if pipeline_toml else ""
    return f"<dl>{dl}</dl><h3>Inputs</h3>{inputs}{toml}"
