"""The Python entry point of a campaign: :func:`run` checks the campaign file
and the options, then runs the campaign's workflow (:data:`SNAKEFILE`) in the
output folder with this interpreter's Snakemake. ``modal campaign`` calls it.

Snakemake runs as a separate process through its command line, the interface
it keeps stable (its Python API changed between versions 7, 8 and 9), and so
that a job's failure cannot take the caller's process with it.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

from .._locks import clear_stale_locks
from ._config import campaign_inputs, read_campaign

#: The workflow :func:`run` (and ``modal campaign``) runs.
SNAKEFILE = Path(__file__).with_name("Snakefile")
#: The shipped Snakemake profiles, by name (a folder of this one each).
PROFILES = Path(__file__).with_name("profiles")


def profile_folder(profile) -> Path:
    """The Snakemake profile folder ``profile`` names.

    A folder that exists is used as it is, and Snakemake reads its settings
    (so a folder ``slurm`` in the working directory wins over the shipped
    profile of that name); otherwise a name of :data:`PROFILES` gives the
    shipped folder.

    Parameters
    ----------
    profile : path-like
        A folder holding ``config.yaml``, or a shipped profile's name.

    Returns
    -------
    pathlib.Path
        The folder, absolute.

    Raises
    ------
    ValueError
        ``profile`` is neither a folder nor a shipped name (the message lists
        the names).
    """
    folder = Path(profile)
    if folder.is_dir():
        return folder.resolve()
    shipped = sorted(p.name for p in PROFILES.iterdir() if (p / "config.yaml").is_file())
    if str(profile) not in shipped:
        raise ValueError(f"profile: {profile} is neither a folder nor a shipped profile ({', '.join(shipped)}); "
                         "a Snakemake profile is a folder with config.yaml")
    return (PROFILES / str(profile)).resolve()


class WorkflowStopped(RuntimeError):
    """The campaign's workflow stopped before it was done: Snakemake exited
    with ``returncode``. Its log is under ``log`` (``out/.snakemake/log``),
    each job's under ``out/logs``. Running again resumes: finished jobs are
    kept."""

    def __init__(self, returncode: int, log: Path):
        super().__init__(f"the workflow stopped (exit {returncode}); its log is in {log}; run again to resume")
        self.returncode = returncode
        self.log = log


def run(campaign, out, cores: int = 1, profile=None, dry_run: bool = False, *, command: str | None = None,
        log: Callable[[str], None] | None = None) -> Path:
    """Identify every record of a campaign, track the modes and write the report.

    Everything is checked before any job runs: the campaign file
    (:func:`modal.campaign.read_campaign`), the output folder (never one of
    the inputs, never holding one), the profile and Snakemake's presence.
    Locks left by a killed run in ``out`` are cleared (a live run there is
    refused). Then the campaign's workflow runs in ``out``; a second call
    with the same campaign resumes, and records added to the index add only
    their jobs (docs: Monitoring campaigns).

    Parameters
    ----------
    campaign : path-like
        The campaign's YAML file.
    out : path-like
        The output folder (created; kept between runs). It receives
        ``tracked.csv``, ``untracked.csv``, ``failed.csv``, ``modes.csv``,
        ``references.csv``, ``tracked_shapes.csv``, ``report.html``, the chunks' files under
        ``chunks/`` and the jobs' logs under ``logs/``.
    cores : int
        Cores to use on this machine (with a cluster profile: jobs at once).
    profile : path-like, optional
        A Snakemake profile: a folder holding ``config.yaml``, or the name
        of a shipped one (``"slurm"``, :func:`profile_folder`).
    dry_run : bool
        Plan only: Snakemake prints the jobs that would run; no job runs.
    command : str, optional
        How the results were asked for, for the report's provenance; by
        default this call, written as Python. Leave out what does not change
        the results (cores, profile): the report is rerun when it changes.
    log : callable, optional
        Called with each progress message (a ``str``): the number of records
        and chunks before the workflow starts, the files written after it.

    Returns
    -------
    pathlib.Path
        ``out``.

    Raises
    ------
    ValueError
        The campaign file is refused (the message names the key and the
        fix), ``cores`` is not a positive integer, ``profile`` is neither a
        folder nor a shipped profile's name, or another run is active in ``out`` (its process named);
        :class:`modal.measured.OutputError` (a ``ValueError``) when ``out``
        is not a folder, cannot be created, or is, holds or lies inside one
        of the campaign's inputs (the campaign file, the index, the
        reference modes, a record).
    ImportError
        The workflow extra (Snakemake, jsonschema, PyYAML) is not installed.
    WorkflowStopped
        The workflow stopped: a job failed (a record that cannot be read or
        identified is not a failure: ``failed.csv`` lists it), or it was
        interrupted.
    """
    from ..measured import OutputError, check_output

    log = log or (lambda message: None)
    if isinstance(cores, bool) or not isinstance(cores, int) or cores < 1:
        raise ValueError(f"cores: {cores!r} is not a positive integer")
    config, index = read_campaign(campaign)
    if importlib.util.find_spec("snakemake") is None:
        raise ImportError("snakemake is not installed")
    profile = None if profile is None else profile_folder(profile)
    out = Path(out)
    # not an input, not holding or inside one (the rule modal identify follows), and a folder (or where one
    # can be made) on a writable file system
    check_output(out, inputs=campaign_inputs(campaign, config, index))
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"out: cannot create {out}: {exc.strerror or exc}") from None
    cleared, live = clear_stale_locks(out)
    if live:
        listed = "; ".join(f"pid {pid}: {cmd[:120]}" for pid, cmd in sorted(live.items()))
        raise ValueError(f"out: a campaign run is active in {out} ({listed}): wait for it or stop it, then run "
                         "again to resume")
    if cleared:
        log(f"cleared {cleared} stale lock(s) of an interrupted run in {out}; resuming")
    if command is None:
        command = f"modal.campaign.run({str(campaign)!r}, {str(out)!r})"
    # The workflow's config as a file (JSON, which YAML reads): Snakemake parses
    # --config values itself, and a path such as "run #1/a: b" does not survive it.
    settings = out / ".modal" / "config.json"
    settings.parent.mkdir(exist_ok=True)
    settings.write_text(json.dumps({"campaign": str(Path(campaign).resolve()), "command": command}))
    call = [sys.executable, "-m", "snakemake", "--snakefile", str(SNAKEFILE), "--directory", str(out),
            "--cores", str(cores), "--rerun-incomplete", "--keep-going", "--configfile", str(settings.resolve())]
    if profile is not None:
        call += ["--profile", str(profile)]
    if dry_run:
        call += ["--dry-run", "--quiet", "rules"]
    log(f"{len(index)} records in {-(-len(index) // config['chunk'])} chunks of up to {config['chunk']}")
    report = out / "report.html"
    before = report.stat().st_mtime_ns if report.exists() else None
    done = subprocess.run(call)
    if done.returncode:
        raise WorkflowStopped(done.returncode, out / ".snakemake" / "log")
    if not dry_run and before is not None and report.stat().st_mtime_ns == before:
        log(f"nothing to do: {out / 'tracked.csv'} and {report} were up to date")
    elif not dry_run:
        log(f"wrote {out / 'tracked.csv'} and {report}")
    return out
