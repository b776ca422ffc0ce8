"""The geometry readers (``modal.setups.read_geometry``), each format read
to the exact nodes, lines, links, sensors and background, the channel
table a pyOMA2 geometry gives, the size of a geometry, and the refusals
word for word. Asked for by the mutation run of ``modal.setups``
(issue 33)."""

import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from modal.setups import Geometry, read_geometry

PALISADEN = Path(__file__).resolve().parents[2] / "data" / "palisaden_geometry"


def _folder(tmp_path, name, files):
    folder = tmp_path / name
    folder.mkdir()
    for file, text in files.items():
        (folder / file).write_text(text)
    return folder


def _refusal(folder):
    with pytest.raises(ValueError) as caught:
        read_geometry(folder)
    return str(caught.value)


def test_the_size_is_the_diagonal_of_the_box_of_nodes_and_background():
    nodes = pd.DataFrame({"x": [1.0, 4.0], "y": [2.0, 6.0], "z": [5.0, 5.0]}, index=pd.Index(["a", "b"], name="node"))
    assert Geometry(nodes).size == 5.0  # the box from (1, 2, 5) to (4, 6, 5)
    background = np.array([[1.0, 2.0, -7.0], [4.0, 6.0, 5.0]])  # 12 below the nodes
    assert Geometry(nodes, background_nodes=background).size == 13.0


def test_the_projects_own_format_is_read_exactly(tmp_path):
    """Headers in any capitals and with spaces, names kept as text (``01``)
    and stripped, blank lines skipped, nothing read below a ``#`` line."""
    folder = _folder(tmp_path, "own", {
        "nodes.csv": "Node ,X,Y,Z\n01, 0, 0, 0\n   \n b ,3,4.5,-1\n\n# notes\nc,1,1,1\n",
        "lines.csv": "Node_1,NODE_2\n01 , b \n",
        "links.csv": "parent,child,x,y,z\n01, b ,0,1,0\n"})
    g = read_geometry(folder)
    assert list(g.nodes.index) == ["01", "b"] and g.nodes.index.name == "node"
    assert list(g.nodes.columns) == ["x", "y", "z"]
    assert g.nodes.to_numpy().tolist() == [[0.0, 0.0, 0.0], [3.0, 4.5, -1.0]] and g.nodes["x"].dtype == float
    assert g.lines == [("01", "b")] and g.source == str(folder)
    assert g.links.to_dict("list") == {"parent": ["01"], "child": ["b"], "px": [0.0], "py": [1.0], "pz": [0.0],
                                       "cx": [0.0], "cy": [1.0], "cz": [0.0]}
    assert g.sensors.empty and g.background_nodes.shape == (0, 3)
    alone = read_geometry(_folder(tmp_path, "alone", {"nodes.csv": "node,x,y,z\n1,0,0,0\n"}))
    assert alone.lines == [] and alone.links.empty and list(alone.links.columns) == list(g.links.columns)
    assert alone.nodes.dtypes.tolist() == [float] * 3  # integers in the file, floats read


def test_the_projects_own_format_refusals(tmp_path):
    def refusal(files):
        folder = tmp_path / f"case{len(list(tmp_path.iterdir()))}"
        return _refusal(_folder(tmp_path, folder.name, files)).replace(str(folder), "F")

    assert refusal({"nodes.csv": ""}) == "F/nodes.csv: cannot read: No columns to parse from file"
    assert refusal({"nodes.csv": "name,x,y,z\n1,0,0,0\n"}) == "F/nodes.csv: expected columns node,x,y,z"
    assert refusal({"nodes.csv": "node,x,y\n1,0,0\n"}) == \
        "F/nodes.csv: expected columns x, y, z, missing \"['z'] not in index\""
    assert refusal({"nodes.csv": "node,x,y,z\n1,0,0,0\n2,a,b,0\n"}) == \
        "F/nodes.csv: row 2, column x: 'a' is not a number"
    assert refusal({"nodes.csv": "node,x,y,z\n1,0,,0\n"}) == "F: a node's coordinates are missing or not numbers"
    assert refusal({"nodes.csv": "node,x,y,z\n1,0,0,0\n", "lines.csv": "a,b\n1,1\n"}) == \
        "F/lines.csv: expected columns node_1,node_2"
    assert refusal({"nodes.csv": "node,x,y,z\n1,0,0,0\n", "links.csv": "parent,child,x,y,z\n1,1,0,one,0\n"}) == \
        "F/links.csv: row 1, column y: 'one' is not a number"


def test_pyomas_format_is_read_exactly(tmp_path):
    """A parent's direction and its child's differ: each is its own."""
    folder = _folder(tmp_path, "pyoma", {
        "grid.txt": "node_name\t x\t y\t z\n 1 0 0 0\n 2 1 0 0\n 3 1 1 0.5\n\n####\nnotes 4 4 4\n",
        "lines.txt": "node_name_1\t node_name_2\n 1 2\n 2 3\n",
        "parent_child_assignments.txt":
            "parent_node\tx_parent\ty_parent\tz_parent\tchild_node\tx_child\ty_child\tz_child\n"
            " 2\t0.36\t0.48\t0.8\t 3\t0\t0.6\t-0.8\n####\n"})
    g = read_geometry(folder)
    assert list(g.nodes.index) == ["1", "2", "3"] and g.nodes.to_numpy().tolist() == [[0, 0, 0], [1, 0, 0],
                                                                                       [1, 1, 0.5]]
    assert g.lines == [("1", "2"), ("2", "3")] and g.source == str(folder)
    assert g.links.to_dict("list") == {"parent": ["2"], "child": ["3"], "px": [0.36], "py": [0.48], "pz": [0.8],
                                       "cx": [0.0], "cy": [0.6], "cz": [-0.8]}
    alone = read_geometry(_folder(tmp_path, "grid", {"grid.txt": "node x y z label\n1 0 0 0 base\n2 1 2 3 top\n"}))
    assert alone.nodes.to_numpy().tolist() == [[0, 0, 0], [1, 2, 3]]  # a fifth column is not read
    assert alone.lines == [] and alone.links.empty and list(alone.links.columns) == list(g.links.columns)
    (folder / "parent_child_assignments.txt").write_text("a b c d e f g\n2 1 0 0 3 0 -1\n")
    assert _refusal(folder) == (f"{folder}/parent_child_assignments.txt: expected 8 columns: parent node, its x, y, z, "
                                "child node, its x, y, z")


def _palisaden(tmp_path, names, name="p2"):
    folder = tmp_path / name
    folder.mkdir()
    for file in names:
        shutil.copy(PALISADEN / file, folder / file)
    return folder


BOX = [[0, 0, 0], [15, 0, 0], [15, 10, 0], [0, 10, 0], [0, 0, 20], [15, 0, 20], [15, 10, 20], [0, 10, 20]]


def test_pyoma2_geometry_2_is_read_exactly(tmp_path):
    """Palisaden: points, the sensor map (points 4-6 have none), the signs,
    the lines between points and the background box (counted from 1 in the
    file, from 0 here)."""
    folder = _palisaden(tmp_path, ["pts_coord.txt", "sens_map.txt", "sens_sign.txt", "sens_lines.txt",
                                   "BG_nodes.txt", "BG_lines.txt"])
    g = read_geometry(folder)
    assert list(g.nodes.index) == ["1", "2", "3", "4", "5", "6"]
    assert g.nodes.to_numpy().tolist() == [[2, 8, 20], [11, 8, 20], [5, 2, 20], [2, 8, 0], [11, 8, 0], [5, 2, 0]]
    assert g.sensors.to_dict("list") == {
        "name": ["ch1", "ch2", "ch3", "ch4", "ch5", "ch6"], "node": ["1", "1", "2", "2", "3", "3"],
        "x": [-1.0, 0.0, -1.0, 0.0, -1.0, 0.0], "y": [0.0, -1.0, 0.0, -1.0, 0.0, 1.0], "z": [0.0] * 6}
    assert g.lines == [("4", "1"), ("5", "2"), ("6", "3"), ("1", "2"), ("2", "3"), ("3", "1")]
    assert g.background_nodes.tolist() == BOX
    assert g.background_lines.tolist() == [[0, 4], [1, 5], [2, 6], [3, 7], [4, 5], [5, 6], [6, 7], [7, 4]]
    assert g.background_lines.dtype.kind == "i" and g.links.empty and g.source == str(folder)
    assert g.size == math.sqrt(15 ** 2 + 10 ** 2 + 20 ** 2)


def test_pyoma2_geometry_2_without_signs_lines_or_background(tmp_path):
    """Without ``sens_sign.txt`` every sign is +1; a point may have a
    sensor along z after none along y; names and points are stripped."""
    folder = _folder(tmp_path, "p2", {
        "pts_coord.txt": "ptName x y z\nA 0 0 0\nB 1 0 0\n",
        "sens_map.txt": "ptName\tx\ty\tz\n A\t s1\t0\ts2\n B\t0\ts3\t0\n"})
    g = read_geometry(folder)
    assert g.sensors.to_dict("list") == {"name": ["s1", "s2", "s3"], "node": ["A", "A", "B"], "x": [1.0, 0.0, 0.0],
                                         "y": [0.0, 0.0, 1.0], "z": [0.0, 1.0, 0.0]}
    assert g.lines == [] and g.background_nodes.shape == (0, 3) and g.background_lines.shape == (0, 2)
    assert g.background_lines.dtype.kind == "i" and g.source == str(folder)
    (folder / "sens_map.txt").write_text("ptName x y z\nA 0 s1\nB 0 0 0\n")  # A's z is missing: no sensor
    assert read_geometry(folder).sensors["name"].tolist() == ["s1"]
    (folder / "sens_map.txt").write_text("ptName x y z\nA 0 0 0\nB 0 0 0\n")
    none = read_geometry(folder).sensors
    assert none.empty and list(none.columns) == ["name", "node", "x", "y", "z"]
    (folder / "sens_map.txt").write_text("ptName x y z\nA s1 0 s2\nB 0 s3 0\n")
    (folder / "sens_sign.txt").write_text("ptName x y z\nA 1.0 0 -1\nB 0 -1 0\n")
    assert read_geometry(folder).sensors[["x", "y", "z"]].to_numpy().tolist() == [[1, 0, 0], [0, 0, -1], [0, -1, 0]]
    (folder / "sens_sign.txt").write_text("ptName x y z\nA 1 0 2\nB 0 -1 0\n")
    assert _refusal(folder) == f"{folder}/sens_sign.txt: point A, column z: '2' is not a sign: expected 1 or -1"
    (folder / "sens_sign.txt").write_text("ptName x y z\nA 1 0 -1\nB 0 +1 0\n")
    assert read_geometry(folder).sensors["y"].tolist() == [0.0, 0.0, 1.0]


def test_pyoma2_geometry_1_is_read_exactly(tmp_path):
    """Sensors at one position (to 1e-9) are one node; nodes are numbered
    from 1 in the order of their coordinates; the background is read too."""
    folder = _palisaden(tmp_path, ["sens_coord.txt", "sens_dir.txt", "BG_nodes.txt", "BG_lines.txt"], "p1")
    g = read_geometry(folder)
    assert list(g.nodes.index) == ["1", "2", "3"] and g.nodes.index.name == "node"
    assert g.nodes.to_numpy().tolist() == [[2, 8, 20], [5, 2, 20], [11, 8, 20]]
    assert g.sensors.to_dict("list") == {
        "name": ["ch5", "ch6", "ch1", "ch2", "ch3", "ch4"], "node": ["2", "2", "1", "1", "3", "3"],
        "x": [-1.0, 0.0, -1.0, 0.0, -1.0, 0.0], "y": [0.0, 1.0, 0.0, -1.0, 0.0, -1.0], "z": [0.0] * 6}
    assert g.background_nodes.tolist() == BOX and g.background_lines.shape == (8, 2) and g.source == str(folder)
    assert g.lines == [] and g.links.empty
    (folder / "sens_coord.txt").write_text("sName x y z\n a 5.0000000001 2 20\n b 5 2 20\n c 5.000001 2 20\n")
    (folder / "sens_dir.txt").write_text("1 0 0\n0 1 0\n0 0 1\n")
    g = read_geometry(folder)
    assert g.sensors["node"].tolist() == ["1", "1", "2"] and g.sensors["name"].tolist() == ["a", "b", "c"]
    (folder / "sens_dir.txt").write_text("1 0 0\n0 1 0\n")
    assert _refusal(folder) == f"{folder}/sens_dir.txt: 2 directions for 3 sensors"


@pytest.mark.parametrize("file, text, where", [
    ("pts_coord.txt", "ptName x y z\n1 2 8 20\n2 11 eight 20\n", "row 2, column y: 'eight'"),
    ("BG_nodes.txt", "0 0 0\n15 0 O\n", "row 2, column z: 'O'"),
    ("BG_lines.txt", "1 5\nl 6\n", "row 2, column a: 'l'"),
    ("sens_coord.txt", "sName x y z\nch5 5 2 20\nch6 5 2 2O\n", "row 2, column z: '2O'"),
    ("sens_dir.txt", "-1 0 0\n0 I 0\n", "row 2, column y: 'I'")])
def test_pyoma2_files_name_the_bad_number(tmp_path, file, text, where):
    files = ["BG_nodes.txt", "BG_lines.txt"] + (["sens_coord.txt", "sens_dir.txt"] if file.startswith("sens_") else
                                                ["pts_coord.txt", "sens_map.txt", "sens_sign.txt"])
    folder = _palisaden(tmp_path, files)
    (folder / file).write_text(text)
    if file == "sens_coord.txt":
        (folder / "sens_dir.txt").write_text("-1 0 0\n0 1 0\n")
    assert _refusal(folder) == f"{folder}/{file}: {where} is not a number"


def test_a_pyoma2_geometry_gives_the_channel_table_of_a_record_by_name(tmp_path):
    g = read_geometry(_palisaden(tmp_path, ["pts_coord.txt", "sens_map.txt", "sens_sign.txt"]))
    t = g.channel_table(["ch6", "ch5", "ch4", "ch3", "ch2", "ch1", "spare"])
    assert list(t.columns) == ["channel", "name", "node", "x", "y", "z", "quantity", "unit", "role"]
    assert t["channel"].tolist() == [0, 1, 2, 3, 4, 5]
    assert t["name"].tolist() == ["ch6", "ch5", "ch4", "ch3", "ch2", "ch1"]
    assert t["node"].tolist() == ["3", "3", "2", "2", "1", "1"] and t["y"].tolist() == [1, 0, -1, 0, -1, 0]
    assert set(t["quantity"]) == {"acceleration"} and set(t["unit"]) == {""} and set(t["role"]) == {"reference"}
    v = g.channel_table(["ch1", "ch2", "ch3", "ch4", "ch5", "ch6"], quantity="velocity", unit="mm/s")
    assert set(v["quantity"]) == {"velocity"} and set(v["unit"]) == {"mm/s"}
    with pytest.raises(ValueError) as caught:
        g.channel_table(["ch1", "ch3", "ch5", 7])
    assert str(caught.value) == (f"{tmp_path / 'p2'}: sensor(s) ch2, ch4, ch6 are not channels of the record "
                                 "(its channels: ch1, ch3, ch5, 7)")
    named = read_geometry(_folder(tmp_path, "numbers", {
        "pts_coord.txt": "ptName x y z\nA 0 0 0\n", "sens_map.txt": "ptName x y\nA 1 2\n"}))
    assert named.channel_table([2, 1]).to_dict("list")["name"] == ["2", "1"]
    elsewhere = Geometry(g.nodes.drop(index="3"), sensors=g.sensors, source="g")
    with pytest.raises(ValueError, match="^g: "):  # the sensors' nodes must be the geometry's
        elsewhere.channel_table(["ch1", "ch2", "ch3", "ch4", "ch5", "ch6"])


def test_which_format_a_folder_holds(tmp_path):
    (tmp_path / "file").write_text("")
    assert _refusal(tmp_path / "file") == f"geometry {tmp_path / 'file'}: not a folder"
    none = ("no nodes.csv (the project's format), grid.txt (pyOMA's), pts_coord.txt with sens_map.txt or "
            "sens_coord.txt with sens_dir.txt (pyOMA2's)")
    half = _palisaden(tmp_path, ["pts_coord.txt", "sens_coord.txt"], "half")
    assert _refusal(half) == f"geometry {half}: {none}"
    other = _palisaden(tmp_path, ["sens_map.txt", "sens_dir.txt"], "other")
    assert _refusal(other) == f"geometry {other}: {none}"
    both = _palisaden(tmp_path, ["pts_coord.txt", "sens_map.txt", "sens_coord.txt", "sens_dir.txt"], "both")
    assert len(read_geometry(both).nodes) == 6  # geometry 2 before geometry 1
    (both / "grid.txt").write_text("node x y z\n7 0 0 0\n")
    assert list(read_geometry(both).nodes.index) == ["7"]  # pyOMA's before pyOMA2's
    (both / "nodes.csv").write_text("node,x,y,z\n8,0,0,0\n")
    assert list(read_geometry(str(both)).nodes.index) == ["8"]  # the project's first
