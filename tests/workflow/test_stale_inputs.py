"""A changed raw input is rerun whatever its modification time: each raw
input (records, published values, captions, the default config) enters its
rule's params as its SHA-256 (common.smk: content_hashes), and Snakemake's
params trigger reruns the job. A file replaced by different content with an
older time (``cp -p``, an unpacked archive) is not missed."""

import os

import numpy as np
import pytest

from workflow_run import copy_project, run_snakemake

pytestmark = pytest.mark.slow

RECORD = "tests/data/palisaden_20hz_30min.npy"
TARGET = "results/measured/palisaden/modes.csv"


def test_record_rewritten_with_an_older_mtime_is_rerun(tmp_path):
    work = copy_project(tmp_path, searches=True)
    run_snakemake(work, TARGET)
    record = work / RECORD
    old = os.stat(work / TARGET).st_mtime - 3600
    os.utime(record, (old, old))
    plan = run_snakemake(work, "-n", TARGET)
    assert "measured_identify" not in plan.stdout, plan.stdout[-2000:]  # same content: nothing to do
    np.save(record, 1.01 * np.load(record))
    os.utime(record, (old, old))
    plan = run_snakemake(work, "-n", TARGET)
    assert "measured_identify" in plan.stdout, plan.stdout[-2000:]
    assert "params" in plan.stdout.lower(), plan.stdout[-2000:]
