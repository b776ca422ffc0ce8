"""The dependency ranges of pyproject.toml, not the locks: a fresh environment
installed from the declared ranges, once at the newest versions they allow
and once at their lower bounds (uv's ``--resolution lowest-direct``), runs
the small test config end to end (every rule but the searches', which only
repeat the beam studies' code with other settings: they cite the committed
searches, as the default config does).

Needs PyPI (or the index in UV_DEFAULT_INDEX / UV_INDEX_URL / PIP_INDEX_URL):
skipped, with the reason, when it cannot be reached. uv's cache makes a
repeated install quick; the two workflow runs take most of the time.
Run alone with ``pytest -m slow tests/project/test_install.py``.
"""

import os
import shutil
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "workflow"))
from workflow_run import SMALL_CONFIG_FILE, copy_project  # noqa: E402

pytestmark = pytest.mark.slow

#: What the install brings in: the engine, the workflow and its notebooks.
EXTRAS = "workflow"
#: Columns every thesis table CSV of the small config has, and summary.csv.
TABLE_COLUMNS = {"table", "mode", "method", "interpretation", "column", "printed", "published", "flag",
                 "reproduced", "std", "n_seeds", "seed0", "actual"}
SUMMARY_COLUMNS = {"table", "title", "n_published", "n_compared", "verdict"}


def _uv() -> str:
    uv = shutil.which("uv") or str(Path(sys.executable).parent / "uv")
    if not Path(uv).exists():
        pytest.skip("no uv beside this interpreter or on PATH (bash workflow/test.sh installs it)")
    return uv


def _index_reachable() -> None:
    """Skip (with the reason) when the package index cannot be reached."""
    index = (os.environ.get("UV_DEFAULT_INDEX") or os.environ.get("UV_INDEX_URL")
             or os.environ.get("PIP_INDEX_URL") or "https://pypi.org/simple/")
    url = index.rstrip("/") + "/pip/"
    try:
        with urllib.request.urlopen(urllib.request.Request(url, method="HEAD"), timeout=10):
            pass
    except urllib.error.HTTPError as error:  # reached it: any HTTP answer will do
        if error.code >= 500:
            pytest.skip(f"package index {index} answers {error.code}: cannot install from the ranges")
    except (urllib.error.URLError, OSError) as error:
        pytest.skip(f"no network: package index {index} unreachable ({error})")


def _clean_env(venv: Path) -> dict:
    """This process's environment with ``venv`` in place of any active one."""
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH", "PYTHONHOME", "CONDA_PREFIX")}
    env["VIRTUAL_ENV"] = str(venv)
    env["PATH"] = os.pathsep.join([str(venv / "bin"), env.get("PATH", "")])
    return env


@pytest.mark.parametrize("resolution", ["highest", "lowest-direct"])
def test_declared_ranges_run_the_small_workflow(tmp_path, resolution):
    uv = _uv()
    _index_reachable()
    venv = tmp_path / "venv"
    python = venv / "bin" / "python"
    env = _clean_env(venv)
    subprocess.run([uv, "venv", "--quiet", "--python", sys.executable, str(venv)], check=True, env=env)
    # From pyproject.toml's ranges: no requirements/*.txt, no constraints.
    env.pop("UV_CONSTRAINT", None)
    env.pop("UV_OVERRIDE", None)
    install = subprocess.run(
        [uv, "pip", "install", "--python", str(python), "--resolution", resolution, "--no-progress",
         "--compile-bytecode",  # each workflow job imports numpy, pandas, scipy: no .pyc means minutes
         "-e", f"{ROOT}[{EXTRAS}]"], env=env, capture_output=True, text=True, timeout=1200)
    assert install.returncode == 0, f"uv pip install ({resolution}) failed:\n{install.stderr[-4000:]}"
    versions = subprocess.run([uv, "pip", "freeze", "--python", str(python)], env=env, capture_output=True,
                              text=True, check=True).stdout
    print(f"installed ({resolution}):\n{versions}")

    # A copy of the project: the checkout's results/ is never written.
    (tmp_path / "wf").mkdir()
    workdir = copy_project(tmp_path / "wf", searches=True)
    run = subprocess.run([str(python), "-m", "snakemake", "--cores", "2", "--configfile", SMALL_CONFIG_FILE,
                          "--config", "run_searches=False", "--workflow-profile", "workflow/profiles/default"],
                         cwd=workdir, env=env, capture_output=True, text=True, timeout=1800)
    assert run.returncode == 0, f"snakemake ({resolution}) failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"

    tables = workdir / "results" / "tables"
    numbered = sorted(tables.glob("table_*.csv"))
    assert len(numbered) >= 10, f"too few tables: {[p.name for p in numbered]}"
    for path in numbered:
        frame = pd.read_csv(path)
        assert not frame.empty, path.name
        assert TABLE_COLUMNS <= set(frame.columns), f"{path.name}: missing {TABLE_COLUMNS - set(frame.columns)}"
        assert path.with_suffix(".md").exists(), path.with_suffix(".md").name
    summary = pd.read_csv(tables / "summary.csv")
    assert SUMMARY_COLUMNS <= set(summary.columns)
    assert {int(p.stem.split("_")[1]) for p in numbered} <= set(summary["table"])
    assert (workdir / "results" / "report.html").exists()
