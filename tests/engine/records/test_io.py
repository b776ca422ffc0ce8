"""Record input/output (modal.io): round trips and bad files."""

import numpy as np
import pytest

from modal.records import load_record, read_record, save_record_npz, write_uff58

DT = 1 / 200


@pytest.fixture
def acc():
    rng = np.random.default_rng(3)
    return rng.standard_normal((64, 3))


def test_npz_round_trip(tmp_path, acc):
    path = save_record_npz(tmp_path / "rec.npz", acc, DT)
    got, dt = load_record(path)
    np.testing.assert_array_equal(got, acc)
    assert dt == DT


def test_npz_alternative_keys(tmp_path, acc):
    np.savez(tmp_path / "y.npz", y=acc[:, 0], fs=200.0)
    got, dt = load_record(tmp_path / "y.npz")
    assert got.shape == (64, 1)
    assert dt == pytest.approx(DT, rel=1e-15)
    np.savez(tmp_path / "nofs.npz", acc=acc)
    got, dt = load_record(tmp_path / "nofs.npz", fs=200)
    assert dt == pytest.approx(DT)


def test_csv_with_time_column_and_header(tmp_path, acc):
    t = DT * np.arange(acc.shape[0])
    path = tmp_path / "rec.csv"
    np.savetxt(path, np.column_stack([t, acc]), delimiter=",", header="t,a1,a2,a3", comments="", fmt="%.17g")
    got, dt = load_record(path)
    np.testing.assert_array_equal(got, acc)
    assert dt == pytest.approx(DT, rel=1e-12)


def test_csv_with_given_fs(tmp_path, acc):
    path = tmp_path / "rec.csv"
    np.savetxt(path, acc, delimiter=",", fmt="%.17g")
    got, dt = load_record(path, fs=200)
    np.testing.assert_array_equal(got, acc)
    assert dt == pytest.approx(DT)


@pytest.mark.parametrize("binary", [False, True])
def test_uff58_round_trip(tmp_path, acc, binary):
    path = write_uff58(tmp_path / "rec.uff", acc, DT, binary=binary)
    got, dt = load_record(path)
    assert got.shape == acc.shape
    np.testing.assert_allclose(got, acc, rtol=0 if binary else 1e-10, atol=0 if binary else 1e-11)
    assert dt == pytest.approx(DT, rel=1e-12)


def test_bad_files(tmp_path, acc):
    bad = acc.copy()
    bad[5, 1] = np.nan
    np.savez(tmp_path / "nan.npz", acc=bad, dt=DT)
    with pytest.raises(ValueError, match="NaN"):
        load_record(tmp_path / "nan.npz")
    np.savez(tmp_path / "nofs.npz", acc=acc)
    with pytest.raises(ValueError, match="sampling rate"):
        load_record(tmp_path / "nofs.npz")
    np.savez(tmp_path / "both.npz", acc=acc, dt=DT)
    with pytest.raises(ValueError, match="contradicts"):
        load_record(tmp_path / "both.npz", fs=100)
    (tmp_path / "rec.xls").write_text("1,2\n3,4\n")
    with pytest.raises(ValueError, match="unknown record format"):
        load_record(tmp_path / "rec.xls")
    (tmp_path / "ragged.csv").write_text("0,1,2\n0.005,3\n0.01,5,6\n")
    with pytest.raises(ValueError, match="unequal"):
        load_record(tmp_path / "ragged.csv")
    (tmp_path / "hole.csv").write_text("0,1,2\n0.005,,4\n0.01,5,6\n")
    with pytest.raises(ValueError, match=r"hole.csv: row 2, column 2 is empty"):
        load_record(tmp_path / "hole.csv")
    (tmp_path / "jitter.csv").write_text("0,1\n0.005,2\n0.013,3\n")
    with pytest.raises(ValueError, match="uniformly"):
        load_record(tmp_path / "jitter.csv")
    with pytest.raises(ValueError, match="does not exist"):
        load_record(tmp_path / "missing.npz")


def test_uff_unequal_lengths(tmp_path, acc):
    import pyuff

    path = write_uff58(tmp_path / "a.uff", acc, DT)
    short = write_uff58(tmp_path / "b.uff", acc[:10, :1], DT)
    sets = pyuff.UFF(str(path)).read_sets() + [pyuff.UFF(str(short)).read_sets()]
    for s in sets:
        s.setdefault("orddenom_spec_data_type", 0)
    mixed = tmp_path / "mixed.uff"
    pyuff.UFF(str(mixed)).write_sets(sets, mode="overwrite")
    with pytest.raises(ValueError, match="unequal length"):
        load_record(mixed)


def test_writers_reject_bad_input(tmp_path, acc):
    with pytest.raises(ValueError, match="dt"):
        save_record_npz(tmp_path / "x.npz", acc, 0.0)
    with pytest.raises(ValueError, match="NaN"):
        write_uff58(tmp_path / "x.uff", np.full((4, 1), np.nan), DT)
    with pytest.raises(ValueError, match="nodes"):
        write_uff58(tmp_path / "x.uff", acc, DT, nodes=[1])


# Real-world text exports and binary arrays (issue 10).

FS_NI = 51200 / 31  # an NI-9234 rate: 1651.6129 Hz, dt printed as 0.000605


def _printed_time(n, dt, decimals):
    return [f"{t:.{decimals}f}" for t in dt * np.arange(n)]


def test_csv_printed_time_semicolons_decimal_commas_units_row(tmp_path, acc):
    times = _printed_time(len(acc), 1 / FS_NI, 6)
    lines = ["time;a1;a2;a3", "s;g;g;g"] + [
        ";".join([t] + [f"{v:.6f}".replace(".", ",") for v in row]) for t, row in zip(times, acc)
    ]
    path = tmp_path / "export.csv"
    path.write_text("\n".join(lines) + "\n")
    got, dt = load_record(path, decimal=",")
    np.testing.assert_allclose(got, acc, atol=5e-7)
    # The printed steps are 605 and 606 us; the mean over the column recovers the rate.
    assert 1 / dt == pytest.approx(FS_NI, rel=2e-4)


def test_decimal_commas_are_read_without_being_told_where_only_they_read(tmp_path, acc):
    """A European spreadsheet's export (semicolons, decimal commas, a header)
    reads as with ``decimal=','`` when no decimal mark is given; with
    ``decimal='.'`` given it is refused as before. A comma-separated file
    with decimal points stays one of points (three channels, not a comma
    read as a decimal mark), and a file neither reads gives the point's
    error."""
    times = _printed_time(len(acc), 0.01, 2)
    european = tmp_path / "export.csv"
    european.write_text("\n".join(["t;a1;a2;a3"] + [";".join([t.replace(".", ",")] + [f"{v:.6f}".replace(".", ",")
                                                                                    for v in row])
                                                     for t, row in zip(times, acc)]) + "\n")
    auto, told = read_record(european), read_record(european, decimal=",")
    np.testing.assert_array_equal(auto.acc, told.acc)
    assert auto.dt == told.dt == pytest.approx(0.01) and list(auto.channels["name"]) == ["a1", "a2", "a3"]
    np.testing.assert_allclose(auto.acc, acc, atol=5e-7)
    with pytest.raises(ValueError, match=r"fewer than 2 rows of numbers \(delimiter ',', decimal '\.'\)"):
        read_record(european, decimal=".")
    points = tmp_path / "points.csv"
    points.write_text("\n".join(",".join([t] + [f"{v:.6f}" for v in row]) for t, row in zip(times, acc)) + "\n")
    assert read_record(points).acc.shape == acc.shape
    neither = tmp_path / "neither.csv"
    neither.write_text("t;a\n0;x\n1;y\n")
    with pytest.raises(ValueError, match=r"decimal '\.'"):
        read_record(neither)


def test_text_tabs_skip_rows_and_fs_overrides_time_column(tmp_path, acc):
    times = _printed_time(len(acc), 1 / 256, 6)  # %.6f at 256 Hz
    body = ["\t".join([t] + [repr(float(v)) for v in row]) for t, row in zip(times, acc)]
    path = tmp_path / "tabs.txt"
    path.write_text("recorded 2026-01-01\noperator x\n" + "\n".join(body) + "\n")
    got, dt = load_record(path, skip_rows=2)
    np.testing.assert_array_equal(got, acc)
    assert dt == pytest.approx(1 / 256, abs=1e-6 / (len(acc) - 1))  # one printed digit over the span
    # With fs the time column is still not a channel, and fs sets the rate.
    with pytest.warns(UserWarning, match="overrides"):
        got, dt = load_record(path, fs=250, skip_rows=2)
    assert got.shape == acc.shape and dt == 1 / 250


def test_numeric_header_row_is_not_sample_zero(tmp_path, acc):
    t = DT * np.arange(len(acc))
    path = tmp_path / "nodes.csv"
    rows = ["0,101,102,103"] + [",".join(f"{v:.9f}" for v in [ti, *row]) for ti, row in zip(t, acc)]
    path.write_text("\n".join(rows) + "\n")
    got, dt = load_record(path)
    assert got.shape == acc.shape
    np.testing.assert_allclose(got, acc, atol=1e-9)
    assert dt == pytest.approx(DT)
    # Without a time column: node ids far above every sample.
    path.write_text("\n".join(["101,102,103"] + [",".join(f"{v:.9f}" for v in row) for row in acc]) + "\n")
    got, _ = load_record(path, fs=200)
    assert got.shape == acc.shape


def test_text_errors_name_file_row_and_column(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("t,a,b\n0.0,1.0,2.0\n0.005,x,4.0\n0.01,5.0,6.0\n")
    with pytest.raises(ValueError, match=r"bad.csv: row 3, column 2: 'x' is not a finite number"):
        load_record(path)
    path.write_text("0.0;1,5\n0.005;2,5\n0.01;3,5\n")
    with pytest.raises(ValueError, match=r"bad.csv: .*pass delimiter=, decimal="):
        load_record(path, delimiter=";", decimal=".")
    np.testing.assert_array_equal(load_record(path, delimiter=";")[0], [[1.5], [2.5], [3.5]])  # only commas read it


def test_npy_needs_fs_and_refuses_channels_first(tmp_path, acc):
    path = tmp_path / "rec.npy"
    np.save(path, acc.astype(np.float32))
    with pytest.raises(ValueError, match=r"rec.npy: no sampling rate.*fs=<Hz>"):
        load_record(path)
    got, dt = load_record(path, fs=200)
    np.testing.assert_allclose(got, acc, rtol=1e-6)
    assert got.dtype == float and dt == pytest.approx(DT)
    np.save(path, acc.T)
    with pytest.raises(ValueError, match=r"rec.npy: .*transposed.*acc.T"):
        load_record(path, fs=200)


def test_npz_boolean_dt_refused(tmp_path, acc):
    np.savez(tmp_path / "b.npz", acc=acc, dt=True)
    with pytest.raises(ValueError, match=r"b.npz: dt must be one positive number"):
        load_record(tmp_path / "b.npz")


def test_uff_keeps_node_direction_units(tmp_path, acc):

    path = write_uff58(tmp_path / "rec.uff", acc, DT, nodes=[11, 12, 17], direction=2)
    record = read_record(path)
    assert record.channels["node"].tolist() == [11, 12, 17]
    assert record.channels["direction"].tolist() == [2, 2, 2]
    assert record.channels["name"].tolist() == [f"acceleration channel {c}" for c in (1, 2, 3)]


def test_lvm_multi_x_columns(tmp_path, acc):

    header = (
        "LabVIEW Measurement\t\nWriter_Version\t2\nReader_Version\t2\nSeparator\tTab\nDecimal_Separator\t.\n"
        "Multi_Headings\tYes\nX_Columns\tMulti\nTime_Pref\tAbsolute\nOperator\tx\n***End_of_Header***\t\n\t\n"
        "Channels\t1\t\nSamples\t64\t\nY_Unit_Label\tg\t\nX_Dimension\tTime\t\nX0\t0.0000000000000000E+0\t\n"
        "Delta_X\t0.000605\t\n***End_of_Header***\t\t\nX_Value\tAcceleration\tComment\n"
    )
    times = _printed_time(len(acc), 1 / FS_NI, 6)
    body = "".join(f"{t}\t{v:.6E}\n" for t, v in zip(times, acc[:, 0]))
    path = tmp_path / "rec.lvm"
    path.write_text(header + body)
    record = read_record(path)
    assert record.acc.shape == (64, 1)
    np.testing.assert_allclose(record.acc[:, 0], acc[:, 0], rtol=1e-6)
    assert record.channels["unit"].tolist() == ["g"]
    assert record.fs == pytest.approx(FS_NI, rel=2e-4)  # not the rounded Delta_X's 1652.9 Hz
    assert not (tmp_path / "rec.lvm.pkl").exists()


def _asc(path, header, table, fmt="%.10e", gap="   "):
    """An .asc export: header lines, then columns separated by runs of spaces and tabs."""
    lines = [*header, *(gap.join(fmt % v for v in row) + "\t" for row in table)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_asc_reads_as_the_same_csv(tmp_path, acc):
    """A whitespace-separated .asc record with header lines (title, names,
    units) gives exactly the arrays, rate and channel names of the same data
    as CSV."""
    t = DT * np.arange(acc.shape[0])
    table = np.column_stack([t, acc])
    asc = _asc(tmp_path / "ambient.asc", ["# Ambient vibration test of building A", "Time  acc_1  acc_2  acc_3", "s  g  g  g"],
               table, fmt="%.17g")
    csv = tmp_path / "ambient.csv"
    np.savetxt(csv, table, delimiter=",", header="Time,acc_1,acc_2,acc_3", comments="", fmt="%.17g")
    from_asc, from_csv = read_record(asc), read_record(csv)
    np.testing.assert_array_equal(from_asc.acc, from_csv.acc)
    np.testing.assert_array_equal(from_asc.acc, acc)
    assert from_asc.dt == from_csv.dt == pytest.approx(DT, rel=1e-12)
    assert list(from_asc.channels["name"]) == ["acc_1", "acc_2", "acc_3"]
    dat = _asc(tmp_path / "ambient.dat", [], acc, gap="\t \t")
    got, dt = load_record(dat, fs=200)
    np.testing.assert_allclose(got, acc, rtol=1e-10)


@pytest.mark.parametrize("where, message", [
    (10, r"row 13 has 3 whitespace-separated values, row 3 has 4: every row must hold one value per column"),
    (63, r"row 66 has 3 whitespace-separated values, row 3 has 4 \(the last row: is the file cut short\?\)"),
])
def test_ragged_asc_is_refused_naming_the_row(tmp_path, acc, where, message):
    t = DT * np.arange(acc.shape[0])
    path = _asc(tmp_path / "ragged.asc", ["Time acc_1 acc_2 acc_3", "s g g g"], np.column_stack([t, acc]))
    lines = path.read_text().splitlines()
    lines[2 + where] = " ".join(lines[2 + where].split()[:3])  # one value missing (1-based line 3 + where)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=f"ragged.asc: ragged rows \\(channels of unequal length\\): {message}"):
        read_record(path)


def test_a_bad_cell_is_named_also_when_the_rest_is_numbers(tmp_path, acc):
    """The table is parsed at once when every cell is a number; one that is
    not (or NaN) still gets its row and column named."""
    path = _asc(tmp_path / "bad.asc", [], acc)
    lines = path.read_text().splitlines()
    cells = lines[40].split()
    lines[40] = "  ".join([cells[0], "nan", cells[2]])
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"row 41, column 2: 'nan' is not a finite number"):
        read_record(path, fs=200)


def _timed(tmp_path, name, header, time, acc):
    path = tmp_path / name
    path.write_text(header + "".join(",".join(repr(float(v)) for v in (t, *row)) + "\n" for t, row in zip(time, acc)))
    return path


@pytest.mark.parametrize("header, per_second", [
    ("t_ms,a,b,c\n", 1e3), ("Time [ms],a,b,c\n", 1e3), ("time,a,b,c\nms,g,g,g\n", 1e3), ("Zeit/ms,a,b,c\n", 1e3),
    ("Time (µs),a,b,c\n", 1e6), ("time [min],a,b,c\n", 1 / 60), ("t,a,b,c\n[s],g,g,g\n", 1.0), ("Time [s],a,b,c\n", 1.0),
])
def test_a_time_column_in_ms_or_min_is_read_in_seconds(tmp_path, acc, header, per_second):
    """A time column whose header names its unit is scaled to seconds: a
    millisecond column read as seconds made every frequency 1000 times too
    low, silently."""
    record = read_record(_timed(tmp_path, "r.csv", header, DT * np.arange(len(acc)) * per_second, acc))
    assert record.dt == pytest.approx(DT, rel=1e-12)
    np.testing.assert_array_equal(record.acc, acc)


def test_a_sample_counter_or_an_unknown_time_unit_needs_fs(tmp_path, acc):
    """A first column that counts samples, or holds time in a unit not known,
    gives no rate: refused without fs (its step of 1 would read as 1 Hz),
    dropped with it; the rate is fs."""
    for name, header in (("n.csv", "Sample,a,b,c\n"), ("k.csv", "Time [ticks],a,b,c\n")):
        path = _timed(tmp_path, name, header, np.arange(len(acc)), acc)
        with pytest.raises(ValueError, match=rf"{name}: column 1 \('(Sample|Time \[ticks\])'\) (counts samples|holds "
                                             r"time in a unit other than h, min, ms, s, us): give the sampling rate"):
            read_record(path)
        record = read_record(path, fs=200)
        assert record.dt == DT
        np.testing.assert_array_equal(record.acc, acc)


def test_a_gap_in_the_time_column_is_located_and_a_named_time_column_is_never_data(tmp_path, acc):
    """A record with a gap is refused with where the gap is; a column the
    header names time is refused with fs too (before, fs read it as a
    channel); a first column not named time stays data with fs, even one
    named ``T`` (transverse) that is not uniform."""
    time = DT * np.arange(len(acc))
    time[30:] += 0.5  # 100 samples missing after t = 0.145 s
    where = r"the step after t = 0.145 \(data row 30\) is 0.505 against a median of 0.005"
    named = _timed(tmp_path, "named.csv", "Time [s],a,b,c\n", time, acc)
    for fs in (None, 200):
        with pytest.raises(ValueError, match=rf"named.csv: .*not uniformly increasing: {where}; the record is not "
                                             "evenly sampled there"):
            read_record(named, fs=fs)
    for name, header in (("plain.csv", ""), ("transverse.csv", "T,a,b,c\n")):
        path = _timed(tmp_path, name, header, time, acc)
        with pytest.raises(ValueError, match=rf"{name}: .*{where}; a gap or a drifting clock\? .*pass fs \(--fs\)"):
            read_record(path)
        record = read_record(path, fs=200)
        assert record.acc.shape == (len(acc), 4)
        np.testing.assert_array_equal(record.acc[:, 0], time)
    counter = _timed(tmp_path, "counter.csv", "Sample,a,b,c\n", time / DT, acc)
    with pytest.raises(ValueError, match=r"counter.csv: .*the step after t = 29 \(data row 30\) is 101 against"):
        read_record(counter, fs=200)
    restart = DT * np.arange(len(acc))
    restart[40:] -= 0.1  # the clock set back: the step that departs most is negative
    with pytest.raises(ValueError, match=r"the step after t = 0.195 \(data row 40\) is -0.095 against a median of 0.005"):
        read_record(_timed(tmp_path, "restart.csv", "time,a,b,c\n", restart, acc))


def test_a_first_channel_named_like_a_unit_is_data(tmp_path, acc):
    """A unit in a units row counts for the time column only below a name
    that says time: a first channel named ``H`` (horizontal) or ``S`` is
    data, read with fs, and not a time in hours or seconds with a gap."""
    data = np.column_stack([np.cos(np.arange(len(acc))), acc])
    for header in ("H,a,b,c\n", "S,a,b,c\n", "h,a,b,c\nm/s2,m/s2,m/s2,m/s2\n", "x,a,b,c\nms,g,g,g\n"):
        path = tmp_path / "channels.csv"
        path.write_text(header + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in data))
        record = read_record(path, fs=200)
        assert record.acc.shape == (len(acc), 4) and record.dt == DT, header
        np.testing.assert_array_equal(record.acc, data)
