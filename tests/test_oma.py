"""Operational modal analysis of measured records: NExT correlations,
preprocessing, the stabilisation diagram with automatic mode selection, and
the Palisaden record (issue 10)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import modal
from modal.structures._shake_test import foh_modal_response

PALISADEN = Path(__file__).parent / "data" / "palisaden_20hz_30min.npy"
PALISADEN_MODES_HZ = [1.88, 2.42, 2.68]  # pyOMA2 documentation (see tests/data/PALISADEN.md)

# A simply supported beam with sensors off the thesis's evenly spaced layout.
BEAM = modal.SimplySupportedBeam(length=10.0, bending_stiffness=2.0e6, mass_per_length=100.0)
SENSORS_X = np.array([0.9, 2.3, 4.1, 6.6, 8.7])
DAMPING = np.array([0.01, 0.015, 0.02])


def ambient_beam(duration_s=400.0, dt=0.01, seed=1):
    """Acceleration of three beam modes under spatially white, Gaussian white
    noise (exact first-order-hold integration), sensors at SENSORS_X."""
    omega = BEAM.natural_frequencies(3)
    shapes = BEAM.mode_shapes(SENSORS_X, 3)
    rng = np.random.default_rng(seed)
    force = rng.standard_normal((int(duration_s / dt), 3))
    _, _, acc_modal = foh_modal_response(omega, DAMPING, force, dt)
    return acc_modal @ shapes.T, dt, omega / (2 * np.pi)


def test_correlations_equal_direct_sums_both_estimators():
    rng = np.random.default_rng(0)
    y = rng.standard_normal((2, 300, 3))
    for estimator in ("biased", "unbiased"):
        r = modal.correlations(y, 25, refs=[2, 0], estimator=estimator)
        assert r.shape == (2, 25, 3)
        for i, ref in enumerate([2, 0]):
            for k in (0, 7, 24):
                direct = sum(y[m, k:, :].T @ y[m, : 300 - k, ref] for m in range(2)) / 2
                direct /= 300 if estimator == "biased" else 300 - k
                np.testing.assert_allclose(r[i, k], direct, rtol=1e-12, atol=1e-14)


def test_correlations_of_cosines_closed_form():
    """R(k) of a*cos(w t) is a^2/2 cos(w k dt) (unbiased, whole periods)."""
    dt, f = 0.01, 2.0
    t = dt * np.arange(5000)  # 100 whole periods
    y = np.column_stack([3 * np.cos(2 * np.pi * f * t), np.sin(2 * np.pi * f * t)])
    r = modal.correlations(y, 40, refs=[0], estimator="unbiased")
    lag = dt * np.arange(40)
    np.testing.assert_allclose(r[0, :, 0], 4.5 * np.cos(2 * np.pi * f * lag), atol=0.02)
    np.testing.assert_allclose(r[0, :, 1], 1.5 * np.sin(2 * np.pi * f * lag), atol=0.02)


def test_correlations_reject_bad_input():
    y = np.random.default_rng(0).standard_normal((50, 2))
    with pytest.raises(ValueError, match="n_lags = 51 exceeds"):
        modal.correlations(y, 51)
    with pytest.raises(ValueError, match="refs must be distinct channel indices"):
        modal.correlations(y, 5, refs=[2])
    with pytest.raises(ValueError, match="estimator"):
        modal.correlations(y, 5, estimator="welch")
    with pytest.raises(ValueError, match="channel 1 is constant"):
        modal.correlations(np.column_stack([y[:, 0], np.ones(50)]), 5)


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


def test_stabilisation_orders_are_truncations_of_one_decomposition():
    """The poles of order k equal ERA's with n_modes = k / 2."""
    acc, dt, _ = ambient_beam(duration_s=100)
    r = modal.correlations(modal.detrend(acc), 81)
    result = modal.stabilisation(r, dt, 12, rows=40, cols=40)
    assert sorted(result.poles["order"].unique()) == list(range(2, 13, 2))
    for order in (6, 12):
        era = modal.era(r, dt, order // 2, rows=40, cols=40)
        poles = result.poles[result.poles["order"] == order]
        np.testing.assert_allclose(poles["freq_hz"], era.freq_hz, rtol=1e-10)
        np.testing.assert_allclose(poles["damping"], era.damping, rtol=1e-8)


def test_stabilisation_rejects_bad_input():
    r = np.random.default_rng(1).standard_normal((2, 50, 3))
    with pytest.raises(ValueError, match="max_order must be even"):
        modal.stabilisation(r, 0.1, 7, rows=10)
    with pytest.raises(ValueError, match="max_order = 40 exceeds"):
        modal.stabilisation(r, 0.1, 40, rows=10)
    with pytest.raises(ValueError, match="criteria"):
        modal.stabilisation(r, 0.1, 4, rows=10, criteria={"mac_min": 0.9})
    with pytest.raises(ValueError, match="mac_min must be in"):
        modal.StabilityCriteria(mac_min=1.5)
    with pytest.raises(ValueError, match="excitation"):
        modal.identify_record(np.random.default_rng(2).standard_normal((100, 2)), 0.1, "forced")


def test_preprocessing():
    dt = 0.001
    t = dt * np.arange(20000)
    slow, fast = np.sin(2 * np.pi * 3 * t), 0.5 * np.sin(2 * np.pi * 180 * t)
    y = np.column_stack([slow + fast + 2 + 0.1 * t])
    # Zero phase: the 3 Hz wave passes a 20 Hz low-pass in place (edges aside).
    low = modal.zero_phase_filter(modal.detrend(y), dt, lowpass_hz=20)
    np.testing.assert_allclose(low[2000:-2000], modal.detrend(slow[:, None])[2000:-2000], atol=2e-3)
    # Decimation by 30 (stages 10 x 3): 180 Hz would alias to 13.3 Hz; it is removed.
    dec, dt_dec = modal.decimate(y - y.mean(), dt, 30)
    assert dt_dec == pytest.approx(0.03) and dec.shape == (667, 1)
    freqs, amp = modal.amplitude_spectrum(modal.detrend(dec), dt_dec)
    assert amp[np.argmin(np.abs(freqs - 40 / 3)), 0] < 1e-3
    with pytest.raises(ValueError, match="lowpass_hz = 600 must be below the Nyquist"):
        modal.zero_phase_filter(y, dt, lowpass_hz=600)
    with pytest.raises(ValueError, match="highpass_hz = 30 must be below lowpass_hz"):
        modal.zero_phase_filter(y, dt, highpass_hz=30, lowpass_hz=20)
    with pytest.raises(ValueError, match="kind"):
        modal.detrend(y, "quadratic")


def test_palisaden_three_modes_within_half_a_percent():
    acc, dt = modal.load_record(PALISADEN, fs=20)
    result, _ = modal.identify_record(acc, dt, "ambient", max_order=60, fmax=5, highpass_hz=0.5)
    f = result.modes["freq_hz"].to_numpy()
    for published in PALISADEN_MODES_HZ:
        assert np.min(np.abs(f - published)) / published < 0.005
    assert np.all(result.modes["damping"].between(0.005, 0.05))


def test_cli_identify_palisaden(tmp_path):
    from modal.cli import main

    out = tmp_path / "pal"
    code = main(["identify", str(PALISADEN), "--fs", "20", "--ambient", "--fmax", "5", "--highpass", "0.5",
                 "--channels", "0,1,2,3,4,5", "--refs", "0,1,2,3", "--out", str(out), "--quiet"])
    assert code == 0
    import pandas as pd

    modes = pd.read_csv(out / "modes.csv")
    for column in ("freq_hz", "freq_std_hz", "damping", "damping_std", "n_poles", "mpc", "mamc"):
        assert column in modes
    for published in PALISADEN_MODES_HZ:
        assert np.min(np.abs(modes["freq_hz"] - published)) / published < 0.005
    assert (out / "stabilisation.png").stat().st_size > 10_000


def test_cli_errors_and_exit_codes(tmp_path, capsys):
    from modal.cli import EXIT_BAD_FILE, EXIT_CANNOT_IDENTIFY, main

    out = str(tmp_path / "o")
    bad = tmp_path / "bad.csv"
    bad.write_text("t,a\n0,1\n0.1,x\n0.2,3\n")
    assert main(["identify", str(bad), "--ambient", "--out", out]) == EXIT_BAD_FILE
    assert "bad.csv: row 3, column 2" in capsys.readouterr().err
    short = tmp_path / "short.npy"
    np.save(short, np.random.default_rng(0).standard_normal((100, 2)))
    assert main(["identify", str(short), "--fs", "10", "--ambient", "--out", out]) == EXIT_CANNOT_IDENTIFY
    assert "longer record" in capsys.readouterr().err
    assert main(["identify", str(short), "--fs", "10", "--ambient", "--channels", "0,5", "--out", out]) \
        == EXIT_CANNOT_IDENTIFY
    with pytest.raises(SystemExit) as exc:
        main(["identify", str(short), "--ambient", "--free-decay", "--out", out])
    assert exc.value.code == 2
    with pytest.raises(SystemExit):
        main(["identify", str(short), "--ambient", "--channels", "a,b", "--out", out])


def test_python_m_modal_and_import_without_matplotlib():
    code = "import sys, modal; assert 'matplotlib' not in sys.modules and 'lvm_read' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True)
    run = subprocess.run([sys.executable, "-m", "modal", "identify", "--help"], capture_output=True, text=True)
    assert run.returncode == 0 and "--free-decay" in run.stdout


def _per_order_reference(data, dt, max_order, rows, criteria):
    """The stabilisation diagram the straightforward way: ``realise`` at each
    order from the truncated decomposition, each order's poles compared with
    the previous order's through the whole MAC matrix."""
    from modal.identification._era import realise
    from modal.identification._era_kernels import decompose

    y = data if data.ndim == 3 else data[None]
    m, n_samples, l = y.shape
    h_ext = modal.hankel(y, rows + 1, n_samples - rows)
    h0, h1 = h_ext[:-l], h_ext[l:]
    p, d, qt, _ = decompose(h0, max_order, block=(l, m))
    rows_out, shapes_out, previous = [], [], None
    for order in range(2, max_order + 1, 2):
        res = realise(p[:, :order], d[:order], qt[:order], h1, n_channels=l, n_sets=m, dt=dt)
        cur = {"order": np.full(res.n_modes, order), "freq_hz": res.freq_hz, "damping": res.damping,
               "mpc": res.mpc, "mamc": res.mamc, "real_pole": res.real_pole}
        n = res.n_modes
        if previous is None:
            flags = [np.zeros(n, bool)] * 3
        else:
            f0, zeta0, shapes0 = previous
            near = np.argmin(np.abs(cur["freq_hz"][:, None] - f0[None, :]), axis=1)
            with np.errstate(invalid="ignore"):
                flags = [np.abs(cur["freq_hz"] - f0[near]) <= criteria.freq_rtol * cur["freq_hz"],
                         np.abs(res.damping - zeta0[near]) <= criteria.damping_rtol * np.abs(zeta0[near]),
                         modal.mac(res.shapes, shapes0)[np.arange(n), near] >= criteria.mac_min]
        cur.update(stable_freq=flags[0], stable_damping=flags[1], stable_shape=flags[2],
                   stable=flags[0] & flags[1] & flags[2])
        rows_out.append(cur)
        shapes_out.append(res.shapes.T)
        previous = (res.freq_hz, res.damping, res.shapes)
    table = {k: np.concatenate([r[k] for r in rows_out]) for k in rows_out[0]}
    return table, np.concatenate(shapes_out)


@pytest.mark.parametrize("case", ["ambient_correlations", "free_decay"])
def test_stabilisation_equals_per_order_realisations(case):
    """The vectorised diagram (one Phi, indicators for all orders at once,
    stability by nearest pole) equals order-by-order ``realise`` to round-off,
    on noisy data off the thesis geometry: correlations of the ambient beam
    with 5 % sensor noise (5 references: m = 5), and a free decay."""
    rng = np.random.default_rng(11)
    if case == "ambient_correlations":
        acc, dt, _ = ambient_beam(duration_s=120, seed=5)
        acc = acc + 0.05 * acc.std(axis=0) * rng.standard_normal(acc.shape)
        data, rows, max_order = modal.correlations(modal.detrend(acc), 81), 40, 40
    else:
        dt, t = 1 / 200, np.arange(1500) / 200
        f, zeta = np.array([3.1, 11.7, 26.0]), np.array([0.02, 0.01, 0.035])
        decay = np.exp(-zeta * 2 * np.pi * f * t[:, None]) * np.sin(2 * np.pi * f * t[:, None] + 0.3)
        data = decay @ BEAM.mode_shapes(SENSORS_X, 3).T
        data = data + 0.05 * data.std(axis=0) * rng.standard_normal(data.shape)
        rows, max_order = 30, 30
    criteria = modal.StabilityCriteria()
    fast = modal.stabilisation(data, dt, max_order, rows, criteria=criteria)
    table, shapes = _per_order_reference(data, dt, max_order, rows, criteria)
    assert len(fast.poles) == len(table["order"]) > max_order
    for name in ("order", "real_pole", "stable_freq", "stable_damping", "stable_shape", "stable"):
        np.testing.assert_array_equal(fast.poles[name], table[name], err_msg=name)
    for name in ("freq_hz", "damping", "mpc", "mamc"):
        np.testing.assert_allclose(fast.poles[name], table[name], rtol=1e-9, atol=1e-12, err_msg=name)
    np.testing.assert_allclose(fast.pole_shapes, shapes, atol=1e-9)
    assert fast.poles["stable"].sum() > 10 and (~fast.poles["stable"]).sum() > 10
    assert (fast.poles["mamc"] < 0.5).sum() > 0 and (fast.poles["mamc"] > 0.9).sum() > 0


# ------------------------------------------------------- methods that assume a free response
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
    from modal.identification._result import free_response_growth

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
    from modal.identification._result import free_response_growth

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
    from modal.identification._result import free_response_growth

    k = np.arange(2000)
    y = np.column_stack([np.cos(0.99 * np.pi * k), 0.5 * np.cos(0.99 * np.pi * k + 1)])
    assert free_response_growth(y[None], 0.01, [0.99 * np.pi / 0.01]) < 0.01
    assert not _free_response_warnings(lambda: modal.cera(y, 0.01, 1, cols=1000))


def test_ambient_records_warn_free_response():
    """White-noise-driven beam response and the Palisaden record: TCM, CERA
    and ERA on the raw record warn, naming the remedy; ERA on the NExT
    correlation functions of the same record (a free decay) does not."""
    from modal.identification._result import free_response_growth

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


@pytest.mark.parametrize("n", [1, 2, 121, 5000])
def test_mean_spectrum_equals_the_direct_sum(n):
    """The spectrum behind the diagram (one long FFT of the summed
    autocorrelation when the padding allows) equals the root mean square of
    every series' tapered, zero-padded amplitude spectrum."""
    from modal.identification._stabilisation import _mean_spectrum

    y = np.random.default_rng(n).standard_normal((3, n, 2)) * np.array([1.0, 30.0])
    freqs, spectrum = _mean_spectrum(y, 0.01)
    n_fft = max(n, 8192)
    taper = np.hanning(2 * n)[n:]
    direct = np.abs(np.fft.rfft(y * taper[None, :, None], n=n_fft, axis=1)) / n
    direct = np.sqrt(np.mean(direct**2, axis=(0, 2)))
    np.testing.assert_allclose(freqs, np.fft.rfftfreq(n_fft, 0.01))
    np.testing.assert_allclose(spectrum, direct, rtol=1e-9, atol=1e-12 * direct.max())


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

    from modal.identification._result import free_response_growth

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

    from modal.identification._result import free_response_growth, warn_not_free_response

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


def test_paired_mac_is_the_diagonal_of_mac():
    """paired_mac(a, b) is diag(mac(a, b)) for columns of any norms."""
    from modal.identification._indicators import mac, paired_mac

    rng = np.random.default_rng(3)
    a = rng.normal(size=(5, 4)) * np.array([1.0, 3.0, 0.2, 7.0])
    b = (rng.normal(size=(5, 4)) + 1j * rng.normal(size=(5, 4))) * np.array([2.0, 0.5, 1.0, 4.0])
    np.testing.assert_allclose(paired_mac(a, b), np.diag(mac(a, b)), rtol=1e-12)
    np.testing.assert_allclose(paired_mac(a, 3 * a), np.ones(4), rtol=1e-12)


def test_stability_criteria_bounds_and_names():
    """StabilityCriteria accepts the closed bounds (mac_min = 1, min_poles = 1)
    and refuses the rest naming the argument."""
    from modal.identification._stabilisation import StabilityCriteria

    assert StabilityCriteria(mac_min=1.0, mpc_min=1.0, mamc_min=0.0, min_poles=1).mac_min == 1.0
    for kwargs, name in [({"freq_rtol": 0.0}, "freq_rtol"), ({"cluster_distance": -1.0}, "cluster_distance"),
                         ({"mac_min": -0.1}, "mac_min"), ({"mamc_min": 1.5}, "mamc_min"),
                         ({"min_poles": 0}, "min_poles"), ({"min_poles": 2.5}, "min_poles")]:
        with pytest.raises(ValueError, match=f"^{name} must"):
            StabilityCriteria(**kwargs)


def test_stability_of_a_single_pole():
    """A table of one pole (the lowest order) has nothing to compare with:
    not stable, and no index past the table."""
    from modal.identification._stabilisation import StabilityCriteria, _stability

    table = {"order": np.array([2]), "freq_hz": np.array([1.5]), "damping": np.array([0.01])}
    flags = _stability(table, np.ones((1, 3)), StabilityCriteria())
    for key in ("stable_freq", "stable_damping", "stable_shape", "stable"):
        np.testing.assert_array_equal(flags[key], [False])


def _pole_table(freqs, shapes, stable=None):
    n = len(freqs)
    rng = np.random.default_rng(5)
    return ({"order": 2 * np.arange(1, n + 1), "freq_hz": np.asarray(freqs, float),
             "damping": 0.01 + 0.01 * rng.random(n), "mpc": rng.random(n), "mamc": rng.random(n),
             "stable": np.ones(n, bool) if stable is None else np.asarray(stable, bool), "physical": np.ones(n, bool)},
            np.asarray(shapes, float))


def test_select_modes_on_a_known_pole_table():
    """_select_modes on hand-made poles: clusters of >= min_poles poles are
    modes numbered 1, 2, ... by frequency, with the members' mean and sample
    (ddof=1) standard deviation, and the medoid's shape (the member closest,
    in total, to the other members of its cluster)."""
    from modal.identification._stabilisation import _select_modes

    e = np.eye(3)
    a = [e[0] + [0, 1e-4 * i, 0] for i in range(3)]  # near-identical shapes, told apart by index
    freqs = [2.0, 2.002, 1.998, 1.003, 1.0, 0.998, 5.0, 3.0, 3.001]
    shapes = [e[1], e[1], e[1], a[0], a[1], a[2], e[2], e[2], e[2]]
    poles, pole_shapes = _pole_table(freqs, shapes, stable=[1, 1, 1, 1, 1, 1, 0, 1, 1])
    labels, modes, reps = _select_modes(poles, pole_shapes, cluster_distance=0.006, min_poles=3)
    np.testing.assert_array_equal(labels, [2, 2, 2, 1, 1, 1, 0, 0, 0])
    assert labels.dtype.kind == "i"
    np.testing.assert_array_equal(modes["mode"], [1, 2])
    np.testing.assert_array_equal(modes["n_poles"], [3, 3])
    for row, members in ((0, [3, 4, 5]), (1, [0, 1, 2])):
        for column in ("freq_hz", "damping", "mpc", "mamc"):
            assert modes[column].iloc[row] == pytest.approx(poles[column][members].mean(), rel=1e-12)
        assert modes["freq_std_hz"].iloc[row] == pytest.approx(np.std(poles["freq_hz"][members], ddof=1), rel=1e-9)
        assert modes["damping_std"].iloc[row] == pytest.approx(np.std(poles["damping"][members], ddof=1), rel=1e-9)
    np.testing.assert_array_equal(reps[:, 0], a[1])  # the middle frequency, 1.0 Hz, is the medoid
    np.testing.assert_array_equal(reps[:, 1], e[1])


@pytest.mark.parametrize("n_poles, min_poles, n_modes", [(3, 3, 1), (2, 2, 1), (2, 3, 0), (1, 1, 0)])
def test_select_modes_needs_min_poles_candidates(n_poles, min_poles, n_modes):
    """Exactly min_poles (at least 2) coincident poles make a mode; fewer make
    none, and then the shapes are an empty (n_channels, 0) array."""
    from modal.identification._stabilisation import _select_modes

    poles, pole_shapes = _pole_table([1.0] * n_poles, [[1.0, 2.0, 0.0, 1.0]] * n_poles)
    labels, modes, reps = _select_modes(poles, pole_shapes, cluster_distance=0.02, min_poles=min_poles)
    assert len(modes) == n_modes and reps.shape == (4, n_modes)
    np.testing.assert_array_equal(labels, [n_modes] * n_poles)


def test_select_modes_without_a_large_enough_cluster():
    """Three candidates in three distant clusters, min_poles 3: no mode, and
    the shapes are an empty (n_channels, 0) array."""
    from modal.identification._stabilisation import _select_modes

    poles, pole_shapes = _pole_table([1.0, 2.0, 3.0], [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    labels, modes, reps = _select_modes(poles, pole_shapes, cluster_distance=0.02, min_poles=3)
    assert modes.empty and reps.shape == (2, 0) and not labels.any()
    from modal.identification._stabilisation import MODE_COLUMNS

    assert list(modes.columns) == list(MODE_COLUMNS) and all(modes.dtypes == float)


def test_stabilisation_reports_progress_per_order():
    """progress(done, total) after each order: (1, 6), ..., (6, 6) for orders 2..12."""
    acc, dt, _ = ambient_beam(duration_s=30)
    r = modal.correlations(modal.detrend(acc), 81)
    calls = []
    modal.stabilisation(r, dt, 12, rows=40, cols=40, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(i, 6) for i in range(1, 7)]


def _hand_made_diagram():
    """A Stabilisation built by hand for the figure: six poles of orders 2, 4
    and 6, one of each group exactly at fmax = 5 Hz and one above it; modes
    at 2, 5 (= fmax) and 6 Hz; a spectrum on a 0.5 Hz grid up to 10 Hz."""
    import pandas as pd

    from modal.identification._stabilisation import Stabilisation

    poles = pd.DataFrame({"order": [2, 2, 4, 4, 6, 6], "freq_hz": [1.0, 2.0, 2.0, 3.0, 5.0, 6.0],
                          "stable": [False, True, True, False, True, True], "mode": [0, 0, 1, 0, 2, 3]})
    modes = pd.DataFrame({"freq_hz": [2.0, 5.0, 6.0]})
    hz = np.linspace(0.0, 10.0, 21)
    return Stabilisation(modes, np.zeros((2, 3)), poles, np.zeros((6, 2)), np.ones(3), hz, 1.0 + hz**2)


def test_stabilisation_figure_draws_each_group_up_to_fmax():
    """What a reader takes from the diagram: every pole up to fmax (inclusive)
    in grey, the stable ones and those in a mode drawn again over them, a line
    per mode up to fmax, the spectrum over the same band on a log axis behind
    the poles (whose background is transparent), the axis labels and title;
    without fmax, the whole spectrum's band. Colours and sizes are not pinned."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from modal.measured import stabilisation_figure

    result = _hand_made_diagram()
    fig, ax = plt.subplots()
    assert result.plot(fmax=5.0, title="Palisaden", ax=ax) is fig
    assert ax.get_xlim() == (0.0, 5.0)
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_title()) == ("frequency (Hz)", "model order", "Palisaden")
    groups = {c.get_label(): np.asarray(c.get_offsets()) for c in ax.collections}
    assert list(groups) == ["pole", "stable", "in a mode"]
    np.testing.assert_array_equal(groups["pole"], [[1, 2], [2, 2], [2, 4], [3, 4], [5, 6]])
    np.testing.assert_array_equal(groups["stable"], [[2, 2], [2, 4], [5, 6]])
    np.testing.assert_array_equal(groups["in a mode"], [[2, 4], [5, 6]])
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["pole", "stable", "in a mode"]
    np.testing.assert_array_equal([line.get_xdata() for line in ax.lines], [[2, 2], [5, 5]])
    (spectrum_ax,) = [other for other in fig.axes if other is not ax]
    (spectrum,) = spectrum_ax.lines
    np.testing.assert_array_equal(spectrum.get_xdata(), result.spectrum_hz[:11])
    np.testing.assert_array_equal(spectrum.get_ydata(), result.spectrum[:11])
    assert spectrum_ax.get_yscale() == "log" and spectrum_ax.get_ylabel() == "amplitude spectrum"
    assert len(spectrum_ax.get_yticks()) == 0  # arbitrary units: no scale
    assert ax.get_zorder() > spectrum_ax.get_zorder() and not ax.patch.get_visible()
    plt.close(fig)

    fig = stabilisation_figure(result)
    ax, spectrum_ax = fig.axes
    assert ax.get_xlim() == (0.0, 10.0) and ax.get_title() == ""
    assert len(ax.collections[0].get_offsets()) == 6 and len(ax.lines) == 3
    assert len(spectrum_ax.lines[0].get_xdata()) == 21
    plt.close(fig)
    with pytest.raises(ValueError, match="^result must be a Stabilisation, got dict"):
        stabilisation_figure({"poles": None})
    with pytest.raises(ValueError, match="^fmax must"):
        stabilisation_figure(result, fmax=0.0)


def _rank_deficient_decay(rank, n_samples=300):
    """Two channels of (rank - 1) / 2 damped cosines and one real exponential
    per channel pair: H(0) has exactly ``rank`` (odd) non-zero singular values."""
    k = np.arange(n_samples)
    y = 0.5 * (0.9**k)[:, None] * np.array([1.0, 2.0])
    for j in range((rank - 1) // 2):
        y = y + 0.97**k[:, None] * np.cos((0.3 + 0.4 * j) * k[:, None] + np.array([0.0, 1.0 + j]))
    return y


def test_stabilisation_stops_at_the_numerical_rank():
    """H(0) of rank 1 (one real exponential): no order is computed, and the
    empty diagram keeps its columns and dtypes; rank 5: orders 2 and 4 only
    (rank - rank % 2); rank exactly max_order: no rank warning."""
    import warnings

    def run(y, max_order):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = modal.stabilisation(y, 0.01, max_order, rows=10)
        return result, [w for w in caught if issubclass(w.category, modal.ModalWarning)]

    result, caught = run((0.9 ** np.arange(200))[:, None] * np.array([1.0, 2.0]), 4)
    assert [str(w.message) for w in caught] == [
        "H(0) has numerical rank 1: orders above it are not computed",
        "no stable physical poles cluster into a mode: raise max_order or rows, or relax the criteria"]
    from modal.identification._stabilisation import MODE_COLUMNS, POLE_COLUMNS

    assert list(result.poles.columns) == POLE_COLUMNS + ["physical", "mode"] and result.poles.empty
    assert result.poles["order"].dtype.kind == "i" and result.poles["mode"].dtype.kind == "i"
    assert all(result.poles[c].dtype == float for c in ("freq_hz", "damping", "mpc", "mamc"))
    assert all(result.poles[c].dtype == bool for c in POLE_COLUMNS[5:] + ["physical"])
    assert result.pole_shapes.shape == (0, 2) and result.shapes.shape == (2, 0)
    assert list(result.modes.columns) == MODE_COLUMNS and result.modes.empty

    result, caught = run(_rank_deficient_decay(5), 8)
    assert "H(0) has numerical rank 5:" in str(caught[0].message)
    assert sorted(result.poles["order"].unique()) == [2, 4]
    result, caught = run(_rank_deficient_decay(5)[:, :1] - 0.5 * 0.9 ** np.arange(300)[:, None], 4)
    assert not any("numerical rank" in str(w.message) for w in caught)
    assert sorted(result.poles["order"].unique()) == [2, 4]


def test_stabilisation_checks_arguments_at_the_boundary():
    """Refusals name the argument; the bounds themselves are accepted:
    max_order = 2, start = 0, one column (the default cols = n_samples - start
    - rows), max_order equal to the smaller side of H(0)."""
    import warnings

    rng = np.random.default_rng(1)
    r = rng.standard_normal((2, 50, 3))
    for kwargs, message in [
        ({"y": np.full((50, 2), np.nan)}, "^y contains NaN"),
        ({"dt": 0.0}, "^dt must"),
        ({"max_order": 1}, "^max_order must be an integer >= 2"),
        ({"rows": 0}, "^rows must"),
        ({"start": -1}, "^start must be an integer >= 0"),
        ({"cols": 0}, "^cols must"),
        ({"fmax": 0.0}, "^fmax must"),
        ({"criteria": {"mac_min": 0.9}}, "^criteria must be a StabilityCriteria, got dict$"),
        ({"rows": 45, "start": 5}, r"^rows = 45 from start = 5 leaves no column of the 50-sample data$"),
        ({"max_order": 32, "rows": 10, "cols": 20}, r"^max_order = 32 exceeds the smaller dimension of H\(0\) "
                                                     r"\(30 x 40\): reduce max_order or enlarge rows/cols$"),
    ]:
        args = {"y": r, "dt": 0.1, "max_order": 4, "rows": 10} | kwargs
        with pytest.raises(ValueError, match=message):
            modal.stabilisation(**args)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        one_column = modal.stabilisation(r, 0.1, 2, rows=44, start=5)  # H(0): 132 x 2
        assert one_column.singular_values.size == 2
        full = modal.stabilisation(r, 0.1, 30, rows=10, cols=20, start=0)  # H(0): 30 x 40
        assert full.poles["order"].max() == 30
        # the default cols is every column the data allow from start on
        default = modal.stabilisation(r, 0.1, 4, rows=10, start=7)
        explicit = modal.stabilisation(r, 0.1, 4, rows=10, start=7, cols=33)
    np.testing.assert_array_equal(default.singular_values, explicit.singular_values)
    np.testing.assert_allclose(default.singular_values, np.linalg.svd(modal.hankel(r, 10, 33, 7), compute_uv=False),
                               rtol=1e-12)


def test_stabilisation_quality_criteria_and_outputs(monkeypatch):
    """On noisy correlations off the thesis geometry: ``physical`` is exactly
    the documented quality criteria (each of which excludes some poles), only
    physical stable poles join modes, modes lie below fmax, the
    default min_poles is 40 % of the orders (at least 3), and the result keeps
    the singular values of H(0), the criteria and the spectrum of the data
    from ``start`` on."""
    import sys
    import warnings

    from modal.identification._stabilisation import _mean_spectrum

    stab_module = sys.modules["modal.identification._stabilisation"]
    seen = []
    real_select = stab_module._select_modes
    monkeypatch.setattr(stab_module, "_select_modes",
                        lambda *args: seen.append(args[2:]) or real_select(*args))
    acc, dt, f_exact = ambient_beam(duration_s=120, seed=5)
    acc = acc + 0.05 * acc.std(axis=0) * np.random.default_rng(2).standard_normal(acc.shape)
    data = modal.correlations(modal.detrend(acc), 81)
    criteria = modal.StabilityCriteria(max_damping=0.05, mpc_min=0.8, mamc_min=0.6, cluster_distance=0.03)
    fmax = 0.5 * (f_exact[1] + f_exact[2])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        result = modal.stabilisation(data, dt, 40, 40, start=3, fmax=fmax, criteria=criteria)
    poles = result.poles
    parts = {
        "complex": ~poles["real_pole"],
        "positive damping": poles["damping"] > 0,
        "below max_damping": poles["damping"] < criteria.max_damping,
        "mpc": poles["mpc"] >= criteria.mpc_min,
        "mamc": poles["mamc"] >= criteria.mamc_min,
        "below fmax": poles["freq_hz"] < fmax,
    }
    expected = np.logical_and.reduce(list(parts.values()))
    np.testing.assert_array_equal(poles["physical"], expected)
    for name, part in parts.items():
        assert (~part).any(), f"no pole is excluded by {name}"
    assert (poles["mode"] > 0).sum() > 0 and np.all(poles.loc[poles["mode"] > 0, ["stable", "physical"]])
    np.testing.assert_allclose(result.modes["freq_hz"], f_exact[:2], rtol=0.01)
    assert seen == [(criteria.cluster_distance, 8)]  # 20 orders: ceil(0.4 * 20)
    assert result.criteria == criteria
    h0 = modal.hankel(data, 40, 81 - 3 - 40, 3)  # every column from start = 3 on
    np.testing.assert_allclose(result.singular_values, np.linalg.svd(h0, compute_uv=False), rtol=1e-10)
    hz, spectrum = _mean_spectrum(data[:, 3:], dt)
    np.testing.assert_array_equal(result.spectrum_hz, hz)
    np.testing.assert_allclose(result.spectrum, spectrum, rtol=1e-12)

    seen.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        modal.stabilisation(data, dt, 10, 40)  # 5 orders: at least 3
        modal.stabilisation(data, dt, 10, 40, criteria=modal.StabilityCriteria(min_poles=2))
    assert [s[1] for s in seen] == [3, 2]


def _spy_on_stabilisation(monkeypatch):
    """Replace the stabilisation that identify_record calls by a recorder of
    its arguments (identify_record's own work is what is tested)."""
    import sys

    calls = []

    def spy(data, dt, max_order, rows, **kwargs):
        calls.append(dict(data=data, dt=dt, max_order=max_order, rows=rows, **kwargs))
        return "diagram"

    monkeypatch.setattr(sys.modules["modal.measured._pipeline"], "stabilisation", spy)
    return calls


def test_identify_record_ambient_preprocessing(monkeypatch):
    """Ambient: detrend, decimate by floor(fs / (2.5 fmax)) when that is at
    least 2, high-pass, then NExT correlations with 2 rows + 1 lags from the
    chosen references; rows default to max(60, ceil(2 max_order / n_channels));
    the log names each step with its numbers."""
    calls = _spy_on_stabilisation(monkeypatch)
    rng = np.random.default_rng(8)
    acc = rng.standard_normal((3000, 3)) + 0.01 * np.arange(3000)[:, None]
    criteria, progress, lines = modal.StabilityCriteria(min_poles=4), (lambda done, total: None), []
    # fs = 100 Hz, fmax = 15 Hz: q = floor(100 / 37.5) = 2
    out = modal.identify_record(acc, 0.01, "ambient", max_order=10, fmax=15.0, refs=[1], highpass_hz=0.5,
                                criteria=criteria, log=lines.append, progress=progress)
    assert out == ("diagram", 0.02)
    assert lines == ["decimating by 2: 100 Hz -> 50 Hz", "high-pass at 0.5 Hz",
                     "correlations: 121 lags, references [1]", "stabilisation: orders 2 ... 10, 60 block rows"]
    (call,) = calls
    y, dt = modal.decimate(modal.detrend(acc), 0.01, 2)
    expected = modal.correlations(modal.zero_phase_filter(y, dt, highpass_hz=0.5), 121, refs=[1])
    data = call.pop("data")
    assert data.shape == (1, 121, 3)
    np.testing.assert_allclose(data, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    assert call == dict(dt=0.02, max_order=10, rows=60, cols=None, start=0, fmax=15.0, criteria=criteria,
                        progress=progress)

    calls.clear()
    # fmax = 30 Hz: q = floor(100 / 75) = 1, no decimation; 2 * 100 / 3 channels: 67 rows
    assert modal.identify_record(acc, 0.01, "ambient", max_order=100, fmax=30.0)[1] == 0.01
    assert modal.identify_record(acc, 0.01, "ambient", log=lines.append) == ("diagram", 0.01)
    assert lines[-2:] == ["correlations: 121 lags, references [0, 1, 2]",
                          "stabilisation: orders 2 ... 60, 60 block rows"]
    assert [(c["rows"], c["max_order"], c["data"].shape) for c in calls] == [(67, 100, (3, 135, 3)),
                                                                             (60, 60, (3, 121, 3))]
    expected = modal.correlations(modal.detrend(acc), 121)
    np.testing.assert_allclose(calls[1]["data"], expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    # the lags may fill half the record: 751 of 1502 samples, not 753
    assert modal.identify_record(acc[:1502], 0.01, "ambient", rows=375)[0] == "diagram"
    with pytest.raises(ValueError, match="^rows = 376 needs 753 lags, more than half the 1502-sample record"):
        modal.identify_record(acc[:1502], 0.01, "ambient", rows=376)


def test_identify_record_free_decay_window(monkeypatch):
    """Free decay: the record from decay_start on, at most 10 rows columns
    (fewer when the decay is shorter), down to a single column."""
    calls = _spy_on_stabilisation(monkeypatch)
    rng = np.random.default_rng(9)
    k = np.arange(800)
    decay = 0.995**k[:, None] * np.cos(np.array([0.2, 0.35]) * k[:, None])
    acc = np.vstack([0.01 * rng.standard_normal((200, 2)), decay])
    start = modal.decay_start(modal.detrend(acc))
    assert start == 200
    lines = []
    modal.identify_record(acc, 0.01, "free_decay", rows=50, log=lines.append)
    assert lines == ["free decay from sample 200 (t = 2 s)", "stabilisation: orders 2 ... 60, 50 block rows"]
    modal.identify_record(acc, 0.01, "free_decay", rows=80)
    modal.identify_record(acc, 0.01, "free_decay", rows=799)
    assert [(c["rows"], c["cols"], c["start"]) for c in calls] == [(50, 500, 200), (80, 720, 200), (799, 1, 200)]
    np.testing.assert_allclose(calls[0]["data"], modal.detrend(acc))
    with pytest.raises(ValueError, match="^rows = 800: the decay after sample 200 is too short; reduce rows$"):
        modal.identify_record(acc, 0.01, "free_decay", rows=800)


def test_identify_record_refusals_name_the_argument(monkeypatch):
    calls = _spy_on_stabilisation(monkeypatch)
    acc = np.random.default_rng(10).standard_normal((1000, 2))
    for kwargs, message in [({"dt": 0.0}, "^dt must"), ({"max_order": 1}, "^max_order must be an integer >= 2"),
                            ({"rows": 0}, "^rows must"), ({"fmax": 0.0}, "^fmax must"),
                            ({"fmax": 50.0}, "^fmax = 50.0 Hz must be below the Nyquist frequency 50 Hz$")]:
        with pytest.raises(ValueError, match=message):
            modal.identify_record(acc, **({"dt": 0.01, "excitation": "ambient", "rows": 20} | kwargs))
    assert modal.identify_record(acc, 0.01, "ambient", max_order=2, rows=20, fmax=49.9)[1] == 0.01
    assert calls[0]["max_order"] == 2


def test_mean_spectrum_of_a_spectral_null_is_zero_not_nan():
    """Six samples whose tapered values are 1, -1, 0, ...: their sum, the
    spectrum at 0 Hz, is zero; rounding in the autocorrelation route leaves
    the power there at -2e-16, which must read as 0, not as NaN."""
    import warnings

    from modal.identification._stabilisation import _mean_spectrum

    taper = np.hanning(12)[6:]
    y = np.zeros((1, 6, 1))
    y[0, :2, 0] = np.array([1.0, -1.0]) / taper[:2]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        freqs, spectrum = _mean_spectrum(y, 0.01)
    assert np.all(np.isfinite(spectrum)) and spectrum[0] <= 1e-7 * spectrum.max()
    np.testing.assert_allclose(spectrum, np.abs(np.fft.rfft(y[0, :, 0] * taper, n=8192)) / 6, atol=1e-7)


def test_select_modes_joins_groups_by_average_linkage():
    """Three poles of one shape at 1.00, 1.01 and 1.02 Hz (distances 0.0099,
    0.0098 and 0.0196), cluster distance 0.012: 1.01 and 1.02 Hz join; 1.00
    Hz is 0.0147 from them on average, so it stays out (single linkage, or a
    distance matrix shrunk by 2/3, would join all three)."""
    from modal.identification._stabilisation import _select_modes

    poles, pole_shapes = _pole_table([1.0, 1.01, 1.02], [[1.0, 2.0]] * 3)
    labels, modes, _ = _select_modes(poles, pole_shapes, cluster_distance=0.012, min_poles=2)
    np.testing.assert_array_equal(labels, [0, 1, 1])
    assert modes["n_poles"].tolist() == [2] and modes["freq_hz"].iloc[0] == pytest.approx(1.015, rel=1e-12)


def test_select_modes_numbers_modes_by_mean_frequency():
    """Modes are numbered by their members' mean frequency, not by a sum that
    grows with the number of poles: five poles near 1 Hz are mode 1 and two
    near 2 Hz mode 2 (the sums, 5 and 4 Hz, or sums times counts, 25 and 8,
    would order them the other way)."""
    from modal.identification._stabilisation import _select_modes

    freqs = [2.0, 2.001, 1.0, 1.001, 0.999, 1.0005, 0.9995]
    shapes = [[0.0, 1.0, 1.0]] * 2 + [[1.0, 0.0, 0.5]] * 5
    poles, pole_shapes = _pole_table(freqs, shapes)
    labels, modes, reps = _select_modes(poles, pole_shapes, cluster_distance=0.01, min_poles=2)
    np.testing.assert_array_equal(labels, [2, 2, 1, 1, 1, 1, 1])
    np.testing.assert_array_equal(modes["n_poles"], [5, 2])
    np.testing.assert_allclose(modes["freq_hz"], [1.0, 2.0005], rtol=1e-12)
    np.testing.assert_array_equal(reps.T, [[1.0, 0.0, 0.5], [0.0, 1.0, 1.0]])


def test_select_modes_one_pole_modes_have_nan_spread_silently():
    """min_poles = 1: two distant poles are two one-pole modes, whose sample
    standard deviations (ddof = 1) are NaN without a floating-point warning;
    their means and shapes are the poles' own."""
    import warnings

    from modal.identification._stabilisation import _select_modes

    poles, pole_shapes = _pole_table([3.0, 1.0], [[1.0, 0.0], [0.0, 1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        labels, modes, reps = _select_modes(poles, pole_shapes, cluster_distance=0.02, min_poles=1)
    np.testing.assert_array_equal(labels, [2, 1])
    np.testing.assert_array_equal(modes["n_poles"], [1, 1])
    np.testing.assert_array_equal(modes["freq_hz"], [1.0, 3.0])
    np.testing.assert_array_equal(modes["damping"], poles["damping"][[1, 0]])
    assert modes["freq_std_hz"].isna().all() and modes["damping_std"].isna().all()
    np.testing.assert_array_equal(reps, [[0.0, 1.0], [1.0, 0.0]])
