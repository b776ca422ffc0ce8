"""Shared by the workflow's scripts: run a script by hand for debugging.

Every script ends its imports with::

    if "snakemake" not in globals():
        snakemake = mock_snakemake("table", number="04")

so ``python workflow/scripts/table.py`` (from the project root, or in
IPython with ``%run``) builds the same ``snakemake`` object the workflow
would hand the script, from the Snakefile and config, and runs it.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def mock_snakemake(rule: str, configfiles=(), **wildcards):
    """The ``snakemake`` object of one job of ``rule`` (PyPSA-Eur's pattern).

    Parameters
    ----------
    rule : str
        A rule of the Snakefile, e.g. ``"table"``.
    configfiles : sequence of path, optional
        Configs layered over ``config/config.yaml`` (``--configfile``),
        e.g. ``["config/test/config.small.yaml"]``.
    **wildcards
        The job's wildcards, e.g. ``number="04"``.

    The job's inputs must exist (run the workflow up to them first); its
    outputs and log are written where the workflow would write them.
    """
    from snakemake.api import SnakemakeApi
    from snakemake.script import Snakemake
    from snakemake.settings.types import (ConfigSettings, DAGSettings, OutputSettings, ResourceSettings,
                                          StorageSettings)

    if Path.cwd().resolve() != ROOT:
        raise RuntimeError(f"run scripts from the project root {ROOT} (the workflow's working directory)")
    with SnakemakeApi(OutputSettings(quiet={"all"})) as api:
        workflow_api = api.workflow(
            resource_settings=ResourceSettings(),
            config_settings=ConfigSettings(configfiles=[Path(f).resolve() for f in configfiles]),
            storage_settings=StorageSettings(),
            snakefile=ROOT / "Snakefile",
            workdir=ROOT,
        )
        workflow = workflow_api._workflow
        job_rule = workflow.get_rule(rule)
        wildcards = {k: str(v) for k, v in wildcards.items()}
        # expand the rule for these wildcards exactly as the scheduler would
        from snakemake.dag import DAG
        from snakemake.jobs import Job

        workflow.dag_settings = DAGSettings()
        dag = DAG(workflow, rules=[job_rule])
        # wildcards the rule does not have pick one item of a rule that writes
        # several (rule table: number="04"), see item_job
        own = {k: v for k, v in wildcards.items() if k in job_rule.wildcard_names}
        job = Job(job_rule, dag, wildcards_dict=own)
        for path in [*job.output, *job.log]:
            os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
        smk = Snakemake(job.input, job.output, job.params, job.wildcards, job.threads, job.resources,
                        job.log, workflow.config, job.rule.name, None)
    if own == wildcards:
        return smk
    items = [i for i, item in enumerate(smk.params.each)
             if {k: str(v) for k, v in item["wildcards"].items()} == {k: wildcards[k] for k in item["wildcards"]}]
    if len(items) != 1 or set(wildcards) - set(own) != set(smk.params.each[items[0]]["wildcards"]):
        raise ValueError(f"rule {rule}: no item with wildcards {wildcards}")
    return item_job(smk, items[0])


def item_job(snakemake, index: int):
    """The ``snakemake`` object of item ``index`` of a job that writes several
    items in one process (rules ``table`` and ``grid_table``: every table in
    one job, so the imports are paid once), as a rule of one item per job
    would hand it to the item's script.

    The rule declares ``params.each``, one mapping per item with its
    ``wildcards`` and its own ``input`` and ``params``; every named output is a
    list with one file per item, and ``log`` one file per item. The item's
    object has the rule's other inputs and params, the item's inputs, params
    and wildcards, the item's file of each named output, and its log.
    """
    from snakemake.iocontainers import InputFiles, Log, OutputFiles, Params, Wildcards
    from snakemake.script import Snakemake

    item = snakemake.params.each[index]
    inputs = {k: getattr(snakemake.input, k) for k in snakemake.input.keys()}
    params = {k: getattr(snakemake.params, k) for k in snakemake.params.keys() if k != "each"}
    outputs = {k: getattr(snakemake.output, k)[index] for k in snakemake.output.keys()}
    return Snakemake(_named(InputFiles, {**inputs, **item.get("input", {})}), _named(OutputFiles, outputs),
                     Params(fromdict={**params, **item.get("params", {})}),
                     Wildcards(fromdict={k: str(v) for k, v in item["wildcards"].items()}), snakemake.threads,
                     snakemake.resources, Log([snakemake.log[index]]), snakemake.config, snakemake.rule, None)


def _named(cls, files):
    """A snakemake file list with named entries, a list entry spread over
    several positions under one name (as snakemake builds ``input``)."""
    out = cls()
    for name, value in files.items():
        start = len(out)
        if isinstance(value, (list, tuple)):
            out.extend(value)
            out._set_name(name, start, len(out))
        else:
            out.append(value)
            out._set_name(name, start)
    return out


def run_items(snakemake, script: str) -> None:
    """Run ``script`` (a file beside this one) once per item of the job, each
    with its :func:`item_job` object as its ``snakemake``."""
    import runpy

    path = Path(__file__).with_name(script)
    for index in range(len(snakemake.params.each)):
        runpy.run_path(str(path), init_globals={"snakemake": item_job(snakemake, index)}, run_name="__main__")


def limit_blas_threads(threads: int) -> int:
    """Limit the BLAS and OpenMP thread pools of this process to ``threads``.

    Snakemake sets ``OMP_NUM_THREADS`` and friends to a job's ``threads`` for
    the scripts it runs, but a script run by hand (:func:`mock_snakemake`)
    inherits the shell's environment, and numpy is imported before any
    script line could set it. ``threadpoolctl`` changes the loaded libraries'
    pools at run time, so the limit holds however the script was started.
    Returns the largest pool size now in effect.
    """
    from threadpoolctl import threadpool_info, threadpool_limits

    if not isinstance(threads, int) or threads < 1:
        raise ValueError(f"threads must be a positive integer, got {threads!r}")
    threadpool_limits(limits=threads)
    return max((pool["num_threads"] for pool in threadpool_info()), default=threads)


def start_job(snakemake) -> None:
    """The scripts' common entry: BLAS threads follow the rule's ``threads``,
    and warnings and errors go to the rule's (first) log file, which starts
    with the thread count in effect."""
    in_effect = limit_blas_threads(snakemake.threads)
    sys.stderr = open(snakemake.log[0], "w")
    print(f"threads: {snakemake.threads}, BLAS/OpenMP threads in effect: {in_effect}", file=sys.stderr)
