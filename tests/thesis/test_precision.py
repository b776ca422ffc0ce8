"""The precision rule of the committed tables (modal.thesis.precision): the
digits each chapter keeps, round-off written as an exact match, and the
writer that applies it."""

import math

import numpy as np
import pandas as pd
import pytest

from modal.thesis import precision
from modal.thesis.precision import (EXACT, ROUND_OFF, committed, deviation, deviation_decimals, is_exact, percent,
                                    significant, significant_digits)
from modal.thesis.tables import read_table, write_csv


def test_digits_follow_the_measured_spread_with_the_margin():
    # beam: 3e-11 * 100 = 3e-9 leaves 8 digits, capped at 6; grid: 5e-6 * 100 = 5e-4 leaves 3
    assert significant_digits("beam") == 6
    assert significant_digits("grid") == 3
    assert deviation_decimals("beam") == 8
    assert deviation_decimals("grid") == 3
    for chapter in precision.CHAPTERS:
        quantum = 10.0 ** -deviation_decimals(chapter)
        # the margin holds: the spread is at most a hundredth of the last kept decimal
        assert precision.KERNEL_SPREAD[chapter] * precision.MARGIN <= quantum
        assert precision.KERNEL_SPREAD[chapter] * precision.MARGIN > quantum / 10


def test_an_unknown_chapter_is_refused():
    with pytest.raises(ValueError, match="chapter"):
        significant(1.0, "plate")


@pytest.mark.parametrize("value, chapter, expected", [
    (2.16232145, "beam", 2.16232),
    (19.46087, "beam", 19.4609),
    (0.000123456789, "beam", 0.000123457),
    (1.2133047, "grid", 1.21),
    (4.69959, "grid", 4.70),
    (0.824583, "grid", 0.825),
    (-2.57674, "grid", -2.58),
    (0.0, "grid", 0.0),
])
def test_values_keep_their_chapters_significant_digits(value, chapter, expected):
    assert significant(value, chapter) == expected


def test_nan_and_infinity_pass_through():
    out = significant(np.array([np.nan, np.inf, 1.23456789]), "beam")
    assert np.isnan(out[0]) and out[1] == np.inf and out[2] == 1.23457


@pytest.mark.parametrize("value, expected", [
    (8.88e-15, True), (-4.64e-13, True), (2.03e-11, True), (9.9e-11, True),
    (1.01e-10, False), (5.45e-7, False), (-0.0245, False), (np.nan, False),
])
def test_round_off_threshold(value, expected):
    # the exact method's round-off (ERA, CERA noise-free: <= 2e-11) is exact;
    # the smallest real deviation (5e-7, ERA spillover) is not
    assert bool(is_exact(value)) is expected


@pytest.mark.parametrize("value, chapter, expected", [
    (6.29052e-13, "beam", 0.0),             # round-off: exact, written 0
    (-4.64406e-13, "beam", 0.0),            # no "-0"
    (1.01677e-05, "beam", 1.017e-05),       # 8 decimals of the fraction
    (-0.0245248, "beam", -0.0245248),       # 6 significant digits
    (-0.120794, "grid", -0.121),            # 3 decimals: 0.1 %
    (0.00043, "grid", 0.0),                 # below the grid's 0.1 %, yet not exact
    (0.0459, "grid", 0.046),
])
def test_deviations_are_rounded_absolutely(value, chapter, expected):
    out = deviation(value, chapter)
    assert out == expected
    assert math.copysign(1, out) == 1 or out != 0


@pytest.mark.parametrize("fraction, chapter, expected", [
    (8.88e-15, "beam", "exact (< 1e-10)"),
    (-6.22e-15, "beam", "exact (< 1e-10)"),
    (1.14e-13, "beam", "exact (< 1e-10)"),
    (0.00166, "beam", "0.166 %"),
    (0.0525, "beam", "5.25 %"),
    (5.45e-7, "beam", "5.4e-05 %"),
    (1e-4, "beam", "0.01 %"),
    (0.04321, "grid", "4.3 %"),
    (0.1734, "grid", "17.3 %"),
    (0.2, "grid", "20 %"),
])
def test_percent_text(fraction, chapter, expected):
    assert percent(fraction, chapter) == expected


def test_exact_text_names_the_threshold():
    assert EXACT == "exact (< 1e-10)"
    assert ROUND_OFF == 1e-10


def test_committed_rounds_row_by_row_and_leaves_other_columns():
    frame = pd.DataFrame({"table": [1, 10], "reproduced": [2.16232145, 1.2133047],
                          "rel_dev": [6.3e-13, -0.120794], "worst": ["ERA r=1", "TCM r=3"]})
    out = committed(frame, ["beam", "grid"], deviations=["rel_dev"])
    assert out["reproduced"].tolist() == [2.16232, 1.21]
    assert out["rel_dev"].tolist() == [0.0, -0.121]
    assert out["table"].tolist() == [1, 10] and out["worst"].tolist() == ["ERA r=1", "TCM r=3"]
    assert frame["reproduced"].iloc[0] == 2.16232145  # the input is left as it was
    with pytest.raises(ValueError, match="chapter"):
        committed(frame, ["beam"])


def test_write_csv_prints_the_rounded_values(tmp_path):
    frame = pd.DataFrame({"mode": [1, 2], "reproduced": [1.2133047, 4.69959], "rel_dev": [-0.120794, 8.9e-15],
                          "rel_err": [6.29e-13, 0.0245248]})
    write_csv(frame, tmp_path / "grid.csv", "grid")
    assert (tmp_path / "grid.csv").read_text() == "mode,reproduced,rel_dev,rel_err\n1,1.21,-0.121,0\n2,4.7,0,0.025\n"
    write_csv(frame, tmp_path / "beam.csv")
    assert (tmp_path / "beam.csv").read_text() == (
        "mode,reproduced,rel_dev,rel_err\n1,1.2133,-0.120794,0\n2,4.69959,0,0.0245248\n")
    assert read_table(tmp_path / "beam.csv")["reproduced"].tolist() == [1.2133, 4.69959]
