"""Grid chapter: records (virtual or measured) -> every identification of Tables 10-15."""
import sys

import numpy as np

import modal.thesis.grid_study as gs

sys.stderr = open(snakemake.log[0], "w")
spec = snakemake.params.spec
records = gs.grid_records(spec)
identified, selection = gs.run_grid_study(records, spec)
identified.to_csv(snakemake.output.identified, index=False)
selection.to_csv(snakemake.output.selection, index=False)
first = records[min(records)]
np.savez(snakemake.output.record, acceleration=first.acceleration, dt=first.dt, true_hz=first.true_hz,
         labels=first.labels)
