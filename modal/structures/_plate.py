"""A structure with known two-dimensional modes, the simply supported
Kirchhoff plate, and its ambient response: the truth a simulated roving
test is checked against."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._checks import finite_array, positive_float, positive_int
from ._shake_test import foh_modal_response
from ._simulate import damping_ratios


@dataclass(frozen=True)
class SimplySupportedPlate:
    """Uniform rectangular Kirchhoff plate, simply supported on all edges.

    Parameters
    ----------
    length_x, length_y : float
        Sides ``a`` and ``b`` (m).
    bending_stiffness : float
        ``D = E h^3 / (12 (1 - nu^2))`` (N m).
    mass_per_area : float
        ``rho h`` (kg/m^2).
    """

    length_x: float
    length_y: float
    bending_stiffness: float
    mass_per_area: float

    def __post_init__(self):
        for name in ("length_x", "length_y", "bending_stiffness", "mass_per_area"):
            positive_float(name, getattr(self, name))

    def mode_numbers(self, n_modes: int) -> np.ndarray:
        """Half-wave numbers ``(m, n)`` of the lowest ``n_modes`` modes, by
        frequency; shape ``(n_modes, 2)``."""
        n_modes = positive_int("n_modes", n_modes)
        k = n_modes + 1
        m, n = np.meshgrid(np.arange(1, k + 1), np.arange(1, k + 1), indexing="ij")
        pairs = np.column_stack([m.ravel(), n.ravel()])
        key = (pairs[:, 0] / self.length_x) ** 2 + (pairs[:, 1] / self.length_y) ** 2
        return pairs[np.argsort(key, kind="stable")[:n_modes]]

    def natural_frequencies(self, n_modes: int) -> np.ndarray:
        """``omega_mn = pi^2 ((m/a)^2 + (n/b)^2) sqrt(D / (rho h))`` (rad/s)."""
        mn = self.mode_numbers(n_modes)
        return np.pi**2 * ((mn[:, 0] / self.length_x) ** 2 + (mn[:, 1] / self.length_y) ** 2) * \
            np.sqrt(self.bending_stiffness / self.mass_per_area)

    def mode_shapes(self, xy, n_modes: int) -> np.ndarray:
        """Mass-normalised ``2 / sqrt(rho h a b) sin(m pi x / a) sin(n pi y / b)``
        at the points ``xy`` (k, 2); shape ``(k, n_modes)``."""
        xy = finite_array("xy", np.atleast_2d(xy), ndim=(2,))
        if xy.shape[1] != 2:
            raise ValueError(f"xy must be (n_points, 2), got shape {xy.shape}")
        mn = self.mode_numbers(n_modes)
        amp = 2 / np.sqrt(self.mass_per_area * self.length_x * self.length_y)
        return amp * np.sin(np.pi * np.outer(xy[:, 0], mn[:, 0]) / self.length_x) * \
            np.sin(np.pi * np.outer(xy[:, 1], mn[:, 1]) / self.length_y)


def ambient_response(omega, damping, sensor_shapes, force_shapes, n_samples, dt, seed=0, force_rms=1.0):
    """Accelerations of a structure under independent white forces (ambient
    excitation), exact for forces linear between samples
    (:func:`foh_modal_response`).

    Parameters
    ----------
    omega : array_like, shape (n_modes,)
        Natural frequencies (rad/s).
    damping : float or sequence
        Damping ratios (:func:`damping_ratios`).
    sensor_shapes : array_like, shape (n_sensors, n_modes)
        Mass-normalised modes at the sensors, along their directions.
    force_shapes : array_like, shape (n_forces, n_modes)
        The same at the points the forces act on.
    n_samples : int
    dt : float
    seed : int
        Seed of the forces (numpy's default generator).
    force_rms : float

    Returns
    -------
    ndarray, shape (n_samples, n_sensors)
    """
    omega = finite_array("omega", np.atleast_1d(omega), ndim=(1,))
    n_samples = positive_int("n_samples", n_samples, minimum=2)
    dt = positive_float("dt", dt)
    sensors = finite_array("sensor_shapes", sensor_shapes, ndim=(2,))
    forces = finite_array("force_shapes", force_shapes, ndim=(2,))
    if sensors.shape[1] != omega.size or forces.shape[1] != omega.size:
        raise ValueError(f"sensor_shapes and force_shapes need one column per mode ({omega.size}), got "
                         f"{sensors.shape} and {forces.shape}")
    f = positive_float("force_rms", force_rms) * np.random.default_rng(seed).standard_normal((n_samples,
                                                                                              forces.shape[0]))
    _, _, a = foh_modal_response(omega, damping_ratios(damping, omega.size), f @ forces, dt)
    return a @ sensors.T
