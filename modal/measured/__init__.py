"""Measured records: the pipeline behind ``modal identify`` (preprocessing,
NExT correlations or the free decay, the stabilisation diagram), a record's
results written to a folder, and the diagram drawn."""

from ._figures import stabilisation_figure
from ._pipeline import EXCITATIONS, identify_record, write_identification

__all__ = ["EXCITATIONS", "identify_record", "stabilisation_figure", "write_identification"]
