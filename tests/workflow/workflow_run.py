"""Helpers of the workflow tests: the project root, a copy of the project
as a fresh clone would have it, and snakemake run with this interpreter."""

import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: The small test config (YAML, layered over config/config.yaml).
SMALL_CONFIG_FILE = "config/test/config.small.yaml"
#: What a clone holds that the workflow reads (results/ is generated).
PROJECT_ITEMS = ("Snakefile", "workflow", "config", "modal", "notebooks", "tests/data")


def copy_project(dest: Path) -> Path:
    """Copy the project's workflow files (no results, no caches) to ``dest``."""
    for item in PROJECT_ITEMS:
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(src, dest / item, ignore=shutil.ignore_patterns("__pycache__"))
        elif src.exists():
            shutil.copy(src, dest / item)
    return dest


def run_snakemake(workdir, *args, check=True, timeout=900):
    """``python -m snakemake --cores 2 *args`` in ``workdir`` (this interpreter)."""
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *args], cwd=workdir,
                          capture_output=True, text=True, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc
