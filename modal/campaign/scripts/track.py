"""Rule track of ``modal campaign``: gather the chunks, number the modes;
warnings and errors go to the job's log."""

import sys
from pathlib import Path

from modal.campaign import track_campaign

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 (given by Snakemake)
track_campaign(snakemake.input.modes, snakemake.input.failed, snakemake.params.n_records,  # noqa: F821
               snakemake.params.tracking, Path(snakemake.output.tracked).parent)  # noqa: F821
