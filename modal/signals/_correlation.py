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
#: Samples per block of the correlation sums: a longer record is summed block
#: by block, so memory does not grow with its length (time grows linearly) ...
BLOCK_SAMPLES = 2**16
#: ... fewer when one block's cross-spectra (references x channels x bins)
#: would exceed this many bytes, but never fewer than four times the lags: the
#: products then stay in a core's cache, and the inverse FFT has the block's
#: length, not the record's (one BLAS thread, measured: a 10-minute 4-channel
#: record at 25 Hz, 121 lags, 2.9 -> 1.8 ms; 20 minutes of 12 channels at
#: 60 Hz, 301 lags, 259 -> 46 ms; an hour of 8 at 100 Hz, 241 lags, 400 -> 207 ms).
CROSS_SPECTRA_BYTES = 2**18


def correlations(y, n_lags, refs=None, estimator="biased") -> np.ndarray:
    """NExT cross-correlation functions, computed by FFT.

    ``R[r, k, c] = 1 / N_k sum_t y_c(t + k) y_{refs[r]}(t)`` for lags
    ``k = 0 ... n_lags - 1``, averaged over the data sets. The sum over ``t``
    is taken in blocks of at most :data:`BLOCK_SAMPLES` samples, fewer where
    their cross-spectra would exceed :data:`CROSS_SPECTRA_BYTES` (one block
    for a short record): each block's reference samples and the channels'
    samples from the same start to ``n_lags - 1`` beyond its end are
    zero-padded to at least their length plus ``n_lags`` before the FFT, so
    the circular correlation equals the linear one (no wrap-around), and the
    cross-spectra of all blocks are summed before one inverse FFT. Memory is
    that of one block, whatever the record's length.

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
        ``N_k = N`` (biased: always a positive semi-definite sequence; it
        tapers lag ``k`` by ``1 - k / N ~ exp(-k / N)``, which adds
        ``1 / (omega N dt)`` to each mode's damping ratio: negligible only
        when the record is far longer than the mode's decay time ``1 /
        (zeta omega)``, e.g. 23 % of a 0.23 % damped 1.2 Hz mode in 240 s) or
        ``N_k = N - k`` (unbiased, what :func:`modal.identify_record` uses;
        over ``n_lags << N`` its larger variance is negligible).

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
    cross, n_fft = _cross_spectra_sum(y, n_lags, refs)
    # reference by reference: each inverse FFT's output (all n_fft lags, n_lags of them kept) a quarter the size
    corr = np.stack([scipy.fft.irfft(cross[:, r], n=n_fft, axis=0)[:n_lags] for r in range(len(refs))])
    counts = n_samples - np.arange(n_lags) if estimator == "unbiased" else np.full(n_lags, n_samples)
    return np.ascontiguousarray(corr / (n_sets * counts)[None, :, None])


def _cross_spectra_sum(y, n_lags, refs):
    """``sum over blocks and data sets of conj(FFT(y_r)) FFT(y_c)``, shape
    ``(n_bins, n_refs, n_channels)``, on one FFT length for all blocks, and
    that length. A record of one block allocates no array beyond its
    spectra and their products (each a fresh page of memory costs time)."""
    n_sets, n_samples, n_channels = y.shape
    block = max(4 * n_lags, min(BLOCK_SAMPLES, CROSS_SPECTRA_BYTES // (8 * len(refs) * n_channels)))
    n_fft = scipy.fft.next_fast_len(min(block, n_samples) + n_lags, real=True)
    cross = None
    for start in range(0, n_samples, block):
        stop = min(start + block, n_samples)
        ahead = y[:, start:min(stop + n_lags - 1, n_samples)]  # the channels, n_lags - 1 beyond the block
        spectra = scipy.fft.rfft(ahead, n=n_fft, axis=1)  # (m, bins, l)
        ref_spectra = spectra[:, :, refs] if stop == ahead.shape[1] + start else scipy.fft.rfft(
            y[:, start:stop][:, :, refs], n=n_fft, axis=1)
        # per bin, the (references x channels) sum over data sets: one small matrix product (faster than einsum)
        product = np.matmul(ref_spectra.conj().transpose(1, 2, 0), spectra.transpose(1, 0, 2))
        if cross is None:
            cross = product
        else:
            cross += product
    return cross, n_fft
