"""Grid figures (thesis Figures 12-21, numbers from grid.figures): the grid,
the raw and the filtered responses of the chosen accelerometers."""
import numpy as np

import modal.thesis.grid_study as gs
import modal.thesis.intermediates
import modal.thesis.plots as plots
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

spec, captions = snakemake.params.spec, snakemake.params.captions
numbers = spec["figures"]
paths = dict(zip([numbers["layout"], *numbers["responses"], *numbers["filtered"]], snakemake.output))
rec = np.load(snakemake.input.record)
selection = modal.thesis.intermediates.read_selection(snakemake.input.selection, spec)
chosen = selection[selection["seed"] == selection["seed"].min()].sort_values("rank")["channel"].to_numpy()
acc, dt = rec["acceleration"][:, chosen], float(rec["dt"])

title = plots.figure_titles(captions)

layout = numbers["layout"]
if spec["source"] == "virtual":
    fig = plots.grid_figure(gs.grid_model(spec), np.asarray(spec["test"]["sensors"]), chosen, title(layout))
else:
    channels = list(range(1, rec["acceleration"].shape[1] + 1))
    fig = plots.response_figure(rec["acceleration"], dt, channels, title(layout) + " (measured record: all channels)",
                                spectrum=False)
fig.savefig(paths[layout], dpi=110)
# the spectra mark our peak-picked "est." frequencies and the thesis's (the first grid table's est column)
picked = selection[selection["seed"] == selection["seed"].min()].sort_values("rank")["est_hz"].dropna().to_numpy()
published = modal.thesis.tables.read_published(snakemake.input.published)
thesis_hz = modal.thesis.tables.published_estimates(published, min(spec["tables"]))
for k, number in enumerate(numbers["responses"]):
    plots.response_figure(acc[:, [k]], dt, [k + 1], title(number), peaks_hz=picked,
                          thesis_hz=thesis_hz).savefig(paths[number], dpi=110)
cutoff = spec["figures_cutoff_hz"]
filtered = gs.preprocess(acc, dt, cutoff)
for k, number in enumerate(numbers["filtered"]):
    pair = [2 * k, 2 * k + 1]
    plots.response_figure(filtered[:, pair], dt, [p + 1 for p in pair], f"{title(number)}, {cutoff:g} Hz low-pass",
                          spectrum=False).savefig(paths[number], dpi=110)
