"""A run's ``meta["warnings"]`` holds that run's warnings: not another thread's, and not fewer
because the user filtered them from the screen (issue 14, deliverable 5)."""

from __future__ import annotations

import threading
import time
import warnings

import pytest

import footnav
from footnav import StanceDetector
from footnav.core.warning_log import recording

pytestmark = pytest.mark.fault


class _ChattyDetector(StanceDetector):
    """The threshold detector, warning once under its own tag and pausing so threads interleave."""

    name = "chatty"

    def __init__(self, *, tag: str = "a", pause_s: float = 0.0) -> None:
        self.tag = tag
        self.pause_s = pause_s

    def detect(self, imu):
        footnav.warn(f"chatty {self.tag} before", footnav.DataQualityWarning)
        time.sleep(self.pause_s)
        footnav.warn(f"chatty {self.tag} after", footnav.DataQualityWarning)
        return footnav.make_detector("threshold").detect(imu)


@pytest.fixture(scope="module")
def rec():
    return footnav.simulate("straight", seed=3, distance_m=10.0)


def _chatty_lines(result) -> list[str]:
    return [w for w in result.meta["warnings"] if "chatty" in w]


def test_concurrent_runs_record_only_their_own_warnings(rec):
    results: dict[str, object] = {}
    errors: list[BaseException] = []
    barrier = threading.Barrier(4)

    def run(tag: str) -> None:
        try:
            pipe = footnav.Pipeline(
                _ChattyDetector(tag=tag, pause_s=0.05),
                footnav.make_estimator("ekf"),
                footnav.make_fusion("independent"),
            )
            barrier.wait()
            results[tag] = pipe.run(rec.left)
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=run, args=(tag,)) for tag in "abcd"]
    with warnings.catch_warnings():  # set once, outside the threads: catch_warnings is process-global
        warnings.simplefilter("ignore")
        for th in threads:
            th.start()
        for th in threads:
            th.join()
    assert not errors
    for tag in "abcd":
        assert _chatty_lines(results[tag]) == [
            f"DataQualityWarning: chatty {tag} before",
            f"DataQualityWarning: chatty {tag} after",
        ]


def test_warnings_hidden_by_the_users_filter_are_still_recorded(rec):
    pipe = footnav.Pipeline(_ChattyDetector(tag="x"), footnav.make_estimator("ekf"), footnav.make_fusion("independent"))
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("ignore")
        result = pipe.run(rec.left)
    assert shown == []
    assert len(_chatty_lines(result)) == 2


def test_warnings_are_shown_once_each_not_replayed(rec):
    pipe = footnav.Pipeline(_ChattyDetector(tag="y"), footnav.make_estimator("ekf"), footnav.make_fusion("independent"))
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        pipe.run(rec.left)
    assert [str(w.message) for w in shown if "chatty" in str(w.message)] == ["chatty y before", "chatty y after"]


def test_nested_recordings_each_see_their_own_and_the_outer_sees_all():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with recording() as outer:
            footnav.warn("one")
            with recording() as inner:
                footnav.warn("two")
            footnav.warn("three")
    assert [w.message for w in inner] == ["two"]
    assert [w.message for w in outer] == ["one", "two", "three"]


def test_warn_outside_a_run_is_an_ordinary_warning():
    with pytest.warns(footnav.DataQualityWarning, match="plain"):
        footnav.warn("plain")


def test_a_quiet_recording_collects_without_showing_or_passing_up():
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        with recording() as outer:
            with recording(quiet=True) as inner:
                footnav.warn("hidden")
            footnav.warn("said")
    assert [w.message for w in inner] == ["hidden"]
    assert [w.message for w in outer] == ["said"]
    assert [str(w.message) for w in shown] == ["said"]
