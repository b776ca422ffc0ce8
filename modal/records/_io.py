"""Reading and writing measured records: NumPy ``.npy`` and ``.npz``, CSV and
other delimited or whitespace-separated text (``.asc``, ``.dat``), LabVIEW ``.lvm`` (via ``lvm-read``) and Universal File
Format data set 58 (via ``pyuff``).

A record is an array ``acc`` of shape ``(n_samples, n_channels)`` sampled
every ``dt`` seconds, the input of :func:`modal.tcm`, :func:`modal.era`,
:func:`modal.cera` and :func:`modal.stabilisation`; a measured grid record
(thesis Sec. 7.2: 4096 samples at 200 Hz from eleven accelerometers) loads
with :func:`load_record` and feeds the same pipeline as the virtual test of
:func:`modal.structures.shake_test`. :func:`read_record` returns the same arrays with the
channels' metadata (name, node, direction, unit) where the file has them.

Every error raised while reading names the file, and for text files the row
(1-based line number) and column (1-based).
"""

from __future__ import annotations

import csv
import re
import stat
import unicodedata
import warnings
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from .._checks import finite_array, positive_float
from ..identification import ModalWarning

#: Relative tolerance on the uniformity of a CSV time column and on the
#: agreement of sampling rates given twice.
DT_RTOL = 1e-6
#: How a record without a sampling rate gets one, in the API and on the command line.
GIVE_FS = "give the sampling rate: fs=<Hz> (on the command line --fs <Hz>)"
#: How a refusal of an ``fs`` the file's own sampling interval contradicts reads.
FS_CONTRADICTS = "contradicts the file's dt"
#: The start of a UFF data set of type 58 (58b: binary): a line ``-1``, then its type.
_UFF58_START = re.compile(rb"(?m)^ *-1\r?\n *58b?\b")

#: Sampling rates that differ by more than this (relative) draw a warning
#: when ``fs`` overrides a text file's time column.
FS_WARN_RTOL = 1e-3

CHANNEL_COLUMNS = ["name", "node", "direction", "unit"]


@dataclass(frozen=True)
class MeasuredRecord:
    """A record as read from a file.

    Attributes
    ----------
    acc : ndarray, shape (n_samples, n_channels)
    dt : float
        Sampling interval (s).
    channels : pandas.DataFrame
        One row per channel: ``name``, ``node``, ``direction``, ``unit``
        (missing where the file does not say).
    path : pathlib.Path
    """

    acc: np.ndarray
    dt: float
    channels: pd.DataFrame = field(default_factory=pd.DataFrame)
    path: Path | None = None

    @property
    def fs(self) -> float:
        """Sampling rate (Hz)."""
        return 1.0 / self.dt


def _channels(n, **columns) -> pd.DataFrame:
    data = {c: np.full(n, None, dtype=object) for c in CHANNEL_COLUMNS}  # not a Series each: a third of the time
    data.update((name, list(values)) for name, values in columns.items())
    if columns.get("name") is None:
        data["name"] = [f"ch{c + 1}" for c in range(n)]
    return pd.DataFrame(data)  # one frame, not one column at a time (half the time)


def _as_record(acc, name: str = "acc") -> np.ndarray:
    """``acc`` as a finite ``(n_samples, n_channels)`` float array (1-D: one channel)."""
    a = finite_array(name, acc, ndim=(1, 2))
    if a.ndim == 1:
        a = a[:, None]
    if a.shape[0] < 2:
        raise ValueError(f"{name} needs at least 2 samples, got {a.shape[0]}")
    return a


def _check_layout(acc: np.ndarray) -> None:
    """Refuse a record that looks channels-first."""
    n_samples, n_channels = acc.shape
    if n_channels > n_samples:
        raise ValueError(
            f"shape {acc.shape} has more channels ({n_channels}) than samples ({n_samples}): the array looks "
            "transposed (channels first); store it as (n_samples, n_channels), e.g. np.save(path, acc.T)"
        )


def _resolve_dt(dt_file, fs, path) -> float:
    """Combine a sampling interval stored in the file with an ``fs`` argument."""
    dt_arg = None if fs is None else 1.0 / positive_float("fs", fs)
    if dt_file is None and dt_arg is None:
        raise ValueError(f"{path}: no sampling rate in the file; {GIVE_FS}")
    if dt_file is not None and dt_arg is not None and abs(dt_file - dt_arg) > DT_RTOL * dt_arg:
        raise ValueError(f"{path}: fs = {fs} Hz {FS_CONTRADICTS} = {dt_file} s")
    return dt_file if dt_file is not None else dt_arg


def _stored_positive(name, value) -> float:
    """A positive number stored in a file (booleans refused: ``dt=True`` is not 1 s)."""
    if np.asarray(value).dtype.kind not in "iuf" or np.asarray(value).size != 1:
        raise ValueError(f"{name} must be one positive number, got {value!r}")
    return positive_float(name, np.asarray(value).item())


def _load_npy(path: Path, fs):
    acc = np.load(path, allow_pickle=False)
    acc = _as_record(acc)
    return MeasuredRecord(acc, _resolve_dt(None, fs, path), _channels(acc.shape[1]), path)


def _load_npz(path: Path, fs):
    # numpy leaves a path it opened open when the zip is unreadable: the file is opened here
    with open(path, "rb") as fh:
        head = fh.read(4)
        if len(head) == 4 and head not in (b"PK\x03\x04", b"PK\x05\x06"):  # numpy: other bytes are a pickle
            raise ValueError(f"{path}: not an .npz archive (no zip header): the file is damaged or of another kind")
        fh.seek(0)
        with np.load(fh, allow_pickle=False) as data:
            keys = set(data.files)
            name = "acc" if "acc" in keys else "y" if "y" in keys else None
            if name is None:
                raise ValueError(f"{path}: expected an array 'acc' or 'y', found {sorted(keys)}")
            acc = data[name]
            dt_file = None
            if "dt" in keys:
                dt_file = _stored_positive("dt", data["dt"])
            if "fs" in keys:
                dt_fs = 1.0 / _stored_positive("fs", data["fs"])
                if dt_file is not None and abs(dt_file - dt_fs) > DT_RTOL * dt_fs:
                    raise ValueError(f"{path}: the file's dt = {dt_file} s contradicts its fs = "
                                     f"{float(data['fs'])} Hz")
                dt_file = dt_fs
    acc = _as_record(acc)
    return MeasuredRecord(acc, _resolve_dt(dt_file, fs, path), _channels(acc.shape[1]), path)


def _printed_resolution(values: np.ndarray) -> float:
    """The last printed digit's value: the largest ``10^-k`` of which every
    value is a whole multiple (0 when printed to full precision)."""
    scale = max(1.0, float(np.max(np.abs(values))))
    for k in range(0, 13):
        shifted = values * 10.0**k
        if np.all(np.abs(shifted - np.round(shifted)) <= 1e-14 * scale * 10.0**k + 1e-9):
            return 10.0**-k
    return 0.0


def _time_step(time: np.ndarray) -> float | None:
    """The step of a uniformly increasing time column, or None.

    Printed times are rounded (``%.6f`` at 1651.6 Hz: steps of 605 and 606
    microseconds), so each step may be off by one unit of the last printed
    digit; the step is the mean over the whole column.
    """
    if len(time) < 2 or not np.all(np.isfinite(time)):
        return None
    dt = (time[-1] - time[0]) / (len(time) - 1)
    if dt <= 0:
        return None
    tolerance = DT_RTOL * dt + 1.000001 * _printed_resolution(time) + 1e-12 * np.max(np.abs(time))
    return float(dt) if np.max(np.abs(np.diff(time) - dt)) <= tolerance else None


#: Seconds per unit of a text file's time column, by the unit its header names.
TIME_UNITS = {"s": 1.0, "sec": 1.0, "secs": 1.0, "second": 1.0, "seconds": 1.0,
              "ms": 1e-3, "msec": 1e-3, "millisecond": 1e-3, "milliseconds": 1e-3,
              "us": 1e-6, "usec": 1e-6, "microsecond": 1e-6, "microseconds": 1e-6,
              "min": 60.0, "minute": 60.0, "minutes": 60.0, "h": 3600.0, "hour": 3600.0, "hours": 3600.0}
#: Names of a time column (lower case), alone or with a unit (``Time [ms]``, ``time/s``); a bare ``t`` only
#: with a unit (``t_ms``, ``t [s]``): alone it may name a channel (transverse).
TIME_NAMES = ("time", "times", "timestamp", "zeit", "temps", "tiempo", "tempo", "tid", "czas")
#: Names of a first column that counts samples (lower case): it gives no rate.
SAMPLE_NAMES = ("sample", "samples", "sample no", "sample number", "index", "#")
_UNIT_IN_NAME = re.compile(r"^(?P<name>[^\[\(/_]*?)\s*(?:[\[\(](?P<bracketed>[^\]\)]*)[\]\)]|[/_](?P<suffix>\S+))?$")


def _first_column(headers) -> tuple[str | None, float | None, str]:
    """What a text file's header says of its first column: ``"time"``,
    ``"samples"`` (a sample counter) or None (nothing: time if it is uniform
    and data otherwise); the seconds per unit of a time column's values (a
    time named in ms, µs, min or h, as ``Time [ms]``, ``t_ms`` or a units row
    ``ms``, is scaled to seconds; None for a unit not known); and the header
    cell that said so."""
    kind, scale, said, named_t = None, 1.0, "", False
    for row in headers:
        cell = unicodedata.normalize("NFKC", row[0] if row else "").strip().replace("\u03bc", "u")
        key = cell.lower()
        if key in SAMPLE_NAMES:
            kind, said = "samples", cell
            continue
        if (kind == "time" or named_t) and key.strip("[]() ") in TIME_UNITS:  # a units row below the name
            kind, scale, said = "time", TIME_UNITS[key.strip("[]() ")], cell
            continue
        match = _UNIT_IN_NAME.match(key)
        unit = match and (match["bracketed"] or match["suffix"] or "").strip()
        named_t = named_t or key == "t"  # time only with a unit (here or in a units row): alone a channel's name
        if match and (match["name"].strip() in TIME_NAMES or match["name"].strip() == "t" and unit):
            kind, scale, said = "time", TIME_UNITS.get(unit) if unit else scale, cell
    return kind, scale, said


def _gap(time: np.ndarray) -> str:
    """Where a time column departs most from its median step: ``"the step
    after t = 2.99 (data row 300) is 2.01 against a median of 0.01"``."""
    steps = np.diff(time)
    median = float(np.median(steps))
    k = int(np.argmax(np.abs(steps - median)))
    return f"the step after t = {time[k]:.6g} (data row {k + 1}) is {steps[k]:.6g} against a median of {median:.6g}"


def _rate_from_time(time, fs, path, named=False):
    """``dt`` from a time column, overridden by ``fs`` when given (a
    column the header ``named`` as time must be uniform either way: a record
    with a gap is not one evenly sampled record)."""
    dt_time = _time_step(time)
    if dt_time is None and (fs is None or named):
        advice = ("the record is not evenly sampled there: cut it into its continuous parts" if named else
                  "a gap or a drifting clock? Cut the record into its continuous parts; if column 1 is data, "
                  "not time, pass fs (--fs)")
        raise ValueError(f"{path}: the time column (column 1) is not uniformly increasing: {_gap(time)}; {advice}")
    if fs is None:
        return dt_time
    dt = 1.0 / positive_float("fs", fs)
    if dt_time is not None and abs(dt_time - dt) > FS_WARN_RTOL * dt:
        warnings.warn(f"{path}: fs = {fs} Hz overrides the time column's {1 / dt_time:.6g} Hz",
                      ModalWarning, stacklevel=5)  # the caller of read_record
    return dt


_DELIMITERS = (",", ";", "\t", "|")


def _sniff_delimiter(lines, decimal):
    """The delimiter on most sampled lines, most often at least once per line; else whitespace (also
    when tabs and spaces both separate the numbers of a line)."""
    sample = [line for line in lines if line.strip()][-20:]
    best, count = None, 0
    for candidate in _DELIMITERS:
        if candidate == decimal or not sample:
            continue
        if candidate == "\t" and any(" " in cell.strip() or not cell.strip()
                                      for line in sample for cell in line.split("\t")):
            continue  # tabs among spaces, or runs of them (an .asc export's columns): whitespace separates
        # the count of most lines (the median): a row cut short does not hide the delimiter,
        # it is named by the ragged-row check
        typical = sorted(line.count(candidate) for line in sample)[len(sample) // 2]
        if typical > count:
            best, count = candidate, typical
    return best


def _number(text: str, decimal: str) -> float | None:
    text = text.strip()
    if decimal != ".":
        text = text.replace(decimal, ".")
    try:
        return float(text)
    except ValueError:
        return None


def _is_integer_literal(text: str) -> bool:
    return re.fullmatch(r"\s*[+-]?\d+\s*", text) is not None


def _numeric_header(rows, table) -> bool:
    """Is the first row a header of whole numbers (node ids) above data
    printed with decimals? It is when it breaks the time column that the rows
    below it form, or (no time column) when it is ten times larger than
    every sample below it in some column."""
    if len(rows) < 4 or not all(_is_integer_literal(c) for c in rows[0][1]):
        return False
    if all(_is_integer_literal(c) for _, row in rows[1:3] for c in row):
        return False
    if _time_step(table[1:, 0]) is not None:
        return _time_step(table[:, 0]) is None
    return bool(np.any(np.abs(table[0]) > 10 * np.max(np.abs(table[1:]), axis=0)))


def _load_csv(path: Path, fs, delimiter=None, decimal=".", skip_rows=0):
    if decimal not in (".", ","):
        raise ValueError(f"decimal must be '.' or ',', got {decimal!r}")
    if not isinstance(skip_rows, int) or isinstance(skip_rows, bool) or skip_rows < 0:
        raise ValueError(f"skip_rows must be an integer >= 0, got {skip_rows!r}")
    with open(path, newline="", encoding="utf-8-sig", errors="replace") as fh:
        lines = fh.read().splitlines()[skip_rows:]
    if delimiter is None:
        delimiter = _sniff_delimiter(lines, decimal)
    elif not isinstance(delimiter, str) or len(delimiter) != 1 or delimiter == decimal:
        raise ValueError(f"delimiter must be one character other than the decimal mark, got {delimiter!r}")
    if delimiter is None:
        split = [line.split() for line in lines]
    else:
        split = list(csv.reader(lines, delimiter=delimiter))
    rows = [(skip_rows + i + 1, row) for i, row in enumerate(split) if row and any(c.strip() for c in row)]
    # Header rows: leading rows with a non-numeric cell (names, units) ...
    headers = []
    while rows and any(_number(c, decimal) is None for c in rows[0][1] if c.strip()):
        headers.append(rows[0][1])
        rows = rows[1:]
    # ... or a row of whole numbers (node ids) narrower or wider than the data.
    if len(rows) >= 2 and all(_is_integer_literal(c) for c in rows[0][1]) and len(rows[0][1]) != len(rows[1][1]):
        rows = rows[1:]
    if len(rows) < 2:
        raise ValueError(f"{path}: fewer than 2 rows of numbers (delimiter {delimiter or 'whitespace'!r}, "
                         f"decimal {decimal!r}); pass delimiter=, decimal= or skip_rows= "
                         "(--delimiter, --decimal, --skip-rows)")
    width = len(rows[0][1])
    separated = "whitespace-separated values" if delimiter is None else f"values separated by {delimiter!r}"
    for k, (line, row) in enumerate(rows):
        if len(row) != width:
            cut = " (the last row: is the file cut short?)" if k == len(rows) - 1 else ""
            raise ValueError(f"{path}: ragged rows (channels of unequal length): row {line} has {len(row)} {separated}, row {rows[0][0]} has "
                             f"{width}{cut}: every row must hold one value per column (a value missing or extra, "
                             "or another delimiter: pass delimiter=, --delimiter)")
    table = _fast_table(rows, decimal)
    slow = table is None
    if slow:
        table = np.empty((len(rows), width))
    for i, (line, row) in enumerate(rows if slow else []):
        for j, cell in enumerate(row):
            if not cell.strip():
                raise ValueError(f"{path}: row {line}, column {j + 1} is empty")
            value = _number(cell, decimal)
            if value is None or not np.isfinite(value):
                raise ValueError(f"{path}: row {line}, column {j + 1}: {cell.strip()!r} is not a finite number"
                                 + ("" if decimal == "," else " (decimal commas: pass decimal=',', --decimal ,)"))
            table[i, j] = value
    if _numeric_header(rows, table):
        table = table[1:]
    names = _header_names(headers, width)
    first, scale, said = _first_column(headers)
    if first == "samples" or scale is None:  # a first column whose step is no sampling interval in seconds
        if fs is None:
            what = "counts samples" if first == "samples" else "holds time in a unit other than h, min, ms, s, us"
            raise ValueError(f"{path}: column 1 ({said!r}) {what}: {GIVE_FS}, or write the time in s")
        _rate_from_time(table[:, 0], None, path, named=True)  # uniform, or its gap is named
        dt, acc, names = 1.0 / positive_float("fs", fs), table[:, 1:], names and names[1:]
    elif width >= 2 and (fs is None or first == "time" or _time_step(table[:, 0]) is not None):
        table[:, 0] *= scale
        dt = _rate_from_time(table[:, 0], fs, path, named=first == "time")
        acc, names = table[:, 1:], names and names[1:]
    elif fs is None:
        raise ValueError(f"{path}: without fs the first column must be time (s), followed by channels")
    else:
        dt, acc = 1.0 / positive_float("fs", fs), table
    acc = _as_record(acc)
    return MeasuredRecord(acc, dt, _channels(acc.shape[1], **({"name": names} if names else {})), path)


def _load_text(path: Path, fs, decimal=None, **options):
    """:func:`_load_csv` with the decimal mark given, or else with a point,
    or with a comma where only a comma reads the numbers (a European
    spreadsheet's export); when neither does, the point's error."""
    if decimal is not None:
        return _load_csv(path, fs, decimal=decimal, **options)
    try:
        return _load_csv(path, fs, decimal=".", **options)
    except ValueError as point:
        try:
            return _load_csv(path, fs, decimal=",", **options)
        except ValueError:
            raise point from None


def _fast_table(rows, decimal) -> np.ndarray | None:
    """The rows' cells as one float array when every cell is a finite
    number with a point as decimal mark (numpy parses them at C speed); else
    None, and the caller's cell-by-cell pass names the first bad cell."""
    if decimal != ".":
        return None
    try:
        table = np.array([row for _, row in rows], dtype=float)
    except (ValueError, TypeError):
        return None
    return table if np.all(np.isfinite(table)) else None


def _header_names(headers, width):
    """The channel names of a text file: its first header row with one
    non-empty cell per column (a second row is usually the units), or None."""
    for row in headers:
        cells = [c.strip() for c in row]
        if len(cells) == width and all(cells):
            return cells
    return None


def _load_lvm(path: Path, fs):
    import lvm_read

    # No pickle cache next to the user's file: read the text every time.
    lvm = lvm_read.read(str(path), read_from_pickle=False, dump_file=False)
    if lvm.get("Segments", 1) != 1:
        raise ValueError(f"{path}: {lvm['Segments']} segments; only single-segment LabVIEW files are supported")
    segment = lvm[0]
    data = np.asarray(segment["data"], dtype=float)
    # the header's samples per channel (NaN for the comment column): more than the rows read means cut short
    declared = pd.to_numeric(pd.Series(np.atleast_1d(segment.get("Samples", [])), dtype=object), errors="coerce")
    if declared.max() > len(data):
        raise ValueError(f"{path}: the header says {int(declared.max())} samples, the file holds {len(data)} "
                         "rows: is the file cut short?")
    names = list(segment.get("Channel names", []))[: data.shape[1]]
    is_time = np.array([name == "X_Value" for name in names] + [False] * (data.shape[1] - len(names)))
    if is_time.all():
        raise ValueError(f"{path}: no data column, only time")
    acc = data[:, ~is_time]
    for j in range(acc.shape[1]):
        bad = np.flatnonzero(~np.isfinite(acc[:, j]))
        if bad.size:
            raise ValueError(f"{path}: data row {bad[0] + 1}, channel {j + 1} is empty or not a number")
    if is_time.any():
        dt = _rate_from_time(data[:, np.argmax(is_time)], fs, path)
    elif fs is not None:
        dt = 1.0 / positive_float("fs", fs)
    else:
        deltas = np.asarray(segment.get("Delta_X", [np.nan]), dtype=float)
        if not np.isfinite(deltas[0]) or deltas[0] <= 0:
            raise ValueError(f"{path}: no time column and no Delta_X; {GIVE_FS}")
        dt = float(deltas[0])
    units = list(segment.get("Y_Unit_Label", []))[: acc.shape[1]]
    units += [None] * (acc.shape[1] - len(units))
    y_names = [n for n, t in zip(names, is_time) if not t]
    y_names += [f"ch{c + 1}" for c in range(len(y_names), acc.shape[1])]
    return MeasuredRecord(_as_record(acc), dt, _channels(acc.shape[1], name=y_names, unit=units), path)


def _load_uff(path: Path, fs):
    import pyuff

    try:
        sets = pyuff.UFF(str(path)).read_sets()
    except Exception as exc:  # pyuff raises a bare Exception on a malformed set
        raise ValueError(f"{path}: not a readable UFF file ({type(exc).__name__}: {exc})") from None
    if isinstance(sets, dict):
        sets = [sets]
    sets = [s for s in sets if s.get("type") == 58]
    if not sets:
        raise ValueError(f"{path}: no UFF data set of type 58")
    # pyuff skips a last set without its end: a file cut short reads as fewer channels
    with open(path, "rb") as fh:
        begun = len(_UFF58_START.findall(fh.read()))
    if begun > len(sets):
        raise ValueError(f"{path}: {begun} data sets of type 58 begin but only {len(sets)} are complete: "
                         "is the file cut short?")
    lengths = {len(s["data"]) for s in sets}
    if len(lengths) != 1:
        raise ValueError(f"{path}: type-58 sets of unequal length {sorted(lengths)}")
    if any(np.iscomplexobj(s["data"]) for s in sets):
        raise ValueError(f"{path}: complex type-58 data (a spectrum, not a time record)")
    incs = np.array([float(s.get("abscissa_inc", 0.0)) for s in sets])
    dt_file = None
    if np.all(incs > 0):
        if np.max(np.abs(incs - incs[0])) > DT_RTOL * incs[0]:
            raise ValueError(f"{path}: type-58 sets with different abscissa_inc {np.unique(incs).tolist()}")
        dt_file = float(incs[0])
    acc = _as_record(np.column_stack([np.asarray(s["data"], dtype=float) for s in sets]))
    channels = _channels(
        len(sets),
        name=[str(s.get("id1", "")).strip() or f"ch{c + 1}" for c, s in enumerate(sets)],
        node=[s.get("rsp_node") for s in sets],
        direction=[s.get("rsp_dir") for s in sets],
        unit=[_uff_unit(s.get("ordinate_axis_units_lab")) for s in sets],
    )
    return MeasuredRecord(acc, _resolve_dt(dt_file, fs, path), channels, path)


def _uff_unit(label) -> str | None:
    """A type-58 set's ordinate unit label, or None (none, blank, or pyuff's ``NONE``)."""
    label = "" if label is None else str(label).strip()
    return None if label.upper() in ("", "NONE") else label


def _file_kind(mode: int) -> str:
    """What a file that is not a regular file is, for messages."""
    for test, kind in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return kind
    return "not a regular file"


_LOADERS = {".npy": _load_npy, ".npz": _load_npz, ".csv": _load_csv, ".txt": _load_csv, ".tsv": _load_csv,
            ".asc": _load_csv, ".dat": _load_csv, ".lvm": _load_lvm, ".uff": _load_uff, ".unv": _load_uff}


def read_record(path, fs=None, *, delimiter=None, decimal=None, skip_rows=0) -> MeasuredRecord:
    """Read a measured record with its channels' metadata.

    Formats, by extension:

    ``.npy``
        One array ``(n_samples, n_channels)`` or ``(n_samples,)``; pass ``fs``.
    ``.npz``
        An array ``acc`` (or ``y``) and ``dt`` (s) or ``fs`` (Hz).
    ``.csv``, ``.txt``, ``.tsv``, ``.asc``, ``.dat``
        Delimited numbers: ``, ; tab |`` when every row holds one (sniffed),
        else whitespace (the ``.asc`` export of ambient test systems: columns
        separated by spaces or tabs, however many). Leading rows with text (names, units) are headers,
        and so is a first row of whole numbers (node ids) above data printed
        with decimals. Without ``fs`` the first column is time in s; with
        ``fs`` a uniformly increasing first column is still time, dropped,
        and ``fs`` sets the rate (a warning when they disagree). Printed
        times may be rounded: each step may be off by one unit of the last
        printed digit; the rate is the mean step.
    ``.lvm``
        LabVIEW measurement file (``lvm_read.read``); ``X_Value`` columns are
        time, the others channels, with their names and ``Y_Unit_Label``.
        The rate is the time column's mean step (the header's ``Delta_X`` is
        rounded), or ``fs``.
    ``.uff``, ``.unv``
        Universal File Format; every data set of type 58 becomes a channel,
        in file order, with its node (``rsp_node``), direction (``rsp_dir``)
        and unit label; ``dt`` is its ``abscissa_inc`` (6 significant digits).

    Parameters
    ----------
    path : str or path-like
    fs : float, optional
        Sampling rate in Hz, needed when the file has none. Binary formats
        must agree with it; text formats' time columns are overridden.
    delimiter : str, optional
        Text files: one character (default: sniffed from ``, ; tab |``, else
        whitespace).
    decimal : {".", ","}, optional
        Text files: decimal mark (default: a point, or a comma when the
        file reads only with a comma, as a European spreadsheet's export
        ``0,01;1,234;...`` does; the error is then the point's).
    skip_rows : int
        Text files: lines skipped at the top before anything is read.

    Returns
    -------
    MeasuredRecord

    Raises
    ------
    ValueError
        Naming the file (and the row and column of a text file): unknown
        extension, a path that is not a regular file (a directory, a FIFO or
        a device: refused before opening, which could block or never end), an
        empty or non-numeric cell, NaN or inf, data that are not real numbers
        (booleans, complex, strings, ``datetime64``, ``timedelta64``), channels
        of unequal length (a text file's ragged rows: the message names the
        first row whose count of values differs), missing or contradictory
        sampling rate, a channels-first array.
    """
    path = Path(path)
    ext = path.suffix.lower()
    if path.is_dir():
        raise ValueError(f"path: {path} is a folder, not a record file (a roving test's setup is a folder with a "
                         "channels.csv or pyOMA's channel_dofs.txt beside its record; the setups of a folder are "
                         f"given one by one, e.g. {path / '*'})")
    if ext not in _LOADERS:
        raise ValueError(f"path: {path}: unknown record format {ext!r}; expected one of {sorted(_LOADERS)}")
    if not path.exists():
        raise ValueError(f"path: {path} does not exist")
    # Only a regular file is a record: opening a FIFO blocks until a writer
    # comes, and a device (/dev/zero, a terminal) never ends.
    try:
        mode = path.stat().st_mode
    except OSError as exc:
        raise ValueError(f"path: {path} cannot be read ({exc.strerror})") from None
    if not stat.S_ISREG(mode):
        raise ValueError(f"path: {path} is {_file_kind(mode)}, not a record file")
    try:
        if _LOADERS[ext] is _load_csv:
            record = _load_text(path, fs, delimiter=delimiter, decimal=decimal, skip_rows=skip_rows)
        else:
            record = _LOADERS[ext](path, fs)
        _check_layout(record.acc)
    except ValueError as exc:
        if str(path) in str(exc):
            raise
        raise ValueError(f"{path}: {exc}") from None
    except (OSError, UnicodeError, EOFError, zipfile.BadZipFile) as exc:  # an empty .npy, a .npz cut short
        raise ValueError(f"{path}: cannot be read as {ext} ({exc})") from None
    return record


def load_record(path, fs=None, **options):
    """Read a measured record: ``acc`` (n_samples x n_channels) and ``dt`` (s).

    The formats, options and errors of :func:`read_record`, which also
    returns the channels' metadata.

    Returns
    -------
    acc : ndarray, shape (n_samples, n_channels)
    dt : float
        Sampling interval in s.
    """
    record = read_record(path, fs, **options)
    return record.acc, record.dt


def save_record_npz(path, acc, dt) -> Path:
    """Write ``acc`` (n_samples x n_channels) and ``dt`` (s) to ``path`` (.npz)."""
    acc = _as_record(acc)
    dt = positive_float("dt", dt)
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise ValueError(f"path must end in .npz, got {path.name!r}")
    with open(path, "wb") as fh:  # np.savez(path) would append .npz to a path ending in .NPZ
        np.savez(fh, acc=acc, dt=dt)
    return path


def write_uff58(path, acc, dt, nodes=None, direction=3, binary=False) -> Path:
    """Write each channel of ``acc`` as a UFF type-58 time record (func_type 1,
    response node ``nodes[c]``, direction ``direction``), with ``pyuff``.

    Parameters
    ----------
    path : str or path-like
        Output file (``.uff`` or ``.unv``); overwritten.
    acc : array_like, shape (n_samples, n_channels)
    dt : float
        Sampling interval (s).
    nodes : sequence of int, optional
        Response node number per channel; default ``1..n_channels``.
    direction : int
        UFF direction code (3 = +Z, out of the grid's plane).
    binary : bool
        Binary (exact doubles) instead of ASCII (11 decimal digits) data.
    """
    import pyuff

    acc = _as_record(acc)
    dt = positive_float("dt", dt)
    path = Path(path)
    if path.suffix.lower() not in (".uff", ".unv"):
        raise ValueError(f"path must end in .uff or .unv, got {path.name!r}")
    n, l = acc.shape
    nodes = list(range(1, l + 1)) if nodes is None else [int(v) for v in nodes]
    if len(nodes) != l:
        raise ValueError(f"nodes must have {l} entries, got {len(nodes)}")
    t = dt * np.arange(n)
    sets = [
        pyuff.prepare_58(
            binary=int(bool(binary)),
            id1=f"acceleration channel {c + 1}",
            func_type=1,
            rsp_node=nodes[c],
            rsp_dir=direction,
            ref_node=0,
            ref_dir=0,
            ord_data_type=4,
            num_pts=n,
            abscissa_spacing=1,
            abscissa_min=0.0,
            abscissa_inc=dt,
            abscissa_spec_data_type=17,  # time
            ordinate_spec_data_type=12,  # acceleration
            orddenom_spec_data_type=0,
            data=acc[:, c].copy(),
            x=t,
        )
        for c in range(l)
    ]
    if path.exists():
        path.unlink()
    # "add" on a fresh file: pyuff 2.5 truncates binary data written in "overwrite" mode.
    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path
