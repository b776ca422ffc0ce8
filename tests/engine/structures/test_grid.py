"""The finite-element model of the AFAL grid (thesis Sec. 7.1): closed forms,
symmetry, mass normalisation, convergence, gravity, nodes, bad parameters."""

import numpy as np
import pytest
import scipy.linalg

from modal import Grid, shake_test


# ---------------------------------------------------------------- the model
def test_strips_alone_are_euler_bernoulli_cantilevers(model):
    # Horizontal strips of negligible stiffness and mass, no gravity, no sensor
    # masses: each vertical strip is a clamped-free beam of length `height`,
    # f_k = (beta_k L)^2 / (2 pi L^2) sqrt(EI / (rho A)), four times over.
    grid = Grid(**{**model, "gravity": 0, "sensor_mass": 0, "n_horizontal": 24, "horizontal_y": None,
                   "thickness_horizontal": 1e-7, "strip_width_horizontal": 1e-4, "elements_per_bay": 1})
    b, t = grid.section(0)
    ei, rho_a = grid.youngs_modulus * b * t**3 / 12, grid.density * b * t
    beta_l = np.array([1.87510407, 4.69409113, 7.85475744])
    exact = beta_l**2 / (2 * np.pi * grid.height**2) * np.sqrt(ei / rho_a)
    np.testing.assert_allclose(grid.frequencies_hz(12), np.repeat(exact, 4), rtol=2e-5)


def test_modes_above_10_hz(grid):
    omega, _ = grid.modes(fmax_hz=50)
    assert np.sum(omega / (2 * np.pi) > 10) >= 5


def test_matrices_symmetric_positive_definite(model, grid):
    for name, a in (("K", grid.stiffness()), ("M", grid.mass())):
        assert np.allclose(a, a.T, rtol=0, atol=1e-13 * np.abs(a).max()), name
        scipy.linalg.cholesky(a)  # raises LinAlgError unless positive definite
    scipy.linalg.cholesky(Grid(**{**model, "gravity": 0}).stiffness())  # elastic part alone


def test_modes_are_mass_normalised_and_complete(grid):
    K, M = grid.stiffness(), grid.mass()
    omega, phi = grid.modes()
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(omega.size), atol=1e-9)
    np.testing.assert_allclose(phi.T @ K @ phi, np.diag(omega**2), atol=1e-9 * omega[-1] ** 2)
    # Independent check of the modal force and static response: sum over all
    # modes phi phi^T F / omega^2 = K^{-1} F for a unit force at a corner.
    f = np.zeros(K.shape[0])
    f[grid.dof(19)] = 1.0
    static = np.linalg.solve(K, f)
    np.testing.assert_allclose((phi / omega**2) @ (phi.T @ f), static, atol=1e-6 * np.abs(static).max())


@pytest.mark.slow
def test_mesh_convergence(model):
    coarse = Grid(**{**model, "elements_per_bay": 4}).frequencies_hz(4)
    fine = Grid(**{**model, "elements_per_bay": 8}).frequencies_hz(4)
    assert np.max(np.abs(fine / coarse - 1)) < 0.01


def test_gravity_stiffens_the_hanging_grid(model, grid):
    assert Grid(**{**model, "gravity": 0}).frequencies_hz(1)[0] < 0.7 * grid.frequencies_hz(1)[0]


def test_crossings_and_dofs(grid):
    nodes, xy = grid.crossings()
    assert nodes.size == 20 and np.array_equal(nodes, np.arange(20))
    np.testing.assert_allclose(xy[0], [0.0, 0.37])
    np.testing.assert_allclose(xy[-1], [1.0, 0.0])
    assert np.unique(grid.dof(nodes)).size == 20
    clamped = int(np.flatnonzero(np.isclose(grid.coordinates[:, 1], grid.height))[0])
    with pytest.raises(ValueError, match="clamped"):
        grid.dof(clamped)


# ---------------------------------------------------------------- time integration








# ---------------------------------------------------------------- manual steps




# ---------------------------------------------------------------- bad input


def test_bad_parameters(model, grid, settings):
    with pytest.raises(ValueError, match="thickness"):
        Grid(**{**model, "thickness": -1e-3})
    with pytest.raises(ValueError, match="horizontal_y"):
        Grid(**{**model, "horizontal_y": (0.1, 0.2, 0.3, 0.4, 0.5)})
    with pytest.raises(ValueError, match="poisson"):
        Grid(**{**model, "poisson": 0.5})
    with pytest.raises(ValueError, match="clamped"):
        shake_test(grid, **{**settings, "sensors": [int(np.flatnonzero(np.isclose(grid.coordinates[:, 1], grid.height))[0])]})
    with pytest.raises(ValueError, match="node"):
        shake_test(grid, **{**settings, "force_nodes": [10_000]})
    with pytest.raises(ValueError, match="damping"):
        shake_test(grid, **{**settings, "damping": 1.5})
    with pytest.raises(ValueError, match="distinct"):
        shake_test(grid, **{**settings, "sensors": [0, 0]})
    with pytest.raises(ValueError, match="fmax_hz"):
        shake_test(grid, **{**settings, "fmax_hz": 0.1})
    with pytest.raises(ValueError, match="grid"):
        shake_test("grid", **settings)
    with pytest.raises(ValueError, match="force_rms"):
        shake_test(grid, **{**settings, "force_rms": 0})
