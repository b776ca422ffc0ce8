"""A broad estimate fitted across two close modes is flagged, modes are not
(issue 32: impact tests whose damping falls with the amplitude gave a
trusted "mode" between a close pair, 182 and 187 Hz, of 3-4 % damping and a
mixed shape).

The rule (:func:`modal.identification.blends`, applied by the spectral
witness after its own checks): a mode
whose half-power band holds a sharper trusted mode on each side and whose
shape lies in the plane of theirs. Each case sits on one side of one
condition, so that an inverted comparison, a dropped condition, a wrong
width or a conjugate turns a test red."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
from modal.identification import BLEND
from modal.identification import blends as _blends
from modal.identification._stabilisation import MIN_CHANNELS_ALIKE

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "benchmarks"))
from _simulation import falling_damping_decays  # noqa: E402  (the impact records of bench_impact.py)

#: Two close modes' shapes on four channels (complex, of MAC 0.1 with each other) and one of their own.
A = np.array([1.0, 0.6 + 0.1j, -0.4, 0.2])
B = np.array([0.3, -1.0, 0.8 - 0.2j, 0.5])
OWN = np.array([0.2, 0.3, 0.4, -1.0])


def blends(freq, damping, shapes, trusted=None, mac_min=0.98):
    freq = np.asarray(freq, dtype=float)
    return _blends(freq, damping, np.column_stack(shapes), [True] * len(freq) if trusted is None else trusted,
                   mac_min)


def test_a_broad_mode_in_the_plane_of_two_sharp_ones_within_its_band_is_a_blend():
    """182 and 187 Hz at 0.9 %, 184.4 Hz at 3.8 % (half-width 7.0 Hz) of shape
    0.7 A + (0.4 - 0.3i) B: flagged, naming both; the two stay trusted."""
    flags = blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], [A, 0.7 * A + (0.4 - 0.3j) * B, B])
    assert flags == ["", f"{BLEND} 182 and 187 Hz", ""]


def test_a_broad_mode_of_its_own_shape_is_a_mode():
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], [A, OWN, B]) == ["", "", ""]


def test_the_span_is_judged_against_mac_min():
    """A shape with 2 % of its energy out of the plane: a blend at mac_min 0.97, a mode at 0.99."""
    out = OWN - A * np.vdot(A, OWN) / np.vdot(A, A)
    out -= B * np.vdot(B, out) / np.vdot(B, B)
    inside = 0.7 * A + (0.4 - 0.3j) * B
    out *= np.sqrt(0.02 / 0.98 * np.vdot(inside, inside).real / np.vdot(out, out).real)
    shapes = [A, inside + out, B]
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], shapes, mac_min=0.97)[1].startswith(BLEND)
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], shapes, mac_min=0.99)[1] == ""


def test_the_span_is_complex_and_conjugated_right():
    """The shape (1 + 1j) A + (1 - 1j) B is in the complex plane of A and B;
    the same coefficients on conjugated B (a shape of its own) are not."""
    freq, damping = [182.0, 184.4, 187.0], [0.009, 0.038, 0.009]
    assert blends(freq, damping, [A, (1 + 1j) * A + (1 - 1j) * B, B])[1].startswith(BLEND)
    assert blends(freq, damping, [A, (1 + 1j) * A + (1 - 1j) * B.conj(), B])[1] == ""


def test_both_sharp_modes_must_lie_within_the_half_power_band():
    """Half-width 0.02 x 184.4 = 3.69 Hz: 181.0 (3.4 Hz below) is inside, 180.5 (3.9 Hz) not;
    the upper side likewise."""
    shapes = [A, 0.7 * A + 0.4 * B, B]
    assert blends([181.0, 184.4, 187.0], [0.009, 0.02, 0.009], shapes)[1].startswith(BLEND)
    assert blends([180.5, 184.4, 187.0], [0.009, 0.02, 0.009], shapes)[1] == ""
    assert blends([182.0, 184.4, 188.3], [0.009, 0.02, 0.009], shapes)[1] == ""


def test_a_mode_between_two_broader_ones_is_no_blend():
    """The same three with the middle one the sharpest: it is not broader than either, and
    each outer one has a neighbour on one side only."""
    assert blends([182.0, 184.4, 187.0], [0.05, 0.009, 0.05], [A, 0.7 * A + 0.4 * B, B]) == ["", "", ""]
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.04], [A, 0.7 * A + 0.4 * B, B])[1] == ""
    # as damped as the middle one, on either side: not sharper
    assert blends([182.0, 184.4, 187.0], [0.038, 0.038, 0.009], [A, 0.7 * A + 0.4 * B, B])[1] == ""
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.038], [A, 0.7 * A + 0.4 * B, B])[1] == ""


def test_a_sharp_mode_at_the_same_frequency_lies_on_neither_side():
    """A sharp mode of shape A at 184.4 Hz exactly, and B at 187 Hz: nothing below 184.4 Hz's broad row."""
    assert blends([184.4, 184.4, 187.0], [0.009, 0.038, 0.009], [A, 0.7 * A + 0.4 * B, B])[1] == ""
    assert blends([182.0, 184.4, 184.4], [0.009, 0.038, 0.009], [A, 0.7 * A + 0.4 * B, B])[1] == ""


def test_of_two_pairs_the_nearest_is_named():
    """Two sharp modes of shape A below (181.0 and 182.5 Hz) and B above: the flag names 182.5 and 187 Hz,
    whichever order the modes come in."""
    between = 0.7 * A + 0.4 * B
    assert blends([181.0, 182.5, 184.4, 187.0], [0.009, 0.009, 0.038, 0.009],
                  [A, (1 + 0.5j) * A, between, B])[2] == f"{BLEND} 182.5 and 187 Hz"
    assert blends([182.5, 181.0, 184.4, 187.5, 187.0], [0.009, 0.009, 0.038, 0.009, 0.009],
                  [A, (1 + 0.5j) * A, between, B, B])[2] == f"{BLEND} 182.5 and 187 Hz"


def test_two_sharp_modes_on_one_side_are_no_blend():
    assert blends([182.0, 183.0, 184.4], [0.009, 0.009, 0.038], [A, B, 0.7 * A + 0.4 * B])[2] == ""


def test_only_trusted_modes_explain_another():
    flags = blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], [A, 0.7 * A + 0.4 * B, B],
                   trusted=[True, True, False])
    assert flags[1] == ""


def test_a_blend_explains_no_broader_mode():
    """183.0 Hz at 2.5 % (half-width 4.6 Hz) blends 182 and 187 Hz. 188 Hz at
    3 % (half-width 5.6 Hz: 183 and 187 Hz below, 190 Hz above) lies in the
    plane of 183.0 and 190 Hz, not of 187 and 190 Hz: a mode, since a blend
    explains nothing."""
    freq, damping = [182.0, 183.0, 187.0, 188.0, 190.0], [0.009, 0.025, 0.009, 0.03, 0.009]
    between = 0.9 * A + 0.2 * B
    flags = blends(freq, damping, [A, between, B, 0.6 * between + 0.5 * OWN, OWN])
    assert flags == ["", f"{BLEND} 182 and 187 Hz", "", "", ""]
    # had 183.0 Hz been a mode, 188 Hz would be its blend with 190 Hz
    assert blends(freq, damping, [A, between, B, 0.6 * between + 0.5 * OWN, OWN],
                  trusted=[False, True, True, True, True])[3] == f"{BLEND} 183 and 190 Hz"


def test_two_channels_span_every_shape():
    two = [A[:2], OWN[:2], B[:2]]
    assert MIN_CHANNELS_ALIKE == 3
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], two) == ["", "", ""]
    three = [A[:3], 0.7 * A[:3] + 0.4 * B[:3], B[:3]]
    assert blends([182.0, 184.4, 187.0], [0.009, 0.038, 0.009], three)[1].startswith(BLEND)


def _spectrum(peaks, df=0.25, n_freq=1600):
    """A singular-value spectrum whose first singular value is the larger of
    half-power bells at ``peaks`` (``(freq_hz, zeta, vector)``), its vector
    that bell's, the second singular value far below."""
    f = df * np.arange(n_freq)
    bells = np.array([1 / ((1 - (f / f0) ** 2) ** 2 + (2 * zeta * f / f0) ** 2) for f0, zeta, _ in peaks])
    top = np.argmax(bells, axis=0)
    units = np.array([np.asarray(v, dtype=complex) / np.linalg.norm(v) for _, _, v in peaks])
    first = units[top]
    other = np.array([np.linalg.svd(v[None, :].conj())[2][1].conj() for v in first])
    values = np.column_stack([bells.max(axis=0), 1e-6 * np.ones(n_freq)])
    return modal.SingularValueSpectrum(f, values, np.stack([first, other], axis=2), nperseg=int(round(1 / (df * 1e-4))))


def _three_modes(shapes, damping=(0.009, 0.038, 0.009)):
    from modal.identification import Stabilisation, StabilityCriteria

    modes = pd.DataFrame({"mode": [1, 2, 3], "freq_hz": [182.0, 184.4, 187.0], "damping": list(damping),
                          "n_poles": [25, 19, 24], "flag": ["", "", ""]})
    shapes = np.column_stack(shapes).astype(complex)
    return Stabilisation(modes, shapes.real, pd.DataFrame(), np.empty((0, 0)), np.empty(0), np.empty(0), np.empty(0),
                         StabilityCriteria(), complex_shapes=shapes)


def test_the_witness_flags_a_blend_of_two_modes_with_peaks_of_their_own_once():
    """182 and 187 Hz, each with its own peak, and a broad 184.4 Hz of shape
    0.7 A + (0.4 - 0.3i) B (MAC below 0.8 with either, so no shared peak):
    flagged a blend, once when witnessed twice; where 187 Hz has no peak of
    its own (its neighbour flagged ``no spectral peak``), 184.4 Hz is no blend
    of it."""
    between = 0.7 * A + (0.4 - 0.3j) * B
    assert np.all(np.real(modal.mac(between[:, None], np.column_stack([A, B]))) < 0.8)
    result = _three_modes([A, between, B])
    both = _spectrum([(182.0, 0.003, A), (187.0, 0.003, B)])
    witnessed = modal.measured.with_spectral_witness(result, both)
    assert witnessed.modes["flag"].tolist() == ["", f"{BLEND} 182 and 187 Hz", ""]
    again = modal.measured.with_spectral_witness(witnessed, both)
    assert again.modes["flag"].tolist() == witnessed.modes["flag"].tolist()
    one = modal.measured.with_spectral_witness(result, _spectrum([(182.0, 0.003, A), (120.0, 0.003, B)]))
    assert one.modes["flag"].tolist()[1:] == ["", "no spectral peak"]


#: The impact test of bench_impact.py: a close pair, 182 and 187 Hz, and two modes well apart, on three channels.
IMPACT_HZ = [182.0, 187.0, 515.0, 2270.0]
IMPACT_DAMPING = [0.006, 0.007, 0.008, 0.006]
IMPACT_SHAPES = np.array([[1.0, 0.6, -0.4], [0.3, -1.0, 0.8], [1.0, -0.2, 0.5], [0.4, 0.9, 1.0]]).T


@pytest.mark.parametrize("seed", [1, 3])
def test_an_impact_whose_damping_falls_with_amplitude_keeps_the_close_pair_and_flags_what_is_between(seed):
    """The impact test, damping four times higher at the blow, 1.5 s at 12.8
    kHz: a broad row between the pair that no other check doubts is flagged a
    blend of the two; both modes of the pair are trusted with their own
    shapes (MAC 0.99 with the truth)."""
    dt = 1 / 12800
    y = falling_damping_decays(IMPACT_HZ, IMPACT_DAMPING, IMPACT_SHAPES, dt, 19200, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        result, _ = modal.identify_record(y, dt, "free_decay")
    modes = result.modes
    table = modes[["freq_hz", "damping", "mpc", "flag"]]
    f, flags = modes["freq_hz"].to_numpy(), modes["flag"].to_numpy()
    blend = [k for k in range(len(f)) if flags[k].startswith(BLEND)]
    assert blend and all(182.0 < f[k] < 187.0 for k in blend), table
    assert any(";" not in flags[k] for k in blend), table  # a row no other check doubts
    pair = [int(np.argmin(np.where(flags == "", np.abs(f - target), np.inf))) for target in IMPACT_HZ[:2]]
    assert np.allclose(f[pair], IMPACT_HZ[:2], rtol=0.005), table
    assert np.all(np.diag(np.real(modal.mac(result.shapes[:, pair], IMPACT_SHAPES[:, :2]))) > 0.99), table
