"""footnav.analysis.metrics: hand-computed cases (arithmetic in the comments), properties
(hypothesis) and, for the DTW distance, a cross-check against dtaidistance; the height RMSE
removes the constant offset only.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from footnav.analysis.metrics import (
    DtwResult,
    ate_rmse,
    dtw_distance,
    end_to_end_error,
    event_timing_error,
    final_position_error,
    final_separation,
    footprint_errors,
    height_rmse,
    interpolate_positions,
    loop_closure_error,
    match_events,
    max_deviation,
    rigid_align,
    sample_scores,
    step_detection,
    step_detection_from_swings,
    stride_length_errors,
    travelled_distance,
    travelled_distance_error,
)
from footnav.core.errors import DataQualityWarning, InvalidInputError, InvalidParameterError
from footnav.nav.dtw import dtw_align


def test_height_rmse_after_the_best_constant_offset():
    # mutant: metrics-height-rmse-offset. z errors 0.5 + (+0.1, -0.1, +0.1, -0.1): RMSE 0.1
    ref = np.column_stack([np.arange(4.0), np.zeros(4), [0.0, 0.2, 0.4, 0.6]])
    est = ref + np.array([[0.0, 0.0, 0.6], [0.0, 0.0, 0.4], [0.0, 0.0, 0.6], [0.0, 0.0, 0.4]])
    assert height_rmse(est, ref) == pytest.approx(0.1, abs=1e-12)
    assert height_rmse(est[:, 2], ref[:, 2]) == pytest.approx(0.1, abs=1e-12)
    est[:, :2] += 3.0  # the plane does not count
    assert height_rmse(est, ref) == pytest.approx(0.1, abs=1e-12)


#: Absolute tolerance of exact (closed-form) results, m.
EXACT = 1e-9


def rot_z(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# An asymmetric, non-planar point set (no mirror symmetry), m.
SHAPE = np.array(
    [[0.0, 0.0, 0.0], [4.0, 0.0, 0.1], [4.0, 1.0, 0.3], [1.0, 3.0, -0.2], [0.5, 2.0, 0.7], [2.0, 0.5, 1.1]]
)


# ---------------------------------------------------------------------------------------------
# rigid_align / ate_rmse
# ---------------------------------------------------------------------------------------------
def test_rigid_align_2d_recovers_heading_and_offset_and_keeps_z():
    rot = rot_z(math.radians(37.0))
    t = np.array([2.0, -3.0, 0.0])
    est = SHAPE.copy()
    ref = est @ rot.T + t
    ref[:, 2] += 5.0  # a z offset dims=2 must NOT remove
    aligned, r, tt = rigid_align(est, ref, dims=2)
    np.testing.assert_allclose(r, rot, atol=EXACT)
    np.testing.assert_allclose(tt, t, atol=EXACT)
    np.testing.assert_allclose(aligned[:, :2], ref[:, :2], atol=EXACT)
    np.testing.assert_allclose(aligned[:, 2], est[:, 2], atol=EXACT)  # z untouched
    assert ate_rmse(est, ref, dims=2) < EXACT


def test_rigid_align_3d_recovers_rotation_translation_and_scale():
    from scipy.spatial.transform import Rotation

    rot = Rotation.from_rotvec([0.3, -0.8, 1.9]).as_matrix()
    t = np.array([10.0, -2.0, 0.5])
    ref = SHAPE @ rot.T + t
    res = rigid_align(SHAPE, ref, dims=3)
    np.testing.assert_allclose(res.rotation, rot, atol=EXACT)
    np.testing.assert_allclose(res.translation, t, atol=EXACT)
    np.testing.assert_allclose(res.aligned, ref, atol=EXACT)
    assert res.scale == 1.0
    assert ate_rmse(SHAPE, ref, dims=3) < EXACT
    # similarity: ref = 2 R est + t -> scale 2
    res_s = rigid_align(SHAPE, 2.0 * SHAPE @ rot.T + t, dims=3, with_scale=True)
    assert res_s.scale == pytest.approx(2.0, abs=EXACT)
    np.testing.assert_allclose(res_s.rotation, rot, atol=EXACT)
    np.testing.assert_allclose(res_s.apply(SHAPE), 2.0 * SHAPE @ rot.T + t, atol=EXACT)


@pytest.mark.parametrize("dims", [2, 3])
def test_rigid_align_never_reflects(dims):
    mirrored = SHAPE * np.array([1.0, -1.0, 1.0])  # mirror in the x-z plane
    res = rigid_align(mirrored, SHAPE, dims=dims)
    k = dims
    assert np.linalg.det(res.rotation[:k, :k]) == pytest.approx(1.0, abs=EXACT)
    # a reflection would fit exactly; a proper rotation cannot
    assert ate_rmse(mirrored, SHAPE, dims=dims) > 0.1


def test_ate_rmse_hand_computed():
    # ref (-1,0),(1,0); est (-2,0),(2,0). Centroids 0, best rotation identity, so each point is
    # 1 m off: RMSE = sqrt((1 + 1) / 2) = 1 m. With scale s = 0.5 it fits exactly.
    ref = np.array([[-1.0, 0.0], [1.0, 0.0]])
    est = np.array([[-2.0, 0.0], [2.0, 0.0]])
    assert ate_rmse(est, ref) == pytest.approx(1.0, abs=EXACT)
    assert ate_rmse(est, ref, with_scale=True) == pytest.approx(0.0, abs=EXACT)


def test_rigid_align_bad_input():
    with pytest.raises(InvalidInputError, match="'reference'"):
        rigid_align(SHAPE, SHAPE[:-1])
    bad = SHAPE.copy()
    bad[2, 1] = np.nan
    with pytest.raises(InvalidInputError, match="'estimate'.*index 2"):
        rigid_align(bad, SHAPE)
    with pytest.raises(InvalidInputError, match="'estimate'"):
        rigid_align(np.empty((0, 3)), np.empty((0, 3)))
    with pytest.raises(InvalidInputError, match="'estimate'"):
        rigid_align(SHAPE[:, :2], SHAPE, dims=3)
    with pytest.raises(InvalidParameterError):
        rigid_align(SHAPE, SHAPE, dims=4)


# ---------------------------------------------------------------------------------------------
# [001] E_s, E_p
# ---------------------------------------------------------------------------------------------
def test_final_separation_and_position_error_seed001_eq8():
    # [001] eq. (8): E_s = ||P1_end - P2_end||, E_p = ||P_i,end(est) - P_i,end(true)||, 2-norm of
    # the n-frame (3-D) position.
    left = np.array([[0.0, 0.0, 0.0], [0.5, 1.0, 0.0], [1.0, 2.0, 0.2]])
    right = np.array([[0.0, 0.2, 0.0], [1.3, 1.6, -1.0]])
    # end difference (1.0-1.3, 2.0-1.6, 0.2-(-1.0)) = (-0.3, 0.4, 1.2):
    # 3-D sqrt(0.09 + 0.16 + 1.44) = sqrt(1.69) = 1.3 m; horizontal sqrt(0.25) = 0.5 m
    assert final_separation(left, right) == pytest.approx(1.3, abs=EXACT)
    assert final_separation(left[-1], right[-1]) == pytest.approx(1.3, abs=EXACT)
    assert final_separation(left, right, dims=2) == pytest.approx(0.5, abs=EXACT)
    # closed loop (true end = start = origin); estimated end (3, 4, 12):
    # 3-D sqrt(9 + 16 + 144) = 13 m, horizontal 5 m
    est = np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 12.0]])
    assert final_position_error(est, np.zeros(3)) == pytest.approx(13.0, abs=EXACT)
    assert final_position_error(est, np.zeros(3), dims=2) == pytest.approx(5.0, abs=EXACT)
    with pytest.raises(InvalidInputError, match="'reference_final'"):
        final_position_error(est, [np.nan, 0.0, 0.0])


# ---------------------------------------------------------------------------------------------
# distances ([003] Table 2)
# ---------------------------------------------------------------------------------------------
def test_travelled_distance():
    pos = np.array([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [3.0, 4.0, 12.0]])
    # horizontal: 5 + 0 = 5 m; 3-D: 5 + 12 = 17 m
    assert travelled_distance(pos) == pytest.approx(5.0, abs=EXACT)
    assert travelled_distance(pos, dims=3) == pytest.approx(17.0, abs=EXACT)
    assert travelled_distance(pos[:1]) == 0.0


def test_loop_closure_and_closed_loop_end_to_end():
    # legs 41 + 10 + 41 + 8 = 100 m; end (0, 2) is 2 m from the start -> 2 % of the distance
    pos = np.array([[0.0, 0.0], [41.0, 0.0], [41.0, 10.0], [0.0, 10.0], [0.0, 2.0]])
    res = loop_closure_error(pos)
    assert res.error_m == pytest.approx(2.0, abs=EXACT)
    assert res.distance_m == pytest.approx(100.0, abs=EXACT)
    assert res.error_percent == pytest.approx(2.0, abs=EXACT)
    assert end_to_end_error(pos) == res
    # known course length as denominator: 2 / 80 = 2.5 %
    assert end_to_end_error(pos, reference_distance_m=80.0).error_percent == pytest.approx(2.5)


def test_end_to_end_error_reproduces_seed003_table2():
    # [003] Table 2, HMM+GDA: end-to-end error 23.31 m on the 1075 m ground truth:
    # 100 * 23.31 / 1075 = 2.1684 % (reported 2.16, truncated).
    ref = np.array([[0.0, 0.0], [1075.0, 0.0]])
    est = np.array([[0.0, 0.0], [1075.0, 23.31]])
    res = end_to_end_error(est, ref)
    assert res.error_m == pytest.approx(23.31, abs=EXACT)
    assert res.distance_m == pytest.approx(1075.0)
    assert res.error_percent == pytest.approx(2.16837, abs=1e-5)
    assert math.floor(res.error_percent * 100) / 100 == 2.16


def test_travelled_distance_error_reproduces_seed003_table2():
    # [003] Table 2: travel distance 1077.69 m vs 1075 m -> 100 * 2.69 / 1075 = 0.2502 %;
    # 1131.19 m -> 100 * 56.19 / 1075 = 5.2270 % (reported 5.22, truncated)
    for d_est, pct in ((1077.69, 0.250233), (1131.19, 5.226977)):
        est = np.array([[0.0, 0.0], [d_est, 0.0]])
        res = travelled_distance_error(est, 1075.0)
        assert res.distance_m == pytest.approx(d_est)
        assert res.error_m == pytest.approx(d_est - 1075.0)
        assert res.error_percent == pytest.approx(pct, abs=1e-6)
    # reference given as a trajectory of the same length
    res = travelled_distance_error(np.array([[0.0, 0.0], [0.0, 9.0]]), np.array([[0.0, 0.0], [6.0, 8.0]]))
    assert res.reference_distance_m == pytest.approx(10.0)
    assert res.error_percent == pytest.approx(-10.0)


# ---------------------------------------------------------------------------------------------
# DTW
# ---------------------------------------------------------------------------------------------
# The kernel itself (hand-computed cases, a full-matrix DTW, dtaidistance, long inputs) is tested
# in test_dtw_core.py; here what dtw_distance adds: the ``dims`` columns, its input checks, and that
# it returns dtw_align's numbers unchanged.
def test_dtw_distance_is_dtw_align_on_the_chosen_columns():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(40, 3)), rng.normal(size=(35, 3))
    for kw in ({}, {"band": 7}, {"cost": "sqeuclidean", "normalize": "none"}):
        ours = dtw_align(a[:, :2], b[:, :2], return_path=True, **kw)
        theirs = dtw_distance(a, b, dims=2, return_path=True, **kw)
        assert isinstance(theirs, DtwResult)
        assert (theirs.distance_m, theirs.total_cost) == (ours.distance_m, ours.total_cost)
        assert theirs.n_pairs == ours.n_pairs
        np.testing.assert_array_equal(theirs.path, ours.path)
    assert dtw_distance(a, b, dims=3).total_cost == dtw_align(a, b).total_cost


def test_dtw_distance_dims_hand_computed():
    # x: a = 0 0 0 1, b = 0 1 1 1; unbounded, a0..a2 -> b0 and a3 -> b1..b3 cost 0 in x, y.
    # With z (a3 at 3 m, the rest 0) each pair of a3 costs >= 3 m, so a3 pairs with b3 only and
    # b1, b2 go to a0..a2 at 1 m each: 0 + 1 + 1 + 3 = 5 m (a3 on k pairs costs 3 k + (3 - k)
    # >= 5 m). Paths through (1, 0) tie; the kernel prefers the diagonal step.
    a = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 3.0]])
    b = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    assert dtw_distance(a, b).total_cost == pytest.approx(0.0, abs=EXACT)  # dims=2 ignores z
    three = dtw_distance(a, b, dims=3, return_path=True)
    assert three.total_cost == pytest.approx(5.0, abs=EXACT)
    np.testing.assert_array_equal(three.path, [[0, 0], [1, 1], [2, 2], [3, 3]])


@settings(max_examples=30, deadline=None)
@given(n=st.integers(2, 12), band=st.integers(0, 5), seed=st.integers(0, 2**31 - 1))
def test_dtw_distance_3d_against_dtaidistance(n, band, seed):
    dtw_ndim = pytest.importorskip("dtaidistance.dtw_ndim")
    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    # dtaidistance: sqrt of the sum of squared Euclidean costs over all columns; window w allows
    # |i - j| <= w - 1 for equal lengths
    ours = dtw_distance(a, b, dims=3, band=band, cost="sqeuclidean", normalize="none")
    assert ours.distance_m == pytest.approx(dtw_ndim.distance(a, b, window=band + 1, use_pruning=False), rel=1e-9)


def test_dtw_distance_bad_input():
    a = np.zeros((3, 3))
    with pytest.raises(InvalidParameterError, match="dims"):
        dtw_distance(a, a, dims=1)
    with pytest.raises(InvalidInputError, match="'b'.*index 1"):
        dtw_distance(a, [[0.0, 0.0], [np.inf, 0.0]])
    with pytest.raises(InvalidInputError, match="'a'.*empty"):
        dtw_distance(np.empty((0, 2)), a)
    with pytest.raises(InvalidInputError, match="'b'.*shape"):
        dtw_distance(a, np.zeros((3, 4)))
    with pytest.raises(InvalidInputError, match="'a'.*shape"):
        dtw_distance(a[:, :2], a, dims=3)
    with pytest.raises(InvalidParameterError, match="band"):
        dtw_distance(a, a, band=-1)
    with pytest.raises(InvalidParameterError, match="normalize"):
        dtw_distance(a, a, normalize="sum")


# ---------------------------------------------------------------------------------------------
# [002] Table 2 maximum deviation
# ---------------------------------------------------------------------------------------------
def test_max_deviation_hand_computed():
    # reference: x = 0..10 m at 1 m per sample; estimate off in y by 0.3 m at k=2 and 0.5 m at k=10.
    # max deviation 0.5 m at k=10, 0.5 / 10 = 5 % of the 10 m walked.
    # ratio d_k / s_k: k=2 -> 0.3 / 2 = 0.15, k=10 -> 0.5 / 10 = 0.05.
    ref = np.column_stack([np.arange(11.0), np.zeros(11)])
    est = ref.copy()
    est[2, 1], est[10, 1] = 0.3, 0.5
    res = max_deviation(est, ref, min_distance_m=1.0)
    assert res.max_deviation_m == pytest.approx(0.5, abs=EXACT) and res.max_deviation_index == 10
    assert res.distance_m == pytest.approx(10.0) and res.max_deviation_percent == pytest.approx(5.0)
    assert res.max_ratio == pytest.approx(0.15, abs=EXACT) and res.max_ratio_index == 2
    # default: ratio only after 5 m -> 0.05 at k=10
    res5 = max_deviation(est, ref)
    assert res5.max_ratio == pytest.approx(0.05, abs=EXACT) and res5.max_ratio_index == 10
    with pytest.raises(InvalidInputError, match="'reference'"):
        max_deviation(est, ref[:-1])


def test_interpolate_positions():
    t = np.array([0.0, 1.0, 2.0])
    p = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 4.0, 1.0]])
    np.testing.assert_allclose(interpolate_positions(t, p, [0.5, 1.5]), [[1.0, 0.0, 0.5], [2.0, 2.0, 1.0]])
    with pytest.raises(InvalidInputError, match="'t_new'"):
        interpolate_positions(t, p, [2.5])


# ---------------------------------------------------------------------------------------------
# strides
# ---------------------------------------------------------------------------------------------
def test_stride_length_errors_hand_computed():
    # strides est 1.2, 1.3, 1.1; ref 1.25, 1.25, 1.2 -> errors -0.05, +0.05, -0.10 m
    # mean -0.0333, mean |e| 0.0667, RMSE sqrt((0.0025 + 0.0025 + 0.01) / 3) = sqrt(0.005), max 0.1
    est = np.array([[0.0, 0.0], [1.2, 0.0], [2.5, 0.0], [3.6, 0.0]])
    ref = np.array([[0.0, 0.1], [1.25, 0.1], [2.5, 0.1], [3.7, 0.1]])
    res = stride_length_errors(est, ref)
    np.testing.assert_allclose(res.errors_m, [-0.05, 0.05, -0.1], atol=EXACT)
    assert res.mean_error_m == pytest.approx(-0.1 / 3)
    assert res.mean_abs_error_m == pytest.approx(0.2 / 3)
    assert res.rmse_m == pytest.approx(math.sqrt(0.005))
    assert res.max_abs_error_m == pytest.approx(0.1) and res.n_strides == 3
    with pytest.warns(DataQualityWarning):
        assert stride_length_errors(est, ref[:3]).n_strides == 2
    with pytest.raises(InvalidInputError, match="'est_footprints'"):
        stride_length_errors(est[:1], ref)


# ---------------------------------------------------------------------------------------------
# events and steps
# ---------------------------------------------------------------------------------------------
def test_match_events_hand_computed():
    # one detection between two references: it can serve only one of them
    m, missed, false = match_events([10], [9, 11], tolerance=2)
    assert len(m) == 1 and len(missed) == 1 and len(false) == 0
    # greedy-by-distance would take (6, 5) (distance 1) and leave 4 and 8 unmatched;
    # the optimal one-to-one matching is (4, 5) and (6, 8)
    m, missed, false = match_events([4, 6], [5, 8], tolerance=2)
    np.testing.assert_array_equal(m, [[4, 5], [6, 8]])
    assert len(missed) == 0 and len(false) == 0
    # tolerance is inclusive
    assert len(match_events([0], [3], tolerance=2).matches) == 0
    assert len(match_events([0], [3], tolerance=3).matches) == 1
    # empty inputs are valid: everything missed / false
    r = match_events([], [1, 2], tolerance=1)
    assert len(r.matches) == 0 and list(r.missed) == [1, 2] and len(r.false) == 0
    with pytest.raises(InvalidInputError, match="'reference'"):
        match_events([1], [np.nan], tolerance=1)
    with pytest.raises(InvalidParameterError):
        match_events([1], [1], tolerance=-1)


def greedy_max_matching(det, ref, tol):
    """Maximum number of one-to-one matches for equal-width windows: sorted greedy is optimal."""
    det = sorted(det)
    used = [False] * len(det)
    count = 0
    for r in sorted(ref):
        for i, d in enumerate(det):
            if not used[i] and r - tol <= d <= r + tol:
                used[i] = True
                count += 1
                break
    return count


@settings(max_examples=200, deadline=None)
@given(
    det=st.lists(st.integers(0, 60), max_size=15), ref=st.lists(st.integers(0, 60), max_size=15), tol=st.integers(0, 6)
)
def test_match_events_is_one_to_one_and_maximal(det, ref, tol):
    m, missed, false = match_events(np.array(det, dtype=np.int64), np.array(ref, dtype=np.int64), tolerance=tol)
    assert (np.abs(m[:, 0] - m[:, 1]) <= tol).all()
    # every event is used once: matched + leftover reproduce each input multiset exactly
    assert sorted(list(m[:, 0]) + list(false)) == sorted(det)
    assert sorted(list(m[:, 1]) + list(missed)) == sorted(ref)
    assert len(m) == greedy_max_matching(det, ref, tol)


def stance_mask(n: int, runs) -> np.ndarray:
    mask = np.zeros(n, bool)
    for a, b in runs:
        mask[a:b] = True
    return mask


def test_step_detection_hand_computed():
    # reference stances [2,6) [12,16) [22,26): centers 3.5, 13.5, 23.5
    # detected [3,7) [12,15) [30,34) [35,37): centers 4.5, 13, 31.5, 35.5
    # tolerance 2: 4.5<->3.5, 13<->13.5 found; 23.5 missed; 31.5, 35.5 false
    ref = stance_mask(40, [(2, 6), (12, 16), (22, 26)])
    det = stance_mask(40, [(3, 7), (12, 15), (30, 34), (35, 37)])
    res = step_detection(det, ref, tolerance_samples=2)
    assert (res.n_detected, res.n_reference, res.n_found, res.n_missed, res.n_false) == (4, 3, 2, 1, 2)
    assert res.missed_percent == pytest.approx(100 / 3) and res.false_percent == pytest.approx(200 / 3)
    # onsets 3, 12, 30, 35 vs 2, 12, 22: same counts here
    on = step_detection(det, ref, tolerance_samples=2, anchor="onset")
    assert (on.n_found, on.n_missed, on.n_false) == (2, 1, 2)
    with pytest.raises(InvalidInputError, match="'detected_mask'"):
        step_detection(det[:-1], ref, tolerance_samples=2)


def test_step_detection_reproduces_seed003_table1_rate():
    # [003] Table 1, LR-HMM: 735 steps detected for 729 true steps, 0 missing, 6 extra:
    # 100 * 6 / 729 = 0.823 %.
    period, n_ref = 10, 729
    ref = stance_mask(period * n_ref, [(period * k, period * k + 4) for k in range(n_ref)])
    extra = [(period * k + 6, period * k + 8) for k in (5, 100, 200, 300, 400, 500)]
    det = ref | stance_mask(period * n_ref, extra)
    res = step_detection(det, ref, tolerance_samples=2)
    assert (res.n_detected, res.n_found, res.n_missed, res.n_false) == (735, 729, 0, 6)
    assert (res.found, res.missed, res.false) == (729, 0, 6)
    assert round(res.false_percent, 3) == 0.823


def test_sample_scores_hand_computed():
    # det 1 1 0 0 1 0 / ref 1 0 0 1 1 0: TP = {0, 4} = 2, FP = {1} = 1, FN = {3} = 1, TN = {2, 5} = 2
    # precision 2/3, recall 2/3, F1 = 4 / (4 + 1 + 1) = 2/3, accuracy 4/6
    s = sample_scores([1, 1, 0, 0, 1, 0], [1, 0, 0, 1, 1, 0])
    assert (s.n_true_positive, s.n_false_positive, s.n_false_negative, s.n_true_negative) == (2, 1, 1, 2)
    assert s.precision == pytest.approx(2 / 3) and s.recall == pytest.approx(2 / 3)
    assert s.f1 == pytest.approx(2 / 3) and s.accuracy == pytest.approx(4 / 6)
    assert math.isnan(sample_scores([0, 0], [1, 0]).precision)
    with pytest.raises(InvalidInputError, match="'reference_mask'"):
        sample_scores([1, 0], [1, 2])
    with pytest.raises(InvalidInputError, match="'detected_mask'"):
        sample_scores([], [])


def test_event_timing_error_hand_computed():
    # at 100 Hz: pairs (102,100) +2, (198,200) -2, (305,300) +5 samples = +0.02, -0.02, +0.05 s;
    # 500 is false. |e| = 0.02, 0.02, 0.05: mean 0.03, population std sqrt((1+1+4)e-4 / 3) =
    # sqrt(2e-4), max 0.05; signed mean 0.05 / 3
    res = event_timing_error([102, 198, 305, 500], [100, 200, 300], tolerance=10, rate_hz=100.0)
    assert res.mean_abs_error_s == pytest.approx(0.03)
    assert res.std_abs_error_s == pytest.approx(math.sqrt(2e-4))
    assert res.max_abs_error_s == pytest.approx(0.05)
    assert res.mean_error_s == pytest.approx(0.05 / 3)
    assert (res.n_matched, res.n_missed, res.n_false) == (3, 0, 1)
    assert math.isnan(event_timing_error([], [1], tolerance=1, rate_hz=100.0).mean_abs_error_s)
    with pytest.raises(InvalidParameterError):
        event_timing_error([1], [1], tolerance=1, rate_hz=0.0)


def test_step_detection_from_events_hand_case():
    from footnav.analysis.metrics import step_detection_from_events

    #            stance phases: [2,5) [10,14) [20,22) [30,35)   [40,45)
    mask = np.zeros(50, dtype=bool)
    for a, b in [(2, 5), (10, 14), (20, 22), (30, 35), (40, 45)]:
        mask[a:b] = True
    # reference mid-stance events: 11 and 12 both in [10,14) (one can match), 25 in no phase,
    # 31 in [30,35); [20,22) holds no event -> false; [2,5) and [40,45) lie outside the span
    # [11, 31] of the reference -> ignored
    res = step_detection_from_events(mask, [11, 12, 25, 31])
    assert (res.n_found, res.n_missed, res.n_false) == (2, 2, 1)
    assert res.n_detected == 3 and res.n_reference == 4
    np.testing.assert_array_equal(res.matches.missed, [12, 25])
    # widening by 4 samples lets [20,22) reach 25 (21 + 4 = 25) -> found
    res = step_detection_from_events(mask, [11, 12, 25, 31], tolerance_samples=4)
    assert (res.n_found, res.n_missed, res.n_false) == (3, 1, 0)


# ---------------------------------------------------------------------------------------------
# footprint errors (gait-driven data set) and step detection against labelled swings (IPOL)
# ---------------------------------------------------------------------------------------------
FOOTPRINTS = np.array([[0.0, 0.0], [0.6, 0.1], [1.2, -0.1], [1.8, 0.4], [1.5, 1.3]])


def test_footprint_errors_zero_for_a_rigidly_moved_estimate():
    # the estimate = footprints turned by 30 deg and shifted by (2, -1): one rigid fit undoes it
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    est = FOOTPRINTS @ np.array([[c, -s], [s, c]]).T + [2.0, -1.0]
    res = footprint_errors(est, FOOTPRINTS)
    assert res.rmse_m == pytest.approx(0.0, abs=1e-12) and res.final_m == pytest.approx(0.0, abs=1e-12)
    assert res.n == 5
    # a per-sample trajectory picked at the footprints' indices gives the same
    traj = np.zeros((20, 3))
    idx = [2, 6, 9, 14, 19]
    traj[idx, :2] = est
    assert footprint_errors(traj, FOOTPRINTS, index=idx).rmse_m == pytest.approx(0.0, abs=1e-12)


def test_footprint_errors_one_displaced_footprint_hand_computed():
    # 4 footprints on the x axis, the last one displaced by d = 0.4 m along x. Collinear points
    # displaced along their line: the best rotation is 0 (no cross term), the best translation
    # the mean displacement d/4 = 0.1 m. Residuals 0.1, 0.1, 0.1 and 0.4 - 0.1 = 0.3 m:
    # RMSE = sqrt((3 * 0.01 + 0.09) / 4) = sqrt(0.03) = 0.1732 m; final = 0.3 m.
    fp = np.array([[0.0, 0.0], [0.6, 0.0], [1.2, 0.0], [1.8, 0.0]])
    est = fp.copy()
    est[-1, 0] += 0.4
    res = footprint_errors(est, fp)
    assert res.rmse_m == pytest.approx(math.sqrt(0.03))
    assert res.final_m == pytest.approx(0.3)
    np.testing.assert_allclose(res.errors_m, [0.1, 0.1, 0.1, 0.3])
    # displacing the first footprint instead: the final footprint's error is 0.1 m
    est = fp.copy()
    est[0, 0] += 0.4
    assert footprint_errors(est, fp).final_m == pytest.approx(0.1)


def test_footprint_errors_refuses_a_mirror_and_bad_input():
    # a mirrored estimate (y negated) is not fitted away: a proper rotation cannot undo it
    assert footprint_errors(FOOTPRINTS * [1.0, -1.0], FOOTPRINTS).rmse_m > 0.1
    with pytest.raises(InvalidInputError, match=r"index.*index 1|index 1"):
        footprint_errors(np.zeros((10, 2)), FOOTPRINTS[:2], index=[3, 10])
    with pytest.raises(InvalidInputError, match="estimate"):
        footprint_errors(np.zeros((4, 2)), FOOTPRINTS)
    with pytest.raises(InvalidInputError, match="footprints"):
        footprint_errors(np.zeros((1, 2)), FOOTPRINTS[:1])


# Swings [10, 20), [40, 50), [70, 80) inside the span [5, 95): reference stances
# [5, 10) (centre 7), [20, 40) (29.5), [50, 70) (59.5), [80, 95) (87).
SWINGS = np.array([[10, 20], [40, 50], [70, 80]])


def _mask(n, runs):
    m = np.zeros(n, dtype=bool)
    for a, b in runs:
        m[a:b] = True
    return m


def test_step_detection_from_swings_hand_computed():
    # detected: [0, 11) -> clipped [5, 11), centre 7.5, inside [5, 10) +- 3: found; [22, 39)
    # centre 30 inside [20, 40): found; [44, 46) centre 44.5, inside the swing [40, 50) and more
    # than 3 from both neighbouring stances (last sample 39, first 50): false; [50, 70) not
    # detected: missed; [81, 97) -> clipped [81, 95), centre 87.5: found; [98, 100) outside.
    det = _mask(100, [(0, 11), (22, 39), (44, 46), (81, 97), (98, 100)])
    res = step_detection_from_swings(det, SWINGS, (5, 95), tolerance_samples=3)
    assert (res.n_detected, res.n_reference) == (4, 4)
    assert (res.found, res.missed, res.false) == (3, 1, 1)
    # precision = recall = 3/4; F1 = 2 * 3 / (4 + 4) = 0.75
    assert res.precision == pytest.approx(0.75) and res.recall == pytest.approx(0.75)
    assert res.f1 == pytest.approx(0.75)
    np.testing.assert_allclose(res.matches.missed, [59.5])
    np.testing.assert_allclose(res.matches.false, [44.5])


def test_step_detection_from_swings_counts_a_stance_by_containment_one_to_one():
    # Reference stance [50, 70) (heel strike to toe-off, centre 59.5). A detector's still part
    # [60, 68) has its centre 63.5 four samples from the reference centre, more than the
    # tolerance 3, but inside the stance: found. Split in two, [52, 56) and [60, 68): one found,
    # the other false (one to one); the pairing keeps the anchor nearest the centre (59.5 - 53.5
    # = 6 > 63.5 - 59.5 = 4).
    base = [(5, 10), (20, 40), (80, 95)]
    res = step_detection_from_swings(_mask(100, base + [(60, 68)]), SWINGS, (5, 95), tolerance_samples=3)
    assert (res.found, res.missed, res.false) == (4, 0, 0)
    res = step_detection_from_swings(_mask(100, base + [(52, 56), (60, 68)]), SWINGS, (5, 95), tolerance_samples=3)
    assert (res.found, res.missed, res.false) == (4, 0, 1)
    np.testing.assert_allclose(res.matches.false, [53.5])
    assert res.f1 == pytest.approx(2 * 4 / (5 + 4))


def test_step_detection_from_swings_ignores_stances_outside_the_boundaries():
    # perfect inside the span; the standing before and after, and spurious stances out there,
    # change nothing
    inside = _mask(100, [(5, 10), (20, 40), (50, 70), (80, 95)])
    perfect = step_detection_from_swings(inside, SWINGS, (5, 95), tolerance_samples=3)
    assert (perfect.found, perfect.missed, perfect.false, perfect.f1) == (4, 0, 0, 1.0)
    outside = inside | _mask(100, [(0, 2), (3, 4), (96, 97), (98, 100)])
    res = step_detection_from_swings(outside, SWINGS, (5, 95), tolerance_samples=3)
    assert (res.found, res.missed, res.false) == (4, 0, 0)


def test_step_detection_from_swings_boundary_at_a_toe_off():
    # IPOL's start boundary is a toe-off: this foot has no stance in the span before its first
    # swing [5, 15). A detected stance ending 2 samples late, [0, 7), leaves a 2-sample sliver
    # [5, 7) inside: timing jitter within the tolerance, not a false step.
    swings = np.array([[5, 15], [40, 50]])
    ref_only = step_detection_from_swings(_mask(60, [(15, 40)]), swings, (5, 50), tolerance_samples=3)
    assert (ref_only.n_reference, ref_only.found) == (1, 1)
    res = step_detection_from_swings(_mask(60, [(0, 7), (15, 40)]), swings, (5, 50), tolerance_samples=3)
    assert (res.found, res.missed, res.false) == (1, 0, 0)
    # a longer overhang (6 samples > tolerance 3) is a stance the reference does not have
    res = step_detection_from_swings(_mask(60, [(0, 11), (15, 40)]), swings, (5, 50), tolerance_samples=3)
    assert res.false == 1


def test_step_detection_from_swings_bad_input():
    det = np.zeros(100, dtype=bool)
    with pytest.raises(InvalidInputError, match="swings.*index 1|index 1"):
        step_detection_from_swings(det, [[10, 20], [40, 30]], (5, 95), tolerance_samples=3)
    with pytest.raises(InvalidInputError, match="boundaries"):
        step_detection_from_swings(det, SWINGS, (50, 20), tolerance_samples=3)
    with pytest.raises(InvalidParameterError):
        step_detection_from_swings(det, SWINGS, (5, 95), tolerance_samples=-1)
    empty = step_detection_from_swings(det, SWINGS, (5, 95), tolerance_samples=3)
    assert (empty.n_detected, empty.missed, empty.precision == empty.precision, empty.f1) == (0, 4, False, 0.0)


def test_step_detection_f1_property_on_the_existing_function():
    ref = _mask(50, [(0, 10), (20, 30), (40, 50)])
    det = _mask(50, [(0, 10), (20, 30), (33, 35)])
    res = step_detection(det, ref, tolerance_samples=2)
    # found 2 of 3 reference, 1 false: F1 = 2 * 2 / (3 + 3)
    assert res.f1 == pytest.approx(2 / 3)


def test_height_rmse_ignores_a_constant_offset_and_the_plane():
    ref = np.zeros((3, 3))
    est = np.array([[5.0, 1.0, 1.0], [-2.0, 0.0, 2.0], [0.0, 7.0, 3.0]])
    # d = 1, 2, 3 -> mean 2, residuals -1, 0, 1: sqrt(2 / 3)
    assert height_rmse(est, ref) == pytest.approx(np.sqrt(2.0 / 3.0))
    assert height_rmse(est + [0.0, 0.0, 10.0], ref) == pytest.approx(np.sqrt(2.0 / 3.0))
    assert height_rmse(est[:, 2], ref[:, 2]) == pytest.approx(np.sqrt(2.0 / 3.0))
    with pytest.raises(InvalidInputError):
        height_rmse(est[:2], ref)
    with pytest.raises(InvalidInputError, match="non-finite"):
        height_rmse(np.array([0.0, np.nan, 1.0]), np.zeros(3))


# mutant: metrics-rmse-mean
# metrics-rmse-mean: ATE is a root mean square. Errors 1, 1, 0, 0 m after the best fit (identity:
# the cross-covariance is diag(4, 8)) give sqrt(1/2), not their mean 1/2
def test_ate_is_a_root_mean_square():
    from footnav.analysis.metrics import ate_rmse

    ref = np.array([[-1.0, 0.0], [1.0, 0.0], [0.0, -2.0], [0.0, 2.0]])
    est = np.array([[-2.0, 0.0], [2.0, 0.0], [0.0, -2.0], [0.0, 2.0]])
    assert ate_rmse(est, ref) == pytest.approx(np.sqrt(0.5), abs=1e-12)


# mutant: metrics-waypoint-radius
# metrics-waypoint-radius: a pass at exactly radius_m counts
def test_a_pass_at_exactly_the_radius_counts():
    from footnav.analysis.metrics import waypoint_errors

    x = np.linspace(-3.0, 3.0, 61)
    ref = np.column_stack([x, np.ones_like(x)])
    res = waypoint_errors(ref + [0.0, 0.25], ref, [[0.0, 0.0]], radius_m=1.0)
    np.testing.assert_allclose(res.errors_m, [0.25])


# mutant: metrics-deviation-min-distance
# metrics-deviation-min-distance: the ratio counts samples with s_k >= min_distance_m
def test_deviation_ratio_includes_the_minimum_distance():
    from footnav.analysis.metrics import max_deviation

    ref = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    est = np.array([[0.0, 0.0], [1.0, 0.5], [2.0, 0.1]])
    res = max_deviation(est, ref, min_distance_m=1.0)
    assert res.max_ratio == pytest.approx(0.5) and res.max_ratio_index == 1


# mutant: metrics-interp-duplicates
# metrics-interp-duplicates: times must increase strictly
def test_interpolation_refuses_repeated_times():
    from footnav.analysis.metrics import interpolate_positions
    from footnav.core.errors import InvalidInputError

    with pytest.raises(InvalidInputError):
        interpolate_positions([0.0, 1.0, 1.0, 2.0], np.zeros((4, 3)), [0.5])


# mutant: metrics-distance-3d
# metrics-distance-3d: the start heading comes from the first distance_m walked horizontally; a
# climb straight up first (stairs, a lift) does not count
def test_start_heading_uses_horizontal_distance():
    from footnav.analysis.metrics import align_at_start

    climb = np.column_stack([np.zeros(11), np.zeros(11), np.linspace(0.0, 3.0, 11)])
    s = np.linspace(0.2, 4.0, 20)
    ref = np.vstack([climb, np.column_stack([np.zeros(20), s, np.full(20, 3.0)])])
    est = np.vstack([climb, np.column_stack([s, np.zeros(20), np.full(20, 3.0)])])
    np.testing.assert_allclose(align_at_start(est, ref).aligned, ref, atol=1e-12)
