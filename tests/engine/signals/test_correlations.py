"""NExT correlation functions (modal.correlations)."""

import numpy as np
import pytest

import modal

def test_correlations_equal_direct_sums_both_estimators():
    rng = np.random.default_rng(0)
    y = rng.standard_normal((2, 300, 3))
    for estimator in ("biased", "unbiased"):
        r = modal.correlations(y, 25, refs=[2, 0], estimator=estimator)
        assert r.shape == (2, 25, 3)
        for i, ref in enumerate([2, 0]):
            for k in (0, 7, 24):
                direct = sum(y[m, k:, :].T @ y[m, : 300 - k, ref] for m in range(2)) / 2
                direct /= 300 if estimator == "biased" else 300 - k
                np.testing.assert_allclose(r[i, k], direct, rtol=1e-12, atol=1e-14)


def test_correlations_of_cosines_closed_form():
    """R(k) of a*cos(w t) is a^2/2 cos(w k dt) (unbiased, whole periods)."""
    dt, f = 0.01, 2.0
    t = dt * np.arange(5000)  # 100 whole periods
    y = np.column_stack([3 * np.cos(2 * np.pi * f * t), np.sin(2 * np.pi * f * t)])
    r = modal.correlations(y, 40, refs=[0], estimator="unbiased")
    lag = dt * np.arange(40)
    np.testing.assert_allclose(r[0, :, 0], 4.5 * np.cos(2 * np.pi * f * lag), atol=0.02)
    np.testing.assert_allclose(r[0, :, 1], 1.5 * np.sin(2 * np.pi * f * lag), atol=0.02)


def test_correlations_reject_bad_input():
    y = np.random.default_rng(0).standard_normal((50, 2))
    with pytest.raises(ValueError, match="n_lags = 51 exceeds"):
        modal.correlations(y, 51)
    with pytest.raises(ValueError, match="refs must be distinct channel indices"):
        modal.correlations(y, 5, refs=[2])
    with pytest.raises(ValueError, match="estimator"):
        modal.correlations(y, 5, estimator="welch")
    with pytest.raises(ValueError, match="channel 1 is constant"):
        modal.correlations(np.column_stack([y[:, 0], np.ones(50)]), 5)
