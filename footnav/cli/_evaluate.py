"""``footnav evaluate`` (pipelines measured against the truth of recordings) and
``footnav compare-detectors`` (stance detectors compared on one recording)."""

from __future__ import annotations

import argparse
import logging
from contextlib import ExitStack
from pathlib import Path as FilePath

from footnav.cli._common import EXIT_INTERNAL, EXIT_OK, REPORT_CSV_HEADER, _claim_figure, _require_matplotlib
from footnav.core.errors import FootnavError


def cmd_evaluate(args: argparse.Namespace) -> int:
    import sys

    from footnav.analysis.batch import evaluate_many, serial_is_faster
    from footnav.core.warning_log import recording
    from footnav.data.datasets import load_dataset
    from footnav.data.io import load
    from footnav.data.output import claim_output, csv_signature
    from footnav.data.results import write_report
    from footnav.pipeline.factory import load_pipeline, make_pipeline

    if not args.dataset and not args.recordings:
        raise FootnavError("nothing to evaluate: give --dataset NAME and/or recording paths")
    inputs = [*args.recordings, *args.pipeline]
    with ExitStack() as claims:
        out_claim = (
            claims.enter_context(claim_output(args.out, force=args.force, inputs=inputs, what="output folder"))
            if args.out
            else None
        )
        # a table with failed pairs has a last column "error" (EvaluationReport.to_csv)
        ours = [csv_signature(REPORT_CSV_HEADER), csv_signature(REPORT_CSV_HEADER + ",error")]
        csv_claim = (
            claims.enter_context(
                claim_output(
                    args.csv,
                    kind="file",
                    force=args.force,
                    inputs=inputs,
                    signature=lambda path: any(s(path) for s in ours),
                    what="table",
                )
            )
            if args.csv
            else None
        )
        plot_claim = None
        if args.plot:
            _require_matplotlib()
            plot_claim = claims.enter_context(
                claim_output(args.plot, force=args.force, inputs=inputs, what="figure folder")
            )
        pipelines = [(FilePath(p).stem, load_pipeline(p)) for p in args.pipeline] or [("default", make_pipeline())]
        # every warning shown from here on (reading: clipping, off g; the runs; the truth checks) is
        # also written to report.json; the runs' own are in their meta as well (parallel workers')
        with recording() as shown:
            recordings = [load_dataset(name, args.data_dir) for name in args.dataset]
            recordings += [load(path) for path in args.recordings]
            backend = "dask" if args.dask_scheduler else "loky"
            jobs, serial_why = (
                args.jobs,
                None if args.dask_scheduler else serial_is_faster(recordings, len(pipelines), args.jobs),
            )
            if serial_why:
                jobs = 1
                print(f"footnav evaluate: running serially, not --jobs {args.jobs}: {serial_why}", file=sys.stderr)
            logging.getLogger("footnav").info(
                "evaluating %d pipeline(s) on %d recording(s)", len(pipelines), len(recordings)
            )
            report = evaluate_many(pipelines, recordings, n_jobs=jobs, backend=backend, scheduler=args.dask_scheduler)
        batch = {"backend": backend, "jobs_asked": args.jobs, "jobs_used": jobs, "serial_because": serial_why}
        with ExitStack() as staged:
            figures = staged.enter_context(plot_claim.staged()) if plot_claim else None
            if figures is not None:
                from footnav.analysis.plot import has_path_truth, plot_position_errors, plot_trajectories

                by_name = {rec.name: rec for rec in recordings}
                for (rec_name, pname), result in report.results.items():
                    safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in f"{rec_name}-{pname}")
                    rec = by_name.get(rec_name)
                    plot_trajectories(result, rec, figures / f"{safe}.png")
                    if has_path_truth(rec):  # no empty error axes for a recording without a path truth
                        plot_position_errors(result, rec, figures / f"{safe}-errors.png")
            if csv_claim:
                staged.enter_context(csv_claim.staged()).write_text(report.to_csv(), encoding="utf-8")
            if out_claim:
                write_report(
                    report,
                    out_claim,
                    pipelines={name: pipe.to_toml() for name, pipe in pipelines},
                    warnings=shown,
                    batch=batch,
                    html=True,
                    recordings=recordings,
                )
    print(report.to_text())
    if args.csv:
        print(f"table written to {args.csv}")
    if args.out:
        print(f"report written to {args.out}")
    if plot_claim:
        print(f"figures written to {args.plot}")
    return EXIT_INTERNAL if report.failures else EXIT_OK  # the failures are listed under the table


def cmd_compare_detectors(args: argparse.Namespace) -> int:
    from footnav.data.output import claim_output, csv_signature

    sources = [x for x in (args.recording, args.dataset, args.simulate) if x]
    if len(sources) != 1:
        raise FootnavError("give exactly one of RECORDING, --dataset NAME or --simulate SCENARIO")
    inputs = [args.recording] if args.recording else []
    with ExitStack() as claims:
        csv_claim = (
            claims.enter_context(
                claim_output(
                    args.csv,
                    kind="file",
                    force=args.force,
                    inputs=inputs,
                    signature=csv_signature(REPORT_CSV_HEADER),
                    what="table",
                )
            )
            if args.csv
            else None
        )
        plot_claim = _claim_figure(claims, args.plot, args.force, inputs)
        return _compare(args, csv_claim, plot_claim)


def _compare(args: argparse.Namespace, csv_claim, plot_claim) -> int:
    from footnav.analysis.comparison import compare_detectors
    from footnav.data.datasets import load_dataset
    from footnav.data.io import load
    from footnav.data.simulate import simulate

    if args.recording:
        rec = load(args.recording)
    elif args.dataset:
        rec = load_dataset(args.dataset, args.data_dir)
    else:
        rec = simulate(args.simulate, seed=args.seed, rate_hz=args.rate_hz)
    names = [d.strip() for d in args.detectors.split(",") if d.strip()] if args.detectors else None
    comparison = compare_detectors(rec, names, tolerance_s=args.tolerance_s)
    with ExitStack() as staged:
        if csv_claim:
            staged.enter_context(csv_claim.staged()).write_text(comparison.to_csv(), encoding="utf-8")
        if plot_claim:
            comparison.plot(
                staged.enter_context(plot_claim.staged()), seconds=tuple(args.seconds) if args.seconds else None
            )
    print(comparison.to_text())
    if csv_claim:
        print(f"table written to {args.csv}")
    if plot_claim:
        print(f"figure: {args.plot}")
    return EXIT_OK
