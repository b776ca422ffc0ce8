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
- :mod:`modal.campaign`: monitoring campaigns (a Snakemake workflow);
- :mod:`modal.thesis`: the reproduction layer of the workflow (not the engine).

The subpackages are loaded lazily (PEP 562, as SciPy does): ``import modal``
imports none of them, and ``modal.era`` imports :mod:`modal.identification`
on first use. ``import modal`` therefore loads neither matplotlib nor
Snakemake, and a script that uses ``modal.read_record`` runs only the
subpackages that name needs (the workflow's code inputs rely on it:
:mod:`modal.thesis.dependencies` reads :data:`_LAZY_NAMES` below).
"""

import importlib
from typing import TYPE_CHECKING

#: The public names, by the subpackage that defines them: ``modal.<name>`` is
#: ``modal.<subpackage>.<name>``. Keep it a literal: the workflow reads it with
#: ``ast`` (modal.thesis.dependencies) to know which subpackage a script's
#: ``modal.<name>`` runs, without importing anything.
_LAZY_NAMES = {
    "identification": (
        "FLAGS", "ModalResult", "ModalWarning", "SingularValueSpectrum", "Stabilisation", "StabilityCriteria",
        "align_shapes", "auto_mac", "cera", "decompose", "efdd", "era", "fdd", "hankel", "mac",
        "modal_amplitude_coherence", "modal_phase_collinearity", "spectral_support", "stabilisation",
        "stabilisation_figure", "tcm",
    ),
    "measured": (
        "IdentifyOptions", "OutputError", "available_memory", "identify_record", "memory_needed", "write_identification",
    ),
    "records": ("MeasuredRecord", "clipped_samples", "clipping_warnings", "despiked", "load_record", "read_record",
                "save_record_npz", "spike_samples", "spike_warnings", "write_uff58"),
    "setups": (
        "Geometry", "MergedModes", "Setup", "check_setups", "direction_from_angles", "draw_mode", "draw_modes",
        "identify_setup", "merge_setups", "mode_shape_animation", "mode_shape_figure", "modes_figure",
        "node_motion", "node_shapes", "plate_roving_test", "read_channel_table", "read_geometry",
        "read_pyoma_setup", "read_setup", "save_geometry", "save_setup", "write_setups",
    ),
    "signals": (
        "acceleration_offset", "amplitude_spectrum", "correlations", "decay_start", "decimate", "detrend",
        "integrate_acceleration", "lowpass_fft", "spectral_density", "split_record", "zero_phase_filter",
    ),
    "structures": (
        "Grid", "Record", "ShakeTest", "SimplySupportedBeam", "SimplySupportedPlate", "add_noise",
        "ambient_response", "beam_impulse_response", "damping_ratios", "impulse_response", "pick_peaks",
        "select_sharpest", "shake_test", "sharpness", "with_noise",
    ),
}
#: The subpackage of each public name (the inverse of :data:`_LAZY_NAMES`).
_SUBPACKAGE_OF = {name: subpackage for subpackage, names in _LAZY_NAMES.items() for name in names}
#: Submodules reachable as attributes (``modal.setups``) without importing them first.
_SUBMODULES = ("campaign", "cli", "identification", "measured", "records", "setups", "signals", "structures",
               "thesis")

__all__ = sorted(_SUBPACKAGE_OF)


def __getattr__(name):
    """``modal.<name>``, imported from its subpackage on first use (PEP 562).

    Nothing is cached here: once the subpackage is imported the lookup is a
    dictionary access, and ``modal.era`` stays whatever
    ``modal.identification.era`` is.
    """
    if name in _SUBPACKAGE_OF:
        return getattr(importlib.import_module(f"{__name__}.{_SUBPACKAGE_OF[name]}"), name)
    if name in _SUBMODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    """The public names and the subpackages, though none may be imported yet."""
    return sorted({*__all__, *_SUBMODULES})


if TYPE_CHECKING:  # what static type checkers and IDEs see; never run (tested against _LAZY_NAMES)
    from .identification import (FLAGS, ModalResult, ModalWarning, SingularValueSpectrum, Stabilisation,
                                 StabilityCriteria, align_shapes, auto_mac, cera, decompose, efdd, era, fdd, hankel,
                                 mac,
                                 modal_amplitude_coherence, modal_phase_collinearity, spectral_support,
                                 stabilisation, stabilisation_figure, tcm)
    from .measured import (IdentifyOptions, OutputError, available_memory, identify_record, memory_needed,
                           write_identification)
    from .records import (MeasuredRecord, clipped_samples, clipping_warnings, despiked, load_record, read_record,
                          save_record_npz, spike_samples, spike_warnings, write_uff58)
    from .setups import (Geometry, MergedModes, Setup, check_setups, direction_from_angles, draw_mode, draw_modes,
                         identify_setup, merge_setups, mode_shape_animation, mode_shape_figure, modes_figure,
                         node_motion, node_shapes, plate_roving_test, read_channel_table, read_geometry,
                         read_pyoma_setup, read_setup, save_geometry, save_setup, write_setups)
    from .signals import (acceleration_offset, amplitude_spectrum, correlations, decay_start, decimate, detrend,
                          integrate_acceleration, lowpass_fft, spectral_density, split_record, zero_phase_filter)
    from .structures import (Grid, Record, ShakeTest, SimplySupportedBeam, SimplySupportedPlate, add_noise,
                             ambient_response, beam_impulse_response, damping_ratios, impulse_response, pick_peaks,
                             select_sharpest, shake_test, sharpness, with_noise)
