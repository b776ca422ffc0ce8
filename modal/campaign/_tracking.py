"""Modes tracked over a campaign: a stable numbering by matching each
record's modes to reference modes by shape (MAC) within the frequencies the
campaign observed for each, the references given or built from the campaign
itself by clustering its estimates on frequency and shape together."""

from __future__ import annotations

import numpy as np
import pandas as pd
from scipy.optimize import linear_sum_assignment

from ..identification import mac, normalise_shapes
from ._jobs import shape_matrix

TRACKED_COLUMNS = ["record", "time", "mode", "freq_hz", "freq_std_hz", "damping", "damping_std", "mac"]
#: In the assignment a relative frequency gap to the reference of 1 % costs as
#: much as 0.001 of MAC, about the scatter of a well-identified shape's MAC
#: between records: two estimates of one shape (a mode and a spurious row of
#: its shape 2.6 % off, MAC 0.9994 and 0.9997) go by frequency, estimates of
#: different shapes by MAC (0.85 at the reference frequency loses to 0.99 4 %
#: off as long as this stays below 3.5).
FREQ_WEIGHT = 0.1
#: Shapes compared when a reference shape is chosen (the medoid): at most
#: this many of a cluster's, evenly spread over it, so a 10,000-record
#: campaign compares 400 x 400 shapes, not 10^8 pairs.
MEDOID_SAMPLE = 400
#: Records whose modes build the references: at most this many, evenly
#: spread over the campaign's time, so that the clustering's pairs stay
#: some 10^5 to 10^6 whatever the campaign's length (a year of hourly records
#: still spans every temperature the year saw).
REFERENCE_SAMPLE = 1000
#: Two clusters of one shape whose frequency ranges meet are one mode split
#: by a few records that show it twice (two poles of one mode), when the
#: records they share are at most this share of the smaller one's.
SPLIT_SHARE = 0.2
#: Columns of a reference's frequency range: the lowest and highest frequency
#: the campaign observed for it (:func:`observed_ranges`).
RANGE_COLUMNS = ["freq_low_hz", "freq_high_hz"]


def read_reference_modes(path) -> pd.DataFrame:
    """Reference modes from a CSV with ``freq_hz`` and shape columns
    ``phi_<...>`` (in file order), e.g. a ``modes.csv`` of ``modal identify``;
    renumbered 1, 2, ... by frequency with shape columns ``phi_0``, ....

    Raises ``ValueError`` naming the file (and the row) when it cannot be
    read, lacks those columns or any mode, holds a frequency that is not a
    positive number or a shape entry that is not a finite number (an empty
    cell), or gives one mode twice (a row repeated)."""
    try:
        table = pd.read_csv(path)
    except (OSError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise ValueError(f"{path}: cannot read the reference modes: {exc}") from None
    columns = [c for c in table.columns if str(c).startswith("phi_")]
    if "freq_hz" not in table.columns or not columns:
        raise ValueError(f"{path}: reference modes need a freq_hz column and shape columns phi_...; it has "
                         f"{', '.join(map(str, table.columns)) or 'none'}")
    if table.empty:
        raise ValueError(f"{path}: no reference mode (a header and no row)")
    values = table[["freq_hz", *columns]].apply(pd.to_numeric, errors="coerce")
    bad = ~np.isfinite(values.to_numpy(dtype=float)) | (values[["freq_hz"]].reindex(columns=values.columns)
                                                        .fillna(1).to_numpy() <= 0)
    if bad.any():
        row, column = (int(k) for k in np.argwhere(bad)[0])
        given = table[values.columns[column]].iloc[row]
        what = "a positive frequency" if column == 0 else "a finite number"
        shown = "(empty)" if pd.isna(given) else f"'{given}'"
        raise ValueError(f"{path}: row {row + 2}: {values.columns[column]} {shown} is not {what}")
    repeated = values.duplicated()
    if repeated.any():
        row = int(np.flatnonzero(repeated.to_numpy())[0])
        first = int(np.flatnonzero((values == values.iloc[row]).all(axis=1).to_numpy())[0])
        raise ValueError(f"{path}: row {row + 2} repeats row {first + 2}: give each mode once")
    values = values.sort_values("freq_hz", kind="stable").reset_index(drop=True)
    out = pd.DataFrame({"mode": np.arange(1, len(values) + 1), "freq_hz": values["freq_hz"]})
    for k, c in enumerate(columns):
        out[f"phi_{k}"] = values[c]
    return out


def _unit_shapes(shapes: np.ndarray) -> np.ndarray:
    norms = np.linalg.norm(shapes, axis=0)
    return shapes / np.where(norms > 0, norms, 1.0)


def _neighbours(f: np.ndarray, unit: np.ndarray, gap_rtol: float, mac_min: float):
    """Pairs ``(i, j)`` of estimates (indices into ``f``, sorted ascending)
    with ``f_j / f_i - 1 <= gap_rtol`` and MAC >= ``mac_min``, and their
    distance ``(f_j / f_i - 1) / gap_rtol + (1 - MAC) / (1 - mac_min)``
    (each term at most 1 for a neighbour)."""
    first, second, distance = [], [], []
    for offset in range(1, len(f)):
        i = np.arange(len(f) - offset)
        j = i + offset
        gap = f[j] / f[i] - 1
        within = gap <= gap_rtol
        if not within.any():
            break
        i, j, gap = i[within], j[within], gap[within]
        similarity = np.abs(np.einsum("ck,ck->k", unit[:, i].conj(), unit[:, j])) ** 2
        close = similarity >= mac_min
        first.append(i[close])
        second.append(j[close])
        distance.append(gap[close] / gap_rtol + (1 - similarity[close]) / max(1 - mac_min, 1e-9))
    if not first:
        return np.zeros(0, int), np.zeros(0, int), np.zeros(0)
    return np.concatenate(first), np.concatenate(second), np.concatenate(distance)


def _clusters(f, unit, record, gap_rtol, mac_min) -> np.ndarray:
    """Cluster labels of the estimates: single linkage over neighbours
    (:func:`_neighbours`), nearest pairs first, where two clusters that
    hold estimates of the same record are never merged (one record shows a
    mode once: two of its estimates are two modes). That is what keeps two
    modes apart where their frequencies cross and a few estimates with
    blended shapes lie between them."""
    first, second, distance = _neighbours(f, unit, gap_rtol, mac_min)
    parent = list(range(len(f)))
    records = [{r} for r in record]

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for k in np.argsort(distance, kind="stable"):
        a, b = root(int(first[k])), root(int(second[k]))
        if a == b or not records[a].isdisjoint(records[b]):
            continue
        if len(records[a]) < len(records[b]):
            a, b = b, a
        parent[b] = a
        records[a] |= records[b]
        records[b] = set()
    return np.array([root(i) for i in range(len(f))])


def _medoid(shapes: np.ndarray, members: np.ndarray) -> int:
    """The member of largest summed MAC with the others (on at most
    :data:`MEDOID_SAMPLE` of them, evenly spread; of equal sums, the first
    member)."""
    sample = members[np.linspace(0, len(members) - 1, min(len(members), MEDOID_SAMPLE)).astype(int)]
    return int(sample[int(np.argmax(mac(shapes[:, sample], shapes[:, sample]).sum(axis=0)))])


def _join_split_modes(label, f, shapes, record, freq_rtol, mac_min, damping=None) -> np.ndarray:
    """Labels with the clusters of one mode joined: largest first, a cluster
    joins the larger one whose medoid shape matches its own best (MAC >=
    ``mac_min``) when their frequency ranges lie within ``freq_rtol`` of
    each other and

    - they share at most :data:`SPLIT_SHARE` of its records (the single
      linkage never merges clusters sharing a record, so one record holding
      a mode twice splits it), or
    - they lie within one resonance peak, whatever records they share: their
      median frequencies at most the sum of their half-power half-widths
      apart, ``|f_a - f_b| <= zeta_a f_a + zeta_b f_b`` (median frequency
      and damping ratio of each; ``damping``: each estimate's; without it,
      this rule is not applied). One shape within one peak is one mode
      whose record-by-record identification sometimes gives a second
      estimate beside the first (as
      :func:`modal.stabilisation` states a second estimate within the
      half-power band of one record); modes of one shape closer than that
      are not told apart by their spectra either.

    Modes that cross keep their medoids' MAC near 0 and stay apart."""
    zeta = np.zeros(len(f)) if damping is None else np.nan_to_num(np.asarray(damping, dtype=float))
    clusters = [np.flatnonzero(label == c) for c in np.unique(label)]
    clusters.sort(key=len, reverse=True)
    kept = []  # (members, medoid, low, high, records, median frequency, half-power half-width)
    for members in clusters:
        medoid, low, high = _medoid(shapes, members), f[members].min(), f[members].max()
        records = set(record[members])
        centre = float(np.median(f[members]))
        half_width = float(np.median(zeta[members])) * centre
        best, best_mac = None, mac_min
        for k, (_, other, other_low, other_high, other_records, other_centre, other_half) in enumerate(kept):
            if low > other_high * (1 + freq_rtol) or high < other_low * (1 - freq_rtol):
                continue
            one_peak = damping is not None and abs(centre - other_centre) <= half_width + other_half
            if not one_peak and len(records & other_records) > SPLIT_SHARE * len(records):
                continue
            similarity = float(mac(shapes[:, [medoid]], shapes[:, [other]])[0, 0])
            if similarity >= best_mac:
                best, best_mac = k, similarity
        if best is None:
            kept.append((members, medoid, low, high, records, centre, half_width))
        else:
            joined, other, other_low, other_high, other_records, other_centre, other_half = kept[best]
            kept[best] = (np.concatenate([joined, members]), other, min(low, other_low), max(high, other_high),
                          other_records | records, other_centre, other_half)
    joined = np.empty(len(f), dtype=int)
    for k, (members, *_) in enumerate(kept):
        joined[members] = k
    return joined


def reference_modes(modes: pd.DataFrame, n_records: int, freq_rtol=0.05, min_share=0.3,
                    mac_min=0.8) -> pd.DataFrame:
    """Reference modes built from the campaign's own modes, by frequency and
    shape together.

    Two estimates are neighbours when their frequencies lie within
    ``freq_rtol`` (relative) and their shapes have MAC >= ``mac_min``; the
    estimates are clustered by single linkage over neighbours, nearest first
    (distance: the relative frequency difference over ``freq_rtol`` plus
    ``1 - MAC`` over ``1 - mac_min``), never merging two clusters that share
    a record (a record shows a mode once); clusters of one shape whose
    frequencies meet and that share only a few records (a mode shown twice
    in those: :data:`SPLIT_SHARE`), or that lie within one resonance peak
    (median frequencies at most the sum of their half-power half-widths
    apart: a mode some records show twice, a second estimate beside the
    first), are joined after. A mode drifting with
    the temperature is one chain of
    neighbours, however sparse the records (a step of up to ``freq_rtol``
    between neighbours); two modes that cross in frequency stay apart when their
    shapes differ (their MAC is below ``mac_min``), even when a few blended
    estimates lie between them. A cluster holding modes of at least
    ``min_share`` of the ``n_records`` records is a reference mode: its
    median frequency, its medoid shape (largest summed MAC with the
    cluster's others) and its frequency range (:data:`RANGE_COLUMNS`).

    Campaigns of more than :data:`REFERENCE_SAMPLE` records are clustered on
    that many records, evenly spread in time (``n_records`` then counts in
    the same proportion).

    Returns
    -------
    pandas.DataFrame
        ``mode`` (1, 2, ... by frequency), ``freq_hz``, ``n_records`` (the
        records holding it, among those clustered), ``freq_low_hz``,
        ``freq_high_hz``, ``phi_0``, ``phi_1``, ....
    """
    columns = ["mode", "freq_hz", "n_records", *RANGE_COLUMNS]
    if modes.empty:
        return pd.DataFrame(columns=columns)
    names = modes.sort_values("time", kind="stable")["record"].drop_duplicates().to_numpy()
    if len(names) > REFERENCE_SAMPLE:
        kept = names[np.linspace(0, len(names) - 1, REFERENCE_SAMPLE).round().astype(int)]
        n_records = n_records * len(kept) / len(names)
        modes = modes[modes["record"].isin(set(kept))]
    ordered = modes.sort_values("freq_hz", kind="stable").reset_index(drop=True)
    f = ordered["freq_hz"].to_numpy(dtype=float)
    shapes = shape_matrix(ordered)
    record = ordered["record"].to_numpy()
    label = _clusters(f, _unit_shapes(shapes), record, freq_rtol, mac_min)
    damping = ordered["damping"].to_numpy(dtype=float) if "damping" in ordered else None
    label = _join_split_modes(label, f, shapes, record, freq_rtol, mac_min, damping)
    rows = []
    for cluster in np.unique(label):
        members = np.flatnonzero(label == cluster)
        seen = ordered["record"].iloc[members].nunique()
        if seen / max(n_records, 1) < min_share:  # not seen < min_share * n_records: 0.3 * 10 is 3.0000000000000004
            continue
        medoid = _medoid(shapes, members)
        row = {"freq_hz": float(np.median(f[members])), "n_records": int(seen),
               **dict(zip(RANGE_COLUMNS, (float(f[members].min()), float(f[members].max()))))}
        row.update({f"phi_{c}": v for c, v in enumerate(shapes[:, medoid])})
        rows.append(row)
    if not rows:
        return pd.DataFrame(columns=columns)
    table = pd.DataFrame(rows).sort_values("freq_hz", kind="stable").reset_index(drop=True)
    table.insert(0, "mode", np.arange(1, len(table) + 1))
    return table


def observed_ranges(modes: pd.DataFrame, references: pd.DataFrame, freq_rtol=0.05, mac_min=0.8) -> pd.DataFrame:
    """The frequencies the campaign observed for each reference mode: of the
    estimates whose shape matches the reference's (MAC >= ``mac_min``),
    sorted by frequency and cut where neighbours lie more than ``freq_rtol``
    apart, the band nearest the reference frequency, if within ``freq_rtol``
    of it. A mode drifting with the temperature, however far, is one band;
    another mode of similar shape elsewhere in frequency is another.

    Returns ``references`` with :data:`RANGE_COLUMNS` (the band's lowest and
    highest frequency, the reference frequency included)."""
    out = references.copy()
    f_ref = references["freq_hz"].to_numpy(dtype=float)
    low, high = f_ref.copy(), f_ref.copy()
    if len(modes) and len(references):
        f = modes["freq_hz"].to_numpy(dtype=float)
        similarity = mac(shape_matrix(modes), shape_matrix(references))
        for j, centre in enumerate(f_ref):
            matching = np.sort(f[similarity[:, j] >= mac_min])
            if not len(matching):
                continue
            band = np.concatenate([[0], np.cumsum(matching[1:] / matching[:-1] - 1 > freq_rtol)])
            nearest = int(np.argmin(np.abs(matching - centre)))
            if abs(matching[nearest] / centre - 1) > freq_rtol:
                continue
            members = matching[band == band[nearest]]
            low[j], high[j] = min(members.min(), centre), max(members.max(), centre)
    out[RANGE_COLUMNS[0]], out[RANGE_COLUMNS[1]] = low, high
    return out


def track_modes(modes: pd.DataFrame, references: pd.DataFrame, freq_rtol=0.05, mac_min=0.8, shapes=False):
    """Each record's modes matched one to one to the ``references``, by shape.

    A record's mode may match a reference when its shape does (MAC >=
    ``mac_min``) and its frequency lies within ``freq_rtol`` (relative) of
    the frequencies the campaign observed for that mode
    (:data:`RANGE_COLUMNS` of the references, as :func:`reference_modes`
    builds them; else :func:`observed_ranges`), so a mode is followed
    however far it drifts, and a mode whose shape matches no reference stays
    untracked whatever its frequency. Among the allowed pairs the assignment
    of least summed cost ``1 - MAC + FREQ_WEIGHT |f / f_ref - 1|`` is taken
    (scipy's ``linear_sum_assignment``): the MAC decides between different
    shapes, the frequency between estimates of one shape
    (:data:`FREQ_WEIGHT`).

    ``shapes``: also give each tracked estimate's shape (its ``phi_<k>``
    columns after :data:`TRACKED_COLUMNS`), e.g. for :func:`mean_shapes`.

    Returns
    -------
    tracked : pandas.DataFrame
        :data:`TRACKED_COLUMNS`: ``mode`` is the reference's number, ``mac``
        the MAC with its shape.
    untracked : pandas.DataFrame
        The modes that matched no reference (their record-local numbers).
    """
    phi = [c for c in modes.columns if str(c).startswith("phi_")] if shapes else []
    if modes.empty or references.empty:
        return pd.DataFrame(columns=TRACKED_COLUMNS + phi), modes.copy()
    ref_shapes = shape_matrix(references)
    estimates = shape_matrix(modes)
    if estimates.shape[0] != ref_shapes.shape[0]:
        raise ValueError(f"the records' shapes have {estimates.shape[0]} channels, the reference modes "
                         f"{ref_shapes.shape[0]}: track the same channels")
    if not set(RANGE_COLUMNS) <= set(references.columns):
        references = observed_ranges(modes, references, freq_rtol, mac_min)
    f_ref = references["freq_hz"].to_numpy(dtype=float)
    low = references[RANGE_COLUMNS[0]].to_numpy(dtype=float) * (1 - freq_rtol)
    high = references[RANGE_COLUMNS[1]].to_numpy(dtype=float) * (1 + freq_rtol)
    f = modes["freq_hz"].to_numpy(dtype=float)
    tracked_rows, matched = [], np.zeros(len(modes), dtype=bool)
    for _, rows in modes.groupby("record", sort=False).indices.items():
        similarity = mac(estimates[:, rows], ref_shapes)
        within = (f[rows, None] >= low[None, :]) & (f[rows, None] <= high[None, :])
        allowed = within & (similarity >= mac_min)
        if not allowed.any():
            continue
        gap = np.minimum(np.abs(f[rows, None] / f_ref[None, :] - 1), 1.0)
        cost = np.where(allowed, 1 - similarity + FREQ_WEIGHT * gap, 1e6)
        for i, j in zip(*linear_sum_assignment(cost)):
            if allowed[i, j]:
                matched[rows[i]] = True
                tracked_rows.append((rows[i], int(references["mode"].iloc[j]), float(similarity[i, j])))
    picked = [r for r, _, _ in tracked_rows]
    tracked = modes.iloc[picked][["record", "time", "freq_hz", "freq_std_hz", "damping", "damping_std", *phi]].copy()
    tracked.insert(2, "mode", [m for _, m, _ in tracked_rows])
    tracked["mac"] = [s for _, _, s in tracked_rows]
    tracked = tracked.sort_values(["time", "record", "mode"], kind="stable").reset_index(drop=True)
    return tracked[TRACKED_COLUMNS + phi], modes[~matched].reset_index(drop=True)


def mean_shapes(tracked: pd.DataFrame, references: pd.DataFrame) -> pd.DataFrame:
    """Each reference mode's mean shape over its tracked estimates.

    Each estimate's shape (``tracked``'s ``phi_<k>`` columns, as
    :func:`track_modes` gives them with ``shapes=True``) is scaled to unit
    norm and turned to the sign of the reference's shape (a real shape's
    sign is arbitrary: estimates of opposite signs would cancel), then the
    mean is normalised as every shape is
    (``normalise_shapes`` of the identification: unit norm, largest entry
    positive).

    Returns
    -------
    pandas.DataFrame
        One row per reference mode tracked at least once: ``mode``,
        ``freq_hz`` (the mean of the tracked estimates), ``n_estimates``,
        ``mac_reference`` (the mean shape's MAC with the reference's),
        ``phi_0``, ``phi_1``, ....
    """
    columns = ["mode", "freq_hz", "n_estimates", "mac_reference"]
    phi = sorted((c for c in tracked.columns if str(c).startswith("phi_")), key=lambda c: int(c[4:]))
    rows = []
    for mode, reference in zip(references["mode"], shape_matrix(references).T):
        members = tracked[tracked["mode"] == mode]
        if members.empty:
            continue
        unit = _unit_shapes(shape_matrix(members))
        signs = np.sign(reference @ unit)
        mean = normalise_shapes((unit * np.where(signs == 0, 1.0, signs)).mean(axis=1)[:, None])[:, 0]
        row = {"mode": int(mode), "freq_hz": float(members["freq_hz"].mean()), "n_estimates": len(members),
               "mac_reference": float(mac(mean[:, None], reference[:, None])[0, 0])}
        row.update(dict(zip(phi, mean)))
        rows.append(row)
    return pd.DataFrame(rows, columns=columns + phi)
