"""CERA against the Hankel width s (not in the thesis, which does not give s)."""
import sys

import pandas as pd

import modal.thesis.plots
import modal.thesis.tables

sys.stderr = open(snakemake.log[0], "w")
frames = {i: pd.read_csv(f) for i, f in zip(snakemake.params.interpretations, snakemake.input.identified)}
table = modal.thesis.tables.cera_sensitivity(frames, snakemake.params.first_seed)
table.to_csv(snakemake.output.csv, index=False)
modal.thesis.plots.cera_sensitivity_figure(table, "CERA: frequency error against Hankel width s (modes 1-3)").savefig(
    snakemake.output.png, dpi=120)
