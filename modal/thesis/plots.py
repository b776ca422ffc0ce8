"""Figures of the thesis, drawn on matplotlib Figure objects (no pyplot, no
backend assumption: scripts save them, notebooks display them)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from ..indicators import align_shapes
from ..structures import SimplySupportedBeam
from .tables import match_to_reference

MARKERS = {"tcm": "o", "era": "x", "cera": "s"}
STYLES = {0: "-", 1: "--", 2: ":"}


def _shape_columns(frame):
    return [c for c in frame.columns if c.startswith("phi_")]


def shape_figure(beam_spec: Mapping, identified: Mapping[str, pd.DataFrame], case: str, method: str,
                 first_seed: int, title: str, n_shown: int = 3) -> Figure:
    """Identified mode shapes (first seed) against the exact ones, one panel
    per mode, one marker series per interpretation (Figs. 1-8)."""
    beam = SimplySupportedBeam(beam_spec["length"], beam_spec["bending_stiffness"], beam_spec["mass_per_length"])
    x_s = beam.length / beam_spec["stations"] * np.asarray(beam_spec["sensors"], float)
    x = np.linspace(0, beam.length, 200)
    exact_s = beam.mode_shapes(x_s, n_shown)
    norms = np.linalg.norm(exact_s, axis=0)
    exact_s, exact = exact_s / norms, beam.mode_shapes(x, n_shown) / norms
    fig = Figure(figsize=(6.5, 2.2 * n_shown), layout="constrained")
    axes = fig.subplots(n_shown, 1, sharex=True)
    for k, (interp, frame) in enumerate(identified.items()):
        rows = frame[(frame["case"] == case) & (frame["method"] == method)
                     & frame["seed"].isin([first_seed, -1])]
        rows = rows[rows["n"] == rows["n"].max()].sort_values("mode").head(n_shown)
        shapes = align_shapes(rows[_shape_columns(rows)].to_numpy().T, exact_s[:, : len(rows)])
        for r in range(shapes.shape[1]):
            axes[r].plot(x_s, shapes[:, r], MARKERS[method] if k == 0 else "+", ms=7,
                         label=f"{method.upper()} ({interp})", ls="none")
    for r, ax in enumerate(axes):
        ax.plot(x, exact[:, r], "k-", lw=1, label="exact")
        ax.axhline(0, color="0.8", lw=0.5)
        ax.set_ylabel(f"mode {r + 1}")
    axes[0].legend(fontsize=8, ncols=3, loc="lower center")  # mode 1 is positive: its lower half is empty
    axes[-1].set_xlabel("x (m)")
    fig.suptitle(title, fontsize=10)
    return fig


def noise_figure(identified: Mapping[str, pd.DataFrame], mode: int, title: str) -> Figure:
    """Identified frequency of one mode against snr = 1 / eta: mean and a
    +-1 std band over seeds, the first seed's realisation as markers, the
    exact value as a line (Figs. 9-11). In each seed the mode is the entry
    matched to it by frequency (:func:`modal.thesis.tables.match_to_reference`), so a
    real pole or a lost mode does not shift the others."""
    fig = Figure(figsize=(6.5, 2.6 * len(identified)), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(identified), 1, sharex=True))
    for ax, (interp, frame) in zip(axes, identified.items()):
        matched = pd.concat([match_to_reference(g) for _, g in frame.groupby(["method", "noise"])])
        rows = frame[matched.reindex(frame.index) == mode]
        for method, group in rows.groupby("method"):
            stats = group.groupby("noise")["omega"].agg(["mean", "std"]).sort_index()
            snr = 1 / stats.index.to_numpy()
            (line,) = ax.plot(snr, stats["mean"], "-", label=f"{method.upper()} mean over seeds")
            ax.fill_between(snr, stats["mean"] - stats["std"], stats["mean"] + stats["std"], alpha=0.25,
                            color=line.get_color())
            first = group[group["seed"] == group["seed"].min()].sort_values("noise")
            ax.plot(1 / first["noise"], first["omega"], MARKERS[method], color=line.get_color(),
                    label=f"{method.upper()} first seed")
        exact = frame.loc[frame["mode"] == mode, "actual"].iloc[0]
        ax.axhline(exact, color="k", lw=1, label="exact")
        ax.set_ylabel(f"omega_{mode} (rad/s)\n[{interp}]")
        ax.legend(fontsize=7, ncols=2)
    axes[-1].set_xlabel("snr = 1 / eta")
    fig.suptitle(title, fontsize=10)
    return fig


def cera_sensitivity_figure(table: pd.DataFrame, title: str) -> Figure:
    """CERA frequency error against the Hankel width s, per case and mode."""
    cases = list(dict.fromkeys(table["case"]))
    fig = Figure(figsize=(6.5, 2.4 * len(cases)), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(cases), 1, sharex=True))
    for ax, case in zip(axes, cases):
        rows = table[table["case"] == case]
        for (interp, mode), g in rows.groupby(["interpretation", "mode"]):
            ax.plot(g["cols"], 100 * g["rel_err"], STYLES.get(list(dict.fromkeys(rows["interpretation"])).index(interp), "-"),
                    marker=".", label=f"mode {mode} ({interp})")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_ylabel(f"error (%)\n{case}")
        ax.set_ylim(-60, 60)
        ax.legend(fontsize=6, ncols=3)
    axes[-1].set_xlabel("Hankel width s (samples; whole fundamental periods at multiples of 360)")
    fig.suptitle(title, fontsize=10)
    return fig


def grid_figure(grid, nodes, chosen, title: str) -> Figure:
    """The grid's strips, the clamp along the top, all accelerometers and the
    chosen ones numbered 1..k in order of choice (Fig. 12)."""
    xy = grid.coordinates
    fig = Figure(figsize=(6.0, 4.6), layout="constrained")
    ax = fig.subplots()
    for x in grid.x_vertical:
        ax.plot([x, x], [0, grid.height], color="0.5", lw=4, solid_capstyle="butt")
    for y in grid.y_horizontal:
        ax.plot([0, grid.width], [y, y], color="0.5", lw=4, solid_capstyle="butt")
    ax.plot([-0.1, grid.width + 0.1], [grid.height, grid.height], "k-", lw=6)
    ax.text(grid.width / 2, grid.height + 0.05, "clamped (I-beam)", ha="center", va="bottom")
    ax.plot(*xy[nodes].T, "o", mfc="white", mec="k", ms=9, label="accelerometers")
    for rank, node in enumerate(np.asarray(nodes)[chosen]):
        ax.plot(*xy[node], "o", color="tab:red", ms=9)
        ax.annotate(str(rank + 1), xy[node], xytext=(6, 6), textcoords="offset points", color="tab:red",
                    fontweight="bold")
    ax.plot([], [], "o", color="tab:red", label="used (numbered by choice)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.25), ncols=2, fontsize=8)
    fig.suptitle(title, fontsize=10)
    return fig


def response_figure(acc: np.ndarray, dt: float, numbers, title: str, spectrum: bool = True,
                    fmax_hz: float = 25.0) -> Figure:
    """Time response (and amplitude spectrum) of accelerometers (Figs. 13-21)."""
    from ..signals import amplitude_spectrum

    acc = np.atleast_2d(acc.T).T
    n = acc.shape[1]
    t = dt * np.arange(acc.shape[0])
    fig = Figure(figsize=(7, 2.4 * n), layout="constrained")
    axes = np.atleast_2d(fig.subplots(n, 2 if spectrum else 1, squeeze=False))
    freqs, amp = amplitude_spectrum(acc - acc.mean(axis=0), dt)
    band = (freqs > 0) & (freqs <= fmax_hz)  # the mean is removed: no DC line
    for k in range(n):
        axes[k, 0].plot(t, acc[:, k], lw=0.6)
        axes[k, 0].set_ylabel(f"accelerometer {numbers[k]}\n(m/s²)")
        axes[k, 0].set_xlabel("t (s)")
        if spectrum:
            axes[k, 1].semilogy(freqs[band], amp[band, k], lw=0.8)
            axes[k, 1].set_xlabel("f (Hz)")
            axes[k, 1].set_ylabel("|FFT| / N")
    fig.suptitle(title, fontsize=10)
    return fig
