"""The grid chapter (thesis Ch. 7) from plain configuration mappings: get the
records (virtual shaking test or measured file), choose the accelerometers,
estimate frequencies from the spectra, filter, identify with the settings of
Tables 10-15, and compare with the published values."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..identification import era
from ..structures import pick_peaks, select_sharpest, sharpness, shake_test
from ..structures import Grid
from ..records import load_record
from ..identification import FLAGS
from ..signals import lowpass_fft, split_record
from .chunks import chunk_seeds
from .study import flags_recorded
from .tables import aggregate, decimals, inclusion_holds, match_to_reference, published_estimates
from ..identification import tcm


@dataclass(frozen=True)
class GridRecord:
    """One grid measurement: eleven (or any number of) accelerometers.

    ``true_hz`` holds the virtual grid's natural frequencies (NaN for a
    measured record); ``labels`` names the channels (node ids for the virtual
    grid, column numbers for a file)."""

    acceleration: np.ndarray
    dt: float
    true_hz: np.ndarray
    labels: np.ndarray


def grid_model(spec: Mapping) -> Grid:
    """The finite-element grid of ``spec["model"]``."""
    return Grid(**spec["model"])


def model_against_estimates(number: int, published: pd.DataFrame, spec: Mapping):
    """``(model_hz, estimates_hz)`` for the table whose finding is the grid
    model (Table 10): the model's lowest natural frequencies and the thesis's
    "est." column of that table in ``published``, one per estimate;
    ``(None, None)`` for every other table and for a measured record."""
    if spec["source"] != "virtual" or spec["tables"][number].get("finding") != "model":
        return None, None
    estimates = published_estimates(published, number)
    return grid_model(spec).frequencies_hz(estimates.size), estimates


def grid_records(spec: Mapping, chunk: int | None = None) -> dict[int, GridRecord]:
    """Records of the grid chapter, keyed by seed.

    ``spec["source"] == "virtual"``: one virtual shaking test per seed
    ``seeds.first ...`` (force burst and sensor noise from that seed,
    :func:`modal.shake_test`), or per seed of chunk number
    ``chunk`` (:func:`modal.thesis.chunks.seed_chunks`). ``"measured"``: the
    single record at ``spec["measured"]["path"]`` (:func:`modal.load_record`),
    seed 0, in chunk 0.
    """
    if spec["source"] == "measured":
        if chunk not in (None, 0):
            raise ValueError(f"chunk: a measured grid record has only chunk 0, got {chunk}")
        m = spec["measured"]
        acc, dt = load_record(m["path"], m.get("fs"))
        if m.get("channels") is not None:
            acc = acc[:, list(m["channels"])]
        problems = measured_record_problems(acc, dt, spec)
        if problems:
            raise ValueError(f"{m['path']}: this record cannot fill the grid chapter's tables "
                             "(for its own modes use `modal identify`):\n  " + "\n  ".join(problems))
        return {0: GridRecord(acc, dt, np.full(4, np.nan), np.arange(acc.shape[1]))}
    grid = grid_model(spec)
    test = dict(spec["test"])
    out = {}
    for seed in chunk_seeds(spec["seeds"], chunk):
        shaken = shake_test(grid, **{**test, "seed": seed})
        out[seed] = GridRecord(shaken.acceleration, shaken.dt, shaken.freq_hz, shaken.nodes)
    return out


def measured_record_problems(acc: np.ndarray, dt: float, spec: Mapping) -> list[str]:
    """Why a measured record cannot fill Tables 10-15 with the settings of
    ``spec`` (empty when it can): too few channels for the accelerometers
    chosen or the runs' sensors, cutoffs above its Nyquist frequency,
    Hankel matrices longer than its (split) data sets, and a length or rate
    other than ``grid.test``'s, which the tables' settings were sized for."""
    from .config import grid_problems

    n_samples, n_channels = acc.shape
    problems = []
    chosen = list(spec.get("accelerometers") or [])
    needed = max(chosen) + 1 if chosen else spec["n_selected"]
    if n_channels < max(2, needed):
        problems.append(f"{n_channels} channel(s), but the grid chapter chooses "
                        f"{len(chosen) or spec['n_selected']} accelerometers"
                        + (f" up to channel {max(chosen)}" if chosen else ""))
    test = spec["test"]
    if n_samples != test["n_samples"] or abs(dt * test["fs"] - 1) > 1e-6:
        problems.append(f"{n_samples} samples at {1 / dt:.6g} Hz, but grid.test describes {test['n_samples']} "
                        f"at {test['fs']} Hz (the tables' Hankel sizes and cutoffs assume that record): "
                        "set grid.test.n_samples and grid.test.fs to the record's")
    sized = {**spec, "test": {**test, "n_samples": n_samples, "fs": 1 / dt}}
    problems += [p for p in grid_problems(sized) if "grid.measured.path" not in p]
    return problems


def choose_accelerometers(record: GridRecord, spec: Mapping) -> np.ndarray:
    """Channel indices of the accelerometers used, best first: ``spec
    ["accelerometers"]`` if given, else the ``n_selected`` with the sharpest
    spectral peaks (thesis Sec. 7.2), ordered by sharpness."""
    if spec.get("accelerometers") is not None:
        chosen = np.asarray(spec["accelerometers"], dtype=int)
        if chosen.max() >= record.acceleration.shape[1]:
            raise ValueError(f"grid.accelerometers: index {chosen.max()} exceeds the "
                             f"{record.acceleration.shape[1]} channels")
        return chosen
    sel = spec["selection"]
    args = (sel["n_peaks"], sel.get("fmin_hz"), sel["fmax_hz"])
    chosen = select_sharpest(record.acceleration, record.dt, spec["n_selected"], *args)
    score = sharpness(record.acceleration, record.dt, *args)[chosen]
    return chosen[np.argsort(-score, kind="stable")]


def preprocess(acc: np.ndarray, dt: float, cutoff_hz) -> np.ndarray:
    """Raw (``cutoff_hz`` None) or the thesis's FFT low-pass (Sec. 7.2)."""
    return acc if cutoff_hz is None else lowpass_fft(acc, dt, cutoff_hz)


def run_grid_study(records: Mapping[int, GridRecord], spec: Mapping) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Every identification of the grid chapter.

    For each record: choose accelerometers, estimate frequencies by peak
    picking (the "est." column), then for each case (raw or a cutoff) and
    each run of ``spec["runs"]``: the TCM on the first n chosen channels
    (acceleration, velocity integrated, Eq. 31), the ERA on the first
    ``sensors`` channels with ``sets`` data sets (the record split into
    equal subintervals, Table 13).

    Returns
    -------
    identified : DataFrame
        ``seed, case, run, method, n, sets, cols, mode, omega, freq_hz,
        real_pole, actual`` (``actual``: true frequency in Hz of that mode
        number, NaN for measured data).
    selection : DataFrame
        ``seed, rank, channel, label, est_hz`` (peak-picked estimates by mode).
    """
    rows, chosen_rows = [], []
    for seed, rec in records.items():
        chosen = choose_accelerometers(rec, spec)
        acc = rec.acceleration[:, chosen]
        peaks = spec["peaks"]
        est = pick_peaks(acc, rec.dt, peaks["n_peaks"], peaks.get("fmin_hz"), peaks["fmax_hz"])
        for rank, ch in enumerate(chosen):
            chosen_rows.append(dict(seed=seed, rank=rank + 1, channel=int(ch), label=int(rec.labels[ch]),
                                    est_hz=est[rank] if rank < est.size else np.nan))
        for case, cutoff in spec["cases"].items():
            y = preprocess(acc, rec.dt, cutoff)
            for run, settings in spec["runs"].items():
                if case not in settings["cases"]:
                    continue
                for n in settings.get("n_identified", [settings.get("n_modes")]):
                    with flags_recorded():
                        result = _identify(y, rec.dt, settings, n)
                    frame = result.to_frame()[["mode", "omega", "freq_hz", *FLAGS]]
                    frame.insert(0, "cols", settings.get("cols", -1))
                    frame.insert(0, "sets", settings.get("sets", 1))
                    frame.insert(0, "n", n)
                    frame.insert(0, "method", settings["method"])
                    frame.insert(0, "run", run)
                    frame.insert(0, "case", case)
                    frame.insert(0, "seed", seed)
                    rows.append(frame)
    identified = pd.concat(rows, ignore_index=True)
    true = {s: r.true_hz for s, r in records.items()}
    identified["actual"] = [true[s][m - 1] if m <= true[s].size else np.nan
                            for s, m in zip(identified["seed"], identified["mode"])]
    return identified, pd.DataFrame(chosen_rows)


def _identify(y, dt, settings, n):
    l = n if settings["method"] == "tcm" else settings["sensors"]
    if l > y.shape[1]:
        raise ValueError(f"{settings['method']} needs {l} accelerometers (one per mode for the TCM), "
                         f"but only {y.shape[1]} are chosen: n_identified/sensors exceeds the {y.shape[1]} channels")
    if settings["method"] == "tcm":
        return tcm(y[:, :n], dt)  # n sensors for n modes (Table 14)
    data = split_record(y[:, :l], settings["sets"]) if settings.get("sets", 1) > 1 else y[:, :l]
    return era(data, dt, n, settings["rows"], settings["cols"])


def grid_table(number: int, published: pd.DataFrame, identified: pd.DataFrame, selection: pd.DataFrame,
               spec: Mapping, first_seed: int) -> pd.DataFrame:
    """Tidy comparison for grid Tables 10-15 (frequencies in Hz).

    ``spec["tables"][number]`` names the ``case`` and, per published method
    and column, the run that reproduces it. Beside each published value:
    ``reproduced`` (mean over the virtual tests), ``std``, ``seed0``,
    ``actual`` (the virtual grid's true frequency) and ``est`` (our peak
    picking). Table 12's percent changes are ``100 |f_7.5 - f_10| / f_10``.
    """
    tspec = spec["tables"][number]
    hz = identified.assign(omega=identified["freq_hz"])
    est = selection.groupby("rank")["est_hz"].agg(["mean", "std"])
    out = []
    for _, pub in published.iterrows():
        base = dict(table=number, mode=pub["mode"], method=pub["method"], interpretation="named",
                    column=pub["column"], printed=pub["printed"], published=pub["value"], flag=pub["flag"])
        if pub["method"] == "est":
            m = pub["mode"]
            vals = dict(reproduced=est["mean"].get(m, np.nan), std=est["std"].get(m, 0.0),
                        n_seeds=selection["seed"].nunique(),
                        seed0=selection[(selection["seed"] == first_seed) & (selection["rank"] == m)]["est_hz"].mean())
            out.append({**base, **vals, "actual": _true(hz, m)})
            continue
        column = pub["column"]
        run = tspec["runs"].get(f"{pub['method']} {column}", tspec["runs"][pub["method"]])
        n = int(column[2:]) if column.startswith("n=") else None
        stats = _stats(hz, tspec["case"], run, n, pub["mode"], first_seed)
        if column == "pct_change_from_10hz":
            ref = _stats(hz, tspec["reference_case"], run, n, pub["mode"], first_seed)
            stats = dict(stats, reproduced=100 * abs(stats["reproduced"] - ref["reproduced"]) / ref["reproduced"],
                         seed0=100 * abs(stats["seed0"] - ref["seed0"]) / ref["seed0"], std=np.nan)
        out.append({**base, **stats, "n": n})
    table = pd.DataFrame(out)
    table["z"] = np.where(table["std"] > 0, (table["published"] - table["reproduced"]) / table["std"], np.nan)
    # percent changes (Table 12) are compared in percentage points, not relatively
    pct = table["column"] == "pct_change_from_10hz"
    table["rel_dev"] = ((table["reproduced"] - table["published"]) / table["published"]).where(~pct)
    table["printed_match"] = [bool(np.isfinite(r) and round(r, decimals(p)) == float(p))
                              for r, p in zip(table["reproduced"], table["printed"])]
    return table


def _true(hz, mode):
    vals = hz.loc[hz["mode"] == mode, "actual"]
    return vals.mean() if len(vals) else np.nan


def _stats(hz, case, run, n, mode, first_seed):
    rows = hz[(hz["case"] == case) & (hz["run"] == run)]
    rows = rows[rows["n"] == (rows["n"].max() if n is None else n)]
    agg = aggregate(rows[rows["mode"] == mode], first_seed)
    if agg.empty:
        return dict(reproduced=np.nan, std=np.nan, n_seeds=0, seed0=np.nan, actual=_true(hz, mode))
    return agg.iloc[0][["reproduced", "std", "n_seeds", "seed0", "seed0_real_pole", "real_pole_frac",
                        "actual"]].to_dict()



def grid_mode_errors(identified: pd.DataFrame, case: str, run: str, n=None, modes=(1, 2, 3, 4)) -> pd.DataFrame:
    """|f / f_true - 1| of each true mode in each virtual test (seed) of one
    run: each seed's entries paired with the true modes by
    :func:`modal.thesis.tables.match_to_reference` (so a real pole or a missed
    mode shifts nothing); a mode missed in a seed counts as a 100 % error.

    Returns
    -------
    DataFrame
        ``seed, mode, freq_hz`` (NaN when missed), ``error``.
    """
    rows = identified[(identified["case"] == case) & (identified["run"] == run)]
    rows = rows[rows["n"] == (rows["n"].max() if n is None else n)].assign(omega=lambda f: f["freq_hz"])
    matched = match_to_reference(rows)
    true = rows.groupby("mode")["actual"].first()
    out = []
    for seed, seed_rows in rows.groupby("seed"):
        m = matched.reindex(seed_rows.index)
        for mode in modes:
            hit = seed_rows[m == mode]
            f = hit["omega"].iloc[0] if len(hit) else np.nan
            out.append(dict(seed=seed, mode=mode, freq_hz=f, error=abs(f / true[mode] - 1) if len(hit) else 1.0))
    return pd.DataFrame(out, columns=["seed", "mode", "freq_hz", "error"])


def _mean_abs_err(identified, case, run, method, n=None):
    """Mean |f / f_true - 1| of the true modes 1-4 over the virtual tests
    (:func:`grid_mode_errors`: missed = 100 %)."""
    return float(grid_mode_errors(identified, case, run, n)["error"].mean())


def grid_findings(number: int, identified: pd.DataFrame, spec: Mapping, model_hz=None,
                  estimates_hz=None) -> list[dict]:
    """The thesis's findings that grid Table ``number`` illustrates
    (``spec["tables"][number]["finding"]``), checked on the virtual grid
    against its true frequencies (Sec. 7.2-7.3).

    Returns
    -------
    list of dict
        ``finding`` (the thesis's statement in short), ``holds`` (bool),
        ``partly`` (bool: holds in some virtual tests, not all),
        ``numbers`` (the numbers behind it, as text) and ``note`` (the
        sentence under the table). Empty for a measured record and for a
        table without a finding.
    """
    if (model_hz is None) != (estimates_hz is None):
        raise ValueError("model_hz and estimates_hz: give both or neither")
    if spec["source"] != "virtual":
        return []
    tspec = spec["tables"][number]
    finding = tspec.get("finding")
    out = []
    if finding == "model" and model_hz is not None:
        estimates_hz = [float(e) for e in estimates_hz]
        if len(estimates_hz) != len(model_hz):
            raise ValueError(f"estimates_hz: expected {len(model_hz)} estimates, one per model frequency, "
                             f"got {len(estimates_hz)}")
        dev = np.asarray(model_hz) / np.asarray(estimates_hz) - 1
        numbers = ", ".join(f"{f:.3f} Hz ({100 * d:+.1f} % from {e})" for f, d, e in zip(model_hz, dev, estimates_hz))
        holds = bool(np.all(np.abs(dev) <= 0.05))
        out.append(dict(finding="the stand-in's lowest frequencies are the thesis's estimates within 5 %",
                        holds=holds, partly=False, numbers=numbers,
                        note=f"Grid model, four lowest frequencies: {numbers}; all within 5 %: "
                             f"{'yes' if holds else 'no'}."))
    if finding in ("filtering", "cutoff"):
        cut, ref = spec["cases"][tspec["case"]], spec["cases"][tspec["reference_case"]]
        for method in ("tcm", "era"):
            run = tspec["runs"][method]
            before = _mean_abs_err(identified, tspec["reference_case"], run, method)
            after = _mean_abs_err(identified, tspec["case"], run, method)
            if finding == "filtering":
                name = f"filtering at {cut:g} Hz improves the {method.upper()}"
                holds = after < before
                numbers = f"mean |error| of true modes 1-4 (missed = 100 %) {100 * before:.1f} % raw -> {100 * after:.1f} % filtered"
            else:
                name = f"filtering at {cut:g} Hz instead of {ref:g} Hz does not improve the {method.upper()}"
                holds = after >= before
                numbers = f"mean |error| {100 * before:.1f} % -> {100 * after:.1f} %"
            out.append(dict(finding=name, holds=holds, partly=False, numbers=numbers,
                            note=f"Finding '{name}': {numbers}: {'reproduced' if holds else 'not reproduced'}."))
    if finding == "data_sets":
        m1 = _mean_abs_err(identified, tspec["case"], tspec["runs"]["era m=1"], "era")
        m3 = _mean_abs_err(identified, tspec["case"], tspec["runs"]["era m=3"], "era")
        name, numbers, holds = ("multiple data sets help the ERA",
                                f"mean |error| {100 * m1:.1f} % (m = 1) -> {100 * m3:.1f} % (m = 3)", m3 < m1)
        out.append(dict(finding=name, holds=holds, partly=False, numbers=numbers,
                        note=f"Finding '{name}': {numbers}: {'reproduced' if holds else 'not reproduced'}."))
    if finding == "inclusion":
        (method, run), = tspec["runs"].items()
        rows = identified[(identified["case"] == tspec["case"]) & (identified["run"] == run)]
        ok = []
        for seed, g in rows.groupby("seed"):
            by_n = {n: h.sort_values("mode")["freq_hz"].to_numpy() for n, h in g.groupby("n")}
            ok.append(inclusion_holds(by_n))
        name = f"the {method.upper()} frequencies obey the inclusion principle as n grows"
        numbers = f"holds in {sum(ok)} of {len(ok)} virtual tests"
        out.append(dict(finding=name, holds=all(ok), partly=any(ok) and not all(ok), numbers=numbers,
                        note=f"Finding '{name}' (Eq. 20): {numbers}: "
                             f"{'reproduced' if all(ok) else 'reproduced in part' if any(ok) else 'not reproduced'}."))
    return out


def grid_notes(number: int, table: pd.DataFrame, identified: pd.DataFrame, spec: Mapping,
               model_hz=None, estimates_hz=None) -> list[str]:
    """Computed notes under a grid table: the model's frequencies
    ``model_hz`` against the thesis's estimates ``estimates_hz`` (its "est."
    column, from the published tables; both or neither), and the thesis's
    qualitative findings, each stated as reproduced or not (errors against the
    virtual grid's true frequencies, :func:`grid_findings`)."""
    findings = grid_findings(number, identified, spec, model_hz, estimates_hz)
    notes = [f["note"] for f in findings if f["note"].startswith("Grid model")]
    virtual = spec["source"] == "virtual"
    n_seeds = identified["seed"].nunique()
    notes.append(f"Reproduced = mean over {n_seeds} {'virtual shaking tests (seeds)' if virtual else 'record(s)'}; "
                 "'actual' is the virtual grid's true frequency, 'est' our automatic peak picking.")
    notes += [f["note"] for f in findings if not f["note"].startswith("Grid model")]
    if virtual and spec["tables"][number].get("finding") == "cutoff":
        notes.append("Percent changes are 100 |f(7.5 Hz) - f(10 Hz)| / f(10 Hz) of the means. The thesis's own ERA "
                     "percentages do not follow from its Tables 11 and 12 (.78 -> .84 is 7.7 %, printed 65.0), and "
                     "its Table 12 ERA column equals Table 13's m = 3 column: probably a slip in the thesis.")
    return notes


def stand_in_findings(identified: pd.DataFrame, published: pd.DataFrame, spec: Mapping) -> dict[int, list[dict]]:
    """Every grid table's findings on the virtual grid (:func:`grid_findings`),
    keyed by table number, for :func:`modal.thesis.report.reproduction_summary`
    (``stand_in``); empty for a measured record, which is no stand-in."""
    if spec["source"] != "virtual":
        return {}
    out = {}
    for number in sorted(int(n) for n in spec["tables"]):
        rows = published[published["table"] == number]
        out[number] = grid_findings(number, identified, spec, *model_against_estimates(number, rows, spec))
    return out
