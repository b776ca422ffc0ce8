"""The steps of the campaign workflow (``modal/campaign/Snakefile``) after
the chunks: gather, track, report."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from ._jobs import gather
from ._tracking import TRACKED_COLUMNS, mean_shapes, observed_ranges, read_reference_modes, reference_modes, track_modes


def track_campaign(modes_files, failed_files, n_records: int | pd.DataFrame, tracking: dict, folder) -> None:
    """Gather the chunks' files and write ``folder/modes.csv`` (every mode of
    every record), ``failed.csv``, ``references.csv`` (from
    ``tracking["reference_modes"]`` or :func:`reference_modes`),
    ``tracked.csv`` and ``untracked.csv`` (:func:`track_modes`), and
    ``tracked_shapes.csv`` (each reference mode's mean shape over its tracked
    estimates, :func:`modal.campaign._tracking.mean_shapes`). Given
    references get the frequency range the campaign observed for each
    (:func:`modal.campaign._tracking.observed_ranges`), as built ones have it.

    ``n_records`` is the number of records in the campaign (the index itself,
    as :func:`modal.campaign.read_campaign` returns it, is taken too: its length);
    built references need ``tracking["min_share"]`` of those identified
    (the failed ones, listed in ``failed_files``, left out)."""
    folder = Path(folder)
    if isinstance(n_records, pd.DataFrame):
        n_records = len(n_records)
    modes, failed = gather(modes_files, failed_files)
    if tracking.get("reference_modes"):
        references = observed_ranges(modes, read_reference_modes(tracking["reference_modes"]),
                                     tracking["freq_rtol"], tracking["mac_min"])
    else:
        # min_share of the records identified: failed and missing ones show no mode
        references = reference_modes(modes, n_records - failed["record"].nunique(), tracking["freq_rtol"],
                                     tracking["min_share"], tracking["mac_min"])
    tracked, untracked = track_modes(modes, references, tracking["freq_rtol"], tracking["mac_min"], shapes=True)
    mean_shapes(tracked, references).to_csv(folder / "tracked_shapes.csv", index=False, float_format="%.8g")
    tracked = tracked[TRACKED_COLUMNS]
    modes.to_csv(folder / "modes.csv", index=False, float_format="%.8g")
    failed.to_csv(folder / "failed.csv", index=False)
    references.to_csv(folder / "references.csv", index=False, float_format="%.8g")
    tracked.to_csv(folder / "tracked.csv", index=False, float_format="%.8g")
    untracked.to_csv(folder / "untracked.csv", index=False, float_format="%.8g")


def report_campaign(folder, n_records: int, campaign_path, command: str, covariates=None, geometry=None) -> None:
    """``folder/report.html`` from the files :func:`track_campaign` wrote.

    ``covariates``: per record, quantities to plot the frequencies against
    (the index's other columns, e.g. ``temperature_c``): a DataFrame or a
    mapping of lists with a ``record`` column, or None. ``geometry``: the
    campaign's ``geometry`` as :func:`modal.campaign.read_campaign` checked
    it (``folder``, ``table``, ``shape_channels``), to draw each tracked
    mode's mean shape (``tracked_shapes.csv``) on the structure; None: no
    drawing."""
    from ._report import campaign_report  # matplotlib: only the report job needs it

    folder = Path(folder)
    read = {name: pd.read_csv(folder / f"{name}.csv") for name in ("tracked", "untracked", "failed", "references")}
    read["tracked"]["time"] = pd.to_datetime(read["tracked"]["time"])
    drawing = shapes = None
    if geometry and geometry.get("table"):
        from ..setups import read_geometry

        drawing = (read_geometry(geometry["folder"]), pd.DataFrame(geometry["table"]), geometry["shape_channels"])
        shapes = pd.read_csv(folder / "tracked_shapes.csv")
    campaign_report(folder / "report.html", read["tracked"], read["untracked"], read["failed"], read["references"],
                    n_records, Path(campaign_path).read_text(), command,
                    covariates=None if covariates is None else pd.DataFrame(covariates), geometry=drawing,
                    shapes=shapes)
