"""The engine stays light: ``import modal`` loads no plotting, templating,
notebook or workflow package, and the engine never imports the thesis layer."""

import ast
import subprocess
import sys
from pathlib import Path

HEAVY = ("matplotlib", "jinja2", "nbformat", "papermill", "snakemake", "yaml", "modal.thesis")
ENGINE = Path(__file__).resolve().parents[2] / "modal"


def test_import_modal_loads_no_heavy_package():
    code = ("import sys, modal; "
            f"print(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r} or m.startswith('modal.thesis')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out


def test_engine_modules_do_not_import_the_thesis_layer():
    paths = [p for p in ENGINE.rglob("*.py") if "thesis" not in p.relative_to(ENGINE).parts]
    assert len(paths) > 20
    for path in paths:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                assert "thesis" not in (node.module or "").split("."), path
            if isinstance(node, ast.Import):
                assert not any(a.name.startswith("modal.thesis") for a in node.names), path


def test_public_names_are_the_functions_whatever_is_imported():
    """``modal.era`` ... are the functions, also after every implementation
    module is loaded, and ``modal.__all__`` lists exactly what the package
    re-exports from its subpackages."""
    code = ("import sys, modal.thesis.study, modal.cli, modal.measured, modal.identification._era; import modal; "
            "print(all(callable(getattr(modal, n)) and not isinstance(getattr(modal, n), type(sys))"
            " for n in ('era', 'tcm', 'cera', 'hankel', 'stabilisation'))); "
            "subs = [modal.identification, modal.signals, modal.records, modal.measured, modal.structures, "
            "modal.setups]; "
            "print(sorted(modal.__all__) == sorted(n for s in subs for n in s.__all__ if n != 'EXCITATIONS')); "
            "from modal import *; print(era is sys.modules['modal.identification._era'].era)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split("\n")[:3] == ["True", "True", "True"], out
