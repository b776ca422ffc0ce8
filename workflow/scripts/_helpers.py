"""Shared by the workflow's scripts: the common start of a job.

To run a script by hand (in a debugger or IPython), let Snakemake keep the
script it hands the job: ``snakemake --cores 1 --forcerun table
--skip-script-cleanup results/tables/table_01.csv`` prints the path of the
kept script under ``.snakemake/scripts/``, which holds the job's ``snakemake``
object and runs with plain ``python`` from the project root.
"""

from __future__ import annotations

import sys


def limit_blas_threads(threads: int) -> int:
    """Limit the BLAS and OpenMP thread pools of this process to ``threads``.

    Snakemake sets ``OMP_NUM_THREADS`` and friends to a job's ``threads`` for
    the scripts it runs, but a script run by hand inherits the shell's
    environment, and numpy is imported before any script line could set it.
    ``threadpoolctl`` changes the loaded libraries' pools at run time, so the
    limit holds however the script was started. Returns the largest pool size
    now in effect.
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
