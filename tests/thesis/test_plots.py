"""Figures of the thesis layer: what a reader tells apart on them."""

import numpy as np
import pandas as pd

from modal.thesis.plots import MARKERS, UNSTABLE_MARKER, noise_figure


def _identified(unstable):
    """Two seeds of one method at three noise levels, one mode (exact 2.0 rad/s)."""
    rows = []
    for seed in (0, 1):
        for k, noise in enumerate((0.01, 0.02, 0.05)):
            rows.append(dict(seed=seed, noise=noise, method="era", mode=1, omega=2.0 + 0.01 * k + 0.001 * seed,
                             actual=2.0, real_pole=False, unstable=bool(unstable[k]) and seed == 0))
    return pd.DataFrame(rows)


def test_figure_9_tells_unstable_entries_apart():
    """Unstable entries of the first seed get their own marker, hollow, distinct
    from the method's own (ERA's × has no face, so hollow alone would not show)."""
    fig = noise_figure({"named": _identified([False, True, False])}, 1, "Figure 9")
    lines = {line.get_label(): line for line in fig.axes[0].get_lines()}
    ordinary = lines["ERA first seed (seed 0)"]
    unstable = lines["ERA first seed, flagged unstable (|z| > 1)"]
    assert ordinary.get_marker() == MARKERS["era"] and unstable.get_marker() == UNSTABLE_MARKER != MARKERS["era"]
    assert unstable.get_markerfacecolor() == "none"
    np.testing.assert_allclose(unstable.get_xdata(), [1 / 0.02])
    np.testing.assert_allclose(ordinary.get_xdata(), [1 / 0.01, 1 / 0.05])

