"""The engine off the thesis's geometry: other beams, irregular sensor layouts,
several data sets, flags, refusals, scale and offset invariance.

The thesis's sensors at i L / 7 give a mode-shape matrix with orthogonal
columns, which hides layout bugs (the symmetric part of Eq. (52)'s matrix was
exact there and 100 % off elsewhere). Every exactness test below therefore
also runs on irregular layouts, and the property-based tests draw beams,
layouts, damping and data sets at random.

Exactness conditions used throughout: a simply supported beam's frequencies
are ``i^2 omega_1``, so a record of whole fundamental periods spans whole
periods of every mode; with ``dt = T_1 / 360`` the sixth mode has ten samples
per period (the thesis's choice) and ``360 k`` samples are ``k`` periods.
"""

import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import modal

EXACT_MAC = 1 - 1e-10
PER_PERIOD = 360  # samples per fundamental period (dt = T_1 / 360 = T_6 / 10)

THESIS_BEAM = (5.0, 30.0, 1.0)
IRREGULAR = np.array([0.3, 0.9, 1.7, 2.2, 3.1, 4.4])  # the layout on the 5 m beam
OTHER_BEAM = (3.2, 71.0, 2.3)
OTHER_LAYOUT = np.array([0.21, 0.55, 1.02, 1.66, 2.31, 2.93])

LAYOUTS = {
    "thesis": (THESIS_BEAM, 5.0 * np.arange(1, 7) / 7, 10 / 7),
    "irregular": (THESIS_BEAM, IRREGULAR, 10 / 7),
    "other_beam": (OTHER_BEAM, OTHER_LAYOUT, 0.77),
}


def beam_record(layout, n_samples, damping=0.0, n_modes=6, impact=None):
    """Impulse response of ``n_modes`` beam modes at a layout, ``dt = T_1 / 360``."""
    (length, stiffness, mass), sensors, default_impact = LAYOUTS[layout]
    beam = modal.SimplySupportedBeam(length, stiffness, mass)
    omega = beam.natural_frequencies(n_modes)
    dt = 2 * np.pi / omega[0] / PER_PERIOD
    x = default_impact if impact is None else impact
    rec = modal.beam_impulse_response(beam, n_modes, x, sensors, dt, n_samples, damping)
    return rec, omega, dt


def acos_tolerance(omega, t_o, dlam=1e-12):
    """Round-off bound of ``omega = acos(lambda) / T_o`` for an error ``dlam`` in lambda."""
    return dlam / (omega * t_o * np.abs(np.sin(omega * t_o)))


def diag_mac(a, b):
    return np.diag(modal.mac(a, b))


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        yield


# ------------------------------------------------------------------ exactness on every layout
@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("zeta", [0.0, 0.02])
def test_era_exact_on_every_layout(layout, zeta):
    rec, omega, dt = beam_record(layout, 1200, damping=zeta)
    res = modal.era(rec.acceleration, dt, 6, rows=8, cols=400)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-8)
    np.testing.assert_allclose(res.damping, zeta, rtol=1e-8, atol=1e-10)
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)
    assert np.all(res.mamc > 1 - 1e-8) and np.all(res.mpc > 1 - 1e-8)
    assert not (res.real_pole.any() or res.unstable.any() or res.aliased.any())


@pytest.mark.parametrize("layout", LAYOUTS)
def test_tcm_exact_on_every_layout(layout):
    rec, omega, dt = beam_record(layout, 3 * PER_PERIOD)
    res = modal.tcm(rec.acceleration, dt, vel=rec.velocity)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-9)
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("lag", [1, 3])
def test_tcm_lagged_exact_on_every_layout(layout, lag):
    rec, omega, dt = beam_record(layout, 3 * PER_PERIOD + lag)
    res = modal.tcm(rec.velocity, dt, lag=lag)
    assert np.all(np.abs(res.omega / omega - 1) < acos_tolerance(omega, lag * dt, dlam=1e-11))
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)
    assert not res.aliased.any()


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("periods", [1, 2])
def test_cera_exact_on_every_layout(layout, periods):
    cols = periods * PER_PERIOD
    rec, omega, dt = beam_record(layout, cols + 1)
    res = modal.cera(rec.acceleration, dt, 6, cols=cols)
    assert np.all(np.abs(res.omega / omega - 1) < max(1e-8, *acos_tolerance(omega, dt)))
    assert np.all(diag_mac(res.shapes, rec.shapes) >= 1 - 1e-8)
    assert not res.real_pole.any()


def test_cera_with_several_data_sets_is_exact():
    sets = [beam_record("irregular", PER_PERIOD + 1, impact=x)[0].velocity for x in (0.7, 2.9)]
    _, omega, dt = beam_record("irregular", 2)
    res = modal.cera(np.stack(sets), dt, 6, cols=PER_PERIOD)
    assert np.all(np.abs(res.omega / omega - 1) < 1e-8)


def test_era_several_data_sets_on_irregular_layout():
    sets = [beam_record("irregular", 600, damping=0.01, impact=x)[0].acceleration for x in (0.7, 2.9, 4.1)]
    rec, omega, dt = beam_record("irregular", 2, damping=0.01)
    res = modal.era(np.stack(sets), dt, 6, rows=4, cols=200)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-8)
    np.testing.assert_allclose(res.damping, 0.01, rtol=1e-7)
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)


# ------------------------------------------------------------------ property-based
@st.composite
def beam_cases(draw):
    length = draw(st.floats(1.0, 10.0))
    stiffness = draw(st.floats(1.0, 100.0))
    mass = draw(st.floats(0.5, 5.0))
    n_modes = draw(st.integers(2, 5))
    extra = draw(st.integers(0, 2))
    fractions = draw(
        st.lists(st.floats(0.03, 0.97), min_size=n_modes + extra, max_size=n_modes + extra, unique=True)
    )
    impacts = draw(st.lists(st.floats(0.05, 0.95), min_size=1, max_size=2, unique=True))
    zeta = draw(st.sampled_from([0.0, 0.001, 0.01, 0.05]))
    beam = modal.SimplySupportedBeam(length, stiffness, mass)
    sensors = np.sort(np.array(fractions)) * length
    shapes = beam.mode_shapes(sensors, n_modes)
    assume(np.min(np.diff(sensors)) > 0.01 * length)
    sv = np.linalg.svd(shapes, compute_uv=False)
    assume(sv[-1] > 0.05 * sv[0])  # every mode observed, independently
    modal_impulses = beam.mode_shapes(np.array(impacts) * length, n_modes)
    assume(np.all(np.abs(modal_impulses) > 0.1))  # every impact excites every mode
    return beam, n_modes, sensors, [x * length for x in impacts], zeta


def _records(beam, n_modes, sensors, impacts, zeta, n_samples):
    omega = beam.natural_frequencies(n_modes)
    dt = 2 * np.pi / omega[0] / (10 * n_modes**2)  # ten samples per period of the highest mode
    recs = [modal.beam_impulse_response(beam, n_modes, x, sensors, dt, n_samples, zeta) for x in impacts]
    return recs, omega, dt


PROPERTY = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@PROPERTY
@given(beam_cases())
def test_property_era_exact(case):
    beam, n, sensors, impacts, zeta = case
    recs, omega, dt = _records(beam, n, sensors, impacts, zeta, 600)
    y = np.stack([r.acceleration for r in recs])
    res = modal.era(y, dt, n, rows=4, cols=300)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-7)
    np.testing.assert_allclose(res.damping, zeta, rtol=1e-6, atol=1e-8)
    assert np.all(diag_mac(res.shapes, recs[0].shapes) >= 1 - 1e-8)
    assert np.all(res.mamc > 1 - 1e-6)


@PROPERTY
@given(beam_cases())
def test_property_tcm_and_cera_exact_over_whole_periods(case):
    beam, n, sensors, impacts, _ = case
    per_period = 10 * n**2
    recs, omega, dt = _records(beam, n, sensors, impacts[:1], 0.0, 2 * per_period + 1)
    rec = recs[0]
    if len(sensors) == n:  # the TCM needs exactly one sensor per mode
        tcm = modal.tcm(rec.acceleration[:-1], dt, vel=rec.velocity[:-1])
        np.testing.assert_allclose(tcm.omega, omega, rtol=1e-8)
        assert np.all(diag_mac(tcm.shapes, rec.shapes) >= 1 - 1e-8)
    cera = modal.cera(rec.acceleration, dt, n, cols=2 * per_period)
    assert np.all(np.abs(cera.omega / omega - 1) < np.maximum(1e-7, acos_tolerance(omega, dt, 1e-11)))
    assert np.all(diag_mac(cera.shapes, rec.shapes) >= 1 - 1e-7)


@PROPERTY
@given(beam_cases(), st.floats(-150, 150))
def test_property_results_do_not_depend_on_scale(case, exponent):
    beam, n, sensors, impacts, zeta = case
    recs, _, dt = _records(beam, n, sensors, impacts[:1], zeta, 400)
    y = recs[0].acceleration
    for method, kwargs in (("era", dict(n_modes=n, rows=4, cols=200)), ("cera", dict(n_modes=n, cols=200))):
        ref = getattr(modal, method)(y, dt, **kwargs)
        scaled = getattr(modal, method)(y * 10.0**exponent, dt, **kwargs)
        np.testing.assert_allclose(scaled.omega, ref.omega, rtol=1e-9)


# ------------------------------------------------------------------ indicators where they must be low
def test_mamc_and_mpc_low_for_noise_modes_above_the_physical_order():
    rec, omega, dt = beam_record("irregular", 1000, damping=0.01)
    noisy = modal.add_noise(rec.displacement, 0.01, 0)
    res = modal.era(noisy, dt, 10, rows=20, cols=400)
    physical = np.array([np.min(np.abs(w / omega - 1)) < 0.01 for w in res.omega])
    assert physical.sum() == 6
    assert np.all(res.mamc[physical] > 0.99) and np.all(res.mpc[physical] > 0.99)
    noise = ~physical
    assert np.all(res.mamc[noise] < 0.5)
    complex_noise = noise & ~res.real_pole
    assert np.min(res.mpc[complex_noise]) < 0.5


def test_mpc_of_known_shapes():
    shapes = np.array([[1, 1, 1 + 1j], [1j, -2, 2 + 2j], [0, 1, -1 - 1j]], dtype=complex)
    np.testing.assert_allclose(modal.modal_phase_collinearity(shapes), [0.0, 1.0, 1.0], atol=1e-12)
    # entries at 45 degrees with equal weight: S = [[1, 1/2], [1/2, 1/2]] per unit, MPC = 0.2
    mixed = np.array([[1.0], [np.exp(1j * np.pi / 4)]])
    l1, l2 = np.linalg.eigvalsh(np.array([[1.5, 0.5], [0.5, 0.5]]))[::-1]
    np.testing.assert_allclose(modal.modal_phase_collinearity(mixed), ((l1 - l2) / (l1 + l2)) ** 2)


def test_mamc_of_known_histories():
    z = np.array([0.9 * np.exp(0.3j), 0.95 * np.exp(1.1j)])
    ideal = z[:, None] ** np.arange(50)[None, :] * np.array([[2.0], [1 - 1j]])
    np.testing.assert_allclose(modal.modal_amplitude_coherence(ideal, z, 1), 1, atol=1e-12)
    wrong_frequency = ideal * np.exp(0.3j * np.arange(50))[None, :]
    assert np.all(modal.modal_amplitude_coherence(wrong_frequency, z, 1) < 0.7)
    # two data sets: interleaved columns (block column j, set k at j m + k)
    two = np.stack([ideal, 3 * ideal], axis=2).reshape(2, 100)
    np.testing.assert_allclose(modal.modal_amplitude_coherence(two, z, 2), 1, atol=1e-12)


# ------------------------------------------------------------------ flags
def test_era_flags_growing_modes_unstable():
    dt, t = 0.01, 0.01 * np.arange(800)
    grow, decay = np.exp(0.02 * 3.0 * t), np.exp(-0.01 * 7.0 * t)
    y = np.column_stack([grow * np.sin(3.0 * t) + decay * np.sin(7.0 * t), grow * np.sin(3.0 * t) - decay * np.sin(7.0 * t)])
    res = modal.era(y, dt, 2, rows=10, cols=300)
    np.testing.assert_allclose(res.omega, [3.0 * np.hypot(1, 0.02), 7.0 * np.hypot(1, 0.01)], rtol=1e-6)
    np.testing.assert_array_equal(res.unstable, [True, False])
    assert res.damping[0] < 0 < res.damping[1]
    np.testing.assert_array_equal(res.to_frame()["unstable"], [True, False])


def test_tcm_flags_folded_frequencies_with_a_lag():
    lag = 8
    rec, omega, dt = beam_record("thesis", 3 * PER_PERIOD + lag)
    limit = np.pi / (lag * dt)
    res = modal.tcm(rec.acceleration, dt, lag=lag)
    assert omega[3] < limit < omega[4]  # modes 5 and 6 fold back
    assert res.aliased.sum() >= 2
    # every entry not flagged is a true mode, exactly
    for w in res.omega[~res.aliased]:
        assert np.min(np.abs(w / omega - 1)) < 1e-6
    # without the lag-one check, the folded mode 5 (43.2 rad/s) would pass as a mode
    folded = (2 * np.pi - omega[4] * lag * dt) / (lag * dt)
    hit = np.argmin(np.abs(res.omega - folded))
    assert abs(res.omega[hit] / folded - 1) < 1e-6 and res.aliased[hit]


def test_short_window_flags_the_modes_with_fewer_than_six_periods():
    rec, omega, dt = beam_record("irregular", 2 * PER_PERIOD)  # two fundamental periods
    res = modal.tcm(rec.acceleration, dt, vel=rec.velocity)
    # mode 1: 2 periods, mode 2: 8 periods (omega_2 = 4 omega_1)
    np.testing.assert_array_equal(res.short_window, [True, False, False, False, False, False])
    with pytest.warns(modal.ModalWarning, match="short window"):
        warnings.simplefilter("default", modal.ModalWarning)
        modal.tcm(rec.acceleration, dt, vel=rec.velocity)
    era = modal.era(rec.acceleration, dt, 6, rows=4, cols=2 * PER_PERIOD - 4)
    np.testing.assert_array_equal(era.short_window, res.short_window)
    cera = modal.cera(rec.acceleration[: PER_PERIOD + 1], dt, 6, cols=PER_PERIOD)  # one period
    np.testing.assert_array_equal(cera.short_window, [True, True, False, False, False, False])


def test_clean_long_record_raises_no_warning():
    rec, _, dt = beam_record("irregular", 7 * PER_PERIOD)
    with warnings.catch_warnings():
        warnings.simplefilter("error", modal.ModalWarning)
        modal.tcm(rec.acceleration, dt, vel=rec.velocity)
        modal.era(rec.acceleration, dt, 6, rows=4, cols=7 * PER_PERIOD - 4)


def test_to_frame_carries_every_flag():
    rec, _, dt = beam_record("irregular", 800)
    frame = modal.era(rec.acceleration, dt, 6, rows=8, cols=400).to_frame()
    assert {"real_pole", "unstable", "aliased", "short_window"} <= set(frame)


# ------------------------------------------------------------------ refusals
def test_vel_with_a_lag_is_refused():
    rec, _, dt = beam_record("irregular", 800)
    with pytest.raises(ValueError, match="vel"):
        modal.tcm(rec.acceleration, dt, vel=rec.velocity, lag=2)


@pytest.mark.parametrize("value", [0.0, 3.5])
@pytest.mark.parametrize("method", ["era", "cera", "tcm"])
def test_constant_channel_is_refused(method, value):
    rec, _, dt = beam_record("irregular", 800)
    y = rec.acceleration.copy()
    y[:, 2] = value
    call = {
        "era": lambda: modal.era(y, dt, 2, rows=8, cols=300),
        "cera": lambda: modal.cera(y, dt, 2, cols=300),
        "tcm": lambda: modal.tcm(y, dt),
    }[method]
    with pytest.raises(ValueError, match="channel 2 is constant"):
        call()


def test_data_sets_on_the_last_axis_are_refused():
    rec, _, dt = beam_record("irregular", 800)
    wrong = np.stack([rec.acceleration] * 3, axis=2)  # (n_samples, n_channels, n_sets)
    with pytest.raises(ValueError, match=r"\(n_sets, n_samples, n_channels\)"):
        modal.era(wrong, dt, 2, rows=2, cols=3)


def test_channels_first_is_refused():
    rec, _, dt = beam_record("irregular", 800)
    for call in (lambda y: modal.era(y, dt, 1, rows=2, cols=2), lambda y: modal.tcm(y, dt),
                 lambda y: modal.cera(y, dt, 1, cols=2)):
        with pytest.raises(ValueError, match="transpose"):
            call(rec.acceleration.T)


# ------------------------------------------------------------------ scale and offset
@pytest.mark.parametrize("scale", [1e-160, 1e-30, 1e30, 1e150])
def test_tcm_does_not_depend_on_scale(scale):
    rec, _, dt = beam_record("irregular", 3 * PER_PERIOD, damping=0.01)
    ref = modal.tcm(rec.acceleration, dt)
    # 1e-160 and 1e+150 are no powers of two: the scaled data differ in their last bits
    np.testing.assert_allclose(modal.tcm(rec.acceleration * scale, dt).omega, ref.omega, rtol=1e-8)
    lagged = modal.tcm(rec.acceleration, dt, lag=2)
    np.testing.assert_allclose(modal.tcm(rec.acceleration * scale, dt, lag=2).omega, lagged.omega, rtol=1e-8)


@pytest.mark.parametrize("layout", LAYOUTS)
def test_acceleration_offset_does_not_move_tcm(layout):
    rec, omega, dt = beam_record(layout, 4 * PER_PERIOD)
    acc = rec.acceleration
    offset = 0.01 * np.sqrt(np.mean(acc**2, axis=0)) * np.array([1, -2, 3, -1, 2, 1.5])
    base = modal.tcm(acc, dt)
    shifted = modal.tcm(acc + offset, dt)
    assert np.max(np.abs(shifted.omega / base.omega - 1)) < 5e-3
    np.testing.assert_allclose(base.omega, omega, rtol=5e-3)  # integrated velocity: close to exact


def test_integration_removes_the_offset_ramp():
    dt, n = 0.01, 2000
    t = dt * np.arange(n)
    acc = -2 * np.pi * np.sin(2 * np.pi * t)[:, None] + 0.3  # velocity cos(2 pi t), offset 0.3
    vel = modal.integrate_acceleration(acc, dt)
    # without the offset removal the error would be a ramp of +-3; what remains is
    # the least-squares slope of the sampled cosine itself (about 1.5e-3 here)
    np.testing.assert_allclose(vel[:, 0], np.cos(2 * np.pi * t), atol=2e-3)
    np.testing.assert_allclose(modal.signals.acceleration_offset(acc, dt), [0.3], rtol=1e-3)
