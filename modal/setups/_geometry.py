"""The geometry a mode shape is drawn on: nodes, lines between them, and
nodes that move with others.

Three formats are read by :func:`read_geometry`, by the files the folder
holds:

- the project's own: ``nodes.csv`` (``node,x,y,z``), optional ``lines.csv``
  (``node_1,node_2``) and ``links.csv`` (``parent,child,x,y,z``: the child
  node moves as the parent along the unit direction ``x,y,z``);
- pyOMA's: ``grid.txt`` (node, x, y, z), ``lines.txt`` (node pairs),
  ``parent_child_assignments.txt`` (parent, its direction, child, its
  direction);
- pyOMA2's "geometry 2": ``pts_coord.txt`` (points), ``sens_map.txt`` (the
  sensor measuring each point along x, y, z; ``0`` none), ``sens_sign.txt``
  (its sign), optional ``sens_lines.txt`` (point pairs), ``BG_nodes.txt`` and
  ``BG_lines.txt`` (a background drawn in grey); or its "geometry 1":
  ``sens_coord.txt`` (each sensor's name and position) and ``sens_dir.txt``
  (its direction, same order). pyOMA2's geometries name the sensors, so
  they also give the channel table of a record whose channels bear those
  names (:meth:`Geometry.channel_table`).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ._channels import check_channel_table, text_of


@dataclass(frozen=True)
class Geometry:
    """Nodes, lines and linked nodes of a structure.

    Attributes
    ----------
    nodes : pandas.DataFrame
        Index ``node`` (text), columns ``x``, ``y``, ``z``.
    lines : list of (str, str)
        Pairs of nodes drawn as lines.
    links : pandas.DataFrame
        ``parent``, ``child``, ``px, py, pz`` and ``cx, cy, cz``: the child's
        motion along ``c`` equals the parent's along ``p`` (a rigid floor:
        a corner moves as its neighbour in that direction).
    sensors : pandas.DataFrame
        Sensors named by the geometry (pyOMA2): ``name``, ``node``, ``x``,
        ``y``, ``z``; empty for the other formats.
    background_nodes : ndarray, shape (k, 3)
    background_lines : ndarray, shape (j, 2)
        Indices into ``background_nodes``: a context drawn in grey.
    source : str
    """

    nodes: pd.DataFrame
    lines: list = field(default_factory=list)
    links: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(
        columns=["parent", "child", "px", "py", "pz", "cx", "cy", "cz"]))
    sensors: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(columns=["name", "node", "x", "y", "z"]))
    background_nodes: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    background_lines: np.ndarray = field(default_factory=lambda: np.empty((0, 2), dtype=int))
    source: str = "geometry"

    def __post_init__(self):
        index = [str(n) for n in self.nodes.index]
        if len(set(index)) != len(index):
            raise ValueError(f"{self.source}: node(s) {sorted({n for n in index if index.count(n) > 1})} "
                             "defined twice")
        xyz = self.nodes[["x", "y", "z"]].to_numpy(dtype=float)
        if not np.all(np.isfinite(xyz)):
            raise ValueError(f"{self.source}: a node's coordinates are missing or not numbers")
        known = set(index)
        for a, b in self.lines:
            if str(a) not in known or str(b) not in known:
                raise ValueError(f"{self.source}: line {a}-{b} names a node not in the geometry")
        for p, c in zip(self.links["parent"], self.links["child"]):
            if str(p) not in known or str(c) not in known:
                raise ValueError(f"{self.source}: link {p}->{c} names a node not in the geometry")
        if len(self.background_lines) and (self.background_lines.min() < 0
                                           or self.background_lines.max() >= len(self.background_nodes)):
            raise ValueError(f"{self.source}: a background line names a background node that does not exist")

    @property
    def coordinates(self) -> np.ndarray:
        """``(n_nodes, 3)`` coordinates in the order of ``nodes``."""
        return self.nodes[["x", "y", "z"]].to_numpy(dtype=float)

    @property
    def size(self) -> float:
        """The diagonal of the bounding box of nodes and background."""
        points = np.vstack([self.coordinates, self.background_nodes])
        return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))) or 1.0

    def channel_table(self, channel_names, quantity="acceleration", unit="") -> pd.DataFrame:
        """The channel table of a record whose channels are named
        ``channel_names``, from the geometry's sensors (pyOMA2): each
        sensor is matched by name; every channel is a reference (one
        setup). Channels the geometry does not name are not used."""
        if self.sensors.empty:
            raise ValueError(f"{self.source}: the geometry names no sensors, so it gives no channel table; "
                             "give the record a channels.csv (docs: Roving tests)")
        names = [str(n) for n in channel_names]
        missing = [s for s in self.sensors["name"] if s not in names]
        if missing:
            raise ValueError(f"{self.source}: sensor(s) {', '.join(missing)} are not channels of the record "
                             f"(its channels: {', '.join(names)})")
        table = self.sensors.assign(channel=[names.index(s) for s in self.sensors["name"]], quantity=quantity,
                                    unit=unit, role="reference").sort_values("channel")
        return check_channel_table(table, len(names), source=self.source, nodes=self.nodes.index)


def read_geometry(folder) -> Geometry:
    """The geometry in ``folder``, in whichever of the three formats it holds
    (module docstring); ``ValueError`` when it holds none or a file is
    malformed (the message names the file)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"geometry {folder}: not a folder")
    if (folder / "nodes.csv").is_file():
        return _read_own(folder)
    if (folder / "grid.txt").is_file():
        return _read_pyoma(folder)
    if (folder / "pts_coord.txt").is_file() and (folder / "sens_map.txt").is_file():
        return _read_pyoma2_points(folder)
    if (folder / "sens_coord.txt").is_file() and (folder / "sens_dir.txt").is_file():
        return _read_pyoma2_sensors(folder)
    raise ValueError(f"geometry {folder}: no nodes.csv (the project's format), grid.txt (pyOMA's), "
                     "pts_coord.txt with sens_map.txt or sens_coord.txt with sens_dir.txt (pyOMA2's)")


def _table(path: Path, names=None, sep=r"\s+", header="infer", dtype=str) -> pd.DataFrame:
    """A table file up to its first line starting with ``#`` (pyOMA's files
    end in notes below a ``####`` line); blank lines skipped."""
    import io

    try:
        lines = text_of(path).splitlines()
        body = "\n".join(line for line in itertools.takewhile(lambda t: not t.startswith("#"), lines) if line.strip())
        table = pd.read_csv(io.StringIO(body), sep=sep, header=header, names=names, dtype=dtype,
                            skipinitialspace=True)
    except (OSError, pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read: {exc}") from None
    table.columns = [str(c).strip().lower() for c in table.columns]
    return table


def _numbers(table, columns, path) -> np.ndarray:
    try:
        values = table[columns]
    except KeyError as exc:
        raise ValueError(f"{path}: expected columns {', '.join(map(str, columns))}, missing {exc}") from None
    numbers = values.apply(pd.to_numeric, errors="coerce")
    bad = numbers.isna().to_numpy() & values.notna().to_numpy()
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise ValueError(f"{path}: row {r + 1}, column {columns[c]}: {values.iat[r, c]!r} is not a number")
    return numbers.to_numpy(dtype=float)


def _nodes(names, xyz) -> pd.DataFrame:
    return pd.DataFrame(xyz, index=pd.Index([str(n).strip() for n in names], name="node"), columns=["x", "y", "z"])


def _read_own(folder: Path) -> Geometry:
    path = folder / "nodes.csv"
    table = _table(path, sep=",")
    if "node" not in table:
        raise ValueError(f"{path}: expected columns node,x,y,z")
    nodes = _nodes(table["node"], _numbers(table, ["x", "y", "z"], path))
    lines = []
    if (folder / "lines.csv").is_file():
        t = _table(folder / "lines.csv", sep=",")
        if not {"node_1", "node_2"} <= set(t.columns):
            raise ValueError(f"{folder / 'lines.csv'}: expected columns node_1,node_2")
        lines = [(str(a).strip(), str(b).strip()) for a, b in zip(t["node_1"], t["node_2"])]
    links = Geometry.__dataclass_fields__["links"].default_factory()
    if (folder / "links.csv").is_file():
        t = _table(folder / "links.csv", sep=",")
        d = _numbers(t, ["x", "y", "z"], folder / "links.csv")
        links = pd.DataFrame({"parent": t["parent"].str.strip(), "child": t["child"].str.strip(),
                              "px": d[:, 0], "py": d[:, 1], "pz": d[:, 2],
                              "cx": d[:, 0], "cy": d[:, 1], "cz": d[:, 2]})
    return Geometry(nodes, lines, links, source=str(folder))


def _read_pyoma(folder: Path) -> Geometry:
    grid = _table(folder / "grid.txt")
    nodes = _nodes(grid.iloc[:, 0], _numbers(grid, list(grid.columns[1:4]), folder / "grid.txt"))
    lines = []
    if (folder / "lines.txt").is_file():
        t = _table(folder / "lines.txt")
        if t.shape[1] != 2:
            raise ValueError(f"{folder / 'lines.txt'}: expected 2 columns (the two nodes of each line), "
                             f"found {t.shape[1]}")
        lines = [(str(a).strip(), str(b).strip()) for a, b in zip(t.iloc[:, 0], t.iloc[:, 1])]
    links = Geometry.__dataclass_fields__["links"].default_factory()
    path = folder / "parent_child_assignments.txt"
    if path.is_file():
        t = _table(path)
        if t.shape[1] != 8:
            raise ValueError(f"{path}: expected 8 columns: parent node, its x, y, z, child node, its x, y, z")
        d = _numbers(t, [t.columns[i] for i in (1, 2, 3, 5, 6, 7)], path)
        links = pd.DataFrame({"parent": t.iloc[:, 0].str.strip(), "child": t.iloc[:, 4].str.strip(),
                              "px": d[:, 0], "py": d[:, 1], "pz": d[:, 2], "cx": d[:, 3], "cy": d[:, 4],
                              "cz": d[:, 5]})
    return Geometry(nodes, lines, links, source=str(folder))


def _background(folder: Path):
    nodes, lines = np.empty((0, 3)), np.empty((0, 2), dtype=int)
    if (folder / "BG_nodes.txt").is_file():
        nodes = _numbers(_table(folder / "BG_nodes.txt", header=None, names=["x", "y", "z"]), ["x", "y", "z"],
                         folder / "BG_nodes.txt")
    if (folder / "BG_lines.txt").is_file():
        lines = _numbers(_table(folder / "BG_lines.txt", header=None, names=["a", "b"]), ["a", "b"],
                         folder / "BG_lines.txt").astype(int) - 1  # pyOMA2 counts from 1
    return nodes, lines


def _read_pyoma2_points(folder: Path) -> Geometry:
    points = _table(folder / "pts_coord.txt")
    nodes = _nodes(points.iloc[:, 0], _numbers(points, ["x", "y", "z"], folder / "pts_coord.txt"))
    where = _table(folder / "sens_map.txt").set_index("ptname")
    where.index = where.index.str.strip()
    sign = (_table(folder / "sens_sign.txt").set_index("ptname") if (folder / "sens_sign.txt").is_file()
            else where.map(lambda v: "1"))
    sign.index = sign.index.str.strip()
    rows = []
    for point in where.index:
        for axis, column in enumerate(c for c in where.columns if c in ("x", "y", "z")):
            name = str(where.loc[point, column]).strip()
            if name in ("0", "nan", ""):
                continue
            e = np.zeros(3)
            e["xyz".index(column)] = _sign(sign.loc[point, column], point, column, folder / "sens_sign.txt")
            rows.append({"name": name, "node": point, "x": e[0], "y": e[1], "z": e[2]})
    lines = []
    if (folder / "sens_lines.txt").is_file():
        t = _table(folder / "sens_lines.txt", header=None, names=["a", "b"])
        lines = [(str(a).strip(), str(b).strip()) for a, b in zip(t["a"], t["b"])]
    bg_nodes, bg_lines = _background(folder)
    return Geometry(nodes, lines, sensors=pd.DataFrame(rows, columns=["name", "node", "x", "y", "z"]),
                    background_nodes=bg_nodes, background_lines=bg_lines, source=str(folder))


def _sign(value, point, column, path) -> float:
    """A sensor's sign in pyOMA2's ``sens_sign.txt``: 1 or -1."""
    try:
        sign = float(value)
    except (TypeError, ValueError):
        sign = np.nan
    if sign not in (1.0, -1.0):
        raise ValueError(f"{path}: point {point}, column {column}: {str(value).strip()!r} is not a sign: "
                         "expected 1 or -1")
    return sign


def _read_pyoma2_sensors(folder: Path) -> Geometry:
    coords = _table(folder / "sens_coord.txt")
    xyz = _numbers(coords, ["x", "y", "z"], folder / "sens_coord.txt")
    directions = _numbers(_table(folder / "sens_dir.txt", header=None, names=["x", "y", "z"]), ["x", "y", "z"],
                          folder / "sens_dir.txt")
    if len(directions) != len(xyz):
        raise ValueError(f"{folder / 'sens_dir.txt'}: {len(directions)} directions for {len(xyz)} sensors")
    unique, node_of = np.unique(np.round(xyz, 9), axis=0, return_inverse=True)
    nodes = _nodes([str(i + 1) for i in range(len(unique))], unique)
    sensors = pd.DataFrame({"name": coords.iloc[:, 0].str.strip(), "node": [str(i + 1) for i in node_of.ravel()],
                            "x": directions[:, 0], "y": directions[:, 1], "z": directions[:, 2]})
    bg_nodes, bg_lines = _background(folder)
    return Geometry(nodes, sensors=sensors, background_nodes=bg_nodes, background_lines=bg_lines,
                    source=str(folder))
