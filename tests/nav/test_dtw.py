"""footnav.nav.dtw, dtw_heading and dtw_average against hand-computed cases, a textbook full-matrix DTW
and dtaidistance.

dtaidistance conventions (used only here, as an independent reference):
``dtw_ndim.distance`` sums *squared* Euclidean point costs and returns the square root of the sum
(our ``cost="sqeuclidean", normalize="none"``); ``inner_dist="euclidean"`` sums Euclidean costs
(our ``total_cost`` with the default cost). Its ``window=w`` allows ``|i - j| <= w - 1`` for equal
lengths; for unequal lengths it widens the band on one side by ``|N - M|``, so there it brackets
our symmetric band instead of matching it.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import footnav
from footnav.core.errors import InvalidInputError, InvalidParameterError
from footnav.nav.dtw import dtw_align
from footnav.nav.dtw_average import AveragedPath, timed_average, timeless_average
from footnav.nav.dtw_heading import heading_mismatch

EXACT = 1e-12


def full_dtw(a: np.ndarray, b: np.ndarray, band: int | None, squared: bool = False) -> float:
    """Textbook DTW on the full (N+1) x (M+1) matrix, cells outside |i - j| <= band set to inf."""
    n, m = len(a), len(b)
    c = np.sum((a[:, None, :] - b[None, :, :]) ** 2, axis=2)
    c = c if squared else np.sqrt(c)
    if band is not None:
        c[np.abs(np.arange(n)[:, None] - np.arange(m)[None, :]) > band] = np.inf
    d = np.full((n + 1, m + 1), np.inf)
    d[0, 0] = 0.0
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            d[i, j] = c[i - 1, j - 1] + min(d[i - 1, j - 1], d[i - 1, j], d[i, j - 1])
    return float(d[n, m])


def assert_valid_path(path: np.ndarray, n: int, m: int, band: int | None = None) -> None:
    assert path.dtype == np.int64 and path.ndim == 2 and path.shape[1] == 2
    assert tuple(path[0]) == (0, 0) and tuple(path[-1]) == (n - 1, m - 1)  # endpoints
    steps = np.diff(path, axis=0)
    assert ((steps >= 0) & (steps <= 1)).all()  # monotone and continuous
    assert (steps.sum(axis=1) >= 1).all()  # never stands still
    assert max(n, m) <= len(path) <= n + m - 1
    if band is not None:
        assert (np.abs(path[:, 0] - path[:, 1]) <= band).all()


def path_cost(a, b, path, squared=False):
    c = np.sum((a[path[:, 0]] - b[path[:, 1]]) ** 2, axis=1)
    return float((c if squared else np.sqrt(c)).sum())


def rotate_about_start(p: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    out = p.copy()
    out[:, :2] = p[0, :2] + (p[:, :2] - p[0, :2]) @ np.array([[c, -s], [s, c]]).T
    return out


# ---------------------------------------------------------------------------------------------
# DTW: hand-computed cases
# ---------------------------------------------------------------------------------------------
def test_hand_computed_unequal_lengths():
    # a = x 0, 1, 2; b = x 0, 2. D(0,0)=0, D(1,0)=1, D(2,1)=0+min(D(1,0)=1, D(1,1)=1, D(2,0)=3)=1:
    # path (0,0) (1,0) (2,1), total 1 m over 3 pairs, mean 1/3 m (tie broken to the diagonal)
    a = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    b = np.array([[0.0, 0.0], [2.0, 0.0]])
    r = dtw_align(a, b, return_path=True)
    assert r.total_cost == pytest.approx(1.0, abs=EXACT)
    assert r.n_pairs == 3
    assert r.distance_m == pytest.approx(1.0 / 3.0, abs=EXACT)
    np.testing.assert_array_equal(r.path, [[0, 0], [1, 0], [2, 1]])
    assert not r.path.flags.writeable
    assert dtw_align(a, b, normalize="none").distance_m == pytest.approx(1.0, abs=EXACT)
    # squared cost: 0 + 1 + 0 = 1 m^2; "none" -> sqrt(1) = 1 m, "mean" -> sqrt(1/3) m (RMS)
    assert dtw_align(a, b, cost="sqeuclidean", normalize="none").distance_m == pytest.approx(1.0, abs=EXACT)
    assert dtw_align(a, b, cost="sqeuclidean").distance_m == pytest.approx(np.sqrt(1.0 / 3.0), abs=EXACT)
    assert dtw_align(a, b, band=1).total_cost == pytest.approx(1.0, abs=EXACT)


def test_hand_computed_band():
    # x: a = 0 0 0 1, b = 0 1 1 1.
    # band 0 = lock-step: |0-0| + |0-1| + |0-1| + |1-1| = 2.
    # band 1: D(1,0)=0, D(2,1)=1+D(1,0)=1, D(3,2)=0+D(2,1)=1, D(3,3)=0+min(2, 3, 1)=1 -> 1.
    # band 2 reaches (2,0) and (3,1): a0..a2 -> b0, a3 -> b1..b3, total 0 (= unbounded).
    a = np.array([[0.0], [0.0], [0.0], [1.0]])
    b = np.array([[0.0], [1.0], [1.0], [1.0]])
    expected = {0: 2.0, 1: 1.0, 2: 0.0, 3: 0.0, None: 0.0}
    for band, total in expected.items():
        r = dtw_align(a, b, band=band, return_path=True)
        assert r.total_cost == pytest.approx(total, abs=EXACT), band
        assert_valid_path(r.path, 4, 4, band)
    np.testing.assert_array_equal(dtw_align(a, b, band=0, return_path=True).path, [[0, 0], [1, 1], [2, 2], [3, 3]])
    np.testing.assert_array_equal(
        dtw_align(a, b, band=2, return_path=True).path, [[0, 0], [1, 0], [2, 0], [3, 1], [3, 2], [3, 3]]
    )


def test_single_points_and_identical():
    r = dtw_align([[1.0, 2.0]], [[4.0, 6.0]], band=0, return_path=True)
    assert (r.total_cost, r.n_pairs, r.distance_m) == (5.0, 1, 5.0)
    np.testing.assert_array_equal(r.path, [[0, 0]])
    x = np.random.default_rng(0).normal(size=(50, 3))
    r = dtw_align(x, x, band=3, return_path=True)
    assert r.total_cost == 0.0 and r.n_pairs == 50
    np.testing.assert_array_equal(r.path, np.column_stack([np.arange(50), np.arange(50)]))


# ---------------------------------------------------------------------------------------------
# DTW: against a textbook implementation and dtaidistance
# ---------------------------------------------------------------------------------------------
traj = st.integers(1, 10).flatmap(
    lambda n: st.lists(st.tuples(*[st.floats(-5, 5, allow_nan=False)] * 3), min_size=n, max_size=n)
)


@settings(max_examples=120, deadline=None)
@given(a=traj, b=traj, extra=st.one_of(st.none(), st.integers(0, 5)), squared=st.booleans())
def test_matches_full_matrix_dtw(a, b, extra, squared):
    a, b = np.array(a), np.array(b)
    n, m = len(a), len(b)
    band = None if extra is None else abs(n - m) + extra
    cost = "sqeuclidean" if squared else "euclidean"
    r = dtw_align(a, b, band=band, cost=cost, return_path=True)
    assert r.total_cost == pytest.approx(full_dtw(a, b, band, squared), rel=1e-9, abs=1e-12)
    assert_valid_path(r.path, n, m, band)
    assert len(r.path) == r.n_pairs
    assert path_cost(a, b, r.path, squared) == pytest.approx(r.total_cost, rel=1e-9, abs=1e-12)
    # without the path: the same numbers
    q = dtw_align(a, b, band=band, cost=cost)
    assert (q.total_cost, q.n_pairs, q.path) == (r.total_cost, r.n_pairs, None)


@pytest.mark.parametrize("seed", range(6))
def test_band_wider_than_the_length_is_full_dtw(seed):
    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=(30, 2)), rng.normal(size=(23, 2))
    full = dtw_align(a, b, return_path=True)
    assert full.total_cost == pytest.approx(full_dtw(a, b, None), rel=1e-12)
    for band in (30, 31, 1000):
        r = dtw_align(a, b, band=band, return_path=True)
        assert r.total_cost == full.total_cost and r.n_pairs == full.n_pairs
        np.testing.assert_array_equal(r.path, full.path)


@pytest.mark.parametrize("seed", range(4))
def test_cost_does_not_grow_with_the_band(seed):
    rng = np.random.default_rng(seed)
    a = np.cumsum(rng.normal(size=(80, 2)), axis=0)
    b = np.cumsum(rng.normal(size=(70, 2)), axis=0)
    totals = [dtw_align(a, b, band=w).total_cost for w in range(10, 81, 5)]
    assert all(x >= y - 1e-12 for x, y in zip(totals, totals[1:]))
    assert totals[-1] == pytest.approx(dtw_align(a, b).total_cost)
    # band 0 on equal lengths is the lock-step (Euclidean) sum
    assert dtw_align(a[:70], b, band=0).total_cost == pytest.approx(np.linalg.norm(a[:70] - b, axis=1).sum())


@settings(max_examples=40, deadline=None)
@given(n=st.integers(2, 14), m=st.integers(2, 14), extra=st.integers(0, 6), seed=st.integers(0, 2**31 - 1))
def test_against_dtaidistance(n, m, extra, seed):
    dtw_ndim = pytest.importorskip("dtaidistance.dtw_ndim")
    rng = np.random.default_rng(seed)
    a, b = rng.normal(size=(n, 2)), rng.normal(size=(m, 2))
    # unbounded: sqrt(sum of squared costs), and the Euclidean-cost total
    ours = dtw_align(a, b, cost="sqeuclidean", normalize="none", return_path=True)
    assert ours.distance_m == pytest.approx(dtw_ndim.distance(a, b, use_pruning=False), rel=1e-9)
    assert dtw_align(a, b).total_cost == pytest.approx(
        dtw_ndim.distance(a, b, inner_dist="euclidean", use_pruning=False), rel=1e-9
    )
    # its warping path costs what ours does (paths may differ only by ties)
    ref_path = np.array(dtw_ndim.warping_path(a, b, use_pruning=False))
    assert_valid_path(ref_path.astype(np.int64), n, m)
    assert path_cost(a, b, ref_path, squared=True) == pytest.approx(ours.total_cost, rel=1e-9)
    # banded, equal lengths: window = band + 1 is exactly |i - j| <= band
    band = extra
    a2 = rng.normal(size=(n, 2))
    eq = dtw_align(a, a2, band=band, cost="sqeuclidean", normalize="none")
    assert eq.distance_m == pytest.approx(dtw_ndim.distance(a, a2, window=band + 1, use_pruning=False), rel=1e-9)
    # banded, unequal lengths: dtaidistance's band is one-sided wider; ours lies between the
    # window that contains it and the window it contains
    band = abs(n - m) + extra
    r = dtw_align(a, b, band=band, cost="sqeuclidean", normalize="none").distance_m
    wider = dtw_ndim.distance(a, b, window=band + 1, use_pruning=False)
    narrower = dtw_ndim.distance(a, b, window=band - abs(n - m) + 1, use_pruning=False)
    assert wider - 1e-9 <= r <= narrower + 1e-9


def test_long_banded_input():
    # 20000 x 101 cells; the back-pointers of the band (2 MB), not N x M (400 MB)
    rng = np.random.default_rng(1)
    a = np.cumsum(rng.normal(size=(20000, 3)), axis=0)
    b = a + rng.normal(scale=0.1, size=a.shape)
    r = dtw_align(a, b, band=50, return_path=True)
    assert_valid_path(r.path, 20000, 20000, 50)
    assert r.distance_m < 0.2


@pytest.mark.parametrize("seed", range(4))
def test_distance_kernel_is_the_path_kernel_to_the_bit(seed):
    # dtw_align without the path runs its own kernel (no back-pointers, predecessors padded
    # with inf, a row that may stop early): the same totals and pair counts, ties included
    # (integer coordinates tie often), in 1-3 dimensions, any band
    from footnav.nav.dtw import _dtw_cost_kernel, _dtw_kernel

    rng = np.random.default_rng(seed)
    for _ in range(300):
        n, m, d = int(rng.integers(1, 30)), int(rng.integers(1, 30)), int(rng.integers(1, 4))
        a, b = (rng.integers(0, 3, (k, d)).astype(float) if seed % 2 else rng.normal(size=(k, d)) for k in (n, m))
        band = np.int64(rng.integers(abs(n - m), max(n, m) + 3))
        for squared in (False, True):
            total, pairs, _ = _dtw_kernel(a, b, band, squared, False)
            assert _dtw_cost_kernel(a, b, band, squared, np.inf) == (total, pairs)
            # stopping early only where the mean is certainly above the limit
            stopped = _dtw_cost_kernel(a, b, band, squared, 0.999 * total / pairs)
            assert stopped == (total, pairs) or stopped == (np.inf, 0)
            assert _dtw_cost_kernel(a, b, band, squared, total / pairs) == (total, pairs)


# ---------------------------------------------------------------------------------------------
# DTW: errors
# ---------------------------------------------------------------------------------------------
def test_band_too_narrow_is_a_clear_error():
    a, b = np.zeros((10, 2)), np.zeros((7, 2))
    with pytest.raises(InvalidParameterError, match=r"band=2 .*10 and 7 .*\|N - M\| = 3"):
        dtw_align(a, b, band=2)
    with pytest.raises(ValueError):  # InvalidParameterError is a ValueError too
        dtw_align(b, a, band=0)
    assert dtw_align(a, b, band=3).total_cost == 0.0


@pytest.mark.parametrize("band", [-1, 1.5, True, "3", [2]])
def test_bad_band(band):
    with pytest.raises(InvalidParameterError, match="band"):
        dtw_align(np.zeros((3, 2)), np.zeros((3, 2)), band=band)


def test_whole_float_band_is_accepted():
    a = np.random.default_rng(0).normal(size=(6, 2))
    assert dtw_align(a, a[::-1], band=2.0).total_cost == dtw_align(a, a[::-1], band=2).total_cost


def test_bad_input():
    good = np.zeros((3, 2))
    with pytest.raises(InvalidInputError, match="'b'.*index 1.*finite"):
        dtw_align(good, [[0.0, 0.0], [np.nan, 0.0]])
    with pytest.raises(InvalidInputError, match="'a'.*empty"):
        dtw_align(np.empty((0, 2)), good)
    with pytest.raises(InvalidInputError, match="'a'.*shape"):
        dtw_align(np.zeros(3), good)
    with pytest.raises(InvalidInputError, match="2 coordinate.*3"):
        dtw_align(good, np.zeros((3, 3)))
    with pytest.raises(InvalidParameterError, match="cost"):
        dtw_align(good, good, cost="manhattan")
    with pytest.raises(InvalidParameterError, match="normalize"):
        dtw_align(good, good, normalize="sum")


# ---------------------------------------------------------------------------------------------
# heading mismatch
# ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def rect():
    return footnav.simulate("rectangle", width_m=20, height_m=10)


def centre_line_distance(rec, p):
    """Horizontal distance (m) of points p to the simulated centre line: the rectangle of
    ``meta["rectangle_corners_m"]`` with corners rounded to ``turn_radius_m`` (a rounded box)."""
    corners = rec.meta["rectangle_corners_m"]
    r = rec.meta["options"]["turn_radius_m"]
    centre = 0.5 * (corners.min(axis=0) + corners.max(axis=0))
    half = 0.5 * (corners.max(axis=0) - corners.min(axis=0))
    q = np.abs(p[:, :2] - centre) - (half - r)
    return np.abs(np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0) - r)


def test_heading_of_a_turned_straight_line():
    a = np.column_stack([np.linspace(0, 10, 50), np.zeros(50)])
    b = np.column_stack([np.zeros(50), np.linspace(0, 10, 50)])  # +90 deg
    h = heading_mismatch(a, b, band=5)
    assert h.angle_rad == pytest.approx(-np.pi / 2, abs=1e-3)
    assert h.distance_m == pytest.approx(0.0, abs=1e-2)
    np.testing.assert_allclose(h.apply(b), a, atol=1e-2)


@pytest.mark.parametrize("angle", [0.6, -2.0, 3.0])
def test_heading_recovers_a_rotation_of_the_same_foot(rect, angle):
    a = rect.truth_left.position[::10]  # 100 Hz -> 10 Hz
    h = heading_mismatch(a, rotate_about_start(a, angle), band=20)
    assert h.angle_rad == pytest.approx(-angle, abs=1e-3)
    assert h.distance_m == pytest.approx(0.0, abs=1e-3)


@pytest.mark.parametrize("angle", [0.6, -2.0, 3.0])
@pytest.mark.parametrize("translation", ["none", "start"])
def test_heading_recovers_a_rotation_of_the_other_foot(rect, angle, translation):
    # The feet walk 0.2 m apart, so the DTW-optimal angle is not exactly the true one: turning
    # the right foot's loop slightly brings it nearer the left one on some sides. Measured
    # |error| 0.009-0.012 rad ("none") and 0.014-0.015 rad ("start"); the tolerance is 0.02 rad.
    a, b = rect.truth_left.position[::10], rect.truth_right.position[::10]
    br = rotate_about_start(b, angle)
    h = heading_mismatch(a, br, band=20, translation=translation)
    assert -np.pi < h.angle_rad <= np.pi
    assert h.angle_rad == pytest.approx(-angle, abs=0.02)
    back = h.apply(br)
    np.testing.assert_array_equal(back[:, 2], br[:, 2])  # z untouched
    np.testing.assert_allclose(back[0, :2], a[0, :2] if translation == "start" else b[0, :2], atol=1e-12)
    assert h.distance_m == pytest.approx(dtw_align(a[:, :2], back[:, :2], band=20).distance_m, rel=1e-9)
    assert h.distance_m < 0.3  # feet 0.2 m apart plus the stride phase
    if translation == "none":  # the search can only improve on the true rotation
        assert h.distance_m <= dtw_align(a[:, :2], b[:, :2], band=20).distance_m + 1e-9


def test_heading_coarse_grid_is_exhaustive(rect):
    # the coarse angles stop early once certainly worse than the best so far: the angle and the
    # distance found equal a search that evaluates every coarse angle in full
    from scipy.optimize import minimize_scalar

    from footnav.nav import dtw_heading

    a, b = rect.truth_left.position[::10, :2], rotate_about_start(rect.truth_right.position[::10], 2.0)[:, :2]
    pivot, shift = b[0], a[0] - b[0]
    a_rel, b_rel = np.ascontiguousarray(a - pivot - shift), b - pivot

    def cost(x):
        return dtw_align(a_rel, dtw_heading._rotate_xy(b_rel, x), band=20).distance_m

    angles = np.linspace(-np.pi, np.pi, 36, endpoint=False)
    costs = np.array([cost(x) for x in angles])
    best = float(angles[int(np.argmin(costs))])
    res = minimize_scalar(
        cost, bounds=(best - np.pi / 18, best + np.pi / 18), method="bounded", options={"xatol": 1e-4}
    )
    h = heading_mismatch(a, b, band=20, translation="start")
    assert (h.angle_rad, h.distance_m) == (float(res.x), float(res.fun))


def test_heading_errors():
    a = np.zeros((10, 2))
    with pytest.raises(InvalidParameterError, match=r"\|N - M\| = 4"):
        heading_mismatch(a, np.zeros((6, 2)), band=2)
    with pytest.raises(InvalidParameterError, match="translation"):
        heading_mismatch(a, a, band=2, translation="optimal")
    with pytest.raises(InvalidParameterError, match="grid"):
        heading_mismatch(a, a, band=2, grid=2)
    with pytest.raises(InvalidInputError, match="'b'.*shape"):
        heading_mismatch(a, np.zeros((10, 1)), band=2)


# ---------------------------------------------------------------------------------------------
# averaged path
# ---------------------------------------------------------------------------------------------
def test_timeless_average_hand_computed():
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    b = np.array([[0.0, 0.2, 1.0], [2.0, 0.2, 1.0]])
    r = timeless_average(a, b, band=1, dims=2, t_a=[0.0, 1.0, 2.0], t_b=[10.0, 11.0])
    assert isinstance(r, AveragedPath)
    np.testing.assert_array_equal(r.pairs, [[0, 0], [1, 0], [2, 1]])
    np.testing.assert_allclose(r.position, [[0.0, 0.1, 0.5], [0.5, 0.1, 0.5], [2.0, 0.1, 0.5]], atol=EXACT)
    np.testing.assert_allclose(r.t, [5.0, 5.5, 6.5])
    # matched in x, y: |(0, -0.2)| + |(1, -0.2)| + |(0, -0.2)| over 3 pairs, in m
    assert r.distance_m == pytest.approx((0.4 + np.sqrt(1.04)) / 3.0, abs=EXACT)
    assert timeless_average(a, b, band=1, dims=2).t is None
    # matching in 3-D with z differing by 1 m: same pairs here, same averages
    np.testing.assert_array_equal(timeless_average(a, b, band=None).pairs, r.pairs)


def test_timed_average_hand_computed():
    # a moves along x at 1 m/s sampled at 0, 1, 2, 3 s; b 0.2 m to the right at 0.5, 1.5, 2.5 s
    ta = np.arange(4.0)
    a = np.column_stack([ta, np.full(4, 0.1)])
    tb = np.array([0.5, 1.5, 2.5])
    b = np.column_stack([tb, np.full(3, -0.1)])
    r = timed_average(ta, a, tb, b)
    np.testing.assert_array_equal(r.t, [1.0, 2.0])  # a's times inside the common span 0.5..2.5 s
    np.testing.assert_allclose(r.position, [[1.0, 0.0], [2.0, 0.0]], atol=EXACT)
    assert r.pairs is None and r.distance_m is None
    r = timed_average(ta, a, tb, b, t=[0.5, 0.75, 2.5])
    np.testing.assert_allclose(r.position, [[0.5, 0.0], [0.75, 0.0], [2.5, 0.0]], atol=EXACT)
    with pytest.raises(InvalidInputError, match="'t'.*index 1.*outside"):
        timed_average(ta, a, tb, b, t=[1.0, 2.75])
    with pytest.raises(InvalidInputError, match="do not overlap"):
        timed_average(ta, a, tb + 10.0, b)
    with pytest.raises(InvalidInputError, match="'t_a'.*increase"):
        timed_average([0.0, 1.0, 1.0, 2.0], a, tb, b)
    with pytest.raises(InvalidInputError, match="'t_b'.*shape"):
        timed_average(ta, a, tb[:2], b)


def test_averages_lie_on_the_centre_line(rect):
    # Each foot walks step_width / 2 = 0.1 m beside the centre line (the inner foot up to 0.2 m
    # where it cuts a corner). Their averages stay within step_width / 2 of it; measured max
    # 0.072 m (timeless, 100 and 10 Hz) and 0.061 m (timed).
    tol = 0.5 * rect.meta["options"]["step_width_m"]
    L, R = rect.truth_left, rect.truth_right
    assert centre_line_distance(rect, L.position).max() > tol - 1e-9  # the feet alone are not on it
    timed = timed_average(L.t, L.position, R.t, R.position)
    assert len(timed.t) == len(L.t)
    assert centre_line_distance(rect, timed.position).max() < tol
    for step, band in ((1, 200), (10, 20)):
        a, b = L.position[::step], R.position[::step]
        r = timeless_average(a, b, band=band, t_a=L.t[::step], t_b=R.t[::step])
        assert centre_line_distance(rect, r.position).max() < tol
        assert np.all(np.diff(r.t) >= 0)
        assert_valid_path(r.pairs, len(a), len(b), band)
        np.testing.assert_allclose(r.position[0], 0.5 * (a[0] + b[0]))
        np.testing.assert_allclose(r.position[-1], 0.5 * (a[-1] + b[-1]))
        np.testing.assert_allclose(r.position, 0.5 * (a[r.pairs[:, 0]] + b[r.pairs[:, 1]]), atol=EXACT)


def test_average_errors():
    a = np.zeros((4, 3))
    with pytest.raises(InvalidParameterError, match="dims"):
        timeless_average(a, a, band=1, dims=4)
    with pytest.raises(InvalidParameterError, match="t_a and t_b"):
        timeless_average(a, a, band=1, t_a=np.arange(4.0))
    with pytest.raises(InvalidInputError, match="'t_b'.*shape"):
        timeless_average(a, a, band=1, t_a=np.arange(4.0), t_b=np.arange(3.0))
    with pytest.raises(InvalidInputError, match="3 coordinate.*2"):
        timeless_average(a, a[:, :2], band=1)


# mutant: dtw-tie-break
# dtw-tie-break: among equal accumulated costs the diagonal step wins (the path with fewest pairs)
def test_dtw_prefers_the_diagonal_on_ties():
    from footnav.nav.dtw import dtw_align

    res = dtw_align(np.zeros((3, 1)), np.zeros((3, 1)), return_path=True)
    np.testing.assert_array_equal(res.path, [[0, 0], [1, 1], [2, 2]])
