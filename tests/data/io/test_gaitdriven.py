"""Gait-driven mini-data set (Cetin & Koroglu 2026): one foot, hand-marked footprints in a mirrored frame."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.io import savemat

from footnav.analysis.metrics import ate_rmse
from footnav.core.errors import DataNotFoundError, InvalidInputError
from footnav.core.types import GRAVITY_MPS2
from footnav.data.datasets import data_dir
from footnav.data.io import guess_format, load, read_gaitdriven


def _mat(path, n=400, stride=None, gcp=None):
    rng = np.random.default_rng(0)
    acc = np.array([4.0, 1.0, -np.sqrt(GRAVITY_MPS2**2 - 17.0)]) + 0.01 * rng.standard_normal((n, 3))
    gyr = 0.01 * rng.standard_normal((n, 3))
    stride = np.array([[50, 150, 250, n - 1]]) if stride is None else stride
    k = stride.size
    gcp = np.column_stack((np.arange(k) * 0.6, np.arange(k) * 0.1)) if gcp is None else gcp
    savemat(
        path,
        {
            "imu_data": np.hstack((acc, gyr)),
            "timestamps": (np.arange(n) * 0.005)[None, :],
            "strideIndex": stride,
            "GCP": gcp,
            "traveled_distance": np.array([[1.8]]),
            "pyshoeTrajectory": np.column_stack((np.linspace(0, 1.8, n), np.linspace(0, 0.3, n))),
        },
    )
    return path


def test_synthetic_truth_is_y_negated_footprints(tmp_path):
    p = _mat(tmp_path / "SensorConnectData_99_LLIO.mat")
    rec = read_gaitdriven(p)
    assert rec.n_feet == 1 and rec.meta["format"] == "gaitdriven"
    # axes kept: gravity still reads on -z with an x component, as stored
    assert rec.left.acc[:, 2].mean() < -8.0 and rec.left.acc[:, 0].mean() == pytest.approx(4.0, abs=0.01)
    t = rec.truth_left
    assert t.frame == "footprints"
    np.testing.assert_array_equal(t.events["footprint"], [50, 150, 250, 399])
    np.testing.assert_allclose(t.t, [0.25, 0.75, 1.25, 1.995])
    np.testing.assert_allclose(t.position[:, 1], [0.0, -0.1, -0.2, -0.3])
    np.testing.assert_allclose(t.position[:, 0], [0.0, 0.6, 1.2, 1.8])
    assert not np.signbit(t.position[0, 1])  # no -0.0 from negating the origin
    assert t.meta["pyshoe_trajectory"][-1, 1] == pytest.approx(-0.3)
    assert t.meta["traveled_distance_m"] == pytest.approx(1.8) and t.meta["stride_index_base"] == 0


def test_synthetic_bad_stride_index_is_named(tmp_path):
    # N = 400 samples: 400 would be a 1-based index of the last sample, not a 0-based one
    p = _mat(tmp_path / "a.mat", stride=np.array([[50, 150, 400]]))
    with pytest.raises(InvalidInputError, match=r"strideIndex.*index 2|index 2.*strideIndex"):
        read_gaitdriven(p)
    q = _mat(tmp_path / "b.mat", stride=np.array([[50, 150]]), gcp=np.zeros((3, 2)))
    with pytest.raises(InvalidInputError, match="GCP"):
        read_gaitdriven(q)


def test_load_guesses_from_variable_names(tmp_path):
    p = _mat(tmp_path / "whatever.mat")
    assert guess_format(p)[0] == "gaitdriven"
    assert load(p).meta["format"] == "gaitdriven"


# ---------------------------------------------------------------------------------------------
# the shared data
# ---------------------------------------------------------------------------------------------
@pytest.fixture
def gd_dir():
    try:
        d = data_dir() / "gaitdriven_dev"
    except DataNotFoundError as exc:
        pytest.skip(str(exc))
    if not d.is_dir():
        pytest.skip(f"{d} not found")
    return d


TRIALS = (31, 33, 35, 37, 39, 41, 43, 45)


@pytest.mark.parametrize("nn", TRIALS)
def test_real_stride_index_is_zero_based_and_in_range(gd_dir, nn):
    rec = read_gaitdriven(gd_dir / f"SensorConnectData_{nn}_LLIO.mat")
    t = rec.truth_left
    idx = t.events["footprint"]
    n = rec.left.n_samples
    assert idx.min() >= 0 and idx.max() == n - 1 and (np.diff(idx) > 0).all()
    # the publisher's CSV time stamps are timestamps[strideIndex] with 0-based indices
    csv = np.loadtxt(gd_dir / f"SensorConnectData_{nn}_strideIndex_timestamp_gcpX_gcpY.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(csv[:, 0], idx)
    np.testing.assert_allclose(t.t, csv[:, 1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(t.position[:, :2], csv[:, 2:] * [1.0, -1.0])
    np.testing.assert_allclose(t.position[0], 0.0)


@pytest.mark.parametrize("nn", TRIALS)
def test_real_footprints_and_publisher_trajectory_share_the_negation(gd_dir, nn):
    # GCP and pyshoeTrajectory are stored in one frame: negated alike they still fit each other
    # (the README's 0.3-2.3 m), while negating only one of them is a mirror no rotation undoes.
    t = read_gaitdriven(gd_dir / f"SensorConnectData_{nn}_LLIO.mat").truth_left
    at_fp = t.meta["pyshoe_trajectory"][t.events["footprint"]]
    same = ate_rmse(at_fp, t.position[:, :2])
    mirrored = ate_rmse(at_fp, t.meta["gcp_as_stored"])
    assert same < 2.5 and mirrored > same


def test_real_z_up_estimate_fits_the_negated_footprints(gd_dir):
    # A z-up estimate (footnav's own pipeline) fits the y-negated footprints, not the stored ones:
    # the check that the negation is the right conversion, independent of the publisher's frame.
    import warnings

    import footnav

    rec = read_gaitdriven(gd_dir / "SensorConnectData_39_LLIO.mat")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = footnav.make_pipeline().run(rec.left)
    idx = rec.truth_left.events["footprint"]
    est = res.left.position[idx, :2]
    assert ate_rmse(est, rec.truth_left.position[:, :2]) < 0.5 * ate_rmse(est, rec.truth_left.meta["gcp_as_stored"])


def test_real_mountings_differ_but_axes_are_kept(gd_dir):
    a = read_gaitdriven(gd_dir / "SensorConnectData_31_LLIO.mat").left
    b = read_gaitdriven(gd_dir / "SensorConnectData_39_LLIO.mat").left
    assert a.acc[:50, 0].mean() > 3.0 and b.acc[:50, 0].mean() < -3.0
    assert a.meta["body_rotation"]["applied"] is None


def _mat_per_stride(path, n=400, with_stride_index=True, shift_s=0.0):
    """The other published layout: ``timestamps`` per stride, ``timestamps_all`` per sample."""
    rng = np.random.default_rng(1)
    acc = np.array([4.0, 1.0, -np.sqrt(GRAVITY_MPS2**2 - 17.0)]) + 0.01 * rng.standard_normal((n, 3))
    gyr = 0.01 * rng.standard_normal((n, 3))
    t_all = np.arange(n) * 0.005
    stride = np.array([50, 150, 250, n - 1])
    gcp = np.array([[0.0, 0.0], [0.6, 0.1], [1.2, 0.2], [1.8, 0.3]])
    mat = {
        "imu_data": np.hstack((acc, gyr)),
        "timestamps": (t_all[stride] + shift_s)[None, :],
        "timestamps_all": t_all[None, :],
        "GCP": gcp,
    }
    if with_stride_index:
        mat["strideIndex"] = stride[None, :]
    savemat(path, mat)
    return path


@pytest.mark.parametrize("with_stride_index", [True, False])
def test_per_stride_timestamps_layout_reads_as_the_other(tmp_path, with_stride_index):
    p = _mat_per_stride(tmp_path / "walk_LLIO.mat", with_stride_index=with_stride_index)
    assert guess_format(p)[0] == "gaitdriven"
    rec = load(p)
    assert len(rec.left) == 400
    np.testing.assert_allclose(rec.left.t, np.arange(400) * 0.005)  # timestamps_all, per sample
    t = rec.truth_left
    np.testing.assert_array_equal(t.events["footprint"], [50, 150, 250, 399])
    np.testing.assert_allclose(t.t, [0.25, 0.75, 1.25, 1.995])
    # mirrored like the per-sample layout: y negated
    np.testing.assert_allclose(t.position[:, :2], [[0, 0], [0.6, -0.1], [1.2, -0.2], [1.8, -0.3]])
    assert t.meta["truth_conversion"]["mirror_y"] is True
    assert t.meta["time_layout"].startswith("timestamps per stride")


def test_per_stride_layout_errors_are_named(tmp_path):
    p = _mat_per_stride(tmp_path / "a_LLIO.mat", shift_s=0.05)  # 10 samples off strideIndex
    with pytest.raises(InvalidInputError, match=r"field 'timestamps', index 0.*differs"):
        read_gaitdriven(p)
    q = tmp_path / "b_LLIO.mat"
    savemat(q, {"imu_data": np.zeros((40, 6)), "timestamps": np.zeros((1, 4))})
    with pytest.raises(InvalidInputError, match=r"timestamps.*4 values.*timestamps_all"):
        read_gaitdriven(q)
