"""One grid table (10-15): published beside reproduced -> table_NN.csv and .md."""
import sys

import pandas as pd

import modal.thesis.grid_study as gs
import modal.thesis.tables

sys.stderr = open(snakemake.log[0], "w")
number = int(snakemake.wildcards.number)
spec = snakemake.params.spec
published = modal.thesis.tables.read_published(snakemake.input.published)
identified = pd.read_csv(snakemake.input.identified)
selection = pd.read_csv(snakemake.input.selection)
table = gs.grid_table(number, published[published["table"] == number], identified, selection, spec,
                      snakemake.params.first_seed)
table.to_csv(snakemake.output.csv, index=False)
model_hz = gs.grid_model(spec).frequencies_hz(4) if spec["source"] == "virtual" and number == 10 else None
notes = gs.grid_notes(number, table, identified, spec, model_hz)
with open(snakemake.output.md, "w") as fh:
    fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {spec['tables'][number]['title']} "
                                       f"(Hz; {'virtual grid' if spec['source'] == 'virtual' else 'measured record'})", notes))
