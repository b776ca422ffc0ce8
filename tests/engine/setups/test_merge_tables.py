"""What the merge's tables say, cell by cell: a merged setup's reason
(none), its reference share whatever the scale of its shapes, the
references a setup lacks named one by one, and merged modes built from
their three tables alone (no disagreements: an empty table with its
columns). Synthetic identifications, as in ``test_merge_checks``; asked
for by the mutation run of ``modal.setups`` (issue 33)."""

import re

import numpy as np
import pandas as pd
import pytest

from modal.setups import MergedModes, Setup, check_setups, merge_setups
from modal.setups._results import log_merge

from .test_merge_checks import _setups, _truth


def test_a_setup_missing_two_references_and_adding_one_is_told_all_three():
    """s2 declares r1 and r2 roving and n2 a reference: the refusal lists
    both missing references and the extra one, each once, in that order."""
    setups, _ = _setups(2, _truth())
    table = setups[1].channels.copy()
    table["role"] = ["roving", "roving", "reference", "roving"]
    setups[1] = Setup("s2", setups[1].record, table)
    expected = ("setup s2: its reference channels differ from setup s1's: missing node r1 along (0, 0, 1); "
                "node r2 along (0, 0, 1); extra node n2 along (0, 0, 1)")
    with pytest.raises(ValueError, match=f"^{re.escape(expected)}$"):
        check_setups(setups)


def test_a_merged_setup_has_no_reason_a_left_out_one_has_its_own():
    """Three setups, s3's 7 Hz reference part swapped: every merged row of
    matches has an empty reason (not a missing one), s3's left-out row the
    residual of its scale fit."""
    setups, results = _setups(3, _truth())
    results[2].complex_shapes = results[2].complex_shapes.copy()
    results[2].complex_shapes[:2, 1] = results[2].complex_shapes[[1, 0], 1]
    matches = merge_setups(setups, results).matches
    merged, left_out = matches[matches["status"] == "merged"], matches[matches["status"] == "left out"]
    assert len(merged) == 8 and merged["reason"].tolist() == [""] * 8
    assert left_out["reason"].tolist() == ["its reference part disagrees with the others': residual of its complex "
                                           "scale fit 0.22 > 0.2 (MAC 0.95)"]


def test_the_reference_share_is_the_references_part_of_the_setup_s_own_shape():
    """ref_share = |r| / |phi| of the setup's shape: the same when the
    setup's shapes are 100 e^i times larger (the scale then 100 x smaller),
    between 0.2 and 1 for the synthetic setups (2 references of 4 channels)."""
    setups, results = _setups(3, _truth(complex_modes=True))
    before = merge_setups(setups, results).matches.set_index(["mode", "setup"])
    phi = results[1].complex_shapes
    expected = np.linalg.norm(phi[:2], axis=0) / np.linalg.norm(phi, axis=0)
    np.testing.assert_allclose(before.xs("s2", level="setup")["ref_share"], expected, rtol=1e-12)
    results[1].complex_shapes = phi * 100 * np.exp(1j)
    after = merge_setups(setups, results).matches.set_index(["mode", "setup"])
    np.testing.assert_allclose(after["ref_share"], before["ref_share"], rtol=1e-9)
    np.testing.assert_allclose(after.xs("s2", level="setup")["scale"], before.xs("s2", level="setup")["scale"] / 100,
                               rtol=1e-9)
    assert 0.2 < after["ref_share"].min() and after["ref_share"].max() < 1


def test_merged_modes_from_their_three_tables_have_no_disagreement():
    """MergedModes built from modes, shapes and matches alone (as read back
    from a results folder) have an empty disagreements table with its
    columns: the log then tells only of the modes' left-out setups."""
    setups, results = _setups(3, _truth())
    results[2].complex_shapes = results[2].complex_shapes.copy()
    results[2].complex_shapes[:2, 1] = results[2].complex_shapes[[1, 0], 1]
    full = merge_setups(setups, results)
    read_back = MergedModes(full.modes, full.shapes, full.matches)
    assert read_back.disagreements.empty and list(read_back.disagreements.columns) == ["setup", "check", "evidence"]
    lines = []
    log_merge(read_back, lines.append)
    assert len(lines) == 1 and lines[0].startswith("mode 2: setup s3 left out: its reference part disagrees")
    pd.testing.assert_frame_equal(read_back.matches, full.matches)


def test_two_setups_give_a_spread_and_a_reference_mac():
    """Two setups, the 7 Hz mode at 7.00 and 7.07 Hz with damping 1 % and
    2 %, s2's 3 Hz reference part turned to MAC 0.97: the spreads are the
    standard deviations of two values (not missing: two is enough) and
    each mode's ref_mac is the smallest of its own merged setups'."""
    from .test_merge_bounds import _tilted

    setups, results = _setups(2, _truth(), freq_std=0.01)
    for result, f, zeta in zip(results, [7.0, 7.07], [0.01, 0.02]):
        result.modes.loc[1, "freq_hz"] = f
        result.modes["damping"] = [0.01, zeta, 0.01]
    results[1].complex_shapes = results[1].complex_shapes.copy()
    results[1].complex_shapes[:, 0] = _tilted(results[1].complex_shapes[:, 0], 0.97)
    modes = merge_setups(setups, results).modes
    assert list(modes["n_setups"]) == [2, 2, 2]
    assert modes["freq_spread_hz"].iloc[1] == pytest.approx(0.07 / np.sqrt(2), rel=1e-9)
    assert modes["damping_spread"].iloc[1] == pytest.approx(0.01 / np.sqrt(2), rel=1e-9)
    assert modes["damping_spread"].iloc[0] == 0.0 and modes["freq_spread_hz"].iloc[0] > 0
    np.testing.assert_allclose(modes["ref_mac"], [0.97, 1.0, 1.0], rtol=1e-9)


def test_every_setup_left_out_of_a_mode_is_named_in_its_row():
    """Five setups, s2 with a wrong rate and s4 with a unit slip: both left
    out of every mode, the modes' left_out column names both, space
    separated, in the setups' order."""
    from .test_merge_checks import _spoil

    setups, results = _setups(5, _truth())
    _spoil(setups, results, 1, "wrong rate")
    _spoil(setups, results, 3, "unit slip")
    modes = merge_setups(setups, results).modes
    assert list(modes["left_out"]) == ["s2 s4"] * 3 and list(modes["setups"]) == ["s1 s3 s5"] * 3
