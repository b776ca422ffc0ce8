"""One setting of one search: its study under each interpretation, scored
against the printed tables -> results/searches/<search>/<setting>.csv."""
import modal.thesis.search
import modal.thesis.study
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

setting, seeds = snakemake.params.setting, snakemake.params.seeds
identified = {name: modal.thesis.study.run_study(setting["study"], setting["beam"], signals, seeds)
              for name, signals in snakemake.params.interpretations.items()}
published = modal.thesis.tables.read_published(snakemake.input.published)
scores = modal.thesis.search.score_setting(published, identified, snakemake.params.tables, setting["study"],
                                           seeds["first"])
modal.thesis.tables.write_csv(scores, snakemake.output[0])
