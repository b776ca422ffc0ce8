"""A campaign's run as processes: signals stop the workflow and its jobs, one
run per output folder, a live run told from other processes working in the
folder, braces in any path."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

import modal.campaign
from modal._locks import descendants, live_snakemake_processes
from modal.campaign import simulate_campaign
from modal.cli import main as cli


def small_campaign(folder, n_records=24, duration=300.0) -> Path:
    """A simulated campaign in chunks of three records; its YAML file."""
    simulate_campaign(folder, n_records=n_records, every_hours=12, duration=duration)
    (folder / "campaign.yaml").write_text((folder / "campaign.yaml").read_text().replace("chunk: 25", "chunk: 3"))
    return folder / "campaign.yaml"


def start(campaign, out, **popen) -> subprocess.Popen:
    """``modal campaign`` as a process of its own (this interpreter, this
    checkout: PYTHONPATH is passed on), in a session of its own."""
    return subprocess.Popen([sys.executable, "-m", "modal", "campaign", str(campaign), "--out", str(out),
                             "--cores", "2"], start_new_session=True, **popen)


def wait_for(condition, seconds=120.0):
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.05)


def alive(pid) -> bool:
    try:
        return "zombie" not in next(line for line in Path(f"/proc/{pid}/status").read_text().splitlines()
                                    if line.startswith("State:"))
    except (OSError, StopIteration):
        return False


@pytest.mark.slow  # runs campaigns
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_to_the_command_stops_snakemake_and_its_jobs_and_the_same_command_resumes(tmp_path, signum):
    """``kill <pid>`` of ``modal campaign`` alone (not its group): Snakemake
    and the jobs running end with it, no lock is left, and the same command
    resumes."""
    campaign, out = small_campaign(tmp_path / "campaign"), tmp_path / "out"
    log = tmp_path / "run.log"
    with open(log, "w") as stderr:
        run = start(campaign, out, stderr=stderr, stdout=subprocess.DEVNULL)
    try:
        wait_for(lambda: list((out / "logs" / "identify_chunk").glob("*.log")))  # a job runs
        started = descendants(run.pid)
        assert len(started) >= 2, "no job ran: nothing was tested"
        stopped_at = time.monotonic()
        os.kill(run.pid, signum)
        assert run.wait(timeout=60) == 128 + signum
        took = time.monotonic() - stopped_at
    finally:
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGKILL)
            run.wait()
    time.sleep(0.5)
    assert [pid for pid in started if alive(pid)] == []  # Snakemake and its jobs: none left
    assert took < 30, took
    said = log.read_text()
    assert f"modal campaign: interrupted ({signum.name}); the workflow stopped" in said
    assert "run the same command again to resume" in said
    assert not list((out / ".snakemake" / "locks").glob("*.lock"))
    assert not (out / "tracked.csv").exists()
    assert cli(["campaign", str(campaign), "--out", str(out), "--cores", "2"]) == 0
    assert len(pd.read_csv(out / "failed.csv")) == 0 and (out / "report.html").is_file()


@pytest.mark.slow  # runs campaigns
def test_a_second_run_in_the_same_folder_is_refused_naming_the_first(tmp_path, capsys):
    campaign, out = small_campaign(tmp_path / "campaign", n_records=6), tmp_path / "out"
    first = start(campaign, out, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
    try:
        time.sleep(0.3)  # the second starts while the first is still reading the campaign (as in the report)
        second = subprocess.run([sys.executable, "-m", "modal", "campaign", str(campaign), "--out", str(out)],
                                capture_output=True, text=True)
        assert second.returncode == 2, second.stderr
        assert f"a campaign run is active in {out} (pid {first.pid}: " in second.stderr
        assert "--unlock" not in second.stderr and "LockException" not in second.stderr
        # while the first one's workflow runs, too
        wait_for(lambda: (out / ".snakemake" / "locks").is_dir() and list((out / ".snakemake" / "locks").iterdir()))
        assert cli(["campaign", str(campaign), "--out", str(out)]) == 2
        assert f"(pid {first.pid}: " in capsys.readouterr().err
        assert first.wait(timeout=300) == 0
    finally:
        if first.poll() is None:
            os.killpg(first.pid, signal.SIGKILL)
            first.wait()
    assert (out / "tracked.csv").is_file()


def fake_snakemake(folder: Path, cwd: Path) -> subprocess.Popen:
    """A process whose command line is Snakemake's (``python .../snakemake``)
    working in ``cwd``: a Snakemake left running by a killed caller."""
    script = folder / "snakemake"
    script.write_text(f"#!{sys.executable}\nimport time\ntime.sleep(60)\n")
    script.chmod(0o755)
    return subprocess.Popen([str(script), "--directory", "."], cwd=cwd)


@pytest.mark.slow  # runs a campaign
def test_after_a_kill_9_other_commands_in_the_folder_are_no_run_but_snakemake_is(tmp_path):
    """A lock left behind, and in the folder a ``tail -f`` of Snakemake's log
    and a program naming snakemake: the lock is stale, the campaign runs. A
    Snakemake process working there (a killed run's) is stopped, the others
    are left alone."""
    campaign = small_campaign(tmp_path / "campaign", n_records=2, duration=60.0)
    out = tmp_path / "out"
    (out / ".snakemake" / "log").mkdir(parents=True)
    (out / ".snakemake" / "log" / "2026-01-01T000000.000000.snakemake.log").write_text("Building DAG of jobs...\n")
    (out / ".snakemake" / "locks").mkdir()
    (out / ".snakemake" / "locks" / "0.input.lock").write_text("")
    tail = subprocess.Popen(["tail", "-f", ".snakemake/log/2026-01-01T000000.000000.snakemake.log"], cwd=out,
                            stdout=subprocess.DEVNULL)
    named = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)", "snakemake"], cwd=out)
    snakemake = fake_snakemake(tmp_path, out)
    try:
        time.sleep(0.3)
        said = []
        modal.campaign.run(campaign, out, log=said.append)
        assert snakemake.wait(timeout=5) == -signal.SIGINT
        assert f"stopped the workflow a killed run left running in {out} (pid {snakemake.pid}); resuming" in said
        assert [tail.poll(), named.poll()] == [None, None]
    finally:
        for process in (tail, named, snakemake):
            process.kill()
            process.wait()
    assert (out / "tracked.csv").is_file() and not list((out / ".snakemake" / "locks").glob("*.lock"))


def test_a_snakemake_run_is_its_scheduler_or_its_jobs_working_in_the_folder(tmp_path):
    here = tmp_path / "here"
    (here / ".snakemake" / "scripts").mkdir(parents=True)
    job = here / ".snakemake" / "scripts" / "tmpab12.identify_chunk.py"
    job.write_text("import time\ntime.sleep(60)\n")
    sleep = "import time; time.sleep(60)"
    processes = {
        "scheduler": fake_snakemake(tmp_path, here),
        "module": None,
        "job": subprocess.Popen([sys.executable, str(job)], cwd=here),
        "tail": subprocess.Popen(["tail", "-f", "/dev/null", ".snakemake/scripts/x.py"], cwd=here),
        "tail named": subprocess.Popen(["tail", "-f", "snakemake"], cwd=here, stderr=subprocess.DEVNULL),
        "named": subprocess.Popen([sys.executable, "-c", sleep, "snakemake", "-m", "snakemake"], cwd=here),
        "elsewhere": subprocess.Popen([str(tmp_path / "snakemake")], cwd=tmp_path),
    }
    fake_module = tmp_path / "fake" / "snakemake"
    fake_module.mkdir(parents=True)
    (fake_module / "__main__.py").write_text(sleep + "\n")
    processes["module"] = subprocess.Popen([sys.executable, "-m", "snakemake", "--cores", "1"], cwd=here,
                                           env=dict(os.environ, PYTHONPATH=str(tmp_path / "fake")))
    try:
        time.sleep(0.5)
        found = live_snakemake_processes(here)
        assert set(found) == {processes[name].pid for name in ("scheduler", "module", "job")}
        assert found[processes["module"].pid] == f"{sys.executable} -m snakemake --cores 1"
        assert live_snakemake_processes(here / ".." / "here") == found
    finally:
        for process in processes.values():
            process.kill()
            process.wait()


@pytest.mark.slow  # runs a campaign
def test_braces_in_the_campaign_folder_a_record_s_path_and_the_output_folder(tmp_path):
    folder = tmp_path / "br {A}"
    campaign = small_campaign(folder, n_records=3, duration=60.0)
    index = pd.read_csv(folder / "index.csv")
    moved = "records/sub {x}/" + Path(index.loc[0, "path"]).name
    (folder / "records" / "sub {x}").mkdir()
    shutil.move(folder / index.loc[0, "path"], folder / moved)
    index.loc[0, "path"] = moved
    index.to_csv(folder / "index.csv", index=False)
    out = tmp_path / "out {B}}"
    assert cli(["campaign", str(campaign), "--out", str(out)]) == 0
    assert moved in set(pd.read_csv(out / "tracked.csv")["record"])
    assert len(pd.read_csv(out / "failed.csv")) == 0 and (out / "report.html").is_file()


@pytest.mark.slow  # runs a campaign twice
def test_bytes_that_are_not_utf8_in_the_campaign_folder_and_a_record_s_name(tmp_path):
    """A file name that is not UTF-8 (a logger's Latin-1 ``\\xe9``): Snakemake
    cannot write it to its locks, so before, one such record found by a glob
    (or such a campaign folder) stopped the whole workflow on every run (exit
    7, "run the same command again to resume"). It is identified with the
    others, named with ``\\xe9`` in every CSV, and its chunk reruns when its
    bytes change."""
    folder = Path(os.fsdecode(os.fsencode(tmp_path) + b"/camp\xff\xfe"))
    small_campaign(folder, n_records=3, duration=60.0)
    records = sorted((folder / "records").iterdir())
    odd = records[1].with_name(os.fsdecode(os.fsencode(records[1].stem) + b"_\xe9.npz"))
    records[1].rename(odd)
    campaign = folder / "glob.yaml"
    campaign.write_text("records:\n  glob: 'records/*.npz'\n  time_format: '%Y%m%d_%H%M'\n"
                        "  time_regex: '_(\\d{8}_\\d{4})'\nidentify:\n  excitation: ambient\n  fmax: 10\n")
    out = tmp_path / "out"
    assert cli(["campaign", str(campaign), "--out", str(out)]) == 0
    name = "records/" + records[1].stem + "_\\xe9.npz"
    tracked = pd.read_csv(out / "tracked.csv")
    assert set(tracked["record"]) == {"records/" + records[0].name, name, "records/" + records[2].name}
    assert len(pd.read_csv(out / "failed.csv")) == 0 and (out / "report.html").is_file()
    # its bytes replaced by another record's, same size and time stamps: its chunk reruns
    stat = odd.stat()
    odd.write_bytes(records[0].read_bytes())
    os.utime(odd, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    assert cli(["campaign", str(campaign), "--out", str(out)]) == 0
    tracked = pd.read_csv(out / "tracked.csv")
    first = tracked[tracked["record"] == "records/" + records[0].name]
    assert tracked[tracked["record"] == name]["freq_hz"].tolist() == first["freq_hz"].tolist()


def test_an_interrupted_campaign_names_its_command(tmp_path, capsys, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(modal.campaign, "run", interrupted)
    assert cli(["campaign", str(tmp_path / "campaign.yaml"), "--out", str(tmp_path / "out")]) == 130
    assert capsys.readouterr().err == "modal campaign: interrupted\n"
