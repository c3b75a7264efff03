"""Every warning the command line prints is in the result it writes (issue 34): the reader's
(clipping, an accelerometer off g) as well as the pipeline's."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import footnav
from footnav.data.io.footnav_csv import write_footnav_csv

PREFIX = "footnav: warning: "


def _printed(stderr: str) -> list[str]:
    return [line[len(PREFIX) :] for line in stderr.splitlines() if line.startswith(PREFIX)]


def test_run_writes_every_printed_warning_to_summary_json(tmp_path):
    rec = footnav.simulate("straight", seed=2, distance_m=15.0, rate_hz=100.0)
    acc = rec.left.acc * 1.075  # 7.5 % off g at rest: a reader's warning
    acc[300:305, 2] = 160.0  # a plateau at the largest reading: clipping
    path = write_footnav_csv(replace(rec.left, acc=acc), tmp_path / "left.csv")
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(Path(__file__).resolve().parents[1]), os.environ.get("PYTHONPATH", "")]),
    }
    done = subprocess.run(
        [sys.executable, "-m", "footnav.cli", "run", "--left", str(path), "--out", str(tmp_path / "out")],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    printed = _printed(done.stderr)
    assert any("off g" in w for w in printed) and any("clipping" in w for w in printed), done.stderr
    recorded = json.loads((tmp_path / "out" / "summary.json").read_text())["provenance"]["warnings"]
    for message in printed:
        assert any(r.endswith(message) for r in recorded), (message, recorded)
    assert len(recorded) == len(set(recorded))


def test_write_report_lists_given_and_run_warnings_once(tmp_path):
    from footnav.analysis.evaluation import evaluate
    from footnav.data.results import merge_warnings, write_report

    assert merge_warnings(["a", "b"], ["b", "c"]) == ["a", "b", "c"]
    rec = footnav.simulate("straight", seed=1, distance_m=10.0)
    report = evaluate(footnav.make_pipeline(), rec)
    write_report(report, tmp_path / "rep", warnings=["DataQualityWarning: read"])
    doc = json.loads((tmp_path / "rep" / "report.json").read_text())
    assert doc["warnings"][0] == "DataQualityWarning: read"


def test_small_batches_run_serially_large_ones_and_paths_not():
    from footnav.analysis.batch import SERIAL_BELOW_SAMPLES, serial_is_faster

    rec = footnav.simulate("straight", seed=1, distance_m=10.0)
    assert "under" in serial_is_faster([rec, rec], 2, 2)
    assert serial_is_faster([rec], 1, 1) is None  # serial asked for
    assert serial_is_faster(["walk.csv"], 1, 2) is None  # the workers read it: not counted here
    n = rec.left.n_samples + rec.right.n_samples
    assert serial_is_faster([rec] * (SERIAL_BELOW_SAMPLES // n + 1), 1, 2) is None


def test_the_python_route_lists_the_reader_s_warnings_in_the_run_s_meta(tmp_path):
    import warnings

    rec = footnav.simulate("straight", seed=2, distance_m=15.0, rate_hz=100.0)
    path = write_footnav_csv(replace(rec.left, acc=rec.left.acc * 1.075), tmp_path / "left.csv")
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        loaded = footnav.load(path)
        result = footnav.make_pipeline().run(loaded.left)
    said = [f"{w.category.__name__}: {w.message}" for w in shown if issubclass(w.category, footnav.DataQualityWarning)]
    assert any("off g" in s for s in said)
    assert loaded.left.meta["read_warnings"] == [s for s in said if "off g" in s]
    for s in said:  # every warning shown, reading and running, is in the run's meta
        assert s in result.meta["warnings"], (s, result.meta["warnings"])
    assert len(result.meta["warnings"]) == len(set(result.meta["warnings"]))
