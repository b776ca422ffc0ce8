"""Linear-algebra kernels of the ERA: the leading singular triplets of a
Hankel matrix (thin SVD or the Gram route) and the eigensystems of the
realisations in real arithmetic (LAPACK dgeev).

The algorithm (Eqs. 34-45) reads in :mod:`modal.identification._era`; these
are its speed kernels.
"""

from __future__ import annotations

import numpy as np

from .._checks import positive_int, square_matrix

#: |Im z| below this (relative to |z|) makes an eigenvalue a real pole.
REAL_POLE_TOL = 1e-10

#: ``decompose`` methods: ``"full"`` is the thin SVD, ``"gram"`` the Gram matrix's
#: eigenvectors refined by Rayleigh-Ritz, ``"auto"`` the latter where it pays.
DECOMPOSE_METHODS = ("auto", "full", "gram")
#: ``"auto"`` considers the Gram path only when the thin SVD would take at least
#: this many floating-point operations (about 20-50 ms here); below, the thin SVD
#: costs a few ms anyway (and the thesis's own Hankel matrices, 144 x 100 to
#: 192 x 150, stay on it).
GRAM_MIN_FLOPS = 1e8
#: Rayleigh-Ritz steps tried before falling back to the thin SVD.
GRAM_MAX_STEPS = 3
#: A triplet is accepted when its residual ``||H(0)^T p - sigma q||`` is below the
#: larger of ``GRAM_REL_TOL * sigma`` and ``GRAM_ABS_TOL * sigma_1``: it is then an
#: exact triplet of a matrix within that distance of ``H(0)`` (a thin SVD's own
#: rounding is some 1e-15 ``sigma_1``).
GRAM_REL_TOL = 1e-12
GRAM_ABS_TOL = 1e-13
#: :func:`leading_eigenpairs` bisects (dsyevr) for fewer than this fraction of
#: the eigenvalues, and computes all of them (dsterf) for more.
BISECTION_MAX_FRACTION = 0.1


def decompose(h0, order, method="auto", block=None):
    """The ``order`` dominant singular triplets of ``H(0)`` (Eq. 35, Sec. 4.4).

    The ERA needs only the ``2 n`` leading triplets ``P D Q^T``, not the whole
    thin SVD. ``method="gram"`` takes them from the symmetric eigenproblem of
    the Gram matrix of ``H(0)``'s shorter side (``H H^T`` or ``H^T H``; with
    ``block`` given it is summed from Eq. 34's shift structure, without a product
    of the whole Hankel matrix), then refines them by Rayleigh-Ritz on ``H(0)``
    itself: ``Q_w = orth(H^T U)``, thin SVD of ``H Q_w`` (a ``l r x order``
    matrix), which undoes the Gram matrix's squared condition number as far as
    the subspace allows. Each triplet's residual ``||H^T p - sigma q||`` is then
    checked; while it exceeds :data:`GRAM_REL_TOL` ``sigma`` and
    :data:`GRAM_ABS_TOL` ``sigma_1`` another step is taken, and after
    :data:`GRAM_MAX_STEPS` (or at once, when the Gram matrix's rounding already
    swamps ``sigma_order^2``) the thin SVD is used instead. Accepted triplets
    are thus exact for a matrix within 1e-13 ``sigma_1`` (or 1e-12 ``sigma``) of
    ``H(0)``; anything less accurate is never returned.

    Parameters
    ----------
    h0 : ndarray, shape (l r, m s)
        ``H(0)`` of Eq. (34).
    order : int
        Number of triplets (the model order ``2 n``).
    method : {"auto", "full", "gram"}
        ``"full"``: thin SVD by LAPACK gesdd. ``"gram"``: as above (falling back
        to ``"full"`` when the check fails). ``"auto"``: ``"gram"`` when it costs
        less than half the thin SVD on this shape and order
        (:func:`gram_pays`), else ``"full"``.
    block : tuple (l, m), optional
        Block shape of ``H(0)`` (sensors, data sets) when it is a block Hankel
        matrix of Eq. (34), so the Gram matrix is built from its first block row
        and last block column; without it the Gram matrix is a plain product.
        Checked: ``H(0)`` must be block Hankel with these blocks.

    Returns
    -------
    p : ndarray, shape (l r, order)
        Leading left singular vectors ``P``.
    d : ndarray, shape (order,)
        Leading singular values ``D``, decreasing.
    qt : ndarray, shape (order, m s)
        Leading right singular vectors ``Q^T``.
    singular_values : ndarray
        Every singular value computed: all ``min(l r, m s)`` of them for the
        thin SVD, the ``order`` leading ones (equal to ``d``) for the Gram path.
    """
    method = decompose_method("method", method)
    h0 = np.asarray(h0, dtype=float)
    order = positive_int("order", order)
    n_short = min(h0.shape)
    if order > n_short:
        raise ValueError(f"order = {order} exceeds the smaller dimension of h0 {h0.shape}")
    if block is not None:
        _check_block(h0, block)
    use_gram = method == "gram" or (method == "auto" and gram_pays(h0.shape, order))
    if use_gram and order < n_short:
        triplets = _gram_triplets(h0, order, block)
        if triplets is not None:
            return (*triplets, triplets[1])
    # Thin SVD (Eq. 35) by LAPACK gesdd; numpy hands the C-ordered H(0) to
    # LAPACK as its transpose without a copy, which scipy.linalg.svd does not.
    u, sv, vt = np.linalg.svd(h0, full_matrices=False)
    return u[:, :order], sv[:order], vt[:order], sv


def gram_pays(shape, order) -> bool:
    """Whether the Gram route is worth it for ``order`` triplets of a matrix of
    ``shape``, by counting floating-point operations of both routes.

    With ``a <= b`` the sides: the thin SVD (gesdd, vectors included) takes
    about ``6 a^2 b + 10 a^3``; the Gram route about ``a^2 b`` (the Gram
    matrix) ``+ 2 a^3`` (its eigenproblem) ``+ 4 a b order + 2 b order^2``
    (one Rayleigh-Ritz step). The Gram route is taken when the SVD would
    cost at least :data:`GRAM_MIN_FLOPS` and the Gram route less than half
    of it, so a wide, short Hankel matrix (160 x 1e6) takes it as a square
    one does, and small ones stay on the SVD.
    """
    a, b = sorted(int(n) for n in shape)
    svd = 6.0 * a * a * b + 10.0 * a**3
    gram = 1.0 * a * a * b + 2.0 * a**3 + 4.0 * a * b * order + 2.0 * b * order**2
    return order < a and svd >= GRAM_MIN_FLOPS and gram < svd / 2


def decompose_method(name, value):
    """``value`` if it names one of :data:`DECOMPOSE_METHODS`."""
    if not isinstance(value, str) or value not in DECOMPOSE_METHODS:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, DECOMPOSE_METHODS))}, got {value!r}")
    return value


def _check_block(h0, block):
    """Raise unless ``h0`` is a block Hankel matrix with ``block = (l, m)`` blocks."""
    try:
        l, m = (positive_int("block", b) for b in block)
    except (TypeError, ValueError):
        raise ValueError(f"block must be a pair (l, m) of positive integers, got {block!r}") from None
    if h0.shape[0] % l or h0.shape[1] % m or not np.array_equal(h0[l:, :-m], h0[:-l, m:]):
        raise ValueError(f"block = {block!r}: h0 {h0.shape} is not a block Hankel matrix with {l} x {m} blocks")


def _gram_triplets(h0, order, block):
    """Leading triplets of ``h0`` by the Gram route of :func:`decompose`, or
    ``None`` when they do not pass the residual check (the caller then takes
    the thin SVD)."""
    from scipy.linalg import qr  # scipy is imported only where it is used

    transpose = h0.shape[0] > h0.shape[1]
    a = h0.T if transpose else h0  # the Gram matrix is a a^T, of a's shorter side
    if block is None:
        gram = a @ a.T
    else:
        l, m = block
        gram = block_hankel_gram(a, *((m, l) if transpose else (l, m)))
    lam, u = leading_eigenpairs(gram, order)
    # The Gram matrix carries rounding errors of about eps lambda_1 times the
    # length of its sums: where they swamp lambda_order its eigenvectors hold no
    # information about the weakest triplets, and no refinement can restore it.
    if lam[-1] <= max(a.shape) * np.finfo(float).eps * lam[0]:
        return None
    z = a.T @ u
    for _ in range(GRAM_MAX_STEPS):
        # Rayleigh-Ritz on a itself: a (a^T u) spans the wanted left subspace with
        # the unwanted directions damped by sigma_{order+1} / sigma_order.
        q_w = qr(z, mode="economic")[0]
        ub, sv, vbt = np.linalg.svd(a @ q_w, full_matrices=False)
        q = q_w @ vbt.T
        z = a.T @ ub
        residual = np.linalg.norm(z - q * sv, axis=0)
        if np.all(residual <= np.maximum(GRAM_REL_TOL * sv, GRAM_ABS_TOL * sv[0])):
            break
    else:
        return None
    p, qt = ub, q.T
    if transpose:
        p, qt = qt.T, p.T
    return p, sv, qt


def leading_eigenpairs(sym, k):
    """The ``k`` largest eigenvalues of the symmetric matrix ``sym``, decreasing,
    and their eigenvectors.

    LAPACK's tridiagonal reduction (dsytrd), every eigenvalue of the
    tridiagonal matrix (dsterf, ``O(n^2)``), inverse iteration for the ``k``
    wanted eigenvectors (dstein) and the back-transformation of those ``k``
    only (dormqr on dsytrd's reflectors): dsyevx's route with dsterf in place
    of bisection (dstebz), which costs more once ``k`` is a tenth of ``n``
    (60 eigenvalues of a 360 x 360 tridiagonal matrix: 4.7 ms by bisection,
    0.9 ms for all 360 by dsterf, measured). For fewer eigenvalues
    (:data:`BISECTION_MAX_FRACTION`), or when dstein does not converge,
    scipy.linalg.eigh's subset driver (dsyevr) is used.

    Parameters
    ----------
    sym : array_like, shape (n, n)
        Symmetric; only its lower triangle is read.
    k : int
        How many eigenpairs, ``1 <= k <= n``.

    Returns
    -------
    lam : ndarray, shape (k,)
    u : ndarray, shape (n, k)
        Orthonormal eigenvectors, ``sym u = u diag(lam)``.
    """
    from scipy.linalg import eigh
    from scipy.linalg.lapack import dormqr, dstein, dsterf, dsytrd, dsytrd_lwork

    sym = square_matrix("sym", sym)
    n = sym.shape[0]
    k = positive_int("k", k)
    if k > n:
        raise ValueError(f"k = {k} exceeds the order {n} of sym")
    if k >= n - 1:
        lam, u = np.linalg.eigh(sym)
        return lam[::-1][:k], u[:, ::-1][:, :k]
    if k >= BISECTION_MAX_FRACTION * n:
        # the lower triangle: Q = H(1) ... H(n-1), reflector i stored below A(i+1, i), as geqrf
        # stores the QR factors of A(2:n, 1:n-1) (LAPACK's dormtr applies them so)
        # with LAPACK's optimal workspace: the default (n) leaves dsytrd unblocked, 1.6 x slower at n = 360
        lwork, info = dsytrd_lwork(n, lower=1)
        reflectors, diag, off, tau, info = dsytrd(sym, lower=1, lwork=int(lwork))
        lam, info_sterf = dsterf(diag, off)
        wanted = lam[n - k:]  # increasing, as dstein wants them (one block: no split given)
        vectors, info_stein = dstein(diag, off, wanted, np.ones(n, dtype=np.int32), np.full(n, n, dtype=np.int32))
        if not (info or info_sterf or info_stein):
            head = dormqr("L", "N", reflectors[1:, :-1], tau, vectors[1:], lwork=max(1, 64 * k))[0]
            return wanted[::-1], np.vstack([vectors[:1], head])[:, ::-1]
    lam, u = eigh(sym, subset_by_index=[n - k, n - 1])
    return lam[::-1], u[:, ::-1]


def block_hankel_gram(a, rows_per_block, cols_per_block):
    """``a a^T`` for a block Hankel matrix ``a`` (blocks ``Y(i + j)`` of shape
    ``rows_per_block x cols_per_block``, as in Eq. 34), without the full product.

    Block ``(i, j)`` of the Gram matrix is ``sum_k Y(i + k) Y(j + k)^T`` over the
    ``s`` block columns, so it follows from block ``(i - 1, j - 1)`` by adding
    ``Y(i - 1 + s) Y(j - 1 + s)^T`` and removing ``Y(i - 1) Y(j - 1)^T``: only the
    first block row costs a product with ``a``, the rest is a cumulative sum
    along the block diagonals.
    """
    bl, bm = rows_per_block, cols_per_block
    r, s = a.shape[0] // bl, a.shape[1] // bm
    gram = np.empty((r * bl, r * bl))
    gram[:bl] = a[:bl] @ a.T
    gram[bl:, :bl] = gram[:bl, bl:].T
    if r > 1:
        # Every Y(t), t = 0 .. r+s-2: the first block row, then the last block column.
        samples = np.concatenate([
            a[:bl].reshape(bl, s, bm).transpose(1, 0, 2),
            a[bl:, (s - 1) * bm:].reshape(r - 1, bl, bm),
        ])
        head = samples[: r - 1].reshape((r - 1) * bl, bm)
        tail = samples[s:].reshape((r - 1) * bl, bm)
        step = tail @ tail.T - head @ head.T  # block (t, u): Y(t+s) Y(u+s)^T - Y(t) Y(u)^T
        for i in range(1, r):
            row = gram[(i - 1) * bl:i * bl, (i - 1) * bl:-bl] + step[(i - 1) * bl:i * bl, (i - 1) * bl:]
            gram[i * bl:(i + 1) * bl, i * bl:] = row  # block row i from its diagonal block on
            gram[(i + 1) * bl:, i * bl:(i + 1) * bl] = row[:, bl:].T  # and, mirrored, block column i
    return gram


def real_eigensystem(phi, output, states):
    """Solve ``Phi psi = psi z`` (Eq. 42) in real arithmetic (LAPACK dgeev)
    and map the output matrix and the states onto the eigenvectors.

    dgeev's real eigenvector matrix ``V`` holds a real eigenvalue's
    eigenvector as one column and a complex pair ``psi = x +- i y`` (the
    eigenvalue with ``wi > 0`` first, its conjugate next) as the two columns
    ``x, y``; ``V^{-1}`` holds the rows of ``psi^{-1}`` the same way
    (:func:`complex_poles`), so no complex matrix is factorised.

    Parameters
    ----------
    phi, output, states
        As :func:`modal.identification._era.eigen_poles`, which checks them (here they are taken as
        they come: :func:`modal.stabilisation` calls this once per order on
        a realisation of checked data).

    Returns
    -------
    wr, wi : ndarray, shape (k,)
        Real and imaginary parts of the eigenvalues ``z``.
    real_shapes : ndarray, shape (l, k)
        ``E_p^T P D^{1/2} V`` (Eq. 45 in ``V``'s columns).
    real_histories : ndarray, shape (k, m s)
        ``V^{-1} D^{1/2} Q^T``.
    """
    from scipy.linalg.lapack import dgeev, dgetrf, dgetri  # scipy is imported only where it is used

    wr, wi, _, vectors, info = dgeev(phi, compute_vl=0)
    if info:
        raise np.linalg.LinAlgError(f"the QR algorithm did not converge on the {len(phi)}-order state matrix "
                                    f"(LAPACK dgeev info = {info})")
    lu, pivots, info = dgetrf(vectors)
    if not info:
        inverse, info = dgetri(lu, pivots)
    if info:
        raise np.linalg.LinAlgError(f"the eigenvectors of the {len(phi)}-order state matrix are linearly dependent "
                                    "(a defective state matrix)")
    return wr, wi, output @ vectors, inverse @ states


def complex_poles(wr, wi, real_shapes, real_histories):
    """:func:`modal.identification._era.eigen_poles`'s outputs from one or more real eigensystems
    (:func:`real_eigensystem`) concatenated along the eigenvalues.

    The complex eigenvectors are ``psi = V M`` with ``M = [[1, 1], [i, -i]]``
    on each complex pair, so the shape of ``z = wr + i wi`` (``wi > 0``) is
    ``x + i y`` and its row of ``psi^{-1} = M^{-1} V^{-1}`` is
    ``(r_x - i r_y) / 2``, with ``x, y`` and ``r_x, r_y`` the pair's columns of
    ``real_shapes`` and rows of ``real_histories``; its conjugate's are
    ``x - i y`` and ``(r_x + i r_y) / 2`` (kept when the pair is near-real).

    Parameters
    ----------
    wr, wi, real_shapes, real_histories : ndarray
        As :func:`real_eigensystem` returns them, or several of its results
        concatenated (a complex pair never straddles two of them).

    Returns
    -------
    z, real, complex_shapes, histories
        As :func:`modal.identification._era.eigen_poles`.
    kept : ndarray of int
        Positions of the kept eigenvalues in ``wr``.
    """
    z = wr + 1j * wi
    real = np.abs(wi) <= REAL_POLE_TOL * np.abs(z)
    kept = np.flatnonzero(real | (wi > 0))
    sign = np.sign(wi[kept])
    x = kept - (sign < 0)  # the pair's first column (its own for a real eigenvalue)
    y = x + (sign != 0)
    complex_shapes = real_shapes[:, x] + 1j * (sign * real_shapes[:, y])  # Eq. (45)
    half = np.where(sign != 0, 0.5, 1.0)[:, None]
    histories = np.empty((len(kept), real_histories.shape[1]), dtype=complex)
    np.multiply(real_histories[x], half, out=histories.real)
    np.multiply(real_histories[y], -half * sign[:, None], out=histories.imag)
    return z[kept], real[kept], complex_shapes, histories, kept


