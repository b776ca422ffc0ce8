"""Accuracy indicators: MAC, MPC, MAMC, shape alignment."""

import numpy as np
import pytest

import modal

from ..cases import flagged, beam_record

def test_mac_properties():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((6, 3))
    m = modal.mac(a, a)
    np.testing.assert_allclose(np.diag(m), 1)
    assert np.all((m >= 0) & (m <= 1 + 1e-12))
    np.testing.assert_allclose(modal.mac(a, -3 * a), m)
    q, _ = np.linalg.qr(a)
    np.testing.assert_allclose(modal.mac(q, q), np.eye(3), atol=1e-12)


def test_mamc_and_mpc_low_for_noise_modes_above_the_physical_order():
    rec, omega, dt = beam_record("irregular", 1000, damping=0.01)
    noisy = modal.add_noise(rec.displacement, 0.01, 0)
    res = flagged(modal.era, noisy, dt, 10, rows=20, cols=400)
    physical = np.array([np.min(np.abs(w / omega - 1)) < 0.01 for w in res.omega])
    assert physical.sum() == 6
    assert np.all(res.mamc[physical] > 0.99) and np.all(res.mpc[physical] > 0.99)
    noise = ~physical
    assert np.all(res.mamc[noise] < 0.5)
    complex_noise = noise & ~res.real_pole
    assert np.min(res.mpc[complex_noise]) < 0.5


def test_mpc_of_known_shapes():
    shapes = np.array([[1, 1, 1 + 1j], [1j, -2, 2 + 2j], [0, 1, -1 - 1j]], dtype=complex)
    np.testing.assert_allclose(modal.modal_phase_collinearity(shapes), [0.0, 1.0, 1.0], atol=1e-12)
    # entries at 45 degrees with equal weight: S = [[1, 1/2], [1/2, 1/2]] per unit, MPC = 0.2
    mixed = np.array([[1.0], [np.exp(1j * np.pi / 4)]])
    l1, l2 = np.linalg.eigvalsh(np.array([[1.5, 0.5], [0.5, 0.5]]))[::-1]
    np.testing.assert_allclose(modal.modal_phase_collinearity(mixed), ((l1 - l2) / (l1 + l2)) ** 2)


def test_mamc_of_known_histories():
    z = np.array([0.9 * np.exp(0.3j), 0.95 * np.exp(1.1j)])
    ideal = z[:, None] ** np.arange(50)[None, :] * np.array([[2.0], [1 - 1j]])
    np.testing.assert_allclose(modal.modal_amplitude_coherence(ideal, z, 1), 1, atol=1e-12)
    wrong_frequency = ideal * np.exp(0.3j * np.arange(50))[None, :]
    assert np.all(modal.modal_amplitude_coherence(wrong_frequency, z, 1) < 0.7)
    # two data sets: interleaved columns (block column j, set k at j m + k)
    two = np.stack([ideal, 3 * ideal], axis=2).reshape(2, 100)
    np.testing.assert_allclose(modal.modal_amplitude_coherence(two, z, 2), 1, atol=1e-12)


def test_indicators_of_zero_vectors_are_zero():
    """MAC, MPC and MAMC of a zero shape or history are 0, not NaN."""
    a = np.array([[1.0, 0.0], [2.0, 0.0], [0.5, 0.0]])
    np.testing.assert_array_equal(modal.mac(a, a), [[1.0, 0.0], [0.0, 0.0]])
    np.testing.assert_array_equal(modal.modal_phase_collinearity(np.zeros((3, 2), dtype=complex)), [0.0, 0.0])
    histories = np.array([np.zeros(6), 0.9 ** np.arange(6)], dtype=complex)
    np.testing.assert_allclose(modal.modal_amplitude_coherence(histories, np.array([0.5, 0.9]), 1), [0.0, 1.0], rtol=1e-14)


def test_align_shapes_flips_and_scales_to_the_reference():
    reference = np.array([[1.0, 0.0, 2.0], [2.0, 3.0, 0.0], [2.0, -4.0, 0.0]])  # norms 3, 5, 2
    shapes = np.array([[-0.5, 0.0, 1.0], [-1.0, -6.0, 0.0], [-1.0, 8.0, 0.0]])  # flipped, rescaled
    out = modal.align_shapes(shapes, reference)
    np.testing.assert_allclose(out, reference, rtol=1e-15)
    # shapes of norm below 1 are scaled up as well
    np.testing.assert_allclose(modal.align_shapes(shapes * 1e-3, reference), reference, rtol=1e-13)
    # fewer shapes than references: only as many columns; a zero column stays zero
    out = modal.align_shapes(np.column_stack([-shapes[:, 0], np.zeros(3)]), reference)
    np.testing.assert_allclose(out, np.column_stack([reference[:, 0], np.zeros(3)]), rtol=1e-15)
    # a shape orthogonal to its reference keeps its sign
    out = modal.align_shapes(np.array([[0.0], [4.0], [3.0]]), np.array([[1.0], [0.0], [0.0]]))
    np.testing.assert_allclose(out, [[0.0], [0.8], [0.6]], rtol=1e-15)
    for bad, name in (((shapes[:2], reference), "shapes and reference"), ((shapes[:, 0], reference), "shapes"),
                      ((shapes, reference[:, 0]), "reference"), ((shapes * np.nan, reference), "shapes")):
        with pytest.raises(ValueError, match=rf"^{name}\b"):
            modal.align_shapes(*bad)


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int64, np.complex64])
def test_modal_amplitude_coherence_of_any_numeric_histories(dtype):
    """Histories given as float32, float64, integers or complex64 (the function
    is public) give the coherence of the same values as complex128, not of
    their bytes reinterpreted."""
    modal_amplitude_coherence = modal.modal_amplitude_coherence
    rng = np.random.default_rng(8)
    values = np.round(rng.standard_normal((3, 20)) * 100)  # exact in every dtype
    if np.issubdtype(dtype, np.complexfloating):
        values = values + 1j * np.round(rng.standard_normal((3, 20)) * 100)
    z = np.array([0.9, 0.5 + 0.5j, -0.3])
    expected = modal_amplitude_coherence(values.astype(complex), z, 2)
    np.testing.assert_allclose(modal_amplitude_coherence(values.astype(dtype), z, 2), expected, rtol=1e-14)
    assert np.all((expected > 0.05) & (expected < 0.95))  # neither degenerate case
