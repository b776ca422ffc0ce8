"""The Constrained ERA (thesis Ch. 5, Eqs. 46-52)."""

from __future__ import annotations

import numpy as np

from .._checks import positive_float, positive_int, records, unit_scale
from ._hankel import hankel
from ._result import (ModalResult, near_limit, normalise_shapes, short_window, sort_modes, warn_flags,
                     warn_not_free_response)

#: How Eq. (52) is solved (:func:`cera`'s ``eigenproblem``): the default first.
EIGENPROBLEMS = ("symmetrised", "as_printed")


def cera(y, dt, n_modes, cols, start=0, singular_values=None, eigenproblem="symmetrised") -> ModalResult:
    """Identify modes with the CERA.

    The constrained Hankel matrix ``H_c(k)`` has one block row, ``l x (m s)``
    (Eq. 34 with r = 1). Its thin SVD ``P D Q^T`` is truncated to
    ``singular_values`` singular values (Eq. 49; the thesis, Sec. 5.2: "only n
    singular values are retained", n the number of identified modes, the
    default), and the eigenproblem of Eq. (52),
    ``lambda w = D^{-1/2} P^T H_c(k+1) Q D^{-1/2} w``, is solved; the frequency
    follows from Eq. (30) with ``T_o = dt``: ``omega = acos(lambda) / dt``.
    Shapes are ``P D^{1/2} w`` (as Eq. 45).

    Which matrix is solved, and why (``eigenproblem``):

    - ``"symmetrised"`` (the default): Eq. (52)'s matrix is similar (through
      ``D^{1/2}``) to ``D^{-1} P^T H_c(k+1) Q = D^{-1} (P^T R_1 P) D^{-1}``
      with ``R_1 = H_c(k+1) H_c(k)^T`` the lag-one correlation matrix of the
      channels (``s B``, Eq. 47), since ``Q D = H_c(k)^T P``. ``R_1`` is
      symmetric when the ``s`` columns span whole periods of undamped modes,
      the case in which the thesis derives real eigenvalues and orthogonal
      eigenvectors (Sec. 5.1), so the symmetric part of ``P^T R_1 P`` is taken
      and the symmetric matrix ``D^{-1} sym(P^T R_1 P) D^{-1}`` solved; its
      eigenvectors ``u`` give ``w = D^{1/2} u`` and shapes ``P D u``. This is
      the lag-one TCM (Eq. 30, whose ``B`` :func:`~modal.tcm` symmetrises
      too) projected on the ``n`` dominant directions of ``H_c``. (The
      symmetric part of Eq. (52)'s own matrix is not similar to it unless
      ``P^T R_1 P`` commutes with ``D``, which holds only when the sensors'
      mode-shape matrix has orthogonal columns, as at ``x_i = i L / (l + 1)``
      on a beam.)
    - ``"as_printed"``: Eq. (52)'s matrix as the thesis prints it, not
      symmetric, by a general eigensolver: with ``singular_values = l`` this
      is exactly the lag-one TCM's ``lambda A y = B y`` of Eq. (48) without
      symmetrising ``B``. An eigenvalue with an imaginary part (a complex
      pair) gives no frequency by Eq. (30) and is flagged as one outside
      [-1, 1] is; ``omega`` is then ``acos`` of its real part.

    The two agree, up to round-off, whenever ``R_1`` is symmetric (``s``
    spanning whole periods of undamped modes); otherwise they differ by the
    antisymmetric part of ``R_1``, which the thesis's derivation neglects.

    Exact, up to round-off, for undamped modes when ``s`` spans whole periods
    of every mode (modal cross-correlations vanish) and ``singular_values``
    equals the number of modes in the response; otherwise expect a bias,
    largest for the lowest mode because ``d omega = d lambda / (dt sin(omega dt))``.

    Parameters
    ----------
    y : array_like, shape (n_samples, l) or (m, n_samples, l)
    dt : float
    n_modes : int
        Modes returned, ``n <= l``.
    cols : int
        Block columns ``s``.
    start : int
        ``k``, the first sample.
    singular_values : int, optional
        Singular values retained (the order of Eq. 52's eigenproblem),
        ``n_modes <= singular_values <= l``; default ``n_modes``, as Sec. 5.2
        states. With more, the realisation has more modes than asked for and
        the ``n_modes`` lowest frequencies are returned (e.g. all six
        participating modes realised, the lowest three reported).
    eigenproblem : {"symmetrised", "as_printed"}
        How Eq. (52) is solved (above).

    Returns
    -------
    ModalResult
        ``real_pole`` flags eigenvalues outside [-1, 1] or complex (no
        oscillatory mode by Eq. 30); ``aliased`` frequencies within 2 % of
        ``pi / dt``; ``short_window`` modes with fewer than six periods in
        ``s dt``; ``eigenvalues`` holds ``lambda`` (its real part). A
        :class:`~modal.ModalWarning` names flagged modes, and another warns
        when the record from ``start`` on is not a free response
        (:func:`modal.identification._result.free_response_growth`).

    Raises
    ------
    ValueError
        ``n_modes`` above the channels or Hankel columns, ``singular_values``
        outside ``n_modes ... l``, ``H_c`` of lower rank than the singular
        values retained, or an unknown ``eigenproblem``.
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
    kept = n_modes if singular_values is None else positive_int("singular_values", singular_values)
    if not n_modes <= kept <= min(l, cols * m):
        raise ValueError(f"singular_values = {kept} must lie between n_modes = {n_modes} and the "
                         f"{min(l, cols * m)} singular values of H_c (its channels and columns)")
    if eigenproblem not in EIGENPROBLEMS:
        raise ValueError(f"eigenproblem must be one of {', '.join(EIGENPROBLEMS)}, got {eigenproblem!r}")
    scale = unit_scale(y)
    h_ext = hankel(y / scale, 2, cols, start)
    h0, h1 = h_ext[:l], h_ext[l:]
    p, sv, qt = np.linalg.svd(h0, full_matrices=False)
    if sv[kept - 1] <= sv[0] * np.finfo(float).eps * max(h0.shape):
        named = "n_modes" if singular_values is None else "singular_values"  # the argument the caller gave
        raise ValueError(f"{named} = {kept}: H_c has fewer than {kept} non-zero singular values")
    p, d, qt = p[:, :kept], sv[:kept], qt[:kept]
    if eigenproblem == "symmetrised":
        lagged = (p.T @ h1 @ qt.T) * d[None, :]  # P^T R_1 P, as P^T H_c(k+1) Q D
        lam, u = np.linalg.eigh(((lagged + lagged.T) / 2) / np.outer(d, d))
        shapes = p @ (d[:, None] * u)  # P D^{1/2} w with w = D^{1/2} u
        bad = np.abs(lam) > 1
    else:
        root = np.sqrt(d)
        lam, w = np.linalg.eig((p.T @ h1 @ qt.T) / np.outer(root, root))  # Eq. (52) as printed
        complex_pair = np.abs(lam.imag) > 1e3 * np.finfo(float).eps * max(1.0, np.abs(lam).max())
        lam, shapes = lam.real, p @ (root[:, None] * w)  # P D^{1/2} w (Eq. 45)
        bad = (np.abs(lam) > 1) | complex_pair
    omega = np.arccos(np.clip(lam, -1, 1)) / dt  # Eq. (30), T_o = dt
    omega, shapes, c = sort_modes(omega, normalise_shapes(shapes), real_pole=bad, lam=lam)
    keep = slice(0, n_modes)
    result = ModalResult(
        omega=omega[keep],
        shapes=shapes[:, keep],
        method="cera",
        real_pole=c["real_pole"][keep],
        aliased=near_limit(omega[keep], dt),
        short_window=short_window(omega[keep], cols * dt),
        singular_values=sv * scale,
        eigenvalues=c["lam"][keep],
    )
    warn_not_free_response(result, y[:, start:], dt)
    return warn_flags(result, cols * dt)
