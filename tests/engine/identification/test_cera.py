"""CERA (thesis Eqs. 46-52) through modal.cera: exact when the Hankel matrix
spans whole periods, biased when not, several data sets, flags."""

import numpy as np
import pytest
from hypothesis import given

import modal

from ..cases import (flagged, LAYOUTS, PER_PERIOD, PROPERTY, _records, acos_tolerance, beam_cases, beam_record, diag_mac,
                     two_sinusoids)

@pytest.mark.parametrize("periods", [1, 2, 3])
def test_cera_exact_when_s_spans_whole_periods(demo, periods):
    s = 360 * periods  # dt = T_6 / 10 = T_1 / 360
    rec = demo["make"](s + 1)
    res = flagged(modal.cera, rec.acceleration, demo["dt"], 6, cols=s)
    tol = acos_tolerance(demo["omega"], demo["dt"])
    assert np.all(np.abs(res.omega / demo["omega"] - 1) < tol)
    assert np.all(np.diag(modal.mac(res.shapes, rec.shapes)) >= 1 - 1e-10)
    assert not res.real_pole.any()


def test_cera_biased_when_s_cuts_a_period(demo):
    # The invariant the thesis's Table 7 shows: off whole periods, mode 1 is biased.
    rec = demo["make"](301)
    res = flagged(modal.cera, rec.acceleration, demo["dt"], 6, cols=300)
    assert abs(res.omega[0] / demo["omega"][0] - 1) > 1e-3


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("periods", [1, 2])
def test_cera_exact_on_every_layout(layout, periods):
    cols = periods * PER_PERIOD
    rec, omega, dt = beam_record(layout, cols + 1)
    res = flagged(modal.cera, rec.acceleration, dt, 6, cols=cols)
    assert np.all(np.abs(res.omega / omega - 1) < max(1e-8, *acos_tolerance(omega, dt)))
    assert np.all(diag_mac(res.shapes, rec.shapes) >= 1 - 1e-8)
    assert not res.real_pole.any()


def test_cera_with_several_data_sets_is_exact():
    sets = [beam_record("irregular", PER_PERIOD + 1, impact=x)[0].velocity for x in (0.7, 2.9)]
    _, omega, dt = beam_record("irregular", 2)
    res = flagged(modal.cera, np.stack(sets), dt, 6, cols=PER_PERIOD)
    assert np.all(np.abs(res.omega / omega - 1) < 1e-8)


@PROPERTY
@given(beam_cases())
def test_property_tcm_and_cera_exact_over_whole_periods(case):
    beam, n, sensors, impacts, _ = case
    per_period = 10 * n**2
    recs, omega, dt = _records(beam, n, sensors, impacts[:1], 0.0, 2 * per_period + 1)
    rec = recs[0]
    if len(sensors) == n:  # the TCM needs exactly one sensor per mode
        tcm = flagged(modal.tcm, rec.acceleration[:-1], dt, vel=rec.velocity[:-1])
        np.testing.assert_allclose(tcm.omega, omega, rtol=1e-8)
        assert np.all(diag_mac(tcm.shapes, rec.shapes) >= 1 - 1e-8)
    cera = flagged(modal.cera, rec.acceleration, dt, n, cols=2 * per_period)
    assert np.all(np.abs(cera.omega / omega - 1) < np.maximum(1e-7, acos_tolerance(omega, dt, 1e-11)))
    assert np.all(diag_mac(cera.shapes, rec.shapes) >= 1 - 1e-7)


def test_cera_eigenvalues_and_start():
    """CERA over whole periods: lambda = cos(omega dt) exactly; ``start``
    shifts the Hankel matrix (same as slicing the record)."""
    dt, _, _, acc = two_sinusoids(omega=(2.0, 5.0))
    n_period = int(round(np.pi / dt))  # one period of omega = 2
    res = flagged(modal.cera, acc, dt, 2, cols=2 * n_period)
    np.testing.assert_allclose(res.eigenvalues, np.cos(np.array([2.0, 5.0]) * dt), rtol=1e-12)
    damped = acc * np.exp(-0.03 * dt * np.arange(len(acc)))[:, None]
    a = flagged(modal.cera, damped, dt, 2, cols=2 * n_period, start=37)
    b = flagged(modal.cera, damped[37:], dt, 2, cols=2 * n_period)
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=1e-13)
    unshifted = flagged(modal.cera, damped, dt, 2, cols=2 * n_period)
    assert np.max(np.abs(a.eigenvalues - unshifted.eigenvalues)) > 1e-9


def test_cera_flags_a_mode_near_nyquist_aliased():
    dt = 0.01
    k = np.arange(500)
    y = np.column_stack([np.cos(0.99 * np.pi * k), np.sin(0.3 * k)])
    res = flagged(modal.cera, y, dt, 2, cols=400)
    np.testing.assert_array_equal(res.aliased, [False, True])


# The choices the thesis's text allows (Sec. 5.2: retained singular values; Eq. 52 as printed or symmetrised).

@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("eigenproblem", ["symmetrised", "as_printed"])
def test_cera_choices_exact_over_whole_periods(layout, eigenproblem):
    # Whole periods of undamped modes: R_1 is symmetric, both readings of Eq. (52) are exact,
    # on the thesis's layout and off it.
    rec, omega, dt = beam_record(layout, PER_PERIOD + 1)
    res = flagged(modal.cera, rec.displacement, dt, 6, cols=PER_PERIOD, eigenproblem=eigenproblem)
    assert np.all(np.abs(res.omega / omega - 1) < max(1e-8, *acos_tolerance(omega, dt)))
    assert np.all(diag_mac(res.shapes, rec.shapes) >= 1 - 1e-8)


@pytest.mark.parametrize("layout", ["thesis", "irregular", "other_beam"])
def test_cera_as_printed_is_the_lag_one_tcm_of_eq_48(layout):
    # Off whole periods R_1 is not symmetric. With every singular value retained, Eq. (52) as printed is
    # Eq. (48)'s lambda A y = B y with A = H_c(k) H_c(k)^T, B = H_c(k+1) H_c(k)^T, B as it is; the default
    # symmetrises B (as the lag-one TCM does), and the two differ.
    cols = 284  # 2.37 fundamental periods at dt = T_1 / 120 (mode 1 then comes out a real pole)
    rec, omega, dt = beam_record(layout, 3 * cols + 1)
    y, dt = rec.displacement[::3], 3 * dt
    a, b = y[:cols].T @ y[:cols], y[1:cols + 1].T @ y[:cols]
    literal = flagged(modal.cera, y, dt, 6, cols=cols, eigenproblem="as_printed")
    np.testing.assert_allclose(np.sort(literal.eigenvalues), np.sort(np.linalg.eigvals(np.linalg.solve(a, b)).real),
                               rtol=1e-9)
    default = flagged(modal.cera, y, dt, 6, cols=cols)
    assert np.max(np.abs(np.sort(default.eigenvalues) - np.sort(literal.eigenvalues))) > 1e-4
    symmetric = flagged(modal.tcm, y[:cols + 1], dt, lag=1)
    np.testing.assert_allclose(np.sort(default.eigenvalues), np.sort(symmetric.eigenvalues), rtol=1e-9)


def test_cera_retains_the_singular_values_asked_for():
    # Six modes participate. Three singular values (Sec. 5.2's n) realise three modes; six realise all six,
    # of which the three lowest are returned: exact over whole periods, unlike three (spillover).
    rec, omega, dt = beam_record("irregular", PER_PERIOD + 1)
    six = flagged(modal.cera, rec.acceleration, dt, 3, cols=PER_PERIOD, singular_values=6)
    np.testing.assert_allclose(six.omega, omega[:3], rtol=1e-8)
    all_six = flagged(modal.cera, rec.acceleration, dt, 6, cols=PER_PERIOD)
    np.testing.assert_allclose(six.eigenvalues, all_six.eigenvalues[:3], rtol=1e-12)
    three = flagged(modal.cera, rec.acceleration, dt, 3, cols=PER_PERIOD)
    assert three.omega.size == 3 and np.max(np.abs(three.omega / omega[:3] - 1)) > 1e-2
    assert three.singular_values.size == 6  # all of H_c's, whatever is retained


def test_cera_thesis_table_7_reading():
    # The reading under which Table 7's CERA column reproduces (docs/thesis.md): beam of Sec. 6.4,
    # dt = pi / (5 omega_3) (Sec. 3.4's guideline for n = 3 identified modes), s = 500 from t = 0,
    # three singular values, Eq. (52) as printed, the impulse response's displacement.
    beam = modal.SimplySupportedBeam(10.0, 20.0, 1.0)
    omega = beam.natural_frequencies(6)
    dt = np.pi / (5 * omega[2])
    rec = modal.beam_impulse_response(beam, 6, 20 / 7, 10 / 7 * np.arange(1, 7), dt, 501)
    res = flagged(modal.cera, rec.displacement, dt, 3, cols=500, eigenproblem="as_printed")
    np.testing.assert_array_equal(np.round(res.omega, 3), [0.434, 1.722, 3.972])
    default = flagged(modal.cera, rec.displacement, dt, 3, cols=500)
    assert round(default.omega[0], 3) != 0.434


@pytest.mark.parametrize("kwargs, match", [
    ({"singular_values": 2}, "singular_values"), ({"singular_values": 7}, "singular_values"),
    ({"eigenproblem": "literal"}, "eigenproblem"),
])
def test_cera_refuses_bad_choices(kwargs, match):
    rec, _, dt = beam_record("thesis", 50)
    with pytest.raises(ValueError, match=match):
        modal.cera(rec.acceleration, dt, 3, cols=40, **kwargs)


def test_cera_as_printed_flags_a_complex_pair():
    # Eq. (52)'s matrix is not symmetric: here (dt = T_1 / 60, the sixth mode folded onto the fifth) two of its
    # eigenvalues form a complex pair, which no frequency of Eq. (30) matches: flagged as a real pole is.
    rec, _, dt = beam_record("irregular", 6 * 142 + 1)
    res = flagged(modal.cera, rec.displacement[::6], 6 * dt, 6, cols=142, eigenproblem="as_printed")
    assert res.real_pole.sum() == 2 and res.eigenvalues[res.real_pole][0] == res.eigenvalues[res.real_pole][1]
    assert not flagged(modal.cera, rec.displacement[::6], 6 * dt, 6, cols=142).real_pole[-2:].all()
