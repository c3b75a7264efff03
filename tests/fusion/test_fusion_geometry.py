"""Two-foot fusion geometry against the simulator's truth and hand-computed cases (issue 17).

Which foot is left, the sign of the step width, each foot's final position against its truth,
the range constraint's projections computed by hand, the particle update at the stance end it
belongs to, the DTW fusion's band against dtaidistance. Measured values in the comments are from
``python tests/fusion/test_fusion_geometry.py`` (prints them; seeds 0-2).
"""

from types import SimpleNamespace

import numpy as np
import pytest

import footnav
from footnav.core.types import StanceResult
from footnav.estimators.ekf import EkfEstimator
from footnav.fusion import dtw as dtw_fusion
from footnav.fusion import particle as particle_fusion
from footnav.fusion import range_constraint
from footnav.fusion.joint import LEFT, RIGHT

DRIFTY = {"gyr_bias_walk_radps2_sqrthz": 1e-4}
FUSIONS = ("range", "step-vector", "particle", "dtw")
WALKS = {
    "straight": ("straight", {"distance_m": 30.0}),
    "rectangle": ("rectangle", {"width_m": 20.0, "height_m": 10.0}),
}


def _run(fusion, scenario, seed, **params):
    name, opts = WALKS[scenario]
    rec = footnav.simulate(name, seed=seed, **DRIFTY, **opts)
    det = footnav.make_detector("threshold")
    res = footnav.make_fusion(fusion, **params).fuse(
        EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right)
    )
    return rec, res


def _signed_separation(rec, res):
    """Left minus right foot across the walking direction (the truth's left), m: at the end, and
    the mean over the truth's double support."""
    true_sep = (rec.truth_left.position - rec.truth_right.position)[:, :2]
    across = true_sep / np.linalg.norm(true_sep, axis=1, keepdims=True)
    sep = np.sum((res.left.position - res.right.position)[:, :2] * across, axis=1)
    both = rec.truth_left.stance & rec.truth_right.stance
    return float(sep[-1]), float(sep[both].mean())


def _final_errors(rec, res):
    """Each foot's final 3-D position error against its truth, m, and its z error."""
    out = []
    for traj, truth in ((res.left, rec.truth_left), (res.right, rec.truth_right)):
        d = traj.position[-1] - truth.position[-1]
        out.append((float(np.linalg.norm(d[:2])), float(d[2])))
    return out


# -- which foot is left, each foot against its truth -------------------------------------------------

# Signed separation (final, mean over double support), m; the truth is +0.2 m. Measured over seeds
# 0-2, both walks: step-vector 0.196-0.207 / 0.198-0.203, particle 0.200-0.224 / 0.201-0.213; range
# bounds the distance, not the side: 0.005-0.355 / 0.103-0.278; dtw ties the feet at mid-swing with
# lateral offset 0 (the paper), so its feet meet: -0.043-0.056 / 0.078-0.128. Feet on the wrong
# side measure about -0.2 m.
SIDE = {"range": (-0.1, 0.05), "step-vector": (0.15, 0.15), "particle": (0.15, 0.15), "dtw": (-0.1, 0.04)}
# 2-D final error per foot against its truth, m, max over seeds 0-2, both feet, both walks (30 m
# straight, 20 x 10 m rectangle, drifty gyro): range 0.228, step-vector 0.187, particle 0.219,
# dtw 0.208. Bounds about 2x.
FINAL_ERROR_M = {"range": 0.5, "step-vector": 0.4, "particle": 0.45, "dtw": 0.45}
# z at the end, m: every fusion inherits the ekf's downward drift (about 1 mm per step at 100 Hz
# from the mechanization, under investigation); measured |z| max 0.138 (range, particle, dtw),
# 0.242 (step-vector, whose step elevation 0 ties the feet's drifts together). Today's behaviour
# as the bound, to tighten when the drift is fixed.
FINAL_Z_M = {"range": 0.3, "step-vector": 0.45, "particle": 0.3, "dtw": 0.3}


@pytest.mark.parametrize("scenario", sorted(WALKS))
@pytest.mark.parametrize("fusion", FUSIONS)
def test_left_foot_is_left_and_each_foot_ends_near_its_truth(fusion, scenario):
    lo_final, lo_mean = SIDE[fusion]
    for seed in range(3):
        rec, res = _run(fusion, scenario, seed)
        final, mean = _signed_separation(rec, res)
        assert mean >= lo_mean, (seed, mean)
        assert final >= lo_final, (seed, final)
        for err_xy, err_z in _final_errors(rec, res):
            assert err_xy <= FINAL_ERROR_M[fusion], (seed, err_xy)
            assert abs(err_z) <= FINAL_Z_M[fusion], (seed, err_z)


def test_step_vector_puts_the_step_width_on_the_front_foot_side():
    # the measured step width (0.2 m) on the left of the walking direction for the left foot: the
    # separation across the walk stays at +0.2 m all through, on straights and in turns
    for scenario in WALKS:
        rec, res = _run("step-vector", scenario, 0)
        final, mean = _signed_separation(rec, res)
        assert final == pytest.approx(0.2, abs=0.03) and mean == pytest.approx(0.2, abs=0.02)


def test_range_constraint_keeps_the_feet_on_a_long_drifty_walk():
    # the 100 m walk, shortened: the constraint fires and pulls each foot to its truth.
    # Measured (seed 0, 60 m straight): final 2-D errors 0.31 / 0.30 m, 0.9 / 1.0 m independent.
    rec = footnav.simulate("straight", seed=0, distance_m=60.0, **DRIFTY)
    det = footnav.make_detector("threshold")
    args = (EkfEstimator(), rec.left, det.detect(rec.left), rec.right, det.detect(rec.right))
    res = footnav.make_fusion("range").fuse(*args)
    assert res.meta["constraint_updates"] > 10
    for err_xy, _ in _final_errors(rec, res):
        assert err_xy < 0.7


# -- the range constraint's projections, by hand --------------------------------------------------


class _StubFilter:
    """Joint filter stand-in: fixed positions, fixed sample index; records the position updates."""

    def __init__(self, p_left, p_right, k):
        self.p = [np.asarray(p_left, float), np.asarray(p_right, float)]
        self.k = k
        self.updates = []

    def run_until(self, t):
        pass

    def position(self, foot):
        return self.p[foot].copy()

    def index(self, foot):
        return self.k

    def update_position(self, foot, z, std):
        self.updates.append((foot, np.asarray(z, float).copy()))


def _project(monkeypatch, projection, p_left, p_right, left_standing, right_standing):
    stub = _StubFilter(p_left, p_right, k=5)
    monkeypatch.setattr(range_constraint, "start_joint", lambda *a, **k: stub)
    monkeypatch.setattr(range_constraint, "closing_time", lambda *a, **k: np.inf)
    monkeypatch.setattr(range_constraint, "finish_joint", lambda *a, **k: stub.updates)
    imu = SimpleNamespace(t=np.arange(10) * 0.1, rate_hz=10.0)
    masks = []
    for standing in (left_standing, right_standing):
        m = np.zeros(10, bool)
        m[:2] = True  # a first stance, then at sample 5 standing or not
        m[5] = standing
        masks.append(StanceResult(m))
    fusion = range_constraint.RangeConstraintFusion(max_separation_m=1.0, projection=projection, check_interval_s=10.0)
    updates = fusion._fuse_span(None, imu, masks[0], imu, masks[1])
    assert updates, "the constraint must fire: the feet are 5 m apart"
    return updates[0] if projection == "moving" and left_standing != right_standing else updates[:2]


def test_range_moving_projection_hand_computed(monkeypatch):
    # left foot standing at the origin, right foot at (3, 4, 0), 5 m away: the right foot is moved
    # onto the 1 m sphere around the left, towards where it is: (0.6, 0.8, 0)
    foot, z = _project(monkeypatch, "moving", [0, 0, 0], [3, 4, 0], True, False)
    assert foot == RIGHT
    np.testing.assert_allclose(z, [0.6, 0.8, 0.0], atol=1e-12)
    # right foot standing at (1, 1, 0), left at (1, -4, 0): the left moves to (1, 0, 0)
    foot, z = _project(monkeypatch, "moving", [1, -4, 0], [1, 1, 0], False, True)
    assert foot == LEFT
    np.testing.assert_allclose(z, [1.0, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize(
    "projection, standing", [("symmetric", (True, False)), ("moving", (True, True)), ("moving", (False, False))]
)
def test_range_symmetric_projection_hand_computed(monkeypatch, projection, standing):
    # both feet move about their centroid (1.5, 2, 0) to 0.5 m each side, along the line joining them
    (f1, z1), (f2, z2) = _project(monkeypatch, projection, [3, 4, 0], [0, 0, 0], *standing)
    assert (f1, f2) == (LEFT, RIGHT)
    np.testing.assert_allclose(z1, [1.8, 2.4, 0.0], atol=1e-12)
    np.testing.assert_allclose(z2, [1.2, 1.6, 0.0], atol=1e-12)


# -- the particle update at the stance end it belongs to ---------------------------------------------


@pytest.mark.parametrize("mode", ["footnav", "paper"])
def test_particle_update_comes_at_the_last_sample_of_each_stance(monkeypatch, mode):
    # Lee, Cho & Park (2022), Alg. 1: the PF update of a foot is at the end of its zero-velocity
    # phase, i.e. after its last stance sample and before its first swing sample
    rec = footnav.simulate("straight", seed=0, distance_m=8.0)
    stances = [StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)]
    seen = []
    if mode == "footnav":
        real_start = particle_fusion.start_joint

        def spying_start(*args, **kwargs):
            filt = real_start(*args, **kwargs)
            real_update = filt.update

            def update(h, innovation, r, **kw):
                foot = LEFT if np.any(h[:, filt.block(LEFT, "pos")]) else RIGHT
                seen.append((foot, filt.index(foot)))
                return real_update(h, innovation, r, **kw)

            filt.update = update
            return filt

        monkeypatch.setattr(particle_fusion, "start_joint", spying_start)
    else:
        real_set = particle_fusion.PaperFoot.set_cloud

        def set_cloud(self, cloud):
            seen.append((LEFT if self.side < 0 else RIGHT, self.k))
            return real_set(self, cloud)

        monkeypatch.setattr(particle_fusion.PaperFoot, "set_cloud", set_cloud)
    res = particle_fusion.ParticleFusion(mode=mode).fuse(EkfEstimator(), rec.left, stances[0], rec.right, stances[1])
    expected = sorted((foot, int(stop) - 1) for foot in (LEFT, RIGHT) for _, stop in stances[foot].intervals[:-1])
    assert res.meta["pf_updates"] == len(expected)
    assert sorted(seen) == expected


# -- the DTW fusion's band ------------------------------------------------------------------------


def test_dtw_timeless_average_uses_exactly_band_s_against_dtaidistance():
    dtw_ndim = pytest.importorskip("dtaidistance.dtw_ndim")
    # two feet on the same track, the right one 4 samples (0.4 s at 10 Hz) behind: a band of 3
    # samples cannot pair them exactly, a band of 4 can
    rate, lag = 10.0, 4
    s = np.arange(56) / rate
    base = np.stack([np.cumsum(np.abs(np.sin(s))), np.sin(1.3 * s), 0.1 * np.cos(s)], axis=1)
    # the same track, one foot waiting 4 samples at the end, the other at the start
    track = np.vstack([base, np.repeat(base[-1:], lag, axis=0)])
    late = np.vstack([np.repeat(base[:1], lag, axis=0), base])
    t = np.arange(len(track)) / rate

    def traj(pos):
        n = len(pos)
        return footnav.FootTrajectory(
            t=t,
            position=pos,
            velocity=np.zeros((n, 3)),
            quaternion=np.tile([1.0, 0, 0, 0], (n, 1)),
            position_std=np.zeros((n, 3)),
            steps=np.zeros((0, 2), dtype=np.int64),
        )

    # the fusion resamples to its rate on [t0, t1): the samples the pairing sees
    n = len(np.arange(t[0], t[-1], 1.0 / rate))
    ours, ref = {}, {}
    for band in range(2, 7):
        ours[band] = dtw_fusion.feet_timeless_average(traj(track), traj(late), band / rate, rate).meta["dtw_distance_m"]
        # dtaidistance: window w allows |i - j| < w, so a band of b samples is window b + 1. Its
        # distance is the root of summed squared costs, footnav's a mean Euclidean cost: the two
        # differ in value, but a band one sample wider changes both or neither
        ref[band] = dtw_ndim.distance(track[:n], late[:n], window=band + 1, use_c=False)
    for band in range(2, 6):
        widening_helps_ref = ref[band + 1] < ref[band] - 1e-9
        widening_helps_ours = ours[band + 1] < ours[band] - 1e-9
        assert widening_helps_ours == widening_helps_ref, (band, ours, ref)
    assert ref[3] > ref[4] + 1e-3  # the case discriminates: the 4-sample lag needs band 4


def test_dtw_heading_search_band_is_band_s_at_the_dtw_rate(monkeypatch):
    seen = []
    real = dtw_fusion.feet_heading_mismatch

    def spy(a, b, band, *args, **kwargs):
        seen.append((len(a), len(b), band))
        return real(a, b, band, *args, **kwargs)

    monkeypatch.setattr(dtw_fusion, "feet_heading_mismatch", spy)
    rec = footnav.simulate("straight", seed=0, distance_m=8.0)
    stances = [StanceResult(rec.truth_left.stance), StanceResult(rec.truth_right.stance)]
    dtw_fusion.DtwFusion(band_s=1.5, dtw_rate_hz=10.0).fuse(EkfEstimator(), rec.left, stances[0], rec.right, stances[1])
    ((n, m, band),) = seen
    # the paper's maximum index difference: band_s x rate samples (15), widened only to |N - M|
    assert band == max(15, abs(n - m))
    assert abs(n - m) < 15


if __name__ == "__main__":  # print the measured values the comments quote
    for fusion in FUSIONS:
        for scenario in sorted(WALKS):
            for seed in range(3):
                rec, res = _run(fusion, scenario, seed)
                print(
                    fusion,
                    scenario,
                    seed,
                    "side final/mean {:.3f} {:.3f}".format(*_signed_separation(rec, res)),
                    "err xy/z",
                    [(round(a, 3), round(b, 3)) for a, b in _final_errors(rec, res)],
                )
