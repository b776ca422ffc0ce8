"""Signal preprocessing: integration, the thesis's FFT low-pass filter,
splitting a record into data sets."""

from __future__ import annotations

import functools

import numpy as np
import scipy.fft

from .._checks import finite_array, positive_float, positive_int


def integrate_acceleration(acc, dt) -> np.ndarray:
    """Velocity from acceleration, as a real experiment must obtain it.

    The samples are interpolated by a not-a-knot cubic spline
    (:class:`scipy.interpolate.CubicSpline`) whose antiderivative is evaluated
    at the sample times. An accelerometer's offset ``c`` (bias, gravity
    component, drift) would integrate into a ramp ``c t`` that dominates the
    velocity (a 1 % offset moved TCM frequencies by up to 54 %), so the offset
    is removed before integrating: it is estimated as the least-squares slope
    of the integrated record and subtracted from the acceleration (which is
    the same as removing the best-fit line from the integral). The mean acceleration itself is not the offset: for a
    decaying impulse response it is ``(v(T) - v(0)) / T``, of the size of the
    response. The constant of integration is then fixed by requiring zero
    mean velocity, since a structure vibrating freely about its equilibrium
    has no net drift. For a sinusoid sampled ``N`` times per period the
    amplitude error is ``O((2 pi / N)^4)`` (about 2e-3 at N = 10), against
    ``(2 pi / N)^2 / 12`` (3 %) for the trapezoidal rule.

    Parameters
    ----------
    acc : array_like, shape (n_samples, n_channels)
    dt : float

    Returns
    -------
    ndarray, shape (n_samples, n_channels)
    """
    acc = finite_array("acc", acc, ndim=(2,))
    dt = positive_float("dt", dt)
    acc = acc - acceleration_offset(acc, dt)
    vel = _antiderivative(acc, dt)
    return vel - vel.mean(axis=0)


def acceleration_offset(acc, dt) -> np.ndarray:
    """The constant offset of each acceleration channel, estimated as the
    least-squares slope of its integral (see :func:`integrate_acceleration`).

    Returns
    -------
    ndarray, shape (n_channels,)
    """
    acc = finite_array("acc", acc, ndim=(2,))
    dt = positive_float("dt", dt)
    t = dt * np.arange(acc.shape[0])
    return np.polynomial.polynomial.polyfit(t, _antiderivative(acc, dt), 1)[1]


def _antiderivative(acc, dt):
    """Cubic-spline antiderivative of ``acc`` at the sample times, from 0."""
    if acc.shape[0] < 4:
        raise ValueError(f"acc needs at least 4 samples to integrate, got {acc.shape[0]}")
    from scipy.interpolate import CubicSpline  # here: importing it costs every job ~0.15 s

    t = dt * np.arange(acc.shape[0])
    return CubicSpline(t, acc, axis=0).antiderivative()(t)


def lowpass_fft(y, dt, cutoff_hz) -> np.ndarray:
    """The thesis's filter (Sec. 7.2): FFT each channel, set every bin above
    ``cutoff_hz`` to zero, inverse FFT.

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
    dt : float
        Sampling interval (s).
    cutoff_hz : float
        Cutoff in Hz, ``0 < cutoff_hz < 1 / (2 dt)`` (Nyquist).
    """
    y = finite_array("y", y, ndim=(2,))
    dt = positive_float("dt", dt)
    cutoff_hz = positive_float("cutoff_hz", cutoff_hz)
    nyquist = 0.5 / dt
    if cutoff_hz >= nyquist:
        raise ValueError(f"cutoff_hz = {cutoff_hz} must be below the Nyquist frequency {nyquist} Hz")
    spectrum = scipy.fft.rfft(y, axis=0)
    freqs = scipy.fft.rfftfreq(y.shape[0], dt)
    spectrum[freqs > cutoff_hz] = 0
    return scipy.fft.irfft(spectrum, n=y.shape[0], axis=0)


def split_record(y, n_sets) -> np.ndarray:
    """Split one record into ``n_sets`` consecutive, equally long data sets
    (Sec. 7.2, Table 13); trailing samples that do not fill a set are dropped.

    Returns
    -------
    ndarray, shape (n_sets, n_samples // n_sets, n_channels)
    """
    y = finite_array("y", y, ndim=(2,))
    n_sets = positive_int("n_sets", n_sets)
    length = y.shape[0] // n_sets
    if length < 2:
        raise ValueError(f"n_sets = {n_sets} leaves fewer than 2 samples per set from {y.shape[0]}")
    return y[: length * n_sets].reshape(n_sets, length, y.shape[1])


def amplitude_spectrum(y, dt):
    """One-sided amplitude spectrum ``|FFT| / n`` per channel.

    Returns
    -------
    freqs_hz : ndarray, shape (n_bins,)
    amplitude : ndarray, shape (n_bins, n_channels)
    """
    y = finite_array("y", y, ndim=(2,))
    dt = positive_float("dt", dt)
    return scipy.fft.rfftfreq(y.shape[0], dt), np.abs(scipy.fft.rfft(y, axis=0)) / y.shape[0]


# Preprocessing of measured records (detrend, zero-phase filtering, anti-aliased
# decimation, the start of a free decay). scipy.signal is imported inside each
# function: it costs about 0.3 s and most jobs never need it.


def detrend(y, kind="linear", overwrite=False) -> np.ndarray:
    """Remove the mean (``kind="constant"``) or the least-squares line
    (``kind="linear"``) from each channel.

    The line is the projection on the orthogonal pair ``1`` and ``t - t_mean``
    (what :func:`scipy.signal.detrend` solves by least squares), subtracted in
    blocks of :data:`DETREND_BLOCK` samples, so no temporary as large as the
    record is made: a long record needs one copy (none with ``overwrite``).

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
    kind : {"linear", "constant"}
    overwrite : bool
        Detrend ``y`` in place when it is a writeable float64 array.
    """
    if kind not in ("linear", "constant"):
        raise ValueError(f"kind must be 'linear' or 'constant', got {kind!r}")
    y = finite_array("y", y, ndim=(2,))
    own = overwrite and isinstance(y, np.ndarray) and y.dtype == np.float64 and y.flags.writeable
    out = y if own else np.array(y, dtype=float)
    n = out.shape[0]
    mean = out.mean(axis=0)
    t = np.arange(n) - (n - 1) / 2
    slope = (t @ out) / (t @ t) if kind == "linear" and n > 1 else np.zeros(out.shape[1])
    for start in range(0, n, DETREND_BLOCK):
        block = slice(start, start + DETREND_BLOCK)
        out[block] -= mean + t[block, None] * slope
    return out


#: Samples per block of :func:`detrend`'s subtraction: its temporaries stay
#: small enough to be reused from one block to the next (blocks of 2**16
#: samples took fresh memory for each record, 0.7 ms of a ten-minute record).
DETREND_BLOCK = 2**12

#: Values (samples x channels) :func:`decimate` filters in one call: 4 M, 32 MB of float64.
DECIMATE_BLOCK = 2**22


def zero_phase_filter(y, dt, highpass_hz=None, lowpass_hz=None, order=4) -> np.ndarray:
    """Butterworth high-, low- or band-pass filter run forwards and backwards
    (:func:`scipy.signal.sosfiltfilt`), so it shifts no phase and no peak.

    The magnitude response is the square of an ``order``-th order
    Butterworth's. Unlike :func:`lowpass_fft` (the thesis's filter), it does
    not ring across the whole record at a step or an impact.

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
    dt : float
        Sampling interval (s).
    highpass_hz, lowpass_hz : float, optional
        Cut-off frequencies in Hz (at least one), below the Nyquist frequency;
        ``highpass_hz < lowpass_hz`` when both are given.
    order : int
        Butterworth order of each pass.
    """
    from scipy.signal import butter, sosfiltfilt

    y = finite_array("y", y, ndim=(2,))
    dt = positive_float("dt", dt)
    order = positive_int("order", order)
    nyquist = 0.5 / dt
    edges = {}
    for name, value in (("highpass_hz", highpass_hz), ("lowpass_hz", lowpass_hz)):
        if value is not None:
            edges[name] = positive_float(name, value)
            if edges[name] >= nyquist:
                raise ValueError(f"{name} = {value} must be below the Nyquist frequency {nyquist} Hz")
    if not edges:
        raise ValueError("highpass_hz or lowpass_hz must be given")
    if len(edges) == 2:
        if edges["highpass_hz"] >= edges["lowpass_hz"]:
            raise ValueError(f"highpass_hz = {highpass_hz} must be below lowpass_hz = {lowpass_hz}")
        sos = butter(order, [edges["highpass_hz"], edges["lowpass_hz"]], btype="bandpass", fs=1 / dt, output="sos")
    elif "highpass_hz" in edges:
        sos = butter(order, edges["highpass_hz"], btype="highpass", fs=1 / dt, output="sos")
    else:
        sos = butter(order, edges["lowpass_hz"], btype="lowpass", fs=1 / dt, output="sos")
    if y.shape[0] <= 3 * (2 * len(sos) + 1):
        raise ValueError(f"y has {y.shape[0]} samples, too few to filter with order {order}")
    return sosfiltfilt(sos, y, axis=0)


def decimate(y, dt, factor) -> tuple[np.ndarray, float]:
    """Keep every ``factor``-th sample after an anti-aliasing low-pass:
    Chebyshev type I of order 8, 0.05 dB ripple, its edge at 0.8 of the new
    Nyquist frequency, run forwards and backwards (zero phase,
    :func:`scipy.signal.sosfiltfilt`). This is :func:`scipy.signal.decimate`'s
    default filter with ``zero_phase=True``, and the same samples; the
    filter is designed once per stage's factor (:func:`_antialiasing`).

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
    dt : float
        Sampling interval (s).
    factor : int
        Decimation factor ``q >= 1``; factors above 13 are done in stages,
        as scipy advises.

    Returns
    -------
    y : ndarray, shape (ceil(n_samples / q), n_channels)
    dt : float
        The new sampling interval ``q dt``.
    """
    from scipy.signal import sosfiltfilt

    y = finite_array("y", y, ndim=(2,))
    dt = positive_float("dt", dt)
    factor = positive_int("factor", factor)
    stages = _stages(factor)
    n_samples, kept = y.shape[0], y.shape[0]
    for done, step in enumerate(stages):
        if kept <= 27 * step:  # the filter, run forwards and backwards, needs 27 q samples
            stage = f" (stage {done + 1} of {stages}: {kept} samples left, more than {27 * step} needed)"
            raise ValueError(f"y has {n_samples} samples, too few to decimate by {factor}"
                             f"{stage if done else ''}")
        kept = -(-kept // step)
    def some_channels(x):
        for step in stages:
            x = sosfiltfilt(_antialiasing(step), x, axis=0)[::step]
        return x

    # channels in blocks of at most DECIMATE_BLOCK values: the filter's temporaries stay bounded on a long
    # record (one channel at a time), and a short one is filtered in one call (one filter design)
    width = max(1, DECIMATE_BLOCK // n_samples)
    blocks = [some_channels(y[:, c:c + width]) for c in range(0, y.shape[1], width)]
    return np.ascontiguousarray(np.hstack(blocks)), dt * factor


def _stages(factor: int) -> list[int]:
    """:func:`decimate`'s factors stage by stage: the largest divisor up to 13
    first, so that each stage's filter stays stable."""
    stages, remaining = [], factor
    while remaining > 1:
        step = next((q for q in range(min(13, remaining), 1, -1) if remaining % q == 0), remaining)
        stages.append(step)
        remaining //= step
    return stages


def antialiasing_pole(factor, dt) -> tuple[float, float]:
    """The least damped pole of :func:`decimate`'s last low-pass for the
    factor ``factor`` (``>= 2``), ``dt`` the sampling interval after it:
    ``(freq_hz, damping)``, some 0.83-0.84 of the new Nyquist frequency damped
    5-7 %. Noise or modes in the filter's transition band (above 0.8 of the
    new Nyquist frequency) ring at it: a stable, well-shaped "mode" of the
    record as decimated that the structure does not have."""
    step = _stages(positive_int("factor", factor))[-1]
    s = _antialiasing_log_poles(step) * step / positive_float("dt", dt)  # continuous-time, before the last step
    k = int(np.argmin(-s.real / np.abs(s)))
    return float(np.abs(s[k]) / (2 * np.pi)), float(-s[k].real / np.abs(s[k]))


@functools.lru_cache(maxsize=None)
def _antialiasing_log_poles(q: int) -> np.ndarray:
    """``ln z`` of the poles ``z`` of :func:`_antialiasing` ``(q)`` (finding
    them, the roots of its sections, cost 0.5 ms per record); read-only."""
    from scipy.signal import sos2zpk

    _, poles, _ = sos2zpk(_antialiasing(q))
    logs = np.log(poles.astype(complex))
    logs.flags.writeable = False
    return logs


@functools.lru_cache(maxsize=None)
def _antialiasing(q: int) -> np.ndarray:
    """:func:`decimate`'s low-pass for the factor ``q`` as second-order
    sections: Chebyshev type I, order 8, 0.05 dB ripple, edge at ``0.8 / q``
    of the Nyquist frequency (designing it cost 1.5 ms per record)."""
    from scipy.signal import cheby1

    return cheby1(8, 0.05, 0.8 / q, output="sos")


def decay_start(y) -> int:
    """Sample where a free decay starts: the peak of the response to an
    impact, so that ERA (Eq. 34, ``start``) sees only the free response.

    The peak is that of ``sum_c (y_c / max|y_c|)^2``, so every channel counts
    whatever its units or gain. A hammer pulse lasts a few samples and its
    response peaks within them; what follows is free.

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)

    Returns
    -------
    int
        Index of the first sample of the free decay.
    """
    y = finite_array("y", y, ndim=(2,))
    peak = np.max(np.abs(y), axis=0)
    if not np.any(peak > 0):
        raise ValueError("y is zero everywhere: no impact to find")
    energy = np.sum((y / np.where(peak > 0, peak, 1)) ** 2, axis=1)
    return int(np.argmax(energy))
