"""Accuracy indicators: MAC, modal amplitude coherence, modal phase collinearity."""

from __future__ import annotations

import numpy as np

from .._checks import finite_array


def mac(a, b) -> np.ndarray:
    """Modal assurance criterion between two shape sets.

    ``MAC_ij = |a_i^H b_j|^2 / ((a_i^H a_i)(b_j^H b_j))``.

    Parameters
    ----------
    a : array_like, shape (n_channels, p)
    b : array_like, shape (n_channels, q)

    Returns
    -------
    ndarray, shape (p, q), entries in [0, 1].
    """
    a = np.atleast_2d(np.asarray(a))
    b = np.atleast_2d(np.asarray(b))
    if a.ndim != 2 or b.ndim != 2 or a.shape[0] != b.shape[0]:
        raise ValueError(f"a and b must be (n_channels, modes) with the same rows, got {a.shape} and {b.shape}")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise ValueError("a and b must not contain NaN or inf")
    return _normalised(np.abs(a.conj().T @ b) ** 2, np.outer(_squared_norms(a), _squared_norms(b)))


def paired_mac(a, b) -> np.ndarray:
    """MAC of each column of ``a`` with the same column of ``b``: the diagonal
    of ``mac(a, b)`` without the rest of the matrix (no input checks; for the
    engine's own finite shapes).

    Parameters
    ----------
    a, b : ndarray, shape (n_channels, p)

    Returns
    -------
    ndarray, shape (p,)
    """
    return _normalised(np.abs(np.sum(a.conj() * b, axis=0)) ** 2, _squared_norms(a) * _squared_norms(b))


def _squared_norms(a):
    return np.sum(np.abs(a) ** 2, axis=0)


def _normalised(cross, denom):
    """``cross / denom``, 0 where ``denom`` is 0 (a zero shape)."""
    return np.divide(cross, denom, out=np.zeros_like(cross), where=denom > 0)


def align_shapes(shapes, reference) -> np.ndarray:
    """Flip the sign of each column of ``shapes`` to agree with the same column
    of ``reference`` and scale it to the reference's norm (for plotting
    identified against exact shapes)."""
    shapes = finite_array("shapes", shapes, ndim=(2,))
    reference = finite_array("reference", reference, ndim=(2,))
    k = min(shapes.shape[1], reference.shape[1])
    if shapes.shape[0] != reference.shape[0]:
        raise ValueError("shapes and reference must have the same number of channels")
    s, ref = shapes[:, :k], reference[:, :k]
    sign = np.sign(np.sum(s * ref, axis=0))
    sign[sign == 0] = 1
    scale = np.linalg.norm(ref, axis=0) / np.where(np.linalg.norm(s, axis=0) > 0, np.linalg.norm(s, axis=0), 1)
    return s * sign * scale


def modal_phase_collinearity(shapes) -> np.ndarray:
    """Modal phase collinearity of complex mode shapes (Juang and Pappa).

    With ``S = [[Re^T Re, Re^T Im], [Im^T Re, Im^T Im]]`` for each shape and its
    eigenvalues ``l1 >= l2``, ``MPC = ((l1 - l2) / (l1 + l2))^2``: 1 for a shape
    whose entries are in phase (a normal mode), 0 for uncorrelated phases.
    """
    shapes = np.atleast_2d(np.asarray(shapes, dtype=complex))
    re, im = shapes.real, shapes.imag
    sxx = np.sum(re * re, axis=0)
    syy = np.sum(im * im, axis=0)
    sxy = np.sum(re * im, axis=0)
    trace = sxx + syy
    gap = np.sqrt((sxx - syy) ** 2 + 4 * sxy**2)
    return np.divide(gap, trace, out=np.zeros_like(trace), where=trace > 0) ** 2


def mean_phase_deviation(shapes) -> np.ndarray:
    """Mean phase deviation (degrees) of complex mode shapes from their best
    straight line in the complex plane (Reynders, Houbrechts and De Roeck
    2012): 0 for a normal mode, growing with its complexity.

    The line is the leading right singular vector of the ``n_channels x 2``
    matrix ``[Re phi, Im phi]``, ``(v12, v22)`` its normal (the other
    singular vector); each entry's deviation
    ``arccos(|Re phi_c v22 - Im phi_c v12| / (|phi_c| sqrt(v12^2 + v22^2)))``
    is averaged with weights ``|phi_c|``.
    """
    shapes = np.atleast_2d(np.asarray(shapes, dtype=complex))
    # every mode at once: the right singular vectors of [Re phi, Im phi] are the eigenvectors of its 2 x 2
    # Gram matrix; the one of the smaller eigenvalue (eigh: the first) is the normal to the best line, as (re, im)
    parts = np.stack([shapes.real.T, shapes.imag.T], axis=-1)  # (n_modes, n_channels, 2)
    _, vectors = np.linalg.eigh(np.swapaxes(parts, 1, 2) @ parts)
    v12, v22 = vectors[:, 0, 0, None], vectors[:, 1, 0, None]
    weights = np.abs(shapes.T)  # (n_modes, n_channels)
    along = np.abs(shapes.real.T * v22 - shapes.imag.T * v12) / np.hypot(v12, v22)
    cosines = np.clip(np.divide(along, weights, out=np.ones_like(along), where=weights > 0), 0, 1)
    total = weights.sum(axis=1)
    deviation = np.divide(np.sum(weights * np.arccos(cosines), axis=1), total, out=np.zeros_like(total),
                          where=total > 0)
    return np.degrees(deviation)


def modal_amplitude_coherence(histories, z, n_sets: int) -> np.ndarray:
    """Modal amplitude coherence (Juang and Pappa) of identified modal amplitude
    histories against ideal ones.

    Parameters
    ----------
    histories : ndarray, shape (n_modes, s * m)
        Rows of ``psi^{-1} D^{1/2} Q^T``: each mode's identified amplitude over
        the Hankel columns (block column j, data set k at column ``j m + k``).
    z : ndarray, shape (n_modes,)
        Identified discrete-time eigenvalues.
    n_sets : int
        ``m``, data sets per block column.

    Returns
    -------
    ndarray
        ``|q . conj(q_ideal)| / (|q| |q_ideal|)`` with ``q_ideal[j m + k] =
        b_k z^j``, ``b_k`` the identified initial amplitudes (block column 0).
    """
    histories = np.asarray(histories, dtype=complex)  # any real or complex input, as complex128
    n_modes, width = histories.shape
    s = width // n_sets
    blocks = histories.reshape(n_modes, s, n_sets)  # [i, j, k]: mode i, block column j, data set k
    b = blocks[:, 0]  # (n, m)
    # z^j, j = 0 .. s-1, as a running product: 30 x faster than a complex power,
    # and its rounding (about s eps relative) is immaterial to an indicator
    z = np.asarray(z)
    factors = np.broadcast_to(z[:, None], (n_modes, s)).copy()
    factors[:, 0] = 1
    powers = np.cumprod(factors, axis=1)  # (n, s)
    # q . conj(q_ideal) = sum_j conj(z^j) sum_k q[j m + k] conj(b_k), and
    # |q_ideal|^2 = |b|^2 sum_j |z^j|^2: q_ideal is never formed
    num = np.abs(np.einsum("ij,ij->i", (blocks @ b.conj()[:, :, None])[:, :, 0], powers.conj()))
    ideal_norm = np.linalg.norm(b, axis=1) * np.linalg.norm(powers, axis=1)
    flat = np.ascontiguousarray(histories).view(float)  # |q|^2 as a real dot product: no complex abs
    den = np.sqrt(np.einsum("ij,ij->i", flat, flat)) * ideal_norm
    return np.divide(num, den, out=np.zeros_like(num), where=den > 0)


#: :func:`quadrature_groups`: an entry counts in a mode when it holds at least
#: this share of its channel's largest entry over the modes compared (a
#: channel's weak entries are its noise, of random phase) ...
QUADRATURE_MIN_SHARE = 0.1
#: ... two channels are in phase (or opposite) when their phases differ by at
#: most this many degrees from 0 or 180, a quarter period apart when by at
#: most this from 90 (median over the modes both show): a derivative of a
#: mode damped ``zeta`` lies ``asin(zeta)`` from 90 (2.9 degrees at 5 %), the
#: Weimar frame's velocity and acceleration channels 0.1-0.5 from 90 in all 15
#: setups; at 10 or 20 degrees, one and two of 360 simulated records of
#: ``bench_selection`` (mixtures of close pairs, 78.9 and 83.7 degrees) were
#: parted, at 5 none ...
QUADRATURE_TOLERANCE_DEG = 5.0
#: ... and a pair is judged on at least this many modes.
QUADRATURE_MIN_MODES = 3


def quadrature_groups(shapes) -> tuple[list[int], list[int], float, int] | None:
    """Two groups of channels a quarter period apart in every mode, or None.

    A channel that measures another derivative of the motion than the others
    (a velocity among accelerations: ``a = s v``, ``s = i omega`` for light
    damping) is 90 degrees out of phase with them in every mode, so shapes
    identified as if all channels measured one quantity are complex (low
    MPC) although the modes are normal. For each pair of channels, the
    phase difference of their entries in each mode both show
    (:data:`QUADRATURE_MIN_SHARE`), folded to 0-90 degrees (a sign is the
    sensor's orientation), has a median over those modes; the channels are
    parted in two groups so that every pair within a group is in phase and
    every pair across is a quarter period apart (within
    :data:`QUADRATURE_TOLERANCE_DEG`). A pair in between, a pair that
    contradicts the parting, or one group left empty: None. Channels no
    pair places (too weak in every mode) are in neither group.

    Parameters
    ----------
    shapes : array_like, shape (n_channels, n_modes)
        Complex shapes of modes whose shapes are well identified (e.g. MAMC
        high), as identified (the entries' units do not matter).

    Returns
    -------
    tuple or None
        ``(first, second, median_deg, n_modes)``: the channels of each group
        (``first`` holds the lowest channel placed), the median over the
        pairs across of their median phase difference (degrees), and the
        number of modes in which a pair across was judged.
    """
    shapes = np.atleast_2d(np.asarray(shapes, dtype=complex))
    n_channels = shapes.shape[0]
    magnitude = np.abs(shapes)
    largest = magnitude.max(axis=1, keepdims=True, initial=0.0)  # no mode: nothing shown
    shown = magnitude >= QUADRATURE_MIN_SHARE * np.where(largest > 0, largest, np.inf)
    apart = np.full((n_channels, n_channels), np.nan)
    counts = np.zeros((n_channels, n_channels), dtype=int)
    for c in range(n_channels):
        for d in range(c + 1, n_channels):
            both = shown[c] & shown[d]
            if both.sum() < QUADRATURE_MIN_MODES:
                continue
            angle = np.degrees(np.abs(np.angle(shapes[c, both] * np.conj(shapes[d, both]))))
            apart[c, d] = apart[d, c] = np.median(np.minimum(angle, 180.0 - angle))
            counts[c, d] = counts[d, c] = both.sum()
    judged = np.isfinite(apart)
    if np.any(judged & (apart > QUADRATURE_TOLERANCE_DEG) & (apart < 90.0 - QUADRATURE_TOLERANCE_DEG)):
        return None
    group = np.full(n_channels, -1)
    for start in range(n_channels):  # each connected set of judged pairs, coloured from its lowest channel
        if group[start] >= 0 or not judged[start].any():
            continue
        group[start], queue = 0, [start]
        while queue:
            c = queue.pop()
            for d in np.flatnonzero(judged[c]):
                side = group[c] if apart[c, d] <= QUADRATURE_TOLERANCE_DEG else 1 - group[c]
                if group[d] < 0:
                    group[d] = side
                    queue.append(d)
                elif group[d] != side:
                    return None
        if start != int(np.flatnonzero(group >= 0)[0]):
            return None  # two unconnected sets: their relation is unknown
    first, second = np.flatnonzero(group == 0), np.flatnonzero(group == 1)
    if not first.size or not second.size:
        return None
    across = [(c, d) for c in first for d in second if judged[c, d]]
    return ([int(c) for c in first], [int(d) for d in second], float(np.median([apart[c, d] for c, d in across])),
            int(max(counts[c, d] for c, d in across)))
