"""The reproduction summary, computed once: one row per thesis table with its
graded verdict and its reason -> results/tables/summary.csv (the notebooks and
the HTML read it). The grid tables are judged by the thesis's findings on the
virtual grid that stands in for the lost records."""
import modal.thesis.grid_study
import modal.thesis.intermediates
import modal.thesis.report
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

tables = {}
for path in snakemake.input.tables:
    tables.update(modal.thesis.report.load_tables(path.rsplit("/", 1)[0], numbers={int(path[-6:-4])}))
stand_in = {}
if snakemake.input.get("grid"):
    spec = snakemake.params.grid
    identified = modal.thesis.intermediates.read_grid_identified(snakemake.input.grid[0], spec)
    published = modal.thesis.tables.read_published(snakemake.input.published)
    stand_in = modal.thesis.grid_study.stand_in_findings(identified, published, spec)
searches = modal.thesis.tables.read_table(snakemake.input.searches[0]) if snakemake.input.searches else None
summary = modal.thesis.report.reproduction_summary(tables, snakemake.params.titles, snakemake.params.causes, stand_in,
                                                   searches)
grid_tables = {int(n) for n in (snakemake.params.grid or {}).get("tables", {})}
chapters = ["grid" if int(n) in grid_tables else "beam" for n in summary["table"]]
modal.thesis.tables.write_csv(summary, snakemake.output[0], chapters)
