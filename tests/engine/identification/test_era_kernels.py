"""The ERA's kernels on their own (private modules, tested beside their public
function modal.era as scipy tests its private modules): the Gram-matrix
route's LAPACK eigensolver and block-Hankel Gram product, the real-arithmetic
eigensystem and the pole indicators, the realisation at one order."""

import warnings

import numpy as np
import pytest

import modal
import modal.identification._era as era_module
import modal.identification._era_kernels as kernels
from modal.identification._era import pole_indicators, realise
from modal.identification._era_kernels import block_hankel_gram, decompose, leading_eigenpairs

from ..cases import flagged
from .test_era import _hard_beam, _noisy_record, _took_gram

@pytest.mark.slow
def test_many_decades_refinement_restores_exactness(beam):
    y, dt, omega = _hard_beam(beam)
    rows, cols, l = 40, 400, y.shape[1]
    h = modal.hankel(y, rows + 1, cols)
    h0, h1 = h[:-l], h[l:]
    sv = np.linalg.svd(h0, compute_uv=False)
    assert sv[13] / sv[0] < 1e-5  # the case is what it claims to be

    # The Gram matrix's eigenvectors alone: frequencies off far beyond 1e-8.
    gram = block_hankel_gram(h0, l, 1)
    lam, u = np.linalg.eigh(gram)
    u, d = u[:, ::-1][:, :14], np.sqrt(lam[::-1][:14])
    raw = realise(u, d, (u.T @ h0) / d[:, None], h1, l, 1, dt)
    assert raw.omega.size != 7 or np.max(np.abs(np.sort(raw.omega) / omega - 1)) > 1e-6

    # Refined: kept on the Gram route, and exact.
    assert _took_gram(h0, 14, (l, 1))
    res = flagged(modal.era, y, dt, 7, rows, cols, svd="gram")
    assert res.singular_values.size == 14
    # damping ratio to 1e-8 absolute (-Re s to 1e-8 |s|): at this conditioning the
    # thin SVD itself misses 0.01 by ~1e-9
    np.testing.assert_allclose(res.omega, omega, rtol=1e-8)
    np.testing.assert_allclose(res.damping, 0.01, atol=1e-8)
    full = flagged(modal.era, y, dt, 7, rows, cols, svd="full")
    errors = [(res.omega / omega - 1, full.omega / omega - 1), (res.damping - 0.01, full.damping - 0.01)]
    for fast_err, full_err in errors:
        # no worse than the thin SVD, or within the 1e-8 (the two differ in
        # rounding: 1.6e-9 against 5.9e-9 with the pinned numpy/OpenBLAS)
        assert np.max(np.abs(fast_err)) <= max(3 * np.max(np.abs(full_err)), 1e-8)


def _block_diagonal(rng):
    """Two decoupled blocks, the second a copy of the first: the tridiagonal
    matrix splits and every eigenvalue is double."""
    a = rng.standard_normal((70, 90))
    block = a @ a.T
    return np.block([[block, np.zeros_like(block)], [np.zeros_like(block), block]])


@pytest.mark.parametrize("n, k", [(157, 23), (157, 12), (40, 39), (40, 40), (12, 1)])
def test_leading_eigenpairs_against_numpy(n, k):
    rng = np.random.default_rng(n + k)
    a = rng.standard_normal((n, n + 3))
    sym = a @ a.T
    lam, u = leading_eigenpairs(sym, k)
    expected = np.linalg.eigvalsh(sym)[::-1][:k]
    assert lam.shape == (k,) and u.shape == (n, k)
    np.testing.assert_allclose(lam, expected, rtol=1e-12)
    assert np.all(np.diff(lam) <= 0)
    np.testing.assert_allclose(sym @ u, u * lam, atol=1e-12 * expected[0])
    np.testing.assert_allclose(u.T @ u, np.eye(k), atol=1e-13)


def test_leading_eigenpairs_refuses_bad_input():
    sym = np.eye(5)
    for bad, message in [
        ((np.ones((4, 5)), 2), "^sym must be a square matrix, got shape \\(4, 5\\)"),
        ((np.where(sym > 0, np.nan, 0), 2), "^sym contains NaN or inf"),
        ((np.ones(5), 1), "^sym must be a 2-dimensional array"),
        ((sym, 0), "^k must be an integer >= 1"),
        ((sym, 6), "^k = 6 exceeds the order 5 of sym"),
    ]:
        with pytest.raises(ValueError, match=message):
            leading_eigenpairs(*bad)
    lam, u = leading_eigenpairs(sym * 2, 5)  # k = n is accepted
    np.testing.assert_allclose(lam, 2.0)


def test_leading_eigenpairs_of_a_split_matrix_with_double_eigenvalues():
    sym = _block_diagonal(np.random.default_rng(5))
    lam, u = leading_eigenpairs(sym, 30)
    np.testing.assert_allclose(lam, np.linalg.eigvalsh(sym)[::-1][:30], rtol=1e-12)
    np.testing.assert_allclose(lam[::2], lam[1::2], rtol=1e-12)
    np.testing.assert_allclose(sym @ u, u * lam, atol=1e-12 * lam[0])
    np.testing.assert_allclose(u.T @ u, np.eye(30), atol=1e-13)


@pytest.mark.parametrize("routine", ["dstein", "dsterf"])
def test_leading_eigenpairs_falls_back_when_a_lapack_step_fails(monkeypatch, routine):
    """dstein (inverse iteration) or dsterf (the eigenvalues) reporting
    non-convergence, with garbage in its output: the eigenpairs come from
    scipy's eigh, finite and orthonormal (NaN vectors would pass the residual
    check, assert_allclose taking NaN for equal to NaN). 20 of 140 is above the
    bisection fraction, so the dsterf route is tried first."""
    import scipy.linalg.lapack

    calls = []

    def dstein(d, e, w, iblock, isplit):
        calls.append("dstein")
        return np.full((d.size, w.size), np.nan), 1

    def dsterf(diag, off):
        calls.append("dsterf")
        return np.zeros_like(diag), 1

    monkeypatch.setattr(scipy.linalg.lapack, routine, {"dstein": dstein, "dsterf": dsterf}[routine])
    sym = _block_diagonal(np.random.default_rng(6))
    lam, u = leading_eigenpairs(sym, 20)
    assert calls == [routine]
    np.testing.assert_allclose(lam, np.linalg.eigvalsh(sym)[::-1][:20], rtol=1e-12)
    assert np.all(np.isfinite(u))
    np.testing.assert_allclose(sym @ u, u * lam, atol=1e-12 * lam[0])
    np.testing.assert_allclose(u.T @ u, np.eye(20), atol=1e-13)


@pytest.mark.slow
def test_decompose_serves_every_order_up_to_120():
    """One Gram decomposition at order 120, truncated to lower orders (as a
    stabilisation diagram does), matches the thin SVD's at every order."""
    y = _noisy_record()
    rows, cols, l = 40, 1000, 12
    h = modal.hankel(y, rows + 1, cols)
    h0, h1 = h[:-l], h[l:]
    p, d, qt, sv = decompose(h0, 120, method="gram", block=(l, 1))
    assert sv.size == 120
    u, s, vt = np.linalg.svd(h0, full_matrices=False)
    np.testing.assert_allclose(d, s[:120], rtol=1e-10)
    for order in (24, 60, 100):
        fast = realise(p[:, :order], d[:order], qt[:order], h1, l, 1, 0.01)
        full = realise(u[:, :order], s[:order], vt[:order], h1, l, 1, 0.01)
        np.testing.assert_allclose(fast.omega, full.omega, rtol=1e-6)


@pytest.mark.parametrize("sets, transpose", [(1, False), (3, False), (2, True)])
def test_block_hankel_gram_is_the_product(sets, transpose):
    rng = np.random.default_rng(sets)
    y = rng.standard_normal((sets, 90, 5))
    h = modal.hankel(y, 12, 40)
    a, block = (h.T, (sets, 5)) if transpose else (h, (5, sets))
    np.testing.assert_allclose(block_hankel_gram(a, *block), a @ a.T, rtol=1e-12, atol=1e-12 * np.abs(a).max() ** 2)


def test_block_hankel_gram_of_two_block_rows():
    """Two block rows: the second block row comes from the recursion too."""
    h = modal.hankel(np.random.default_rng(4).standard_normal((1, 90, 5)), 2, 40)
    np.testing.assert_allclose(block_hankel_gram(h, 5, 1), h @ h.T, rtol=1e-12, atol=1e-12 * np.abs(h).max() ** 2)


def test_eigen_poles_match_the_complex_eigendecomposition():
    """Shapes and modal histories from dgeev's real eigenvectors and their real
    inverse (Eqs. 42, 45) equal those of the complex eigendecomposition: ``E_p^T
    P D^{1/2} psi`` and the rows of ``psi^{-1} D^{1/2} Q^T`` of the kept poles.
    The state matrix has real eigenvalues, complex pairs, and a pair whose
    imaginary part is 1e-12 of its modulus: both of that pair are kept as real
    poles, the second with the conjugate shape and history."""
    rng = np.random.default_rng(11)
    near_real = 0.9 * np.array([[1, -1e-12], [1e-12, 1]])
    phi = np.zeros((9, 9))
    phi[:7, :7] = rng.standard_normal((7, 7)) / 3
    phi[7:, 7:] = near_real
    output, states = rng.standard_normal((4, 9)), rng.standard_normal((9, 50))
    z, real, shapes, histories = era_module.eigen_poles(phi, output, states)

    w, psi = np.linalg.eig(phi)
    kept = (np.abs(w.imag) <= kernels.REAL_POLE_TOL * np.abs(w)) | (w.imag > 0)
    np.testing.assert_allclose(z, w[kept], rtol=1e-14)
    np.testing.assert_allclose(shapes, output @ psi[:, kept], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(histories, np.linalg.inv(psi)[kept] @ states, rtol=1e-10, atol=1e-10)
    assert real.sum() == 5 and (~real).sum() == 2  # R: 3 real eigenvalues and 2 pairs; the near-real pair
    assert np.sum(w.imag == 0) == 3
    pair = np.flatnonzero(np.abs(z - 0.9) < 1e-9)
    assert len(pair) == 2 and real[pair].all()
    np.testing.assert_allclose(shapes[:, pair[1]], shapes[:, pair[0]].conj(), rtol=1e-14)
    np.testing.assert_allclose(histories[pair[1]], histories[pair[0]].conj(), rtol=1e-14)


@pytest.mark.parametrize("failure, message", [
    ("no convergence", r"^the QR algorithm did not converge on the 2-order state matrix \(LAPACK dgeev info = 1\)$"),
    ("defective", r"^the eigenvectors of the 2-order state matrix are linearly dependent \(a defective state matrix\)$"),
])
def test_eigen_poles_refuse_what_lapack_cannot_decompose(monkeypatch, failure, message):
    """dgeev reporting no convergence, or a defective state matrix (a Jordan
    block: one eigenvector for a double eigenvalue, so psi^{-1} does not exist),
    give a LinAlgError that says so instead of NaN or garbage. dgeev's own
    rounding hides the exact defect, so it is stood in for."""
    import scipy.linalg.lapack

    phi = np.array([[0.5, 1.0], [0.0, 0.5]])
    vectors = np.array([[1.0, 1.0], [0.0, 0.0]])  # the exact eigenvectors, twice the same
    info = 1 if failure == "no convergence" else 0
    monkeypatch.setattr(scipy.linalg.lapack, "dgeev",
                        lambda a, compute_vl: (np.full(2, 0.5), np.zeros(2), None, vectors, info))
    with pytest.raises(np.linalg.LinAlgError, match=message):
        era_module.eigen_poles(phi, np.ones((1, 2)), np.ones((2, 5)))


def test_real_pole_test_is_relative_to_the_modulus():
    """A pole is real when ``|Im z| <= REAL_POLE_TOL |z|``, i.e. when its angle
    is below the tolerance, whatever its modulus: 2 x 2 blocks ``r [[c, -s], [s,
    c]]`` (eigenvalues ``r e^{+-i theta}``, exactly) with ``sin theta`` half or
    twice the tolerance, at moduli 0.05 and 0.06 (well inside the unit circle)
    and 20 and 25 (far outside). The half-tolerance pairs are two real poles
    each, with conjugate shapes; the others one complex pole, as
    numpy.linalg.eig and the inverse of its eigenvectors give them."""
    tol = kernels.REAL_POLE_TOL
    blocks = [(0.05, 0.5 * tol), (0.06, 2 * tol), (20.0, 0.5 * tol), (25.0, 2 * tol)]
    phi = np.zeros((8, 8))
    for i, (r, sin) in enumerate(blocks):
        c = np.sqrt(1 - sin**2)
        phi[2 * i:2 * i + 2, 2 * i:2 * i + 2] = r * np.array([[c, -sin], [sin, c]])
    rng = np.random.default_rng(12)
    output, states = rng.standard_normal((3, 8)), rng.standard_normal((8, 40))
    z, real, shapes, histories = era_module.eigen_poles(phi, output, states)

    for r, sin in blocks:
        at = np.flatnonzero(np.isclose(np.abs(z), r, rtol=1e-12))
        if sin < tol:
            assert len(at) == 2 and real[at].all(), r
            np.testing.assert_allclose(z[at].imag, [r * sin, -r * sin], rtol=1e-9)
            np.testing.assert_allclose(shapes[:, at[1]], shapes[:, at[0]].conj(), rtol=1e-14)
        else:
            assert len(at) == 1 and not real[at].any(), r
            assert z[at[0]].imag == pytest.approx(r * sin, rel=1e-9)
    w, psi = np.linalg.eig(phi)
    kept = [0, 1, 2, 4, 5, 6]  # both of each half-tolerance pair, the Im > 0 one of the others
    assert np.all(w.imag[[2, 6]] > 0)
    np.testing.assert_allclose(z, w[kept], rtol=1e-14)
    np.testing.assert_allclose(shapes, output @ psi[:, kept], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(histories, np.linalg.inv(psi)[kept] @ states, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("name", ["phi", "output", "states"])
def test_eigen_poles_refuse_nan_naming_the_argument(name):
    """NaN in the state matrix, the output matrix or the states: a ValueError
    naming it, not NaN poles; a non-square state matrix is refused too."""
    args = {"phi": np.diag([0.5, 0.9]), "output": np.ones((1, 2)), "states": np.ones((2, 5))}
    args[name] = args[name].copy()
    args[name][0, 0] = np.nan
    with pytest.raises(ValueError, match=f"^{name} contains NaN or inf"):
        era_module.eigen_poles(**args)
    with pytest.raises(ValueError, match=r"^phi must be a square matrix, got shape \(2, 3\)"):
        era_module.eigen_poles(np.ones((2, 3)), np.ones((1, 3)), np.ones((3, 5)))


def test_pole_indicators_of_an_overflowing_spurious_pole_are_silent():
    """A spurious pole |z| = 50 over 400 block columns: its powers overflow
    (50^399 > 1e308), so its MAMC is 0 (as documented), without a floating-point
    warning, whether the poles are complex or all real; the physical pole
    beside it (damping 3 %) keeps MAMC 1."""

    dt, omega, zeta, n_cols, n_sets = 0.01, 2 * np.pi * 4.2, 0.03, 400, 2
    z = np.array([np.exp((-zeta + 1j * np.sqrt(1 - zeta**2)) * omega * dt), 50.0])
    b = np.array([[1.0, 2.0 - 1j], [1.0, -1.0]])  # initial amplitudes per data set
    powers = np.array([z[0] ** np.arange(n_cols), np.full(n_cols, 50.0**5)])  # the spurious history saturates
    histories = (powers[:, :, None] * b[:, None, :]).reshape(2, n_cols * n_sets)
    shapes = np.array([[1.0, 0.3], [0.5j, 1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pole_indicators(z, np.array([False, True]), shapes, histories, dt, n_sets)
    np.testing.assert_allclose(out["mamc"], [1.0, 0.0], atol=1e-12)
    assert out["damping"][0] == pytest.approx(zeta, rel=1e-9) and np.isnan(out["damping"][1])
    assert out["omega"][0] == pytest.approx(omega, rel=1e-9)
    np.testing.assert_array_equal(out["unstable"], [False, True])
    # all poles real: numpy's eigvals returns them as a real array, whose powers
    # overflow to inf without NaN, so the coherence is inf / inf = NaN before it is set to 0
    z_real = np.array([0.5, 50.0])
    histories = np.array([0.5 ** np.arange(n_cols), 50.0 ** np.minimum(np.arange(n_cols), 5)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pole_indicators(z_real, np.array([True, True]), shapes, histories, dt, 1)
    np.testing.assert_allclose(out["mamc"], [1.0, 0.0], atol=1e-12)


def test_pole_indicators_of_a_pole_at_the_origin_are_silent():
    """A state matrix with a zero eigenvalue (e.g. a realisation of zero-padded
    data) gives a real pole at z = 0: s = ln z / dt is -inf, so its frequency
    is inf and its damping NaN (a real pole's), without a floating-point
    warning; the pole beside it is unaffected."""

    dt = 0.01
    z = np.array([0.0, 0.9 * np.exp(0.3j)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pole_indicators(z, np.array([True, False]), np.array([[1.0, 1.0], [0.5, 1j]]),
                              np.ones((2, 8), complex), dt, 1)
    assert out["omega"][0] == np.inf and np.isnan(out["damping"][0]) and not out["unstable"][0]
    assert out["omega"][1] == pytest.approx(np.hypot(np.log(0.9), 0.3) / dt, rel=1e-12)


def test_realise_at_one_order_reports_the_kept_singular_values():
    """realise() alone (one decomposition, any order) reports the kept
    singular values and the poles of modal.era: two real poles (e^{-t},
    e^{-2t}) and one damped pair."""
    dt = 0.05
    t = dt * np.arange(400)
    y = np.column_stack([np.exp(-t) + np.exp(-0.05 * t) * np.sin(3 * t), np.exp(-2 * t) - np.exp(-0.05 * t) * np.sin(3 * t)])
    res = flagged(modal.era, y, dt, 2, rows=20, cols=300)
    h = modal.hankel(y, 21, 300)
    p, d, qt, _ = decompose(h[:-2], 4)
    low = realise(p, d, qt, h[2:], n_channels=2, n_sets=1, dt=dt)
    np.testing.assert_array_equal(low.singular_values, d)
    np.testing.assert_allclose(low.omega, res.omega, rtol=1e-12)


@pytest.mark.parametrize("modulus", [0.05, 0.99, 20.0])
def test_a_pair_at_a_small_angle_is_one_complex_pole(modulus):
    """An oscillation at 1e-8 rad a sample (a mode at 1.6e-9 of the sampling
    rate), inside, near or outside the unit circle, is a complex pair (one
    pole with Im z > 0), not two real poles."""
    sin = 1e-8
    phi = modulus * np.array([[np.sqrt(1 - sin**2), -sin], [sin, np.sqrt(1 - sin**2)]])
    rng = np.random.default_rng(13)
    z, real, _, _ = era_module.eigen_poles(phi, rng.standard_normal((2, 2)), rng.standard_normal((2, 10)))
    assert z.shape == (1,) and not real.any()
    assert z[0].imag == pytest.approx(modulus * sin, rel=1e-6)
