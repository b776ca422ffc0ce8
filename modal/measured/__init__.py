"""Measured records: the pipeline behind ``modal identify`` (preprocessing,
NExT correlations or the free decay, the stabilisation diagram), a record's
results written to a folder, and the diagram drawn."""

from ._figures import stabilisation_figure
from ._output import OutputError, check_output
from ._pipeline import (EXCITATIONS, NO_VIBRATION_RTOL, available_memory, identify_record, memory_needed,
                        no_vibration, shape_columns, write_identification)

__all__ = ["EXCITATIONS", "NO_VIBRATION_RTOL", "OutputError", "available_memory", "check_output", "identify_record",
           "memory_needed", "no_vibration", "shape_columns", "stabilisation_figure", "write_identification"]
