"""Signal preprocessing: integration, the thesis's FFT low-pass filter,
splitting a record into data sets."""

from __future__ import annotations

import numpy as np
import scipy.fft
from scipy.interpolate import CubicSpline

from ._checks import finite_array, positive_float, positive_int


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
