"""Roving tests: channel tables, geometry, setups merged (PoSER) into
shapes in the global frame, checked against a simulated plate's exact
modes, pyOMA's and pyOMA2's formats, and the refusals."""

import hashlib
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
from modal.cli import blas_threads
from modal.cli import main as cli
from modal.setups import (direction_from_angles, merge_setups, node_motion, node_shapes, plate_roving_test,
                          read_channel_table, read_geometry, read_pyoma_setup, read_setup, save_geometry, save_setup,
                          write_setups)

from ...browser import assert_readable, rendered

DATA = Path(__file__).resolve().parents[2] / "data"
WEIMAR = Path(__file__).resolve().parents[4] / "shared" / "data" / "weimar_frame"
PLATE = modal.SimplySupportedPlate(1.2, 0.8, 20.0, 10.0)  # 5.01, 9.64, 15.43, 17.36, 20.05 Hz


@pytest.fixture(scope="module")
def plate_test():
    return plate_roving_test(PLATE, duration=200.0)


@pytest.fixture(scope="module")
def plate_folders(plate_test, tmp_path_factory):
    """The simulated test saved in the project's own format and read back."""
    setups, geometry, _ = plate_test
    root = tmp_path_factory.mktemp("plate")
    for s in setups:
        save_setup(s, root / s.name)
    save_geometry(geometry, root / "geometry")
    return root, [root / s.name for s in setups]


@pytest.fixture(scope="module")
def plate_merged(plate_folders, tmp_path_factory):
    root, folders = plate_folders
    geometry = read_geometry(root / "geometry")
    setups = [read_setup(f, geometry=geometry) for f in folders]
    out = tmp_path_factory.mktemp("plate_out") / "out"
    merged, results = write_setups(setups, out, "ambient", geometry=geometry, fmax=25, animate=False)
    return merged, results, out, geometry


@pytest.mark.slow
def test_merged_plate_modes_match_the_exact_ones(plate_test, plate_merged):
    """Six setups (two references, three roving sensors each, every other
    channel pointing down, a third of them recording in g, a different
    excitation level per setup, 2 % noise) merge into the plate's five
    modes: frequencies within 0.5 %, shapes at all 20 nodes with MAC >=
    0.999 against sin(m pi x / a) sin(n pi y / b)."""
    setups, geometry, (freq, modes) = plate_test
    merged = plate_merged[0]
    assert len(merged.modes) == 5
    np.testing.assert_allclose(merged.modes["freq_hz"], freq, rtol=5e-3)
    assert (merged.modes["n_setups"] == len(setups)).all()
    for k in range(5):
        rows = merged.shapes[merged.shapes["mode"] == k + 1].set_index("node").loc[list(geometry.nodes.index)]
        assert rows[["x", "y"]].isna().all().all()  # only z is measured
        assert modal.mac(rows["z"].to_numpy()[:, None], modes[:, k:k + 1])[0, 0] >= 0.999
        assert np.nanmax(np.abs(rows[["x", "y", "z"]].to_numpy())) == pytest.approx(1.0)


@pytest.mark.slow
def test_units_and_directions_matter(plate_test):
    """Read without their units (g taken as m/s2) or their directions (-z
    taken as +z), the same setups give wrong shapes: the merge uses both."""
    setups, geometry, (freq, modes) = plate_test
    keys = list(geometry.nodes.index)

    def worst_mac(ss):
        merged = merge_setups(ss, [modal.identify_setup(s, "ambient", fmax=25)[0] for s in ss])
        macs = []
        for k in range(len(merged.modes)):
            z = merged.shapes[merged.shapes["mode"] == k + 1].set_index("node").loc[keys, "z"].to_numpy()
            macs.append(modal.mac(z[:, None], modes[:, k:k + 1])[0, 0])
        return min(macs)

    assert worst_mac(setups) >= 0.999
    no_units = [modal.Setup(s.name, s.record, s.channels.assign(unit="")) for s in setups]
    assert worst_mac(no_units) < 0.95
    up = [modal.Setup(s.name, s.record, s.channels.assign(z=1.0)) for s in setups]
    assert worst_mac(up) < 0.95


@pytest.mark.slow
def test_merged_outputs_on_disk(plate_merged):
    merged, results, out, _ = plate_merged
    shapes = pd.read_csv(out / "shapes.csv")
    assert list(shapes.columns) == ["mode", "node", "x", "y", "z", "x_im", "y_im", "z_im", "flag"]
    assert len(shapes) == 5 * 20
    matches = pd.read_csv(out / "matches.csv")
    assert len(matches) == 5 * 6 and set(matches["source"]) == {"selected"}
    for name in ("setup_1", "setup_6"):
        assert (out / "setups" / name / "stabilisation.png").stat().st_size > 10_000
        assert len(pd.read_csv(out / "setups" / name / "modes.csv")) >= 5
    assert (out / "mode_1.png").stat().st_size > 10_000
    assert len(pd.read_csv(out / "channels.csv")) == 6 * 5


@pytest.mark.slow
def test_a_mode_a_setup_did_not_select_comes_from_its_diagram(plate_test):
    """A mode dropped from one setup's selection is still found in that
    setup's diagram, so its roving nodes keep a shape."""
    setups, geometry, (freq, modes) = plate_test
    results = [modal.identify_setup(s, "ambient", fmax=25)[0] for s in setups]
    first = results[0]
    keep = first.modes["freq_hz"] < 9  # setup 1 "missed" every mode above 9 Hz
    results[0] = modal.Stabilisation(first.modes[keep], first.shapes[:, keep.to_numpy()], first.poles,
                                     first.pole_shapes, first.singular_values, first.spectrum_hz, first.spectrum,
                                     first.criteria, first.complex_shapes[:, keep.to_numpy()], first.candidates)
    merged = merge_setups(setups, results)
    assert list(merged.modes["n_from_diagram"]) == [0, 1, 1, 1, 1]
    assert list(merged.modes["n_setups"]) == [6, 5, 5, 5, 5]
    diagram = merged.matches[merged.matches["source"] == "diagram"]
    assert set(diagram["setup"]) == {"setup_1"} and (diagram["setup_mode"] == 0).all()
    for k in range(5):
        z = merged.shapes[merged.shapes["mode"] == k + 1].set_index("node").loc[list(geometry.nodes.index), "z"]
        assert z.notna().all()
        assert modal.mac(z.to_numpy()[:, None], modes[:, k:k + 1])[0, 0] >= 0.999


@pytest.mark.slow
def test_min_setups_drops_a_mode_seen_once(plate_test):
    setups, _, _ = plate_test
    results = [modal.identify_setup(s, "ambient", fmax=12)[0] for s in setups[:2]]
    merged = merge_setups(setups[:2], results, min_setups=2)
    trusted = merged.modes[merged.modes["flag"] == ""]  # a mode both setups flag doubtful is flagged, not trusted
    assert np.allclose(trusted["freq_hz"], [5.014, 9.642], rtol=5e-3)
    assert all(f.startswith("doubtful in every setup that selected it (") for f in
               merged.modes.loc[merged.modes["flag"] != "", "flag"])


def test_node_shapes_resolve_oblique_directions():
    """Three oblique directions at a node give its full motion; two in the
    horizontal plane give x and y, z unknown (NaN); one oblique direction
    gives no global component."""
    e = direction_from_angles([28.9, 81.0, 55.9], [-8.7, -7.3, 29.3])
    u = np.array([0.3 - 0.1j, -1.0, 0.25j])
    rows = [("a", tuple(d)) for d in e] + [("b", (-1.0, 0, 0)), ("b", (0, -1.0, 0)), ("c", tuple(e[0]))]
    values = list(e @ u) + [-u[0], -u[1], e[0] @ u]
    out = node_shapes(rows, values)
    np.testing.assert_allclose(out["a"], u, atol=1e-12)
    np.testing.assert_allclose(out["b"][:2], u[:2], atol=1e-12)
    assert np.isnan(out["b"][2]) and np.isnan(out["c"]).all()


def test_direction_from_angles_follows_pyoma():
    """pyOMA: e = (cos b cos a, cos b sin a, sin b); the Weimar references
    (0, 180) and (-90, 0) point along -x and -y, (0, 90) along z."""
    np.testing.assert_array_equal(direction_from_angles([0, -90, 0, 90], [180, 0, 90, 0]),
                                  [[-1, 0, 0], [0, -1, 0], [0, 0, 1], [0, 1, 0]])


def _pyoma_folder(folder, acc, nodes, angles, refs, deleted, accel, velo, rate=100):
    folder.mkdir(parents=True)
    np.save(folder / f"{folder.name}.npy", acc)
    lines = ["Channel-Nr.\tNode\tAzimuth\tElevation\tChannel Name"]
    lines += [f"{c}\t{n}\t{a}\t{e}\tch_{c}" for c, (n, (a, e)) in enumerate(zip(nodes, angles))]
    (folder / "channel_dofs.txt").write_text("\n".join(lines) + "\n")
    info = ["Setup Name:", folder.name, "Sampling Rate [Hz]:", str(rate), "Reference Channels:", " ".join(map(str, refs)),
            "Delete Channels:", " ".join(map(str, deleted)), "Accel. Channels:", " ".join(map(str, accel)),
            "Velo. Channels:", " ".join(map(str, velo)), "Disp. Channels:", "", "####", "Note:", "a note"]
    (folder / "setup_info.txt").write_text("\n".join(info) + "\n")
    return folder


def test_pyoma_layout_is_read(tmp_path):
    acc = np.random.default_rng(0).standard_normal((500, 4))
    folder = _pyoma_folder(tmp_path / "measurement_1", acc, [5, 5, 24, 24], [(30, -8), (81, -7), (0, 180), (-90, 0)],
                           refs=[2, 3], deleted=[1], accel=[2, 3], velo=[0, 1])
    path, rate, table = read_pyoma_setup(folder)
    assert path.name == "measurement_1.npy" and rate == 100
    assert list(table["channel"]) == [0, 2, 3]  # channel 1 deleted
    assert list(table["role"]) == ["roving", "reference", "reference"]
    assert list(table["quantity"]) == ["velocity", "acceleration", "acceleration"]
    np.testing.assert_allclose(table.loc[1, ["x", "y", "z"]].to_numpy(dtype=float), [-1, 0, 0], atol=1e-12)
    setup = read_setup(folder)
    assert setup.record.fs == 100 and setup.name == "measurement_1"
    with pytest.raises(ValueError, match="states 100 Hz, --fs 50 Hz"):
        read_setup(folder, fs=50)


def test_pyoma_layout_refusals(tmp_path):
    acc = np.zeros((100, 3))
    folder = _pyoma_folder(tmp_path / "m", acc, [1, 1, 2], [(0, 0), (90, 0), (0, 0)], refs=[5], deleted=[],
                           accel=[0, 1, 2], velo=[])
    with pytest.raises(ValueError, match=r"reference channel\(s\) \[5\] not in channel_dofs.txt"):
        read_pyoma_setup(folder)
    folder = _pyoma_folder(tmp_path / "n", acc, [1, 1, 2], [(0, 0), (90, 0), (0, 0)], refs=[2], deleted=[],
                           accel=[0, 1], velo=[])
    with pytest.raises(ValueError, match=r"channel\(s\) \[2\] are neither"):
        read_pyoma_setup(folder)


def _table(**changes):
    base = {"channel": [0, 1], "name": ["a", "b"], "node": ["1", "2"], "x": [1.0, 0.0], "y": [0.0, 0.0],
            "z": [0.0, 1.0], "quantity": ["acceleration"] * 2, "unit": ["m/s2", "g"], "role": ["reference", "roving"]}
    base.update(changes)
    return pd.DataFrame(base)


@pytest.mark.parametrize("changes, message", [
    ({"x": [0.0, 0.0], "z": [0.0, 1.0]}, r"channel 0: direction \(0, 0, 0\) is not a unit vector"),
    ({"x": [2.0, 0.0]}, "is not a unit vector"),
    ({"quantity": ["acceleration", "strain"]}, "quantity 'strain'"),
    ({"unit": ["m/s", "g"]}, "unit 'm/s' is not a unit of acceleration"),
    ({"role": ["reference", "fixed"]}, "role 'fixed'"),
    ({"channel": [0, 7]}, r"channel\(s\) \[7\] beyond the record's 2 columns"),
    ({"channel": [0, float("inf")]}, r"row 2: channel must be a column number >= 0, got inf"),
    ({"channel": [0, float("nan")]}, r"row 2: channel must be a column number >= 0, got nan"),
    ({"channel": [0, "99999999999999999999"]}, r"row 2: channel must be a column number >= 0, got 1e\+20"),
    ({"channel": ["one", 1]}, r"row 1: channel must be a number, got 'one'"),  # rows of channels, as below
    ({"channel": [0, 1.5]}, r"row 2: channel must be a column number >= 0, got 1.5"),
    ({"channel": [-1, 1]}, r"row 1: channel must be a column number >= 0, got -1"),
    ({"channel": [1, 1]}, r"channel\(s\) \[1\] listed twice"),
    ({"node": ["1", "1"], "z": [0.0, 0.0], "x": [1.0, 1.0]}, "measure the same node 1 in the same direction"),
    ({"node": ["1", "9"]}, r"node\(s\) 9 not in the geometry"),
    ({"node": ["1", " "]}, "no node"),
])
def test_channel_table_refusals(tmp_path, changes, message):
    path = tmp_path / "channels.csv"
    _table(**changes).to_csv(path, index=False)
    with pytest.raises(ValueError, match=message):
        read_channel_table(path, n_channels=2, nodes=["1", "2"])


def test_channel_table_angles_and_defaults(tmp_path):
    path = tmp_path / "channels.csv"
    path.write_text("channel,node,azimuth,elevation,quantity,role\n0,7,0,180,acceleration,reference\n"
                    "1,8,-90,0,velocity,roving\n")
    t = read_channel_table(path, n_channels=2)
    np.testing.assert_allclose(t[["x", "y", "z"]].to_numpy(dtype=float), [[-1, 0, 0], [0, -1, 0]], atol=1e-12)
    assert list(t["name"]) == ["ch0", "ch1"] and list(t["unit"]) == ["", ""]


@pytest.mark.slow
def test_setups_must_share_their_references(plate_test):
    setups, _, _ = plate_test
    moved = setups[1].channels.copy()
    moved.loc[0, "node"] = "2-2"
    with pytest.raises(ValueError, match=r"setup setup_2: its reference channels differ .* missing node 1-1"):
        modal.check_setups([setups[0], modal.Setup("setup_2", setups[1].record, moved)])
    none = setups[1].channels.assign(role="roving")
    with pytest.raises(ValueError, match="no reference channel"):
        modal.check_setups([modal.Setup("a", setups[1].record, none), modal.Setup("b", setups[1].record, none)])
    with pytest.raises(ValueError, match="names repeat"):
        modal.check_setups([setups[0], setups[0]])


@pytest.mark.slow
def test_pyoma2_geometry_gives_palisaden_channel_table_and_modes(tmp_path):
    """pyOMA2's geometry 2 (points, sensor map and signs) names the
    Palisaden channels: one command identifies the record on it, finds the
    three published modes (1.882, 2.421, 2.689 Hz, within 1 %) and draws
    them; the sensors measure x and y only (z is NaN)."""
    geometry = read_geometry(DATA / "palisaden_geometry")
    assert list(geometry.nodes.index) == ["1", "2", "3", "4", "5", "6"]
    sensors = geometry.sensors.set_index("name")
    np.testing.assert_array_equal(sensors.loc[["ch5", "ch6", "ch2"], ["x", "y"]].to_numpy(dtype=float),
                                  [[-1, 0], [0, 1], [0, -1]])
    out = tmp_path / "out"
    code = cli(["identify", str(DATA / "palisaden_20hz_30min.npy"), "--fs", "20", "--geometry",
                str(DATA / "palisaden_geometry"), "--ambient", "--fmax", "5", "--highpass", "0.5", "--out", str(out),
                "--quiet", "--no-animation"])
    assert code == 0
    modes = pd.read_csv(out / "modes.csv")
    for published in (1.882, 2.421, 2.689):
        assert np.min(np.abs(modes["freq_hz"] - published)) / published < 0.01
    shapes = pd.read_csv(out / "shapes.csv")
    assert set(shapes["node"].astype(str)) == {"1", "2", "3"} and shapes["z"].isna().all()
    assert (out / "mode_1.png").is_file() and not (out / "mode_1.gif").exists()


def test_pyoma2_geometry_1_groups_sensors_into_nodes(tmp_path):
    folder = tmp_path / "geo1"
    folder.mkdir()
    for name in ("sens_coord.txt", "sens_dir.txt"):
        (folder / name).write_text((DATA / "palisaden_geometry" / name).read_text())
    geometry = read_geometry(folder)
    assert len(geometry.nodes) == 3 and len(geometry.sensors) == 6
    t = geometry.channel_table([f"ch{k}" for k in range(1, 7)])
    assert list(t["channel"]) == [0, 1, 2, 3, 4, 5]
    assert t.groupby("node").size().tolist() == [2, 2, 2]


def test_pyoma_geometry_and_links(tmp_path):
    """pyOMA's grid, lines and parent-child files (with their notes below
    ####): a child node moves as its parent in the linked direction."""
    (tmp_path / "grid.txt").write_text("node_name\t x\t y\t z\n 1 0 0 0\n 2 1 0 0\n 3 1 1 0\n")
    (tmp_path / "lines.txt").write_text("node_name_1\t node_name_2\n 1 2\n 2 3\n")
    (tmp_path / "parent_child_assignments.txt").write_text(
        "parent_node\tx_parent\ty_parent\tz_parent\tchild_node\tx_child\ty_child\tz_child\n"
        "2\t\t1.00\t0.00\t0.00\t3\t1.00\t0.00\t0.00\n\n\n########\ntab separated file\n")
    geometry = read_geometry(tmp_path)
    assert geometry.lines == [("1", "2"), ("2", "3")]
    shapes = pd.DataFrame({"mode": 1, "node": ["2"], "x": [0.5], "y": [0.2], "z": [np.nan], "x_im": [0.0],
                           "y_im": [0.0], "z_im": [np.nan]})
    u, measured = node_motion(geometry, shapes, 1)
    np.testing.assert_allclose(u.real, [[0, 0, 0], [0.5, 0.2, 0], [0.5, 0, 0]])
    assert list(measured) == [False, True, False]


def test_geometry_refusals(tmp_path):
    with pytest.raises(ValueError, match="no nodes.csv"):
        read_geometry(tmp_path)
    (tmp_path / "nodes.csv").write_text("node,x,y,z\n1,0,0,0\n2,1,0,0\n")
    (tmp_path / "lines.csv").write_text("node_1,node_2\n1,3\n")
    with pytest.raises(ValueError, match="line 1-3 names a node not in the geometry"):
        read_geometry(tmp_path)
    (tmp_path / "nodes.csv").write_text("node,x,y,z\n1,0,0,0\n1,1,0,0\n")
    with pytest.raises(ValueError, match=r"node\(s\) \['1'\] defined twice"):
        read_geometry(tmp_path)


@pytest.mark.slow
def test_command_line_setups(plate_folders, tmp_path, capsys):
    root, folders = plate_folders
    out = tmp_path / "out"
    code = cli(["identify", *map(str, folders), "--geometry", str(root / "geometry"), "--ambient", "--fmax", "25",
                "--out", str(out), "--quiet", "--no-animation"])
    assert code == 0, capsys.readouterr().err
    assert "6 setup(s): 5 modes" in capsys.readouterr().out
    # the page a reader opens, in Chromium: the shapes and the six diagrams, one row per merged mode
    seen = rendered(out / "report.html")
    assert_readable(seen, images=1 + 6)
    setups_table, modes_table = seen["tables"][:2]
    assert setups_table["rows"] == 1 + 6 and modes_table["rows"] == 1 + len(pd.read_csv(out / "modes.csv"))
    assert_readable(rendered(out / "setups" / folders[0].name / "report.html"), images=2)
    assert cli(["identify", *map(str, folders), "--refs", "0", "--ambient", "--out", str(tmp_path / "x")]) == 2
    assert "--refs: with setups" in capsys.readouterr().err
    assert cli(["identify", str(folders[0]), str(tmp_path), "--ambient", "--out", str(tmp_path / "y")]) == 3
    assert "a setup folder holds channel_dofs.txt" in capsys.readouterr().err
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()


@pytest.mark.skipif(not WEIMAR.is_dir(), reason=f"the Weimar frame's records are not at {WEIMAR}")
def test_weimar_frame_fifteen_setups(tmp_path):
    """All 15 setups of the Weimar frame (pyOMA's layout): the 11 modes
    below 15 Hz of pyOMA's PoSER merge (their means, within 0.1 %: 13.85 Hz scatters by 0.01 Hz over their setups), each
    with a shape at all 16 measured nodes."""
    published = [1.22830363, 1.43578505, 2.10004249, 4.01751194, 4.77037789, 6.68235152, 7.61569118, 9.66534022,
                 12.16628982, 12.59793635, 13.85447573]
    geometry = read_geometry(WEIMAR)
    setups = [read_setup(WEIMAR / f"measurement_{k}", geometry=geometry) for k in range(1, 16)]
    results = [modal.identify_setup(s, "ambient", fmax=15)[0] for s in setups]
    merged = merge_setups(setups, results)
    np.testing.assert_allclose(merged.modes["freq_hz"], published, rtol=1e-3)
    assert (merged.modes["n_setups"] + merged.modes["n_from_diagram"] == 15).all()
    counts = merged.shapes.dropna(subset=["x"]).groupby("mode")["node"].nunique()
    assert (counts == 16).all()


def test_two_close_modes_of_one_setup_stay_two():
    """Matching takes at most one mode per setup into a merged mode: two
    modes of setup 0 at 10.00 and 10.05 Hz (0.5 % apart, same reference
    part) stay apart, and setup 1's 10.02 Hz joins the nearer one."""
    from modal.setups._merge import _match

    r = np.array([1.0, 1.0 + 0j])
    clusters = _match([(0, 0, 10.0, r, 0.005), (0, 1, 10.05, r, 0.005), (1, 0, 10.02, r, 0.005)], freq_rtol=0.01,
                      mac_min=0.8)
    assert sorted(sorted((s, k) for s, k, *_ in c) for c in clusters) == [[(0, 0), (1, 0)], [(0, 1)]]
    different = np.array([1.0, -1.0 + 0j])  # orthogonal reference part: not the same mode
    clusters = _match([(0, 0, 10.0, r, 0.005), (1, 0, 10.01, different, 0.005)], freq_rtol=0.01, mac_min=0.8)
    assert len(clusters) == 2


@pytest.mark.slow
def test_a_second_run_replaces_the_folder_of_setups(plate_test, tmp_path):
    """Writing into an existing results folder replaces its setups/ folder
    as a whole (a setup left out is gone), other files stay."""
    setups, geometry, _ = plate_test
    out = tmp_path / "out"
    write_setups(setups[:3], out, "ambient", fmax=12)
    (out / "notes.txt").write_text("mine")
    write_setups(setups[:2], out, "ambient", fmax=12)
    assert sorted(p.name for p in (out / "setups").iterdir()) == ["setup_1", "setup_2"]
    assert (out / "notes.txt").read_text() == "mine"
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


def test_roving_report_settings_and_drawing_progress(tmp_path):
    """Two short setups saved and read back, merged and drawn: a report and
    settings per setup and for the test (each setup's files hashed), and a
    log line for each picture before it is drawn."""
    setups, geometry, _ = plate_roving_test(PLATE, duration=60.0)
    for s in setups[:2]:
        save_setup(s, tmp_path / s.name)
    read = [read_setup(tmp_path / s.name, geometry=geometry) for s in setups[:2]]
    lines = []
    out = tmp_path / "out"
    with blas_threads():  # as modal identify runs it
        merged, _ = write_setups(read, out, "ambient", geometry=geometry, fmax=25, max_order=20, animate=False,
                                 log=lines.append, command="modal identify setup_1 setup_2")
    n = len(merged.modes)
    assert n >= 3
    drawing = [line for line in lines if "mode_" in line and ".png" in line]
    assert len(drawing) == n and drawing[0].strip().startswith(f"mode 1 (1/{n})")
    assert any(line.startswith(f"drawing {n} modes") for line in lines)
    page = (out / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 1 + 2  # the shapes, each setup's diagram
    assert "setup_1" in page and "setup_2" in page and "modal identify setup_1 setup_2" in page
    settings = json.loads((out / "settings.json").read_text())
    hashed = {f["path"]: f["sha256"] for f in settings["provenance"]["inputs"]}
    assert len(hashed) == 4  # two records, two channel tables
    table = tmp_path / "setup_1" / "channels.csv"
    assert hashed[str(table.resolve())] == hashlib.sha256(table.read_bytes()).hexdigest()
    for s in read:
        own = json.loads((out / "setups" / s.name / "settings.json").read_text())
        assert own["options"]["channels"] == list(s.channels["channel"])
        assert own["options"]["quantities"] == list(s.channels["quantity"])
        assert (out / "setups" / s.name / "report.html").is_file() and (out / "setups" / s.name / "mac.csv").is_file()


@pytest.mark.parametrize("quantity, spellings, factor", [
    ("acceleration", ["m/s2", "m/s^2", "m/s**2", "m s^-2", "m s-2", "m·s⁻²", "M/S²"], 1.0),
    ("acceleration", ["mg", "mG"], 9.80665e-3),
    ("acceleration", ["g", "G"], 9.80665),
    ("acceleration", ["cm/s2", "gal", "Gal"], 1e-2),
    ("velocity", ["µm/s", "\u03bcm/s", "um/s", "µm s^-1"], 1e-6),  # the micro sign and the Greek mu
    ("velocity", ["mm/s", "mm s-1"], 1e-3),
    ("displacement", ["µm", "\u03bcm"], 1e-6),
])
def test_unit_spellings_are_one_unit(quantity, spellings, factor):
    from modal.setups._channels import unit_factor

    for unit in spellings:
        assert unit_factor(quantity, unit) == pytest.approx(factor, rel=1e-15), unit


@pytest.mark.parametrize("quantity, unit", [("acceleration", "m/s"), ("velocity", "m/s2"), ("acceleration", "ms"),
                                            ("displacement", "mg"), ("acceleration", "m s-1")])
def test_a_unit_of_another_quantity_is_refused(quantity, unit):
    from modal.setups._channels import unit_factor

    with pytest.raises(ValueError, match=rf"unit '{unit}' is not a unit of {quantity}: expected one of"):
        unit_factor(quantity, unit)


# --- setup and geometry files as exported elsewhere ---------------------------------------------
def test_pyoma_setup_in_latin1_reads_as_in_utf8(tmp_path):
    """A Windows export: setup_info.txt in Latin-1 (a name with 'ä') reads
    like its UTF-8 copy; an empty channel_dofs.txt is named as empty."""
    acc = np.random.default_rng(0).standard_normal((200, 2))
    utf8 = _pyoma_folder(tmp_path / "a", acc, [1, 2], [(0, 0), (90, 0)], refs=[0], deleted=[], accel=[0, 1], velo=[])
    latin = _pyoma_folder(tmp_path / "b", acc, [1, 2], [(0, 0), (90, 0)], refs=[0], deleted=[], accel=[0, 1], velo=[])
    for folder in (utf8, latin):
        info = (folder / "setup_info.txt").read_text().replace(f"\n{folder.name}\n", "\nMessung_ä\n", 1)
        (folder / "setup_info.txt").write_bytes(info.encode("utf-8" if folder is utf8 else "latin-1"))
    pd.testing.assert_frame_equal(read_pyoma_setup(latin)[2], read_pyoma_setup(utf8)[2])
    assert read_pyoma_setup(latin)[1] == 100
    (latin / "channel_dofs.txt").write_text("")
    with pytest.raises(ValueError, match=r"b/channel_dofs.txt: expected tab-separated columns .*the file is empty"):
        read_pyoma_setup(latin)


def test_channel_table_with_xyz_and_angles_that_disagree_is_refused(tmp_path):
    """Both ways of giving a direction: used when they agree, refused naming
    the row when they do not (the angles were silently ignored)."""
    table = _table()
    table["azimuth"], table["elevation"] = [0.0, 0.0], [0.0, 90.0]  # (1, 0, 0) and (0, 0, 1): as x, y, z
    table.to_csv(tmp_path / "channels.csv", index=False)
    agreed = read_channel_table(tmp_path / "channels.csv", n_channels=2, nodes=["1", "2"])
    np.testing.assert_allclose(agreed[["x", "y", "z"]].to_numpy(dtype=float), [[1, 0, 0], [0, 0, 1]], atol=1e-12)
    table["elevation"] = [0.0, -90.0]  # row 2 now points down, x, y, z up
    table.to_csv(tmp_path / "channels.csv", index=False)
    with pytest.raises(ValueError, match=r"channels.csv: row 2: x, y, z = \(0.0, 0.0, 1.0\) and azimuth, elevation "
                                         r"= \(0.0, -90.0\) \(direction \(0.0, 0.0, -1.0\)\) disagree"):
        read_channel_table(tmp_path / "channels.csv", n_channels=2, nodes=["1", "2"])
    (tmp_path / "channels.csv").write_text("")
    with pytest.raises(ValueError, match="the channel table is empty"):
        read_channel_table(tmp_path / "channels.csv", n_channels=2)


def test_geometry_files_name_the_bad_row(tmp_path):
    (tmp_path / "grid.txt").write_text("node_name\t x\t y\t z\n 1 0 0 0\n 2 1 zero 0\n")
    with pytest.raises(ValueError, match=r"grid.txt: row 2, column y: 'zero' is not a number"):
        read_geometry(tmp_path)
    (tmp_path / "grid.txt").write_text("node_name\t x\t y\t z\n 1 0 0 0\n 2 1 0 0\n")
    (tmp_path / "lines.txt").write_text("1\n2\n")
    with pytest.raises(ValueError, match=r"lines.txt: expected 2 columns \(the two nodes of each line\), found 1"):
        read_geometry(tmp_path)
    signs = tmp_path / "p2"
    signs.mkdir()
    for name in ("pts_coord.txt", "sens_map.txt", "sens_sign.txt"):
        (signs / name).write_text((DATA / "palisaden_geometry" / name).read_text())
    (signs / "sens_sign.txt").write_text((signs / "sens_sign.txt").read_text().replace("-1", "minus", 1))
    with pytest.raises(ValueError, match=r"sens_sign.txt: point 1, column x: 'minus' is not a sign: expected 1 or -1"):
        read_geometry(signs)


def test_a_setup_given_twice_through_a_link_is_refused(tmp_path):
    """setup_1 and a symbolic link to it would merge as two setups that
    always agree."""
    (tmp_path / "again").symlink_to(DATA / "roving_plate" / "setup_1")
    setups = [read_setup(DATA / "roving_plate" / "setup_1"), read_setup(DATA / "roving_plate" / "setup_2"),
              read_setup(tmp_path / "again")]
    with pytest.raises(ValueError, match=r"setups setup_1 and again are one record \(.*setup_1/record.npz\): give "
                                         r"each setup once"):
        modal.check_setups(setups)
    assert modal.check_setups(setups[:2])
