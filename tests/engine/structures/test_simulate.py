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




# --- what "5 % of the measurement" means: the noise definitions a search compares ---------------
def test_noise_scales_follow_their_definitions(demo):
    a = demo["make"](20000).acceleration[:, :4]
    eta = 0.05
    noise = {scale: modal.add_noise(a, eta, 3, scale=scale) - a
             for scale in ("channel_rms", "record_rms", "channel_peak", "proportional")}
    # the same draws, scaled four ways: 20000 samples give the std within 1 % (5 sigma)
    np.testing.assert_allclose(np.std(noise["channel_rms"], axis=0) / np.sqrt(np.mean(a**2, axis=0)), eta, rtol=0.025)
    np.testing.assert_allclose(np.std(noise["record_rms"], axis=0) / np.sqrt(np.mean(a**2)), eta, rtol=0.025)
    np.testing.assert_allclose(np.std(noise["channel_peak"], axis=0) / np.max(np.abs(a), axis=0), eta, rtol=0.025)
    relative = noise["proportional"][a != 0] / np.abs(a[a != 0])
    np.testing.assert_allclose(np.std(relative), eta, rtol=0.025)
    # proportional noise vanishes where the signal does; the others do not
    zero = np.zeros((50, 2))
    assert np.array_equal(modal.add_noise(zero, eta, 1, scale="proportional"), zero)
    # channels of different size get different noise under channel scales, one level under record_rms
    levels = np.std(noise["record_rms"], axis=0)
    np.testing.assert_allclose(levels / levels.mean(), 1, rtol=0.03)
    with pytest.raises(ValueError, match="scale must be one of channel_rms, record_rms"):
        modal.add_noise(a, eta, 1, scale="rms")


def test_default_noise_is_unchanged():
    # the committed tables depend on it: independent noise on d, v, a, drawn in that order
    rec = modal.impulse_response([2.0, 5.0], [[1.0, 0.5], [0.3, -1.0]], [1.0, 0.4], 0.05, 300, 0.01)
    rng = np.random.default_rng(11)
    expected = [s + 0.03 * np.sqrt(np.mean(s**2, axis=0)) * rng.standard_normal(s.shape)
                for s in (rec.displacement, rec.velocity, rec.acceleration)]
    noisy = modal.with_noise(rec, 0.03, 11)
    for got, want in zip((noisy.displacement, noisy.velocity, noisy.acceleration), expected):
        np.testing.assert_array_equal(got, want)


def test_velocity_sources():
    w, zeta, f, dt = 3.0, 0.02, 0.7, 0.002
    rec = modal.impulse_response([w], [[1.0]], [f], dt, 3000, zeta)
    noisy = modal.with_noise(rec, 0.05, 4)
    exact = modal.with_noise(rec, 0.05, 4, velocity="exact")
    # only the accelerometers are noisy: the same acceleration draws, exact velocity and displacement
    np.testing.assert_array_equal(exact.acceleration, noisy.acceleration)
    np.testing.assert_array_equal(exact.velocity, rec.velocity)
    np.testing.assert_array_equal(exact.displacement, rec.displacement)
    # integrated from a noise-free acceleration: the trapezoidal rule's O(dt^2) error, exact start
    clean = modal.with_noise(rec, 0.0, 4, velocity="integrated")
    assert clean.velocity[0, 0] == rec.velocity[0, 0] and clean.displacement[0, 0] == rec.displacement[0, 0]
    peak_v, peak_a = np.max(np.abs(rec.velocity)), np.max(np.abs(rec.acceleration))
    bound = rec.t[-1] * dt**2 / 12 * w**2 * peak_a  # |error| <= T dt^2 max|a''| / 12, a'' ~ -w^2 a
    assert np.max(np.abs(clean.velocity - rec.velocity)) <= 1.5 * bound
    assert np.max(np.abs(clean.velocity - rec.velocity)) < 1e-4 * peak_v
    # integrated from the noisy acceleration: the noise integrates to a random walk, not white noise
    drift = modal.with_noise(rec, 0.05, 4, velocity="integrated").velocity - rec.velocity
    np.testing.assert_allclose(np.diff(drift[:, 0]) / dt,
                               (noisy.acceleration[1:, 0] + noisy.acceleration[:-1, 0]) / 2
                               - (rec.velocity[1:, 0] - rec.velocity[:-1, 0]) / dt, atol=1e-9)
    with pytest.raises(ValueError, match="velocity must be one of noisy, exact, integrated"):
        modal.with_noise(rec, 0.05, 4, velocity="measured")
