"""Structures with known modes: the simply supported Euler-Bernoulli beam."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._checks import finite_array, positive_float, positive_int


@dataclass(frozen=True)
class SimplySupportedBeam:
    """Uniform simply supported Euler-Bernoulli beam (thesis Sec. 6.1, Eqs. 53-54).

    Parameters
    ----------
    length : float
        Span ``L`` in m.
    bending_stiffness : float
        ``EI`` in N m^2.
    mass_per_length : float
        ``m`` in kg/m.
    """

    length: float
    bending_stiffness: float
    mass_per_length: float

    def __post_init__(self):
        positive_float("length", self.length)
        positive_float("bending_stiffness", self.bending_stiffness)
        positive_float("mass_per_length", self.mass_per_length)

    def natural_frequencies(self, n_modes: int) -> np.ndarray:
        """``omega_r = sqrt(EI/m) (r pi / L)^2`` in rad/s, r = 1..n_modes."""
        n_modes = positive_int("n_modes", n_modes)
        r = np.arange(1, n_modes + 1)
        return np.sqrt(self.bending_stiffness / self.mass_per_length) * (r * np.pi / self.length) ** 2

    def mode_shapes(self, x, n_modes: int) -> np.ndarray:
        """Mass-normalised modes ``phi_r(x) = sqrt(2/(mL)) sin(r pi x / L)``
        (Eq. 5), shape ``(len(x), n_modes)``."""
        n_modes = positive_int("n_modes", n_modes)
        x = finite_array("x", np.atleast_1d(x), ndim=(1,))
        if np.any((x < 0) | (x > self.length)):
            raise ValueError(f"x must lie on the beam, 0 <= x <= {self.length}")
        r = np.arange(1, n_modes + 1)
        amp = np.sqrt(2.0 / (self.mass_per_length * self.length))
        return amp * np.sin(np.outer(x, r) * np.pi / self.length)

    def stations(self, n_divisions: int) -> np.ndarray:
        """Interior stations ``x_i = i L / n_divisions``, i = 1..n_divisions-1."""
        n_divisions = positive_int("n_divisions", n_divisions, minimum=2)
        return self.length * np.arange(1, n_divisions) / n_divisions
