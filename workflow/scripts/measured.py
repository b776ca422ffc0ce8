"""One measured record -> modes.csv, poles.csv and the stabilisation diagram
(the same files as `modal identify`)."""
from argparse import Namespace
from pathlib import Path

from _helpers import start_job

from modal.cli import identify

start_job(snakemake)
spec = snakemake.params.spec
args = Namespace(
    path=Path(snakemake.input.record), fs=spec.get("fs"), channels=spec.get("channels"), refs=spec.get("refs"),
    ambient=spec["excitation"] == "ambient", free_decay=spec["excitation"] == "free_decay",
    fmax=spec.get("fmax"), max_order=spec.get("max_order", 60), rows=spec.get("rows"),
    highpass=spec.get("highpass_hz"), delimiter=None, decimal=".", skip_rows=0,
    out=Path(snakemake.output.modes).parent, quiet=False,
)
code = identify(args)
if code != 0:
    raise SystemExit(f"modal identify failed with exit code {code}: see {snakemake.log[0]}")
