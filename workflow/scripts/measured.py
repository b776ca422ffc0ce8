"""One measured record -> modes.csv, poles.csv and the stabilisation diagram
(the same files as `modal identify`)."""
import sys
from argparse import Namespace
from pathlib import Path

from modal.cli import identify

if "snakemake" not in globals():  # by hand: python workflow/scripts/measured.py PATH OUT_DIR
    raise SystemExit("run through Snakemake, or use `modal identify` directly")

sys.stderr = open(snakemake.log[0], "w")
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
