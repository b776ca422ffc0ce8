"""Simulated responses (impulse responses, sensor noise) against an ODE solver and their definition."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import modal






@pytest.mark.parametrize("zeta", [0.0, 0.02])
def test_impulse_response_matches_ode_integration(zeta):
    # One mode, u'' + 2 zeta w u' + w^2 u = 0, u(0) = 0, u'(0) = f: compare with an ODE solver.
    w, f = 3.0, 0.7
    rec = modal.impulse_response([w], [[1.0]], [f], 0.01, 500, zeta)
    sol = solve_ivp(lambda t, x: [x[1], -w**2 * x[0] - 2 * zeta * w * x[1]], (0, rec.t[-1]), [0, f],
                    t_eval=rec.t, rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(rec.displacement[:, 0], sol.y[0], atol=1e-9)
    np.testing.assert_allclose(rec.velocity[:, 0], sol.y[1], atol=1e-9)
    acc = -(w**2) * sol.y[0] - 2 * zeta * w * sol.y[1]
    np.testing.assert_allclose(rec.acceleration[:, 0], acc, atol=1e-8)


def test_noise_is_eta_times_rms_and_seeded(demo):
    rec = demo["make"](4000)
    a = rec.acceleration
    noisy = modal.add_noise(a, 0.05, 7)
    ratio = np.std(noisy - a, axis=0) / np.sqrt(np.mean(a**2, axis=0))
    np.testing.assert_allclose(ratio, 0.05, rtol=0.05)  # 4000 samples: std of the std ~ 1.1 %
    np.testing.assert_array_equal(noisy, modal.add_noise(a, 0.05, 7))
    assert not np.array_equal(noisy, modal.add_noise(a, 0.05, 8))
    noisy_rec = modal.with_noise(rec, 0.03, 1)
    assert np.array_equal(noisy_rec.acceleration, modal.with_noise(rec, 0.03, 1).acceleration)


