"""Tests from a mutation run of the OMA work (branch oma): each pins down a
behaviour of the changed functions that no other test checked, found by a
surviving mutant (named in the test's docstring)."""

import re

import numpy as np
import pytest

import modal
from modal.measured import _pipeline
from modal.signals import _correlation


# --- lowest_peak_hz: the spectral peak that sets rows and decimation without fmax ---


def fake_welch(monkeypatch, spectra, df):
    """Make scipy.signal.welch return ``spectra[c]`` (on bins ``k df``) for
    channel ``c``, in call order; return the list of ``nperseg`` it was asked for."""
    import scipy.signal

    asked, calls = [], iter(spectra)

    def welch(x, fs, nperseg):
        asked.append(nperseg)
        power = np.asarray(next(calls), dtype=float)
        return df * np.arange(len(power)), power

    monkeypatch.setattr(scipy.signal, "welch", welch)
    return asked


def bumps(n_bins, peaks, floor=1.0):
    """A flat spectrum ``floor`` with single-bin peaks ``{bin: height}``."""
    power = np.full(n_bins, floor)
    for k, height in peaks.items():
        power[k] = height
    return power


def test_lowest_peak_needs_six_db_of_prominence(monkeypatch):
    """A peak 5.7 dB above its surroundings is not one, 6.5 dB is (the
    documented default ``prominence_db=6``); the lowest such peak wins.
    (lowest_peak_hz mutants: prominence 7 dB, dB scaled by 11, 10 / log10.)"""
    y = np.zeros((100000, 1))
    fake_welch(monkeypatch, [bumps(200, {16: 10**0.57, 32: 10**0.65, 48: 10.0})], df=0.125)
    assert _pipeline.lowest_peak_hz(y, 0.01) == 4.0
    fake_welch(monkeypatch, [bumps(200, {16: 10**0.57, 48: 10.0})], df=0.125)
    assert _pipeline.lowest_peak_hz(y, 0.01) == 6.0


def test_lowest_peak_in_a_spectrum_with_empty_bins(monkeypatch):
    """Bins of zero power (a silent band) are far below any peak, not NaN."""
    fake_welch(monkeypatch, [bumps(200, {24: 1.0}, floor=0.0)], df=0.125)
    assert _pipeline.lowest_peak_hz(np.zeros((100000, 1)), 0.01) == 3.0


@pytest.mark.parametrize("k, expected", [(3, None), (4, 0.5), (5, 0.625)])
def test_lowest_peak_lies_above_three_bins(monkeypatch, k, expected):
    """A peak counts only strictly above three frequency bins (here the
    record's ten periods lie lower)."""
    fake_welch(monkeypatch, [bumps(200, {k: 100.0})], df=0.125)
    assert _pipeline.lowest_peak_hz(np.zeros((100000, 1)), 0.01) == expected


def test_lowest_peak_lies_above_ten_periods_per_record(monkeypatch):
    """64 samples at 100 Hz: a peak must lie above 10 / 0.64 s = 15.6 Hz
    (here three bins are lower): of peaks at 10 and 16 Hz, 16 Hz."""
    fake_welch(monkeypatch, [bumps(100, {20: 100.0, 32: 100.0})], df=0.5)
    assert _pipeline.lowest_peak_hz(np.zeros((64, 1)), 0.01) == 16.0


def test_lowest_peak_weighs_every_channel_alike(monkeypatch):
    """Each channel's spectrum is normalised to its maximum before the
    average: a channel 1e4 times weaker still shows its (lower) peak, and a
    silent channel (all zero) leaves the other's peak (no division by zero)."""
    weak = bumps(200, {16: 1e-8}, floor=1e-11)  # all below 1
    strong = bumps(200, {64: 1e-4}, floor=1e-6)
    fake_welch(monkeypatch, [weak, strong], df=0.125)
    assert _pipeline.lowest_peak_hz(np.zeros((100000, 2)), 0.01) == 2.0
    fake_welch(monkeypatch, [np.zeros(200), strong], df=0.125)
    assert _pipeline.lowest_peak_hz(np.zeros((100000, 2)), 0.01) == 8.0


@pytest.mark.parametrize("n, nperseg", [(64, 64), (255, 255), (256, 32), (2047, 128), (2048, 256)])
def test_lowest_peak_welch_segments(monkeypatch, n, nperseg):
    """Welch's segments: the largest power of two up to an eighth of the
    record, the whole record below 256 samples."""
    asked = fake_welch(monkeypatch, [bumps(40, {})], df=0.125)
    _pipeline.lowest_peak_hz(np.zeros((n, 1)), 0.01)
    assert asked == [nperseg]


def test_lowest_peak_of_a_sine_in_noise_is_its_frequency_in_hz():
    """A sine on bin 5 of Welch's 512-sample segments (4096 samples at
    100 Hz: bins of 100 / 512 Hz) in white noise 100 times weaker: the
    lowest peak is 5 x 100 / 512 = 0.9765625 Hz, at the rate dt gives (the
    noise's own peaks lie higher; only bin 4, the sine's main lobe, is
    lower and above three bins). The 64-sample sine below stands on
    round-off alone, whose ripples make peaks too."""
    t = 0.01 * np.arange(4096)
    y = np.sin(2 * np.pi * 0.9765625 * t) + 0.01 * np.random.default_rng(4).standard_normal(len(t))
    assert _pipeline.lowest_peak_hz(y[:, None], 0.01) == 0.9765625


def test_lowest_peak_of_short_and_silent_records():
    """From 64 samples on (a sine 16 times over the record: 25 Hz at
    100 Hz); None for 63 samples, and None when no peak stands out."""
    t = np.arange(64)
    assert _pipeline.lowest_peak_hz(np.sin(2 * np.pi * 16 * t / 64 + 0.3)[:, None], 0.01) == 25.0
    assert _pipeline.lowest_peak_hz(np.sin(2 * np.pi * 16 * t[:63] / 64)[:, None], 0.01) is None
    assert _pipeline.lowest_peak_hz(np.zeros((1000, 2)), 0.01) is None


# --- decimate: the stages, channel by channel ---


@pytest.mark.parametrize("block, widths", [(2**22, [2]), (5003, [1, 1]), (2 * 5003 - 1, [1, 1]), (2 * 5003, [2])])
def test_decimate_stages_channels_in_blocks(monkeypatch, block, widths):
    """Factors above 13 in stages, the largest divisor <= 13 first, a prime
    factor above 13 one stage; the channels are filtered in blocks of at most
    DECIMATE_BLOCK values (samples x channels), each block through all the
    stages, and every channel exactly as scipy's decimate (its default
    filter, zero phase) filters it alone."""
    import scipy.signal

    import modal.signals._filters as filters

    calls, scipy_decimate, sosfiltfilt = [], scipy.signal.decimate, scipy.signal.sosfiltfilt

    def spy(sos, x, **kwargs):
        q = next(q for q in range(2, 170) if np.array_equal(sos, scipy.signal.cheby1(8, 0.05, 0.8 / q, output="sos")))
        calls.append((x.shape[1], q))
        return sosfiltfilt(sos, x, **kwargs)

    monkeypatch.setattr(scipy.signal, "sosfiltfilt", spy)
    monkeypatch.setattr(filters, "DECIMATE_BLOCK", block)
    y = np.random.default_rng(5).standard_normal((5003, 2))
    expected = {1: [], 2: [2], 4: [4], 12: [12], 14: [7, 2], 17: [17], 26: [13, 2], 30: [10, 3], 34: [2, 17],
                169: [13, 13]}
    for factor, stages in expected.items():
        calls.clear()
        out, dt = modal.decimate(y, 0.002, factor)
        assert calls == [(w, q) for w in widths for q in stages], factor
        assert out.shape == (-(-5003 // factor), 2) and dt == pytest.approx(0.002 * factor, rel=1e-15)
        for c in range(2):
            x = y[:, c]
            for q in stages:
                x = scipy_decimate(x, q, zero_phase=True)
            np.testing.assert_array_equal(out[:, c], x)


# --- correlations: blocks ---


def direct_correlations(y, n_lags, refs):
    """R[r, k, c] = 1 / (m N) sum over sets and t of y_c(t + k) y_refs[r](t)."""
    m, n, l = y.shape
    out = np.zeros((len(refs), n_lags, l))
    for k in range(n_lags):
        out[:, k, :] = np.einsum("mtr,mtc->rc", y[:, : n - k, refs], y[:, k:, :])
    return out / (m * n)


@pytest.mark.parametrize("block_samples", [7, 20, 45, 50, 1000])
def test_correlations_in_blocks_equal_the_direct_sums(monkeypatch, block_samples):
    """Summed block by block (blocks shorter or longer than the lags, a
    last block cut short), the correlations equal the direct sums at every
    lag, the last one included."""
    monkeypatch.setattr(_correlation, "BLOCK_SAMPLES", block_samples)
    y = np.random.default_rng(11).standard_normal((2, 237, 3))
    refs = [2, 0]
    np.testing.assert_allclose(modal.correlations(y, 12, refs=refs), direct_correlations(y, 12, refs),
                               rtol=1e-10, atol=1e-12)


def test_correlations_of_many_channels():
    """12 channels, all of them references (the cross-spectra limit sets the
    block): the direct sums."""
    y = np.random.default_rng(12).standard_normal((1, 300, 12))
    np.testing.assert_allclose(modal.correlations(y, 5), direct_correlations(y, 5, list(range(12))),
                               rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("n_lags, refs, limit, block", [
    (10, [0], 10**9, 1000),  # BLOCK_SAMPLES
    (10, [0, 1], 8 * 2 * 4 * 300, 300),  # the cross-spectra bytes: 8 bytes x refs x channels
    (10, [1], 8 * 1 * 4 * 100, 100),
    (30, [0, 3], 8 * 2 * 4 * 100, 120),  # never fewer than four times the lags
])
def test_correlation_blocks_follow_the_memory_limits(monkeypatch, n_lags, refs, limit, block):
    """The blocks: BLOCK_SAMPLES samples, fewer when the summed cross-spectra
    would exceed CROSS_SPECTRA_BYTES, never fewer than 4 n_lags; each block's
    FFT is ``next_fast_len(block + n_lags)`` long."""
    import scipy.fft

    monkeypatch.setattr(_correlation, "BLOCK_SAMPLES", 1000)
    monkeypatch.setattr(_correlation, "CROSS_SPECTRA_BYTES", limit)
    lengths, rfft = [], scipy.fft.rfft
    monkeypatch.setattr(scipy.fft, "rfft", lambda x, n=None, axis=-1: lengths.append(n) or rfft(x, n=n, axis=axis))
    y = np.random.default_rng(13).standard_normal((1, 2500, 4))
    modal.correlations(y, n_lags, refs=refs)
    assert set(lengths) == {scipy.fft.next_fast_len(block + n_lags, real=True)}
    assert len(lengths) >= -(-2500 // block)


def test_correlations_with_an_odd_fft_length():
    """40 samples and 5 lags: the FFT is 45 samples long (odd); the inverse
    FFT is taken on that length."""
    y = np.random.default_rng(14).standard_normal((2, 40, 3))
    np.testing.assert_allclose(modal.correlations(y, 5), direct_correlations(y, 5, [0, 1, 2]), rtol=1e-10, atol=1e-12)


def test_correlations_refusals_name_the_argument():
    """As many lags as samples is allowed, one more is not; each refusal
    names what is wrong."""
    y = np.random.default_rng(15).standard_normal((1, 10, 3))
    assert modal.correlations(y, 10).shape == (3, 10, 3)
    with pytest.raises(ValueError, match=r"^n_lags = 11 exceeds the 10 samples"):
        modal.correlations(y, 11)
    with pytest.raises(ValueError, match=r"^n_lags must be an integer >= 1, got 0"):
        modal.correlations(y, 0)
    with pytest.raises(ValueError, match=r"^y contains NaN"):
        modal.correlations(np.full((1, 10, 2), np.nan), 3)
    for refs in ([[0, 1]], [0.5], []):
        with pytest.raises(ValueError, match=r"^refs must be a non-empty sequence of channel indices"):
            modal.correlations(y, 3, refs=refs)
    for refs in ([-1], [3], [1, 1]):
        with pytest.raises(ValueError, match=r"^refs must be distinct channel indices in 0 \.\.\. 2, got"):
            modal.correlations(y, 3, refs=refs)


# --- detrend: in blocks, in place on request ---


@pytest.mark.parametrize("n", [1, 2, 3, 50])
@pytest.mark.parametrize("kind", ["linear", "constant"])
def test_detrend_in_blocks_equals_scipy(monkeypatch, n, kind):
    """Subtracted in blocks (7 samples here, the last one cut short), the
    line or mean is scipy.signal.detrend's; one sample leaves zero, two
    samples lie on their line."""
    import scipy.signal

    from modal.signals import _filters

    monkeypatch.setattr(_filters, "DETREND_BLOCK", 7)
    y = np.random.default_rng(16).standard_normal((n, 3)) + 5.0
    np.testing.assert_allclose(modal.detrend(y, kind), scipy.signal.detrend(y, axis=0, type=kind), atol=1e-12)


def test_detrend_overwrite():
    """overwrite=True detrends a writeable float64 array in place (the same
    object returned); otherwise, or for another dtype, the input is untouched."""
    rng = np.random.default_rng(17)
    y = rng.standard_normal((100, 2)) + np.arange(100)[:, None]
    expected = modal.detrend(y)
    kept = y.copy()
    assert modal.detrend(y) is not y
    np.testing.assert_array_equal(y, kept)
    out = modal.detrend(y, overwrite=True)
    assert out is y
    np.testing.assert_allclose(y, expected, atol=1e-12)
    single = kept.astype(np.float32)
    out = modal.detrend(single, overwrite=True)
    assert out is not single and out.dtype == np.float64
    np.testing.assert_array_equal(single, kept.astype(np.float32))
    frozen = kept.copy()
    frozen.flags.writeable = False
    assert modal.detrend(frozen, overwrite=True) is not frozen


# --- stabilisation and mode selection ---


def one_mode_decay(n=800, dt=0.01):
    t = dt * np.arange(n)[:, None]
    y = np.exp(-0.02 * 2 * np.pi * 3 * t) * np.cos(2 * np.pi * 3 * t) * np.array([1.0, 0.6, -0.4])
    return y + 1e-5 * np.random.default_rng(20).standard_normal(y.shape), dt


def test_one_mode_table_types():
    """One mode: labels are integers, ``close`` is False (bool), ``close_mac``
    NaN (float); no candidate is a mode."""
    y, dt = one_mode_decay()
    result = modal.stabilisation(y, dt, 12, 40)
    assert len(result.modes) == 1
    assert result.poles["mode"].dtype.kind == "i"
    assert result.modes["close"].dtype == bool and not result.modes["close"][0]
    assert result.modes["close_mac"].dtype == float and np.isnan(result.modes["close_mac"][0])
    assert result.complex_shapes.dtype == complex
    assert not np.any(np.isclose(result.candidates["freq_hz"], 3.0, rtol=0.01))


def test_no_mode_warning_names_the_reason_at_the_caller():
    """No mode: a ModalWarning 'no mode selected: ...', pointing at the
    caller, not at stabilisation itself."""
    from modal.identification import _stabilisation

    y, dt = one_mode_decay()
    with pytest.warns(modal.ModalWarning, match=r"^no mode selected: ") as record:
        result = modal.stabilisation(y, dt, 12, 40, criteria=modal.StabilityCriteria(min_poles=100))
    assert result.modes.empty and result.complex_shapes.shape == (3, 0) and result.complex_shapes.dtype == complex
    ours = [w for w in record if str(w.message).startswith("no mode selected")]
    assert ours and all(w.filename != _stabilisation.__file__ for w in ours)


@pytest.mark.parametrize("limit, cols", [(8 * 61 * 3 * 2 * 50, 50), (1, 1)])
def test_default_columns_keep_hankel_within_the_byte_limit(monkeypatch, limit, cols):
    """Default columns: at most as many as keep H(0) = (rows l) x (cols m)
    within HANKEL_MAX_BYTES (8 (rows + 1) l m bytes per column), at least one."""
    from modal.identification import _stabilisation

    monkeypatch.setattr(_stabilisation, "HANKEL_MAX_BYTES", limit)
    y = np.random.default_rng(21).standard_normal((2, 400, 3))
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        result = modal.stabilisation(y, 0.01, 2, 60)
    assert len(result.singular_values) == min(60 * 3, cols * 2)


def pole_table(freqs, orders, shapes):
    n = len(freqs)
    table = {"order": np.asarray(orders), "freq_hz": np.asarray(freqs, float), "damping": np.full(n, 0.01),
             "mpc": np.ones(n), "mamc": np.ones(n), "mpd": np.zeros(n), "stable_freq": np.ones(n, bool),
             "physical": np.ones(n, bool)}
    return table, np.asarray(shapes, dtype=complex)


def test_select_modes_small_tables():
    """Two coincident poles make a mode when min_poles is 2; one pole makes
    nothing (an empty complex (n_channels, 0) shape array)."""
    from modal.identification._stabilisation import _select_modes

    criteria = modal.StabilityCriteria()
    table, shapes = pole_table([1.0, 1.0], [2, 4], [[1.0, 2.0, 0.5]] * 2)
    labels, modes, reps, _, _ = _select_modes(table, shapes, criteria, 2)
    assert len(modes) == 1 and labels.tolist() == [1, 1] and reps.shape == (3, 1)
    table, shapes = pole_table([1.0], [2], [[1.0, 2.0, 0.5]])
    labels, modes, reps, candidates, _ = _select_modes(table, shapes, criteria, 1)
    assert modes.empty and candidates.empty and labels.tolist() == [0]
    assert reps.shape == (3, 0) and reps.dtype == complex


def test_select_modes_medoid_is_the_central_pole():
    """The representative shape is the medoid's: the pole with the least
    summed distance to its cluster (here the middle frequency, not the first)."""
    from modal.identification._stabilisation import _select_modes

    e = np.eye(3)
    shapes = [e[0] + [0, 1e-4 * i, 0] for i in (0, 1, 2)]
    table, shapes = pole_table([1.003, 1.0, 0.998], [2, 4, 6], shapes)
    _, modes, reps, _, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 3)
    assert len(modes) == 1
    np.testing.assert_array_equal(reps[:, 0], shapes[1])


def test_select_modes_candidates_need_half_of_min_poles():
    """Clusters of 1, 2, 3 and 6 poles (far apart): with min_poles 4 the 6
    make a mode and the 2 and 3 candidates (at least half, at least 2);
    with min_poles 5 only the 3."""
    from modal.identification._stabilisation import _select_modes

    e = np.eye(4)
    freqs, orders, shapes = [], [], []
    for f, size, shape in ((1.0, 1, e[0]), (2.0, 2, e[1]), (3.0, 3, e[2]), (5.0, 6, e[3])):
        freqs += [f] * size
        orders += list(range(2, 2 * size + 1, 2))
        shapes += [shape] * size
    table, shapes = pole_table(freqs, orders, shapes)
    _, modes, _, candidates, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 4)
    assert modes["freq_hz"].tolist() == [5.0]
    assert candidates["freq_hz"].tolist() == [2.0, 3.0] and candidates["n_poles"].tolist() == [2, 3]
    _, modes, _, candidates, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 5)
    assert modes["freq_hz"].tolist() == [5.0] and candidates["freq_hz"].tolist() == [3.0]


def test_select_modes_cut_at_cluster_distance():
    """Two groups of poles at different orders, 2.4 % apart with the same
    shape, are two clusters at cluster_distance 0.02 (not joined: the merge
    distance is tiny)."""
    from modal.identification._stabilisation import _select_modes

    table, shapes = pole_table([1.0] * 3 + [1.025] * 3, [2, 4, 6, 8, 10, 12], [[1.0, 0.5]] * 6)
    criteria = modal.StabilityCriteria(merge_distance=1e-3)
    _, modes, _, _, _ = _select_modes(table, shapes, criteria, 3)
    assert modes["freq_hz"].tolist() == [1.0, 1.025]


def test_select_modes_same_order_poles_never_share_a_cluster():
    """Two groups of ten poles 0.01 % apart sharing one order: never one
    cluster, however many other pairs pull them together. With one shape (and
    within each other's half-power band) they are one mode whose second
    estimate is the smaller group; with shapes of MAC 0.8 two modes."""
    from modal.identification._stabilisation import _select_modes

    orders = list(range(2, 21, 2)) + list(range(20, 39, 2))
    freqs = [1.0] * 10 + [1.0001] * 9 + [1.0002]
    table, shapes = pole_table(freqs, orders, [[1.0, 0.5]] * 20)
    labels, modes, _, _, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 5)
    assert len(modes) == 1 and modes["n_poles"].tolist() == [10] and labels.tolist() == [1] * 20
    assert modes["freq_hz"][0] == 1.0 and modes["second_freq_hz"][0] == pytest.approx(1.00011)
    assert modes["second_damping"][0] == pytest.approx(0.01)
    table, shapes = pole_table(freqs, orders, [[1.0, 0.5]] * 10 + [[1.0, -0.1]] * 10)
    labels, modes, _, _, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 5)
    assert len(modes) == 2 and np.isnan(modes["second_freq_hz"]).all()
    for k in (1, 2):
        assert len(set(np.asarray(orders)[labels == k])) == (labels == k).sum()


def test_join_split_clusters_nearest_pair_among_many():
    """Clusters 1 and 3 (no common order, close) join; 1 and 2 share an
    order; 4 is far. Exactly the merge distance does not join."""
    from modal.identification._stabilisation import _join_split_clusters

    clusters = np.array([1, 1, 2, 2, 3, 3, 4, 4])
    order = np.array([2, 4, 2, 4, 6, 8, 10, 12])
    far = np.full((8, 8), 0.75)
    d = far.copy()
    d[np.ix_([0, 1], [4, 5])] = d[np.ix_([4, 5], [0, 1])] = 0.125
    np.fill_diagonal(d, 0)
    assert _join_split_clusters(clusters, order, d, 0.25).tolist() == [1, 1, 2, 2, 1, 1, 4, 4]
    assert _join_split_clusters(clusters, order, d, 0.125).tolist() == clusters.tolist()


def test_close_modes_strictly_within_close_rtol():
    """Two modes exactly close_rtol apart are not close; nearer, they are."""
    from modal.identification._stabilisation import _close_modes

    shapes = np.array([[1.0, 1.0], [0.0, 1.0]])
    close, close_mac = _close_modes(np.array([0.75, 1.0]), shapes, 0.25)
    assert close.tolist() == [False, False]
    np.testing.assert_allclose(close_mac, [0.5, 0.5])
    close, _ = _close_modes(np.array([0.76, 1.0]), shapes, 0.25)
    assert close.tolist() == [True, True]


# --- identify_record: settings from the record ---


def ambient_record(fs=128, seconds=60, seed=22):
    rng = np.random.default_rng(seed)
    return rng.standard_normal((fs * seconds, 2)), 1 / fs


@pytest.mark.parametrize("low, max_order, lines, dt_factor", [
    (None, 10, ["no spectral peak found: 60 block rows, no decimation"], 1),
    (None, 80, ["no spectral peak found: 80 block rows, no decimation"], 1),
    (0.75, 10, ["lowest spectral peak 0.75 Hz: 86 block rows span 1.34 s (1 period of it), decimated by 2 to 64 Hz "
                "(set --fmax and --rows to choose)"], 2),
    (3.0, 10, ["lowest spectral peak 3 Hz: 43 block rows span 0.336 s (1 period of it) "
               "(set --fmax and --rows to choose)"], 1),
    (3.0, 100, ["lowest spectral peak 3 Hz: 100 block rows span 0.781 s (2.3 periods of it) "
                "(set --fmax and --rows to choose)"], 1),
    (0.4, 10, ["lowest spectral peak 0.4 Hz: 80 block rows span 2.5 s (1 period of it), decimated by 4 to 32 Hz "
               "(set --fmax and --rows to choose)"], 4),
    (20.0, 10, ["lowest spectral peak 20 Hz: 10 block rows span 0.0781 s (1.6 periods of it) "
                "(set --fmax and --rows to choose)"], 1),
])
def test_settings_from_the_lowest_peak(monkeypatch, low, max_order, lines, dt_factor):
    """Without fmax and rows: rows span AUTO_PERIODS periods of the lowest
    peak (at least 2 max_order / channels: at 20 Hz one period is 6.4 rows,
    2 x 10 / 2 = 10 rows), the record decimated to about AUTO_SAMPLES
    samples per period; the choice is logged and in the settings (the peak,
    the decimation, the rows)."""
    monkeypatch.setattr(_pipeline, "spectral_peaks",
                        lambda y, dt: (np.array([] if low is None else [low]), np.array([] if low is None else [20.0])))
    acc, dt = ambient_record()
    log, details = [], {}
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        _, dt_used = modal.identify_record(acc, dt, "ambient", max_order=max_order, log=log.append, details=details)
    assert dt_used == dt * dt_factor
    assert [line for line in log if line.startswith(("lowest spectral", "no spectral"))] == lines
    settings = details["settings"]
    assert (settings["lowest_peak_hz"], settings["decimation"]) == (low, dt_factor)
    assert settings["rows"] == int(re.search(r"(\d+) block rows", lines[0]).group(1))


@pytest.mark.parametrize("max_order, line", [
    (10, "lowest spectral peak 3 Hz: 128 block rows span 1 s (3 periods of it) (set --fmax and --rows to choose)"),
    (10, None), (140, "lowest spectral peak 3 Hz: 140 block rows span 1.09 s (3.3 periods of it) "
                      "(set --fmax and --rows to choose)")])
def test_a_free_decay_keeps_three_periods_and_sixty_rows(monkeypatch, max_order, line):
    """A free decay's rows span DECAY_PERIODS periods of the lowest peak and
    at least 60 and ``2 max_order / channels`` (the ambient rule was
    measured on ambient records only); at 8 Hz, 3 periods would be 9 rows: 60."""
    monkeypatch.setattr(_pipeline, "spectral_peaks", lambda y, dt: (np.array([3.0 if line else 8.0 / 3]), np.array([20.0])))
    acc, dt = ambient_record()
    acc = acc * np.exp(-np.arange(len(acc)) * dt / 20)[:, None]
    if line is None:
        acc, dt = acc[::16], dt * 16  # 8 Hz
    log = []
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        modal.identify_record(acc, dt, "free_decay", max_order=max_order, log=log.append)
    expected = line or "lowest spectral peak 2.667 Hz: 60 block rows span 7.5 s (20 periods of it) (set --fmax and --rows to choose)"
    assert [entry for entry in log if entry.startswith("lowest spectral")] == [expected]


def test_rows_given_with_fmax_are_kept():
    acc, dt = ambient_record(seconds=20)
    log = []
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        modal.identify_record(acc, dt, "ambient", max_order=4, fmax=20, rows=70, log=log.append)
    assert "stabilisation: orders 2 ... 4, 70 block rows" in log


def test_select_modes_spread_and_candidate_table():
    """The modes' spreads are sample standard deviations (ddof 1) over their
    poles; a one-pole mode (min_poles 1) has NaN spread, silently; the
    candidates table has its documented columns, by frequency from 0."""
    import warnings

    from modal.identification._stabilisation import CANDIDATE_COLUMNS, _select_modes

    e = np.eye(3)
    table, shapes = pole_table([1.0, 1.004, 1.002, 3.0, 3.003, 2.0], [2, 4, 6, 2, 4, 2], [e[0]] * 3 + [e[1]] * 2 + [e[2]])
    table["damping"] = np.array([0.01, 0.012, 0.014, 0.02, 0.021, 0.03])
    _, modes, _, candidates, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 3)
    assert modes["freq_hz"].tolist() == pytest.approx([1.002])
    assert modes["freq_spread_hz"][0] == pytest.approx(0.002, rel=1e-9)
    assert modes["damping_spread"][0] == pytest.approx(0.002, rel=1e-9)
    assert list(candidates.columns) == CANDIDATE_COLUMNS
    assert candidates.index.tolist() == [0] and candidates["freq_hz"][0] == pytest.approx(3.0015)
    assert candidates["damping"][0] == pytest.approx(0.0205)
    table["mpc"] = np.linspace(0.5, 1.0, 6)
    table["mamc"] = np.linspace(0.6, 0.9, 6)
    table["mpd"] = np.linspace(1.0, 6.0, 6)
    _, _, _, candidates, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 4)
    assert candidates["freq_hz"].tolist() == pytest.approx([1.002, 3.0015])
    assert candidates.index.tolist() == [0, 1]
    for name in ("mpc", "mamc", "mpd"):
        assert candidates[name].tolist() == pytest.approx([table[name][:3].mean(), table[name][3:5].mean()])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, modes, _, _, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 1)
    assert modes["n_poles"].tolist() == [3, 1, 2] and np.isnan(modes["freq_spread_hz"][1])


def test_gram_pays_follows_the_documented_operation_counts():
    """The Gram route where the thin SVD costs at least GRAM_MIN_FLOPS and
    the Gram route (a^2 b + 2 a^3 + 4 a b k + 2 b k^2) less than half of the
    SVD (6 a^2 b + 10 a^3), a <= b the sides, k the order (< a)."""
    from modal.identification._era_kernels import GRAM_MIN_FLOPS, gram_pays

    checked = 0
    for a in (20, 60, 100, 150, 200, 300, 500, 1000, 3000):
        for ratio in (1, 1.3, 2, 5, 30, 1000):
            b = int(a * ratio)
            for k in (2, 6, 12, 30, 60, 100, 200, 400, 900, 2999):
                svd = 6.0 * a * a * b + 10.0 * a**3
                gram = a * a * b + 2.0 * a**3 + 4.0 * a * b * k + 2.0 * b * k**2
                expected = k < a and svd >= GRAM_MIN_FLOPS and gram < svd / 2
                assert gram_pays((a, b), k) == expected == gram_pays((b, a), k), (a, b, k)
                checked += expected
    assert checked > 50


def test_gram_pays_at_its_boundaries():
    """The SVD at exactly GRAM_MIN_FLOPS (100 x 1500: 1e8) is enough; the
    Gram route at exactly half the SVD (200 x 1200, order 100) is not."""
    from modal.identification._era_kernels import gram_pays

    assert gram_pays((100, 1500), 2)
    assert not gram_pays((200, 1200), 100) and gram_pays((200, 1200), 99)


def test_select_modes_cuts_by_distance_and_sorts_candidates():
    """Two single poles 5.7 % apart (different orders) are two clusters,
    however few their links; candidates listed in reverse are numbered
    0, 1, 2 by frequency."""
    from modal.identification._stabilisation import _select_modes

    table, shapes = pole_table([1.0, 1.06], [2, 4], [[1.0, 0.5]] * 2)
    _, modes, _, _, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 1)
    assert modes["freq_hz"].tolist() == [1.0, 1.06]
    e = np.eye(3)
    freqs = [5.0, 5.0, 3.0, 3.0, 1.0, 1.0]
    table, shapes = pole_table(freqs, [2, 4, 2, 4, 2, 4], [e[2], e[2], e[1], e[1], e[0], e[0]])
    _, modes, _, candidates, _ = _select_modes(table, shapes, modal.StabilityCriteria(), 4)
    assert modes.empty
    assert candidates["freq_hz"].tolist() == [1.0, 3.0, 5.0] and candidates.index.tolist() == [0, 1, 2]


# --- complex shapes: mean phase deviation, normalisation, mixed quantities ---


def test_mean_phase_deviation_values():
    """0 for real shapes (round-off never makes it NaN) and for a zero shape;
    30 degrees for two equal entries 60 degrees apart (either magnitude),
    with a zero entry that weighs nothing, and for [2, 1j] (weights |phi|)."""
    from modal.identification._indicators import mean_phase_deviation

    rng = np.random.default_rng(23)
    real = rng.standard_normal((7, 40))
    np.testing.assert_array_equal(mean_phase_deviation(real), 0.0)
    turn = np.exp(1j * np.pi / 3)
    shapes = np.array([[0, 1, 0.5, 1, 2], [0, turn, 0.5 * turn, 0, 1j], [0, 0, 0, turn, 0]], dtype=complex)
    np.testing.assert_allclose(mean_phase_deviation(shapes), [0, 30, 30, 30, 30], atol=1e-9)


def test_normalise_complex_shapes_values():
    """Unit norm, the largest entry real and positive, phases kept; a zero
    column stays zero; real input comes back complex."""
    from modal.identification._result import normalise_complex_shapes

    shapes = np.array([[0.1, 0.0, 3.0], [-0.05j, 0.0, 1.0], [0.02, 0.0, -4.0]], dtype=complex)
    out = normalise_complex_shapes(shapes)
    np.testing.assert_allclose(out[:, 0], shapes[:, 0] / np.linalg.norm(shapes[:, 0]), rtol=1e-12)
    np.testing.assert_array_equal(out[:, 1], 0)
    np.testing.assert_allclose(out[:, 2], -shapes[:, 2] / np.linalg.norm(shapes[:, 2]), rtol=1e-12)
    rotated = normalise_complex_shapes(shapes * np.exp(0.7j))
    np.testing.assert_allclose(rotated, out, atol=1e-12)
    assert normalise_complex_shapes(np.array([[1.0], [2.0]])).dtype == complex


@pytest.mark.slow
def test_three_quantities_give_one_shape():
    """Displacement, velocity and acceleration on three of four channels:
    declared, the shapes are the displacement shapes (each channel divided
    by s^k, k its derivative order)."""
    from .test_mode_selection import chain, chain_free_decay, true_modes

    c = 0.0005 * chain()[2]
    mass, damping, stiffness = chain(c=c)
    f_true, _, shapes_true = true_modes(mass, damping, stiffness)
    dt = 1 / (8 * f_true[-1])
    disp, vel, acc = chain_free_decay(mass, damping, stiffness, dt, 4000, seed=4)
    mixed = np.column_stack([disp[:, 0], vel[:, 1], acc[:, 2], acc[:, 3]])
    result = modal.stabilisation(mixed, dt, 16, 40, quantities=["displacement", "velocity", "acceleration",
                                                                "acceleration"])
    assert len(result.modes) == 4
    np.testing.assert_array_less(0.9999, np.diag(modal.mac(result.complex_shapes, shapes_true)))


def test_correlations_blocks_as_long_as_the_channels(monkeypatch):
    """Blocks of 12 samples on 12 channels: each block's references are its
    own samples, not the samples beyond it."""
    monkeypatch.setattr(_correlation, "BLOCK_SAMPLES", 12)
    y = np.random.default_rng(24).standard_normal((1, 100, 12))
    np.testing.assert_allclose(modal.correlations(y, 3), direct_correlations(y, 3, list(range(12))),
                               rtol=1e-10, atol=1e-12)


def test_mean_phase_deviation_of_rotated_real_shapes_is_zero():
    """Real shapes turned by any phase lie on a line: MPD 0, never NaN (the
    cosines' round-off above 1 is clipped)."""
    from modal.identification._indicators import mean_phase_deviation

    rng = np.random.default_rng(25)
    shapes = rng.standard_normal((5, 3000)) * np.exp(1j * rng.uniform(0, 2 * np.pi, 3000))
    mpd = mean_phase_deviation(shapes)
    assert np.all(np.isfinite(mpd)) and np.max(mpd) < 1e-5
