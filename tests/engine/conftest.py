"""The thesis's virtual grid (Sec. 7.1-7.2), read from config/config.yaml, its one source."""

from pathlib import Path

import pytest
import yaml


@pytest.fixture(scope="session")
def thesis_grid_config():
    """The ``grid`` block of config/config.yaml: ``model`` (a :class:`modal.Grid`)
    and ``test`` (the settings of :func:`modal.shake_test`)."""
    config = Path(__file__).resolve().parents[2] / "config" / "config.yaml"
    return yaml.safe_load(config.read_text())["grid"]
