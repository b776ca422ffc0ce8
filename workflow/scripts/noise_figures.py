"""Figures 9-11: identified frequency against signal-to-noise ratio."""
import sys

import pandas as pd

import modal.thesis.plots

sys.stderr = open(snakemake.log[0], "w")
identified = {i: pd.read_csv(f) for i, f in zip(snakemake.params.interpretations, snakemake.input.identified)}
for path, (number, mode) in zip(snakemake.output, sorted(snakemake.params.figures.items(), key=lambda kv: int(kv[0]))):
    title = f"Figure {int(number)}. Effect of noise (natural frequency {mode}), x-ERA, o-TCM"
    modal.thesis.plots.noise_figure(identified, mode, title).savefig(path, dpi=120)
