"""Grid chapter: records (one chunk of virtual tests, or the measured one) -> every identification of the grid tables."""
import numpy as np

import modal.thesis.grid_study as gs
from _helpers import start_job

start_job(snakemake)

spec = snakemake.params.spec
records = gs.grid_records(spec, chunk=snakemake.params.chunk)
identified, selection = gs.run_grid_study(records, spec)
identified.to_csv(snakemake.output.identified, index=False)
selection.to_csv(snakemake.output.selection, index=False)
first = records[min(records)]
np.savez(snakemake.output.record, acceleration=first.acceleration, dt=first.dt, true_hz=first.true_hz,
         labels=first.labels)
