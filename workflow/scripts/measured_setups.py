"""A roving test's setups -> merged modes.csv, shapes.csv and the modes drawn
(the same files as `modal identify SETUP ... --geometry`: modal.write_setups)."""
from pathlib import Path

from _helpers import start_job

import modal

start_job(snakemake)
spec = snakemake.params.spec
geometry = modal.read_geometry(spec["geometry"])
setups = [modal.read_setup(path, spec.get("fs"), geometry) for path in spec["setups"]]
modal.write_setups(
    setups, Path(snakemake.output.modes).parent, spec["excitation"], geometry=geometry,
    min_setups=spec.get("min_setups"), animate=False, log=print, max_order=spec.get("max_order", 60),
    fmax=spec.get("fmax"), rows=spec.get("rows"), highpass_hz=spec.get("highpass_hz"),
)
