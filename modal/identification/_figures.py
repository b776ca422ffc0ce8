"""The stabilisation diagram drawn (matplotlib, imported when called)."""

from __future__ import annotations

from .._checks import positive_float
from ._stabilisation import Stabilisation


def stabilisation_figure(result: Stabilisation, fmax=None, title=None, ax=None):
    """Stabilisation diagram: poles by model order over frequency, with the
    data's spectrum (log scale, right axis) behind them.

    Grey dots: every pole; blue: stable (frequency, damping and shape);
    filled red: stable and physical, clustered into a mode; vertical lines:
    the selected modes. Imports matplotlib only when called.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure  # no pyplot: no global state, any backend

    if not isinstance(result, Stabilisation):
        raise ValueError(f"result must be a Stabilisation, got {type(result).__name__}")
    if ax is None:
        fig = Figure(figsize=(8, 4.5), layout="constrained")
        ax = fig.subplots()
    else:
        fig = ax.figure
    fmax = float(result.spectrum_hz[-1]) if fmax is None else positive_float("fmax", fmax)
    poles = result.poles
    spectrum_ax = ax.twinx()
    band = result.spectrum_hz <= fmax
    spectrum_ax.semilogy(result.spectrum_hz[band], result.spectrum[band], color="0.75", lw=1, zorder=0)
    spectrum_ax.set_ylabel("amplitude spectrum")
    spectrum_ax.set_yticks([])
    ax.set_zorder(spectrum_ax.get_zorder() + 1)
    ax.patch.set_visible(False)
    shown = poles["freq_hz"] <= fmax
    groups = [
        (shown, dict(color="0.6", marker=".", s=4, label="pole")),
        (shown & poles["stable"], dict(color="tab:blue", marker="o", s=10, facecolors="none", label="stable")),
        (shown & (poles["mode"] > 0), dict(color="tab:red", marker="o", s=12, label="in a mode")),
    ]
    for mask, style in groups:
        ax.scatter(poles.loc[mask, "freq_hz"], poles.loc[mask, "order"], **style)
    for f in result.modes["freq_hz"]:
        if f <= fmax:
            ax.axvline(f, color="tab:red", lw=0.6, alpha=0.5)
    ax.set_xlim(0, fmax)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("model order")
    ax.legend(loc="upper left", fontsize="small", framealpha=0.9)
    if title:
        ax.set_title(title)
    return fig
