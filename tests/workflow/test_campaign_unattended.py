"""A campaign left running: reruns by content whatever the time stamps, no
record stops the others, resume after ``kill -9``, never an input as output."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
import modal.campaign
import modal._locks
from modal._hashes import content_hashes
from modal._locks import live_snakemake_processes
from modal.campaign import simulate_campaign
from modal.cli import main as cli

ROOT = Path(__file__).resolve().parents[2]


def planned(capfd, campaign, out) -> dict[str, int]:
    """The jobs a dry run of the campaign plans, by rule."""
    capfd.readouterr()
    modal.campaign.run(campaign, out, dry_run=True)
    text = capfd.readouterr().out
    jobs = {}
    if "Nothing to be done" in text:
        return jobs
    rows = text[text.index("Job stats"):].splitlines()[3:]
    for row in rows:
        parts = row.split()
        if len(parts) != 2 or parts[0] in ("total", "all"):
            if parts and parts[0] == "total":
                break
            continue
        jobs[parts[0]] = int(parts[1])
    return jobs


@pytest.fixture
def small(tmp_path):
    """Six two-minute records in two chunks of three, run once."""
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=6, every_hours=12, duration=120.0)
    text = (folder / "campaign.yaml").read_text().replace("chunk: 25", "chunk: 3")
    (folder / "campaign.yaml").write_text(text)
    out = tmp_path / "out"
    modal.campaign.run(folder / "campaign.yaml", out, cores=2)
    return folder, out


@pytest.mark.slow  # runs a campaign
def test_a_changed_record_reruns_its_chunk_whatever_its_time_stamp(small, capfd):
    folder, out = small
    assert planned(capfd, folder / "campaign.yaml", out) == {}
    record = sorted((folder / "records").glob("*.npz"))[4]  # in the second chunk
    stamp = record.stat()
    loaded = modal.read_record(record)
    modal.save_record_npz(record, loaded.acc * 1.5, loaded.dt)
    os.utime(record, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))  # as it was: only the content changed
    assert planned(capfd, folder / "campaign.yaml", out) == {"identify_chunk": 1, "track": 1, "report": 1}
    modal.campaign.run(folder / "campaign.yaml", out)
    assert planned(capfd, folder / "campaign.yaml", out) == {}


@pytest.mark.slow  # runs a campaign
def test_a_changed_reference_modes_file_reruns_the_tracking(small, capfd):
    folder, out = small
    references = pd.read_csv(out / "references.csv")
    references.to_csv(folder / "refs.csv", index=False)
    with open(folder / "campaign.yaml", "a") as fh:
        fh.write("tracking: {reference_modes: refs.csv}\n")
    modal.campaign.run(folder / "campaign.yaml", out)
    assert planned(capfd, folder / "campaign.yaml", out) == {}
    stamp = (folder / "refs.csv").stat()
    references.assign(freq_hz=references["freq_hz"] * 1.01).to_csv(folder / "refs.csv", index=False)
    os.utime(folder / "refs.csv", ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
    assert planned(capfd, folder / "campaign.yaml", out) == {"track": 1, "report": 1}


def test_content_hashes_see_a_rewrite_that_keeps_size_and_time(tmp_path):
    path = tmp_path / "r.bin"
    path.write_bytes(b"a" * 100)
    cache = tmp_path / "cache.json"
    first = content_hashes([path, tmp_path / "missing"], cache=cache)
    assert first[str(tmp_path / "missing")] is None
    stamp = path.stat()
    time.sleep(0.01)
    path.write_bytes(b"b" * 100)
    os.utime(path, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
    assert content_hashes([path], cache=cache)[str(path)] != first[str(path)]
    assert content_hashes([path], cache=cache) == content_hashes([path])  # the cache agrees with a fresh read


@pytest.mark.slow  # runs a campaign
def test_no_record_stops_the_others(tmp_path):
    """A corrupt UFF (its reader raises a bare Exception), a record with a
    channel fewer (a file cut short) and one at another rate fail with their
    reason; the others are identified and tracked."""
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=4, every_hours=12, duration=120.0)
    good = modal.read_record(folder / "records" / "frame_20250101_0000.npz")
    modal.write_uff58(folder / "records" / "corrupt.uff", good.acc, good.dt)
    data = (folder / "records" / "corrupt.uff").read_text().splitlines()
    (folder / "records" / "corrupt.uff").write_text("\n".join(data[:40] + ["garbage"] + data[41:60]) + "\n")
    modal.save_record_npz(folder / "records" / "short.npz", good.acc[:, :3], good.dt)
    modal.save_record_npz(folder / "records" / "slow.npz", good.acc[::2], 2 * good.dt)
    index = pd.read_csv(folder / "index.csv")
    extra = pd.DataFrame({"path": ["records/corrupt.uff", "records/short.npz", "records/slow.npz"],
                          "time": ["2025-03-01T00:00:00", "2025-03-02T00:00:00", "2025-03-03T00:00:00"]})
    pd.concat([index, extra]).to_csv(folder / "index.csv", index=False)
    out = tmp_path / "out"
    assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(out)]) == 0
    failed = pd.read_csv(out / "failed.csv").set_index("record")["reason"]
    assert set(failed.index) == {"records/corrupt.uff", "records/short.npz", "records/slow.npz"}
    assert "3 channels, the campaign's records 4" in failed["records/short.npz"]
    assert "sampled at 25 Hz, the campaign's records at 50 Hz" in failed["records/slow.npz"]
    assert set(pd.read_csv(out / "tracked.csv")["record"]) == set(index["path"])


def test_an_output_folder_over_the_inputs_is_refused(tmp_path, capsys):
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=2, duration=60.0)
    before = {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    for out, says in [(folder, "holds the input"), (folder / "records", "holds the input"),
                      (folder / "index.csv", "is the input"), (folder / "campaign.yaml" / "x", "lies inside")]:
        assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(out)]) == 2
        assert says in capsys.readouterr().err
    assert {p: p.read_bytes() for p in folder.rglob("*") if p.is_file()} == before


@pytest.mark.slow  # runs a campaign
def test_a_left_run_that_does_not_stop_is_refused_with_its_pid(tmp_path, monkeypatch):
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=2, duration=60.0)
    out = tmp_path / "out"
    (out / ".snakemake" / "locks").mkdir(parents=True)
    (out / ".snakemake" / "locks" / "0.input.lock").write_text("")
    fake = tmp_path / "snakemake"  # a Snakemake left running there by a caller killed alone, deaf to Ctrl-C
    fake.write_text(f"#!{sys.executable}\nimport signal, time\nsignal.signal(signal.SIGINT, signal.SIG_IGN)\n"
                    "time.sleep(60)\n")
    fake.chmod(0o755)
    other = subprocess.Popen([str(fake), "--directory", str(out)], cwd=out)
    monkeypatch.setattr(modal.campaign._workflow, "LEFTOVER_GRACE", 0.5)
    try:
        time.sleep(0.3)
        with pytest.raises(ValueError, match=f"did not stop within 0.5 s of SIGINT \\(pid {other.pid}: "):
            modal.campaign.run(folder / "campaign.yaml", out)
        assert other.poll() is None
    finally:
        other.kill()
        other.wait()
    # the process gone, the lock is stale: cleared, and the campaign runs
    modal.campaign.run(folder / "campaign.yaml", out)
    assert (out / "tracked.csv").is_file() and not list((out / ".snakemake" / "locks").glob("*.lock"))


@pytest.mark.slow
@pytest.mark.parametrize("alone", [False, True], ids=["group", "command alone"])
def test_the_same_command_resumes_after_kill_9_with_a_clean_runs_results(tmp_path, alone):
    """``kill -9`` of the run's process group (Snakemake and its jobs die
    with it, their locks left behind), or of ``modal campaign`` alone (its
    workflow runs on, to be stopped by the rerun): the same command resumes
    at once, to a clean run's results."""
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=12, every_hours=12, duration=300.0)
    (folder / "campaign.yaml").write_text((folder / "campaign.yaml").read_text().replace("chunk: 25", "chunk: 3"))
    killed, clean = tmp_path / "killed", tmp_path / "clean"
    command = [sys.executable, "-m", "modal", "campaign", str(folder / "campaign.yaml"), "--out", str(killed),
               "--cores", "2"]
    run = subprocess.Popen(command, start_new_session=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while not list((killed / "chunks").glob("*/modes.csv")) and time.monotonic() < deadline:
        time.sleep(0.05)
    if alone:
        os.kill(run.pid, signal.SIGKILL)
    else:
        os.killpg(run.pid, signal.SIGKILL)  # the scheduler and its jobs, at once
    run.wait()
    assert list((killed / ".snakemake" / "locks").glob("*.lock")), "the kill left no lock: nothing was tested"
    left = live_snakemake_processes(killed)
    assert bool(left) == alone, left
    assert not (killed / "tracked.csv").exists()
    assert cli(command[3:]) == 0  # the same command
    assert not any(modal._locks._alive(pid) for pid in left)
    assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(clean), "--cores", "2"]) == 0
    for name in ("tracked.csv", "modes.csv", "failed.csv", "references.csv"):
        assert (killed / name).read_bytes() == (clean / name).read_bytes(), name


@pytest.mark.slow
def test_an_edit_of_the_engine_reruns_the_identification_and_of_the_report_only_the_report(tmp_path, capfd):
    """In a copy of the package (its own Snakefile and modules): editing the
    pipeline reruns every chunk; editing the report's module only the report."""
    package = tmp_path / "pkg"
    shutil.copytree(ROOT / "modal", package / "modal", ignore=shutil.ignore_patterns("__pycache__"))
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=4, every_hours=12, duration=120.0)
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": str(package)}

    def campaign(*extra):
        done = subprocess.run([sys.executable, "-m", "modal", "campaign", str(folder / "campaign.yaml"), "--out",
                               str(out), *extra], env=env, capture_output=True, text=True, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        return done.stdout + done.stderr

    campaign()
    assert "Nothing to be done" in campaign("--dry-run")
    pipeline = package / "modal" / "measured" / "_pipeline.py"
    stamp, original = pipeline.stat(), pipeline.read_text()
    pipeline.write_text(original + "\n# an edit\n")
    os.utime(pipeline, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))  # an older time stamp: content decides
    plan = campaign("--dry-run")
    assert "identify_chunk" in plan and "track" in plan
    pipeline.write_text(original)  # the edit undone, with a newer time stamp: nothing to rerun
    assert "Nothing to be done" in campaign("--dry-run")
    report = package / "modal" / "campaign" / "_report.py"
    report.write_text(report.read_text() + "\n# an edit\n")
    plan = campaign("--dry-run")
    assert "report" in plan and "identify_chunk" not in plan and "track " not in plan


def test_the_index_is_data(tmp_path):
    """Times in ISO 8601 or as time_format says (01/02/2025 is refused
    without one: day or month first?), one record once however its path is
    written, other columns kept, settings of the wrong kind refused."""
    simulate_campaign(tmp_path, n_records=2, duration=60.0)
    first, second = sorted(p.relative_to(tmp_path) for p in (tmp_path / "records").glob("*.npz"))

    def read(index, records="", rest=""):
        (tmp_path / "index.csv").write_text(index)
        (tmp_path / "c.yaml").write_text(f"records: {{index: index.csv{records}}}\n"
                                         f"identify: {{excitation: ambient}}\n{rest}")
        return modal.campaign.read_campaign(tmp_path / "c.yaml")

    _, index = read(f"path,time,temperature_c\n{first},2025-01-01 06:00,3.5\n{second},2025-01-01T00:00,-1\n")
    assert list(index["record"]) == [str(second), str(first)]  # in time order
    assert list(index["temperature_c"]) == [-1.0, 3.5]
    _, index = read(f"path,time\n{first},01/02/2025 10:00\n{second},13/02/2025 11:00\n",
                    ", time_format: '%d/%m/%Y %H:%M'")
    assert list(index["time"].dt.month) == [2, 2] and list(index["time"].dt.day) == [1, 13]
    with pytest.raises(ValueError, match=r"index.csv: row 2: time '01/02/2025' does not follow ISO 8601"):
        read(f"path,time\n{first},01/02/2025\n{second},13/02/2025\n")
    with pytest.raises(ValueError, match=f"records: {first} is listed 2 times"):
        read(f"path,time\n{first},2025-01-01\n./{first},2025-01-02\n")
    with pytest.raises(ValueError, match="chunk: 2.0 is not a whole number of records"):
        read(f"path,time\n{first},2025-01-01\n", rest="chunk: 2.0\n")
    (tmp_path / "c.yaml").write_text("records: {glob: 'records/*.npz', time_format: '%Y', time_regex: '(['}\n"
                                     "identify: {excitation: ambient}\n")
    with pytest.raises(ValueError, match=r"c.yaml: records.time_regex '\(\[' is not a regular expression"):
        modal.campaign.read_campaign(tmp_path / "c.yaml")


def test_the_campaign_file_is_data(tmp_path, capsys):
    """A key given twice (YAML keeps the last) and an alias bomb are refused
    at once, before anything is expanded or run."""
    duplicate = tmp_path / "twice.yaml"
    duplicate.write_text("records: {index: index.csv}\nidentify: {excitation: ambient, fmax: 3, fmax: 4}\n")
    assert cli(["campaign", str(duplicate), "--out", str(tmp_path / "o")]) == 2
    assert "twice.yaml: key 'fmax' given twice in one mapping" in capsys.readouterr().err
    lines = ["a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]"]
    lines += [f"{n}: &{n} [{', '.join([f'*{p}'] * 10)}]" for p, n in zip("abcdefg", "bcdefgh")]
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text("\n".join(lines) + "\nrecords: {index: index.csv}\nidentify: {excitation: ambient, channels: *h}\n")
    started = time.monotonic()
    assert cli(["campaign", str(bomb), "--out", str(tmp_path / "o")]) == 2
    assert "bomb.yaml: line 2: YAML alias *a: a config is plain data, aliases are refused" in capsys.readouterr().err
    assert time.monotonic() - started < 10 and not (tmp_path / "o").exists()


@pytest.mark.slow  # runs a campaign
def test_any_folder_name_and_a_rerun_that_did_nothing_says_so(tmp_path, capsys):
    folder = tmp_path / "run #1" / "a: b"
    simulate_campaign(folder, n_records=2, duration=60.0)
    out = tmp_path / "run #1" / "out: x"
    assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(out)]) == 0
    assert "wrote" in capsys.readouterr().err and (out / "tracked.csv").is_file()
    assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(out)]) == 0
    assert "nothing to do" in capsys.readouterr().err


@pytest.mark.slow  # runs a campaign, twice
def test_an_odd_first_record_fails_alone_and_mixed_chunks_are_tracked(tmp_path, capsys):
    """Six records and 20 listed that do not exist, in chunks of 3: the first
    in time has a channel fewer (it fails alone: the layout is the records'
    majority's); the first chunk's times are whole days, the second's have a
    fractional second (one time format in every chunk); index columns
    ``mode`` and ``freq_hz`` are kept as ``index_mode``, ``index_freq_hz``;
    the references need min_share of the 5 records identified, not of the
    26 listed. Deleting the first record reruns its chunk only: the chunks
    depend on the layout's values, not on which record gave them."""
    folder = tmp_path / "campaign"
    simulate_campaign(folder, n_records=6, every_hours=12, duration=120.0)
    text = (folder / "campaign.yaml").read_text().replace("chunk: 25", "chunk: 3").split("geometry:")[0]
    (folder / "campaign.yaml").write_text(text)
    index = pd.read_csv(folder / "index.csv")
    first = modal.read_record(folder / index["path"][0])
    modal.save_record_npz(folder / index["path"][0], first.acc[:, :3], first.dt)
    index["time"] = ["2025-01-01", "2025-01-02", "2025-01-03",
                     "2025-01-03T06:00:00.25", "2025-01-03T07:00:00", "2025-01-03T08:00:00.5"]
    index["mode"], index["freq_hz"] = 7, 1.5
    missing = pd.DataFrame({"path": [f"records/later_{k}.npz" for k in range(20)],
                            "time": [f"2025-02-{k + 1:02d}T00:00:00" for k in range(20)]})
    pd.concat([index, missing]).to_csv(folder / "index.csv", index=False)
    out = tmp_path / "out"
    assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(out), "--cores", "2"]) == 0
    failed = pd.read_csv(out / "failed.csv").set_index("record")["reason"]
    assert len(failed) == 21
    assert failed[index["path"][0]] == "3 channels, the campaign's records 4"
    tracked = pd.read_csv(out / "tracked.csv")
    assert sorted(tracked["record"].unique()) == sorted(index["path"][1:])
    assert len(tracked) == 5 * 4 and sorted(tracked["mode"].unique()) == [1, 2, 3, 4]
    times = pd.to_datetime(tracked.drop_duplicates("record")["time"], format="ISO8601")
    assert list(times) == list(pd.to_datetime(index["time"][1:], format="ISO8601"))
    assert pd.read_csv(out / "references.csv")["n_records"].tolist() == [5, 5, 5, 5]
    report = (out / "report.html").read_text()
    assert "<b>26</b> records: <b>5</b> identified" in report and "<h2>Frequency against the index" in report
    stamps = {p.parent.name: p.stat().st_mtime_ns for p in (out / "chunks").glob("*/modes.csv")}
    (folder / index["path"][0]).unlink()
    assert cli(["campaign", str(folder / "campaign.yaml"), "--out", str(out), "--cores", "2"]) == 0
    after = {p.parent.name: p.stat().st_mtime_ns for p in (out / "chunks").glob("*/modes.csv")}
    assert len(after) == 9 and sorted(c for c in after if after[c] != stamps[c]) == ["c00000"]
    assert "does not exist" in pd.read_csv(out / "failed.csv").set_index("record")["reason"][index["path"][0]]


@pytest.mark.slow  # runs a campaign
def test_a_campaign_with_no_record_identified_says_so_and_exits_4(tmp_path, capsys):
    """Every record fails (here: none exists): the outputs are written, a
    warning names failed.csv, the exit code is 4 (done, nothing identified)."""
    simulate_campaign(tmp_path / "c", n_records=2, duration=60.0)
    for p in (tmp_path / "c" / "records").iterdir():
        p.unlink()
    out = tmp_path / "out"
    assert cli(["campaign", str(tmp_path / "c" / "campaign.yaml"), "--out", str(out)]) == 4
    err = capsys.readouterr().err
    assert f"modal campaign: warning: no record was identified: all 2 failed; {out / 'failed.csv'} says why" in err
    assert len(pd.read_csv(out / "failed.csv")) == 2 and (out / "report.html").is_file()
    with pytest.raises(modal.campaign.NoRecordIdentified) as info:
        modal.campaign.run(tmp_path / "c" / "campaign.yaml", out)
    assert info.value.n_records == 2 and info.value.failed == out / "failed.csv"
