"""Figures 12-21: the grid, raw and filtered responses of the chosen accelerometers."""
import sys

import numpy as np
import pandas as pd

import modal.thesis.grid_study as gs
import modal.thesis.plots

sys.stderr = open(snakemake.log[0], "w")
spec = snakemake.params.spec
rec = np.load(snakemake.input.record)
selection = pd.read_csv(snakemake.input.selection)
chosen = selection[selection["seed"] == selection["seed"].min()].sort_values("rank")["channel"].to_numpy()
acc, dt = rec["acceleration"][:, chosen], float(rec["dt"])
paths = iter(snakemake.output)
if spec["source"] == "virtual":
    grid = gs.grid_model(spec)
    fig = modal.thesis.plots.grid_figure(grid, np.asarray(spec["test"]["sensors"]), chosen,
                                  "Figure 12. The (virtual) AFAL grid and its accelerometers")
else:
    fig = modal.thesis.plots.response_figure(rec["acceleration"], dt, list(range(1, rec["acceleration"].shape[1] + 1)),
                                      "Figure 12. Measured record: all channels (no grid geometry)", spectrum=False)
fig.savefig(next(paths), dpi=110)
for k in range(6):
    modal.thesis.plots.response_figure(acc[:, [k]], dt, [k + 1], f"Figure {13 + k}. Time and frequency responses of the "
                                f"grid (accelerometer no. {k + 1})").savefig(next(paths), dpi=110)
filtered = gs.preprocess(acc, dt, snakemake.params.cutoff)
for k, pair in enumerate(([0, 1], [2, 3], [4, 5])):
    modal.thesis.plots.response_figure(filtered[:, pair], dt, [p + 1 for p in pair],
                                f"Figure {19 + k}. Filtered ({snakemake.params.cutoff:g} Hz) time responses of the grid",
                                spectrum=False).savefig(next(paths), dpi=110)
