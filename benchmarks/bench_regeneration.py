"""Benchmark the whole regeneration (not a test; prints wall times).

Copies the workflow into a temporary directory and times, with this
interpreter's snakemake on all cores: a cold run of everything (all tables,
figures, notebooks and the report), a no-op rerun, and a rerun after a
config edit that touches one study.

Run: ``.venv/bin/python benchmarks/bench_regeneration.py``

The jobs import ``modal`` as installed in this interpreter (editable: this
checkout); to time another checkout's code, run its copy of this script with
``PYTHONPATH=<that checkout>``. Without compiled packages (``.pyc``) and with
``PYTHONDONTWRITEBYTECODE`` set, every job compiles its imports from source:
the script warns when numpy has no bytecode.
"""

from __future__ import annotations

import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


def timed(workdir, *args):
    """Wall time and CPU time (user + system, every process of the run) in s.

    On a shared machine the wall time depends on the other users' load; the
    CPU time hardly does, and CPU time / cores bounds the wall time an idle
    machine would need from below."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", str(os.cpu_count()), "--quiet", "all",
                           *args], cwd=workdir, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"snakemake failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    import numpy

    if not list(Path(numpy.__file__).parent.glob("__pycache__/__init__.*.pyc")):
        print("# warning: numpy is not compiled to bytecode (run workflow/setup.sh): every job will compile "
              "its imports", file=sys.stderr)
    load = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        # what a fresh clone holds that the workflow reads (tests/data: the measured record;
        # the committed searches' summary, which the summary cites without run_searches)
        for item in ("Snakefile", "workflow", "config", "modal", "notebooks", "tests/data",
                     "results/tables/searches.csv"):
            src = ROOT / item
            if src.is_dir():
                shutil.copytree(src, tmp / item, ignore=shutil.ignore_patterns("__pycache__"))
            else:
                (tmp / item).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy(src, tmp / item)
        cold = timed(tmp)
        noop = timed(tmp)
        (tmp / "edit.yaml").write_text(yaml.safe_dump({"studies": {"spillover": {"n_identified": [3, 4, 5, 6]},
                                                                   "demo": {"cases": {"c4": {"damping": 0.01,
                                                                                             "noise": 0.04}}}}}))
        edit = timed(tmp, "--configfile", "edit.yaml")
    print(f"# {os.cpu_count()} cores, load average {load[0]:.1f} before, {os.getloadavg()[0]:.1f} after")
    print("| run | wall time (s) | CPU time, all processes (s) |\n|---|---|---|")
    print(f"| everything, cold (tables, figures, notebooks, report) | {cold[0]:.1f} | {cold[1]:.1f} |")
    print(f"| rerun, nothing changed | {noop[0]:.1f} | {noop[1]:.1f} |")
    print(f"| rerun after editing one demo case | {edit[0]:.1f} | {edit[1]:.1f} |")


if __name__ == "__main__":
    import argparse

    # No options: --help explains, anything else is refused (a long run never starts by mistake).
    argparse.ArgumentParser(description=__doc__,
                            epilog="Run without arguments to start the benchmark (it takes minutes).",
                            formatter_class=argparse.RawDescriptionHelpFormatter).parse_args()
    main()
