"""Chistyakov et al. (2021) as published: Alg. 1's closed loop inside Alg. 2's two-foot filter,
applied only at a checked final rest; the DTW heading search on Alg. 1's output."""

import numpy as np
import pytest

import footnav
from footnav import InvalidInputError

CLOSED = {"name": "ekf", "smoother": "whole", "closed_loop": True}


@pytest.fixture(scope="module")
def loop():
    rec = footnav.simulate("rectangle", seed=1)
    assert rec.truth_left.closed_loop and rec.truth_right.closed_loop
    return rec


@pytest.mark.parametrize("tracks", ["smoothed", "forward"])
def test_alg2_with_the_closed_loop_ends_both_feet_at_their_start(loop, tracks):
    res = footnav.make_pipeline("glrt", CLOSED, {"name": "dtw", "heading_tracks": tracks}).run(loop)
    for traj, truth in ((res.left, loop.truth_left), (res.right, loop.truth_right)):
        # the truth's own end (the walk returns to its start), not the estimate's start
        assert np.linalg.norm(truth.position[-1] - truth.position[0]) < 1e-9
        assert np.linalg.norm(traj.position[-1] - traj.position[0]) < 0.05
    assert set(res.meta["fusion"]["closed_loop"]) == {"left", "right"}


def test_without_the_closed_loop_the_same_walk_does_not_close(loop):
    # guards the test above: the closure comes from the measurement, not from an easy walk
    res = footnav.make_pipeline("glrt", {"name": "ekf", "smoother": "whole"}, "dtw").run(loop)
    assert np.linalg.norm(res.left.position[-1] - res.left.position[0]) > 0.3


def test_the_closed_loop_applies_at_the_final_rest(loop):
    res = footnav.make_pipeline("glrt", CLOSED, "range").run(loop)
    st = res.stance_left
    last = res.meta["fusion"]["closed_loop"]["left"]["index"]
    assert last == st.intervals[-1, 1] - 1
    assert st.mask[last] and loop.left.t[-1] - loop.left.t[last] <= 0.5


def test_a_walk_that_does_not_end_at_rest_is_refused(loop):
    n = loop.left.n_samples
    left, right = loop.left.slice(0, int(n * 0.6)), loop.right.slice(0, int(n * 0.6))
    with pytest.raises(InvalidInputError, match="does not end at rest"):
        footnav.make_pipeline("glrt", CLOSED, "dtw").run(left, right)


def test_fusions_that_do_not_apply_the_closed_loop_say_so_or_apply_it(loop):
    for name in footnav.list_components()["fusion"]:
        if name == "independent":
            continue
        try:
            res = footnav.make_pipeline("glrt", CLOSED, name).run(loop)
        except footnav.CompositionError as exc:
            assert "closed_loop" in str(exc)
            continue
        # range projects the feet onto absolute positions and trusts them: its covariance is too
        # small for the closing measurement to pull all the way (0.058 m here; dtw 0.006 m)
        assert np.linalg.norm(res.left.position[-1] - res.left.position[0]) < 0.1, name


def test_heading_tracks_is_validated():
    with pytest.raises(footnav.InvalidParameterError, match="heading_tracks"):
        footnav.make_fusion("dtw", heading_tracks="backward").validate_params()
