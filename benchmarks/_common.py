"""What the benchmark scripts share: the machine's name, best-of-N timing and the simulated walk."""

from __future__ import annotations

import platform
import time
from collections.abc import Callable
from typing import Any


def cpu_name() -> str:
    """The CPU's model name (Linux /proc/cpuinfo), else what platform knows."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "cpu"


def best_of(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """The shortest wall time of ``repeat`` calls of ``fn`` (s) and the last call's result."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


#: The simulator's default walking speed: stride length 1.4 m over a stride period of 1.1 s, m/s.
WALK_SPEED_MPS = 1.4 / 1.1


def straight_walk(minutes: float, rate_hz: float, seed: int = 0):
    """A simulated two-foot straight walk lasting about ``minutes`` at ``rate_hz``."""
    import footnav

    return footnav.simulate("straight", seed=seed, rate_hz=rate_hz, distance_m=minutes * 60 * WALK_SPEED_MPS)
