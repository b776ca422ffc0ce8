"""config/thesis_tables.csv must be an exact transcription of thesis Tables 1-15.

Every row of every table is re-read from the thesis text itself
(``<repo root>/../shared/thesis.txt``) with a small parser that derives the
column layout from each table's own header, and compared cell by cell with the
CSV.  A handful of hand-typed spot checks guard the parser, and the beam
tables' "actual" columns are checked against the closed-form frequencies.
"""

import math
import os
import re
from pathlib import Path

import pandas as pd
import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
CSV_PATH = REPO_ROOT / "config" / "thesis_tables.csv"
# The thesis text is not part of the project: it is looked for beside the
# checkout (``../shared/thesis.txt``) or where MODAL_THESIS_TEXT points.
THESIS_PATH = Path(os.environ.get("MODAL_THESIS_TEXT", REPO_ROOT.parent / "shared" / "thesis.txt"))

COLUMNS = ["table", "mode", "method", "column", "value", "printed", "flag"]
METHODS = {"tcm", "era", "cera", "actual", "est"}
PCT = "pct_change_from_10hz"
NUMERIC = re.compile(r"^-?(\d+\.?\d*|\.\d+)$")


# --------------------------------------------------------------------------- #
# loading
# --------------------------------------------------------------------------- #
@pytest.fixture(scope="module")
def raw():
    """The CSV exactly as pandas reads it by default."""
    return pd.read_csv(CSV_PATH)


@pytest.fixture(scope="module")
def text_df():
    """The CSV with every cell kept as text (so '.79' and '17.140' survive)."""
    return pd.read_csv(CSV_PATH, dtype=str, keep_default_na=False)


@pytest.fixture(scope="module")
def csv_cells(text_df):
    cells = {}
    for rec in text_df.itertuples(index=False):
        key = (int(rec.table), int(rec.mode), rec.method, rec.column)
        assert key not in cells, f"duplicate CSV row {key}"
        cells[key] = rec.printed
    return cells


@pytest.fixture(scope="module")
def thesis_lines():
    if not THESIS_PATH.is_file():
        pytest.skip(f"thesis text not found at {THESIS_PATH} (put the shared folder beside the "
                    "checkout or set MODAL_THESIS_TEXT): transcription not re-read from the thesis")
    return THESIS_PATH.read_text(encoding="utf-8").splitlines()


# --------------------------------------------------------------------------- #
# a small parser for the thesis's tab-separated tables
# --------------------------------------------------------------------------- #
def _classify(cell, caption_method):
    """Map one header cell to (method, column)."""
    m = re.search(r"\(m\s*=\s*(\d+)\)", cell)
    column = f"m={m.group(1)}" if m else ""
    if "CERA" in cell:
        return "cera", column
    if "ERA" in cell:
        return "era", column
    if "TCM" in cell:
        return "tcm", column
    if "actual" in cell:
        return "actual", column
    if "est" in cell:
        return "est", column
    return caption_method, None  # bare omega_r over the n = ... columns


def parse_table(lines, number):
    """Return (layout, rows) for thesis table `number`.

    layout: list of (method, column) in printed order.
    rows:   {mode r: [(method, column, printed), ...]} in printed order, with a
            Table-12 style cell "x (y)" split into (method, "", x) and
            (method, PCT, y).
    """
    caption = re.compile(rf"^Table {number}\.\s")
    starts = [i for i, line in enumerate(lines) if caption.match(line)]
    assert len(starts) == 1, f"caption 'Table {number}.' found {len(starts)} times"
    start = starts[0]
    cap = lines[start]
    caption_method = "era" if "ERA" in cap else "tcm" if "TCM" in cap else None

    header, data = [], []
    for line in lines[start + 1:]:
        if re.match(r"^\d+\t", line):
            data.append(line)
        elif data:
            break
        elif line.strip():
            header.append(line)
    assert header and data, f"Table {number}: no header/data rows found"

    # header line 1: one cell per method (after the 'r' label)
    first = [c.strip() for c in header[0].split("\t")[1:] if c.strip()]
    classified = [_classify(c, caption_method) for c in first]
    layout = []
    if any(col is None for _, col in classified):
        # spillover table: second header line carries n = k for each column
        assert len(header) == 2, f"Table {number}: expected an 'n =' header line"
        ns = [c.strip().strip("$") for c in header[1].split("\t")[1:] if c.strip()]
        ns = [re.sub(r"^n\s*=\s*", "", c) for c in ns]
        assert all(c.isdigit() for c in ns), (number, ns)
        for method, col in classified:
            if col is None:
                layout.extend((method, f"n={k}") for k in ns)
            else:
                layout.append((method, col))
    else:
        assert len(header) == 1, f"Table {number}: unexpected header lines {header}"
        layout = classified
    assert all(m in METHODS for m, _ in layout), (number, layout)

    rows = {}
    for line in data:
        cells = [c.strip() for c in line.split("\t")]
        mode = int(cells[0])
        cells = [c for c in cells[1:] if c]
        assert len(cells) == len(layout), f"Table {number} row {mode}: {cells} vs {layout}"
        row = []
        for (method, col), cell in zip(layout, cells):
            pm = re.fullmatch(r"(\S+)\s+\((\S+)\)", cell)
            if pm:
                row.append((method, col, pm.group(1)))
                row.append((method, PCT, pm.group(2)))
            else:
                row.append((method, col, cell))
        rows[mode] = row
    assert sorted(rows) == list(range(1, len(rows) + 1)), (number, sorted(rows))
    return layout, rows


@pytest.fixture(scope="module")
def thesis_tables(thesis_lines):
    return {n: parse_table(thesis_lines, n) for n in range(1, 16)}


# --------------------------------------------------------------------------- #
# structure of the CSV
# --------------------------------------------------------------------------- #
def test_columns(raw):
    assert list(raw.columns) == COLUMNS


def test_every_table_present(raw):
    assert sorted(raw["table"].unique()) == list(range(1, 16))
    assert raw["table"].dtype.kind == "i" and raw["mode"].dtype.kind == "i"
    assert raw["value"].dtype.kind == "f"
    assert (raw["mode"] >= 1).all()


def test_methods_and_columns(text_df):
    assert set(text_df["method"]) <= METHODS
    for rec in text_df.itertuples(index=False):
        t, col = int(rec.table), rec.column
        if t in (5, 6, 14, 15):
            ok = col == "" if rec.method in ("actual", "est") else re.fullmatch(r"n=\d+", col)
        elif t == 13:
            ok = col == "" if rec.method == "est" else col in ("m=1", "m=3")
        elif t == 12:
            ok = col in ("", PCT) and (col == "" or rec.method in ("tcm", "era"))
        else:
            ok = col == ""
        assert ok, f"bad column {col!r} for {rec}"


def test_sorted(text_df):
    keys = [(int(r.table), r.method, r.column, int(r.mode))
            for r in text_df.itertuples(index=False)]
    assert keys == sorted(keys)


def test_value_matches_printed(raw, text_df):
    for i, rec in enumerate(text_df.itertuples(index=False)):
        value = raw["value"].iloc[i]
        if NUMERIC.match(rec.printed):
            assert rec.value != "", f"missing value for {rec}"
            assert float(rec.printed) == float(rec.value), rec
            assert float(rec.printed) == value, rec
        else:
            assert rec.value == "" and math.isnan(value), rec


def test_flags(text_df):
    for rec in text_df.itertuples(index=False):
        if NUMERIC.match(rec.printed):
            assert rec.flag == "", rec
        elif rec.printed == "*":
            assert rec.flag == "real_pole", rec
        elif re.fullmatch(r"-{2,}", rec.printed):
            assert rec.flag == "absent", rec
        else:
            pytest.fail(f"unexpected printed cell {rec.printed!r} in {rec}")
    assert set(text_df["flag"]) <= {"", "real_pole", "absent"}
    # the only starred cells: Table 6, first mode, n = 4 and 5
    stars = text_df[text_df["flag"] == "real_pole"]
    assert sorted(zip(stars["table"], stars["mode"], stars["column"])) == [
        ("6", "1", "n=4"), ("6", "1", "n=5")]


# --------------------------------------------------------------------------- #
# the CSV against the thesis text, every row of every table
# --------------------------------------------------------------------------- #
@pytest.mark.parametrize("number", range(1, 16))
def test_table_rows_match_thesis(number, thesis_tables, csv_cells):
    layout, rows = thesis_tables[number]
    csv_keys = {k for k in csv_cells if k[0] == number}
    seen = set()
    for mode, row in rows.items():
        expected = [(m, c, p) for m, c, p in row]
        got = [(m, c, csv_cells.get((number, mode, m, c))) for m, c, _ in row]
        assert got == expected, f"Table {number}, row r={mode}"
        seen |= {(number, mode, m, c) for m, c, _ in row}
    assert csv_keys == seen, f"Table {number}: CSV rows not in the thesis: {csv_keys - seen}"


EXPECTED_SHAPES = {  # table: (rows r, cells per row incl. Table 12's pct cells)
    1: (3, 3), 2: (3, 3), 3: (3, 3), 4: (3, 3), 5: (6, 5), 6: (6, 5),
    7: (3, 4), 8: (3, 4), 9: (3, 4), 10: (4, 3), 11: (4, 3), 12: (4, 5),
    13: (4, 3), 14: (4, 4), 15: (4, 4),
}


@pytest.mark.parametrize("number", range(1, 16))
def test_table_shapes(number, thesis_tables, text_df):
    n_rows, n_cells = EXPECTED_SHAPES[number]
    _, rows = thesis_tables[number]
    assert len(rows) == n_rows
    assert all(len(r) == n_cells for r in rows.values())
    assert (text_df["table"] == str(number)).sum() == n_rows * n_cells


# Hand-typed from the thesis, independent of the parser above:
# (table, r, method, column, printed)
SPOT = [
    (1, 1, "tcm", "", "2.1659"), (1, 3, "era", "", "19.461"),
    (2, 3, "tcm", "", "19.407"), (2, 1, "actual", "", "2.1623"),
    (3, 1, "era", "", "2.1033"), (3, 3, "tcm", "", "18.499"),
    (4, 3, "tcm", "", "17.140"), (4, 2, "era", "", "8.6881"),
    (5, 1, "tcm", "n=3", "3.07"), (5, 4, "tcm", "n=3", "-----"),
    (5, 4, "tcm", "n=6", "34.58"), (5, 4, "actual", "", "34.60"),
    (6, 1, "era", "n=3", ".79"), (6, 1, "era", "n=4", "*"),
    (6, 1, "era", "n=5", "*"), (6, 3, "era", "n=5", "32.46"),
    (7, 1, "cera", "", ".434"), (7, 2, "tcm", "", "1.767"),
    (8, 1, "cera", "", ".463"), (8, 3, "tcm", "", "3.927"),
    (9, 2, "cera", "", "1.800"), (9, 3, "tcm", "", "3.760"),
    (10, 4, "era", "", "13.14"), (10, 1, "est", "", ".83"),
    (11, 1, "era", "", ".78"), (11, 4, "tcm", "", "5.98"),
    (12, 1, "era", "", ".84"), (12, 1, "era", PCT, "65.0"),
    (12, 2, "tcm", PCT, "1.1"), (12, 4, "tcm", "", "5.96"),
    (13, 2, "era", "m=1", "2.46"), (13, 2, "era", "m=3", "1.96"),
    (14, 3, "tcm", "n=2", "----"), (14, 3, "tcm", "n=3", "4.99"),
    (14, 4, "est", "", "6.49"), (15, 1, "era", "n=2", "1.36"),
    (15, 3, "era", "n=3", "6.58"), (15, 4, "era", "n=3", "----"),
]


def test_spot_checks_cover_all_tables():
    assert len(SPOT) >= 25
    assert {s[0] for s in SPOT} == set(range(1, 16))


@pytest.mark.parametrize("table,mode,method,column,printed", SPOT)
def test_spot_check(table, mode, method, column, printed, csv_cells, thesis_tables):
    assert csv_cells[(table, mode, method, column)] == printed
    _, rows = thesis_tables[table]
    assert (method, column, printed) in rows[mode]


# --------------------------------------------------------------------------- #
# closed-form beam frequencies
# --------------------------------------------------------------------------- #
def _decimals(printed):
    return len(printed.split(".")[1]) if "." in printed else 0


@pytest.mark.parametrize("table,coef,length", [
    (1, 30, 5), (2, 30, 5), (3, 30, 5), (4, 30, 5), (5, 30, 5), (6, 30, 5),
    (7, 20, 10), (8, 20, 10), (9, 20, 10),
])
def test_actual_closed_form(table, coef, length, text_df):
    """omega_r = sqrt(EI/m) (r pi / L)^2: Eq. for the 5 m beam, Eq. (53) for the 10 m one."""
    sub = text_df[(text_df["table"] == str(table)) & (text_df["method"] == "actual")]
    assert len(sub) >= 3
    for rec in sub.itertuples(index=False):
        r = int(rec.mode)
        exact = math.sqrt(coef) * (r * math.pi / length) ** 2
        d = _decimals(rec.printed)
        assert float(f"{exact:.{d}f}") == float(rec.value), (table, r, exact, rec.printed)
