"""Engine tests written against the mutants that survived the other engine
tests (benchmarks/mutation.sh, benchmarks/mutation_survivors.md).

Each asserts a number or a contract that a wrong engine would break: closed
forms (an exponential's lag-one ratio is exactly ``e^{a dt}``, a pair of
sinusoids over whole periods gives ``lambda = omega^2`` exactly), the
documented flags (real poles, |lambda| > 1, aliasing, short windows), the
defaults of ``ModalResult``, refusals that name the argument and the
boundaries of what is accepted, and the normalisation of complex shapes.
"""

import warnings

import numpy as np
import pytest

import modal
from modal.identification._era import realise
from modal.identification._era_kernels import decompose
from modal.identification._indicators import modal_amplitude_coherence, modal_phase_collinearity
from modal.identification._result import near_limit, normalise_shapes, sort_modes


@pytest.fixture(autouse=True)
def _quiet_modal_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", modal.ModalWarning)
        yield


def two_sinusoids(omega=(0.5, 2.0), periods=3, per_period=400, mixing=((1.0, 0.4), (-0.7, 1.3)), amplitude=1.0):
    """Displacement, velocity and acceleration of two modes seen through a
    non-orthogonal ``mixing`` matrix, over whole periods of both modes."""
    omega = np.asarray(omega)
    t_end = periods * 2 * np.pi / omega.min()
    n = periods * per_period
    dt = t_end / n
    t = dt * np.arange(n)
    q = np.sin(omega[None, :] * t[:, None])
    mix = amplitude * np.asarray(mixing)
    return dt, q @ mix.T, (omega * np.cos(omega[None, :] * t[:, None])) @ mix.T, (-(omega**2) * q) @ mix.T


def growing(rate, dt, n, alternate=False):
    """One channel ``e^{rate t}`` (or ``(-1)^k e^{rate t}``): its lag-``k``
    ratio ``sum y(t + k dt) y(t) / sum y(t)^2`` is exactly ``(+-e^{rate dt})^k``."""
    y = np.exp(rate * dt * np.arange(n))
    return (y * (-1.0) ** np.arange(n) if alternate else y)[:, None]


# --------------------------------------------------------------------------- #
# Refusals name the argument (every message starts with it)
# --------------------------------------------------------------------------- #
Y2 = np.column_stack([np.sin(0.1 * np.arange(300)), np.cos(0.37 * np.arange(300))])

REFUSALS = [
    ("tcm dt", lambda: modal.tcm(Y2, -1.0), "dt"),
    ("tcm lag", lambda: modal.tcm(Y2, 0.01, lag=-1), "lag"),
    ("tcm n_modes", lambda: modal.tcm(Y2, 0.01, n_modes=0), "n_modes"),
    ("tcm duration", lambda: modal.tcm(Y2, 0.01, duration=-2.0), "duration"),
    ("tcm constant acc", lambda: modal.tcm(np.column_stack([Y2[:, 0], np.ones(300)]), 0.01), "acc"),
    ("tcm constant vel", lambda: modal.tcm(Y2, 0.01, vel=np.column_stack([Y2[:, 0], np.zeros(300)])), "vel"),
    ("cera dt", lambda: modal.cera(Y2, 0.0, 1, 50), "dt"),
    ("cera n_modes", lambda: modal.cera(Y2, 0.01, 0, 50), "n_modes"),
    ("cera cols", lambda: modal.cera(Y2, 0.01, 1, 0), "cols"),
    ("era dt", lambda: modal.era(Y2, 0.0, 1, 5, 50), "dt"),
    ("era n_modes", lambda: modal.era(Y2, 0.01, 0, 5, 50), "n_modes"),
    ("era rows", lambda: modal.era(Y2, 0.01, 1, 0, 50), "rows"),
    ("era cols", lambda: modal.era(Y2, 0.01, 1, 5, 0), "cols"),
    ("hankel rows", lambda: modal.hankel(Y2, 0, 5), "rows"),
    ("hankel cols", lambda: modal.hankel(Y2, 5, 0), "cols"),
    ("hankel start", lambda: modal.hankel(Y2, 5, 5, start=-1), "start"),
    ("integrate dt", lambda: modal.integrate_acceleration(Y2, 0.0), "dt"),
    ("offset acc", lambda: modal.signals.acceleration_offset(Y2[:, 0], 0.01), "acc"),
    ("offset dt", lambda: modal.signals.acceleration_offset(Y2, -0.01), "dt"),
    ("lowpass dt", lambda: modal.lowpass_fft(Y2, 0.0, 1.0), "dt"),
    ("lowpass cutoff_hz", lambda: modal.lowpass_fft(Y2, 0.01, 0.0), "cutoff_hz"),
    ("split y", lambda: modal.split_record(Y2[:, 0], 2), "y"),
    ("split n_sets", lambda: modal.split_record(Y2, 0), "n_sets"),
    ("spectrum y", lambda: modal.amplitude_spectrum(Y2[:, 0], 0.01), "y"),
    ("spectrum dt", lambda: modal.amplitude_spectrum(Y2, np.inf), "dt"),
    ("mac rows", lambda: modal.mac(np.ones((3, 1)), np.ones((4, 1))), "a and b"),
    ("mac NaN in b only", lambda: modal.mac(np.ones((3, 1)), np.array([[1.0], [np.nan], [0.0]])), "a and b"),
    ("mac 3-d a", lambda: modal.mac(np.ones((3, 2, 2)), np.ones((3, 2))), "a and b"),
]


@pytest.mark.parametrize("call, name", [r[1:] for r in REFUSALS], ids=[r[0] for r in REFUSALS])
def test_refusal_names_the_argument(call, name):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        call()


def test_refusals_state_the_numbers_involved():
    with pytest.raises(ValueError, match=r"^acc needs at least 4 samples to integrate, got 3$"):
        modal.integrate_acceleration(np.ones((3, 2)) * [[1.0], [2.0], [4.0]], 0.1)
    with pytest.raises(ValueError, match=r"^n_sets = 4 leaves fewer than 2 samples per set from 7$"):
        modal.split_record(np.arange(14.0).reshape(7, 2), 4)
    with pytest.raises(ValueError, match=r"rows \+ cols - 1 = 14 samples from start = 3 need 17 samples"):
        modal.hankel(np.arange(32.0).reshape(16, 2), 5, 10, start=3)
    with pytest.raises(ValueError, match=r"\(6 x 8\)"):  # l r = 2 x 3, m s = 2 x 4
        modal.era(np.random.default_rng(0).standard_normal((2, 60, 2)), 0.01, 4, rows=3, cols=4)
    with pytest.raises(ValueError, match=r"^n_modes = 7 exceeds the 6 Hankel columns"):
        modal.cera(np.random.default_rng(1).standard_normal((3, 50, 8)), 0.01, 7, cols=2)
    with pytest.raises(ValueError, match=r"^cutoff_hz = 50.0 must be below the Nyquist frequency 50.0 Hz"):
        modal.lowpass_fft(Y2, 0.01, 50.0)  # exactly Nyquist
    with pytest.raises(ValueError, match=r"^vel is used only with lag = 0"):
        modal.tcm(Y2, 0.01, vel=Y2, lag=1)


def test_rank_deficient_data_are_refused_before_realisation():
    """Three channels carrying two modes (channel 3 = channel 1 + channel 2)
    support two modes, not three, in the CERA; one sinusoid supports one ERA
    mode, not two."""
    dt, _, _, acc = two_sinusoids(omega=(2.0, 5.0))
    dependent = np.column_stack([acc, acc[:, 0] + acc[:, 1]])
    modal.cera(dependent, dt, 2, cols=600)
    with pytest.raises(ValueError, match=r"^n_modes = 3: H_c has fewer than 3 non-zero singular values"):
        modal.cera(dependent, dt, 3, cols=600)
    one_mode = np.column_stack([np.sin(2 * np.arange(400) * 0.05), -0.3 * np.sin(2 * np.arange(400) * 0.05)])
    with pytest.raises(ValueError, match=r"^n_modes = 2: the Hankel matrix has fewer than 4"):
        modal.era(one_mode, 0.05, 2, rows=10, cols=100)


def test_tcm_refuses_nearly_dependent_channels_beside_a_weak_one():
    """Singularity of A is judged against its largest eigenvalue, whatever the
    other channels' sizes."""
    t = 0.01 * np.arange(2000)
    y = np.column_stack([np.sin(2 * t), 1e-3 * np.sin(5 * t), np.sin(2 * t) + 1e-9 * np.cos(7 * t)])
    with pytest.raises(ValueError, match="the correlation matrix A is singular"):
        modal.tcm(y, 0.01, lag=1)


# --------------------------------------------------------------------------- #
# Boundaries of what is accepted
# --------------------------------------------------------------------------- #
def test_smallest_accepted_sizes():
    # integration needs 4 samples: a cubic spline through 4 samples of a cubic is exact
    t = 0.1 * np.arange(4)
    offset = modal.signals.acceleration_offset(np.column_stack([np.full(4, 2.5), 3 * t]), 0.1)
    np.testing.assert_allclose(offset[0], 2.5, rtol=1e-12)
    # split_record: two samples per set
    y = np.arange(10.0).reshape(5, 2)
    np.testing.assert_array_equal(modal.split_record(y, 2), [y[0:2], y[2:4]])
    # TCM: lag + l + 1 samples (and at least 3)
    rng = np.random.default_rng(3)
    assert modal.tcm(rng.standard_normal((5, 3)), 0.01, lag=1).n_modes == 3
    assert modal.tcm(rng.standard_normal((3, 2)), 0.01, vel=rng.standard_normal((3, 2))).n_modes == 2
    with pytest.raises(ValueError, match="too few samples"):
        modal.tcm(rng.standard_normal((4, 3)), 0.01, lag=1)
    # ERA: 2 n_modes equal to the smaller Hankel dimension (l r = 6, m s = 8)
    sets = np.stack([np.column_stack([np.exp(-0.01 * k * np.arange(60)) * np.sin((0.3 + 0.2 * k) * np.arange(60) + j)
                                      for k in range(2)]) for j in range(2)])
    sets = sets + np.stack([np.column_stack([np.exp(-0.02 * np.arange(60)) * np.cos(1.1 * np.arange(60) + j)] * 2)
                            * [1.0, -0.5] for j in range(2)])
    assert modal.era(sets, 1.0, 3, rows=3, cols=4).n_modes == 3
    # CERA: n_modes equal to the m s Hankel columns
    assert modal.cera(rng.standard_normal((3, 50, 8)), 0.01, 6, cols=2).n_modes == 6


def test_vel_is_refused_with_the_smallest_lag():
    dt, _, vel, acc = two_sinusoids()
    with pytest.raises(ValueError, match=r"^vel is used only with lag = 0"):
        modal.tcm(acc, dt, vel=vel, lag=1)


# --------------------------------------------------------------------------- #
# Closed forms: frequencies, eigenvalues, singular values, flags
# --------------------------------------------------------------------------- #
@pytest.mark.parametrize("amplitude", [1.0, 1e3])
def test_tcm_below_one_rad_per_s_is_exact_and_not_flagged(amplitude):
    """lambda = omega^2 exactly over whole periods; omega = 0.5 rad/s gives
    lambda = 0.25 < 1, an ordinary mode. ``singular_values`` are A's
    eigenvalues, largest first, in the data's units."""
    dt, _, vel, acc = two_sinusoids(amplitude=amplitude)
    res = modal.tcm(acc, dt, vel=vel)
    np.testing.assert_allclose(res.omega, [0.5, 2.0], rtol=1e-10)
    np.testing.assert_allclose(res.eigenvalues, [0.25, 4.0], rtol=1e-10)
    assert not res.real_pole.any() and res.real_pole.dtype == bool
    a = vel.T @ vel / len(vel)
    np.testing.assert_allclose(res.singular_values, np.linalg.eigvalsh(a)[::-1], rtol=1e-12)
    assert res.method == "tcm" and res.to_frame()["method"].tolist() == ["tcm", "tcm"]
    lowest = modal.tcm(acc, dt, n_modes=1, vel=vel)
    assert lowest.n_modes == 1 and lowest.shapes.shape == (2, 1)
    np.testing.assert_allclose(lowest.omega, [0.5], rtol=1e-10)


@pytest.mark.parametrize("method", ["tcm", "cera"])
def test_growing_channel_is_flagged_with_its_exact_eigenvalue(method):
    """A growing exponential has lambda = e^{a dt} > 1 exactly: no oscillation,
    flagged ``real_pole``, frequency 0 (acos clipped)."""
    dt, rate = 0.05, 10.0  # lambda = e^0.5 = 1.6487
    y = growing(rate, dt, 200)
    res = modal.tcm(y, dt, lag=1) if method == "tcm" else modal.cera(y, dt, 1, cols=150)
    np.testing.assert_allclose(res.eigenvalues, [np.exp(rate * dt)], rtol=1e-12)
    np.testing.assert_array_equal(res.real_pole, [True])
    np.testing.assert_array_equal(res.omega, [0.0])
    assert res.method == method


@pytest.mark.parametrize("method", ["tcm", "cera"])
def test_alternating_growth_sits_at_the_nyquist_limit(method):
    """(-1)^k e^{a t}: lambda = -e^{a dt} < -1, flagged, omega = pi / dt
    (acos clipped at -1), and flagged possibly aliased."""
    dt, rate = 0.05, 10.0
    y = growing(rate, dt, 200, alternate=True)
    res = modal.tcm(y, dt, lag=1) if method == "tcm" else modal.cera(y, dt, 1, cols=150)
    np.testing.assert_allclose(res.eigenvalues, [-np.exp(rate * dt)], rtol=1e-12)
    np.testing.assert_array_equal(res.real_pole, [True])
    np.testing.assert_allclose(res.omega, [np.pi / dt], rtol=1e-15)
    np.testing.assert_array_equal(res.aliased, [True])


def test_tcm_lag_two_sees_alternation_through_the_lag_one_quotient():
    """With lag 2, (-1)^k e^{a t} gives lambda = e^{2 a dt} > 1 (omega 0), but
    its lag-one quotient is -e^{a dt}: omega_1 = pi / dt, beyond pi / (2 dt),
    so the entry is flagged possibly aliased."""
    dt, rate = 0.05, 4.0
    res = modal.tcm(growing(rate, dt, 200, alternate=True), dt, lag=2)
    np.testing.assert_allclose(res.eigenvalues, [np.exp(2 * rate * dt)], rtol=1e-12)
    np.testing.assert_array_equal(res.omega, [0.0])
    np.testing.assert_array_equal(res.aliased, [True])


def test_tcm_lag_flags_only_the_folded_modes():
    """Lag 7 on the thesis's beam: pi / (7 dt) is 25.7 x mode 1, so modes 1-5
    (1, 4, 9, 16, 25 x) must not be flagged aliased (the lag-one check sees
    their true frequency) and mode 6 (36 x) folds to 51.43 - 36 = 15.43 x,
    flagged. (With lag 8 mode 6 folds exactly onto mode 3: their eigenvalues
    coincide and the eigenvectors mix, so no flag can tell them apart.)"""
    beam = modal.SimplySupportedBeam(5.0, 30.0, 1.0)
    omega = beam.natural_frequencies(6)
    dt, lag = 2 * np.pi / omega[0] / 360, 7
    rec = modal.beam_impulse_response(beam, 6, 0.77, np.array([0.3, 0.9, 1.7, 2.2, 3.1, 4.4]), dt, 3 * 360 + lag, 0.0)
    res = modal.tcm(rec.acceleration, dt, lag=lag)
    for w in omega[:5]:
        hit = np.argmin(np.abs(res.omega - w))
        assert res.omega[hit] == pytest.approx(w, rel=1e-6) and not res.aliased[hit]
    folded = (2 * np.pi / (lag * dt) - omega[5])
    np.testing.assert_allclose(res.omega[res.aliased], [folded], rtol=1e-6)


def test_tcm_lag_short_window_counts_the_lagged_instants():
    """With a lag the inner products span (n - lag) dt: 5.95 fundamental
    periods is short (flagged), 6.05 is not."""
    dt, lag, per_period = 2 * np.pi / 360, 40, 360  # omega_1 = 1 rad/s
    for periods, short in ((5.95, True), (6.05, False)):
        n = int(round(periods * per_period)) + lag
        t = dt * np.arange(n)
        y = np.column_stack([np.sin(t) + 0.2 * np.sin(3 * t), np.sin(t) - 0.5 * np.sin(3 * t)])
        res = modal.tcm(y, dt, lag=lag)
        assert res.omega[0] == pytest.approx(1.0, rel=0.03)
        assert res.short_window[0] == short


def test_era_keeps_real_poles_with_their_decay_rate():
    """Two real poles (e^{-t}, e^{-2t}) and one damped pair: the real poles
    are entries with omega = |ln z| / dt = the decay rate, ``real_pole`` set
    and damping NaN; the pair has zeta = 0.05 / |s|."""
    dt = 0.05
    t = dt * np.arange(400)
    y = np.column_stack([np.exp(-t) + np.exp(-0.05 * t) * np.sin(3 * t), np.exp(-2 * t) - np.exp(-0.05 * t) * np.sin(3 * t)])
    res = modal.era(y, dt, 2, rows=20, cols=300)
    s_pair = np.hypot(0.05, 3.0)
    np.testing.assert_allclose(res.omega, [1.0, 2.0, s_pair], rtol=1e-8)
    np.testing.assert_array_equal(res.real_pole, [True, True, False])
    assert np.isnan(res.damping[:2]).all()
    assert res.damping[2] == pytest.approx(0.05 / s_pair, rel=1e-7)
    np.testing.assert_allclose(res.eigenvalues, np.exp(np.array([-1.0, -2.0, -0.05 + 3.0j]) * dt), rtol=1e-9)
    # realise() alone (one decomposition, any order) reports the kept singular values
    h = modal.hankel(y, 21, 300)
    p, d, qt, _ = decompose(h[:-2], 4)
    low = realise(p, d, qt, h[2:], n_channels=2, n_sets=1, dt=dt)
    np.testing.assert_array_equal(low.singular_values, d)
    np.testing.assert_allclose(low.omega, res.omega, rtol=1e-12)


def test_era_flags_a_mode_near_nyquist_aliased():
    dt, k = 0.01, np.arange(600)
    decay = np.exp(-0.001 * k)
    y = np.column_stack([decay * np.cos(0.99 * np.pi * k) + np.sin(0.3 * k), decay * np.cos(0.99 * np.pi * k) - np.sin(0.3 * k)])
    res = modal.era(y, dt, 2, rows=10, cols=400)
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
    era = modal.era(acc, dt, 2, rows=4, cols=200)
    np.testing.assert_allclose(era.singular_values, np.linalg.svd(h, compute_uv=False), rtol=1e-10)
    cera = modal.cera(acc, dt, 2, cols=200)
    np.testing.assert_allclose(cera.singular_values, np.linalg.svd(h[:2], compute_uv=False), rtol=1e-10)
    assert era.method == "era" and cera.method == "cera"


def test_cera_eigenvalues_and_start():
    """CERA over whole periods: lambda = cos(omega dt) exactly; ``start``
    shifts the Hankel matrix (same as slicing the record)."""
    dt, _, _, acc = two_sinusoids(omega=(2.0, 5.0))
    n_period = int(round(np.pi / dt))  # one period of omega = 2
    res = modal.cera(acc, dt, 2, cols=2 * n_period)
    np.testing.assert_allclose(res.eigenvalues, np.cos(np.array([2.0, 5.0]) * dt), rtol=1e-12)
    damped = acc * np.exp(-0.03 * dt * np.arange(len(acc)))[:, None]
    a = modal.cera(damped, dt, 2, cols=2 * n_period, start=37)
    b = modal.cera(damped[37:], dt, 2, cols=2 * n_period)
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=1e-13)
    unshifted = modal.cera(damped, dt, 2, cols=2 * n_period)
    assert np.max(np.abs(a.eigenvalues - unshifted.eigenvalues)) > 1e-9


def test_cera_flags_a_mode_near_nyquist_aliased():
    dt = 0.01
    k = np.arange(500)
    y = np.column_stack([np.cos(0.99 * np.pi * k), np.sin(0.3 * k)])
    res = modal.cera(y, dt, 2, cols=400)
    np.testing.assert_array_equal(res.aliased, [False, True])


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
    assert not w.filename.endswith("result.py")
    with pytest.warns(modal.ModalWarning, match=rf"short window \({96 * dt:.4g} s holds"):
        warnings.simplefilter("always", modal.ModalWarning)
        modal.cera(acc, dt, 2, cols=96)


# --------------------------------------------------------------------------- #
# Result, shapes and indicators
# --------------------------------------------------------------------------- #
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
    res = {"tcm": lambda: modal.tcm(acc, dt, vel=vel), "era": lambda: modal.era(acc, dt, 2, 4, 600),
           "cera": lambda: modal.cera(acc, dt, 2, 600)}[method]()
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


def test_indicators_of_zero_vectors_are_zero():
    """MAC, MPC and MAMC of a zero shape or history are 0, not NaN."""
    a = np.array([[1.0, 0.0], [2.0, 0.0], [0.5, 0.0]])
    np.testing.assert_array_equal(modal.mac(a, a), [[1.0, 0.0], [0.0, 0.0]])
    np.testing.assert_array_equal(modal_phase_collinearity(np.zeros((3, 2), dtype=complex)), [0.0, 0.0])
    histories = np.array([np.zeros(6), 0.9 ** np.arange(6)], dtype=complex)
    np.testing.assert_allclose(modal_amplitude_coherence(histories, np.array([0.5, 0.9]), 1), [0.0, 1.0], rtol=1e-14)


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


# --------------------------------------------------------------------------- #
# Signals
# --------------------------------------------------------------------------- #
def test_lowpass_keeps_a_bin_exactly_at_the_cutoff_on_an_odd_record():
    """Bins above the cutoff go, the bin at the cutoff stays; an odd-length
    record comes back with its own length."""
    dt, n = 0.01, 101  # bins at k / 1.01 Hz
    t = dt * np.arange(n)
    f_cut = 5 / (n * dt)
    keep = np.sin(2 * np.pi * f_cut * t)
    drop = np.cos(2 * np.pi * 20 / (n * dt) * t)
    out = modal.lowpass_fft(np.column_stack([keep + drop, drop]), dt, f_cut)
    assert out.shape == (n, 2)
    np.testing.assert_allclose(out[:, 0], keep, atol=1e-12)
    np.testing.assert_allclose(out[:, 1], 0.0, atol=1e-12)


def test_pole_indicators_of_an_overflowing_spurious_pole_are_silent():
    """A spurious pole |z| = 50 over 400 block columns: its powers overflow
    (50^399 > 1e308), so its MAMC is 0 (as documented), without a floating-point
    warning, whether the poles are complex or all real; the physical pole
    beside it (damping 3 %) keeps MAMC 1."""
    from modal.identification._era import pole_indicators

    dt, omega, zeta, n_cols, n_sets = 0.01, 2 * np.pi * 4.2, 0.03, 400, 2
    z = np.array([np.exp((-zeta + 1j * np.sqrt(1 - zeta**2)) * omega * dt), 50.0])
    b = np.array([[1.0, 2.0 - 1j], [1.0, -1.0]])  # initial amplitudes per data set
    powers = np.array([z[0] ** np.arange(n_cols), np.full(n_cols, 50.0**5)])  # the spurious history saturates
    histories = (powers[:, :, None] * b[:, None, :]).reshape(2, n_cols * n_sets)
    shapes = np.array([[1.0, 0.3], [0.5j, 1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pole_indicators(z, np.array([False, True]), shapes, histories, dt, n_sets)
    np.testing.assert_allclose(out["mamc"], [1.0, 0.0], atol=1e-12)
    assert out["damping"][0] == pytest.approx(zeta, rel=1e-9) and np.isnan(out["damping"][1])
    assert out["omega"][0] == pytest.approx(omega, rel=1e-9)
    np.testing.assert_array_equal(out["unstable"], [False, True])
    # all poles real: numpy's eigvals returns them as a real array, whose powers
    # overflow to inf without NaN, so the coherence is inf / inf = NaN before it is set to 0
    z_real = np.array([0.5, 50.0])
    histories = np.array([0.5 ** np.arange(n_cols), 50.0 ** np.minimum(np.arange(n_cols), 5)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pole_indicators(z_real, np.array([True, True]), shapes, histories, dt, 1)
    np.testing.assert_allclose(out["mamc"], [1.0, 0.0], atol=1e-12)


def test_pole_indicators_of_a_pole_at_the_origin_are_silent():
    """A state matrix with a zero eigenvalue (e.g. a realisation of zero-padded
    data) gives a real pole at z = 0: s = ln z / dt is -inf, so its frequency
    is inf and its damping NaN (a real pole's), without a floating-point
    warning; the pole beside it is unaffected."""
    from modal.identification._era import pole_indicators

    dt = 0.01
    z = np.array([0.0, 0.9 * np.exp(0.3j)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = pole_indicators(z, np.array([True, False]), np.array([[1.0, 1.0], [0.5, 1j]]),
                              np.ones((2, 8), complex), dt, 1)
    assert out["omega"][0] == np.inf and np.isnan(out["damping"][0]) and not out["unstable"][0]
    assert out["omega"][1] == pytest.approx(np.hypot(np.log(0.9), 0.3) / dt, rel=1e-12)


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int64, np.complex64])
def test_modal_amplitude_coherence_of_any_numeric_histories(dtype):
    """Histories given as float32, float64, integers or complex64 (the function
    is public) give the coherence of the same values as complex128, not of
    their bytes reinterpreted."""
    from modal.identification._indicators import modal_amplitude_coherence

    rng = np.random.default_rng(8)
    values = np.round(rng.standard_normal((3, 20)) * 100)  # exact in every dtype
    if np.issubdtype(dtype, np.complexfloating):
        values = values + 1j * np.round(rng.standard_normal((3, 20)) * 100)
    z = np.array([0.9, 0.5 + 0.5j, -0.3])
    expected = modal_amplitude_coherence(values.astype(complex), z, 2)
    np.testing.assert_allclose(modal_amplitude_coherence(values.astype(dtype), z, 2), expected, rtol=1e-14)
    assert np.all((expected > 0.05) & (expected < 0.95))  # neither degenerate case
