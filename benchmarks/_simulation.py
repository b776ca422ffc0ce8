"""Exact simulation of ambient records of lumped-mass structures, shared by
the benchmarks (``bench_selection.py``, ``bench_uncertainty.py``), and
the free decay of an impact whose damping falls with its amplitude
(``bench_impact.py``, ``tests/engine/identification/test_blends.py``).

A structure is its mass, damping and stiffness matrices; the record is the
accelerations at some DOFs under independent random forces at every DOF,
white or coloured, simulated in state space with the forces held over each
sample (zero-order hold: exact for such forces), plus white sensor noise.
Everything is drawn from the generator passed in, so a record is fixed by
its seed.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.signal


def chain(masses, stiffnesses):
    """Mass and stiffness matrices of a fixed-free chain: storey ``i``
    joins floor ``i`` to the one below (the ground below the first), so
    ``K = D^T diag(k) D`` with ``D x`` the storey drifts."""
    n = len(masses)
    drift = np.eye(n) - np.eye(n, k=-1)
    return np.diag(masses), drift.T @ np.diag(stiffnesses) @ drift


def from_modes(omega, modes):
    """Mass and stiffness matrices of a structure with natural frequencies
    ``omega`` (rad/s) and mass-normalised ``modes`` (DOFs x modes, square):
    ``Phi^T M Phi = I`` gives ``M = (Phi Phi^T)^-1``, and ``K = M Phi
    diag(omega^2) Phi^T M``."""
    modes = np.asarray(modes, dtype=float)
    m = np.linalg.inv(modes @ modes.T)
    return m, m @ modes @ np.diag(np.square(omega)) @ modes.T @ m


def proportional(m, k, zeta):
    """Damping matrix giving each mode the damping ratio ``zeta[r]``."""
    w2, phi = scipy.linalg.eigh(k, m)
    phi = phi / np.sqrt(np.einsum("ir,ij,jr->r", phi, m, phi))
    modal_c = np.diag(2 * np.asarray(zeta) * np.sqrt(w2))
    inv = np.linalg.inv(phi)
    return inv.T @ modal_c @ inv


def with_dashpot(c, dof, value):
    """``c`` with a dashpot of ``value`` (N s/m) from ``dof`` to the ground:
    damping no longer proportional, the modes complex."""
    c = np.array(c, dtype=float)
    c[dof, dof] += value
    return c


def natural_hz(m, k, mode):
    """Undamped natural frequency (Hz) of mode number ``mode`` (0 the lowest)."""
    return float(np.sqrt(scipy.linalg.eigh(k, m, eigvals_only=True)[mode]) / (2 * np.pi))


def simulate(m, c, k, sensors, dt, n_samples, rng, colour_hz=None, noise=0.02):
    """Accelerations at the ``sensors`` (DOF indices) under independent
    forces at every DOF, with white noise of ``noise`` times each channel's
    RMS; and the true modes.

    The forces are white, or coloured: low-passed at ``colour_hz`` by a
    second-order Butterworth filter (40 dB/decade less force above it), so
    the modes above it are excited less and the response is no longer the
    white-noise response the identification assumes.

    Returns
    -------
    acc : ndarray, shape (n_samples, len(sensors))
    freq_hz : ndarray
        The true modes' frequencies, ``|lambda| / 2 pi`` of the state
        matrix's eigenvalues (upper half plane, ascending).
    damping : ndarray
        Their damping ratios ``-Re lambda / |lambda|``.
    """
    n = len(m)
    inv = np.linalg.inv(m)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-inv @ k, -inv @ c]])
    b = np.vstack([np.zeros((n, n)), inv])
    ad = scipy.linalg.expm(a * dt)
    bd = np.linalg.solve(a, (ad - np.eye(2 * n)) @ b)
    f = rng.standard_normal((n_samples, n))
    if colour_hz is not None:
        sos = scipy.signal.butter(2, colour_hz, fs=1 / dt, output="sos")
        f = scipy.signal.sosfilt(sos, f, axis=0)
    x = np.zeros((n_samples, 2 * n))
    for t in range(1, n_samples):
        x[t] = ad @ x[t - 1] + bd @ f[t - 1]
    acc = x @ a[n:].T + f @ inv.T
    acc = acc[:, sensors]
    acc += noise * acc.std(axis=0) * rng.standard_normal(acc.shape)
    lam = np.linalg.eigvals(a)
    lam = lam[lam.imag > 0]
    lam = lam[np.argsort(np.abs(lam))]
    return acc, np.abs(lam) / (2 * np.pi), -lam.real / np.abs(lam)


def falling_damping_decays(freq_hz, low, shapes, dt, n_samples, seed=0, growth=3.0, quiet=256):
    """An impact's free decay whose damping falls with the amplitude (friction
    in a joint): each mode ``q'' + 2 zeta(a) omega q' + omega^2 q = 0``, from
    ``q' = a_0 omega`` (``a_0`` drawn in 0.5-1), with ``zeta(a) = low (1 +
    growth min(a / a_0, 1))``: four times ``low`` at the blow, ``low`` at the
    end (``scipy.integrate.solve_ivp``); acceleration after ``quiet`` samples
    of none, with 0.1 % noise."""
    from scipy.integrate import solve_ivp

    rng = np.random.default_rng(seed)
    omega, low = 2 * np.pi * np.asarray(freq_hz), np.asarray(low)
    a0 = rng.uniform(0.5, 1.0, len(omega))
    n = len(omega)

    def zeta(q, v):  # q, v: (n_modes,) or (n_modes, n_samples)
        q, v = q.T, v.T
        return (low * (1 + growth * np.minimum(np.sqrt(q**2 + (v / omega) ** 2) / a0, 1))).T

    def motion(_, x):
        q, v = x[:n], x[n:]
        return np.concatenate([v, -2 * zeta(q, v) * omega * v - omega**2 * q])

    t = dt * np.arange(n_samples)
    q, v = np.split(solve_ivp(motion, (0, t[-1]), np.concatenate([np.zeros(n), a0 * omega]), t_eval=t, rtol=1e-9,
                              atol=1e-12, method="DOP853").y, 2)
    acc = np.vstack([np.zeros((quiet, len(shapes))),
                     (shapes @ (-2 * zeta(q, v) * omega[:, None] * v - omega[:, None] ** 2 * q)).T])
    return acc + 1e-3 * acc.std() * rng.standard_normal(acc.shape)


def storey_frame(rng, n=15):
    """``(m, c, k)`` of a tall shear frame drawn from ``rng``: ``n`` storeys
    of 0.8-1.2 x 10^6 kg, storey stiffness falling linearly from 4.4 to 2.5 x
    10^8 N/m up the height (0.31-7.3 Hz for fifteen), proportional damping
    0.8-3 % drawn per mode: its upper modes lie a few half-power bandwidths
    apart, so their peaks overlap."""
    m, k = chain(rng.uniform(0.8, 1.2, n) * 1e6, np.linspace(1.4, 0.8, n) * 2.5e9 / 8)
    return m, proportional(m, k, rng.uniform(0.008, 0.03, n)), k
