"""Checks of a workflow configuration, run by the Snakefile before any job:
the config files read strictly (duplicate keys refused), numbered keys
normalised, the JSON schema with integers that are integers, then what a
schema cannot express: cross references, sizes against the record, paths
that must exist, a measured record opened and checked. Each problem names
its key."""

from __future__ import annotations

import math
import os
import re
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import yaml

from .._config_text import (MAX_CONFIG_BYTES, YTE_KEYS, SafeLoader,  # noqa: F401
                            check_config_text, load_strict)
from .chunks import study_cases

#: Top-level and grid mappings keyed by a thesis table or figure number.
NUMBERED = (("tables",), ("shape_figures",), ("noise_figures",), ("grid", "tables"))
#: Schema keywords whose failure on a fraction or ratio gets a hint on the intended value.
FRACTION_KEYS = ("noise", "damping")
#: Most identification jobs (beam and grid chunks) one plan may hold.
MAX_IDENTIFY_JOBS = 10_000


def check_config_files(configfiles: Sequence, argv: Sequence[str] = ()) -> None:
    """What the Snakefile checks before Snakemake reads ``config/config.yaml``
    (its ``configfile:`` directive would run yte over a template): the raw
    text of every file (:func:`check_config_text`), and a command line that
    gives ``--configfile`` more than once (Snakemake keeps only the last
    occurrence's files and silently drops the others).

    Parameters
    ----------
    configfiles : sequence of path
        ``config/config.yaml`` and ``workflow.configfiles``.
    argv : sequence of str
        ``sys.argv`` of the snakemake command.
    """
    given = configfile_options(argv)
    if len(given) > 1:
        dropped = [f for files in given[:-1] for f in files]
        everything = " ".join(f for files in given for f in files)
        raise ValueError(f"--configfile is given {len(given)} times: Snakemake keeps only the last one "
                         f"({' '.join(given[-1])}) and would silently ignore {' '.join(dropped)}; "
                         f"give all files after one option: --configfile {everything}")
    for path in [*configfiles, *profile_config_files(argv)]:
        check_config_text(path)


#: Names of a profile's settings file (Snakemake: ``profile.yaml`` or
#: ``config.yaml``, optionally for a least major version, ``config.v8+.yaml``).
PROFILE_FILE = re.compile(r"(profile|config)(\.v\d+\+)?\.yaml")


def profile_config_files(argv: Sequence[str], environ=None) -> list[Path]:
    """The files by which Snakemake's profiles may bring it a config, for
    the checks before it starts: every settings file of each profile the
    command line or the environment names (``--profile``, ``--workflow-profile``,
    ``$SNAKEMAKE_PROFILE``, the workflow's default ``profiles/default``), and
    the files their ``configfile``/``configfiles`` keys name (relative to
    the current folder, as Snakemake reads them). A profile given by name is
    looked up where Snakemake looks: the current folder, the user's and the
    site's configuration folders. Every version-suffixed settings file
    counts, whichever Snakemake picks. A settings file's own text is read
    (:func:`load_strict`) only after :func:`check_config_text` passed it.
    """
    environ = os.environ if environ is None else environ
    profiles, workflow_profiles = [], []
    args = list(argv)[1:]
    for i, arg in enumerate(args):
        for option, found in (("--profile", profiles), ("--workflow-profile", workflow_profiles)):
            name, eq, value = arg.partition("=")
            if name == option:
                value = value if eq else (args[i + 1] if i + 1 < len(args) else "")
                if value and value != "none":
                    found.append(value)
    if not profiles and environ.get("SNAKEMAKE_PROFILE"):
        profiles.append(environ["SNAKEMAKE_PROFILE"])
    if not workflow_profiles:
        workflow_profiles = ["profiles/default", "workflow/profiles/default"]
    config_home = Path(environ.get("XDG_CONFIG_HOME") or Path.home() / ".config")
    folders = [Path.cwd(), config_home / "snakemake", Path("/etc/xdg/snakemake")]
    files = []
    for profile in [*profiles, *workflow_profiles]:
        path = Path(profile)
        candidates = [path] if path.exists() else [folder / profile for folder in folders]
        for candidate in candidates:
            if candidate.is_file():
                files.append(candidate)
            elif candidate.is_dir():
                files += sorted(f for f in candidate.iterdir() if PROFILE_FILE.fullmatch(f.name))
    named = []
    for settings in files:
        check_config_text(settings)
        data = load_strict(settings)
        for key in ("configfile", "configfiles"):
            value = data.get(key) if isinstance(data, dict) else None
            named += [Path(v) for v in ([value] if isinstance(value, str) else value or [])]
    return files + named


def configfile_options(argv: Sequence[str]) -> list[list[str]]:
    """The files after each ``--configfile``/``--configfiles`` (or an
    abbreviation argparse accepts, ``--configf``...) of a command line."""
    given, current = [], None
    for arg in list(argv)[1:]:
        name, eq, value = arg.partition("=")
        if name.startswith("--configf") and "--configfiles".startswith(name):
            current = [value] if eq else []
            given.append(current)
        elif arg.startswith("-"):
            current = None
        elif current is not None:
            current.append(arg)
    return given


def check_or_exit(check, *args) -> None:
    """For the Snakefile: ``check(*args)``, and a refusal (``ValueError``)
    printed as its message with exit 2, as ``workflow/regenerate.sh``'s
    pre-check does, instead of Snakemake's traceback of the Snakefile."""
    try:
        check(*args)
    except ValueError as exc:
        print(f"refused: {exc}", file=sys.stderr)
        raise SystemExit(2) from None


def check_workflow_config(config: dict, configfiles, schema) -> None:
    """Everything the Snakefile checks before any job, in order.

    Parameters
    ----------
    config : dict
        The merged config (modified in place: numbered keys become ints).
    configfiles : sequence of path
        The files it came from (``config/config.yaml`` and every
        ``--configfile``): re-read with :func:`load_strict`.
    schema : path
        ``workflow/schemas/config.schema.yaml``.
    """
    for path in configfiles:
        check_config_text(path)
        load_strict(path)
    normalise_numbers(config)
    problems = nonfinite(config)
    if problems:
        raise ValueError("invalid config:\n  " + "\n  ".join(problems))
    validate(config, schema)
    check(config)
    problems = search_problems(config, schema)
    if problems:
        raise ValueError("invalid config:\n  " + "\n  ".join(problems))
    if configfiles:
        check_run_name(config, configfiles[0])


#: Keys that may differ from the default config in the default run: they
#: choose which outputs a run computes, not their content. ``run_searches``
#: recomputes the committed results/tables/searches.csv from the default config.
SAME_OUTPUTS = ("run_searches",)

#: What the summary and the report cite when a run does not compute the searches.
COMMITTED_SEARCHES = "results/tables/searches.csv"


def check_run_name(config: Mapping, default_file) -> None:
    """Refuse a config that differs from the default (``default_file``,
    ``config/config.yaml``), apart from :data:`SAME_OUTPUTS`, but keeps the run ``default``, whose outputs
    overwrite ``results/``, where this folder's git commits the thesis's
    tables (``results/tables``). A parameter study names its run instead
    (``--config run=<name>`` or ``run: <name>`` in its file) and writes
    under ``results/runs/<name>/``. Outside a git work tree, or where git
    tracks no ``results/tables``, nothing committed can be overwritten.

    Raises
    ------
    ValueError
        Naming the keys that differ and how to name the run.
    """
    if config.get("run", "default") != "default":
        return
    default = load_strict(default_file)
    normalise_numbers(default)
    changed = sorted((key, value) for key, value in set(_flat(default).items()) ^ set(_flat(config).items())
                     if key not in SAME_OUTPUTS)
    if not changed or not _committed("results/tables"):
        return
    keys = sorted({key for key, _ in changed})
    shown = ", ".join(keys[:5]) + (f" and {len(keys) - 5} more" if len(keys) > 5 else "")
    raise ValueError(f"invalid config:\n  run = 'default' with a config that differs from {default_file} "
                     f"({shown}): its outputs would overwrite the committed results/tables. Name the run: "
                     "--config run=<name> or 'run: <name>' in your config file (outputs go to results/runs/<name>/)")


def _flat(node, key="") -> dict:
    """Dotted key -> leaf value (lists as tuples, so that they compare and hash)."""
    if isinstance(node, Mapping) and node:
        return {k2: v2 for k, v in node.items() for k2, v2 in _flat(v, f"{key}.{k}" if key else str(k)).items()}
    if isinstance(node, list):
        return {key: repr(node)}
    return {key: repr(node) if isinstance(node, Mapping) else node}


def _committed(path) -> bool:
    """Whether git tracks files under ``path`` in the work tree around the current folder."""
    import subprocess

    try:
        done = subprocess.run(["git", "ls-files", "--", path], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return False
    return done.returncode == 0 and bool(done.stdout.strip())


def nonfinite(config, key="") -> list[str]:
    """Every NaN or infinite number in ``config`` (``.nan``, ``.inf`` in
    YAML), by dotted key: JSON-schema bounds compare false with NaN and so
    let it through."""
    if isinstance(config, Mapping):
        return [p for k, v in config.items() for p in nonfinite(v, f"{key}.{k}" if key else str(k))]
    if isinstance(config, list):
        return [p for i, v in enumerate(config) for p in nonfinite(v, f"{key}.{i}")]
    if isinstance(config, float) and not math.isfinite(config):
        return [f"{key} = {config!r}: not a finite number"]
    return []


def normalise_numbers(config: dict) -> None:
    """Key every table and figure mapping by ``int`` in place: ``1``, ``"1"``
    and ``"01"`` are one table. An override keyed ``"01"`` is merged over
    the entry keyed ``1`` it follows (Snakemake merged the files without
    knowing they are the same number)."""
    for path in NUMBERED:
        parent = config
        for key in path[:-1]:
            parent = parent.get(key) if isinstance(parent, Mapping) else None
        if not isinstance(parent, Mapping) or not isinstance(parent.get(path[-1]), Mapping):
            continue
        name = ".".join(path)
        merged = {}
        for key, value in parent[path[-1]].items():
            number = _number_key(name, key)
            if number in merged and isinstance(merged[number], Mapping) and isinstance(value, Mapping):
                merged[number] = {**merged[number], **value}
            else:
                merged[number] = value
        parent[path[-1]] = merged


def _number_key(name, key) -> int:
    if isinstance(key, bool) or not (isinstance(key, int) or (isinstance(key, str) and key.strip().isdigit())):
        raise ValueError(f"invalid config:\n  {name}: key {key!r} is not a table or figure number")
    return int(key)


def _integer(checker, instance) -> bool:
    """JSON-schema ``integer``: an int, not ``3.0`` and not ``True``."""
    return isinstance(instance, int) and not isinstance(instance, bool)


def validate(config: Mapping, schema) -> None:
    """Validate ``config`` against the JSON schema at ``schema``, reporting
    every violation with its dotted key (integers must be written as
    integers: ``3.0`` is refused where a count or size is expected).

    Raises
    ------
    ValueError
        One line per violation, e.g. ``studies.demo.cases.c3.noise = 5: 5 is
        greater than the maximum of 1 (a fraction: 5 % is 0.05)``.
    """
    problems = schema_problems(config, read_schema(schema))
    if problems:
        raise ValueError("invalid config:\n  " + "\n  ".join(problems))


def read_schema(schema) -> dict:
    """The JSON schema in the YAML file ``schema`` (PyYAML's C loader where
    installed: every job of the workflow reads it)."""
    with open(schema, encoding="utf-8") as fh:
        return yaml.load(fh, Loader=SafeLoader)


def schema_problems(config: Mapping, document: Mapping) -> list[str]:
    """Every violation of the JSON schema ``document`` by ``config``, by dotted key."""
    import jsonschema

    base = jsonschema.validators.validator_for(document)
    checker = base.TYPE_CHECKER.redefine("integer", _integer)
    validator = jsonschema.validators.extend(base, type_checker=checker)(document)
    return sorted(_describe(err) for err in validator.iter_errors(_jsonable(config)))


def search_problems(config: Mapping, schema) -> list[str]:
    """Searches (config ``searches``, :mod:`modal.thesis.search`) that cannot
    run: an unknown study, a table of another study, a key the study does not
    have, or a setting whose study or beam the schema or :func:`study_problems`
    refuses (e.g. a Hankel larger than a shortened record), named with its values."""
    from .search import describe, search_settings, setting_under
    from .study import SIGNAL_ORDER

    document = read_schema(schema)
    parts = {"$defs": document["$defs"], "type": "object",
             "properties": {k: document["properties"][k] for k in ("beams", "studies")}}
    problems = []
    for name, search in config.get("searches", {}).items():
        key = f"searches.{name}"
        if search["study"] not in config["studies"]:
            problems.append(f"{key}.study = {search['study']!r} is not one of studies: {sorted(config['studies'])}")
            continue
        tables = {int(n): t for n, t in config["tables"].items()}
        wrong = [n for n in search["tables"] if n not in tables or tables[n]["study"] != search["study"]]
        if wrong:
            problems.append(f"{key}.tables: {wrong} are not tables of studies.{search['study']}")
            continue
        try:
            settings = search_settings(search, config["studies"], config["beams"], tables)
        except ValueError as err:
            problems.append(f"{key}.{err}")
            continue
        for setting, spec in settings.items():
            where = f"{key}, setting {setting} ({describe(spec['values'])})"
            found = schema_problems({"beams": {"beam": spec["beam"]},
                                     "studies": {"study": {**spec["study"], "beam": "beam"}}}, parts)
            found = found or study_problems("study", spec["study"], spec["beam"], "its beam")
            for interp in config["studies"][search["study"]]["interpretations"]:
                if found or interp not in config["interpretations"]:
                    break
                study, beam, signals = setting_under(spec, config["interpretations"][interp], search["study"])
                found = [f"as interpretations.{interp} reads it: {p}"
                         for p in study_problems("study", study, beam, "its beam")]
                found += [f"signals.{m} = {v!r} is not one of {list(SIGNAL_ORDER)}" for m, v in signals.items()
                          if m != "tcm" and v not in SIGNAL_ORDER]
            problems += [f"{where}: {p.replace('studies.study.', '').replace('beams.', '').removeprefix('study.')}"
                         for p in found]
    return problems


def _jsonable(node):
    """Mapping keys as strings (JSON schema sees object keys as strings)."""
    if isinstance(node, Mapping):
        return {str(k): _jsonable(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_jsonable(v) for v in node]
    return node


def _describe(err) -> str:
    """One violation as ``dotted.key = value: message (hint)``."""
    key = ".".join(str(p) for p in err.absolute_path) or "(top level)"
    if err.validator == "additionalProperties":
        extra = sorted(set(err.instance) - set(err.schema.get("properties", {})))
        return f"{key}: unknown key(s) {extra}; allowed: {sorted(err.schema.get('properties', {}))}"
    if err.validator == "required":
        return f"{key}: {err.message}"
    text = f"{key} = {err.instance!r}: {err.message}"
    if err.validator in ("pattern", "maxLength") and "description" in err.schema:
        return f"{key}: {err.message}: {err.schema['description']}"
    leaf = str(err.absolute_path[-1]) if err.absolute_path else ""
    value = err.instance
    if err.validator == "type" and "integer" in str(err.validator_value) and isinstance(value, float):
        text += f" (write an integer: {int(value) if value.is_integer() else round(value)})"
    elif (leaf in FRACTION_KEYS or _in_list_of(err, FRACTION_KEYS)) and isinstance(value, (int, float)) \
            and not isinstance(value, bool) and 1 <= value <= 100:
        text += f" (a fraction: {value:g} % is {value / 100:g})"
    return text


def _in_list_of(err, names) -> bool:
    path = list(err.absolute_path)
    return len(path) >= 2 and isinstance(path[-1], int) and str(path[-2]) in names


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
        problems += study_problems(key, study, beams[study["beam"]], f"beams.{study['beam']}")
        for interp in study["interpretations"]:
            reading = config["interpretations"].get(interp, {})
            if name in (reading.get("studies") or {}):
                from .study import interpreted

                read, beam = interpreted(study, beams[study["beam"]], reading, name)
                problems += study_problems(f"{key} as interpretations.{interp} reads it", read, beam,
                                           f"beams.{study['beam']} as interpretations.{interp} reads it")
    for interp, reading in config["interpretations"].items():
        for name in reading.get("studies") or {}:
            if name not in studies or interp not in studies[name]["interpretations"]:
                problems.append(f"interpretations.{interp}.studies.{name}: not a study that lists {interp!r} "
                                "among its interpretations")
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
    problems += path_problems(config) + case_problems(config) + plan_problems(config)
    if "grid" in config:
        problems += grid_problems(config["grid"])
        if not problems and config["grid"]["source"] == "measured":
            problems += record_problems(config["grid"])
    if problems:
        raise ValueError("invalid config:\n  " + "\n  ".join(problems))


def study_problems(key: str, study: Mapping, beam: Mapping, beam_name: str) -> list[str]:
    """What makes one study impossible on its beam: no cases, more modes than
    sensors for the TCM or CERA, Hankel matrices larger than the record, 2n
    above the Hankel size for the ERA, a TCM lag leaving too few samples."""
    problems = []
    if not study_cases(study):
        problems.append(f"{key} needs cases or noise_sweep")
    n_samples, n_sensors = beam["n_samples"], len(beam["sensors"])
    if beam.get("period_mode", 1) > beam["n_modes"]:
        problems.append(f"{beam_name}.period_mode = {beam['period_mode']} exceeds its n_modes = {beam['n_modes']}")
    ns = study.get("n_identified") or []
    for method, s in study["methods"].items():
        mkey = f"{key}.methods.{method}"
        n_modes = max(ns + [s.get("n_modes", n_sensors if method == "tcm" else 1)])
        if method in ("tcm", "cera") and n_modes > n_sensors:
            problems.append(f"{mkey}: n = {n_modes} modes exceeds the {n_sensors} sensors of {beam_name}")
        kept = s.get("singular_values")
        if kept is not None and not n_modes <= kept <= n_sensors:
            problems.append(f"{mkey}.singular_values = {kept} must lie between n_modes = {n_modes} and the "
                            f"{n_sensors} sensors of {beam_name}")
        if method != "cera" and ("singular_values" in s or "eigenproblem" in s):
            problems.append(f"{mkey}: singular_values and eigenproblem are CERA settings")
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
                                    f"{needed} samples > n_samples = {n_samples} of {beam_name}")
            if method == "era" and 2 * n_modes > min(rows * n_sensors, s["cols"]):
                problems.append(f"{mkey}: 2 n_modes = {2 * n_modes} exceeds the Hankel size "
                                f"{rows * n_sensors} x {s['cols']}")
        lag, duration = s.get("lag", 0), s.get("duration")
        if method == "tcm" and lag + n_sensors + 1 > n_samples:
            problems.append(f"{mkey}.lag = {lag} leaves too few of the {n_samples} samples")
        if duration is not None and duration <= 0:
            problems.append(f"{mkey}.duration must be > 0")
    return problems


def _n_chunks(seeds: Mapping) -> int:
    """``len(seed_chunks(seeds))`` without building the list."""
    return -(-seeds["count"] // (seeds.get("chunk") or seeds["count"]))


def plan_problems(config: Mapping) -> list[str]:
    """A plan of more than :data:`MAX_IDENTIFY_JOBS` identification jobs
    (noisy studies x interpretations x seed chunks, plus the grid's chunks
    and, with ``run_searches``, the search settings),
    refused before Snakemake builds it."""
    n_beam = 0
    for study in config["studies"].values():
        noisy = any(c["noise"] > 0 for c in study_cases(study).values())
        n_beam += len(study["interpretations"]) * (_n_chunks(config["seeds"]) if noisy else 1)
    grid = config.get("grid")
    n_grid = _n_chunks(grid["seeds"]) if grid and grid["source"] == "virtual" else (1 if grid else 0)
    n_search = sum(math.prod(len(values) for values in search["vary"].values())
                   for search in config.get("searches", {}).values()) if config.get("run_searches") else 0
    if n_beam + n_grid + n_search > MAX_IDENTIFY_JOBS:
        return [f"seeds: the plan would hold {n_beam + n_grid + n_search} identification jobs ({n_beam} beam, "
                f"{n_grid} grid, {n_search} search settings), more than {MAX_IDENTIFY_JOBS}: raise seeds.chunk / "
                "grid.seeds.chunk, lower the counts or search fewer settings"]
    return []


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
    if grid["source"] == "virtual":
        for i, c in enumerate(grid.get("accelerometers") or []):
            if c >= n_channels:
                problems.append(f"grid.accelerometers[{i}] = {c}: grid.test.sensors has {n_channels} "
                                f"accelerometers (0..{n_channels - 1})")
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


def path_problems(config: Mapping) -> list[str]:
    """Files the workflow reads that must exist before any job runs."""
    problems = []
    published = Path(config["published"])
    if not published.is_file():
        problems.append(f"published = {str(published)!r}: no such file (relative to {Path.cwd()})")
    measured = (config.get("grid") or {}).get("measured") or {}
    if config.get("grid", {}).get("source") == "measured" and measured.get("path"):
        if not Path(measured["path"]).is_file():
            problems.append(f"grid.measured.path = {measured['path']!r}: no such file (relative to {Path.cwd()})")
    for name, spec in (config.get("measured") or {}).items():
        problems += measured_problems(f"measured.{name}", spec)
    if config.get("searches") and not config.get("run_searches") and not Path(COMMITTED_SEARCHES).is_file():
        problems.append(f"run_searches = false cites the committed {COMMITTED_SEARCHES}: no such file (relative "
                        f"to {Path.cwd()}); compute it once with --config run_searches=True")
    return problems


def measured_problems(key: str, spec: Mapping) -> list[str]:
    """Open one record of the ``measured`` list (:func:`modal.read_record`)
    and check its options against it (:class:`modal.IdentifyOptions`:
    channels it has, fmax below its Nyquist frequency, ...), before any job
    runs."""
    from ..measured import IdentifyOptions
    from ..records import read_record

    if "setups" in spec:
        return setups_problems(key, spec)
    if not Path(spec["path"]).is_file():
        return [f"{key}.path = {spec['path']!r}: no such file (relative to {Path.cwd()})"]
    try:
        record = read_record(spec["path"], spec.get("fs"))
    except ValueError as exc:
        return [f"{key}.path = {spec['path']!r}: {exc}"]
    try:
        options = IdentifyOptions.from_mapping(spec, other=["path"])
    except ValueError as exc:
        return [f"{key}.{exc}"]
    return [f"{key}.{problem}" for problem in options.record_problems(record.acc.shape[1], record.fs,
                                                                        record.acc.shape[0])]


def setups_problems(key: str, spec: Mapping) -> list[str]:
    """Read a roving test's setups and geometry (:func:`modal.read_setup`,
    :func:`modal.read_geometry`) and check that they share their reference
    channels (:func:`modal.check_setups`), and the options they are
    identified with, before any job runs."""
    from ..measured import IdentifyOptions
    from ..setups import check_setups, read_geometry, read_setup

    try:
        options = IdentifyOptions.from_mapping(spec, other=["setups", "geometry", "min_setups"])
    except ValueError as exc:
        return [f"{key}.{exc}"]
    try:
        geometry = read_geometry(spec["geometry"]) if spec.get("geometry") else None
    except ValueError as exc:
        return [f"{key}.geometry = {spec['geometry']!r}: {exc}"]
    setups, problems = [], []
    for i, path in enumerate(spec["setups"]):
        try:
            setups.append(read_setup(path, spec.get("fs"), geometry))
        except (ValueError, OSError) as exc:
            problems.append(f"{key}.setups[{i}] = {path!r}: {exc}")
    if not problems:
        try:
            check_setups(setups)
        except ValueError as exc:
            problems.append(f"{key}.setups: {exc}")
    for setup in setups if not problems else []:
        problems += [f"{key}.setups ({setup.name}): {p}" for p in options.record_problems(
            setup.record.acc.shape[1], setup.record.fs, setup.record.acc.shape[0])]
    return problems


#: "ζ = .05" / "η = 5 %" in a table title (as the thesis writes them; "zeta",
#: "eta" too), checked against the table's case.
_TITLE_VALUES = {"damping": re.compile(r"(?<!\w)(?:ζ|zeta)\s*=\s*(\d*\.?\d+)"),
                 "noise": re.compile(r"(?<!\w)(?:η|eta)\s*=\s*(\d*\.?\d+)\s*%")}


def case_problems(config: Mapping) -> list[str]:
    """Case names that collide (a noise sweep names its cases ``eta_<eta:g>``,
    so 0.03 and 0.030000001 would be one case), table titles that print a
    damping or noise other than their case's, figure modes the beam lacks."""
    problems = []
    for name, study in config["studies"].items():
        sweep = study.get("noise_sweep")
        if not sweep:
            continue
        names = list(study.get("cases", {}))
        for i, eta in enumerate(sweep["noise"]):
            case = f"eta_{eta:g}"
            if case in names:
                problems.append(f"studies.{name}.noise_sweep.noise[{i}] = {eta!r} gives the case name {case!r} "
                                "of another case: noise levels must differ in their first 6 significant digits")
            names.append(case)
    for number, table in config["tables"].items():
        study = config["studies"].get(table["study"])
        case = study_cases(study).get(table.get("case")) if study else None
        if case is None:
            continue
        for what, pattern in _TITLE_VALUES.items():
            found = pattern.search(table["title"])
            if not found:
                continue
            printed = float(found.group(1)) / (100 if what == "noise" else 1)
            if not np.isclose(printed, case[what], rtol=1e-9, atol=1e-12):
                problems.append(f"tables.{number}.title says {found.group(0)!r} but studies.{table['study']}.cases."
                                f"{table['case']}.{what} = {case[what]!r}: change the title or the case")
    if "noise" in config["studies"]:
        study = config["studies"]["noise"]
        n_modes = config["beams"].get(study["beam"], {}).get("n_modes")
        for number, mode in config["noise_figures"].items():
            if n_modes is not None and mode > n_modes:
                problems.append(f"noise_figures.{number} = {mode}: the noise study's beam {study['beam']} "
                                f"has {n_modes} modes")
    elif config["noise_figures"]:
        problems.append("noise_figures needs studies.noise")
    if config["shape_figures"] and "demo" not in config["studies"]:
        problems.append("shape_figures needs studies.demo")
    return problems


def record_problems(grid: Mapping) -> list[str]:
    """Open the measured record (:func:`modal.load_record`) and check it
    against ``grid.test`` (n_samples, fs) and the channel choices, before any
    job runs."""
    from ..records import load_record

    measured = grid["measured"]
    key = "grid.measured.path"
    try:
        acc, dt = load_record(measured["path"], measured.get("fs"))
    except ValueError as exc:
        return [f"{key} = {measured['path']!r}: {exc}"]
    problems = []
    n_samples, n_channels = acc.shape
    if n_samples < n_channels:
        problems.append(f"{key}: {n_samples} samples of {n_channels} channels: a record has more samples than "
                        "channels (transposed? rows are samples, columns channels)")
    channels = measured.get("channels")
    for i, c in enumerate(channels or []):
        if c >= n_channels:
            problems.append(f"grid.measured.channels[{i}] = {c}: the record has {n_channels} channels (0..{n_channels - 1})")
    used = len(channels) if channels else n_channels
    for i, c in enumerate(grid.get("accelerometers") or []):
        if c >= used:
            problems.append(f"grid.accelerometers[{i}] = {c}: only {used} channels are read (0..{used - 1})")
    if n_samples != grid["test"]["n_samples"]:
        problems.append(f"grid.test.n_samples = {grid['test']['n_samples']} but {measured['path']} holds "
                        f"{n_samples} samples")
    if not np.isclose(1 / dt, grid["test"]["fs"], rtol=1e-6):
        problems.append(f"grid.test.fs = {grid['test']['fs']} Hz but {measured['path']} is sampled at {1 / dt:g} Hz")
    return problems
