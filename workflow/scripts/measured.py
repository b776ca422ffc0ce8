"""One measured record -> modes.csv, poles.csv and the stabilisation diagram
(the same files as `modal identify`: modal.write_identification)."""
from pathlib import Path

from _helpers import start_job

import modal

start_job(snakemake)
spec = snakemake.params.spec
record = modal.read_record(snakemake.input.record, spec.get("fs"))
modal.write_identification(
    record, Path(snakemake.output.modes).parent, spec["excitation"], channels=spec.get("channels"),
    refs=spec.get("refs"), max_order=spec.get("max_order", 60), fmax=spec.get("fmax"), rows=spec.get("rows"),
    highpass_hz=spec.get("highpass_hz"), title=Path(snakemake.input.record).name, log=print,
)
