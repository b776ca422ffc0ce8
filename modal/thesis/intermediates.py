"""Readers of the workflow's intermediate files (``results/identified/*.csv``,
``results/grid/*.csv``) that check what they read: the columns, the expected
cases x seeds x methods, no NaN where none may be. A truncated or corrupted
file is refused with its path named, never turned into a table built from
part of the data."""

from __future__ import annotations

from collections.abc import Mapping

import pandas as pd

from .chunks import study_cases

#: Columns of a beam study's identified modes (:func:`modal.thesis.study.run_study`)
#: that must be present and never NaN.
IDENTIFIED_LABELS = ("case", "damping", "noise", "method", "n", "cols", "seed", "mode", "omega")
#: The same for the grid chapter (:func:`modal.thesis.grid_study.run_grid_study`).
GRID_LABELS = ("seed", "case", "run", "method", "n", "sets", "cols", "mode", "omega", "freq_hz", "real_pole")
SELECTION_LABELS = ("seed", "rank", "channel", "label")


def _read(path, required) -> pd.DataFrame:
    try:
        frame = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a readable CSV file ({exc})") from None
    missing = [c for c in required if c not in frame]
    if missing:
        raise ValueError(f"{path}: missing columns {missing} (has {list(frame.columns)}); "
                         "rerun the job that writes it")
    nan = [c for c in required if frame[c].isna().any()]
    if nan:
        raise ValueError(f"{path}: NaN in columns {nan}, where every row needs a value (truncated file?)")
    if frame.empty:
        raise ValueError(f"{path}: no rows")
    return frame


def _missing(path, present, expected, what) -> None:
    absent = sorted(set(expected) - set(present), key=str)
    if absent:
        label = (lambda key: "(" + ", ".join(map(str, key)) + ")") if isinstance(absent[0], tuple) else str
        shown = ", ".join(map(label, absent[:5])) + (f" and {len(absent) - 5} more" if len(absent) > 5 else "")
        raise ValueError(f"{path}: {len(absent)} expected {what} missing ({shown}); the file is incomplete")


def read_identified(path, study: Mapping, seeds: Mapping) -> pd.DataFrame:
    """The identified modes of one beam study, checked.

    Parameters
    ----------
    path : path-like
        ``results/identified/{study}_{interpretation}.csv``.
    study : mapping
        ``config["studies"][name]``: its cases (and noise sweep), methods,
        ``n_identified``.
    seeds : mapping
        ``config["seeds"]`` (``first``, ``count``): every noisy case must
        hold every seed, a noise-free one seed -1.

    Raises
    ------
    ValueError
        Naming ``path``: missing columns, NaN labels, or a (case, seed,
        method, n) combination the config expects but the file lacks.
    """
    frame = _read(path, IDENTIFIED_LABELS)
    noisy = list(range(seeds["first"], seeds["first"] + seeds["count"]))
    ns = study.get("n_identified")
    expected = []
    for case, params in study_cases(study).items():
        for seed in ([-1] if params["noise"] == 0 else noisy):
            for method, settings in study["methods"].items():
                for n in ns or [None]:
                    expected.append((case, seed, method) + ((n,) if ns else ()))
    keys = ["case", "seed", "method"] + (["n"] if ns else [])
    present = set(frame[keys].itertuples(index=False, name=None))
    _missing(path, present, expected, "(" + ", ".join(keys) + ") combinations")
    return frame


def read_interpretations(paths, interpretations, study: Mapping, seeds: Mapping) -> dict[str, pd.DataFrame]:
    """Each interpretation's identified modes of one beam study, checked
    (:func:`read_identified`), keyed by interpretation.

    Parameters
    ----------
    paths : sequence of path-like
        ``results/identified/{study}_{interpretation}.csv``, one per entry of
        ``interpretations``, in the same order.
    interpretations : sequence of str
        ``config["studies"][name]["interpretations"]``.
    study, seeds : mapping
        As for :func:`read_identified`.
    """
    paths, interpretations = list(paths), list(interpretations)
    if len(paths) != len(interpretations):
        raise ValueError(f"paths: expected one file per interpretation {interpretations}, got {len(paths)}")
    return {i: read_identified(path, study, seeds) for i, path in zip(interpretations, paths)}


def read_grid_identified(path, spec: Mapping, seeds=None) -> pd.DataFrame:
    """The grid chapter's identified modes, checked: every seed (virtual
    test) x every (case, run) that ``spec["runs"]`` asks for.

    Parameters
    ----------
    path : path-like
        ``results/grid/identified.csv``.
    spec : mapping
        ``config["grid"]``.
    seeds : sequence of int, optional
        Default: ``spec["seeds"]`` for a virtual test, ``[0]`` for a
        measured record.
    """
    frame = _read(path, GRID_LABELS)
    seeds = _grid_seeds(spec) if seeds is None else seeds
    expected = [(seed, case, run) for seed in seeds for run, settings in spec["runs"].items()
                for case in settings["cases"]]
    present = set(frame[["seed", "case", "run"]].itertuples(index=False, name=None))
    _missing(path, present, expected, "(seed, case, run) combinations")
    return frame


def read_selection(path, spec: Mapping) -> pd.DataFrame:
    """The grid's chosen accelerometers per seed, checked: every seed, ranks
    1..k without gaps."""
    frame = _read(path, SELECTION_LABELS)
    _missing(path, set(frame["seed"]), _grid_seeds(spec), "seeds")
    for seed, group in frame.groupby("seed"):
        if sorted(group["rank"]) != list(range(1, len(group) + 1)):
            raise ValueError(f"{path}: seed {seed}: ranks {sorted(group['rank'])} are not 1..{len(group)}")
    return frame


def _grid_seeds(spec):
    if spec["source"] == "measured":
        return [0]
    return list(range(spec["seeds"]["first"], spec["seeds"]["first"] + spec["seeds"]["count"]))
