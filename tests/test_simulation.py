"""The beam and its simulated response against closed form."""

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

import modal


def test_beam_frequencies_closed_form(beam):
    omega = beam.natural_frequencies(6)
    # omega_r = sqrt(EI/m) (r pi / L)^2 = sqrt(30) (r pi / 5)^2; Table 1's "actual" column
    np.testing.assert_allclose(omega[:3], [2.1623, 8.6493, 19.461], rtol=5e-5)
    np.testing.assert_allclose(omega / omega[0], np.arange(1, 7) ** 2, rtol=1e-14)


def test_beam_modes_are_mass_orthonormal(beam):
    # Eq. (5): int m phi_r phi_s dx = delta_rs
    for r in range(1, 5):
        for s in range(1, 5):
            val, _ = quad(lambda x: beam.mass_per_length * beam.mode_shapes([x], 4)[0, r - 1]
                          * beam.mode_shapes([x], 4)[0, s - 1], 0, beam.length)
            assert val == pytest.approx(float(r == s), abs=1e-10)


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


def test_integrated_velocity_accuracy(demo):
    # 10 samples per period of mode 6: the cubic-spline antiderivative keeps the
    # velocity to better than 0.5 % RMS (the trapezoidal rule would lose 3 % of mode 6).
    rec = demo["make"](3600)
    vel = modal.integrate_acceleration(rec.acceleration, demo["dt"])
    exact = rec.velocity - rec.velocity.mean(axis=0)
    err = np.sqrt(np.mean((vel - exact) ** 2)) / np.sqrt(np.mean(exact**2))
    assert err < 5e-3
