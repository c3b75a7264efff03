"""Counts the fault-injection cases and prints "N bad-input cases tried, N handled as specified".

A bad-input case is a test marked ``fault`` (``pytestmark = pytest.mark.fault`` in a file whose
tests all are, ``@pytest.mark.fault`` on a single test). A case is tried when it runs (a test
skipped on this machine is not tried) and handled when it passes.

With ``FOOTNAV_FAULT_REPORT=<path>`` the outcome of every test under tests/faults, marked or not,
is also written there as JSON; ``docs/make_reliability.py`` reads it to regenerate the figures of
docs/reliability.md.
"""

import json
import os
from pathlib import Path

REPORT_ENV = "FOOTNAV_FAULT_REPORT"
_HERE = Path(__file__).resolve().parent

_TRIED: list[str] = []
_HANDLED: list[str] = []
#: nodeid -> {"file", "fault", "outcome"} of every test under tests/faults (for the report).
_OUTCOMES: dict[str, dict] = {}


#: The rootdir the reports' node ids are relative to (set by pytest_configure).
_ROOT: list[Path] = []


def _ours(item) -> bool:
    return _HERE in Path(item.path).resolve().parents


def _ours_report(report) -> bool:
    return _HERE in (_ROOT[0] / report.nodeid.split("::")[0]).resolve().parents


def _worker(config) -> bool:
    """True in a pytest-xdist worker: its reports reach the controller, which counts and writes."""
    return hasattr(config, "workerinput")


def pytest_runtest_logreport(report):
    # logreport, not makereport: under pytest-xdist (pytest -n 2) it also runs in the controller,
    # with the workers' reports, so the summary counts every worker's cases
    fault = "fault" in report.keywords
    if report.when == "call" and fault:
        _TRIED.append(report.nodeid)
        if report.passed:
            _HANDLED.append(report.nodeid)
    if _ours_report(report):
        entry = _OUTCOMES.setdefault(
            report.nodeid, {"file": Path(report.nodeid.split("::")[0]).name, "fault": fault, "outcome": "not run"}
        )
        if report.skipped:
            entry["outcome"] = "skipped"
        elif report.failed:
            entry["outcome"] = "failed"
        elif report.when == "call" and entry["outcome"] == "not run":
            entry["outcome"] = "passed"


def pytest_configure(config):
    _ROOT[:] = [Path(config.rootpath)]
    config.addinivalue_line("markers", "fault: a bad-input case of the fault-injection suite")


def pytest_collection_finish(session):
    for item in session.items:
        if _ours(item):
            _OUTCOMES.setdefault(
                item.nodeid,
                {
                    "file": Path(item.path).name,
                    "fault": item.get_closest_marker("fault") is not None,
                    "outcome": "not run",
                },
            )


def pytest_sessionfinish(session, exitstatus):
    path = os.environ.get(REPORT_ENV)
    if path and not _worker(session.config):
        report = {"exitstatus": int(exitstatus), "tests": _OUTCOMES}
        Path(path).write_text(json.dumps(report, indent=1), encoding="utf-8")


def pytest_terminal_summary(terminalreporter):
    if _TRIED:
        terminalreporter.write_sep("-", "fault injection")
        terminalreporter.write_line(f"{len(_TRIED)} bad-input cases tried, {len(_HANDLED)} handled as specified")
