"""Words about a reproduced table: which interpretation matches, how the
published values sit in the seed spread, whether the inclusion principle holds."""

from __future__ import annotations

import numpy as np
import pandas as pd

from .tables import inclusion_holds, interpretation_summary


def table_notes(number: int, table: pd.DataFrame) -> list[str]:
    """Notes printed under a reproduced table (computed, not hand-written)."""
    notes = []
    summary = interpretation_summary(table)
    for interp, row in summary.iterrows():
        notes.append(f"{interp}: {int(row['matched'])} of {int(row['values'])} identified values match the "
                     f"printed digits; mean |deviation| {100 * row['mean_abs_dev']:.2f} %, "
                     f"largest {100 * row['max_abs_dev']:.2f} %.")
    if len(summary) > 1:
        best = summary["mean_abs_dev"].idxmin()
        notes.append(f"The '{best}' interpretation matches the published values best (smallest mean |deviation|).")
    noisy = table[(table["n_seeds"] > 1) & table["z"].notna()]
    if len(noisy):
        n = int(noisy["n_seeds"].max())
        for interp, g in noisy.groupby("interpretation"):
            inside = int((g["z"].abs() <= 2).sum())
            notes.append(f"{interp}: reproduced = mean ± std over {n} noise seeds; the published value lies "
                         f"within 2 std for {inside} of {len(g)} values (z = (published - mean) / std).")
    poles = table[table["flag"] == "real_pole"]
    if len(poles):
        for interp, g in table.groupby("interpretation"):
            ours = g[g["seed0_real_pole"].fillna(False).astype(bool) | (g["real_pole_frac"].fillna(0) > 0)]
            cells = ", ".join(f"r={r.mode} {r.column}" for r in ours.itertuples()) or "none"
            notes.append(f"{interp}: the thesis marks real poles (*) at "
                         + ", ".join(f"r={r.mode} {r.column}" for r in poles[poles['interpretation'] == interp].itertuples())
                         + f"; reproduced real poles: {cells}.")
    if table["column"].str.startswith("n=").any():
        for interp, g in table.groupby("interpretation"):
            by_n = {}
            for col, h in g[g["column"].str.startswith("n=")].groupby("column"):
                vals = h.sort_values("mode")["reproduced"].to_numpy()
                by_n[int(col[2:])] = vals[np.isfinite(vals)]
            published = {}
            for col, h in g[g["column"].str.startswith("n=")].groupby("column"):
                vals = h.sort_values("mode")["published"].to_numpy()
                published[int(col[2:])] = vals[np.isfinite(vals)]
            notes.append(f"{interp}: inclusion principle (Eq. 20) over n = {min(by_n)}..{max(by_n)} "
                         f"{'holds' if inclusion_holds(by_n) else 'does not hold'} for the reproduced frequencies "
                         f"({'holds' if inclusion_holds(published) else 'does not hold'} for the published ones).")
    return notes
