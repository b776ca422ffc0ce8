"""Roving tests that cannot mislead (issue 33): no results over an input,
every setup identified with all its channels, a setup whose reference part,
reference levels or frequencies disagree with the others' named and left
out, matching that follows the modes' own scatter, the majority rule, a
robust normalisation and the complex rescaling checked on synthetic
identifications (no identification is run where none is needed)."""

import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from modal.cli import main as cli

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
