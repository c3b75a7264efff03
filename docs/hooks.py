"""MkDocs hook: the component pages are generated from footnav's registry at every build.

Each built-in (and installed plugin) component gets its name, origin, needs, summary and the
parameter table of :meth:`footnav.core.component.Component.parameter_info` (defaults, units and
descriptions from the class's numpydoc), so the pages cannot drift from the code.
"""

from __future__ import annotations

import inspect
from pathlib import Path

KINDS = {
    "detector": ("detectors", "Stance detectors"),
    "estimator": ("estimators", "Estimators"),
    "fusion": ("fusions", "Fusions"),
    "heading_aid": ("heading-aids", "Heading aids"),
}
INTRO = {
    "detector": "A stance detector turns one foot's IMU data (or both feet's) into a `StanceResult`: the "
    "zero-velocity mask, gait events and, where the method has them, phases and probabilities.",
    "estimator": "A per-foot estimator turns one foot's IMU data and stance into a `FootTrajectory` in the nav "
    "frame; `ekf` also exposes its step-able filter for the fusions.",
    "fusion": "A fusion combines the feet into one pedestrian: both corrected foot trajectories and the path.",
    "heading_aid": "A heading aid corrects the heading of the fused trajectories after the fusion "
    "(`make_pipeline(heading_aid=...)`, TOML `[heading_aid]`); docs/heading.md says when to use which.",
}


def component_pages() -> dict[str, str]:
    """Markdown of each component page, by file name."""
    import footnav
    from footnav.pipeline.factory import _registry

    reg = _registry()
    pages = {}
    for kind, (fname, title) in KINDS.items():
        lines = [
            f"# {title}",
            "",
            "Generated from the registry when the docs are built (`docs/hooks.py`).",
            "",
            INTRO[kind],
            "",
        ]
        for name in footnav.list_components()[kind]:
            entry = reg.get(kind, name)
            cls, origin = entry.cls, entry.origin
            doc = inspect.getdoc(cls) or ""
            summary = doc.split("\n\n")[0].replace("\n", " ")
            needs = [
                n
                for n, flag in (
                    ("two feet", getattr(cls, "needs_two_feet", False)),
                    ("a magnetometer", getattr(cls, "needs_magnetometer", False)),
                    ("an estimator with a step-able filter (ekf)", getattr(cls, "needs_stepable_estimator", False)),
                )
                if flag
            ]
            lines += [
                f"## `{name}`",
                "",
                f"`{cls.__module__}.{cls.__name__}` (from {origin})"
                + (f"; needs {' and '.join(needs)}" if needs else ""),
                "",
                summary,
                "",
            ]
            params = cls.parameter_info()
            if params:
                lines += ["| parameter | default | unit | description |", "|---|---|---|---|"]
                for p in params:
                    desc = p.description.replace("|", "\\|")
                    lines.append(f"| `{p.name}` | `{p.default!r}` | {p.unit} | {desc} |")
                lines.append("")
            else:
                lines += ["No parameters.", ""]
        pages[f"{fname}.md"] = "\n".join(lines)
    return pages


def on_pre_build(config, **kwargs) -> None:
    out = Path(config["docs_dir"]) / "reference"
    out.mkdir(exist_ok=True)
    for fname, text in component_pages().items():
        (out / fname).write_text(text, encoding="utf-8")
