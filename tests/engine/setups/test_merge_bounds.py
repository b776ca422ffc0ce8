"""The merge's bounds and edge cases, each just inside and just outside:
the documented tolerances and limits of the checks that setups agree
(levels 30 x, reference ratio 3 x, reference residual 0.2), references
recorded in another unit and declared so, a setup that found no mode, a
channel table with an index of its own. Synthetic identifications, as in
``test_merge_checks`` (no identification is run)."""

import numpy as np
import pandas as pd
import pytest

from modal.records import MeasuredRecord
from modal.setups import Setup, merge_setups
from modal.setups._agreement import rate_ratio, relative_uncertainty, tolerance

from .test_merge_checks import NODES, _assert_merged_shapes_are_the_truth, _merged_shape, _setups, _truth


def _levelled(setups, factors=None):
    """``setups`` with every channel of unit standard deviation, the
    reference channels of setup ``s`` then multiplied by ``factors[s]``
    (one per reference channel)."""
    out = []
    for s, setup in enumerate(setups):
        acc = setup.record.acc / setup.record.acc.std(axis=0)
        if factors is not None and s in factors:
            acc[:, :2] *= factors[s]
        out.append(Setup(setup.name, MeasuredRecord(acc, setup.record.dt), setup.channels))
    return out


def test_documented_tolerances():
    """docs/roving.md: the frequency tolerance is 3 combined standard
    deviations kept within 0.2 % ... 3 %; a mode without an estimate counts
    as 0.5 %, a mode at 0 Hz too (without a warning)."""
    assert tolerance(1e-5, 0.0) == 0.002 and tolerance(0.5, 0.5) == 0.03
    assert tolerance(0.004, 0.003) == pytest.approx(0.015)
    modes = pd.DataFrame({"freq_hz": [2.0, 0.0, 0.0, 4.0], "freq_std_hz": [0.02, 0.0, 0.1, np.nan]})
    np.testing.assert_array_equal(relative_uncertainty(modes), [0.01, 0.005, 0.005, 0.005])
    none = pd.DataFrame({"freq_hz": [2.0, 3.0], "freq_std_hz": [None, None]})  # no estimate at all: object column
    np.testing.assert_array_equal(relative_uncertainty(none), [0.005, 0.005])


def test_rate_ratio_without_any_mode_lined_up_is_one():
    """No pair within 5 x: the ratio is 1, nothing lined up (not e, nor
    any other ratio)."""
    assert rate_ratio([1.0], [100.0]) == (1.0, 0, 0)
    ratio, lined, at_one = rate_ratio([5.0], [1.0])  # 5 x is still a ratio looked at
    assert ratio == pytest.approx(5.0, rel=1e-12) and (lined, at_one) == (1, 0)
    assert rate_ratio([1.0, 2.0], [10.0, 20.0]) == (1.0, 0, 0)


@pytest.mark.parametrize("factor, named", [(29.5, False), (30.5, True)])
def test_reference_levels_up_to_30_times_apart_agree(factor, named):
    """Three setups of equal levels, the references of s2 scaled by
    ``factor``: 29.5 x is a stronger excitation, 30.5 x a unit slip."""
    setups, results = _setups(3, _truth())
    setups = _levelled(setups, {1: [factor, factor]})
    merged = merge_setups(setups, results)
    assert list(merged.disagreements["setup"]) == (["s2"] if named else [])
    if named:
        assert list(merged.disagreements["check"]) == ["reference levels"]
        assert "its reference channels record 30.5 x the level of 2 of 2" in merged.disagreements["evidence"].iloc[0]
    assert list(merged.modes["n_setups"]) == [2 + (not named)] * 3


@pytest.mark.parametrize("factor, named", [(2.9, False), (3.1, True)])
def test_reference_channels_up_to_3_times_apart_in_ratio_agree(factor, named):
    """s2's second reference channel scaled by ``factor`` relative to its
    first: 2.9 x is another direction of excitation, 3.1 x a slip."""
    setups, results = _setups(3, _truth())
    setups = _levelled(setups, {1: [1.0, factor]})
    merged = merge_setups(setups, results)
    assert list(merged.disagreements["setup"]) == (["s2"] if named else [])
    if named:
        assert list(merged.disagreements["check"]) == ["reference ratio"]
        assert f"node r2 (0, 0, 1): {factor:.3g} (others 1)" in merged.disagreements["evidence"].iloc[0]


def test_references_recorded_in_another_unit_and_declared_so_agree():
    """s2 records its references in mm/s2 (1000 x the numbers) and says so
    in its channel table: the same levels as the others, nothing named."""
    setups, results = _setups(3, _truth())
    setups = _levelled(setups, {1: [1000.0, 1000.0]})
    table = setups[1].channels.copy()
    table.loc[table["role"] == "reference", "unit"] = "mm/s2"
    setups[1] = Setup("s2", setups[1].record, table)
    merged = merge_setups(setups, results)
    assert merged.disagreements.empty and list(merged.modes["n_setups"]) == [3, 3, 3]
    setups[1] = Setup("s2", setups[1].record, table.assign(unit="m/s2"))  # the same numbers declared in m/s2
    assert list(merge_setups(setups, results).disagreements["setup"]) == ["s2"]


def _tilted(phi, value):
    """``phi`` with its reference part (rows 0, 1) turned so that its MAC
    with the original is ``value``, its norm kept."""
    r = phi[:2]
    unit = r / np.linalg.norm(r)
    normal = np.array([-np.conj(unit[1]), np.conj(unit[0])])  # orthogonal to unit
    out = phi.copy()
    out[:2] = np.linalg.norm(r) * (np.sqrt(value) * unit + np.sqrt(1 - value) * normal)
    return out


@pytest.mark.parametrize("value, agrees", [(0.97, True), (0.95, False)])
def test_a_reference_residual_up_to_0_2_agrees(value, agrees):
    """s2's reference part of every mode turned to MAC ``value`` with the
    others' (residual sqrt(1 - MAC) 0.17 or 0.22, the limit 0.2): merged,
    or named for its reference shapes and left out."""
    setups, results = _setups(3, _truth())
    results[1].complex_shapes = np.column_stack([_tilted(results[1].complex_shapes[:, k], value) for k in range(3)])
    merged = merge_setups(setups, results)
    if agrees:
        assert merged.disagreements.empty and list(merged.modes["n_setups"]) == [3, 3, 3]
        np.testing.assert_allclose(merged.matches.query("setup == 's2'")["ref_mac"], value, rtol=1e-9)
    else:
        assert list(merged.disagreements["setup"]) == ["s2"]
        assert list(merged.disagreements["check"]) == ["reference shapes"]
        assert "(median MAC 0.95 over the modes paired by frequency)" in merged.disagreements["evidence"].iloc[0]
        assert list(merged.modes["n_setups"]) == [2, 2, 2]


def test_a_setup_that_found_no_mode_is_counted_as_missing():
    """s2 selected no mode: the other two merge every mode (2 of 3), s2 is
    not named as disagreeing (it has nothing to disagree with)."""
    setups, results = _setups(3, _truth())
    results[1].modes = results[1].modes.iloc[:0]
    results[1].complex_shapes = results[1].complex_shapes[:, :0]
    merged = merge_setups(setups, results)
    assert merged.disagreements.empty
    assert list(merged.modes["n_setups"]) == [2, 2, 2] and list(merged.modes["setups"]) == ["s1 s3"] * 3
    assert "s2" not in set(merged.matches["setup"])


def test_a_channel_table_with_an_index_of_its_own_merges_as_renumbered():
    """Channel tables whose rows keep the index of a larger table (rows
    picked from it, in another order): the same merge as the tables
    renumbered 0, 1, ... (rows are positions, never labels)."""
    truth = _truth()
    setups, results = _setups(3, truth)
    expected = merge_setups(setups, results)
    picked = []
    for setup in setups:
        table = setup.channels.copy()
        table.index = [7, 3, 9, 5][:len(table)]
        picked.append(Setup(setup.name, setup.record, table))
    merged = merge_setups(_levelled(picked), results)
    pd.testing.assert_frame_equal(merged.modes, expected.modes)
    pd.testing.assert_frame_equal(merged.shapes, expected.shapes)
    _assert_merged_shapes_are_the_truth(merged, truth)


def test_swapped_references_are_seen_in_modes_paired_within_the_tolerance():
    """s2's frequencies are 1 % above the others' (uncertainty 0.4 %, so
    within the 1.7 % tolerance) and its references swapped: its modes are
    still paired with the others' by frequency, and it is named."""
    from .test_merge_checks import _spoil

    setups, results = _setups(3, _truth(), shifts=[0.0, 0.01, 0.0])
    _spoil(setups, results, 1, "swapped references")
    merged = merge_setups(setups, results)
    assert list(merged.disagreements["setup"]) == ["s2"]
    assert list(merged.disagreements["check"]) == ["reference shapes"]


def _with_modes(result, freqs, seed=0):
    """``result`` holding modes at ``freqs`` (Hz), each with a random shape."""
    rng = np.random.default_rng(seed)
    n = result.complex_shapes.shape[0]
    result.modes = pd.DataFrame({"mode": range(1, len(freqs) + 1), "freq_hz": freqs,
                                 "freq_std_hz": 0.001 * np.asarray(freqs), "damping": 0.01})
    result.complex_shapes = rng.standard_normal((n, len(freqs))) + 1j * rng.standard_normal((n, len(freqs)))


@pytest.mark.parametrize("at_half, rate", [([1.5, 3.5, 5.5, 7.5], False), ([1.5, 3.5, 5.5, 7.5, 9.5], True)])
def test_a_wrong_rate_needs_more_than_twice_as_many_modes_at_its_ratio_as_at_one(at_half, rate):
    """s1 and s3 have modes at 3, 7, 11, 15, 19 Hz; s2 at 11 and 19 Hz
    (at ratio 1) and at half of 4 or 5 of them: 4 is not more than twice
    2, 5 is; a wrong rate is named then only."""
    setups, results = _setups(3, _truth())
    for s, freqs in enumerate([[3.0, 7.0, 11.0, 15.0, 19.0], at_half + [11.0, 19.0], [3.0, 7.0, 11.0, 15.0, 19.0]]):
        _with_modes(results[s], freqs, seed=s % 2)  # s1 and s3 alike
    ratio, lined, at_one = rate_ratio(results[1].modes["freq_hz"], results[0].modes["freq_hz"])
    assert ratio == pytest.approx(0.5, rel=1e-12) and (lined, at_one) == (len(at_half), 2)
    merged = merge_setups(setups, results)
    named = set(zip(merged.disagreements["setup"], merged.disagreements["check"]))
    assert (("s2", "rate") in named) == rate and {s for s, _ in named} <= {"s2"}


def _two_modes(results):
    for r in results:
        r.modes, r.complex_shapes = r.modes.iloc[:2], r.complex_shapes[:, :2]


def test_reference_shapes_of_two_modes_judge_a_setup_by_their_majority():
    """Setups with two modes each: s2's references swapped in both modes is
    a bad setup (two paired modes are enough); its reference part wrong in
    one mode of two is not (not more than half): it is left out of that
    mode only."""
    from .test_merge_checks import _spoil

    setups, results = _setups(3, _truth())
    _two_modes(results)
    _spoil(setups, results, 1, "swapped references")
    merged = merge_setups(setups, results)
    assert set(zip(merged.disagreements["setup"], merged.disagreements["check"])) == {("s2", "reference shapes")}
    setups, results = _setups(3, _truth())
    _two_modes(results)
    results[1].complex_shapes = results[1].complex_shapes.copy()
    results[1].complex_shapes[:2, 0] = results[1].complex_shapes[[1, 0], 0]
    merged = merge_setups(setups, results)
    assert merged.disagreements.empty and list(merged.modes["n_setups"]) == [2, 3]
    assert list(merged.matches.query("status == 'left out'")[["setup", "mode"]].itertuples(index=False)) == [("s2", 1)]


def test_with_two_setups_the_evidence_says_which_one_cannot_be_told():
    from .test_merge_checks import _spoil

    setups, results = _setups(2, _truth())
    _spoil(setups, results, 1, "wrong rate")
    evidence = merge_setups(setups, results).disagreements.set_index("setup")["evidence"]
    assert evidence["s2"] == ("its frequencies are 0.5 x those of 1 of 1 other setup(s) (s1; with two setups, which one "
                              "is wrong cannot be told): a wrong sampling rate (setup_info.txt, --fs, the record's time "
                              "column)?")


def test_the_evidence_of_a_reference_ratio_lists_every_reference():
    """Three reference channels (r1, r2, n9 in every setup), s2's third
    scaled by 4: the evidence lists r2 and n9 relative to r1, each with
    the others' value."""
    truth = _truth()
    setups, results = _setups(3, truth)
    setups = _levelled(setups)
    for s, (setup, result) in enumerate(zip(setups, results)):
        table = setup.channels.copy()
        table.loc[2, ["node", "role"]] = ["n9", "reference"]
        acc = setup.record.acc.copy()
        if s == 1:
            acc[:, 2] *= 4.0
        setups[s] = Setup(setup.name, MeasuredRecord(acc, setup.record.dt), table)
        scale = result.complex_shapes[0] / truth[0]
        result.complex_shapes = result.complex_shapes.copy()
        result.complex_shapes[2] = truth[NODES.index("n9")] * scale
    merged = merge_setups(setups, results)
    assert list(merged.disagreements["setup"]) == ["s2"]
    evidence = merged.disagreements["evidence"].iloc[0]
    assert evidence.startswith("the levels of its reference channels relative to node r1 (0, 0, 1) (node r2 (0, 0, 1): "
                               "1 (others 1), node n9 (0, 0, 1): 4 (others 1)) differ from those of 2 of 2 other "
                               "setup(s) (s1, s3) by up to 4 x"), evidence


def test_modes_exactly_at_the_largest_tolerance_are_paired():
    """s2's modes at 100 and 200 Hz, the others' at 103 and 206 Hz: 3 % of
    s2's apart, the largest tolerance (their uncertainty 5 %), so still
    paired; s2's references swapped are seen."""
    from .test_merge_checks import _spoil

    setups, results = _setups(3, _truth())
    _two_modes(results)
    for s, result in enumerate(results):
        freq = np.array([100.0, 200.0]) * (1.0 if s == 1 else 1.03)
        result.modes = result.modes.assign(freq_hz=freq, freq_std_hz=0.05 * freq)
    _spoil(setups, results, 1, "swapped references")
    merged = merge_setups(setups, results)
    assert set(zip(merged.disagreements["setup"], merged.disagreements["check"])) == {("s2", "reference shapes")}


def test_setups_that_cannot_be_merged_are_refused_naming_them():
    from modal.setups import check_setups, identify_setup

    setups, results = _setups(3, _truth())
    assert check_setups(setups) == [("r1", 0.0, 0.0, 1.0), ("r2", 0.0, 0.0, 1.0)]
    with pytest.raises(ValueError, match=r"^setups: none given$"):
        check_setups([])
    with pytest.raises(ValueError, match=r"^setups: names repeat \(s1, s2, s1\); each setup needs a name of its own$"):
        check_setups([setups[0], setups[1], setups[0]])
    roving = [Setup(s.name, s.record, s.channels.assign(role="roving")) for s in setups]
    assert check_setups(roving[:1]) == []  # one setup needs none
    with pytest.raises(ValueError, match=r"^setup s1: no reference channel: several setups are merged through the "
                                         r"reference channels \(role reference\), present in every setup$"):
        check_setups(roving[:2])
    moved = setups[1].channels.copy()
    moved.loc[1, "node"] = "n9"
    with pytest.raises(ValueError, match=r"^setup s2: its reference channels differ from setup s1's: missing node r2 "
                                         r"along \(0, 0, 1\); extra node n9 along \(0, 0, 1\)$"):
        check_setups([setups[0], Setup("s2", setups[1].record, moved)])
    with pytest.raises(ValueError, match=r"^setup s2: its reference channels differ from setup s1's: missing node r2 "
                                         r"along \(0, 0, 1\)$"):
        check_setups([setups[0], Setup("s2", setups[1].record, setups[1].channels.assign(role=["reference", "roving",
                                                                                                 "roving", "roving"]))])
    with pytest.raises(ValueError, match=r"^setup s2: its reference channels differ from setup s1's: extra node n2 "
                                         r"along \(0, 0, 1\)$"):
        check_setups([setups[0], Setup("s2", setups[1].record, setups[1].channels.assign(role=["reference"] * 3
                                                                                         + ["roving"]))])
    with pytest.raises(ValueError, match=r"^results: 2 for 3 setups$"):
        merge_setups(setups, results[:2])
    with pytest.raises(ValueError, match=r"^channels, quantities: a setup's channel table says which channels are used, "
                                         r"which are references and what they measure$"):
        identify_setup(setups[0], "ambient", channels=[0, 1], quantities=["acceleration"] * 2)


@pytest.mark.parametrize("flags, expected", [
    (["low MPC", "low MPC", "no spectral peak"], "doubtful in every setup that selected it (low MPC)"),
    (["no spectral peak", "", "no spectral peak"], ""),
    (["no spectral peak", np.nan, "low MPC"], ""),
])
def test_a_mode_every_setup_flags_keeps_their_most_common_reason(flags, expected):
    """Mode 2 flagged as doubtful by each setup (its most common reason
    kept) or not by one of them (a blank or a missing flag: trusted)."""
    setups, results = _setups(3, _truth())
    for result, flag in zip(results, flags):
        result.modes["flag"] = ["", flag, ""]
    merged = merge_setups(setups, results)
    assert list(merged.modes["flag"]) == ["", expected, ""]


def test_a_setup_and_a_merge_cannot_be_changed_afterwards():
    """Frozen records: a setup's name or a merge's tables are not
    reassigned by code that holds them (the report and the files would then
    disagree)."""
    import dataclasses

    setups, results = _setups(3, _truth())
    merged = merge_setups(setups, results)
    with pytest.raises(dataclasses.FrozenInstanceError):
        setups[0].name = "s9"
    with pytest.raises(dataclasses.FrozenInstanceError):
        merged.modes = merged.modes.iloc[:1]


def test_a_merged_complex_mode_keeps_the_truths_phase_collinearity():
    """The merged complex shape is the truth times one number, so its MPC
    is the truth's at the same nodes (below 1), and one setup alone has no
    spread (NaN), its own reference MAC none (NaN)."""
    from modal import modal_phase_collinearity

    truth = _truth(complex_modes=True)
    setups, results = _setups(5, truth)
    merged = merge_setups(setups, results)
    for k in range(3):
        rows, _ = _merged_shape(merged, k + 1)
        exact = truth[[NODES.index(n) for n in rows.index], k]
        assert merged.modes["mpc"].iloc[k] == pytest.approx(modal_phase_collinearity(exact[:, None])[0], rel=1e-9)
    assert (merged.modes["mpc"] < 0.95).all() and (merged.modes["flag"] == "").all()  # no flag column: trusted
    alone = merge_setups(setups[:1], results[:1])
    assert list(alone.modes["n_setups"]) == [1, 1, 1]
    assert alone.modes[["freq_spread_hz", "damping_spread", "ref_mac"]].isna().all().all()
    np.testing.assert_array_equal(alone.modes["freq_hz"], results[0].modes["freq_hz"])
    np.testing.assert_array_equal(alone.modes["freq_std_hz"], results[0].modes["freq_std_hz"])  # its own
    assert alone.modes["damping_std"].isna().all()  # none of its own, no spread


@pytest.mark.parametrize("freq_rtol, n_modes", [(None, 3), (0.01, 3), (0.002, 6)])
def test_a_fixed_frequency_tolerance_is_used_when_given(freq_rtol, n_modes):
    """s2 0.5 % above s1 (uncertainty 0.4 %): one mode each within the
    modes' own tolerance or a fixed 1 %, two apart within a fixed 0.2 %
    (then each seen by one setup, kept with min_setups 1)."""
    setups, results = _setups(2, _truth(), shifts=[0.0, 0.005])
    merged = merge_setups(setups, results, freq_rtol=freq_rtol, min_setups=1)
    assert len(merged.modes) == n_modes and set(merged.modes["n_setups"]) == {6 // n_modes}


def test_the_log_names_each_setup_left_out_and_each_node_flagged():
    """log_merge: a setup left out of the merge once (with its check and
    evidence, not again per mode), one left out of one mode with the
    reason, a flagged node per mode."""
    from modal.setups._results import log_merge

    from .test_merge_checks import _spoil

    setups, results = _setups(5, _truth())
    _spoil(setups, results, 4, "wrong rate")
    results[2].complex_shapes = results[2].complex_shapes.copy()
    results[2].complex_shapes[:2, 1] = results[2].complex_shapes[[1, 0], 1]
    lines = []
    log_merge(merge_setups(setups, results), lines.append)
    assert len(lines) == 2, lines
    assert lines[0].startswith("setup s5 left out of the merge (rate): its frequencies are 0.5 x those of 4 of 4")
    assert lines[1].startswith("mode 2: setup s3 left out: its reference part disagrees with the others': residual")
    truth = _truth()
    truth[NODES.index("n0")] *= 3 * np.abs(truth).max() / np.abs(truth[NODES.index("n0")])
    setups, results = _setups(3, truth)
    lines = []
    log_merge(merge_setups(setups, results), lines.append)
    assert [line.split(":")[0] + ":" + line.split(":")[1] for line in lines] == \
        [f"mode {k}: node n0 flagged" for k in (1, 2, 3)]
    assert all(line.endswith("x as much as any other node: not used to normalise") for line in lines)


def test_the_merge_does_not_depend_on_how_a_setup_scaled_its_shapes():
    """A setup's shapes are known up to a complex factor: s2's multiplied
    by 100 e^i give the same merged modes and shapes, also when its
    reference part differs a little from the others' (MAC 0.99), so that
    the consensus must weigh each setup's reference part as a direction,
    not by its size."""
    setups, results = _setups(3, _truth(complex_modes=True))
    results[1].complex_shapes = np.column_stack([_tilted(results[1].complex_shapes[:, k], 0.99) for k in range(3)])
    before = merge_setups(setups, results)
    results[1].complex_shapes = results[1].complex_shapes * 100 * np.exp(1j)
    after = merge_setups(setups, results)
    pd.testing.assert_frame_equal(after.shapes, before.shapes, rtol=1e-9, atol=1e-12)
    pd.testing.assert_frame_equal(after.modes, before.modes, rtol=1e-9)


def _seven_hz(results, freqs):
    for result, f in zip(results, freqs):
        result.modes.loc[1, "freq_hz"] = f


@pytest.mark.parametrize("freqs, n_setups", [
    ([7.0, 7.03, 7.015 * 1.0095], [3]),  # 0.95 % above the mean of the first two: within their scatter (1.06 %)
    ([7.0, 7.03, 7.2], [2, 1]),  # 2.6 % above: beyond it
    ([7.0, 7.1, 7.05], [3]),  # in order of frequency 7.05 joins 7.0 first, then 7.1 joins both
])
def test_a_cluster_s_tolerance_grows_with_its_members_scatter(freqs, n_setups):
    """The 7 Hz mode of three setups (uncertainty 0.2 % or 0.3 %): a mode
    joins a cluster within 3 combined standard deviations of its own
    uncertainty and the cluster's (the members' uncertainty and their
    scatter about their mean); modes are matched in order of frequency."""
    setups, results = _setups(3, _truth(), freq_std=0.003 if freqs[1] == 7.1 else 0.002)
    _seven_hz(results, freqs)
    merged = merge_setups(setups, results, min_setups=1)
    seven = merged.modes[merged.modes["freq_hz"].round() == 7]
    assert list(seven["n_setups"]) == n_setups


def test_a_cluster_of_three_leaves_out_a_member_that_disagrees_with_the_other_two():
    """Three setups, s3's 7 Hz reference part swapped (MAC 0.95 with the
    others': it matches at 0.8 but its residual is 0.22 > 0.2): left out of
    that mode, which the other two still merge."""
    setups, results = _setups(3, _truth())
    results[2].complex_shapes = results[2].complex_shapes.copy()
    results[2].complex_shapes[:2, 1] = results[2].complex_shapes[[1, 0], 1]
    merged = merge_setups(setups, results)
    assert list(merged.modes["n_setups"]) == [3, 2, 3] and list(merged.modes["left_out"]) == ["", "s3", ""]
    row = merged.matches.query("status == 'left out'")
    assert list(row["setup"]) == ["s3"] and row["ref_mac"].iloc[0] == pytest.approx(0.95, abs=0.01)


def test_a_fixed_tolerance_includes_its_bound():
    """freq_rtol 0.03: modes exactly 3 % apart (100 and 103 Hz, 200 and 206
    Hz) are one mode each."""
    setups, results = _setups(2, _truth())
    _two_modes(results)
    for s, result in enumerate(results):
        result.modes = result.modes.assign(freq_hz=np.array([100.0, 200.0]) * (1.03 if s else 1.0))
    merged = merge_setups(setups, results, freq_rtol=0.03)
    assert list(merged.modes["n_setups"]) == [2, 2]


def test_a_mode_passes_over_a_near_cluster_of_another_shape_to_a_farther_one_of_its_own():
    """s1 has modes at 7.0 Hz (shape of mode 2) and 7.03 Hz (shape of mode
    1), s2 one at 7.05 Hz with mode 1's shape: after 7.0 Hz's cluster
    refuses it (MAC 0.08) it still joins s1's 7.03 Hz."""
    setups, results = _setups(2, _truth())
    first, second = results
    first.modes = pd.concat([first.modes, first.modes.iloc[[0]].assign(mode=4, freq_hz=7.03)], ignore_index=True)
    first.complex_shapes = first.complex_shapes[:, [0, 1, 2, 0]]
    second.modes.loc[1, "freq_hz"] = 7.05
    second.complex_shapes = second.complex_shapes[:, [0, 0, 2]]
    merged = merge_setups(setups, results)
    np.testing.assert_allclose(merged.modes["freq_hz"], [3.0, 7.04, 11.0], rtol=2e-3)
    assert list(merged.modes["n_setups"]) == [2, 2, 2]


@pytest.mark.parametrize("offset, listed", [(0.015, True), (0.025, False)])
def test_a_setup_s_mode_of_another_shape_is_named_within_the_tolerance_only(offset, listed):
    """s3's modes near 7 Hz have a reference part orthogonal to the
    others' (they cannot join): the nearer of two within the tolerance
    (1.7 %: uncertainty 0.4 % each) is named as left out with its number;
    none is named when both lie beyond it."""
    setups, results = _setups(4, _truth())
    third = results[2]
    orthogonal = third.complex_shapes[:, 1].copy()
    orthogonal[:2] = [-np.conj(orthogonal[1]), np.conj(orthogonal[0])]
    third.modes = pd.concat([third.modes, third.modes.iloc[[1]].assign(mode=4)], ignore_index=True)
    third.modes.loc[1, "freq_hz"] = 7.0 * (1 - offset - 0.0015)  # below, a little farther
    third.modes.loc[3, "freq_hz"] = 7.0 * (1 + offset)  # the nearer, listed last
    third.complex_shapes = np.column_stack([third.complex_shapes, orthogonal])
    third.complex_shapes[:, 1] = orthogonal
    merged = merge_setups(setups, results)
    row = merged.matches.query("setup == 's3' and mode == 2")
    assert list(merged.modes["n_setups"]) == [4, 3, 4]
    if listed:
        assert list(row["status"]) == ["left out"] and list(row["setup_mode"]) == [4]
        assert row["freq_hz"].iloc[0] == pytest.approx(7.0 * (1 + offset))
    else:
        assert row.empty


def test_modes_are_numbered_by_their_mean_frequency():
    """Two clusters near 7 Hz of different shapes: (7.0, 7.2) with mean 7.1
    and (7.05, 7.06) with mean 7.055; the second is mode 2, the first 3."""
    setups, results = _setups(2, _truth(), freq_std=0.02)
    first, second = results
    first.modes = pd.concat([first.modes, first.modes.iloc[[0]].assign(mode=4, freq_hz=7.05)], ignore_index=True)
    first.complex_shapes = first.complex_shapes[:, [0, 1, 2, 0]]
    second.modes = pd.concat([second.modes, second.modes.iloc[[0]].assign(mode=4, freq_hz=7.06)], ignore_index=True)
    second.complex_shapes = second.complex_shapes[:, [0, 1, 2, 0]]
    _seven_hz(results, [7.0, 7.2])
    merged = merge_setups(setups, results)
    np.testing.assert_allclose(merged.modes["freq_hz"], [3.0, 7.055, 7.1, 11.0], rtol=1e-3)


def test_a_mode_from_the_diagram_is_looked_for_within_the_mode_s_own_tolerance():
    """s2 did not select the 7 Hz mode; its diagram has a stable pole of
    the right shape 2 % away, beyond the mode's tolerance (1.2 %: its
    members' uncertainty 0.4 %): not taken."""
    setups, results = _setups(3, _truth())
    second = results[1]
    second.poles = pd.DataFrame({"freq_hz": [7.15], "damping": [0.01], "stable": [True], "physical": [True]})
    second.pole_shapes = second.complex_shapes[:, [1]].T
    second.modes = second.modes.drop(index=1).reset_index(drop=True)
    second.complex_shapes = second.complex_shapes[:, [0, 2]]
    merged = merge_setups(setups, results)
    assert list(merged.modes["n_setups"]) == [3, 2, 3] and list(merged.modes["n_from_diagram"]) == [0, 0, 0]


def test_one_setup_without_references_is_not_rescaled():
    setups, results = _setups(1, _truth())
    setups = [Setup("alone", setups[0].record, setups[0].channels.assign(role="roving"))]
    assert list(merge_setups(setups, results).matches["scale"]) == [1.0, 1.0, 1.0]


def test_a_setup_failing_two_checks_gives_both_reasons():
    from .test_merge_checks import _spoil

    setups, results = _setups(3, _truth())
    _spoil(setups, results, 1, "unit slip")
    _spoil(setups, results, 1, "wrong rate")
    merged = merge_setups(setups, results)
    assert sorted(merged.disagreements["check"]) == ["rate", "reference levels"]
    reasons = merged.matches.query("setup == 's2'")["reason"]
    assert (reasons.str.count("; a wrong sampling rate|; its reference channels record") == 1).all(), list(reasons)
