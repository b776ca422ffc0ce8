"""A roving test's results written to a folder: what ``modal identify`` does
with several setups (or one record with its channel table)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pandas as pd

from ._merge import MergedModes, identify_setup, merge_setups, required_setups


def write_setups(setups, out, options=None, geometry=None, freq_rtol=None, mac_min=0.8, min_setups=None,
                 animate=True, log: Callable[[str], None] | None = None, progress=None, command=None, **keywords):
    """Identify each setup, merge them (:func:`merge_setups`) and write
    ``out``:

    - ``modes.csv``: the merged modes (:class:`MergedModes` ``modes``);
    - ``shapes.csv``: one row per mode and node, ``mode, node, x, y, z``
      in the global frame (real, largest component 1, NaN where no channel
      measures that direction) and ``x_im, y_im, z_im``;
    - ``matches.csv``: which mode of which setup went into each mode, its
      reference MAC and rescaling;
    - ``channels.csv``: every setup's channel table;
    - ``setups/<name>/``: each setup's own results, as ``modal identify``
      writes a record's (modes, complex shapes, MAC matrix, candidates,
      poles, the stabilisation diagram over the singular values,
      ``settings.json``, ``report.html``);
    - with a ``geometry``: ``modes.png`` (every mode drawn on the
      structure), ``mode_<k>.png`` (one mode) and, with ``animate``,
      ``mode_<k>.gif`` (one cycle);
    - ``settings.json``: the options, the merge's settings and the
      provenance (every setup's record and channel table with its sha256);
    - ``report.html``: the merged modes, the per-setup summary, the shapes
      drawn and each setup's diagram (:func:`modal.measured.roving_report`).

    The folder is complete or untouched, as :func:`modal.write_identification`
    writes one (:func:`modal.measured.check_output`, a staged folder); a
    folder that is, holds or lies inside an input (a setup's folder, record
    or channel table, the geometry) is refused before any identification.

    Parameters
    ----------
    setups : sequence of Setup
    out : str or Path
    options : IdentifyOptions or str
        The identification's options for every setup (:func:`identify_setup`;
        or the excitation with the options as ``keywords``).
    geometry : Geometry, optional
    freq_rtol, mac_min, min_setups
        As :func:`merge_setups`.
    animate : bool
    log, progress : callable, optional
        As :func:`modal.identify_record`; ``log`` also hears of each mode
        drawn and animated.
    command : str, optional
        The command that asked for the results (``settings.json``, the
        report); default this process's command line.
    **keywords
        Options (fields of :class:`modal.IdentifyOptions`) given one by one.

    Returns
    -------
    merged : MergedModes
    results : list of Stabilisation
    """
    import json

    from ..measured import check_output, identify_options, staged_folder, write_results, write_settings
    from ..measured import kept_warnings, provenance
    from ..measured import identification_report, roving_report

    outer = log or (lambda message: None)
    steps = []

    def log(message):
        steps.append(message)
        outer(message)

    options = identify_options(options, **keywords)
    setups = list(setups)
    out = check_output(out, inputs=_inputs(setups, geometry))
    results = []
    with staged_folder(out) as staging, kept_warnings() as caught:
        for setup in setups:
            log(f"setup {setup.name}: {setup.record.acc.shape[0]} samples, {len(setup.channels)} channels "
                f"({sum(setup.channels['role'] == 'reference')} references)")
            setup_steps, details = [], {}

            def setup_log(message, setup_steps=setup_steps):
                setup_steps.append(message)
                log("  " + message)

            seen = len(caught)
            try:
                result, dt = identify_setup(setup, options, log=setup_log, progress=progress, details=details)
            except ValueError as exc:
                raise ValueError(f"setup {setup.name}: {exc}") from None
            folder = staging / "setups" / setup.name
            folder.mkdir(parents=True)
            names = list(setup.channels["name"])
            columns = [f"phi_{n}" for n in names] if len(set(names)) == len(names) else \
                [f"phi_{c}" for c in setup.channels["channel"]]
            write_results(folder, result, dt, columns, fmax=options.fmax, title=setup.name,
                          spectrum=details["spectrum"])
            settings = write_settings(folder, options.replace(**_setup_options(setup)), setup.record.dt, dt,
                                      chosen=details["settings"], inputs=_setup_inputs(setup), command=command,
                                      criteria=result.criteria)
            identification_report(folder, result, settings, title=f"setup {setup.name}", steps=setup_steps,
                                  warnings=[str(w.message) for w in caught[seen:]])
            log(f"  {len(result.modes)} modes: " + ", ".join(f"{f:.4g}" for f in result.modes["freq_hz"]) + " Hz")
            results.append(result)
        merged = merge_setups(setups, results, freq_rtol=freq_rtol, mac_min=mac_min, min_setups=min_setups,
                              geometry=geometry)
        log_merge(merged, log)
        merged.modes.to_csv(staging / "modes.csv", index=False, float_format="%.6g")
        merged.shapes.to_csv(staging / "shapes.csv", index=False, float_format="%.6g")
        merged.matches.to_csv(staging / "matches.csv", index=False, float_format="%.6g")
        pd.concat([s.channels.assign(setup=s.name) for s in setups])[["setup", *setups[0].channels.columns]] \
            .to_csv(staging / "channels.csv", index=False, float_format="%.6g")
        if geometry is not None:
            draw_modes(geometry, merged, staging, animate=animate, log=log)
        inputs = [path for s in setups for path in _setup_inputs(s)]
        settings = {"options": options.to_dict(),
                    "merge": {"freq_rtol": freq_rtol, "mac_min": mac_min,
                              "min_setups": required_setups(len(setups), min_setups),
                              "setups": [s.name for s in setups]},
                    "geometry": None if geometry is None else geometry.source,
                    "version": None, "provenance": provenance(inputs, command)}
        settings["version"] = settings["provenance"]["version"]
        (staging / "settings.json").write_text(json.dumps(settings, indent=2) + "\n")
        roving_report(staging, merged, setups, results, settings, steps=steps,
                      warnings=[str(w.message) for w in caught])
    return merged, results


def log_merge(merged: MergedModes, log) -> None:
    """Tell ``log`` which setups were left out of the merge and why, which
    were left out of single modes, and which nodes are flagged."""
    for row in merged.disagreements.itertuples():
        log(f"setup {row.setup} left out of the merge ({row.check}): {row.evidence}")
    bad = set(merged.disagreements["setup"])
    for row in merged.matches[merged.matches["status"] == "left out"].itertuples():
        if row.setup not in bad:
            log(f"mode {row.mode}: setup {row.setup} left out: {row.reason}")
    for row in merged.shapes[merged.shapes["flag"] != ""].itertuples():
        log(f"mode {row.mode}: node {row.node} flagged: {row.flag}")


def _setup_options(setup) -> dict:
    """The options a setup's channel table sets (as :func:`identify_setup` does)."""
    t = setup.channels
    return {"channels": [int(c) for c in t["channel"]], "quantities": list(t["quantity"])}


def _inputs(setups, geometry) -> list[Path]:
    """What the results must not overwrite, hold or lie inside: each setup's
    folder, record and channel table, and the geometry's folder."""
    paths = [path for s in setups for path in [s.path, *_setup_inputs(s)] if path is not None]
    source = None if geometry is None else Path(geometry.source)
    return paths + ([source] if source is not None and source.exists() else [])


def _setup_inputs(setup) -> list:
    """The files a setup was read from: its record and, where they exist
    beside it, its channel table and pyOMA's setup files."""
    from pathlib import Path

    path = getattr(setup.record, "path", None)
    if path is None:
        return []
    path = Path(path)
    beside = [path.parent / name for name in ("channels.csv", "channel_dofs.txt", "setup_info.txt")]
    return [path, *[p for p in beside if p.is_file()]]


def draw_modes(geometry, merged: MergedModes, folder, animate=True, log=None) -> list[Path]:
    """``modes.png`` (all modes), ``mode_<k>.png`` (and ``mode_<k>.gif``) of
    each merged mode in ``folder``; returns the pictures' paths. ``log``
    hears of each picture before it is drawn (an animation takes seconds)."""
    from ._drawing import mode_shape_animation, mode_shape_figure, modes_figure

    log = log or (lambda message: None)
    folder = Path(folder)
    n = len(merged.modes)
    log(f"drawing {n} modes on the geometry (modes.png)")
    titles = {mode.mode: f"mode {mode.mode}: {mode.freq_hz:.4g} Hz, damping {100 * mode.damping:.2g} %"
              for mode in merged.modes.itertuples()}
    paths = [folder / "modes.png"]
    modes_figure(geometry, merged.shapes, titles).savefig(paths[0], dpi=90)
    for k, mode in enumerate(merged.modes.itertuples(), start=1):
        title = titles[mode.mode]
        log(f"  mode {mode.mode} ({k}/{n}): mode_{mode.mode}.png" + (f", animating mode_{mode.mode}.gif"
                                                                      if animate else ""))
        figure = mode_shape_figure(geometry, merged.shapes, mode.mode, title=title)
        paths.append(folder / f"mode_{mode.mode}.png")
        figure.savefig(paths[-1], dpi=110)
        if animate:
            mode_shape_animation(geometry, merged.shapes, mode.mode, folder / f"mode_{mode.mode}.gif", title=title)
    return paths
