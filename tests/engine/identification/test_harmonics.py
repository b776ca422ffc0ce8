"""Harmonics told from modes by their steady amplitude (modal.identification.envelope_variation)."""

from __future__ import annotations

import numpy as np
import pytest

import modal
from modal.identification import envelope_variation, steady

from ..cases import _foh_acceleration, ambient_beam


def mode_and_sine(duration_s=600.0, dt=0.05, seed=0):
    """Two channels: a 2 Hz mode (1 % damping, white load) of shape [1, 0.5]
    and a 3 Hz sine of shape [1, -1] as strong as the mode."""
    rng = np.random.default_rng(seed)
    t = dt * np.arange(int(duration_s / dt))
    mode = _foh_acceleration(2 * np.pi * 2.0, 0.01, rng.standard_normal(len(t)), dt)
    sine = mode.std() * np.sqrt(2) * np.sin(2 * np.pi * 3.0 * t + 0.3)
    return np.column_stack([mode + sine, 0.5 * mode - sine]), dt


def test_a_random_mode_varies_a_harmonic_does_not():
    """The mode's envelope varies as a Rayleigh amplitude does (0.52; here
    0.35-0.65), the sine's hardly at all (below 0.1); ``envelope_values`` is ``pi zeta f
    T`` (37.7 and 5.65 correlation times). With the sine's shape the mode's
    shape, or the bands swapped, the numbers change."""
    y, dt = mode_and_sine()
    shapes = np.array([[1.0, 1.0], [0.5, -1.0]])
    variation = envelope_variation(y, dt, [2.0, 3.0], [0.01, 0.001], shapes)
    cv = variation["envelope_cv"].to_numpy()
    assert 0.35 < cv[0] < 0.65 and cv[1] < 0.1, cv
    np.testing.assert_allclose(variation["envelope_values"], [np.pi * 0.01 * 2.0 * 600, np.pi * 0.001 * 3.0 * 600])
    # the sine seen through the mode's shape is still the sine (its band holds nothing else) ...
    assert envelope_variation(y, dt, [3.0], [0.001], shapes[:, :1])["envelope_cv"][0] < 0.1
    # ... and the mode's band through the sine's shape still the mode
    assert envelope_variation(y, dt, [2.0], [0.01], shapes[:, 1:])["envelope_cv"][0] > 0.35


def test_steady_needs_a_steady_envelope_over_enough_correlation_times():
    """Steady: CV below 0.2 on at least 8 correlation times; 0.2 itself, or
    7.9 correlation times, is not; NaN (a band too narrow to judge) is not."""
    import pandas as pd

    table = pd.DataFrame({"envelope_cv": [0.05, 0.2, 0.199, 0.05, np.nan, 0.5],
                          "envelope_values": [8.0, 30.0, 30.0, 7.9, 30.0, 30.0]})
    assert steady(table).tolist() == [True, False, True, False, False, False]


def test_a_band_too_narrow_to_judge_is_nan_and_bad_input_is_refused():
    """A 600-sample record (0.033 Hz bins at 20 Hz) cannot resolve a band of
    +-0.01 Hz around 1 Hz: NaN. Shapes of the wrong size, a 1-D record and
    NaN frequencies are refused naming the argument."""
    y, dt = mode_and_sine(duration_s=30.0)
    assert np.isnan(envelope_variation(y, dt, [1.0], [0.001], np.ones((2, 1)))["envelope_cv"][0])
    with pytest.raises(ValueError, match="shapes"):
        envelope_variation(y, dt, [2.0, 3.0], [0.01, 0.01], np.ones((3, 2)))
    with pytest.raises(ValueError, match="^y "):
        envelope_variation(y[:, 0], dt, [2.0], [0.01], np.ones((1, 1)))
    with pytest.raises(ValueError, match="freq_hz"):
        envelope_variation(y, dt, [np.nan], [0.01], np.ones((2, 1)))


def test_identify_record_flags_a_wandering_harmonic_and_no_mode():
    """A beam's three modes under white load and a machine's line at 2.89 Hz
    whose phase wanders (a random walk of 0.033 rad per sample: identified
    as a 0.3 % damped mode, within the factor the damping check allows): its
    row is flagged 'harmonic (envelope CV ...)', the beam's modes are
    trusted; the columns are in the modes table. A free decay is not
    judged."""
    acc, dt, freq = ambient_beam(400.0)
    t = dt * np.arange(len(acc))
    phase = np.cumsum(np.random.default_rng(3).normal(0.0, 0.033, len(t)))
    machine = acc + 0.5 * acc.std(axis=0) * np.sin(2 * np.pi * 2.89 * t + phase)[:, None]
    messages = []
    result, _ = modal.identify_record(machine, dt, "ambient", log=messages.append)
    modes = result.modes.set_index(result.modes["freq_hz"].round(1))
    assert modes.loc[2.9, "flag"].startswith("harmonic (envelope CV 0.1"), modes.loc[2.9, "flag"]
    assert modes.loc[2.9, "envelope_values"] >= 8
    trusted = result.trusted_modes["freq_hz"].to_numpy()
    np.testing.assert_allclose(trusted, freq, rtol=0.01)
    assert (result.trusted_modes["envelope_cv"] > 0.35).all()
    assert any("steady amplitude (a harmonic, not a mode) at 2.89" in m for m in messages), messages
    decay_t = dt * np.arange(3000)
    decay = np.outer(np.exp(-0.02 * 2 * np.pi * 3 * decay_t) * np.cos(2 * np.pi * 3 * decay_t), [1.0, 0.6])
    decay += 1e-4 * np.random.default_rng(1).standard_normal(decay.shape)
    result, _ = modal.identify_record(decay, dt, "free_decay")
    assert len(result.modes) and "envelope_cv" not in result.modes
