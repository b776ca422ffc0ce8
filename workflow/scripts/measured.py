"""One measured record -> modes.csv, poles.csv, settings.json and the
stabilisation diagram (the same files as `modal identify`:
modal.write_identification); the entry's keys other than `path` are the
options of modal.IdentifyOptions."""
from pathlib import Path

from _helpers import start_job

import modal

start_job(snakemake)
options = modal.IdentifyOptions.from_mapping(snakemake.params.spec, where="measured", other=["path"])
record = modal.read_record(snakemake.input.record, options.fs)
modal.write_identification(
    record, Path(snakemake.output.modes).parent, options, title=Path(snakemake.input.record).name, log=print
)
