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
(``modal.read_record`` after ``import modal``), relative imports inside the
package, and ``importlib.import_module("modal.x")`` with a literal name;
never one under ``if TYPE_CHECKING:`` (it never runs).

An import inside a function runs when the function does, so it counts when
the function may run: a module's top-level code always runs; a function or
class of it may run if it is taken from the module (``from m import f``,
``m.f``, every one for a script, ``from m import *`` or a module object
passed on as a whole), or named by code that may run (a call, a callback, a
default). The Snakefile's config checks, for example, import the roving
setups inside a function that the grid study, which imports one other check
of that module, never calls.

A package that loads its names on first use (a module-level ``__getattr__``,
PEP 562, as ``modal`` does) runs only what a name needs: ``modal.era`` or
``from modal import era`` counts the submodule that the package's lazy map
(:data:`LAZY_MAP`, a literal ``{submodule: (name, ...)}`` in its
``__init__``) names for ``era``, its imports and nothing else. A name a lazy
package without such a map hands out could come from any of its modules, so
all of them count; so do all the map's submodules for ``from modal import *``.
"""

from __future__ import annotations

import ast
import functools
import json
from pathlib import Path

__all__ = ["LAZY_MAP", "code_inputs", "imported_names"]

#: The name of a lazy package's map from each submodule to the names it hands
#: out (``modal._LAZY_NAMES``), read from the package's ``__init__`` with ast.
LAZY_MAP = "_LAZY_NAMES"
#: "Every name of the module": a script, a star import, a module object passed on.
EVERYTHING = "*"


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
    # the names of each file that may run; a file is read again when that grows
    taken: dict[Path, set[str]] = {}
    files_of: dict[str, list[tuple[Path, set[str]]]] = {}
    pending = [(start, {EVERYTHING})]
    while pending:
        file, names = pending.pop()
        if file in taken and names <= taken[file]:
            continue
        taken[file] = taken.get(file, set()) | names
        module = _module_name(file, root, package)
        for name in _imports_of(file, module, file.name == "__init__.py", frozenset(taken[file])):
            if name not in files_of:  # the same names recur for every module that imports them
                files_of[name] = _files_of(name, root, package)
            for file_, names_ in files_of[name]:
                found.add(file_)
                pending.append((file_, names_))
    return sorted(f.relative_to(root).as_posix() for f in found)


def imported_names(source: str, module: str | None = None, is_package: bool = False) -> set[str]:
    """Absolute names of the modules ``source`` imports, and of what it takes
    from them (``from a import b`` gives ``a`` and ``a.b``: ``b`` may be a
    submodule; ``from a import *`` gives ``a`` and ``a.*``), anywhere in the
    file. ``module`` is the importing module's own name (for relative
    imports; ``None`` for a script), ``is_package`` whether it is an
    ``__init__``. Imports under ``if TYPE_CHECKING:`` are left out: they
    never run."""
    return _imports(ast.parse(source), module, is_package, {EVERYTHING})


def _imports(tree, module, is_package, taken) -> set[str]:
    """What running the module ``tree`` imports when the names ``taken`` of
    it are used: dotted names as :func:`imported_names` gives them."""
    scope = _running_code(tree, taken)
    names = set()
    # names bound to a module of the package (``import a.b`` binds ``a``,
    # ``import a.b as c`` binds ``c``, ``from a import b`` binds ``b``, maybe a
    # module): ``c.x`` takes ``x`` from it, a bare ``c`` takes everything
    bound = {}
    for node in scope:
        if isinstance(node, ast.Import):
            for alias in node.names:
                names.add(alias.name)
                top = alias.name.split(".")[0]
                bound[alias.asname or top] = alias.name if alias.asname else top
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(node.module, node.level, module, is_package)
            if base is None:
                continue
            names.add(base)
            for alias in node.names:
                names.add(f"{base}.{alias.name}")
                if alias.name != "*":
                    bound[alias.asname or alias.name] = f"{base}.{alias.name}"
        elif (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
              and isinstance(node.args[0].value, str) and _is_import_module(node.func)):
            names.update((node.args[0].value, f"{node.args[0].value}.{EVERYTHING}"))
    parents = {child: node for node in scope for child in ast.iter_child_nodes(node)}
    for node in scope:
        if isinstance(node, ast.Name) and node.id in bound and isinstance(node.ctx, ast.Load):
            chain, top = [], node
            while isinstance(parents.get(top), ast.Attribute) and parents[top].value is top:
                top = parents[top]
                chain.append(top.attr)
            base = bound[node.id]
            names.update(".".join([base, *chain[:i]]) for i in range(1, len(chain) + 1))
            if not chain:  # the object itself goes on: any of its names may be used
                names.add(f"{base}.{EVERYTHING}")
    return names


def _running_code(tree, taken) -> list:
    """The nodes of a module that may run when the names ``taken`` of it are
    used: its top-level code, and the functions and classes that it, those
    names or other such functions name (transitively); never the body of
    ``if TYPE_CHECKING:``."""
    definitions, top_level = {}, []
    for statement in _top_level(tree.body):
        if isinstance(statement, (ast.FunctionDef, ast.AsyncFunctionDef)):
            definitions[statement.name] = [statement]
            # decorators and defaults run when the function is defined
            top_level += [*statement.decorator_list, *statement.args.defaults,
                          *(d for d in statement.args.kw_defaults if d is not None)]
        elif isinstance(statement, ast.ClassDef):
            methods = [s for s in statement.body if isinstance(s, (ast.FunctionDef, ast.AsyncFunctionDef))]
            definitions[statement.name] = methods
            # a class body runs when the class is defined; its methods when called
            top_level += [*statement.decorator_list, *statement.bases, *statement.keywords,
                          *(s for s in statement.body if s not in methods)]
        else:
            top_level.append(statement)
    nodes = [n for root in top_level for n in _walk(root)]
    pending = list(definitions) if EVERYTHING in taken else list(taken)
    pending += [n.id for n in nodes if isinstance(n, ast.Name)]
    while pending:
        name = pending.pop()
        for root in definitions.pop(name, ()):  # popped: each definition is read once
            walked = list(_walk(root))
            nodes += walked
            pending += [n.id for n in walked if isinstance(n, ast.Name)]
    return nodes


def _top_level(statements):
    """Statements that run at import, through ``if``, ``try`` and ``with``
    blocks (``if TYPE_CHECKING:``: only its ``else``)."""
    for statement in statements:
        if isinstance(statement, ast.If):
            if not _is_type_checking(statement.test):
                yield statement.test
                yield from _top_level(statement.body)
            yield from _top_level(statement.orelse)
        elif isinstance(statement, ast.Try):
            yield from _top_level(statement.body)
            for handler in statement.handlers:
                yield from _top_level(handler.body)
            yield from _top_level(statement.orelse)
            yield from _top_level(statement.finalbody)
        elif isinstance(statement, ast.With):
            yield from statement.items
            yield from _top_level(statement.body)
        else:
            yield statement


def _walk(tree):
    """Every node of ``tree`` but those under ``if TYPE_CHECKING:`` (or
    ``typing.TYPE_CHECKING``): imports for static type checkers only, which a
    lazy package's ``__init__`` holds for all it hands out."""
    pending = [tree]
    while pending:
        node = pending.pop()
        yield node
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            pending.extend(node.orelse)
            continue
        pending.extend(ast.iter_child_nodes(node))


def _is_type_checking(test) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


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


def _files_of(name, root, package) -> list[tuple[Path, set[str]]]:
    """The files importing module ``name`` executes (its packages' ``__init__``
    and its own file), or, for a name that is not a module, what may define
    it; each with the names of it that may run (a module's own: none but its
    top-level code; the name taken: that name)."""
    parts = name.split(".")
    if parts[0] != package:
        return []
    files = []
    folder = root
    for i, part in enumerate(parts):
        init, file = folder / part / "__init__.py", folder / f"{part}.py"
        rest = set(parts[i + 1:i + 2])  # the name taken from this module, if any
        if init.is_file():
            files.append((init, rest))
            folder = folder / part
        elif file.is_file():  # the module, or the module defining the name parts[i + 1]
            files.append((file, rest))
            break
        else:
            # ``parts[i]`` is no module: a name defined in the package parts[:i],
            # by its ``__init__`` (counted already) or, lazily, by a submodule
            files.extend(_lazy_sources(part, folder, root, package, ".".join(parts[:i])))
            break
    return files


def _lazy_sources(name, folder, root, package, module):
    """The files that taking ``name`` (``*``: everything) from the lazy package
    ``module`` (in ``folder``) may run: those of the submodule its map names,
    all of the map's for ``*``, every module of the package if it has no map;
    none if the package is not lazy."""
    init = folder / "__init__.py"
    if not _loads_lazily(init):
        return []
    submodules = _lazy_map(init)
    if submodules is None:
        return [(file, {EVERYTHING}) for file in sorted(folder.glob("*.py"))]
    if name == EVERYTHING:
        return [f for sub in sorted(set(submodules.values()))
                for f in _files_of(f"{module}.{sub}.{EVERYTHING}", root, package)]
    if name not in submodules:
        return []
    return _files_of(f"{module}.{submodules[name]}.{name}", root, package)


def _loads_lazily(init: Path) -> bool:
    """Whether a package's ``__init__`` defines a module-level ``__getattr__``."""
    if not init.is_file():
        return False
    tree = _tree(init)
    return any(isinstance(node, ast.FunctionDef) and node.name == "__getattr__" for node in tree.body)


def _lazy_map(init: Path) -> dict[str, str] | None:
    """Name -> submodule (relative: ``"identification"``) of a lazy package,
    from the literal :data:`LAZY_MAP` assigned in its ``__init__``; ``None``
    without one."""
    for node in _tree(init).body:
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
            node, ast.AnnAssign) and node.value is not None else []
        if any(isinstance(t, ast.Name) and t.id == LAZY_MAP for t in targets):
            by_submodule = ast.literal_eval(node.value)
            return {name: sub for sub, names in by_submodule.items() for name in names}
    return None


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


def _imports_of(file: Path, module, is_package: bool, names: frozenset) -> set[str]:
    """:func:`_imports` of ``file``'s tree, computed once per content and names
    in this process (a workflow's planning asks again for every rule)."""
    stat = file.stat()
    return _imports_cached(str(file.resolve()), stat.st_mtime_ns, stat.st_size, module, is_package, names)


@functools.lru_cache(maxsize=None)
def _imports_cached(path: str, mtime_ns: int, size: int, module, is_package: bool, names: frozenset) -> set[str]:
    return _imports(_tree(Path(path)), module, is_package, set(names))


def _tree(file: Path) -> ast.Module:
    """The parsed source of ``file``, parsed once per content seen by this
    process (planning a workflow asks for the same engine modules once per
    rule; never modified by the callers)."""
    stat = file.stat()
    return _parsed(str(file.resolve()), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=None)
def _parsed(path: str, mtime_ns: int, size: int) -> ast.Module:
    return ast.parse(_source(Path(path)))


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
