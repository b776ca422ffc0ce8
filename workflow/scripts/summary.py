"""The reproduction summary, computed once: one row per thesis table with its
graded verdict -> results/tables/summary.csv (the notebooks and the HTML read it)."""
import modal.thesis.report
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

tables = {}
for path in snakemake.input.tables:
    tables.update(modal.thesis.report.load_tables(path.rsplit("/", 1)[0], numbers={int(path[-6:-4])}))
summary = modal.thesis.report.reproduction_summary(tables, snakemake.params.titles)
modal.thesis.tables.write_csv(summary, snakemake.output[0])
