"""`modal identify` on what it must refuse: every failure ends with a
documented exit code and one line on stderr, never a traceback, and never
with a half-written or clobbered results folder."""

import json
import os
import resource
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
from modal.cli import main

# the documented exit codes (modal.cli's docstring and --help)
EXIT_BAD_OPTIONS, EXIT_BAD_FILE, EXIT_CANNOT_IDENTIFY, EXIT_NO_MODES, EXIT_CANNOT_WRITE = 2, 3, 4, 5, 6

PALISADEN = Path(__file__).resolve().parents[2] / "data" / "palisaden_20hz_30min.npy"
PALISADEN_OPTIONS = ["--fs", "20", "--ambient", "--fmax", "5", "--highpass", "0.5", "--channels", "0,1,2,3,4,5",
                     "--refs", "0,1,2,3", "--quiet"]


def _run(capsys, *argv):
    """main(argv) -> (exit code, stdout, stderr), checking the stderr contract."""
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def _one_line(err):
    """The message: one line (progress lines, "[  1.2 s] ...", aside)."""
    lines = [line for line in err.splitlines() if line.strip() and not line.startswith("[")]
    assert len(lines) == 1, err
    return lines[0]


def _cli(*argv, timeout=120, preexec_fn=None, cwd=None):
    """``python -m modal`` in a child process (a hang or a crash stays there)."""
    return subprocess.run([sys.executable, "-m", "modal", *map(str, argv)], capture_output=True, text=True,
                          timeout=timeout, preexec_fn=preexec_fn, cwd=cwd)


@pytest.fixture
def noise(tmp_path):
    path = tmp_path / "noise.npy"
    np.save(path, np.random.default_rng(0).standard_normal((4000, 3)))
    return path


def _no_partial_files(folder: Path):
    hidden = [p.name for p in folder.iterdir() if p.name.startswith(".") or p.name.endswith(".partial")]
    assert hidden == []


# --- the output folder ---------------------------------------------------------------------------------------


def test_out_naming_the_input_is_refused_and_the_record_kept(capsys, noise):
    before = noise.read_bytes()
    code, _, err = _run(capsys, "identify", noise, "--fs", 100, "--ambient", "--out", noise)
    assert code == EXIT_BAD_OPTIONS
    assert "is the input" in _one_line(err)
    assert noise.read_bytes() == before


@pytest.mark.parametrize("name", ["modes.csv", "record.npy"])
def test_out_holding_the_input_is_refused(capsys, tmp_path, name):
    """The folder of the record is refused, whether or not a result bears the
    record's name: results and data never share a folder (issue 33)."""
    record = tmp_path / name  # modes.csv: a record that happens to bear a result's name
    t = np.arange(2000) / 100
    if name.endswith(".csv"):
        record.write_text("t,a,b\n" + "\n".join(f"{v:.2f},{np.sin(7 * v):.6f},{np.cos(3 * v):.6f}" for v in t))
    else:
        np.save(record, np.random.default_rng(0).standard_normal((4000, 3)))
    before = record.read_bytes()
    code, _, err = _run(capsys, "identify", record, "--fs", 100, "--ambient", "--out", tmp_path)
    assert code == EXIT_BAD_OPTIONS
    assert "holds the input" in _one_line(err)
    assert record.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


@pytest.mark.parametrize("out, why", [("/dev/null/x", "/dev/null is a device, not a folder"),
                                      ("/proc/version", "exists and is a file, not a folder")])
def test_out_that_cannot_be_a_folder_is_refused(capsys, noise, out, why):
    if not Path(out).parent.exists():
        pytest.skip(f"{Path(out).parent} does not exist here")
    code, _, err = _run(capsys, "identify", noise, "--fs", 100, "--ambient", "--out", out)
    assert code == EXIT_BAD_OPTIONS
    assert why in _one_line(err)


@pytest.mark.parametrize("folder", ["/proc", "/sys"])
def test_out_where_nothing_can_be_created_is_refused(capsys, noise, folder):
    """Even root cannot make a folder in /proc or /sys: refused before any work."""
    if not Path(folder).is_dir():
        pytest.skip(f"no {folder} here")
    out = Path(folder) / "modal-identify-results"
    code, _, err = _run(capsys, "identify", noise, "--fs", 100, "--ambient", "--out", out)
    assert code == EXIT_BAD_OPTIONS
    assert f"cannot create the results folder {out}" in _one_line(err) or "not writable" in err
    assert not out.exists()


def _small_file_limit():
    """In the child: files may not grow beyond 2000 bytes (modes.csv fits,
    poles.csv does not), and writing more fails with an OSError (EFBIG)
    instead of killing the process: a disk that fills up part-way."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))


@pytest.mark.slow
def test_failure_part_way_leaves_the_previous_results_untouched(tmp_path):
    out = tmp_path / "results"
    out.mkdir()
    previous = {"modes.csv": b"mode,freq_hz\n1,1.88\n", "poles.csv": b"order\n2\n", "notes.txt": b"mine\n"}
    for name, content in previous.items():
        (out / name).write_bytes(content)
    run = _cli("identify", PALISADEN, *PALISADEN_OPTIONS, "--out", out, preexec_fn=_small_file_limit)
    assert run.returncode == EXIT_CANNOT_WRITE, run.stderr
    assert "Traceback" not in run.stderr
    assert f"cannot write the results to {out}" in _one_line(run.stderr)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == previous
    _no_partial_files(tmp_path)


@pytest.mark.slow
def test_failure_part_way_creates_no_folder(tmp_path):
    out = tmp_path / "new" / "results"
    run = _cli("identify", PALISADEN, *PALISADEN_OPTIONS, "--out", out, preexec_fn=_small_file_limit)
    assert run.returncode == EXIT_CANNOT_WRITE, run.stderr
    assert not (tmp_path / "new").exists()
    _no_partial_files(tmp_path)


def test_write_identification_full_disk_keeps_previous_results(tmp_path, monkeypatch):
    """The workflow calls write_identification: a full disk while the diagram
    is saved raises OSError and leaves the folder as it was."""
    import errno

    from matplotlib.figure import Figure

    out = tmp_path / "measured"
    out.mkdir()
    (out / "modes.csv").write_text("old\n")

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(Figure, "savefig", full)
    record = modal.read_record(PALISADEN, fs=20)
    with pytest.raises(OSError, match="No space left"):
        modal.write_identification(record, out, "ambient", channels=range(6), refs=[0, 1, 2, 3], fmax=5,
                                   highpass_hz=0.5)
    assert [p.name for p in out.iterdir()] == ["modes.csv"] and (out / "modes.csv").read_text() == "old\n"
    _no_partial_files(tmp_path)


@pytest.mark.slow
def test_complete_results_replace_the_previous_ones(tmp_path, capsys):
    out = tmp_path / "results"
    out.mkdir()
    (out / "modes.csv").write_text("old\n")
    (out / "notes.txt").write_text("mine\n")
    code, _, _ = _run(capsys, "identify", PALISADEN, *PALISADEN_OPTIONS, "--out", out)
    assert code == 0
    assert sorted(p.name for p in out.iterdir()) == ["candidates.csv", "complex_shapes.csv", "mac.csv", "mac.png",
                                                     "modes.csv", "notes.txt", "poles.csv", "report.html",
                                                     "settings.json", "singular_values.csv", "stabilisation.png"]
    assert len(pd.read_csv(out / "modes.csv")) >= 3
    settings = json.loads((out / "settings.json").read_text())
    assert settings["options"]["fmax"] == 5 and settings["options"]["highpass_hz"] == 0.5
    assert settings["fs_record_hz"] == 20 and settings["decimation"] == 1
    _no_partial_files(tmp_path)


def _address_space(limit):
    def set_limit():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    return set_limit


def test_record_larger_than_the_memory_exits_4_not_internal_error(tmp_path):
    """A .npy header that promises 10 GiB under a 3 GiB address space:
    "not enough memory", exit 4 (the contract), no traceback, no --out."""
    path = tmp_path / "huge.npy"
    with open(path, "wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "<f8", "fortran_order": False,
                                                  "shape": (1_342_177_280, 1)})
        fh.write(bytes(80))
    run = _cli("identify", path, "--fs", 100, "--ambient", "--out", tmp_path / "out",
               preexec_fn=_address_space(3 * 2**30))
    assert run.returncode == EXIT_CANNOT_IDENTIFY, run.stderr
    assert _one_line(run.stderr).startswith("modal identify: not enough memory")
    assert "Traceback" not in run.stderr and not (tmp_path / "out").exists()


def test_a_record_whose_name_is_not_utf8_is_identified_and_drawn(tmp_path):
    """A file name with a Latin-1 byte (Python keeps it as a lone surrogate)
    is shown with U+FFFD in the diagram's title and the report; exit 0."""
    folder = os.fsencode(tmp_path)
    np.save(tmp_path / "r.npy", np.load(PALISADEN)[:6000])
    os.rename(os.path.join(folder, b"r.npy"), os.path.join(folder, b"rec_\xe9.npy"))
    (record,) = [p for p in tmp_path.iterdir() if p.name.startswith("rec_")]
    # the command prints the name as the file system holds it (byte 0xe9), as ls does
    options = [o for o in PALISADEN_OPTIONS if o != "--quiet"]
    run = subprocess.run([sys.executable, "-m", "modal", "identify", record, *options, "--out", tmp_path / "out"],
                         capture_output=True, text=True, errors="surrogateescape", timeout=300)
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr and (tmp_path / "out" / "stabilisation.png").is_file()
    assert "rec_\ufffd.npy" in (tmp_path / "out" / "report.html").read_text(encoding="utf-8")
    # the log names every file written, no more
    (wrote,) = [line for line in run.stderr.splitlines() if " wrote " in line]
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert wrote.split(f"wrote {tmp_path / 'out'}/: ")[1].split(", ") == written and "report.html" in written


def test_printable_replaces_only_undecodable_bytes():
    from modal._checks import printable

    assert printable("rec_\udce9 \u00e9\u03bc.npy") == "rec_\ufffd \u00e9\u03bc.npy"  # é and µ kept
    assert printable(os.fsdecode(b"caf\xc3\xa9")) == "caf\u00e9"


# --- the record --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["fifo", "directory", "device"])
def test_record_that_is_not_a_file_is_refused_without_hanging(tmp_path, kind):
    record = tmp_path / "record.csv"
    if kind == "fifo":
        os.mkfifo(record)
    elif kind == "directory":
        record.mkdir()
    else:
        record.symlink_to("/dev/zero")
    run = _cli("identify", record, "--fs", 100, "--ambient", "--out", tmp_path / "out", timeout=60)
    assert run.returncode == EXIT_BAD_FILE
    assert "not a record file" in _one_line(run.stderr)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("dtype", ["datetime64[s]", "timedelta64[s]"])
def test_dates_are_not_a_record(capsys, tmp_path, dtype):
    path = tmp_path / "dates.npy"
    np.save(path, np.arange(12000).reshape(4000, 3).astype(dtype))
    code, _, err = _run(capsys, "identify", path, "--fs", 100, "--ambient", "--out", tmp_path / "out")
    assert code == EXIT_BAD_FILE
    assert f"must hold real numbers, got dtype {dtype}" in _one_line(err)


# --- records without vibration -----------------------------------------------------------------------------


def _records_without_vibration():
    t = np.arange(4000) / 100
    rng = np.random.default_rng(1)
    return {
        "ramps": np.column_stack([t, 2 * t + 1, -3 * t]),  # gave 3 "modes" (28, 44, 46 Hz, MPC 0.9999), exit 0
        "constants": np.column_stack([np.ones_like(t), np.full_like(t, -2.5), np.full_like(t, 7.0)]),
        "round-off on an offset": 1e6 + 1e-9 * rng.standard_normal((4000, 3)),
    }


@pytest.mark.parametrize("name", list(_records_without_vibration()))
def test_record_without_vibration_is_refused_with_the_reason(capsys, tmp_path, name):
    path = tmp_path / "flat.npy"
    np.save(path, _records_without_vibration()[name])
    code, out, err = _run(capsys, "identify", path, "--fs", 100, "--ambient", "--out", tmp_path / "out", "--quiet")
    assert code == EXIT_CANNOT_IDENTIFY
    line = _one_line(err)
    assert "no channel holds vibration" in line and "linear ramp" in line
    assert "modes" not in out
    assert not (tmp_path / "out").exists()


def test_one_dead_channel_is_named_in_the_record_numbering(capsys, tmp_path):
    acc = np.random.default_rng(2).standard_normal((4000, 4))
    acc[:, 2] = 0.5 * np.arange(4000)  # a drift
    path = tmp_path / "drift.npy"
    np.save(path, acc)
    code, _, err = _run(capsys, "identify", path, "--fs", 100, "--ambient", "--channels", "1,2,3",
                        "--out", tmp_path / "out")
    assert code == EXIT_CANNOT_IDENTIFY
    assert "channel 2 holds no vibration" in _one_line(err) and "leave it out" in err


def test_vibration_on_a_huge_offset_is_named_as_such(tmp_path, capsys):
    """1e9 added to a good record in double precision: not "no vibration"
    but a vibration lost in an offset, with the fix."""
    path = tmp_path / "offset.npy"
    np.save(path, np.load(PALISADEN)[:6000].astype(float) + 1e9)
    code, _, err = _run(capsys, "identify", path, *PALISADEN_OPTIONS, "--out", tmp_path / "out")
    assert code == EXIT_CANNOT_IDENTIFY
    line = _one_line(err)
    assert "channels 0, 1, 2, 3, 4, 5: vibration lost in an offset" in line and "(mean 1e+09)" in line
    assert "subtract the offset" in line and "no vibration" not in line


# --- memory ------------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_more_memory_than_available_is_refused_with_the_size(tmp_path):
    """2000 ambient channels: correlations through cross-spectra, a
    122000 x 122000 Hankel matrix and its SVD: hundreds of GB."""
    from modal.measured import available_memory, memory_needed

    need = memory_needed(4000, 2000, rows=60, cols=61, n_refs=2000)["peak"]
    if need <= available_memory():
        pytest.skip("this machine has the memory")
    path = tmp_path / "many.npy"
    np.save(path, np.random.default_rng(3).standard_normal((4000, 2000)))
    run = _cli("identify", path, "--fs", 100, "--ambient", "--out", tmp_path / "out", "--quiet", timeout=300)
    assert run.returncode == EXIT_CANNOT_IDENTIFY
    line = _one_line(run.stderr)
    assert f"would need about {need / 1e9:.3g} GB of memory" in line
    assert "Hankel matrix 122000 x 122000" in line and "available" in line


# --- what is written and printed ---------------------------------------------------------------------------


@pytest.mark.slow
def test_modes_csv_keeps_channel_names_and_damping_is_a_fraction_on_screen_too(capsys, tmp_path):
    acc = np.load(PALISADEN)[:, :6]
    names = ["north", "south", "east", "west", "mid 1", "mid 2"]
    path = tmp_path / "named.csv"
    t = np.arange(len(acc)) / 20
    pd.DataFrame(acc, columns=names).assign(time=t)[["time", *names]].to_csv(path, index=False,
                                                                             float_format="%.7g")
    code, out, _ = _run(capsys, "identify", path, "--ambient", "--fmax", 5, "--highpass", 0.5, "--refs", "0,1,2,3",
                        "--out", tmp_path / "out", "--quiet")
    assert code == 0
    modes = pd.read_csv(tmp_path / "out" / "modes.csv")
    assert [c for c in modes if c.startswith("phi_")] == [f"phi_{n}" for n in names]
    assert "ratio to critical (fraction, not %)" in out
    header = next(line for line in out.splitlines() if line.split()[:2] == ["mode", "freq_hz"])
    assert "damping" in header.split() and "damping_pct" not in header
    printed = [float(line.split()[header.split().index("damping")]) for line in out.splitlines()
               if line.split() and line.split()[0].isdigit()]
    np.testing.assert_allclose(printed, modes["damping"], rtol=1e-3)
    assert np.all(modes["damping"] < 0.1)  # a fraction


def test_modes_csv_numbers_unnamed_channels(capsys, tmp_path):
    code, _, _ = _run(capsys, "identify", PALISADEN, *PALISADEN_OPTIONS, "--channels", "1,2,3,4,5",
                      "--refs", "1,2,3", "--out", tmp_path / "out")
    assert code == 0
    modes = pd.read_csv(tmp_path / "out" / "modes.csv")
    assert [c for c in modes if c.startswith("phi_")] == [f"phi_{c}" for c in range(1, 6)]


def test_no_mode_message_says_what_was_found_without_false_advice(capsys, noise, tmp_path):
    code, _, err = _run(capsys, "identify", noise, "--fs", 100, "--ambient", "--out", tmp_path / "out")
    assert code == EXIT_NO_MODES
    line = _one_line(err)
    assert "no mode selected" in line
    assert "stable" in line and "poles over 30 orders" in line
    assert "raise --max-order" not in line
    assert "Noise alone" in line or "noise alone" in line


def test_a_model_order_beyond_memory_is_refused_before_the_work(monkeypatch):
    """max_order 4000 on a 12,000 x 4 record: 2000 block rows, a Hankel
    matrix of 0.5 GB, but the modal histories of 4,002,000 eigenvalues over
    8004 columns (the MAMC's): 513 GB. It was killed by the system after
    minutes, or numpy's bare 'Unable to allocate'; now refused at once,
    naming the order."""
    from modal.measured import _pipeline, memory_needed

    assert memory_needed(12000, 4, 2000, 2001, 4, 4000)["poles"] == 16 * 2000 * 2001 * 8004
    assert memory_needed(12000, 4, 60, 61, 4, 60)["poles"] == 16 * 30 * 31 * 244
    assert "poles" not in memory_needed(12000, 4, 60, 61, 4)
    monkeypatch.setattr(_pipeline, "available_memory", lambda: 16e9)
    y = np.random.default_rng(0).standard_normal((12000, 4))
    with pytest.raises(ValueError, match=r"would need about 513 GB of memory .*the modal histories of 4002000 "
                                         r"eigenvalues \(orders 2 \.\.\. 4000\): 513 GB\), only 16 GB available: .*"
                                         r"or a lower --max-order"):
        modal.identify_record(y, 0.005, "ambient", max_order=4000)
