"""modal: the engine of the modal-identification workflow.

TCM (Eqs. 21-31), ERA (Eqs. 34-45) and CERA (Eqs. 46-52) of the thesis
"Experimental Verification and Development of Structural Identification
Techniques on a Grid", and what they need around them. The public names are
re-exported here from the subpackages, one per concern:

- :mod:`modal.identification`: Hankel matrix, ERA, TCM, CERA, indicators,
  :class:`ModalResult`, the stabilisation diagram;
- :mod:`modal.signals`: preprocessing and NExT correlation functions;
- :mod:`modal.records`: reading and writing measured records;
- :mod:`modal.measured`: the measured-record pipeline (``modal identify``);
- :mod:`modal.setups`: roving tests: channel tables, geometry, setups merged,
  shapes drawn on the structure;
- :mod:`modal.structures`: beam, grid FE model, virtual shaking test;
- :mod:`modal.thesis`: the reproduction layer of the workflow (not the engine).

``import modal`` loads numpy, scipy and pandas, never matplotlib: figures
import it when they are drawn.
"""

from .identification import (FLAGS, ModalResult, ModalWarning, Stabilisation, StabilityCriteria, align_shapes, cera,
                             decompose, era, hankel, mac, modal_amplitude_coherence, modal_phase_collinearity,
                             stabilisation, stabilisation_figure, tcm)
from .measured import (OutputError, available_memory, identify_record, memory_needed,
                       write_identification)
from .records import MeasuredRecord, load_record, read_record, save_record_npz, write_uff58
from .setups import (Geometry, MergedModes, Setup, check_setups, direction_from_angles, draw_mode, draw_modes,
                     identify_setup,
                     merge_setups, mode_shape_animation, mode_shape_figure, modes_figure, node_motion, node_shapes, plate_roving_test,
                     read_channel_table, read_geometry, read_pyoma_setup, read_setup, save_geometry, save_setup,
                     write_setups)
from .signals import (acceleration_offset, amplitude_spectrum, correlations, decay_start, decimate, detrend, integrate_acceleration,
                      lowpass_fft, split_record, zero_phase_filter)
from .structures import (Grid, Record, ShakeTest, SimplySupportedBeam, SimplySupportedPlate, add_noise,
                         ambient_response, beam_impulse_response, damping_ratios, impulse_response, pick_peaks, select_sharpest, shake_test, sharpness,
                         with_noise)

__all__ = [
    "FLAGS", "Geometry", "Grid", "MeasuredRecord", "MergedModes", "ModalResult", "ModalWarning", "OutputError",
    "Record", "Setup", "ShakeTest", "SimplySupportedBeam", "SimplySupportedPlate", "Stabilisation", "StabilityCriteria",
    "acceleration_offset", "add_noise", "align_shapes", "ambient_response", "amplitude_spectrum", "available_memory",
    "beam_impulse_response", "cera", "check_setups", "correlations", "damping_ratios", "decay_start", "decimate",
    "decompose", "detrend", "direction_from_angles", "draw_mode", "draw_modes", "era", "hankel", "identify_record",
    "identify_setup", "impulse_response", "integrate_acceleration", "load_record", "lowpass_fft", "mac",
    "memory_needed", "merge_setups", "modal_amplitude_coherence", "modal_phase_collinearity", "mode_shape_animation",
    "mode_shape_figure", "modes_figure", "node_motion", "node_shapes", "pick_peaks", "plate_roving_test", "read_channel_table", "read_geometry",
    "read_pyoma_setup", "read_record", "read_setup", "save_geometry", "save_record_npz", "save_setup", "select_sharpest", "shake_test", "sharpness",
    "split_record", "stabilisation", "stabilisation_figure", "tcm", "with_noise", "write_identification",
    "write_setups", "write_uff58", "zero_phase_filter",
]
