"""read_record refuses what is not a record file of real numbers, at once and
with a message naming the file, instead of blocking, reading forever, or
turning dates into "accelerations"."""

import os
import re
import subprocess
import sys

import numpy as np
import pytest

import modal


def _refused(path, match, **options):
    with pytest.raises(ValueError, match=match):
        modal.read_record(path, **options)


@pytest.mark.parametrize("suffix", [".npy", ".csv"])
def test_fifo_is_refused_without_blocking(tmp_path, suffix):
    fifo = tmp_path / f"record{suffix}"
    os.mkfifo(fifo)
    # in a child process, so that a regression blocks the child, not the test run
    code = f"import modal\ntry:\n    modal.read_record({str(fifo)!r}, fs=100)\nexcept ValueError as e:\n    print(e)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert "is a FIFO (named pipe), not a record file" in run.stdout
    assert str(fifo) in run.stdout


def test_directory_is_refused(tmp_path):
    """A folder (of setups, or one named like a record) is no record: the
    message says how setups are given."""
    for name in ("record.npy", "setups"):
        folder = tmp_path / name
        folder.mkdir()
        _refused(folder, rf"{name} is a folder, not a record file .* given one by one, e\.g\. .*{name}/\*\)", fs=100)


# --- records read short: never fewer rows or channels in silence -------------------
def test_csv_whose_last_row_is_cut_short_is_refused_naming_the_row(tmp_path):
    """The delimiter is the one of most rows, so the short last row is named,
    not mistaken for a whitespace-separated file."""
    rows = "\n".join(f"{0.01 * i:.2f},{np.sin(i):.6f},{np.cos(i):.6f}" for i in range(200))
    path = tmp_path / "r.csv"
    path.write_text("time,a,b\n" + rows + "\n1.99,0.5\n")
    _refused(path, r"row 202 has 2 values separated by ',', row 2 has 3 \(the last row: is the file cut short\?\)")
    path.write_text("time,a,b\n" + rows + "\n")
    assert modal.read_record(path).acc.shape == (200, 2)


@pytest.mark.parametrize("binary", [False, True])
def test_uff_cut_short_is_refused_not_read_as_fewer_channels(tmp_path, binary):
    acc = np.random.default_rng(3).standard_normal((500, 4))
    whole = modal.records.write_uff58(tmp_path / "whole.uff", acc, 0.01, binary=binary).read_bytes()
    assert modal.read_record(tmp_path / "whole.uff").acc.shape == (500, 4)
    for fraction in (0.6, 0.9, 0.99):
        cut = tmp_path / f"cut_{fraction}.uff"
        cut.write_bytes(whole[: int(fraction * len(whole))])
        complete = int(fraction * 4)  # the next one begun, not ended
        _refused(cut, rf"cut_{fraction}.uff: {complete + 1} data sets of type 58 begin but only {complete} are complete: "
                      r"is the file cut short\?")


def test_corrupt_uff_is_refused_naming_the_file(tmp_path):
    """pyuff raises a bare Exception on a malformed set: a ValueError naming the file."""
    path = tmp_path / "bad.uff"
    text = modal.records.write_uff58(tmp_path / "ok.uff", np.ones((50, 1)), 0.01).read_text()
    lines = text.splitlines()
    lines[7] = "not a number line"  # inside the set's header records
    path.write_text("\n".join(lines) + "\n")
    _refused(path, r"bad.uff: not a readable UFF file \(")


def test_lvm_with_fewer_rows_than_its_header_says_is_refused(tmp_path):
    header = ("LabVIEW Measurement\t\nWriter_Version\t2\nReader_Version\t2\nSeparator\tTab\nDecimal_Separator\t.\n"
              "Multi_Headings\tNo\nX_Columns\tOne\nTime_Pref\tRelative\nOperator\tx\n***End_of_Header***\t\n\t\n"
              "Channels\t1\t\nSamples\t{n}\t\nY_Unit_Label\tg\t\nX_Dimension\tTime\t\nX0\t0.0000000000000000E+0\t\n"
              "Delta_X\t0.01\t\n***End_of_Header***\t\t\nX_Value\tAcceleration\tComment\n")
    body = "".join(f"{0.01 * i:.2f}\t{np.sin(i):.6E}\n" for i in range(64))
    path = tmp_path / "r.lvm"
    path.write_text(header.format(n=64) + body)
    assert modal.read_record(path).acc.shape == (64, 1)
    path.write_text(header.format(n=81920) + body)
    _refused(path, r"r.lvm: the header says 81920 samples, the file holds 64 rows: is the file cut short\?")


def test_npy_without_a_rate_says_how_to_give_it(tmp_path):
    np.save(tmp_path / "r.npy", np.ones((10, 2)))
    _refused(tmp_path / "r.npy", r"r.npy: no sampling rate in the file; give the sampling rate: fs=<Hz> "
                                 r"\(on the command line --fs <Hz>\)")


def test_device_is_refused_without_reading_it(tmp_path):
    """/dev/zero never ends: reading it as text would fill the memory."""
    link = tmp_path / "record.csv"
    link.symlink_to("/dev/zero")
    code = f"import modal\ntry:\n    modal.read_record({str(link)!r}, fs=100)\nexcept ValueError as e:\n    print(e)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert "record.csv is a character device, not a record file" in run.stdout


@pytest.mark.parametrize("dtype", ["datetime64[s]", "timedelta64[ms]", "bool", "U8", "complex128"])
def test_non_numeric_npy_is_refused(tmp_path, dtype):
    path = tmp_path / "record.npy"
    values = np.arange(3000).reshape(1000, 3)
    np.save(path, values.astype(dtype) if dtype != "bool" else values % 2 == 0)
    _refused(path, re.escape(f"record.npy: acc must hold real numbers, got dtype {np.dtype(dtype)}"), fs=100)


def test_non_numeric_npz_is_refused(tmp_path):
    path = tmp_path / "record.npz"
    np.savez(path, acc=np.arange(3000).reshape(1000, 3).astype("datetime64[D]"), dt=0.01)
    _refused(path, "record.npz: acc must hold real numbers, got dtype datetime64", fs=None)


def test_csv_header_names_the_channels(tmp_path):
    path = tmp_path / "named.csv"
    t = np.arange(50) * 0.01
    rows = "\n".join(f"{v:.2f},{np.sin(v):.6f},{np.cos(v):.6f}" for v in t)
    path.write_text("time,north deck,south deck\ns,m/s2,m/s2\n" + rows + "\n")
    record = modal.read_record(path)
    assert record.channels["name"].tolist() == ["north deck", "south deck"]
    assert record.acc.shape == (50, 2)
