"""The project code a workflow script or notebook runs, read from its imports.

Snakemake does not see edits to modules a script imports, so every rule
declares them as inputs. :func:`code_inputs` derives that list instead of
keeping it by hand: it parses the script (or a notebook's code cells) with
:mod:`ast`, without importing anything, and follows its imports of the
project's package transitively. Importing ``modal.x.y`` executes
``modal/__init__.py`` and ``modal/x/__init__.py`` before ``modal/x/y.py``, so
every package on the way counts too, with whatever its ``__init__`` imports:
if the package's ``__init__`` imports the engine eagerly, every script that
imports anything of the package depends on the whole engine, as it does when
it runs.

What counts as an import: ``import modal.x``, ``from modal.x import y``
(``y`` a submodule or a name), an attribute of an imported module
(``modal.read_record`` after ``import modal``), relative imports inside the package, and
``importlib.import_module("modal.x")`` with a literal name; anywhere in the
file, including inside functions (they run when the function does). A name
taken from a package that loads its names on first use (a module-level
``__getattr__``, PEP 562) and is not a submodule could come from any module of
that package, so all of them count.
"""

from __future__ import annotations

import ast
import json
from pathlib import Path

__all__ = ["code_inputs", "imported_names"]


def code_inputs(path, root=".", package: str = "modal") -> list[str]:
    """Files of ``package`` that running ``path`` executes, as sorted paths relative to ``root``.

    Parameters
    ----------
    path : path
        A Python script or module, or a Jupyter notebook (``.ipynb``: its code
        cells), absolute or relative to ``root``.
    root : path
        The folder holding the package (the project root).
    package : str
        The top-level package whose modules count (the project's engine and
        thesis layer); imports of anything else (numpy, ``_helpers``) are not
        followed.

    Returns
    -------
    list of str
        POSIX paths relative to ``root``, e.g. ``["modal/__init__.py",
        "modal/era.py", ...]``; ``path`` itself only if something it
        imports imports it back.
    """
    root = Path(root)
    start = Path(path) if Path(path).is_absolute() else root / path
    found: set[Path] = set()
    pending = [(start, _module_name(start, root, package))]
    seen = set()
    while pending:
        file, name = pending.pop()
        if file in seen:
            continue
        seen.add(file)
        for module in imported_names(_source(file), name, file.name == "__init__.py"):
            for file_ in _files_of(module, root, package):
                found.add(file_)
                pending.append((file_, _module_name(file_, root, package)))
    return sorted(f.relative_to(root).as_posix() for f in found)


def imported_names(source: str, module: str | None = None, is_package: bool = False) -> set[str]:
    """Absolute names of the modules ``source`` imports, and of what it takes
    from them (``from a import b`` gives ``a`` and ``a.b``: ``b`` may be a
    submodule). ``module`` is the importing module's own name (for relative
    imports; ``None`` for a script), ``is_package`` whether it is an ``__init__``."""
    names = set()
    tree = ast.parse(source)
    # what ``import a.b`` (binds ``a``) and ``import a.b as c`` (binds ``c``) bind,
    # so that ``a.x`` and ``c.x`` count as taking ``x`` from the module
    bound = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                bound[alias.asname or alias.name.split(".")[0]] = alias.name if alias.asname else alias.name.split(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.Attribute):
            chain = []
            while isinstance(node, ast.Attribute):
                chain.insert(0, node.attr)
                node = node.value
            if isinstance(node, ast.Name) and node.id in bound:
                names.update(".".join([bound[node.id], *chain[:i]]) for i in range(1, len(chain) + 1))
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(node.module, node.level, module, is_package)
            if base is None:
                continue
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names if alias.name != "*")
        elif (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
              and isinstance(node.args[0].value, str) and _is_import_module(node.func)):
            names.add(node.args[0].value)
    return names


def _is_import_module(func) -> bool:
    """``importlib.import_module`` or a bare ``import_module``."""
    return (isinstance(func, ast.Attribute) and func.attr == "import_module") or (
        isinstance(func, ast.Name) and func.id == "import_module")


def _absolute(name, level, module, is_package):
    """The absolute module name of ``from <level dots><name> import ...``."""
    if level == 0:
        return name
    if module is None:  # a relative import outside a package: not ours to follow
        return None
    parts = module.split(".") if is_package else module.split(".")[:-1]
    if level - 1 > len(parts) - 1:
        return None
    parts = parts[: len(parts) - (level - 1)]
    return ".".join(parts + ([name] if name else []))


def _files_of(name, root, package):
    """The files importing module ``name`` executes (its packages' ``__init__``
    and its own file), or, for a name that is not a module, what may define it."""
    parts = name.split(".")
    if parts[0] != package:
        return []
    files = []
    folder = root
    for i, part in enumerate(parts):
        init, file = folder / part / "__init__.py", folder / f"{part}.py"
        if init.is_file():
            files.append(init)
            folder = folder / part
        elif file.is_file():  # the module, or the module defining the name parts[i + 1]
            files.append(file)
            break
        else:
            # ``parts[i]`` is no module: a name defined in the package parts[:i].
            if i == len(parts) - 1 and _loads_lazily(folder / "__init__.py"):
                files.extend(sorted(folder.glob("*.py")))
            break
    return files


def _loads_lazily(init: Path) -> bool:
    """Whether a package's ``__init__`` defines a module-level ``__getattr__``."""
    if not init.is_file():
        return False
    tree = ast.parse(_source(init))
    return any(isinstance(node, ast.FunctionDef) and node.name == "__getattr__" for node in tree.body)


def _module_name(file: Path, root: Path, package: str):
    """``modal.x.y`` for ``root/modal/x/y.py`` (``modal.x`` for its
    ``__init__.py``); ``None`` for a file outside the package."""
    try:
        parts = list(file.resolve().relative_to((root / package).resolve()).with_suffix("").parts)
    except ValueError:
        return None
    if parts and parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join([package, *parts])


def _source(file: Path) -> str:
    """Python source of a module, or of a notebook's code cells (IPython
    magics and shell lines, ``%`` and ``!``, left out)."""
    text = file.read_text(encoding="utf-8")
    if file.suffix != ".ipynb":
        return text
    cells = [c for c in json.loads(text)["cells"] if c["cell_type"] == "code"]
    lines = []
    for cell in cells:
        source = cell["source"] if isinstance(cell["source"], str) else "".join(cell["source"])
        lines += [line for line in source.splitlines() if not line.lstrip().startswith(("%", "!"))]
    return "\n".join(lines)
