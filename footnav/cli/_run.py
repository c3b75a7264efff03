"""``footnav run``: a pipeline on recordings of one or both feet, in any format footnav reads,
results written to a claimed output folder."""

from __future__ import annotations

import argparse
import sys
from contextlib import ExitStack, nullcontext

from footnav.cli._common import EXIT_OK, _claim_figure, _format_table, _plot_trajectories
from footnav.core.errors import FootnavError


def _pipeline_from_args(args: argparse.Namespace):
    from footnav.pipeline.factory import load_pipeline, make_pipeline

    sync = getattr(args, "sync", None)
    if args.pipeline:
        if any(getattr(args, k, None) for k in ("detector", "estimator", "fusion", "heading_aid")):
            raise FootnavError("give either --pipeline or --detector/--estimator/--fusion/--heading-aid, not both")
        pipeline = load_pipeline(args.pipeline)
        if sync is not None:
            if pipeline.sync is not None:
                raise FootnavError(f"{args.pipeline} has a [sync] table already; give it or --sync, not both")
            return make_pipeline(
                pipeline.detector, pipeline.estimator, pipeline.fusion, sync=sync, heading_aid=pipeline.heading_aid
            )
        return pipeline
    return make_pipeline(
        args.detector or "adaptive",
        args.estimator or "ekf",
        args.fusion or "independent",
        sync=sync,
        heading_aid=getattr(args, "heading_aid", None),
    )


#: CLI flag -> reader option (footnav.data.io.load.reader_options says which reader takes which).
READER_FLAGS = {
    "format": "--format",
    "acc_unit": "--acc-unit",
    "gyr_unit": "--gyr-unit",
    "t_unit": "--t-unit",
    "rate_hz": "--rate-hz",
    "columns": "--columns",
    "drop_duplicates": "--drop-duplicates",
}


def _read_recording(path: str, args: argparse.Namespace):
    """Read ``path`` in any format footnav reads, with the reader options given on the command
    line; an option the file's reader does not take is an error naming both."""
    from footnav.data.io.load import guess_format, load, reader_options

    given = {k: getattr(args, k) for k in READER_FLAGS if k != "format" and getattr(args, k, None) not in (None, False)}
    fmt = args.format or guess_format(path)[0]
    accepted = reader_options(fmt)
    refused = [READER_FLAGS[k] for k in given if k not in accepted]
    if refused:
        takes = ", ".join(READER_FLAGS[k] for k in READER_FLAGS if k in accepted) or "none"
        raise FootnavError(
            f"{path}: {' and '.join(refused)} {'does' if len(refused) == 1 else 'do'} not apply to {fmt} files (the "
            f"format fixes them); options this format takes: {takes}"
        )
    return load(path, format=args.format, **given)


def _run_inputs(args: argparse.Namespace):
    """The left and right feet from --left / --right: one file per foot, or one two-foot
    recording (gaitmap, IPOL, azure_fgo ...) given as --left; and what the report draws beside
    the result (the feet's gyroscopes, the truth a recording holds)."""
    from types import SimpleNamespace

    rec = _read_recording(args.left, args)
    if args.right is None:
        if rec.right is not None:
            print(f"footnav: {args.left} holds both feet ({rec.meta.get('format')}): running both", file=sys.stderr)
        return rec.left, rec.right, rec
    if rec.right is not None:
        raise FootnavError(f"{args.left} holds both feet already; give it alone, without --right")
    other = _read_recording(args.right, args)
    if other.right is not None:
        raise FootnavError(f"{args.right} holds both feet; give it alone as --left")
    seen = SimpleNamespace(
        name=None, left=rec.left, right=other.left, truth_left=rec.truth_left, truth_right=other.truth_left
    )
    return rec.left, other.left, seen


def cmd_run(args: argparse.Namespace) -> int:
    from footnav.core.warning_log import recording
    from footnav.data.output import claim_output
    from footnav.data.results import with_warnings, write_results

    pipeline = _pipeline_from_args(args)
    inputs = [p for p in (args.left, args.right, args.pipeline) if p]
    with ExitStack() as claims:
        # every output is claimed before any work, and appears only when all of it succeeded
        out_claim = claims.enter_context(claim_output(args.out, force=args.force, inputs=inputs, what="output folder"))
        plot_claim = _claim_figure(claims, args.plot, args.force, inputs)
        with recording() as read_warnings:  # shown as they happen, and kept for summary.json
            left, right, seen = _run_inputs(args)
        result = with_warnings(pipeline.run(left, right), read_warnings)
        summary = {"left_path_length_m": result.left.path_length_m, "left_stances": result.stance_left.n_stances}
        if result.right is not None:
            summary["right_path_length_m"] = result.right.path_length_m
            summary["right_stances"] = result.stance_right.n_stances
        with plot_claim.staged() if plot_claim else nullcontext() as figure:
            if figure is not None:
                _plot_trajectories(result, None, figure)
            out = write_results(
                result,
                out_claim,
                force=args.force,
                summary=summary,
                pipeline_toml=pipeline.to_toml(),
                html=True,
                recording=seen,
            )
    print(_format_table(("quantity", "value"), list(summary.items())))
    print(f"results written to {out}")
    if plot_claim:
        print(f"figure: {args.plot}")
    return EXIT_OK
