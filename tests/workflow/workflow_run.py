"""Helpers of the workflow tests: the project root, a copy of the project
as a fresh clone would have it, and snakemake run with this interpreter."""

import shutil
import subprocess
import sys
from pathlib import Path

import yaml

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


#: :func:`set_key`'s value that deletes the key.
DELETE = object()


def base_config():
    """config/config.yaml as a dict."""
    return yaml.safe_load((ROOT / "config/config.yaml").read_text())


def set_key(config, path, value):
    """Set the dotted ``path`` (``"tables.3.title"``) of ``config`` to ``value``,
    or delete it when ``value`` is :data:`DELETE`; returns ``config``."""
    node = config
    keys = path.split(".")
    for key in keys[:-1]:
        node = node[key] if key in node else node[int(key)]
    last = keys[-1]
    if last not in node and last.isdigit() and str(int(last)) == last:
        last = int(last)  # "01" stays a string: an override beside table 1
    if value is DELETE:
        del node[last]
    else:
        node[last] = value
    return config
