"""A campaign's report: one self-contained HTML page with every identified
mode over time, the tracked modes' frequency and damping with their
uncertainty, frequency against the index's other columns (temperature,
wind, ...), each tracked mode's mean shape drawn on the structure (when the
campaign gives a geometry), the failed records and the provenance.

Damping is given in % of critical everywhere in the report (tables and
axes); the CSV files keep the ratio (``tracked.csv``'s ``damping``)."""

from __future__ import annotations

import base64
import html
import io
import platform
from importlib.metadata import PackageNotFoundError, version

import numpy as np
import pandas as pd

from .._checks import printable

#: Half-width of the bands drawn around each estimate, in standard deviations
#: (a 95 % interval for a normal estimate).
BAND = 1.96
#: Damping ratio to the report's unit, % of critical.
PERCENT = 100.0
#: Grey of the modes that matched no reference.
UNTRACKED_GREY = "0.6"


def _colour(number) -> str:
    return f"C{(int(number) - 1) % 10}"


def _interval(value: np.ndarray, std: np.ndarray) -> np.ndarray:
    """``(2, n)`` error-bar lengths of ``value`` +- BAND ``std``, the lower
    end clipped at zero (a frequency or a damping ratio is never negative);
    a missing std draws no bar."""
    std = np.nan_to_num(std, nan=0.0)
    lower = np.minimum(BAND * std, np.maximum(value, 0.0))
    return np.vstack([lower, BAND * std])


def overview_figure(tracked: pd.DataFrame, untracked: pd.DataFrame, references: pd.DataFrame):
    """Every identified mode's frequency over time: the tracked ones coloured
    by their mode, those that matched no reference grey. Returns a
    matplotlib ``Figure``."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(10, 4))
    ax = figure.subplots()
    if len(untracked):
        ax.plot(pd.to_datetime(untracked["time"]), untracked["freq_hz"], ".", ms=3, color=UNTRACKED_GREY,
                label=f"untracked ({len(untracked)})", zorder=1)
    numbers = list(references["mode"]) if len(references) else []
    for number in numbers:
        t = tracked[tracked["mode"] == number]
        ax.plot(pd.to_datetime(t["time"]), t["freq_hz"], ".", ms=4, color=_colour(number),
                label=f"mode {number} ({t['record'].nunique()})", zorder=2)
    ax.set_ylabel("frequency (Hz)")
    ax.set_title("every identified mode (records holding it in brackets)", fontsize=10)
    if numbers or len(untracked):
        ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)
    ax.grid(alpha=0.3)
    figure.autofmt_xdate()
    figure.tight_layout()
    return figure


def tracking_figure(tracked: pd.DataFrame, references: pd.DataFrame):
    """Frequency (left) and damping in % of critical (right) of each tracked
    mode over time, each estimate with a bar of :data:`BAND` standard
    deviations, clipped at zero. Returns a matplotlib ``Figure``."""
    from matplotlib.figure import Figure

    numbers = list(references["mode"]) if len(references) else []
    figure = Figure(figsize=(10, 1.9 * max(1, len(numbers)) + 0.8))
    axes = figure.subplots(max(1, len(numbers)), 2, squeeze=False, sharex=True)
    for row, number in enumerate(numbers):
        t = tracked[tracked["mode"] == number].sort_values("time")
        time = pd.to_datetime(t["time"])
        for ax, value, std, scale, label in ((axes[row, 0], "freq_hz", "freq_std_hz", 1.0, "Hz"),
                                             (axes[row, 1], "damping", "damping_std", PERCENT, "damping %")):
            y, s = scale * t[value].to_numpy(dtype=float), scale * t[std].to_numpy(dtype=float)
            ax.errorbar(time, y, yerr=_interval(y, s), fmt=".", ms=3, color=_colour(number), ecolor=_colour(number),
                        elinewidth=0.8, alpha=0.8)
            ax.set_ylabel(f"mode {number}\n{label}", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.grid(alpha=0.3)
        axes[row, 1].set_ylim(bottom=0)
    axes[0, 0].set_title(f"frequency, bars ±{BAND} std", fontsize=9)
    axes[0, 1].set_title(f"damping (% of critical), bars ±{BAND} std, clipped at 0", fontsize=9)
    figure.autofmt_xdate()
    figure.tight_layout()
    return figure


def covariate_figure(tracked: pd.DataFrame, references: pd.DataFrame, covariates: pd.DataFrame):
    """Each tracked mode's frequency (rows) against each numeric column of
    ``covariates`` (``record`` and e.g. ``temperature_c``, ``wind_ms``:
    columns), estimates with bars of :data:`BAND` standard deviations.
    Returns a matplotlib ``Figure``, or None without such columns."""
    from matplotlib.figure import Figure

    columns = [c for c in covariates.columns if c != "record" and pd.api.types.is_numeric_dtype(covariates[c])]
    numbers = list(references["mode"]) if len(references) else []
    if not columns or not numbers:
        return None
    joined = tracked.merge(covariates[["record", *columns]], on="record", how="inner")
    figure = Figure(figsize=(max(6.0, min(10.0, 3.4 * len(columns) + 1)), 1.6 * len(numbers) + 0.6))
    axes = figure.subplots(len(numbers), len(columns), squeeze=False, sharex="col")
    for row, number in enumerate(numbers):
        t = joined[joined["mode"] == number]
        y, s = t["freq_hz"].to_numpy(dtype=float), t["freq_std_hz"].to_numpy(dtype=float)
        for col, name in enumerate(columns):
            ax = axes[row, col]
            ax.errorbar(t[name], y, yerr=_interval(y, s), fmt=".", ms=3, color=_colour(number),
                        elinewidth=0.8, alpha=0.8)
            ax.grid(alpha=0.3)
            ax.tick_params(labelsize=7)
            if col == 0:
                ax.set_ylabel(f"mode {number}\nHz", fontsize=8)
            if row == len(numbers) - 1:
                ax.set_xlabel(name, fontsize=8)
    figure.tight_layout()
    return figure


def drawn_shapes(shapes: pd.DataFrame, table: pd.DataFrame, shape_channels, geometry=None) -> pd.DataFrame:
    """The tracked modes' shapes on the geometry's nodes, as ``modal
    identify`` draws a roving test's (:func:`modal.setups.modes_figure`).

    Parameters
    ----------
    shapes : pandas.DataFrame
        ``mode`` and ``phi_<k>`` (real, over the channels identified): the
        mean shapes of ``tracked_shapes.csv``
        (:func:`modal.campaign._tracking.mean_shapes`).
    table : pandas.DataFrame
        The channel table (``channel``: the record's column, ``node``,
        ``x, y, z``: the measuring direction, ``quantity`` and ``unit``).
    shape_channels : sequence of int
        The record channel of each entry ``phi_<k>`` (``identify.channels``,
        or all the record's channels).
    geometry : modal.setups.Geometry, optional
        Its lines and links say which nodes are neighbours for the
        normalisation (without it: every other node).

    Returns
    -------
    pandas.DataFrame
        Long form, one row per mode and node: ``mode``, ``node``, ``x``,
        ``y``, ``z``, ``x_im``, ``y_im``, ``z_im``, ``flag``. Each channel's
        value is brought to SI by its unit; each node's motion is solved
        from its channels (:func:`modal.setups.node_shapes`) and the shape
        normalised by the roving route's rule (:func:`modal.setups.normalise`:
        largest component 1 among the nodes that agree with their
        neighbours; the others flagged).
    """
    from ..setups import node_neighbours, node_shapes, normalise, unit_factor

    position = {int(c): k for k, c in enumerate(shape_channels)}
    entries = [position[int(c)] for c in table["channel"]]
    where = [(str(node), tuple(e)) for node, e in zip(table["node"], table[["x", "y", "z"]].to_numpy(dtype=float))]
    factors = np.array([unit_factor(q, u) for q, u in zip(table["quantity"], table["unit"])])
    neighbours, rows = node_neighbours(geometry), []
    for mode, phi in zip(shapes["mode"], _phi(shapes)):
        per_node = node_shapes(where, phi[entries] * factors)
        pivot, flags = normalise(per_node, neighbours)
        for node, u in per_node.items():
            u = u / pivot
            rows.append({"mode": int(mode), "node": node, "x": u[0].real, "y": u[1].real, "z": u[2].real,
                         "x_im": u[0].imag, "y_im": u[1].imag, "z_im": u[2].imag, "flag": flags.get(node, "")})
    return pd.DataFrame(rows, columns=["mode", "node", "x", "y", "z", "x_im", "y_im", "z_im", "flag"])


def _phi(shapes: pd.DataFrame) -> np.ndarray:
    columns = sorted((c for c in shapes.columns if str(c).startswith("phi_")), key=lambda c: int(c[4:]))
    return shapes[columns].to_numpy(dtype=float)


def shapes_figure(geometry, table: pd.DataFrame, shape_channels, shapes: pd.DataFrame):
    """Each tracked mode's mean shape drawn on the structure
    (:func:`drawn_shapes`, :func:`modal.setups.modes_figure`), titled with its
    mean frequency and the number of estimates averaged; a matplotlib
    ``Figure``, or None when no mode was tracked."""
    from ..setups import modes_figure

    if shapes.empty:
        return None
    titles = {int(row.mode): f"mode {int(row.mode)}: {row.freq_hz:.4g} Hz (mean of {int(row.n_estimates)})"
              for row in shapes.itertuples()}
    return modes_figure(geometry, drawn_shapes(shapes, table, shape_channels, geometry), titles,
                        columns=min(3, len(titles)))


def _png(figure) -> str:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=100)
    return base64.b64encode(buffer.getvalue()).decode()


def _img(figure, alt: str) -> str:
    return f"<img alt='{html.escape(alt)}' style='max-width:100%' src='data:image/png;base64,{_png(figure)}'>"


def _versions() -> str:
    names = ["modal-identification", "numpy", "scipy", "pandas", "matplotlib", "snakemake"]
    found = []
    for name in names:
        try:
            found.append(f"{name} {version(name)}")
        except PackageNotFoundError:
            pass
    return f"Python {platform.python_version()}; " + ", ".join(found)


def mode_summary(tracked: pd.DataFrame, references: pd.DataFrame, n_identified: int) -> pd.DataFrame:
    """One row per reference mode: its frequency (and the range the campaign
    observed, when known), in how many records and what share of the
    identified ones it was tracked, the median std of a frequency estimate,
    the mean damping and the median std of a damping estimate in %, and the
    median MAC with the reference shape."""
    summary = references.drop(columns=[c for c in references.columns if c.startswith("phi_") or c == "n_records"])
    summary = summary.rename(columns={"freq_hz": "reference_hz"})
    if len(tracked):
        stats = tracked.groupby("mode").agg(tracked_in=("record", "nunique"),
                                            median_freq_std_hz=("freq_std_hz", "median"),
                                            damping_mean_pct=("damping", "mean"),
                                            median_damping_std_pct=("damping_std", "median"),
                                            median_mac=("mac", "median"))
        stats[["damping_mean_pct", "median_damping_std_pct"]] *= PERCENT
        summary = summary.merge(stats, left_on="mode", right_index=True, how="left")
        summary["tracked_in"] = summary["tracked_in"].fillna(0).astype(int)
        summary.insert(summary.columns.get_loc("tracked_in") + 1, "tracked_share_pct",
                       PERCENT * summary["tracked_in"] / max(n_identified, 1))
    return summary


def campaign_report(path, tracked, untracked, failed, references, n_records, config_text, command,
                    covariates: pd.DataFrame | None = None, geometry=None, shapes: pd.DataFrame | None = None) -> None:
    """Write the report to ``path``: counts, the reference modes with what
    share of records holds each, every identified mode over time, each
    tracked mode's frequency and damping over time, its frequency against
    each numeric column of ``covariates`` (``record`` and e.g. the index's
    temperature; none: no such plot), each tracked mode's mean shape drawn
    on the structure (``geometry``: the :class:`modal.setups.Geometry`, the
    channel table and the record channel of each shape entry;
    ``shapes``: the mean shapes, :func:`shapes_figure`; either None: no
    drawing), the failed records and why, and the provenance (command,
    configuration, versions)."""
    n_failed = failed["record"].nunique() if len(failed) else 0
    n_identified = n_records - n_failed
    summary = mode_summary(tracked, references, n_identified)
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>Monitoring campaign</title>",
        "<style>body{font-family:sans-serif;max-width:1100px;margin:1em auto;font-size:14px}"
        "table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
        "pre{background:#f6f6f6;padding:6px;font-size:11px;white-space:pre-wrap}</style></head><body>",
        "<h1>Monitoring campaign</h1>",
        f"<p><b>{n_records}</b> records: <b>{n_identified}</b> identified, <b>{n_failed}</b> failed; "
        f"<b>{len(references)}</b> tracked modes, {len(tracked)} tracked estimates, {len(untracked)} untracked "
        f"modes. Damping in % of critical throughout this page (the CSV files keep the ratio); bars "
        f"±{BAND} standard deviations of each estimate, clipped at zero.</p>",
        "<h2>Every identified mode</h2>",
        "<p>Tracked modes coloured by their number, modes whose shape or frequency matched no reference grey.</p>",
        _img(overview_figure(tracked, untracked, references), "every identified mode over time"),
        "<h2>Tracked modes</h2>",
        "<p><i>tracked_share_pct</i>: share of the identified records in which the mode was tracked; "
        "<i>freq_low_hz</i>-<i>freq_high_hz</i>: the frequencies the campaign observed for it (the tracking gate "
        "widens them by <code>freq_rtol</code>).</p>",
        summary.to_html(index=False, float_format=lambda v: f"{v:.5g}", border=0, na_rep="–"),
        _img(tracking_figure(tracked, references), "tracked modes over time"),
    ]
    if covariates is not None:
        figure = covariate_figure(tracked, references, pd.DataFrame(covariates))
        if figure is not None:
            parts += ["<h2>Frequency against the index's columns</h2>",
                      _img(figure, "frequency against the index's columns")]
    if geometry is not None and shapes is not None:
        figure = shapes_figure(*geometry, shapes)
        parts += ["<h2>Tracked shapes</h2>",
                  "<p>Each tracked mode's mean shape over the records it was tracked in, drawn on the structure: "
                  "undeformed dashed, measured nodes red, the largest component of the nodes that agree with "
                  "the others 1.</p>",
                  _img(figure, "tracked shapes on the structure") if figure is not None else "<p>None tracked.</p>"]
    parts += [
        "<h2>Failed records</h2>",
        (failed.to_html(index=False, border=0) if n_failed else "<p>None.</p>"),
        "<h2>Provenance</h2>", f"<p>Command: <code>{html.escape(command)}</code></p>",
        f"<p>{html.escape(_versions())}</p>", f"<pre>{html.escape(config_text)}</pre>",
        "</body></html>",
    ]
    with open(path, "w", encoding="utf-8") as out:
        out.write(printable("\n".join(parts)))
