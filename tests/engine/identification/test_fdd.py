"""Frequency domain decomposition, the spectral witness of `modal identify`:
the spectral density matrix's convention (a transposed or conjugated matrix
gives conjugated shapes), its singular values' peaks at the closed-form
frequencies of a simulated 2-DOF system, the support check and the auto-MAC;
and, on spectra built in closed form, the rules of the peaks, the support and
the EFDD bell bin by bin (the tests of the mutation run,
``benchmarks/mutation_witness.py``)."""

import warnings

import numpy as np
import pandas as pd
import pytest
import scipy.linalg
import scipy.signal

import modal


def two_dof(mass, damping, stiffness, n_samples, dt, seed=0):
    """Accelerations of a 2-DOF system under two independent white forces
    (exact zero-order-hold discretisation), its poles with positive
    imaginary part and their complex displacement shapes."""
    m, c, k = (np.asarray(a, dtype=float) for a in (mass, damping, stiffness))
    m_inv = np.linalg.inv(m)
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-m_inv @ k, -m_inv @ c]])
    b = np.vstack([np.zeros((2, 2)), m_inv])
    system = scipy.signal.cont2discrete((a, b, np.hstack([-m_inv @ k, -m_inv @ c]), m_inv), dt)
    forces = np.random.default_rng(seed).standard_normal((n_samples, 2))
    _, acc, _ = scipy.signal.dlsim(system[:4] + (dt,), forces)
    poles, vectors = np.linalg.eig(a)
    keep = poles.imag > 0
    order = np.argsort(poles[keep].imag)
    return acc, poles[keep][order], vectors[:2, keep][:, order]


MASS = np.diag([1.0, 1.5])
STIFFNESS = np.array([[60.0, -25.0], [-25.0, 45.0]])


def test_spectral_density_is_scipys_csd_in_the_convention_g_equals_y_y_hermitian():
    y = np.random.default_rng(1).standard_normal((4096, 3))
    y[:, 1] += 0.5 * np.roll(y[:, 0], 3)
    freq_hz, g = modal.spectral_density(y, 0.01, nperseg=256)
    for i in range(3):
        for j in range(3):
            _, expected = scipy.signal.csd(y[:, j], y[:, i], fs=100.0, nperseg=256)
            np.testing.assert_allclose(g[:, i, j], expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(g, np.conj(np.swapaxes(g, 1, 2)), atol=1e-15)
    assert freq_hz[1] == pytest.approx(100.0 / 256)


def test_spectral_density_phase_of_a_delayed_channel():
    """Channel 1 is channel 0 delayed by 4 samples: ``G_10 = E[Y_1 Y_0^*] =
    exp(-i 2 pi f tau) S_00`` (a transposed or conjugated matrix has the
    opposite phase)."""
    rng = np.random.default_rng(2)
    x = rng.standard_normal(2**15 + 4)
    dt, delay = 0.01, 4
    y = np.column_stack([x[delay:], x[:-delay]])
    freq_hz, g = modal.spectral_density(y, dt, nperseg=512)
    band = (freq_hz > 1) & (freq_hz < 10)  # 2 pi f tau < 2.5 rad: no wrapping
    np.testing.assert_allclose(np.angle(g[band, 1, 0]), -2 * np.pi * freq_hz[band] * delay * dt, atol=0.03)
    np.testing.assert_allclose(np.abs(g[band, 1, 0]), g[band, 0, 0].real, rtol=0.02)


def test_welch_segment_follows_the_record_length():
    assert modal.signals.welch_segment(36000) == 4096  # 36000 / 8 = 4500
    assert modal.signals.welch_segment(2**20) == 2**15  # capped
    assert modal.signals.welch_segment(1000) == 64 and modal.signals.welch_segment(2048) == 256
    assert modal.signals.welch_segment(40) == 40


def test_first_singular_value_peaks_at_the_closed_form_frequencies():
    """Proportional damping (zeta = 0.5 % at both modes): the peaks of the
    first singular value lie within 0.3 bin of the undamped natural
    frequencies sqrt(eig(K, M)) / 2 pi (an acceleration spectrum peaks at
    f_n / sqrt(1 - 2 zeta^2), 2.5e-5 higher; measured 0.2 bin at most over
    seeds), and the singular vector there is the mode shape."""
    omega2, phi = scipy.linalg.eigh(STIFFNESS, MASS)
    omega = np.sqrt(omega2)
    alpha, beta = np.linalg.solve([[1 / (2 * omega[0]), omega[0] / 2], [1 / (2 * omega[1]), omega[1] / 2]],
                                  [0.005, 0.005])
    acc, _, _ = two_dof(MASS, alpha * MASS + beta * STIFFNESS, STIFFNESS, 2**16, 0.05)
    assert modal.fdd(acc, 0.05).nperseg == 8192  # the default: 2**16 / 8
    spectrum = modal.fdd(acc, 0.05, nperseg=2048)
    assert spectrum.df == pytest.approx(20 / 2048) and spectrum.values.shape == (1025, 2)
    assert np.all(spectrum.values[:, 0] >= spectrum.values[:, 1])
    peaks = spectrum.peaks()
    first = peaks[peaks["sv_number"] == 1]
    closed_form = omega / (2 * np.pi)
    assert len(first) == 2, peaks
    np.testing.assert_allclose(first["freq_hz"], closed_form, atol=0.3 * spectrum.df)
    for k, b in enumerate(first["bin"]):
        vector = spectrum.vectors[b, :, 0]
        assert modal.mac(vector[:, None], phi[:, k:k + 1])[0, 0] > 0.999
        assert np.argmax(np.abs(vector)) == np.argmax(np.abs(phi[:, k]))  # not the other mode's shape
        assert np.abs(vector).max() == pytest.approx(vector[np.argmax(np.abs(vector))].real)  # largest real
    support = modal.spectral_support(spectrum, closed_form, phi, damping=[0.005, 0.005])
    assert support["spectral_support"].all() and (support["sv_number"] == 1).all()
    assert (support["sv_mac"] > 0.999).all()
    # EFDD from each bell: frequency within 0.3 % (measured 0.1-0.2 %), damping within a factor 1.6
    # (measured 0.75-1.3 over seeds and segment lengths: one 55-minute record).
    np.testing.assert_allclose(support["efdd_freq_hz"], closed_form, rtol=0.003)
    assert np.all((support["efdd_damping"] > 0.005 / 1.6) & (support["efdd_damping"] < 0.005 * 1.6))


def test_efdd_of_one_channel_gives_each_mode_its_own_bell():
    """One channel: every singular vector is alike (MAC 1), so only the
    level and the neighbouring peaks end a mode's bell; each mode's EFDD
    frequency is its own (within 0.5 %), not one frequency for all."""
    omega2, phi = scipy.linalg.eigh(STIFFNESS, MASS)
    omega = np.sqrt(omega2)
    alpha, beta = np.linalg.solve([[1 / (2 * omega[0]), omega[0] / 2], [1 / (2 * omega[1]), omega[1] / 2]],
                                  [0.01, 0.01])
    acc, _, _ = two_dof(MASS, alpha * MASS + beta * STIFFNESS, STIFFNESS, 2**15, 0.05, seed=2)
    spectrum = modal.fdd(acc[:, :1], 0.05, nperseg=2048)
    support = modal.spectral_support(spectrum, omega / (2 * np.pi), phi[:1], damping=[0.01, 0.01])
    assert support["spectral_support"].all()
    np.testing.assert_allclose(support["efdd_freq_hz"], omega / (2 * np.pi), rtol=0.005)


def test_first_singular_vector_is_the_complex_shape_not_its_conjugate():
    """Non-proportional damping (one dashpot) and close modes give complex
    shapes (MAC of a shape with its conjugate 0.90): the first singular
    vector at the lighter mode's peak is its shape, MAC 0.999; with the
    spectral matrix transposed (or conjugated) it would be the conjugate,
    MAC 0.91."""
    acc, poles, psi = two_dof(np.eye(2), [[0.5, 0.0], [0.0, 0.0]], [[45.0, -3.0], [-3.0, 50.0]], 2**16, 0.1, seed=1)
    freq_hz, zeta = np.abs(poles) / (2 * np.pi), -poles.real / np.abs(poles)
    assert np.diag(modal.mac(psi, psi.conj()))[1] < 0.92
    spectrum = modal.fdd(acc, 0.1)
    lighter = int(np.argmin(zeta))
    support = modal.spectral_support(spectrum, freq_hz, psi, damping=zeta)
    assert support.loc[lighter, "spectral_support"] and support.loc[lighter, "sv_number"] == 1
    assert support.loc[lighter, "sv_mac"] > 0.998
    conjugate = modal.spectral_support(spectrum, freq_hz, psi.conj(), damping=zeta)
    assert conjugate.loc[lighter, "sv_mac"] < 0.95


def test_a_mode_far_from_any_peak_has_no_support():
    omega2, phi = scipy.linalg.eigh(STIFFNESS, MASS)
    acc, _, _ = two_dof(MASS, 0.02 * STIFFNESS, STIFFNESS, 2**14, 0.05)
    spectrum = modal.fdd(acc, 0.05)
    f = np.sqrt(omega2) / (2 * np.pi)
    support = modal.spectral_support(spectrum, [f[0], 3.3], np.column_stack([phi[:, 0], phi[:, 1]]),
                                     damping=[0.01, 0.01])
    assert list(support["spectral_support"]) == [True, False]
    assert np.isnan(support.loc[1, "sv_peak_hz"]) and np.isnan(support.loc[1, "sv_mac"])
    assert support.loc[1, "sv_number"] == 0
    # The tolerance: two bins, or the half-power band f (1 +- zeta), zeta clipped at 10 %.
    df = spectrum.df
    tolerance = modal.identification._fdd.support_tolerance_hz(
        [1.0, 2.0, 2.0, 9.0, 3.0], [0.0, 0.3, np.nan, 0.01, 0.08], df)
    np.testing.assert_allclose(tolerance, [2 * df, 0.1 * 2.0, 2 * df, max(2 * df, 0.09), 0.24])
    # a missing damping (None, as a column of objects holds it) counts as NaN: bins only
    np.testing.assert_allclose(modal.identification._fdd.support_tolerance_hz([3.0, 3.0], [None, 0.05], df),
                               [2 * df, 0.15])


def rayleigh(zeta):
    """Damping matrix of MASS and STIFFNESS giving both modes the ratio ``zeta``."""
    omega = np.sqrt(scipy.linalg.eigh(STIFFNESS, MASS, eigvals_only=True))
    alpha, beta = np.linalg.solve([[1 / (2 * omega[0]), omega[0] / 2], [1 / (2 * omega[1]), omega[1] / 2]],
                                  [zeta, zeta])
    return alpha * MASS + beta * STIFFNESS


def test_a_heavily_damped_mode_is_supported_by_its_broad_peak():
    """Both modes damped 10 % (0.71 and 1.33 Hz, 27 minutes): each peak is
    judged within four half-power half-widths of its mode (the SDOF curve
    falls 12.3 dB there), so both are supported, near their frequencies. A
    fixed window of +-25 % of the frequency (the peaks' own rule,
    :meth:`SingularValueSpectrum.peaks`) sees neither: the old witness
    flagged such modes. Modes with no energy, 8 % damped at 0.3 and 2.5 Hz
    (the window then spans +-0.1 and +-0.8 Hz), are not supported."""
    acc, poles, psi = two_dof(MASS, rayleigh(0.1), STIFFNESS, 2**14, 0.05)
    freq_hz, zeta = np.abs(poles) / (2 * np.pi), -poles.real / np.abs(poles)
    spectrum = modal.fdd(acc, 0.05)
    support = modal.spectral_support(spectrum, freq_hz, psi, damping=zeta)
    assert support["spectral_support"].all()
    np.testing.assert_allclose(support["sv_peak_hz"], freq_hz, rtol=0.05)  # within the half-power band
    peaks = spectrum.peaks()
    assert not any(np.any(np.abs(peaks["freq_hz"] - f) <= 0.1 * f) for f in freq_hz)  # what the fixed window sees
    none = modal.spectral_support(spectrum, [0.3, 2.5], np.ones((2, 2)), damping=[0.08, 0.08])
    assert not none["spectral_support"].any()


def test_the_damping_is_a_ratio_not_percent():
    """A mode 6 % above a real one damped 1 %, with that damping: its
    half-power band (1 %) does not reach the real peak, so it has no support;
    damping read as percent (1 for 1 %) would clip to a 10 % band that does."""
    acc, poles, psi = two_dof(MASS, rayleigh(0.01), STIFFNESS, 2**14, 0.05)
    f = np.abs(poles[0]) / (2 * np.pi)
    spectrum = modal.fdd(acc, 0.05)
    support = modal.spectral_support(spectrum, [f, 1.06 * f], psi[:, [0, 0]], damping=[0.01, 0.01])
    assert list(support["spectral_support"]) == [True, False]
    assert support.loc[0, "sv_peak_hz"] == pytest.approx(f, abs=2 * spectrum.df)


def test_auto_mac_of_known_vectors():
    """Diagonal 1, symmetric, off-diagonal exact; ``[1, i]`` and its
    conjugate ``[1, -i]`` are orthogonal (MAC 0), which ``a^T b`` in place of
    ``a^H b`` would call identical (MAC 1)."""
    shapes = np.array([[1.0, 1.0, 1.0, 1.0, 2.0], [1j, -1j, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0]])
    matrix = modal.auto_mac(shapes)
    np.testing.assert_allclose(np.diag(matrix), 1.0)
    np.testing.assert_allclose(matrix, matrix.T)
    assert matrix[0, 1] == pytest.approx(0.0, abs=1e-15)
    assert matrix[0, 2] == pytest.approx(0.5)  # |1|^2 / (2 * 1)
    assert matrix[0, 3] == pytest.approx(0.5)  # |1 - i|^2 / (2 * 2)
    assert matrix[2, 3] == pytest.approx(0.5)
    assert matrix[2, 4] == pytest.approx(1.0)  # a multiple
    assert modal.auto_mac(np.empty((3, 0))).shape == (0, 0)
    np.testing.assert_allclose(modal.auto_mac(np.array([[1.0], [2j], [0.0]])), [[1.0]])  # one mode, not none
    with pytest.raises(ValueError, match="shapes must be"):
        modal.auto_mac(np.ones(3))


def test_refusals_name_the_argument():
    y = np.random.default_rng(3).standard_normal((100, 2))
    with pytest.raises(ValueError, match="^dt must"):
        modal.spectral_density(y, 0.0)
    with pytest.raises(ValueError, match="^nperseg = 200 is longer than the record"):
        modal.spectral_density(y, 0.01, nperseg=200)
    with pytest.raises(ValueError, match="^y must not contain NaN|^y "):
        modal.spectral_density(np.full((100, 2), np.nan), 0.01)
    spectrum = modal.fdd(y, 0.01)
    with pytest.raises(ValueError, match=r"^shapes must be \(n_channels, n_modes\) = \(2, 1\)"):
        modal.spectral_support(spectrum, [1.0], np.ones((3, 1)))


def test_support_is_judged_within_the_modes_own_window():
    """The prominence counts within four half-widths of the mode: a row
    claiming 0.2 % damping at the top of a 10 %-damped mode's broad peak
    (window +-8 bins, where that peak falls some 4 dB) is not supported,
    while the same frequency with the mode's own damping is; over the whole
    spectrum the peak would stand out for both."""
    acc, poles, psi = two_dof(MASS, rayleigh(0.1), STIFFNESS, 2**14, 0.05)
    spectrum = modal.fdd(acc, 0.05)
    own = modal.spectral_support(spectrum, np.abs(poles) / (2 * np.pi), psi, damping=-poles.real / np.abs(poles))
    assert own["spectral_support"].all()
    narrow = modal.spectral_support(spectrum, own["sv_peak_hz"].to_numpy(), psi, damping=[0.002, 0.002])
    assert not narrow["spectral_support"].any()


def test_of_several_supporting_maxima_the_nearest_counts():
    """Close modes (1.053 and 1.139 Hz, one dashpot): a row at 1.125 Hz
    whose band (+-10 %) holds the first singular value's peak at 1.139 Hz
    and the second's at 1.096 Hz (where the two cross) is supported by the
    nearer, 1.139 Hz."""
    acc, _, _ = two_dof(np.eye(2), [[0.5, 0.0], [0.0, 0.0]], [[45.0, -3.0], [-3.0, 50.0]], 2**16, 0.1, seed=1)
    spectrum = modal.fdd(acc, 0.1)
    index, sv_number, _ = spectrum.supporting_peak(1.125, 0.11)
    assert sv_number == 1 and spectrum.freq_hz[index] == pytest.approx(1.139, abs=2 * spectrum.df)
    index, sv_number, _ = spectrum.supporting_peak(1.10, 0.11)
    assert sv_number == 2 and spectrum.freq_hz[index] == pytest.approx(1.097, abs=2 * spectrum.df)



def test_spectral_supports_efdd_is_efdd_of_the_supporting_peak():
    """spectral_support computes the Hann window's autocorrelation once for
    all its modes: each mode's EFDD columns are exactly those of
    :func:`modal.efdd` at its supporting peak, its bell bounded half-way to
    the neighbouring peaks."""
    from modal.identification._fdd import support_tolerance_hz

    omega2, phi = scipy.linalg.eigh(STIFFNESS, MASS)
    omega = np.sqrt(omega2)
    alpha, beta = np.linalg.solve([[1 / (2 * omega[0]), omega[0] / 2], [1 / (2 * omega[1]), omega[1] / 2]],
                                  [0.01, 0.01])
    acc, _, _ = two_dof(MASS, alpha * MASS + beta * STIFFNESS, STIFFNESS, 2**15, 0.05, seed=2)
    spectrum = modal.fdd(acc, 0.05, nperseg=2048)
    freq_hz = omega / (2 * np.pi)
    support = modal.spectral_support(spectrum, freq_hz, phi, damping=[0.01, 0.01])
    assert support["spectral_support"].all() and support["efdd_freq_hz"].notna().all()
    bins = spectrum.peaks()["bin"].to_numpy()
    for k, tolerance in enumerate(support_tolerance_hz(freq_hz, [0.01, 0.01], spectrum.df)):
        here, sv_number, _ = spectrum.supporting_peak(freq_hz[k], tolerance)
        below, above = bins[bins < here], bins[bins > here]
        limits = ((here + below.max()) // 2 + 1 if below.size else 1,
                  (here + above.min()) // 2 if above.size else len(spectrum.freq_hz) - 1)
        assert (support["efdd_freq_hz"][k], support["efdd_damping"][k]) == modal.efdd(spectrum, here, sv_number,
                                                                                      limits)


def synthetic(db, df=0.125, vectors=None, nperseg=None):
    """A :class:`modal.SingularValueSpectrum` whose singular values are the
    curves ``db`` (n_freq, n_values) in dB (the first curve's top at 0 dB:
    :meth:`decibels` gives them back to round-off), ``df`` apart from 0 Hz,
    Welch segments of ``2 (n_freq - 1)`` samples unless given; the vectors
    (2 channels) ``e_k`` for the k-th value unless given."""
    db = np.asarray(db, dtype=float)
    n_freq, n_values = db.shape
    if vectors is None:
        vectors = np.broadcast_to(np.eye(2, n_values, dtype=complex), (n_freq, 2, n_values))
    return modal.SingularValueSpectrum(freq_hz=df * np.arange(n_freq), values=10 ** (db / 10),
                                       vectors=np.asarray(vectors), nperseg=nperseg or 2 * (n_freq - 1))


def test_peaks_skip_the_first_two_bins_keep_their_bounds_and_go_on():
    """A flat floor at -40 dB (df = 1/8 Hz): the first value peaks at bins 1
    (0 dB), 20 (-30 dB on a -33 dB shelf between dips: prominence 10 dB,
    height 3 dB above its median) 40 and 80 (-10 dB), the second at bin 2
    (-10 dB). Bin 1 is below the first two bins and bin 20 too low, both
    skipped, and the search goes on past them (a ``break`` would lose bins
    40 and 80); bin 2 counts (``index <= 2`` would drop it), a peak at
    exactly ``fmax`` or exactly ``height_db`` too. Each remaining peak stands
    30 dB above its troughs and its median, sorted by frequency and numbered
    from 0."""
    db = np.full((129, 2), -40.0)
    db[[1, 40, 80], 0] = [0.0, -10.0, -10.0]
    db[11:30, 0], db[[19, 20, 21], 0] = -33.0, [-40.0, -30.0, -40.0]
    db[2, 1] = -10.0
    spectrum = synthetic(db)
    peaks = spectrum.peaks()
    assert list(peaks["bin"]) == [2, 40, 80] and list(peaks["sv_number"]) == [2, 1, 1]
    assert list(peaks.index) == [0, 1, 2]
    np.testing.assert_allclose(peaks["freq_hz"], [0.25, 5.0, 10.0])
    for column, expected in (("db", -10.0), ("prominence_db", 30.0), ("height_db", 30.0)):
        np.testing.assert_allclose(peaks[column], expected, atol=1e-9)
    assert list(spectrum.peaks(fmax=10.0)["bin"]) == [2, 40, 80]
    assert list(spectrum.peaks(fmax=9.9)["bin"]) == [2, 40]
    exactly = float(peaks["height_db"][2])
    assert 80 in list(spectrum.peaks(height_db=exactly)["bin"])
    for name in ("prominence_db", "height_db"):
        with pytest.raises(ValueError, match=f"^{name} must"):
            spectrum.peaks(**{name: -1.0})


def test_peak_height_is_above_the_median_of_its_own_window():
    """V-shaped floors, a different slope either side, so that the median
    depends on every bin of the window. The first value peaks (0 dB) at
    20 Hz, bin 160: its window is +-40 bins (25 % of 20 Hz in 1/8 Hz bins),
    bins 120 ... 200, not the +-10 bins of a low peak. The second peaks at
    bin 5 (-10 dB): its window of +-10 bins is cut at bin 0, bins 0 ... 15.
    A window a bin short or long, shifted, or of the wrong width changes
    the median and so the height."""
    j = np.arange(257)
    db = np.empty((257, 2))
    db[:, 0] = np.where(j < 160, -40 + 0.2 * (160 - j), -40 + 0.3 * (j - 160))
    db[:, 1] = np.where(j < 5, -40 + 1.1 * (5 - j), np.minimum(-40 + 0.5 * (j - 5), -20.0))
    db[160, 0], db[5, 1] = 0.0, -10.0
    peaks = synthetic(db).peaks()
    assert list(peaks["bin"]) == [5, 160] and list(peaks["sv_number"]) == [2, 1]
    np.testing.assert_allclose(peaks["height_db"], [-10 - np.median(db[0:16, 1]), -np.median(db[120:201, 0])],
                               atol=1e-9)
    # by hand: the mean of -37 and -36.7 (8th and 9th of 16); 5 dB, the 41st of 0.2 a and 0.3 b (a, b = 1 ... 40)
    np.testing.assert_allclose(peaks["height_db"], [-10 + 36.85, 40 - 5.0], atol=1e-9)


def test_supporting_peak_bounds_window_and_ties():
    """Synthetic curves at -40 dB, df = 1/8 Hz, tolerance 1/4 Hz (two bins;
    the prominence window +-8 bins). The first value peaks at bin 2 (the
    lowest that counts), at bin 60 on a -5 dB shelf of bins 52 ... 68 (5 dB
    within +-8 bins, 40 dB a bin further: not enough, unless 5 dB are asked,
    an exact bound), and at bins 96 and 100, each exactly the tolerance from
    12.25 Hz (the bound counts; of the tie the first, the lower, wins). The
    second value alone peaks at bin 120: found after the first has no
    maximum there."""
    db = np.full((129, 2), -40.0)
    db[52:69, 0], db[[2, 60, 96, 100], 0] = -5.0, [0.0, 0.0, -10.0, -10.0]
    db[120, 1] = -10.0
    spectrum = synthetic(db)
    assert spectrum.supporting_peak(0.25, 0.25)[:2] == (2, 1)
    assert spectrum.supporting_peak(7.5, 0.25) is None
    shelf = spectrum.supporting_peak(7.5, 0.25, prominence_db=0.0)
    assert shelf[:2] == (60, 1) and shelf[2] == pytest.approx(5.0, abs=1e-9)
    assert spectrum.supporting_peak(7.5, 0.25, prominence_db=shelf[2]) == shelf
    assert spectrum.supporting_peak(12.25, 0.25)[:2] == (96, 1)
    assert spectrum.supporting_peak(15.0, 0.25)[:2] == (120, 2)


def test_fdd_default_segment_for_every_record_shape():
    """The default segment is :func:`modal.signals.welch_segment` of the
    samples for a one-dimensional record as for a single column (the same
    spectrum), down to a record of two samples (one segment); a record of
    one sample is refused by the spectral density, which names the reason,
    and so is a count of values below one."""
    y = np.random.default_rng(4).standard_normal(3000)
    column = modal.fdd(y[:, None], 0.01)
    flat = modal.fdd(y, 0.01)
    assert column.nperseg == flat.nperseg == modal.signals.welch_segment(3000) == 256
    np.testing.assert_array_equal(flat.values, column.values)
    assert modal.fdd(y[:2], 0.01).nperseg == 2
    with pytest.raises(ValueError, match="^y needs at least 2 samples"):
        modal.fdd(np.ones((1, 2)), 0.01)
    with pytest.raises(ValueError, match="^n_values must"):
        modal.fdd(y, 0.01, n_values=0)


def test_singular_vectors_are_the_eigenvectors_of_the_two_largest_values():
    """Three correlated channels: at every frequency the two kept values are
    the two largest eigenvalues of ``G`` (descending) and each vector
    satisfies ``G v = s v``, unit norm, its largest entry real and positive.
    The third (smallest) vector in place of the second, a conjugated or
    unrotated vector, would break one of these."""
    rng = np.random.default_rng(5)
    y = rng.standard_normal((4096, 3)) @ np.array([[1.0, 0.5, 0.2], [0.0, 1.0, 0.7], [0.0, 0.0, 1.0]])
    y[:, 2] += np.roll(y[:, 0], 2)
    spectrum = modal.fdd(y, 0.01, nperseg=128)
    _, g = modal.spectral_density(y, 0.01, nperseg=128)
    assert spectrum.values.shape == (65, 2) and spectrum.vectors.shape == (65, 3, 2)
    np.testing.assert_allclose(spectrum.values, np.linalg.eigvalsh(g)[:, ::-1][:, :2], rtol=1e-10)
    v = spectrum.vectors
    np.testing.assert_allclose(np.einsum("fij,fjk->fik", g, v), v * spectrum.values[:, None, :],
                               atol=1e-10 * spectrum.values.max())
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), 1.0, rtol=1e-12)
    largest = np.take_along_axis(v, np.argmax(np.abs(v), axis=1)[:, None, :], axis=1)
    np.testing.assert_allclose(largest.imag, 0.0, atol=1e-12)
    assert np.all(largest.real > 0)


def bells(modes, nperseg=1024):
    """One channel's spectrum (every vector alike, MAC 1) of ``modes``,
    pairs of frequency (Hz) and damping ratio, of equal static response,
    sampled at 12.8 Hz in segments of ``nperseg`` (``df = 1/80`` Hz by
    default, up to 6.4 Hz)."""
    f = 12.8 / nperseg * np.arange(nperseg // 2 + 1)
    s = sum(np.abs(fn**2 / (fn**2 - f**2 + 2j * zeta * fn * f)) ** 2 for fn, zeta in modes)
    return synthetic(10 * np.log10(s / s.max())[:, None], df=12.8 / nperseg, nperseg=nperseg)


#: 2.7 and 3.0125 Hz damped 1 %, 4.8 Hz damped 4 %: peaks at bins 216, 241 and 383.
THREE_BELLS = ((2.7, 0.01), (3.0125, 0.01), (4.8, 0.04))


def test_each_modes_efdd_bell_ends_half_way_to_the_neighbouring_peaks():
    """Three close bells in one channel, where only the limits end a bell:
    the lowest mode's runs from bin 1 to 228 (half-way to bin 241, rounded
    down), the middle one's from 229 (half-way to 216, plus one) to 312, the
    highest one's from 313 to the last bin, 512. spectral_support's EFDD is
    exactly that of these limits, and a limit one bin off (or two) gives
    another: the limits matter here. Each EFDD lies within 0.5 % of the
    mode's frequency and 10 % of its damping."""
    spectrum = bells(THREE_BELLS)
    assert list(spectrum.peaks()["bin"]) == [216, 241, 383]
    freq_hz, zeta = np.array(THREE_BELLS).T
    support = modal.spectral_support(spectrum, freq_hz, np.eye(2)[[0, 0, 0]].T, damping=zeta)
    assert support["spectral_support"].all() and np.allclose(support["sv_mac"], 1.0)
    for m, (peak, limits, off) in enumerate([(216, (1, 228), (1, 229)), (241, (229, 312), (227, 312)),
                                             (383, (313, 512), (313, 511))]):
        expected = modal.efdd(spectrum, peak, 1, limits)
        assert (support["efdd_freq_hz"][m], support["efdd_damping"][m]) == expected
        assert modal.efdd(spectrum, peak, 1, off) != expected
    np.testing.assert_allclose(support["efdd_freq_hz"], freq_hz, rtol=0.005)
    np.testing.assert_allclose(support["efdd_damping"], zeta, rtol=0.1)


def test_spectral_support_without_damping_or_modes():
    """Without damping the tolerance is two bins (1/40 Hz): 2.725 Hz is
    supported by the peak at 2.7 Hz, 2.7375 Hz (three bins off) is not; a
    frame of unsupported modes keeps float columns; no modes give an empty
    frame with the columns; a NaN frequency is refused by name."""
    spectrum = bells(THREE_BELLS)
    shapes = np.eye(2)[[0, 0]].T
    support = modal.spectral_support(spectrum, [2.725, 2.7375], shapes)
    assert list(support["spectral_support"]) == [True, False] and list(support["sv_number"]) == [1, 0]
    none = modal.spectral_support(spectrum, [1.0, 5.5], shapes)
    assert not none["spectral_support"].any()
    for column in ("sv_peak_hz", "sv_mac", "efdd_freq_hz", "efdd_damping"):
        assert none[column].dtype == float and none[column].isna().all()
    empty = modal.spectral_support(spectrum, [], np.empty((2, 0)))
    assert empty.empty and list(empty.columns) == modal.identification._fdd.SUPPORT_COLUMNS
    with pytest.raises(ValueError, match="^freq_hz"):
        modal.spectral_support(spectrum, [np.nan], shapes[:, :1])


def test_the_lowest_modes_bell_starts_at_bin_1():
    """A single mode at 0.3 Hz damped 10 % (peak at bin 24): its bell,
    within 20 dB of the peak, reaches down to bin 1 (bin 0, the mean, never
    counts), and spectral_support's EFDD is that of limits (1, 512), not
    (2, 512), which are :func:`modal.efdd`'s defaults for the first value."""
    spectrum = bells([(0.3, 0.1)])
    support = modal.spectral_support(spectrum, [0.3], np.eye(2)[:, :1], damping=[0.1])
    expected = modal.efdd(spectrum, 24, 1, (1, 512))
    assert (support["efdd_freq_hz"][0], support["efdd_damping"][0]) == expected
    assert modal.efdd(spectrum, 24, 1, (2, 512)) != expected
    assert modal.efdd(spectrum, 24) == expected  # the defaults: the first value, the whole spectrum
    assert expected[0] == pytest.approx(0.3, rel=0.005) and expected[1] == pytest.approx(0.1, rel=0.1)


def test_decibels_and_resolution_of_a_small_spectrum():
    """Values 1/2, 1/4 and 1/8 (and 1/8, 1/16 and 0) at 1, 1.25 and 1.5 Hz (a
    band cut from a spectrum): 0, -3.01 and -6.02 dB relative to the largest
    first value, below 1 (a zero value -300 dB, silently; all zero, all -300
    dB), ``df`` the spacing 0.25 Hz (not the sum of the first two
    frequencies), from two bins on; a single bin has no resolution."""
    def spectrum(values):
        n = len(values)
        return modal.SingularValueSpectrum(freq_hz=np.array([1.0, 1.25, 1.5])[:n], values=np.array(values),
                                           vectors=np.ones((n, 2, 2), dtype=complex), nperseg=8)

    small = spectrum([[0.5, 0.125], [0.25, 0.0625], [0.125, 0.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        db, zero = small.decibels(), spectrum(np.zeros((3, 2))).decibels()
    three = 10 * np.log10(2)
    np.testing.assert_allclose(db, [[0.0, -2 * three], [-three, -3 * three], [-2 * three, -300.0]], atol=1e-12)
    np.testing.assert_array_equal(zero, -300.0)
    assert small.df == spectrum([[1.0, 0.5], [0.5, 0.25]]).df == 0.25  # two bins are enough
    assert np.isnan(spectrum([[1.0, 0.5]]).df)


def test_refined_frequency_is_the_vertex_of_a_parabolic_peak():
    """Curves parabolic in dB (a Gaussian peak), df = 1/8 Hz: the first
    value's vertex at bin 40.24 (5.03 Hz), the second's, 20 dB lower, at bin
    80.7 (10.0875 Hz), a third's and a fourth's next to either end, at bins
    1.3 and 127.4. The parabola through the three bins around each maximum
    gives the vertex exactly, each from its own curve (the other curve, a
    sign or a factor slipped would not), at bins 1 and 127 too; at either end
    of the spectrum, and where the curve is flat (clipped at -300 dB), the
    bin's own frequency."""
    j = np.arange(129)
    db = -0.5 * (j[:, None] - np.array([40.24, 80.7, 1.3, 127.4])) ** 2 - [0.0, 20.0, 20.0, 20.0]
    spectrum = synthetic(db)
    assert spectrum.refined_hz(40) == pytest.approx(5.03, abs=1e-9)
    assert spectrum.refined_hz(40, sv_number=1) == pytest.approx(5.03, abs=1e-9)
    assert spectrum.refined_hz(81, sv_number=2) == pytest.approx(10.0875, abs=1e-9)
    assert spectrum.refined_hz(1, sv_number=3) == pytest.approx(1.3 * 0.125, abs=1e-9)
    assert spectrum.refined_hz(127, sv_number=4) == pytest.approx(127.4 * 0.125, abs=1e-9)
    peaks = spectrum.peaks()
    np.testing.assert_allclose(peaks["freq_hz"][peaks["sv_number"] <= 2], [5.03, 10.0875], atol=1e-9)
    assert spectrum.decibels()[126, 0] == spectrum.decibels()[127, 0] == -300.0
    assert [spectrum.refined_hz(i) for i in (0, 127, 128)] == [0.0, 127 * 0.125, 128 * 0.125]


def test_window_correlation_of_the_periodic_hann_window():
    """The periodic Hann window of 4 samples is 0, 1/2, 1, 1/2 (the
    symmetric one 0, 3/4, 3/4, 0): sum of squares 3/2, lag products 1, 1/4
    and 0, so its autocorrelation at lags 0 ... 3 is 1, 2/3, 1/6, 0. A
    symmetric window, a lag shifted or the power multiplied would not give
    these; and :func:`modal.efdd` numbers the values from 1."""
    from modal.identification._fdd import _window_correlation

    np.testing.assert_allclose(_window_correlation(4), [1.0, 2 / 3, 1 / 6, 0.0], atol=1e-15)
    with pytest.raises(ValueError, match="^sv_number must"):
        modal.efdd(bells([(0.3, 0.1)]), 24, sv_number=0)


def designed_bell():
    """Three channels, df = 1/8 Hz: a first value with a Lorentzian peak at
    bin 100 (12.5 Hz, half-power half-width 2 bins, 1 at the top) whose
    vector is ``u = [1, i, 0] / sqrt(2)`` on bins 88 ... 115, except a MAC
    of 0.85 with ``u`` at bin 103 and of 0.81 at bin 115;
    bin 88 set to exactly 1 % of the peak (-20 dB), bin 87 to 5 % but with
    a MAC of 0.5, bin 116 to 0.9 % with ``u``, every other bin the conjugate
    ``conj(u)`` (MAC 0 with ``u``, 1 with ``u^T`` in place of ``u^H``). The
    second value, 1000 times lower, has ``w = [0, 0, 1]`` (MAC 0). Its bell
    is bins 88 ... 115, exactly."""
    j = np.arange(257)
    values = np.zeros((257, 2))
    values[:, 0] = 1 / (1 + ((j - 100) / 2) ** 2)
    values[[87, 88, 116], 0] = [0.05, 10 ** (-20 / 10), 0.009]
    values[:, 1] = values[:, 0] / 1000
    u = np.array([1, 1j, 0]) / np.sqrt(2)
    w = np.array([0, 0, 1.0])
    vectors = np.empty((257, 3, 2), dtype=complex)
    vectors[:, :, 0], vectors[:, :, 1] = u.conj(), w
    vectors[88:117, :, 0] = u
    for b, mac in ((87, 0.5), (103, 0.85), (115, 0.81)):
        vectors[b, :, 0] = np.sqrt(mac) * u + np.sqrt(1 - mac) * w
    return synthetic(10 * np.log10(values), vectors=vectors)


def test_efdd_bell_is_where_a_vector_is_alike_and_the_value_within_20_db():
    """The designed bell: EFDD without limits is exactly EFDD on bins
    88 ... 115 (wider limits change nothing), and a bin less on either side
    gives another answer, so every rule counts: MAC at least 0.8 with the peak's vector
    (``|u^H v|`` squared: 0.85 passes, a cube would not, 0.5 does not, twice
    ``|u^H v|`` would), the value at least 1 % of the peak's (a bin at
    exactly 1 % counts, a bin above it with another shape or one with the
    shape at 0.9 % ends the bell: 11**-2 in place of 10**-2 would take it),
    and a limit inside the bell is where it stops. The frequency lies within
    1 % of 12.5 Hz."""
    spectrum = designed_bell()
    bell = modal.efdd(spectrum, 100, 1, (88, 115))
    assert modal.efdd(spectrum, 100) == bell
    for limits in ((89, 115), (88, 114)):  # a bin less on either side
        assert modal.efdd(spectrum, 100, 1, limits) != bell, limits
    assert modal.efdd(spectrum, 100, 1, (87, 116)) == bell  # bins 87 and 116 are not in it
    assert bell[0] == pytest.approx(12.5, rel=0.01) and bell[1] > 0


def test_efdd_of_odd_and_even_segments_and_of_a_bell_up_to_the_last_bin():
    """A bell at 2.7 Hz damped 1 % in segments of 1024 and of 1023 samples
    (the lag is then ``1 / (df n)``, the correlation ``n`` samples long, not
    ``2 (n_freq - 1)``): EFDD within 0.02 % of the frequency either way (a
    lag or a length one sample off is 0.1 %). A bell at 4.8 Hz damped 4 %
    runs up to the last bin, 512: the default limits and limits beyond the
    spectrum take it in, one bin less does not."""
    for nperseg in (1024, 1023):
        spectrum = bells([(2.7, 0.01)], nperseg=nperseg)
        peak = int(spectrum.peaks()["bin"][0])
        freq_hz, damping = modal.efdd(spectrum, peak)
        assert freq_hz == pytest.approx(2.7, rel=2e-4), nperseg
        assert damping == pytest.approx(0.01, rel=0.1), nperseg
    spectrum = bells([(4.8, 0.04)])
    whole = modal.efdd(spectrum, 383)
    assert whole == modal.efdd(spectrum, 383, 1, (1, 512)) == modal.efdd(spectrum, 383, 1, (1, 600))
    assert modal.efdd(spectrum, 383, 1, (1, 511)) != whole


def test_efdd_needs_three_extrema_of_the_correlation():
    """A 2 Hz bell damped 20 % (whole spectrum within 20 dB up to bin 351):
    its correlation has exactly three extrema between 0.9 and 0.1 of its
    envelope, enough for EFDD (within 1 % of the frequency, 10 % of the
    damping: the truncated bell); damped 30 %, two, and EFDD gives NaN for
    both (``< 3`` in place of ``<= 3``, or no value, would not)."""
    enough, too_few = (bells([(2.0, zeta)]) for zeta in (0.2, 0.3))
    freq_hz, damping = modal.efdd(enough, int(np.argmax(enough.values[:, 0])))
    assert freq_hz == pytest.approx(2.0, rel=0.01) and damping == pytest.approx(0.2, rel=0.1)
    assert np.isnan(modal.efdd(too_few, int(np.argmax(too_few.values[:, 0])))).all()


def test_efdd_of_a_silent_spectrum_is_nan_silently():
    """All values zero: the bell and its correlation are zero, so EFDD is
    NaN for both, with no warning (dividing by the zero correlation at lag 0
    would warn and go on with NaNs)."""
    spectrum = synthetic(np.full((129, 1), -np.inf))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.isnan(modal.efdd(spectrum, 50)).all()


def test_efdd_of_a_flat_bell_is_its_centre():
    """A flat bell (one channel) on bins 90 ... 110, 40 dB above the rest:
    its correlation is the cosine of the centre, 12.5 Hz, under the
    Dirichlet kernel of 21 bins, so EFDD's frequency is 12.5 Hz (within
    0.05 %, measured 0.007 %); a band two bins short on either side, or
    bins added, moves the centre by a bin, 1 %."""
    db = np.full((257, 1), -40.0)
    db[90:111, 0] = 0.0
    assert modal.efdd(synthetic(db), 100)[0] == pytest.approx(12.5, rel=5e-4)


def test_efdd_of_a_beating_bell_is_nan():
    """A bell (one channel) of two lines, 1 at bin 50 and 1/2 at bin 55,
    joined by bins at 1.1 % (all within 20 dB): its correlation beats, its
    envelope never falls to 0.1 and its extrema fit a growing line, so EFDD
    gives NaN for both rather than a negative damping."""
    db = np.full((257, 1), -40.0)
    db[50:56, 0] = 10 * np.log10([1.0, 0.011, 0.011, 0.011, 0.011, 0.5])
    assert np.isnan(modal.efdd(synthetic(db), 50)).all()


def support_rows(rows):
    """A :func:`modal.spectral_support` table from ``(sv_number, sv_peak_hz)`` pairs."""
    return pd.DataFrame([{"sv_peak_hz": peak, "sv_number": number, "sv_mac": np.nan, "spectral_support": number > 0,
                          "efdd_freq_hz": np.nan, "efdd_damping": np.nan} for number, peak in rows],
                        columns=modal.identification._fdd.SUPPORT_COLUMNS)


def test_two_modes_of_one_shape_on_one_peak_are_one_mode():
    """Modes at 2.47 Hz (29 poles) and 2.61 Hz (23 poles) that the first
    singular value's peak at 2.466 Hz supports, shapes of MAC 0.9997: the
    one farther from the peak is the other's second estimate, whatever
    their poles. Each condition undone in turn (shapes apart, another peak,
    the same frequency on the other singular value, no peak at all) leaves
    both alone; as far from the peak, the one with more poles stays, as
    many poles too, the lower frequency; of three on one peak both others
    name the nearest."""
    from modal.identification import shared_peaks

    a = np.array([1.0, 0.6, -0.3])
    b = a + np.array([0.0, 0.02, 0.01])  # MAC 0.9997 with a
    other = np.array([0.3, -0.2, 1.0])  # MAC 0.01 with a
    freq, poles = [2.47, 2.61], [29, 23]
    one = support_rows([(1, 2.466), (1, 2.466)])
    mac_ab = modal.mac(a[:, None], b[:, None])[0, 0]
    assert shared_peaks(freq, one, np.column_stack([a, b]), poles, 0.98) == \
        ["", f"same spectral peak as 2.47 Hz (MAC {mac_ab:.3f})"]
    assert shared_peaks(freq, one, np.column_stack([a, b]), [10, 30], 0.98)[1].startswith("same spectral peak as 2.47")
    assert shared_peaks([2.61, 2.47], one, np.column_stack([b, a]), poles[::-1], 0.98)[0] == \
        f"same spectral peak as 2.47 Hz (MAC {mac_ab:.3f})"  # the peak decides, not the order
    even = support_rows([(1, 2.5), (1, 2.5)])  # 2.25 and 2.75 Hz exactly 0.25 Hz from it
    assert shared_peaks([2.25, 2.75], even, np.column_stack([a, b]), [12, 20], 0.98)[0].startswith(
        "same spectral peak as 2.75")
    assert shared_peaks([2.25, 2.75], even, np.column_stack([a, b]), [20, 20], 0.98)[1].startswith(
        "same spectral peak as 2.25")
    assert shared_peaks(freq, one, np.column_stack([a, other]), poles, 0.98) == ["", ""]
    assert shared_peaks(freq, one, np.column_stack([a, b]), poles, 0.99999) == ["", ""]  # mac_min is passed on
    assert shared_peaks(freq, support_rows([(1, 2.466), (1, 2.59)]), np.column_stack([a, b]), poles, 0.98) == ["", ""]
    assert shared_peaks(freq, support_rows([(1, 2.466), (2, 2.466)]), np.column_stack([a, b]), poles, 0.98) == ["", ""]
    none = support_rows([(0, np.nan), (0, np.nan)])
    assert shared_peaks(freq, none, np.column_stack([a, b]), poles, 0.98) == ["", ""]
    tie = shared_peaks([2.25, 2.75], even, np.column_stack([a, b]), [20, 20], 0.98)
    assert tie[0] == "" and tie[1] != ""
    at_bound = modal.auto_mac(np.column_stack([a, b]))[0, 1]
    assert shared_peaks(freq, one, np.column_stack([a, b]), poles, at_bound)[1].startswith("same spectral peak")
    three = support_rows([(1, 2.466)] * 3)
    flags = shared_peaks([2.40, 2.47, 2.61], three, np.column_stack([b, a, b]), [12, 29, 23], 0.98)
    assert flags[1] == "" and flags[0].startswith("same spectral peak as 2.47") and \
        flags[2].startswith("same spectral peak as 2.47")
    # the reason names the nearest of several nearer modes, not the last in the table
    flags = shared_peaks([2.47, 2.40, 2.61], three, np.column_stack([a, b, b]), [29, 12, 23], 0.98)
    assert flags[0] == "" and flags[2].startswith("same spectral peak as 2.47")
    assert shared_peaks([], support_rows([]), np.empty((3, 0)), [], 0.98) == []
    # a trusted mode keeps the peak over a nearer one flagged for another reason (both flagged would leave
    # the resonance without a trusted row), whichever comes first; two doubtful ones: the nearer keeps it
    for doubtful, kept in (([True, False], 1), ([False, True], 0), ([True, True], 0), ([False, False], 0)):
        flags = shared_peaks(freq, one, np.column_stack([a, b]), poles, 0.98, doubtful=doubtful)
        assert flags[kept] == "" and flags[1 - kept].startswith(f"same spectral peak as {freq[kept]:g} Hz")
        flags = shared_peaks(freq[::-1], one, np.column_stack([b, a]), poles[::-1], 0.98, doubtful=doubtful[::-1])
        assert flags[1 - kept] == "" and flags[kept].startswith(f"same spectral peak as {freq[kept]:g} Hz")
    # a pair the selection decided (one named 'same shape as' the other) is left as it is, whichever it named
    for shadows in ([True, False], [False, True]):
        assert shared_peaks(freq, one, np.column_stack([a, b]), poles, 0.98, shadows) == ["", ""]
    flags = shared_peaks([2.40, 2.47, 2.61], three, np.column_stack([b, a, b]), [12, 29, 23], 0.98, [False, True, False])
    assert flags[1] == "" and flags[0] == "" and flags[2].startswith("same spectral peak as 2.4 Hz")
