"""Bad truths that evaluation used to score silently (issue 30, deliverable 5): positions in mm or cm,
times in ms, a truth covering part of the walk, a mirrored (left-handed) truth. Each must give its
error (InvalidInputError naming the foot, the ratio and the conversion) or its recorded warning; a
genuine truth gives neither. The bad truths are the simulator's own, changed one way each."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

import footnav
from footnav.analysis.batch import evaluate_many
from footnav.analysis.evaluation import evaluate
from footnav.cli import main
from footnav.core.errors import DataQualityWarning, InvalidInputError
from footnav.core.types import FootTruth, Recording
from footnav.core.warning_log import recording as recorded_warnings
from footnav.data.io.footnav_csv import write_footnav_csv, write_footnav_truth

pytestmark = pytest.mark.fault

CHECKS = ["time_span", "coverage", "scale", "mirror_2d", "tilt_3d", "height"]


@pytest.fixture(scope="module")
def walk() -> Recording:
    # a small rectangle (turns: a mirror image is not the walk itself), both feet, ~22 s
    return footnav.simulate("rectangle", seed=5, width_m=8.0, height_m=4.0)


@pytest.fixture(scope="module")
def pipe():
    return footnav.make_pipeline()


def with_left_truth(walk: Recording, **changes) -> Recording:
    """The walk's left foot alone, with its truth changed (t, position)."""
    truth = replace(walk.truth_left, **changes) if changes else walk.truth_left
    return Recording(left=walk.left, truth_left=truth, name="bad")


def left_truth_part(walk: Recording, keep: np.ndarray) -> Recording:
    tr = walk.truth_left
    return with_left_truth(walk, t=tr.t[keep], position=tr.position[keep], quaternion=None, velocity=None)


def test_genuine_truth_passes_every_check_and_records_its_figures(walk, pipe):
    with recorded_warnings(quiet=True) as log:
        report = evaluate(pipe, walk, pipeline_name="p")
    assert not [w for w in log if "truth" in w.message]
    assert report.warnings == () and "truth warnings" not in report.to_text()
    assert [(c.foot, c.name) for c in report.checks] == [(f, n) for f in ("left", "right") for n in CHECKS]
    assert all(c.status == "ok" for c in report.checks)
    figures = {(c.foot, c.name): c.value for c in report.checks}
    for foot in ("left", "right"):
        assert figures[foot, "time_span"] == pytest.approx(1.0)
        assert figures[foot, "coverage"] == pytest.approx(1.0)
        assert figures[foot, "scale"] == pytest.approx(1.0, abs=0.05)
        assert figures[foot, "mirror_2d"] > 10  # a reflection fits far worse than a rotation
        assert figures[foot, "tilt_3d"] < 5


@pytest.mark.parametrize("factor, unit", [(1000.0, "mm"), (100.0, "cm")])
def test_truth_in_mm_or_cm_is_an_error_naming_the_ratio_and_the_conversion(walk, pipe, factor, unit):
    bad = with_left_truth(walk, position=walk.truth_left.position * factor)
    with pytest.raises(InvalidInputError) as exc:
        evaluate(pipe, bad)
    msg = str(exc.value)
    assert exc.value.field == "truth_left"
    assert "the left foot's truth of 'bad'" in msg
    ratio = float(msg.split("ratio ")[1].split(",")[0])
    assert ratio == pytest.approx(factor, rel=0.05)
    assert f"it looks like {unit}" in msg
    assert f"convert the truth's positions to metres (FootTruth.position in m, divide by {factor:.4g})" in msg


def test_truth_times_in_ms_are_an_error_naming_the_unit(walk, pipe):
    bad = with_left_truth(walk, t=walk.truth_left.t * 1000.0)
    with pytest.raises(
        InvalidInputError, match=r"1000 times the recording's .* its times look like ms .*divide by 1000"
    ):
        evaluate(pipe, bad)


def test_truth_on_another_clock_is_an_error(walk, pipe):
    bad = with_left_truth(walk, t=walk.truth_left.t + 1000.0)
    with pytest.raises(
        InvalidInputError, match=r"covers 0\.000 s .* with 0 truth point\(s\) inside the recording: nothing to score"
    ):
        evaluate(pipe, bad)


def test_truth_of_half_the_walk_warns_and_is_recorded(walk, pipe):
    tr = walk.truth_left
    bad = left_truth_part(walk, tr.t <= tr.t[0] + 0.5 * (tr.t[-1] - tr.t[0]))
    with pytest.warns(
        DataQualityWarning, match=r"covers .* % of the estimate's distance .*the errors are of that part only"
    ):
        report = evaluate(pipe, bad, pipeline_name="p")
    (warned,) = report.warnings
    assert (warned.foot, warned.name, warned.status) == ("left", "coverage", "warning")
    assert 0.4 < warned.value < 0.6
    text = report.to_text()
    assert "truth warnings (1):" in text and "bad / p / left: coverage = 0." in text
    assert np.isfinite(report.value("ate_2d"))  # still scored, on the covered half


def test_truth_of_two_seconds_of_walking_warns(walk, pipe):
    tr = walk.truth_left
    mid = tr.t[0] + 0.5 * (tr.t[-1] - tr.t[0])
    bad = left_truth_part(walk, (tr.t >= mid) & (tr.t <= mid + 2.0))
    with pytest.warns(DataQualityWarning, match=r"covers 2\.000 s of the recording's"):
        report = evaluate(pipe, bad)
    assert [c.name for c in report.warnings] == ["coverage"]
    assert report.warnings[0].value < 0.2


def test_truth_of_two_seconds_of_standing_is_an_error(walk, pipe):
    # the walk starts standing: a truth of its first 2 s covers none of the distance
    tr = walk.truth_left
    bad = left_truth_part(walk, tr.t <= tr.t[0] + 2.0)
    with pytest.raises(InvalidInputError, match=r"and 0\.0 % of the estimate's distance .*nothing to score"):
        evaluate(pipe, bad)


def test_mirrored_planar_truth_warns_and_the_3d_fit_does_not_hide_it(walk, pipe):
    bad = with_left_truth(walk, position=walk.truth_left.position * [1.0, -1.0, 1.0])
    with recorded_warnings(quiet=True) as log:
        report = evaluate(pipe, bad, pipeline_name="p")
    assert [c.name for c in report.warnings] == ["mirror_2d", "tilt_3d"]
    mirror, tilt = report.warnings
    assert mirror.value < 0.1 and "the truth looks mirrored" in mirror.message and "negate its y" in mirror.message
    assert tilt.value > 170 and "upside down" in tilt.message and "the truth is mirrored or not z up" in tilt.message
    # what the check exists for: the 3-D fit turned the estimate over and scored it as good
    assert report.value("ate_3d") < 0.2 < 1.0 < report.value("ate_2d")
    assert [w.category for w in log if "truth" in w.message] == [DataQualityWarning] * 2
    assert "truth warnings (2):" in report.to_text()


def test_footprint_truth_is_checked_like_with_like(walk, pipe):
    # footprints (one point per stance, z = 0): its path matches the estimate's at the same times
    from footnav.core.types import stance_intervals

    runs = stance_intervals(walk.truth_left.stance)
    idx = (runs[:, 0] + runs[:, 1]) // 2
    tr = walk.truth_left
    fp = FootTruth(t=tr.t[idx], position=tr.position[idx] * [1.0, 1.0, 0.0], frame="footprints")
    report = evaluate(pipe, Recording(left=walk.left, truth_left=fp, name="fp"))
    assert report.warnings == ()
    assert [c.name for c in report.checks] == [
        "time_span",
        "coverage",
        "scale",
        "mirror_2d",
    ]  # no 3-D fit for footprints
    with pytest.raises(InvalidInputError, match="it looks like mm"):
        evaluate(pipe, Recording(left=walk.left, truth_left=replace(fp, position=fp.position * 1000.0), name="fp"))


def test_batch_records_the_bad_truth_and_scores_the_others(walk, pipe):
    bad = with_left_truth(walk, position=walk.truth_left.position * 1000.0)
    half = left_truth_part(walk, walk.truth_left.t <= 10.0)
    half = replace(half, name="half")
    with pytest.warns(footnav.FootnavWarning):
        report = evaluate_many({"p": pipe}, [walk, bad, half], keep_results=False)
    (failure,) = report.failures
    assert (failure.recording, failure.error_type) == ("bad", "InvalidInputError")
    assert "it looks like mm" in failure.message
    assert np.isfinite(report.value("ate_2d", recording=walk.name)) and np.isfinite(
        report.value("ate_2d", recording="half")
    )
    assert [(c.recording, c.name) for c in report.warnings] == [("half", "coverage")]  # kept without results


def test_cli_evaluate_lists_the_bad_truth_as_a_failure(walk, tmp_path, capsys):
    good, bad = tmp_path / "good", tmp_path / "bad"
    for folder, scale in ((good, 1.0), (bad, 1000.0)):
        folder.mkdir()
        write_footnav_csv(walk.left, folder / "left.csv")
        write_footnav_truth(
            replace(walk.truth_left, position=walk.truth_left.position * scale), folder / "left_truth.csv"
        )
    code = main(["evaluate", str(good), str(bad), "--out", str(tmp_path / "report")])
    out = capsys.readouterr().out
    assert code != 0
    assert "failed (1 of 2 runs):" in out
    line = next(l for l in out.splitlines() if l.strip().startswith("bad /"))
    assert "InvalidInputError" in line and "left_truth.csv" in line and "divide by 1000" in line
    assert float(line.split("ratio ")[1].split(",")[0]) == pytest.approx(1000.0, rel=0.05)
    assert "ate_2d" in out  # the good recording is scored
    doc = json.loads((tmp_path / "report" / "report.json").read_text())
    assert [(c["recording"], c["name"], c["status"]) for c in doc["truth_checks"]] == [
        ("good", n, "ok") for n in CHECKS
    ]


def test_non_finite_truth_is_an_error_naming_the_sample(walk, pipe):
    pos = walk.truth_left.position.copy()
    pos[500] = np.nan
    with pytest.raises(
        InvalidInputError, match=r"index 500: the left foot's truth of 'bad': non-finite truth position"
    ) as exc:
        evaluate(pipe, with_left_truth(walk, position=pos))
    assert exc.value.field == "truth_left"


def test_truth_with_z_down_warns_even_when_its_plane_is_not_mirrored(walk, pipe):
    # z negated alone (left-handed): the horizontal fit and the 3-D tilt see nothing, the heights do
    bad = with_left_truth(walk, position=walk.truth_left.position * [1.0, 1.0, -1.0])
    with pytest.warns(DataQualityWarning, match=r"the truth's z points down; negate its z"):
        report = evaluate(pipe, bad)
    (height,) = report.warnings
    assert height.name == "height" and height.value < -0.9
