"""One setting of one search: its study under each interpretation, scored
against the printed tables -> results/searches/<search>/<setting>.csv."""
import modal.thesis.search
import modal.thesis.study
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

setting, seeds = snakemake.params.setting, snakemake.params.seeds
identified, methods = {}, {}
for name, reading in snakemake.params.interpretations.items():
    study, beam, signals = modal.thesis.search.setting_under(setting, reading, snakemake.params.study)
    identified[name] = modal.thesis.study.run_study(study, beam, signals, seeds)
    methods[name] = study["methods"]
published = modal.thesis.tables.read_published(snakemake.input.published)
scores = modal.thesis.search.score_setting(published, identified, snakemake.params.tables, setting["study"],
                                           seeds["first"], methods)
modal.thesis.tables.write_csv(scores, snakemake.output[0])
