"""The committed ``results/tables`` are what a fresh clone regenerates, byte for
byte (floats at ``modal.thesis.tables.FLOAT_FORMAT``): the README's command
(the searches cited from the committed table), then the searches' command of
the thesis page (docs/thesis.md), which recomputes that table."""

import shlex

import pytest

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


@pytest.mark.skipif(not SEARCHES.exists(), reason="no committed results/tables/searches.csv to compare with")
def test_the_searches_command_recomputes_the_committed_searches(regenerated):
    work = regenerated[0]
    assert SEARCH_COMMAND in (ROOT / "docs/thesis.md").read_text()
    (work / "results/tables/searches.csv").unlink()
    run(work, *shlex.split(SEARCH_COMMAND)[2:], timeout=1800)
    assert sorted(p.stem for p in (work / "results/searches").glob("*.csv")) == sorted(base_config()["searches"])
    assert not changed(work), f"tables differ from the committed ones: {changed(work)}"
