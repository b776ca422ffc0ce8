"""Preprocessing: the thesis's FFT filter, record splitting, integration of
accelerations, and the preprocessing of measured records (detrend, zero-phase
filter, decimation, decay start)."""

import numpy as np
import pytest

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


# Preprocessing of measured records: detrend, zero-phase filtering, decimation,
# the start of a free decay. Off the thesis's geometry on purpose: odd channel
# counts, lengths and sampling rates.


def test_detrend_removes_a_line_or_the_mean_exactly():
    """A residual orthogonal to 1 and t plus a line per channel: "linear"
    returns the residual, "constant" only the mean (the slope stays)."""
    rng = np.random.default_rng(11)
    n, dt = 737, 1 / 333
    t = dt * np.arange(n)
    basis = np.column_stack([np.ones(n), t])
    noise = rng.standard_normal((n, 5))
    residual = noise - basis @ np.linalg.lstsq(basis, noise, rcond=None)[0]
    offset, slope = np.array([3.0, -1.0, 0.0, 250.0, 0.5]), np.array([2.0, 0.0, -7.5, 1.0, 40.0])
    y = residual + offset + slope * t[:, None]
    np.testing.assert_allclose(modal.detrend(y), residual, atol=1e-12)
    np.testing.assert_allclose(modal.detrend(y, "linear"), residual, atol=1e-12)
    centred = modal.detrend(y, "constant")
    np.testing.assert_allclose(centred, residual + slope * (t - t.mean())[:, None], atol=1e-12)
    np.testing.assert_allclose(centred.mean(axis=0), 0, atol=1e-12)


def _sines(t, freqs_hz):
    """One sinusoid per channel, at its own frequency and phase."""
    freqs_hz = np.asarray(freqs_hz)
    return np.sin(2 * np.pi * freqs_hz * t[:, None] + 0.7 * np.arange(freqs_hz.size))


def _butterworth_gain(freqs_hz, fs, order, highpass_hz=None, lowpass_hz=None):
    """|H(f)|^2 of the digital Butterworth (bilinear transform with prewarped
    edges, so the analog response at tan(pi f / fs)): the gain of the filter
    run forwards and backwards."""
    w = np.tan(np.pi * np.asarray(freqs_hz) / fs)
    if highpass_hz is not None and lowpass_hz is not None:
        w1, w2 = np.tan(np.pi * highpass_hz / fs), np.tan(np.pi * lowpass_hz / fs)
        x = (w**2 - w1 * w2) / (w * (w2 - w1))
    elif lowpass_hz is not None:
        x = w / np.tan(np.pi * lowpass_hz / fs)
    else:
        x = np.tan(np.pi * highpass_hz / fs) / w
    return 1 / (1 + x ** (2 * order))


@pytest.mark.parametrize(("edges", "order", "freqs_hz"), [
    (dict(lowpass_hz=12.0), None, [5.0, 12.0, 17.0]),  # None: the default order, 4
    (dict(lowpass_hz=12.0), 3, [5.0, 12.0, 17.0]),
    (dict(highpass_hz=2.0), None, [0.7, 2.0, 6.0, 31.0]),
    (dict(highpass_hz=4.0, lowpass_hz=20.0), None, [2.5, 4.0, 9.0, 20.0, 40.0]),
])
def test_zero_phase_filter_gain_is_butterworth_squared_with_no_lag(edges, order, freqs_hz):
    """A sinusoid comes out scaled by |H(f)|^2 of the Butterworth (1/2 at a
    cut-off) and in phase, away from the ends of the record."""
    dt = 1 / 250
    t = dt * np.arange(3001)
    y = _sines(t, freqs_hz)
    kwargs = {} if order is None else dict(order=order)
    out = modal.zero_phase_filter(y, dt, **edges, **kwargs)
    gain = _butterworth_gain(freqs_hz, 1 / dt, order or 4, **edges)
    assert out.shape == y.shape
    np.testing.assert_allclose(out[750:-750], (gain * y)[750:-750], atol=1e-6)


@pytest.mark.parametrize("factor, stages", [(2, 1), (17, 1), (30, 2), (34, 2), (169, 2)])
def test_decimate_keeps_a_low_sinusoid_and_rejects_its_alias(factor, stages):
    """fs = 1000 Hz, decimated by 2 (one stage), 17 (a prime above 13: one
    stage), 30 (10 then 3), 34 (2 then 17) and 169 (13 then 13: scipy
    advises at most 13 a stage). A sinusoid at 0.07 of the new
    rate keeps its amplitude within the Chebyshev ripple run twice per stage
    (0.05 dB each way: gain in [0.9886^stages, 1]) and its phase; one at 0.75 of the new rate, which would alias
    to 0.25, is gone."""
    dt, n = 1e-3, 201 * factor - 7
    fs_new = 1 / (factor * dt)
    f_low, f_alias = 0.07 * fs_new, 0.75 * fs_new
    t = dt * np.arange(n)
    low = np.column_stack([np.sin(2 * np.pi * f_low * t + 0.4), 2 * np.cos(2 * np.pi * f_low * t)])
    y = low + 0.8 * np.sin(2 * np.pi * f_alias * t)[:, None]
    out, dt_out = modal.decimate(y, dt, factor)
    assert dt_out == pytest.approx(factor * dt, rel=1e-15)
    assert out.shape == (-(-n // factor), 2) and out.flags.c_contiguous
    # least-squares amplitude and phase at f_low over the middle of the record
    t_out = dt_out * np.arange(out.shape[0])
    middle = slice(50, -50)  # away from the filter's end transients
    basis = np.column_stack([np.sin(2 * np.pi * f_low * t_out), np.cos(2 * np.pi * f_low * t_out)])[middle]
    coef = np.linalg.lstsq(basis, out[middle], rcond=None)[0]
    expected = low[::factor][middle]
    gain = np.hypot(*coef) / np.array([1.0, 2.0])
    assert np.all((gain > 0.9886**stages) & (gain < 1 + 1e-6))
    # in phase: the fit is the input scaled by the gain; and nothing else is left
    np.testing.assert_allclose(basis @ coef, expected * gain, atol=1e-5)
    np.testing.assert_allclose(out[middle], expected * gain, atol=1e-4)


def test_decimate_output_length_and_step_for_any_factor():
    """Any factor, prime or composite, small or above scipy's advised 13: one
    sample in ``factor`` kept (the first included), the step multiplied, and
    factor 1 returns the record unchanged."""
    y = np.random.default_rng(5).standard_normal((5003, 2))
    for factor in (1, 2, 12, 14, 17, 26, 30, 34, 169):
        out, dt = modal.decimate(y, 0.002, factor)
        assert out.shape == (-(-5003 // factor), 2) and dt == pytest.approx(0.002 * factor, rel=1e-15)
    np.testing.assert_array_equal(modal.decimate(y, 0.002, 1)[0], y)


def test_decay_start_weighs_every_channel_alike():
    """An impact at sample 412 of 1900 (fs = 400 Hz) after noise: one 6.5 Hz
    mode seen with gains 3e4 (a sine, as a velocity), -2e-3 (a reversed
    sensor) and 0.6, and a dead channel. Normalised per channel the energy
    (sin^2 + 2 cos^2) e^(-2 zeta omega t) peaks at the impact; the high-gain
    channel alone would put it a quarter period (15 samples) later, and a
    signed sum would cancel the two cosines."""
    dt, start, f, zeta = 1 / 400, 412, 6.5, 0.02
    t = dt * np.arange(1900 - start)
    envelope = np.exp(-zeta * 2 * np.pi * f * t)
    phase = 2 * np.pi * f * np.sqrt(1 - zeta**2) * t
    gains = np.array([3e4, -2e-3, 0.6, 0.0])
    decay = gains * np.column_stack([envelope * np.sin(phase), *(2 * [envelope * np.cos(phase)]), 0 * t])
    rng = np.random.default_rng(12)
    y = np.vstack([np.zeros((start, 4)), decay]) + 1e-3 * np.abs(gains) * rng.standard_normal((1900, 4))
    assert np.all(y[:, 3] == 0)
    assert abs(modal.decay_start(y) - start) <= 1
    # without the dead channel, and with all gains scaled alike: the same sample
    assert modal.decay_start(y[:, :3]) == modal.decay_start(1e-6 * y) == modal.decay_start(y)


@pytest.mark.parametrize(("call", "message"), [
    (lambda: modal.detrend(np.ones(50)), "^y must be a 2-dimensional array"),
    (lambda: modal.detrend(np.ones((50, 2)), "quadratic"), "^kind must be 'linear' or 'constant', got 'quadratic'$"),
    (lambda: modal.zero_phase_filter(np.ones(50), 0.01, lowpass_hz=5), "^y must be a 2-dimensional array"),
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.0, lowpass_hz=5), "^dt must be a finite number > 0"),
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.01, lowpass_hz=5, order=0), "^order must be an integer >= 1"),
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.01, highpass_hz=-1.0),
     "^highpass_hz must be a finite number > 0"),
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.01, highpass_hz=1, lowpass_hz=0),
     "^lowpass_hz must be a finite number > 0"),
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.01), "^highpass_hz or lowpass_hz must be given$"),
    # the Nyquist frequency itself and equal edges are refused: the bounds are strict
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.01, highpass_hz=50),
     r"^highpass_hz = 50 must be below the Nyquist frequency 50\.0 Hz$"),
    (lambda: modal.zero_phase_filter(np.ones((50, 2)), 0.01, highpass_hz=10, lowpass_hz=10.0),
     r"^highpass_hz = 10 must be below lowpass_hz = 10\.0$"),
    # sosfiltfilt pads 3 (2 n_sections + 1) = 15 samples at order 4 (2 sections) and needs more than that
    (lambda: modal.zero_phase_filter(np.ones((15, 2)), 0.01, lowpass_hz=5),
     "^y has 15 samples, too few to filter with order 4$"),
    (lambda: modal.decimate(np.ones(500), 0.01, 2), "^y must be a 2-dimensional array"),
    (lambda: modal.decimate(np.ones((500, 2)), -0.01, 2), "^dt must be a finite number > 0"),
    (lambda: modal.decimate(np.ones((500, 2)), 0.01, 0), "^factor must be an integer >= 1"),
    (lambda: modal.decimate(np.ones((500, 2)), 0.01, 2.5), "^factor must be an integer >= 1"),
    # scipy's order-8 filter pads 27 samples: more than 27 per unit of the factor are needed
    (lambda: modal.decimate(np.ones((135, 2)), 0.01, 5), "^y has 135 samples, too few to decimate by 5$"),
    (lambda: modal.decimate(np.ones((810, 2)), 0.01, 30),
     r"^y has 810 samples, too few to decimate by 30 \(stage 2 of \[10, 3\]: 81 samples left, more than 81 needed\)$"),
    (lambda: modal.decay_start(np.ones(50)), "^y must be a 2-dimensional array"),
    (lambda: modal.decay_start(np.zeros((50, 3))), "^y is zero everywhere: no impact to find$"),
])
def test_preprocessing_refusals_name_the_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_preprocessing_accepts_the_shortest_records():
    """One sample more than the refused lengths above is filtered and decimated."""
    y = np.sin(np.arange(16))[:, None] * np.array([1.0, -2.0])
    assert modal.zero_phase_filter(y, 0.01, lowpass_hz=5).shape == (16, 2)
    y = np.sin(np.arange(136))[:, None] * np.array([1.0, -2.0])
    assert modal.decimate(y, 0.01, 5)[0].shape == (28, 2)


def test_lowpass_keeps_a_bin_exactly_at_the_cutoff_on_an_odd_record():
    """Bins above the cutoff go, the bin at the cutoff stays; an odd-length
    record comes back with its own length."""
    dt, n = 0.01, 101  # bins at k / 1.01 Hz
    t = dt * np.arange(n)
    f_cut = 5 / (n * dt)
    keep = np.sin(2 * np.pi * f_cut * t)
    drop = np.cos(2 * np.pi * 20 / (n * dt) * t)
    out = modal.lowpass_fft(np.column_stack([keep + drop, drop]), dt, f_cut)
    assert out.shape == (n, 2)
    np.testing.assert_allclose(out[:, 0], keep, atol=1e-12)
    np.testing.assert_allclose(out[:, 1], 0.0, atol=1e-12)


def test_integration_removes_the_offset_ramp():
    dt, n = 0.01, 2000
    t = dt * np.arange(n)
    acc = -2 * np.pi * np.sin(2 * np.pi * t)[:, None] + 0.3  # velocity cos(2 pi t), offset 0.3
    vel = modal.integrate_acceleration(acc, dt)
    # without the offset removal the error would be a ramp of +-3; what remains is
    # the least-squares slope of the sampled cosine itself (about 1.5e-3 here)
    np.testing.assert_allclose(vel[:, 0], np.cos(2 * np.pi * t), atol=2e-3)
    np.testing.assert_allclose(modal.signals.acceleration_offset(acc, dt), [0.3], rtol=1e-3)


def test_preprocessing():
    dt = 0.001
    t = dt * np.arange(20000)
    slow, fast = np.sin(2 * np.pi * 3 * t), 0.5 * np.sin(2 * np.pi * 180 * t)
    y = np.column_stack([slow + fast + 2 + 0.1 * t])
    # Zero phase: the 3 Hz wave passes a 20 Hz low-pass in place (edges aside).
    low = modal.zero_phase_filter(modal.detrend(y), dt, lowpass_hz=20)
    np.testing.assert_allclose(low[2000:-2000], modal.detrend(slow[:, None])[2000:-2000], atol=2e-3)
    # Decimation by 30 (stages 10 x 3): 180 Hz would alias to 13.3 Hz; it is removed.
    dec, dt_dec = modal.decimate(y - y.mean(), dt, 30)
    assert dt_dec == pytest.approx(0.03) and dec.shape == (667, 1)
    freqs, amp = modal.amplitude_spectrum(modal.detrend(dec), dt_dec)
    assert amp[np.argmin(np.abs(freqs - 40 / 3)), 0] < 1e-3
    with pytest.raises(ValueError, match="lowpass_hz = 600 must be below the Nyquist"):
        modal.zero_phase_filter(y, dt, lowpass_hz=600)
    with pytest.raises(ValueError, match="highpass_hz = 30 must be below lowpass_hz"):
        modal.zero_phase_filter(y, dt, highpass_hz=30, lowpass_hz=20)
    with pytest.raises(ValueError, match="kind"):
        modal.detrend(y, "quadratic")


def test_integrated_velocity_accuracy(demo):
    # 10 samples per period of mode 6: the cubic-spline antiderivative keeps the
    # velocity to better than 0.5 % RMS (the trapezoidal rule would lose 3 % of mode 6).
    rec = demo["make"](3600)
    vel = modal.integrate_acceleration(rec.acceleration, demo["dt"])
    exact = rec.velocity - rec.velocity.mean(axis=0)
    err = np.sqrt(np.mean((vel - exact) ** 2)) / np.sqrt(np.mean(exact**2))
    assert err < 5e-3
