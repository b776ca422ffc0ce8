"""Record readers: behaviours pinned by mutation testing
(benchmarks/mutation_records.py): exact rates, delimiters, headers and
channels of small records written to tmp_path."""

import warnings
from pathlib import Path

import numpy as np
import pytest

from modal.identification import ModalWarning
from modal.records import load_record, read_record, unit_key
from modal.records._io import _printed_resolution, _time_step


@pytest.mark.parametrize("spelling, key", [
    ("m/s^2", "m/s2"), ("m s^-2", "m/s2"), ("m·s⁻²", "m/s2"), ("M/S**2", "m/s2"), (" m/s² ", "m/s2"),
    ("m s-1", "m/s"), ("µm/s", "um/s"), ("\u03bcm", "um"), ("mm s^-1", "mm/s"), ("g", "g"), ("s-3", "s-3"),
])
def test_unit_key_spellings(spelling, key):
    assert unit_key(spelling) == key


# --- the time column: its printed resolution and its step ----------------------------------------
@pytest.mark.parametrize("values, resolution", [
    ([0.0, 1.0, 2.0], 1.0),                      # whole numbers
    ([0.0, 0.005, 0.01], 1e-3),                  # printed with three decimals
    ([0.0, 1000000.005000002], 1e-3),            # 2e-15 of the value is a double's rounding: still 1e-3
    ([1700000000.0, 1700000000.01], 1e-2),       # a Unix time printed to the 1/100 s
    ([0.0, 0.9999999995], 1.0),                  # within the absolute 1e-9 of a whole number
    ([0.0, 1e-14 + 1e-9], 1.0),                  # the bound (1e-14 of max(1, |value|), + 1e-9) is included
    ([0.0, 0.1000000015], 1e-10),                # 1.5e-9 is a printed digit, not rounding
    ([0.0, 0.123456 + 1.6e-14], 0.0),            # 1.6e-14 at 0.12 is printed too: full precision
    ([0.0, 0.123456789012305], 0.0),             # 15 decimals: finer than 1e-12 counts as full precision
])
def test_printed_resolution(values, resolution):
    assert _printed_resolution(np.array(values)) == pytest.approx(resolution, rel=1e-12, abs=0)


def _jittered(step, offset=50.0, by=0.0):
    time = offset + step * np.arange(5)
    time[2] += by
    return time


@pytest.mark.parametrize("time, step", [
    ([0.0, 0.5], 0.5),                           # two samples are enough
    ([12.5, 12.51, 12.52, 12.53], 0.01),         # a record cut from a longer one: the first time is not 0
    ([0.0, 2.0, 3.0, 4.0, 6.0], 1.5),            # 1.5 s printed in whole seconds: each step off by up to 1 s
    ([0.0, 0.011, 0.02, 0.03], 0.01),            # a step off by one printed unit (1 ms)
    ([0.001, 0.011, 0.031, 0.041], None),        # a sample missing
    ([0.0, 0.0, 0.0], None),                     # constant
    ([0.3, 0.2, 0.1], None),                     # decreasing
    ([0.0, np.inf, 0.02], None),                 # not finite
    ([0.0, np.nan, 0.02], None),
    ([0.0], None),
    (_jittered(1e-4, by=1.2e-10), 1e-4),         # full precision at 50 s: 1e-6 of dt + 1e-12 of 50 s is allowed
    (_jittered(1e-4, by=1.3e-6), None),          # ... 1.3 % of dt is not
])
def test_time_step(time, step):
    got = _time_step(np.array(time))
    assert got == (None if step is None else pytest.approx(step, rel=1e-9))



def test_a_gap_in_a_unix_time_column_is_refused(tmp_path):
    """Times printed to the 1/1000 s as Unix time: the printed resolution is
    1 ms (it was 1 s: the rounding allowed was 1e-9 of 1.7e9 s), so half a
    second missing is no rounding."""
    rows = [f"{1700000000 + 0.01 * k:.3f},{np.sin(k):.6f}" for k in range(100)]
    path = tmp_path / "unix.csv"
    path.write_text("\n".join(rows) + "\n")
    assert read_record(path).dt == pytest.approx(0.01, rel=1e-6)
    path.write_text("\n".join(rows[:10] + rows[60:]) + "\n")
    with pytest.raises(ValueError, match=r"unix.csv: the time column \(column 1\) is not uniformly increasing"):
        read_record(path)

# --- the delimiter -------------------------------------------------------------------------------
T = 0.005 * np.arange(30)
A = np.round(np.sin(np.arange(30)), 6)
B = np.round(np.cos(np.arange(30)), 6)


def _text(tmp_path, lines, name="rec.csv"):
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def _rows(sep, n=30):
    return [sep.join([f"{t:.3f}", f"{a:.6f}", f"{b:.6f}"]) for t, a, b in zip(T[:n], A[:n], B[:n])]


def _same(record, n=30, names=("ch1", "ch2")):
    np.testing.assert_array_equal(record.acc, np.column_stack([A[:n], B[:n]]))
    assert record.dt == pytest.approx(0.005, rel=1e-12)
    assert record.channels["name"].tolist() == list(names)


@pytest.mark.parametrize("case, lines", [
    ("lines of spaces at the end", _rows(",") + ["   "] * 25),
    ("a space after each comma", _rows(", ")),
    ("pipes between spaces", _rows(" | ")),
    ("a tab at the end of each line", [row + "\t" for row in _rows("\t")]),
    ("a preamble of twelve lines above ten rows", [f"Operator {k}: x" for k in range(12)] + _rows(",", 10)),
    ("a preamble of three lines above five rows", ["Test", "Operator x", "Site y"] + _rows(",", 5)),
])
def test_the_delimiter_is_sniffed_from_the_rows(tmp_path, case, lines):
    n = sum(1 for line in lines if line[:1].isdigit())
    _same(read_record(_text(tmp_path, lines)), n)


def test_tabs_with_a_space_beside_them_keep_the_names_with_spaces(tmp_path):
    """A space next to a tab is no run of whitespace between columns: the
    tabs separate, so names with spaces stay whole."""
    lines = ["time\tnorth deck\tsouth deck"] + ["\t ".join(row.split("\t")) for row in _rows("\t")]
    _same(read_record(_text(tmp_path, lines, "rec.txt")), names=("north deck", "south deck"))


def test_decimal_commas_and_semicolons(tmp_path):
    lines = [";".join(c.replace(".", ",") for c in row.split(",")) for row in _rows(",")]
    _same(read_record(_text(tmp_path, lines), decimal=","))


# --- header rows ---------------------------------------------------------------------------------
def test_a_numeric_header_above_three_rows_and_a_time_column(tmp_path):
    """Node ids 0..3 (not ten times the samples) break the time column below them: a header."""
    _same(read_record(_text(tmp_path, ["0,1,2"] + _rows(",", 3))), 3)
    _same(read_record(_text(tmp_path, ["0,1,2"] + _rows(","))))


def test_a_numeric_header_above_a_time_column_and_a_sample_counter(tmp_path):
    lines = ["0,0,7"] + [f"{t:.3f},{k + 1},{a:.6f}" for k, (t, a) in enumerate(zip(T, A))]
    record = read_record(_text(tmp_path, lines))
    np.testing.assert_array_equal(record.acc, np.column_stack([np.arange(1, 31), A]))


def test_a_narrower_row_of_node_ids_is_a_header(tmp_path):
    _same(read_record(_text(tmp_path, ["101,102"] + _rows(","))))
    with pytest.raises(ValueError, match=r"rec.csv: fewer than 2 rows of numbers"):
        read_record(_text(tmp_path, ["101,102"] + _rows(",", 1)))


def _no_time(first, rows):
    """Samples without a time column (the first column is not uniform), below a first row."""
    return [first] + [",".join(f"{v:.3f}" for v in row) for row in rows]


SAMPLES = np.round(np.random.default_rng(1).uniform(-1, 1, (8, 2)), 3)


@pytest.mark.parametrize("first, maxima, header", [
    ("20,500", (1.0, 100.0), True),   # each column against its own samples
    ("105,5", (10.0, 10.0), True),    # more than ten times
    ("10,20", (1.0, 2.0), False),     # exactly ten times is a sample
    ("20,20", (5.0, 5.0), False),     # four times
])
def test_a_numeric_header_is_ten_times_the_samples_below_it(tmp_path, first, maxima, header):
    samples = SAMPLES * np.array(maxima)
    samples[3] = maxima  # each column's largest
    record = read_record(_text(tmp_path, _no_time(first, samples)), fs=100)
    expected = samples if header else np.vstack([[float(v) for v in first.split(",")], samples])
    np.testing.assert_allclose(record.acc, expected, rtol=1e-12)


def test_the_largest_sample_below_a_numeric_header_may_be_the_first(tmp_path):
    samples = SAMPLES.copy()
    samples[0] = (9.0, 9.0)
    record = read_record(_text(tmp_path, _no_time("50,50", samples)), fs=100)
    assert record.acc.shape == (9, 2)


def test_whole_numbers_in_the_first_rows_are_samples(tmp_path):
    """Integer first rows: a header only when the two rows below it are not integers too."""
    samples = np.vstack([[1, 2], [2, 1], SAMPLES])
    record = read_record(_text(tmp_path, ["101,102", "1,2", "2,1"] + _no_time("x", SAMPLES)[1:]), fs=100)
    np.testing.assert_allclose(record.acc, np.vstack([[101, 102], samples]))
    lines = ["101,102", "0.500,0.250", "1,2"] + _no_time("x", SAMPLES)[1:]
    assert read_record(_text(tmp_path, lines), fs=100).acc.shape == (10, 2)


def test_a_numeric_header_above_a_broken_first_time_is_a_sample_with_fs(tmp_path):
    lines = ["0,1,2", "0.50,0.1,0.2"] + _rows(",")[1:]
    record = read_record(_text(tmp_path, lines), fs=100)
    assert record.acc.shape == (31, 3)


# --- what a text file may hold -------------------------------------------------------------------
@pytest.mark.parametrize("options, message", [
    ({"decimal": ";"}, r"decimal must be '\.' or ',', got ';'"),
    ({"skip_rows": -1}, r"skip_rows must be an integer >= 0, got -1"),
    ({"skip_rows": True}, r"skip_rows must be an integer >= 0, got True"),
    ({"skip_rows": 1.0}, r"skip_rows must be an integer >= 0, got 1\.0"),
    ({"delimiter": ";;"}, r"delimiter must be one character other than the decimal mark, got ';;'"),
    ({"delimiter": 1}, r"delimiter must be one character other than the decimal mark, got 1"),
    ({"delimiter": ",", "decimal": ","}, r"delimiter must be one character other than the decimal mark, got ','"),
])
def test_text_options_are_checked(tmp_path, options, message):
    with pytest.raises(ValueError, match=rf"rec.csv: {message}"):
        read_record(_text(tmp_path, _rows(",")), **options)


def test_a_byte_order_mark_is_not_part_of_the_first_sample(tmp_path):
    path = tmp_path / "excel.csv"
    path.write_text("\n".join(_rows(",")) + "\n", encoding="utf-8-sig")
    _same(read_record(path))


def test_a_latin1_header_reads(tmp_path):
    path = tmp_path / "latin.csv"
    path.write_bytes(("time,a1,a2\ns,m/s²,m/s²\n" + "\n".join(_rows(",")) + "\n").encode("latin-1"))
    _same(read_record(path), names=("a1", "a2"))


def test_rows_of_bare_delimiters_are_skipped(tmp_path):
    rows = _rows(",")
    _same(read_record(_text(tmp_path, ["time, a1 , a2 "] + rows[:10] + [",,", " , , "] + rows[10:])), names=("a1", "a2"))


def test_a_blank_cell_in_the_first_row_is_named(tmp_path):
    rows = _rows(",")
    rows[0] = "0.000, ,1.000000"
    with pytest.raises(ValueError, match=r"rec.csv: row 1, column 2 is empty"):
        read_record(_text(tmp_path, rows))


def test_ragged_rows_name_the_first_row_and_its_width(tmp_path):
    rows = _rows(",")
    rows[1] = rows[1].rsplit(",", 1)[0]
    with pytest.raises(ValueError, match=r"rec.csv: ragged rows \(channels of unequal length\): row 2 has 2 values "
                                         r"separated by ',', row 1 has 3: every row"):
        read_record(_text(tmp_path, rows))
    with pytest.raises(ValueError, match=r"row 3 has 2 values separated by ',', row 2 has 3 \(the last row"):
        read_record(_text(tmp_path, ["101,102"] + _rows(",", 1) + [rows[1]]))


@pytest.mark.parametrize("decimal, hint", [(".", " (decimal commas: pass decimal=',', --decimal ,)"), (",", "")])
def test_a_cell_that_is_no_number_is_named_with_the_hint_that_fits(tmp_path, decimal, hint):
    rows = [row.replace(",", ";") for row in _rows(",")]
    rows[4] = rows[4].split(";")[0] + ";1e;2"
    import re
    with pytest.raises(ValueError, match=re.escape(f"rec.csv: row 5, column 2: '1e' is not a finite number{hint}") + "$"):
        read_record(_text(tmp_path, rows), decimal=decimal)


def test_one_column_needs_fs_and_fs_is_checked(tmp_path):
    path = _text(tmp_path, [f"{a:.6f}" for a in A])
    with pytest.raises(ValueError, match=r"rec.csv: without fs the first column must be time \(s\), followed by channels"):
        read_record(path)
    with pytest.raises(ValueError, match=r"rec.csv: fs must be a finite number > 0, got -1"):
        read_record(path, fs=-1)
    record = read_record(path, fs=200)
    assert record.acc.shape == (30, 1) and record.dt == 1 / 200
    with pytest.raises(ValueError, match=r"rec.csv: fs must be a finite number > 0, got 0"):
        read_record(_text(tmp_path, _rows(",")), fs=0)  # a time column and a bad fs


def test_header_names_are_stripped(tmp_path):
    _same(read_record(_text(tmp_path, [" time ; a1 ;\ta2 "] + [r.replace(",", ";") for r in _rows(",")])),
          names=("a1", "a2"))


def test_fs_that_agrees_with_the_time_column_draws_no_warning_one_that_does_not_points_at_the_caller(tmp_path):
    path = _text(tmp_path, _rows(","))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert read_record(path, fs=200.0 * (1 + 5e-4)).dt == 1 / (200.0 * (1 + 5e-4))
    with pytest.warns(ModalWarning, match=r"rec.csv: fs = 201 Hz overrides the time column's 200 Hz") as caught:
        read_record(path, fs=201)
    assert caught[0].filename == __file__


def test_an_upper_case_extension_is_read(tmp_path):
    _same(read_record(_text(tmp_path, _rows(","), "REC.CSV")))


# --- NumPy records -------------------------------------------------------------------------------
def test_npy_channels_are_named_in_order_and_a_square_array_is_no_transpose(tmp_path):
    np.save(tmp_path / "r.npy", np.arange(9.0).reshape(3, 3))
    record = read_record(tmp_path / "r.npy", fs=100)
    assert record.channels["name"].tolist() == ["ch1", "ch2", "ch3"]
    assert list(record.channels.columns) == ["name", "node", "direction", "unit"]
    assert record.acc.shape == (3, 3) and record.fs == 100


def test_a_record_needs_two_samples(tmp_path):
    np.save(tmp_path / "r.npy", np.array([1.0, 2.0]))
    assert read_record(tmp_path / "r.npy", fs=10).acc.shape == (2, 1)
    np.save(tmp_path / "r.npy", np.array([1.0]))
    with pytest.raises(ValueError, match=r"r.npy: acc needs at least 2 samples, got 1"):
        read_record(tmp_path / "r.npy", fs=10)


def test_npy_fs_is_checked(tmp_path):
    np.save(tmp_path / "r.npy", np.ones((4, 1)))
    with pytest.raises(ValueError, match=r"r.npy: fs must be a finite number > 0, got -1"):
        read_record(tmp_path / "r.npy", fs=-1)


@pytest.mark.parametrize("suffix", [".npy", ".npz"])
def test_object_arrays_are_not_unpickled(tmp_path, suffix):
    values = np.empty((4, 1), dtype=object)
    values[:] = 1.0
    path = tmp_path / f"r{suffix}"
    np.save(path, values) if suffix == ".npy" else np.savez(path, acc=values, dt=0.01)
    with pytest.raises(ValueError, match=rf"r{suffix}: .*allow_pickle=False"):
        read_record(path, fs=100 if suffix == ".npy" else None)


@pytest.mark.parametrize("content", [bytes(range(256)) * 4, b"\x93NUMPY" + bytes(60), b"PK\x01\x02" + bytes(40)])
def test_an_npz_that_is_no_zip_is_named_so_not_a_pickle(tmp_path, content):
    """Random bytes, an .npy's header under an .npz name, a zip's central
    directory without its files: numpy would call them pickled data or a bad
    zip; the reader says no zip header (an empty file: numpy's 'No data left
    in file')."""
    (tmp_path / "r.npz").write_bytes(content)
    with pytest.raises(ValueError, match=r"r.npz: not an .npz archive \(no zip header\): the file is damaged"):
        read_record(tmp_path / "r.npz")
    np.savez(tmp_path / "r.npz", acc=np.ones((4, 1)), dt=0.01)  # a zip: read
    assert read_record(tmp_path / "r.npz").acc.shape == (4, 1)


def test_npz_without_acc_or_y_names_its_arrays(tmp_path):
    np.savez(tmp_path / "r.npz", x=np.ones((4, 1)), dt=0.01)
    with pytest.raises(ValueError, match=r"r.npz: expected an array 'acc' or 'y', found \['dt', 'x'\]"):
        read_record(tmp_path / "r.npz")


@pytest.mark.parametrize("stored, message", [
    ({"dt": -0.01}, r"dt must be a finite number > 0, got -0.01$"),
    ({"fs": 0.0}, r"fs must be a finite number > 0, got 0.0$"),
    ({"dt": [0.01, 0.02]}, r"dt must be one positive number, got array"),
])
def test_npz_rates_are_checked(tmp_path, stored, message):
    np.savez(tmp_path / "r.npz", acc=np.ones((4, 1)), **stored)
    with pytest.raises(ValueError, match=rf"r.npz: {message}"):
        read_record(tmp_path / "r.npz")


def test_npz_dt_and_fs_agree_to_one_part_in_a_million(tmp_path):
    np.savez(tmp_path / "r.npz", acc=np.ones((4, 1)), dt=0.005, fs=200 * (1 + 5e-7))
    assert read_record(tmp_path / "r.npz").dt == 1 / (200 * (1 + 5e-7))  # the stored fs
    assert read_record(tmp_path / "r.npz", fs=200).dt == 1 / (200 * (1 + 5e-7))  # fs agrees with it
    np.savez(tmp_path / "r.npz", acc=np.ones((4, 1)), dt=0.005, fs=200 * (1 + 2e-6))
    with pytest.raises(ValueError, match=r"r.npz: the file's dt = 0.005 s contradicts its fs = 200.0004 Hz"):
        read_record(tmp_path / "r.npz")
    np.savez(tmp_path / "r.npz", acc=np.ones((4, 1)), dt=0.005)
    assert read_record(tmp_path / "r.npz", fs=200 * (1 + 5e-7)).dt == 0.005  # the file's dt
    with pytest.raises(ValueError, match=r"r.npz: fs = 200.0004 Hz contradicts the file's dt = 0.005 s"):
        read_record(tmp_path / "r.npz", fs=200.0004)


# --- LabVIEW .lvm --------------------------------------------------------------------------------
LVM_HEADER = ("LabVIEW Measurement\t\nWriter_Version\t2\nReader_Version\t2\nSeparator\tTab\nDecimal_Separator\t.\n"
              "Multi_Headings\tNo\nX_Columns\t{x}\nTime_Pref\tRelative\nOperator\tx\n***End_of_Header***\t\n\t\n")
LVM_SEGMENT = ("Channels\t2\t\nSamples\t{n}\t{n}\t\nY_Unit_Label\tg\tm/s^2\t\nX_Dimension\tTime\tTime\t\n"
               "X0\t0.0000000000000000E+0\t0.0000000000000000E+0\t\n{delta}***End_of_Header***\t\t\t\n"
               "X_Value\tAcc A\tAcc B\tComment\n")


def _lvm(path, rows, x="No", delta="Delta_X\t0.005\t0.005\t\n", segments=1, heading=None):
    segment = LVM_SEGMENT.format(n=len(rows), delta=delta)
    if heading is not None:
        segment = segment.replace("X_Value\tAcc A\tAcc B\tComment\n", heading)
    lead = "\t" if x == "No" else ""  # no X column: the rows start with an empty field
    body = "".join(lead + "\t".join(row) + "\n" for row in rows)
    path.write_text(LVM_HEADER.format(x=x) + "\n".join([segment + body] * segments))
    return path


LVM_ROWS = [[f"{a:.6f}", f"{b:.6f}"] for a, b in zip(A[:8], B[:8])]


def test_lvm_without_a_time_column_takes_delta_x_or_fs(tmp_path):
    path = _lvm(tmp_path / "r.lvm", LVM_ROWS)
    record = read_record(path)
    np.testing.assert_array_equal(record.acc, np.column_stack([A[:8], B[:8]]))
    assert record.dt == 0.005
    assert record.channels["name"].tolist() == ["Acc A", "Acc B"]
    assert record.channels["unit"].tolist() == ["g", "m/s^2"]
    assert read_record(path, fs=100).dt == 0.01
    with pytest.raises(ValueError, match=r"r.lvm: fs must be a finite number > 0, got -1"):
        read_record(path, fs=-1)
    for delta in ("", "Delta_X\t0\t0\t\n", "Delta_X\t\t\t\n"):
        with pytest.raises(ValueError, match=r"r.lvm: no time column and no Delta_X; give the sampling rate"):
            read_record(_lvm(tmp_path / "r.lvm", LVM_ROWS, delta=delta))


def test_lvm_with_a_time_column_and_fs(tmp_path):
    rows = [[f"{0.005 * k:.3f}", *row] for k, row in enumerate(LVM_ROWS)]
    path = _lvm(tmp_path / "r.lvm", rows, x="One")
    assert read_record(path).dt == pytest.approx(0.005, rel=1e-12)
    assert read_record(path, fs=200.0 * (1 + 1e-4)).dt == 1 / (200.0 * (1 + 1e-4))
    # a column the heading does not name is a channel
    record = read_record(_lvm(tmp_path / "r.lvm", rows, x="One", heading="X_Value\tAcc A\n"))
    assert record.channels["name"].tolist() == ["Acc A", "ch2"]
    np.testing.assert_array_equal(record.acc, np.column_stack([A[:8], B[:8]]))


def test_lvm_refusals(tmp_path):
    with pytest.raises(ValueError, match=r"r.lvm: 2 segments; only single-segment LabVIEW files are supported"):
        read_record(_lvm(tmp_path / "r.lvm", LVM_ROWS, segments=2))
    rows = [row.copy() for row in LVM_ROWS]
    rows[2][1] = "x"
    with pytest.raises(ValueError, match=r"r.lvm: data row 3, channel 2 is empty or not a number"):
        read_record(_lvm(tmp_path / "r.lvm", rows))
    with pytest.raises(ValueError, match=r"r.lvm: no data column, only time"):
        read_record(_lvm(tmp_path / "r.lvm", [[f"{0.005 * k:.3f}"] for k in range(8)], x="One"))


def test_lvm_is_read_from_its_text_not_from_a_pickle_beside_it(tmp_path):
    """lvm_read would load <record>.pkl when newer than the record: never a
    pickle (stale, or anyone's) in place of the text."""
    import lvm_read

    path = _lvm(tmp_path / "r.lvm", LVM_ROWS)
    other = _lvm(tmp_path / "other.lvm", LVM_ROWS[:4])
    lvm_read.read(str(other))  # leaves other.lvm.pkl beside it
    (tmp_path / "other.lvm.pkl").rename(tmp_path / "r.lvm.pkl")
    assert read_record(path).acc.shape == (8, 2)
    assert not (tmp_path / "other.lvm.pkl").exists()  # and none written
    read_record(other)
    assert not (tmp_path / "other.lvm.pkl").exists()


# --- UFF data sets 58 ----------------------------------------------------------------------------
def _uff(path, sets):
    import pyuff

    pyuff.UFF(str(path)).write_sets(sets, mode="add")
    return path


def _set58(data, inc=0.01, x=None, spacing=1, complex_data=False, **labels):
    import pyuff

    n = len(data)
    return pyuff.prepare_58(func_type=1, rsp_node=3, rsp_dir=2, ref_node=0, ref_dir=0, ord_data_type=6 if complex_data else 4,
                            num_pts=n, abscissa_spacing=spacing, abscissa_min=0.0, abscissa_inc=inc,
                            abscissa_spec_data_type=17, ordinate_spec_data_type=12, orddenom_spec_data_type=0,
                            data=data, x=inc * np.arange(n) if x is None else x, **labels)


def test_one_uff_set_is_one_channel_with_its_unit_label(tmp_path):
    """pyuff returns one set as a dict, not a list; the unit is the ordinate's
    label (pyuff's NONE where there is none), the name is id1 or ch<n>."""
    path = _uff(tmp_path / "one.uff", [_set58(A[:8], id1="", ordinate_axis_units_lab="m/s^2")])
    record = read_record(path)
    np.testing.assert_allclose(record.acc[:, 0], A[:8], rtol=1e-10)
    assert record.dt == 0.01
    assert record.channels.to_dict("records") == [{"name": "ch1", "node": 3, "direction": 2, "unit": "m/s^2"}]
    path = _uff(tmp_path / "two.uff", [_set58(A[:8], id1="north"), _set58(B[:8], id1="south")])
    assert read_record(path).channels[["name", "unit"]].values.tolist() == [["north", None], ["south", None]]


def test_uff_refusals(tmp_path):
    with pytest.raises(ValueError, match=r"inc.uff: type-58 sets with different abscissa_inc \[0.01, 0.02\]"):
        read_record(_uff(tmp_path / "inc.uff", [_set58(A[:8]), _set58(B[:8], inc=0.02)]))
    with pytest.raises(ValueError, match=r"frf.uff: complex type-58 data \(a spectrum, not a time record\)"):
        read_record(_uff(tmp_path / "frf.uff", [_set58(A[:8] * (1 + 1j), complex_data=True)]))
    nodes = tmp_path / "nodes.uff"
    nodes.write_text("    -1\n    15\n         1         0         0         1 0.0000E+00 0.0000E+00 0.0000E+00\n    -1\n")
    with pytest.raises(ValueError, match=r"nodes.uff: no UFF data set of type 58"):
        read_record(nodes)


def test_uff_abscissa_increments_must_agree_and_uneven_ones_need_fs(tmp_path):
    """The file holds 6 significant digits: 1e-4 apart is another rate."""
    path = _uff(tmp_path / "r.uff", [_set58(A[:8], inc=0.005), _set58(B[:8], inc=0.0050005)])
    with pytest.raises(ValueError, match=r"r.uff: type-58 sets with different abscissa_inc \[0.005, 0.0050005\]"):
        read_record(path)
    uneven = _uff(tmp_path / "uneven.uff", [_set58(A[:8], x=0.01 * np.arange(8) ** 1.1, spacing=0)])
    with pytest.raises(ValueError, match=r"uneven.uff: no sampling rate in the file"):
        read_record(uneven)
    assert read_record(uneven, fs=100).dt == 0.01


# --- read_record ---------------------------------------------------------------------------------
def test_a_socket_is_refused_naming_what_it_is(tmp_path):
    import socket

    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(tmp_path / "r.csv"))
        with pytest.raises(ValueError, match=r"r.csv is a socket, not a record file"):
            read_record(tmp_path / "r.csv", fs=100)


def test_load_record_passes_the_text_options(tmp_path):
    path = _text(tmp_path, ["recorded by x"] + [r.replace(",", "|") for r in _rows(",")])
    acc, dt = load_record(path, delimiter="|", skip_rows=1)
    np.testing.assert_array_equal(acc, np.column_stack([A, B]))
    assert dt == pytest.approx(0.005, rel=1e-12)


@pytest.mark.skipif(not Path("/dev/loop0").exists(), reason="no block device /dev/loop0 here")
def test_a_block_device_is_refused_without_reading_it(tmp_path):
    (tmp_path / "r.csv").symlink_to("/dev/loop0")
    with pytest.raises(ValueError, match=r"r.csv is a block device, not a record file"):
        read_record(tmp_path / "r.csv", fs=100)


def test_a_cell_led_by_a_control_character_that_strip_removes_reads(tmp_path):
    """numpy and float() refuse '\\x1f0.5' (a unit separator); the cell-by-cell pass strips it."""
    rows = _rows(",")
    rows[3] = rows[3].replace(",", ",\x1f", 1)
    _same(read_record(_text(tmp_path, rows)))


@pytest.mark.parametrize("suffix", [".csv", ".txt", ".tsv", ".asc", ".dat", ".TSV"])
def test_every_text_extension_is_read_as_text(tmp_path, suffix):
    _same(read_record(_text(tmp_path, _rows("\t"), "r" + suffix)))


def test_unv_is_uff(tmp_path):
    assert read_record(_uff(tmp_path / "r.unv", [_set58(A[:8])])).acc.shape == (8, 1)


def test_a_measured_record_is_frozen_with_empty_defaults():
    import dataclasses

    from modal.records import MeasuredRecord

    record = MeasuredRecord(np.ones((4, 1)), 0.5)
    assert record.channels.empty and record.path is None and record.fs == 2.0
    assert MeasuredRecord(np.ones((4, 1)), 0.5).channels is not record.channels
    with pytest.raises(dataclasses.FrozenInstanceError):
        record.dt = 1.0


# --- the writers ---------------------------------------------------------------------------------
def test_write_uff58_fields_of_each_set(tmp_path):
    import pyuff

    from modal.records import write_uff58

    acc = np.column_stack([A[:8], B[:8]])
    path = write_uff58(tmp_path / "r.UNV", acc, 0.005)
    sets = pyuff.UFF(str(path)).read_sets()
    assert len(sets) == 2
    for c, s in enumerate(sets):
        got = {k: s[k] for k in ("type", "func_type", "id1", "rsp_node", "rsp_dir", "ref_node", "ref_dir", "ord_data_type",
                                 "num_pts", "abscissa_spacing", "abscissa_min", "abscissa_inc",
                                 "abscissa_spec_data_type", "ordinate_spec_data_type", "orddenom_spec_data_type")}
        assert got == {"type": 58, "func_type": 1, "id1": f"acceleration channel {c + 1}", "rsp_node": c + 1, "rsp_dir": 3,
                       "ref_node": 0, "ref_dir": 0, "ord_data_type": 4, "num_pts": 8, "abscissa_spacing": 1,
                       "abscissa_min": 0.0, "abscissa_inc": 0.005, "abscissa_spec_data_type": 17,
                       "ordinate_spec_data_type": 12, "orddenom_spec_data_type": 0}
        np.testing.assert_allclose(s["data"], acc[:, c], rtol=1e-10)
    assert write_uff58(tmp_path / "r.uff", acc, 0.005).suffix == ".uff"
    write_uff58(tmp_path / "r.uff", acc[:, :1], 0.005)  # overwritten, not appended to
    assert read_record(tmp_path / "r.uff").acc.shape == (8, 1)


@pytest.mark.parametrize("writer, name, message", [
    ("write_uff58", "r.txt", r"path must end in .uff or .unv, got 'r.txt'"),
    ("write_uff58", "r.uff", r"dt must be a finite number > 0, got 0"),
    ("save_record_npz", "r.npy", r"path must end in .npz, got 'r.npy'"),
    ("save_record_npz", "r.npz", r"dt must be a finite number > 0, got 0"),
])
def test_writers_name_what_they_refuse(tmp_path, writer, name, message):
    import modal.records

    with pytest.raises(ValueError, match=message):
        getattr(modal.records, writer)(tmp_path / name, np.ones((4, 1)), 0 if "dt" in message else 0.01)
    assert not (tmp_path / name).exists()


def test_save_record_npz_takes_an_upper_case_extension(tmp_path):
    from modal.records import save_record_npz

    path = save_record_npz(tmp_path / "r.NPZ", np.ones((4, 1)), 0.01)
    assert read_record(path).dt == 0.01


def test_empty_and_cut_short_numpy_files_are_refused_naming_the_file(tmp_path):
    """np.load raises EOFError on an empty file and BadZipFile on a .npz cut
    short: a ValueError naming the file, as for every other bad record."""
    np.savez(tmp_path / "whole.npz", acc=np.ones((100, 2)), dt=0.01)
    whole = (tmp_path / "whole.npz").read_bytes()
    (tmp_path / "cut.npz").write_bytes(whole[: len(whole) // 2])
    (tmp_path / "empty.npy").write_bytes(b"")
    (tmp_path / "empty.npz").write_bytes(b"")
    for name, why in (("cut.npz", "File is not a zip file"), ("empty.npy", "No data left in file"),
                      ("empty.npz", "No data left in file")):
        with pytest.raises(ValueError, match=rf"^{tmp_path / name}: cannot be read as \.np[yz] \({why}\)$"):
            read_record(tmp_path / name, fs=100 if name.endswith(".npy") else None)


def test_a_message_names_the_file_once(tmp_path):
    np.save(tmp_path / "r.npy", np.ones((4, 1)))
    with pytest.raises(ValueError, match=rf"^{tmp_path / 'r.npy'}: no sampling rate in the file"):
        read_record(tmp_path / "r.npy")
    with pytest.raises(ValueError, match=rf"^{tmp_path / 'r.npy'}: acc needs at least 2 samples, got 1$"):
        np.save(tmp_path / "r.npy", np.ones((1, 1)))
        read_record(tmp_path / "r.npy", fs=10)


@pytest.mark.parametrize("label", ["", "none", "NONE"])
def test_a_uff_unit_label_that_is_blank_or_none_is_no_unit(tmp_path, label):
    path = _uff(tmp_path / "r.uff", [_set58(A[:8], ordinate_axis_units_lab=label)])
    assert read_record(path).channels["unit"].tolist() == [None]


def test_lvm_delta_x_is_the_first_channels(tmp_path):
    for second in ("", "-1", "0.01"):
        assert read_record(_lvm(tmp_path / "r.lvm", LVM_ROWS, delta=f"Delta_X\t0.005\t{second}\t\n")).dt == 0.005
