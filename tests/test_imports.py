"""The engine stays light: ``import modal`` loads no plotting, templating,
notebook or workflow package, and the engine never imports the thesis layer."""

import ast
import subprocess
import sys
from pathlib import Path

HEAVY = ("matplotlib", "jinja2", "nbformat", "papermill", "snakemake", "yaml", "modal.thesis")
ENGINE = Path(__file__).resolve().parents[1] / "modal"


def test_import_modal_loads_no_heavy_package():
    code = ("import sys, modal; "
            f"print(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r} or m.startswith('modal.thesis')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out


def test_engine_modules_do_not_import_the_thesis_layer():
    for path in ENGINE.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                assert not (node.module or "").startswith(("thesis", "modal.thesis")), path
            if isinstance(node, ast.Import):
                assert not any(a.name.startswith("modal.thesis") for a in node.names), path


def test_import_modal_is_lazy_and_keeps_its_functions():
    """``import modal`` (and the chunk helpers Snakemake plans with) loads no
    numpy, pandas or scipy; the names load on first use, and ``modal.era``,
    ``modal.stabilisation`` ... stay the functions when their submodules are
    loaded by other imports."""
    code = ("import sys, modal, modal.thesis.chunks; "
            "print(sorted(m for m in ('numpy', 'pandas', 'scipy') if m in sys.modules)); "
            "import modal.thesis.study, modal.stabilisation, modal.cli; "
            "print(all(callable(getattr(modal, n)) and not isinstance(getattr(modal, n), type(sys))"
            " for n in ('era', 'tcm', 'cera', 'hankel', 'stabilisation'))); "
            "print(sorted(dir(modal)) == sorted(set(dir(modal))) and set(modal.__all__) <= set(dir(modal))); "
            "from modal import *; print(era is sys.modules['modal.era'].era)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split("\n")[:4] == ["[]", "True", "True", "True"], out
