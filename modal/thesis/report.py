"""Words about a reproduced table: which interpretation matches, how the
published values sit in the seed spread, whether the inclusion principle holds."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import numpy as np
import pandas as pd

from .tables import inclusion_holds, interpretation_summary, read_table


def table_notes(number: int, table: pd.DataFrame) -> list[str]:
    """Notes printed under a reproduced table (computed, not hand-written)."""
    notes = []
    summary = interpretation_summary(table)
    for interp, row in summary.iterrows():
        notes.append(f"{interp}: {int(row['matched'])} of {int(row['values'])} identified values match the "
                     f"printed digits; mean |deviation| {100 * row['mean_abs_dev']:.2f} %, "
                     f"largest {100 * row['max_abs_dev']:.2f} %.")
    if len(summary) > 1:
        best = summary["mean_abs_dev"].idxmin()
        notes.append(f"The '{best}' interpretation matches the published values best (smallest mean |deviation|).")
    noisy = table[(table["n_seeds"] > 1) & table["z"].notna()]
    if len(noisy):
        n = int(noisy["n_seeds"].max())
        for interp, g in noisy.groupby("interpretation"):
            inside = int((g["z"].abs() <= 2).sum())
            notes.append(f"{interp}: reproduced = mean ± std over {n} noise seeds; the published value lies "
                         f"within 2 std for {inside} of {len(g)} values (z = (published - mean) / std).")
    poles = table[table["flag"] == "real_pole"]
    if len(poles):
        for interp, g in table.groupby("interpretation"):
            ours = g[g["seed0_real_pole"].fillna(False).astype(bool) | (g["real_pole_frac"].fillna(0) > 0)]
            cells = ", ".join(f"r={r.mode} {r.column}" for r in ours.itertuples()) or "none"
            notes.append(f"{interp}: the thesis marks real poles (*) at "
                         + ", ".join(f"r={r.mode} {r.column}" for r in poles[poles['interpretation'] == interp].itertuples())
                         + f"; reproduced real poles: {cells}.")
    if table["column"].str.startswith("n=").any():
        for interp, g in table.groupby("interpretation"):
            by_n, published = {}, {}
            for col, h in g[g["column"].str.startswith("n=")].groupby("column"):
                h = h.sort_values("mode")
                for values, column in ((by_n, "reproduced"), (published, "published")):
                    vals = h[column].to_numpy()
                    values[int(col[2:])] = vals[np.isfinite(vals)]
            notes.append(f"{interp}: inclusion principle (Eq. 20) over n = {min(by_n)}..{max(by_n)} "
                         f"{'holds' if inclusion_holds(by_n) else 'does not hold'} for the reproduced frequencies "
                         f"({'holds' if inclusion_holds(published) else 'does not hold'} for the published ones).")
    return notes


# --------------------------------------------------------------------------- #
# The reproduction summary: one verdict per thesis table
# --------------------------------------------------------------------------- #

#: Methods whose rows are reference values, not identifications.
REFERENCE_METHODS = ("actual", "est")
#: A published value is "within the noise spread" when |z| <= NOISE_Z, with
#: z = (published - mean over seeds) / std over seeds ...
NOISE_Z = 2.0
#: ... and a noisy table is "within noise spread" when at least this fraction
#: of its identified values are (the rest may be the thesis's unlucky draws).
NOISE_FRACTION = 2 / 3
#: A published real pole (*) in a noisy table is within the spread when our
#: seeds give a real pole at least this often (the tail mass beyond 2 std).
REAL_POLE_FRACTION = 0.05

#: A table whose every identified value is within this |relative deviation|
#: of the printed one is "within 1 %" (the thesis prints three or four digits).
CLOSE_DEV = 0.01
#: A noisy table is "within noise spread" only when its largest |relative
#: deviation| is at most this: a seed spread wide enough to cover a larger
#: deviation cannot confirm a value (the grid's virtual tests scatter by
#: 35-51 %).
NOISE_MAX_DEV = 0.10

VERDICT_REPRODUCED = "reproduced to the printed digits"
VERDICT_CLOSE = f"within {100 * CLOSE_DEV:g} %"
VERDICT_NOISE = "within noise spread"
VERDICT_NOT = "not reproduced"
#: Verdicts from best to worst (the ``rank`` of :func:`_assess`).
VERDICTS = (VERDICT_REPRODUCED, VERDICT_CLOSE, VERDICT_NOISE, VERDICT_NOT)

VERDICT_DEFINITIONS = [
    f"'{VERDICT_REPRODUCED}': under the best interpretation, every identified value of the table, rounded to "
    "the digits the thesis printed, equals the printed value (a printed real pole '*' must be a real pole in our "
    "single realisation).",
    f"'{VERDICT_CLOSE}': not every value matches the printed digits, but every identified "
    f"value is within {100 * CLOSE_DEV:g} % of the printed one (and every printed '*' is a real pole in our first "
    "realisation): a difference in the last printed digit, e.g. of the record length or integration the thesis "
    "does not state.",
    f"'{VERDICT_NOISE}': the table has noisy cases (several noise seeds), at least "
    f"{Fraction(NOISE_FRACTION).limit_denominator(10)} of its identified values are consistent with the seed spread "
    f"(they match the printed digits or |z| <= {NOISE_Z:g}, z = (published - mean over seeds) / std over seeds; a "
    f"printed '*' counts when at least {100 * REAL_POLE_FRACTION:g} % of our seeds give a real pole), and the "
    f"largest |relative deviation| is at most {100 * NOISE_MAX_DEV:g} %. If the thesis's value were one draw from "
    "our seed distribution, each value would pass the z test with about 95 % probability; the deviation bound "
    "keeps a spread so wide that it covers anything from confirming a value.",
    f"'{VERDICT_NOT}': none of these; the reason names how many values match, the largest |relative deviation| "
    "and where it occurs, values we could not identify and published real poles we do not get.",
    "Identification rows only (TCM, ERA, CERA): the 'actual' and 'est' columns are references. The best "
    "interpretation is the one with the best verdict, then the fewest values not identified, then the smallest "
    "mean |relative deviation|. Every verdict comes with its reason.",
]


def _truthy(value) -> bool:
    return value is True or (isinstance(value, (bool, np.bool_)) and bool(value)) or str(value) == "True"


def _text(column: pd.Series) -> pd.Series:
    """A text column with missing entries as "" (whatever dtype CSV reading gave it)."""
    return column.astype(object).where(column.notna(), "").astype(str)


def _pct(fraction: float) -> str:
    """A relative deviation in percent, three significant digits."""
    return f"{100 * fraction:.3g} %"


def _where(row) -> str:
    column = row["column"] if isinstance(row["column"], str) and row["column"] else ""
    return f"{str(row['method']).upper()} r={int(row['mode'])}" + (f" {column}" if column else "")


def _assess(cells: pd.DataFrame) -> dict:
    """Verdict of one interpretation's identified cells of one table."""
    star = cells["flag"] == "real_pole"
    numeric = cells[~star & cells["published"].notna()]
    stars = cells[star]
    n = len(numeric) + len(stars)
    noisy = bool((cells["n_seeds"].fillna(0) > 1).any())
    match = numeric["printed_match"].map(_truthy)
    star_match = stars["seed0_real_pole"].map(_truthy) if len(stars) else pd.Series(dtype=bool)
    z_ok = (numeric["n_seeds"] > 1) & (numeric["std"] > 0) & (numeric["z"].abs() <= NOISE_Z)
    star_ok = star_match | (stars["real_pole_frac"].fillna(0) >= REAL_POLE_FRACTION) if len(stars) else star_match
    n_match = int(match.sum() + star_match.sum())
    n_consistent = int((match | z_ok).sum() + star_ok.sum())
    missing = numeric[numeric["reproduced"].isna()]
    dev = numeric["rel_dev"].abs()
    worst = numeric.loc[dev.idxmax()] if dev.notna().any() else None
    largest = float(dev.max()) if dev.notna().any() else np.nan
    all_found = len(missing) == 0 and bool(star_match.all())
    need = int(np.ceil(NOISE_FRACTION * n - 1e-9))
    if n and n_match == n:
        rank = 0
    elif n and all_found and largest <= CLOSE_DEV:
        rank = 1
    elif n and noisy and n_consistent >= need and largest <= NOISE_MAX_DEV:
        rank = 2
    else:
        rank = 3
    where = f"{_pct(largest)} ({_where(worst)})" if worst is not None else "none"
    if rank == 0:
        why = [f"all {n} values match the printed digits"]
    elif rank == 1:
        why = [f"{n_match} of {n} values match the printed digits",
               f"largest absolute deviation {where} <= {100 * CLOSE_DEV:g} %"]
    elif rank == 2:
        why = [f"{n_consistent} of {n} are within {NOISE_Z:g} std of the seed mean or match (needs {need})",
               f"largest absolute deviation {where} <= {100 * NOISE_MAX_DEV:g} %"]
    else:
        why = [f"{n_match} of {n} values match the printed digits"]
        if noisy:
            why.append(f"{n_consistent} of {n} are within {NOISE_Z:g} std of the seed mean or match (needs {need})")
        if worst is not None:
            why.append(f"largest absolute deviation {where}"
                       + (f" > {100 * NOISE_MAX_DEV:g} %" if noisy and n_consistent >= need else ""))
        if len(missing):
            why.append(f"not identified (real poles in our {'seeds' if noisy else 'run'}): "
                       + ", ".join(_where(r) for _, r in missing.iterrows()))
        bad_stars = stars[~star_ok] if len(stars) else stars
        if len(bad_stars):
            why.append("thesis real pole (*) not reproduced at " + ", ".join(_where(r) for _, r in bad_stars.iterrows()))
    verdict = VERDICTS[rank]
    return dict(n_compared=n, noisy=noisy, n_match=n_match, n_consistent=n_consistent if noisy else np.nan,
                n_missing=len(missing), mean_abs_dev=float(dev.mean()) if dev.notna().any() else np.nan,
                max_abs_dev=largest,
                worst=_where(worst) if worst is not None else "", verdict=verdict, rank=rank, why="; ".join(why))


def reproduction_summary(tables: dict[int, pd.DataFrame], titles: dict[int, str] | None = None) -> pd.DataFrame:
    """One row per thesis table: how well it is reproduced.

    Parameters
    ----------
    tables : dict
        Table number -> the tidy comparison (``results/tables/table_NN.csv``,
        as written by :func:`modal.thesis.tables.compare`). Needs the columns
        ``mode, method, column, printed, published, flag, reproduced, std,
        n_seeds, z, rel_dev, printed_match`` (``interpretation``,
        ``seed0_real_pole`` and ``real_pole_frac`` when present).
    titles : dict, optional
        Table number -> title (from config: ``tables`` and ``grid.tables``).

    Returns
    -------
    DataFrame
        ``table, title, n_published`` (printed values and real-pole marks,
        references included), ``n_compared`` (identified values),
        ``interpretation`` (the best one), ``n_match`` (identified values
        matching the printed digits), ``n_within_noise`` (matching or
        ``|z| <= NOISE_Z``; NaN for noise-free tables), ``max_abs_rel_dev``
        and ``worst`` (where it occurs), ``verdict`` (one of
        :data:`VERDICTS`), ``why`` (its reason), ``by_interpretation`` (every interpretation's
        matches and verdict). See :data:`VERDICT_DEFINITIONS`.
    """
    titles = titles or {}
    rows = []
    for number in sorted(tables):
        frame = tables[number]
        if "interpretation" not in frame:
            frame = frame.assign(interpretation="reproduced")
        for col, default in (("flag", ""), ("seed0_real_pole", False), ("real_pole_frac", 0.0), ("column", "")):
            if col not in frame:
                frame = frame.assign(**{col: default})
        frame = frame.assign(flag=_text(frame["flag"]), column=_text(frame["column"]))
        cells = frame[(frame["flag"] == "real_pole") | frame["published"].notna()]
        ident = cells[~cells["method"].isin(REFERENCE_METHODS)]
        n_published = len(cells.drop_duplicates(["mode", "method", "column"]))
        assessed = {interp: _assess(g) for interp, g in ident.groupby("interpretation", sort=True)}
        title = titles.get(number, "")
        if not assessed:
            rows.append(dict(table=number, title=title, n_published=n_published, n_compared=0, interpretation="",
                             n_match=0, n_within_noise=np.nan, max_abs_rel_dev=np.nan, worst="",
                             verdict=VERDICT_NOT, why="no identified values to compare", by_interpretation=""))
            continue
        best = min(assessed, key=lambda i: (assessed[i]["rank"], assessed[i]["n_missing"],
                                            np.inf if np.isnan(assessed[i]["mean_abs_dev"]) else assessed[i]["mean_abs_dev"]))
        a = assessed[best]
        by = "; ".join(f"{i}: {v['n_match']}/{v['n_compared']} match"
                       + (f", {v['n_consistent']}/{v['n_compared']} within noise" if v["noisy"] else "")
                       + f" ({v['verdict']})" for i, v in assessed.items())
        rows.append(dict(table=number, title=title, n_published=n_published, n_compared=a["n_compared"],
                         interpretation=best, n_match=a["n_match"], n_within_noise=a["n_consistent"],
                         max_abs_rel_dev=a["max_abs_dev"], worst=a["worst"], verdict=a["verdict"], why=a["why"],
                         by_interpretation=by))
    columns = ["table", "title", "n_published", "n_compared", "interpretation", "n_match", "n_within_noise",
               "max_abs_rel_dev", "worst", "verdict", "why", "by_interpretation"]
    return pd.DataFrame(rows, columns=columns)


def load_tables(directory, numbers=None) -> dict[int, pd.DataFrame]:
    """The ``table_NN.csv`` files present in ``directory`` (all, or those in
    ``numbers``), as :func:`reproduction_summary` takes them."""
    directory = Path(directory)
    tables = {}
    for path in sorted(directory.glob("table_[0-9][0-9].csv")):
        number = int(path.stem.split("_")[1])
        if numbers is None or number in numbers:
            tables[number] = read_table(path)
    return tables


def write_notes(path, notes) -> None:
    """The notes of one table, one per line (``results/notes/table_NN.txt``)."""
    Path(path).write_text("".join(f"{note}\n" for note in notes))


def read_notes(path) -> list[str]:
    """The notes :func:`write_notes` wrote; none when ``path`` is None or absent."""
    return Path(path).read_text().splitlines() if path is not None and Path(path).is_file() else []
