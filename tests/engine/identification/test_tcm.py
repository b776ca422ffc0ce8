"""TCM (thesis Eqs. 21-31) through modal.tcm: exact over whole periods on every
layout, with a lag, scale and offset invariance, the flags it sets."""

import numpy as np
import pytest

import modal

from ..cases import (flagged, EXACT_MAC, LAYOUTS, PER_PERIOD, TABLE_1, THESIS_SAMPLES, acos_tolerance, beam_record, diag_mac,
                     growing, printed, two_sinusoids)

def test_tcm_duration_truncates_inner_product(demo):
    rec = demo["make"](5000)
    full = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity, duration=29.001)
    assert printed(full.omega[:3], TABLE_1["tcm"]) == TABLE_1["tcm"]


def test_tcm_with_integrated_velocity_stays_close(demo):
    # vel=None integrates the acceleration, as an experiment must; on Table 2's case
    # the frequencies move by less than 1e-3 relative.
    rec = demo["make"](THESIS_SAMPLES, damping=0.05)
    exact = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity)
    integ = modal.tcm(rec.acceleration, demo["dt"])
    np.testing.assert_allclose(integ.omega, exact.omega, rtol=1e-3)


def test_tcm_shapes_match_exact_modes(demo):
    rec = demo["make"](3600)  # ten whole fundamental periods: TCM is exact
    res = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity)
    np.testing.assert_allclose(res.omega, demo["omega"], rtol=1e-9)
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)


@pytest.mark.parametrize("lag", [1, 2, 3])
def test_tcm_lagged_exact_over_whole_periods(demo, lag):
    rec = demo["make"](3600 + lag)
    res = modal.tcm(rec.acceleration, demo["dt"], lag=lag)
    tol = acos_tolerance(demo["omega"], lag * demo["dt"])
    assert np.all(np.abs(res.omega / demo["omega"] - 1) < tol)
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_tcm_exact_on_every_layout(layout):
    rec, omega, dt = beam_record(layout, 3 * PER_PERIOD)
    res = flagged(modal.tcm, rec.acceleration, dt, vel=rec.velocity)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-9)
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("lag", [1, 3])
def test_tcm_lagged_exact_on_every_layout(layout, lag):
    rec, omega, dt = beam_record(layout, 3 * PER_PERIOD + lag)
    res = flagged(modal.tcm, rec.velocity, dt, lag=lag)
    assert np.all(np.abs(res.omega / omega - 1) < acos_tolerance(omega, lag * dt, dlam=1e-11))
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)
    assert not res.aliased.any()


def test_tcm_flags_folded_frequencies_with_a_lag():
    lag = 8
    rec, omega, dt = beam_record("thesis", 3 * PER_PERIOD + lag)
    limit = np.pi / (lag * dt)
    res = flagged(modal.tcm, rec.acceleration, dt, lag=lag)
    assert omega[3] < limit < omega[4]  # modes 5 and 6 fold back
    assert res.aliased.sum() >= 2
    # every entry not flagged is a true mode, exactly
    for w in res.omega[~res.aliased]:
        assert np.min(np.abs(w / omega - 1)) < 1e-6
    # without the lag-one check, the folded mode 5 (43.2 rad/s) would pass as a mode
    folded = (2 * np.pi - omega[4] * lag * dt) / (lag * dt)
    hit = np.argmin(np.abs(res.omega - folded))
    assert abs(res.omega[hit] / folded - 1) < 1e-6 and res.aliased[hit]


def test_vel_with_a_lag_is_refused():
    rec, _, dt = beam_record("irregular", 800)
    with pytest.raises(ValueError, match="vel"):
        modal.tcm(rec.acceleration, dt, vel=rec.velocity, lag=2)


@pytest.mark.parametrize("scale", [1e-160, 1e-30, 1e30, 1e150])
def test_tcm_does_not_depend_on_scale(scale):
    rec, _, dt = beam_record("irregular", 3 * PER_PERIOD, damping=0.01)
    ref = flagged(modal.tcm, rec.acceleration, dt)
    # 1e-160 and 1e+150 are no powers of two: the scaled data differ in their last bits
    np.testing.assert_allclose(flagged(modal.tcm, rec.acceleration * scale, dt).omega, ref.omega, rtol=1e-8)
    lagged = flagged(modal.tcm, rec.acceleration, dt, lag=2)
    np.testing.assert_allclose(flagged(modal.tcm, rec.acceleration * scale, dt, lag=2).omega, lagged.omega, rtol=1e-8)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_acceleration_offset_does_not_move_tcm(layout):
    rec, omega, dt = beam_record(layout, 4 * PER_PERIOD)
    acc = rec.acceleration
    offset = 0.01 * np.sqrt(np.mean(acc**2, axis=0)) * np.array([1, -2, 3, -1, 2, 1.5])
    base = flagged(modal.tcm, acc, dt)
    shifted = flagged(modal.tcm, acc + offset, dt)
    assert np.max(np.abs(shifted.omega / base.omega - 1)) < 5e-3
    np.testing.assert_allclose(base.omega, omega, rtol=5e-3)  # integrated velocity: close to exact


def test_tcm_refuses_nearly_dependent_channels_beside_a_weak_one():
    """Singularity of A is judged against its largest eigenvalue, whatever the
    other channels' sizes."""
    t = 0.01 * np.arange(2000)
    y = np.column_stack([np.sin(2 * t), 1e-3 * np.sin(5 * t), np.sin(2 * t) + 1e-9 * np.cos(7 * t)])
    with pytest.raises(ValueError, match="the correlation matrix A is singular"):
        modal.tcm(y, 0.01, lag=1)


def test_vel_is_refused_with_the_smallest_lag():
    dt, _, vel, acc = two_sinusoids()
    with pytest.raises(ValueError, match=r"^vel is used only with lag = 0"):
        modal.tcm(acc, dt, vel=vel, lag=1)


@pytest.mark.parametrize("amplitude", [1.0, 1e3])
def test_tcm_below_one_rad_per_s_is_exact_and_not_flagged(amplitude):
    """lambda = omega^2 exactly over whole periods; omega = 0.5 rad/s gives
    lambda = 0.25 < 1, an ordinary mode. ``singular_values`` are A's
    eigenvalues, largest first, in the data's units."""
    dt, _, vel, acc = two_sinusoids(amplitude=amplitude)
    res = flagged(modal.tcm, acc, dt, vel=vel)
    np.testing.assert_allclose(res.omega, [0.5, 2.0], rtol=1e-10)
    np.testing.assert_allclose(res.eigenvalues, [0.25, 4.0], rtol=1e-10)
    assert not res.real_pole.any() and res.real_pole.dtype == bool
    a = vel.T @ vel / len(vel)
    np.testing.assert_allclose(res.singular_values, np.linalg.eigvalsh(a)[::-1], rtol=1e-12)
    assert res.method == "tcm" and res.to_frame()["method"].tolist() == ["tcm", "tcm"]
    lowest = flagged(modal.tcm, acc, dt, n_modes=1, vel=vel)
    assert lowest.n_modes == 1 and lowest.shapes.shape == (2, 1)
    np.testing.assert_allclose(lowest.omega, [0.5], rtol=1e-10)


@pytest.mark.parametrize("method", ["tcm", "cera"])
def test_growing_channel_is_flagged_with_its_exact_eigenvalue(method):
    """A growing exponential has lambda = e^{a dt} > 1 exactly: no oscillation,
    flagged ``real_pole``, frequency 0 (acos clipped)."""
    dt, rate = 0.05, 10.0  # lambda = e^0.5 = 1.6487
    y = growing(rate, dt, 200)
    res = (flagged(modal.tcm, y, dt, lag=1, free_response=True) if method == "tcm"
           else flagged(modal.cera, y, dt, 1, cols=150, free_response=True))
    np.testing.assert_allclose(res.eigenvalues, [np.exp(rate * dt)], rtol=1e-12)
    np.testing.assert_array_equal(res.real_pole, [True])
    np.testing.assert_array_equal(res.omega, [0.0])
    assert res.method == method


@pytest.mark.parametrize("method", ["tcm", "cera"])
def test_alternating_growth_sits_at_the_nyquist_limit(method):
    """(-1)^k e^{a t}: lambda = -e^{a dt} < -1, flagged, omega = pi / dt
    (acos clipped at -1), and flagged possibly aliased."""
    dt, rate = 0.05, 10.0
    y = growing(rate, dt, 200, alternate=True)
    res = flagged(modal.tcm, y, dt, lag=1) if method == "tcm" else flagged(modal.cera, y, dt, 1, cols=150)
    np.testing.assert_allclose(res.eigenvalues, [-np.exp(rate * dt)], rtol=1e-12)
    np.testing.assert_array_equal(res.real_pole, [True])
    np.testing.assert_allclose(res.omega, [np.pi / dt], rtol=1e-15)
    np.testing.assert_array_equal(res.aliased, [True])


def test_tcm_lag_two_sees_alternation_through_the_lag_one_quotient():
    """With lag 2, (-1)^k e^{a t} gives lambda = e^{2 a dt} > 1 (omega 0), but
    its lag-one quotient is -e^{a dt}: omega_1 = pi / dt, beyond pi / (2 dt),
    so the entry is flagged possibly aliased."""
    dt, rate = 0.05, 4.0
    res = flagged(modal.tcm, growing(rate, dt, 200, alternate=True), dt, lag=2, free_response=True)
    np.testing.assert_allclose(res.eigenvalues, [np.exp(2 * rate * dt)], rtol=1e-12)
    np.testing.assert_array_equal(res.omega, [0.0])
    np.testing.assert_array_equal(res.aliased, [True])


def test_tcm_lag_flags_only_the_folded_modes():
    """Lag 7 on the thesis's beam: pi / (7 dt) is 25.7 x mode 1, so modes 1-5
    (1, 4, 9, 16, 25 x) must not be flagged aliased (the lag-one check sees
    their true frequency) and mode 6 (36 x) folds to 51.43 - 36 = 15.43 x,
    flagged. (With lag 8 mode 6 folds exactly onto mode 3: their eigenvalues
    coincide and the eigenvectors mix, so no flag can tell them apart.)"""
    beam = modal.SimplySupportedBeam(5.0, 30.0, 1.0)
    omega = beam.natural_frequencies(6)
    dt, lag = 2 * np.pi / omega[0] / 360, 7
    rec = modal.beam_impulse_response(beam, 6, 0.77, np.array([0.3, 0.9, 1.7, 2.2, 3.1, 4.4]), dt, 3 * 360 + lag, 0.0)
    res = flagged(modal.tcm, rec.acceleration, dt, lag=lag)
    for w in omega[:5]:
        hit = np.argmin(np.abs(res.omega - w))
        assert res.omega[hit] == pytest.approx(w, rel=1e-6) and not res.aliased[hit]
    folded = (2 * np.pi / (lag * dt) - omega[5])
    np.testing.assert_allclose(res.omega[res.aliased], [folded], rtol=1e-6)


def test_tcm_lag_short_window_counts_the_lagged_instants():
    """With a lag the inner products span (n - lag) dt: 5.95 fundamental
    periods is short (flagged), 6.05 is not."""
    dt, lag, per_period = 2 * np.pi / 360, 40, 360  # omega_1 = 1 rad/s
    for periods, short in ((5.95, True), (6.05, False)):
        n = int(round(periods * per_period)) + lag
        t = dt * np.arange(n)
        y = np.column_stack([np.sin(t) + 0.2 * np.sin(3 * t), np.sin(t) - 0.5 * np.sin(3 * t)])
        res = flagged(modal.tcm, y, dt, lag=lag)
        assert res.omega[0] == pytest.approx(1.0, rel=0.03)
        assert res.short_window[0] == short
