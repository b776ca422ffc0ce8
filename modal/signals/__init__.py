"""Signals: preprocessing of records (integration, filters, decimation,
splitting into data sets) and NExT correlation functions."""

from ._correlation import correlations
from ._filters import (acceleration_offset, amplitude_spectrum, decay_start, decimate, detrend, integrate_acceleration, lowpass_fft,
                       split_record, zero_phase_filter)

__all__ = [
    "acceleration_offset", "amplitude_spectrum", "correlations", "decay_start", "decimate", "detrend", "integrate_acceleration",
    "lowpass_fft", "split_record", "zero_phase_filter",
]
