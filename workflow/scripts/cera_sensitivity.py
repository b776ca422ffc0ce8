"""CERA against the Hankel width s (not in the thesis, which does not give s)."""
import pandas as pd

import modal.thesis.plots
import modal.thesis.tables
from _helpers import mock_snakemake, redirect_log

if "snakemake" not in globals():
    snakemake = mock_snakemake("cera_sensitivity")
redirect_log(snakemake)

frames = {i: pd.read_csv(f) for i, f in zip(snakemake.params.interpretations, snakemake.input.identified)}
table = modal.thesis.tables.cera_sensitivity(frames, snakemake.params.first_seed)
modal.thesis.tables.write_csv(table, snakemake.output.csv)
panels = {case: f"Table {number}. {title}" for number, (case, title) in sorted(snakemake.params.tables.items())}
modal.thesis.plots.cera_sensitivity_figure(table, snakemake.params.title, panels,
                                           snakemake.params.configured).savefig(snakemake.output.png, dpi=120)
