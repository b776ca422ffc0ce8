"""The documentation: the site builds strictly, the docstrings' cross-references
resolve, and the README's examples run as typed.

``mkdocs build --strict`` fails on a broken link, a missing page in the
navigation or an API reference mkdocstrings cannot resolve. The docstrings'
Sphinx roles (:func:`modal.era`) are shown as code on the site (they stay
roles for ``help()`` and IDEs), so no build resolves them: a test does, against
the objects themselves. The README's
``modal`` commands and Python examples are run from a scratch folder that sees the project's
``tests/`` and this interpreter's environment as ``.venv``, so they write
nowhere in the checkout.
"""

from __future__ import annotations

import ast
import importlib
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
    assert 'id="modal.campaign.run"' in (site / "api/campaign.html").read_text()
    # The configuration reference was written from both schemas (docs/_hooks/config_reference.py).
    reference = (site / "configuration.html").read_text()
    assert "config-reference:" not in reference
    for key in ("seeds.chunk", "grid.model.width", "measured.&lt;name&gt;.max_order", "tracking.freq_rtol"):
        assert f"<code>{key}</code>" in reference, key


#: A Sphinx cross-reference role in a docstring: :func:`modal.era`, :class:`~modal.ModalResult`.
ROLE = re.compile(r":(?:py:)?(?:func|class|meth|data|attr|mod|obj|exc|const):`~?([^`]+)`")


def _attribute(obj, name):
    """``getattr``, and a class's annotated fields (a dataclass field without
    a default is no class attribute)."""
    try:
        return getattr(obj, name)
    except AttributeError:
        if isinstance(obj, type) and any(name in vars(c).get("__annotations__", {}) for c in obj.__mro__):
            return None
        raise


def _resolves(target: str, scopes: list) -> bool:
    """Whether ``target`` names an object, as Sphinx's Python domain looks it
    up: a dotted path from its longest importable module; otherwise (a short
    name, or one with a leading dot) an attribute or submodule of one of
    ``scopes`` (the enclosing class, the module, its package, ``modal``)."""
    parts = target.lstrip(".").split(".")
    if not target.startswith("."):
        for i in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:i]))
            except ImportError:
                continue
            try:
                for part in parts[i:]:
                    obj = _attribute(obj, part)
                return True
            except AttributeError:
                break
    for scope in scopes:
        obj = scope
        try:
            for part in parts:
                obj = _attribute(obj, part)
            return True
        except AttributeError:
            pass
        if getattr(scope, "__path__", None) is not None or hasattr(scope, "__file__"):
            try:
                importlib.import_module(f"{scope.__name__}.{'.'.join(parts)}")
                return True
            except ImportError:
                pass
    return False


def docstring_roles():
    """``(module, target, scopes)`` for every role in the docstrings of the
    package ``modal`` (modules, classes, functions; not the workflow scripts
    shipped in it, which run only under Snakemake)."""
    import modal

    for path in sorted((ROOT / "modal").rglob("*.py")):
        if "scripts" in path.relative_to(ROOT).parts or path.name == "__main__.py":
            continue
        name = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        module = importlib.import_module(name)
        package = module if path.name == "__init__.py" else importlib.import_module(name.rpartition(".")[0])
        stack = [(ast.parse(path.read_text()), [module])]
        while stack:
            node, scopes = stack.pop()
            if isinstance(node, ast.ClassDef):
                cls = getattr(scopes[0], node.name, None)
                scopes = [cls, *scopes] if cls is not None else scopes
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                for target in ROLE.findall(ast.get_docstring(node, clean=False) or ""):
                    yield name, target.strip(), [*scopes, package, modal]
            stack.extend((child, scopes) for child in ast.iter_child_nodes(node))


def test_docstring_cross_references_resolve():
    """Every :func:, :class:, :mod:, ... role in modal's docstrings names an
    object that exists: a renamed or moved function leaves no stale reference."""
    roles = list(docstring_roles())
    assert len(roles) > 100
    stale = sorted({f"{module}: {target}" for module, target, scopes in roles if not _resolves(target, scopes)})
    assert not stale, "stale cross-references:\n" + "\n".join(stale)


def test_a_stale_cross_reference_is_caught():
    import modal
    import modal.identification._era as era_module

    scopes = [era_module, modal.identification, modal]
    assert _resolves("modal.era", scopes) and _resolves("era", scopes) and _resolves("modal.ModalResult.omega", scopes)
    assert _resolves("hankel", scopes)  # imported into the module
    assert not _resolves("modal.nonexistent", scopes)
    assert not _resolves("modal.result.free_response_growth", scopes)  # a module that moved
    assert not _resolves("modal.era.realise", scopes)  # a function, not a module: no attribute realise


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
@pytest.mark.slow
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
@pytest.mark.slow
def test_readme_python_runs(block, tmp_path):
    """The README's Python examples run from the project folder as shown,
    without a warning: a first try that warns reads as a misuse."""
    (tmp_path / "tests").symlink_to(ROOT / "tests")
    run = subprocess.run([sys.executable, "-W", "error", "-c", block], cwd=tmp_path, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, f"{block}\n{run.stderr[-3000:]}"
