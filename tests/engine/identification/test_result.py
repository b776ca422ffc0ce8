"""ModalResult: its defaults and frame, the flags every method sets (short
window, aliasing, real poles) and the warnings that name them, and the
free-response check that tells a method its record is ambient."""

import warnings
from pathlib import Path

import numpy as np
import pytest

import modal
# No public door: the free-response statistic and its threshold, the shape
# normalisation, sorting and alias margin that every method shares.
from modal.identification._result import (free_response_growth, near_limit, normalise_shapes, sort_modes,
                                          warn_not_free_response)

from ..cases import flagged, PALISADEN, PER_PERIOD, SENSORS_X, BEAM, THESIS_SAMPLES, ambient_beam, beam_record, two_sinusoids

def test_modal_result_frame(demo):
    rec = demo["make"](THESIS_SAMPLES)
    res = flagged(modal.era, rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    frame = res.to_frame()
    assert list(frame["mode"]) == [1, 2, 3, 4, 5, 6]
    assert {"omega", "freq_hz", "damping", "real_pole", "mamc", "mpc", "phi_1", "phi_6"} <= set(frame)
    np.testing.assert_allclose(frame["freq_hz"], demo["omega"] / (2 * np.pi), rtol=1e-8)
    assert np.all(np.diff(res.omega) > 0)


def test_short_window_flags_the_modes_with_fewer_than_six_periods():
    rec, omega, dt = beam_record("irregular", 2 * PER_PERIOD)  # two fundamental periods
    with pytest.warns(modal.ModalWarning, match=r"^tcm: short window \(5.812 s holds fewer than 6 periods\): omega = 2.162 rad/s \(see"):  # mode 1 only
        res = modal.tcm(rec.acceleration, dt, vel=rec.velocity)
    # mode 1: 2 periods, mode 2: 8 periods (omega_2 = 4 omega_1)
    np.testing.assert_array_equal(res.short_window, [True, False, False, False, False, False])
    with pytest.warns(modal.ModalWarning, match=r"^era: short window \(5.812 s"):
        era = modal.era(rec.acceleration, dt, 6, rows=4, cols=2 * PER_PERIOD - 4)
    np.testing.assert_array_equal(era.short_window, res.short_window)
    with pytest.warns(modal.ModalWarning, match=r"^cera: short window \(2.906 s"):
        cera = modal.cera(rec.acceleration[: PER_PERIOD + 1], dt, 6, cols=PER_PERIOD)  # one period
    np.testing.assert_array_equal(cera.short_window, [True, True, False, False, False, False])


def test_clean_long_record_raises_no_warning():
    rec, _, dt = beam_record("irregular", 7 * PER_PERIOD)
    with warnings.catch_warnings():
        warnings.simplefilter("error", modal.ModalWarning)
        modal.tcm(rec.acceleration, dt, vel=rec.velocity)
        modal.era(rec.acceleration, dt, 6, rows=4, cols=7 * PER_PERIOD - 4)


def test_to_frame_carries_every_flag():
    rec, _, dt = beam_record("irregular", 800)
    frame = flagged(modal.era, rec.acceleration, dt, 6, rows=8, cols=400).to_frame()
    assert {"real_pole", "unstable", "aliased", "short_window"} <= set(frame)


def test_warning_names_window_and_frequencies_and_points_at_the_caller():
    dt, _, _, acc = two_sinusoids(omega=(2.0, 5.0))
    rows, cols = 4, 96
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", modal.ModalWarning)
        res = modal.era(acc, dt, 2, rows=rows, cols=cols)
    (w,) = [w for w in caught if issubclass(w.category, modal.ModalWarning)]
    message = str(w.message)
    assert f"short window ({(rows + cols) * dt:.4g} s holds fewer than 6 periods)" in message
    assert f"omega = {res.omega[0]:.4g}, {res.omega[1]:.4g} rad/s" in message
    assert message.startswith("era: ") and message.endswith(" (see the result's flags)")
    # the warning points at the caller, not at the engine's result module
    # (not at this file exactly: under mutmut, trampolines add frames)
    assert Path(w.filename).name != "_result.py"
    with pytest.warns(modal.ModalWarning, match=rf"short window \({96 * dt:.4g} s holds"):
        modal.cera(acc, dt, 2, cols=96)


def test_modal_result_defaults():
    res = modal.ModalResult(omega=np.array([1.0, 2.0, 3.0]), shapes=np.eye(3), method="tcm")
    for name in ("damping", "mamc", "mpc"):
        values = getattr(res, name)
        assert values.dtype == float and values.shape == (3,) and np.isnan(values).all()
    for name in modal.FLAGS:
        values = getattr(res, name)
        assert values.dtype == bool and values.shape == (3,) and not values.any()
    frame = res.to_frame()
    assert list(frame.columns[:11]) == ["mode", "method", "omega", "freq_hz", "damping", "real_pole", "unstable",
                                        "aliased", "short_window", "mamc", "mpc"]
    for i in range(3):
        np.testing.assert_array_equal(frame[f"phi_{i + 1}"], res.shapes[i])


@pytest.mark.parametrize("method", ["tcm", "era", "cera"])
def test_flags_are_boolean_in_every_method(method):
    dt, _, vel, acc = two_sinusoids(omega=(2.0, 5.0))
    res = {"tcm": lambda: flagged(modal.tcm, acc, dt, vel=vel), "era": lambda: flagged(modal.era, acc, dt, 2, 4, 600),
           "cera": lambda: flagged(modal.cera, acc, dt, 2, 600)}[method]()
    for name in modal.FLAGS:
        assert getattr(res, name).dtype == bool
    if method != "era":
        assert np.isnan(res.damping).all() and np.isnan(res.mamc).all()


def test_normalise_complex_shapes():
    """Rotate by the largest entry's phase, unit norm per column, largest
    entry positive; a zero column stays zero."""
    real = np.array([[0.3, 0.02, 0.0], [-2.0, 0.05, 0.0], [0.5, -0.01, 0.0]])
    phase = np.exp(1j * np.array([0.7, -2.1, 0.0]))
    out = normalise_shapes(real * phase)
    expected = -real[:, :2] / np.linalg.norm(real[:, :2], axis=0) * [1, -1]
    np.testing.assert_allclose(out[:, :2], expected, atol=1e-15)
    np.testing.assert_array_equal(out[:, 2], 0.0)
    assert not np.iscomplexobj(out)
    # a complex (non-collinear) shape: the largest entry, not the first, sets the phase
    shape = 0.1 * np.array([[0.1 + 0.3j], [2.0 * np.exp(0.5j)], [0.5 - 0.5j]])
    out = normalise_shapes(shape)
    rotated = (shape * np.exp(-0.5j)).real
    np.testing.assert_allclose(out, rotated / np.linalg.norm(rotated), atol=1e-15)
    # a small-norm real shape: still unit norm, largest entry positive
    np.testing.assert_allclose(normalise_shapes(np.array([[1e-3], [-4e-3]])), [[-0.2425356250363330], [0.9701425001453319]],
                               rtol=1e-14)


def test_sort_modes_passes_missing_columns_through():
    omega, shapes, cols = sort_modes(np.array([3.0, 1.0]), np.eye(2), damping=None, z=np.array([30.0, 10.0]))
    np.testing.assert_array_equal(omega, [1.0, 3.0])
    assert cols["damping"] is None
    np.testing.assert_array_equal(cols["z"], [10.0, 30.0])


def test_near_limit_margin():
    assert near_limit(0.99 * np.pi, 1.0) and near_limit(0.98 * np.pi, 1.0) and not near_limit(0.97 * np.pi, 1.0)


def _free_response_warnings(call):
    """The free-response ModalWarnings ``call()`` issues (other flags aside)."""
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()
    return [w for w in caught if issubclass(w.category, modal.ModalWarning) and "free response" in str(w.message)]


def test_free_response_growth_of_a_known_envelope():
    """Whole periods of a sine with amplitude a_i in window i (4 periods each):
    the window energies are a_i^2 / 2, so the statistic is the sum of their
    rises over the first: (4 - 1) + (9 - 1) = 11."""

    dt, f = 0.01, 2.5  # 40 samples per period, windows of 160 samples
    amplitudes = np.array([1, 1, 2, 1, 3, 3, 3, 3.0])
    t = dt * np.arange(160)
    y = np.concatenate([a * np.sin(2 * np.pi * f * t) for a in amplitudes])
    y = np.column_stack([y, 0.5 * y])[None]
    assert free_response_growth(y, dt, [2 * np.pi * f]) == pytest.approx(11, rel=1e-9)
    decaying = y * np.exp(-0.2 * np.arange(y.shape[1]) * dt)[None, :, None]
    assert free_response_growth(decaying, dt, [2 * np.pi * f, 7.0]) == 0.0
    assert np.isnan(free_response_growth(y[:, :100], dt, [2 * np.pi * f]))  # 100 samples: not two windows


@pytest.mark.parametrize("zeta, eta", [(0.0, 0.0), (0.0, 0.05), (0.05, 0.0), (0.02, 0.05), (0.005, 0.03)])
def test_free_decays_do_not_warn_free_response(zeta, eta):
    """Impulse responses of the beam off the thesis geometry (sensors at
    SENSORS_X, impact at 0.37 L), undamped to 5 % damping, noise to 5 %:
    no method calls them ambient, and the statistic stays far below 1."""

    n = 3
    omega = BEAM.natural_frequencies(n)
    dt = 2 * np.pi / omega[-1] / 12
    rec = modal.beam_impulse_response(BEAM, n, 0.37 * BEAM.length, SENSORS_X[[0, 2, 4]], dt, 2400, zeta)
    rec = modal.with_noise(rec, eta, seed=3) if eta else rec
    for signal in (rec.displacement, rec.velocity, rec.acceleration):
        assert free_response_growth(signal[None], dt, omega) < 0.1
    assert not _free_response_warnings(lambda: modal.tcm(rec.acceleration, dt, vel=rec.velocity))
    assert not _free_response_warnings(lambda: modal.cera(rec.acceleration, dt, n, cols=2000))
    assert not _free_response_warnings(lambda: modal.era(rec.acceleration, dt, n, rows=20, cols=400))
    assert not _free_response_warnings(lambda: modal.era(rec.acceleration, dt, n, rows=20, cols=400, start=150))


def test_a_mode_near_nyquist_is_not_mistaken_for_growth():
    """Sampled, an undamped mode at 0.99 of the Nyquist frequency beats with
    period 100 samples (its energy oscillates at 2 omega dt, folded to 0.02
    pi): windows of 8 such beats hold a constant energy, so no warning."""

    k = np.arange(2000)
    y = np.column_stack([np.cos(0.99 * np.pi * k), 0.5 * np.cos(0.99 * np.pi * k + 1)])
    assert free_response_growth(y[None], 0.01, [0.99 * np.pi / 0.01]) < 0.01
    assert not _free_response_warnings(lambda: modal.cera(y, 0.01, 1, cols=1000))


@pytest.mark.slow
def test_ambient_records_warn_free_response():
    """White-noise-driven beam response and the Palisaden record: TCM, CERA
    and ERA on the raw record warn, naming the remedy; ERA on the NExT
    correlation functions of the same record (a free decay) does not."""

    acc, dt, f_exact = ambient_beam(duration_s=30, seed=7)
    assert free_response_growth(acc[None], dt, 2 * np.pi * f_exact) > 3
    for call in (lambda: modal.tcm(acc[:, :3], dt), lambda: modal.cera(acc, dt, 3, cols=1000),
                 lambda: modal.era(acc, dt, 3, rows=20, cols=1000)):
        (w,) = _free_response_warnings(call)
        assert "assumes free (or impulse) response" in str(w.message)
        assert "modal.correlations" in str(w.message) and "modal.stabilisation" in str(w.message)
    r = modal.correlations(modal.detrend(acc), 201)
    assert not _free_response_warnings(lambda: modal.era(r, dt, 3, rows=40, cols=120))

    raw, dt = modal.load_record(PALISADEN, fs=20)
    filtered = modal.zero_phase_filter(modal.detrend(raw), dt, highpass_hz=0.5)
    for call in (lambda: modal.tcm(filtered, dt), lambda: modal.cera(raw, dt, 3, cols=2000),
                 lambda: modal.era(filtered, dt, 4, rows=60, cols=600)):
        assert len(_free_response_warnings(call)) == 1
    # Unfiltered, ERA fits the record's drift (lowest "modes" near 0.01 Hz):
    # 30 min hold fewer than 8 of their periods, too few to judge.
    assert not _free_response_warnings(lambda: modal.era(raw, dt, 4, rows=60, cols=600))
    r = modal.correlations(filtered, 121)
    assert not _free_response_warnings(lambda: modal.era(r, dt, 4, rows=60, cols=61))


def test_a_model_missing_the_lowest_mode_is_told_so():
    """A free decay of a weak 2 Hz and a strong 30 Hz mode, one channel: with
    one mode the ERA finds 30 Hz, its windows (4 periods of 30 Hz) do not
    average out the 2 Hz oscillation, and the warning names that cause and the
    lowest mode found; with both modes there is no warning."""
    dt = 1 / 400
    t = dt * np.arange(4000)
    y = (0.3 * np.exp(-0.002 * 2 * np.pi * 2 * t) * np.cos(2 * np.pi * 2 * t)
         + np.exp(-0.005 * 2 * np.pi * 30 * t) * np.cos(2 * np.pi * 30 * t))[:, None]
    (w,) = _free_response_warnings(lambda: modal.era(y, dt, 1, rows=40, cols=400))
    assert "missed a mode below the lowest it found, 29.95 Hz" in str(w.message)
    assert not _free_response_warnings(lambda: modal.era(y, dt, 2, rows=40, cols=400))


def _alternating(amplitudes, window):
    """One channel: +-a alternating within each window of ``window`` (even)
    samples, a from ``amplitudes``; each window has zero mean and energy a^2."""
    return np.concatenate([a * np.resize([1.0, -1.0], window) for a in amplitudes])[None, :, None]


def test_free_response_growth_edge_cases_exact():
    """free_response_growth on records whose window energies are known exactly
    (mutation run of issue 15): non-positive and non-finite frequencies are
    ignored, means are removed per channel, the no-mode window is n // 8
    samples (down to one sample), a silent first window gives inf (nan when
    all is silent), and no numpy warning escapes."""
    import warnings

    dt, f = 0.01, 2.5
    t = dt * np.arange(160)
    amplitudes = np.array([1, 1, 2, 1, 3, 3, 3, 3.0])
    y = np.concatenate([a * np.sin(2 * np.pi * f * t) for a in amplitudes])[None, :, None]
    w = 2 * np.pi * f
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert free_response_growth(y, dt, [w]) == pytest.approx(11, rel=1e-9)
        # zero and infinite frequencies are ignored (not a window of inf samples)
        assert free_response_growth(y, dt, [w, 0.0, np.inf, np.nan]) == pytest.approx(11, rel=1e-9)
        # a channel's constant offset is removed per channel, not with the grand mean
        two = np.concatenate([y + 5.0, 0.5 * y - 3.0], axis=2)
        assert free_response_growth(two, dt, [w]) == pytest.approx(11, rel=1e-9)
        # a mode at the Nyquist rate beats infinitely slowly: too short to tell, silently
        assert np.isnan(free_response_growth(y, dt, [np.pi / dt]))
        # no mode: windows of n // 8 samples; 1007 // 8 = 125 (round(1007 / 8) would be 126)
        x = np.zeros((1, 1007, 1))
        x[0, :125:2, 0], x[0, 1:125:2, 0] = 1.0, -1.0
        x[0, 126:250:2, 0], x[0, 125:249:2, 0] = 3.0, -3.0  # window 1: 62 pairs of +-3, one 0 at 249
        x = x - x[:, :1000].mean()  # zero mean over the 1000 samples analysed; the tail is cut
        tail = x[0, :1000, 0].reshape(8, 125)
        energy = (tail ** 2).mean(axis=1)
        expected = np.sum(np.maximum(np.diff(energy), 0)) / energy[0]
        assert free_response_growth(x, dt, []) == pytest.approx(expected, rel=1e-12)
        assert expected > 7
        # 8 to 15 samples and no mode: windows of one sample each
        one = np.array([0.5, -0.5, 1.0, -1.0, 0.0, 0.0, 0.5, -0.5])[None, :, None]
        assert free_response_growth(one, dt, []) == pytest.approx((0.75 + 0.25) / 0.25, rel=1e-12)  # rises 0.25 -> 1 and 0 -> 0.25
        # energy in the first window only, then silence: no rise
        assert free_response_growth(_alternating([0.5, 0, 0, 0, 0, 0, 0, 0], 10), dt, []) == 0.0
        # a silent first window: inf as soon as anything follows (however small), nan if all is silent
        assert free_response_growth(_alternating([0, 0.5, 0, 0, 0, 0, 0, 0], 10), dt, []) == np.inf
        assert np.isnan(free_response_growth(np.zeros((1, 80, 2)), dt, []))


def test_warn_not_free_response_threshold_and_lowest_frequency():
    """The warning fires for a growth above FREE_RESPONSE_MAX_GROWTH = 1 only
    (exactly 1 is not above), and names the lowest positive finite frequency."""
    import warnings
    from types import SimpleNamespace

    dt = 0.01
    exactly_one = _alternating([1, 0, 1, 0, 0, 0, 0, 0], 2)  # rises: 1 over a first energy of 1
    assert free_response_growth(exactly_one, dt, []) == 1.0
    quiet = SimpleNamespace(method="era", omega=np.array([]), freq_hz=np.array([]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert warn_not_free_response(quiet, exactly_one, dt) is quiet
    twice = _alternating([1, 0, 1, 0, 1, 0, 0, 0], 2)
    found = SimpleNamespace(method="era", omega=np.array([]), freq_hz=np.array([np.nan, -1.0, 0.0, 0.5, 3.0, np.inf]))
    with pytest.warns(modal.ModalWarning, match="2 x the initial energy") as record:
        warn_not_free_response(found, twice, dt)
    (w,) = record
    assert "lowest it found, 0.5 Hz" in str(w.message)


def test_repr_is_one_line_in_hz_whatever_the_size():
    """At the prompt a result shows its method, frequencies in Hz (not rad/s),
    channels and flag counts on one line, not every array."""
    omega = 2 * np.pi * np.arange(1.0, 11.0)  # 1 ... 10 Hz
    shapes = np.ones((500, 10))
    flags = np.zeros(10, dtype=bool)
    flags[[2, 7]] = True
    res = modal.ModalResult(omega=omega, shapes=shapes, method="era", real_pole=flags)
    text = repr(res)
    assert "\n" not in text and len(text) < 200
    assert text == ("<ModalResult era: 10 modes at [1, 2, 3, 4, 5, 6, 7, 8, ...] Hz, 500 channels; "
                    "2 real_pole>")
    few = modal.ModalResult(omega=omega[:2] * 1.23456, shapes=shapes[:3, :2], method="tcm")
    assert repr(few) == "<ModalResult tcm: 2 modes at [1.235, 2.469] Hz, 3 channels>"
