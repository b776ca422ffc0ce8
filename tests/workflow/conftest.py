"""Fixtures of the workflow, report and notebook tests (they need the
``workflow`` extra: snakemake, pyyaml, papermill, matplotlib, jinja2). The
engine tests beside ``tests/conftest.py`` need only numpy, scipy, pandas."""

import pytest
from workflow_run import SMALL_CONFIG_FILE, copy_project, run_snakemake


@pytest.fixture(scope="session")
def small_workflow(tmp_path_factory):
    """A copy of the workflow in a temporary directory, run to completion with
    the small config ``config/test/config.small.yaml`` (3 seeds, short sweeps)."""
    tmp = copy_project(tmp_path_factory.mktemp("wf"))
    run_snakemake(tmp, "--configfile", SMALL_CONFIG_FILE)
    return tmp
