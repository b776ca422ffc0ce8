"""Join the chunks of one identification rule -> the file of an unsplit run,
byte for byte: merge_identified (one study and interpretation, rows grouped
by case) and grid_merge (identified modes, selection and first record).

A script, not a ``run:`` block: Snakemake 8 runs a ``run:`` job in a new
Snakemake process that parses the whole workflow again (about 1.7 s of CPU
per job, measured), a script job in plain Python.
"""
from pathlib import Path

from modal.thesis.chunks import merge_chunks, merge_grid_chunks

if snakemake.rule == "grid_merge":
    merge_grid_chunks(snakemake.input.identified, snakemake.input.selection, snakemake.input.record,
                      snakemake.output)
else:
    merge_chunks(snakemake.input.chunks, snakemake.output[0], group_by="case")
Path(snakemake.log[0]).write_text(f"merged {snakemake.params.n_chunks} chunks\n")
