"""Reading a setup (:func:`modal.setups.read_setup`): which files make a
setup, its name, and each refusal naming the file and the fix; what
:func:`modal.setups.identify_setup` passes on."""

import shutil
from pathlib import Path

import numpy as np
import pytest

from modal.setups import read_geometry, read_setup

from .test_setups import _pyoma_folder

DATA = Path(__file__).resolve().parents[2] / "data"
SETUP_1 = DATA / "roving_plate" / "setup_1"


def test_a_setup_folder_is_named_after_it_and_reads_its_one_record(tmp_path):
    shutil.copytree(SETUP_1, tmp_path / "north")
    (tmp_path / "north" / "notes.md").write_text("not a record")
    (tmp_path / "north" / "old.npz").mkdir()  # a folder, whatever its name, is not a record
    setup = read_setup(tmp_path / "north", geometry=read_geometry(DATA / "roving_plate" / "geometry"))
    assert setup.name == "north" and setup.path == tmp_path / "north"
    assert setup.record.acc.shape[1] == 5 and list(setup.channels["channel"]) == [0, 1, 2, 3, 4]
    assert list(setup.channels["node"][:2]) == ["1-1", "5-3"] and setup.reference_keys[1] == ("5-3", 0.0, 0.0, -1.0)


def test_every_kind_of_record_beside_a_channel_table_is_counted(tmp_path):
    """One file of each record kind (any case of suffix) beside
    channels.csv: all named as candidates, channels.csv and other files
    not."""
    folder = tmp_path / "s"
    shutil.copytree(SETUP_1, folder)
    (folder / "record.npz").unlink()
    for suffix in (".npy", ".NPZ", ".csv", ".txt", ".tsv", ".lvm", ".uff", ".unv", ".md", ".png"):
        (folder / f"r{suffix}").write_text("")
    with pytest.raises(ValueError, match=r"s: expected one record file beside channels.csv, found r.NPZ, r.csv, "
                                         r"r.lvm, r.npy, r.tsv, r.txt, r.uff, r.unv$"):
        read_setup(folder)
    for path in folder.glob("r.*"):
        path.unlink()
    with pytest.raises(ValueError, match=r"expected one record file beside channels.csv, found none"):
        read_setup(folder)


def test_setup_refusals(tmp_path):
    with pytest.raises(ValueError, match=r"nowhere: no such setup \(a folder or a record file\)"):
        read_setup(tmp_path / "nowhere")
    (tmp_path / "empty").mkdir()
    with pytest.raises(ValueError, match=r"empty: a setup folder holds channel_dofs.txt and setup_info.txt \(pyOMA\) "
                                         "or channels.csv beside one record"):
        read_setup(tmp_path / "empty")
    (tmp_path / "empty" / "channels.csv").mkdir()  # a folder named channels.csv is not a table
    with pytest.raises(ValueError, match="a setup folder holds channel_dofs.txt"):
        read_setup(tmp_path / "empty")
    record = tmp_path / "alone.npy"
    np.save(record, np.zeros((100, 2)))
    with pytest.raises(ValueError, match=r"alone.npy: a record alone has no channel table: give a setup folder"):
        read_setup(record, fs=100)


def test_pyoma_setup_refusals_name_the_channel_and_the_nodes(tmp_path):
    acc = np.random.default_rng(0).standard_normal((200, 2))
    folder = _pyoma_folder(tmp_path / "m", acc, [1, 2, 2], [(0, 0), (90, 0), (0, 0)], refs=[0], deleted=[],
                           accel=[0, 1, 2], velo=[])  # channel 2 beyond the record's 2 columns
    with pytest.raises(ValueError, match=r"m: channel_dofs.txt names channel 2, the record has 2"):
        read_setup(folder)
    folder = _pyoma_folder(tmp_path / "n", acc, ["1-1", "9-9"], [(0, 0), (90, 0)], refs=[0], deleted=[],
                           accel=[0, 1], velo=[])
    geometry = read_geometry(DATA / "roving_plate" / "geometry")
    with pytest.raises(ValueError, match=r"n: node\(s\) 9-9 not in the geometry .*roving_plate/geometry$"):
        read_setup(folder, geometry=geometry)
    setup = read_setup(folder, fs=100.0 * (1 + 1e-7))  # the stated rate, to one part in a million
    assert setup.record.fs == 100 and setup.name == "n"
    with pytest.raises(ValueError, match="states 100 Hz, --fs 100.001 Hz"):
        read_setup(folder, fs=100.001)


def test_a_record_alone_takes_its_channel_table_from_a_geometry_naming_its_sensors():
    """pyOMA2's geometry names the Palisaden record's six channels: the
    record alone is a setup (named after the file), every channel a
    reference, in the record's order."""
    geometry = read_geometry(DATA / "palisaden_geometry")
    setup = read_setup(DATA / "palisaden_20hz_30min.npy", fs=20, geometry=geometry)
    assert setup.name == "palisaden_20hz_30min" and setup.record.fs == 20 and setup.record.acc.shape == (36000, 6)
    assert list(setup.channels["channel"]) == [0, 1, 2, 3, 4, 5] and set(setup.channels["role"]) == {"reference"}
    np.testing.assert_array_equal(setup.channels.set_index("name").loc[["ch5", "ch6", "ch2"], ["x", "y"]].to_numpy(float),
                                  [[-1, 0], [0, 1], [0, -1]])


def test_identify_setup_passes_on_the_criteria_log_and_details():
    """The stability criteria, the log and the details reach the
    identification of a setup (they are not options); the channels are
    named by the record's columns the table picks (4, 2, 0, 1), not by
    their order."""
    import modal

    setup = modal.plate_roving_test(modal.SimplySupportedPlate(1.2, 0.8, 20.0, 10.0), duration=20.0)[0][0]
    setup = modal.Setup(setup.name, setup.record, setup.channels.iloc[[4, 2, 0, 1]].reset_index(drop=True))
    criteria = modal.StabilityCriteria(mac_min=0.9, max_damping=0.2)
    lines, details = [], {}
    result, dt = modal.identify_setup(setup, "ambient", fmax=25, max_order=16, criteria=criteria, log=lines.append,
                                      details=details)
    assert result.criteria == criteria and dt == pytest.approx(0.01)
    assert lines and details["settings"]["channels"] == [4, 2, 0, 1] and "spectrum" in details
