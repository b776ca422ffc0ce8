"""Figures 1-8: identified mode shapes against the exact ones."""
import sys

import pandas as pd

import modal.thesis.plots

sys.stderr = open(snakemake.log[0], "w")
identified = {i: pd.read_csv(f) for i, f in zip(snakemake.params.interpretations, snakemake.input.identified)}
for path, (number, fig) in zip(snakemake.output, sorted(snakemake.params.figures.items(), key=lambda kv: int(kv[0]))):
    title = f"Figure {int(number)}. {fig['method'].upper()} mode shapes, case {fig['case']}"
    modal.thesis.plots.shape_figure(snakemake.params.beam, identified, fig["case"], fig["method"],
                             snakemake.params.first_seed, title).savefig(path, dpi=120)
