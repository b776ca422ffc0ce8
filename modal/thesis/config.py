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
    if "grid" in config:
        for number in config["tables"]:
            if int(number) in {int(n) for n in config["grid"]["tables"]}:
                problems.append(f"tables.{number}: table {number} is a grid table (grid.tables); "
                                "beam table numbers must differ")
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
    if "grid" in config:
        problems += grid_problems(config["grid"])
    if problems:
        raise ValueError("invalid config:\n  " + "\n  ".join(problems))


def grid_problems(grid: Mapping) -> list[str]:
    """Inconsistencies of the ``grid`` block (Ch. 7): cutoffs at or above
    Nyquist, runs needing more accelerometers than are chosen, Hankel
    matrices longer than a (split) record, unknown cases, runs or nodes."""
    problems = []
    test = grid["test"]
    n_channels = len(test["sensors"])
    if grid["source"] == "virtual":
        model = grid["model"]
        n_cross = model.get("n_vertical", 4) * model.get("n_horizontal", 5)
        for key in ("sensors", "force_nodes"):
            for i, node in enumerate(test[key]):
                if node >= n_cross:
                    problems.append(f"grid.test.{key}[{i}] = {node} is not a strip crossing (0..{n_cross - 1})")
    elif not (grid.get("measured") or {}).get("path"):
        problems.append("grid.measured.path is required when grid.source is 'measured'")
    n_samples, nyquist = test["n_samples"], test["fs"] / 2
    chosen = len(grid["accelerometers"]) if grid.get("accelerometers") else grid["n_selected"]
    if grid["source"] == "virtual" and chosen > n_channels:
        problems.append(f"grid.n_selected = {chosen} exceeds the {n_channels} accelerometers of grid.test.sensors")
    for case, cutoff in grid["cases"].items():
        if cutoff is not None and cutoff >= nyquist:
            problems.append(f"grid.cases.{case} = {cutoff} Hz must be below the Nyquist frequency {nyquist} Hz")
    if grid["figures_cutoff_hz"] >= nyquist:
        problems.append(f"grid.figures_cutoff_hz = {grid['figures_cutoff_hz']} Hz must be below Nyquist {nyquist} Hz")
    for name, run in grid["runs"].items():
        key = f"grid.runs.{name}"
        for case in run["cases"]:
            if case not in grid["cases"]:
                problems.append(f"{key}.cases: {case!r} is not one of grid.cases {sorted(grid['cases'])}")
        ns = run.get("n_identified") or [run.get("n_modes")]
        if None in ns:
            problems.append(f"{key} needs n_modes or n_identified")
            continue
        if run["method"] == "tcm" and max(ns) > chosen:
            problems.append(f"{key}: n = {max(ns)} modes needs {max(ns)} sensors, but {chosen} accelerometers are chosen")
        if run["method"] == "era":
            missing = [k for k in ("sensors", "rows", "cols") if k not in run]
            if missing:
                problems.append(f"{key} needs {', '.join(missing)}")
                continue
            if run["sensors"] > chosen:
                problems.append(f"{key}.sensors = {run['sensors']} exceeds the {chosen} chosen accelerometers")
            length = n_samples // run.get("sets", 1)
            if run["rows"] + run["cols"] > length:
                problems.append(f"{key}: rows + cols = {run['rows'] + run['cols']} exceeds the {length} samples "
                                f"of each of the {run.get('sets', 1)} data sets")
            if 2 * max(ns) > min(run["rows"] * run["sensors"], run["cols"] * run.get("sets", 1)):
                problems.append(f"{key}: 2 n = {2 * max(ns)} exceeds the Hankel size")
    for number, table in grid["tables"].items():
        key = f"grid.tables.{number}"
        for case in (table["case"], table.get("reference_case", table["case"])):
            if case not in grid["cases"]:
                problems.append(f"{key}: case {case!r} is not one of grid.cases")
        for label, run in table["runs"].items():
            if run not in grid["runs"]:
                problems.append(f"{key}.runs.{label} = {run!r} is not one of grid.runs")
    return problems
