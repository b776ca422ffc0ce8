"""Measured records: the pipeline behind ``modal identify`` (preprocessing,
NExT correlations or the free decay, the stabilisation diagram) and a record's
results written to a folder."""

from ._options import EXCITATIONS, MAX_ORDER, QUANTITY_NAMES, IdentifyOptions, identify_options
from ._output import OutputError, check_output, overlapping_input, staged_folder
from ._pipeline import (NO_SPECTRAL_PEAK, NO_VIBRATION_RTOL, available_memory, identify_record, kept_warnings,
                        mac_figure, memory_needed, no_vibration, onset_spectrum, provenance, shape_columns,
                        with_spectral_witness, write_identification, write_results, write_settings)
from ._report import identification_report, roving_report

# check_output, overlapping_input, staged_folder, no_vibration, NO_VIBRATION_RTOL, shape_columns, write_results,
# write_settings, identify_options, provenance, kept_warnings, with_spectral_witness, onset_spectrum, mac_figure
# and the reports (identification_report, roving_report) are helpers of the pipeline (the roving test's and the
# campaign's routes use them), importable from here; the names below are also re-exported by modal.
__all__ = ["EXCITATIONS", "IdentifyOptions", "OutputError", "available_memory", "identify_record",
           "memory_needed", "write_identification"]
