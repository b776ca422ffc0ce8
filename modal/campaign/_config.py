"""A campaign's configuration and its index of records.

A campaign is a YAML file::

    records:
      index: records.csv          # columns path,time; paths relative to this file
      # or
      glob: "data/*.npy"          # relative to this file
      time_format: "%Y%m%d_%H%M"  # strptime pattern of the time in each name
      time_regex: "(\\d{8}_\\d{4})"  # optional: the part of the name that holds it
    identify:                     # the options of ``modal identify`` (same defaults)
      fs: 50
      excitation: ambient
      fmax: 10
    tracking:                     # optional
      reference_modes: refs.csv   # freq_hz and phi_<k> columns; default: built from the campaign
      freq_rtol: 0.05
      mac_min: 0.8
      min_share: 0.3
    chunk: 50                     # records per job

:func:`read_campaign` checks it (unknown keys, types and ranges are
refused with the key named) and returns it with absolute paths and the
index, sorted by time.
"""

from __future__ import annotations

import math
import re
from datetime import datetime
from pathlib import Path

import pandas as pd

def _identify_schema() -> dict:
    """The ``identify`` section's schema: :class:`modal.IdentifyOptions`'s own."""
    from ..measured import IdentifyOptions

    schema = IdentifyOptions.json_schema()
    return {"type": "object", "additionalProperties": False, "required": schema["required"],
            "properties": schema["properties"]}


SCHEMA = {
    "type": "object",
    "additionalProperties": False,
    "required": ["records", "identify"],
    "properties": {
        "records": {
            "type": "object", "additionalProperties": False,
            "properties": {"index": {"type": "string"}, "glob": {"type": "string"},
                           "time_format": {"type": "string"}, "time_regex": {"type": "string"}},
            "oneOf": [{"required": ["index"], "not": {"required": ["glob"]}},
                      {"required": ["glob", "time_format"], "not": {"required": ["index"]}}],
        },
        "identify": _identify_schema(),
        "tracking": {
            "type": "object", "additionalProperties": False,
            "properties": {"reference_modes": {"type": ["string", "null"]},
                           "freq_rtol": {"type": "number", "exclusiveMinimum": 0, "maximum": 0.5},
                           "mac_min": {"type": "number", "minimum": 0, "maximum": 1},
                           "min_share": {"type": "number", "exclusiveMinimum": 0, "maximum": 1}},
        },
        "chunk": {"type": "integer", "minimum": 1},
    },
}

TRACKING_DEFAULTS = {"reference_modes": None, "freq_rtol": 0.05, "mac_min": 0.8, "min_share": 0.3}
CHUNK = 50


def _refuse(path, error) -> None:
    where = ".".join(str(p) for p in error.absolute_path) or "(top level)"
    if error.validator == "oneOf" and list(error.absolute_path) == ["records"]:
        message = "give either index (a CSV of path,time) or glob with time_format"
    else:
        message = error.message
    raise ValueError(f"{path}: {where}: {message}")


def read_campaign(path) -> tuple[dict, pd.DataFrame]:
    """The campaign configuration at ``path`` and its index.

    Returns
    -------
    config : dict
        As written, with the defaults filled in and paths made absolute.
    index : pandas.DataFrame
        ``record`` (a name unique in the campaign: the path relative to the
        configuration's folder), ``path`` (absolute), ``time``
        (``datetime64``), sorted by time then record.
    """
    import jsonschema
    import yaml

    from ..measured import IdentifyOptions

    path = Path(path).resolve()
    try:
        config = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise ValueError(f"{path}: cannot read the campaign: {exc}") from None
    if not isinstance(config, dict):
        raise ValueError(f"{path}: a campaign is a mapping with records and identify")
    errors = sorted(jsonschema.Draft202012Validator(SCHEMA).iter_errors(config), key=lambda e: list(e.path))
    if errors:
        _refuse(path, errors[0])
    for section in ("identify", "tracking"):
        for key, value in (config.get(section) or {}).items():
            if isinstance(value, float) and not math.isfinite(value):
                raise ValueError(f"{path}: {section}.{key}: {value} is not a finite number")
    base = path.parent
    config["tracking"] = {**TRACKING_DEFAULTS, **(config.get("tracking") or {})}
    config.setdefault("chunk", CHUNK)
    # The options checked once (IdentifyOptions: bounds and cross-checks) and
    # written out in full, defaults included, for the jobs.
    config["identify"] = IdentifyOptions.from_mapping(config["identify"], where=f"{path}: identify").to_dict()
    if config["tracking"]["reference_modes"]:
        reference = (base / config["tracking"]["reference_modes"]).resolve()
        if not reference.is_file():
            raise ValueError(f"{path}: tracking.reference_modes: no file {reference}")
        config["tracking"]["reference_modes"] = str(reference)
    records = config["records"]
    if "index" in records:
        index = _read_index(base / records["index"], base)
    else:
        index = _glob_index(base, records["glob"], records["time_format"], records.get("time_regex"))
    if index.empty:
        raise ValueError(f"{path}: records: no record found")
    repeated = index["record"][index["record"].duplicated()].tolist()
    if repeated:
        raise ValueError(f"{path}: records: {repeated[0]} listed twice")
    index = index.sort_values(["time", "record"], kind="stable").reset_index(drop=True)
    _refuse_options_no_record_takes(path, IdentifyOptions.from_mapping(config["identify"]), index)
    return config, index


def _refuse_options_no_record_takes(path, options, index) -> None:
    """Options the campaign's first readable record cannot take (fmax above
    its Nyquist frequency, a channel it lacks: :meth:`IdentifyOptions.record_problems`)
    would fail every record alike: refused before any job. A record that
    cannot be read is left to its job (it lands in ``failed.csv``)."""
    from ..records import read_record

    for record_path, name in zip(index["path"], index["record"]):
        try:
            record = read_record(record_path, options.fs)
        except (ValueError, OSError):
            continue
        problems = options.record_problems(record.acc.shape[1], record.fs)
        if problems:
            raise ValueError(f"{path}: identify.{problems[0]} (record {name}, the first that reads)")
        return


def _read_index(index_path: Path, base: Path) -> pd.DataFrame:
    try:
        table = pd.read_csv(index_path, dtype={"path": str, "time": str})
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise ValueError(f"{index_path}: cannot read the index: {exc}") from None
    if not {"path", "time"} <= set(table.columns):
        raise ValueError(f"{index_path}: the index needs columns path,time; it has {', '.join(table.columns)}")
    times = pd.to_datetime(table["time"], errors="coerce", format="mixed")
    if times.isna().any():
        row = int(times.isna().to_numpy().nonzero()[0][0])
        raise ValueError(f"{index_path}: row {row + 2}: time {table['time'][row]!r} is not a date and time")
    paths = [(base / p).resolve() if not Path(p).is_absolute() else Path(p) for p in table["path"]]
    return pd.DataFrame({"record": [str(p) for p in table["path"]], "path": [str(p) for p in paths],
                         "time": times})


def _glob_index(base: Path, pattern: str, time_format: str, time_regex: str | None) -> pd.DataFrame:
    rows = []
    for p in sorted(base.glob(pattern)):
        if not p.is_file():
            continue
        text = p.stem
        if time_regex:
            match = re.search(time_regex, p.name)
            if not match:
                raise ValueError(f"{p}: records.time_regex {time_regex!r} does not match the name")
            text = match.group(1) if match.groups() else match.group(0)
        try:
            time = datetime.strptime(text, time_format)
        except ValueError:
            raise ValueError(f"{p}: records.time_format {time_format!r} does not parse {text!r}") from None
        rows.append({"record": str(p.relative_to(base)), "path": str(p), "time": time})
    return pd.DataFrame(rows, columns=["record", "path", "time"]).astype({"time": "datetime64[ns]"})


def chunks(index: pd.DataFrame, size: int) -> dict[str, pd.DataFrame]:
    """The index in consecutive chunks of ``size`` records (in time order),
    named ``c00000``, ``c00001``, ...: records added later in time add
    chunks at the end and change at most the last one."""
    return {f"c{k // size:05d}": index.iloc[k:k + size] for k in range(0, len(index), size)}
