"""One thesis table: published beside reproduced -> table_NN.csv and .md."""
import sys

import pandas as pd

import modal.thesis.tables
import modal.thesis.report

sys.stderr = open(snakemake.log[0], "w")
number = int(snakemake.wildcards.number)
published = modal.thesis.tables.read_published(snakemake.input.published)
identified = {i: pd.read_csv(f) for i, f in zip(snakemake.params.interpretations, snakemake.input.identified)}
table = modal.thesis.tables.compare(published[published["table"] == number], identified, snakemake.params.spec,
                             snakemake.params.methods, snakemake.params.first_seed)
table.to_csv(snakemake.output.csv, index=False)
notes = modal.thesis.report.table_notes(number, table)
with open(snakemake.output.md, "w") as fh:
    fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {snakemake.params.spec['title']}", notes))
