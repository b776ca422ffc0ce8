"""The committed ``results/tables`` are what a fresh clone regenerates, byte for
byte (floats at ``modal.thesis.tables.FLOAT_FORMAT``): the README's command
(the searches cited from the committed table), then the searches' command of
the thesis page (docs/thesis.md), which recomputes that table."""

import re
import shlex

import pytest

import modal.thesis.search
from workflow_run import ROOT, base_config, regenerate, regenerate_project

pytestmark = pytest.mark.slow

COMMITTED = sorted(p.relative_to(ROOT) for p in (ROOT / "results/tables").iterdir() if p.suffix in (".csv", ".md"))
SEARCHES = ROOT / "results/tables/searches.csv"
#: The thesis page's command that computes the searches, as typed there.
SEARCH_COMMAND = "bash workflow/regenerate.sh --config run_searches=True"


def run(work, *args, timeout):
    proc = regenerate(work, *args)
    out, _ = proc.communicate(timeout=timeout)
    assert proc.returncode == 0, out[-3000:]


def changed(work):
    return [str(p) for p in COMMITTED if (work / p).read_bytes() != (ROOT / p).read_bytes()]


@pytest.fixture(scope="module")
def regenerated(tmp_path_factory):
    """A fresh copy regenerated with ``bash workflow/regenerate.sh`` (the copy
    holds the committed searches' summary, as a clone does: regenerate_project):
    the folder, the tables that differ and whether the searches ran."""
    work = regenerate_project(tmp_path_factory.mktemp("regeneration"))
    run(work, timeout=900)
    return work, changed(work), (work / "results/searches").exists()


@pytest.mark.skipif(not COMMITTED, reason="no committed results/tables to compare with")
def test_fresh_regeneration_gives_the_committed_tables(regenerated):
    _, differ, searched = regenerated
    assert not searched, "a default regeneration computed the searches"
    assert not differ, f"regenerated tables differ from the committed ones: {differ}"


def test_the_searches_command_works_as_typed(regenerated):
    """The thesis page's command that recomputes the searches plans every
    search's settings in the default run (a dry run: running them is a
    parameter study of about 9 CPU-minutes, docs/benchmarks.md; their scoring
    is tested in tests/thesis/test_search.py)."""
    work = regenerated[0]
    assert SEARCH_COMMAND in (ROOT / "docs/thesis.md").read_text()
    proc = regenerate(work, *shlex.split(SEARCH_COMMAND)[2:], "-n")
    out, _ = proc.communicate(timeout=600)
    assert proc.returncode == 0, out[-3000:]
    config = base_config()
    n_settings = sum(len(modal.thesis.search.search_settings(search, config["studies"], config["beams"],
                                                             config["tables"]))
                     for search in config["searches"].values())
    planned = re.search(r"^search_setting\s+(\d+)$", out, re.M)
    assert planned and int(planned.group(1)) == n_settings, out[-3000:]
