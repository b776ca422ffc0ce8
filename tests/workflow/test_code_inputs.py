"""The code inputs of a rule come from its script's imports (modal.thesis.dependencies)."""

import json
import textwrap

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
