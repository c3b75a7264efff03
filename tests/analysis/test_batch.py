"""Batch evaluation: serial, local processes (joblib loky) and Dask give the same report."""

import numpy as np
import pytest

import footnav
from footnav import InvalidParameterError
from footnav.analysis.batch import evaluate_many


def _comparable(report):
    """Every metric but the wall-clock runtime, in report order."""
    return [(m.recording, m.pipeline, m.foot, m.name, m.unit, m.value) for m in report.metrics if m.name != "runtime"]


@pytest.fixture(scope="module")
def work():
    recs = [footnav.simulate("straight", seed=s, distance_m=8.0, standstill_s=1.0) for s in range(3)]
    recs = [footnav.core.types.Recording(**{**r.__dict__, "name": f"walk-{i}"}) for i, r in enumerate(recs)]
    pipes = {
        "default": footnav.make_pipeline(),
        "glrt-fwd": footnav.make_pipeline("glrt", "ekf", estimator_params={"smoother": "none"}),
    }
    return pipes, recs


@pytest.fixture(scope="module")
def serial(work):
    pipes, recs = work
    return evaluate_many(pipes, recs)


def test_serial_report_is_in_recording_then_pipeline_order(work, serial):
    pipes, recs = work
    order = []
    for m in serial.metrics:
        key = (m.recording, m.pipeline)
        if not order or order[-1] != key:
            order.append(key)
    assert order == [(r.name, p) for r in recs for p in pipes]


def test_local_processes_give_the_serial_report(work, serial):
    pipes, recs = work
    parallel = evaluate_many(pipes, recs, n_jobs=2, progress=False)
    assert _comparable(parallel) == _comparable(serial)


def test_dask_local_cluster_gives_the_serial_report(work, serial):
    distributed = pytest.importorskip("dask.distributed")
    pipes, recs = work
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        with distributed.Client(cluster):
            report = evaluate_many(pipes, recs, backend="dask", progress=False)
    assert _comparable(report) == _comparable(serial)
    np.testing.assert_allclose(
        report.results[("walk-1", "default")].left.position, serial.results[("walk-1", "default")].left.position
    )


def test_bad_arguments_are_named():
    rec = footnav.simulate("straight", distance_m=3.0)
    with pytest.raises(InvalidParameterError, match="backend"):
        evaluate_many([footnav.make_pipeline()], [rec], backend="spark")
    with pytest.raises(InvalidParameterError, match="n_jobs"):
        evaluate_many([footnav.make_pipeline()], [rec], n_jobs=0)
    with pytest.raises(InvalidParameterError, match="unique"):
        evaluate_many([footnav.make_pipeline(), footnav.make_pipeline()], [rec])
