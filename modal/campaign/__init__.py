"""Monitoring campaigns: many records of one structure over time, each
identified as ``modal identify`` would, its modes tracked with a stable
numbering and their uncertainty, as a Snakemake workflow (``modal campaign``)
that resumes, grows with the index and runs on a cluster: :func:`run` from
Python, ``modal campaign`` from the command line."""

from ._config import chunks, read_campaign
from ._jobs import gather, identify_chunk, identify_one
from ._report import campaign_report, tracking_figure
from ._run import report_campaign, track_campaign
from ._simulated import shear_frame_modes, simulate_campaign
from ._tracking import read_reference_modes, reference_modes, track_modes
from ._workflow import SNAKEFILE, WorkflowStopped, run

__all__ = ["SNAKEFILE", "WorkflowStopped", "campaign_report", "chunks", "gather", "identify_chunk", "identify_one",
           "read_campaign", "read_reference_modes", "reference_modes", "report_campaign", "run", "shear_frame_modes",
           "simulate_campaign", "track_campaign", "track_modes", "tracking_figure"]
