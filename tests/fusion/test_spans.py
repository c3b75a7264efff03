"""Coupled fusions on feet that do not share their whole time span (footnav.nav.spans).

Each coupled fusion must fuse on the common span (as if both feet had been cut to it), keep
each foot's trajectory sample-aligned with its input (samples outside: the foot alone), warn
when a foot was cut, and refuse feet that share no time span. ``independent`` warns only when
the spans differ markedly.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.errors import DataQualityWarning
from footnav.nav.spans import MIN_COMMON_S, common_span, slice_stance, span_difference

COUPLED = ["range", "step-vector", "particle", "dtw"]


@pytest.fixture(scope="module")
def walk():
    return footnav.simulate("straight", seed=3, distance_m=30.0)


def _run(fusion, left, right):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = footnav.make_pipeline("adaptive", "ekf", fusion).run(left, right)
    spans = [
        str(w.message) for w in caught if issubclass(w.category, DataQualityWarning) and "time span" in str(w.message)
    ]
    return res, spans


def _cut(rec, case):
    """(left, right, index range of the common span in both feet): the walk with 10 s cut off one foot."""
    n, k = len(rec.left.t), round(10.0 * rec.left.rate_hz)
    if case == "left-start":
        return rec.left.slice(k, None), rec.right, (k, n)
    if case == "left-end":
        return rec.left.slice(0, n - k), rec.right, (0, n - k)
    return rec.left, rec.right.slice(0, n - k), (0, n - k)  # right-end


def _displacement(p):
    return float(np.linalg.norm(p[-1, :2] - p[0, :2]))


@pytest.mark.parametrize("case", ["left-start", "left-end", "right-end"])
@pytest.mark.parametrize("fusion", COUPLED)
def test_coupled_fusion_fuses_on_the_common_span(walk, fusion, case):
    left, right, (a, b) = _cut(walk, case)
    res, spans = _run(fusion, left, right)
    # the reference: both feet cut to the common span by hand, fused as any equal-span walk
    ref, ref_spans = _run(fusion, walk.left.slice(a, b), walk.right.slice(a, b))
    assert ref_spans == []
    assert len(spans) == 1, spans
    assert "common span" in spans[0] and "10 s" in spans[0]
    # sample-aligned with each foot's input
    assert len(res.left.t) == len(left.t) and len(res.right.t) == len(right.t)
    np.testing.assert_array_equal(res.left.t, left.t)
    np.testing.assert_array_equal(res.right.t, right.t)
    # inside the common span: the reference's answer (the detector saw the whole feet, hence a tolerance)
    t0, t1 = walk.left.t[a], walk.left.t[b - 1]
    for foot, got, want in (("left", res.left, ref.left), ("right", res.right, ref.right)):
        inside = (got.t >= t0 + 2.0) & (got.t <= t1)  # after the reference's first stance
        mine = got.position[inside]
        theirs = np.stack([np.interp(got.t[inside], want.t, want.position[:, i]) for i in range(3)], axis=1)
        # the reference starts its own nav frame: compare displacements from the first common sample
        err = np.linalg.norm((mine - mine[0])[:, :2] - (theirs - theirs[0])[:, :2], axis=1)
        assert err.max() < 0.5, (foot, err.max())
    # no jumps anywhere, the span edges included (a swinging foot moves at most ~5.5 m/s: 0.055 m a sample)
    for got in (res.left, res.right):
        assert np.isfinite(got.position).all()
        assert np.linalg.norm(np.diff(got.position[:, :2], axis=0), axis=1).max() < 0.08
    # each foot travels what it truly travelled over its own samples (the cut one alone outside)
    for got, imu, truth in ((res.left, left, walk.truth_left), (res.right, right, walk.truth_right)):
        true_pos = np.stack([np.interp(imu.t, truth.t, truth.position[:, i]) for i in range(3)], axis=1)
        assert abs(_displacement(got.position) - _displacement(true_pos)) < 1.0


@pytest.mark.parametrize("fusion", COUPLED)
def test_meta_says_which_samples_were_fused_and_which_alone(walk, fusion):
    left, right, (a, _) = _cut(walk, "left-start")  # the right foot has 10 s more at the start
    res, _ = _run(fusion, left, right)
    assert "span" not in res.left.meta  # the left foot lies wholly inside the common span
    info = res.right.meta["span"]
    first = info["fused_samples"][0]
    assert a <= first < a + 200  # the fused estimate starts at its first stance in the span
    assert info == {"fused_samples": [first, len(right.t)], "alone_samples": [[0, first]]}
    assert res.right.meta["estimate_start_index"] == first


def test_span_meta_of_the_fusion_result():
    rec = footnav.simulate("straight", seed=1, distance_m=20.0)
    k = 1000
    fusion = footnav.make_fusion("range")
    det = footnav.make_detector("adaptive")
    est = footnav.make_estimator("ekf")
    left = rec.left.slice(k, None)
    with pytest.warns(DataQualityWarning, match="common span"):
        out = fusion.fuse(est, left, det.detect(left), rec.right, det.detect(rec.right))
    span = out.meta["span"]
    assert span["common_s"] == [pytest.approx(rec.left.t[k]), pytest.approx(rec.left.t[-1])]
    assert span["right"]["start_index"] == k and span["right"]["cut_before_s"] == pytest.approx(10.0)
    assert span["left"]["start_index"] == 0 and span["left"]["cut_before_s"] == 0.0
    assert "alone" in span["outside"]
    assert out.path.t[0] >= rec.left.t[k]


@pytest.mark.parametrize("fusion", COUPLED)
def test_equal_spans_are_fused_as_before_without_a_warning(fusion):
    rec = footnav.simulate("straight", seed=2, distance_m=10.0)
    res, spans = _run(fusion, rec.left, rec.right)
    assert spans == []
    assert res.meta["warnings"] == [] or not any("time span" in w for w in res.meta["warnings"])


def test_the_issue_case_range_with_a_14_s_left_and_an_83_s_right_foot():
    """Before: the left foot's end moved 42 m from where the foot alone ends."""
    rec = footnav.simulate("straight", seed=1, distance_m=100.0)
    left = rec.left.slice(0, 1400)
    alone = footnav.make_pipeline("adaptive", "ekf", "independent").run(left).left.position[-1]
    res, spans = _run("range", left, rec.right)
    assert spans and "right foot loses 0 s before and 69.3 s after" in spans[0]
    assert np.linalg.norm(res.left.position[-1, :2] - alone[:2]) < 0.5
    assert abs(res.right.position[-1, 0] - rec.truth_right.position[-1, 0]) < 2.0


# -- the span arithmetic -----------------------------------------------------------------------


def test_common_span_indices_and_cuts():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    n = len(rec.left.t)
    span = common_span(rec.left.slice(200, None), rec.right.slice(0, n - 300))
    assert span.start_s == pytest.approx(2.0) and span.stop_s == pytest.approx(rec.left.t[n - 301])
    assert (span.left.start_index, span.left.stop_index) == (0, n - 300 - 200)
    assert (span.right.start_index, span.right.stop_index) == (200, n - 300)
    assert span.left.cut_after_s == pytest.approx(3.0) and span.right.cut_before_s == pytest.approx(2.0)
    assert span.cut and span.warn
    same = common_span(rec.left, rec.right)
    assert not same.cut and not same.warn


def test_slice_stance_keeps_events_inside_shifted():
    rec = footnav.simulate("straight", seed=0, distance_m=10.0)
    st = footnav.make_detector("adaptive").detect(rec.left)
    cut = slice_stance(st, 300, 800)
    np.testing.assert_array_equal(cut.mask, st.mask[300:800])
    for name, ev in st.events.items():
        np.testing.assert_array_equal(cut.events[name], ev[(ev >= 300) & (ev < 800)] - 300)


def test_span_difference_marked_and_not():
    rec = footnav.simulate("straight", seed=0, distance_m=20.0)
    n = len(rec.left.t)
    assert not span_difference(rec.left, rec.right)["marked"]
    assert not span_difference(rec.left, rec.right.slice(0, n - 100))["marked"]  # 1 s: not marked
    d = span_difference(rec.left, rec.right.slice(0, n - 500))  # 5 s
    assert d["marked"] and d["end_difference_s"] == pytest.approx(-5.0) and "5" in d["message"]


# -- independent ---------------------------------------------------------------------------------


def test_independent_warns_on_markedly_different_spans():
    rec = footnav.simulate("straight", seed=0, distance_m=20.0)
    right = rec.right.slice(1000, None)
    with pytest.warns(DataQualityWarning, match="differ markedly") as rec_w:
        res = footnav.make_pipeline("adaptive", "ekf", "independent").run(rec.left, right)
    msg = next(str(w.message) for w in rec_w if "markedly" in str(w.message))
    assert "left foot 0.." in msg and "right foot 10.." in msg
    assert res.meta["warnings"] and any("markedly" in w for w in res.meta["warnings"])
    assert len(res.right.t) == len(right.t)  # estimated alone over its own span, nothing cut


def test_independent_is_silent_on_equal_spans():
    rec = footnav.simulate("straight", seed=0, distance_m=20.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = footnav.make_pipeline("adaptive", "ekf", "independent").run(rec.left, rec.right)
    assert not [w for w in caught if "time span" in str(w.message)]
    assert not any("markedly" in w for w in res.meta["warnings"])


def test_min_common_constant_is_a_few_seconds():
    assert 1.0 <= MIN_COMMON_S <= 10.0
