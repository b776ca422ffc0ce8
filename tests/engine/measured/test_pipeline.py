"""identify_record: the measured-record pipeline behind `modal identify`
(preprocessing, NExT correlations or the free decay, the diagram), on the
ambient beam, a closed-form free decay and the Palisaden record."""

import re
import warnings

import numpy as np
import pandas as pd
import pytest

import modal

from ..cases import BEAM, DAMPING, PALISADEN, PALISADEN_MODES_HZ, SENSORS_X, ambient_beam

def test_ambient_beam_frequencies_and_damping_from_stabilisation():
    acc, dt, f_exact = ambient_beam()
    result, _ = modal.identify_record(acc, dt, "ambient", max_order=40, fmax=f_exact[2] * 1.3)
    f = result.modes["freq_hz"].to_numpy()
    assert len(f) == 3
    np.testing.assert_allclose(f, f_exact, rtol=0.005)
    # Damping from 400 s of white noise: a 25 % statistical tolerance.
    np.testing.assert_allclose(result.modes["damping"], DAMPING, rtol=0.25)
    shapes_exact = BEAM.mode_shapes(SENSORS_X, 3)
    assert np.all(np.diag(modal.mac(result.shapes, shapes_exact)) > 0.99)


def test_free_decay_closed_form_with_decay_start():
    """Damped cosines after 300 samples of noise: decay_start finds the
    impact and the stabilisation the exact poles."""
    dt = 1 / 500
    f_exact, zeta = np.array([7.3, 31.0, 64.0]), np.array([0.004, 0.01, 0.02])
    shapes = BEAM.mode_shapes(SENSORS_X[:3], 3)
    t = dt * np.arange(4000)
    modal_decay = np.exp(-zeta * 2 * np.pi * f_exact * t[:, None]) * np.cos(
        2 * np.pi * f_exact * np.sqrt(1 - zeta**2) * t[:, None])
    rng = np.random.default_rng(4)
    acc = np.vstack([np.zeros((300, 3)), modal_decay @ shapes.T]) + 1e-4 * rng.standard_normal((4300, 3))
    assert modal.decay_start(acc) == 300
    result, _ = modal.identify_record(acc, dt, "free_decay", max_order=30, rows=60)
    np.testing.assert_allclose(result.modes["freq_hz"], f_exact, rtol=1e-3)
    np.testing.assert_allclose(result.modes["damping"], zeta, rtol=0.05)


@pytest.mark.slow
def test_palisaden_three_modes_within_half_a_percent():
    acc, dt = modal.load_record(PALISADEN, fs=20)
    result, _ = modal.identify_record(acc, dt, "ambient", max_order=60, fmax=5, highpass_hz=0.5)
    f = result.modes["freq_hz"].to_numpy()
    for published in PALISADEN_MODES_HZ:
        assert np.min(np.abs(f - published)) / published < 0.005
    assert np.all(result.modes["damping"].between(0.005, 0.05))


def _run(call, *args, **kwargs):
    """``call(*args, **kwargs)`` and the messages of the ModalWarnings it issued
    (random records give diagrams with few or no modes, which warn)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = call(*args, **kwargs)
    assert all(issubclass(w.category, modal.ModalWarning) for w in caught), [str(w.message) for w in caught]
    return out, [str(w.message) for w in caught]


def _same_diagram(got, expected, ambient=True):
    """identify_record's diagram and warnings equal those of modal.stabilisation called on ``expected`` data
    (``ambient``: the record's modes also carry the harmonic check's columns)."""
    (result, dt), got_warnings = got
    reference, expected_warnings = expected
    assert got_warnings == expected_warnings
    pd.testing.assert_frame_equal(result.poles, reference.poles, rtol=1e-9)
    # identify_record adds the spectral witness's columns (modal.spectral_support) to the diagram's modes, and of
    # an ambient record the harmonic check's (modal.identification.envelope_variation)
    assert list(result.modes.columns) == [*reference.modes.columns, "sv_peak_hz", "sv_number", "sv_mac",
                                          "sv_prominence_db", "spectral_support", "efdd_freq_hz", "efdd_damping",
                                          *(["envelope_cv", "envelope_values"] if ambient else [])]
    # the uncertainty columns come from the record's segments, which identify_record cuts and a bare
    # stabilisation call does not get (tests/engine/measured/test_uncertainty.py covers them)
    same = [c for c in reference.modes.columns if c not in ("freq_std_hz", "damping_std", "flag")]
    pd.testing.assert_frame_equal(result.modes[same], reference.modes[same], rtol=1e-9)
    # the witness adds its reasons to the selection's flag, nothing else
    for flag, selection in zip(result.modes["flag"], reference.modes["flag"]):
        added = [r for r in flag.split("; ") if r and r not in selection.split("; ")]
        assert flag.startswith(selection) and all(r == "no spectral peak" or r.startswith("same spectral peak as ")
                                                  or (ambient and r.startswith("harmonic (envelope CV "))
                                                  for r in added), (flag, selection)
    np.testing.assert_allclose(result.singular_values, reference.singular_values, rtol=1e-10)
    return dt


UNBIASED = "unbiased"  # identify_record's correlations: the biased taper adds 1 / (omega T) to the damping


@pytest.mark.slow
def test_identify_record_ambient_preprocessing():
    """Ambient: detrend, decimate by floor(fs / (2.5 fmax)) when that is at
    least 2, high-pass, then NExT correlations with 2 rows + 1 lags from the
    chosen references (the unbiased estimator); rows default to max(60, ceil(2 max_order / n_channels)).
    The diagram is the stabilisation of exactly those correlations (of the
    detrended record divided by the power of two nearest its peak)."""

    def detrended(y):
        y = modal.detrend(y)
        return y / 2.0 ** np.frexp(np.abs(y).max())[1]

    rng = np.random.default_rng(8)
    acc = rng.standard_normal((3000, 3)) + 0.01 * np.arange(3000)[:, None]
    criteria, calls = modal.StabilityCriteria(min_poles=4), []
    # fs = 100 Hz, fmax = 15 Hz: q = floor(100 / 37.5) = 2
    got = _run(modal.identify_record, acc, 0.01, "ambient", max_order=10, fmax=15.0, refs=[1], highpass_hz=0.5,
               criteria=criteria, progress=lambda done, total: calls.append((done, total)))
    y, dt = modal.decimate(detrended(acc), 0.01, 2)
    data = modal.correlations(modal.zero_phase_filter(y, dt, highpass_hz=0.5), 121, refs=[1], estimator=UNBIASED)
    assert _same_diagram(got, _run(modal.stabilisation, data, 0.02, 10, 60, fmax=15.0, criteria=criteria)) == 0.02
    assert calls == [(i, 5) for i in range(1, 6)]  # orders 2 ... 10

    # fmax = 30 Hz: q = floor(100 / 75) = 1, no decimation; 2 * 100 / 3 channels: 67 rows, 135 lags
    got = _run(modal.identify_record, acc, 0.01, "ambient", max_order=100, fmax=30.0)
    expected = _run(modal.stabilisation, modal.correlations(detrended(acc), 135, estimator=UNBIASED), 0.01, 100, 67, fmax=30.0)
    assert _same_diagram(got, expected) == 0.01
    # the defaults: orders up to 60, 60 rows, 121 lags from every channel
    got = _run(modal.identify_record, acc, 0.01, "ambient")
    assert _same_diagram(got, _run(modal.stabilisation, modal.correlations(detrended(acc), 121, estimator=UNBIASED), 0.01, 60, 60)) == 0.01
    # the lags may fill half the record: 151 of 302 samples (751 of 1502), not 153 (753)
    got = _run(modal.identify_record, acc[:302], 0.01, "ambient", rows=75)
    expected = _run(modal.stabilisation, modal.correlations(detrended(acc[:302]), 151, estimator=UNBIASED), 0.01, 60, 75)
    assert _same_diagram(got, expected) == 0.01
    with pytest.raises(ValueError, match="^rows = 376 needs 753 lags, more than half the 1502-sample record"):
        modal.identify_record(acc[:1502], 0.01, "ambient", rows=376)
    with pytest.raises(ValueError, match="^rows = 76 needs 153 lags, more than half the 302-sample record"):
        modal.identify_record(acc[:302], 0.01, "ambient", rows=76)


def test_identify_record_free_decay_window():
    """Free decay: the record from decay_start on, at most 10 rows columns
    (fewer when the decay is shorter), down to a single column."""
    rng = np.random.default_rng(9)
    k = np.arange(800)
    decay = 0.995**k[:, None] * np.cos(np.array([0.2, 0.35]) * k[:, None])
    acc = np.vstack([0.01 * rng.standard_normal((200, 2)), decay])
    start = modal.decay_start(modal.detrend(acc))
    assert start == 200
    for rows, cols in ((50, 500), (80, 720)):
        got = _run(modal.identify_record, acc, 0.01, "free_decay", rows=rows)
        expected = _run(modal.stabilisation, modal.detrend(acc), 0.01, 60, rows, cols=cols, start=200)
        assert _same_diagram(got, expected, ambient=False) == 0.01
    # 799 rows leave one column: H(0) is 1598 x 1, too small for any order
    with pytest.raises(ValueError, match=r"^max_order = 2 exceeds the smaller dimension of H\(0\) \(1598 x 1\)"):
        modal.identify_record(acc, 0.01, "free_decay", rows=799, max_order=2)
    with pytest.raises(ValueError, match="^rows = 800: the decay after sample 200 is too short; reduce rows$"):
        modal.identify_record(acc, 0.01, "free_decay", rows=800)


def test_identify_record_refusals_name_the_argument():
    acc = np.random.default_rng(10).standard_normal((1000, 2))
    for kwargs, message in [({"dt": 0.0}, "^dt must"), ({"max_order": 1}, "^max_order must be at least 2"),
                            ({"rows": 0}, "^rows must"), ({"fmax": 0.0}, "^fmax must"),
                            ({"fmax": 50.0}, r"^fmax = 50 Hz must be below the Nyquist frequency 50 Hz \(fs = 100 Hz\)$")]:
        with pytest.raises(ValueError, match=message):
            modal.identify_record(acc, **({"dt": 0.01, "excitation": "ambient", "rows": 20} | kwargs))
    (result, dt), _ = _run(modal.identify_record, acc, 0.01, "ambient", max_order=2, rows=20, fmax=49.9)
    assert dt == 0.01 and set(result.poles["order"]) <= {2}
    assert re.match(r"\d+ poles at one model order \(2\): stability is judged between consecutive orders, .*raise "
                    r"--max-order", result.no_mode_reason())
    # an fmax that decimates the record below what the lags need: the lowest fmax the record allows is named
    with pytest.raises(ValueError, match=r"^fmax = 0.5 Hz decimates the 1000-sample record by 80 to 12 samples, fewer "
                                         r"than the 242 the identification needs \(60 rows: 121 lags\): fmax must be "
                                         r"above 8 Hz for this record \(or give a longer record\)$"):
        modal.identify_record(acc, 0.01, "ambient", fmax=0.5)
    _run(modal.identify_record, acc, 0.01, "ambient", fmax=8.01, max_order=4)  # 250 samples: enough
    # channels first (the reader's layout check, also in the API), and fs given twice, unalike
    with pytest.raises(ValueError, match=r"^acc of shape \(2, 1000\) reads as 2 samples of 1000 channels; .*acc\.T"):
        modal.identify_record(acc.T, 0.01, "ambient")
    with pytest.raises(ValueError, match=r"^options.fs = 50 Hz contradicts dt = 0.01 s \(100 Hz\)"):
        modal.identify_record(acc, 0.01, modal.IdentifyOptions(excitation="ambient", fs=50.0, rows=20))
    (result, dt), _ = _run(modal.identify_record, acc, 0.01, modal.IdentifyOptions(
        excitation="ambient", fs=100.0, rows=20, max_order=2, fmax=49.9))
    assert dt == 0.01


def test_spectral_witness_compares_shapes_in_each_channels_quantity():
    """Channel 0 an acceleration, channel 1 a velocity (a 2-DOF system,
    modes 0.71 and 1.35 Hz): the shape comes out in channel 0's quantity,
    the spectrum holds each channel's own, so the witness multiplies the
    velocity entry back by the pole before the MAC with the singular
    vector: 0.99999 at 1.35 Hz (0.86 without)."""
    import scipy.signal

    m, k = np.diag([1.0, 1.5]), np.array([[60.0, -25.0], [-25.0, 45.0]])
    m_inv, c = np.linalg.inv(m), 0.01 * k + 0.02 * m
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-m_inv @ k, -m_inv @ c]])
    b = np.vstack([np.zeros((2, 2)), m_inv])
    outputs = np.vstack([np.hstack([-m_inv @ k, -m_inv @ c])[0], [0.0, 0.0, 0.0, 1.0]])  # acc of DOF 0, vel of DOF 1
    system = scipy.signal.cont2discrete((a, b, outputs, np.vstack([m_inv[0], [0.0, 0.0]])), 0.05)
    _, y, _ = scipy.signal.dlsim(system[:4] + (0.05,), np.random.default_rng(0).standard_normal((2**15, 2)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        result, _ = modal.identify_record(y, 0.05, "ambient", quantities=["acceleration", "velocity"], fmax=2.5,
                                          max_order=8)
    modes = result.modes
    upper = modes.iloc[int(np.argmin(np.abs(modes["freq_hz"] - 1.3455)))]
    assert upper["freq_hz"] == pytest.approx(1.3455, rel=0.01)
    assert upper["spectral_support"] and upper["sv_mac"] > 0.999


def _one_peak_spectrum(freq_hz, vector, df=0.05, zeta=0.02, n_freq=400):
    """A singular-value spectrum with one peak, a half-power bell of
    damping ``zeta`` at ``freq_hz``, whose first singular vector is
    ``vector`` at every frequency (the second far below)."""
    f = df * np.arange(n_freq)
    bell = 1 / ((1 - (f / freq_hz) ** 2) ** 2 + (2 * zeta * f / freq_hz) ** 2)
    values = np.column_stack([bell, 1e-6 * np.ones(n_freq)])
    vector = np.asarray(vector, dtype=complex) / np.linalg.norm(vector)
    other = np.linalg.svd(vector[None, :].conj())[2][1].conj()  # a unit vector orthogonal to it
    vectors = np.stack([np.tile(vector, (n_freq, 1)), np.tile(other, (n_freq, 1))], axis=2)
    return modal.SingularValueSpectrum(f, values, vectors, nperseg=int(round(1 / (df * 0.01))))


def _one_mode(freq_hz, damping, shape, index=(0,), flag=None):
    """A Stabilisation of one mode (only what the witness reads)."""
    from modal.identification._stabilisation import Stabilisation

    modes = pd.DataFrame({"mode": [1], "freq_hz": [freq_hz], "damping": [damping], "n_poles": [20]}, index=list(index))
    if flag is not None:
        modes["flag"] = [flag]
    shape = np.asarray(shape, dtype=complex)[:, None]
    return Stabilisation(modes, shape.real, pd.DataFrame(), np.empty((0, 0)), np.empty(0), np.empty(0), np.empty(0),
                         complex_shapes=shape)


def test_the_witness_carries_each_entry_into_its_channels_quantity_by_the_damped_pole():
    """A mode of 8 % damping at 4 Hz, shape ``phi`` in the first channel's
    quantity (a velocity), the channels velocity, displacement and
    acceleration: the spectrum's vector is ``phi_c s^(k_c - k_0)`` with
    ``s = 2 pi f (-zeta + i sqrt(1 - zeta^2))``, so the MAC is 1 to
    round-off; the undamped pole's phase or another magnitude would not
    give it (MAC 0.9939 with ``+zeta``). The witness's columns come last,
    a modes table's own index is kept, and a table without ``flag`` gets
    none."""
    f, zeta = 4.0, 0.08
    phi = np.array([1.0, 0.5 - 0.2j, -0.7 + 0.1j])
    s = 2 * np.pi * f * (-zeta + 1j * np.sqrt(1 - zeta**2))
    spectrum = _one_peak_spectrum(f, phi * s ** np.array([0, -1, 1]))
    witnessed = modal.measured.with_spectral_witness(_one_mode(f, zeta, phi, index=(7,)), spectrum,
                                                     quantities=["velocity", "displacement", "acceleration"])
    modes = witnessed.modes
    assert modes.index.tolist() == [7] and "flag" not in modes
    assert modes.columns.tolist()[-7:] == ["sv_peak_hz", "sv_number", "sv_mac", "sv_prominence_db",
                                           "spectral_support", "efdd_freq_hz", "efdd_damping"]
    assert bool(modes["spectral_support"].iloc[0]) and modes["sv_number"].iloc[0] == 1
    assert modes["sv_mac"].iloc[0] == pytest.approx(1.0, abs=1e-12)
    undamped_phase = phi * np.conj(s) ** np.array([0, -1, 1]) * -1
    assert modal.mac(undamped_phase[:, None], (phi * s ** np.array([0, -1, 1]))[:, None])[0, 0] < 0.995


def test_a_free_decays_onset_spectrum_supports_a_mode_within_its_half_power_band():
    """A mode the record's spectrum has no peak for (its peak lies at 10 Hz,
    the mode at 4 Hz) is judged on the onset spectrum: there a peak 0.15 Hz
    (3 bins) away supports it when its damping of 5 % (half-width 0.2 Hz)
    is taken into the tolerance, and not at two bins without it; its flag
    keeps its other reasons and no ``no spectral peak``."""
    phi = np.array([1.0, -0.4, 0.8])
    record = _one_peak_spectrum(10.0, phi)
    onset = _one_peak_spectrum(4.15, phi, zeta=0.05)
    witnessed = modal.measured.with_spectral_witness(_one_mode(4.0, 0.05, phi, index=(3,), flag="low MAMC 0.90"),
                                                     record, onset=onset)
    assert witnessed.modes.index.tolist() == [3]
    assert bool(witnessed.modes["spectral_support"].iloc[0])
    assert witnessed.modes["sv_peak_hz"].iloc[0] == pytest.approx(4.15, abs=0.05)
    assert witnessed.modes["flag"].iloc[0] == "low MAMC 0.90"
    alone = modal.measured.with_spectral_witness(_one_mode(4.0, 0.05, phi, flag="low MAMC 0.90"), record)
    assert alone.modes["flag"].iloc[0] == "low MAMC 0.90; no spectral peak"


def test_the_onset_spectrums_first_window_peaks_at_the_impact():
    """An impulse (a decay that is over at once) weighs most in Welch's
    average where a Hann window is at its peak, the middle of a segment:
    of the impulse placed at every sample of the first two segments of a
    record as long as the padded decay, the onset spectrum's level is the
    highest (the impulse at sample ``nperseg // 2``), in segments of the
    ``nperseg`` asked, flat over frequency above the lowest bins."""
    from modal.measured import onset_spectrum

    nperseg, dt = 64, 0.01
    decay = np.zeros((4000, 1))  # fdd's own segments would be longer
    decay[0] = 1.0
    onset = onset_spectrum(decay, dt, nperseg)
    assert onset.nperseg == nperseg and len(onset.freq_hz) == nperseg // 2 + 1
    np.testing.assert_allclose(onset.values[3:-1, 0], onset.values[3, 0], rtol=1e-9)  # not DC, its neighbours, Nyquist
    levels = []
    for k in range(2 * nperseg):
        record = np.zeros((4000 + nperseg // 2, 1))
        record[k] = 1.0
        levels.append(modal.fdd(record, dt, nperseg=nperseg).values[5, 0])
    assert int(np.argmax(levels)) == nperseg // 2
    assert onset.values[5, 0] == pytest.approx(max(levels), rel=1e-9)


def test_no_vibration_judges_each_channel_against_its_largest_magnitude():
    """A channel's content after detrending is judged against its largest
    magnitude, negative values included: a vibration of 1e-12 on an offset
    of -1 is round-off (below 1e-10 of 1); the same on +1, and a constant
    and a ramp, too; a vibration of 1e-9 on -1 is not, nor white noise."""
    from modal.measured import no_vibration

    t = np.arange(2000)
    wave = np.sin(0.3 * t)
    raw = np.column_stack([-1 + 1e-12 * wave, 1 + 1e-12 * wave, np.full(len(t), -5.0), 3e-3 * t - 2,
                           -1 + 1e-9 * wave, np.random.default_rng(0).standard_normal(len(t))])
    assert no_vibration(raw, modal.detrend(raw)).tolist() == [0, 1, 2, 3]


def test_a_second_mode_on_the_first_ones_peak_and_shape_is_named_so():
    """The beam's three modes with a copy of its first mode added 0.3
    half-widths above it with fewer poles: the witness finds both on one
    peak of one shape and names the copy ``same spectral peak as <first>``;
    the real modes keep their flags. Where the selection already named the
    copy ``same shape as ...``, that reason stays alone."""
    import dataclasses

    acc, dt, f_exact = ambient_beam()
    details = {}
    result, _ = modal.identify_record(acc, dt, "ambient", max_order=40, fmax=f_exact[2] * 1.3, details=details)
    modes = result.modes
    copy = modes.iloc[[0]].assign(mode=4, n_poles=int(modes["n_poles"].iloc[0]) - 5,
                                  freq_hz=modes["freq_hz"].iloc[0] * (1 + 0.3 * modes["damping"].iloc[0]))
    doubled = dataclasses.replace(result, modes=pd.concat([modes, copy], ignore_index=True),
                                  shapes=np.column_stack([result.shapes, result.shapes[:, 0]]),
                                  complex_shapes=np.column_stack([result.complex_shapes, result.complex_shapes[:, 0]]))
    bare = doubled.modes.drop(columns=[c for c in doubled.modes.columns if c.startswith("sv_") or c.startswith("efdd")
                                       or c == "spectral_support"])
    witnessed = modal.measured.with_spectral_witness(dataclasses.replace(doubled, modes=bare), details["spectrum"])
    first = f"{modes['freq_hz'].iloc[0]:.4g}"
    assert witnessed.modes["sv_peak_hz"].iloc[3] == witnessed.modes["sv_peak_hz"].iloc[0]
    assert list(witnessed.modes["flag"]) == list(modes["flag"]) + [f"same spectral peak as {first} Hz (MAC 1.000)"]
    again = modal.measured.with_spectral_witness(witnessed, details["spectrum"])  # a second witness as the first
    assert again.modes["flag"].tolist() == witnessed.modes["flag"].tolist()
    shadow = bare.assign(flag=list(modes["flag"]) + [f"same shape as {first} Hz (MAC 1.000)"])
    witnessed = modal.measured.with_spectral_witness(dataclasses.replace(doubled, modes=shadow), details["spectrum"])
    assert witnessed.modes["flag"].iloc[3] == f"same shape as {first} Hz (MAC 1.000)"
    # the first mode flagged for another reason: the trusted copy keeps the peak, the resonance a trusted row
    doubtful = bare.assign(flag=["damping 0.05 % implausibly low (median 1 %)"] + list(modes["flag"].iloc[1:]) + [""])
    witnessed = modal.measured.with_spectral_witness(dataclasses.replace(doubled, modes=doubtful), details["spectrum"])
    copied = f"{copy['freq_hz'].iloc[0]:.4g}"
    assert witnessed.modes["flag"].iloc[3] == ""
    assert witnessed.modes["flag"].iloc[0].startswith("damping 0.05 % implausibly low (median 1 %)")
    assert f"same spectral peak as {copied} Hz (MAC 1.000)" in witnessed.modes["flag"].iloc[0]


@pytest.mark.parametrize("alike, named", [(0.85, True), (0.5, False)])
def test_a_weaker_estimate_of_a_peaks_shape_within_mac_0_8_is_named_its_second(alike, named):
    """Two modes on one peak of the first singular value (at 4 Hz, vector
    ``a``): the stronger (20 poles, at the peak) has shape ``a``, the weaker
    (10 poles, 4.03 Hz, twice the damping) a shape of MAC ``alike`` with
    it. At 0.85 (as the weaker estimates beside a frame's and a chain's mode
    in ``bench_selection``, 0.89 and 0.90) the weaker is the stronger's
    second estimate; at 0.5 it has a shape of its own (a close mode) and
    stays."""
    from modal.identification._stabilisation import Stabilisation

    a = np.array([1.0, 0.5, -0.7]) / np.linalg.norm([1.0, 0.5, -0.7])
    u = np.array([0.5, -1.0, 0.0]) / np.linalg.norm([0.5, -1.0, 0.0])  # orthogonal to a
    theta = np.arccos(np.sqrt(alike))
    b = a * np.cos(theta) + u * np.sin(theta)
    shapes = np.column_stack([a, b]).astype(complex)
    modes = pd.DataFrame({"mode": [1, 2], "freq_hz": [4.0, 4.03], "damping": [0.02, 0.04], "n_poles": [20, 10],
                          "flag": ["", ""]})
    result = Stabilisation(modes, shapes.real, pd.DataFrame(), np.empty((0, 0)), np.empty(0), np.empty(0),
                           np.empty(0), complex_shapes=shapes)
    witnessed = modal.measured.with_spectral_witness(result, _one_peak_spectrum(4.0, a))
    assert witnessed.modes["spectral_support"].tolist() == [True, True]
    assert witnessed.modes["sv_mac"].iloc[1] == pytest.approx(alike, abs=1e-9)
    assert witnessed.modes["flag"].tolist() == ["", f"same spectral peak as 4 Hz (MAC {alike:.3f})" if named else ""]


def test_a_heavily_damped_mode_with_its_own_peak_is_trusted():
    """The beam's three modes damped 1, 8 and 1.2 %: the second lies more
    than ``damping_factor`` = 5 times above the record's median damping,
    but its broad resonance is a peak of the singular values of its own, so
    it is trusted, at its damping (EFDD agrees); the others too."""
    from ..cases import _foh_acceleration

    omega, shapes, zeta, dt = BEAM.natural_frequencies(3), BEAM.mode_shapes(SENSORS_X, 3), [0.01, 0.08, 0.012], 0.01
    force = np.random.default_rng(1).standard_normal((40000, 3))
    acc = np.column_stack([_foh_acceleration(w, z, f, dt) for w, z, f in zip(omega, zeta, force.T)]) @ shapes.T
    result, _ = modal.identify_record(acc, dt, "ambient", max_order=40, fmax=omega[2] / (2 * np.pi) * 1.3)
    modes = result.modes
    assert modes["flag"].tolist() == ["", "", ""]
    np.testing.assert_allclose(modes["freq_hz"], omega / (2 * np.pi), rtol=0.005)
    np.testing.assert_allclose(modes["damping"], zeta, rtol=0.25)
    assert modes["damping"].iloc[1] > modal.StabilityCriteria().damping_factor * np.median(modes["damping"])
    np.testing.assert_allclose(modes["efdd_damping"].iloc[1], zeta[1], rtol=0.25)


def test_a_mode_with_a_peak_of_its_own_keeps_no_implausibly_high_damping():
    """The witness takes ``damping ... implausibly high`` back from a mode
    with a singular-value peak of its own (a heavily damped real mode) and
    from no other: a mode between the beam's first two, where the spectrum
    has no peak, keeps it; an implausibly low damping stays (a harmonic's
    peak is sharp); other reasons stay. A mode so cleared is trusted, so it
    keeps its peak over a copy of its shape that is farther from it; the
    notes say which and why (mode 1's unchanged before the others')."""
    import dataclasses

    from modal.identification import doubtful_note

    acc, dt, f_exact = ambient_beam()
    details = {}
    result, _ = modal.identify_record(acc, dt, "ambient", max_order=40, fmax=f_exact[2] * 1.3, details=details)
    modes = result.modes
    high, low = "damping 6 % implausibly high (median 1 %)", "damping 0.05 % implausibly low (median 1 %)"
    between = modes.iloc[[0]].assign(mode=4, freq_hz=np.sqrt(f_exact[0] * f_exact[1]), damping=0.01)
    four = dataclasses.replace(result, modes=pd.concat([modes, between], ignore_index=True),
                               shapes=np.column_stack([result.shapes, result.shapes[:, 0]]),
                               complex_shapes=np.column_stack([result.complex_shapes, result.complex_shapes[:, 0]]))
    bare = four.modes.drop(columns=[c for c in four.modes.columns if c.startswith("sv_") or c.startswith("efdd")
                                    or c == "spectral_support"])
    flags = [low, f"low MPC 0.50; {high}; low MAMC 0.90", high, high]
    said = tuple(doubtful_note(n, f, flag) for n, f, flag in zip(bare["mode"], bare["freq_hz"], flags)) + ("other",)
    flagged = dataclasses.replace(four, modes=bare.assign(flag=flags), notes=said)
    witnessed = modal.measured.with_spectral_witness(flagged, details["spectrum"])
    assert witnessed.modes["spectral_support"].tolist() == [True, True, True, False]
    assert witnessed.modes["flag"].tolist() == [low, "low MPC 0.50; low MAMC 0.90", "", f"{high}; no spectral peak"]
    again = modal.measured.with_spectral_witness(witnessed, details["spectrum"])  # each reason once, notes as they were
    assert again.modes["flag"].tolist() == witnessed.modes["flag"].tolist() and again.notes == witnessed.notes
    # the log and the report say so: mode 3 trusted for its peak, mode 2 doubtful for what is left, the rest as said
    peak = witnessed.modes["sv_peak_hz"].iloc[2]
    assert witnessed.notes == (said[0], doubtful_note(2, bare["freq_hz"].iloc[1], "low MPC 0.50; low MAMC 0.90"),
                               f"mode 3 ({bare['freq_hz'].iloc[2]:.4g} Hz): its damping "
                               f"{100 * bare['damping'].iloc[2]:.2g} % lies above the record's other modes', but its "
                               f"own singular-value peak at {peak:.4g} Hz vouches for it (a heavily damped mode: "
                               "trusted)") + said[3:]
    # the first mode cleared of its damping is trusted: it keeps its peak over a farther copy of its shape
    copy = modes.iloc[[0]].assign(mode=4, n_poles=int(modes["n_poles"].iloc[0]) + 5,
                                  freq_hz=modes["freq_hz"].iloc[0] * (1 + 0.3 * modes["damping"].iloc[0]))
    doubled = dataclasses.replace(four, modes=pd.concat([bare.iloc[:3], copy[bare.columns]], ignore_index=True))
    doubled = dataclasses.replace(doubled, modes=doubled.modes.assign(flag=[high, "", "", ""]))
    witnessed = modal.measured.with_spectral_witness(doubled, details["spectrum"])
    assert witnessed.modes["flag"].iloc[0] == ""
    assert witnessed.modes["flag"].iloc[3].startswith(f"same spectral peak as {modes['freq_hz'].iloc[0]:.4g} Hz")


def test_a_mode_that_decays_within_a_welch_segment_has_its_peak_in_a_free_decay():
    """A free decay at 12.8 kHz, three channels, of 182, 515 and 2270 Hz
    (damped 0.3, 0.4, 0.6 %: the last lasts some 150 samples, a Welch segment
    of the 1.5 s record holds 2048). Welch's first Hann segment starts at the
    impact and tapers the 2270 Hz mode away, so the record's own spectrum
    has no peak for it; the spectrum with its first segment centred on the
    impact has, and the mode is trusted. The slow modes keep the peaks of the
    record's own spectrum, and the noise mode the selection also finds
    (6220 Hz) has a peak in neither."""
    fs, n, start = 12800.0, 19200, 640
    freq_hz, zeta = np.array([182.0, 515.0, 2270.0]), np.array([0.003, 0.004, 0.006])
    shapes = np.array([[1.0, 0.9, -0.7], [0.8, -0.4, 0.9], [0.5, -1.0, 0.6]])
    t = np.arange(n - start) / fs
    omega = 2 * np.pi * freq_hz
    q = np.exp(-zeta * omega * t[:, None]) * np.cos(omega * np.sqrt(1 - zeta**2) * t[:, None])
    y = np.zeros((n, 3))
    y[start:] = q * np.array([1.0, 0.5, 0.2]) @ shapes.T
    y += 0.005 * np.random.default_rng(3).standard_normal(y.shape)
    details = {}
    result, dt = modal.identify_record(y, 1 / fs, "free_decay", details=details)
    modes = result.modes
    nearest = [int(np.argmin(np.abs(modes["freq_hz"].to_numpy() - f))) for f in freq_hz]
    np.testing.assert_allclose(modes["freq_hz"].to_numpy()[nearest], freq_hz, rtol=1e-3)
    assert list(modes["flag"].iloc[nearest]) == ["", "", ""]
    assert modes["spectral_support"].iloc[nearest].all()
    plain = modal.spectral_support(details["spectrum"], modes["freq_hz"].iloc[nearest[:2]],
                                   result.complex_shapes[:, nearest[:2]], damping=modes["damping"].iloc[nearest[:2]])
    assert not modal.spectral_support(details["spectrum"], modes["freq_hz"].iloc[nearest[2:]],
                                      result.complex_shapes[:, nearest[2:]],
                                      damping=modes["damping"].iloc[nearest[2:]])["spectral_support"].any()
    np.testing.assert_array_equal(modes["sv_peak_hz"].iloc[nearest[:2]].to_numpy(), plain["sv_peak_hz"].to_numpy())
    others = modes.drop(index=modes.index[nearest])
    assert len(others) and others["flag"].str.contains("no spectral peak").all()  # a noise mode finds no peak either


def _mixed_quantities_record(seed=0, n=2**15, dt=0.05):
    """Ambient response of a three-mass chain (0.44, 1.15, 1.68 Hz) under
    white forces: channels 0 and 1 the accelerations of masses 0 and 1,
    channels 2 and 3 the velocities of masses 2 and 1 (exact ZOH)."""
    import scipy.signal

    m, k = np.diag([1.0, 1.2, 0.9]), np.array([[80.0, -40.0, 0.0], [-40.0, 70.0, -30.0], [0.0, -30.0, 30.0]])
    m_inv = np.linalg.inv(m)
    c = 0.004 * k + 0.01 * m
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-m_inv @ k, -m_inv @ c]])
    acc = np.hstack([-m_inv @ k, -m_inv @ c])
    outputs = np.vstack([acc[0], acc[1], np.eye(6)[5], np.eye(6)[4]])
    feed = np.vstack([m_inv[0], m_inv[1], np.zeros(3), np.zeros(3)])
    system = scipy.signal.cont2discrete((a, np.vstack([np.zeros((3, 3)), m_inv]), outputs, feed), dt)
    _, y, _ = scipy.signal.dlsim(system[:4] + (dt,), np.random.default_rng(seed).standard_normal((n, 3)))
    return y, dt


def test_velocities_among_accelerations_taken_as_one_quantity_draw_a_warning():
    """Two velocity channels among accelerations, no quantities given: the
    warning names the groups (channel 2 is too weak in two of the modes to
    be placed) and the low-MPC flag it explains; quantities all
    ``acceleration`` (one quantity) warn the same, and so do quantities
    that name the wrong channels velocities; each channel's own quantity
    gives normal shapes (MPC 0.999+) and no warning. The velocities
    10^4 times weaker (scaled up for the identification: MPC high) still
    draw it, without a low-MPC flag to explain."""
    import re

    y, dt = _mixed_quantities_record()

    def run(quantities):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result, _ = modal.identify_record(y, dt, "ambient", quantities=quantities)
        return result.modes, [str(w.message) for w in caught if "quarter period" in str(w.message)]

    modes, said = run(None)
    assert len(said) == 1
    assert re.match(r"channels 0, 1 and channels (2, )?3 are a quarter period apart in every mode both show "
                    r"\(8[5-9]\.\d degrees, median over up to \d modes\)", said[0]), said[0]
    low = modes["mpc"][modes["mpc"] < 0.7]
    assert len(low) == 1 and f"1 mode(s) read as complex and are flagged low MPC ({low.iloc[0]:.2f}-" in said[0]
    assert run(["acceleration"] * 4)[1] == said
    assert len(run(["acceleration", "velocity", "acceleration", "velocity"])[1]) == 1
    modes, said = run(["acceleration", "acceleration", "velocity", "velocity"])
    assert said == [] and (modes["mpc"].iloc[:3] > 0.999).all()
    y[:, 2:] *= 1e-4
    modes, said = run(None)
    assert (modes["mpc"].iloc[:3] > 0.7).all() and len(said) == 1
    assert said[0].startswith("channels 0, 1 and channels ") and "so the shapes read as complex; give" in said[0]


def test_the_quadrature_warning_judges_only_well_identified_shapes():
    """Four normal modes whose channels 2 and 3 are a quarter period from 0
    and 1, and four of MAMC 0.5 (noise modes) whose channel 2 lies 45
    degrees from the others: those are left out (MAMC below
    ``doubtful_mamc``), so the groups are named; at MAMC 0.99 they are
    judged, the medians fall between, and no parting holds. Labels are the
    record's channel names."""
    import dataclasses

    from modal.identification._stabilisation import Stabilisation
    from modal.measured._pipeline import quadrature_warning

    rng = np.random.default_rng(4)
    real = rng.uniform(0.3, 1.0, (4, 8)) * rng.choice([-1.0, 1.0], (4, 8))
    shapes = real * np.array([1, 1, 1j, 1j])[:, None]
    shapes[:, 4:] = real[:, 4:] * np.array([1, 1, np.exp(0.25j * np.pi), 1])[:, None]  # the noise modes
    modes = pd.DataFrame({"mode": np.arange(1, 9), "freq_hz": np.arange(1.0, 9.0), "mpc": [0.5] * 4 + [0.9] * 4,
                          "mamc": [0.999] * 4 + [0.5] * 4})
    result = Stabilisation(modes, shapes.real, pd.DataFrame(), np.empty((0, 0)), np.empty(0), np.empty(0),
                           np.empty(0), complex_shapes=shapes)
    said = quadrature_warning(result, ["x1", "x2", "v3", "v4"])
    assert said.startswith("channels x1, x2 and channels v3, v4 are a quarter period apart in every mode both show "
                           "(90.0 degrees, median over up to 4 modes)")
    assert "so 4 mode(s) read as complex and are flagged low MPC (0.50-0.50)" in said
    judged = dataclasses.replace(result, modes=modes.assign(mamc=0.99))
    assert quadrature_warning(judged, ["x1", "x2", "v3", "v4"]) is None


def test_channels_of_one_quantity_a_hundred_fold_apart_draw_a_warning():
    """A channel in other units (x 1000) among channels of the same quantity
    is named with the weakest; levels within 100-fold, or apart only across
    quantities (a velocity beside accelerations), are not; a channel's level
    is its RMS."""
    from modal.measured._pipeline import LEVEL_RATIO, level_warning

    rng = np.random.default_rng(5)
    y = rng.standard_normal((4000, 4)) * [1.0, 2.0, 0.5, 1.5]
    labels = ["a", "b", "c", "d"]
    assert level_warning(y, labels) is None
    scaled = y * [1.0, 1000.0, 1.0, 1.0]
    message = level_warning(scaled, labels)
    rms = np.sqrt(np.mean(scaled**2, axis=0))
    assert message.startswith(f"channels b (rms {rms[1]:.3g}) and c (rms {rms[2]:.3g}), both the same quantity, "
                              f"differ {rms[1] / rms[2]:.0f}-fold in level: a channel in other units")
    assert level_warning(scaled, labels, ["acceleration", "velocity", "acceleration", "acceleration"]) is None
    assert "both acceleration" in level_warning(scaled, labels, ["acceleration"] * 4)
    square = np.resize([1.0, -1.0], 4000)[:, None] * [1.0, LEVEL_RATIO]  # rms exactly 1 and 100
    assert "differ 100-fold" in level_warning(square, labels[:2])
    assert level_warning(square * [1.0, 0.999], labels[:2]) is None
    for quantities, expected in ((None, 1), (("acceleration", "velocity", "acceleration", "acceleration"), 0)):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            modal.identify_record(scaled, 0.01, "ambient", rows=20, max_order=4, fmax=20, quantities=quantities)
        said = [str(w.message) for w in caught if "-fold in level" in str(w.message)]
        assert len(said) == expected and all(m.startswith("channels 1 (rms") and " and 2 (rms" in m for m in said)


def _hammer_test(fs=200.0, seconds=20.0, impact=400):
    """Accelerations of two unit masses (a chain of springs of 3 Hz,
    stiffness-proportional damping: 1.854 and 4.854 Hz, 1.2 and 3.1 %) struck
    at the second at sample ``impact`` (exact ZOH state space): the direct
    response is one sharp sample; 0.5 % noise."""
    import scipy.signal

    k = np.array([[2.0, -1.0], [-1.0, 1.0]]) * (2 * np.pi * 3.0) ** 2
    c = 0.002 * k
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-k, -c]])
    system = scipy.signal.cont2discrete((a, np.array([[0.0], [0.0], [0.0], [1.0]]), np.hstack([-k, -c]),
                                          np.array([[0.0], [1.0]])), 1 / fs)
    force = np.zeros(int(seconds * fs))
    force[impact] = fs
    _, y, _ = scipy.signal.dlsim(system[:4] + (1 / fs,), force)
    return y + 0.005 * np.abs(y).max(axis=0) * np.random.default_rng(1).standard_normal(y.shape), 1 / fs


def test_a_hammer_blow_is_no_spike_in_a_free_decay():
    """An accelerometer's direct response to an impact is one sharp sample:
    the spike check flags it, so an ambient identification replaces it with a
    warning; a free decay keeps it (it is where the decay starts) and warns of
    nothing, and still finds both modes; a spike elsewhere is still replaced."""
    y, dt = _hammer_test()
    assert [at.tolist() for at in modal.spike_samples(y)] == [[], [400]]
    expected = np.sort(np.sqrt(np.linalg.eigvalsh(np.array([[2.0, -1.0], [-1.0, 1.0]])))) * 3.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result, _ = modal.identify_record(y, dt, "free_decay", max_order=20, fmax=20)
    assert [str(w.message) for w in caught if "spike" in str(w.message)] == []
    np.testing.assert_allclose(np.sort(result.modes["freq_hz"])[:2], expected, rtol=2e-3)
    glitch = y.copy()
    glitch[3000, 0] += 50 * np.abs(y[:, 0]).max()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        modal.identify_record(glitch, dt, "free_decay", max_order=20, fmax=20)
    assert sum("spike" in str(w.message) for w in caught) == 1
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        modal.identify_record(y, dt, "ambient", max_order=8, fmax=20, rows=40)
    assert sum("spike" in str(w.message) for w in caught) == 1


def test_a_channel_in_other_units_is_scaled_up_and_its_shape_entries_back():
    """A channel 1000 times weaker than its quantity's strongest (mm/s²
    recorded as m/s²... the other way round) is multiplied by the power of
    two bringing it to about a tenth of the strongest for the
    identification, logged and in the settings; the shapes come back in the
    record's units (that channel's entries 1000 times smaller than
    unscaled), the frequencies as without the gain. Channels within
    ten-fold, or apart only across quantities, are left alone."""
    from modal.measured._pipeline import level_scales

    acc, dt, f_exact = ambient_beam(duration_s=300.0)
    gains = np.array([1.0, 1e-3, 1.0, 1.0, 1.0])
    rms = np.sqrt(np.mean(acc**2, axis=0))
    scales = level_scales(acc * gains)
    expected = np.exp2(np.round(np.log2(0.1 * rms.max() / (rms[1] * 1e-3))))
    np.testing.assert_array_equal(scales, [1.0, expected, 1.0, 1.0, 1.0])
    np.testing.assert_array_equal(level_scales(acc * gains, ["acceleration", "velocity"] + ["acceleration"] * 3), 1.0)
    np.testing.assert_array_equal(level_scales(acc * [1.0, 0.2, 1.0, 1.0, 1.0]), 1.0)  # within ten-fold of the strongest
    runs = {}
    for name, factor in (("same", np.ones(5)), ("gain", gains)):
        log, details = [], {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            runs[name] = modal.identify_record(acc * factor, dt, "ambient", fmax=float(f_exact[2] * 1.3), max_order=40,
                                               log=log.append, details=details)[0], log, details["settings"]
    (same, same_log, same_settings), (gain, gain_log, gain_settings) = runs["same"], runs["gain"]
    assert "channel_scales" not in same_settings and not any("scaled up" in line for line in same_log)
    assert gain_settings["channel_scales"] == {"1": expected}
    assert [line for line in gain_log if "scaled up" in line] == [
        f"scaled up for the identification (weaker than a tenth of the strongest of their quantity): channel 1 x {expected:g}"]
    np.testing.assert_allclose(np.sort(gain.trusted_modes["freq_hz"]), np.sort(same.trusted_modes["freq_hz"]), rtol=2e-3)
    np.testing.assert_allclose(np.sort(gain.trusted_modes["freq_hz"]), f_exact, rtol=5e-3)
    for k in gain.trusted_modes.index:
        j = int(np.argmin(np.abs(same.modes["freq_hz"].to_numpy() - gain.modes["freq_hz"].iloc[k])))
        ratio_gain = gain.complex_shapes[1, k] / gain.complex_shapes[0, k]
        ratio_same = same.complex_shapes[1, j] / same.complex_shapes[0, j]
        np.testing.assert_allclose(abs(ratio_gain), 1e-3 * abs(ratio_same), rtol=0.05)
        assert np.isclose(np.linalg.norm(gain.complex_shapes[:, k]), 1.0)
        assert np.allclose(np.linalg.norm(gain.pole_shapes, axis=1), 1.0)


def _modes_near_nyquist(seed=0, minutes=5.0, fs=400.0):
    """Seven channels, seven modes damped 1 % (orthonormal shapes) under white
    forces, two of them (37 and 39 Hz) above the edge (32 Hz) of the
    anti-aliasing filter of the default decimation by 5 to 80 Hz."""
    import scipy.linalg as sl
    import scipy.signal as ss

    freqs = 2 * np.pi * np.array([1.0, 3.1, 7.3, 12.2, 19.5, 37.0, 39.0])
    q, _ = np.linalg.qr(np.random.default_rng(123).standard_normal((7, 7)))
    k, c = q @ np.diag(freqs**2) @ q.T, q @ np.diag(0.02 * freqs) @ q.T
    a = np.block([[np.zeros((7, 7)), np.eye(7)], [-k, -c]])
    b = np.vstack([np.zeros((7, 7)), np.eye(7)])
    ad = sl.expm(a / fs)
    system = ss.StateSpace(ad, np.linalg.solve(a, ad - np.eye(14)) @ b, np.hstack([-k, -c]), np.eye(7), dt=1 / fs)
    rng = np.random.default_rng(seed)
    _, acc, _ = ss.dlsim(system, rng.standard_normal((int(minutes * 60 * fs), 7)))
    return acc + 0.02 * acc.std(axis=0) * rng.standard_normal(acc.shape), 1 / fs


def test_the_default_decimation_filters_own_pole_is_flagged_not_trusted(monkeypatch):
    """Decimated by 5 (67 samples per period of the 1 Hz peak, the default
    when the spectrum's peaks are taken to end there: the 37 and 39 Hz peaks
    now keep a decimation by 3, ``test_auto_band.py``): the modes at 37 and
    39 Hz make its Chebyshev filter ring at its pole (33.5 Hz, 6.6 %); that
    ringing is no mode of the structure and is flagged, while a structural
    mode just below the filter's edge (31 Hz, damped 1 %) keeps no such flag.
    Checked again, each flag names it once."""
    from modal.measured import _pipeline
    from modal.measured._pipeline import with_filter_check

    monkeypatch.setattr(_pipeline, "spectral_peaks", lambda y, dt: (np.array([1.0]), np.array([20.0])))
    acc, dt = _modes_near_nyquist()
    result, dt_used = modal.identify_record(acc, dt, "ambient")
    assert dt_used == pytest.approx(5 * dt)
    modes = result.modes
    ringing = modes[(modes["freq_hz"] - 33.2).abs() < 1.0]
    assert len(ringing) and ringing["damping"].between(0.03, 0.1).all()
    assert ringing["flag"].str.contains("anti-aliasing filter's pole (33.52 Hz, 6.6 %)", regex=False).all()
    again = with_filter_check(result, 5, dt_used).modes["flag"]  # checked again: the reason once
    assert again.str.count("anti-aliasing filter's pole").tolist() == modes["flag"].str.count("anti-aliasing").tolist()
    trusted = result.trusted_modes["freq_hz"].to_numpy()
    assert not np.any((trusted > 32) & (trusted < 35))
    for f in (1.0, 3.1, 7.3, 12.2, 19.5):
        assert np.min(np.abs(trusted / f - 1)) < 0.01
    pole_hz, pole_zeta = modal.signals.antialiasing_pole(5, dt_used)
    assert pole_hz == pytest.approx(0.8381 * 40, rel=1e-3) and pole_zeta == pytest.approx(0.0663, abs=1e-3)
