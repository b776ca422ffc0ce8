"""A campaign's configuration and its index of records.

A campaign is a YAML file::

    records:
      index: records.csv          # columns path,time (ISO 8601, or as time_format says) and any
                                  # others (temperature, ...); paths relative to this file
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
    geometry:                     # optional: the tracked shapes drawn on the structure in the report
      folder: geometry            # as ``modal identify --geometry`` reads it (nodes.csv, pyOMA's, pyOMA2's)
      channels: channels.csv      # where each channel sits (docs: Roving tests); not needed when
                                  # the geometry names the records' channels (pyOMA2's sensors)

:func:`read_campaign` checks it (unknown keys, types and ranges are
refused with the key named) and returns it with absolute paths and the
index, sorted by time.
"""

from __future__ import annotations

import json
import math
import os
import re
import warnings
from datetime import datetime
from pathlib import Path

import pandas as pd

from ._jobs import as_text


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
        "geometry": {
            "type": "object", "additionalProperties": False, "required": ["folder"],
            "description": "draw each tracked mode's mean shape on the structure in the report",
            "properties": {
                "folder": {"type": "string", "minLength": 1,
                           "description": "the geometry's folder, relative to the campaign file, in any format "
                                          "modal identify --geometry reads (nodes.csv; pyOMA's grid.txt; "
                                          "pyOMA2's files)"},
                "channels": {"type": "string", "minLength": 1,
                             "description": "channel table (channels.csv, docs: Roving tests) placing each "
                                            "identified channel at a node and direction; not needed when the "
                                            "geometry's sensors name the records' channels (pyOMA2)"}},
        },
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


def read_campaign(path, out=None) -> tuple[dict, pd.DataFrame]:
    """The campaign configuration at ``path`` and its index; ``out``, the
    campaign's output folder: a file a ``glob`` finds inside it is the
    campaign's own (a ``failed.csv`` under ``data/**/*.csv``), never a record.

    Returns
    -------
    config : dict
        As written, with the defaults filled in (``identify`` holds every
        option of :class:`modal.IdentifyOptions`) and paths made absolute;
        ``layout``: the channel count, rate and units every record must
        share (those most records read agree on: :func:`_layout`);
        ``geometry``: None, or the geometry's ``folder``, the ``channels``
        file (or None), the channel table of the channels identified
        (``table``: records of :mod:`modal.setups`' channel table) and the
        record channels each shape entry stands for (``shape_channels``):
        :func:`_geometry`.
    index : pandas.DataFrame
        ``record`` (a name unique in the campaign: the path relative to the
        configuration's folder), ``path`` (absolute), ``time``
        (``datetime64``), sorted by time then record.
    """
    import jsonschema

    from .._config_text import check_config_text, load_strict

    from ..measured import IdentifyOptions

    path = Path(path).resolve()
    try:  # data, never code: no template, no alias bomb, no key given twice
        check_config_text(path)
        config = load_strict(path)
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the campaign: {exc.strerror or exc}") from None
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
    if isinstance(config["chunk"], bool) or not isinstance(config["chunk"], int):
        raise ValueError(f"{path}: chunk: {config['chunk']!r} is not a whole number of records")
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
        index = _read_index(base / records["index"], base, records.get("time_format"))
    else:
        try:
            re.compile(records.get("time_regex") or "")
        except re.error as exc:
            raise ValueError(f"{path}: records.time_regex {records['time_regex']!r} is not a regular expression: "
                             f"{exc}") from None
        index = _glob_index(base, records["glob"], records["time_format"], records.get("time_regex"), out)
    if index.empty:
        raise ValueError(f"{path}: records: no record found")
    repeated = index["path"].duplicated(keep=False)
    if repeated.any():
        name = index["record"][repeated.idxmax()]
        count = int((index["path"] == index["path"][repeated.idxmax()]).sum())
        raise ValueError(f"{path}: records: {name} is listed {count} times (paths naming the same file, such as "
                         "x and ./x, are one record)")
    index = index.sort_values(["time", "record"], kind="stable").reset_index(drop=True)
    options = IdentifyOptions.from_mapping(config["identify"])
    if options.fs is None:  # a .npy array holds no rate: every such record would fail in its job
        npy = index["record"][index["path"].str.lower().str.endswith(".npy")]
        if len(npy):
            raise ValueError(f"{path}: identify.fs: {len(npy)} record(s) are .npy arrays, which hold no sampling "
                             f"rate (e.g. {npy.iloc[0]}): give their rate as identify.fs (Hz) in the campaign file")
    config["layout"], example = _layout(path, options, index)
    config["geometry"] = _geometry(path, config.get("geometry"), options, config["layout"], index, example)
    if config["tracking"]["reference_modes"]:
        _check_reference_modes(path, config["tracking"]["reference_modes"], options, config["layout"])
    return config, index


def _check_reference_modes(path: Path, reference: str, options, layout: dict | None) -> None:
    """The ``tracking.reference_modes`` file read
    (:func:`modal.campaign.read_reference_modes`: a table of modes, finite
    frequencies and shapes, no row twice), its shape entries as many as the
    channels identified (``identify.channels``, else the records'): refused
    before any job."""
    from ._tracking import read_reference_modes

    try:
        table = read_reference_modes(reference)
    except ValueError as exc:
        raise ValueError(f"{path}: tracking.reference_modes: {exc}") from None
    used = len(options.channels) if options.channels is not None else \
        (None if layout is None else layout["n_channels"])
    given = sum(1 for c in table.columns if str(c).startswith("phi_"))
    if used is not None and given != used:
        where = f"identify.channels names {used}" if options.channels is not None else \
            f"the records have {used}"
        raise ValueError(f"{path}: tracking.reference_modes: {reference} has shapes over {given} channels, "
                         f"{where}: give one phi_ column per channel identified")


def _geometry(path: Path, given: dict | None, options, layout: dict | None, index: pd.DataFrame,
              example: str | None = None) -> dict | None:
    """The ``geometry`` section checked, with absolute paths, or None when
    absent: the geometry read (:func:`modal.setups.read_geometry`), the
    channel table read against it (``channels``, else the geometry's sensors
    matched by name to the channels of ``example``, a record of the
    layout: :func:`_layout`), every channel
    of the table among those identified (``identify.channels``). Adds
    ``table`` (the table's rows, as records) and ``shape_channels`` (the
    record channel of each shape entry ``phi_<k>``); ``table`` is None when
    no record reads (the sensors cannot be matched to names)."""
    from ..records import read_record
    from ..setups import read_channel_table, read_geometry

    if given is None:
        return None
    base = path.parent
    folder = (base / given["folder"]).resolve()
    try:
        geometry = read_geometry(folder)
    except ValueError as exc:
        raise ValueError(f"{path}: geometry.folder: {exc}") from None
    n_channels = None if layout is None else layout["n_channels"]
    channels = None if given.get("channels") is None else (base / given["channels"]).resolve()
    try:
        if channels is not None:
            if not channels.is_file():
                raise ValueError(f"no file {channels}")
            table = read_channel_table(channels, n_channels, geometry.nodes.index)
        elif geometry.sensors.empty:
            raise ValueError(f"{folder} names no sensors: give geometry.channels, a channel table placing each "
                             "channel at a node and direction (docs: Roving tests)")
        elif layout is None:
            table = None
        else:
            record = read_record(index.loc[index["record"] == example, "path"].iloc[0], options.fs)
            table = geometry.channel_table(record.channels["name"])
    except ValueError as exc:
        raise ValueError(f"{path}: geometry.{'channels' if channels is not None else 'folder'}: {exc}") from None
    used = list(options.channels) if options.channels is not None else \
        (list(range(n_channels)) if n_channels is not None else None)
    if table is not None and used is not None:
        outside = [int(c) for c in table["channel"] if c not in used]
        if outside:
            raise ValueError(f"{path}: geometry: channel(s) {outside} of the channel table are not identified "
                             f"(identify.channels: {', '.join(map(str, used))}): place the channels identified")
    return {"folder": str(folder), "channels": None if channels is None else str(channels),
            # plain values (a workflow's params): JSON's types, not numpy's
            "table": None if table is None else json.loads(table.to_json(orient="records")),
            "shape_channels": used}


#: Records read to find the campaign's layout (:func:`_layout`): this many
#: (all of a smaller campaign), evenly spread over its time.
LAYOUT_SAMPLE = 9


def _layout(path, options, index) -> tuple[dict | None, str | None]:
    """The channel count, sampling rate and channel units (``n_channels``,
    ``fs``, ``units``: the jobs' ``channel_units``) the campaign's records agree
    on, which every record must share (:func:`modal.campaign.identify_one`
    fails one that does not), and the first record in time that has them
    (whose channel names a geometry's sensors are matched to); ``(None,
    None)`` when no record reads.

    :data:`LAYOUT_SAMPLE` records are read (all of a small campaign): those
    evenly spread over the campaign's time first, then, for each of them
    that is missing or does not read, the others in time order; the layout is
    the one most of them share (of equal counts, the earliest's), so one odd
    record (a file cut short, a logger reconfigured for a day) fails alone in
    its job, whatever its place. The layout holds only these values, not
    which record gave them: the chunks' jobs depend on the values alone.

    Options no record of that layout can take (fmax above its Nyquist
    frequency, a channel it lacks: :meth:`IdentifyOptions.record_problems`;
    rows whose lags the longest record read cannot hold:
    :meth:`IdentifyOptions.length_problems`)
    would fail every record alike: refused here, before any job, as is a
    record whose file holds no sampling rate when ``identify.fs`` is not
    given. A record that cannot be read otherwise is left to its job (it
    lands in ``failed.csv``)."""
    import numpy as np

    from ..records import FS_CONTRADICTS, GIVE_FS, read_record
    from ._jobs import channel_units

    n = len(index)
    spread = list(dict.fromkeys(np.linspace(0, n - 1, min(n, LAYOUT_SAMPLE)).round().astype(int).tolist()))
    taken = set(spread)
    found, read = {}, 0  # layout (as a key) -> (position, name, rate, samples) of the records that have it
    contradicted = None  # the first record whose own rate identify.fs contradicts
    for k in spread + [k for k in range(n) if k not in taken]:
        if read == LAYOUT_SAMPLE:
            break
        name, record_path = index["record"].iloc[k], index["path"].iloc[k]
        if not os.path.isfile(record_path):  # missing: its job says so
            continue
        try:
            record = read_record(record_path, options.fs)
        except Exception as exc:  # any reader's failure: the record's job names it
            if options.fs is None and GIVE_FS in str(exc):
                raise ValueError(f"{path}: identify.fs: record {name} holds no sampling rate: give the rate of "
                                 "the campaign's records as identify.fs (Hz) in the campaign file") from None
            if contradicted is None and FS_CONTRADICTS in str(exc):
                contradicted = name
            continue
        read += 1
        key = (int(record.acc.shape[1]), float(f"{record.fs:.9g}"), tuple(channel_units(record)))
        found.setdefault(key, []).append((int(k), name, float(record.fs), int(record.acc.shape[0])))
    if not found:
        if contradicted is not None:  # no record reads with it: a setting every record would fail
            raise ValueError(f"{path}: identify.fs = {options.fs:g} Hz contradicts the rate the records hold (as "
                             f"{contradicted}, and no record read with it): leave identify.fs out, it is for "
                             "records that hold no rate (.npy)")
        return None, None
    key = max(found, key=lambda key: (len(found[key]), -min(k for k, *_ in found[key])))
    _, name, fs, _ = min(found[key])
    layout = {"n_channels": key[0], "fs": fs, "units": list(key[2])}
    problems = options.record_problems(layout["n_channels"], fs)
    if not problems:  # the longest record read: a shorter one alone fails in its job
        _, longest, _, n_samples = max(found[key], key=lambda read: read[3])
        used = layout["n_channels"] if options.channels is None else len(options.channels)
        problems = [problem + ("" if longest == name else f" (the longest record read: {longest})")
                    for problem in options.length_problems(n_samples, 1 / fs, used)]
    if problems:
        agreeing = len(found[key])
        raise ValueError(f"{path}: identify.{problems[0]} (the campaign's records: {layout['n_channels']} "
                         f"channels at {fs:g} Hz, as {name}" + (f" and {agreeing - 1} other(s)" if agreeing > 1
                                                                 else "") + f" of the {read} read)")
    return layout, name


def _read_index(index_path: Path, base: Path, time_format: str | None = None) -> pd.DataFrame:
    """The index's rows: ``record`` (the path as given, normalised: ``./x``
    is ``x``), ``path`` (absolute), ``time``, and any other column (a
    temperature, a wind speed) as it is. Times are ISO 8601
    (``2025-02-01T13:00``, ``2025-02-01 13:00``) or follow ``time_format``:
    ``01/02/2025`` could be either day or month first, so it needs the
    format said. Times with a UTC offset are converted to UTC
    (:func:`_index_times`); another column named as one of the campaign's
    own (``record``, ``mode``, ``freq_hz``, ...) is kept as ``index_<name>``
    (:func:`_index_column_names`)."""
    try:
        table = pd.read_csv(index_path, dtype={"path": str, "time": str})
    except (OSError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise ValueError(f"{index_path}: cannot read the index: {exc}") from None
    if not {"path", "time"} <= set(table.columns):
        raise ValueError(f"{index_path}: the index needs columns path,time; it has {', '.join(table.columns)}")
    missing = table["path"].isna() | table["time"].isna()
    if missing.any():
        row = int(missing.to_numpy().nonzero()[0][0])
        raise ValueError(f"{index_path}: row {row + 2}: no {'path' if pd.isna(table['path'][row]) else 'time'}")
    times = _index_times(index_path, table["time"], time_format)
    if times.isna().any():
        row = int(times.isna().to_numpy().nonzero()[0][0])
        expected = f"records.time_format {time_format!r}" if time_format else \
            "ISO 8601 (e.g. 2025-02-01T13:00); for another layout give records.time_format, e.g. '%d/%m/%Y %H:%M'"
        raise ValueError(f"{index_path}: row {row + 2}: time {table['time'][row]!r} does not follow {expected}")
    given = [os.path.normpath(p) for p in table["path"]]
    paths = [str((base / p).resolve()) for p in given]
    others = table.drop(columns=["path", "time"])
    return pd.concat([pd.DataFrame({"record": given, "path": paths, "time": times}),
                      others.rename(columns=_index_column_names(others.columns))], axis=1)


def _index_column_names(columns) -> dict:
    """The index's other columns (a temperature, a wind speed) renamed where
    a name is one of the campaign's own (the index's, the modes' and the
    tracked modes': ``record``, ``mode``, ``freq_hz``, ..., or a shape's
    ``phi_<k>``), which the report joins them to: ``mode`` is kept as
    ``index_mode`` (``index_index_mode`` when the index has that too)."""
    from ._jobs import FAILED_COLUMNS, MODE_COLUMNS
    from ._tracking import TRACKED_COLUMNS

    own = {"path", "time", *FAILED_COLUMNS, *MODE_COLUMNS, *TRACKED_COLUMNS}
    taken, renamed = set(map(str, columns)), {}
    for column in columns:
        name = str(column)
        if name in own or name.startswith("phi_"):
            new = f"index_{name}"
            while new in taken:
                new = f"index_{new}"
            renamed[column] = new
            taken.add(new)
    return renamed


def _index_times(index_path: Path, text: pd.Series, time_format: str | None) -> pd.Series:
    """The index's times (``NaT`` where one does not parse). Times with a
    UTC offset (``+01:00``, ``Z``) are converted to UTC, whatever their
    offsets (daylight saving changes them in the year); times with one and
    times without are refused (which zone would the latter be in?), naming
    a row of each."""
    form = time_format or "ISO8601"
    try:
        with warnings.catch_warnings():  # pandas 2 warns of offsets that differ and gives objects
            warnings.simplefilter("ignore", FutureWarning)
            times = pd.to_datetime(text, errors="coerce", format=form)
        mixed = times.dtype == object
    except ValueError:  # pandas 3: offsets that differ, or times with an offset and times without
        mixed = True
    if mixed:
        parsed = [pd.to_datetime(t, errors="coerce", format=form) for t in text]
        aware = [t is not pd.NaT and t.tzinfo is not None for t in parsed]
        naive = [t is not pd.NaT and t.tzinfo is None for t in parsed]
        if any(aware) and any(naive):
            with_offset, without = aware.index(True), naive.index(True)
            raise ValueError(f"{index_path}: row {without + 2}: time {text.iloc[without]!r} has no UTC offset, "
                             f"row {with_offset + 2}'s {text.iloc[with_offset]!r} has one: give every time an "
                             "offset (e.g. +01:00, converted to UTC) or none") from None
        times = pd.to_datetime(text, errors="coerce", format=form, utc=True)
    if isinstance(times.dtype, pd.DatetimeTZDtype):
        times = times.dt.tz_convert("UTC")
    return times


def _glob_index(base: Path, pattern: str, time_format: str, time_regex: str | None, out=None) -> pd.DataFrame:
    own = None if out is None else Path(out).resolve()
    rows = []
    for p in sorted(base.glob(pattern)):
        if not p.is_file() or (own is not None and p.resolve().is_relative_to(own)):
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
        # the record's name is text (in every CSV): a name's bytes that are not UTF-8 as \\xe9
        rows.append({"record": as_text(str(p.relative_to(base))), "path": str(p), "time": time})
    return pd.DataFrame(rows, columns=["record", "path", "time"]).astype({"time": "datetime64[ns]"})


def campaign_inputs(path, config: dict, index: pd.DataFrame) -> list[Path]:
    """Every file a campaign reads: the campaign file, its index (if any),
    the reference modes (if given), the geometry's folder and channel table
    (if given) and each record."""
    path = Path(path).resolve()
    files = [path]
    if "index" in config["records"]:
        files.append(path.parent / config["records"]["index"])
    if config["tracking"]["reference_modes"]:
        files.append(Path(config["tracking"]["reference_modes"]))
    geometry = config.get("geometry")
    if geometry:
        files += [Path(geometry["folder"])] + ([Path(geometry["channels"])] if geometry["channels"] else [])
    return files + [Path(p) for p in index["path"]]


def chunks(index: pd.DataFrame, size: int) -> dict[str, pd.DataFrame]:
    """The index in consecutive chunks of ``size`` records (in time order),
    named ``c00000``, ``c00001``, ...: records added later in time add
    chunks at the end and change at most the last one."""
    return {f"c{k // size:05d}": index.iloc[k:k + size] for k in range(0, len(index), size)}
