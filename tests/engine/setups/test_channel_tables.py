"""Channel tables cell by cell (``modal.setups._channels``): every unit's
factor, a table written by hand (spaces, capitals, floats for channel
numbers, rounded directions, no unit) read to the exact normalised table,
the refusals with their whole message, the column numbers a record can
have and the reference keys' rounding. Asked for by the mutation run of
``modal.setups`` (issue 33)."""

import re

import numpy as np
import pandas as pd
import pytest

from modal.setups import direction_from_angles
from modal.setups._channels import COLUMNS, _column_number, check_channel_table, dof_keys, unit_factor

FACTORS = [
    ("displacement", "m", 1.0), ("displacement", "cm", 1e-2), ("displacement", "mm", 1e-3),
    ("displacement", "um", 1e-6), ("displacement", "in", 0.0254),
    ("velocity", "m/s", 1.0), ("velocity", "cm/s", 1e-2), ("velocity", "mm/s", 1e-3), ("velocity", "um/s", 1e-6),
    ("velocity", "in/s", 0.0254),
    ("acceleration", "m/s2", 1.0), ("acceleration", "cm/s2", 1e-2), ("acceleration", "gal", 1e-2),
    ("acceleration", "mm/s2", 1e-3), ("acceleration", "g", 9.80665), ("acceleration", "mg", 9.80665e-3),
    ("acceleration", "in/s2", 0.0254),
]


@pytest.mark.parametrize("quantity, unit, factor", FACTORS)
def test_each_unit_s_factor_to_si(quantity, unit, factor):
    """The documented table (docs/roving.md): an inch is 25.4 mm, g is
    9.80665 m/s2, gal is cm/s2."""
    assert unit_factor(quantity, unit) == factor


@pytest.mark.parametrize("unit", [None, float("nan"), "", "  "])
def test_no_unit_is_si(unit):
    assert unit_factor("velocity", unit) == 1.0


def test_a_direction_from_one_pair_of_angles():
    """Angles given as numbers (not lists): one direction, shape (1, 3)."""
    np.testing.assert_array_equal(direction_from_angles(90, 0), [[0.0, 1.0, 0.0]])
    np.testing.assert_array_equal(direction_from_angles(0, -90), [[0.0, 0.0, -1.0]])


@pytest.mark.parametrize("value, number", [(0, 0), (62, 62), (63.0, 63), (2**31 - 1, 2**31 - 1), (2**31, None),
                                           (2**32, None), (-1, None), (True, None)])
def test_column_numbers_up_to_2_to_the_31(value, number):
    assert _column_number(value) == number


def _table(**changes):
    base = {"channel": [0, 1], "name": ["a", "b"], "node": ["1", "2"], "x": [1.0, 0.0], "y": [0.0, 0.0],
            "z": [0.0, 1.0], "quantity": ["acceleration"] * 2, "unit": ["m/s2", "g"], "role": ["reference", "roving"]}
    base.update(changes)
    return pd.DataFrame(base)


def test_a_table_written_by_hand_is_normalised():
    """Channel numbers as floats, names as numbers, spaces and capitals
    around nodes, quantities, units and roles, directions rounded to 4
    digits, a unit left out (None or NaN), an index of its own and a column
    more: the checked table has exactly the columns, in order, with the
    values normalised."""
    table = pd.DataFrame({
        "comment": ["top", "mid", "low"], "channel": [2.0, 0.0, 1.0], "name": [5, "b", "c"],
        "node": [" 7 ", "8", 9], "x": [0.7071, 0.0, 0.0], "y": [0.7071, -1.0, 0.0], "z": [0.0, 0.0, 0.9999],
        "quantity": [" Acceleration ", "VELOCITY", "displacement"], "unit": [" g ", None, np.nan],
        "role": [" Reference", "ROVING ", "roving"]}, index=[10, 11, 12])
    t = check_channel_table(table, n_channels=3)
    assert list(t.columns) == COLUMNS and list(t.index) == [0, 1, 2]
    assert list(t["channel"]) == [2, 0, 1] and list(t["name"]) == ["5", "b", "c"]
    assert list(t["node"]) == ["7", "8", "9"]
    np.testing.assert_allclose(t[["x", "y", "z"]].to_numpy(), [[np.sqrt(0.5), np.sqrt(0.5), 0], [0, -1, 0], [0, 0, 1]],
                               rtol=0, atol=1e-15)
    assert list(t["quantity"]) == ["acceleration", "velocity", "displacement"]
    assert list(t["unit"]) == ["g", "", ""] and list(t["role"]) == ["reference", "roving", "roving"]
    assert list(table["channel"]) == [2.0, 0.0, 1.0] and table["node"].iloc[0] == " 7 "  # the given table unchanged


@pytest.mark.parametrize("table, n_channels, message", [
    (_table().drop(columns=["role", "unit"]), None,
     "the channel table: missing column(s) unit, role; expected channel, name, node, x, y, z, quantity, unit, role"),
    (_table().iloc[:0], None, "the channel table: no channel"),
    (_table(channel=[0, 2]), 2, "the channel table: channel(s) [2] beyond the record's 2 columns (0 ... 1)"),
    (_table(node=["1", "None"]), None, "the channel table: row(s) [2]: no node"),
    (_table(node=["", "nan"]), None, "the channel table: row(s) [1, 2]: no node"),
    (_table(node=["1", "1"], x=[1.0, 1.0], z=[0.0, 0.0], channel=[3, 5]), None,
     "the channel table: channels [3, 5] measure the same node 1 in the same direction"),
])
def test_refusals_say_what_and_where(table, n_channels, message):
    with pytest.raises(ValueError, match=f"^{re.escape(message)}$"):
        check_channel_table(table, n_channels)


def test_reference_keys_round_directions_to_a_thousandth_without_minus_zero():
    """A direction 2e-4 off an axis is that axis (as another setup's
    reference channel is recognised); a component of -2e-4 rounds to 0,
    never -0 (printed in messages)."""
    table = check_channel_table(_table(x=[0.0002, -0.0002], z=[1.0, 1.0], node=["1", "2"]))
    keys = dof_keys(table)
    assert keys == [("1", 0.0, 0.0, 1.0), ("2", 0.0, 0.0, 1.0)]
    assert [f"{k[1]:g}" for k in keys] == ["0", "0"]


# --- the project's CSV ------------------------------------------------------------------------------------------


def test_a_csv_written_by_hand_keeps_its_text_as_written(tmp_path):
    """Spaces after commas and around header names, capitals in the
    header ("Node"), names and nodes with leading zeros: names and nodes
    read as text, trimmed, never as numbers (a "Node" column was once read
    as numbers, node 01 becoming 1)."""
    from modal.setups import read_channel_table

    path = tmp_path / "channels.csv"
    path.write_text("Channel , NAME,Node,x,y,z,Quantity,role\n0, top,01,1,0,0,acceleration,reference\n"
                    "1, 007,02,0,0,-1,velocity,roving\n")
    t = read_channel_table(path, n_channels=2)
    assert list(t["name"]) == ["top", "007"] and list(t["node"]) == ["01", "02"] and list(t["unit"]) == ["", ""]
    np.testing.assert_array_equal(t[["x", "y", "z"]].to_numpy(), [[1, 0, 0], [0, 0, -1]])


NOTHING = " (a zero or missing direction measures nothing)"


@pytest.mark.parametrize("header, row, message", [
    ("x,y,z,azimuth,elevation", "2,0,0,0,0", "channel 0: direction (2, 0, 0) is not a unit vector" + NOTHING),
    ("x,y,z,azimuth,elevation", "0.5,0,0,0,0", "channel 0: direction (0.5, 0, 0) is not a unit vector" + NOTHING),
    ("x,y,z,azimuth,elevation", "0,0,0,0,0", "row 1: x, y, z = (0, 0, 0) and azimuth, elevation = (0, 0) "
                                             "(direction (1.0, 0.0, 0.0)) disagree: give one or the other"),
    ("azimuth,elevation", "north,0", "channel 0: direction (nan, nan, 0) is not a unit vector" + NOTHING),
    ("x,y,z,azimuth,elevation", "one,0,0,0,0", "row 1: x must be a number, got 'one'"),
    ("x,y,z", "one,0,0", "row 1: x must be a number, got 'one'"),
    ("x,y,z", "0,two,1", "row 1: y must be a number, got 'two'"),
    ("x,y,z", "0,0,three", "row 1: z must be a number, got 'three'"),
])
def test_directions_as_written_are_checked_as_written(tmp_path, header, row, message):
    """x, y, z beside azimuth, elevation: compared as directions (scaled to
    unit length, a zero one disagrees), then checked as given; a word where
    a number belongs named with its row and column."""
    from modal.setups import read_channel_table

    path = tmp_path / "channels.csv"
    path.write_text(f"channel,node,{header},quantity,role\n0,1,{row},acceleration,reference\n")
    with pytest.raises(ValueError) as caught:
        read_channel_table(path)
    assert str(caught.value) == f"{path}: {message}"


def test_files_that_are_no_table_are_named(tmp_path):
    from modal.setups import read_channel_table

    cases = {"blank.csv": b"  \n \n", "binary.csv": b"channel,node\x00\n0,1\n",
             "ragged.csv": b"channel,node\n0,1\n1,2,3,4\n"}
    for name, data in cases.items():
        (tmp_path / name).write_bytes(data)
    (tmp_path / "folder.csv").mkdir()
    said = {}
    for name in [*cases, "folder.csv"]:
        with pytest.raises(ValueError) as caught:
            read_channel_table(tmp_path / name)
        said[name] = str(caught.value).removeprefix(f"{tmp_path / name}: ")
    assert said["blank.csv"].startswith("the channel table is empty; expected a header")
    assert said["binary.csv"] == "binary data (a NUL byte), not a text file (UTF-16 text: save it as UTF-8)"
    assert said["ragged.csv"].startswith("cannot read the channel table: Error tokenizing data")
    assert said["folder.csv"] == "cannot be read (Is a directory)"


# --- pyOMA's setup folders ---------------------------------------------------------------------------------------


def _pyoma(tmp_path, name="m", rate="100", info_extra=(), dofs=None, **lists):
    from .test_setups import _pyoma_folder

    acc = np.random.default_rng(0).standard_normal((200, 3))
    folder = _pyoma_folder(tmp_path / name, acc, ["1", "2", "3"], [(90, 0), (0, -90), (45, 0)], refs=[0],
                           deleted=[], accel=[0], velo=[1], rate=rate)
    info = (folder / "setup_info.txt").read_text().replace("Disp. Channels:\n\n", "Disp. Channels:\n2\n")
    for key, value in lists.items():
        info = info.replace(f"{key}:\n", f"{key}:\n{value}\n", 1) if value is not None else \
            info.replace(f"{key}:\n", "", 1)
    (folder / "setup_info.txt").write_text(info + "".join(info_extra))
    if dofs is not None:
        (folder / "channel_dofs.txt").write_text(dofs)
    return folder


def test_a_pyoma_folder_read_cell_by_cell(tmp_path):
    """Directions from (azimuth, elevation) in that order, the quantities of
    the three lists, the channel names, a rate below 1 Hz; a note below
    #### that looks like an entry changes nothing."""
    from modal.setups import read_pyoma_setup

    folder = _pyoma(tmp_path, rate="0.5", info_extra=["Reference Channels:\n2\n"])
    path, rate, table = read_pyoma_setup(folder)
    assert path == folder / "m.npy" and rate == 0.5
    np.testing.assert_allclose(table[["x", "y", "z"]].to_numpy(), [[0, 1, 0], [0, 0, -1],
                                                                   [np.sqrt(0.5), np.sqrt(0.5), 0]], atol=1e-15)
    assert list(table["quantity"]) == ["acceleration", "velocity", "displacement"]
    assert list(table["name"]) == ["ch_0", "ch_1", "ch_2"] and list(table["role"]) == ["reference", "roving", "roving"]
    header = "Channel-Nr. \t Node\tAzimuth \tElevation\tChannel Name \n"  # spaces around the names
    folder = _pyoma(tmp_path, "n", dofs=header + "0\t1\t90\t0\tch_a\n1\t2\t0\t-90\tch_b\n2\t3\t45\t0\tch_c\n")
    assert list(read_pyoma_setup(folder)[2]["name"]) == ["ch_a", "ch_b", "ch_c"]


def test_a_last_label_without_values_lists_none(tmp_path):
    """setup_info.txt ending on 'Disp. Channels:' (no line after it): no
    displacement channel, not an error."""
    from modal.setups import read_pyoma_setup

    folder = _pyoma(tmp_path)
    info = (folder / "setup_info.txt").read_text().split("Disp. Channels:")[0] + "Disp. Channels:"
    (folder / "setup_info.txt").write_text(info.replace("Accel. Channels:\n0\n", "Accel. Channels:\n0 2\n"))
    assert list(read_pyoma_setup(folder)[2]["quantity"]) == ["acceleration", "velocity", "acceleration"]


@pytest.mark.parametrize("change, message", [
    ({"rate": "0"}, "setup_info.txt: 'Sampling Rate [Hz]' must be one positive number, got [0.0]"),
    ({"rate": "100 200"}, "setup_info.txt: 'Sampling Rate [Hz]' must be one positive number, got [100.0, 200.0]"),
    ({"Velo. Channels": None}, "setup_info.txt: no 'velo. channels' entry"),
    ({"Reference Channels": "a b"}, "setup_info.txt: 'reference channels' must list numbers, got 'a b'"),
    ({"dofs": " \n\t\n"}, "channel_dofs.txt: expected tab-separated columns Channel-Nr., Node, Azimuth, Elevation, "
                          "Channel Name (the file is empty)"),
    ({"dofs": "Channel-Nr.\tNode\tAzimuth\tElevation\tChannel Name\n0\t1\t90\t0\ta\n1\t1\t90\t0\tb\n2\t3\t0\t0\tc\n"},
     "channel_dofs.txt: channels [0, 1] measure the same node 1 in the same direction"),
])
def test_pyoma_refusals_name_the_file_and_the_entry(tmp_path, change, message):
    from modal.setups import read_pyoma_setup

    change = dict(change)
    folder = _pyoma(tmp_path, rate=change.pop("rate", "100"), dofs=change.pop("dofs", None), **change)
    with pytest.raises(ValueError) as caught:
        read_pyoma_setup(folder)
    assert str(caught.value) == f"{folder}/{message}"


def test_a_pyoma_folder_without_its_files_or_with_two_records(tmp_path):
    from modal.setups import read_pyoma_setup

    folder = _pyoma(tmp_path)
    np.save(folder / "other.npy", np.zeros((10, 3)))
    with pytest.raises(ValueError, match=r"m: a pyOMA setup folder holds one \.npy record, found 2$"):
        read_pyoma_setup(folder)
    (folder / "setup_info.txt").unlink()
    with pytest.raises(ValueError, match=r"m: not a pyOMA setup folder: setup_info.txt is missing$"):
        read_pyoma_setup(folder)
    (folder / "setup_info.txt").mkdir()  # a folder of that name is not the file
    with pytest.raises(ValueError, match=r"m: not a pyOMA setup folder: setup_info.txt is missing$"):
        read_pyoma_setup(folder)


def test_a_setup_info_written_by_another_tool(tmp_path):
    """Labels indented, with a space before the colon or spaces after it,
    values with trailing spaces, the file ending on the last values without
    a newline: read as pyOMA's own; a refusal quotes the values trimmed."""
    from modal.setups import read_pyoma_setup

    folder = _pyoma(tmp_path)
    info = ("  Setup Name :  \nm\nSampling Rate [Hz]:   \n100  \n Reference Channels :\n0\nDelete Channels:\n\n"
            "Accel. Channels :\n0 \nVelo. Channels:\n1\t\nDisp. Channels:\n2")
    (folder / "setup_info.txt").write_text(info)
    path, rate, table = read_pyoma_setup(folder)
    assert rate == 100 and list(table["role"]) == ["reference", "roving", "roving"]
    assert list(table["quantity"]) == ["acceleration", "velocity", "displacement"]
    (folder / "setup_info.txt").write_text(info.replace("Reference Channels :\n0\n", "Reference Channels :\na b  \n"))
    with pytest.raises(ValueError, match=r"'reference channels' must list numbers, got 'a b'$"):
        read_pyoma_setup(folder)
