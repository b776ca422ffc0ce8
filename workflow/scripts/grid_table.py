"""Every grid table of rule ``grid_table``: published beside reproduced -> table_NN.csv, .md and notes."""
import modal.thesis.grid_study as gs
import modal.thesis.intermediates
import modal.thesis.report
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

spec = snakemake.params.spec
published_all = modal.thesis.tables.read_published(snakemake.input.published)
identified = modal.thesis.intermediates.read_grid_identified(snakemake.input.identified, spec)
selection = modal.thesis.intermediates.read_selection(snakemake.input.selection, spec)
source = "virtual grid" if spec["source"] == "virtual" else "measured record"
numbers = sorted(int(n) for n in spec["tables"])
for number, csv, md, notes_file in zip(numbers, snakemake.output.csv, snakemake.output.md, snakemake.output.notes,
                                       strict=True):
    published = published_all[published_all["table"] == number]
    table = gs.grid_table(number, published, identified, selection, spec, spec["seeds"]["first"])
    modal.thesis.tables.write_csv(table, csv, "grid")
    notes = gs.grid_notes(number, table, identified, spec, *gs.model_against_estimates(number, published, spec))
    modal.thesis.report.write_notes(notes_file, notes)
    with open(md, "w") as fh:
        fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {spec['tables'][number]['title']} "
                                                 f"(Hz; {source})", notes))
