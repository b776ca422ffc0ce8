"""modal: the engine of the modal-identification workflow.

TCM (Eqs. 21-31), ERA (Eqs. 34-45) and CERA (Eqs. 46-52) of the thesis
"Experimental Verification and Development of Structural Identification
Techniques on a Grid", with beam simulation, preprocessing and indicators,
the finite-element grid and its virtual shaking test (Ch. 7), record I/O,
and operational modal analysis of measured records (NExT correlations, a
stabilisation diagram with automatic mode selection, ``modal identify``).
"""

from .cera import cera
from .correlation import correlations
from .era import era
from .experiment import ShakeTest, pick_peaks, select_sharpest, shake_test, sharpness
from .grid import Grid
from .hankel import hankel
from .io import MeasuredRecord, load_record, read_record, save_record_npz, write_uff58
from .indicators import align_shapes, mac, modal_amplitude_coherence, modal_phase_collinearity
from .result import ModalResult, ModalWarning
from .signals import (
    amplitude_spectrum,
    decay_start,
    decimate,
    detrend,
    integrate_acceleration,
    lowpass_fft,
    split_record,
    zero_phase_filter,
)
from .simulate import Record, add_noise, beam_impulse_response, impulse_response, with_noise
from .stabilisation import Stabilisation, StabilityCriteria, identify_record, stabilisation, stabilisation_figure
from .structures import SimplySupportedBeam
from .tcm import tcm

__all__ = [
    "Grid",
    "MeasuredRecord",
    "ModalResult",
    "ModalWarning",
    "Record",
    "ShakeTest",
    "SimplySupportedBeam",
    "Stabilisation",
    "StabilityCriteria",
    "add_noise",
    "align_shapes",
    "amplitude_spectrum",
    "beam_impulse_response",
    "cera",
    "correlations",
    "decay_start",
    "decimate",
    "detrend",
    "era",
    "hankel",
    "identify_record",
    "impulse_response",
    "integrate_acceleration",
    "load_record",
    "lowpass_fft",
    "mac",
    "modal_amplitude_coherence",
    "modal_phase_collinearity",
    "pick_peaks",
    "read_record",
    "save_record_npz",
    "select_sharpest",
    "shake_test",
    "sharpness",
    "split_record",
    "stabilisation",
    "stabilisation_figure",
    "tcm",
    "with_noise",
    "write_uff58",
    "zero_phase_filter",
]
