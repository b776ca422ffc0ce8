"""The ERA's fast decomposition: leading singular triplets of H(0) from its Gram
matrix, refined by Rayleigh-Ritz and checked, against closed form and the thin SVD."""

import importlib

import numpy as np
import pytest

import modal

era_module = importlib.import_module("modal.identification._era")
kernels = importlib.import_module("modal.identification._era_kernels")
decompose, realise, block_hankel_gram = kernels.decompose, era_module.realise, kernels.block_hankel_gram
leading_eigenpairs = kernels.leading_eigenpairs

THESIS_SAMPLES = 3594
IRREGULAR = np.array([0.4, 1.1, 1.9, 2.3, 3.05, 3.7, 4.45])  # off the thesis's iL/7


def _took_gram(h0, order, block):
    """True when ``decompose`` kept the Gram route (it then returns ``order``
    singular values; the thin SVD returns all of them)."""
    return decompose(h0, order, method="gram", block=block)[3].size == order


def _exact(res, omega, zeta, rtol=1e-8):
    np.testing.assert_allclose(np.sort(res.omega), omega, rtol=rtol)
    np.testing.assert_allclose(res.damping, zeta, rtol=rtol, atol=1e-10)
    assert not res.real_pole.any()


@pytest.mark.parametrize("signal", ["displacement", "velocity", "acceleration"])
@pytest.mark.parametrize("zeta", [0.0, 0.005, 0.02, 0.05])
def test_gram_route_exact_on_thesis_beam(demo, signal, zeta):
    rec = demo["make"](THESIS_SAMPLES, damping=zeta)
    y = getattr(rec, signal)
    res = modal.era(y, demo["dt"], 6, rows=24, cols=100, svd="gram")
    _exact(res, demo["omega"], zeta)
    assert res.singular_values.size == 12  # the Gram route was kept, not the fallback
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) > 0.9999)


def test_auto_takes_gram_route_off_thesis_geometry(beam):
    """7 irregular sensors, 2 data sets (impulses at two points), 320 x 600 Hankel:
    "auto" takes the Gram route there and is exact."""
    omega = beam.natural_frequencies(5)
    dt = 2 * np.pi / omega[-1] / 12
    sets = [modal.beam_impulse_response(beam, 5, x, IRREGULAR, dt, 800, 0.01).velocity for x in (1.3, 3.4)]
    y = np.stack(sets)
    res = modal.era(y, dt, 5, rows=40, cols=300)
    _exact(res, omega, 0.01)
    assert res.singular_values.size == 10
    h0 = modal.hankel(y, 40, 300)
    assert _took_gram(h0, 10, (7, 2))


def _hard_beam(beam, modes=7, per_period=80, damping=0.01):
    """Displacements sampled 80 times per period of the highest mode: the
    singular values of H(0) span six decades (sigma_14 / sigma_1 ~ 2e-6), so
    the Gram matrix's eigenvectors are wrong in the third digit."""
    omega = beam.natural_frequencies(modes)
    dt = 2 * np.pi / omega[-1] / per_period
    rec = modal.beam_impulse_response(beam, modes, 1.3, IRREGULAR, dt, 6000, damping)
    return rec.displacement, dt, omega


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
    res = modal.era(y, dt, 7, rows, cols, svd="gram")
    assert res.singular_values.size == 14
    # damping ratio to 1e-8 absolute (-Re s to 1e-8 |s|): at this conditioning the
    # thin SVD itself misses 0.01 by ~1e-9
    np.testing.assert_allclose(res.omega, omega, rtol=1e-8)
    np.testing.assert_allclose(res.damping, 0.01, atol=1e-8)
    full = modal.era(y, dt, 7, rows, cols, svd="full")
    errors = [(res.omega / omega - 1, full.omega / omega - 1), (res.damping - 0.01, full.damping - 0.01)]
    for fast_err, full_err in errors:
        # no worse than the thin SVD, or within the 1e-8 (the two differ in
        # rounding: 1.6e-9 against 5.9e-9 with the pinned numpy/OpenBLAS)
        assert np.max(np.abs(fast_err)) <= max(3 * np.max(np.abs(full_err)), 1e-8)


def test_falls_back_when_gram_matrix_cannot_resolve(beam):
    """sigma_12 / sigma_1 ~ 3e-9: lambda_12 sits below the Gram matrix's rounding,
    so the thin SVD is used and the result is the full-SVD ERA's."""
    y, dt, _ = _hard_beam(beam, modes=6, per_period=200)
    h0 = modal.hankel(y, 40, 400)
    p, d, qt, sv = decompose(h0, 12, method="gram", block=(7, 1))
    u, s, vt = np.linalg.svd(h0, full_matrices=False)
    assert sv.size == min(h0.shape)
    np.testing.assert_array_equal(d, s[:12])
    np.testing.assert_array_equal(p, u[:, :12])
    gram = modal.era(y, dt, 6, 40, 400, svd="gram")
    full = modal.era(y, dt, 6, 40, 400, svd="full")
    np.testing.assert_array_equal(gram.omega, full.omega)


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


def test_falls_back_when_residual_check_fails():
    """A plain matrix (no block structure) whose 24th singular value is 1e-6 of the
    first and the 25th 0.9 of it: the Gram eigenvectors are wrong by an angle of
    ~1e-5 and Rayleigh-Ritz shrinks it by only 0.81 a step, so the residual check
    must send it to the thin SVD."""
    rng = np.random.default_rng(7)
    n_rows, n_cols, order = 240, 500, 24
    sigma = np.concatenate([np.logspace(0, -6, order), 0.9e-6 * np.logspace(0, -3, n_rows - order)])
    u = np.linalg.qr(rng.standard_normal((n_rows, n_rows)))[0]
    v = np.linalg.qr(rng.standard_normal((n_cols, n_rows)))[0]
    h0 = (u * sigma) @ v.T
    p, d, qt, sv = decompose(h0, order, method="gram")
    assert sv.size == n_rows
    np.testing.assert_allclose(d, sigma[:order], rtol=1e-6)
    # a gap of 10 after the 24th value: one Rayleigh-Ritz step leaves a residual
    # of ~1e-12, a second passes the check; a gap of 1e6: one step suffices
    for gap in (10, 1e6):
        sigma[order:] = 1e-6 / gap * np.logspace(0, -3, n_rows - order)
        h0 = (u * sigma) @ v.T
        p, d, qt, sv = decompose(h0, order, method="gram")
        assert sv.size == order
        np.testing.assert_allclose(d, sigma[:order], rtol=1e-8)
        np.testing.assert_allclose(np.abs(np.sum(p * u[:, :order], axis=0)), 1, atol=1e-6)


def _noisy_record(n_channels=12, n_samples=8000, seed=0):
    rng = np.random.default_rng(seed)
    w = np.linspace(5.0, 300.0, n_channels)
    rec = modal.impulse_response(w, rng.standard_normal((n_channels, n_channels)), np.ones(n_channels),
                                 0.005, n_samples, 0.01)
    return modal.with_noise(rec, 0.02, seed + 1).acceleration


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_noisy_agrees_with_full_svd(seed):
    y = _noisy_record(seed=seed)
    fast = modal.era(y, 0.01, 12, rows=40, cols=1000)
    full = modal.era(y, 0.01, 12, rows=40, cols=1000, svd="full")
    assert fast.singular_values.size == 24  # "auto" took the Gram route on 480 x 1000
    np.testing.assert_allclose(fast.omega, full.omega, rtol=1e-6)
    np.testing.assert_allclose(fast.damping, full.damping, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(np.abs(np.diag(modal.mac(fast.shapes, full.shapes))), 1, atol=1e-6)
    np.testing.assert_allclose(fast.singular_values, full.singular_values[:24], rtol=1e-10)


def test_noisy_several_sets_taller_than_wide():
    """3 data sets, 480 x 300 Hankel: the Gram matrix is that of the columns."""
    y = np.stack([_noisy_record(n_samples=300, seed=s) for s in range(3)])
    h0 = modal.hankel(y, 40, 100)
    assert h0.shape == (480, 300) and _took_gram(h0, 24, (12, 3))
    fast = modal.era(y, 0.01, 12, rows=40, cols=100, svd="gram")
    full = modal.era(y, 0.01, 12, rows=40, cols=100, svd="full")
    np.testing.assert_allclose(fast.omega, full.omega, rtol=1e-6)
    np.testing.assert_allclose(fast.damping, full.damping, rtol=1e-6, atol=1e-9)


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


@pytest.mark.parametrize("bad", ["fast", "SVD", None, 1])
def test_method_keyword_refused(demo, bad):
    rec = demo["make"](400)
    with pytest.raises(ValueError, match="svd must be one of"):
        modal.era(rec.acceleration, demo["dt"], 6, rows=24, cols=100, svd=bad)
    with pytest.raises(ValueError, match="method must be one of"):
        decompose(modal.hankel(rec.acceleration, 24, 100), 12, method=bad)


def test_decompose_order_checked():
    with pytest.raises(ValueError, match="^order = 6 exceeds"):
        decompose(np.ones((5, 8)), 6)
    with pytest.raises(ValueError, match="^order must"):
        decompose(np.ones((5, 8)), 0)


def test_decompose_a_single_triplet_by_gram():
    """order = 1 on the Gram route: the leading singular triplet, as the thin SVD's
    (the absolute tolerance is relative to sigma_1, the only one there is)."""
    h0 = np.random.default_rng(3).standard_normal((40, 60))
    p, d, qt, sv = decompose(h0, 1, method="gram")
    u, s, vt = np.linalg.svd(h0, full_matrices=False)
    assert sv.size == 1
    np.testing.assert_allclose(d, s[:1], rtol=1e-12)
    np.testing.assert_allclose(np.abs(p[:, 0] @ u[:, 0]), 1, rtol=1e-12)
    np.testing.assert_allclose(np.abs(qt[0] @ vt[0]), 1, rtol=1e-12)


def test_block_hankel_gram_of_two_block_rows():
    """Two block rows: the second block row comes from the recursion too."""
    h = modal.hankel(np.random.default_rng(4).standard_normal((1, 90, 5)), 2, 40)
    np.testing.assert_allclose(block_hankel_gram(h, 5, 1), h @ h.T, rtol=1e-12, atol=1e-12 * np.abs(h).max() ** 2)


def test_block_checked():
    h0 = modal.hankel(np.random.default_rng(0).standard_normal((90, 3)), 10, 40)
    for bad in [(4, 1), (3, 2), (0, 1), 3, ("3", 1)]:
        with pytest.raises(ValueError, match="block"):
            decompose(h0, 4, method="gram", block=bad)
    with pytest.raises(ValueError, match="not a block Hankel"):
        decompose(np.random.default_rng(1).standard_normal(h0.shape), 4, method="gram", block=(3, 1))
    # shifted copies of themselves, but 5 rows are not whole blocks of 2, nor 8 columns of 3
    for shape, block in [((5, 8), (2, 1)), ((6, 8), (1, 3))]:
        with pytest.raises(ValueError, match="not a block Hankel"):
            decompose(np.ones(shape), 1, method="gram", block=block)


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
