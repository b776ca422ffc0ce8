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


def _quadrature_shapes(seed=0, n_modes=5):
    """Normal shapes of four channels, each mode's entries real times one
    phase per mode; channels 2 and 3 a derivative away (times ``i``)."""
    rng = np.random.default_rng(seed)
    real = rng.uniform(0.3, 1.0, (4, n_modes)) * rng.choice([-1.0, 1.0], (4, n_modes))
    return real * np.exp(1j * rng.uniform(0, 2 * np.pi, n_modes)) * np.array([1, 1, 1j, 1j])[:, None]


def test_quadrature_groups_part_channels_a_derivative_apart():
    """Channels 2 and 3 a quarter period from 0 and 1 in five modes (signs
    of every entry random: opposite is in phase): the groups, 90 degrees,
    five modes; -i instead of i (a sensor the other way round) the same;
    the groups whatever the channel order (the first holds the lowest); the
    derivative of a mode damped 5 % (87.1 degrees) parted, 83 degrees (a
    mixture of close modes came as near) not."""
    from modal.identification import quadrature_groups

    shapes = _quadrature_shapes()
    first, second, degrees, n_modes = quadrature_groups(shapes)
    assert (first, second, n_modes) == ([0, 1], [2, 3], 5) and degrees == pytest.approx(90.0, abs=1e-9)
    flipped = shapes * np.array([1, 1, -1, 1])[:, None]
    assert quadrature_groups(flipped)[:2] == ([0, 1], [2, 3])
    assert quadrature_groups(shapes[[2, 0, 3, 1]])[:2] == ([0, 2], [1, 3])
    damped = shapes * np.exp(1j * np.arcsin(0.05) * np.array([0, 0, 1, 1]))[:, None]  # s v of a mode damped 5 %
    assert quadrature_groups(damped)[2] == pytest.approx(90 - np.degrees(np.arcsin(0.05)), abs=1e-9)
    assert quadrature_groups(shapes * np.exp(1j * np.radians(7.0) * np.array([0, 0, 1, 1]))[:, None]) is None  # 83
    assert quadrature_groups(shapes * np.exp(1j * np.radians(4.5) * np.array([0, 0, 1, 1]))[:, None])[:2] == (
        [0, 1], [2, 3])  # 85.5 degrees: within 5 of 90
    opposite = shapes.copy()
    opposite[1] = -opposite[0] * np.exp(1j * np.radians(4.5))  # 175.5 degrees: within 5 of opposite, in phase
    assert quadrature_groups(opposite)[:2] == ([0, 1], [2, 3])
    assert quadrature_groups(shapes[[0, 2]])[:2] == ([0], [1])  # two channels: their one pair


def test_quadrature_groups_none_for_normal_complex_or_contradicting_shapes():
    """None: every channel of one quantity (one group); a phase of 45 degrees
    (between in phase and quadrature: a complex mode, not a derivative);
    a consistent parting found as the pairs' medians give it, none once a
    pair lies in between; modes with random phases per entry (complex
    modes)."""
    from modal.identification import quadrature_groups

    shapes = _quadrature_shapes()
    assert quadrature_groups(shapes * np.array([1, 1, -1j, -1j])[:, None]) is None  # all in phase
    assert quadrature_groups(shapes * np.array([1, 1, np.exp(-0.25j * np.pi), 1])[:, None] / np.array(
        [1, 1, 1j, 1j])[:, None]) is None  # channel 2 at 45 degrees
    contradicting = shapes.copy()
    contradicting[1] *= 1j  # channel 1 now with 2 and 3, but 0 with 2 in quadrature and 0 with 1 too
    contradicting[3] /= 1j  # 3 back with 0: 1-3 in quadrature, 2-3 in quadrature, 0-3 in phase, 0-2 quadrature
    assert quadrature_groups(contradicting)[:2] == ([0, 3], [1, 2])  # a consistent parting is found ...
    contradicting[3, :3] *= 1j  # channel 3 a quarter period on in three of five modes: the median moves it
    assert quadrature_groups(contradicting)[:2] == ([0], [1, 2, 3])
    contradicting[3] *= np.exp(0.3j * np.pi)  # and 54 degrees on in all: in between, no parting
    assert quadrature_groups(contradicting) is None
    rng = np.random.default_rng(1)
    assert quadrature_groups(np.exp(1j * rng.uniform(0, 2 * np.pi, (4, 8)))) is None
    assert quadrature_groups(np.empty((4, 0), dtype=complex)) is None  # no mode well identified


def test_quadrature_groups_leave_weak_and_rare_channels_out():
    """A channel whose entries are all below a tenth of its largest but one
    is judged in fewer than three modes: in neither group, its noise-like
    phases ignored; three modes suffice; a channel shown only where no other
    is (or never: all zero) in neither group; a channel judged with one
    other alone is placed through it; two sets of channels no judged pair
    joins give no parting."""
    from modal.identification._indicators import QUADRATURE_MIN_MODES, QUADRATURE_MIN_SHARE, quadrature_groups

    shapes = np.vstack([_quadrature_shapes(), np.exp(1j * np.arange(5.0))])  # channel 4: random phases ...
    shapes[4, :3] *= 0.5 * QUADRATURE_MIN_SHARE  # ... shown in two modes only
    assert QUADRATURE_MIN_MODES == 3
    assert quadrature_groups(shapes)[:2] == ([0, 1], [2, 3])
    shapes[4, 2] /= 0.5 * QUADRATURE_MIN_SHARE  # shown in three: judged, and its phases contradict
    assert quadrature_groups(shapes) is None
    three = _quadrature_shapes(n_modes=3)
    assert quadrature_groups(three)[3] == 3 and quadrature_groups(three[:, :2]) is None
    extra = np.hstack([_quadrature_shapes(), np.zeros((4, 3))])
    alone = np.vstack([extra, np.r_[np.zeros(5), 1.0, -1.0, 1.0]])  # channel 4 only where no other shows
    assert quadrature_groups(alone)[:2] == ([0, 1], [2, 3])
    chained = extra.copy()
    chained[3] = np.r_[np.zeros(5), 2j * chained[2, 5:]]  # channel 3 judged with 2 alone, over three added modes
    chained[2, 5:] = [1.0, -0.5, 0.8]
    chained[3, 5:] = [2j, -1j, 1.6j]
    assert quadrature_groups(chained)[:2] == ([0, 1, 3], [2])  # placed through channel 2, a quarter period on
    zero = np.vstack([_quadrature_shapes(), np.zeros(5)])
    assert quadrature_groups(zero)[:2] == ([0, 1], [2, 3])  # an all-zero channel shows in no mode
    unconnected = extra.copy()
    unconnected[2:, :5] = 0.0
    unconnected[2, 5:] = [1.0, -0.5, 0.8]
    unconnected[3, 5:] = [0.5, 1.0, -0.7]  # 2 and 3 in phase, judged only with each other; 0 and 1 in quadrature
    unconnected[1, :5] *= 1j
    assert quadrature_groups(unconnected) is None  # how 2, 3 relate to 0, 1 is unknown
    assert quadrature_groups(unconnected[:2])[:2] == ([0], [1])
    apart = _quadrature_shapes()
    apart[[0, 1], :2] = 0.0
    apart[[2, 3], 2:] = 0.0  # channels 0, 1 only in modes 2-4 and 2, 3 only in 0-1: no pair across judged
    assert quadrature_groups(apart) is None
