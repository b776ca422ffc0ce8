"""Checks of a workflow configuration that a JSON schema cannot express:
cross references and sizes against the record. Each problem names its key."""

from __future__ import annotations

from collections.abc import Mapping

from .study import study_cases


def check(config: Mapping) -> None:
    """Raise ``ValueError`` listing every inconsistency in ``config`` (already
    schema-valid): unknown beam, interpretation, study or case; sensors or
    impact off the beam's stations; Hankel matrices larger than the record;
    more modes than sensors for the TCM or CERA; 2n above the Hankel size for ERA."""
    problems = []
    beams, studies = config["beams"], config["studies"]
    for name, beam in beams.items():
        key = f"beams.{name}"
        for i, s in enumerate(beam["sensors"]):
            if s >= beam["stations"]:
                problems.append(f"{key}.sensors[{i}] = {s} must be < stations = {beam['stations']}")
        if beam["impact"] >= beam["stations"]:
            problems.append(f"{key}.impact = {beam['impact']} must be < stations = {beam['stations']}")
    for name, study in studies.items():
        key = f"studies.{name}"
        if study["beam"] not in beams:
            problems.append(f"{key}.beam = {study['beam']!r} is not one of beams: {sorted(beams)}")
            continue
        for interp in study["interpretations"]:
            if interp not in config["interpretations"]:
                problems.append(f"{key}.interpretations: {interp!r} is not one of {sorted(config['interpretations'])}")
        if not study_cases(study):
            problems.append(f"{key} needs cases or noise_sweep")
        beam = beams[study["beam"]]
        n_samples, n_sensors = beam["n_samples"], len(beam["sensors"])
        ns = study.get("n_identified") or []
        for method, s in study["methods"].items():
            mkey = f"{key}.methods.{method}"
            n_modes = max(ns + [s.get("n_modes", n_sensors if method == "tcm" else 1)])
            if method in ("tcm", "cera") and n_modes > n_sensors:
                problems.append(f"{mkey}: n = {n_modes} modes exceeds the {n_sensors} sensors of beams.{study['beam']}")
            if method in ("era", "cera"):
                for req in ("n_modes", "cols") + (("rows",) if method == "era" else ()):
                    if req not in s:
                        problems.append(f"{mkey}.{req} is required")
                if any(req not in s for req in ("n_modes", "cols")):
                    continue
                rows = s.get("rows", 1)
                widths = [s["cols"]] + (study.get("cols_sweep", []) if method == "cera" else [])
                for cols in widths:
                    needed = s.get("start", 0) + rows + cols
                    if needed > n_samples:
                        problems.append(f"{mkey}: rows + cols = {rows + cols} (cols = {cols}) from start needs "
                                        f"{needed} samples > n_samples = {n_samples} of beams.{study['beam']}")
                if method == "era" and 2 * n_modes > min(rows * n_sensors, s["cols"]):
                    problems.append(f"{mkey}: 2 n_modes = {2 * n_modes} exceeds the Hankel size "
                                    f"{rows * n_sensors} x {s['cols']}")
            lag, duration = s.get("lag", 0), s.get("duration")
            if method == "tcm" and lag + n_sensors + 1 > n_samples:
                problems.append(f"{mkey}.lag = {lag} leaves too few of the {n_samples} samples")
            if duration is not None and duration <= 0:
                problems.append(f"{mkey}.duration must be > 0")
    for number, table in config["tables"].items():
        key = f"tables.{number}"
        study = studies.get(table["study"])
        if study is None:
            problems.append(f"{key}.study = {table['study']!r} is not one of studies: {sorted(studies)}")
        elif "case" in table and table["case"] not in study_cases(study):
            problems.append(f"{key}.case = {table['case']!r} is not a case of studies.{table['study']}")
    if "demo" in studies:
        for number, fig in config["shape_figures"].items():
            if fig["case"] not in study_cases(studies["demo"]):
                problems.append(f"shape_figures.{number}.case = {fig['case']!r} is not a case of studies.demo")
            if fig["method"] not in studies["demo"]["methods"]:
                problems.append(f"shape_figures.{number}.method = {fig['method']!r} is not run in studies.demo")
    if problems:
        raise ValueError("invalid config:\n  " + "\n  ".join(problems))
