"""Cross-correlation functions of ambient responses (the Natural Excitation
Technique, NExT), the input of ERA for output-only data.

Under broadband stationary excitation, the cross-correlation function
``R_cr(k) = E[y_c(t + k dt) y_r(t)]`` between channel ``c`` and a reference
channel ``r`` is a sum of decaying sinusoids with the structure's
frequencies, damping ratios and mode shapes (James, Carne and Lauffer 1995):
it behaves as a free response, one data set per reference, so it feeds
:func:`modal.era` (Eq. 34) in place of the impulse responses of Ch. 4.
"""

from __future__ import annotations

import numpy as np
import scipy.fft

from .._checks import positive_int, records

ESTIMATORS = ("biased", "unbiased")


def correlations(y, n_lags, refs=None, estimator="biased") -> np.ndarray:
    """NExT cross-correlation functions, computed by FFT.

    ``R[r, k, c] = 1 / N_k sum_t y_c(t + k) y_{refs[r]}(t)`` for lags
    ``k = 0 ... n_lags - 1``, averaged over the data sets. Each channel is
    zero-padded to at least ``n_samples + n_lags`` before the FFT, so the
    circular correlation equals the linear one (no wrap-around).

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels) or (n_sets, n_samples, n_channels)
        Ambient responses; several data sets (e.g. setups of equal length
        and channels, or a long record cut with :func:`modal.split_record`)
        are averaged. Remove the mean first (:func:`modal.detrend`).
    n_lags : int
        Number of lags, ``1 <= n_lags <= n_samples``.
    refs : sequence of int, optional
        Reference channels (0-based); all channels by default.
    estimator : {"biased", "unbiased"}
        ``N_k = N`` (biased: lower variance, always a positive semi-definite
        sequence; it tapers lag ``k`` by ``1 - k / N``, which adds an apparent
        damping ``~ 1 / (omega N dt)`` to each mode, negligible when
        ``n_lags << N``) or ``N_k = N - k`` (unbiased).

    Returns
    -------
    ndarray, shape (n_refs, n_lags, n_channels)
        One data set per reference, in the layout of :func:`modal.era`.
    """
    y = records("y", y)
    n_sets, n_samples, n_channels = y.shape
    n_lags = positive_int("n_lags", n_lags)
    if n_lags > n_samples:
        raise ValueError(f"n_lags = {n_lags} exceeds the {n_samples} samples per data set")
    if estimator not in ESTIMATORS:
        raise ValueError(f"estimator must be one of {ESTIMATORS}, got {estimator!r}")
    if refs is None:
        refs = np.arange(n_channels)
    else:
        refs = np.atleast_1d(np.asarray(refs))
        if refs.ndim != 1 or refs.size == 0 or refs.dtype.kind not in "iu":
            raise ValueError(f"refs must be a non-empty sequence of channel indices, got {refs!r}")
        if np.any(refs < 0) or np.any(refs >= n_channels) or len(set(refs.tolist())) != refs.size:
            raise ValueError(f"refs must be distinct channel indices in 0 ... {n_channels - 1}, got {refs.tolist()}")
    n_fft = scipy.fft.next_fast_len(n_samples + n_lags, real=True)
    spectra = scipy.fft.rfft(y, n=n_fft, axis=1)  # (m, bins, l)
    # Cross-spectra conj(Y_r) Y_c summed over the data sets, then back to lags.
    cross = np.einsum("mfr,mfc->rfc", spectra[:, :, refs].conj(), spectra)
    corr = scipy.fft.irfft(cross, n=n_fft, axis=1)[:, :n_lags, :]
    counts = n_samples - np.arange(n_lags) if estimator == "unbiased" else np.full(n_lags, n_samples)
    return corr / (n_sets * counts)[None, :, None]
