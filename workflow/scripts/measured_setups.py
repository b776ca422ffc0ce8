"""A roving test's setups -> merged modes.csv, shapes.csv and the modes drawn
(the same files as `modal identify SETUP ... --geometry`: modal.write_setups);
the entry's keys other than `setups`, `geometry` and `min_setups` are the
options of modal.IdentifyOptions."""
from pathlib import Path

from _helpers import start_job

import modal

start_job(snakemake)
spec = snakemake.params.spec
options = modal.IdentifyOptions.from_mapping(spec, where="measured", other=["setups", "geometry", "min_setups"])
geometry = modal.read_geometry(spec["geometry"])
setups = [modal.read_setup(path, options.fs, geometry) for path in spec["setups"]]
modal.write_setups(
    setups, Path(snakemake.output.modes).parent, options, geometry=geometry,
    min_setups=spec.get("min_setups"), animate=False, log=print,
)
