"""One grid table: published beside reproduced -> table_NN.csv, .md and notes."""
import modal.thesis.grid_study as gs
import modal.thesis.intermediates
import modal.thesis.report
import modal.thesis.tables
from _helpers import mock_snakemake, start_job

if "snakemake" not in globals():
    snakemake = mock_snakemake("grid_table", number="11")
start_job(snakemake)

number = int(snakemake.wildcards.number)
spec = snakemake.params.spec
published = modal.thesis.tables.read_published(snakemake.input.published)
identified = modal.thesis.intermediates.read_grid_identified(snakemake.input.identified, spec)
selection = modal.thesis.intermediates.read_selection(snakemake.input.selection, spec)
published = published[published["table"] == number]
table = gs.grid_table(number, published, identified, selection, spec, snakemake.params.first_seed)
modal.thesis.tables.write_csv(table, snakemake.output.csv)
notes = gs.grid_notes(number, table, identified, spec, *gs.model_against_estimates(number, published, spec))
modal.thesis.report.write_notes(snakemake.output.notes, notes)
source = "virtual grid" if spec["source"] == "virtual" else "measured record"
with open(snakemake.output.md, "w") as fh:
    fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {spec['tables'][number]['title']} "
                                             f"(Hz; {source})", notes))
