"""The Constrained ERA (thesis Ch. 5, Eqs. 46-52)."""

from __future__ import annotations

import numpy as np

from .._checks import positive_float, positive_int, records, unit_scale
from ._hankel import hankel
from ._result import (ModalResult, near_limit, normalise_shapes, short_window, sort_modes, warn_flags,
                     warn_not_free_response)


def cera(y, dt, n_modes, cols, start=0) -> ModalResult:
    """Identify modes with the CERA.

    The constrained Hankel matrix ``H_c(k)`` has one block row, ``l x (m s)``
    (Eq. 34 with r = 1). Its thin SVD ``P D Q^T`` is truncated to ``n``
    singular values (Eq. 49), and the eigenproblem of Eq. (52),
    ``lambda w = D^{-1/2} P^T H_c(k+1) Q D^{-1/2} w``, is solved; the frequency
    follows from Eq. (30) with ``T_o = dt``: ``omega = acos(lambda) / dt``.
    Shapes are ``P D^{1/2} w`` (as Eq. 45).

    Which matrix is solved, and why: Eq. (52)'s matrix is similar (through
    ``D^{1/2}``) to ``D^{-1} P^T H_c(k+1) Q = D^{-1} (P^T R_1 P) D^{-1}`` with
    ``R_1 = H_c(k+1) H_c(k)^T`` the lag-one correlation matrix of the
    channels, since ``Q D = H_c(k)^T P``. ``R_1`` is symmetric when the ``s``
    columns span whole periods of undamped modes, the case in which the thesis
    derives real eigenvalues and orthogonal eigenvectors (Sec. 5.1), so the
    symmetric part of ``P^T R_1 P`` is taken and the symmetric matrix
    ``D^{-1} sym(P^T R_1 P) D^{-1}`` solved; its eigenvectors ``u`` give
    ``w = D^{1/2} u`` and shapes ``P D u``. This is the lag-one TCM (Eq. 30)
    projected on the ``n`` dominant directions of ``H_c``. (The symmetric part
    of Eq. (52)'s own matrix is not similar to it unless ``P^T R_1 P``
    commutes with ``D``, which holds only when the sensors' mode-shape matrix
    has orthogonal columns, as at ``x_i = i L / (l + 1)`` on a beam.)

    Exact, up to round-off, for undamped modes when ``s`` spans whole periods
    of every mode (modal cross-correlations vanish) and ``n`` equals the
    number of modes in the response; otherwise expect a bias, largest for the
    lowest mode because ``d omega = d lambda / (dt sin(omega dt))``.

    Parameters
    ----------
    y : array_like, shape (n_samples, l) or (m, n_samples, l)
    dt : float
    n_modes : int
        ``n <= l``.
    cols : int
        Block columns ``s``.
    start : int
        ``k``, the first sample.

    Returns
    -------
    ModalResult
        ``real_pole`` flags eigenvalues outside [-1, 1] (no oscillatory
        mode); ``aliased`` frequencies within 2 % of ``pi / dt``;
        ``short_window`` modes with fewer than six periods in ``s dt``;
        ``eigenvalues`` holds ``lambda``. A :class:`~modal.ModalWarning` names
        flagged modes, and another warns when the record from ``start`` on is
        not a free response (:func:`modal.identification._result.free_response_growth`).
    """
    y = records("y", y)
    dt = positive_float("dt", dt)
    n_modes = positive_int("n_modes", n_modes)
    cols = positive_int("cols", cols)
    m, _, l = y.shape
    if n_modes > l:
        raise ValueError(f"n_modes = {n_modes} exceeds the {l} channels; the CERA needs l >= n")
    if n_modes > cols * m:
        raise ValueError(f"n_modes = {n_modes} exceeds the {cols * m} Hankel columns")
    scale = unit_scale(y)
    h_ext = hankel(y / scale, 2, cols, start)
    h0, h1 = h_ext[:l], h_ext[l:]
    p, sv, qt = np.linalg.svd(h0, full_matrices=False)
    if sv[n_modes - 1] <= sv[0] * np.finfo(float).eps * max(h0.shape):
        raise ValueError(f"n_modes = {n_modes}: H_c has fewer than {n_modes} non-zero singular values")
    p, d, qt = p[:, :n_modes], sv[:n_modes], qt[:n_modes]
    lagged = (p.T @ h1 @ qt.T) * d[None, :]  # P^T R_1 P, as P^T H_c(k+1) Q D
    lam, u = np.linalg.eigh(((lagged + lagged.T) / 2) / np.outer(d, d))
    bad = np.abs(lam) > 1
    omega = np.arccos(np.clip(lam, -1, 1)) / dt  # Eq. (30), T_o = dt
    shapes = normalise_shapes(p @ (d[:, None] * u))  # P D^{1/2} w with w = D^{1/2} u
    omega, shapes, c = sort_modes(omega, shapes, real_pole=bad, lam=lam)
    result = ModalResult(
        omega=omega,
        shapes=shapes,
        method="cera",
        real_pole=c["real_pole"],
        aliased=near_limit(omega, dt),
        short_window=short_window(omega, cols * dt),
        singular_values=sv * scale,
        eigenvalues=c["lam"],
    )
    warn_not_free_response(result, y[:, start:], dt)
    return warn_flags(result, cols * dt)
