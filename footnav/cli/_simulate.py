"""``footnav simulate``: a simulated two-foot walk written as footnav CSV with its truth."""

from __future__ import annotations

import argparse
from pathlib import Path as FilePath

from footnav.cli._common import EXIT_OK
from footnav.core.errors import FootnavError


def cmd_simulate(args: argparse.Namespace) -> int:
    from footnav.data.io.footnav_csv import write_footnav_csv, write_footnav_truth
    from footnav.data.output import claim_output
    from footnav.data.simulate import simulate

    out = FilePath(args.out)
    options = dict(args.set or [])
    if args.segments is not None:
        options["segments"] = args.segments
    if args.scenario == "path" and "segments" not in options:
        raise FootnavError("the path scenario needs --segments, e.g. --segments 10:90,5:-90,3:0 (metres:turn degrees)")
    with claim_output(out, force=args.force, what="output folder") as claim:
        rec = simulate(args.scenario, seed=args.seed, rate_hz=args.rate_hz, **options)
        with claim.staged() as tmp:
            for side, imu, truth in (("left", rec.left, rec.truth_left), ("right", rec.right, rec.truth_right)):
                write_footnav_csv(imu, tmp / f"{side}.csv")
                write_footnav_truth(truth, tmp / f"{side}_truth.csv")
    print(f"simulated {args.scenario!r} walk, {rec.left.duration_s:.1f} s at {args.rate_hz:g} Hz, written to {out}")
    return EXIT_OK
