"""Online detection of both feet together (footnav.pipeline.online_pair): the dual-gait detector
live, in blocks on windows of both feet, gives the offline stances on the simulator and on
shared recordings, the same in any chunks; close() is the offline run."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from online_replay import STEP, _replay, shared_recordings  # tests/online_replay.py

import footnav
from footnav.core.errors import CompositionError


@pytest.fixture(scope="module")
def walk():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.simulate("rectangle", seed=3, width_m=12, height_m=6)


def _pipe(fusion="independent"):
    return footnav.make_pipeline("dual-gait", "ekf", fusion, estimator_params=STEP)


def _offline(pipe, left, right):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pipe.run(left, right)


def _live(pipe, left, right, *sizes, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got, _, result, stream = _replay(pipe, left, right, *sizes, **options)
    masks = {f.foot: f.trajectory()[1].mask for f in stream.feet}  # the decisions the stream took
    return got, masks, result, stream


@pytest.mark.parametrize("sizes", [(1, 1), (7, 13), (1000, 1000)])
def test_chunks_give_the_offline_stances_and_samples(walk, sizes):
    pipe = _pipe()
    off = _offline(pipe, walk.left, walk.right)
    got, masks, result, stream = _live(pipe, walk.left, walk.right, *sizes)
    assert stream.rerun and stream.latency_s == pipe.detector.latency_s
    for foot in ("left", "right"):
        ref = getattr(off, foot)
        np.testing.assert_array_equal(masks[foot], getattr(off, f"stance_{foot}").mask)
        np.testing.assert_allclose(got[foot], ref.position, atol=1e-9, rtol=0)  # live: the offline step-wise run
        np.testing.assert_allclose(getattr(result, foot).position, ref.position, atol=1e-9, rtol=0)


def test_feet_on_different_spans(walk):
    """The right foot starts 0.3 s after the left and stops 1.5 s before it: the left foot's first
    and last samples are decided with the right foot absent from their windows, as offline."""
    left, right = walk.left, walk.right.slice(30, walk.right.n_samples - 150)
    pipe = _pipe()
    off = _offline(pipe, left, right)
    _, masks, result, _ = _live(pipe, left, right, 7, 5)
    for foot in ("left", "right"):
        np.testing.assert_array_equal(masks[foot], getattr(off, f"stance_{foot}").mask)
        np.testing.assert_allclose(getattr(result, foot).position, getattr(off, foot).position, atol=1e-9, rtol=0)


def test_latency_is_declared_and_kept(walk):
    """Pushed sample by sample: each step is final within the declared latency (the block it
    falls in, the detector's reach past it) and the 3 samples a step end needs."""
    pipe = _pipe()
    _, _, _, stream = _live(pipe, walk.left, walk.right, 1, 1)
    latency = pipe.detector.latency_s
    for f in stream.feet:
        lat = [(b - a) / f.rate_hz for a, b in f.step_final_at]
        assert len(lat) > 15 and max(lat) <= latency + 3 / f.rate_hz + 1e-9
        assert min(lat) >= latency - pipe.detector.online_block_s - 1e-9  # nothing is final before its window is


def test_a_coupled_fusion_on_dual_gait_stances(walk):
    pipe = _pipe("range")
    off = _offline(pipe, walk.left, walk.right)
    _, masks, result, _ = _live(pipe, walk.left, walk.right, 7, 13)
    for foot in ("left", "right"):
        np.testing.assert_array_equal(masks[foot], getattr(off, f"stance_{foot}").mask)
        np.testing.assert_allclose(getattr(result, foot).position, getattr(off, foot).position, atol=1e-9, rtol=0)


def test_one_foot_is_refused():
    with pytest.raises(CompositionError, match="detector 'dual-gait' needs both feet"):
        _pipe().online(feet=1)


def test_shared_recordings(shared_data):
    """gaitmap and azure_fgo: the live stances and step-wise samples are the offline ones
    (tests/online_startup.py --dual-gait gives every shared two-foot recording)."""
    pipe = _pipe()
    seen = 0
    for rec in shared_recordings(shared_data, ("gaitmap", "azure_fgo")):
        off = _offline(pipe, rec.left, rec.right)
        got, masks, _, _ = _live(pipe, rec.left, rec.right, 50, rate_hz=rec.left.rate_hz)
        for foot in ("left", "right"):
            np.testing.assert_array_equal(masks[foot], getattr(off, f"stance_{foot}").mask)
            np.testing.assert_allclose(got[foot], getattr(off, foot).position, atol=1e-9, rtol=0)
        seen += 1
    if not seen:
        pytest.skip("no shared two-foot recording found")
