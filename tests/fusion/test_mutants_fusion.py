"""Fusion tests that kill mutants of ``tools/mutate.py`` the rest of the suite let through."""

from __future__ import annotations

import warnings

import numpy as np

import footnav


# joint-alone-std: past the span both feet cover, a foot continues alone from the fused estimate:
# its horizontal position std starts at the fused std and grows from there
def test_position_std_continues_from_the_fused_span():
    rec = footnav.simulate("straight", seed=3, distance_m=12.0)
    right = rec.right.slice(0, rec.right.n_samples - 300)  # the right foot's recording stops 3 s early
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = footnav.make_pipeline("glrt", "ekf", "range").run(rec.left, right)
    first, stop = res.left.meta["span"]["fused_samples"]
    assert stop < rec.left.n_samples
    std = res.left.position_std
    assert np.all(std[stop:, :2] >= std[stop - 1, :2] - 1e-9)
