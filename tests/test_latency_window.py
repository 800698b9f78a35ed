"""The search window of estimate_latency: the lags j − offset within ±reach samples."""

import numpy as np
import pytest

from dstoolkit.gauge._latency import _within


@pytest.mark.parametrize("reach", [0.0, 0.5, 1.0, 2.9, 3.0, 7.25, 40.0, np.inf, -1.0, np.nan])
@pytest.mark.parametrize("offset", [0, 3, 11, 25, 60])
def test_the_window_is_the_lags_within_reach(offset, reach):
    size = 30
    lags = np.arange(size) - offset  # scipy.signal.correlation_lags(n, m, "valid") − offset
    np.testing.assert_array_equal(_within(size, offset, reach), np.abs(lags) <= reach)
