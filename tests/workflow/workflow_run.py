"""Helpers of the workflow tests: the project root, a copy of the project
as a fresh clone would have it, and snakemake run with this interpreter."""

import os
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
#: The committed searches' summary, which a run that does not compute the
#: searches (config run_searches false, the default config's) cites.
COMMITTED_SEARCHES = "results/tables/searches.csv"


def copy_project(dest: Path, searches: bool = False) -> Path:
    """Copy the project's workflow files (no results, no caches) to ``dest``;
    with ``searches``, also the committed searches' summary, as a clone holds
    it (the default config needs it; the small config computes its own, and a
    copied one would stand in for it where a target names only that file)."""
    for item in PROJECT_ITEMS + ((COMMITTED_SEARCHES,) if searches else ()):
        src = ROOT / item
        if src.is_dir():
            shutil.copytree(src, dest / item, ignore=shutil.ignore_patterns("__pycache__"))
        elif src.exists():
            (dest / item).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(src, dest / item)
    return dest


def regenerate_project(dest: Path) -> Path:
    """A project copy whose ``.venv`` points at this interpreter (run with
    ``SETUP_SKIP=1``), so ``bash workflow/regenerate.sh`` runs as a user would."""
    work = copy_project(dest, searches=True)
    (work / "pyproject.toml").write_bytes((ROOT / "pyproject.toml").read_bytes())
    bin_ = work / ".venv/bin"
    bin_.mkdir(parents=True)
    for name, command in (("python", [sys.executable]), ("snakemake", [sys.executable, "-m", "snakemake"])):
        (bin_ / name).write_text("#!/bin/sh\nexec " + " ".join(command) + ' "$@"\n')
        (bin_ / name).chmod(0o755)
    return work


def regenerate(work, *args, **kwargs) -> subprocess.Popen:
    """``bash workflow/regenerate.sh *args`` in a :func:`regenerate_project`
    copy, on 2 cores, started (output in ``stdout``, the process a group of its own)."""
    env = {**os.environ, "CORES": "2", "SETUP_SKIP": "1"}  # the wrapper .venv is the environment
    return subprocess.Popen(["bash", "workflow/regenerate.sh", *args], cwd=work, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True, **kwargs)


def run_snakemake(workdir, *args, check=True, timeout=900):
    """``python -m snakemake --cores 2 *args`` in ``workdir`` (this interpreter)."""
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *args], cwd=workdir,
                          capture_output=True, text=True, timeout=timeout)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc


class _Delete:
    """:data:`DELETE`'s type: a sentinel whose repr is the same in every
    process (test ids must agree between pytest-xdist's workers)."""

    def __repr__(self):
        return "DELETE"


#: :func:`set_key`'s value that deletes the key.
DELETE = _Delete()


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
