"""footnav.nav.order_stats: the kernels' sort and median give numpy's values."""

import numpy as np
import pytest

from footnav.nav.order_stats import median, sort


@pytest.mark.parametrize("n", [1, 2, 3, 8, 9, 200, 201])
def test_sort_and_median_match_numpy(n):
    rng = np.random.default_rng(n)
    for values in (rng.normal(size=n), rng.integers(0, 5, size=n).astype(float)):  # ties too
        x = np.concatenate([values, [np.inf, -np.inf]])  # beyond n: left alone
        sort(x, n)
        np.testing.assert_array_equal(x[:n], np.sort(values))
        assert x[n] == np.inf and x[n + 1] == -np.inf
        got = median(values.copy(), n)
        assert got == np.median(values)  # to the bit
        assert got == np.nanmedian(np.concatenate([values, [np.nan]]))


def test_median_of_a_prefix_reads_only_the_prefix():
    x = np.array([5.0, 1.0, 3.0, 100.0, -100.0])
    assert median(x, 3) == 3.0
    np.testing.assert_array_equal(x[3:], [100.0, -100.0])
