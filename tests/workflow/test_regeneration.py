"""The committed ``results/tables`` are what a fresh clone regenerates, byte for
byte (floats at ``modal.thesis.tables.FLOAT_FORMAT``)."""

import pytest

from workflow_run import ROOT, copy_project, run_snakemake

COMMITTED = sorted(p.relative_to(ROOT) for p in (ROOT / "results/tables").iterdir() if p.suffix in (".csv", ".md"))


@pytest.mark.skipif(not COMMITTED, reason="no committed results/tables to compare with")
def test_fresh_regeneration_gives_the_committed_tables(tmp_path):
    work = copy_project(tmp_path)
    run_snakemake(work, *map(str, COMMITTED))
    changed = [str(p) for p in COMMITTED if (work / p).read_bytes() != (ROOT / p).read_bytes()]
    assert not changed, f"regenerated tables differ from the committed ones: {changed}"
