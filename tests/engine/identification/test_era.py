"""ERA (thesis Eqs. 34-45) through modal.era and modal.decompose: exact on the
thesis's beam and off its geometry, several data sets, the flags it sets,
the Gram route of the decomposition against the thin SVD, refusals."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import modal
from modal import decompose

from ..cases import (flagged, LAYOUTS, PROPERTY, TABLE_1, TABLE_2, THESIS_SAMPLES, _records, beam_cases, beam_record,
                     diag_mac, printed, two_sinusoids)

EXACT_MAC = 1 - 1e-10
IRREGULAR_7 = np.array([0.4, 1.1, 1.9, 2.3, 3.05, 3.7, 4.45])  # seven sensors off the thesis's iL/7

@pytest.mark.parametrize("zeta", [0.0, 0.005, 0.02, 0.05])
def test_era_exact_on_noise_free_beam(demo, zeta):
    rec = demo["make"](THESIS_SAMPLES, damping=zeta)
    res = flagged(modal.era, rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    np.testing.assert_allclose(res.omega, demo["omega"], rtol=1e-8)
    np.testing.assert_allclose(res.damping, zeta, rtol=1e-8, atol=1e-10)
    assert not res.real_pole.any()
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)
    np.testing.assert_allclose(res.mamc, 1, atol=1e-6)
    np.testing.assert_allclose(res.mpc, 1, atol=1e-6)
    # exactly 2n = 12 singular values carry the response
    sv = res.singular_values
    assert sv[11] / sv[0] > 1e-8 and sv[12] / sv[0] < 1e-10


TABLE_1 = {"tcm": [2.1659, 8.6617, 19.474], "era": [2.1623, 8.6493, 19.461]}


TABLE_2 = {"tcm": [2.1711, 8.6614, 19.407], "era": [2.1623, 8.6493, 19.461]}


@pytest.mark.parametrize("zeta, table", [(0.0, TABLE_1), (0.05, TABLE_2)])
def test_thesis_tables_1_and_2_to_printed_digits(demo, zeta, table):
    rec = demo["make"](THESIS_SAMPLES, damping=zeta)
    tcm = flagged(modal.tcm, rec.acceleration, demo["dt"], vel=rec.velocity)
    era = flagged(modal.era, rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    assert printed(tcm.omega[:3], table["tcm"]) == table["tcm"]
    assert printed(era.omega[:3], table["era"]) == table["era"]


def test_era_multiple_data_sets_identify_repeated_frequency():
    # Two modes with the same frequency and different shapes: one data set sees
    # only one combination; m = 2 sets with different excitations resolve both.
    w = np.array([2.0, 2.0, 5.0])
    shapes = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, -0.5], [0.7, 0.4, 1.0]])
    dt = 0.05
    sets = [modal.impulse_response(w, shapes, f, dt, 400, 0.01).acceleration
            for f in ([1.0, 0.2, 0.5], [0.1, 1.0, -0.3])]
    res = flagged(modal.era, np.stack(sets), dt, 3, rows=10, cols=100)
    np.testing.assert_allclose(res.omega, w, rtol=1e-8)
    with pytest.raises(ValueError, match="n_modes"):
        flagged(modal.era, sets[0], dt, 3, rows=10, cols=100)


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("zeta", [0.0, 0.02])
def test_era_exact_on_every_layout(layout, zeta):
    rec, omega, dt = beam_record(layout, 1200, damping=zeta)
    res = flagged(modal.era, rec.acceleration, dt, 6, rows=8, cols=400)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-8)
    np.testing.assert_allclose(res.damping, zeta, rtol=1e-8, atol=1e-10)
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)
    assert np.all(res.mamc > 1 - 1e-8) and np.all(res.mpc > 1 - 1e-8)
    assert not (res.real_pole.any() or res.unstable.any() or res.aliased.any())


def test_era_several_data_sets_on_irregular_layout():
    sets = [beam_record("irregular", 600, damping=0.01, impact=x)[0].acceleration for x in (0.7, 2.9, 4.1)]
    rec, omega, dt = beam_record("irregular", 2, damping=0.01)
    res = flagged(modal.era, np.stack(sets), dt, 6, rows=4, cols=200)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-8)
    np.testing.assert_allclose(res.damping, 0.01, rtol=1e-7)
    assert np.all(diag_mac(res.shapes, rec.shapes) >= EXACT_MAC)


@PROPERTY
@given(beam_cases())
def test_property_era_exact(case):
    beam, n, sensors, impacts, zeta = case
    recs, omega, dt = _records(beam, n, sensors, impacts, zeta, 600)
    y = np.stack([r.acceleration for r in recs])
    res = flagged(modal.era, y, dt, n, rows=4, cols=300)
    np.testing.assert_allclose(res.omega, omega, rtol=1e-7)
    np.testing.assert_allclose(res.damping, zeta, rtol=1e-6, atol=1e-8)
    assert np.all(diag_mac(res.shapes, recs[0].shapes) >= 1 - 1e-8)
    assert np.all(res.mamc > 1 - 1e-6)


@PROPERTY
@given(beam_cases(), st.floats(-150, 150))
def test_property_results_do_not_depend_on_scale(case, exponent):
    beam, n, sensors, impacts, zeta = case
    recs, _, dt = _records(beam, n, sensors, impacts[:1], zeta, 400)
    y = recs[0].acceleration
    for method, kwargs in (("era", dict(n_modes=n, rows=4, cols=200)), ("cera", dict(n_modes=n, cols=200))):
        ref = flagged(getattr(modal, method), y, dt, **kwargs)
        scaled = flagged(getattr(modal, method), y * 10.0**exponent, dt, **kwargs)
        np.testing.assert_allclose(scaled.omega, ref.omega, rtol=1e-9)


def test_era_flags_growing_modes_unstable():
    dt, t = 0.01, 0.01 * np.arange(800)
    grow, decay = np.exp(0.02 * 3.0 * t), np.exp(-0.01 * 7.0 * t)
    y = np.column_stack([grow * np.sin(3.0 * t) + decay * np.sin(7.0 * t), grow * np.sin(3.0 * t) - decay * np.sin(7.0 * t)])
    res = flagged(modal.era, y, dt, 2, rows=10, cols=300)
    np.testing.assert_allclose(res.omega, [3.0 * np.hypot(1, 0.02), 7.0 * np.hypot(1, 0.01)], rtol=1e-6)
    np.testing.assert_array_equal(res.unstable, [True, False])
    assert res.damping[0] < 0 < res.damping[1]
    np.testing.assert_array_equal(res.to_frame()["unstable"], [True, False])


def test_data_sets_on_the_last_axis_are_refused():
    rec, _, dt = beam_record("irregular", 800)
    wrong = np.stack([rec.acceleration] * 3, axis=2)  # (n_samples, n_channels, n_sets)
    with pytest.raises(ValueError, match=r"\(n_sets, n_samples, n_channels\)"):
        modal.era(wrong, dt, 2, rows=2, cols=3)


def test_era_keeps_real_poles_with_their_decay_rate():
    """Two real poles (e^{-t}, e^{-2t}) and one damped pair: the real poles
    are entries with omega = |ln z| / dt = the decay rate, ``real_pole`` set
    and damping NaN; the pair has zeta = 0.05 / |s|."""
    dt = 0.05
    t = dt * np.arange(400)
    y = np.column_stack([np.exp(-t) + np.exp(-0.05 * t) * np.sin(3 * t), np.exp(-2 * t) - np.exp(-0.05 * t) * np.sin(3 * t)])
    res = flagged(modal.era, y, dt, 2, rows=20, cols=300)
    s_pair = np.hypot(0.05, 3.0)
    np.testing.assert_allclose(res.omega, [1.0, 2.0, s_pair], rtol=1e-8)
    np.testing.assert_array_equal(res.real_pole, [True, True, False])
    assert np.isnan(res.damping[:2]).all()
    assert res.damping[2] == pytest.approx(0.05 / s_pair, rel=1e-7)
    np.testing.assert_allclose(res.eigenvalues, np.exp(np.array([-1.0, -2.0, -0.05 + 3.0j]) * dt), rtol=1e-9)


def test_era_flags_a_mode_near_nyquist_aliased():
    dt, k = 0.01, np.arange(600)
    decay = np.exp(-0.001 * k)
    y = np.column_stack([decay * np.cos(0.99 * np.pi * k) + np.sin(0.3 * k), decay * np.cos(0.99 * np.pi * k) - np.sin(0.3 * k)])
    res = flagged(modal.era, y, dt, 2, rows=10, cols=400)
    np.testing.assert_allclose(res.omega[1] * dt, np.hypot(0.99 * np.pi, 0.001), rtol=1e-8)
    np.testing.assert_array_equal(res.aliased, [False, True])
    np.testing.assert_array_equal(res.to_frame()["aliased"], [False, True])


@pytest.mark.parametrize("size", [1.0, 1e6])
def test_era_refuses_an_order_the_data_cannot_support(size):
    """A real pole and one pair are three states: order 4 is refused, judged
    against the largest singular value (here a real pole ``size`` times the
    pair)."""
    t = 0.05 * np.arange(400)
    y = np.column_stack([size * np.exp(-t) + np.sin(3 * t), size * np.exp(-t) - 0.5 * np.sin(3 * t)])
    with pytest.raises(ValueError, match=r"^n_modes = 2: the Hankel matrix has fewer than 4"):
        modal.era(y, 0.05, 2, rows=10, cols=300)


def test_singular_values_are_in_the_data_units():
    """ERA and CERA report the singular values of the Hankel matrix of the
    data as given (the internal power-of-two scaling undone)."""
    dt, _, _, acc = two_sinusoids(omega=(2.0, 5.0), amplitude=1e3)
    h = modal.hankel(acc, 4, 200)
    era = flagged(modal.era, acc, dt, 2, rows=4, cols=200)
    np.testing.assert_allclose(era.singular_values, np.linalg.svd(h, compute_uv=False), rtol=1e-10)
    cera = flagged(modal.cera, acc, dt, 2, cols=200)
    np.testing.assert_allclose(cera.singular_values, np.linalg.svd(h[:2], compute_uv=False), rtol=1e-10)
    assert era.method == "era" and cera.method == "cera"


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
    res = flagged(modal.era, y, demo["dt"], 6, rows=24, cols=100, svd="gram")
    _exact(res, demo["omega"], zeta)
    assert res.singular_values.size == 12  # the Gram route was kept, not the fallback
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) > 0.9999)


def test_auto_takes_gram_route_off_thesis_geometry(beam):
    """7 irregular sensors, 2 data sets (impulses at two points), 320 x 600 Hankel:
    "auto" takes the Gram route there and is exact."""
    omega = beam.natural_frequencies(5)
    dt = 2 * np.pi / omega[-1] / 12
    sets = [modal.beam_impulse_response(beam, 5, x, IRREGULAR_7, dt, 800, 0.01).velocity for x in (1.3, 3.4)]
    y = np.stack(sets)
    res = flagged(modal.era, y, dt, 5, rows=40, cols=300)
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
    rec = modal.beam_impulse_response(beam, modes, 1.3, IRREGULAR_7, dt, 6000, damping)
    return rec.displacement, dt, omega


@pytest.mark.slow
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
    gram = flagged(modal.era, y, dt, 6, 40, 400, svd="gram")
    full = flagged(modal.era, y, dt, 6, 40, 400, svd="full")
    np.testing.assert_array_equal(gram.omega, full.omega)


@pytest.mark.slow
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
@pytest.mark.slow
def test_noisy_agrees_with_full_svd(seed):
    y = _noisy_record(seed=seed)
    fast = flagged(modal.era, y, 0.01, 12, rows=40, cols=1000)
    full = flagged(modal.era, y, 0.01, 12, rows=40, cols=1000, svd="full")
    assert fast.singular_values.size == 24  # "auto" took the Gram route on 480 x 1000
    # what the Gram route achieves (seeds 0-4: 7.5e-14, 8.7e-12 and 7e-16 at worst)
    np.testing.assert_allclose(fast.omega, full.omega, rtol=1e-12)
    np.testing.assert_allclose(fast.damping, full.damping, rtol=1e-10)
    np.testing.assert_allclose(np.abs(np.diag(modal.mac(fast.shapes, full.shapes))), 1, atol=1e-13)
    np.testing.assert_allclose(fast.singular_values, full.singular_values[:24], rtol=1e-10)


@pytest.mark.slow
def test_noisy_several_sets_taller_than_wide():
    """3 data sets, 480 x 300 Hankel: the Gram matrix is that of the columns."""
    y = np.stack([_noisy_record(n_samples=300, seed=s) for s in range(3)])
    h0 = modal.hankel(y, 40, 100)
    assert h0.shape == (480, 300) and _took_gram(h0, 24, (12, 3))
    fast = modal.era(y, 0.01, 12, rows=40, cols=100, svd="gram")
    full = modal.era(y, 0.01, 12, rows=40, cols=100, svd="full")
    np.testing.assert_allclose(fast.omega, full.omega, rtol=1e-6)
    np.testing.assert_allclose(fast.damping, full.damping, rtol=1e-6, atol=1e-9)


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
