"""Noise figures (thesis Figures 9-11): identified frequency against signal-to-noise ratio."""
import modal.thesis.intermediates
import modal.thesis.plots
from _helpers import start_job

start_job(snakemake)

identified = modal.thesis.intermediates.read_interpretations(
    snakemake.input.identified, snakemake.params.study["interpretations"], snakemake.params.study, snakemake.params.seeds)
for path, (title, mode) in zip(snakemake.output, modal.thesis.plots.numbered(snakemake.params.figures,
                                                                           snakemake.params.captions)):
    modal.thesis.plots.noise_figure(identified, mode, title).savefig(path, dpi=120)
