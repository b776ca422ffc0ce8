"""The shipped campaign profile: ``modal campaign ... --profile slurm`` as
typed names the profile inside the package (run on a real Slurm by
tests/workflow/test_slurm.py); a folder of that name in the working
directory wins; an unknown name is refused with the shipped names; the
profile is package data, so a wheel carries it."""

import fnmatch
import tomllib

import pytest
import yaml

from modal.campaign._workflow import PROFILES, profile_folder
from workflow_run import ROOT


def test_the_shipped_name_gives_the_packaged_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # no folder named slurm here
    folder = profile_folder("slurm")
    assert folder == (PROFILES / "slurm").resolve() and folder.is_absolute()
    settings = yaml.safe_load((folder / "config.yaml").read_text())
    # what docs/campaigns.md says it does: Slurm jobs, states from squeue (a cluster without sacct)
    assert settings["executor"] == "slurm" and settings["slurm-status-command"] == "squeue"


def test_a_folder_of_that_name_wins(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "slurm").mkdir()
    assert profile_folder("slurm") == (tmp_path / "slurm").resolve()
    assert profile_folder(tmp_path / "slurm") == (tmp_path / "slurm").resolve()


@pytest.mark.parametrize("name", ["slrum", "profiles/slurm", "default"])
def test_an_unknown_name_is_refused_with_the_shipped_names(tmp_path, monkeypatch, name):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=r"profile: .* is neither a folder nor a shipped profile \(slurm\)"):
        profile_folder(name)


def test_the_profile_is_package_data():
    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["modal"]
    shipped = [str(p.relative_to(ROOT / "modal")) for p in PROFILES.glob("*/config.yaml")]
    assert shipped and all(any(fnmatch.fnmatch(f, pat) for pat in patterns) for f in shipped), shipped
