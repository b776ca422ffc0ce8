"""A mode the spectrum shows by its direction, not by a peak (issue 32:
the upper modes of a storey frame, which overlap, were flagged ``no
spectral peak``).

Modes that overlap leave troughs shallower than the witness's 6 dB between
them; each still turns the singular vector to its shape. A mode without a
prominent peak is supported when a local maximum within its half-power band
has a singular vector of MAC >= 0.9 with its shape, on three channels or
more, and no trusted mode shares its shape. Each case sits on one side of
one condition (the MAC bound, the channel count, the band, the trusted
mask, the order of a comparison), so that a slip turns a test red."""

import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import modal
from modal.identification import own_shapes
from modal.identification._fdd import (PEAK_PROMINENCE_DB, SHAPE_SUPPORT_CHANNELS, SHAPE_SUPPORT_MAC,
                                       spectral_support)

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "benchmarks"))
from _simulation import simulate, storey_frame  # noqa: E402  (the records of bench_storeys.py)

DF = 0.125


def spectrum_with_shoulder(vector, n_channels=3, bump_db=2.0, at=40, other=None):
    """Two singular values on ``n_channels``, df = 1/8 Hz (5 Hz at bin 40):
    the first a slope from 0 to -30 dB with a ``bump_db`` local maximum at
    bin ``at`` (a shoulder: far below the 6 dB of a peak), whose singular
    vector there is ``vector`` and elsewhere ``other`` (the first unit vector
    by default); the second 20 dB lower, flat."""
    n_freq = 81
    db = np.stack([np.linspace(0.0, -30.0, n_freq), np.full(n_freq, -50.0)], axis=1)
    db[at, 0] += bump_db
    base = np.zeros(n_channels, dtype=complex)
    base[0] = 1.0
    other = base if other is None else np.asarray(other, dtype=complex)
    vectors = np.zeros((n_freq, n_channels, 2), dtype=complex)
    vectors[:, :, 0] = other / np.linalg.norm(other)
    vectors[:, -1, 1] = 1.0
    vectors[at, :, 0] = np.asarray(vector) / np.linalg.norm(vector)
    return modal.SingularValueSpectrum(freq_hz=DF * np.arange(n_freq), values=10 ** (db / 10), vectors=vectors,
                                       nperseg=2 * (n_freq - 1))


def shape_of_mac(target, level):
    """A unit vector of MAC ``level`` with the unit vector ``target`` (real,
    three or more channels): ``target`` turned towards an orthogonal one."""
    target = np.asarray(target, dtype=float) / np.linalg.norm(target)
    orthogonal = np.zeros_like(target)
    orthogonal[np.argmin(np.abs(target))] = 1.0
    orthogonal -= orthogonal.dot(target) * target
    orthogonal /= np.linalg.norm(orthogonal)
    return np.sqrt(level) * target + np.sqrt(1 - level) * orthogonal


SHAPE = np.array([0.2, 1.0, -0.7])


def test_a_shoulder_whose_vector_is_the_shape_supports_a_mode_of_its_own():
    spectrum = spectrum_with_shoulder(SHAPE)
    support = spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.01], own_shape=[True]).iloc[0]
    assert support["spectral_support"] and support["sv_number"] == 1
    assert support["sv_peak_hz"] == pytest.approx(5.0, abs=DF)
    assert support["sv_mac"] == pytest.approx(1.0)
    # the shoulder's prominence (2 dB less the slope's 0.375 dB a bin), not a peak's: in modes.csv it tells a
    # direction from a peak
    assert support["sv_prominence_db"] == pytest.approx(1.625) and support["sv_prominence_db"] < PEAK_PROMINENCE_DB


def test_without_own_shape_or_on_two_channels_a_shoulder_supports_nothing():
    spectrum = spectrum_with_shoulder(SHAPE)
    for own in (None, [False]):
        assert not spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.01], own_shape=own).iloc[0][
            "spectral_support"]
    assert SHAPE_SUPPORT_CHANNELS == 3
    two = spectrum_with_shoulder(SHAPE[:2], n_channels=2)
    assert not spectral_support(two, [5.0], SHAPE[:2, None], damping=[0.01], own_shape=[True]).iloc[0][
        "spectral_support"]


@pytest.mark.parametrize("level, supported", [(SHAPE_SUPPORT_MAC + 0.005, True), (SHAPE_SUPPORT_MAC - 0.005, False),
                                              (0.02, False)])
def test_the_vectors_mac_with_the_shape_decides(level, supported):
    """A vector just above the bound supports, just below does not; a
    vector of MAC 1 - level (the MAC taken the wrong way round) neither."""
    spectrum = spectrum_with_shoulder(shape_of_mac(SHAPE, level))
    row = spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.01], own_shape=[True]).iloc[0]
    assert bool(row["spectral_support"]) is supported
    if supported:
        assert row["sv_mac"] == pytest.approx(level, abs=1e-9)


def test_the_complex_vector_not_its_conjugate_is_the_shape():
    """A complex shape: its singular vector matches it; the conjugate (a
    slip in the MAC or in the vectors) would not (MAC 0.47 here)."""
    shape = np.array([1.0, 0.3 + 0.8j, -0.5 + 0.4j])
    assert modal.mac(shape[:, None], shape.conj()[:, None])[0, 0] < SHAPE_SUPPORT_MAC
    spectrum = spectrum_with_shoulder(shape)
    assert spectral_support(spectrum, [5.0], shape[:, None], damping=[0.01], own_shape=[True]).iloc[0][
        "spectral_support"]
    conjugate = spectrum_with_shoulder(shape.conj())
    assert not spectral_support(conjugate, [5.0], shape[:, None], damping=[0.01], own_shape=[True]).iloc[0][
        "spectral_support"]


def test_the_shoulder_must_lie_within_the_half_power_band():
    """Half-width ``zeta f`` = 0.5 Hz at 10 % of 5 Hz, capped: a shoulder
    0.5 Hz away counts, one 0.625 Hz away does not; at 1 % the band is two
    bins (0.25 Hz)."""
    spectrum = spectrum_with_shoulder(SHAPE, at=44)  # 5.5 Hz
    assert spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.1], own_shape=[True]).iloc[0]["spectral_support"]
    assert not spectral_support(spectrum, [4.875], SHAPE[:, None], damping=[0.1],
                                own_shape=[True]).iloc[0]["spectral_support"]
    assert not spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.01],
                                own_shape=[True]).iloc[0]["spectral_support"]
    # far from the shoulder (3.5 Hz away, two bins' band): nothing, whatever lies below twice its frequency
    assert not spectral_support(spectrum, [9.0], SHAPE[:, None], damping=[0.01],
                                own_shape=[True]).iloc[0]["spectral_support"]


def test_a_vector_of_exactly_the_bound_matches():
    """``matching_maximum`` with ``mac_min`` the very MAC of the shoulder's
    vector: the bound counts."""
    vector = shape_of_mac(SHAPE, 0.93)
    spectrum = spectrum_with_shoulder(vector)
    exact = float(modal.mac(SHAPE[:, None], spectrum.vectors[40, :, 0][:, None])[0, 0])
    assert spectrum.matching_maximum(5.0, 0.25, SHAPE, mac_min=exact)[:2] == (40, 1)
    assert spectrum.matching_maximum(5.0, 0.25, SHAPE, mac_min=np.nextafter(exact, 2.0)) is None


def test_of_two_shoulders_the_better_matching_vector_counts():
    """Two local maxima within the band: bin 40 of MAC 0.92 and bin 42 of
    MAC 0.99 with the shape; the second counts (its MAC is the one given),
    wherever the nearer one lies."""
    spectrum = spectrum_with_shoulder(shape_of_mac(SHAPE, 0.92))
    spectrum.values[42, 0] *= 10 ** (1.5 / 10)
    spectrum.vectors[42, :, 0] = shape_of_mac(SHAPE, 0.99)
    row = spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.1], own_shape=[True]).iloc[0]
    assert row["sv_peak_hz"] == pytest.approx(5.25, abs=0.05) and row["sv_mac"] == pytest.approx(0.99)


def test_a_prominent_peak_still_wins_and_keeps_its_prominence():
    spectrum = spectrum_with_shoulder(SHAPE, bump_db=12.0)
    row = spectral_support(spectrum, [5.0], SHAPE[:, None], damping=[0.01], own_shape=[False]).iloc[0]
    assert row["spectral_support"] and row["sv_prominence_db"] >= PEAK_PROMINENCE_DB


def test_own_shapes_compares_with_trusted_modes_only():
    a, b = np.array([1.0, 0.5, -0.2]), np.array([0.1, -0.3, 1.0])
    near_a = shape_of_mac(a, 0.85)  # a second estimate of a
    shapes = np.stack([a, b, near_a], axis=1)
    assert own_shapes(shapes, [True, True, True]).tolist() == [False, True, False]
    assert own_shapes(shapes, [False, True, True]).tolist() == [False, True, True]  # a doubtful: near_a its own
    assert own_shapes(shapes, [True, True, False]).tolist() == [True, True, False]
    assert own_shapes(shapes, [False, False, False]).tolist() == [True, True, True]  # a mode is not its own shadow
    assert own_shapes(shapes, np.array([1.0, 1.0, 0.0])).tolist() == [True, True, False]  # any truth values
    # the bound: a MAC of exactly mac_max is shared
    assert own_shapes(shapes, [True, True, True], mac_max=float(modal.mac(a[:, None], near_a[:, None])[0, 0])
                      ).tolist() == [False, True, False]
    with pytest.raises(ValueError, match="trusted"):
        own_shapes(shapes, [True, True])
    with pytest.raises(ValueError, match="own_shape"):
        spectral_support(spectrum_with_shoulder(SHAPE), [5.0], SHAPE[:, None], own_shape=[True, False])


def storey_frame_record(seed=1, minutes=10.0, fs=20.0, n=15, n_sensors=6):
    """A fifteen-storey shear frame (0.31-7.3 Hz), damping 0.8-3 %, white
    forces at every floor, six floors measured, 2 % noise: its modes above
    4 Hz lie 0.2-0.5 Hz apart with half-widths of 0.07-0.18 Hz."""
    rng = np.random.default_rng(seed)
    m, c, k = storey_frame(rng, n)
    sensors = sorted(rng.choice(n, n_sensors, replace=False))
    return simulate(m, c, k, sensors, 1 / fs, int(minutes * 60 * fs), rng, noise=0.02), fs


def test_a_storey_frames_overlapping_upper_modes_are_each_trusted_once():
    """Before: seven of its fifteen modes (4.3-6.2 Hz) flagged ``no
    spectral peak`` (SV peaks of 1.6-4.9 dB); now every mode below 0.8 of
    the Nyquist frequency is one trusted row within 1 %, and no trusted row
    is spurious."""
    (acc, f_true, _), fs = storey_frame_record()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result, _ = modal.identify_record(acc, 1 / fs, "ambient")
    trusted = result.trusted_modes["freq_hz"].to_numpy()
    expected = f_true[f_true < 0.8 * fs / 2]
    assert len(expected) == 15
    nearest = np.abs(trusted[:, None] / expected[None, :] - 1)
    assert np.all(nearest.min(axis=1) < 0.02)  # no spurious trusted row
    assert np.sum(nearest < 0.02, axis=0).tolist() == [1] * 15  # each mode once
    modes = result.modes[result.modes["flag"].fillna("") == ""]
    shoulders = modes[modes["sv_prominence_db"] < PEAK_PROMINENCE_DB]
    assert len(shoulders) >= 5 and (shoulders["sv_mac"] >= SHAPE_SUPPORT_MAC).all()


def test_a_direction_does_not_take_back_an_implausibly_high_damping():
    """The witness takes ``damping ... implausibly high`` back for a mode
    with a peak of its own; a shoulder's direction is not enough."""
    from modal.identification import DAMPED_ABOVE
    from modal.measured._pipeline import with_spectral_witness

    (acc, _, _), fs = storey_frame_record()
    details = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result, _ = modal.identify_record(acc, 1 / fs, "ambient", details=details)
    modes = result.modes
    shoulder = int(np.flatnonzero((modes["sv_prominence_db"] < PEAK_PROMINENCE_DB).to_numpy())[0])
    peak = int(np.flatnonzero((modes["sv_prominence_db"] >= PEAK_PROMINENCE_DB).to_numpy())[0])
    flags = modes["flag"].fillna("").to_numpy(dtype=object)
    for j in (shoulder, peak):
        flags[j] = f"{DAMPED_ABOVE} (test)"
    import dataclasses

    again = with_spectral_witness(dataclasses.replace(result, modes=modes.assign(flag=flags)), details["spectrum"])
    assert again.modes["flag"].iloc[shoulder].startswith(DAMPED_ABOVE)
    assert again.modes["flag"].iloc[peak] == ""


def two_modes(shape_2, flag_1="", flag_2="", damping_2=0.01):
    """A Stabilisation of two modes, as the witness reads it: mode 1 at
    2 Hz (shape ``SHAPE``, no peak in :func:`spectrum_with_shoulder`), mode
    2 at the shoulder's 5 Hz (``shape_2``), each with its selection flag."""
    from modal.identification._stabilisation import Stabilisation

    shapes = np.stack([SHAPE, shape_2], axis=1).astype(complex)
    modes = pd.DataFrame({"mode": [1, 2], "freq_hz": [2.0, 5.0], "damping": [0.01, damping_2], "n_poles": [20, 20],
                          "flag": [flag_1, flag_2]})
    return Stabilisation(modes, shapes.real, pd.DataFrame(), np.empty((0, 0)), np.empty(0), np.empty(0), np.empty(0),
                         complex_shapes=shapes)


def test_the_witness_asks_the_selections_trusted_modes_for_the_shape():
    """Mode 2's vector is its shape at the shoulder. Of MAC 0.85 with a
    trusted mode 1 it is that mode's second estimate: not supported; with
    mode 1 flagged by the selection (low MPC), or of a shape of its own, it
    is."""
    from modal.measured._pipeline import NO_SPECTRAL_PEAK, with_spectral_witness

    shadow = shape_of_mac(SHAPE, 0.85)
    flags = with_spectral_witness(two_modes(shadow), spectrum_with_shoulder(shadow)).modes["flag"].tolist()
    assert flags == [NO_SPECTRAL_PEAK, NO_SPECTRAL_PEAK]
    flags = with_spectral_witness(two_modes(shadow, flag_1="low MPC 0.50"), spectrum_with_shoulder(shadow)).modes
    assert flags["flag"].tolist() == [f"low MPC 0.50; {NO_SPECTRAL_PEAK}", ""]
    assert flags["sv_prominence_db"].iloc[1] < PEAK_PROMINENCE_DB
    own = shape_of_mac(SHAPE, 0.1)
    assert with_spectral_witness(two_modes(own), spectrum_with_shoulder(own)).modes["flag"].tolist() == [
        NO_SPECTRAL_PEAK, ""]


def test_a_free_decays_onset_spectrum_supports_by_direction_too():
    """No maximum near 5 Hz in the decay's spectrum (a bare slope); the
    onset spectrum's shoulder, of mode 2's shape, supports it."""
    from modal.measured._pipeline import NO_SPECTRAL_PEAK, with_spectral_witness

    own = shape_of_mac(SHAPE, 0.1)
    bare = spectrum_with_shoulder(own, bump_db=0.0)
    assert with_spectral_witness(two_modes(own), bare).modes["flag"].tolist() == [NO_SPECTRAL_PEAK] * 2
    witnessed = with_spectral_witness(two_modes(own), bare, onset=spectrum_with_shoulder(own)).modes
    assert witnessed["flag"].tolist() == [NO_SPECTRAL_PEAK, ""] and witnessed["sv_prominence_db"].iloc[1] < 6


def test_a_peak_of_exactly_the_bound_takes_an_implausible_damping_back(monkeypatch):
    """The bound of a peak of its own counts: with ``PEAK_PROMINENCE_DB``
    set to the very prominence of mode 2's peak, its ``implausibly high``
    is taken back; a hair above, it is not."""
    import modal.identification
    from modal.identification import DAMPED_ABOVE
    from modal.measured._pipeline import with_spectral_witness

    own = shape_of_mac(SHAPE, 0.1)
    spectrum = spectrum_with_shoulder(own, bump_db=12.0)
    high = f"damping 8 % {DAMPED_ABOVE} (median 1 %)"
    exact = with_spectral_witness(two_modes(own, flag_2=high), spectrum).modes["sv_prominence_db"].iloc[1]
    assert exact > PEAK_PROMINENCE_DB
    monkeypatch.setattr(modal.identification, "PEAK_PROMINENCE_DB", exact)
    assert with_spectral_witness(two_modes(own, flag_2=high), spectrum).modes["flag"].iloc[1] == ""
    monkeypatch.setattr(modal.identification, "PEAK_PROMINENCE_DB", np.nextafter(exact, np.inf))
    assert with_spectral_witness(two_modes(own, flag_2=high), spectrum).modes["flag"].iloc[1] == high


def test_the_report_tells_a_shoulder_from_a_peak():
    """``evidence`` (the report's sentence per mode): below 6 dB the
    support is a shoulder of the mode's own shape, at 6 dB a peak."""
    from modal.measured._report import evidence

    row = {"mode": 1, "freq_hz": 5.0, "n_poles": 20, "spectral_support": True, "sv_number": 2, "sv_peak_hz": 5.1,
           "sv_mac": 0.97, "efdd_freq_hz": 5.05, "efdd_damping": 0.02, "flag": ""}
    shoulder, peak = evidence(pd.DataFrame([{**row, "sv_prominence_db": 3.04}, {**row, "sv_prominence_db": 6.0}]), 30)
    assert "a shoulder of the second singular value at 5.1 Hz (3.0 dB, under the 6 dB of a peak" in shoulder
    assert "(MAC 0.97) and no other trusted mode's, that shoulder's EFDD cross-check 5.05 Hz" in shoulder
    assert "a peak of the second singular value at 5.1 Hz (shape MAC 0.97" in peak and "shoulder" not in peak
