"""Harmonics told from modes by the steadiness of their amplitude.

A structural mode under broadband random load responds as narrow-band
Gaussian noise: the envelope of its band (the amplitude of its analytic
signal) is Rayleigh distributed, with a coefficient of variation
``sqrt((4 - pi) / pi) = 0.52``, and it changes over the mode's correlation
time ``1 / (pi zeta f)``. A harmonic (a machine's rotation, a sinusoidal
force) keeps a steady amplitude: its envelope barely varies. Brincker,
Andersen and Møller (2000, "An indicator for separation of structural and
harmonic modes in output-only modal testing", IMAC XVIII) tell the two
apart by the distribution of the band-filtered response (a sine's is
bimodal, kurtosis 1.5, a random mode's Gaussian, kurtosis 3); the envelope's
variation is the same property, read on one number whose spread is known.
An identification sees a harmonic as a lightly damped mode whose shape is
the forced response's: no other indicator need doubt it (an exploratory run:
a 2.0 Hz sinusoidal force on a bridge, 5 % below a mode, was trusted in 4 of
6 ten-minute records, damping 0.26-0.49 % against a median of 1 %).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import scipy.fft

from .._checks import finite_array, positive_float

#: A mode whose band's envelope varies by less than this (standard deviation
#: over mean) has a steady amplitude: a harmonic. A random mode's is 0.52: of
#: 1000 simulated single modes (1 %, 2 Hz, white load) over 8 of their
#: correlation times, none varied less than 0.24 (1 % less than 0.32), and
#: of the 1465 real modes the selection benchmark found (two seeds) none less
#: than 0.37; the exploratory run's harmonics varied 0.07-0.10, a harmonic
#: whose phase wanders (a line as wide as a 0.3-1.8 % mode's) 0.12-0.19.
HARMONIC_CV = 0.2
#: ... judged only when the record holds at least this many of the mode's
#: correlation times ``1 / (pi zeta f)`` (independent envelope values): a
#: shorter record of a lightly damped mode shows a steady amplitude whatever
#: the mode is.
MIN_ENVELOPE_VALUES = 8.0
#: The band around a mode: ``f +- max(BAND_WIDTHS zeta f, BAND_RTOL f)``, its
#: resonance with room to spare (a harmonic whose frequency wanders has a
#: line as wide as a mode's, and a band that cuts its skirts makes its
#: amplitude vary), without its neighbours 2 % away.
BAND_WIDTHS = 4.0
BAND_RTOL = 0.01
#: Samples of the envelope per bin of the band (the band's analytic signal
#: at baseband, interpolated by zero padding).
ENVELOPE_OVERSAMPLING = 4
ENVELOPE_COLUMNS = ["envelope_cv", "envelope_values"]


def envelope_variation(y, dt, freq_hz, damping, shapes) -> pd.DataFrame:
    """How steady each mode's amplitude is over the record.

    The record is projected on each mode's (real) shape, ``q = y phi``;
    the bins of ``q``'s spectrum (``scipy.fft``) within ``f +- max(``
    :data:`BAND_WIDTHS` ``zeta f,`` :data:`BAND_RTOL` ``f)`` are taken to baseband and transformed back (the
    analytic signal of the band, :data:`ENVELOPE_OVERSAMPLING` samples per
    bin); its magnitude is the envelope.

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
        The ambient record, as identified (detrended).
    dt : float
        Sampling interval (s).
    freq_hz, damping : array_like, shape (n_modes,)
        The modes' frequencies (Hz) and damping ratios (fractions).
    shapes : array_like, shape (n_channels, n_modes)
        Their real shapes at the record's channels.

    Returns
    -------
    pandas.DataFrame
        One row per mode: ``envelope_cv`` (standard deviation of the
        envelope over its mean; NaN when the band holds fewer than three
        bins or nothing) and ``envelope_values`` (``pi zeta f T``: the
        record's length ``T`` in the mode's correlation times).
    """
    y = finite_array("y", y, ndim=(2,))
    dt = positive_float("dt", dt)
    freq_hz = finite_array("freq_hz", np.atleast_1d(freq_hz), ndim=(1,)) if np.size(freq_hz) else np.empty(0)
    damping = np.asarray(damping, dtype=float).reshape(-1)
    shapes = np.real(np.asarray(shapes))
    if damping.shape != freq_hz.shape or shapes.shape != (y.shape[1], freq_hz.size):
        raise ValueError(f"damping must be ({freq_hz.size},) and shapes ({y.shape[1]}, {freq_hz.size}), "
                         f"got {damping.shape} and {shapes.shape}")
    n = y.shape[0]
    spectra = scipy.fft.rfft(y @ shapes, axis=0)
    zeta = np.clip(np.nan_to_num(damping), 0.0, None)
    half = np.maximum(BAND_WIDTHS * zeta * freq_hz, BAND_RTOL * freq_hz)
    df = 1 / (n * dt)
    cv = np.full(freq_hz.size, np.nan)
    for k in range(freq_hz.size):
        low = max(1, int(np.ceil((freq_hz[k] - half[k]) / df)))
        high = min(spectra.shape[0] - 1, int(np.floor((freq_hz[k] + half[k]) / df)))
        if high - low < 2:
            continue
        band = spectra[low:high + 1, k]
        envelope = np.abs(scipy.fft.ifft(band, n=ENVELOPE_OVERSAMPLING * len(band)))
        if envelope.mean() > 0:
            cv[k] = envelope.std() / envelope.mean()
    return pd.DataFrame({"envelope_cv": cv, "envelope_values": np.pi * zeta * freq_hz * n * dt},
                        columns=ENVELOPE_COLUMNS)


def steady(variation: pd.DataFrame) -> np.ndarray:
    """Which modes of :func:`envelope_variation` keep a steady amplitude
    (harmonics): an envelope varying less than :data:`HARMONIC_CV`, on at
    least :data:`MIN_ENVELOPE_VALUES` independent values."""
    cv, values = variation["envelope_cv"].to_numpy(float), variation["envelope_values"].to_numpy(float)
    with np.errstate(invalid="ignore"):
        return (values >= MIN_ENVELOPE_VALUES) & (cv < HARMONIC_CV)
