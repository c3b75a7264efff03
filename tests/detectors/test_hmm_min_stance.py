"""The HMM detector's minimum stance duration (issue 36): the expanded-state Viterbi of
footnav.detectors.hmm.decoding against hmmlearn's, on a hand-built model, and on simulated walks."""

import warnings

import numpy as np
import pytest

import footnav
from footnav.core.types import stance_intervals
from footnav.detectors.hmm.decoding import MIN_STANCE_S, min_stance_samples, viterbi_min_stance
from footnav.detectors.hmm.detector import HmmDetector
from footnav.detectors.hmm.features import model_grid
from footnav.detectors.hmm.model import build_hmm


def _model_1d():
    """Eq. (1)'s structure on a 1-D feature: stance near 0, push-up +1, swing +3, step-down -1."""
    a = np.array([[0.9, 0.1, 0, 0], [0, 0.8, 0.2, 0], [0, 0, 0.8, 0.2], [0.2, 0, 0, 0.8]])
    means = np.array([[0.0], [1.0], [3.0], [-1.0]])
    covars = np.full((4, 1, 1), 0.25)
    return build_hmm(np.full(4, 0.25), a, means, covars, seed=0)


def test_one_sub_state_is_hmmlearns_viterbi():
    model = _model_1d()
    x = np.random.default_rng(3).normal(0.0, 1.5, (400, 1))
    lp, states = viterbi_min_stance(model, x, 1)
    lp_ref, states_ref = model.decode(x, algorithm="viterbi")
    np.testing.assert_array_equal(states, states_ref)
    assert lp == pytest.approx(lp_ref, rel=1e-12)


def test_a_one_sample_stance_needs_the_chain_to_be_longer():
    # stance, push-up, swing with -1, 0, +1 inside it (a zero crossing), step-down, stance:
    # the plain path goes round the cycle there with a one-sample stance (sample 21)
    x = np.r_[np.zeros(10), np.ones(5), 3.0 * np.ones(5), -1.0, 0.0, 1.0, 3.0 * np.ones(5), -np.ones(5), np.zeros(10)][
        :, None
    ]
    model = _model_1d()
    _, plain = model.decode(x, algorithm="viterbi")
    assert len(stance_intervals(plain == 0)) == 3 and plain[21] == 0 and plain[20] == 3
    _, chained = viterbi_min_stance(model, x, 6)
    runs = stance_intervals(chained == 0)
    assert len(runs) == 2 and np.all(np.diff(runs, axis=1) >= 6)
    # the path still follows eq. (1): stay or move to the next phase
    step = (chained[1:] - chained[:-1]) % 4
    assert set(step.tolist()) <= {0, 1}


def test_sub_states_cover_the_minimum_at_the_model_rate():
    assert min_stance_samples(100.0) == 6 and min_stance_samples(60.0) == 4 and min_stance_samples(200.0) == 11
    assert min_stance_samples(100.0, 0.15) == 16 and min_stance_samples(100.0, 0.0) == 1


def _walk(rate_hz, swing_scale, minutes=2.0, side_m=12.0, seed=1):
    n = int(minutes * 60 * 1.3 / side_m) + 1  # a side every ~9 s, turning left and right by fives
    segments = [(side_m, 90.0 if (i // 5) % 2 == 0 else -90.0) for i in range(n)] + [(side_m, 0.0)]
    return footnav.simulate("path", seed=seed, segments=segments, rate_hz=rate_hz, swing_scale=swing_scale)


@pytest.mark.parametrize("rate_hz", [60.0, 100.0, 200.0])
@pytest.mark.parametrize("swing_scale", [None, (1.0, 0.7, 1.3, 0.85, 1.15)])
def test_simulated_walks_every_step_and_no_micro_stance(rate_hz, swing_scale):
    rec = _walk(rate_hz, swing_scale)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        st = HmmDetector().detect(rec.left)
    truth = stance_intervals(rec.truth_left.stance)
    runs = st.intervals
    assert len(runs) == len(truth)
    assert np.all(np.diff(runs, axis=1).ravel() / rate_hz >= MIN_STANCE_S - 1e-9)
    # each detected stance overlaps its true one (no step missed, none false)
    mid = (runs[:, 0] + runs[:, 1]) // 2
    assert np.all((mid >= truth[:, 0]) & (mid < truth[:, 1]))


@pytest.mark.parametrize("rate_hz", [60.0, 100.0, 200.0])
def test_ten_minutes_of_varied_swings_every_step_and_none_false(rate_hz):
    # issue 36's acceptance: 10 min, 66 turns, swing_scale (1, 0.5, 1.5): the learned model fails
    # its check (measured at 60 Hz: 495 of 1373 plain-path stance runs one sample long, 483
    # false steps with a 0.05 s minimum); with the default 0.15 s, 687 of 687, none false
    rec = _walk(rate_hz, (1.0, 0.5, 1.5), minutes=10.0, seed=2)
    # both feet at the rate it was measured at; one foot at the others (the model runs at 100 Hz
    # whatever the rate: the others differ in the resampling onto it)
    feet = ((rec.left, rec.truth_left), (rec.right, rec.truth_right))
    for imu, truth in feet if rate_hz == 60.0 else feet[:1]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            st = HmmDetector().detect(imu)
        true = stance_intervals(truth.stance)
        runs = st.intervals
        assert len(runs) == len(true)
        mid = (runs[:, 0] + runs[:, 1]) // 2
        assert np.all((mid >= true[:, 0]) & (mid < true[:, 1]))


def test_shuffles_give_no_micro_stance_where_the_plain_path_has_many():
    # a gyro-only model on shuffling swings (swing_scale 0.2) at 60 Hz: the plain Viterbi path
    # has one-sample stances at the swing's zero crossings; the returned mask has none
    rec = _walk(60.0, (1.0, 0.2))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        det = HmmDetector().fit(rec.left)
        st = det.detect(rec.left)
    grid = model_grid(rec.left, "gyr", 100.0)
    model = build_hmm(det.startprob_, det.transmat_, det.means_, det.covars_, seed=0)
    plain = stance_intervals(model.decode(grid.features, algorithm="viterbi")[1] == 0)
    assert np.sum(np.diff(plain, axis=1) < 5) > 10
    assert np.all(np.diff(st.intervals, axis=1).ravel() / 60.0 >= MIN_STANCE_S - 1e-9)
