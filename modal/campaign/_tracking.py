"""Modes tracked over a campaign: a stable numbering by matching each
record's modes to reference modes (frequency and MAC), the references given
or built from the campaign itself."""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from ..identification import mac
from ._jobs import shape_matrix

TRACKED_COLUMNS = ["record", "time", "mode", "freq_hz", "freq_std_hz", "damping", "damping_std", "mac"]
#: Shapes compared when a reference shape is chosen (the medoid): at most
#: this many of a cluster's, evenly spread over it, so a 10,000-record
#: campaign compares 400 x 400 shapes, not 10^8 pairs.
MEDOID_SAMPLE = 400


def read_reference_modes(path) -> pd.DataFrame:
    """Reference modes from a CSV with ``freq_hz`` and shape columns
    ``phi_<...>`` (in file order), e.g. a ``modes.csv`` of ``modal identify``;
    renumbered 1, 2, ... by frequency with shape columns ``phi_0``, ...."""
    table = pd.read_csv(path)
    columns = [c for c in table.columns if str(c).startswith("phi_")]
    if "freq_hz" not in table.columns or not columns:
        raise ValueError(f"{path}: reference modes need a freq_hz column and shape columns phi_...")
    table = table.sort_values("freq_hz", kind="stable").reset_index(drop=True)
    out = pd.DataFrame({"mode": np.arange(1, len(table) + 1), "freq_hz": table["freq_hz"].astype(float)})
    for k, c in enumerate(columns):
        out[f"phi_{k}"] = table[c].astype(float)
    return out


def reference_modes(modes: pd.DataFrame, n_records: int, gap_rtol=0.01, min_share=0.3) -> pd.DataFrame:
    """Reference modes built from the campaign's own modes.

    All identified frequencies, sorted, are cut where two neighbours lie more
    than ``gap_rtol`` apart (a mode that drifts with temperature stays one
    band); a band holding modes of at least ``min_share`` of the
    ``n_records`` records is a reference mode: its median frequency and its
    medoid shape (largest summed MAC with the band's others). Modes closer
    than ``gap_rtol`` that overlap in frequency over the campaign fall into
    one band: give ``reference_modes`` in the configuration for them.
    """
    columns = ["mode", "freq_hz", "n_records"]
    if modes.empty:
        return pd.DataFrame(columns=columns)
    ordered = modes.sort_values("freq_hz", kind="stable").reset_index(drop=True)
    f = ordered["freq_hz"].to_numpy(dtype=float)
    band = np.concatenate([[0], np.cumsum(f[1:] / f[:-1] - 1 > gap_rtol)])
    shapes = shape_matrix(ordered)
    rows = []
    for b in np.unique(band):
        members = np.flatnonzero(band == b)
        seen = ordered["record"].iloc[members].nunique()
        if seen < min_share * n_records:
            continue
        sample = members[np.linspace(0, len(members) - 1, min(len(members), MEDOID_SAMPLE)).astype(int)]
        medoid = sample[int(np.argmax(mac(shapes[:, sample], shapes[:, sample]).sum(axis=0)))]
        row = {"freq_hz": float(np.median(f[members])), "n_records": int(seen)}
        row.update({f"phi_{c}": v for c, v in enumerate(shapes[:, medoid])})
        rows.append(row)
    table = pd.DataFrame(rows)
    if table.empty:
        return pd.DataFrame(columns=columns)
    table.insert(0, "mode", np.arange(1, len(table) + 1))
    return table


def track_modes(modes: pd.DataFrame, references: pd.DataFrame, freq_rtol=0.05, mac_min=0.8):
    """Each record's modes matched one to one to the ``references``.

    A record's mode may match a reference within ``freq_rtol`` (relative)
    and with MAC >= ``mac_min``; among the allowed pairs the assignment
    minimising ``|f - f_ref| / (freq_rtol f_ref) + (1 - MAC) / (1 - mac_min)``
    is taken (scipy's ``linear_sum_assignment``).

    Returns
    -------
    tracked : pandas.DataFrame
        :data:`TRACKED_COLUMNS`: ``mode`` is the reference's number, ``mac``
        the MAC with its shape.
    untracked : pandas.DataFrame
        The modes that matched no reference (their record-local numbers).
    """
    if modes.empty or references.empty:
        return pd.DataFrame(columns=TRACKED_COLUMNS), modes.copy()
    ref_shapes = shape_matrix(references)
    shapes = shape_matrix(modes)
    if shapes.shape[0] != ref_shapes.shape[0]:
        raise ValueError(f"the records' shapes have {shapes.shape[0]} channels, the reference modes "
                         f"{ref_shapes.shape[0]}: track the same channels")
    f_ref = references["freq_hz"].to_numpy(dtype=float)
    f = modes["freq_hz"].to_numpy(dtype=float)
    tracked_rows, matched = [], np.zeros(len(modes), dtype=bool)
    for _, rows in modes.groupby("record", sort=False).indices.items():
        gap = np.abs(f[rows, None] - f_ref[None, :]) / f_ref[None, :]
        similarity = mac(shapes[:, rows], ref_shapes)
        allowed = (gap <= freq_rtol) & (similarity >= mac_min)
        if not allowed.any():
            continue
        cost = np.where(allowed, gap / freq_rtol + (1 - similarity) / max(1 - mac_min, 1e-9), 1e6)
        for i, j in zip(*linear_sum_assignment(cost)):
            if allowed[i, j]:
                matched[rows[i]] = True
                tracked_rows.append((rows[i], int(references["mode"].iloc[j]), float(similarity[i, j])))
    picked = [r for r, _, _ in tracked_rows]
    tracked = modes.iloc[picked][["record", "time", "freq_hz", "freq_std_hz", "damping", "damping_std"]].copy()
    tracked.insert(2, "mode", [m for _, m, _ in tracked_rows])
    tracked["mac"] = [s for _, _, s in tracked_rows]
    tracked = tracked.sort_values(["time", "record", "mode"], kind="stable").reset_index(drop=True)
    return tracked[TRACKED_COLUMNS], modes[~matched].reset_index(drop=True)
