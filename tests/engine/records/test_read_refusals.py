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
    folder = tmp_path / "record.npy"
    folder.mkdir()
    _refused(folder, "record.npy is a directory, not a record file", fs=100)


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
