"""The report of an identification: one self-contained HTML page
(``report.html``, pictures embedded) beside the results of ``modal identify``.

It shows what the files beside it hold and nothing else: the modes with
their flags, uncertainty and spectral witness, why each mode is believed,
the stabilisation diagram over the singular-value spectrum, the MAC matrix,
the candidates, the warnings, every setting (those chosen from the record
too) and the provenance; for a roving test also the per-setup summary and
the shapes drawn. The page is the jinja2 template ``report.html.j2`` beside
this module, its tables pandas ``Styler`` tables.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path

import numpy as np
import pandas as pd

from .._checks import printable

#: Damping ratio to the report's unit, % of critical.
PERCENT = 100.0
#: A supporting peak's singular vector is this mode's shape when their MAC is at least this; below, the
#: sentence of why a mode is believed says the peak's shape is another (a neighbour's, or two modes mixed).
SHAPE_AGREES = 0.8
#: Columns of a record's modes shown, in order, with their headings (those
#: absent from a table are skipped).
MODE_HEADINGS = {
    "mode": "mode", "freq_hz": "frequency (Hz)", "freq_std_hz": "std (Hz)", "damping": "damping (%)",
    "damping_std": "std (%)", "n_poles": "poles", "mpc": "MPC", "mpd": "MPD (°)", "close": "close",
    "close_mac": "MAC nearest", "sv_peak_hz": "SV peak (Hz)", "sv_number": "SV", "sv_mac": "SV MAC",
    "sv_prominence_db": "SV prominence (dB)", "spectral_support": "spectral peak", "efdd_freq_hz": "EFDD (Hz)",
    "efdd_damping": "EFDD damping (%)",
    "second_freq_hz": "2nd estimate (Hz)", "envelope_cv": "envelope CV", "flag": "flag",
}
#: ... of a roving test's merged modes.
MERGED_HEADINGS = {
    "mode": "mode", "freq_hz": "frequency (Hz)", "freq_std_hz": "std (Hz)", "freq_spread_hz": "spread (Hz)",
    "damping": "damping (%)", "damping_std": "std (%)", "damping_spread": "spread (%)", "n_setups": "setups",
    "n_from_diagram": "from diagram", "ref_mac": "ref. MAC", "mpc": "MPC", "n_nodes": "nodes", "setups": "in setups",
    "flag": "flag",
}
_PERCENT_COLUMNS = ("damping", "damping_std", "damping_spread", "efdd_damping")
_TEXT_COLUMNS = ("flag", "setups", "setup", "modes_hz")


def _template():
    import jinja2

    environment = jinja2.Environment(loader=jinja2.FileSystemLoader(Path(__file__).parent),
                                     autoescape=True, undefined=jinja2.StrictUndefined,
                                     trim_blocks=True, lstrip_blocks=True)
    return environment.get_template("report.html.j2")


def _image(path) -> str:
    return base64.b64encode(Path(path).read_bytes()).decode()


def table_html(frame: pd.DataFrame, headings: dict | None = None, flagged=None, digits=4, name="table") -> str:
    """``frame`` as an HTML table (pandas ``Styler``): the columns of
    ``headings`` that it has, renamed; damping columns in %; numbers to
    ``digits`` significant digits, NaN as a dash; rows where ``flagged`` is
    true shaded; ``name`` makes the table's HTML ids (unique on a page)."""
    frame = frame.copy()
    if headings is not None:
        frame = frame[[c for c in headings if c in frame.columns]]
    for column in _PERCENT_COLUMNS:
        if column in frame:
            frame[column] = PERCENT * pd.to_numeric(frame[column], errors="coerce")
    flagged = np.zeros(len(frame), dtype=bool) if flagged is None else np.asarray(flagged, dtype=bool)
    text = [c for c in frame.columns if c in _TEXT_COLUMNS or frame[c].dtype == object]
    if headings is not None:
        frame = frame.rename(columns=headings)
        text = [headings.get(c, c) for c in text]

    def shade(row):
        return ["background-color: #fff3cd" if flagged[row.name] else ""] * len(row)

    def number(value):
        if isinstance(value, (bool, np.bool_)):
            return "yes" if value else "no"
        if isinstance(value, (int, np.integer)):
            return str(value)
        if isinstance(value, (float, np.floating)):
            return "–" if np.isnan(value) else f"{value:.{digits}g}"
        return "" if value is None else str(value)

    frame = frame.reset_index(drop=True)
    styler = frame.style.set_uuid(name).hide(axis="index").format(number).apply(shade, axis=1)
    if text:
        styler = styler.set_properties(subset=text, **{"text-align": "left"})
    return styler.to_html()


def evidence(modes: pd.DataFrame, n_orders: int, n_channels: int | None = None) -> list[str]:
    """One sentence per mode: why it is believed (or doubted), from its
    columns: poles at how many orders, the standard deviation of its
    frequency, its MPC, the singular-value peak near it and the MAC of its
    shape with that peak's singular vector, and its flag. Of a record of
    one channel (``n_channels``) the MPC and the MAC are 1 by construction
    and no evidence: left out."""
    from ..identification import PEAK_PROMINENCE_DB

    shaped = n_channels is None or n_channels > 1
    lines = []
    for row in modes.to_dict("records"):
        parts = [f"Mode {int(row['mode'])} at {row['freq_hz']:.4g} Hz"]
        if "n_poles" in row:
            parts.append(f"stable poles at {int(row['n_poles'])} of {n_orders} model orders")
        if np.isfinite(row.get("freq_std_hz", np.nan)):
            parts.append(f"frequency ±{row['freq_std_hz']:.2g} Hz (std over the segments)")
        if shaped and np.isfinite(row.get("mpc", np.nan)):
            parts.append(f"MPC {row['mpc']:.2f}")
        if "spectral_support" in row:
            if row["spectral_support"]:
                number = int(row["sv_number"])
                which = {1: "first", 2: "second", 3: "third"}.get(number, f"{number}th")
                alike = row["sv_mac"] >= SHAPE_AGREES
                prominence = row.get("sv_prominence_db", np.nan)
                shoulder = prominence < PEAK_PROMINENCE_DB  # supported by its direction alone (modal.spectral_support)
                if shoulder:
                    parts.append(f"a shoulder of the {which} singular value at {row['sv_peak_hz']:.4g} Hz "
                                 f"({prominence:.1f} dB, under the {PEAK_PROMINENCE_DB:g} dB of a peak: modes that "
                                 f"overlap) whose singular vector is this shape (MAC {row['sv_mac']:.2f}) and no "
                                 "other trusted mode's")
                else:
                    parts.append(f"a peak of the {which} singular value at {row['sv_peak_hz']:.4g} Hz"
                                 + ("" if not shaped else
                                    f" (shape MAC {row['sv_mac']:.2f} with its singular vector)" if alike else
                                    f" whose singular vector is not this shape (MAC {row['sv_mac']:.2f}): "
                                    "another mode's peak, or two modes in one"))
                if np.isfinite(row.get("efdd_freq_hz", np.nan)):
                    parts.append(f"that {'shoulder' if shoulder else 'peak'}'s EFDD cross-check "
                                 f"{row['efdd_freq_hz']:.4g} Hz and damping {PERCENT * row['efdd_damping']:.2g} %")
            else:
                parts.append("no singular-value peak near it")
        flag = row.get("flag")
        sentence = ", ".join(parts) + "."
        if isinstance(flag, str) and flag:
            sentence += f" Doubtful: {flag}."
        lines.append(sentence)
    return lines


def _settings_groups(settings: dict) -> list[dict]:
    def show(value, unset="—"):
        if value is None:
            return unset
        if isinstance(value, float):
            return f"{value:.6g}"
        if isinstance(value, dict) and set(value) == {"first", "last", "step"}:
            return f"{value['first']}, {value['first'] + value['step']}, ... {value['last']}"
        return ", ".join(map(str, value)) if isinstance(value, list) else str(value)

    groups = [{"heading": "Options", "items": [(k, show(v, "— (not given: from the record, or the default)"))
                                               for k, v in settings.get("options", {}).items()]}]
    chosen = dict(settings.get("chosen") or {})
    if chosen:
        groups.append({"heading": "Chosen from the record", "items": [(k, show(v)) for k, v in chosen.items()]})
    if settings.get("criteria"):
        groups.append({"heading": "Selection criteria",
                       "items": [(k, show(v)) for k, v in settings["criteria"].items()]})
    return groups


def _flagged(modes: pd.DataFrame) -> np.ndarray:
    if "flag" not in modes:
        return np.zeros(len(modes), dtype=bool)
    return modes["flag"].fillna("").astype(str).str.len().to_numpy() > 0


def identification_report(folder, result, settings: dict, title: str, steps=(), warnings=()) -> Path:
    """Write ``folder/report.html`` for one record's identification, whose
    files (``stabilisation.png``, ``mac.png``, ...) are already in
    ``folder``; returns its path.

    Parameters
    ----------
    folder : path
    result : Stabilisation
        As :func:`modal.identify_record` returns it (with the spectral
        witness's columns).
    settings : dict
        What :func:`modal.measured.write_settings` wrote.
    title : str
    steps : sequence of str
        The identification's log, one line per step.
    warnings : sequence of str
    """
    folder = Path(folder)
    return _write_page(folder, title=title, warnings=list(warnings), setups=None, per_setup_figures=None,
                       steps=list(steps), **_record_sections(folder, result, settings))


def _write_page(folder: Path, **fields) -> Path:
    """Render the template with ``fields`` into ``folder/report.html``; its path."""
    path = folder / "report.html"
    path.write_text(printable(_template().render(**fields)), encoding="utf-8")
    return path


def _record_sections(folder, result, settings: dict) -> dict:
    """The parts of a page about one record's identification, whose
    pictures are in ``folder``: the summary, the modes with why each is
    believed, the diagram and the MAC matrix, the candidates, the settings
    and the provenance (the template's fields)."""
    modes = result.modes
    n_orders = int(result.poles["order"].nunique()) if len(result.poles) else 0
    flagged = _flagged(modes)
    summary = (f"{len(modes)} modes selected" + (f", {int(flagged.sum())} of them flagged as doubtful"
                                                  if flagged.any() else "")
               + f" from {n_orders} model orders ({len(result.poles)} poles), "
               f"{len(result.candidates)} candidates; "
               f"{settings['options']['excitation'].replace('_', ' ')} record, "
               f"{settings['fs_record_hz']:.6g} Hz" + (f" decimated to {settings['fs_identified_hz']:.6g} Hz"
                                                       if settings.get("decimation", 1) > 1 else "") + ".")
    modes_note = ("Flagged modes (shaded) are doubtful for the reason given; the standard deviations are those of "
                  "the estimates (from segments of the record); SV peak: the nearest peak of the singular values "
                  "of the spectral density matrix, SV MAC: the MAC of the mode's shape with that singular vector; "
                  "EFDD: frequency and damping from that peak's bell (enhanced FDD), a cross-check.")
    n_channels = result.shapes.shape[0] if result.shapes is not None and result.shapes.ndim == 2 else None
    if n_channels == 1:
        modes_note += (" One channel: every shape is the same number, so MPC, MAC and the selection's 'same "
                       "shape' are 1 by construction and tell modes apart by nothing; the modes rest on the "
                       "stability of their poles and on the spectrum's peaks alone.")
    figures = [{"heading": "Stabilisation diagram",
                "caption": "Poles by model order over the singular values of the record's spectral density matrix "
                           "(dB, right axis; the first darker). Red: poles clustered into a mode; vertical lines: "
                           "the selected modes (dashed: no singular-value peak near it).",
                "data": _image(folder / "stabilisation.png"), "kind": "png", "css": "diagram"}]
    if len(modes):
        figures.append({"heading": "MAC of the selected modes", "caption": "Also in mac.csv.",
                        "data": _image(folder / "mac.png"), "kind": "png", "css": "mac"})
    return {"summary": summary, "provenance": settings["provenance"],
            "modes": table_html(modes, MODE_HEADINGS, flagged, name="modes") if len(modes) else "",
            "modes_note": modes_note, "no_mode_reason": result.no_mode_reason(), "evidence": evidence(modes, n_orders, n_channels),
            "notes": list(getattr(result, "notes", ()) or ()), "figures": figures, "mac_table": None,
            "candidates": table_html(result.candidates, name="candidates") if len(result.candidates) else None,
            "settings": _settings_groups(settings)}


def roving_report(folder, merged, setups, results, settings: dict, steps=(), warnings=(), title=None) -> Path:
    """Write ``folder/report.html`` for a roving test (``modal identify`` of
    several setups, :func:`modal.write_setups`): the merged modes, the
    per-setup summary, the shapes drawn (``modes.png`` where a geometry gave
    one), each setup's diagram, the settings and the provenance. Each
    setup's own report is ``setups/<name>/report.html``.

    One setup (one record with a geometry or a channel table) gets one page
    with everything about it: the record's page (:func:`identification_report`:
    its modes with flags, uncertainty and spectral witness, diagram, MAC
    matrix, candidates, settings) with the shapes drawn on the geometry,
    if one was given."""
    folder = Path(folder)
    shapes = []
    if (folder / "modes.png").is_file():
        shapes.append({"heading": "Shapes", "caption": "Every mode drawn on the geometry (one picture per mode in "
                       "mode_<k>.png, animated in mode_<k>.gif; shapes.csv holds them at the nodes).",
                       "data": _image(folder / "modes.png"), "kind": "png", "css": "shapes"})
    if len(setups) == 1:
        own = folder / "setups" / setups[0].name
        sections = _record_sections(own, results[0], json.loads((own / "settings.json").read_text()))
        if shapes:
            sections["summary"] += f" Shapes drawn at {merged.shapes['node'].nunique()} nodes of the geometry."
            sections["figures"][1:1] = shapes  # after the diagram, before the MAC matrix
        sections["provenance"] = settings["provenance"]
        return _write_page(folder, title=title or setups[0].name + (" on its geometry" if shapes else ""),
                           warnings=list(warnings), setups=None, per_setup_figures=None, steps=list(steps),
                           **sections)
    rows = []
    for setup, result in zip(setups, results):
        t = setup.channels
        modes = result.modes
        rows.append({"setup": setup.name, "samples": int(setup.record.acc.shape[0]),
                     "fs_hz": float(setup.record.fs), "channels": len(t),
                     "references": int((t["role"] == "reference").sum()), "modes": len(modes),
                     "flagged": int(_flagged(modes).sum()),
                     "no_spectral_peak": int((~modes["spectral_support"].astype(bool)).sum())
                     if "spectral_support" in modes else 0,
                     "modes_hz": ", ".join(f"{f:.4g}" for f in modes["freq_hz"])})
    table = pd.DataFrame(rows)
    modes = merged.modes
    per_setup = [{"heading": f"setup {s.name}: {len(r.modes)} modes",
                  "data": _image(folder / "setups" / s.name / "stabilisation.png")}
                 for s, r in zip(setups, results) if (folder / "setups" / s.name / "stabilisation.png").is_file()]
    summary = (f"{len(setups)} setups merged into {len(modes)} modes "
               f"({modes['n_setups'].sum() if len(modes) else 0} setup-modes), shapes at "
               f"{merged.shapes['node'].nunique()} nodes.")
    return _write_page(
        folder, title=title or "Roving test", summary=summary, provenance=settings["provenance"], warnings=list(warnings),
        setups=table_html(table, name="setups"),
        modes=table_html(modes, MERGED_HEADINGS, _flagged(modes), name="modes") if len(modes) else "",
        modes_note="Frequency and damping: means over the setups that hold the mode; std: the standard deviation "
                   "of that mean, from each setup's own (over its segments) or, where larger, from the setups' "
                   "spread; spreads: the setups' standard deviations; ref. MAC: the smallest MAC of a setup's "
                   "reference channels with the consensus.",
        no_mode_reason="", evidence=[], notes=[], figures=shapes, mac_table=None, candidates=None,
        per_setup_figures=per_setup, steps=list(steps), settings=_settings_groups(settings))
