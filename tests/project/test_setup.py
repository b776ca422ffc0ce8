"""The pinned set-up: the lock files in requirements/ against pyproject.toml,
and a build that prints no deprecation."""

import subprocess
import sys
import tomllib

import pytest
from packaging.utils import canonicalize_name

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

sys.path.insert(0, str(ROOT / "workflow"))
import lock_check  # noqa: E402

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
EXTRAS = sorted(PYPROJECT["project"]["optional-dependencies"])


@pytest.mark.parametrize("extra", ["tools", *EXTRAS])
def test_every_lock_satisfies_pyproject(extra):
    """After a dependency is added to pyproject.toml, this fails until
    `bash workflow/lock.sh` is rerun and requirements/ committed."""
    assert lock_check.problems(extra, PYPROJECT) == []


@pytest.mark.parametrize("extra", EXTRAS)
def test_every_extra_pins_the_versions_of_the_whole_lock(extra):
    """regenerate.sh and test.sh install different extras into one .venv:
    their locks must never disagree, so each is constrained to all.txt
    (markers may differ: a package may be needed on fewer platforms)."""
    everything = lock_check.read_lock(ROOT / "requirements/all.txt")
    pins = lock_check.read_lock(ROOT / f"requirements/{extra}.txt")
    assert pins, extra
    def versions(reqs):
        return {str(r.specifier) for r in reqs}

    for name, reqs in pins.items():
        assert versions(reqs) <= versions(everything[name]), name


def test_every_package_is_pinned_to_one_version():
    """The lock pins exact versions (==), nothing else, for the project's
    own dependencies and everything they pull in."""
    for lock in sorted((ROOT / "requirements").glob("*.txt")):
        for name, reqs in lock_check.read_lock(lock).items():
            for req in reqs:
                (spec,) = req.specifier
                assert spec.operator == "==", (lock.name, str(req))
    tools = lock_check.read_lock(ROOT / "requirements/tools.txt")
    assert {"pip", "setuptools", "uv"} <= set(tools)


def test_lock_check_names_a_dependency_the_lock_lacks():
    added = {**PYPROJECT, "project": {**PYPROJECT["project"]}}
    optional = dict(added["project"]["optional-dependencies"])
    optional["workflow"] = [*optional["workflow"], "no-such-package-xyz>=1"]
    added["project"]["optional-dependencies"] = optional
    added["project"]["dependencies"] = ["numpy>=999", *added["project"]["dependencies"][1:]]
    found = lock_check.problems("test", added)
    assert any("no-such-package-xyz" in p and "does not pin" in p for p in found), found
    assert any(p.startswith("test.txt pins numpy==") and "numpy>=999" in p for p in found), found
    # engine-test does not include the workflow extra: only numpy is wrong there.
    assert [p for p in lock_check.problems("engine-test", added) if "xyz" in p] == []


def test_lock_check_refuses_an_unknown_extra():
    with pytest.raises(ValueError, match="extra must be one of"):
        lock_check.problems("no-such-extra", PYPROJECT)


def test_self_referencing_extras_expand():
    names = {canonicalize_name(r.name) for r in lock_check.project_requirements(PYPROJECT, "test")}
    assert {"numpy", "snakemake", "pytest"} <= names
    assert canonicalize_name(PYPROJECT["project"]["name"]) not in names


@pytest.mark.slow
def test_building_the_project_prints_no_deprecation(tmp_path):
    """Issue 12: `license = {text = ...}` made setuptools print a deprecation
    three times per install; the SPDX string form with setuptools >= 77 does not."""
    run = subprocess.run(
        [sys.executable, "-W", "always", "-c",
         "import sys; from setuptools import build_meta as b; "
         "b.prepare_metadata_for_build_wheel(sys.argv[1])", str(tmp_path)],
        cwd=ROOT, capture_output=True, text=True, check=True)
    output = run.stdout + run.stderr
    assert "deprecat" not in output.lower(), output
    (dist_info,) = tmp_path.glob("*.dist-info")
    assert "License-Expression: MIT" in (dist_info / "METADATA").read_text()
