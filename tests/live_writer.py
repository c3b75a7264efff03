"""A sensor logger for the tests of ``footnav follow``: appends the rows of a footnav CSV to a file
in bursts, flushing each, as a logger writes a sensor's samples.

    python tests/live_writer.py SOURCE TARGET [--burst N] [--pause-s S] [--hold-after-s T --go FILE]

The units line and the header come first, then ``--burst`` rows every ``--pause-s`` seconds. With
``--hold-after-s``, the writer stops after the last row with t <= T and waits until the file
``--go`` exists before it writes the rest: a test that must see something happen *while* the walk
is still being written (a step printed, a figure drawn) waits for that event, then creates the go
file, so the outcome does not depend on how fast either process runs.
"""

from __future__ import annotations

import argparse
import os
import time


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("source")
    p.add_argument("target")
    p.add_argument("--burst", type=int, default=40)
    p.add_argument("--pause-s", type=float, default=0.15)
    p.add_argument("--hold-after-s", type=float)
    p.add_argument("--go")
    args = p.parse_args()
    with open(args.source) as f:
        lines = f.read().splitlines(keepends=True)
    header, rows = lines[:2], lines[2:]
    hold = len(rows)
    if args.hold_after_s is not None:
        hold = sum(float(row.split(",", 1)[0]) <= args.hold_after_s for row in rows)
    with open(args.target, "w") as out:
        out.writelines(header)
        out.flush()
        for a in range(0, len(rows), args.burst):
            b = min(a + args.burst, len(rows))
            if a < hold < b:  # the burst that crosses the hold point stops at it
                out.writelines(rows[a:hold])
                out.flush()
                a = hold
            if a == hold and hold < len(rows):
                while not os.path.exists(args.go):  # the test's event, not a duration
                    time.sleep(0.01)
            out.writelines(rows[a:b])
            out.flush()
            time.sleep(args.pause_s)


if __name__ == "__main__":
    main()
