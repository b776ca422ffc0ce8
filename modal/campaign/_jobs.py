"""One job of a campaign: the records of a chunk identified one after the
other in one process, so start-up is paid once per chunk."""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

MODE_COLUMNS = ["record", "time", "mode", "freq_hz", "freq_std_hz", "damping", "damping_std", "mpc", "n_poles"]
FAILED_COLUMNS = ["record", "reason"]
#: How a campaign's record without a sampling rate gets one (in place of the
#: command line's :data:`modal.records.GIVE_FS`).
CAMPAIGN_FS = "give the sampling rate: identify.fs (Hz) in the campaign file"


def as_text(name: str) -> str:
    """``name`` as UTF-8 text: a path's bytes that are not UTF-8 (held by
    Python as surrogates, ``\\udce9``) written as ``\\xe9``, so that every
    CSV, log and report can hold it (a surrogate cannot be written)."""
    try:
        return name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    except UnicodeEncodeError:  # a surrogate no file name's byte gives
        return name.encode("utf-8", "backslashreplace").decode("utf-8")


def channel_units(record) -> list:
    """The unit each channel of ``record`` declares (a UFF's or LVM's unit
    label) in one spelling (:func:`modal.records.unit_key`: ``m/s^2`` and
    ``m/s²`` are one unit), None where the file names none."""
    from ..records import unit_key

    units = record.channels["unit"] if "unit" in record.channels else [None] * record.acc.shape[1]
    return [None if u is None or (isinstance(u, float) and u != u) or not str(u).strip() else unit_key(u)
            for u in units]


def identify_one(path, options, layout: dict | None = None, warned: list | None = None):
    """Modes of one record with ``modal identify``'s options
    (:class:`modal.IdentifyOptions`, or a mapping of them such as a campaign
    file's ``identify`` section): the :class:`Stabilisation`, or
    ``ValueError``/``OSError`` saying why it cannot be read or identified.

    ``layout`` (``n_channels``, ``fs``, ``units``: those the campaign's
    records agree on, :func:`modal.campaign.read_campaign`) is what every record must
    share: a record with another channel count or rate (a file cut short, a
    logger reconfigured) is refused before identification.

    The identification's warnings (a clipped channel, no mode selected, ...)
    are not shown; each is appended to ``warned`` (a list, when given) as
    ``"<category>: <message>"`` on one line, also when the identification
    then fails."""
    from ..measured import identify_options, identify_record
    from ..records import read_record

    options = identify_options(options)
    record = read_record(path, options.fs)
    if layout is not None:
        n_channels = record.acc.shape[1]
        if n_channels != layout["n_channels"]:
            raise ValueError(f"{n_channels} channels, the campaign's records {layout['n_channels']}")
        if not math.isclose(record.fs, layout["fs"], rel_tol=1e-9):
            raise ValueError(f"sampled at {record.fs:g} Hz, the campaign's records at {layout['fs']:g} Hz")
        units, expected = channel_units(record), layout.get("units") or [None] * n_channels
        differ = [c for c, (u, e) in enumerate(zip(units, expected)) if u and e and u != e]
        if differ:
            c = differ[0]
            raise ValueError(f"channel {c} in {units[c]}, the campaign's records in {expected[c]}: the shapes "
                             "would mix units")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # each of them, however often one line of code warns
        try:
            result, _ = identify_record(record.acc, record.dt, options)
        finally:
            if warned is not None:
                warned.extend(f"{w.category.__name__}: {' '.join(str(w.message).split())}" for w in caught)
    return result


def identify_chunk(records: pd.DataFrame, options, modes_csv, failed_csv, layout: dict | None = None) -> None:
    """Identify each record of ``records`` (``record``, ``path``, ``time``)
    and write ``modes_csv`` (one row per trusted mode, those without a
    ``flag`` from the selection, as ``modal identify`` prints them:
    :data:`MODE_COLUMNS` and the real shape, ``phi_0``, ``phi_1``, ... over
    the channels used) and
    ``failed_csv`` (``record, reason``: could not be read or identified, or
    does not share the campaign's ``layout``, :func:`identify_one`). Each
    warning of a record's identification (a clipped channel, no mode
    selected, ...) is one line ``<record>: <category>: <message>`` on
    standard error: the job's log.

    No record stops the others: any failure of one (an exception of any type,
    e.g. a reader's bare ``Exception`` on a corrupt file) puts it in
    ``failed_csv`` with a one-line reason. A record with no structural
    response gives no row in either."""
    from ..records import GIVE_FS

    rows, failed = [], []
    for rec in records.itertuples():
        warned = []
        try:
            result = identify_one(rec.path, options, layout, warned)
        except Exception as exc:  # one record's failure, whatever its kind, is that record's
            # the rate is the campaign file's identify.fs, not the command line's --fs
            reason = _reason(exc).replace(GIVE_FS, CAMPAIGN_FS)
            failed.append({"record": as_text(rec.record), "reason": as_text(reason)})
            continue
        finally:
            for line in warned:
                print(as_text(f"{rec.record}: {line}"), file=sys.stderr)
        modes = result.modes
        trusted = (modes["flag"].fillna("") == "").to_numpy() if "flag" in modes else np.ones(len(modes), bool)
        time = pd.Timestamp(rec.time).isoformat()  # one format in every chunk: ISO 8601, whole or not
        for k in np.flatnonzero(trusted):  # a doubtful mode (its flag says why) is never tracked
            row = {"record": as_text(rec.record), "time": time}
            row.update({c: modes[c].iloc[k] for c in MODE_COLUMNS[2:]})
            row.update({f"phi_{c}": v for c, v in enumerate(result.shapes[:, k])})
            rows.append(row)
    table = pd.DataFrame(rows)
    if table.empty:
        table = pd.DataFrame(columns=MODE_COLUMNS)
    for path in (modes_csv, failed_csv):
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(modes_csv, index=False, float_format="%.8g")
    pd.DataFrame(failed, columns=FAILED_COLUMNS).to_csv(failed_csv, index=False)


def _reason(exc: BaseException) -> str:
    """One line saying why a record failed: the message, else the exception's
    type; the type is named too unless the engine's own refusal
    (``ValueError``) or an ``OSError`` already says what happened."""
    message = " ".join(str(exc).split())
    if isinstance(exc, (ValueError, OSError)) and message:
        return message
    if isinstance(exc, MemoryError):
        return f"out of memory ({message})" if message else "out of memory"
    return f"{type(exc).__name__}: {message}" if message else type(exc).__name__


def gather(modes_files, failed_files) -> tuple[pd.DataFrame, pd.DataFrame]:
    """All chunks' modes (with ``time`` as datetime) and failures, in order."""
    frames = [pd.read_csv(f) for f in modes_files]
    modes = pd.concat([f for f in frames if not f.empty] or [pd.DataFrame(columns=MODE_COLUMNS)],
                      ignore_index=True)
    # ISO 8601 as identify_chunk writes it; a chunk written before that, as its time's own string
    modes["time"] = pd.to_datetime(modes["time"], format="ISO8601")
    failed = pd.concat([pd.read_csv(f) for f in failed_files] or [pd.DataFrame(columns=FAILED_COLUMNS)],
                       ignore_index=True)
    return modes, failed


def shape_matrix(modes: pd.DataFrame) -> np.ndarray:
    """The ``phi_<k>`` columns of ``modes`` as ``(n_channels, n_modes)``."""
    columns = sorted((c for c in modes.columns if c.startswith("phi_")), key=lambda c: int(c[4:]))
    return modes[columns].to_numpy(dtype=float).T
