"""Counts the fault-injection cases and prints "N bad-input cases tried, N handled as specified"."""

import pytest

_TRIED: list[str] = []
_HANDLED: list[str] = []


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if report.when == "call" and item.get_closest_marker("fault") is not None:
        _TRIED.append(item.nodeid)
        if report.passed:
            _HANDLED.append(item.nodeid)


def pytest_configure(config):
    config.addinivalue_line("markers", "fault: a bad-input case of the fault-injection suite")


def pytest_terminal_summary(terminalreporter):
    if _TRIED:
        terminalreporter.write_sep("-", "fault injection")
        terminalreporter.write_line(f"{len(_TRIED)} bad-input cases tried, {len(_HANDLED)} handled as specified")
