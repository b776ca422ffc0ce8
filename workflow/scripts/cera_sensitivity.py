"""CERA against the Hankel width s (not in the thesis, which does not give s)."""
import modal.thesis.intermediates
import modal.thesis.plots
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

frames = modal.thesis.intermediates.read_interpretations(
    snakemake.input.identified, snakemake.params.study["interpretations"], snakemake.params.study, snakemake.params.seeds)
table = modal.thesis.tables.cera_sensitivity(frames, snakemake.params.seeds["first"])
modal.thesis.tables.write_csv(table, snakemake.output.csv, "beam")
panels = {case: f"Table {number}. {title}" for number, (case, title) in sorted(snakemake.params.tables.items())}
modal.thesis.plots.cera_sensitivity_figure(table, snakemake.params.title, panels,
                                           snakemake.params.configured).savefig(snakemake.output.png, dpi=120)
