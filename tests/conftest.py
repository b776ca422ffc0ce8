"""Shared fixtures: the thesis's beam demonstration (Sec. 6.1)."""

import numpy as np
import pytest

import modal

L, EI, M = 5.0, 30.0, 1.0
N_MODES = 6


@pytest.fixture(scope="session")
def beam():
    return modal.SimplySupportedBeam(L, EI, M)


@pytest.fixture(scope="session")
def demo(beam):
    """dt = one tenth of the 6th mode's period, sensors at iL/7, impulse at 2L/7."""
    omega = beam.natural_frequencies(N_MODES)
    dt = 2 * np.pi / omega[-1] / 10
    sensors = beam.stations(7)

    def make(n_samples, damping=0.0, modes=N_MODES, sensors=sensors):
        return modal.beam_impulse_response(beam, modes, 2 * L / 7, sensors, dt, n_samples, damping)

    return dict(omega=omega, dt=dt, sensors=sensors, make=make)


# --------------------------------------------------------------------------- #
# The whole workflow (all rules: beam, grid, report) on a small config, once
# per session, in a temporary copy; shared by test_workflow and test_notebooks.
# --------------------------------------------------------------------------- #
import shutil
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
SMALL_CONFIG = {
    "seeds": {"first": 0, "count": 3},
    "studies": {
        "noise": {"noise_sweep": {"damping": 0.01, "noise": [0.03, 0.034]}},
        "cera": {"cols_sweep": [360, 500]},
    },
    "grid": {"seeds": {"first": 0, "count": 2}},
}


def run_snakemake(workdir, *args, check=True):
    """``python -m snakemake --cores 2 *args`` in ``workdir`` (this interpreter)."""
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *args], cwd=workdir,
                          capture_output=True, text=True, timeout=900)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc


@pytest.fixture(scope="session")
def small_workflow(tmp_path_factory):
    """A copy of the workflow in a temporary directory, run to completion with
    the small config ``small.yaml`` (3 seeds, short sweeps)."""
    tmp = tmp_path_factory.mktemp("wf")
    for item in ("Snakefile", "workflow", "config", "modal", "notebooks", "tests/data"):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(src, tmp / item, ignore=shutil.ignore_patterns("__pycache__"))
        elif src.exists():
            shutil.copy(src, tmp / item)
    (tmp / "small.yaml").write_text(yaml.safe_dump(SMALL_CONFIG))
    run_snakemake(tmp, "--configfile", "small.yaml")
    return tmp
