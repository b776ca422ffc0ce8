"""The code inputs of a rule come from its script's imports (modal.thesis.dependencies)."""

import json
import textwrap

import pytest
from modal.thesis.dependencies import code_inputs
from workflow_run import ROOT


def write(root, files):
    for path, text in files.items():
        (root / path).parent.mkdir(parents=True, exist_ok=True)
        (root / path).write_text(textwrap.dedent(text))


TREE = {
    "modal/__init__.py": "",
    "modal/engine/__init__.py": "from ._era import era\n",
    "modal/engine/_era.py": "from .._checks import square\n",
    "modal/engine/_tcm.py": "",
    "modal/_checks.py": "",
    "modal/thesis/__init__.py": "",
    "modal/thesis/study.py": "import numpy as np\nfrom ..engine import era\n",
    "modal/thesis/plots.py": "from .tables import x\n",
    "modal/thesis/tables.py": "",
    "workflow/scripts/identify.py": "import modal.thesis.study\nfrom _helpers import start_job\n",
    "workflow/scripts/figures.py": "from modal.thesis import plots\n",
}


def test_imports_are_followed_through_every_package_init(tmp_path):
    write(tmp_path, TREE)
    assert code_inputs("workflow/scripts/identify.py", root=tmp_path) == [
        "modal/__init__.py", "modal/_checks.py", "modal/engine/__init__.py", "modal/engine/_era.py",
        "modal/thesis/__init__.py", "modal/thesis/study.py"]
    assert code_inputs("workflow/scripts/figures.py", root=tmp_path) == [
        "modal/__init__.py", "modal/thesis/__init__.py", "modal/thesis/plots.py", "modal/thesis/tables.py"]


def test_adding_an_import_adds_the_input(tmp_path):
    write(tmp_path, TREE)
    before = code_inputs("workflow/scripts/figures.py", root=tmp_path)
    (tmp_path / "modal/thesis/tables.py").write_text("def x():\n    from ..engine._tcm import tcm\n")
    after = code_inputs("workflow/scripts/figures.py", root=tmp_path)
    # the new module, its package's __init__ and what that imports
    assert set(after) - set(before) == {"modal/engine/__init__.py", "modal/engine/_era.py", "modal/_checks.py",
                                        "modal/engine/_tcm.py"}


def test_an_eager_package_init_makes_every_importer_depend_on_what_it_imports(tmp_path):
    write(tmp_path, {**TREE, "modal/__init__.py": "from .engine import era\n"})
    assert "modal/engine/_era.py" in code_inputs("workflow/scripts/figures.py", root=tmp_path)


def test_a_name_of_a_lazy_package_may_come_from_any_of_its_modules(tmp_path):
    lazy = "def __getattr__(name):\n    import importlib\n    return importlib.import_module('.' + name, __name__)\n"
    write(tmp_path, {**TREE, "modal/engine/__init__.py": lazy,
                     "workflow/scripts/measured.py": "import modal.engine\nmodal.engine.tcm(1)\n"})
    assert {"modal/engine/_era.py", "modal/engine/_tcm.py"} <= set(
        code_inputs("workflow/scripts/measured.py", root=tmp_path))


def test_notebook_code_cells_are_read(tmp_path):
    write(tmp_path, TREE)
    cells = [{"cell_type": "markdown", "metadata": {}, "source": "import modal.thesis.study"},
             {"cell_type": "code", "metadata": {}, "execution_count": None, "outputs": [],
              "source": ["%matplotlib inline\n", "from modal.thesis.plots import x\n"]}]
    (tmp_path / "nb.ipynb").write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4,
                                                   "nbformat_minor": 5}))
    assert code_inputs("nb.ipynb", root=tmp_path) == [
        "modal/__init__.py", "modal/thesis/__init__.py", "modal/thesis/plots.py", "modal/thesis/tables.py"]


def test_identification_scripts_do_not_import_the_plotting_module():
    """The project's own scripts: a plot edit can rerun no identification."""
    for script in ("identify.py", "grid_identify.py", "measured.py"):
        inputs = code_inputs(f"workflow/scripts/{script}", root=ROOT)
        assert "modal/thesis/plots.py" not in inputs and "modal/__init__.py" in inputs, script


LAZY_INIT = '''\
import importlib
from typing import TYPE_CHECKING

_LAZY_NAMES = {"engine": ("era",), "drawing": ("draw",)}


def __getattr__(name):
    for sub, names in _LAZY_NAMES.items():
        if name in names:
            return getattr(importlib.import_module(f"{__name__}.{sub}"), name)
    raise AttributeError(name)


if TYPE_CHECKING:
    from .drawing import draw
    from .engine import era
'''
LAZY_TREE = {**TREE, "modal/__init__.py": LAZY_INIT, "modal/drawing/__init__.py": "from ._figure import draw\n",
             "modal/drawing/_figure.py": ""}
ENGINE = {"modal/engine/__init__.py", "modal/engine/_era.py", "modal/_checks.py"}
DRAWING = {"modal/drawing/__init__.py", "modal/drawing/_figure.py"}


@pytest.mark.parametrize("script, needs", [
    ("import modal\nmodal.era(1)\n", ENGINE),
    ("from modal import era\n", ENGINE),
    ("import modal as m\nm.draw()\n", DRAWING),
    ("from modal import *\n", ENGINE | DRAWING),
    ("import modal\nfor name in ['era', 'draw']:\n    getattr(modal, name)\n", ENGINE | DRAWING),
])
def test_a_name_of_a_lazy_package_counts_the_submodule_its_map_names(tmp_path, script, needs):
    """``modal.era`` runs modal/engine, not modal/drawing; the imports under
    ``if TYPE_CHECKING:`` never run; the module passed on as a whole (to
    ``getattr``) or a star import may run anything the map names."""
    write(tmp_path, {**LAZY_TREE, "workflow/scripts/s.py": script})
    inputs = set(code_inputs("workflow/scripts/s.py", root=tmp_path))
    assert inputs - {"modal/__init__.py"} == needs


def test_an_import_inside_a_function_counts_when_the_function_may_run(tmp_path):
    checks = '''\
        def grid_problems():
            return _helper()


        def _helper():
            from .tables import x


        def setups_problems():
            from ..drawing import draw
        '''
    write(tmp_path, {**LAZY_TREE, "modal/thesis/checks.py": checks,
                     "workflow/scripts/grid.py": "from modal.thesis.checks import grid_problems\n",
                     "workflow/scripts/setups.py": "import modal.thesis.checks as c\nc.setups_problems()\n",
                     "workflow/scripts/whole.py": "import modal.thesis.checks as c\nprint(c)\n"})
    grid = code_inputs("workflow/scripts/grid.py", root=tmp_path)
    assert "modal/thesis/tables.py" in grid  # through the helper it calls
    assert not DRAWING & set(grid)
    assert DRAWING <= set(code_inputs("workflow/scripts/setups.py", root=tmp_path))
    assert DRAWING <= set(code_inputs("workflow/scripts/whole.py", root=tmp_path))


THESIS_SCRIPTS = ("identify.py", "grid_identify.py", "search_setting.py", "measured.py")


@pytest.mark.parametrize("script", THESIS_SCRIPTS)
def test_identification_scripts_do_not_depend_on_roving_or_campaign_code(script):
    """An edit of the roving tests' or the campaigns' code reruns no
    identification (Snakemake's own plan: test_code_edits.py)."""
    inputs = code_inputs(f"workflow/scripts/{script}", root=ROOT)
    assert "modal/identification/_era.py" in inputs
    assert not [p for p in inputs if p.startswith(("modal/setups/", "modal/campaign/"))], script
