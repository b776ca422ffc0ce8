"""Roving tests that cannot mislead (issue 33): no results over an input,
every setup identified with all its channels, a setup whose reference part,
reference levels or frequencies disagree with the others' named and left
out, matching that follows the modes' own scatter, the majority rule, a
robust normalisation and the complex rescaling checked on synthetic
identifications (no identification is run where none is needed)."""

import re
import shutil
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

import modal
from modal.cli import main as cli
from modal.records import MeasuredRecord
from modal.setups import Setup, identify_setup, merge_setups, normalise, required_setups
from modal.structures import ambient_response

DATA = Path(__file__).resolve().parents[2] / "data"
PLATE_SETUPS = DATA / "roving_plate"


# --- the output folder -----------------------------------------------------------------------------------


@pytest.fixture()
def two_setups(tmp_path):
    for name in ("setup_1", "setup_2", "geometry"):
        shutil.copytree(PLATE_SETUPS / name, tmp_path / name)
    return tmp_path


@pytest.mark.parametrize("out, says", [("setup_1", "is the input"), (".", "holds the input"),
                                       ("setup_2/results", "lies inside the input"),
                                       ("setup_1/channels.csv", "lies inside the input"),
                                       ("geometry/out", "lies inside the input")])
def test_out_over_an_input_of_the_setups_is_refused_before_any_work(two_setups, capsys, out, says):
    """A setup folder, the folder holding the setups, a folder inside a setup,
    a channel table or the geometry's folder as --out: exit 2 naming the
    input, and no file changed (a setup's channels.csv was once replaced by
    the merged table)."""
    before = {p: p.read_bytes() for p in two_setups.rglob("*") if p.is_file()}
    code = cli(["identify", str(two_setups / "setup_1"), str(two_setups / "setup_2"), "--geometry",
                str(two_setups / "geometry"), "--ambient", "--fmax", "25", "--out", str(two_setups / out),
                "--quiet", "--no-animation"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert says in " ".join(err.split())
    assert {p: p.read_bytes() for p in two_setups.rglob("*") if p.is_file()} == before


# --- synthetic identifications: the merge on its own --------------------------------------------------------

FREQS = np.array([3.0, 7.0, 11.0])
NODES = ["r1", "r2", *[f"n{k}" for k in range(10)]]
POLE_COLUMNS = ["freq_hz", "damping", "stable", "physical"]


def _truth(complex_modes=False, seed=1):
    """Mode shapes at the 12 nodes (z), complex with ``complex_modes``."""
    rng = np.random.default_rng(seed)
    shapes = rng.uniform(0.3, 1.0, (len(NODES), len(FREQS))) * rng.choice([-1, 1], (len(NODES), len(FREQS)))
    shapes[:2] = [[1.0, 0.8, -0.5], [0.4, -1.0, 0.9]]  # reference parts far from each other's swap
    if complex_modes:
        shapes = shapes * np.exp(1j * rng.uniform(-0.6, 0.6, shapes.shape))
    return shapes.astype(complex)


def _setups(n, truth, per_setup=2, seed=2, freq_std=0.004, shifts=None):
    """``n`` setups: references r1, r2, then ``per_setup`` roving nodes
    each; every mode's shape a different complex multiple of the truth,
    frequencies off by ``shifts`` (relative, per setup), levels alike."""
    rng = np.random.default_rng(seed)
    setups, results = [], []
    for s in range(n):
        nodes = ["r1", "r2", *NODES[2 + (s * per_setup) % 10: 2 + (s * per_setup) % 10 + per_setup]]
        rows = [NODES.index(node) for node in nodes]
        scale = rng.uniform(0.5, 2, len(FREQS)) * np.exp(1j * rng.uniform(-np.pi, np.pi, len(FREQS)))
        phi = truth[rows] * scale
        phi /= np.linalg.norm(phi, axis=0)
        shift = 0.0 if shifts is None else shifts[s]
        freq = FREQS * (1 + shift + 1e-4 * rng.standard_normal(len(FREQS)))
        modes = pd.DataFrame({"mode": range(1, len(FREQS) + 1), "freq_hz": freq, "freq_std_hz": freq_std * freq,
                              "damping": 0.01})
        table = pd.DataFrame({"channel": range(len(nodes)), "name": nodes, "node": nodes, "x": 0.0, "y": 0.0,
                              "z": 1.0, "quantity": "acceleration", "unit": "m/s2",
                              "role": ["reference"] * 2 + ["roving"] * (len(nodes) - 2)})
        acc = rng.standard_normal((400, len(nodes))) * (1 + 0.2 * s)
        setups.append(Setup(f"s{s + 1}", MeasuredRecord(acc, 0.01), table))
        results.append(SimpleNamespace(modes=modes, complex_shapes=phi,
                                       poles=pd.DataFrame(columns=POLE_COLUMNS), pole_shapes=np.empty((0, len(nodes)))))
    return setups, results


def _merged_shape(merged, mode):
    rows = merged.shapes[merged.shapes["mode"] == mode].set_index("node")
    return rows, (rows["z"] + 1j * rows["z_im"])


def _assert_merged_shapes_are_the_truth(merged, truth, n_modes=3):
    """Each merged mode's shape is its true shape times one complex number
    at every node (phases included); returns the merged shapes."""
    shapes = []
    for k in range(n_modes):
        rows, shape = _merged_shape(merged, k + 1)
        ratio = shape.to_numpy() / truth[[NODES.index(node) for node in rows.index], k]
        np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)
        shapes.append(shape)
    return shapes


def test_complex_modes_rescaled_with_a_complex_scale_per_setup_keep_their_phases():
    """Complex modes, each setup's shapes a different complex multiple of the
    truth: the merged shape is the truth times one complex number at every
    node, phases included (a rescaling factor conjugated on the wrong side
    turns each setup's roving part by a wrong angle)."""
    truth = _truth(complex_modes=True)
    setups, results = _setups(5, truth)
    merged = merge_setups(setups, results)
    assert len(merged.modes) == 3 and (merged.modes["n_setups"] == 5).all()
    for shape in _assert_merged_shapes_are_the_truth(merged, truth):
        assert np.nanmax(np.abs(shape)) == pytest.approx(1.0)
    assert (merged.matches["ref_mac"] > 0.999999).all() and (merged.matches["status"] == "merged").all()


def test_the_majority_rule_rounds_up_and_needs_both_of_two():
    assert [required_setups(n) for n in (1, 2, 3, 4, 5)] == [1, 2, 2, 3, 3]
    assert required_setups(5, 1) == 1
    truth = _truth()
    for n, kept, dropped in [(2, 2, 1), (3, 2, 1), (5, 3, 2)]:
        for present, expected in [(kept, 1), (dropped, 0)]:
            setups, results = _setups(n, truth)
            for r in results[present:]:  # the 7 Hz mode only in the first `present` setups
                r.modes = r.modes.drop(index=1).reset_index(drop=True)
                r.complex_shapes = r.complex_shapes[:, [0, 2]]
            merged = merge_setups(setups, results)
            assert int((merged.modes["freq_hz"].round() == 7).sum()) == expected, (n, present)
    setups, results = _setups(2, truth)
    results[1].modes = results[1].modes.drop(index=1).reset_index(drop=True)
    results[1].complex_shapes = results[1].complex_shapes[:, [0, 2]]
    assert 7 in merge_setups(setups, results, min_setups=1).modes["freq_hz"].round().tolist()


def test_a_mode_joins_the_nearest_cluster_within_its_own_scatter():
    """Setup 1 has two modes 1.4 % apart (6.9, 7.0 Hz, same reference
    part); setup 2's 7.03 Hz is admissible for both (uncertainty 1 %) and
    joins the nearer, 7.0. Two setups 1.2 % apart with 0.5 % uncertainty are
    one mode (a fixed 1 % lost it), 2.5 % apart with 0.05 % they are not."""
    truth = _truth()
    setups, results = _setups(2, truth, freq_std=0.01)
    extra = results[0]
    extra.modes = pd.concat([extra.modes, extra.modes.iloc[[1]].assign(mode=4, freq_hz=6.9)], ignore_index=True)
    extra.complex_shapes = extra.complex_shapes[:, [0, 1, 2, 1]]
    results[1].modes.loc[1, "freq_hz"] = 7.03
    merged = merge_setups(setups, results, min_setups=1)
    joined = merged.matches[(merged.matches["setup"] == "s2") & (merged.matches["freq_hz"] == 7.03)]["mode"]
    partner = merged.matches[(merged.matches["mode"] == joined.iloc[0]) & (merged.matches["setup"] == "s1")]
    assert list(partner["setup_mode"]) == [2]  # 7.0 Hz, not 6.9 Hz
    for shift, std, expected in [(0.012, 0.005, 3), (0.025, 0.0005, 0)]:
        setups, results = _setups(2, truth, freq_std=std, shifts=[0.0, shift])
        assert len(merge_setups(setups, results).modes) == expected


def _spoil(setups, results, s, how):
    setup, result = setups[s], results[s]
    acc = setup.record.acc.copy()
    if how == "unit slip":
        acc[:, :2] *= 1e-6
        result.complex_shapes = result.complex_shapes.copy()
        result.complex_shapes[:2] *= 1e-6
    elif how == "swapped references":
        acc[:, [0, 1]] = acc[:, [1, 0]]
        result.complex_shapes = result.complex_shapes[[1, 0, *range(2, len(acc[0]))]]
    elif how == "wrong rate":
        result.modes = result.modes.assign(freq_hz=result.modes["freq_hz"] * 0.5)
    elif how == "one reference in g":
        acc[:, 1] *= 9.80665
        result.complex_shapes = result.complex_shapes.copy()
        result.complex_shapes[1] *= 9.80665
    setups[s] = Setup(setup.name, MeasuredRecord(acc, setup.record.dt), setup.channels)


EVIDENCE = {
    "unit slip": r"its reference channels record [0-9.]+e-0[67] x the level of (2 of 2|4 of 4) other setup\(s\) \(s1, s3",
    "swapped references": r"the reference part of its modes disagrees with that of (2 of 2|4 of 4) other setup\(s\) "
                          r"\(s1, s3.*\) \(median MAC 0\.[0-8]\d over the modes paired by frequency\): swapped",
    "wrong rate": r"its frequencies are 0\.5(000|001)? x those of (2 of 2|4 of 4) other setup\(s\)",
    "one reference in g": r"the levels of its reference channels relative to node r1 \(0, 0, 1\) \(node r2 \(0, 0, 1\): "
                          r"(9\.\d+|10\.\d) \(others (0\.[89]\d*|1\.\d+)\)\) differ from those of (2 of 2|4 of 4) .* by "
                          r"up to (9\.\d+|1\d\.\d) x",  # 9.8 x
}


@pytest.mark.parametrize("how, check", [("unit slip", "reference levels"), ("swapped references", "reference shapes"),
                                        ("wrong rate", "rate"), ("one reference in g", "reference ratio")])
def test_a_bad_setup_is_named_and_left_out(how, check):
    """Three setups and five, one spoilt: it alone is named, with the
    check it fails, left out of every mode (in matches.csv with the
    reason), and the merged shapes are those of the good setups; with two
    setups nothing is merged and both are named (which one is wrong cannot
    be told)."""
    truth = _truth()
    for n in (3, 5):
        setups, results = _setups(n, truth)
        _spoil(setups, results, 1, how)
        merged = merge_setups(setups, results)
        assert set(merged.disagreements["setup"]) == {"s2"}, merged.disagreements
        assert check in set(merged.disagreements["check"])
        evidence = merged.disagreements.set_index("check").loc[check, "evidence"]
        assert re.search(EVIDENCE[how], evidence), evidence
        assert "cannot be told" not in evidence
        assert len(merged.modes) == 3 and (merged.modes["n_setups"] == n - 1).all()
        assert (merged.modes["left_out"] == "s2").all()
        out = merged.matches[merged.matches["setup"] == "s2"]
        assert (out["status"] == "left out").all() and len(out) == 3 and out["reason"].str.len().min() > 20
        for k in range(3):
            rows, shape = _merged_shape(merged, k + 1)
            exact = truth[[NODES.index(node) for node in rows.index], k]
            assert modal.mac(shape.to_numpy()[:, None], exact[:, None])[0, 0] > 0.9999
    setups, results = _setups(2, truth)
    _spoil(setups, results, 1, how)
    merged = merge_setups(setups, results)
    assert len(merged.modes) == 0 and set(merged.disagreements["setup"]) == {"s1", "s2"}
    assert merged.disagreements["evidence"].str.contains("; with two setups, which one is wrong cannot be told").all()


def test_one_mode_of_a_setup_that_disagrees_is_left_out_of_that_mode_only():
    truth = _truth()
    setups, results = _setups(4, truth)
    results[2].complex_shapes = results[2].complex_shapes.copy()
    results[2].complex_shapes[:2, 1] = results[2].complex_shapes[[1, 0], 1]  # its 7 Hz reference part swapped
    results[2].modes["mode"] = [11, 12, 13]  # numbers as in its modes.csv, whatever they are
    merged = merge_setups(setups, results)
    assert merged.disagreements.empty and list(merged.modes["n_setups"]) == [4, 3, 4]
    row = merged.matches[(merged.matches["setup"] == "s3") & (merged.matches["mode"] == 2)]
    assert list(row["status"]) == ["left out"] and "residual" in row["reason"].iloc[0]
    assert list(row["setup_mode"]) == [12] and row["ref_mac"].iloc[0] < 0.96
    merged_rows = merged.matches[(merged.matches["setup"] == "s3") & (merged.matches["status"] == "merged")]
    assert list(merged_rows["setup_mode"]) == [11, 13]


def test_normalisation_is_not_set_by_a_node_that_disagrees_with_its_neighbours():
    per_node = {"a": np.array([np.nan, np.nan, 1.0 + 0j]), "b": np.array([np.nan, np.nan, 0.9 + 0j]),
                "c": np.array([np.nan, np.nan, -2.0 + 0j]), "d": np.array([np.nan, np.nan, 0.5j])}
    neighbours = {"a": {"b", "c"}, "b": {"a", "c"}, "c": {"a", "b", "d"}, "d": {"c"}}
    pivot, flags = normalise(per_node, neighbours)
    assert pivot == 1.0 and list(flags) == ["c"] and "2 x" in flags["c"]
    pivot, flags = normalise(per_node)  # without a geometry: compared with every other node
    assert pivot == 1.0 and list(flags) == ["c"]
    per_node["c"] = np.array([np.nan, np.nan, -1.4 + 0j])  # within 1.8 x: it sets the scale
    pivot, flags = normalise(per_node, neighbours)
    assert pivot == -1.4 and flags == {}


def test_without_a_geometry_a_node_is_judged_against_three_others_at_least():
    """A single setup's two nodes, one moving 60 x the other (near a modal
    node, as the Weimar frame's node 7 in its torsion mode): no evidence of
    a bad channel, so the larger sets the scale; so with two others. With
    three others (the least, NODE_PEERS) the node far above them is flagged."""
    per_node = {"24": np.array([-4.7 + 0.2j, -82.6 + 0.2j, np.nan]), "7": np.array([0.95 + 0j, 1.0 + 0j, 0.03j])}
    pivot, flags = normalise(per_node)
    assert pivot == -82.6 + 0.2j and flags == {}
    per_node["9"] = np.array([0.5 + 0j, 0.2 + 0j, np.nan])
    assert normalise(per_node) == (-82.6 + 0.2j, {})
    per_node["11"] = np.array([np.nan, np.nan, np.nan])  # no motion: not a peer
    assert normalise(per_node) == (-82.6 + 0.2j, {})
    per_node["11"] = np.array([0.1 + 0j, np.nan, np.nan])
    pivot, flags = normalise(per_node)
    assert pivot == 1.0 and list(flags) == ["24"] and "moves 60 x" in flags["24"]


def test_normalisation_flags_down_to_the_first_node_that_agrees_and_no_further():
    """Two nodes far above their neighbours, one below the other, are both
    flagged; the first that agrees ends the search, so a smaller local peak
    further down is not judged; a ratio of exactly 1.8 is not "more than"."""
    z = np.array([np.nan, np.nan, 1.0 + 0j])
    per_node = {"c": 10 * z, "d": 5 * z, "a": 1.0 * z, "b": 0.9 * z, "e": 0.5 * z}
    neighbours = {"c": {"a", "b"}, "d": {"e"}, "a": {"c", "b"}, "b": {"a", "c"}, "e": {"d"}}
    pivot, flags = normalise(per_node, neighbours)
    assert list(flags) == ["c", "d"] and pivot == 1.0
    per_node = {"a": 10 * z, "b": 9 * z, "d": 3 * z, "e": 1 * z}  # d: 3 x its neighbour, below a that agrees
    neighbours = {"a": {"b"}, "b": {"a", "d"}, "d": {"e"}, "e": {"d"}}
    assert normalise(per_node, neighbours) == (10.0, {})
    per_node = {"a": 2.25 * z, "b": 1.25 * z}  # 2.25 = 1.8 x 1.25 exactly
    assert normalise(per_node, {"a": {"b"}, "b": {"a"}}) == (2.25, {})


def test_a_shape_without_a_finite_or_nonzero_component_is_left_as_it_is():
    """The factor is 1 when no node has a finite component or every component
    is zero (a shape that cannot be scaled is not divided by 0)."""
    nan = np.full(3, np.nan + 0j)
    assert normalise({"a": nan, "b": nan}) == (1.0, {})
    assert normalise({"a": np.zeros(3, complex), "b": nan}) == (1.0, {})


def test_declared_velocity_and_displacement_channels_reach_the_identification():
    """One node measured in acceleration, velocity (mm/s) and displacement:
    a setup is identified with each channel's quantity, so the three give
    one shape value at the 5 Hz mode (without them the velocity would read
    1/omega = 0.03 and the displacement 1/omega^2 = 0.001 of it)."""
    fs, n = 50.0, 3000
    shapes = np.array([[1.0, 0.6], [0.5, -1.0]])
    acc = ambient_response(2 * np.pi * np.array([5.0, 12.0]), 0.02, shapes, shapes, n, 1 / fs, seed=3)
    spectrum = np.fft.rfft(acc[:, 0])
    spectrum[0] = 0
    omega = 2 * np.pi * np.fft.rfftfreq(n, 1 / fs)
    omega[0] = 1.0
    velocity = np.fft.irfft(spectrum / (1j * omega), n)
    displacement = np.fft.irfft(spectrum / (1j * omega) ** 2, n)
    table = pd.DataFrame({"channel": range(4), "name": ["a", "v", "d", "b"], "node": ["1", "1", "1", "2"], "x": 0.0,
                          "y": 0.0, "z": 1.0, "quantity": ["acceleration", "velocity", "displacement", "acceleration"],
                          "unit": ["m/s2", "mm/s", "m", "m/s2"], "role": "roving"})
    record = MeasuredRecord(np.column_stack([acc[:, 0], 1000 * velocity, displacement, acc[:, 1]]), 1 / fs)
    result, _ = identify_setup(Setup("s", record, table), "ambient", fmax=20, max_order=20)
    k = int(np.argmin(np.abs(result.modes["freq_hz"] - 5.0)))
    phi = result.complex_shapes[:, k]
    assert abs(phi[1] / phi[0]) == pytest.approx(1.0, rel=0.1)
    assert 0.5 < abs(phi[2] / phi[0]) < 2.0


def test_a_setup_with_a_unit_slip_is_named_by_the_command(tmp_path, capsys):
    """Three setups of the plate, setup 3's references declared in mm/s2
    (recorded in m/s2): modal identify names it in the log and matches.csv
    and merges the modes of the other two; with setups 1 and 3 alone it
    exits 5 naming both (which one is wrong cannot be told)."""
    for name in ("setup_1", "setup_2", "setup_3"):
        shutil.copytree(PLATE_SETUPS / name, tmp_path / name)
    table = pd.read_csv(tmp_path / "setup_3" / "channels.csv")
    table.loc[table["role"] == "reference", "unit"] = "mm/s2"
    table.to_csv(tmp_path / "setup_3" / "channels.csv", index=False)
    out = tmp_path / "out"
    code = cli(["identify", *(str(tmp_path / f"setup_{k}") for k in (1, 2, 3)), "--ambient", "--fmax", "25",
                "--out", str(out)])
    err = " ".join(capsys.readouterr().err.split())
    assert code == 0, err
    assert "setup setup_3 left out of the merge (reference levels)" in err
    modes, matches = pd.read_csv(out / "modes.csv"), pd.read_csv(out / "matches.csv")
    assert len(modes) >= 5 and (modes["n_setups"] == 2).all() and (modes["left_out"] == "setup_3").all()
    assert set(matches.loc[matches["status"] == "left out", "setup"]) == {"setup_3"}
    code = cli(["identify", str(tmp_path / "setup_1"), str(tmp_path / "setup_3"), "--ambient", "--fmax", "25",
                "--out", str(tmp_path / "two"), "--quiet"])
    err = " ".join(capsys.readouterr().err.split())
    assert code == 5 and "setup setup_1 left out" in err and "setup setup_3 left out" in err
    assert "which one is wrong cannot be told" in err


def test_what_matches_csv_says_of_a_setup_left_out():
    """A setup left out of the merge is listed in every mode with its
    nearest mode (number, frequency, damping, reference MAC) when it has
    one within the tolerance, else with none (a wrong rate)."""
    truth = _truth()
    setups, results = _setups(3, truth)
    _spoil(setups, results, 1, "unit slip")
    results[1].modes["mode"] = [4, 5, 6]
    results[1].modes["damping"] = [0.02, 0.03, 0.04]
    rows = merge_setups(setups, results).matches.query("setup == 's2'")
    assert list(rows["setup_mode"]) == [4, 5, 6] and list(rows["source"]) == ["selected"] * 3
    np.testing.assert_allclose(rows["freq_hz"], results[1].modes["freq_hz"])
    np.testing.assert_allclose(rows["damping"], [0.02, 0.03, 0.04])
    assert (rows["ref_mac"] > 0.9999).all() and rows["ref_share"].isna().all() and rows["scale"].isna().all()
    assert (rows["reason"].str.startswith("its reference channels record")).all()
    setups, results = _setups(3, truth)
    _spoil(setups, results, 1, "wrong rate")
    rows = merge_setups(setups, results).matches.query("setup == 's2'")
    assert list(rows["setup_mode"]) == [0, 0, 0] and rows["freq_hz"].isna().all() and rows["ref_mac"].isna().all()
    assert list(rows["source"]) == [""] * 3 or rows["source"].isna().all()


def test_a_mode_whose_reference_part_is_another_is_left_out_with_its_number():
    """Setup 3's 7 Hz mode has a reference part orthogonal to the others'
    (MAC below mac_min): it cannot join, and is named as left out of that
    mode with its own number and MAC."""
    truth = _truth()
    setups, results = _setups(4, truth)
    results[2].complex_shapes = results[2].complex_shapes.copy()
    r = results[2].complex_shapes[:2, 1]
    results[2].complex_shapes[:2, 1] = [-np.conj(r[1]), np.conj(r[0])]  # orthogonal to r
    results[2].modes["mode"] = [7, 8, 9]
    merged = merge_setups(setups, results)
    assert list(merged.modes["n_setups"]) == [4, 3, 4] and list(merged.modes["left_out"]) == ["", "s3", ""]
    row = merged.matches.query("setup == 's3' and mode == 2")
    assert list(row["status"]) == ["left out"] and list(row["setup_mode"]) == [8]
    assert row["ref_mac"].iloc[0] < 0.05 and "its mode 8 (7 Hz) has a reference part of MAC 0.00 < 0.8" in \
        row["reason"].iloc[0]


def test_a_mode_a_setup_did_not_select_comes_from_its_stable_poles():
    """Setup 2 did not select the 7 Hz mode; its diagram holds stable
    physical poles there: the one with the matching reference part (not the
    one with another, nor one far in frequency, nor an unstable one) gives
    its roving nodes a shape (source diagram, setup_mode 0)."""
    truth = _truth()
    setups, results = _setups(3, truth)
    second = results[1]
    shape = second.complex_shapes[:, 1]
    other = shape.copy()
    other[:2] = [-np.conj(shape[1]), np.conj(shape[0])]
    second.poles = pd.DataFrame({"freq_hz": [7.0, 7.01, 7.9, 7.0], "damping": [0.012, 0.05, 0.01, 0.01],
                                 "stable": [True, True, True, False], "physical": [True, True, True, True]})
    second.pole_shapes = np.stack([shape, other, shape, other])
    second.modes = second.modes.drop(index=1).reset_index(drop=True)
    second.complex_shapes = second.complex_shapes[:, [0, 2]]
    merged = merge_setups(setups, results)
    assert list(merged.modes["n_setups"]) == [3, 2, 3] and list(merged.modes["n_from_diagram"]) == [0, 1, 0]
    row = merged.matches.query("setup == 's2' and mode == 2")
    assert list(row["source"]) == ["diagram"] and list(row["setup_mode"]) == [0] and list(row["damping"]) == [0.012]
    assert merged.modes["freq_hz"].iloc[1] == pytest.approx(np.mean([results[0].modes["freq_hz"].iloc[1],
                                                                    results[2].modes["freq_hz"].iloc[1]]))
    rows, merged_shape = _merged_shape(merged, 2)
    exact = truth[[NODES.index(node) for node in rows.index], 1]
    assert set(rows.index) >= {"n2", "n3"}  # setup 2's roving nodes
    assert modal.mac(merged_shape.to_numpy()[:, None], exact[:, None])[0, 0] > 0.9999


def test_one_setup_without_references_gives_its_own_modes():
    truth = _truth()
    setups, results = _setups(1, truth)
    table = setups[0].channels.assign(role="roving")
    setups = [Setup("alone", setups[0].record, table)]
    merged = merge_setups(setups, results)
    assert len(merged.modes) == 3 and (merged.modes["n_setups"] == 1).all()
    assert merged.matches["ref_mac"].isna().all() and merged.modes["ref_mac"].isna().all()
    assert merged.disagreements.empty and list(merged.matches["setup_mode"]) == [1, 2, 3]
    _assert_merged_shapes_are_the_truth(merged, truth)


def test_a_node_far_above_its_neighbours_on_the_geometry_is_flagged_in_shapes():
    """Node n0 moves 3 x as much as the truth says (a miscalibrated sensor)
    in every mode: on a geometry whose lines and links join it to n1 and
    r1, it is flagged in each mode and the others are normalised without
    it (their largest component 1)."""
    from modal.setups import Geometry

    truth = _truth()
    truth[NODES.index("n0")] *= 3 * np.abs(truth).max() / np.abs(truth[NODES.index("n0")])
    setups, results = _setups(5, truth)
    nodes = pd.DataFrame({"x": np.arange(len(NODES), dtype=float), "y": 0.0, "z": 0.0},
                         index=pd.Index(NODES, name="node"))
    links = pd.DataFrame({"parent": ["r1"], "child": ["n0"], "px": [0.0], "py": [0.0], "pz": [1.0], "cx": [0.0],
                          "cy": [0.0], "cz": [1.0]})
    geometry = Geometry(nodes, [("n0", "n1")], links)
    merged = merge_setups(setups, results, geometry=geometry)
    flagged = merged.shapes[merged.shapes["flag"] != ""]
    assert list(flagged["node"]) == ["n0"] * 3 and (merged.modes["n_flagged"] == 1).all()
    assert flagged["flag"].str.contains("node linked to it").all()
    others = merged.shapes[merged.shapes["flag"] == ""]
    assert others.groupby("mode")["z"].apply(lambda z: np.abs(z).max()).to_numpy() == pytest.approx(1.0)
    assert (np.abs(flagged["z"]) > 1.8).all()
    unlinked = merge_setups(setups, results, geometry=Geometry(nodes, [("n0", "n1")]))
    assert unlinked.modes["n_flagged"].sum() == 3  # n1 alone, far smaller, still tells
    alone = merge_setups(setups, results, geometry=Geometry(nodes))
    assert alone.modes["n_flagged"].sum() == 0  # no node linked to it: nothing to compare with


def test_frequency_uncertainty_and_tolerance():
    from modal.setups._agreement import RTOL_MAX, RTOL_MIN, RTOL_UNKNOWN, relative_uncertainty, tolerance

    modes = pd.DataFrame({"freq_hz": [2.0, 4.0, 5.0], "freq_std_hz": [0.02, np.nan, 0.0]})
    np.testing.assert_allclose(relative_uncertainty(modes), [0.01, RTOL_UNKNOWN, RTOL_UNKNOWN])
    np.testing.assert_allclose(relative_uncertainty(modes[["freq_hz"]]), [RTOL_UNKNOWN] * 3)
    assert tolerance(0.003, 0.004) == pytest.approx(0.015)
    assert tolerance(1e-5, 0.0) == RTOL_MIN and tolerance(0.5, 0.5) == RTOL_MAX


def test_a_constant_frequency_ratio_is_found():
    from modal.setups._agreement import rate_ratio

    ratio, lined, at_one = rate_ratio([2.5, 4.8, 7.7, 9.9], [5.0, 9.6, 15.4, 19.8, 30.0])
    assert ratio == pytest.approx(0.5, rel=1e-3) and lined == 4 and at_one == 0
    assert rate_ratio([5.0, 9.6, 15.4], [5.01, 9.6, 15.42])[1:] == (3, 3)
    assert rate_ratio([], [1.0]) == (1.0, 0, 0) and rate_ratio([1.0], []) == (1.0, 0, 0)
    assert rate_ratio([1.0, 2.0], [10.0, 20.0])[1] == 0  # beyond 5 x: not a rate


@pytest.mark.parametrize("estimates, stds, expected", [
    ([2.0], [0.01], 0.01),  # one setup: its own
    ([2.0], [np.nan], np.nan),  # one setup without its own: unknown
    ([1.0, 1.0, 1.0], [0.3, 0.4, 1.2], 1.3 / 3),  # they agree: the internal sqrt(sum sigma^2) / n
    ([1.0, 1.2], [0.01, 0.01], 0.1),  # they disagree beyond their noise: std(ddof=1) / sqrt(n)
    ([1.0, 1.2], [0.01, np.nan], 0.1),  # one setup's own unknown: the spread alone
    ([1.0, 1.02, 0.98], [0.1, 0.1, 0.1], np.sqrt(0.03) / 3),  # noise above the spread: internal
])
def test_std_of_the_mean_over_setups(estimates, stds, expected):
    """The standard deviation of the mean of the setups' estimates: the
    larger of the internal (from each setup's own) and the external (from
    their spread, ddof 1) one; a slip (ddof 0, n for sqrt(n), the smaller of
    the two) changes every case with two setups or more."""
    from modal.setups._merge import std_of_mean

    got = std_of_mean(estimates, stds)
    assert (np.isnan(got) and np.isnan(expected)) or got == pytest.approx(expected, rel=1e-12)


def test_the_merged_tables_hold_the_setups_statistics_and_directions():
    """modes.csv: mean and spread (ddof 1) of the selected frequencies and
    dampings, the smallest reference MAC, MPC 1 for real modes, the nodes;
    matches.csv: each setup's reference share and rescaling modulus;
    shapes.csv: a roving channel along x or y gives that component only."""
    truth = _truth()
    setups, results = _setups(3, truth)
    for s, (setup, result) in enumerate(zip(setups, results)):
        result.modes["damping"] = [0.01 + 0.001 * s, 0.02, 0.03 - 0.002 * s]
        table = setup.channels.copy()
        table.loc[2, ["x", "y", "z"]] = [1.0, 0.0, 0.0]
        table.loc[3, ["x", "y", "z"]] = [0.0, -1.0, 0.0]
        setups[s] = Setup(setup.name, setup.record, table)
    merged = merge_setups(setups, results)
    freqs = np.array([r.modes["freq_hz"].to_numpy() for r in results])
    np.testing.assert_allclose(merged.modes["freq_hz"], freqs.mean(axis=0))
    np.testing.assert_allclose(merged.modes["freq_spread_hz"], freqs.std(axis=0, ddof=1))
    np.testing.assert_allclose(merged.modes["damping"], [0.011, 0.02, 0.028])
    np.testing.assert_allclose(merged.modes["damping_spread"], [0.001, 0.0, 0.002], atol=1e-12)
    # the mean's std: the setups' own (0.4 % each) over n, far above their 1e-4 scatter; no damping std of their
    # own, so the dampings' spread over sqrt(n)
    np.testing.assert_allclose(merged.modes["freq_std_hz"], np.sqrt(np.sum((0.004 * freqs) ** 2, axis=0)) / 3)
    np.testing.assert_allclose(merged.modes["damping_std"], np.array([0.001, 0.0, 0.002]) / np.sqrt(3), atol=1e-12)
    np.testing.assert_allclose(merged.modes["mpc"], 1.0)
    assert (merged.modes["ref_mac"] > 0.999999).all() and (merged.modes["n_nodes"] == 2 + 2 * 3).all()
    assert list(merged.modes["setups"]) == ["s1 s2 s3"] * 3 and (merged.modes["n_flagged"] == 0).all()
    for row in merged.matches.itertuples():
        result = results[int(row.setup[1:]) - 1]
        phi = result.complex_shapes[:, row.mode - 1]
        assert row.ref_share == pytest.approx(np.linalg.norm(phi[:2]) / np.linalg.norm(phi))
        assert row.scale == pytest.approx(1 / np.linalg.norm(phi[:2]), rel=1e-6)  # onto a unit consensus
    for k in range(3):
        rows, _ = _merged_shape(merged, k + 1)
        values = []
        for node in rows.index:
            exact = truth[NODES.index(node), k]
            setup = next(s for s in setups if node in set(s.channels["node"]))
            direction = setup.channels.set_index("node").loc[node, ["x", "y", "z"]].to_numpy(dtype=float)
            axis = int(np.argmax(np.abs(direction)))
            measured = rows.loc[node, "xyz"[axis]] + 1j * rows.loc[node, "xyz"[axis] + "_im"]
            assert rows.loc[node, [c for c in "xyz" if c != "xyz"[axis]]].isna().all()
            values.append((measured, exact / direction[axis]))  # a channel reads e . u
        ratio = np.array([m / e for m, e in values])
        np.testing.assert_allclose(ratio, ratio[0], rtol=1e-9)
