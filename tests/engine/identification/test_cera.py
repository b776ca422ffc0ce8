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
