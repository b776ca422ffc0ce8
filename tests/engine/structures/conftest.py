"""The thesis's grid (config/config.yaml ``grid``, its one source) and its shaking test."""

import pytest

from modal import Grid


@pytest.fixture(scope="module")
def model(thesis_grid_config):
    """The tuned grid's parameters (config ``grid.model``)."""
    return thesis_grid_config["model"]


@pytest.fixture(scope="module")
def grid(model):
    return Grid(**model)


@pytest.fixture(scope="module")
def settings(thesis_grid_config):
    """The thesis's shaking test (config ``grid.test``) without sensor noise."""
    return {k: v for k, v in thesis_grid_config["test"].items() if k != "noise"}
