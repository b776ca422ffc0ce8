"""Grid chapter: records (virtual or measured) -> every identification of the grid tables."""
import numpy as np

import modal.thesis.grid_study as gs
from _helpers import mock_snakemake, redirect_log

if "snakemake" not in globals():
    snakemake = mock_snakemake("grid_identify")
redirect_log(snakemake)

spec = snakemake.params.spec
records = gs.grid_records(spec)
identified, selection = gs.run_grid_study(records, spec)
identified.to_csv(snakemake.output.identified, index=False)
selection.to_csv(snakemake.output.selection, index=False)
first = records[min(records)]
np.savez(snakemake.output.record, acceleration=first.acceleration, dt=first.dt, true_hz=first.true_hz,
         labels=first.labels)
