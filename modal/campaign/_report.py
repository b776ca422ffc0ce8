"""A campaign's report: one self-contained HTML page with the tracked modes
over time and their uncertainty, the failed records and the provenance."""

from __future__ import annotations

import base64
import html
import io
import platform
from importlib.metadata import PackageNotFoundError, version

import pandas as pd

#: Half-width of the bands drawn around each estimate, in standard deviations
#: (a 95 % interval for a normal estimate).
BAND = 1.96


def tracking_figure(tracked: pd.DataFrame, references: pd.DataFrame):
    """Frequency (left) and damping (right) of each tracked mode over time,
    each estimate with a band of :data:`BAND` standard deviations. Returns
    a matplotlib ``Figure``."""
    from matplotlib.figure import Figure

    numbers = list(references["mode"]) if len(references) else []
    figure = Figure(figsize=(10, 1.9 * max(1, len(numbers)) + 0.6))
    axes = figure.subplots(max(1, len(numbers)), 2, squeeze=False, sharex=True)
    for row, number in enumerate(numbers):
        t = tracked[tracked["mode"] == number].sort_values("time")
        for ax, value, std, scale, label in ((axes[row, 0], "freq_hz", "freq_std_hz", 1.0, "Hz"),
                                             (axes[row, 1], "damping", "damping_std", 100.0, "damping %")):
            y, s = scale * t[value].to_numpy(dtype=float), scale * t[std].to_numpy(dtype=float)
            ax.fill_between(t["time"], y - BAND * s, y + BAND * s, color="C0", alpha=0.25, lw=0)
            ax.plot(t["time"], y, ".", ms=2.5, color="C0")
            ax.set_ylabel(f"mode {number}\n{label}", fontsize=8)
            ax.tick_params(labelsize=7)
    axes[0, 0].set_title(f"frequency, band ±{BAND} std", fontsize=9)
    axes[0, 1].set_title(f"damping ratio, band ±{BAND} std", fontsize=9)
    figure.autofmt_xdate()
    figure.tight_layout()
    return figure


def _png(figure) -> str:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=100)
    return base64.b64encode(buffer.getvalue()).decode()


def _versions() -> str:
    names = ["modal-identification", "numpy", "scipy", "pandas", "matplotlib", "snakemake"]
    found = []
    for name in names:
        try:
            found.append(f"{name} {version(name)}")
        except PackageNotFoundError:
            pass
    return f"Python {platform.python_version()}; " + ", ".join(found)


def campaign_report(path, tracked, untracked, failed, references, n_records, config_text, command) -> None:
    """Write the report to ``path``: counts, the reference modes with what
    share of records holds each, the tracking figure, the failed records and
    why, and the provenance (command, configuration, versions)."""
    summary = references.drop(columns=[c for c in references.columns if c.startswith("phi_")])
    if len(tracked):
        stats = tracked.groupby("mode").agg(tracked_in=("record", "nunique"), freq_mean_hz=("freq_hz", "mean"),
                                            freq_min_hz=("freq_hz", "min"), freq_max_hz=("freq_hz", "max"),
                                            median_freq_std_hz=("freq_std_hz", "median"),
                                            damping_mean=("damping", "mean"), median_mac=("mac", "median"))
        summary = summary.merge(stats, left_on="mode", right_index=True, how="left")
    n_failed = failed["record"].nunique() if len(failed) else 0
    figure = tracking_figure(tracked, references)
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'><title>Monitoring campaign</title>",
        "<style>body{font-family:sans-serif;max-width:1100px;margin:1em auto;font-size:14px}"
        "table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
        "pre{background:#f6f6f6;padding:6px;font-size:11px;white-space:pre-wrap}</style></head><body>",
        "<h1>Monitoring campaign</h1>",
        f"<p><b>{n_records}</b> records: <b>{n_records - n_failed}</b> identified, <b>{n_failed}</b> failed; "
        f"<b>{len(references)}</b> tracked modes, {len(tracked)} tracked estimates, {len(untracked)} untracked "
        f"modes. Damping as a ratio to critical; bands ±{BAND} standard deviations of each estimate.</p>",
        "<h2>Tracked modes</h2>", summary.to_html(index=False, float_format=lambda v: f"{v:.5g}", border=0),
        f"<img alt='tracked modes over time' style='max-width:100%' src='data:image/png;base64,{_png(figure)}'>",
        "<h2>Failed records</h2>",
        (failed.to_html(index=False, border=0) if n_failed else "<p>None.</p>"),
        "<h2>Provenance</h2>", f"<p>Command: <code>{html.escape(command)}</code></p>",
        f"<p>{html.escape(_versions())}</p>", f"<pre>{html.escape(config_text)}</pre>",
        "</body></html>",
    ]
    with open(path, "w", encoding="utf-8") as out:
        out.write("\n".join(parts))

