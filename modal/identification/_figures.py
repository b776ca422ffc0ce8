"""The stabilisation diagram drawn (matplotlib, imported when called)."""

from __future__ import annotations

import numpy as np

from .._checks import positive_float, printable
from ._stabilisation import Stabilisation


def stabilisation_figure(result: Stabilisation, fmax=None, title=None, ax=None, spectrum=None):
    """Stabilisation diagram: poles by model order over frequency, with the
    data's spectrum (log scale, right axis) behind them.

    Grey dots: every pole; blue: stable (frequency, damping and shape);
    filled red: stable and physical, clustered into a mode; vertical lines:
    the selected modes (dashed: a mode with no singular-value peak near it,
    where the modes say so). Imports matplotlib only when called.

    Parameters
    ----------
    result : Stabilisation
    fmax : float, optional
        Highest frequency drawn (Hz); default the spectrum's last.
    title : str, optional
    ax : matplotlib Axes, optional
    spectrum : SingularValueSpectrum, optional
        The record's singular-value spectrum (:func:`modal.fdd`), drawn behind
        the poles in dB (first singular value darker) instead of the mean
        amplitude spectrum of the identified data.

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
    if spectrum is None:
        band = result.spectrum_hz <= fmax
        spectrum_ax.semilogy(result.spectrum_hz[band], result.spectrum[band], color="0.75", lw=1, zorder=0)
        spectrum_ax.set_ylabel("amplitude spectrum")
        spectrum_ax.set_yticks([])
    else:
        band = spectrum.freq_hz <= fmax
        db = spectrum.decibels()
        for k in range(db.shape[1] - 1, -1, -1):
            spectrum_ax.plot(spectrum.freq_hz[band], db[band, k], color="0.55" if k == 0 else "0.8", lw=1, zorder=0,
                             label=f"singular value {k + 1}")
        spectrum_ax.set_ylabel("singular values of the spectral density (dB)", color="0.4")
        spectrum_ax.tick_params(axis="y", colors="0.4", labelsize="small")
        if band.any():
            low = np.percentile(db[band, -1], 1) - 3
            spectrum_ax.set_ylim(max(low, -120.0), 5)
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
    supported = result.modes["spectral_support"] if "spectral_support" in result.modes else [True] * len(result.modes)
    for f, peak in zip(result.modes["freq_hz"], supported):
        if f <= fmax:
            ax.axvline(f, color="tab:red", lw=0.6, alpha=0.5, ls="-" if peak else "--")
    ax.set_xlim(0, fmax)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("model order")
    ax.legend(loc="upper left", fontsize="small", framealpha=0.9)
    if title:
        ax.set_title(printable(title))
    return fig
