"""TCM without a lag (Eq. 31): frequencies the sampling cannot carry are
flagged, and a velocity that is not the velocity of the acceleration given
(a displacement, other units) is named in a warning instead of silently
scaling or squaring every frequency."""

import warnings

import numpy as np
import pytest

import modal

L, EI, M = 5.0, 30.0, 1.0


@pytest.fixture(scope="module")
def demo():
    """The thesis's beam demonstration (Sec. 6.1): dt a tenth of the 6th
    mode's period, sensors at iL/7, impulse at 2L/7, 3594 samples."""
    beam = modal.SimplySupportedBeam(L, EI, M)
    omega = beam.natural_frequencies(6)
    dt = 2 * np.pi / omega[-1] / 10
    record = modal.beam_impulse_response(beam, 6, 2 * L / 7, beam.stations(7), dt, 3594)
    return record, omega, dt


def _tcm(acc, dt, vel):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = modal.tcm(acc, dt, vel=vel)
    return result, [str(w.message) for w in caught if issubclass(w.category, modal.ModalWarning)]


def test_consistent_velocity_gives_the_modes_and_no_warning(demo):
    record, omega, dt = demo
    result, messages = _tcm(record.acceleration, dt, record.velocity)
    np.testing.assert_allclose(result.omega, omega, rtol=0.01)
    assert not result.aliased.any()
    assert messages == []


def test_one_derivative_lower_is_consistent_too(demo):
    """The thesis's alternative reading: TCM on displacement and velocity."""
    record, omega, dt = demo
    result, messages = _tcm(record.velocity, dt, record.displacement)
    np.testing.assert_allclose(result.omega, omega, rtol=0.01)
    assert messages == []


def test_displacement_given_as_velocity_is_flagged_and_named(demo):
    """Before: omega up to 6060 rad/s, 15 x the Nyquist rate, no flag, no warning."""
    record, omega, dt = demo
    result, messages = _tcm(record.acceleration, dt, record.displacement)
    nyquist = np.pi / dt
    assert result.omega.max() > 10 * nyquist
    np.testing.assert_array_equal(result.aliased, result.omega >= 0.98 * nyquist)
    assert result.aliased.sum() == 3
    mix_up = [m for m in messages if "vel and acc" in m]
    assert len(mix_up) == 1 and "is vel a displacement" in mix_up[0]
    assert any("possibly aliased" in m and "6060" in m for m in messages)


@pytest.mark.parametrize("vel_scale, acc_scale, factor", [(1000.0, 1.0, "0.00104"),  # vel in mm/s, acc in m/s^2
                                                          (1.0, 1 / 9.81, "0.106")])  # acc in g, vel in m/s
def test_unit_mix_up_is_named(demo, vel_scale, acc_scale, factor):
    record, omega, dt = demo
    result, messages = _tcm(acc_scale * record.acceleration, dt, vel_scale * record.velocity)
    np.testing.assert_allclose(result.omega / omega, acc_scale / vel_scale, rtol=0.02)  # every omega scaled
    mix_up = [m for m in messages if "vel and acc" in m]
    assert len(mix_up) == 1
    assert f"acc = {factor}" in mix_up[0] and "unit mix-up" in mix_up[0] and "every channel" in mix_up[0]


def test_mm_per_s_puts_the_mean_frequency_outside_the_record(demo):
    record, _, dt = demo
    _, messages = _tcm(record.acceleration, dt, 1000 * record.velocity)
    assert any("rms(acc) / rms(vel) = 0.04426 rad/s" in m and "outside what the record can carry" in m
               for m in messages)


def test_noisy_consistent_pair_draws_no_mix_up_warning(demo):
    record, _, dt = demo
    vel = modal.add_noise(record.velocity, 0.05, 1)
    acc = modal.add_noise(record.acceleration, 0.05, 2)
    _, messages = _tcm(acc, dt, vel)
    assert not [m for m in messages if "vel and acc" in m]
