"""Every beam table of rule ``table``: published beside reproduced -> table_NN.csv, .md and notes.

One job writes them all (the thesis layer is imported once); each table
reads the identified files of its own study."""
from pathlib import Path

import modal.thesis.intermediates
import modal.thesis.report
import modal.thesis.study
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

published = modal.thesis.tables.read_published(snakemake.input.published)
seeds = snakemake.params.seeds
numbers = sorted(snakemake.params.tables)
for number, csv, md, notes_file in zip(numbers, snakemake.output.csv, snakemake.output.md, snakemake.output.notes,
                                       strict=True):
    spec = snakemake.params.tables[number]
    study = snakemake.params.studies[spec["study"]]
    paths = [next(p for p in snakemake.input.identified if Path(p).name == f"{spec['study']}_{i}.csv")
             for i in study["interpretations"]]
    identified = modal.thesis.intermediates.read_interpretations(paths, study["interpretations"], study, seeds)
    readings = {i: modal.thesis.study.interpreted(study, snakemake.params.beams[spec["study"]],
                                                  snakemake.params.interpretations[i], spec["study"])[0]["methods"]
                for i in study["interpretations"]}
    table = modal.thesis.tables.compare(published[published["table"] == number], identified, spec,
                                        study["methods"], seeds["first"], readings)
    modal.thesis.tables.write_csv(table, csv, "beam")
    notes = modal.thesis.report.table_notes(number, table)
    modal.thesis.report.write_notes(notes_file, notes)
    with open(md, "w") as fh:
        fh.write(modal.thesis.tables.to_markdown(table, f"Table {number}. {spec['title']}", notes))
