"""Rule identify_chunk of ``modal campaign``: one chunk of records, BLAS
held to the job's threads (as Snakemake sets them for shell jobs); warnings
and errors go to the job's log."""

import sys

import pandas as pd
from threadpoolctl import threadpool_limits

from modal.campaign import identify_chunk

sys.stderr = open(snakemake.log[0], "w")  # noqa: F821 (given by Snakemake)
records = pd.DataFrame(snakemake.params.records)  # noqa: F821
with threadpool_limits(limits=snakemake.threads):  # noqa: F821
    identify_chunk(records, snakemake.params.options, snakemake.output.modes, snakemake.output.failed,  # noqa: F821
                   layout=snakemake.params.layout)  # noqa: F821
