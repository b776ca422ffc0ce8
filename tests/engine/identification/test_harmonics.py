"""Harmonics told from modes by their steady amplitude (modal.identification.envelope_variation)."""

from __future__ import annotations

import numpy as np
import pandas as pd
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
    table = pd.DataFrame({"envelope_cv": [0.05, 0.2, 0.199, 0.05, np.nan, 0.5],
                          "envelope_values": [8.0, 30.0, 30.0, 7.9, 30.0, 30.0]})
    assert steady(table).tolist() == [True, False, True, False, False, False]


def test_a_band_too_narrow_to_judge_is_nan_and_bad_input_is_refused():
    """A 600-sample record (0.033 Hz bins at 20 Hz) cannot resolve a band of
    +-0.01 Hz around 1 Hz: NaN. Shapes of the wrong size, a 1-D record and
    NaN frequencies and a sampling interval of 0 are refused naming the
    argument."""
    y, dt = mode_and_sine(duration_s=30.0)
    assert np.isnan(envelope_variation(y, dt, [1.0], [0.001], np.ones((2, 1)))["envelope_cv"][0])
    with pytest.raises(ValueError, match="shapes"):
        envelope_variation(y, dt, [2.0, 3.0], [0.01, 0.01], np.ones((3, 2)))
    with pytest.raises(ValueError, match="^y "):
        envelope_variation(y[:, 0], dt, [2.0], [0.01], np.ones((1, 1)))
    with pytest.raises(ValueError, match="^freq_hz "):
        envelope_variation(y, dt, [np.nan], [0.01], np.ones((2, 1)))
    with pytest.raises(ValueError, match="^dt "):
        envelope_variation(y, 0.0, [2.0], [0.01], np.ones((2, 1)))


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


def two_tones_cv(bins_apart, band_bins, phase):
    """The envelope's CV of two tones of equal amplitude ``bins_apart`` bins
    apart in a band of ``band_bins`` bins, sampled 4 times per bin: the
    envelope is ``|1 + exp(i (phase + 2 pi d j / N))|`` at ``N = 4 L``."""
    n = 4 * band_bins
    envelope = np.abs(1 + np.exp(1j * (phase + 2 * np.pi * bins_apart * np.arange(n) / n)))
    return envelope.std() / envelope.mean()


def tones(n, amplitudes):
    """``n`` samples at 1 / n s (bins of 1 Hz) of cosines ``{bin: (amplitude, phase)}``."""
    t = np.arange(n) / n
    return sum(a * np.cos(2 * np.pi * k * t + p) for k, (a, p) in amplitudes.items())[:, None], 1 / n


def test_the_band_is_f_plus_minus_four_zeta_f_or_a_percent_of_f_its_edges_included():
    """Bins of 1 Hz. A mode at 15.5 Hz of damping 5 / 62 (4 zeta f = 5 Hz)
    has the band 10.5-20.5 Hz: bins 11-20. Tones of equal amplitude at 11
    and 20 Hz, three times stronger ones at 10 and 21 Hz just outside: the
    envelope is the two tones' (their CV in closed form, 0.48409, four
    samples per bin); a bin more or less at either edge, a wider band or
    other sampling would change it (one tone alone: 0). Without damping
    (NaN or negative: 0) the band is 1 % of f: 550 Hz, bins 545-555. The
    amplitude (1e-6) does not matter."""
    y, dt = tones(256, {10: (3e-6, 0.0), 11: (1e-6, 0.0), 20: (1e-6, 0.3), 21: (3e-6, 0.0)})
    variation = envelope_variation(y, dt, [15.5], [5 / 62], [[1.0]])
    assert variation["envelope_cv"][0] == pytest.approx(two_tones_cv(9, 10, 0.3), rel=1e-9)
    assert two_tones_cv(9, 10, 0.3) == pytest.approx(0.48409, abs=1e-5)
    assert variation["envelope_values"][0] == pytest.approx(np.pi * 5 / 62 * 15.5 * 1.0)
    y, dt = tones(4096, {544: (3.0, 0.0), 545: (1.0, 0.0), 555: (1.0, 1.1), 556: (3.0, 0.0)})
    variation = envelope_variation(y, dt, [550.0, 550.0], [np.nan, -0.01], np.ones((1, 2)))
    np.testing.assert_allclose(variation["envelope_cv"], two_tones_cv(10, 11, 1.1), rtol=1e-9)
    assert variation["envelope_values"].tolist() == [0.0, 0.0]


def test_the_band_stops_at_bin_1_and_at_the_nyquist_bin():
    """A band reaching below 0 Hz starts at bin 1 (the mean, bin 0, is not
    a vibration): 2.5 Hz +- 3 Hz holds the tones at 1 and 5 Hz, not the
    offset. One reaching beyond the Nyquist frequency (128 Hz) ends there:
    126.5 Hz +- 2.25 Hz holds bins 125-128, the tone at 125 Hz and the
    Nyquist one (its bin holds n a, not n a / 2: amplitude 0.5 for the same
    height)."""
    y, dt = tones(256, {0: (4.0, 0.0), 1: (1.0, 0.0), 5: (1.0, 0.7)})
    cv = envelope_variation(y, dt, [2.5], [0.3], [[1.0]])["envelope_cv"][0]
    assert cv == pytest.approx(two_tones_cv(4, 5, 0.7), rel=1e-9)
    y, dt = tones(256, {125: (1.0, 0.4), 128: (0.5, 0.0)})
    cv = envelope_variation(y, dt, [126.5], [2.25 / (4 * 126.5)], [[1.0]])["envelope_cv"][0]
    assert cv == pytest.approx(two_tones_cv(3, 4, -0.4), rel=1e-9)


def test_a_band_of_three_bins_is_judged_of_two_not_even_at_the_nyquist_bin():
    """15 Hz +- 1.2 Hz is bins 14-16: three, judged (tones at 14 and 16 Hz);
    15.5 Hz +- 0.9 Hz is bins 15-16: two, NaN; 127.6 Hz +- 1.5 Hz reaches
    129.1 Hz, beyond the last bin (128): bins 127-128, NaN. A NaN band
    before a mode does not stop the next one's judgement."""
    y, dt = tones(256, {14: (1.0, 0.0), 16: (1.0, 0.2), 127: (1.0, 0.0), 128: (1.0, 0.0)})
    variation = envelope_variation(y, dt, [15.5, 127.6, 15.0], [0.9 / 62, 1.5 / (4 * 127.6), 1.2 / 60],
                                   np.ones((1, 3)))
    cv = variation["envelope_cv"].to_numpy()
    assert np.isnan(cv[:2]).all()
    assert cv[2] == pytest.approx(two_tones_cv(2, 3, 0.2), rel=1e-9)


def test_a_mode_the_record_does_not_hold_and_no_modes():
    """A shape orthogonal to the motion sees an exactly silent band: NaN,
    no warning (warnings are errors here); no modes: an empty table with
    both columns."""
    y, dt = tones(256, {20: (1.0, 0.0)})
    y = np.column_stack([y[:, 0], y[:, 0]])
    assert np.isnan(envelope_variation(y, dt, [20.0], [0.05], [[1.0], [-1.0]])["envelope_cv"][0])
    empty = envelope_variation(y, dt, [], [], np.empty((2, 0)))
    assert list(empty.columns) == ["envelope_cv", "envelope_values"] and len(empty) == 0


def stabilisation_of(modes, shapes):
    """A bare Stabilisation holding ``modes`` and ``shapes`` (no poles)."""
    from modal.identification import Stabilisation

    return Stabilisation(modes=modes, shapes=shapes, poles=pd.DataFrame(), pole_shapes=np.empty((0, 0)),
                         singular_values=np.empty(0), spectrum_hz=np.empty(0), spectrum=np.empty(0))


def test_the_harmonic_check_adds_its_columns_last_and_its_reason_after_the_others():
    """The mode and the sine of :func:`mode_and_sine` (rows labelled 7 and
    9): the columns ``envelope_cv``, ``envelope_values`` come last, once
    (a second check replaces them), with the values of envelope_variation;
    the sine (11 correlation times at 0.2 %) gets ``harmonic (envelope CV 0.0x)`` after its own
    reason, joined by ``"; "``, a NaN flag counts as none; the flags keep
    their index and type; checked twice, each reason is there once. Without
    a flag column none is added."""
    from modal.measured._pipeline import with_harmonic_check

    y, dt = mode_and_sine()
    shapes = np.array([[1.0, 1.0], [0.5, -1.0]])
    modes = pd.DataFrame({"freq_hz": [2.0, 3.0], "damping": [0.01, 0.002], "flag": ["low MPC 0.41", np.nan]},
                         index=[7, 9]).astype({"flag": object})  # not pandas' own str
    once = with_harmonic_check(stabilisation_of(modes, shapes), y, dt)
    twice = with_harmonic_check(once, y, dt).modes  # a second check as the first: columns and reasons once
    assert list(twice.columns) == list(once.modes.columns) and twice["flag"].tolist() == once.modes["flag"].tolist()
    checked = once.modes
    assert list(checked.columns) == ["freq_hz", "damping", "flag", "envelope_cv", "envelope_values"]
    assert checked.index.tolist() == [7, 9] and checked["flag"].dtype == object
    expected = envelope_variation(y, dt, [2.0, 3.0], [0.01, 0.002], shapes)
    np.testing.assert_array_equal(checked["envelope_cv"], expected["envelope_cv"])
    np.testing.assert_array_equal(checked["envelope_values"], expected["envelope_values"])
    cv = expected["envelope_cv"][1]
    assert cv < 0.1
    assert checked["flag"].tolist() == ["low MPC 0.41", f"harmonic (envelope CV {cv:.2f})"]
    flagged = stabilisation_of(modes.assign(flag=["low MPC 0.41", "single channel"]), shapes)
    assert with_harmonic_check(flagged, y, dt).modes["flag"].tolist() == [
        "low MPC 0.41", f"single channel; harmonic (envelope CV {cv:.2f})"]
    bare = with_harmonic_check(stabilisation_of(modes.drop(columns="flag"), shapes), y, dt).modes
    assert list(bare.columns) == ["freq_hz", "damping", "envelope_cv", "envelope_values"]


def test_the_log_names_every_harmonic_in_one_line(monkeypatch):
    """identify_record logs the modes flagged harmonic in one line, by
    frequency as the table holds them, joined by ", ", in Hz; none when no
    flag names a harmonic (the check itself replaced here by one that flags
    given rows of a given table)."""
    import dataclasses
    import warnings

    from modal.measured import _pipeline

    flags = {"two": ["harmonic (envelope CV 0.05)", "", "low MPC 0.41; harmonic (envelope CV 0.1)"],
             "none": ["", "low MPC 0.41", ""]}
    rng = np.random.default_rng(22)
    acc, dt = rng.standard_normal((2560, 2)), 1 / 128
    for case, expected in (("two", ["steady amplitude (a harmonic, not a mode) at 1.5, 3.125 Hz"]), ("none", [])):
        table = pd.DataFrame({"freq_hz": [1.5, 2.25, 3.125], "spectral_support": True, "flag": flags[case]})
        monkeypatch.setattr(_pipeline, "with_harmonic_check",
                            lambda result, y, dt, table=table: dataclasses.replace(result, modes=table))
        log = []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", modal.ModalWarning)
            modal.identify_record(acc, dt, "ambient", max_order=4, fmax=20, rows=70, log=log.append)
        assert [line for line in log if line.startswith("steady amplitude")] == expected
