"""One job of a campaign: the records of a chunk identified one after the
other in one process, so start-up is paid once per chunk."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pandas as pd

MODE_COLUMNS = ["record", "time", "mode", "freq_hz", "freq_std_hz", "damping", "damping_std", "mpc", "n_poles"]
FAILED_COLUMNS = ["record", "reason"]


def identify_one(path, options):
    """Modes of one record with ``modal identify``'s options
    (:class:`modal.IdentifyOptions`, or a mapping of them such as a campaign
    file's ``identify`` section): the :class:`Stabilisation`, or
    ``ValueError``/``OSError`` saying why it cannot be read or identified."""
    from ..measured import identify_options, identify_record
    from ..records import read_record

    options = identify_options(options)
    record = read_record(path, options.fs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "no mode selected" and the like: the table says it
        result, _ = identify_record(record.acc, record.dt, options)
    return result


def identify_chunk(records: pd.DataFrame, options: dict, modes_csv, failed_csv) -> None:
    """Identify each record of ``records`` (``record``, ``path``, ``time``)
    and write ``modes_csv`` (one row per mode: :data:`MODE_COLUMNS` and the
    real shape, ``phi_0``, ``phi_1``, ... over the channels used) and
    ``failed_csv`` (``record, reason``: could not be read or identified).
    A record with no structural response gives no row in either."""
    rows, failed = [], []
    for rec in records.itertuples():
        try:
            result = identify_one(rec.path, options)
        except (ValueError, OSError, MemoryError) as exc:
            failed.append({"record": rec.record, "reason": " ".join(str(exc).split()) or type(exc).__name__})
            continue
        modes = result.modes
        for k in range(len(modes)):
            row = {"record": rec.record, "time": rec.time}
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


def gather(modes_files, failed_files) -> tuple[pd.DataFrame, pd.DataFrame]:
    """All chunks' modes (with ``time`` as datetime) and failures, in order."""
    frames = [pd.read_csv(f) for f in modes_files]
    modes = pd.concat([f for f in frames if not f.empty] or [pd.DataFrame(columns=MODE_COLUMNS)],
                      ignore_index=True)
    modes["time"] = pd.to_datetime(modes["time"])
    failed = pd.concat([pd.read_csv(f) for f in failed_files] or [pd.DataFrame(columns=FAILED_COLUMNS)],
                       ignore_index=True)
    return modes, failed


def shape_matrix(modes: pd.DataFrame) -> np.ndarray:
    """The ``phi_<k>`` columns of ``modes`` as ``(n_channels, n_modes)``."""
    columns = sorted((c for c in modes.columns if c.startswith("phi_")), key=lambda c: int(c[4:]))
    return modes[columns].to_numpy(dtype=float).T
