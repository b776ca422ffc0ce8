"""Benchmark the whole regeneration (not a test; prints wall times).

Copies the workflow into a temporary directory and times, with this
interpreter's snakemake on all cores: a cold run of everything (all tables,
figures, notebooks and the report), a no-op rerun, and a rerun after a
config edit that touches one study.

Run: ``.venv/bin/python benchmarks/bench_regeneration.py``
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]


def timed(workdir, *args):
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "snakemake", "--cores", str(os.cpu_count()), "--quiet", "all", *args],
                   cwd=workdir, check=True, capture_output=True)
    return time.perf_counter() - t0


def main():
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for item in ("Snakefile", "workflow", "config", "modal", "notebooks"):
            src = ROOT / item
            (shutil.copytree if src.is_dir() else shutil.copy)(src, tmp / item)
        cold = timed(tmp)
        noop = timed(tmp)
        (tmp / "edit.yaml").write_text(yaml.safe_dump({"studies": {"spillover": {"n_identified": [3, 4, 5, 6]},
                                                                   "demo": {"cases": {"c4": {"damping": 0.01,
                                                                                             "noise": 0.04}}}}}))
        edit = timed(tmp, "--configfile", "edit.yaml")
    print(f"# {os.cpu_count()} cores")
    print("| run | wall time (s) |\n|---|---|")
    print(f"| everything, cold (tables, figures, notebooks, report) | {cold:.1f} |")
    print(f"| rerun, nothing changed | {noop:.1f} |")
    print(f"| rerun after editing one demo case | {edit:.1f} |")


if __name__ == "__main__":
    main()
