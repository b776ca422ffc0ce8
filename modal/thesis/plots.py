"""Figures of the thesis, drawn on matplotlib Figure objects (no pyplot, no
backend assumption: scripts save them, notebooks display them)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from .report import VERDICTS
from ..identification import align_shapes
from ..structures import SimplySupportedBeam
from .tables import NOISE_FREE_SEED, assign_modes, interpretation_name

MARKERS = {"tcm": "o", "era": "x", "cera": "s"}
#: Entries flagged ``unstable`` (|z| > 1): a hollow triangle for every method, so
#: they differ from ordinary entries even where the method's marker has no face (×).
UNSTABLE_MARKER = "^"
STYLES = {0: "-", 1: "--", 2: ":"}
#: Markers of the second interpretation (hollow where the first is filled).
SECOND = {"tcm": "D", "era": "+", "cera": "^"}


def figure_titles(captions: Mapping[int, str]):
    """``title(number)``: "Figure N. caption", the caption from
    ``workflow/report/captions.yaml`` (drawn on the figure, printed under it)."""
    return lambda number: f"Figure {int(number)}. {captions[int(number)]}"


def numbered(figures: Mapping, captions: Mapping[int, str]) -> list[tuple[str, object]]:
    """``figures`` (number -> what to draw) as ``(title, what)`` pairs in
    figure order, one per output file."""
    title = figure_titles(captions)
    return [(title(number), what) for number, what in sorted(figures.items(), key=lambda kv: int(kv[0]))]


def _shape_columns(frame):
    return [c for c in frame.columns if c.startswith("phi_")]


def _flagged(entry, flag: str) -> bool:
    return flag in entry and bool(entry[flag])


def _suptitle(fig: Figure, title: str, width: int = 78, fontsize: float = 10) -> None:
    """The figure's title, wrapped so that it never runs off the figure."""
    import textwrap

    fig.suptitle("\n".join(textwrap.fill(line, width) for line in title.split("\n")), fontsize=fontsize)


def _legend_below(fig: Figure, axes, ncols: int = 3) -> None:
    """One legend for the whole figure, below the panels (never over the data)."""
    handles = {}
    for ax in np.ravel(axes):
        for handle, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    if handles:
        fig.legend(list(handles.values()), list(handles), loc="outside lower center", ncols=ncols, fontsize=7,
                   frameon=False)


def shape_figure(beam_spec: Mapping, identified: Mapping[str, pd.DataFrame], case: str, method: str,
                 first_seed: int, title: str, n_shown: int = 3) -> Figure:
    """Identified mode shapes (first seed) against the exact ones, one panel
    per mode, one marker series per interpretation (Figs. 1-8).

    Each panel shows the entry the tables assign to that mode
    (:func:`modal.thesis.tables.assign_modes`: by frequency when seeds
    disagree), never the entry at that position, so a real pole or a lost
    mode shifts nothing. The panel's heading gives the exact and identified
    frequencies; a mode not identified in the first seed is said so, real
    poles are listed under the panels, and entries flagged ``unstable`` are
    circled in red.
    """
    beam = SimplySupportedBeam(beam_spec["length"], beam_spec["bending_stiffness"], beam_spec["mass_per_length"])
    x_s = beam.length / beam_spec["stations"] * np.asarray(beam_spec["sensors"], float)
    x = np.linspace(0, beam.length, 200)
    exact_s = beam.mode_shapes(x_s, n_shown)
    norms = np.linalg.norm(exact_s, axis=0)
    exact_s, exact = exact_s / norms, beam.mode_shapes(x, n_shown) / norms
    omega = beam.natural_frequencies(n_shown)
    fig = Figure(figsize=(6.5, 2.1 * n_shown + 1.2), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n_shown, 1, sharex=True))
    headings = [[f"mode {r + 1}: exact ω = {omega[r]:.3f} rad/s"] for r in range(n_shown)]
    footer = []
    for k, (interp, frame) in enumerate(identified.items()):
        rows = frame[(frame["case"] == case) & (frame["method"] == method)]
        rows = rows[rows["n"] == rows["n"].max()]
        mode_of = assign_modes(rows)
        first = rows[rows["seed"].isin([first_seed, NOISE_FREE_SEED])]
        label = f"{method.upper()} ({interp})"
        marker = MARKERS[method] if k == 0 else SECOND[method]
        for r in range(n_shown):
            entry = first[mode_of.reindex(first.index) == r + 1]
            if entry.empty:
                headings[r].append(f"{label}: not identified")
                axes[r].text(0.5, 0.1 + 0.15 * k, f"{label}: mode {r + 1} not identified in this realisation",
                             transform=axes[r].transAxes, ha="center", fontsize=7, color=f"C{k}")
                continue
            entry = entry.iloc[0]
            shape = align_shapes(entry[_shape_columns(rows)].to_numpy(float)[:, None], exact_s[:, [r]])[:, 0]
            unstable = _flagged(entry, "unstable")
            # the second interpretation hollow, so that it never hides the first
            axes[r].plot(x_s, shape, marker, ms=7 if k == 0 else 8, ls="none", color=f"C{k}",
                         mfc="none" if k else None, label=label)
            if unstable:
                axes[r].plot(x_s, shape, "o", ms=13, ls="none", mfc="none", color="tab:red",
                             label="flagged unstable (|z| > 1)")
            headings[r].append(f"{label} {entry['omega']:.3f}" + (" (unstable)" if unstable else ""))
        poles = first[first["real_pole"].astype(bool)]
        if len(poles):
            footer.append(f"{label}: real pole (*) at " + ", ".join(f"{w:.3g}" for w in poles["omega"])
                          + " rad/s, not a mode")
    for r, ax in enumerate(axes):
        ax.plot(x, exact[:, r], "k-", lw=1, label="exact")
        ax.axhline(0, color="0.8", lw=0.5)
        ax.set_ylabel(f"mode {r + 1}")
        ax.set_title("; ".join(headings[r]), fontsize=7, loc="left")
    axes[-1].set_xlabel("x (m)")
    if footer:
        axes[-1].plot([], [], ls="none", label="; ".join(footer))
    _legend_below(fig, axes, ncols=3)
    _suptitle(fig, title)
    return fig


def noise_figure(identified: Mapping[str, pd.DataFrame], mode: int, title: str) -> Figure:
    """Identified frequency of one mode against snr = 1 / η (Figs. 9-11):
    mean and a ±1 std band over the seeds, the first seed's realisation as
    markers, the exact value as a line, one panel per interpretation.

    Entries are assigned to modes as in the tables
    (:func:`modal.thesis.tables.assign_modes`), so a real pole or a lost
    mode does not shift the others. Noise levels at which the first seed
    did not identify the mode are marked with ``*`` at the foot of the
    panel; entries flagged ``unstable`` are drawn as hollow triangles
    (:data:`UNSTABLE_MARKER`).
    """
    fig = Figure(figsize=(6.5, 2.5 * len(identified) + 1.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(identified), 1, sharex=True))
    for ax, (interp, frame) in zip(axes, identified.items()):
        rows = frame[assign_modes(frame) == mode]
        foot = ax.get_xaxis_transform()
        for method, group in rows.groupby("method"):
            runs = frame[frame["method"] == method]
            n_seeds = runs["seed"].nunique()
            stats = group.groupby("noise")["omega"].agg(["mean", "std"]).sort_index()
            snr = 1 / stats.index.to_numpy()
            (line,) = ax.plot(snr, stats["mean"], "-", label=f"{method.upper()} mean over {n_seeds} seeds")
            ax.fill_between(snr, stats["mean"] - stats["std"], stats["mean"] + stats["std"], alpha=0.25,
                            color=line.get_color(), label=f"{method.upper()} ± 1 std over {n_seeds} seeds")
            seed = runs["seed"].min()
            first = group[group["seed"] == seed].sort_values("noise")
            unstable = first["unstable"].astype(bool) if "unstable" in first else pd.Series(False, first.index)
            ax.plot(1 / first.loc[~unstable, "noise"], first.loc[~unstable, "omega"], MARKERS[method], ls="none",
                    color=line.get_color(), label=f"{method.upper()} first seed (seed {seed})")
            if unstable.any():
                ax.plot(1 / first.loc[unstable, "noise"], first.loc[unstable, "omega"], UNSTABLE_MARKER, ls="none",
                        mfc="none", ms=8, color=line.get_color(),
                        label=f"{method.upper()} first seed, flagged unstable (|z| > 1)")
            lost = sorted(set(runs["noise"]) - set(first["noise"]))
            if lost:
                ax.plot(1 / np.asarray(lost), np.full(len(lost), 0.04), "*", ms=9, ls="none", transform=foot,
                        color=line.get_color(), label=f"{method.upper()} first seed: mode {mode} not identified "
                                                      "(real pole or lost)")
        exact = frame.loc[frame["mode"] == mode, "actual"].iloc[0]
        ax.axhline(exact, color="k", lw=1, label="exact")
        ax.set_ylabel(f"$\\omega_{{{mode}}}$ (rad/s)")
        ax.set_title(interpretation_name(interp), fontsize=8, loc="left")
    axes[-1].set_xlabel("snr = 1 / η")
    _legend_below(fig, axes, ncols=2)
    _suptitle(fig, title)
    return fig


def cera_sensitivity_figure(table: pd.DataFrame, title: str, panels: Mapping[str, str],
                            configured: int | Mapping[str, int]) -> Figure:
    """CERA frequency error against the Hankel width s, one panel per thesis
    table (Tables 7-9), with the configured s marked.

    Parameters
    ----------
    table : DataFrame
        :func:`modal.thesis.tables.cera_sensitivity`.
    title : str
    panels : mapping
        Case -> the heading of its panel ("Table 7. ..."), in panel order.
    configured : int or mapping
        The Hankel width s the tables use (``studies.cera.methods.cera.cols``),
        or interpretation -> its own (an interpretation may read s otherwise,
        :func:`modal.thesis.study.interpreted`).

    The error axis is symmetric-logarithmic (linear within ±1 %), so nothing
    is clipped; widths at which every seed gave a real pole for a mode are
    marked with ``*`` at the panel's foot.
    """
    cases = [c for c in panels if c in set(table["case"])]
    fig = Figure(figsize=(6.5, 2.3 * len(cases) + 1.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(cases), 1, sharex=True))
    interps = list(dict.fromkeys(table["interpretation"]))
    for ax, case in zip(axes, cases):
        rows = table[table["case"] == case]
        for (interp, mode), g in rows.groupby(["interpretation", "mode"]):
            style, color = STYLES.get(interps.index(interp), "-"), f"C{int(mode) - 1}"
            ax.plot(g["cols"], 100 * g["rel_err"], style, marker=".", color=color, label=f"mode {mode} ({interp})")
            lost = g.loc[g["reproduced"].isna(), "cols"]
            if len(lost):
                ax.plot(lost, np.full(len(lost), 0.04), "*", ls="none", color=color, transform=ax.get_xaxis_transform(),
                        label=f"mode {mode} ({interp}): real pole in every seed")
        ax.axhline(0, color="k", lw=0.5)
        widths = configured if isinstance(configured, Mapping) else {None: configured}
        for k, width in enumerate(sorted(set(widths.values()))):
            users = [str(i) for i, w in widths.items() if w == width and i is not None]
            ax.axvline(width, color="0.3", ls=(":", "-.")[k % 2], lw=1.2,
                       label=f"configured s = {width} (Tables 7-9" + (f"; {', '.join(users)})" if users else ")"))
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_ylabel("error (%)")
        ax.set_title(panels[case], fontsize=8, loc="left")
    axes[-1].set_xlabel("Hankel width s (samples; whole fundamental periods: multiples of 360, guideline 90)"
                        if isinstance(configured, Mapping) and len(set(configured.values())) > 1
                        else "Hankel width s (samples; whole fundamental periods at multiples of 360)")
    _legend_below(fig, axes, ncols=2)
    _suptitle(fig, title + "\n(error axis linear within ±1 %, logarithmic beyond)", width=95, fontsize=9)
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
    _suptitle(fig, title)
    return fig


def response_figure(acc: np.ndarray, dt: float, numbers, title: str, spectrum: bool = True,
                    fmax_hz: float = 25.0, peaks_hz=None, thesis_hz=None) -> Figure:
    """Time response (and amplitude spectrum) of accelerometers (Figs. 13-21).

    ``peaks_hz`` (the frequencies our peak picking estimated, the "est."
    column) and ``thesis_hz`` (the thesis's estimates) are marked on the
    spectra as vertical lines.
    """
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
            for i, f in enumerate(np.asarray(peaks_hz if peaks_hz is not None else [], float)):
                axes[k, 1].axvline(f, color="tab:red", ls="--", lw=0.9, label=None if i else "picked peaks (ours)")
            thesis_hz = np.asarray(thesis_hz if thesis_hz is not None else [], float)
            if thesis_hz.size:
                axes[k, 1].plot(thesis_hz, np.full(thesis_hz.size, 0.97), "kv", ms=6, ls="none",
                                transform=axes[k, 1].get_xaxis_transform(), label="the thesis's estimates")
    _legend_below(fig, axes, ncols=2)
    _suptitle(fig, title)
    return fig


VERDICT_COLORS = dict(zip(VERDICTS, ("tab:green", "tab:olive", "tab:orange", "tab:blue", "tab:purple", "tab:red")))


def deviation_figure(summary: pd.DataFrame) -> Figure:
    """The largest |relative deviation| of each thesis table under its best
    interpretation (``summary.csv``), coloured by verdict, on a log scale
    with the 1 % threshold of the graded verdicts."""
    rows = summary.sort_values("table")
    fig = Figure(figsize=(6.5, 0.3 * len(rows) + 1.6), layout="constrained")
    ax = fig.subplots()
    y = np.arange(len(rows))[::-1]
    dev = 100 * rows["max_abs_rel_dev"].fillna(0).clip(lower=1e-4)
    ax.barh(y, dev, color=[VERDICT_COLORS.get(v, "0.5") for v in rows["verdict"]])
    ax.set_yticks(y, [f"Table {n}" for n in rows["table"]])
    ax.set_xscale("log")
    ax.axvline(1, color="k", ls=":", lw=1, label="1 %")
    for verdict, color in VERDICT_COLORS.items():
        if verdict in set(rows["verdict"]):
            ax.plot([], [], "s", ms=9, color=color, label=verdict)
    ax.set_xlabel("largest |relative deviation| from the printed value (%), best interpretation")
    _legend_below(fig, ax, ncols=3)
    fig.suptitle("Deviation per thesis table", fontsize=10)
    return fig


def seed_distribution_figure(identified: pd.DataFrame, table: pd.DataFrame, title: str) -> Figure:
    """Per-seed identified frequencies of one noisy table's case (histograms,
    one panel per method and mode, one colour per interpretation), with the
    published value and the exact one marked. Entries are assigned to modes
    as in the tables (:func:`modal.thesis.tables.assign_modes`); the share
    of seeds without the mode (real pole or lost) is given per panel.

    ``identified``: the case's identified modes of every interpretation
    (column ``interpretation``); ``table``: the tidy ``table_NN.csv``."""
    pub = table[~table["method"].isin(["actual", "est"]) & (table["interpretation"] == table["interpretation"].iloc[0])]
    methods = list(dict.fromkeys(pub["method"]))
    modes = sorted(pub["mode"].unique())
    fig = Figure(figsize=(3.3 * len(methods), 1.9 * len(modes) + 1.2), layout="constrained")
    axes = np.atleast_2d(fig.subplots(len(modes), len(methods), squeeze=False))
    for k, ((interp, frame), color) in enumerate(zip(identified.groupby("interpretation", sort=False),
                                                     ("C0", "C1", "C2"))):
        mode_of = assign_modes(frame)
        for j, method in enumerate(methods):
            runs = frame[frame["method"] == method]
            n_seeds = runs["seed"].nunique()
            for i, mode in enumerate(modes):
                values = runs.loc[mode_of.reindex(runs.index) == mode, "omega"]
                ax = axes[i, j]
                ax.hist(values, bins=20, color=color, alpha=0.5, label=f"{interp} ({n_seeds} seeds)")
                if len(values) < n_seeds:
                    ax.text(0.98, 0.92 - 0.1 * k, f"{interp}: lost in {n_seeds - len(values)} seeds",
                            transform=ax.transAxes, ha="right", fontsize=6, color=color)
    for i, mode in enumerate(modes):
        for j, method in enumerate(methods):
            ax = axes[i, j]
            cell = pub[(pub["method"] == method) & (pub["mode"] == mode)]
            if len(cell) and np.isfinite(cell["published"].iloc[0]):
                ax.axvline(cell["published"].iloc[0], color="k", lw=1.5, label="published (thesis)")
            elif len(cell):
                ax.text(0.02, 0.9, f"thesis: {cell['printed'].iloc[0]}", transform=ax.transAxes, fontsize=7)
            if len(cell) and np.isfinite(cell["actual"].iloc[0]):
                ax.axvline(cell["actual"].iloc[0], color="k", ls=":", lw=1, label="exact")
            ax.set_title(f"{method.upper()}, mode {mode}", fontsize=8, loc="left")
            ax.set_xlabel("ω (rad/s)", fontsize=7)
            ax.tick_params(labelsize=7)
    _legend_below(fig, axes, ncols=3)
    fig.suptitle(title, fontsize=9)
    return fig


def spillover_figure(tables: Mapping[int, pd.DataFrame], titles: Mapping[int, str], inclusion: Mapping) -> Figure:
    """Identified frequency against the number n of identified modes (Tables
    5, 6: spillover), one panel per table: the thesis's values (black), ours
    per interpretation, the exact frequencies (dotted). Under the inclusion
    principle (Eq. 20) each frequency decreases with n towards the exact one,
    the order-n value lying between those of orders n+1 at r and r+1.

    ``inclusion``: table -> text saying whether Eq. (20) holds (the notes)."""
    fig = Figure(figsize=(6.5, 3.0 * len(tables) + 1.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots(len(tables), 1))
    for ax, (number, table) in zip(axes, sorted(tables.items())):
        cells = table[table["column"].astype(str).str.startswith("n=")].copy()
        cells["n_id"] = cells["column"].str[2:].astype(int)
        interps = list(dict.fromkeys(cells["interpretation"]))
        for mode, g in cells.groupby("mode"):
            thesis = g[g["interpretation"] == interps[0]].sort_values("n_id")
            ax.plot(thesis["n_id"], thesis["published"], "ko-", ms=4, lw=0.8, label="thesis")
            stars = thesis[thesis["flag"] == "real_pole"]
            ax.plot(stars["n_id"], np.full(len(stars), 0.04), "k*", ms=9, ls="none",
                    transform=ax.get_xaxis_transform(), label="thesis: real pole (*)")
            for k, interp in enumerate(interps):
                ours = g[g["interpretation"] == interp].sort_values("n_id")
                ax.plot(ours["n_id"] + 0.06 * (k + 1), ours["reproduced"], MARKERS["era"] if k else "s",
                        ls=STYLES[k + 1], color=f"C{k}", ms=5, lw=0.8, label=f"ours ({interp})")
            exact = g["actual"].dropna()
            if len(exact):
                ax.axhline(exact.iloc[0], color="0.5", ls=":", lw=0.8, label="exact")
        ax.set_yscale("log")
        ax.set_xticks(sorted(cells["n_id"].unique()))
        ax.set_xlabel("n (modes identified)")
        ax.set_ylabel("ω (rad/s)")
        import textwrap

        heading = "\n".join([f"Table {number}. {titles.get(number, '')}",
                             *textwrap.wrap(inclusion.get(number, ""), 92)])
        ax.set_title(heading, fontsize=7, loc="left")
    _legend_below(fig, axes, ncols=4)
    fig.suptitle("Identification spillover: frequency against n", fontsize=10)
    return fig
