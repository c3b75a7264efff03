"""footnav.data.results.write_results: every column read back against the result's arrays (the
right foot's too), non-finite numbers as JSON null, both feet's strides in strides.csv."""

from __future__ import annotations

import csv
import json
import math
import warnings

import numpy as np
import pytest

import footnav
from footnav.data.results import TRAJECTORY_COLUMNS, _jsonable, write_results


@pytest.fixture(scope="module")
def result():
    rec = footnav.simulate("straight", seed=2, distance_m=6.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return footnav.make_pipeline().run(rec.left, rec.right)


def test_every_column_of_both_feet_is_written(result, tmp_path):
    # mutant: results-right-stance-left (each foot's stance column is its own)
    out = write_results(result, tmp_path / "res")
    for foot in ("left", "right"):
        traj, stance = getattr(result, foot), getattr(result, f"stance_{foot}")
        data = np.loadtxt(out / f"{foot}.csv", delimiter=",")
        assert (out / f"{foot}.csv").read_text().splitlines()[1] == "# " + TRAJECTORY_COLUMNS
        expected = np.column_stack(
            [traj.t, traj.position, traj.velocity, traj.quaternion, traj.position_std, stance.mask.astype(float)]
        )
        np.testing.assert_allclose(data, expected, rtol=1e-8, atol=1e-9)
        arrays = np.load(out / "trajectories.npz", allow_pickle=False)
        np.testing.assert_array_equal(arrays[f"{foot}_stance"], stance.mask)
        np.testing.assert_array_equal(arrays[f"{foot}_velocity"], traj.velocity)
    assert not np.array_equal(result.stance_left.mask, result.stance_right.mask)
    rows = list(csv.DictReader((out / "strides.csv").open()))
    assert {r["foot"] for r in rows} == {"left", "right"}


def test_non_finite_numbers_are_null_and_finite_ones_kept():
    # mutant: results-jsonable-or
    doc = _jsonable({"a": math.nan, "b": [1.5, math.inf, np.float64(2.5)], "c": np.array([1.0, 2.0]), "d": 3})
    assert doc == {"a": None, "b": [1.5, None, 2.5], "c": [1.0, 2.0], "d": 3}
    assert json.loads(json.dumps(doc)) == doc
