"""``footnav warmup`` fills numba's cache, so that a later process compiles nothing (issue 20)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from footnav.cli import main
from footnav.cli._warmup import _tasks, warm_up
from footnav.core.errors import InvalidParameterError
from footnav.plugins.manager import get_registry

#: Every signature of every footnav kernel this process holds (compiled here or loaded from the
#: cache), found among all live objects: the kernels called from Python (a callee's code is in
#: its caller's cached machine code, so a process that loads the caller holds no callee).
_USED = textwrap.dedent(
    """
    def used():
        import gc
        from numba.core.registry import CPUDispatcher
        out = set()
        for kernel in gc.get_objects():
            if isinstance(kernel, CPUDispatcher) and kernel.py_func.__module__.startswith("footnav."):
                func = kernel.py_func
                out |= {f"{func.__module__}.{func.__qualname__}{sig}" for sig in kernel.signatures}
        return sorted(out)
    """
)
#: ``footnav warmup`` in one process, then the kernels it holds.
_WARMUP = _USED + "from footnav.cli._warmup import warm_up\nwarm_up(jobs=1)\nimport json\nprint(json.dumps(used()))\n"
#: Run after the warmup in a fresh process: what a user runs first, with numba's compile events
#: counted (each compiled function, nested ones included); then the kernels it holds.
_FIRST_RUN = _USED + textwrap.dedent(
    """
    import json
    from numba.core import event
    import footnav
    rec = footnav.simulate("straight", distance_m=20, seed=3)
    with event.install_recorder("numba:compile") as compiled:
        footnav.make_pipeline().run(rec)
        footnav.make_pipeline(estimator="madgwick").run(rec)
        for pipe in (
            footnav.make_pipeline(),
            footnav.make_pipeline("threshold", estimator_params={"smoother": "step"}),
        ):
            stream = pipe.online(feet=2)
            stream.push(left=rec.left, right=rec.right)
            stream.close()
        from footnav.demo import run_demo
        run_demo(plot=None)  # the README's set-up line runs the demo right after the warmup
    names = sorted({ev.data["dispatcher"].py_func.__qualname__ for _, ev in compiled.buffer if ev.is_start})
    print(json.dumps(names))
    print(json.dumps(used()))
    """
)


def test_warmup_runs_every_estimator_and_fusion():
    names = {name for name, _ in _tasks()}
    for e in get_registry():
        if e.kind == "estimator":
            assert f"estimator {e.name}" in names
        elif e.kind == "fusion" and e.name != "independent":
            assert f"fusion {e.name}" in names
    assert "online stream" in names


def test_warmup_command_names_the_cache(capsys):
    assert main(["warmup"]) == 0
    out = capsys.readouterr().out
    assert "estimator ekf" in out and "total" in out
    assert "numba cache: " in out


@pytest.mark.slow
def test_after_warmup_a_new_process_compiles_nothing():
    """Every kernel signature a user's first run holds (compiled or loaded) is one that
    ``footnav warmup`` holds too, so the warmup puts it in the cache; and after the warmup that
    run compiles nothing. Run in the suite's own numba folder (which other tests fill too: the
    first check does not depend on what the folder held before)."""
    env = dict(os.environ)
    root = Path(__file__).resolve().parents[1]
    env["PYTHONPATH"] = os.pathsep.join([str(root), env.get("PYTHONPATH", "")])
    warm = subprocess.run([sys.executable, "-c", _WARMUP], env=env, capture_output=True, text=True, timeout=900)
    assert warm.returncode == 0, warm.stderr[-3000:]
    warmed = set(json.loads(warm.stdout.strip().splitlines()[-1]))
    first = subprocess.run([sys.executable, "-c", _FIRST_RUN], env=env, capture_output=True, text=True, timeout=900)
    assert first.returncode == 0, first.stderr[-3000:]
    compiled, used = (json.loads(line) for line in first.stdout.strip().splitlines()[-2:])
    assert len(used) >= 10 and sorted(set(used) - warmed) == []
    assert compiled == []


def test_warmup_in_processes_runs_every_step_once_in_order(capsys):
    """With jobs > 1 the steps after the first run in new processes; every step is reported
    once, in the order of the steps, and the command says how many processes ran them."""
    steps = [name for name, _ in _tasks()]
    done = warm_up(jobs=2)
    assert [name for name, _ in done] == steps and all(seconds > 0 for _, seconds in done)
    assert main(["warmup", "--jobs", "2"]) == 0
    out = capsys.readouterr().out
    assert all(step in out for step in steps) and "in up to 2 processes" in out


@pytest.mark.parametrize("jobs", [0, -2])
def test_warmup_refuses_a_count_of_processes_that_is_none(jobs):
    with pytest.raises(InvalidParameterError, match="jobs"):
        warm_up(jobs=jobs)
