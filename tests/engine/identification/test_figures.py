"""The stabilisation diagram drawn (modal.stabilisation_figure, Stabilisation.plot)."""

import numpy as np
import pytest

import modal

def _hand_made_diagram():
    """A Stabilisation built by hand for the figure: six poles of orders 2, 4
    and 6, one of each group exactly at fmax = 5 Hz and one above it; modes
    at 2, 5 (= fmax) and 6 Hz; a spectrum on a 0.5 Hz grid up to 10 Hz."""
    import pandas as pd

    poles = pd.DataFrame({"order": [2, 2, 4, 4, 6, 6], "freq_hz": [1.0, 2.0, 2.0, 3.0, 5.0, 6.0],
                          "stable": [False, True, True, False, True, True], "mode": [0, 0, 1, 0, 2, 3]})
    modes = pd.DataFrame({"freq_hz": [2.0, 5.0, 6.0]})
    hz = np.linspace(0.0, 10.0, 21)
    return modal.Stabilisation(modes, np.zeros((2, 3)), poles, np.zeros((6, 2)), np.ones(3), hz, 1.0 + hz**2)


def test_stabilisation_figure_draws_each_group_up_to_fmax():
    """What a reader takes from the diagram: every pole up to fmax (inclusive)
    in grey, the stable ones and those in a mode drawn again over them, a line
    per mode up to fmax, the spectrum over the same band on a log axis, the
    axis labels and title;
    without fmax, the whole spectrum's band. Colours and sizes are not pinned."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from modal.identification import stabilisation_figure

    result = _hand_made_diagram()
    fig, ax = plt.subplots()
    assert result.plot(fmax=5.0, title="Palisaden", ax=ax) is fig
    assert ax.get_xlim() == (0.0, 5.0)
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_title()) == ("frequency (Hz)", "model order", "Palisaden")
    groups = {c.get_label(): np.asarray(c.get_offsets()) for c in ax.collections}
    assert list(groups) == ["pole", "stable", "in a mode"]
    np.testing.assert_array_equal(groups["pole"], [[1, 2], [2, 2], [2, 4], [3, 4], [5, 6]])
    np.testing.assert_array_equal(groups["stable"], [[2, 2], [2, 4], [5, 6]])
    np.testing.assert_array_equal(groups["in a mode"], [[2, 4], [5, 6]])
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["pole", "stable", "in a mode"]
    np.testing.assert_array_equal([line.get_xdata() for line in ax.lines], [[2, 2], [5, 5]])
    (spectrum_ax,) = [other for other in fig.axes if other is not ax]
    (spectrum,) = spectrum_ax.lines
    np.testing.assert_array_equal(spectrum.get_xdata(), result.spectrum_hz[:11])
    np.testing.assert_array_equal(spectrum.get_ydata(), result.spectrum[:11])
    assert spectrum_ax.get_yscale() == "log" and spectrum_ax.get_ylabel() == "amplitude spectrum"
    assert len(spectrum_ax.get_yticks()) == 0  # arbitrary units: no scale
    plt.close(fig)

    fig = stabilisation_figure(result)
    ax, spectrum_ax = fig.axes
    assert ax.get_xlim() == (0.0, 10.0) and ax.get_title() == ""
    assert len(ax.collections[0].get_offsets()) == 6 and len(ax.lines) == 3
    assert len(spectrum_ax.lines[0].get_xdata()) == 21
    plt.close(fig)
    with pytest.raises(ValueError, match="^result must be a Stabilisation, got dict"):
        stabilisation_figure({"poles": None})
    with pytest.raises(ValueError, match="^fmax must"):
        stabilisation_figure(result, fmax=0.0)
