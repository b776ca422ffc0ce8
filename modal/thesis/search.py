"""Searches of the settings the thesis does not state, as parameter studies.

Ch. 6 leaves open settings its tables depend on: how the noise is defined
(Sec. 6.1: "at one standard deviation, the noise added is 5% of the
measurement"), the record length and sampling of the noisy cases, the ERA's
Hankel size in the spillover runs (Sec. 6.3), the CERA's sampling interval
and Hankel width s (Sec. 6.4), and whether the TCM's velocities were
integrated from accelerations (Sec. 6.4 names it as a possible error
source). A search (config ``searches``) varies keys of one study over the
product of their values; every setting is one workflow job that runs the
study and scores it against the printed values of the search's tables:

- noisy tables by the likelihood of the printed values under the seed
  distribution (each printed value a new draw: Student's t prediction
  density, :func:`modal.thesis.report.noise_test`), and by the noise test's
  verdict;
- noise-free tables by their deviation from the printed values.

The best setting is reported as a finding; it is adopted (as the study's
setting) only by editing the config, where the thesis's text supports it or
it explains several tables at once (docs/thesis.md).

:func:`search_settings` is plain Python: Snakemake plans the jobs with it
before any job runs.
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Mapping

from .chunks import study_cases

#: What a study does without ``noise_model`` (:func:`modal.structures.with_noise`).
NOISE_MODEL_DEFAULTS = {"scale": "channel_rms", "velocity": "noisy"}

#: The most settings one search may hold (one job each).
MAX_SETTINGS = 500


def search_settings(search: Mapping, studies: Mapping, beams: Mapping, tables: Mapping) -> dict[str, dict]:
    """Every setting of one search, as the study it runs.

    Parameters
    ----------
    search : mapping
        ``config["searches"][name]``: ``study``, ``tables`` and ``vary``
        (dotted key -> values: ``beam.<key>``, ``methods.<method>.<key>``,
        ``noise_model.<key>``, ``signals.<method>``: the signal that method
        sees, in place of each interpretation's, :data:`SIGNAL_KEYS`).
    studies, beams, tables : mapping
        ``config["studies"]``, ``config["beams"]``, ``config["tables"]``.

    Returns
    -------
    dict
        ``"s000"``, ``"s001"``, ... (the product of the values, the first key
        varying slowest) -> ``{"values": {key: value}, "default": bool (every
        value is the study's own; a searched signal never is), "study": study
        spec, "beam": beam spec}``; the searched signals are applied per
        interpretation by :func:`setting_under`.
        The study keeps only the cases the search's tables read, and no CERA
        ``cols_sweep`` (a search varies the width itself).

    Raises
    ------
    ValueError
        A key the study does not have, or more than :data:`MAX_SETTINGS` settings.
    """
    base = copy.deepcopy(dict(studies[search["study"]]))
    base["beam"] = copy.deepcopy(dict(beams[base["beam"]]))
    base["noise_model"] = {**NOISE_MODEL_DEFAULTS, **base.get("noise_model", {})}
    needed = {tables[_key(tables, n)].get("case") for n in search["tables"]}
    cases = study_cases(base)
    base["cases"] = {name: case for name, case in cases.items() if None in needed or name in needed}
    for key in ("noise_sweep", "cols_sweep"):
        base.pop(key, None)
    keys = list(search["vary"])
    for key in keys:
        if key.startswith("signals.") and key not in SIGNAL_KEYS:
            raise ValueError(f"vary: {key!r} is not a setting of the study (signals of: {', '.join(SIGNAL_KEYS)})")
    defaults = {key: _get(base, key) if not key.startswith("signals.") else None for key in keys}
    combos = list(itertools.product(*(search["vary"][key] for key in keys)))
    if len(combos) > MAX_SETTINGS:
        raise ValueError(f"vary: {len(combos)} settings, more than {MAX_SETTINGS}: search fewer values")
    out = {}
    for k, values in enumerate(combos):
        spec = copy.deepcopy(base)
        for key, value in zip(keys, values):
            if not key.startswith(_SIGNAL_PREFIX):  # signals: see setting_under
                _set(spec, key, value)
        beam = spec.pop("beam")
        out[f"s{k:03d}"] = {"values": dict(zip(keys, values)),
                            "default": all(defaults[key] == value for key, value in zip(keys, values)),
                            "study": spec, "beam": beam}
    return out


#: The signals a search may vary (one signal per method; the TCM's pair is an interpretation's).
SIGNAL_KEYS = ("signals.era", "signals.cera")

#: How a searched signal's key begins (:func:`setting_under`).
_SIGNAL_PREFIX = "signals."


def setting_under(setting: Mapping, interpretation: Mapping, study_name: str) -> tuple[dict, dict, dict]:
    """One search setting as one interpretation runs it.

    The interpretation's own reading of the study
    (:func:`modal.thesis.study.interpreted`) first, then the setting's
    searched values on top (a searched key wins), and the searched signals
    (``signals.<method>``) in place of the interpretation's.

    Returns
    -------
    study, beam, signals : dict
        For :func:`modal.thesis.study.run_study`.
    """
    from .study import interpreted

    study, beam = interpreted(setting["study"], setting["beam"], interpretation, study_name)
    study.pop("cols_sweep", None)  # a search varies the width itself
    signals = {k: v for k, v in interpretation.items() if k != "studies"}
    spec = {**study, "beam": beam}
    for key, value in setting["values"].items():
        if key.startswith(_SIGNAL_PREFIX):
            signals[key.removeprefix(_SIGNAL_PREFIX)] = value
        else:
            _set(spec, key, value)
    beam = spec.pop("beam")
    return spec, beam, signals


def _key(mapping: Mapping, number):
    """``number`` as the key ``mapping`` uses (YAML keys may be int or str)."""
    return number if number in mapping else str(number)


def _get(spec: Mapping, key: str):
    node = spec
    for part in key.split("."):
        if not isinstance(node, Mapping) or part not in node:
            raise ValueError(f"vary: {key!r} is not a setting of the study (no {part!r})")
        node = node[part]
    return node


def _set(spec: dict, key: str, value) -> None:
    *path, last = key.split(".")
    node = spec
    for part in path:
        if part not in node:
            raise ValueError(f"vary: {key!r} is not a setting of the study (no {part!r})")
        node = node[part]
    node[last] = value


def describe(values: Mapping) -> str:
    """``"beam.n_samples = 3594, noise_model.scale = record_rms"``."""
    return ", ".join(f"{key} = {value}" for key, value in values.items())


#: Per table and interpretation, what :func:`score_setting` keeps of the assessment.
SCORE_COLUMNS = ["table", "interpretation", "verdict", "rank", "noisy", "n_compared", "n_match", "n_consistent",
                 "n_missing", "mean_abs_dev", "max_abs_dev", "max_t", "log_likelihood"]


def score_setting(published, identified: Mapping, tables: Mapping, study: Mapping, first_seed: int,
                  interpretation_methods: Mapping | None = None):
    """How well one setting explains the printed values of each table.

    Parameters
    ----------
    published : DataFrame
        ``config/thesis_tables.csv`` (:func:`modal.thesis.tables.read_published`).
    identified : mapping
        Interpretation -> the setting's identified modes
        (:func:`modal.thesis.study.run_study`).
    tables : mapping
        Table number -> its spec (``config["tables"]``).
    study : mapping
        The setting's study (its ``methods`` select the Hankel width).
    first_seed : int
    interpretation_methods : mapping, optional
        Interpretation -> its method settings where it reads them
        differently (:func:`setting_under`).

    Returns
    -------
    DataFrame
        :data:`SCORE_COLUMNS`: per table and interpretation the verdict the
        summary would give (:func:`modal.thesis.report.assess_table`), its
        rank, counts, deviations and, for a noisy table, the log-likelihood
        of the printed values under the seed distribution.
    """
    import pandas as pd

    from .report import assess_table
    from .tables import compare

    rows = []
    for number, spec in tables.items():
        table = compare(published[published["table"] == int(number)], identified, spec, study["methods"], first_seed,
                        interpretation_methods)
        for interp, a in assess_table(table).items():
            rows.append({"table": int(number), "interpretation": interp, **{k: a[k] for k in SCORE_COLUMNS[2:]}})
    return pd.DataFrame(rows, columns=SCORE_COLUMNS)


def _order(row) -> tuple:
    """Best first: verdict, values not identified, then the likelihood of a
    noisy table or the mean deviation of a noise-free one."""
    import math

    fit = -row["log_likelihood"] if row["noisy"] else row["mean_abs_dev"]
    return (row["rank"], row["n_missing"], math.inf if fit != fit else fit)


#: The columns of ``results/tables/searches.csv`` (:func:`search_summary`).
SUMMARY_COLUMNS = ["search", "question", "table", "n_settings", "default", "default_verdict", "default_fit",
                   "best", "best_interpretation", "best_verdict", "best_fit", "explains", "best_overall",
                   "overall_explains"]

#: Ranks of :data:`modal.thesis.report.VERDICTS` that count as explaining a
#: table: reproduced to the printed digits, within 1 %, consistent with the noise.
EXPLAINS_RANK = 2


def fit_words(row) -> str:
    """One setting's fit to one table in words."""
    if row["noisy"]:
        return (f"{int(row['n_consistent'])}/{int(row['n_compared'])} consistent with the seed spread, "
                f"log-likelihood {row['log_likelihood']:.1f}, largest |t| {row['max_t']:.2f}")
    return (f"{int(row['n_match'])}/{int(row['n_compared'])} match the printed digits, mean |deviation| "
            f"{100 * row['mean_abs_dev']:.2f} %")


def search_summary(name: str, search: Mapping, scores):
    """One row per table of one search: the study's own setting against the
    best, and the setting that explains most of the search's tables at once.

    Parameters
    ----------
    name : str
    search : mapping
        ``config["searches"][name]``.
    scores : DataFrame
        Every setting's :func:`score_setting` rows with ``setting`` (its
        name), ``values`` (:func:`describe`) and ``default`` columns.

    Returns
    -------
    DataFrame
        :data:`SUMMARY_COLUMNS`. ``explains``: the best setting makes the
        table at least consistent with the noise (:data:`EXPLAINS_RANK`);
        ``best_overall``: the setting (and interpretation) that explains the
        most tables, then has the best summed rank; ``overall_explains``:
        how many of the tables it explains.
    """
    import pandas as pd

    ranked = scores.assign(order=[_order(r) for _, r in scores.iterrows()]).sort_values(
        ["order", "setting", "interpretation"], kind="stable")
    per_setting = ranked.groupby(["setting", "interpretation"], sort=True).agg(
        explained=("rank", lambda r: int((r <= EXPLAINS_RANK).sum())), rank_sum=("rank", "sum"),
        values=("values", "first"))
    overall = per_setting.sort_values(["explained", "rank_sum"], ascending=[False, True], kind="stable").iloc[0]
    n_tables = scores["table"].nunique()
    rows = []
    for table, group in ranked.groupby("table", sort=True):
        best = group.iloc[0]
        own = group[group["default"].astype(bool)]
        own = own.iloc[0] if len(own) else None
        rows.append(dict(
            search=name, question=search["question"], table=int(table), n_settings=scores["setting"].nunique(),
            default=own["values"] if own is not None else "(not searched)",
            default_verdict=own["verdict"] if own is not None else "",
            default_fit=fit_words(own) if own is not None else "",
            best=best["values"], best_interpretation=best["interpretation"], best_verdict=best["verdict"],
            best_fit=fit_words(best), explains=bool(best["rank"] <= EXPLAINS_RANK),
            best_overall=f"{overall['values']} ({overall.name[1]})",
            overall_explains=f"{int(overall['explained'])} of {n_tables}"))
    return pd.DataFrame(rows, columns=SUMMARY_COLUMNS)
