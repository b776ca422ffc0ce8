"""Free response of a structure with known modes by modal superposition
(thesis Eqs. 7-8 with modal damping), and sensor noise."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import integrate

from .._checks import finite_array, nonnegative_float, positive_float, positive_int


@dataclass(frozen=True)
class Record:
    """A simulated (or measured) free response.

    Attributes
    ----------
    t : ndarray, shape (n_samples,)
        Time in s, ``t[k] = k dt``.
    displacement, velocity, acceleration : ndarray, shape (n_samples, n_channels)
        Outputs at the sensors.
    dt : float
        Sampling interval in s.
    omega : ndarray, shape (n_modes,)
        Exact undamped natural frequencies of the participating modes (rad/s).
    damping : ndarray, shape (n_modes,)
        Modal damping ratios used.
    shapes : ndarray, shape (n_channels, n_modes)
        Exact (mass-normalised) mode shapes at the sensors.
    """

    t: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    dt: float
    omega: np.ndarray
    damping: np.ndarray
    shapes: np.ndarray

    def signal(self, derivative: int) -> np.ndarray:
        """Output by derivative order: 0 displacement, 1 velocity, 2 acceleration."""
        if isinstance(derivative, bool) or derivative not in (0, 1, 2):
            raise ValueError(f"derivative must be 0, 1 or 2, got {derivative!r}")
        return (self.displacement, self.velocity, self.acceleration)[derivative]


def damping_ratios(damping, n_modes: int) -> np.ndarray:
    """Modal damping ratio per mode from one value or a list; modes beyond
    the list take its last value (a list longer than ``n_modes`` is cut).

    Raises ``ValueError`` unless every ratio satisfies ``0 <= zeta < 1``.
    """
    zeta = np.atleast_1d(np.asarray(damping, dtype=float))
    if zeta.ndim != 1 or zeta.size == 0:
        raise ValueError(f"damping must be a number or a list of numbers, got {damping!r}")
    if not np.all(np.isfinite(zeta)) or np.any(zeta < 0) or np.any(zeta >= 1):
        raise ValueError(f"damping ratios must satisfy 0 <= zeta < 1, got {zeta.tolist()}")
    if zeta.size >= n_modes:
        return zeta[:n_modes].copy()
    return np.concatenate([zeta, np.full(n_modes - zeta.size, zeta[-1])])


def free_decay(omega, damping, x0, t):
    """Closed-form free response of each mode from ``x0 = (q0, v0)`` at ``t = 0``.

    ``q_r(t) = exp(-zeta_r omega_r t) (q0 cos(omega_d t) + (v0 + zeta_r omega_r q0) / omega_d sin(omega_d t))``
    with ``omega_d = omega_r sqrt(1 - zeta_r^2)`` (Eq. 8 without force); an
    impulse ``f_r`` at ``t = 0`` is the initial velocity ``v0 = f_r``
    (:func:`impulse_response`).

    Parameters
    ----------
    omega, damping : array_like, shape (n_modes,)
        Natural frequencies (rad/s) and modal damping ratios.
    x0 : array_like, shape (n_modes, 2)
        Initial modal displacement and velocity.
    t : array_like
        Times (s).

    Returns
    -------
    q, v, a : ndarray, shape (len(t), n_modes)
    """
    omega = np.atleast_1d(np.asarray(omega, dtype=float))
    zeta = np.broadcast_to(np.asarray(damping, dtype=float), omega.shape)
    q0, v0 = np.asarray(x0, dtype=float).T
    sigma = zeta * omega
    wd = omega * np.sqrt(1 - zeta**2)
    t = np.asarray(t, dtype=float)[:, None]
    e = np.exp(-sigma * t)
    c, s = np.cos(wd * t), np.sin(wd * t)
    q = e * (q0 * c + (v0 + sigma * q0) / wd * s)
    v = e * (v0 * c - (sigma * v0 + omega**2 * q0) / wd * s)
    a = -(omega**2) * q - 2 * sigma * v
    return q, v, a


def impulse_response(omega, shapes_at_sensors, modal_impulse, dt, n_samples, damping=0.0) -> Record:
    """Response to a unit impulse at t = 0 by modal superposition.

    Each modal coordinate obeys ``u_r'' + 2 zeta_r omega_r u_r' + omega_r^2 u_r = f_r delta(t)``
    (Eq. 8 with modal damping ratio ``zeta_r``): a free decay from rest with
    initial velocity ``f_r`` (:func:`free_decay`), so for t >= 0+

    ``u_r(t) = f_r / omega_d exp(-zeta_r omega_r t) sin(omega_d t)``,
    ``omega_d = omega_r sqrt(1 - zeta_r^2)``,

    and the sensor outputs are ``y(t) = Phi u(t)`` (Eq. 7). Velocity and
    acceleration are the exact derivatives.

    Parameters
    ----------
    omega : array_like, shape (n_modes,)
        Undamped natural frequencies (rad/s).
    shapes_at_sensors : array_like, shape (n_channels, n_modes)
        Mode shapes evaluated at the sensors.
    modal_impulse : array_like, shape (n_modes,)
        Modal force of the impulse, ``f_r = phi_r(x_0)`` (Eq. 10).
    dt : float
        Sampling interval (s).
    n_samples : int
        Number of samples, ``t = 0, dt, ..., (n_samples-1) dt``.
    damping : float or array_like
        Modal damping ratio(s) ``zeta``.
    """
    omega = finite_array("omega", np.atleast_1d(omega), ndim=(1,))
    if np.any(omega <= 0):
        raise ValueError("omega must be > 0")
    n_modes = omega.size
    shapes = finite_array("shapes_at_sensors", shapes_at_sensors, ndim=(2,))
    if shapes.shape[1] != n_modes:
        raise ValueError(f"shapes_at_sensors must have {n_modes} columns, got {shapes.shape[1]}")
    f = finite_array("modal_impulse", np.atleast_1d(modal_impulse), ndim=(1,))
    if f.size != n_modes:
        raise ValueError(f"modal_impulse must have {n_modes} entries, got {f.size}")
    dt = positive_float("dt", dt)
    n_samples = positive_int("n_samples", n_samples, minimum=2)
    zeta = damping_ratios(damping, n_modes)

    t = dt * np.arange(n_samples)
    u, v, a = free_decay(omega, zeta, np.column_stack([np.zeros(n_modes), f]), t)
    return Record(
        t=t,
        displacement=u @ shapes.T,
        velocity=v @ shapes.T,
        acceleration=a @ shapes.T,
        dt=dt,
        omega=omega,
        damping=zeta,
        shapes=shapes,
    )


def beam_impulse_response(beam, n_modes, impact_x, sensor_x, dt, n_samples, damping=0.0) -> Record:
    """Unit impulse at ``impact_x`` on a :class:`~modal.structures.SimplySupportedBeam`
    with its ``n_modes`` lowest modes participating, observed at ``sensor_x``
    (thesis Sec. 6.1)."""
    omega = beam.natural_frequencies(n_modes)
    return impulse_response(
        omega,
        beam.mode_shapes(sensor_x, n_modes),
        beam.mode_shapes([impact_x], n_modes)[0],
        dt,
        n_samples,
        damping,
    )


#: How the noise's standard deviation is scaled (the thesis, Sec. 6.1: "at one
#: standard deviation, the noise added is 5% of the measurement"; which
#: measure of "the measurement" it means is not stated).
NOISE_SCALES = ("channel_rms", "record_rms", "channel_peak", "proportional")

#: Where the noisy record's velocity and displacement come from: their own
#: independent sensor noise ("noisy"), noise-free ("exact": only the
#: accelerometers are noisy), or integrated from the noisy acceleration with
#: the trapezoidal rule from their exact initial values ("integrated", as
#: Sec. 6.4 says real applications may have to).
VELOCITY_SOURCES = ("noisy", "exact", "integrated")


def add_noise(y, noise_ratio, rng, scale: str = "channel_rms") -> np.ndarray:
    """Add Gaussian sensor noise with standard deviation ``noise_ratio`` times
    a measure of the signal (the thesis's ``eta``; 5 % -> 0.05).

    Parameters
    ----------
    y : array_like, shape (n_samples, n_channels)
    noise_ratio : float
        ``eta >= 0`` as a fraction.
    rng : numpy.random.Generator or int
        Generator, or a seed for one.
    scale : {"channel_rms", "record_rms", "channel_peak", "proportional"}
        The measure: each channel's RMS (default), the RMS over all channels,
        each channel's peak ``max |y|``, or the sample itself (``|y(t)|``:
        noise proportional to the measurement at each instant).
    """
    y = finite_array("y", y, ndim=(2,))
    eta = nonnegative_float("noise_ratio", noise_ratio)
    rng = np.random.default_rng(rng)
    if scale == "channel_rms":
        size = np.sqrt(np.mean(y**2, axis=0))
    elif scale == "record_rms":
        size = np.sqrt(np.mean(y**2))
    elif scale == "channel_peak":
        size = np.max(np.abs(y), axis=0)
    elif scale == "proportional":
        size = np.abs(y)
    else:
        raise ValueError(f"scale must be one of {', '.join(NOISE_SCALES)}, got {scale!r}")
    return y + eta * size * rng.standard_normal(y.shape)


def with_noise(record: Record, noise_ratio, seed, scale: str = "channel_rms", velocity: str = "noisy") -> Record:
    """The record with sensor noise (:func:`add_noise`).

    Noise is drawn for displacement, velocity and acceleration, in that order,
    from ``numpy.random.default_rng(seed)`` (so every ``velocity`` choice sees
    the same acceleration noise). ``velocity`` says where the noisy record's
    velocity and displacement come from: ``"noisy"`` (each with its own
    noise), ``"exact"`` (noise-free) or ``"integrated"`` (trapezoidal
    integrals of the noisy acceleration, then of that velocity, from the
    exact initial values).
    """
    if velocity not in VELOCITY_SOURCES:
        raise ValueError(f"velocity must be one of {', '.join(VELOCITY_SOURCES)}, got {velocity!r}")
    rng = np.random.default_rng(seed)
    noisy = [add_noise(record.signal(d), noise_ratio, rng, scale) for d in range(3)]
    if velocity == "exact":
        noisy[:2] = record.displacement, record.velocity
    elif velocity == "integrated":
        vel = record.velocity[0] + integrate.cumulative_trapezoid(noisy[2], dx=record.dt, axis=0, initial=0)
        disp = record.displacement[0] + integrate.cumulative_trapezoid(vel, dx=record.dt, axis=0, initial=0)
        noisy[:2] = disp, vel
    return Record(record.t, *noisy, record.dt, record.omega, record.damping, record.shapes)
