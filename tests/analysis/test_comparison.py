import numpy as np
import pytest

import footnav
from footnav.analysis.comparison import compare_detectors
from footnav.cli import main
from footnav.detectors.threshold import ThresholdDetector


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=5, distance_m=15.0)


def test_rows_match_direct_metrics(walk):
    loose = ThresholdDetector(gyr_threshold_radps=1.5)
    cmp = compare_detectors(walk, [("default", ThresholdDetector()), ("loose", loose)])
    rep = cmp.report
    stance = loose.detect(walk.left)
    scores = footnav.analysis.metrics.sample_scores(stance.mask, walk.truth_left.stance)
    assert rep.value("f1", "left", pipeline="loose") == pytest.approx(scores.f1)
    assert rep.value("steps_missed", "left", pipeline="default") == 0
    np.testing.assert_array_equal(cmp.stances["loose"][0].mask, stance.mask)
    header = cmp.to_text().splitlines()[0].split()
    assert header[-2:] == ["default", "loose"]


def test_event_reference_and_timing(walk):
    # drop the stance mask: only events remain, as in a mocap-labelled recording
    from dataclasses import replace

    truth = walk.truth_left
    # each stride's heel off precedes its foot flat: stance k runs from foot_flat[k] to heel_off[k+1]
    mid = (truth.events["foot_flat"][:-1] + truth.events["heel_off"][1:]) // 2
    ev_truth = replace(truth, stance=None, events={"mid_stance": mid, "heel_off": truth.events["heel_off"]})
    rec = footnav.Recording(left=walk.left, truth_left=ev_truth, name="events")
    rep = compare_detectors(rec, ["threshold"]).report
    assert rep.value("steps_reference") == len(mid)
    assert rep.value("steps_found") == len(mid) and rep.value("steps_false") == 0
    # the threshold detector ends the stance 2 samples after the true heel off: measured 20 ms
    assert rep.value("heel_off_error") <= 50.0  # ms


def test_cli_compare_detectors_writes_table_and_figure(tmp_path, capsys):
    fig, csv = tmp_path / "d.png", tmp_path / "d.csv"
    code = main(
        [
            "compare-detectors",
            "--simulate",
            "straight",
            "--detectors",
            "threshold",
            "--plot",
            str(fig),
            "--csv",
            str(csv),
            "--seconds",
            "0",
            "8",
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "steps_found" in out and "threshold" in out.splitlines()[0]
    assert fig.stat().st_size > 10_000 and csv.read_text().startswith("recording,")


def test_cli_compare_detectors_needs_one_source(capsys):
    assert main(["compare-detectors"]) == 2
    assert "exactly one" in capsys.readouterr().err


def test_a_detector_that_fails_is_reported_not_fatal(walk):
    from footnav.core.errors import InvalidInputError

    class Refuses(ThresholdDetector):
        name = "refuses"

        def detect(self, imu):
            raise InvalidInputError("cannot learn from this recording", field="acc")

    cmp = compare_detectors(walk, [("ok", ThresholdDetector()), ("refuses", Refuses())])
    assert "refuses" in cmp.failures and "cannot learn" in cmp.failures["refuses"]
    assert cmp.report.value("failed", "both", pipeline="refuses") == 1.0
    assert cmp.report.value("steps_found", "left", pipeline="ok") > 0
    assert "refuses failed: " in cmp.to_text()
