"""A real cluster: the small thesis config and a small monitoring campaign
sent through snakemake-executor-plugin-slurm to a single-node Slurm that
tests/cluster/start_slurm.sh starts on this machine (installing Debian's
slurm-wlm and munge when missing, as root). Skipped, saying why, only where
Slurm cannot be installed (not root, no apt-get, no package source)."""

import os
import re
import subprocess
import sys

import pandas as pd
import pytest
import yaml

from modal.campaign import simulate_campaign
from workflow_run import ROOT, SMALL_CONFIG_FILE, copy_project, run_snakemake

pytestmark = pytest.mark.slow

#: What start_slurm.sh says when Slurm cannot be installed here.
CANNOT_INSTALL = ("not root", "no apt-get", "apt-get install")
#: No accounting storage on the test cluster: no account, job states from squeue
#: (asked every 2 s, not Snakemake's 10: the jobs take seconds).
SLURM_OPTIONS = {"executor": "slurm", "slurm-no-account": True, "slurm-status-command": "squeue", "jobs": 4,
                 "latency-wait": 10, "slurm-init-seconds-before-status-checks": 2, "seconds-between-status-checks": 2}
TARGETS = [f"results/identified/{s}_{i}.csv" for s in ("demo", "cera") for i in ("named", "lower")] + [
    "results/tables/table_03.csv"]


@pytest.fixture(scope="module")
def slurm():
    """The test cluster, up; Slurm's client configuration is its own again
    (tests/conftest.py points it at an empty file for local runs)."""
    with pytest.MonkeyPatch.context() as patch:
        if os.environ.get("SLURM_CONF") == os.devnull:
            patch.delenv("SLURM_CONF")
        _start_cluster()
        yield


def _start_cluster():
    run = subprocess.run(["bash", str(ROOT / "tests/cluster/start_slurm.sh")], capture_output=True, text=True,
                         timeout=600)
    reason = (run.stdout + run.stderr).strip()
    if run.returncode != 0:
        if any(word in reason for word in CANNOT_INSTALL):
            pytest.skip(f"Slurm cannot be installed here: {reason}")
        pytest.fail(f"Slurm did not start: {reason}")


def _profile(folder, **more):
    folder.mkdir()
    (folder / "config.yaml").write_text(yaml.safe_dump({**SLURM_OPTIONS, **more}))
    return folder


def _slurm_jobs(workdir) -> list:
    """The Slurm job ids Snakemake's log says it submitted ("Job 3 has been
    submitted with SLURM jobid 2 ...")."""
    text = "".join(p.read_text() for p in (workdir / ".snakemake" / "log").glob("*.log"))
    return re.findall(r"has been submitted with SLURM jobid (\d+)", text)


def test_small_thesis_config_runs_on_slurm(slurm, small_workflow, tmp_path):
    """The small config's identification and a table, each job an sbatch
    job on the test cluster, equal the local run's files byte for byte."""
    (tmp_path / "wf").mkdir()
    work = copy_project(tmp_path / "wf")
    profile = _profile(tmp_path / "profile")
    run_snakemake(work, *TARGETS, "--workflow-profile", str(profile), "--configfile", SMALL_CONFIG_FILE,
                        timeout=900)
    assert len(_slurm_jobs(work)) >= 5
    differ = [t for t in TARGETS if (work / t).read_bytes() != (small_workflow / t).read_bytes()]
    assert not differ, f"the Slurm run differs from the local run: {differ}"


def test_campaign_runs_on_slurm_with_the_shipped_profile(slurm, tmp_path):
    """``modal campaign ... --profile slurm`` as typed (the shipped profile,
    no folder of that name here) sends an 8-record campaign's chunks to the
    cluster; its tracked modes are those of the same campaign run locally."""
    simulate_campaign(tmp_path / "c", n_records=8, every_hours=12, duration=120.0)
    config = tmp_path / "c" / "campaign.yaml"
    config.write_text(config.read_text().replace("chunk: 25", "chunk: 4"))
    on_slurm = subprocess.Popen([sys.executable, "-m", "modal", "campaign", str(config), "--out", "s",
                                 "--profile", "slurm"], cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    # The local run while the Slurm run waits for its first status check (20 s).
    local = subprocess.run([sys.executable, "-m", "modal", "campaign", str(config), "--out", str(tmp_path / "l")],
                           capture_output=True, text=True, timeout=900)
    assert local.returncode == 0, local.stderr[-3000:]
    _, stderr = on_slurm.communicate(timeout=900)
    assert on_slurm.returncode == 0, stderr[-3000:]
    assert len(_slurm_jobs(tmp_path / "s")) >= 2  # the two chunks
    pd.testing.assert_frame_equal(pd.read_csv(tmp_path / "s" / "tracked.csv"),
                                  pd.read_csv(tmp_path / "l" / "tracked.csv"))
