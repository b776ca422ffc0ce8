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
table = gs.grid_table(number, published[published["table"] == number], identified, selection, spec,
                      snakemake.params.first_seed)
modal.thesis.tables.write_csv(table, snakemake.output.csv)
model = spec["source"] == "virtual" and spec["tables"][number].get("finding") == "model"
notes = gs.grid_notes(number, table, identified, spec, gs.grid_model(spec).frequencies_hz(4) if model else None)
modal.thesis.report.write_notes(snakemake.output.notes, notes)
source = "virtual grid" if spec["source"] == "virtual" else "measured record"
with open(snakemake.output.md, "w") as fh:
    fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {spec['tables'][number]['title']} "
                                             f"(Hz; {source})", notes))
