"""Rule report of ``modal campaign``: the self-contained HTML report;
warnings and errors go to the job's log."""

import sys
from pathlib import Path

from modal.campaign import report_campaign

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 (given by Snakemake)
report_campaign(Path(snakemake.output[0]).parent, snakemake.params.n_records,  # noqa: F821
                snakemake.params.campaign, snakemake.params.command,  # noqa: F821
                covariates=snakemake.params.covariates, geometry=snakemake.params.geometry)  # noqa: F821
