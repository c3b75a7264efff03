"""The sliding windows of footnav/nav/windows.py."""

from __future__ import annotations

import pytest


# mutant: win-length-round
# win-length-round: the window is the odd number of samples nearest window_s * rate_hz, ties upward
@pytest.mark.parametrize(
    ("window_s", "rate_hz", "expected"),
    [
        (0.079, 100.0, 7),
        (0.08, 100.0, 9),
        (0.069, 100.0, 7),
        (0.04, 1 / 0.01, 5),
        (0.05, 200.0, 11),
        (0.059, 200.0, 11),
    ],
)
def test_window_is_the_nearest_odd_sample_count(window_s, rate_hz, expected):
    from footnav.nav.windows import window_samples

    assert window_samples(window_s, rate_hz, 10_000) == expected
