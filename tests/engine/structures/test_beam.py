"""The simply supported beam against closed form (thesis Eqs. 1-5)."""

import numpy as np
import pytest
from scipy.integrate import quad

def test_beam_frequencies_closed_form(beam):
    omega = beam.natural_frequencies(6)
    # omega_r = sqrt(EI/m) (r pi / L)^2 = sqrt(30) (r pi / 5)^2; Table 1's "actual" column
    np.testing.assert_allclose(omega[:3], [2.1623, 8.6493, 19.461], rtol=5e-5)
    np.testing.assert_allclose(omega / omega[0], np.arange(1, 7) ** 2, rtol=1e-14)


def test_beam_modes_are_mass_orthonormal(beam):
    # Eq. (5): int m phi_r phi_s dx = delta_rs
    for r in range(1, 5):
        for s in range(1, 5):
            val, _ = quad(lambda x: beam.mass_per_length * beam.mode_shapes([x], 4)[0, r - 1]
                          * beam.mode_shapes([x], 4)[0, s - 1], 0, beam.length)
            assert val == pytest.approx(float(r == s), abs=1e-10)
