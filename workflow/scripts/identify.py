"""Identify one chunk of seeds of one study under one interpretation -> results/identified/chunks/*.csv."""
import modal.thesis.study
from _helpers import start_job

start_job(snakemake)

frame = modal.thesis.study.run_study(snakemake.params.study, snakemake.params.beam, snakemake.params.signals,
                                     snakemake.params.seeds, chunk=snakemake.params.chunk)
frame.to_csv(snakemake.output[0], index=False)
