"""Check that the lock files in ``requirements/`` still satisfy ``pyproject.toml``.

``workflow/lock.sh`` pins every package of every extra; when someone adds or
tightens a dependency in ``pyproject.toml`` and forgets to rerun it, the lock
no longer holds what the project asks for. This script names each such
requirement. ``workflow/setup.sh`` runs it after every install (a warning,
an error under ``CI=true``), and ``tests/project/test_setup.py`` runs it too.

Usage: ``python workflow/lock_check.py [EXTRA ...]`` (default: every extra);
exit status 1 when a requirement is missing or unsatisfied.
"""
from __future__ import annotations

import sys
import tomllib
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[1]
LOCK_DIR = ROOT / "requirements"
TOOLS = "tools"


def read_lock(path: Path) -> dict[str, list[Requirement]]:
    """Pinned requirements of one lock file, by canonical name.

    A universal lock may pin one name several times under exclusive markers,
    so each name maps to a list.
    """
    pins: dict[str, list[Requirement]] = {}
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line or line.startswith("-"):
            continue
        req = Requirement(line)
        pins.setdefault(canonicalize_name(req.name), []).append(req)
    return pins


def project_requirements(pyproject: dict, extra: str) -> list[Requirement]:
    """Requirements of the project installed with ``extra``, self-references expanded."""
    project = pyproject["project"]
    name = canonicalize_name(project["name"])
    optional = project.get("optional-dependencies", {})
    if extra != TOOLS and extra not in optional:
        raise ValueError(f"extra must be one of {sorted(optional)} or {TOOLS!r}, got {extra!r}")
    if extra == TOOLS:
        return [Requirement(r) for r in pyproject["build-system"]["requires"]]
    wanted, todo, seen = [], [extra], set()
    for r in project.get("dependencies", []):
        wanted.append(Requirement(r))
    while todo:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        for text in optional[current]:
            req = Requirement(text)
            if canonicalize_name(req.name) == name:
                todo.extend(req.extras)
            else:
                wanted.append(req)
    return wanted


def problems(extra: str, pyproject: dict | None = None) -> list[str]:
    """What ``requirements/{extra}.txt`` lacks for ``pyproject.toml``, for this interpreter.

    Parameters
    ----------
    extra : str
        An optional-dependency group of ``pyproject.toml``, or ``"tools"``
        (the build requirements, locked with pip and uv).
    pyproject : dict, optional
        The parsed ``pyproject.toml``; read from the project root if omitted.

    Returns
    -------
    list of str
        One message per requirement the lock misses or pins outside its range.
    """
    if pyproject is None:
        pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    wanted = project_requirements(pyproject, extra)
    lock = LOCK_DIR / f"{extra}.txt"
    if not lock.is_file():
        return [f"{lock.relative_to(ROOT)} is missing"]
    pins = read_lock(lock)
    found = []
    for req in wanted:
        if req.marker is not None and not req.marker.evaluate({"extra": extra}):
            continue
        here = [p for p in pins.get(canonicalize_name(req.name), [])
                if p.marker is None or p.marker.evaluate()]
        if not here:
            found.append(f"{lock.name} does not pin {req}")
            continue
        for pin in here:
            version = next(iter(pin.specifier)).version
            if not req.specifier.contains(version, prereleases=True):
                found.append(f"{lock.name} pins {pin.name}=={version}, outside {req}")
    return found


def main(argv: list[str]) -> int:
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    extras = argv or [TOOLS, *pyproject["project"].get("optional-dependencies", {})]
    found = [p for extra in extras for p in problems(extra, pyproject)]
    for message in found:
        print(f"lock_check: {message}", file=sys.stderr)
    if found:
        print("lock_check: the lock is out of date with pyproject.toml; "
              "run `bash workflow/lock.sh` and commit requirements/", file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
