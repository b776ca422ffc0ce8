"""The Constrained ERA (thesis Ch. 5, Eqs. 46-52)."""

from __future__ import annotations

import numpy as np

from ._checks import positive_float, positive_int, records
from .hankel import hankel
from .result import ModalResult, normalise_shapes, sort_modes


def cera(y, dt, n_modes, cols, start=0) -> ModalResult:
    """Identify modes with the CERA.

    The constrained Hankel matrix ``H_c(k)`` has one block row, ``l x (m s)``
    (Eq. 34 with r = 1). Its thin SVD ``P D Q^T`` is truncated to ``n``
    singular values (Eq. 49) and the ``n x n`` eigenproblem
    ``lambda w = D^{-1/2} P^T H_c(k+1) Q D^{-1/2} w`` (Eq. 52) solved; the
    frequency follows from Eq. (30) with ``T_o = dt``:
    ``omega = acos(lambda) / dt``. The symmetric part of the Eq. (52) matrix
    is used (real eigenvalues, orthogonal eigenvectors, Sec. 5.1). Shapes are
    ``P D^{1/2} w`` (as Eq. 45).

    Eq. (52) equals the TCM's eigenproblem only when the ``s`` columns span
    whole periods of every mode (so modal cross-correlations vanish) and the
    damping is light; otherwise expect a bias, largest for the lowest mode
    because ``d omega = d lambda / (dt sin(omega dt))``.

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
        mode); ``eigenvalues`` holds ``lambda``.
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
    h_ext = hankel(y, 2, cols, start)
    h0, h1 = h_ext[:l], h_ext[l:]
    p, sv, qt = np.linalg.svd(h0, full_matrices=False)
    if sv[n_modes - 1] <= sv[0] * np.finfo(float).eps * max(h0.shape):
        raise ValueError(f"n_modes = {n_modes}: H_c has fewer than {n_modes} non-zero singular values")
    p, d, qt = p[:, :n_modes], sv[:n_modes], qt[:n_modes]
    d_isqrt = 1 / np.sqrt(d)
    mat = (d_isqrt[:, None] * (p.T @ h1 @ qt.T)) * d_isqrt[None, :]
    # Eq. (52)'s matrix is symmetric for light damping over whole periods; its
    # symmetric part gives the real eigenvalues and orthogonal eigenvectors the
    # thesis states for the CERA (Sec. 5.1).
    lam, w = np.linalg.eigh((mat + mat.T) / 2)
    bad = np.abs(lam) > 1
    omega = np.arccos(np.clip(lam, -1, 1)) / dt  # Eq. (30), T_o = dt
    shapes = normalise_shapes((p * np.sqrt(d)[None, :]) @ w)
    omega, shapes, c = sort_modes(omega, shapes, real_pole=bad, lam=lam)
    return ModalResult(
        omega=omega,
        shapes=shapes,
        method="cera",
        real_pole=c["real_pole"],
        singular_values=sv,
        eigenvalues=c["lam"],
    )
