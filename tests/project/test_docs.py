"""The documentation: the site builds strictly, and the README's examples run as typed.

``mkdocs build --strict`` fails on a broken link, a missing page in the
navigation or an API reference mkdocstrings cannot resolve. The README's
``modal`` commands and Python examples are run from a scratch folder that sees the project's
``tests/`` and this interpreter's environment as ``.venv``, so they write
nowhere in the checkout.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
BIN = Path(sys.executable).parent

pytest.importorskip("mkdocs", reason="the docs extra (mkdocs, mkdocstrings) is not installed")
pytest.importorskip("mkdocstrings", reason="the docs extra (mkdocs, mkdocstrings) is not installed")


def test_site_builds_strictly(tmp_path):
    site = tmp_path / "site"
    run = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file", str(ROOT / "mkdocs.yml"),
         "--site-dir", str(site)],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, f"mkdocs build --strict failed:\n{run.stderr[-5000:]}"
    for page in ["index.html", "thesis.html", "records.html", "api/identification.html"]:
        assert (site / page).is_file(), page
    # mkdocstrings rendered the API, not an empty page.
    assert 'id="modal.identification.era"' in (site / "api/identification.html").read_text()


def readme_commands(text: str) -> list[str]:
    """Shell lines of the README's code blocks that run the ``modal`` command."""
    commands = []
    for lang, block in re.findall(r"```(\w*)\n(.*?)```", text, flags=re.S):
        if lang not in ("bash", "sh", "shell", "console"):
            continue
        for line in block.splitlines():
            line = line.split(" #", 1)[0].strip()
            if line.startswith((".venv/bin/modal ", "modal ")):
                commands.append(line)
    return commands


def test_readme_shows_modal_commands():
    commands = readme_commands(README.read_text())
    assert any(c.startswith(".venv/bin/modal identify") for c in commands), commands


@pytest.mark.parametrize("command", readme_commands(README.read_text()))
def test_readme_command_runs_as_typed(command, tmp_path):
    """Each ``modal`` command shown in the README exits 0 and writes what it says."""
    (tmp_path / "tests").symlink_to(ROOT / "tests")
    # `.venv/bin/modal` of the README is this environment's console script.
    (tmp_path / ".venv").symlink_to(BIN.parent)
    if not (BIN / "modal").exists():
        pytest.skip(f"no `modal` console script in {BIN} (the project is not installed there)")
    env = {**os.environ, "PATH": f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}"}
    run = subprocess.run(shlex.split(command), cwd=tmp_path, capture_output=True, text=True, env=env,
                         timeout=600)
    assert run.returncode == 0, f"{command}\n{run.stdout}\n{run.stderr[-3000:]}"
    out = shlex.split(command)
    if "--out" in out:
        folder = tmp_path / out[out.index("--out") + 1]
        setups = "--geometry" in out  # several setups or a geometry: the merged folder
        names = ["modes.csv", "shapes.csv", "mode_1.png", "mode_1.gif"] if setups else \
            ["modes.csv", "poles.csv", "stabilisation.png"]
        for name in names:
            assert (folder / name).is_file(), name
    assert "modes" in run.stdout


def readme_python_blocks(text: str) -> list[str]:
    return [block for lang, block in re.findall(r"```(\w*)\n(.*?)```", text, flags=re.S) if lang == "python"]


@pytest.mark.parametrize("block", readme_python_blocks(README.read_text()))
def test_readme_python_runs(block, tmp_path):
    """The README's Python examples run from the project folder as shown."""
    (tmp_path / "tests").symlink_to(ROOT / "tests")
    run = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, f"{block}\n{run.stderr[-3000:]}"
