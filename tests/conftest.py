"""Shared fixtures: the thesis's beam demonstration (Sec. 6.1), used by the
engine's tests and the thesis layer's."""

import os
from pathlib import Path

import numpy as np
import pytest

import modal

#: Snakemake runs locally in every test but the Slurm ones (which take the
#: cluster's configuration back, tests/workflow/test_slurm.py). The Slurm
#: executor plugin (2.8.0) runs ``scontrol show config`` when Snakemake
#: imports it, in every Snakemake process: where Slurm's client is installed
#: and no controller answers (this CI machine between Slurm tests), that waits
#: 9 s per process, 20-40 % of the slow lane. Pointed at an empty
#: configuration, ``scontrol`` fails at once and the plugin carries on. A
#: configuration of the user's own (``SLURM_CONF`` set) is kept.
os.environ.setdefault("SLURM_CONF", os.devnull)

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
