"""Measured records: the pipeline behind ``modal identify`` (preprocessing,
NExT correlations or the free decay, the stabilisation diagram) and a record's
results written to a folder."""

from ._output import OutputError, check_output
from ._pipeline import (EXCITATIONS, NO_VIBRATION_RTOL, available_memory, identify_record, memory_needed,
                        no_vibration, shape_columns, write_identification, write_results)

# check_output, no_vibration, NO_VIBRATION_RTOL and shape_columns are helpers of the
# pipeline, importable from here; the names below are also re-exported by modal.
__all__ = ["EXCITATIONS", "OutputError", "available_memory", "identify_record", "memory_needed",
           "write_identification"]
