"""Every rule declares every file it reads.

Jobs of the small config run again, each in a folder holding only copies of
its declared inputs: Snakemake's ``shadow: "copy-minimal"``, set on every
rule by a wrapper Snakefile, so the job list is Snakemake's own and a rule
added later is audited without touching this file. Audited: one job of each
rule for every value each of its wildcards takes (every study, every
interpretation, every search, every notebook; a rule without wildcards
once), forced in a copy of the small config's finished run, so each reads
the inputs the full run made. What is not in that folder:

- data: anything a job opens by a path relative to the project (results/,
  config/thesis_tables.csv, records, notebooks, templates, captions) must be
  a declared input, or the job fails (FileNotFoundError names the file) or
  writes something else than in the full project (a notebook that shows
  "has not been produced" instead of a table);
- code: a script imports ``modal`` (the installed package) and ``_helpers``
  from their own places, and Snakemake hands it the config through
  ``params``; the Snakefile, rules and config YAML are read by Snakemake
  itself before any job. Code a result depends on is declared too
  (``common.smk``, "What a code edit reruns"); a script's imports do not go
  through the working folder, so only the notebooks, whose Jupyter kernel
  puts its working folder first on ``sys.path``, check their code inputs.

Scripts, ``run:`` blocks and the notebooks' Jupyter kernels all run in the
job's folder, so one mechanism covers them all.
"""

import json
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
from workflow_run import SMALL_CONFIG_FILE, run_snakemake

#: The wrapper: the project's Snakefile with every rule shadowed.
SHADOWED_SNAKEFILE = """\
include: "Snakefile"


for _rule in workflow.rules:
    _rule.shadow_depth = "copy-minimal"
"""
TARGET = "all"  # the Snakefile's default target (an included file sets none)
#: Snakemake prints each job as "rule NAME:" (or "localrule NAME:") and each
#: failure as "Error in rule NAME:", then indented "key: value" lines.
JOB = re.compile(r"^(?:local)?rule (\S+):\n((?:    .*\n)+)", re.M)
ERROR = re.compile(r"^Error in rule (\S+):\n((?:    .*\n)+)", re.M)
#: What a failed job's log, or a notebook, says about a file it could not open.
MISSING = re.compile(r"no such file|does not exist|not (been )?produced|is missing|missing:|\w+Error:", re.I)


def missing_lines(text: str) -> list[str]:
    """The lines (at most 300 characters) of ``text`` that say a file is missing."""
    return sorted({line.strip()[:300] for line in text.splitlines() if MISSING.search(line)})


def _fields(body: str) -> dict:
    return dict(line.strip().split(": ", 1) for line in body.splitlines() if ": " in line)


def planned_jobs(log: str) -> dict:
    """Output file -> (rule, wildcards) of every job in a snakemake log."""
    jobs = {}
    for rule, body in JOB.findall(log):
        fields = _fields(body)
        for output in fields.get("output", "").split(", "):
            if output:
                jobs[output] = (rule, fields.get("wildcards", ""))
    return jobs


def failures(log: str, workdir) -> list[str]:
    """One line per failed job: the rule, its outputs and what its log says
    it could not find (else the log's last lines)."""
    found = {}
    for rule, body in ERROR.findall(log):
        fields = _fields(body)
        logs = re.sub(r"\s*\(check log.*\)$", "", fields.get("log", "")).split(", ")
        text = "".join((workdir / f).read_text(errors="replace") for f in logs if f and (workdir / f).is_file())
        missing = missing_lines(text) or text.splitlines()[-5:] or [fields.get("message", "")]
        found[(rule, fields.get("output", ""))] = "; ".join(m.strip() for m in missing)
    return [f"rule {rule} (output {output}): {why}" for (rule, output), why in sorted(found.items())]


def audited_targets(log: str) -> list[str]:
    """The targets that make Snakemake run, of the jobs a ``--forceall``
    dry run's ``log`` plans, one job of each rule for every value each of its
    wildcards takes: the first job (in the log's order) that brings a value
    not yet seen, by its first output (a rule without outputs by its name)."""
    seen, targets = set(), []
    for rule, body in JOB.findall(log):
        fields = _fields(body)
        values = {(rule, value) for value in fields.get("wildcards", "").split(", ")}
        if not values <= seen:
            seen |= values
            outputs = [o for o in fields.get("output", "").split(", ") if o]
            targets += outputs[:1] or [rule]
    return targets


@pytest.fixture(scope="module")
def shadowed_run(tmp_path_factory, small_workflow):
    """The audited jobs (:func:`audited_targets`) forced, each in a folder of
    its own, in a copy of the small config's finished run (outside the
    project, so no path climbs back into it): their inputs are the full
    run's, and nothing else runs."""
    work = tmp_path_factory.mktemp("shadowed") / "project"
    shutil.copytree(small_workflow, work, symlinks=True)  # time stamps and Snakemake's records too
    (work / "shadowed.smk").write_text(SHADOWED_SNAKEFILE)
    shadows = tmp_path_factory.mktemp("shadows")
    args = ["--snakefile", "shadowed.smk", "--configfile", SMALL_CONFIG_FILE]
    targets = audited_targets(run_snakemake(work, TARGET, "--forceall", "-n", *args).stdout)
    # Snakemake runs each shadowed job in a snakemake process of its own (it
    # changes the working folder), which parses the workflow again (about 2 s
    # CPU per job). Not --force-use-threads: the scheduler then resolves paths
    # while a job's thread has moved the process into the job's folder.
    proc = run_snakemake(work, *targets, "--force", *args, "--shadow-prefix", str(shadows), "--keep-going",
                         check=False, timeout=2400)
    assert (shadows / "shadow").is_dir(), "no job ran in a shadow folder: the wrapper did not take effect"
    return work, proc.stdout + proc.stderr, proc.returncode


def test_every_job_runs_with_only_its_declared_inputs(shadowed_run):
    """Each job, in a folder holding only its declared inputs, succeeds
    (Snakemake also checks that it wrote every declared output)."""
    work, log, returncode = shadowed_run
    failed = failures(log, work)
    assert returncode == 0 and not failed, ("jobs failed with only their declared inputs (declare what they read):\n"
                                            + "\n".join(failed or [log[-3000:]]))


def test_every_rule_is_audited(shadowed_run):
    """Every rule of the Snakefile ran in the audit: a rule the small config
    does not plan would go unaudited, so it fails here by name."""
    work, log, _ = shadowed_run
    out = subprocess.run([sys.executable, "-m", "snakemake", "--list-rules", "--configfile", SMALL_CONFIG_FILE],
                         cwd=work, capture_output=True, text=True, timeout=300, check=True).stdout
    listed = [line.strip() for line in out.splitlines() if line.strip() and not line[0].isspace()]  # not docstrings
    ran = {rule for rule, _ in JOB.findall(log)}
    assert listed, "snakemake --list-rules listed no rule"
    unaudited = sorted(set(listed) - ran)
    assert not unaudited, ("rules the input audit never ran (the small config does not plan them, or a job "
                           f"before them failed): {unaudited}")


def comparable(path):
    """A file's content without what differs between two identical runs: the
    notebooks' execution metadata (times), the random ids of pandas Styler
    tables and the addresses in object reprs, the report's date, the zip timestamps of ``np.savez``."""
    if path.suffix == ".ipynb":
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        outputs = [[{k: v for k, v in out.items() if k != "metadata"} for out in c.get("outputs", [])]
                   for c in cells]
        text = re.sub(r"T_[0-9a-f]{5}(?=[_\\\"])", "T_<id>", json.dumps(outputs))
        return [c["source"] for c in cells], re.sub(r" at 0x[0-9a-f]+>", " at 0x<address>>", text)
    if path.suffix == ".npz":
        with np.load(path) as arrays:
            return {k: (arrays[k].dtype.str, arrays[k].shape, arrays[k].tobytes()) for k in arrays.files}
    if path.suffix == ".html":
        return re.sub(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", "<date>", path.read_text(encoding="utf-8"))
    return path.read_bytes()


def test_jobs_with_only_their_declared_inputs_write_what_the_full_project_writes(shadowed_run, small_workflow):
    """A job that reads an undeclared file only if it exists (a notebook
    showing "has not been produced") succeeds in its folder but writes
    something else: every output equals the full project's run. Each job
    runs twice on the same inputs, so also: a rerun gives the same files
    byte for byte."""
    work, log, _ = shadowed_run
    jobs = planned_jobs(log)
    assert jobs, "no job found in the shadowed run's log"
    differ = []
    for output, (rule, wildcards) in sorted(jobs.items()):
        mine, full = work / output, small_workflow / output
        job = f"rule {rule} ({wildcards or 'no wildcards'}): {output}"
        if not mine.exists() or not full.exists():
            differ.append(f"{job}: not written by the {'shadowed' if full.exists() else 'full'} run")
        elif comparable(mine) != comparable(full):
            what = missing_lines(mine.read_text(errors="replace"))
            differ.append(f"{job} differs from the full run's" + (f": {what[:5]}" if what else ""))
    assert not differ, "outputs differ when a job has only its declared inputs:\n" + "\n".join(differ)
