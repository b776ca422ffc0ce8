"""Without ``fmax``, the record is decimated no further than keeps its highest
prominent spectral peak in the band (``modal.measured._pipeline.auto_decimation``):
a beam's modes lie at ``n^2`` times its first, beyond the 27 times the
lowest peak alone kept."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import modal
from modal.measured import _pipeline
from modal.measured._pipeline import AUTO_BAND, AUTO_MAX_SAMPLES, AUTO_SAMPLES, auto_decimation, prominent_peaks_hz


def test_the_constants():
    assert (AUTO_SAMPLES, AUTO_BAND, AUTO_MAX_SAMPLES) == (200 / 3, 1.25, 512)


@pytest.mark.parametrize("fs, peaks, factor", [
    (400.0, [], 1),  # no peak: no decimation
    (400.0, [2.5], 2),  # the lowest alone: 400 / (66.7 x 2.5) = 2.4
    (400.0, [2.0, 128.0], 1),  # 128 x 1.25 x 2.5 = 400: none
    (400.0, [2.0, 64.0], 2),  # 400 / 200 = 2: exactly the pass band's edge
    (400.0, [2.0, 65.0], 1),  # just above it
    (400.0, [1.0, 32.0], 4),  # 400 / 100 = 4 (the lowest alone: 6)
    (400.0, [1.0, 33.0], 3),
    (12800.0, [2.0, 4000.0], 12),  # the highest would keep all, but 512 samples per period of 2 Hz is the most
    (12800.0, [2.0, 1000.0], 12),
    (12800.0, [2.0, 200.0], 20),  # 12800 / 625: the band, within the most samples
    (12800.0, [40.0, 200.0], 4),  # the lowest alone allows 4
])
def test_auto_decimation(fs, peaks, factor):
    """Each bound on both sides: the lowest peak's samples per period, the
    highest peak's band (at its edge and just beyond), the most samples per
    period of the lowest (a band too wide for one model)."""
    assert auto_decimation(1 / fs, np.array(peaks)) == factor


def test_peaks_ascending_above_the_floor():
    """Two sines and their average spectrum: both peaks, ascending; the
    lowest is :func:`lowest_peak_hz`; a constant record has none."""
    fs, n = 256.0, 2**15
    t = np.arange(n) / fs
    rng = np.random.default_rng(3)
    y = np.column_stack([np.sin(2 * np.pi * 40 * t), np.sin(2 * np.pi * 5 * t) + 0.5 * np.sin(2 * np.pi * 40 * t)])
    y = y + 1e-3 * rng.standard_normal(y.shape)
    peaks = prominent_peaks_hz(y, 1 / fs)
    assert peaks.tolist() == [5.0, 40.0]
    assert _pipeline.lowest_peak_hz(y, 1 / fs) == 5.0
    assert prominent_peaks_hz(np.zeros((1000, 2)), 1 / fs).size == 0
    assert prominent_peaks_hz(y[:63], 1 / fs).size == 0
    assert [part.size for part in _pipeline.spectral_peaks(y[:63], 1 / fs)] == [0, 0]


def test_a_peaks_height_is_over_the_median_within_a_quarter_of_its_frequency(monkeypatch):
    """``spectral_peaks`` with its defaults, on a given averaged spectrum
    (bins of 0.125 Hz, level 1): a peak 6.5 dB above its surroundings at 5
    Hz is one, 5.7 dB at 7.5 Hz is not (prominence 6 dB); a peak of 100 at
    bin 160 (20 Hz) in a trough of +-20 bins at 1 between shelves at 5 out
    to +-60: within +-25 % of 20 Hz (+-40 bins) 40 bins lie at 1, 40 at 5,
    so the median is 5 and the height 10 log10(100 / 5) = 13.0 dB (over
    +-20 bins it would be 20 dB); the 5 Hz peak's window is the ten bins
    either side (+-25 % is 10 bins), its height its 6.5 dB."""
    import scipy.signal

    power = np.ones(300)
    power[100:140] = power[181:221] = 5.0
    power[160], power[40], power[60] = 100.0, 10**0.65, 10**0.57
    monkeypatch.setattr(scipy.signal, "welch", lambda x, fs, nperseg: (0.125 * np.arange(300), power))
    peaks, heights = _pipeline.spectral_peaks(np.zeros((100000, 1)), 0.01)
    assert 5.0 in peaks and 7.5 not in peaks
    assert heights[peaks.tolist().index(5.0)] == pytest.approx(6.5)
    assert heights[peaks.tolist().index(20.0)] == pytest.approx(10 * np.log10(20))


def beam_record(seconds=200.0, fs=400.0, seed=5):
    """A simply supported beam with f1 = 2 Hz (modes at 2 n^2 Hz: eight up to
    128 Hz), 1 % damping, six sensors at uneven positions, white forces at
    five other points, 2 % sensor noise."""
    beam = modal.SimplySupportedBeam(length=1.0, bending_stiffness=(4 / np.pi) ** 2, mass_per_length=1.0)
    omega = beam.natural_frequencies(8)  # sqrt(EI / m) (n pi / L)^2 = 2 pi 2 n^2
    sensors_x = np.array([0.07, 0.21, 0.38, 0.55, 0.81, 0.93])
    forces_x = np.array([0.13, 0.29, 0.47, 0.66, 0.88])
    acc = modal.structures.ambient_response(omega, 0.01, beam.mode_shapes(sensors_x, 8), beam.mode_shapes(forces_x, 8),
                                            int(seconds * fs), 1 / fs, seed=seed)
    rng = np.random.default_rng(seed + 1)
    acc = acc + 0.02 * acc.std(axis=0) * rng.standard_normal(acc.shape)
    return acc, 1 / fs, omega / (2 * np.pi)


def test_a_beams_modes_up_to_the_highest_peak_with_default_options():
    """Eight modes from 2 to 128 Hz (64 times the first): every one trusted,
    within 0.5 % of its closed-form frequency, and not decimated (the lowest
    peak alone decimated by 2 to 200 Hz, and 98 and 128 Hz were lost)."""
    acc, dt, f_true = beam_record()
    log, details = [], {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        result, dt_used = modal.identify_record(acc, dt, "ambient", log=log.append, details=details)
    settings = details["settings"]
    assert dt_used == dt and settings["decimation"] == 1
    assert settings["lowest_peak_hz"] == pytest.approx(2.0, abs=0.1)
    assert settings["highest_peak_hz"] == pytest.approx(128.0, abs=0.5)
    line = next(entry for entry in log if entry.startswith("lowest spectral peak"))
    assert re.search(r"the highest spectral peak 12[78]\.\d Hz kept in the band \(the lowest alone would decimate by 2\)", line)
    assert not [entry for entry in log if entry.startswith("spectral peaks above the band kept")]  # none: not decimated
    modes = result.modes
    trusted = modes[modes["flag"].fillna("") == ""]["freq_hz"].to_numpy()
    nearest = np.min(np.abs(trusted[:, None] / f_true[None, :] - 1), axis=0)
    assert np.all(nearest < 0.005), nearest
    assert len(trusted) == len(f_true)  # each mode once


def test_a_band_too_wide_for_one_model_is_logged(monkeypatch):
    """Peaks from 0.1 to 60 Hz of a 128 Hz record: the band would need 1280
    samples per period of 0.1 Hz; at most 512, so decimated by 2 to 64 Hz,
    and the log names the peaks left out (22 Hz: 1.25 x 22 lies beyond the
    filter's edge at 25.6 Hz; 20 Hz stays, and 20.48 Hz, whose 1.25 x lies
    exactly on it) and the option that keeps them;
    a peak that stands less than 6 dB above the level around it (30 Hz)
    neither widens the band nor is named."""
    monkeypatch.setattr(_pipeline, "spectral_peaks", lambda y, dt: (np.array([0.1, 20.0, 20.48, 22.0, 30.0, 60.0]),
                                                                     np.array([12.0, 9.0, 8.0, 6.0, 5.9, 15.0])))
    rng = np.random.default_rng(4)
    acc = rng.standard_normal((128 * 120, 2))
    log, details = [], {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        _, dt_used = modal.identify_record(acc, 1 / 128, "ambient", max_order=4, log=log.append, details=details)
    assert dt_used == 2 / 128 and details["settings"]["highest_peak_hz"] == 60.0
    line = next(entry for entry in log if entry.startswith("lowest spectral peak"))
    assert line.endswith("decimated by 2 to 64 Hz, the highest spectral peak 60 Hz kept in the band (the lowest alone "
                         "would decimate by 19) (set --fmax and --rows to choose)")  # 128 / (66.7 x 0.1) = 19.2
    lost = [entry for entry in log if entry.startswith("spectral peaks above the band kept")]
    assert lost == ["spectral peaks above the band kept (22, 60 Hz): more than 512 samples per period of the lowest "
                    "peak would be needed; set --fmax to identify them"]


def noise_floor_record(seconds=600.0, fs=500.0, seed=0):
    """Two modes (1.0 and 3.1 Hz, white forces through their filters) on four
    channels, one of them at a node of both, with 2 % sensor noise, sampled
    at 500 Hz: a band of noise from 5 to 250 Hz."""
    from scipy.signal import lfilter

    rng = np.random.default_rng(seed)
    dt, n = 1 / fs, int(seconds * fs)
    responses = []
    for f, zeta in ((1.0, 0.015), (3.1, 0.012)):
        w = 2 * np.pi * f * dt
        r = np.exp(-zeta * w)
        responses.append(lfilter([1.0], [1.0, -2 * r * np.cos(w), r * r], rng.standard_normal(n)))
    shapes = np.array([[0.0, 0.0], [0.5, 1.0], [1.0, 0.3], [0.8, -0.9]])
    y = np.column_stack(responses) @ shapes.T
    return y + 0.02 * rng.standard_normal(y.shape), dt


def test_maxima_of_a_noise_floor_do_not_widen_the_band():
    """Over a wide band of noise, the spectral estimate's random error leaves
    maxima 6 dB above their troughs (here dozens, 5-250 Hz), each a few dB
    above the level around it; the 1 Hz mode's peak stands far above it.
    The band follows the mode's peak: decimated as the lowest peak alone
    decimates (by 7 to 71 Hz, not kept at 500 Hz), both modes trusted and
    nothing else (kept at 500 Hz, three rows at 106-226 Hz, flagged)."""
    from modal.identification import PEAK_HEIGHT_DB

    y, dt = noise_floor_record()
    peaks, heights = _pipeline.spectral_peaks(y, dt)
    noise = peaks > 5.0
    assert noise.sum() >= 10 and np.all(heights[noise] < PEAK_HEIGHT_DB)
    assert peaks[0] == pytest.approx(1.0, abs=0.02) and heights[0] >= PEAK_HEIGHT_DB
    log, details = [], {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        result, dt_used = modal.identify_record(y, dt, "ambient", log=log.append, details=details)
    settings = details["settings"]
    assert settings["decimation"] == int(1 / (dt * AUTO_SAMPLES * peaks[0])) == 7 and dt_used == 7 * dt
    assert settings["highest_peak_hz"] == peaks[0]
    assert not [entry for entry in log if entry.startswith("spectral peaks above the band kept")]
    modes = result.modes
    trusted = modes[modes["flag"].fillna("") == ""]["freq_hz"].to_numpy()
    assert np.sort(trusted) == pytest.approx([1.0, 3.1], rel=0.01)
