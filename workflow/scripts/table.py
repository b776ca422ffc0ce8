"""One thesis table: published beside reproduced -> table_NN.csv, .md and notes."""
import modal.thesis.intermediates
import modal.thesis.report
import modal.thesis.tables
from _helpers import mock_snakemake, start_job

if "snakemake" not in globals():
    snakemake = mock_snakemake("table", number="04")
start_job(snakemake)

number = int(snakemake.wildcards.number)
published = modal.thesis.tables.read_published(snakemake.input.published)
study = snakemake.config["studies"][snakemake.params.spec["study"]]
identified = modal.thesis.intermediates.read_interpretations(
    snakemake.input.identified, snakemake.params.interpretations, study, snakemake.config["seeds"])
table = modal.thesis.tables.compare(published[published["table"] == number], identified, snakemake.params.spec,
                                    snakemake.params.methods, snakemake.params.first_seed)
modal.thesis.tables.write_csv(table, snakemake.output.csv)
notes = modal.thesis.report.table_notes(number, table)
modal.thesis.report.write_notes(snakemake.output.notes, notes)
with open(snakemake.output.md, "w") as fh:
    fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {snakemake.params.spec['title']}", notes))
