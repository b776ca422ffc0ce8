"""The virtual shaking test of the grid (thesis Sec. 7.2): exact time
integration, the record's layout, the manual steps (sharpest channels, peak
picking), bad input."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import modal
from modal.structures import pick_peaks, select_sharpest, shake_test, sharpness
from modal.structures._shake_test import foh_modal_response

from ..cases import flagged

@pytest.fixture(scope="module")
def noisy(grid, settings):
    """The thesis's measurement: 10 s lag, 4096 samples at 200 Hz, 11 sensors, 2 % noise."""
    return shake_test(grid, **settings, noise=0.02, seed=1)


def test_foh_integration_matches_solve_ivp(grid):
    """Exact first-order-hold stepping against DOP853 on the modal ODEs."""
    omega, _ = grid.modes(4)
    zeta = np.array([0.005, 0.01, 0.02, 0.05])
    dt = 1 / 200
    force = np.random.default_rng(7).standard_normal((41, 4))
    q, v, a = foh_modal_response(omega, zeta, force, dt)
    tk = dt * np.arange(force.shape[0])

    def rhs(t, x):
        f = np.array([np.interp(t, tk, force[:, r]) for r in range(4)])
        return np.concatenate([x[4:], f - omega**2 * x[:4] - 2 * zeta * omega * x[4:]])

    sol = solve_ivp(
        rhs, (0, tk[-1]), np.zeros(8), t_eval=tk, method="DOP853", rtol=1e-11, atol=1e-14, max_step=dt / 4
    )
    assert np.max(np.abs(sol.y[:4].T - q)) < 1e-7 * np.max(np.abs(q))
    assert np.max(np.abs(sol.y[4:].T - v)) < 1e-7 * np.max(np.abs(v))


def test_shake_test_matches_solve_ivp(grid, settings):
    """Burst, lag and record end to end, against DOP853 (relative 1e-7)."""
    st = shake_test(grid, **{**settings, "burst": 0.1, "lag": 0.05, "n_samples": 20, "fmax_hz": None}, n_modes=3, seed=4)
    omega, zeta, dt = st.omega, st.damping, st.dt
    phi_f = grid.modes(3)[1][grid.dof(19)]
    force = np.vstack([st.force, 0.0])[:, 0]
    tk = dt * np.arange(force.size)

    def rhs(t, x):
        f = np.interp(t, tk, force, right=0.0) * phi_f
        return np.concatenate([x[3:], f - omega**2 * x[:3] - 2 * zeta * omega * x[3:]])

    t_eval = st.t_start + st.t
    sol = solve_ivp(
        rhs, (0, t_eval[-1]), np.zeros(6), t_eval=t_eval, method="DOP853", rtol=1e-11, atol=1e-14, max_step=dt / 4
    )
    q, v = sol.y[:3].T, sol.y[3:].T
    acc = (-(omega**2) * q - 2 * zeta * omega * v) @ st.shapes.T
    assert np.max(np.abs(acc - st.acceleration)) < 1e-7 * np.max(np.abs(acc))
    np.testing.assert_allclose(st.velocity, v @ st.shapes.T, atol=1e-7 * np.abs(v).max())


def test_shake_test_layout(grid, settings, noisy):
    assert noisy.acceleration.shape == (4096, 11)
    assert noisy.dt == 1 / 200 and noisy.t[-1] == pytest.approx(20.475)
    assert noisy.t_start == pytest.approx(13.0)
    assert noisy.nodes.size == 11 and noisy.shapes.shape == (11, noisy.omega.size)
    assert noisy.freq_hz.max() <= 50 and np.sum(noisy.freq_hz > 10) >= 5
    again = shake_test(grid, **settings, noise=0.02, seed=1)
    np.testing.assert_array_equal(again.acceleration, noisy.acceleration)
    other = shake_test(grid, **settings, noise=0.02, seed=2)
    assert not np.allclose(other.acceleration, noisy.acceleration)
    # The noise is eta x channel RMS.
    resid = noisy.acceleration - noisy.clean_acceleration
    rms = np.sqrt(np.mean(noisy.clean_acceleration**2, axis=0))
    np.testing.assert_allclose(resid.std(axis=0) / rms, 0.02, rtol=0.1)


def test_era_is_exact_on_a_noise_free_virtual_test(grid, settings):
    """Free decay of the modes kept, no filter: ERA recovers them to 1e-6."""
    st = shake_test(grid, **{**settings, "fmax_hz": 10.0})
    assert st.omega.size == 5
    result = flagged(modal.era, st.acceleration, st.dt, st.omega.size, rows=8, cols=400)
    np.testing.assert_allclose(np.sort(result.omega), st.omega, rtol=1e-6)
    np.testing.assert_allclose(result.damping[np.argsort(result.omega)], st.damping, rtol=1e-5)


def test_select_sharpest(noisy):
    chosen = select_sharpest(noisy.acceleration, noisy.dt, k=6, fmax=10)
    assert chosen.size == 6 and np.unique(chosen).size == 6
    assert np.all((chosen >= 0) & (chosen < 11))
    np.testing.assert_array_equal(chosen, select_sharpest(noisy.acceleration, noisy.dt, k=6, fmax=10))
    scores = sharpness(noisy.acceleration, noisy.dt, fmax=10)
    assert np.all(scores[chosen] >= np.max(np.delete(scores, chosen)))
    assert np.all(np.diff(scores[chosen]) <= 0)  # best first
    # A channel of pure noise is never among the sharpest.
    acc = noisy.acceleration.copy()
    acc[:, chosen[0]] = np.random.default_rng(0).standard_normal(acc.shape[0]) * acc.std()
    assert chosen[0] not in select_sharpest(acc, noisy.dt, k=6, fmax=10)


def test_pick_peaks_finds_the_four_lowest(noisy):
    est = pick_peaks(noisy.acceleration, noisy.dt, n_peaks=4, fmax=7.5)
    resolution = 1 / (4096 * noisy.dt)
    assert np.all(np.abs(est - noisy.freq_hz[:4]) < resolution)


def test_bad_input(grid, settings, noisy):
    acc, dt = noisy.acceleration, noisy.dt
    bad = acc.copy()
    bad[100, 3] = np.nan
    for call in (
        lambda: pick_peaks(bad, dt),
        lambda: select_sharpest(bad, dt),
        lambda: modal.era(bad, dt, 4, 36, 100),
        lambda: modal.lowpass_fft(bad, dt, 10.0),
    ):
        with pytest.raises(ValueError, match="NaN"):
            call()
    with pytest.raises(ValueError, match="Nyquist"):
        modal.lowpass_fft(acc, dt, 150.0)
    with pytest.raises(ValueError, match="Nyquist"):
        shake_test(grid, **settings, force_cutoff_hz=150.0)
    with pytest.raises(ValueError, match="n_sets"):
        modal.split_record(acc, acc.shape[0])
    with pytest.raises(ValueError, match="one sensor per mode"):
        modal.tcm(acc[:, :3], dt, n_modes=4)
    with pytest.raises(ValueError, match="k = 12"):
        select_sharpest(acc, dt, k=12)
    with pytest.raises(ValueError, match="fewer than n_peaks"):
        pick_peaks(acc, dt, n_peaks=50, fmax=7.5)
