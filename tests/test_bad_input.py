"""Every engine entry point rejects bad input with a ValueError naming the argument."""

import numpy as np
import pytest

import modal

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


@pytest.mark.parametrize("method", ["era", "cera"])
def test_hankel_larger_than_record(y, method):
    with pytest.raises(ValueError, match="reduce rows or cols"):
        CALLS[method](y, cols=400)


def test_hankel_rows_too_many(y):
    with pytest.raises(ValueError, match="reduce rows or cols"):
        modal.era(y, DT, 1, rows=301, cols=100)  # needs 402 samples with H(1)


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
