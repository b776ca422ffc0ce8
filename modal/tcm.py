"""The Temporal Correlation Method (thesis Ch. 3, Eqs. 21-31)."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from ._checks import finite_array, positive_float, positive_int
from .result import ModalResult, normalise_shapes, sort_modes
from .signals import integrate_acceleration


def correlation(a, b) -> np.ndarray:
    """Temporal inner product ``<a, b^T>`` of Eq. (12), truncated to the record:
    the plain mean over samples of ``a(t) b(t)^T``."""
    return a.T @ b / a.shape[0]


def tcm(acc, dt, n_modes=None, vel=None, lag=0, duration=None) -> ModalResult:
    """Identify modes with the TCM.

    ``lag == 0`` (Eq. 31, k = 2, m = 1, T_o = 0):
    ``A = <v, v^T>`` from velocities, ``B = <a, a^T>`` from accelerations,
    ``lambda A x = B x`` (Eq. 26), ``omega = sqrt(lambda)``. When ``vel`` is not
    given it is integrated from ``acc`` (:func:`modal.signals.integrate_acceleration`).

    ``lag > 0`` (Eq. 30, k = m, T_o = lag dt): one signal ``y = acc``,
    ``A = <y(t), y^T(t)>`` and ``B = <y(t + T_o), y^T(t)>`` over the same
    ``n - lag`` instants ``t``, B symmetrised, ``omega = acos(lambda) / T_o``.

    Mode shapes are ``A v_r`` (Eq. 28: ``v_r = M x_r``, and ``A`` plays ``M``
    up to a diagonal modal scaling), normalised.

    Parameters
    ----------
    acc : array_like, shape (n_samples, l)
        The measured signal (the thesis: accelerations).
    dt : float
        Sampling interval (s).
    n_modes : int, optional
        How many of the ``l`` identified modes to return (the lowest);
        default ``l``. The eigenproblem is always ``l x l``: to identify ``n``
        modes as the thesis does, pass ``n`` sensors.
    vel : array_like, shape (n_samples, l), optional
        Velocities for ``A`` when ``lag == 0``.
    lag : int
        Time offset ``T_o`` in samples.
    duration : float, optional
        Truncate the temporal inner products to ``0 <= t <= duration`` s.

    Returns
    -------
    ModalResult
        ``eigenvalues`` holds ``lambda``; ``real_pole`` flags eigenvalues that
        give no real frequency (``lambda < 0`` for lag 0, ``|lambda| > 1`` for lag > 0);
        ``singular_values`` holds the eigenvalues of ``A``.
    """
    acc = finite_array("acc", acc, ndim=(2,))
    dt = positive_float("dt", dt)
    lag = positive_int("lag", lag, minimum=0)
    n_samples, l = acc.shape
    n_modes = l if n_modes is None else positive_int("n_modes", n_modes)
    if n_modes > l:
        raise ValueError(f"n_modes = {n_modes} exceeds the {l} channels; the TCM needs one sensor per mode")
    if vel is not None:
        vel = finite_array("vel", vel, ndim=(2,))
        if vel.shape != acc.shape:
            raise ValueError(f"vel must have the shape of acc {acc.shape}, got {vel.shape}")
    if duration is not None:
        duration = positive_float("duration", duration)
        n_samples = min(n_samples, int(round(duration / dt)) + 1)
    needed = max(lag + l + 1, 3)
    if n_samples < needed:
        raise ValueError(f"too few samples ({n_samples}) for {l} channels and lag {lag}: need at least {needed}")
    acc = acc[:n_samples]

    if lag == 0:
        if vel is None:
            vel = integrate_acceleration(acc, dt)
        a = correlation(vel[:n_samples], vel[:n_samples])
        b = correlation(acc, acc)
    else:
        early, late = acc[: n_samples - lag], acc[lag:]
        a = correlation(early, early)
        b = correlation(late, early)
        b = (b + b.T) / 2
    a_eig = np.linalg.eigvalsh(a)
    if a_eig[0] <= a_eig[-1] * 1e-13:
        raise ValueError("the correlation matrix A is singular: the channels are linearly dependent")
    lam, v = scipy.linalg.eigh(b, a)  # Eq. (26)
    if lag == 0:
        bad = lam < 0
        omega = np.sqrt(np.abs(lam))  # Eq. (31)
    else:
        bad = np.abs(lam) > 1
        omega = np.arccos(np.clip(lam, -1, 1)) / (lag * dt)  # Eq. (30)
    shapes = normalise_shapes(a @ v)  # Eq. (28)
    omega, shapes, cols = sort_modes(omega, shapes, real_pole=bad, lam=lam)
    return ModalResult(
        omega=omega[:n_modes],
        shapes=shapes[:, :n_modes],
        method="tcm",
        real_pole=cols["real_pole"][:n_modes],
        singular_values=a_eig[::-1],
        eigenvalues=cols["lam"][:n_modes],
    )
