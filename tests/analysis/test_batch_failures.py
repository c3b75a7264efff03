"""A failing (recording, pipeline) pair is recorded and the batch goes on (issue 16, deliverable 3);
the bundled azure_fgo loads without the shared data folder."""

from __future__ import annotations

import csv
import functools
import importlib.util
import io
import math
import types

import pytest

import footnav
from footnav import CompositionError, StanceDetector
from footnav.analysis.batch import evaluate_many
from footnav.analysis.evaluation import EvaluationFailure, evaluate
from footnav.cli import main
from footnav.core.errors import DataNotFoundError, FootnavWarning, UnknownDatasetError
from footnav.data.datasets import DATA_ENV, load_dataset
from footnav.plugins.manager import build_registry, reset_registry

HAS_DASK = importlib.util.find_spec("dask") is not None and importlib.util.find_spec("distributed") is not None


class _ShortOnlyDetector(StanceDetector):
    """A plugin's detector with a bug: it raises on recordings longer than ``max_duration_s``."""

    name = "short-only"

    def __init__(self, *, max_duration_s: float = 30.0) -> None:
        self.max_duration_s = max_duration_s

    def detect(self, imu):
        if imu.duration_s > self.max_duration_s:
            raise ZeroDivisionError("division by zero in the plugin")
        return footnav.make_detector("threshold").detect(imu)


class _Interrupting(StanceDetector):
    name = "interrupting"

    def __init__(self, *, error: str = "KeyboardInterrupt") -> None:
        self.error = error

    def detect(self, imu):
        raise {"KeyboardInterrupt": KeyboardInterrupt, "MemoryError": MemoryError}[self.error]()


@pytest.fixture
def plugin():
    mod = types.ModuleType("buggy_plugin")

    def footnav_register_detectors(register):
        register(_ShortOnlyDetector)
        register(_Interrupting)

    mod.footnav_register_detectors = footnav.hookimpl(footnav_register_detectors)
    reset_registry(build_registry([mod], autoload=False))
    yield
    reset_registry()


@pytest.fixture(scope="module")
def walks():
    """Two two-foot walks, then one foot of the first (named 'left only')."""
    a = footnav.simulate("straight", distance_m=10.0, seed=1)
    b = footnav.simulate("straight", distance_m=12.0, seed=2)
    a, b = footnav.Recording(**{**a.__dict__, "name": "walk a"}), footnav.Recording(**{**b.__dict__, "name": "walk b"})
    one = footnav.Recording(left=a.left, truth_left=a.truth_left, name="left only")
    return [a, one, b]


def _pipes():
    return {"plain": footnav.make_pipeline(), "fused": footnav.make_pipeline(fusion="step-vector")}


def _check_one_failure(report, walks):
    assert [(f.recording, f.pipeline, f.error_type) for f in report.failures] == [
        ("left only", "fused", "CompositionError")
    ]
    assert "needs both feet" in report.failures[0].message
    runs = {(m.recording, m.pipeline) for m in report.metrics}
    assert runs == {
        ("walk a", "plain"),
        ("walk a", "fused"),
        ("left only", "plain"),
        ("walk b", "plain"),
        ("walk b", "fused"),
    }
    assert set(report.results) == runs


@pytest.mark.parametrize(
    "options",
    [
        {},
        {"n_jobs": 2},
        pytest.param({"backend": "dask"}, marks=pytest.mark.skipif(not HAS_DASK, reason="dask not installed")),
    ],
    ids=["serial", "loky", "dask"],
)
def test_a_failing_pair_is_recorded_and_the_others_run(walks, options):
    with pytest.warns(FootnavWarning, match=r"1 of 6 \(recording, pipeline\) pairs failed"):
        report = evaluate_many(_pipes(), walks, **options)
    _check_one_failure(report, walks)


def test_failures_survive_keep_results_false(walks):
    with pytest.warns(FootnavWarning):
        report = evaluate_many(_pipes(), walks, keep_results=False)
    assert len(report.failures) == 1 and report.results == {}


def test_the_table_shows_an_error_row_and_one_line_per_failure(walks):
    with pytest.warns(FootnavWarning):
        report = evaluate_many(_pipes(), walks)
    lines = report.to_text().splitlines()
    assert lines[0].split()[-2:] == ["plain", "fused"]
    error_rows = [line.split() for line in lines if line.split()[:3] == ["left", "only", "error"]]
    assert error_rows == [["left", "only", "error", "both", "CompositionError"]]
    # the good pair of the same recording is still there
    assert any(line.split()[:4] == ["left", "only", "ate_2d", "left"] for line in lines)
    assert lines[-2] == "failed (1 of 6 runs):"
    assert lines[-1].startswith("  left only / fused: CompositionError: fusion 'step-vector' needs both feet")


def test_the_csv_has_an_error_row_with_a_numeric_value(walks):
    with pytest.warns(FootnavWarning):
        report = evaluate_many(_pipes(), walks)
    rows = list(csv.DictReader(io.StringIO(report.to_csv())))
    assert list(rows[0]) == ["recording", "pipeline", "foot", "name", "value", "unit", "error"]
    errors = [r for r in rows if r["name"] == "error"]
    assert len(errors) == 1
    assert (errors[0]["recording"], errors[0]["pipeline"], errors[0]["foot"]) == ("left only", "fused", "both")
    assert math.isnan(float(errors[0]["value"]))
    assert errors[0]["error"].startswith("CompositionError: fusion 'step-vector' needs both feet")
    metric_rows = [r for r in rows if r["name"] != "error"]
    assert len(metric_rows) == len(report.metrics) and all(r["error"] == "" for r in metric_rows)
    assert all(math.isfinite(float(r["value"])) or r["value"] == "nan" for r in rows)


def test_without_failures_the_csv_keeps_six_columns(walks):
    report = evaluate_many(footnav.make_pipeline(), walks[:1])
    assert report.failures == ()
    assert report.to_csv().splitlines()[0] == "recording,pipeline,foot,name,value,unit"


def test_a_plugin_bug_is_recorded_with_its_type_and_named(plugin):
    short = footnav.simulate("straight", distance_m=10.0, seed=1)
    long = footnav.simulate("rectangle", seed=3)
    assert short.left.duration_s < 30.0 < long.left.duration_s
    pipe = footnav.make_pipeline("short-only", detector_params={"max_duration_s": 30.0})
    with pytest.warns(FootnavWarning, match="1 of 2"):
        report = evaluate_many({"buggy": pipe}, [short, long])
    (failure,) = report.failures
    assert failure.error_type == "PluginError"
    assert "short-only" in failure.message and "ZeroDivisionError" in failure.message
    assert "ZeroDivisionError" in failure.traceback
    assert {m.pipeline for m in report.metrics} == {"buggy"} and len(report.results) == 1
    with pytest.raises(KeyError, match="the run failed"):
        report.value("ate_2d", recording=failure.recording)


@pytest.mark.parametrize("error", ["KeyboardInterrupt", "MemoryError"])
def test_interrupts_and_memory_errors_end_the_batch(plugin, walks, error):
    pipe = footnav.make_pipeline("interrupting", detector_params={"error": error})
    with pytest.raises(KeyboardInterrupt if error == "KeyboardInterrupt" else MemoryError):
        evaluate_many({"x": pipe}, walks)


def test_a_recording_that_cannot_be_read_or_made_is_a_failure(walks, tmp_path):
    def broken():
        raise DataNotFoundError("gone")

    recordings = [walks[0], tmp_path / "missing.csv", functools.partial(footnav.simulate, "no-such-scenario"), broken]
    with pytest.warns(FootnavWarning, match="3 of 4"):
        report = evaluate_many({"plain": footnav.make_pipeline()}, recordings)
    labels = [f.recording for f in report.failures]
    assert labels == [str(tmp_path / "missing.csv"), "simulate('no-such-scenario')", "broken"]
    assert report.failures[0].error_type == "DataNotFoundError"
    assert {m.recording for m in report.metrics} == {"walk a"}


def test_a_wrong_recording_type_is_still_raised_at_once(walks):
    with pytest.raises(footnav.InvalidParameterError, match="a recording must be"):
        evaluate_many(footnav.make_pipeline(), [walks[0], 42])


def test_on_error_raise_ends_the_batch(walks):
    with pytest.raises(CompositionError):
        evaluate_many(_pipes(), walks, on_error="raise")


def test_evaluate_raises_by_default_and_records_when_asked(walks):
    one = walks[1]
    pipe = footnav.make_pipeline(fusion="step-vector")
    with pytest.raises(CompositionError):
        evaluate(pipe, one)
    with pytest.warns(FootnavWarning, match="the run failed"):
        report = evaluate(pipe, one, on_error="record", pipeline_name="fused")
    assert report.metrics == ()
    assert report.failures == (EvaluationFailure("left only", "fused", "CompositionError", report.failures[0].message),)
    with pytest.raises(footnav.InvalidParameterError, match="on_error"):
        evaluate(pipe, one, on_error="ignore")


# --- the command line ------------------------------------------------------------------------


@pytest.fixture
def no_shared_data(tmp_path, monkeypatch):
    """An empty data folder in $FOOTNAV_DATA: the shared recordings are absent."""
    empty = tmp_path / "empty-data"
    empty.mkdir()
    monkeypatch.setenv(DATA_ENV, str(empty))
    return empty


def test_bundled_azure_fgo_loads_without_shared_data(no_shared_data):
    rec = load_dataset("azure_fgo")
    assert rec.name == "azure_fgo" and rec.right is not None and rec.truth_left is not None
    assert load_dataset("azure_fgo", no_shared_data / "nowhere").left.n_samples == rec.left.n_samples


def test_other_datasets_still_need_the_shared_data(no_shared_data):
    with pytest.raises(DataNotFoundError, match="short_walk.csv"):
        load_dataset("xio_short")
    with pytest.raises(UnknownDatasetError, match="pyshoe_1"):
        load_dataset("pyshoe_1")
    with pytest.raises(DataNotFoundError, match="shared data folder not found"):
        load_dataset("xio_short", no_shared_data / "nowhere")


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_cli_evaluate_bundled_azure_fgo_without_shared_data(no_shared_data, capsys):
    assert main(["evaluate", "--dataset", "azure_fgo"]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines()]
    assert ["azure_fgo", "ate_2d", "left", "m"] in [r[:4] for r in rows]


@pytest.mark.filterwarnings("ignore::footnav.DataQualityWarning")
def test_cli_evaluate_prints_every_good_row_and_exits_1(no_shared_data, tmp_path, capsys):
    walk = tmp_path / "walk"
    assert main(["simulate", "straight", "--seed", "1", "--out", str(walk)]) == 0
    (tmp_path / "plain.toml").write_text(footnav.make_pipeline().to_toml(), encoding="utf-8")
    (tmp_path / "fused.toml").write_text(footnav.make_pipeline(fusion="step-vector").to_toml(), encoding="utf-8")
    capsys.readouterr()
    table = tmp_path / "r.csv"
    argv = [
        "evaluate",
        "--dataset",
        "azure_fgo",
        str(walk / "left.csv"),
        "--pipeline",
        str(tmp_path / "plain.toml"),
        "--pipeline",
        str(tmp_path / "fused.toml"),
        "--csv",
        str(table),
    ]
    assert main(argv) == 1
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert lines[0].split()[-2:] == ["plain", "fused"]
    rows = {tuple(line.split()[:3]): line.split()[4:] for line in lines[2:] if line.strip()}
    # both pipelines on azure_fgo, and the good pipeline on the one-foot walk
    assert len(rows[("azure_fgo", "ate_2d", "left")]) == 2
    assert len(rows[("azure_fgo", "final_separation", "both")]) == 2
    one_foot = next(r for (rec, name, _), r in rows.items() if name == "path_length" and rec != "azure_fgo")
    assert len(one_foot) == 1
    failed = [line for line in lines if "CompositionError: fusion 'step-vector' needs both feet" in line]
    assert len(failed) == 1 and failed[0].startswith("  ") and "/ fused:" in failed[0]
    assert "1 of 4" in captured.err
    written = list(csv.DictReader(io.StringIO(table.read_text(encoding="utf-8"))))
    assert [r["pipeline"] for r in written if r["name"] == "error"] == ["fused"]
    # the table it wrote is recognised as footnav's: --force may replace it
    assert main([*argv, "--force"]) == 1
