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
    modes = result.modes
    trusted = modes[modes["flag"].fillna("") == ""]["freq_hz"].to_numpy()
    nearest = np.min(np.abs(trusted[:, None] / f_true[None, :] - 1), axis=0)
    assert np.all(nearest < 0.005), nearest
    assert len(trusted) == len(f_true)  # each mode once


def test_a_band_too_wide_for_one_model_is_logged(monkeypatch):
    """Peaks from 0.1 to 60 Hz of a 128 Hz record: the band would need 1280
    samples per period of 0.1 Hz; at most 512, so decimated by 2 to 64 Hz,
    and the log names the peaks left out (22 Hz: 1.25 x 22 lies beyond the
    filter's edge at 25.6 Hz; 20 Hz stays) and the option that keeps them."""
    monkeypatch.setattr(_pipeline, "prominent_peaks_hz", lambda y, dt: np.array([0.1, 20.0, 22.0, 60.0]))
    rng = np.random.default_rng(4)
    acc = rng.standard_normal((128 * 120, 2))
    log, details = [], {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        _, dt_used = modal.identify_record(acc, 1 / 128, "ambient", max_order=4, log=log.append, details=details)
    assert dt_used == 2 / 128 and details["settings"]["highest_peak_hz"] == 60.0
    lost = [entry for entry in log if entry.startswith("spectral peaks above the band kept")]
    assert lost == ["spectral peaks above the band kept (22, 60 Hz): more than 512 samples per period of the lowest "
                    "peak would be needed; set --fmax to identify them"]
