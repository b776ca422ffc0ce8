"""Every search gathered: results/searches/<search>.csv (each setting's
scores, with its values) and results/tables/searches.csv (per search and
table: the study's own setting, the best, and whether it explains the table)."""
from pathlib import Path

import pandas as pd

import modal.thesis.search
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

summaries = []
for out in snakemake.output.searches:
    name, frames = Path(out).stem, []
    for setting, spec in snakemake.params.settings[name].items():
        path = next(p for p in snakemake.input.settings if Path(p) == Path(out).with_suffix("") / f"{setting}.csv")
        frame = pd.read_csv(path)
        frames.append(frame.assign(setting=setting, values=modal.thesis.search.describe(spec["values"]),
                                   default=spec["default"], **spec["values"]))
    scores = pd.concat(frames, ignore_index=True)
    modal.thesis.tables.write_csv(scores, out)
    summaries.append(modal.thesis.search.search_summary(name, snakemake.params.searches[name], scores))
summary = pd.concat(summaries, ignore_index=True) if summaries else pd.DataFrame(
    columns=modal.thesis.search.SUMMARY_COLUMNS)
modal.thesis.tables.write_csv(summary, snakemake.output.summary)
