"""The spectral density matrix of a record (Welch's averaged cross-spectra),
the input of frequency domain decomposition (:func:`modal.fdd`).

Convention: ``G_ij(f) = E[Y_i(f) Y_j(f)^*]``, so ``G(f) = E[Y(f) Y(f)^H]`` is
Hermitian and positive semi-definite, and under white excitation it is, near
a lightly damped mode ``psi``, close to ``d(f) psi psi^H`` (Brincker, Zhang
and Andersen 2001): its first singular vector is the mode shape ``psi``, not
its conjugate. scipy's ``csd(x, y)`` is ``E[X^* Y]``, hence ``G_ij =
csd(y_j, y_i)``.
"""

from __future__ import annotations

import numpy as np

from .._checks import finite_array, positive_float, positive_int

#: Welch segments: the largest power of two up to the record's length divided
#: by this (with half-overlapping Hann windows, about twice as many averages:
#: a singular value then scatters by some +-1.1 dB from one bin to the next),
#: as :func:`modal.measured.lowest_peak_hz` takes them: resolution first, so
#: that two modes 0.2 Hz apart in a 4-minute record are two peaks ...
WELCH_AVERAGES = 8
#: ... but at least this many samples (a shorter record is one segment) and at
#: most this many (a finer resolution than ``fs / 2**15`` is not needed to see
#: a peak, and would only cost memory).
MIN_SEGMENT = 64
MAX_SEGMENT = 2**15


def welch_segment(n_samples: int) -> int:
    """Samples per Welch segment for a record of ``n_samples``: the largest
    power of two up to ``n_samples / WELCH_AVERAGES``, within
    ``MIN_SEGMENT ... MAX_SEGMENT`` (the whole record when it is shorter
    than ``MIN_SEGMENT``)."""
    n_samples = positive_int("n_samples", n_samples, minimum=2)
    if n_samples <= MIN_SEGMENT:
        return n_samples
    return int(min(MAX_SEGMENT, max(MIN_SEGMENT, 2 ** int(np.log2(n_samples / WELCH_AVERAGES)))))


def spectral_density(y, dt, nperseg=None) -> tuple[np.ndarray, np.ndarray]:
    """The spectral density matrix of a record by Welch's method.

    Each column of ``G[:, :, j]`` is ``scipy.signal.csd(y[:, j], y, ...)``
    (Hann windows of ``nperseg`` samples overlapping by half, the mean of each
    segment removed, one-sided density), so ``G[k, i, j] = E[Y_i Y_j^*]`` at
    ``freq_hz[k]``: Hermitian, ``G = E[Y Y^H]``. The segments' spectra are
    computed once for all channels and multiplied pairwise (``csd`` per
    reference channel recomputed every channel's spectra each time: four
    times the work for four channels, a quarter of a campaign record's
    identification); the memory is that of the record's segments, as with
    ``csd``.

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
        The record (one channel: shape ``(n_samples,)``).
    dt : float
        Sampling interval (s).
    nperseg : int, optional
        Samples per segment; default :func:`welch_segment`.

    Returns
    -------
    freq_hz : ndarray, shape (n_freq,)
    G : ndarray, shape (n_freq, n_channels, n_channels), complex
        In the record's units squared per Hz.
    """
    from scipy.signal import get_window

    y = finite_array("y", y, ndim=(1, 2))
    if y.ndim == 1:
        y = y[:, None]
    dt = positive_float("dt", dt)
    n_samples, n_channels = y.shape
    if n_samples < 2:
        raise ValueError(f"y needs at least 2 samples, got {n_samples}")
    nperseg = welch_segment(n_samples) if nperseg is None else positive_int("nperseg", nperseg, minimum=2)
    if nperseg > n_samples:
        raise ValueError(f"nperseg = {nperseg} is longer than the record ({n_samples} samples)")
    # scipy's csd: segments every nperseg - nperseg // 2 samples, each detrended
    # (constant) and windowed (periodic Hann), density scaling, one-sided
    starts = np.arange(0, n_samples - nperseg + 1, nperseg - nperseg // 2)
    window = get_window("hann", nperseg)
    # channel by channel, so each segment's samples are contiguous (a segment cut from the (samples, channels)
    # record strides over the channels: its mean and window took 10 times longer)
    channels = np.ascontiguousarray(y.T)
    # (n_channels, n_seg, nperseg)
    segments = np.lib.stride_tricks.sliding_window_view(channels, nperseg, axis=1)[:, starts]
    spectra = np.fft.rfft((segments - segments.mean(axis=2, keepdims=True)) * window, axis=2)
    per_bin = np.ascontiguousarray(spectra.transpose(2, 0, 1))  # (n_freq, n_channels, n_seg)
    # the sum over segments of Y_i Y_j^*: one small matrix product per bin (5 times faster than by einsum)
    G = (per_bin @ per_bin.conj().transpose(0, 2, 1)) * (dt / (window**2).sum() / len(starts))
    G[1:None if nperseg % 2 else -1] *= 2  # the one-sided density: all but 0 Hz (and Nyquist, for even nperseg)
    return np.fft.rfftfreq(nperseg, dt), G
