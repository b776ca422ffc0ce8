"""Monitoring campaigns: many records of one structure over time, each
identified as ``modal identify`` would, its modes tracked with a stable
numbering and their uncertainty, as a Snakemake workflow (``modal campaign``)
that resumes, grows with the index and runs on a cluster: :func:`run` from
Python, ``modal campaign`` from the command line.

Names load lazily (PEP 562, as :mod:`modal` does): a job that identifies
records imports :mod:`._jobs`, not the report's matplotlib, so an edit of the
report reruns no identification (the workflow's code hashes follow
:data:`_LAZY_NAMES`).
"""

import importlib
from typing import TYPE_CHECKING

#: The public names, by the private module that defines them. Keep it a
#: literal: :mod:`modal.thesis.dependencies` reads it with ``ast``.
_LAZY_NAMES = {
    "_config": ("campaign_inputs", "chunks", "read_campaign"),
    "_jobs": ("gather", "identify_chunk", "identify_one"),
    "_report": ("campaign_report", "covariate_figure", "mode_summary", "overview_figure", "tracking_figure"),
    "_run": ("report_campaign", "track_campaign"),
    "_simulated": ("crossing_frame_modes", "shear_frame_modes", "simulate_campaign"),
    "_tracking": ("observed_ranges", "read_reference_modes", "reference_modes", "track_modes"),
    "_workflow": ("SNAKEFILE", "NoRecordIdentified", "WorkflowStopped", "run"),
}
_MODULE_OF = {name: module for module, names in _LAZY_NAMES.items() for name in names}
# A literal, for the API pages (read without importing); a test holds it equal to the map's names.
__all__ = ["SNAKEFILE", "NoRecordIdentified", "WorkflowStopped", "campaign_inputs", "campaign_report", "chunks",
           "covariate_figure", "crossing_frame_modes", "gather", "identify_chunk", "identify_one", "mode_summary",
           "observed_ranges", "overview_figure", "read_campaign", "read_reference_modes", "reference_modes",
           "report_campaign", "run", "shear_frame_modes", "simulate_campaign", "track_campaign", "track_modes",
           "tracking_figure"]


def __getattr__(name):
    """``modal.campaign.<name>``, imported from its module on first use."""
    if name in _MODULE_OF:
        return getattr(importlib.import_module(f"{__name__}.{_MODULE_OF[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return __all__


if TYPE_CHECKING:  # what static type checkers see; never run
    from ._config import campaign_inputs, chunks, read_campaign
    from ._jobs import gather, identify_chunk, identify_one
    from ._report import campaign_report, covariate_figure, mode_summary, overview_figure, tracking_figure
    from ._run import report_campaign, track_campaign
    from ._simulated import crossing_frame_modes, shear_frame_modes, simulate_campaign
    from ._tracking import observed_ranges, read_reference_modes, reference_modes, track_modes
    from ._workflow import SNAKEFILE, NoRecordIdentified, WorkflowStopped, run
