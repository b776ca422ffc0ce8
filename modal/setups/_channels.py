"""Channel tables: what each channel of a record measures and where.

A channel table is a :class:`pandas.DataFrame` with one row per channel
used, in the order identification sees them:

``channel``
    the record's column (0-based);
``name``
    the channel's name;
``node``
    the geometry node it is fixed at (text: ``"5"``, ``"A3"``);
``x``, ``y``, ``z``
    the unit vector of its measuring direction in the global frame;
``quantity``
    ``displacement``, ``velocity`` or ``acceleration``;
``unit``
    its unit (``m/s``, ``mm/s2``, ``g``, ...; empty: SI);
``role``
    ``reference`` (in every setup, at the same node and direction) or
    ``roving``.

It is read from pyOMA's setup layout (:func:`read_pyoma_setup`), from
pyOMA2's geometry files (:func:`modal.setups.read_geometry`, whose sensors
give one) or from the project's own CSV (:func:`read_channel_table`).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pandas as pd

from ..identification import QUANTITIES
from ..records import unit_key

COLUMNS = ["channel", "name", "node", "x", "y", "z", "quantity", "unit", "role"]
ROLES = ("reference", "roving")

#: Factor to SI of each unit the table may name, in the spelling
#: :func:`unit_key` brings every spelling to: displacement to m, velocity
#: to m/s, acceleration to m/s^2 (``mg`` is milli-g, ``gal`` cm/s^2).
UNITS = {
    "displacement": {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 0.0254},
    "velocity": {"m/s": 1.0, "cm/s": 1e-2, "mm/s": 1e-3, "um/s": 1e-6, "in/s": 0.0254},
    "acceleration": {"m/s2": 1.0, "cm/s2": 1e-2, "gal": 1e-2, "mm/s2": 1e-3, "g": 9.80665, "mg": 9.80665e-3,
                     "in/s2": 0.0254},
}

#: Components of a unit direction whose norm differs from 1 by more than
#: this are refused; smaller deviations (rounded files) are normalised.
DIRECTION_RTOL = 1e-2


def direction_from_angles(azimuth_deg, elevation_deg) -> np.ndarray:
    """Unit vectors ``(cos b cos a, cos b sin a, sin b)`` for azimuth ``a`` and
    elevation ``b`` in degrees (pyOMA's convention: azimuth from x towards y
    in the horizontal plane, elevation up from it); shape ``(n, 3)``."""
    a = np.radians(np.asarray(azimuth_deg, dtype=float))
    b = np.radians(np.asarray(elevation_deg, dtype=float))
    e = np.stack([np.cos(b) * np.cos(a), np.cos(b) * np.sin(a), np.sin(b)], axis=-1)
    e[np.abs(e) < 1e-12] = 0.0  # cos(90 deg) is 6e-17, not 0: keep the axes exact
    return np.atleast_2d(e)


def unit_factor(quantity: str, unit) -> float:
    """The factor that brings a channel in ``unit`` to SI (1 for no unit)."""
    if unit is None or (isinstance(unit, float) and np.isnan(unit)) or str(unit).strip() == "":
        return 1.0
    key = unit_key(unit)
    known = UNITS[quantity]
    if key not in known:
        raise ValueError(f"unit {unit!r} is not a unit of {quantity}: expected one of {', '.join(known)} "
                         "(any case; µ or u for micro; m/s^2, m s^-2 and m/s² alike)")
    return known[key]


def _column_number(value) -> int | None:
    """``value`` as a column number of a record (a whole number from 0 to
    2**31, written as an integer or a float such as ``3.0``), else None:
    text, NaN, inf, a fraction, a negative number or one no record has."""
    if isinstance(value, (bool, np.bool_)):
        return None
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    if not np.isfinite(number) or number != int(number) or not 0 <= number < 2**31:
        return None
    return int(number)


def check_channel_table(table: pd.DataFrame, n_channels: int | None = None, source="the channel table",
                        nodes=None) -> pd.DataFrame:
    """The channel table checked and normalised, or ``ValueError`` saying
    what is wrong and where (``source`` names the file).

    Refused: missing columns; a channel number that is not an integer, out
    of the record's ``n_channels`` columns, or repeated; an empty node; a
    zero or non-finite direction, or one far from unit length; an unknown
    quantity, unit or role; two channels at the same node and direction;
    a node not among ``nodes`` (the geometry's), when given.
    """
    missing = [c for c in COLUMNS if c not in table.columns]
    if missing:
        raise ValueError(f"{source}: missing column(s) {', '.join(missing)}; expected {', '.join(COLUMNS)}")
    t = table[COLUMNS].copy().reset_index(drop=True)
    if t.empty:
        raise ValueError(f"{source}: no channel")
    numbers = [_column_number(value) for value in t["channel"]]
    for row, (value, number) in enumerate(zip(t["channel"], numbers)):
        if number is None:
            raise ValueError(f"{source}: row {row + 1}: channel must be a column number >= 0, got {value!r}")
    t["channel"] = numbers
    if n_channels is not None and t["channel"].max() >= n_channels:
        bad = t.loc[t["channel"] >= n_channels, "channel"].tolist()
        raise ValueError(f"{source}: channel(s) {bad} beyond the record's {n_channels} columns (0 ... {n_channels - 1})")
    repeated = t["channel"][t["channel"].duplicated()].tolist()
    if repeated:
        raise ValueError(f"{source}: channel(s) {repeated} listed twice")
    t["node"] = [str(n).strip() for n in t["node"]]
    empty = [r + 1 for r, n in enumerate(t["node"]) if n in ("", "nan", "None")]
    if empty:
        raise ValueError(f"{source}: row(s) {empty}: no node")
    if nodes is not None:
        unknown = sorted(set(t["node"]) - {str(n) for n in nodes})
        if unknown:
            raise ValueError(f"{source}: node(s) {', '.join(unknown)} not in the geometry")
    e = t[["x", "y", "z"]].to_numpy(dtype=float)
    norm = np.linalg.norm(e, axis=1)
    for row in np.flatnonzero(~np.isfinite(norm) | (np.abs(norm - 1) > DIRECTION_RTOL)):
        raise ValueError(f"{source}: channel {t['channel'][row]}: direction ({e[row, 0]:g}, {e[row, 1]:g}, {e[row, 2]:g}) is not a unit vector "
                         "(a zero or missing direction measures nothing)")
    t[["x", "y", "z"]] = e / norm[:, None]
    t["quantity"] = [str(q).strip().lower() for q in t["quantity"]]
    for row, q in enumerate(t["quantity"]):
        if q not in QUANTITIES:
            raise ValueError(f"{source}: channel {t['channel'][row]}: quantity {q!r}, expected one of "
                             f"{', '.join(QUANTITIES)}")
    t["unit"] = ["" if u is None or (isinstance(u, float) and np.isnan(u)) else str(u).strip() for u in t["unit"]]
    for q, u in zip(t["quantity"], t["unit"]):
        unit_factor(q, u)
    t["role"] = [str(r).strip().lower() for r in t["role"]]
    for row, r in enumerate(t["role"]):
        if r not in ROLES:
            raise ValueError(f"{source}: channel {t['channel'][row]}: role {r!r}, expected reference or roving")
    keys = dof_keys(t)
    for k in set(keys):
        if keys.count(k) > 1:
            rows = [int(t["channel"][r]) for r, key in enumerate(keys) if key == k]
            raise ValueError(f"{source}: channels {rows} measure the same node {k[0]} in the same direction")
    t["name"] = [str(n) for n in t["name"]]
    return t


def dof_keys(table: pd.DataFrame) -> list[tuple]:
    """``(node, x, y, z)`` of each channel, the direction rounded to 1e-3:
    how reference channels are recognised across setups."""
    e = np.round(table[["x", "y", "z"]].to_numpy(dtype=float), 3) + 0.0  # + 0.0: no -0.0
    return [(str(n), *map(float, d)) for n, d in zip(table["node"], e)]


def read_channel_table(path, n_channels=None, nodes=None) -> pd.DataFrame:
    """The project's own channel table, a CSV file with a header row::

        channel,name,node,x,y,z,quantity,unit,role
        0,top_x,7,1,0,0,acceleration,m/s2,reference
        1,mid_y,4,0,-1,0,acceleration,m/s2,roving

    ``azimuth,elevation`` (degrees, :func:`direction_from_angles`) may stand
    for ``x,y,z``; ``name`` and ``unit`` may be left out (names ``ch<channel>``;
    SI). Channels of the record not listed are not used.
    """
    path = Path(path)
    text = text_of(path)
    if not text.strip():
        raise ValueError(f"{path}: the channel table is empty; expected a header {','.join(COLUMNS)} and one row "
                         "per channel")
    try:
        # every cell as text (numbers are converted below): the header may spell "Node" or " node ", and a
        # node, name or unit such as "01" must stay as written
        table = pd.read_csv(io.StringIO(text), dtype=str, skipinitialspace=True)
    except pd.errors.ParserError as exc:
        raise ValueError(f"{path}: cannot read the channel table: {exc}") from None
    table.columns = [str(c).strip().lower() for c in table.columns]
    if {"azimuth", "elevation"} <= set(table.columns):
        angles = table[["azimuth", "elevation"]].apply(pd.to_numeric, errors="coerce").to_numpy()
        from_angles = direction_from_angles(angles[:, 0], angles[:, 1])
        if {"x", "y", "z"} <= set(table.columns):
            xyz = table[["x", "y", "z"]].apply(pd.to_numeric, errors="coerce").to_numpy()
            norm = np.linalg.norm(xyz, axis=1, keepdims=True)
            differ = np.flatnonzero(np.linalg.norm(xyz / np.where(norm > 0, norm, 1) - from_angles, axis=1)
                                    > DIRECTION_RTOL)
            if differ.size:
                r = differ[0]
                raise ValueError(f"{path}: row {r + 1}: x, y, z = {tuple(np.round(xyz[r], 4).tolist())} and "
                                 f"azimuth, elevation = {tuple(angles[r].tolist())} (direction "
                                 f"{tuple(np.round(from_angles[r], 4).tolist())}) disagree: give one or the other")
        else:
            table[["x", "y", "z"]] = from_angles
    if "name" not in table.columns and "channel" in table.columns:
        table["name"] = [f"ch{c}" for c in table["channel"]]
    if "unit" not in table.columns:
        table["unit"] = ""
    for column in ("channel", "x", "y", "z"):
        if column in table.columns:
            numbers = pd.to_numeric(table[column], errors="coerce")
            bad = numbers.isna() & table[column].notna()
            if bad.any():
                row = int(np.flatnonzero(bad)[0])
                # rows counted as the table checks count them: the channels, from 1, the header not counted
                raise ValueError(f"{path}: row {row + 1}: {column} must be a number, got {table[column][row]!r}")
            table[column] = numbers
    return check_channel_table(table, n_channels, source=str(path), nodes=nodes)


def text_of(path: Path) -> str:
    """The text of a setup's or geometry's file: UTF-8 (a byte order mark
    dropped), else Latin-1, which Windows exports of pyOMA's files use and
    which decodes any byte (the numbers read the same).

    Raises
    ------
    ValueError
        Naming the file when it cannot be read or holds binary data (a NUL byte).
    """
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ValueError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if b"\x00" in raw:
        raise ValueError(f"{path}: binary data (a NUL byte), not a text file (UTF-16 text: save it as UTF-8)")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def _pyoma_lists(path: Path) -> dict:
    """pyOMA's ``setup_info.txt``: a label line ending in ``:`` and the
    values on the next line (blank when none)."""
    lines = text_of(path).splitlines()
    info = {}
    for i, line in enumerate(lines):
        if line.strip().endswith(":"):
            info[line.strip().rstrip(":").strip().lower()] = lines[i + 1].strip() if i + 1 < len(lines) else ""
        if line.startswith("####"):
            break
    return info


def read_pyoma_setup(folder) -> tuple[Path, float, pd.DataFrame]:
    """A setup in pyOMA's layout: ``folder/channel_dofs.txt`` (channel, node,
    azimuth, elevation, name), ``folder/setup_info.txt`` (sampling rate,
    reference, deleted, acceleration, velocity and displacement channels)
    and one ``.npy`` record.

    Returns the record's path, the sampling rate (Hz) and the channel table
    (deleted channels left out, SI units assumed: pyOMA states none).
    """
    folder = Path(folder)
    dofs_path, info_path = folder / "channel_dofs.txt", folder / "setup_info.txt"
    for path in (dofs_path, info_path):
        if not path.is_file():
            raise ValueError(f"{folder}: not a pyOMA setup folder: {path.name} is missing")
    records = sorted(folder.glob("*.npy"))
    if len(records) != 1:
        raise ValueError(f"{folder}: a pyOMA setup folder holds one .npy record, found {len(records)}")
    info = _pyoma_lists(info_path)

    def numbers(key, kind=int):
        text = info.get(key)
        if text is None:
            raise ValueError(f"{info_path}: no '{key}' entry")
        try:
            return [kind(v) for v in text.split()]
        except ValueError:
            raise ValueError(f"{info_path}: '{key}' must list numbers, got {text!r}") from None

    rate = numbers("sampling rate [hz]", float)
    if len(rate) != 1 or not rate[0] > 0:
        raise ValueError(f"{info_path}: 'Sampling Rate [Hz]' must be one positive number, got {rate}")
    refs, deleted = set(numbers("reference channels")), set(numbers("delete channels"))
    quantity = {}
    for key, name in (("accel. channels", "acceleration"), ("velo. channels", "velocity"),
                      ("disp. channels", "displacement")):
        for c in numbers(key):
            quantity[c] = name
    try:
        text = text_of(dofs_path)
        if not text.strip():
            raise ValueError("the file is empty")
        dofs = pd.read_csv(io.StringIO(text), sep="\t", dtype=str)
        dofs.columns = [c.strip().lower() for c in dofs.columns]
        channel = dofs["channel-nr."].astype(int)
        angles = dofs[["azimuth", "elevation"]].astype(float).to_numpy()
    except (KeyError, ValueError, pd.errors.ParserError) as exc:
        raise ValueError(f"{dofs_path}: expected tab-separated columns Channel-Nr., Node, Azimuth, Elevation, "
                         f"Channel Name ({exc})") from None
    unknown = sorted(set(channel) - set(quantity) - deleted)
    if unknown:
        raise ValueError(f"{info_path}: channel(s) {unknown} are neither acceleration, velocity nor displacement "
                         "channels, nor deleted")
    missing = sorted(refs - set(channel))
    if missing:
        raise ValueError(f"{info_path}: reference channel(s) {missing} not in {dofs_path.name}")
    e = direction_from_angles(angles[:, 0], angles[:, 1])
    table = pd.DataFrame({
        "channel": channel, "name": dofs.get("channel name", channel.astype(str)).str.strip(),
        "node": dofs["node"].str.strip(), "x": e[:, 0], "y": e[:, 1], "z": e[:, 2],
        "quantity": [quantity.get(c, "") for c in channel], "unit": "",
        "role": ["reference" if c in refs else "roving" for c in channel],
    })
    kept = table[~table["channel"].isin(deleted)]
    return records[0], rate[0], check_channel_table(kept, source=str(dofs_path))
