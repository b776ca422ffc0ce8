"""The stabilisation diagram (modal.stabilisation): orders as truncations of
one decomposition, stability by nearest pole, the quality criteria, the
automatic selection of modes by clustering, refusals and boundaries."""

import dataclasses
import warnings

import numpy as np
import pandas as pd
import pytest

import modal
# No public door: the realisation at one order (the reference diagram), the
# spectrum, stability and clustering of hand-made pole tables.
from modal.identification._era import realise
from modal.identification._stabilisation import _mean_spectrum, _select_modes, _stability

from ..cases import flagged, BEAM, SENSORS_X, ambient_beam

def test_stabilisation_orders_are_truncations_of_one_decomposition():
    """The poles of order k equal ERA's with n_modes = k / 2."""
    acc, dt, _ = ambient_beam(duration_s=100)
    r = modal.correlations(modal.detrend(acc), 81)
    result = modal.stabilisation(r, dt, 12, rows=40, cols=40)
    assert sorted(result.poles["order"].unique()) == list(range(2, 13, 2))
    for order in (6, 12):
        era = flagged(modal.era, r, dt, order // 2, rows=40, cols=40)
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


def _per_order_reference(data, dt, max_order, rows, criteria):
    """The stabilisation diagram the straightforward way: ``realise`` at each
    order from the truncated decomposition, each order's poles compared with
    the previous order's through the whole MAC matrix."""

    y = data if data.ndim == 3 else data[None]
    m, n_samples, l = y.shape
    h_ext = modal.hankel(y, rows + 1, n_samples - rows)
    h0, h1 = h_ext[:-l], h_ext[l:]
    p, d, qt, _ = modal.decompose(h0, max_order, block=(l, m))
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
                         modal.mac(res.complex_shapes, shapes0)[np.arange(n), near] >= criteria.mac_min]
        cur.update(stable_freq=flags[0], stable_damping=flags[1], stable_shape=flags[2],
                   stable=flags[0] & flags[1] & flags[2])
        rows_out.append(cur)
        shapes_out.append(res.complex_shapes.T)
        previous = (res.freq_hz, res.damping, res.complex_shapes)
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


@pytest.mark.parametrize("n", [1, 2, 121, 5000])
def test_mean_spectrum_equals_the_direct_sum(n):
    """The spectrum behind the diagram (one long FFT of the summed
    autocorrelation when the padding allows) equals the root mean square of
    every series' tapered, zero-padded amplitude spectrum."""

    y = np.random.default_rng(n).standard_normal((3, n, 2)) * np.array([1.0, 30.0])
    freqs, spectrum = _mean_spectrum(y, 0.01)
    n_fft = max(n, 8192)
    taper = np.hanning(2 * n)[n:]
    direct = np.abs(np.fft.rfft(y * taper[None, :, None], n=n_fft, axis=1)) / n
    direct = np.sqrt(np.mean(direct**2, axis=(0, 2)))
    np.testing.assert_allclose(freqs, np.fft.rfftfreq(n_fft, 0.01))
    np.testing.assert_allclose(spectrum, direct, rtol=1e-9, atol=1e-12 * direct.max())


def test_stability_criteria_bounds_and_names():
    """StabilityCriteria accepts the closed bounds (mac_min = 1, min_poles = 1)
    and refuses the rest naming the argument."""
    StabilityCriteria = modal.StabilityCriteria
    assert StabilityCriteria(mac_min=1.0, mpc_min=1.0, mamc_min=0.0, min_poles=1).mac_min == 1.0
    for kwargs, name in [({"freq_rtol": 0.0}, "freq_rtol"), ({"cluster_distance": -1.0}, "cluster_distance"),
                         ({"mac_min": -0.1}, "mac_min"), ({"mamc_min": 1.5}, "mamc_min"),
                         ({"min_poles": 0}, "min_poles"), ({"min_poles": 2.5}, "min_poles")]:
        with pytest.raises(ValueError, match=f"^{name} must"):
            StabilityCriteria(**kwargs)


def test_stability_of_a_single_pole():
    """A table of one pole (the lowest order) has nothing to compare with:
    not stable, and no index past the table."""

    table = {"order": np.array([2]), "freq_hz": np.array([1.5]), "damping": np.array([0.01])}
    flags = _stability(table, np.ones((1, 3)), modal.StabilityCriteria())
    for key in ("stable_freq", "stable_damping", "stable_shape", "stable"):
        np.testing.assert_array_equal(flags[key], [False])


def _pole_table(freqs, shapes, stable=None, damping=None):
    """Hand-made poles, one per order (so the same-order rule never acts),
    damped 1-2 % at random unless ``damping`` is given."""
    n = len(freqs)
    rng = np.random.default_rng(5)
    damping = 0.01 + 0.01 * rng.random(n) if damping is None else np.broadcast_to(float(damping), n)
    return ({"order": 2 * np.arange(1, n + 1), "freq_hz": np.asarray(freqs, float),
             "damping": damping, "mpc": rng.random(n), "mamc": rng.random(n),
             "mpd": rng.random(n), "stable_freq": np.ones(n, bool) if stable is None else np.asarray(stable, bool),
             "physical": np.ones(n, bool)},
            np.asarray(shapes, float))


def select(poles, pole_shapes, cluster_distance, min_poles):
    """_select_modes with this cluster distance and no joining beyond it:
    the pole labels, the modes and their (here real) shapes."""
    criteria = modal.StabilityCriteria(cluster_distance=cluster_distance, merge_distance=cluster_distance)
    labels, modes, shapes, _, _ = _select_modes(poles, pole_shapes.astype(complex), criteria, min_poles)
    assert np.all(shapes.imag == 0)
    return labels, modes, shapes.real


def test_select_modes_on_a_known_pole_table():
    """_select_modes on hand-made poles: clusters of >= min_poles poles are
    modes numbered 1, 2, ... by frequency, with the members' mean and sample
    (ddof=1) standard deviation, and the medoid's shape (the member closest,
    in total, to the other members of its cluster)."""

    e = np.eye(3)
    a = [e[0] + [0, 1e-4 * i, 0] for i in range(3)]  # near-identical shapes, told apart by index
    freqs = [2.0, 2.002, 1.998, 1.003, 1.0, 0.998, 5.0, 3.0, 3.001]
    shapes = [e[1], e[1], e[1], a[0], a[1], a[2], e[2], e[2], e[2]]
    poles, pole_shapes = _pole_table(freqs, shapes, stable=[1, 1, 1, 1, 1, 1, 0, 1, 1])
    labels, modes, reps = select(poles, pole_shapes, cluster_distance=0.006, min_poles=3)
    np.testing.assert_array_equal(labels, [2, 2, 2, 1, 1, 1, 0, 0, 0])
    assert labels.dtype.kind == "i"
    np.testing.assert_array_equal(modes["mode"], [1, 2])
    np.testing.assert_array_equal(modes["n_poles"], [3, 3])
    for row, members in ((0, [3, 4, 5]), (1, [0, 1, 2])):
        for column in ("freq_hz", "damping", "mpc", "mamc"):
            assert modes[column].iloc[row] == pytest.approx(poles[column][members].mean(), rel=1e-12)
        assert modes["freq_spread_hz"].iloc[row] == pytest.approx(np.std(poles["freq_hz"][members], ddof=1), rel=1e-9)
        assert modes["damping_spread"].iloc[row] == pytest.approx(np.std(poles["damping"][members], ddof=1), rel=1e-9)
    np.testing.assert_array_equal(reps[:, 0], a[1])  # the middle frequency, 1.0 Hz, is the medoid
    np.testing.assert_array_equal(reps[:, 1], e[1])


@pytest.mark.parametrize("n_poles, min_poles, n_modes", [(3, 3, 1), (2, 2, 1), (2, 3, 0), (1, 1, 0)])
def test_select_modes_needs_min_poles_candidates(n_poles, min_poles, n_modes):
    """Exactly min_poles (at least 2) coincident poles make a mode; fewer make
    none, and then the shapes are an empty (n_channels, 0) array."""

    poles, pole_shapes = _pole_table([1.0] * n_poles, [[1.0, 2.0, 0.0, 1.0]] * n_poles)
    labels, modes, reps = select(poles, pole_shapes, cluster_distance=0.02, min_poles=min_poles)
    assert len(modes) == n_modes and reps.shape == (4, n_modes)
    np.testing.assert_array_equal(labels, [n_modes] * n_poles)


def test_select_modes_without_a_large_enough_cluster():
    """Three candidates in three distant clusters, min_poles 3: no mode, and
    the shapes are an empty (n_channels, 0) array."""

    poles, pole_shapes = _pole_table([1.0, 2.0, 3.0], [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    labels, modes, reps = select(poles, pole_shapes, cluster_distance=0.02, min_poles=3)
    assert modes.empty and reps.shape == (2, 0) and not labels.any()
    assert list(modes.columns) == ["mode", "freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std",
                                   "damping_spread", "n_poles", "mpc", "mamc", "mpd", "close", "close_mac",
                                   "second_freq_hz", "second_damping", "flag"]
    assert all(modes.drop(columns="flag").dtypes == float) and modes["flag"].dtype == object


def test_stabilisation_reports_progress_per_order():
    """progress(done, total) after each order: (1, 6), ..., (6, 6) for orders 2..12."""
    acc, dt, _ = ambient_beam(duration_s=30)
    r = modal.correlations(modal.detrend(acc), 81)
    calls = []
    modal.stabilisation(r, dt, 12, rows=40, cols=40, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(i, 6) for i in range(1, 7)]


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
        "no mode selected: no pole was computed (H(0) has too low a numerical rank): the data hold (almost) no "
        "oscillation; check the record and the channels used"]
    POLE_COLUMNS = ["order", "freq_hz", "damping", "mpc", "mamc", "real_pole",
                    "stable_freq", "stable_damping", "stable_shape", "stable"]
    MODE_COLUMNS = ["mode", "freq_hz", "freq_std_hz", "freq_spread_hz", "damping", "damping_std", "damping_spread",
                    "n_poles", "mpc", "mamc", "mpd", "close", "close_mac", "second_freq_hz", "second_damping", "flag"]

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


def _diagram(*args, **kwargs):
    """modal.stabilisation(*args, **kwargs) and the messages of the warnings it
    issued, which must all be ModalWarnings (noisy data leave flagged orders)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = modal.stabilisation(*args, **kwargs)
    assert all(issubclass(w.category, modal.ModalWarning) for w in caught), [str(w.message) for w in caught]
    return result, [str(w.message) for w in caught]


def _tapered_spectrum(y, dt):
    """The root mean square of every series' tapered (half Hann), zero-padded
    (to 8192 samples at least) amplitude spectrum."""
    n = y.shape[1]
    n_fft = max(n, 8192)
    taper = np.hanning(2 * n)[n:]
    direct = np.abs(np.fft.rfft(y * taper[None, :, None], n=n_fft, axis=1)) / n
    return np.fft.rfftfreq(n_fft, dt), np.sqrt(np.mean(direct**2, axis=(0, 2)))


def test_stabilisation_quality_criteria_and_outputs():
    """On noisy correlations off the thesis geometry: ``physical`` is exactly
    the documented quality criteria (each of which excludes some poles), only
    physical stable poles join modes, modes lie below fmax, the
    default min_poles is 40 % of the orders (at least 3), and the result keeps
    the singular values of H(0), the criteria and the spectrum of the data
    from ``start`` on."""
    acc, dt, f_exact = ambient_beam(duration_s=120, seed=5)
    acc = acc + 0.05 * acc.std(axis=0) * np.random.default_rng(2).standard_normal(acc.shape)
    data = modal.correlations(modal.detrend(acc), 81)
    criteria = modal.StabilityCriteria(max_damping=0.05, mpc_min=0.8, mamc_min=0.6, cluster_distance=0.03)
    fmax = 0.5 * (f_exact[1] + f_exact[2])
    result, _ = _diagram(data, dt, 40, 40, start=3, fmax=fmax, criteria=criteria)
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
    # 20 orders: the default min_poles is ceil(0.4 * 20) = 8
    explicit, _ = _diagram(data, dt, 40, 40, start=3, fmax=fmax, criteria=dataclasses.replace(criteria, min_poles=8))
    pd.testing.assert_frame_equal(result.modes, explicit.modes)
    pd.testing.assert_frame_equal(result.poles, explicit.poles)
    assert result.modes["n_poles"].min() >= 8
    assert result.criteria == criteria
    h0 = modal.hankel(data, 40, 81 - 3 - 40, 3)  # every column from start = 3 on
    # all of them from the thin SVD, the leading max_order = 40 from the Gram route (modal.decompose)
    full = np.linalg.svd(h0, compute_uv=False)
    assert len(result.singular_values) in (40, len(full))
    np.testing.assert_allclose(result.singular_values, full[:len(result.singular_values)], rtol=1e-10)
    hz, spectrum = _tapered_spectrum(data[:, 3:], dt)
    np.testing.assert_allclose(result.spectrum_hz, hz, rtol=1e-15)
    np.testing.assert_allclose(result.spectrum, spectrum, rtol=1e-9, atol=1e-12 * spectrum.max())

    # 5 orders: 40 % is 2, raised to 3; an explicit min_poles is kept
    default, _ = _diagram(data, dt, 10, 40)
    three, _ = _diagram(data, dt, 10, 40, criteria=modal.StabilityCriteria(min_poles=3))
    pd.testing.assert_frame_equal(default.modes, three.modes)
    pd.testing.assert_frame_equal(default.poles, three.poles)
    two, _ = _diagram(data, dt, 10, 40, criteria=modal.StabilityCriteria(min_poles=2))
    assert two.modes["n_poles"].min() >= 2 and len(two.modes) >= len(three.modes)


def test_mean_spectrum_of_a_spectral_null_is_zero_not_nan():
    """Six samples whose tapered values are 1, -1, 0, ...: their sum, the
    spectrum at 0 Hz, is zero; rounding in the autocorrelation route leaves
    the power there at -2e-16, which must read as 0, not as NaN."""
    import warnings

    taper = np.hanning(12)[6:]
    y = np.zeros((1, 6, 1))
    y[0, :2, 0] = np.array([1.0, -1.0]) / taper[:2]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        freqs, spectrum = _mean_spectrum(y, 0.01)
    assert np.all(np.isfinite(spectrum)) and spectrum[0] <= 1e-7 * spectrum.max()
    np.testing.assert_allclose(spectrum, np.abs(np.fft.rfft(y[0, :, 0] * taper, n=8192)) / 6, atol=1e-7)


def test_select_modes_joins_groups_by_average_linkage():
    """Three poles of one shape and damping at 1.00, 1.01 and 1.02 Hz
    (distances 0.0099, 0.0098 and 0.0196), cluster distance 0.012: 1.01 and
    1.02 Hz join; 1.00 Hz is 0.0147 from them on average, so it stays out
    (single linkage, or a distance matrix shrunk by 2/3, would join all
    three)."""

    poles, pole_shapes = _pole_table([1.0, 1.01, 1.02], [[1.0, 2.0]] * 3, damping=0.02)
    labels, modes, _ = select(poles, pole_shapes, cluster_distance=0.012, min_poles=2)
    np.testing.assert_array_equal(labels, [0, 1, 1])
    assert modes["n_poles"].tolist() == [2] and modes["freq_hz"].iloc[0] == pytest.approx(1.015, rel=1e-12)


def test_select_modes_weighs_damping_with_frequency():
    """The pattern of Palisaden's 90 minutes at 3.6 Hz (issue 21), one shape
    throughout: orders 10-22 hold one pole, 3.618 Hz damped 2.7 %; from order
    26 two: 3.605 Hz at 0.9 % (orders 26-44) and 3.680 Hz at 2.4 % (26-60).
    By frequency alone the low-order poles are 0.004 from the 0.9 % ones and
    0.017 from the 2.4 % ones, and join the former: two modes. As poles
    (frequency and damping), the distances are 0.0183 and 0.0171: they join
    the 2.4 % ones, one mode of 25 poles; the 0.9 % poles, 10 of the 12
    needed, are a candidate. Equal damping leaves the distance by frequency."""
    low, late, high = np.arange(10, 23, 2), np.arange(26, 45, 2), np.arange(26, 61, 2)
    poles, pole_shapes = _pole_table(np.repeat([3.618, 3.605, 3.680], [len(low), len(late), len(high)]),
                                     [[1.0, 0.6, -0.3]] * (len(low) + len(late) + len(high)))
    poles["order"] = np.concatenate([low, late, high])
    poles["damping"] = np.repeat([0.027, 0.009, 0.024], [len(low), len(late), len(high)])
    labels, modes, _, candidates, _ = _select_modes(poles, pole_shapes.astype(complex), modal.StabilityCriteria(), 12)
    np.testing.assert_array_equal(labels, np.repeat([1, 0, 1], [len(low), len(late), len(high)]))
    assert modes["n_poles"].tolist() == [25]
    assert modes["freq_hz"].iloc[0] == pytest.approx((7 * 3.618 + 18 * 3.680) / 25, rel=1e-12)
    assert candidates["n_poles"].tolist() == [10] and candidates["freq_hz"].iloc[0] == pytest.approx(3.605)
    # one pole pair: |lambda_1 - lambda_2| / max |lambda|, about sqrt((df / f)^2 + (d zeta)^2); |lambda| = 2 pi f
    # whatever the damping (at 25 %, 1 % apart in frequency is 0.0099 apart, not 0.0102 or 0.0100)
    for freqs, damping, apart in (([3.618, 3.605], [0.027, 0.027], 0.0035931),
                                  ([3.618, 3.605], [0.027, 0.009], 0.0183262),
                                  ([2.0, 2.02], [0.25, 0.25], 0.0099010)):
        pair, shape = _pole_table(freqs, [[1.0, 0.6, -0.3]] * 2)
        pair["damping"] = np.array(damping)
        cut = modal.StabilityCriteria(cluster_distance=apart + 3e-5, merge_distance=1e-6)
        assert _select_modes(pair, shape.astype(complex), cut, 2)[1]["n_poles"].tolist() == [2]
        cut = modal.StabilityCriteria(cluster_distance=apart - 3e-5, merge_distance=1e-6)
        assert len(_select_modes(pair, shape.astype(complex), cut, 2)[1]) == 0


def test_select_modes_numbers_modes_by_mean_frequency():
    """Modes are numbered by their members' mean frequency, not by a sum that
    grows with the number of poles: five poles near 1 Hz are mode 1 and two
    near 2 Hz mode 2 (the sums, 5 and 4 Hz, or sums times counts, 25 and 8,
    would order them the other way)."""

    freqs = [2.0, 2.001, 1.0, 1.001, 0.999, 1.0005, 0.9995]
    shapes = [[0.0, 1.0, 1.0]] * 2 + [[1.0, 0.0, 0.5]] * 5
    poles, pole_shapes = _pole_table(freqs, shapes)
    labels, modes, reps = select(poles, pole_shapes, cluster_distance=0.01, min_poles=2)
    np.testing.assert_array_equal(labels, [2, 2, 1, 1, 1, 1, 1])
    np.testing.assert_array_equal(modes["n_poles"], [5, 2])
    np.testing.assert_allclose(modes["freq_hz"], [1.0, 2.0005], rtol=1e-12)
    np.testing.assert_array_equal(reps.T, [[1.0, 0.0, 0.5], [0.0, 1.0, 1.0]])


def test_select_modes_one_pole_modes_have_nan_spread_silently():
    """min_poles = 1: two distant poles are two one-pole modes, whose sample
    standard deviations (ddof = 1) are NaN without a floating-point warning;
    their means and shapes are the poles' own."""
    import warnings

    poles, pole_shapes = _pole_table([3.0, 1.0], [[1.0, 0.0], [0.0, 1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        labels, modes, reps = select(poles, pole_shapes, cluster_distance=0.02, min_poles=1)
    np.testing.assert_array_equal(labels, [2, 1])
    np.testing.assert_array_equal(modes["n_poles"], [1, 1])
    np.testing.assert_array_equal(modes["freq_hz"], [1.0, 3.0])
    np.testing.assert_array_equal(modes["damping"], poles["damping"][[1, 0]])
    assert modes["freq_spread_hz"].isna().all() and modes["damping_spread"].isna().all()
    np.testing.assert_array_equal(reps, [[0.0, 1.0], [1.0, 0.0]])


def test_a_slowly_growing_mode_is_never_physical():
    """A mode with damping -0.5 % (slowly growing) beside one with +1 %, with
    a little noise: the growing mode's poles are stable from order to order,
    yet never physical (damping must be positive); the decaying one's are."""
    dt = 0.01
    t = dt * np.arange(2000)
    w_grow, w_decay = 2 * np.pi * 1.5, 2 * np.pi * 4.0
    grow = np.exp(0.005 * w_grow * t) * np.cos(w_grow * t)
    decay = np.exp(-0.01 * w_decay * t) * np.cos(w_decay * t)
    y = np.column_stack([grow + decay, grow - 0.5 * decay])
    y = y + 1e-6 * np.random.default_rng(3).standard_normal(y.shape)
    result, _ = _diagram(y, dt, 8, 40)
    growing = np.isclose(result.poles["freq_hz"], 1.5, rtol=1e-3)
    assert growing.sum() >= 3 and result.poles.loc[growing, "stable"].sum() >= 2
    np.testing.assert_allclose(result.poles.loc[growing, "damping"], -0.005, rtol=0.02)
    assert not result.poles.loc[growing, "physical"].any()
    assert result.poles.loc[np.isclose(result.poles["freq_hz"], 4.0, rtol=1e-3), "physical"].any()
