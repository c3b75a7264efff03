"""See the walk: a self-contained HTML report of a result (``report.html`` in every result folder
the command line writes) and of an evaluation.

One file that opens offline: no script, no font or style fetched, figures inline as SVG
(matplotlib, the ``plot`` extra: vector, so it stays sharp when zoomed, and text a browser can
search). Without matplotlib the page still holds every table and text, and says how to get the
figures. What is drawn is decimated (:mod:`footnav.report.figures`), never what is computed: an
hour of two feet is a page of a few hundred kB.

>>> footnav.report.write_html(result, "walk.html")                      # doctest: +SKIP
>>> footnav.report.write_html(result, "walk.html", recording=rec)       # with its truth, doctest: +SKIP
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Mapping
from pathlib import Path as FilePath
from typing import Any

#: Loaded on first use (PEP 562): the live view's process imports footnav.report.live, which
#: must not pull in the analysis layer and pandas while the stream it draws is running.
_LAZY = {"result_html": "footnav.report.result", "evaluation_html": "footnav.report.evaluation"}


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'footnav.report' has no attribute {name!r}")
    return getattr(importlib.import_module(module), name)


__all__ = ["REPORT_NAME", "evaluation_html", "result_html", "write_html"]

#: The report's file name in a result folder.
REPORT_NAME = "report.html"


def write_html(
    result: Any,
    path: str | os.PathLike,
    *,
    recording: Any = None,
    pipeline_toml: str | None = None,
    summary: Mapping[str, Any] | None = None,
) -> FilePath:
    """Write the report of ``result`` (a :class:`~footnav.PipelineResult`) to ``path``.

    ``recording`` (optional) gives the truth to draw and the gyroscope under the stances (without
    it, the angular rate is the estimate's); ``pipeline_toml`` the pipeline as written;
    ``summary`` extra lines for the provenance. The file is written as it is: to write into a
    result folder with footnav's claims, use :func:`footnav.data.results.write_results`.
    """
    from footnav.report.result import result_html

    path = FilePath(path)
    path.write_text(
        result_html(result, recording=recording, pipeline_toml=pipeline_toml, summary=summary), encoding="utf-8"
    )
    return path
