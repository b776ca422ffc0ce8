"""The Eigensystem Realization Algorithm (thesis Ch. 4, Eqs. 34-45)."""

from __future__ import annotations

import numpy as np

from ._checks import positive_float, positive_int, records, unit_scale
from .hankel import hankel
from .indicators import modal_amplitude_coherence, modal_phase_collinearity
from .result import UNSTABLE_TOL, ModalResult, near_limit, normalise_shapes, short_window, sort_modes, warn_flags

#: |Im z| below this (relative to |z|) makes an eigenvalue a real pole.
REAL_POLE_TOL = 1e-10


def era(y, dt, n_modes, rows, cols, start=0) -> ModalResult:
    """Identify modes with the ERA.

    Builds ``H(k-1)`` and ``H(k)`` of Eq. (34) from one Hankel with ``rows + 1``
    block rows, takes the thin SVD ``H(0) = U S V^T`` (Eq. 35), keeps the
    ``2 n_modes`` largest singular values ``P D Q^T`` (Sec. 4.4), realizes
    ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` and ``H = E_p^T P D^{1/2}``
    (Eqs. 41, 43), solves ``Phi psi = psi z`` (Eq. 42) and maps
    ``s = ln z / dt`` (Eq. 44, j = 0). The natural frequency is ``|s|`` and
    the damping ratio ``-Re s / |s|``; mode shapes are ``E_p^T P D^{1/2} psi``
    (Eq. 45). Each complex-conjugate pair gives one mode; a real eigenvalue
    gives one entry flagged ``real_pole`` (its damping is NaN).

    Parameters
    ----------
    y : array_like, shape (n_samples, l) or (m, n_samples, l)
        Free or impulse response, one or ``m`` data sets.
    dt : float
        Sampling interval (s).
    n_modes : int
        ``n``; ``2 n`` singular values are kept.
    rows, cols : int
        Block rows ``r`` and block columns ``s`` of Eq. (34).
    start : int
        First sample used (``k - 1`` in Eq. 34).

    Returns
    -------
    ModalResult
        With ``mamc``, ``mpc``, all ``singular_values`` of ``H(0)`` and the
        discrete eigenvalues ``z`` (one per mode).
    """
    y = records("y", y)
    dt = positive_float("dt", dt)
    n_modes = positive_int("n_modes", n_modes)
    rows = positive_int("rows", rows)
    cols = positive_int("cols", cols)
    m, _, l = y.shape
    order = 2 * n_modes
    if order > min(rows * l, cols * m):
        raise ValueError(
            f"2 * n_modes = {order} exceeds the smaller dimension of the Hankel "
            f"matrix ({rows * l} x {cols * m}): reduce n_modes or enlarge rows/cols"
        )
    scale = unit_scale(y)
    h_ext = hankel(y / scale, rows + 1, cols, start)
    h0, h1 = h_ext[:-l], h_ext[l:]
    p, d, qt, sv = decompose(h0, order)
    if d[-1] <= sv[0] * np.finfo(float).eps * max(h0.shape):
        raise ValueError(
            f"n_modes = {n_modes}: the Hankel matrix has fewer than {order} non-zero "
            "singular values; the data cannot support that many modes"
        )
    result = realise(p, d, qt, h1, n_channels=l, n_sets=m, dt=dt, singular_values=sv * scale,
                     window=(rows + cols) * dt)
    return warn_flags(result, (rows + cols) * dt)


def decompose(h0, order):
    """The ``order`` dominant singular triplets of ``H(0)`` (Eq. 35, Sec. 4.4).

    Returns
    -------
    p : ndarray, shape (l r, order)
        Leading left singular vectors ``P``.
    d : ndarray, shape (order,)
        Leading singular values ``D``, decreasing.
    qt : ndarray, shape (order, m s)
        Leading right singular vectors ``Q^T``.
    singular_values : ndarray
        Every singular value computed (all of them for the full SVD).
    """
    # Thin SVD (Eq. 35) by LAPACK gesdd; numpy hands the C-ordered H(0) to
    # LAPACK as its transpose without a copy, which scipy.linalg.svd does not.
    u, sv, vt = np.linalg.svd(h0, full_matrices=False)
    return u[:, :order], sv[:order], vt[:order], sv


def realise(p, d, qt, h1, n_channels, n_sets, dt, singular_values=None, window=np.inf) -> ModalResult:
    """Realize the state matrix from ``P D Q^T`` and ``H(1)`` and extract modes.

    ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` and ``H = E_p^T P D^{1/2}``
    (Eqs. 41, 43), ``Phi psi = psi z`` (Eq. 42), ``s = ln z / dt`` (Eq. 44,
    j = 0), shapes ``E_p^T P D^{1/2} psi`` (Eq. 45). The model order is
    ``len(d)``; truncating ``p``, ``d``, ``qt`` to their first columns gives
    every lower order from one decomposition. ``window`` (s) is the span of
    data behind the Hankel matrix, for the ``short_window`` flag.
    """
    l, m = n_channels, n_sets
    d_isqrt = 1 / np.sqrt(d)
    phi = (d_isqrt[:, None] * (p.T @ h1 @ qt.T)) * d_isqrt[None, :]
    z, psi = np.linalg.eig(phi)  # Eq. (42)
    complex_shapes = (p[:l] * np.sqrt(d)[None, :]) @ psi  # Eq. (45): E_p^T P D^{1/2} psi
    histories = np.linalg.solve(psi, np.sqrt(d)[:, None] * qt)  # modal amplitudes over the columns

    # One entry per conjugate pair (Im z > 0) and per real eigenvalue.
    real = np.abs(z.imag) <= REAL_POLE_TOL * np.abs(z)
    keep = real | (z.imag > 0)
    z, real = z[keep], real[keep]
    complex_shapes, histories = complex_shapes[:, keep], histories[keep]
    with np.errstate(divide="ignore"):
        s = np.log(z.astype(complex)) / dt  # Eq. (44), j = 0
    omega = np.abs(s)
    damping = np.where(real, np.nan, -s.real / np.where(omega > 0, omega, 1))
    with np.errstate(over="ignore", invalid="ignore"):
        mamc = np.nan_to_num(modal_amplitude_coherence(histories, z, m), nan=0.0)
    mpc = modal_phase_collinearity(complex_shapes)

    unstable = np.abs(z) > 1 + UNSTABLE_TOL
    aliased = near_limit(np.abs(s.imag), dt)

    omega, shapes, cols_ = sort_modes(
        omega, normalise_shapes(complex_shapes), damping=damping, real_pole=real, unstable=unstable,
        aliased=aliased, mamc=mamc, mpc=mpc, z=z
    )
    return ModalResult(
        omega=omega,
        shapes=shapes,
        method="era",
        damping=cols_["damping"],
        real_pole=cols_["real_pole"],
        unstable=cols_["unstable"],
        aliased=cols_["aliased"],
        short_window=short_window(omega, window),
        mamc=cols_["mamc"],
        mpc=cols_["mpc"],
        singular_values=d if singular_values is None else singular_values,
        eigenvalues=cols_["z"],
    )
