"""Identify one study under one interpretation -> results/identified/*.csv."""
import sys

import modal.thesis.study

sys.stderr = open(snakemake.log[0], "w")
frame = modal.thesis.study.run_study(snakemake.params.study, snakemake.params.beam, snakemake.params.signals,
                              snakemake.params.seeds)
frame.to_csv(snakemake.output[0], index=False)
