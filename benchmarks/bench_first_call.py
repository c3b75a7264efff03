"""The first call in a fresh process: with an empty numba cache, after ``footnav warmup``, and warm (issue 20).

Run:  python benchmarks/bench_first_call.py [--runs 3] [--kernels] [--against TREE]

Each run is a new Python process that imports footnav and runs the default pipeline on the demo
recording (what ``footnav demo`` computes), timed from the process's start to the result. "cold"
gives every run its own empty ``NUMBA_CACHE_DIR``: every kernel the call needs compiles. "after
warmup" runs ``footnav warmup`` into a new cache once (timed too), then the call from that cache,
as a user does after the README's set-up. The median of ``--runs`` runs of each is printed;
compare figures of one run of this script, since the machine's speed drifts from day to day.

``--kernels`` also prints, for one more cold call and one more ``footnav warmup`` (each in a
fresh process, empty cache), every compilation numba made (its ``numba:compile`` events,
:mod:`numba.core.event`), longest first: the kernel, its own seconds (without the kernels it
compiled meanwhile), its seconds with them, and its argument types; a kernel compiled for more
than one signature is flagged. Each timing also gives the processes' CPU time, which other jobs
on a shared machine move less than the wall clock. ``--against TREE`` runs every measurement of another source tree
(a ``git worktree`` of the base commit, say) in turn with this one's, so that the two are
compared on the same machine under the same load.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter

from _common import cpu_name

#: The call timed: import, load the demo recording, run the default pipeline on both feet.
CALL = "import footnav; from footnav.demo import demo_recording; footnav.make_pipeline().run(demo_recording())"
#: ``footnav warmup``, without its printing.
WARMUP = "from footnav.cli._warmup import warm_up; warm_up()"

#: Run in the child by ``--kernels``: record numba's compile events around ``code`` and print
#: them as JSON (start and end times of each compilation, the kernel's name, its arguments).
_RECORD = """
import json, sys, time
import numba.core.event as ev
rec = ev.RecordingListener()
ev.register("numba:compile", rec)
t0, c0 = time.perf_counter(), time.process_time()
exec(compile(sys.argv[1], "<timed>", "exec"))
total, cpu = time.perf_counter() - t0, time.process_time() - c0
stack, rows = [], []
for ts, e in rec.buffer:
    if e.is_start:
        stack.append([ts, e.data, 0.0])
        continue
    start, data, inner = stack.pop()
    whole = ts - start
    if stack:
        stack[-1][2] += whole
    f = data["dispatcher"].py_func
    rows.append([f"{f.__module__}.{f.__qualname__}", whole - inner, whole, str(data["args"])])
print(json.dumps({"total": total, "cpu": cpu, "rows": rows}))
"""


#: The source tree this script belongs to (its footnav is "this tree").
HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _env(cache_dir: str, tree: str | None) -> dict[str, str]:
    """The child's environment: its own cache, ``tree`` (default this one) first on the path."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir}
    env["PYTHONPATH"] = os.pathsep.join([tree or HERE, *filter(None, [os.environ.get("PYTHONPATH")])])
    return env


def _child(code: str) -> list[str]:
    """The child's command line, run with the tree as its working folder: ``-c`` puts that
    folder first on the path, so a child started in another tree would import that one's footnav."""
    return [sys.executable, "-W", "ignore", "-c", code]


def _timed(code: str, cache_dir: str, tree: str | None = None) -> tuple[float, float]:
    """Seconds a fresh process takes to run ``code`` with numba's cache in ``cache_dir``: wall
    clock, and its CPU time (user and system; less moved by other jobs on a shared machine)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(_child(code), env=_env(cache_dir, tree), cwd=tree or HERE, check=True, capture_output=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _compilations(code: str, tree: str | None = None) -> dict:
    """numba's compilations while a fresh process with an empty cache runs ``code``."""
    with tempfile.TemporaryDirectory() as cache:
        out = subprocess.run(
            [*_child(_RECORD), code],
            env=_env(cache, tree),
            cwd=tree or HERE,
            check=True,
            capture_output=True,
            text=True,
        )
    return json.loads(out.stdout.strip().splitlines()[-1])


def _print_compilations(title: str, found: dict) -> None:
    rows = sorted(found["rows"], key=lambda r: -r[1])
    twice = Counter(name for name, _ in {(r[0], r[3]) for r in rows})  # distinct signatures per kernel
    own = sum(r[1] for r in rows)
    print(
        f"\n{title}: {found['total']:.2f} s in all (CPU {found['cpu']:.2f} s), {own:.2f} s compiling, "
        f"{len(rows)} compilations "
        f"({sum(1 for n in twice if twice[n] > 1)} kernels for more than one signature: *)"
    )
    print("| kernel | own s | with callees s | arguments |")
    print("|---|---|---|---|")
    for name, mine, whole, args in rows:
        mark = " *" if twice[name] > 1 else ""
        print(f"| {name}{mark} | {mine:.2f} | {whole:.2f} | {args[:160]}{'...' if len(args) > 160 else ''} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=3, help="runs of each measurement (0: --kernels only)")
    ap.add_argument(
        "--only", choices=("cold", "warmup"), help="time only the cold call (and warm), or only warmup (and after)"
    )
    ap.add_argument(
        "--kernels", action="store_true", help="also print every kernel's compile time (cold call and warmup)"
    )
    ap.add_argument("--against", metavar="TREE", help="another source tree measured in turn with this one")
    args = ap.parse_args()
    print(
        f"machine: {cpu_name()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"load average {os.getloadavg()[0]:.1f}"
    )
    trees = [("this tree", None)] + (
        [(f"against {args.against}", os.path.abspath(args.against))] if args.against else []
    )
    times = {label: ([], [], [], []) for label, _ in trees}
    for _ in range(args.runs):
        for label, tree in trees:  # in turn: the machine's load changes from minute to minute
            cold, warmup, after, warm = times[label]
            if args.only != "warmup":
                with tempfile.TemporaryDirectory() as cache:
                    cold.append(_timed(CALL, cache, tree))
                    warm.append(_timed(CALL, cache, tree))  # the same cache, now filled by the cold call
            if args.only != "cold":
                with tempfile.TemporaryDirectory() as cache:
                    warmup.append(_timed(WARMUP, cache, tree))
                    after.append(_timed(CALL, cache, tree))
    for label, _ in trees if args.runs > 0 else ():
        cold, warmup, after, warm = times[label]
        print(f"\n{label}" if args.against else "")
        print("| first call | median s | runs (wall s) | median CPU s |")
        print("|---|---|---|---|")
        for name, xs in (
            ("cold (empty numba cache)", cold),
            ("footnav warmup, once", warmup),
            ("after footnav warmup", after),
            ("warm (the call's own cache)", warm),
        ):
            if not xs:
                continue
            walls = [w for w, _ in xs]
            print(
                f"| {name} | {statistics.median(walls):.2f} | {', '.join(f'{x:.2f}' for x in walls)} "
                f"| {statistics.median(c for _, c in xs):.2f} |"
            )
    print(f"load average after: {os.getloadavg()[0]:.1f}")
    if args.kernels:
        for label, tree in trees:
            _print_compilations(f"cold call, {label}", _compilations(CALL, tree))
            _print_compilations(f"footnav warmup, {label}", _compilations(WARMUP, tree))


if __name__ == "__main__":
    main()
