"""Every engine entry point rejects bad input with a ValueError naming the argument."""

import numpy as np
import pytest

import modal

from .cases import flagged, beam_record, two_sinusoids

DT = 0.01


@pytest.fixture
def y():
    t = DT * np.arange(400)
    return np.column_stack([np.sin(2 * t), np.sin(5 * t + 1), np.cos(9 * t)])


def with_nan(y):
    y = y.copy()
    y[10, 1] = np.nan
    return y


def with_inf(y):
    y = y.copy()
    y[3, 0] = np.inf
    return y


CALLS = {
    "era": lambda y, **kw: modal.era(y, kw.get("dt", DT), kw.get("n", 1), kw.get("rows", 5), kw.get("cols", 50)),
    "tcm": lambda y, **kw: modal.tcm(y, kw.get("dt", DT), kw.get("n")),
    "tcm_lag": lambda y, **kw: modal.tcm(y, kw.get("dt", DT), kw.get("n"), lag=1),
    "cera": lambda y, **kw: modal.cera(y, kw.get("dt", DT), kw.get("n", 1), kw.get("cols", 50)),
}


@pytest.mark.parametrize("method", CALLS)
@pytest.mark.parametrize("corrupt", [with_nan, with_inf])
def test_non_finite_data(y, method, corrupt):
    name = "acc" if method.startswith("tcm") else "y"
    with pytest.raises(ValueError, match=f"{name} contains NaN or inf"):
        CALLS[method](corrupt(y))


@pytest.mark.parametrize("method", CALLS)
@pytest.mark.parametrize("dt", [0.0, -0.1, np.nan, "fast"])
def test_bad_dt(y, method, dt):
    with pytest.raises(ValueError, match="dt"):
        CALLS[method](y, dt=dt)


@pytest.mark.parametrize("method", CALLS)
def test_wrong_rank(y, method):
    with pytest.raises(ValueError, match="dimensional"):
        CALLS[method](y[:, 0])
    with pytest.raises(ValueError, match="dimensional"):
        CALLS[method](y[None, None])


@pytest.mark.parametrize("method", ["tcm", "tcm_lag", "cera"])
def test_more_modes_than_channels(y, method):
    with pytest.raises(ValueError, match="n_modes = 4 exceeds the 3 channels"):
        CALLS[method](y, n=4)


def test_era_order_larger_than_hankel(y):
    # 2n = 16 > min(3 * 5, 50) = 15
    with pytest.raises(ValueError, match="2 \\* n_modes = 16 exceeds the smaller dimension"):
        modal.era(y, DT, 8, rows=5, cols=50)


def test_era_order_beyond_rank(y):
    # three sinusoids give rank 6; asking for 4 modes (rank 8) is impossible
    with pytest.raises(ValueError, match="fewer than 8 non-zero singular values"):
        modal.era(y, DT, 4, rows=10, cols=50)


@pytest.mark.parametrize("bad", [2.5, "3", True, 0, -1, None])
@pytest.mark.parametrize("arg", ["n_modes", "rows", "cols"])
def test_non_integer_sizes_era(y, arg, bad):
    kw = dict(n_modes=1, rows=5, cols=50)
    kw[arg] = bad
    with pytest.raises(ValueError, match=arg):
        modal.era(y, DT, **kw)


@pytest.mark.parametrize("bad", [2.5, "3", -1])
def test_non_integer_sizes_others(y, bad):
    with pytest.raises(ValueError, match="n_modes"):
        modal.tcm(y, DT, bad if bad != -1 else 0)
    with pytest.raises(ValueError, match="lag"):
        modal.tcm(y, DT, lag=bad)
    with pytest.raises(ValueError, match="cols"):
        modal.cera(y, DT, 1, bad)
    with pytest.raises(ValueError, match="start"):
        modal.era(y, DT, 1, 5, 50, start=bad)


def test_too_few_samples():
    y = np.ones((3, 3)) + np.eye(3)
    with pytest.raises(ValueError, match="too few samples"):
        modal.tcm(y, DT, lag=1)
    with pytest.raises(ValueError, match="at least 2 samples"):
        modal.era(np.ones((1, 3)), DT, 1, 1, 1)


def test_tcm_vel_shape_and_singular(y):
    with pytest.raises(ValueError, match="vel must have the shape"):
        modal.tcm(y, DT, vel=y[:, :2])
    with pytest.raises(ValueError, match="vel contains NaN"):
        modal.tcm(y, DT, vel=with_nan(y))
    dependent = np.column_stack([y[:, 0], 2 * y[:, 0]])
    with pytest.raises(ValueError, match="singular"):
        modal.tcm(dependent, DT, lag=1)
    with pytest.raises(ValueError, match="duration"):
        modal.tcm(y, DT, duration=-1)


def test_simulation_bad_input(beam):
    with pytest.raises(ValueError, match="length"):
        modal.SimplySupportedBeam(-1, 1, 1)
    with pytest.raises(ValueError, match="damping"):
        modal.beam_impulse_response(beam, 3, 1.0, [1, 2], 0.01, 100, damping=-0.1)
    with pytest.raises(ValueError, match="damping"):
        modal.beam_impulse_response(beam, 3, 1.0, [1, 2], 0.01, 100, damping=[])
    # A shorter list is padded with its last value (modal.damping_ratios).
    rec = modal.beam_impulse_response(beam, 3, 1.0, [1, 2], 0.01, 100, damping=[0.1, 0.2])
    np.testing.assert_array_equal(rec.damping, [0.1, 0.2, 0.2])
    with pytest.raises(ValueError, match="x must lie on the beam"):
        modal.beam_impulse_response(beam, 3, 1.0, [1, 7], 0.01, 100)
    with pytest.raises(ValueError, match="noise_ratio"):
        modal.add_noise(np.ones((10, 2)), -0.05, 0)
    with pytest.raises(ValueError, match="n_samples"):
        modal.beam_impulse_response(beam, 3, 1.0, [1, 2], 0.01, 1.5)


def test_signals_bad_input(y):
    with pytest.raises(ValueError, match="Nyquist"):
        modal.lowpass_fft(y, DT, 60.0)
    with pytest.raises(ValueError, match="cutoff_hz"):
        modal.lowpass_fft(y, DT, 0)
    with pytest.raises(ValueError, match="y contains NaN"):
        modal.lowpass_fft(with_nan(y), DT, 10)
    with pytest.raises(ValueError, match="n_sets = 300 leaves fewer than 2 samples"):
        modal.split_record(y, 300)
    with pytest.raises(ValueError, match="acc contains NaN"):
        modal.integrate_acceleration(with_nan(y), DT)


def test_more_bad_input(y, tmp_path, thesis_grid_config):
    with pytest.raises(ValueError, match="y contains NaN"):
        modal.hankel(with_nan(y), 3, 4)
    with pytest.raises(ValueError, match="dt"):
        modal.era(y, True, 1, 5, 50)
    with pytest.raises(ValueError, match="real numbers"):
        modal.tcm(y + 1j, DT)
    with pytest.raises(ValueError, match="real numbers"):
        modal.era(y > 0, DT, 1, 5, 50)
    rec = modal.impulse_response([2.0], [[1.0]], [1.0], DT, 10)
    with pytest.raises(ValueError, match="derivative"):
        rec.signal(-1)
    path = tmp_path / "r.npz"
    np.savez(path, acc=y, dt=0.1, fs=5.0)
    with pytest.raises(ValueError, match="contradicts"):
        modal.load_record(path)
    with pytest.raises(ValueError, match="seed"):
        modal.shake_test(modal.Grid(**thesis_grid_config["model"]), **thesis_grid_config["test"], seed=1.5)


@pytest.mark.parametrize("value", [0.0, 3.5])
@pytest.mark.parametrize("method", ["era", "cera", "tcm"])
def test_constant_channel_is_refused(method, value):
    rec, _, dt = beam_record("irregular", 800)
    y = rec.acceleration.copy()
    y[:, 2] = value
    call = {
        "era": lambda: modal.era(y, dt, 2, rows=8, cols=300),
        "cera": lambda: modal.cera(y, dt, 2, cols=300),
        "tcm": lambda: modal.tcm(y, dt),
    }[method]
    with pytest.raises(ValueError, match="channel 2 is constant"):
        call()


def test_a_constant_channel_is_told_from_one_that_ends_where_it_began():
    """The check compares each channel sample by sample only where its last
    sample equals its first: a channel that ends where it began but varies is
    accepted, one constant only in its second data set is named with it, and
    one that varies only in its last sample is not constant."""
    from modal._checks import constant_channels

    t = np.arange(400) * 0.01
    y = np.stack([np.column_stack([np.sin(2 * np.pi * t), np.cos(3.1 * t), t]) for _ in range(2)])
    y[:, -1, 0] = y[:, 0, 0]  # ends where it began, varies between
    constant_channels("y", y)
    y[1, :, 1] = 0.25
    with pytest.raises(ValueError, match=r"y: channel 1 of data set 1 is constant \(0.25\)"):
        constant_channels("y", y)
    y[1, :, 1] = 0.25
    y[1, -1, 1] = 0.5  # varies in its last sample only
    y[0, 1:, 2] = y[0, -1, 2]  # varies in its first sample only
    constant_channels("y", y)
    y[0, 0, 2] = y[0, -1, 2]
    with pytest.raises(ValueError, match="channel 2 of data set 0 is constant"):
        constant_channels("y", y)


def test_channels_first_is_refused():
    rec, _, dt = beam_record("irregular", 800)
    for call in (lambda y: modal.era(y, dt, 1, rows=2, cols=2), lambda y: modal.tcm(y, dt),
                 lambda y: modal.cera(y, dt, 1, cols=2)):
        with pytest.raises(ValueError, match="transpose"):
            call(rec.acceleration.T)


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
    flagged(modal.cera, dependent, dt, 2, cols=600)
    with pytest.raises(ValueError, match=r"^n_modes = 3: H_c has fewer than 3 non-zero singular values"):
        flagged(modal.cera, dependent, dt, 3, cols=600)
    with pytest.raises(ValueError, match=r"^singular_values = 3: H_c has fewer than 3 non-zero singular values"):
        flagged(modal.cera, dependent, dt, 2, cols=600, singular_values=3)
    one_mode = np.column_stack([np.sin(2 * np.arange(400) * 0.05), -0.3 * np.sin(2 * np.arange(400) * 0.05)])
    with pytest.raises(ValueError, match=r"^n_modes = 2: the Hankel matrix has fewer than 4"):
        flagged(modal.era, one_mode, 0.05, 2, rows=10, cols=100)


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
    assert flagged(modal.tcm, rng.standard_normal((5, 3)), 0.01, lag=1).n_modes == 3
    # (random vel and acc are no velocity and acceleration of one motion, and 3 samples a short window: warned)
    with pytest.warns(modal.ModalWarning) as caught:
        assert modal.tcm(rng.standard_normal((3, 2)), 0.01, vel=rng.standard_normal((3, 2))).n_modes == 2
    assert [str(w.message).split(":")[1].split("(")[0].strip() for w in caught] == [
        "vel and acc are not velocity and acceleration of one motion in the same units", "short window"]
    with pytest.raises(ValueError, match="too few samples"):
        flagged(modal.tcm, rng.standard_normal((4, 3)), 0.01, lag=1)
    # ERA: 2 n_modes equal to the smaller Hankel dimension (l r = 6, m s = 8)
    sets = np.stack([np.column_stack([np.exp(-0.01 * k * np.arange(60)) * np.sin((0.3 + 0.2 * k) * np.arange(60) + j)
                                      for k in range(2)]) for j in range(2)])
    sets = sets + np.stack([np.column_stack([np.exp(-0.02 * np.arange(60)) * np.cos(1.1 * np.arange(60) + j)] * 2)
                            * [1.0, -0.5] for j in range(2)])
    assert flagged(modal.era, sets, 1.0, 3, rows=3, cols=4).n_modes == 3
    # CERA: n_modes equal to the m s Hankel columns
    assert flagged(modal.cera, rng.standard_normal((3, 50, 8)), 0.01, 6, cols=2).n_modes == 6
