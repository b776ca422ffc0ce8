"""Monitoring campaigns: many records of one structure over time, each
identified as ``modal identify`` would, its modes tracked with a stable
numbering and their uncertainty, as a Snakemake workflow (``modal campaign``)
that resumes, grows with the index and runs on a cluster."""

from pathlib import Path

from ._config import chunks, read_campaign
from ._jobs import gather, identify_chunk, identify_one
from ._report import campaign_report, tracking_figure
from ._run import report_campaign, track_campaign
from ._simulated import shear_frame_modes, simulate_campaign
from ._tracking import read_reference_modes, reference_modes, track_modes

#: The workflow ``modal campaign`` runs.
SNAKEFILE = Path(__file__).with_name("Snakefile")

__all__ = ["SNAKEFILE", "campaign_report", "chunks", "gather", "identify_chunk", "identify_one", "read_campaign",
           "read_reference_modes", "reference_modes", "report_campaign", "shear_frame_modes", "simulate_campaign",
           "track_campaign", "track_modes",
           "tracking_figure"]
