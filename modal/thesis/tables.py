"""Tables that put each published number beside the reproduced one."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from .precision import MOST_DIGITS, committed, is_exact

NOISE_FREE_SEED = -1

#: How figures and the report name the interpretations (config ``interpretations``).
INTERPRETATION_NAMES = {"named": "signals as named", "lower": "signals one derivative lower",
                        "guideline": "Sec. 6.4 through the thesis's guidelines"}


def interpretation_name(interpretation: str) -> str:
    """``"named (signals as named)"``; an interpretation without a description keeps its name."""
    text = INTERPRETATION_NAMES.get(interpretation)
    return f"{interpretation} ({text})" if text else interpretation

#: Columns of the committed tables that hold relative deviations or errors
#: (rounded by :func:`modal.thesis.precision.deviation`, 0 when exact).
DEVIATION_COLUMNS = ("rel_dev", "rel_err", "max_abs_rel_dev", "z")

#: How :func:`write_csv` prints a float: enough digits for any value that
#: :func:`modal.thesis.precision.committed` has rounded.
FLOAT_FORMAT = f"%.{MOST_DIGITS}g"


def write_csv(frame: pd.DataFrame, path, chapter="beam") -> None:
    """Write a committed table (``results/tables``) at the precision its
    computation holds (:func:`modal.thesis.precision.committed`).

    Parameters
    ----------
    frame : DataFrame
    path : path
    chapter : str or sequence of str
        ``"beam"`` (Tables 1-9) or ``"grid"`` (Tables 10-15), for the whole
        table or row by row; it sets the digits kept
        (:data:`modal.thesis.precision.KERNEL_SPREAD`).
    """
    committed(frame, chapter, DEVIATION_COLUMNS).to_csv(path, index=False, float_format=FLOAT_FORMAT,
                                                        lineterminator="\n")


def read_table(path) -> pd.DataFrame:
    """A table of published values (``config/thesis_tables.csv``) or a tidy
    comparison (``results/tables/table_NN.csv``): ``printed``, ``column``
    and ``flag`` kept as text, an empty one as ``""``."""
    frame = pd.read_csv(path, dtype={"printed": str, "column": str, "flag": str})
    return frame.fillna({"column": "", "flag": ""})


#: The published values of Tables 1-15 (``config/thesis_tables.csv``).
read_published = read_table


def published_estimates(published: pd.DataFrame, number: int) -> np.ndarray:
    """The thesis's "est." column of grid Table ``number`` (Hz, by mode): the
    frequencies it read off the spectra (0.83, 1.76, 4.35, 6.49 in Table 10)."""
    rows = published[(published["table"] == number) & (published["method"] == "est")]
    if rows.empty:
        raise ValueError(f"published: Table {number} has no 'est' rows")
    return rows.sort_values("mode")["value"].to_numpy(float)


def decimals(printed: str) -> int:
    """Digits after the point in a printed number (``".79"`` -> 2)."""
    return len(printed.split(".")[1]) if "." in printed else 0


#: Cost of leaving an identified entry or an exact mode unmatched, in |ln(omega / omega_exact)|:
#: pairing two entries a factor 2 apart costs as much as leaving both unmatched.
SKIP_COST = 0.5 * np.log(2.0)


def _align(entries: np.ndarray, refs: np.ndarray) -> list[tuple[int, int]]:
    """Order-preserving pairing of sorted log-frequencies ``entries`` with
    sorted ``refs`` that minimises the summed distance, where leaving either
    unpaired costs :data:`SKIP_COST` (an edit-distance alignment).

    In Python floats (the same IEEE arithmetic as NumPy's scalars, without
    their overhead: tables and figures align thousands of seeds)."""
    entries, refs = entries.tolist(), refs.tolist()
    k, r = len(entries), len(refs)
    cost = [[SKIP_COST * (i + j) if i == 0 or j == 0 else 0.0 for j in range(r + 1)] for i in range(k + 1)]
    for i in range(1, k + 1):
        for j in range(1, r + 1):
            cost[i][j] = min(cost[i - 1][j - 1] + abs(entries[i - 1] - refs[j - 1]),
                             cost[i - 1][j] + SKIP_COST, cost[i][j - 1] + SKIP_COST)
    pairs, i, j = [], k, r
    while i > 0 and j > 0:
        if _isclose(cost[i][j], cost[i - 1][j - 1] + abs(entries[i - 1] - refs[j - 1])):
            pairs.append((i - 1, j - 1))
            i, j = i - 1, j - 1
        elif _isclose(cost[i][j], cost[i - 1][j] + SKIP_COST):
            i -= 1
        else:
            j -= 1
    return pairs[::-1]


def _isclose(a: float, b: float) -> bool:
    """:func:`numpy.isclose` with its default tolerances, for two finite floats."""
    return abs(a - b) <= 1e-08 + 1e-05 * abs(b)


def match_to_reference(group: pd.DataFrame) -> pd.Series:
    """Mode number each identified entry stands for, seed by seed.

    In every seed the oscillatory entries (real poles left out), sorted by
    frequency, are paired in order with the exact modes (``actual`` by
    ``mode``) so that the summed ``|ln(omega / omega_exact)|`` is smallest,
    an unpaired entry or mode costing :data:`SKIP_COST` (:func:`_align`).
    A real pole or a lost mode thus shifts nothing. Unpaired entries get NaN.
    """
    ref = group.groupby("mode")["actual"].first().dropna().sort_index()
    logs = np.log(ref.to_numpy())
    seeds, omega = group["seed"].to_numpy(), group["omega"].to_numpy(dtype=float)
    oscillating = ~group["real_pole"].astype(bool).to_numpy() & (omega > 0)
    matched = np.full(len(group), np.nan)
    for seed in np.unique(seeds):
        rows = np.flatnonzero((seeds == seed) & oscillating)
        rows = rows[np.argsort(omega[rows], kind="quicksort")]  # as DataFrame.sort_values sorts
        for i, j in _align(np.log(omega[rows]), logs):
            matched[rows[i]] = ref.index[j]
    return pd.Series(matched, index=group.index)


#: Methods whose entries are the eigenvalues of a realisation of 2 n states (Eq. 43): two real
#: eigenvalues side by side take the states of one mode, as a complex pair does.
STATE_SPACE_METHODS = ("era",)


def thesis_rows(group: pd.DataFrame) -> pd.Series:
    """The row of the thesis's layout each entry of one run takes, identification by identification.

    The position in the frequency-sorted list (the ``mode`` column), except
    that for a state-space method (:data:`STATE_SPACE_METHODS`) two real
    poles side by side share one row: a realisation of ``2 n`` states has
    ``n`` rows, a complex pair or a pair of real eigenvalues in each. So
    Table 6 prints one ``*`` where the ERA with ``2 n = 8`` singular values
    finds two real eigenvalues and three complex pairs, and its ``8.87`` is
    the first complex pair's row (r = 2), not the second real pole's.
    """
    rows = group["mode"].copy()
    real = group["real_pole"].astype(bool).to_numpy()
    if not real.any() or group["method"].iloc[0] not in STATE_SPACE_METHODS:
        return rows
    modes, seeds = group["mode"].to_numpy(), group["seed"].to_numpy()
    # each identification's entries are consecutive, numbered from 1 up within one seed
    starts = np.r_[True, (modes[1:] <= modes[:-1]) | (seeds[1:] != seeds[:-1])]
    identification = np.cumsum(starts)
    for run in np.unique(identification):
        where = np.flatnonzero(identification == run)
        where = where[np.argsort(modes[where], kind="stable")]
        row, open_pair = 0, False
        for i in where:
            if real[i] and open_pair:
                open_pair = False
            else:
                row += 1
                open_pair = bool(real[i])
            rows.iloc[i] = row
    return rows


def run_modes(group: pd.DataFrame) -> tuple[pd.Series, bool]:
    """Mode number each identified entry of one run (one method, n and s
    over its seeds) stands for, as every table and figure aligns them.

    When several seeds are aggregated, some seed has a real pole or a
    different number of entries, and the run identifies at least as many
    modes as participate (``participating`` column), each seed's entries are
    matched to the exact modes by frequency (:func:`match_to_reference`);
    otherwise (one realisation, the same entries in every seed, or spillover
    with fewer identified than participating modes) the row of the thesis's
    layout is the mode (:func:`thesis_rows`: the position in the
    frequency-sorted list, two adjacent ERA real poles sharing one row). Real
    poles and unmatched entries get NaN.

    Returns
    -------
    mode_of : Series
        Indexed like ``group``.
    matching : bool
        True when matched by frequency.
    """
    n_seeds = group["seed"].nunique()
    counts = group.groupby("seed")["mode"].count()
    unstable = group["real_pole"].astype(bool).any() or counts.nunique() > 1
    matching = bool(n_seeds > 1 and unstable and "participating" in group
                    and group["n"].iloc[0] >= group["participating"].iloc[0] and group["actual"].notna().any())
    if matching:
        return match_to_reference(group), True
    return thesis_rows(group).where(~group["real_pole"].astype(bool)), False


#: Run labels of an identified-modes file: one run is one identification
#: setting over its seeds (:func:`run_modes`).
RUN_KEYS = ("case", "method", "n", "cols")


def assign_modes(identified: pd.DataFrame) -> pd.Series:
    """:func:`run_modes` over every run of an identified-modes file (grouped
    by the :data:`RUN_KEYS` it has): the mode each entry stands for, NaN for
    real poles and unmatched entries."""
    keys = [k for k in RUN_KEYS if k in identified]
    return pd.concat([run_modes(g)[0] for _, g in identified.groupby(keys, sort=False)]).reindex(identified.index)


def aggregate(identified: pd.DataFrame, first_seed: int) -> pd.DataFrame:
    """Statistics over seeds of each (method, n, cols, mode).

    Table rows are positions in the frequency-sorted list, as the thesis
    prints them (a real pole takes a row, marked ``*``; two adjacent ERA real
    poles share one, :func:`thesis_rows`); the values behind
    each row's mean and std are the entries :func:`run_modes` assigns to that
    mode (by frequency when seeds disagree, so a real pole or a lost mode
    does not mix modes). Real poles and missed modes are left out of the
    mean and std; ``real_pole_frac`` is the fraction of seeds with a real
    pole at that position, ``missed_frac`` the fraction in which that mode
    was not found.
    ``seed0`` is the single realisation with the first seed (or the
    noise-free run), by position.
    """
    rows = []
    for key, group in identified.groupby(["method", "n", "cols"], sort=True):
        n_seeds = group["seed"].nunique()
        mode_of, matching = run_modes(group)
        layout_rows = group["mode"] if matching else thesis_rows(group)
        exact = group.groupby("mode")["actual"].first()
        for mode, sub in group.groupby(layout_rows, sort=True):
            values = group.loc[mode_of == mode, "omega"]
            first = sub[sub["seed"].isin([first_seed, NOISE_FREE_SEED])]
            rows.append(
                dict(
                    method=key[0], n=key[1], cols=key[2], mode=mode,
                    reproduced=values.mean() if len(values) else np.nan,
                    std=values.std(ddof=1) if len(values) > 1 else 0.0,
                    n_seeds=n_seeds,
                    real_pole_frac=sub["real_pole"].astype(bool).groupby(sub["seed"]).any().sum() / n_seeds,
                    missed_frac=1 - len(values) / n_seeds,
                    matched_by="frequency" if matching else "position",
                    seed0=first["omega"].iloc[0] if len(first) else np.nan,
                    seed0_real_pole=bool(first["real_pole"].iloc[0]) if len(first) else False,
                    actual=exact.get(mode, sub["actual"].iloc[0]),
                )
            )
    return pd.DataFrame(rows)


def compare(published: pd.DataFrame, identified: Mapping[str, pd.DataFrame], spec: Mapping,
            methods: Mapping, first_seed: int, interpretation_methods: Mapping | None = None) -> pd.DataFrame:
    """Tidy comparison for one thesis table.

    Parameters
    ----------
    published : DataFrame
        Rows of ``thesis_tables.csv`` for this table.
    identified : mapping
        Interpretation name -> identified modes of the study (see
        :func:`modal.thesis.study.run_study`).
    spec : mapping
        ``case`` (the study's case) for Tables 1-4, 7-9; spillover tables
        (5, 6) take ``method`` and read ``n`` from the published column.
    methods : mapping
        The study's method settings (to select the configured Hankel width).
    first_seed : int
    interpretation_methods : mapping, optional
        Interpretation -> its method settings where it reads them differently
        (:func:`modal.thesis.study.interpreted`); the others use ``methods``.

    Returns
    -------
    DataFrame
        ``table, mode, method, interpretation, column, n, printed, published,
        flag, reproduced, std, n_seeds, z, rel_dev, printed_match, seed0,
        seed0_real_pole, real_pole_frac, actual``.
    """
    rows = []
    for interp, frame in identified.items():
        frame = frame[frame["case"] == spec["case"]] if "case" in spec else frame
        stats = aggregate(frame, first_seed)
        for _, pub in published.iterrows():
            method = pub["method"]
            base = dict(table=pub["table"], mode=pub["mode"], method=method, interpretation=interp,
                        column=pub["column"], printed=pub["printed"], published=pub["value"], flag=pub["flag"])
            if method == "actual":
                exact = frame.loc[frame["mode"] == pub["mode"], "actual"]
                rows.append({**base, "n": np.nan, "reproduced": exact.iloc[0] if len(exact) else np.nan,
                             "std": 0.0, "n_seeds": 1, "seed0": exact.iloc[0] if len(exact) else np.nan})
                continue
            n = int(pub["column"].split("=")[1]) if pub["column"].startswith("n=") else None
            sel = stats[(stats["method"] == method) & (stats["mode"] == pub["mode"])]
            cols = (interpretation_methods or {}).get(interp, methods).get(method, {}).get("cols")
            if cols is not None:
                sel = sel[sel["cols"] == cols]
            if n is not None:
                sel = sel[sel["n"] == n]
            elif len(sel):
                sel = sel[sel["n"] == sel["n"].max()]
            if sel.empty:
                rows.append({**base, "n": n, "reproduced": np.nan, "n_seeds": 0})
                continue
            rows.append({**base, **sel.iloc[0].drop(["method", "mode", "cols"]).to_dict()})
    out = pd.DataFrame(rows)
    out["z"] = np.where(out["std"] > 0, (out["published"] - out["reproduced"]) / out["std"].where(out["std"] > 0), np.nan)
    out["rel_dev"] = (out["reproduced"] - out["published"]) / out["published"]
    out["printed_match"] = [
        bool(np.isfinite(r) and isinstance(p, str) and p[:1] not in ("*", "-") and round(r, decimals(p)) == float(p))
        for r, p in zip(out["reproduced"], out["printed"])
    ]
    order = ["table", "mode", "method", "interpretation", "column", "n", "printed", "published", "flag",
             "reproduced", "std", "n_seeds", "z", "rel_dev", "printed_match", "seed0", "seed0_real_pole",
             "real_pole_frac", "missed_frac", "matched_by", "actual"]
    return out.reindex(columns=order)


def interpretation_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per interpretation: how many identified values match the printed digits,
    the mean and largest ``|rel_dev|`` (identification rows only)."""
    ident = table[~table["method"].isin(["actual", "est"]) & table["published"].notna()]
    return ident.groupby("interpretation").agg(
        matched=("printed_match", "sum"),
        values=("printed_match", "size"),
        mean_abs_dev=("rel_dev", lambda d: np.nanmean(np.abs(d))),
        max_abs_dev=("rel_dev", lambda d: np.nanmax(np.abs(d))),
    )


def inclusion_holds(values_by_n: Mapping[int, Sequence[float]]) -> bool:
    """Eq. (20): for consecutive orders n, n+1, lambda^(n+1)_r <= lambda^(n)_r
    <= lambda^(n+1)_{r+1} (checked on frequencies, which are monotone in lambda)."""
    ns = sorted(values_by_n)
    for a, b in zip(ns, ns[1:]):
        lo, hi = np.asarray(values_by_n[a], float), np.asarray(values_by_n[b], float)
        if b != a + 1 or len(hi) < len(lo) + 1:
            return False
        if np.any(hi[:-1][: len(lo)] > lo) or np.any(lo > hi[1: len(lo) + 1]):
            return False
    return True


METHOD_ORDER = {"tcm": 0, "era": 1, "cera": 2, "actual": 3, "est": 4}


def _cell(row) -> str:
    """The reproduced value to the published cell's decimals (one more where
    the thesis printed a dash or star), with ± std over seeds and real-pole marks."""
    if pd.isna(row["reproduced"]):
        if row["method"] in ("actual", "est"):
            return ""
        # a blank would read as "not computed": say why the value is missing
        poles = row.get("real_pole_frac", 0)
        return "not identified" + (f" (real pole in {100 * poles:.0f} % of seeds)" if poles and poles > 0 else "")
    printed = row["printed"] if isinstance(row["printed"], str) else ""
    digits = decimals(printed) if printed[:1] not in ("*", "-", "") else 2
    text = f"{row['reproduced']:.{digits}f}"
    if row["method"] == "actual":
        return text
    if row["n_seeds"] > 1 and np.isfinite(row["std"]):
        text += f" ± {row['std']:.{digits}f}"
    if row.get("seed0_real_pole") is True or row.get("seed0_real_pole") == 1:
        text += " (seed 0: *)"
    if row.get("real_pole_frac", 0) and row["real_pole_frac"] > 0:
        text += f" [* in {100 * row['real_pole_frac']:.0f} %]"
    if row.get("matched_by") == "frequency" and row.get("missed_frac", 0) > 0:
        text += f" [missed in {100 * row['missed_frac']:.0f} %]"
    return text


def thesis_layout(table: pd.DataFrame) -> pd.DataFrame:
    """The thesis's layout of a tidy table (:func:`compare`): one row per
    mode r, for every published column the printed value and the reproduced
    one per interpretation (:func:`_cell`), plus the model's true frequency
    when the table has no "actual" column. Every cell is text."""
    table = table.copy()
    table["label"] = table["method"] + np.where(table["column"] != "", " " + table["column"], "")
    table = table.sort_values(["method", "column"], key=lambda c: c.map(METHOD_ORDER) if c.name == "method" else c,
                              kind="stable")
    labels = list(dict.fromkeys(table["label"]))
    interps = list(dict.fromkeys(table["interpretation"]))
    modes = sorted(table["mode"].unique())
    columns = {}
    for label in labels:
        cells = table[table["label"] == label]
        printed = cells.groupby("mode")["printed"].first()
        columns[f"{label} (thesis)"] = [printed.get(m) if isinstance(printed.get(m), str) else "" for m in modes]
        if label.startswith(("actual", "est")):
            first = cells.groupby("mode").head(1).set_index("mode")
            name = f"{label} (exact)" if label.startswith("actual") else f"{label} (ours)"
            columns[name] = [_cell(first.loc[m]) if m in first.index else "" for m in modes]
        else:
            for interp in interps:
                rows = cells[cells["interpretation"] == interp].groupby("mode").head(1).set_index("mode")
                columns[f"{label} ({interp})"] = [_cell(rows.loc[m]) if m in rows.index else "" for m in modes]
    if "actual" not in set(table["method"]) and table["actual"].notna().any():
        true = table.groupby("mode")["actual"].first()
        columns["true (model)"] = [f"{true[m]:.3f}" if pd.notna(true.get(m, np.nan)) else "" for m in modes]
    return pd.DataFrame(columns, index=pd.Index(modes, name="r"))


def to_markdown(table: pd.DataFrame, title: str, notes: Sequence[str] = ()) -> str:
    """``table_NN.md``: the title, :func:`thesis_layout` as a pipe table, the notes."""
    layout = thesis_layout(table)
    header = ["r", *layout.columns]
    lines = [f"### {title}", "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for mode, row in layout.iterrows():
        lines.append("| " + " | ".join([str(mode), *row]) + " |")
    if notes:
        lines += [""] + [f"- {note}" for note in notes]
    return "\n".join(lines) + "\n"


def cera_sensitivity(identified: Mapping[str, pd.DataFrame], first_seed: int, modes=(1, 2, 3)) -> pd.DataFrame:
    """CERA frequency of modes 1-3 against the Hankel width s, per case and
    interpretation: mean over seeds (real poles left out), relative error
    against the exact frequency (``exact``: below the round-off threshold,
    :func:`modal.thesis.precision.is_exact`), and the fraction of real poles."""
    frames = []
    for interp, frame in identified.items():
        rows = frame[(frame["method"] == "cera") & frame["mode"].isin(modes)]
        stats = aggregate(rows.assign(method=rows["case"]), first_seed).rename(columns={"method": "case"})
        stats.insert(0, "interpretation", interp)
        frames.append(stats)
    out = pd.concat(frames, ignore_index=True)
    out["rel_err"] = out["reproduced"] / out["actual"] - 1
    out["exact"] = is_exact(out["rel_err"])
    columns = ["interpretation", "case", "cols", "mode", "reproduced", "std", "n_seeds", "real_pole_frac", "actual",
               "rel_err", "exact"]
    return out[columns].sort_values(["interpretation", "case", "mode", "cols"], ignore_index=True)
