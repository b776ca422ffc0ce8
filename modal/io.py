"""Reading and writing measured records: NumPy ``.npz``, CSV and Universal
File Format data set 58 (via the maintained ``pyuff`` library).

A record is an array ``acc`` of shape ``(n_samples, n_channels)`` sampled
every ``dt`` seconds, the input of :func:`modal.tcm`, :func:`modal.era` and
:func:`modal.cera`; a measured grid record (thesis Sec. 7.2: 4096 samples at
200 Hz from eleven accelerometers) loads with :func:`load_record` and feeds the
same pipeline as the virtual test of :mod:`modal.experiment`.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ._checks import finite_array, positive_float

#: Relative tolerance on the uniformity of a CSV time column and on the
#: agreement of sampling rates given twice.
DT_RTOL = 1e-6


def _as_record(acc, name: str = "acc") -> np.ndarray:
    """``acc`` as a finite ``(n_samples, n_channels)`` float array (1-D: one channel)."""
    a = finite_array(name, acc, ndim=(1, 2))
    if a.ndim == 1:
        a = a[:, None]
    if a.shape[0] < 2:
        raise ValueError(f"{name} needs at least 2 samples, got {a.shape[0]}")
    return a


def _resolve_dt(dt_file, fs, path) -> float:
    """Combine a sampling interval stored in the file with an ``fs`` argument."""
    dt_arg = None if fs is None else 1.0 / positive_float("fs", fs)
    if dt_file is None and dt_arg is None:
        raise ValueError(f"{path}: no sampling rate in the file; pass fs (Hz)")
    if dt_file is not None and dt_arg is not None and abs(dt_file - dt_arg) > DT_RTOL * dt_arg:
        raise ValueError(f"{path}: fs = {fs} Hz contradicts the file's dt = {dt_file} s")
    return dt_file if dt_file is not None else dt_arg


def _load_npz(path: Path, fs):
    with np.load(path, allow_pickle=False) as data:
        keys = set(data.files)
        name = "acc" if "acc" in keys else "y" if "y" in keys else None
        if name is None:
            raise ValueError(f"{path}: expected an array 'acc' or 'y', found {sorted(keys)}")
        acc = data[name]
        dt_file = None
        if "dt" in keys:
            dt_file = positive_float("dt", data["dt"])
        if "fs" in keys:
            dt_fs = 1.0 / positive_float("fs", data["fs"])
            if dt_file is not None and abs(dt_file - dt_fs) > DT_RTOL * dt_fs:
                raise ValueError(f"{path}: the file's dt = {dt_file} s contradicts its fs = {float(data['fs'])} Hz")
            dt_file = dt_fs
    return _as_record(acc), _resolve_dt(dt_file, fs, path)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _load_csv(path: Path, fs):
    with open(path, newline="") as fh:
        rows = [row for row in csv.reader(fh) if row and any(cell.strip() for cell in row)]
    if rows and not all(_is_number(cell) for cell in rows[0]):
        rows = rows[1:]  # header row
    if len(rows) < 2:
        raise ValueError(f"{path}: fewer than 2 data rows")
    widths = {len(row) for row in rows}
    if len(widths) != 1:
        raise ValueError(
            f"{path}: rows have unequal numbers of columns {sorted(widths)}: channels of unequal length"
        )
    try:
        table = np.array([[float(cell) if cell.strip() else np.nan for cell in row] for row in rows])
    except ValueError as exc:
        raise ValueError(f"{path}: non-numeric entry ({exc})") from None
    if fs is not None:
        return _as_record(table), 1.0 / positive_float("fs", fs)
    if table.shape[1] < 2:
        raise ValueError(f"{path}: without fs the first column must be time (s), followed by channels")
    time = finite_array("time column", table[:, 0], ndim=(1,))
    steps = np.diff(time)
    dt = float(np.mean(steps))
    if dt <= 0 or np.max(np.abs(steps - dt)) > DT_RTOL * max(dt, 1e-300) + 1e-12:
        raise ValueError(f"{path}: the time column is not uniformly increasing; pass fs if column 1 is data")
    return _as_record(table[:, 1:]), dt


def _load_uff(path: Path, fs):
    import pyuff

    sets = pyuff.UFF(str(path)).read_sets()
    if isinstance(sets, dict):
        sets = [sets]
    sets = [s for s in sets if s.get("type") == 58]
    if not sets:
        raise ValueError(f"{path}: no UFF data set of type 58")
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
    acc = np.column_stack([np.asarray(s["data"], dtype=float) for s in sets])
    return _as_record(acc), _resolve_dt(dt_file, fs, path)


def load_record(path, fs=None):
    """Read a measured record.

    Formats, by extension:

    ``.npz``
        An array ``acc`` (or ``y``), shape ``(n_samples, n_channels)`` or
        ``(n_samples,)``, and ``dt`` (s) or ``fs`` (Hz).
    ``.csv``
        Comma-separated numbers, an optional header row. Without ``fs`` the
        first column is time in s (uniform) and the others are channels; with
        ``fs`` every column is a channel.
    ``.uff``, ``.unv``
        Universal File Format; every data set of type 58 (function at a node,
        real time data) becomes a channel, in file order, and ``dt`` is its
        ``abscissa_inc`` (read with ``pyuff.UFF(path).read_sets()``). The UFF
        header stores ``abscissa_inc`` with 6 significant digits.

    Parameters
    ----------
    path : str or path-like
    fs : float, optional
        Sampling rate in Hz, needed when the file has none; if the file has
        one too, they must agree.

    Returns
    -------
    acc : ndarray, shape (n_samples, n_channels)
    dt : float
        Sampling interval in s.

    Raises
    ------
    ValueError
        Unknown extension, NaN or inf, channels of unequal length, missing
        or contradictory sampling rate.
    """
    path = Path(path)
    loaders = {".npz": _load_npz, ".csv": _load_csv, ".uff": _load_uff, ".unv": _load_uff}
    ext = path.suffix.lower()
    if ext not in loaders:
        raise ValueError(f"path: unknown record format {ext!r}; expected one of {sorted(loaders)}")
    if not path.exists():
        raise ValueError(f"path: {path} does not exist")
    return loaders[ext](path, fs)


def save_record_npz(path, acc, dt) -> Path:
    """Write ``acc`` (n_samples x n_channels) and ``dt`` (s) to ``path`` (.npz)."""
    acc = _as_record(acc)
    dt = positive_float("dt", dt)
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise ValueError(f"path must end in .npz, got {path.name!r}")
    np.savez(path, acc=acc, dt=dt)
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
