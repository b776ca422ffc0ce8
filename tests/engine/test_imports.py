"""The engine stays light: ``import modal`` loads no plotting, templating,
notebook or workflow package and none of its own subpackages (they load on
first use, PEP 562), the engine never imports the thesis layer, and no module
imports another subpackage's private module."""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

HEAVY = ("matplotlib", "jinja2", "jsonschema", "nbformat", "papermill", "snakemake", "yaml", "modal.thesis")
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


def _loaded_after(code: str) -> list[str]:
    """The ``modal.*`` modules loaded by ``code`` in a fresh interpreter."""
    code += "\nimport sys; print(sorted(m for m in sys.modules if m.startswith('modal.')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    return ast.literal_eval(out.strip().splitlines()[-1])


def test_import_modal_loads_no_subpackage():
    assert _loaded_after("import modal; dir(modal); modal.__all__") == []


def test_a_public_name_loads_only_its_subpackage():
    """``modal.read_record`` loads modal.records and what it imports, never the
    roving tests, the campaigns or the pipeline."""
    loaded = {m.split(".")[1] for m in _loaded_after("import modal; modal.read_record")}
    assert "records" in loaded and not loaded & {"setups", "campaign", "measured", "thesis"}, loaded


def test_every_public_name_comes_from_the_subpackage_the_lazy_map_names():
    """Each name of ``modal.__all__`` resolves, to the object of that name in
    the subpackage ``modal._LAZY_NAMES`` names for it, which exports it (a
    name mapped to the wrong subpackage fails here, and would misstate the
    workflow's code inputs); ``dir(modal)`` shows them all."""
    code = ("import importlib, modal\n"
            "for name in modal.__all__:\n"
            "    sub = importlib.import_module('modal.' + modal._SUBPACKAGE_OF[name])\n"
            "    assert name in sub.__all__ and getattr(modal, name) is getattr(sub, name), name\n"
            "assert set(modal.__all__) | {'setups', 'campaign'} <= set(dir(modal))\n"
            "print(len(modal.__all__))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-2000:]
    assert int(out.stdout) > 60


@pytest.mark.parametrize("init", ["__init__.py", "campaign/__init__.py"])
def test_what_type_checkers_see_is_the_lazy_map(init):
    """The imports under ``if TYPE_CHECKING:`` in a lazy package's __init__.py
    (for IDEs and type checkers; they never run) list exactly the lazy map's
    names; so does ``__all__`` where it is written out (the API pages read it)."""
    tree = ast.parse((ENGINE / init).read_text())
    lazy = next(n for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "_LAZY_NAMES")
    block = next(n for n in tree.body if isinstance(n, ast.If) and getattr(n.test, "id", "") == "TYPE_CHECKING")
    seen = {}
    for node in block.body:
        seen.setdefault(node.module, set()).update(alias.name for alias in node.names)
    mapped = {sub: set(names) for sub, names in ast.literal_eval(lazy.value).items()}
    assert seen == mapped
    listed = next((n.value for n in tree.body if isinstance(n, ast.Assign) and n.targets[0].id == "__all__"
                   and isinstance(n.value, ast.List)), None)
    if listed is not None:
        assert sorted(ast.literal_eval(listed)) == sorted(set().union(*mapped.values()))


def test_a_campaign_job_loads_neither_the_report_nor_matplotlib():
    """The identification job's name loads its module, not the report's (so
    a report edit reruns no identification: the workflow hashes what runs)."""
    code = ("import sys, modal.campaign; modal.campaign.identify_chunk; "
            "print(sorted(m for m in sys.modules if m.startswith(('modal.campaign.', 'matplotlib'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert ast.literal_eval(out.strip().splitlines()[-1]) == ["modal.campaign._jobs"]


def private_imports(source: str, module: str, is_package: bool = False) -> list[str]:
    """The private modules or names (a part after the subpackage that starts
    with ``_``) of another subpackage that the module ``module`` imports:
    ``modal.a._b`` from outside ``modal.a``. ``modal._checks``, the package's
    own helpers, is no subpackage's."""
    # the subpackage ``module`` belongs to (none for modal itself and modal/cli.py)
    parts = module.split(".")
    own = parts[1] if len(parts) > 2 or (is_package and len(parts) == 2) else None
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = module.split(".") if is_package else module.split(".")[:-1]
                base = ".".join(parts[: len(parts) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            names = [base, *(f"{base}.{alias.name}" for alias in node.names)]
        else:
            continue
        for name in names:
            parts = name.split(".")
            if (parts[0] == "modal" and len(parts) > 2 and parts[1] != own
                    and any(p.startswith("_") and not p.startswith("__") for p in parts[2:])):
                found.append(name)
    return found


def test_the_private_import_check_sees_one():
    assert private_imports("from ..identification._result import ModalWarning", "modal.records._io") == [
        "modal.identification._result", "modal.identification._result.ModalWarning"]
    assert private_imports("import modal.signals._filters", "modal.cli") == ["modal.signals._filters"]
    assert private_imports("from ..signals import _filters", "modal.identification._tcm") == [
        "modal.signals._filters"]
    assert private_imports("from ._result import ModalWarning\nfrom .._checks import records",
                           "modal.identification._tcm") == []
    assert private_imports("from ..identification import ModalWarning", "modal.records._io") == []


def test_no_module_imports_another_subpackages_private_module():
    """A subpackage's private modules are its own: the others import from its
    ``__init__``, so a private module can be split or renamed freely."""
    found = {}
    for path in sorted(ENGINE.rglob("*.py")):
        parts = path.relative_to(ENGINE.parent).with_suffix("").parts
        is_package = parts[-1] == "__init__"
        module = ".".join(parts[:-1] if is_package else parts)
        if offending := private_imports(path.read_text(), module, is_package):
            found[path.relative_to(ENGINE.parent).as_posix()] = offending
    assert not found, found
