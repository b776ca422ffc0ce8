"""Words about a reproduced table: which interpretation matches, how the
published values sit in the seed spread, whether the inclusion principle holds."""

from __future__ import annotations

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

#: The noise test's family-wise level: a noisy table is "consistent with the
#: noise" when no published value is rejected at this level ...
NOISE_ALPHA = 0.05
#: ... and its verdict is "stable" when the deciding statistic lies at least
#: this many of its own standard errors from the critical value (so more
#: seeds would not flip it; see :func:`noise_test`).
STABLE_SE = 2.0
#: A published real pole (*) in a noisy table is consistent with the noise
#: when our seeds give a real pole there at least this often per value tested
#: (the Bonferroni share ``NOISE_ALPHA / k`` of a table's ``k`` values).
REAL_POLE_ALPHA = NOISE_ALPHA

#: A table whose every identified value is within this |relative deviation|
#: of the printed one is "within 1 %" (the thesis prints three or four digits).
CLOSE_DEV = 0.01
#: A noisy table is "consistent with the noise" only when its largest
#: |relative deviation| is at most this: a seed spread wide enough to cover a
#: larger deviation cannot confirm a value (the grid's virtual tests scatter
#: by 35-51 %).
NOISE_MAX_DEV = 0.10

VERDICT_REPRODUCED = "reproduced to the printed digits"
VERDICT_CLOSE = f"within {100 * CLOSE_DEV:g} %"
VERDICT_NOISE = "consistent with the noise"
VERDICT_STAND_IN = "findings reproduced on a stand-in"
VERDICT_CAUSE = "not reproduced, cause known"
VERDICT_NOT = "not reproduced, unexplained"
#: Verdicts from best to worst (the ``rank`` of :func:`_assess`).
VERDICTS = (VERDICT_REPRODUCED, VERDICT_CLOSE, VERDICT_NOISE, VERDICT_STAND_IN, VERDICT_CAUSE, VERDICT_NOT)

VERDICT_DEFINITIONS = [
    f"'{VERDICT_REPRODUCED}': under the best interpretation, every identified value of the table, rounded to "
    "the digits the thesis printed, equals the printed value (a printed real pole '*' must be a real pole in our "
    "single realisation).",
    f"'{VERDICT_CLOSE}': not every value matches the printed digits, but every identified "
    f"value is within {100 * CLOSE_DEV:g} % of the printed one (and every printed '*' is a real pole in our first "
    "realisation): a difference in the last printed digit, e.g. of the record length or integration the thesis "
    "does not state. Where the config names the remaining deviation's cause (`tables.N.cause`), the summary's "
    "cause column gives it, with what the searches of that table found closest.",
    f"'{VERDICT_NOISE}': the table has noisy cases (the thesis shows one unknown draw; we run n seeds) and passes "
    f"a stated test: each published value p is a new draw from our seed distribution, t = (p - mean) / (std "
    f"sqrt(1 + 1/n)) follows Student's t with n - 1 degrees of freedom, and no value of the table's k is "
    f"rejected at the Bonferroni level {NOISE_ALPHA:g} / k (two-sided; valid however the values are correlated). "
    f"A printed '*' passes when at least a share {NOISE_ALPHA:g} / k of our seeds give a real pole there; a value "
    f"we do not identify fails. The largest |relative deviation| must also be at most {100 * NOISE_MAX_DEV:g} % "
    "(a spread so wide that it covers anything confirms nothing). The test's answer does not drift with the seed "
    "count (its critical value and statistic converge); the verdict is called stable when the deciding |t| lies "
    f"at least {STABLE_SE:g} of its standard errors, sqrt(1/n + t^2 / (2 (n - 1))), from the critical value, and "
    "otherwise says how many seeds would make it so.",
    f"'{VERDICT_STAND_IN}': the grid chapter (Tables 10-15) on the virtual grid that stands in for the lost "
    "records: its numbers cannot reproduce the thesis's, so the table counts as reproduced when the thesis's "
    "findings it illustrates hold on the stand-in (each finding named, with its numbers); the noise test above is "
    "reported beside it.",
    f"'{VERDICT_CAUSE}': none of these, and the cause is named (a setting the thesis does not state that the table "
    "depends on, from the config's `cause`, a setting a search of the unstated settings found to explain it, or a "
    "finding that fails on the stand-in); the searches that covered it are named with what they found. A supposed "
    "cause that a search of that very setting fails to confirm (no setting explains the table) is not a known one.",
    f"'{VERDICT_NOT}': none of these and no cause is known; the reason names how many values match, the largest "
    "|relative deviation| and where it occurs, values we could not identify and published real poles we do not get, "
    "and the cause names the searches of unstated settings that failed to explain it.",
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


def noise_test(published, mean, std, n_seeds, k: int, alpha: float = NOISE_ALPHA) -> pd.DataFrame:
    """The noise test of :data:`VERDICT_DEFINITIONS`, value by value.

    The thesis shows one realisation of each noisy case (Sec. 6.1: Gaussian
    noise, eta = 5 % or 3 %); we have ``n`` seeds. If the published value
    ``p`` were one more draw from our seed distribution (normal, mean and std
    estimated from the seeds), ``t = (p - mean) / (std sqrt(1 + 1/n))``
    follows Student's t with ``n - 1`` degrees of freedom (a prediction
    interval). A table of ``k`` values is tested at the Bonferroni level
    ``alpha / k`` two-sided, which holds whatever the correlation between its
    values (they come from one record).

    Parameters
    ----------
    published, mean, std, n_seeds : array_like
        Per value; ``std`` > 0 and ``n_seeds`` > 1 for a testable value.
    k : int
        Values tested together (the table's identified values).
    alpha : float

    Returns
    -------
    DataFrame
        ``t``, ``critical`` (``t_{n-1}`` quantile at ``1 - alpha / (2 k)``),
        ``passes`` (``|t| <= critical``), ``se`` (standard error of ``t`` from
        the finite seed count, by the delta method: ``sqrt(1/n + t^2 / (2 (n -
        1)))``), ``margin_se`` (``(critical - |t|) / se``: positive when it
        passes; the answer is stable when ``|margin_se| >= STABLE_SE``) and
        ``seeds_for_stable`` (seeds that would make ``|margin_se|`` reach
        :data:`STABLE_SE` if mean, std and t stayed as they are).
    """
    from scipy import stats

    p, m, s, n = (np.asarray(v, dtype=float) for v in (published, mean, std, n_seeds))
    ok = (s > 0) & (n > 1) & np.isfinite(m)
    n_safe = np.where(ok, n, 2.0)
    t = np.where(ok, (p - m) / np.where(ok, s, 1.0) / np.sqrt(1 + 1 / n_safe), np.nan)
    critical = np.where(ok, stats.t.isf(alpha / (2 * max(k, 1)), n_safe - 1), np.nan)
    se = np.sqrt(1 / n_safe + t ** 2 / (2 * (n_safe - 1)))
    margin = (critical - np.abs(t)) / se
    gap = np.abs(critical - np.abs(t))
    with np.errstate(divide="ignore", invalid="ignore"):
        needed = np.ceil(STABLE_SE ** 2 * (1 + t ** 2 / 2) / gap ** 2 + 1)
    return pd.DataFrame(dict(t=t, critical=critical, passes=np.abs(t) <= critical, se=se, margin_se=margin,
                             seeds_for_stable=np.where(ok, needed, np.nan)))


def _log_likelihood(numeric: pd.DataFrame, test: pd.DataFrame) -> float:
    """Log-likelihood of a noisy table's printed values under our seed
    distribution: the sum of the Student's t prediction densities of
    :func:`noise_test` (in the values' own units, so that settings compare);
    NaN when a value has no spread or was not identified."""
    from scipy import stats

    n = numeric["n_seeds"].to_numpy(dtype=float)
    scale = numeric["std"].to_numpy(dtype=float) * np.sqrt(1 + 1 / np.maximum(n, 1))
    t = test["t"].to_numpy(dtype=float)
    if not len(t) or not np.all(np.isfinite(t)):
        return np.nan
    return float(np.sum(stats.t.logpdf(t, n - 1) - np.log(scale)))


def assess_table(frame: pd.DataFrame) -> dict[str, dict]:
    """Each interpretation's assessment of one table's comparison (the
    identified cells: published values and real-pole marks of TCM, ERA and
    CERA rows): verdict rank 0-2 or 5 of :data:`VERDICTS`, counts, deviations,
    the noise test and, for a noisy table, the log-likelihood of the printed
    values (:func:`_log_likelihood`). Used by :func:`reproduction_summary`
    and by the searches (:mod:`modal.thesis.search`)."""
    if "interpretation" not in frame:
        frame = frame.assign(interpretation="reproduced")
    for col, default in (("flag", ""), ("seed0_real_pole", False), ("real_pole_frac", 0.0), ("column", "")):
        if col not in frame:
            frame = frame.assign(**{col: default})
    frame = frame.assign(flag=_text(frame["flag"]), column=_text(frame["column"]))
    cells = frame[(frame["flag"] == "real_pole") | frame["published"].notna()]
    ident = cells[~cells["method"].isin(REFERENCE_METHODS)]
    return {interp: _assess(g) for interp, g in ident.groupby("interpretation", sort=True)}


def _assess(cells: pd.DataFrame) -> dict:
    """Verdict of one interpretation's identified cells of one table (ranks
    0-2 of :data:`VERDICTS`, or 5 when none of them applies)."""
    star = cells["flag"] == "real_pole"
    numeric = cells[~star & cells["published"].notna()]
    stars = cells[star]
    n = len(numeric) + len(stars)
    noisy = bool((cells["n_seeds"].fillna(0) > 1).any())
    match = numeric["printed_match"].map(_truthy)
    star_match = stars["seed0_real_pole"].map(_truthy) if len(stars) else pd.Series(dtype=bool)
    test = noise_test(numeric["published"], numeric["reproduced"], numeric["std"], numeric["n_seeds"], n)
    test.index = numeric.index
    t_ok = test["passes"] & (numeric["n_seeds"] > 1)
    log_likelihood = _log_likelihood(numeric, test) if noisy else np.nan
    star_ok = (star_match | (stars["real_pole_frac"].fillna(0) >= REAL_POLE_ALPHA / max(n, 1))
               if len(stars) else star_match)
    n_match = int(match.sum() + star_match.sum())
    n_consistent = int((match | t_ok).sum() + star_ok.sum())
    missing = numeric[numeric["reproduced"].isna()]
    dev = numeric["rel_dev"].abs()
    worst = numeric.loc[dev.idxmax()] if dev.notna().any() else None
    largest = float(dev.max()) if dev.notna().any() else np.nan
    all_found = len(missing) == 0 and bool(star_match.all())
    tested = test[numeric["n_seeds"] > 1].dropna(subset=["t"])
    max_t = float(tested["t"].abs().max()) if len(tested) else np.nan
    critical = float(tested["critical"].iloc[0]) if len(tested) else np.nan
    consistent = noisy and n_consistent == n and len(missing) == 0 and largest <= NOISE_MAX_DEV
    # stability: a pass needs every tested value's margin; a failure of the test needs one robust failure
    stable, seeds_needed = "", np.nan
    if noisy and len(tested):
        passing = tested[tested["passes"] & ~match.reindex(tested.index).fillna(False)]
        failing = tested[~tested["passes"]]
        if len(failing) and not consistent:
            decisive = failing.loc[[failing["margin_se"].idxmin()]]
        elif len(passing):
            decisive = passing.loc[[passing["margin_se"].idxmin()]]
        else:
            decisive = tested.iloc[:0]
        if len(decisive):
            robust = abs(float(decisive["margin_se"].iloc[0])) >= STABLE_SE
            seeds_needed = float(decisive["seeds_for_stable"].iloc[0])
            n_seeds = int(numeric["n_seeds"].max())
            stable = "yes" if robust else f"no (about {int(seeds_needed)} seeds needed, have {n_seeds})"
        else:
            stable = "yes"
    if n and n_match == n:
        rank = 0
    elif n and all_found and largest <= CLOSE_DEV:
        rank = 1
    elif n and consistent:
        rank = 2
    else:
        rank = 5
    where = f"{_pct(largest)} ({_where(worst)})" if worst is not None else "none"
    test_words = (f"{n_consistent} of {n} consistent with the seed spread (match, or |t| <= {critical:.2f}, the "
                  f"Bonferroni {NOISE_ALPHA:g}/{n} prediction bound; largest |t| {max_t:.2f}; stable: {stable})"
                  if noisy and np.isfinite(critical) else f"{n_consistent} of {n} consistent with the seed spread")
    if rank == 0:
        why = [f"all {n} values match the printed digits"]
    elif rank == 1:
        why = [f"{n_match} of {n} values match the printed digits",
               f"largest absolute deviation {where} <= {100 * CLOSE_DEV:g} %"]
    elif rank == 2:
        why = [test_words, f"largest absolute deviation {where} <= {100 * NOISE_MAX_DEV:g} %"]
    else:
        why = [f"{n_match} of {n} values match the printed digits"]
        if noisy:
            failed = test[~test["passes"] & ~match & (numeric["n_seeds"] > 1) & test["t"].notna()]
            why.append(test_words + ("; rejected: " + ", ".join(
                f"{_where(numeric.loc[i])} (t = {failed.loc[i, 't']:+.2f})" for i in failed.index) if len(failed) else ""))
        if worst is not None:
            why.append(f"largest absolute deviation {where}"
                       + (f" > {100 * NOISE_MAX_DEV:g} %" if noisy and largest > NOISE_MAX_DEV else ""))
        if len(missing):
            why.append(f"not identified (real poles in our {'seeds' if noisy else 'run'}): "
                       + ", ".join(_where(r) for _, r in missing.iterrows()))
        bad_stars = stars[~star_ok] if len(stars) else stars
        if len(bad_stars):
            why.append("thesis real pole (*) not reproduced at " + ", ".join(_where(r) for _, r in bad_stars.iterrows()))
    verdict = VERDICTS[rank]
    return dict(n_compared=n, noisy=noisy, n_match=n_match, n_consistent=n_consistent if noisy else np.nan,
                n_missing=len(missing), mean_abs_dev=float(dev.mean()) if dev.notna().any() else np.nan,
                max_abs_dev=largest, max_t=max_t, t_critical=critical, stable=stable, log_likelihood=log_likelihood,
                worst=_where(worst) if worst is not None else "", verdict=verdict, rank=rank, why="; ".join(why))


def table_searches(searches, number: int, closest: bool = False) -> str:
    """What the searches found for one table, in words (the summary's cause):
    "" when no search covers it. ``closest``: each search's best setting and
    its fit, whatever it explains (for a table already within 1 %, whose
    remaining deviation the searches tried to explain)."""
    if searches is None or not len(searches):
        return ""
    rows = searches[searches["table"] == number]
    words = []
    for _, row in rows.iterrows():
        head = f"search '{row['search']}' ({row['n_settings']} settings): "
        best = f"{row['best']} ({row['best_interpretation']})"
        if str(row["best"]) == str(row["default"]):
            best += ", the config's own setting"
        if closest:
            words.append(f"{head}closest {best}: {row['best_fit']} ({row['best_verdict']})")
        elif row["explains"]:
            words.append(f"{head}{best} makes it '{row['best_verdict']}' ({row['best_fit']}); not adopted")
        else:
            words.append(f"{head}no setting explains it; best {best}: {row['best_fit']}")
    return "; ".join(words)


def reproduction_summary(tables: dict[int, pd.DataFrame], titles: dict[int, str] | None = None,
                         causes: dict[int, str] | None = None,
                         stand_in: dict[int, list[dict]] | None = None,
                         searches: pd.DataFrame | None = None) -> pd.DataFrame:
    """One row per thesis table: how well it is reproduced, and why.

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
    causes : dict, optional
        Table number -> the known cause of a deviation (config
        ``tables.N.cause``: a setting the thesis does not state that the table
        depends on). A table not otherwise reproduced is
        :data:`VERDICT_CAUSE` with it, :data:`VERDICT_NOT` without.
    stand_in : dict, optional
        Table number -> the thesis's findings the table illustrates, checked on
        a stand-in for lost data (the virtual grid, Ch. 7): dicts with
        ``finding``, ``holds`` (bool) and ``numbers`` (text), as
        :func:`modal.thesis.grid_study.grid_findings` returns them. Such a
        table is :data:`VERDICT_STAND_IN` when every finding holds, else
        :data:`VERDICT_CAUSE` naming the findings that fail.
    searches : DataFrame, optional
        ``results/tables/searches.csv`` (:func:`modal.thesis.search.search_summary`):
        the cause of a table not reproduced then names each search of its
        unstated settings and what it found. A table that a searched setting
        explains is :data:`VERDICT_CAUSE`; one that the searches cover but
        none of their settings explains is :data:`VERDICT_NOT`, its config
        ``cause`` kept as the supposed one.

    Returns
    -------
    DataFrame
        ``table, title, n_published`` (printed values and real-pole marks,
        references included), ``n_compared`` (identified values),
        ``interpretation`` (the best one), ``n_match`` (identified values
        matching the printed digits), ``n_within_noise`` (values passing the
        noise test, :func:`noise_test`; NaN for noise-free tables),
        ``max_abs_rel_dev`` and ``worst`` (where it occurs), ``max_t`` and
        ``t_critical`` (the noise test's largest |t| and its Bonferroni bound),
        ``stable`` (whether more seeds could flip the noise test), ``verdict``
        (one of :data:`VERDICTS`), ``cause`` (for the two "not reproduced"
        verdicts: the cause or "unexplained"; for "within 1 %" with a config
        cause: the remaining deviation's cause and the searches that tried
        it), ``why`` (the reason, with the
        numbers), ``by_interpretation`` (every interpretation's matches and
        verdict). See :data:`VERDICT_DEFINITIONS`.
    """
    titles, causes, stand_in = titles or {}, causes or {}, stand_in or {}
    rows = []
    for number in sorted(tables):
        frame = tables[number]
        column = _text(frame["column"]) if "column" in frame else pd.Series("", index=frame.index)
        flag = _text(frame["flag"]) if "flag" in frame else pd.Series("", index=frame.index)
        published = frame.assign(column=column)[(flag == "real_pole") | frame["published"].notna()]
        n_published = len(published.drop_duplicates(["mode", "method", "column"]))
        assessed = assess_table(frame)
        title = titles.get(number, "")
        if not assessed:
            rows.append(dict(table=number, title=title, n_published=n_published, n_compared=0, interpretation="",
                             n_match=0, n_within_noise=np.nan, max_abs_rel_dev=np.nan, worst="", max_t=np.nan,
                             t_critical=np.nan, stable="", verdict=VERDICT_NOT, cause="unexplained",
                             why="no identified values to compare", by_interpretation=""))
            continue
        best = min(assessed, key=lambda i: (assessed[i]["rank"], assessed[i]["n_missing"],
                                            np.inf if np.isnan(assessed[i]["mean_abs_dev"]) else assessed[i]["mean_abs_dev"]))
        a = dict(assessed[best])
        cause = ""
        if number in stand_in:
            findings = stand_in[number]
            failed = [f for f in findings if not f["holds"]]
            words = "; ".join(f"finding '{f['finding']}' {'holds' if f['holds'] else 'does not hold'} "
                              f"({f['numbers']})" for f in findings)
            a["why"] = f"a stand-in for lost records: {words}; the numbers: {a['why']}"
            if findings and not failed:
                a["rank"] = 3
            else:
                a["rank"] = 4
                cause = ("the grid's records are lost; on the virtual grid that stands in, "
                         + (", ".join(f"'{f['finding']}'" for f in failed) + " does not hold" if failed
                            else "no finding is checked"))
        elif a["rank"] == 1 and causes.get(number):
            # within 1 %: the config's cause names what remains, with the searches that tried it
            searched = table_searches(searches, number, closest=True)
            cause = f"remaining deviation: {causes[number]}" + (f"; {searched}" if searched else "")
        elif a["rank"] == 5 and causes.get(number):
            a["rank"], cause = 4, causes[number]
        elif a["rank"] == 5:
            cause = "unexplained"
        searched = table_searches(searches, number) if a["rank"] >= 4 and number not in stand_in else ""
        if searched:
            explained = bool(searches.loc[searches["table"] == number, "explains"].map(_truthy).any())
            if explained:
                a["rank"] = 4
                cause = "a setting the thesis does not state" if cause == "unexplained" else cause
            elif cause != "unexplained":
                # the supposed cause, searched without success, is not a known cause
                a["rank"], cause = 5, f"unexplained (supposed: {cause})"
            cause = f"{cause}; {searched}"
        a["verdict"] = VERDICTS[a["rank"]]
        by = "; ".join(f"{i}: {v['n_match']}/{v['n_compared']} match"
                       + (f", {v['n_consistent']}/{v['n_compared']} within noise" if v["noisy"] else "")
                       + f" ({v['verdict'] if v['rank'] < 5 else 'not reproduced'})" for i, v in assessed.items())
        rows.append(dict(table=number, title=title, n_published=n_published, n_compared=a["n_compared"],
                         interpretation=best, n_match=a["n_match"], n_within_noise=a["n_consistent"],
                         max_abs_rel_dev=a["max_abs_dev"], worst=a["worst"], max_t=a["max_t"],
                         t_critical=a["t_critical"], stable=a["stable"], verdict=a["verdict"], cause=cause,
                         why=a["why"], by_interpretation=by))
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)


#: The columns of ``summary.csv`` (:func:`reproduction_summary`).
SUMMARY_COLUMNS = ["table", "title", "n_published", "n_compared", "interpretation", "n_match", "n_within_noise",
                   "max_abs_rel_dev", "worst", "max_t", "t_critical", "stable", "verdict", "cause", "why",
                   "by_interpretation"]


def headline(summary: pd.DataFrame) -> str:
    """The report's first sentence: ``"Of 15 tables: 2 reproduced to the
    printed digits, 1 within 1 %, ..."``, the verdicts of ``summary.csv``
    counted in the order of :data:`VERDICTS` (none left out, zero counts
    omitted)."""
    counts = summary["verdict"].value_counts()
    parts = [f"{int(counts[v])} {v}" for v in VERDICTS if counts.get(v, 0)]
    parts += [f"{int(c)} {v}" for v, c in counts.items() if v not in VERDICTS]
    return f"Of {len(summary)} tables: " + ", ".join(parts) + "."


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
