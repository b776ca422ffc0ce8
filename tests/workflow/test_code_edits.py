"""An edit of the roving-test or campaign code reruns no thesis job.

Each rule's code inputs are derived from its script's imports
(:func:`modal.thesis.dependencies.code_inputs`); ``import modal`` loads its
subpackages lazily, so a thesis script depends on the subpackages it uses and
no other. Checked where it matters, in Snakemake's own plan: a copy of the
project whose outputs of the small config all exist and are up to date (empty
files, newer than every input: only modification times decide, and no
metadata is recorded), one engine file edited, then ``snakemake -n``.
"""

import os
import re
import time

import pytest
from workflow_run import SMALL_CONFIG_FILE, copy_project, run_snakemake

pytestmark = pytest.mark.slow  # three plans of the whole small config

#: Snakemake prints each planned job as "rule NAME:" (or "localrule NAME:"),
#: then indented "key: value" lines.
JOB = re.compile(r"^(?:local)?rule (\S+):\n((?:    .*\n)+)", re.M)
#: The roving test's rule, and the jobs that read its results (the HTML report
#: has a roving section): what an edit of the roving code may rerun.
ROVING = {"measured_setups", "report_html", "all"}


def planned(log: str) -> dict[str, list[str]]:
    """Rule -> the reasons of its planned jobs, from a ``snakemake -n`` log."""
    jobs = {}
    for rule, body in JOB.findall(log):
        fields = dict(line.strip().split(": ", 1) for line in body.splitlines() if ": " in line)
        jobs.setdefault(rule, []).append(fields.get("reason", ""))
    return jobs


@pytest.fixture(scope="module")
def up_to_date(tmp_path_factory):
    """A copy of the project with every output of the small config present,
    newer than every input."""
    work = copy_project(tmp_path_factory.mktemp("edits"))
    plan = run_snakemake(work, "-n", "--configfile", SMALL_CONFIG_FILE).stdout
    outputs = [path for _, body in JOB.findall(plan) for line in body.splitlines()
               if line.strip().startswith("output: ") for path in line.strip()[len("output: "):].split(", ")]
    assert len(outputs) > 50, plan[-2000:]
    now = time.time()
    for output in outputs:
        (work / output).parent.mkdir(parents=True, exist_ok=True)
        (work / output).touch()
        os.utime(work / output, (now, now))
    return work


def edited_plan(work, path) -> dict[str, list[str]]:
    """The jobs ``snakemake -n`` plans after a comment is appended to
    ``path``; the file and its time are restored afterwards."""
    file = work / path
    text, stat = file.read_text(), file.stat()
    try:
        time.sleep(0.01)
        file.write_text(text + "# an edit that changes no result\n")
        return planned(run_snakemake(work, "-n", "--configfile", SMALL_CONFIG_FILE).stdout)
    finally:
        file.write_text(text)
        os.utime(file, ns=(stat.st_atime_ns, stat.st_mtime_ns))


def test_a_roving_drawing_edit_reruns_only_the_roving_test(up_to_date):
    jobs = edited_plan(up_to_date, "modal/setups/_drawing.py")
    # the roving test itself is rerun: the plan sees the edit (the outputs are up to date otherwise)
    assert [r for r in jobs.get("measured_setups", []) if "Updated input files: modal/setups/_drawing.py" in r], jobs
    assert set(jobs) <= ROVING, sorted(set(jobs) - ROVING)


def test_a_campaign_report_edit_reruns_nothing(up_to_date):
    jobs = edited_plan(up_to_date, "modal/campaign/_report.py")
    assert not jobs, sorted(jobs)


def test_an_engine_edit_with_an_older_time_stamp_reruns_by_content(tmp_path):
    """The code a job runs enters its params as content hashes: an edit of
    the pipeline that keeps an older time stamp (``touch -d``, a restored
    backup, a checkout) still reruns the measured record's identification,
    (the code inputs alone are compared by time)."""
    work = copy_project(tmp_path, searches=True)
    target = "results/measured/palisaden/modes.csv"
    run_snakemake(work, target)
    assert "Nothing to be done" in run_snakemake(work, "-n", target).stdout
    pipeline = work / "modal" / "measured" / "_pipeline.py"
    old = pipeline.stat()
    pipeline.write_text(pipeline.read_text() + "# an edit\n")
    os.utime(pipeline, ns=(old.st_atime_ns, old.st_mtime_ns - 10**12))  # older than every output
    jobs = planned(run_snakemake(work, "-n", target).stdout)
    assert "measured_identify" in jobs and any("Params have changed" in r for r in jobs["measured_identify"]), jobs
