"""Fixtures of the workflow, report and notebook tests (they need the
``workflow`` extra: snakemake, pyyaml, papermill, matplotlib, jinja2). The
engine tests beside ``tests/conftest.py`` need only numpy, scipy, pandas.

Lanes: a test that uses an end-to-end run (a fixture of :data:`END_TO_END`)
is marked ``slow``, so ``bash workflow/test.sh -m "not slow"`` leaves it out;
a test that runs a workflow by itself carries the mark in its module."""

import pytest
from workflow_run import SMALL_CONFIG_FILE, copy_project, run_snakemake

#: Fixtures that run a workflow end to end, each once per session or module.
END_TO_END = {"small_workflow", "workdir", "shadowed_run", "regenerated", "campaign", "slurm"}


def pytest_collection_modifyitems(config, items):
    for item in items:
        if END_TO_END & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.slow)


@pytest.fixture(scope="session")
def small_workflow(tmp_path_factory):
    """A copy of the workflow in a temporary directory, run to completion with
    the small config ``config/test/config.small.yaml`` (3 seeds, short sweeps,
    its searches computed); shared by every test that reads its outputs or
    compares another run with it."""
    tmp = copy_project(tmp_path_factory.mktemp("wf"))
    run_snakemake(tmp, "--configfile", SMALL_CONFIG_FILE)
    return tmp
