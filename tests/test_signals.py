"""Preprocessing: the thesis's FFT filter and record splitting."""

import numpy as np

import modal


def test_lowpass_removes_bins_above_cutoff_only():
    dt, n = 0.005, 4096  # the grid record: 200 Hz, 4096 samples
    t = dt * np.arange(n)
    f_low, f_high = 50 / (n * dt), 2000 / (n * dt)  # on FFT bins: 2.44 Hz and 97.7 Hz
    low = np.sin(2 * np.pi * f_low * t)
    high = 0.5 * np.cos(2 * np.pi * f_high * t)
    out = modal.lowpass_fft(np.column_stack([low + high, high]), dt, 10.0)
    np.testing.assert_allclose(out[:, 0], low, atol=1e-12)
    np.testing.assert_allclose(out[:, 1], 0, atol=1e-12)


def test_lowpass_keeps_the_cutoff_bin():
    dt, n = 0.005, 4096
    freqs = np.fft.rfftfreq(n, dt)
    k = np.searchsorted(freqs, 7.5)
    t = dt * np.arange(n)
    y = np.sin(2 * np.pi * freqs[k - 1] * t)[:, None]
    np.testing.assert_allclose(modal.lowpass_fft(y, dt, 7.5), y, atol=1e-12)


def test_split_record():
    y = np.arange(4096 * 4, dtype=float).reshape(4096, 4)
    sets = modal.split_record(y, 3)
    assert sets.shape == (3, 1365, 4)
    np.testing.assert_array_equal(sets[1, 0], y[1365])


def test_amplitude_spectrum_peak():
    dt, n = 0.005, 4096
    t = dt * np.arange(n)
    f0 = 100 / (n * dt)
    freqs, amp = modal.amplitude_spectrum(np.sin(2 * np.pi * f0 * t)[:, None], dt)
    assert freqs[np.argmax(amp[:, 0])] == f0
    assert abs(amp[:, 0].max() - 0.5) < 1e-12
