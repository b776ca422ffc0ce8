"""Shared fixtures: the thesis's beam demonstration (Sec. 6.1), used by the
engine's tests and the thesis layer's."""

from pathlib import Path

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
