"""TCM, ERA and CERA against closed form and the thesis's Tables 1 and 2."""

import numpy as np
import pytest

import modal

THESIS_SAMPLES = 3594  # t = 0 ... 29.001 s: "truncated after 29 sec., or ten times the fundamental period"


@pytest.mark.parametrize("zeta", [0.0, 0.005, 0.02, 0.05])
def test_era_exact_on_noise_free_beam(demo, zeta):
    rec = demo["make"](THESIS_SAMPLES, damping=zeta)
    res = modal.era(rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    np.testing.assert_allclose(res.omega, demo["omega"], rtol=1e-8)
    np.testing.assert_allclose(res.damping, zeta, rtol=1e-8, atol=1e-10)
    assert not res.real_pole.any()
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)
    np.testing.assert_allclose(res.mamc, 1, atol=1e-6)
    np.testing.assert_allclose(res.mpc, 1, atol=1e-6)
    # exactly 2n = 12 singular values carry the response
    sv = res.singular_values
    assert sv[11] / sv[0] > 1e-8 and sv[12] / sv[0] < 1e-10


# Thesis Tables 1 and 2, printed digits (TCM with exact velocities, ERA r=24, l=6, s=100, m=1)
TABLE_1 = {"tcm": [2.1659, 8.6617, 19.474], "era": [2.1623, 8.6493, 19.461]}
TABLE_2 = {"tcm": [2.1711, 8.6614, 19.407], "era": [2.1623, 8.6493, 19.461]}


def _printed(values, published):
    """Round each value to the number of significant digits printed in the thesis."""
    out = []
    for v, p in zip(values, published):
        decimals = len(str(p).split(".")[1])
        out.append(round(float(v), decimals))
    return out


@pytest.mark.parametrize("zeta, table", [(0.0, TABLE_1), (0.05, TABLE_2)])
def test_thesis_tables_1_and_2_to_printed_digits(demo, zeta, table):
    rec = demo["make"](THESIS_SAMPLES, damping=zeta)
    tcm = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity)
    era = modal.era(rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    assert _printed(tcm.omega[:3], table["tcm"]) == table["tcm"]
    assert _printed(era.omega[:3], table["era"]) == table["era"]


def test_tcm_duration_truncates_inner_product(demo):
    rec = demo["make"](5000)
    full = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity, duration=29.001)
    assert _printed(full.omega[:3], TABLE_1["tcm"]) == TABLE_1["tcm"]


def test_tcm_with_integrated_velocity_stays_close(demo):
    # vel=None integrates the acceleration, as an experiment must; on Table 2's case
    # the frequencies move by less than 1e-3 relative.
    rec = demo["make"](THESIS_SAMPLES, damping=0.05)
    exact = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity)
    integ = modal.tcm(rec.acceleration, demo["dt"])
    np.testing.assert_allclose(integ.omega, exact.omega, rtol=1e-3)


def test_tcm_shapes_match_exact_modes(demo):
    rec = demo["make"](3600)  # ten whole fundamental periods: TCM is exact
    res = modal.tcm(rec.acceleration, demo["dt"], vel=rec.velocity)
    np.testing.assert_allclose(res.omega, demo["omega"], rtol=1e-9)
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)


def _acos_tolerance(omega, t_o, dlam=1e-12):
    """omega = acos(lambda) / T_o, so d omega / omega = d lambda / (omega T_o sin(omega T_o)).

    Over whole fundamental periods the sampled modes are exactly orthogonal
    (sum_k e^{i (w_r +- w_s) k dt} = 0), so lambda_r = cos(w_r T_o) exactly and the
    only error is round-off in lambda, taken as 1e-12 (about 1e4 eps)."""
    return dlam / (omega * t_o * np.abs(np.sin(omega * t_o)))


@pytest.mark.parametrize("lag", [1, 2, 3])
def test_tcm_lagged_exact_over_whole_periods(demo, lag):
    rec = demo["make"](3600 + lag)
    res = modal.tcm(rec.acceleration, demo["dt"], lag=lag)
    tol = _acos_tolerance(demo["omega"], lag * demo["dt"])
    assert np.all(np.abs(res.omega / demo["omega"] - 1) < tol)
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)


@pytest.mark.parametrize("periods", [1, 2, 3])
def test_cera_exact_when_s_spans_whole_periods(demo, periods):
    s = 360 * periods  # dt = T_6 / 10 = T_1 / 360
    rec = demo["make"](s + 1)
    res = modal.cera(rec.acceleration, demo["dt"], 6, cols=s)
    tol = _acos_tolerance(demo["omega"], demo["dt"])
    assert np.all(np.abs(res.omega / demo["omega"] - 1) < tol)
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)
    assert not res.real_pole.any()


def test_cera_biased_when_s_cuts_a_period(demo):
    # The invariant the thesis's Table 7 shows: off whole periods, mode 1 is biased.
    rec = demo["make"](301)
    res = modal.cera(rec.acceleration, demo["dt"], 6, cols=300)
    assert abs(res.omega[0] / demo["omega"][0] - 1) > 1e-3


def test_era_multiple_data_sets_identify_repeated_frequency():
    # Two modes with the same frequency and different shapes: one data set sees
    # only one combination; m = 2 sets with different excitations resolve both.
    w = np.array([2.0, 2.0, 5.0])
    shapes = np.array([[1.0, 0.0, 0.5], [0.0, 1.0, -0.5], [0.7, 0.4, 1.0]])
    dt = 0.05
    sets = [modal.impulse_response(w, shapes, f, dt, 400, 0.01).acceleration
            for f in ([1.0, 0.2, 0.5], [0.1, 1.0, -0.3])]
    res = modal.era(np.stack(sets), dt, 3, rows=10, cols=100)
    np.testing.assert_allclose(res.omega, w, rtol=1e-8)
    with pytest.raises(ValueError, match="n_modes"):
        modal.era(sets[0], dt, 3, rows=10, cols=100)


def test_modal_result_frame(demo):
    rec = demo["make"](THESIS_SAMPLES)
    res = modal.era(rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    frame = res.to_frame()
    assert list(frame["mode"]) == [1, 2, 3, 4, 5, 6]
    assert {"omega", "freq_hz", "damping", "real_pole", "mamc", "mpc", "phi_1", "phi_6"} <= set(frame)
    np.testing.assert_allclose(frame["freq_hz"], demo["omega"] / (2 * np.pi), rtol=1e-8)
    assert np.all(np.diff(res.omega) > 0)


def test_mac_properties():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((6, 3))
    m = modal.mac(a, a)
    np.testing.assert_allclose(np.diag(m), 1)
    assert np.all((m >= 0) & (m <= 1 + 1e-12))
    np.testing.assert_allclose(modal.mac(a, -3 * a), m)
    q, _ = np.linalg.qr(a)
    np.testing.assert_allclose(modal.mac(q, q), np.eye(3), atol=1e-12)


@pytest.mark.parametrize("method", ["tcm", "era", "cera"])
def test_study_frame_is_to_frame_with_labels(demo, method):
    """modal.thesis.study._frame builds in one call what renaming and inserting
    into ModalResult.to_frame() gives (the identified-modes files depend on it)."""
    import pandas as pd

    from modal.thesis.study import _frame

    rec = demo["make"](THESIS_SAMPLES, damping=0.01)
    if method == "tcm":
        res = modal.tcm(rec.acceleration[:, :4], demo["dt"], vel=rec.velocity[:, :4])
    elif method == "era":
        res = modal.era(rec.acceleration, demo["dt"], 6, rows=24, cols=100)
    else:
        res = modal.cera(rec.acceleration, demo["dt"], 6, cols=360)
    labels = dict(case="c1", damping=0.01, noise=0.0, method=method, n=6, cols=-1, seed=-1)
    expected = res.to_frame().rename(columns={"damping": "damping_id"}).drop(columns="method")
    for key, value in reversed(list(labels.items())):
        expected.insert(0, key, value)
    pd.testing.assert_frame_equal(_frame(res, **labels), expected, check_exact=True)
