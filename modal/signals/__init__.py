"""Signals: preprocessing of records (integration, filters, decimation,
splitting into data sets), NExT correlation functions and the spectral
density matrix (Welch)."""

from ._correlation import correlations
from ._spectra import spectral_density, welch_segment
from ._filters import (acceleration_offset, amplitude_spectrum, antialiasing_pole, decay_start, decimate, detrend,
                       integrate_acceleration, lowpass_fft, split_record, zero_phase_filter)

# welch_segment (the default Welch segment) and antialiasing_pole are importable from here; the names below
# are re-exported by modal.
__all__ = [
    "acceleration_offset", "amplitude_spectrum", "correlations", "decay_start", "decimate", "detrend", "integrate_acceleration",
    "lowpass_fft", "spectral_density", "split_record", "zero_phase_filter",
]
