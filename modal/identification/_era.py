"""The Eigensystem Realization Algorithm (thesis Ch. 4, Eqs. 34-45)."""

from __future__ import annotations

import numpy as np

from .._checks import finite_array, positive_float, positive_int, records, square_matrix, unit_scale
from ._era_kernels import complex_poles, decompose, decompose_method, real_eigensystem
from ._hankel import hankel
from ._indicators import mean_phase_deviation, modal_amplitude_coherence, modal_phase_collinearity
from ._result import (UNSTABLE_TOL, ModalResult, near_limit, normalise_complex_shapes, normalise_shapes,
                      short_window, sort_modes, warn_flags, warn_not_free_response)

def era(y, dt, n_modes, rows, cols, start=0, svd="auto") -> ModalResult:
    """Identify modes with the ERA.

    Builds ``H(k-1)`` and ``H(k)`` of Eq. (34) from one Hankel with ``rows + 1``
    block rows, takes the SVD ``H(0) = U S V^T`` (Eq. 35), keeps the
    ``2 n_modes`` largest singular values ``P D Q^T`` (Sec. 4.4), realizes
    ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` and ``H = E_p^T P D^{1/2}``
    (Eqs. 41, 43), solves ``Phi psi = psi z`` (Eq. 42) and maps
    ``s = ln z / dt`` (Eq. 44, j = 0). The natural frequency is ``|s|`` and
    the damping ratio ``-Re s / |s|``; mode shapes are ``E_p^T P D^{1/2} psi``
    (Eq. 45). Each complex-conjugate pair gives one mode; a real eigenvalue
    gives one entry flagged ``real_pole`` (its damping is NaN). Entries with
    ``|z| > 1`` are flagged ``unstable``, damped frequencies within 2 % of the
    Nyquist frequency ``pi / dt`` ``aliased``, and modes with fewer than six
    periods in the ``(rows + cols) dt`` seconds the Hankel matrix spans
    ``short_window``; a :class:`~modal.ModalWarning` names them. Another
    warns when the record from ``start`` on is not a free response (its
    energy keeps rising, as an ambient record's does;
    :func:`modal.identification._result.free_response_growth`): use the NExT correlation
    functions (:func:`modal.correlations`) of such records instead.

    The data are divided by a power of two near their peak before the Hankel
    matrix is formed, so results do not depend on units or scale.

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
    svd : {"auto", "full", "gram"}
        How the ``2 n`` leading singular triplets of ``H(0)`` are computed (see
        :func:`decompose`): ``"full"`` thin SVD, ``"gram"`` the Gram matrix's
        eigenvectors refined by Rayleigh-Ritz and checked (falling back to the
        thin SVD when the check fails), ``"auto"`` the Gram route where it
        costs less than half the thin SVD (:func:`modal.identification._era_kernels.gram_pays`).

    Returns
    -------
    ModalResult
        With ``mamc``, ``mpc``, the ``singular_values`` of ``H(0)`` (all of them
        from the thin SVD; the ``2 n`` leading ones from the Gram route) and
        the discrete eigenvalues ``z`` (one per mode).
    """
    svd = decompose_method("svd", svd)
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
    p, d, qt, sv = decompose(h0, order, method=svd, block=(l, m))
    if d[-1] <= sv[0] * np.finfo(float).eps * max(h0.shape):
        raise ValueError(
            f"n_modes = {n_modes}: the Hankel matrix has fewer than {order} non-zero "
            "singular values; the data cannot support that many modes"
        )
    result = realise(p, d, qt, h1, n_channels=l, n_sets=m, dt=dt, singular_values=sv * scale,
                     window=(rows + cols) * dt)
    warn_not_free_response(result, y[:, start:], dt)
    return warn_flags(result, (rows + cols) * dt)


def realise(p, d, qt, h1, n_channels, n_sets, dt, singular_values=None, window=np.inf) -> ModalResult:
    """Realize the state matrix from ``P D Q^T`` and ``H(1)`` and extract modes.

    ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` and ``H = E_p^T P D^{1/2}``
    (Eqs. 41, 43), ``Phi psi = psi z`` (Eq. 42), ``s = ln z / dt`` (Eq. 44,
    j = 0), shapes ``E_p^T P D^{1/2} psi`` (Eq. 45). The model order is
    ``len(d)``; truncating ``p``, ``d``, ``qt`` to their first columns gives
    every lower order from one decomposition. ``window`` (s) is the span of
    data behind the Hankel matrix, for the ``short_window`` flag.
    """
    z, real, complex_shapes, histories = eigen_poles(*realisation(p, d, qt, h1, n_channels))
    poles = pole_indicators(z, real, complex_shapes, histories, dt, n_sets)
    poles.pop("mpd")
    poles["complex_shapes"] = poles["complex_shapes"].T  # one row per pole, sorted with the rest
    omega, shapes, cols_ = sort_modes(poles.pop("omega"), poles.pop("shapes"), **poles)
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
        complex_shapes=cols_["complex_shapes"].T,
    )


def realisation(p, d, qt, h1, n_channels):
    """The realisation of ``P D Q^T`` and ``H(1)``, as :func:`eigen_poles`
    takes it: ``Phi = D^{-1/2} P^T H(1) Q D^{-1/2}`` (Eq. 41), the output
    matrix ``E_p^T P D^{1/2}`` (Eq. 43, the first ``n_channels`` rows of
    ``P``) and the state sequence ``D^{1/2} Q^T`` over the Hankel columns.

    The realisation of a lower order ``k`` is the leading ``k x k`` block of
    ``Phi``, the first ``k`` columns of the output matrix and the first ``k``
    rows of the states (:func:`modal.stabilisation` uses this).
    """
    sqrt_d = np.sqrt(d)
    d_isqrt = 1 / sqrt_d
    phi = (d_isqrt[:, None] * (p.T @ h1 @ qt.T)) * d_isqrt[None, :]  # Eq. (41)
    return phi, p[:n_channels] * sqrt_d[None, :], sqrt_d[:, None] * qt


def eigen_poles(phi, output, states):
    """Eigenvalues of one realisation and what the indicators need of them.

    Solves ``Phi psi = psi z`` (Eq. 42) and keeps one entry per
    complex-conjugate pair (``Im z > 0``) and per real eigenvalue (``|Im z|``
    at most :data:`modal.identification._era_kernels.REAL_POLE_TOL` ``|z|``).

    Parameters
    ----------
    phi : ndarray, shape (k, k)
        The state matrix of Eq. (41).
    output : ndarray, shape (l, k)
        ``E_p^T P D^{1/2}`` (Eq. 43).
    states : ndarray, shape (k, m s)
        ``D^{1/2} Q^T``, the state sequence over the Hankel columns.

    Returns
    -------
    z : ndarray of complex
        The kept eigenvalues.
    real : ndarray of bool
        Which of them are real poles.
    complex_shapes : ndarray, shape (l, n)
        ``E_p^T P D^{1/2} psi`` (Eq. 45) for the kept eigenvalues.
    histories : ndarray, shape (n, m s)
        Their modal amplitudes over the Hankel columns, the kept rows of
        ``psi^{-1} D^{1/2} Q^T`` (for the modal amplitude coherence).
    """
    phi = square_matrix("phi", phi)
    output, states = finite_array("output", output, ndim=(2,)), finite_array("states", states, ndim=(2,))
    return complex_poles(*real_eigensystem(phi, output, states))[:4]


def pole_indicators(z, real, complex_shapes, histories, dt, n_sets, derivatives=None) -> dict:
    """Frequencies, damping, flags and indicators of poles from
    :func:`eigen_poles`, vectorised over any number of poles (one
    realisation's or many orders' concatenated).

    ``derivatives`` (one integer per channel: 0 displacement, 1 velocity,
    2 acceleration) brings channels of different quantities to one shape:
    a mode ``exp(s t)`` measured as the ``k``-th derivative carries ``s^k``,
    so each channel's entry is divided by ``s^(k - k_0)`` with ``k_0`` the
    first channel's derivative (all channels in its quantity). Without it
    every channel is taken to measure the same quantity.

    ``s = ln z / dt`` (Eq. 44, j = 0), ``omega = |s|``, damping ``-Re s / |s|``
    (NaN for real poles), ``unstable`` where ``|z| > 1 +`` :data:`UNSTABLE_TOL`,
    ``aliased`` damped frequencies near ``pi / dt``, modal amplitude coherence
    (0 where it overflows) and phase collinearity, and the normalised real
    ``shapes`` (n_channels, n), the normalised ``complex_shapes`` and their
    mean phase deviation ``mpd`` (degrees). Returns a dict with these keys,
    ``z`` and ``real_pole``, in the input order.
    """
    with np.errstate(divide="ignore", invalid="ignore"):  # z = 0 (a singular Phi): log z = -inf, omega = inf
        s = np.log(z.astype(complex)) / dt  # Eq. (44), j = 0
        omega = np.abs(s)
        damping = np.where(real, np.nan, -s.real / np.where(omega > 0, omega, 1))
        if derivatives is not None:
            relative = np.asarray(derivatives, dtype=int) - int(derivatives[0])
            if np.any(relative):
                factor = s[None, :] ** relative[:, None]
                complex_shapes = complex_shapes / np.where(np.isfinite(factor) & (factor != 0), factor, 1)
    with np.errstate(over="ignore", invalid="ignore"):
        mamc = np.nan_to_num(modal_amplitude_coherence(histories, z, n_sets), nan=0.0)
    return {
        "omega": omega,
        "shapes": normalise_shapes(complex_shapes),
        "damping": damping,
        "real_pole": real,
        "unstable": np.abs(z) > 1 + UNSTABLE_TOL,
        "aliased": near_limit(np.abs(s.imag), dt),
        "mamc": mamc,
        "mpc": modal_phase_collinearity(complex_shapes),
        "complex_shapes": normalise_complex_shapes(complex_shapes),
        "mpd": mean_phase_deviation(complex_shapes),
        "z": z,
    }
