"""Identify one study under one interpretation -> results/identified/*.csv."""
import modal.thesis.study
from _helpers import mock_snakemake, redirect_log

if "snakemake" not in globals():
    snakemake = mock_snakemake("identify", study="demo", interpretation="named")
redirect_log(snakemake)

frame = modal.thesis.study.run_study(snakemake.params.study, snakemake.params.beam, snakemake.params.signals,
                                     snakemake.params.seeds)
frame.to_csv(snakemake.output[0], index=False)
